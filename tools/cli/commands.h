// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli commands: the parsed options (args.c), the check (check.c),
// track (track.c) and info (info.c) commands, and the meshes they load into
// the library (part.c).
#ifndef SELFCOL_CLI_COMMANDS_H
#define SELFCOL_CLI_COMMANDS_H

#include "cli.h"

enum { CLI_EXIT_CLEAN = 0, CLI_EXIT_FOUND = 1, CLI_EXIT_ERROR = 2 };
enum { CLI_MAX_INPUTS = 4096 };
/** --range limits: FIRST and LAST within +-CLI_RANGE_LIMIT, at most CLI_RANGE_MAX_FRAMES frames. */
#define CLI_RANGE_LIMIT 1000000000L
#define CLI_RANGE_MAX_FRAMES 1000000L

typedef struct cli_options {
    double distance, distance_rel;
    int distance_given, distance_rel_given;
    uint32_t method, narrow;
    int method_given;     /* --method was given (check --continuous defaults to bvh) */
    unsigned int threads; /* --threads: the command's selfcol_context's threads, default 1 */
    const char *json, *csv, *mark, *png;
    int quiet, fail_on_proximity, no_weld, frames;
    int continuous;    /* check --continuous: continuous queries between consecutive frames */
    const char *range; /* "FIRST:LAST[:STEP]" for a pattern */
    long range_first, range_last, range_step; /* --range, checked by cli_parse_options */
    cli_view view;
    /* track */
    const char *jsonl, *png_worst;
    uint32_t remnance; /* default SELFCOL_STORE_DEFAULT_REMNANCE */
    int no_consistency;
    const char *inputs[CLI_MAX_INPUTS];
    int input_count;
} cli_options;

/** Names of the --method and --narrow values, indexed by the library's enums. */
extern const char *const cli_method_names[5];
extern const char *const cli_narrow_names[2];

/** selfcol-cli --help. */
extern const char cli_main_help[];

/**
 * Prints "selfcol-cli: " format (with what) and a pointer to command's --help
 * (command: "check ", "track ", "info " or NULL) on stderr. Returns CLI_EXIT_ERROR.
 */
int cli_usage_error(const char *command, const char *format, const char *what);

/**
 * Parses argv[first..] for command ("check", "track" or "info") into o. Returns 0, -1
 * after --help or --version (exit 0), or CLI_EXIT_ERROR after a usage error.
 */
int cli_parse_options(int argc, char **argv, int first, const char *command, cli_options *o);

/** An output name (--mark, --png) for a frame. Returns 0, or -1 when it does not fit. */
int cli_output_name(const char *name, long frame, char *out, size_t out_size);

/** 1 when an output name has a %d for the frame number, 0 when it is used as is. */
int cli_output_is_pattern(const char *name);

/** An output file of a command, for cli_check_outputs. */
typedef struct cli_output_file {
    const char *option; /* "--png" */
    const char *name;   /* as given; NULL: not given */
    int numbered;       /* a %d in name is the frame number (cli_output_name) */
} cli_output_file;

/**
 * Checks a command's outputs before anything is read or written: every name
 * an output will write (numbered ones for each of the frame numbers) is
 * resolved, by device and inode when the file exists, otherwise as its
 * directory's real path and its name ("-" is standard output). Two outputs,
 * or an output and an input, naming one file are a usage error (command:
 * "track " etc., for the pointer to --help); an output that cannot be
 * written (its directory missing or not writable, a directory, a read-only
 * file) is an error. Devices such as /dev/null are not compared. Returns 0,
 * or -1 with err set.
 */
int cli_check_outputs(const char *command, const cli_output_file *outputs, int output_count,
                      const char *const *inputs, long input_count, const long *frames,
                      long frame_count, cli_error *err);

/**
 * The frame files of --frames or --range and their frame numbers. Returns 0,
 * or -1 with err set; the arrays (count_out names) are to be freed either way.
 */
int cli_frame_list(const cli_options *o, char ***names_out, long **numbers_out, long *count_out,
                   cli_error *err);

/** Fails with the message of a failed selfcol_mesh_create/_set_positions
 *  status rc: the first coordinate or index the library refuses, when it can
 *  be named (triangles may be NULL), else the status string. Returns -1. */
int cli_fail_mesh(cli_error *err, const char *path, int rc, const double *positions,
                  size_t vertex_count, const uint32_t *triangles, size_t triangle_count);

/** Frees what cli_part_create made and the mesh as read, and zeroes part. */
void cli_part_free(cli_part *part);

/**
 * Welds part->file (unless no_weld) and creates its library mesh and, when
 * build_hierarchy, its hierarchy; the part borrows `context` (NULL: one
 * thread) for its refits and queries. Adds the time taken to the two
 * counters. Returns 0, or -1 with err set.
 */
int cli_part_create(cli_part *part, int no_weld, int build_hierarchy, selfcol_context *context,
                    double *seconds_topology, double *seconds_hierarchy, cli_error *err);

/**
 * Reads a later frame of a sequence into part: same vertex count and file
 * triangles as the first frame (else an error naming path), then sets the
 * library mesh's positions. Counts in *split_groups a frame where vertices
 * welded in the first frame have moved apart. Returns 0, or -1 with err set.
 */
int cli_load_next_frame(cli_part *part, const char *path, cli_progress *progress,
                        size_t *split_groups, cli_error *err);

/**
 * Prints "  frames with interferences: 3, 5-9, 12" (runs of consecutive
 * frames of the sequence as FIRST-LAST) and a newline; nothing when frames
 * (long) is empty.
 */
void cli_print_frame_list(FILE *out, const meshio_array *frames, const long *sequence,
                          long sequence_count);

/**
 * The detection distance of --distance, or of --distance-rel times
 * mean_edge, into *distance. Returns 0, or -1 with err set when it exceeds
 * what the library accepts.
 */
int cli_detection_distance(const cli_options *o, double mean_edge, double *distance,
                           cli_error *err);

/** Prints the warning about welded vertices that moved apart (nothing when split_frames is 0). */
void cli_print_weld_warning(FILE *out, size_t split_frames);

/**
 * A command's last step: an exit status other than CLI_EXIT_ERROR becomes
 * CLI_EXIT_ERROR when writing to stdout failed; an error's message is
 * printed on stderr. Returns the exit status.
 */
int cli_finish(int exit_code, cli_error *err);

/** The commands: each returns the exit status. */
int cli_command_check(const cli_options *o);
int cli_command_track(const cli_options *o);
int cli_command_info(const cli_options *o);

#endif /* SELFCOL_CLI_COMMANDS_H */
