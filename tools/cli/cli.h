// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli internals shared by its source files: error messages, progress
// reporting, and the pieces of each command. Mesh files are read and written
// by selfcol_meshio (tools/meshio/meshio.h). Nothing here is part of
// libselfcol; the tool uses only the public API.
#ifndef SELFCOL_CLI_H
#define SELFCOL_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "meshio.h"

/** One error message, "file:line: what": the mesh reader's own type (meshio.h). */
typedef meshio_error cli_error;

/** Formats an error message into err (printf-style); -1 for `return cli_fail(...)`. The
 *  reader library's own (cli_error is its type). */
#define cli_fail meshio_fail

/** Progress on stderr: enabled only when stderr is a terminal and --quiet is off. */
typedef struct cli_progress {
    int enabled;
    double last_draw; /* monotonic seconds of the last redraw */
    int drawn;        /* something is on the line and must be cleared */
    const char *label;
} cli_progress;

void cli_progress_init(cli_progress *progress, int enabled);
/** Redraws "label [####    ] 45%" at most ten times a second. Accepts NULL. */
void cli_progress_update(cli_progress *progress, const char *label, double done, double total);
/** Clears the progress line. Accepts NULL. */
void cli_progress_end(cli_progress *progress);

/** Monotonic wall clock in seconds. */
double cli_now(void);

/**
 * Reads a mesh file with selfcol_meshio (format from its extension, else
 * from its content), drawing the reader's progress on the terminal, then
 * clearing it. Returns 0, or -1 with err set.
 */
int cli_read_mesh(const char *path, meshio_mesh *mesh, cli_error *err, cli_progress *progress);

#include <selfcol/selfcol.h>

/** One entry of a result array: up to 4 indices (as in the JSON) and a distance. */
typedef struct cli_item {
    uint32_t k[4];
    double distance;
} cli_item;

/** The contact sets of one frame, in file indices, ready to print. */
typedef struct cli_sets {
    meshio_array vf, ee, ef, tt; /* cli_item: [v, t], [a0, a1, b0, b1], [a0, a1, t], [t1, t2] */
    selfcol_query_stats stats;   /* summed over the queries of the frame */
} cli_sets;

/** One mesh taking part in a check, with its library handles. */
typedef struct cli_part {
    const char *path;
    meshio_mesh file;           /* as read */
    uint32_t *welded_triangles; /* file triangles through the weld */
    size_t merged_vertices;     /* vertices welded into a lower one */
    selfcol_mesh *mesh;
    selfcol_hierarchy *hierarchy;
    selfcol_sequence *sequence;              /* frames: its self query kept across them, or NULL */
    uint32_t vertex_offset, triangle_offset; /* where its indices start in the output */
    selfcol_context *context; /* --threads N > 1: the command's (borrowed); NULL: one thread */
} cli_part;

/**
 * The self query of a part. With `coherent` (a frame of a sequence) and an
 * exact method, through the part's selfcol_sequence (created at first use):
 * the same contacts as a fresh query, at a fraction of its cost when the
 * surface moves a little from frame to frame. Returns a selfcol_status.
 */
int cli_part_self_collide(cli_part *part, int coherent, selfcol_contacts *contacts,
                          const selfcol_query_options *query);

/** The part's hierarchy refit to its mesh, on its context. Returns a selfcol_status. */
int cli_part_refit(cli_part *part);

/**
 * --threads N: a selfcol_context of N threads into *out, which the
 * command's parts borrow (the library's one place for threads); NULL for
 * one thread. Returns 0, or -1 with err set.
 */
int cli_context_create(unsigned threads, selfcol_context **out, cli_error *err);

void cli_sets_init(cli_sets *sets);
void cli_sets_clear(cli_sets *sets);
void cli_sets_free(cli_sets *sets);

/**
 * Appends the contacts of one query (a self query of parts[i], or the query
 * between parts[0] and parts[1]) to sets, in file indices. classes, if not
 * NULL, receives per output triangle 2 (intersecting) or at least 1 (near a
 * proximity). The intersecting pairs and the classes come from the library
 * (contacts.h), which keeps the pairs in the contact set: not const.
 * Returns 0 or -1 (out of memory).
 */
int cli_sets_add(cli_sets *sets, selfcol_contacts *contacts, cli_part *const parts[2],
                 unsigned char *classes);

/** Sorts every array and removes duplicate triangle pairs. Returns 0 or -1. */
int cli_sets_finish(cli_sets *sets);

/** Describes a run for the JSON object. */
typedef struct cli_run_info {
    const char *method, *narrow;
    double distance, distance_rel; /* distance_rel < 0: given as an absolute distance */
    double mean_edge;
    long frame; /* -1: not a sequence */
    const char *const *files;
    int file_count;
    size_t vertices, triangles, edges, merged_vertices;
    double seconds_load, seconds_topology, seconds_hierarchy, seconds_refit, seconds_query;
} cli_run_info;

void cli_write_json(FILE *out, const cli_run_info *info, const cli_sets *sets);

/** Describes one step of check --continuous for its JSON object. */
typedef struct cli_step_info {
    const char *from_file, *to_file;
    long from, to;     /* frame numbers */
    double separation; /* 0: touching */
    const char *method;
    size_t vertices, triangles, edges, merged_vertices;
    double seconds_load, seconds_refit;
} cli_step_info;

/**
 * Writes one step's colliding pairs as one JSON line: "vf" [v, t, toi,
 * flags] and "ee" [a0, a1, b0, b1, toi, flags] in file indices, sorted as
 * the discrete check's records. Returns 0 or -1 (out of memory).
 */
int cli_write_step_json(FILE *out, const cli_step_info *info, const selfcol_sweep_hit *hits,
                        size_t count, const selfcol_sweep_query_stats *stats);
/** check --continuous --csv: the header, then one row per colliding pair of
 *  a step (step_from,step_to,kind,i0,i1,i2,i3,toi,flags: the JSON's
 *  records, VF (v, t) then EE (a0, a1, b0, b1), in its order). Returns 0, or
 *  -1 when out of memory. */
void cli_write_step_csv_header(FILE *out);
int cli_write_step_csv(FILE *out, long from, long to, const selfcol_sweep_hit *hits, size_t count);
void cli_write_csv_header(FILE *out);
void cli_write_csv(FILE *out, long frame, const cli_sets *sets);
/** Prints a JSON string literal (quotes and escapes included). */
void cli_json_string(FILE *out, const char *s);

/** Opens an output file for writing ("-": stdout). NULL with err set on failure. */
FILE *cli_open_output(const char *path, cli_error *err);
/** Flushes stdout or closes f (NULL: nothing). Returns 0, or -1 with err set on a write error. */
int cli_close_output(FILE *f, const char *path, cli_error *err);
/** Flushes stdout: 1 when anything written to it was lost (errno says why). */
int cli_stdout_write_failed(void);

/**
 * Writes an ASCII PLY with per-face and per-vertex colours from classes
 * (0 plain, 1 proximity, 2 intersecting). Returns 0 or -1 with err set.
 */
int cli_write_marked_ply(const char *path, const double *positions, size_t vertex_count,
                         const uint32_t *triangles, size_t triangle_count,
                         const unsigned char *classes, cli_error *err);

/** View of a picture: angles in degrees, size in pixels (meshio.h). */
typedef meshio_view cli_view;

/** Renders the triangles (flat shaded, z-buffered) coloured by class into a PNG. */
int cli_write_png(const char *path, const double *positions, const uint32_t *triangles,
                  size_t triangle_count, const unsigned char *classes, const cli_view *view,
                  cli_error *err);

#endif /* SELFCOL_CLI_H */
