// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli check: the contacts of one mesh, of two meshes, or of a
// sequence of frames of one topology (hierarchy built once, refit per frame).
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

// Combined geometry of the parts (second mesh's indices after the first's),
// for --png and --mark.
typedef struct joined_mesh {
    double *positions;
    uint32_t *triangles;
    size_t vertex_count, triangle_count;
} joined_mesh;

static int joined_build(joined_mesh *s, cli_part *const *parts, int count) {
    memset(s, 0, sizeof *s);
    for (int i = 0; i < count; ++i) {
        s->vertex_count += parts[i]->file.vertex_count;
        s->triangle_count += parts[i]->file.triangle_count;
    }
    s->positions = malloc(3 * s->vertex_count * sizeof(double) + 1);
    s->triangles = malloc(3 * s->triangle_count * sizeof(uint32_t) + 1);
    if (s->positions == NULL || s->triangles == NULL)
        return -1;
    size_t v = 0, t = 0;
    for (int i = 0; i < count; ++i) {
        const cli_part *p = parts[i];
        memcpy(s->positions + 3 * v, selfcol_mesh_positions(p->mesh),
               3 * p->file.vertex_count * sizeof(double));
        for (size_t j = 0; j < 3 * p->file.triangle_count; ++j)
            s->triangles[3 * t + j] = p->welded_triangles[j] + (uint32_t)v;
        v += p->file.vertex_count;
        t += p->file.triangle_count;
    }
    return 0;
}

static void joined_free(joined_mesh *s) {
    free(s->positions);
    free(s->triangles);
}

static int write_pictures(const cli_options *o, long frame, cli_part *const *parts, int count,
                          const unsigned char *classes, cli_error *err) {
    if (o->mark == NULL && o->png == NULL)
        return 0;
    joined_mesh s;
    if (joined_build(&s, parts, count) != 0) {
        joined_free(&s);
        return cli_fail(err, "out of memory");
    }
    char path[2048];
    int status = 0;
    if (o->mark != NULL) {
        if (cli_output_name(o->mark, frame, path, sizeof path) != 0) {
            joined_free(&s);
            return cli_fail(err, "--mark: the file name is too long");
        }
        status = cli_write_marked_ply(path, s.positions, s.vertex_count, s.triangles,
                                      s.triangle_count, classes, err);
    }
    if (status == 0 && o->png != NULL) {
        if (cli_output_name(o->png, frame, path, sizeof path) != 0) {
            joined_free(&s);
            return cli_fail(err, "--png: the file name is too long");
        }
        status =
            cli_write_png(path, s.positions, s.triangles, s.triangle_count, classes, &o->view, err);
    }
    joined_free(&s);
    return status;
}

typedef struct check_state {
    const cli_options *o;
    FILE *json, *csv, *summary;
    selfcol_contacts *contacts;
    cli_sets sets;
    unsigned char *classes;
    selfcol_query_options query;
    cli_run_info info;
    cli_progress *progress; /* cleared before each summary line */
    long frames_checked, frames_intersecting, frames_near;
    meshio_array intersecting_frames; /* long: frame numbers with interferences */
    int found;                        /* exit status 1 */
    /* --continuous */
    selfcol_sweep *sweep;
    selfcol_context *context; /* --threads N > 1 (the parts borrow it); NULL: one thread */
    double *previous;         /* the positions of the frame before the current one */
    long steps_checked, steps_colliding;
    double earliest; /* least collision-free fraction over the steps */
} check_state;

static void print_summary_header(check_state *st, cli_part *const *parts, int count) {
    if (st->summary == NULL)
        return;
    FILE *s = st->summary;
    fprintf(s, "selfcol-cli %s", selfcol_version_string());
    for (int i = 0; i < count; ++i)
        fprintf(s, "  %s", parts[i]->path);
    fputc('\n', s);
    for (int i = 0; i < count; ++i) {
        const cli_part *p = parts[i];
        fprintf(s, "  %s%s %s: %zu vertices (%zu welded), %zu triangles, %zu edges\n",
                count > 1 ? (i == 0 ? "mesh 1, " : "mesh 2, ") : "",
                meshio_format_name(p->file.format), p->file.format_detail, p->file.vertex_count,
                p->merged_vertices, p->file.triangle_count,
                selfcol_mesh_count(p->mesh, SELFCOL_MESH_EDGES));
    }
    if (st->o->continuous)
        return; // check_step prints what it uses
    if (st->info.distance_rel >= 0)
        fprintf(s, "  detection distance d = %g (%g x mean edge length %g)\n", st->info.distance,
                st->info.distance_rel, st->info.mean_edge);
    else
        fprintf(s, "  detection distance d = %g (mean edge length %g)\n", st->info.distance,
                st->info.mean_edge);
    fprintf(s, "  method %s, narrow phase %s\n", st->info.method, st->info.narrow);
}

// Runs the queries of one frame and writes its outputs.
static int check_frame(check_state *st, cli_part *const *parts, int count, long frame,
                       cli_error *err) {
    const cli_options *o = st->o;
    cli_sets_clear(&st->sets);
    size_t triangles = 0;
    for (int i = 0; i < count; ++i)
        triangles += parts[i]->file.triangle_count;
    if (st->classes)
        memset(st->classes, 0, triangles);
    double start = cli_now();
    for (int q = 0; q < (count == 2 ? 3 : 1); ++q) {
        cli_part *pair[2];
        int rc;
        if (q < count) {
            pair[0] = pair[1] = parts[q];
            rc = cli_part_self_collide(parts[q], o->frames != 0, st->contacts, &st->query);
        } else {
            pair[0] = parts[0];
            pair[1] = parts[1];
            rc = st->context != NULL
                     ? selfcol_context_collide(st->context, parts[0]->hierarchy,
                                               parts[1]->hierarchy, st->contacts, &st->query)
                     : selfcol_hierarchy_collide(parts[0]->hierarchy, parts[1]->hierarchy,
                                                 st->contacts, &st->query);
        }
        if (rc != SELFCOL_OK)
            return cli_fail(err, "query failed: %s", selfcol_status_string(rc));
        if (cli_sets_add(&st->sets, st->contacts, pair, st->classes) != 0)
            return cli_fail(err, "out of memory");
    }
    cli_sets_finish(&st->sets);
    st->info.seconds_query = cli_now() - start;
    st->info.frame = o->frames ? frame : -1;
    if (st->json)
        cli_write_json(st->json, &st->info, &st->sets);
    if (st->csv)
        cli_write_csv(st->csv, o->frames ? frame : 0, &st->sets);
    size_t proximities = st->sets.vf.count + st->sets.ee.count;
    int intersects = st->sets.ef.count > 0;
    st->frames_checked++;
    st->frames_intersecting += intersects;
    if (intersects && meshio_array_reserve(&st->intersecting_frames, 1) == 0)
        ((long *)st->intersecting_frames.data)[st->intersecting_frames.count++] = frame;
    st->frames_near += proximities > 0;
    if (intersects || (o->fail_on_proximity && proximities > 0))
        st->found = 1;
    if (st->summary) {
        FILE *s = st->summary;
        cli_progress_end(st->progress);
        if (o->frames)
            fprintf(s, "  frame %ld (%s): ", frame, parts[0]->path);
        else
            fputs("  ", s);
        fprintf(s,
                "VF proximities %zu, EE proximities %zu, EF interferences %zu, intersecting "
                "triangle pairs %zu\n",
                st->sets.vf.count, st->sets.ee.count, st->sets.ef.count, st->sets.tt.count);
        if (!o->frames)
            fprintf(s,
                    "  time: load %.1f ms, topology %.1f ms, hierarchy %.1f ms, query %.1f ms "
                    "(broad %.1f, narrow %.1f)\n",
                    1e3 * st->info.seconds_load, 1e3 * st->info.seconds_topology,
                    1e3 * st->info.seconds_hierarchy, 1e3 * st->info.seconds_query,
                    1e3 * st->sets.stats.broad_seconds, 1e3 * st->sets.stats.narrow_seconds);
    }
    return write_pictures(o, frame, parts, count, st->classes, err);
}

// The method of --continuous: the continuous query's own default is BVH
// (sweep.h: EXACT over a step costs more than it saves on real steps), so
// --method exact must be asked for; check_usage refused seed and cone,
// which have no continuous query.
static uint32_t continuous_method(const cli_options *o) {
    return o->method_given ? o->method : SELFCOL_METHOD_BVH;
}

// --continuous: the continuous self-query of the step from frame `from` (the
// positions in st->previous, read from from_file) to frame `to` (the mesh's
// current positions, read from to_file).
static int check_step(check_state *st, cli_part *part, long from, long to, const char *from_file,
                      const char *to_file, cli_error *err) {
    const cli_options *o = st->o;
    selfcol_sweep_options so;
    selfcol_sweep_options_init(&so, SELFCOL_SWEEP_OPTIONS_VERSION);
    so.method = continuous_method(o);
    so.separation = o->distance_given ? o->distance : 0.0;
    const int rc =
        st->context != NULL
            ? selfcol_context_self_sweep(st->context, part->hierarchy, st->previous, st->sweep, &so)
            : selfcol_hierarchy_self_sweep(part->hierarchy, st->previous, st->sweep, &so);
    if (rc != SELFCOL_OK)
        return cli_fail(err, "continuous query failed: %s", selfcol_status_string(rc));
    const selfcol_sweep_hit *hits;
    size_t n;
    selfcol_sweep_hits(st->sweep, &hits, &n);
    selfcol_sweep_query_stats stats;
    stats.version = SELFCOL_SWEEP_STATS_VERSION;
    selfcol_sweep_stats(st->sweep, &stats);
    size_t vf = 0;
    for (size_t i = 0; i < n; ++i)
        vf += hits[i].kind == SELFCOL_CONTACT_VF;
    st->steps_checked++;
    st->steps_colliding += n > 0;
    st->earliest = stats.free_fraction < st->earliest ? stats.free_fraction : st->earliest;
    if (n > 0)
        st->found = 1;
    if (st->json) {
        cli_step_info info;
        info.from_file = from_file;
        info.to_file = to_file;
        info.from = from;
        info.to = to;
        info.separation = so.separation;
        info.method = cli_method_names[so.method];
        info.vertices = st->info.vertices;
        info.triangles = st->info.triangles;
        info.edges = st->info.edges;
        info.merged_vertices = st->info.merged_vertices;
        info.seconds_load = st->info.seconds_load;
        info.seconds_refit = st->info.seconds_refit;
        if (cli_write_step_json(st->json, &info, hits, n, &stats) != 0)
            return cli_fail(err, "out of memory");
    }
    if (st->csv && cli_write_step_csv(st->csv, from, to, hits, n) != 0)
        return cli_fail(err, "out of memory");
    if (st->summary) {
        cli_progress_end(st->progress);
        fprintf(st->summary,
                "  step %ld -> %ld: %zu pairs collide (VF %zu, EE %zu); collision-free "
                "fraction %.6g; %.1f ms\n",
                from, to, n, vf, n - vf, stats.free_fraction, 1e3 * stats.total_seconds);
    }
    return 0;
}

// "frames with interferences: 3, 5-9, 12": runs of consecutive frames of the
// sequence (in --range steps) as FIRST-LAST.
int cli_detection_distance(const cli_options *o, double mean_edge, double *distance,
                           cli_error *err) {
    *distance = o->distance_given ? o->distance : o->distance_rel * mean_edge;
    if (*distance <= SELFCOL_MESH_MAX_COORDINATE)
        return 0;
    if (o->distance_given)
        return cli_fail(err, "--distance %g is above the largest the library accepts (%g)",
                        o->distance, SELFCOL_MESH_MAX_COORDINATE);
    return cli_fail(err,
                    "--distance-rel %g x mean edge length %g = %g is above the largest "
                    "distance the library accepts (%g)",
                    o->distance_rel, mean_edge, *distance, SELFCOL_MESH_MAX_COORDINATE);
}

// What went to stdout (summaries, lines): a full disk or a closed pipe there
// is an error too, not a silent exit status.
int cli_finish(int exit_code, cli_error *err) {
    if (exit_code != CLI_EXIT_ERROR && cli_stdout_write_failed()) {
        cli_fail(err, "cannot write to standard output: %s", strerror(errno ? errno : EIO));
        exit_code = CLI_EXIT_ERROR;
    }
    if (exit_code == CLI_EXIT_ERROR)
        fprintf(stderr, "selfcol-cli: %s\n", err->message);
    return exit_code;
}

void cli_print_weld_warning(FILE *out, size_t split_frames) {
    if (split_frames)
        fprintf(out,
                "  warning: in %zu frame(s) vertices welded in the first frame have "
                "moved apart (the weld keeps the first frame's topology)\n",
                split_frames);
}

void cli_print_frame_list(FILE *out, const meshio_array *frames, const long *sequence,
                          long sequence_count) {
    const long *f = frames->data;
    if (frames->count == 0)
        return;
    fputs("  frames with interferences:", out);
    size_t i = 0;
    long at = 0; // position of f[i] in the sequence
    while (i < frames->count) {
        while (at < sequence_count && sequence[at] != f[i])
            ++at;
        size_t j = i;
        while (j + 1 < frames->count && at + (long)(j - i) + 1 < sequence_count &&
               sequence[at + (long)(j - i) + 1] == f[j + 1])
            ++j;
        if (j > i)
            fprintf(out, "%s %ld-%ld", i ? "," : "", f[i], f[j]);
        else
            fprintf(out, "%s %ld", i ? "," : "", f[i]);
        at += (long)(j - i) + 1;
        i = j + 1;
    }
    fputc('\n', out);
}

static double combined_mean_edge(cli_part *const *parts, int count) {
    double sum = 0.0, edges = 0.0;
    for (int i = 0; i < count; ++i) {
        double e = (double)selfcol_mesh_count(parts[i]->mesh, SELFCOL_MESH_EDGES);
        sum += e * selfcol_mesh_mean_edge_length(parts[i]->mesh);
        edges += e;
    }
    return edges > 0 ? sum / edges : 0.0;
}

// 0 when a later frame has the first frame's vertex count and triangles,
// else -1 with a message naming what differs: the counts, or the first
// triangle whose vertices differ.
static int frame_topology_differs(const char *path, const meshio_mesh *next,
                                  const meshio_mesh *first, cli_error *err) {
    if (next->vertex_count != first->vertex_count)
        return cli_fail(err,
                        "%s: %zu vertices; the first frame has %zu (frames must share one "
                        "topology)",
                        path, next->vertex_count, first->vertex_count);
    if (next->triangle_count != first->triangle_count)
        return cli_fail(err,
                        "%s: %zu triangles; the first frame has %zu (frames must share one "
                        "topology)",
                        path, next->triangle_count, first->triangle_count);
    for (size_t t = 0; t < next->triangle_count; ++t) {
        const uint32_t *a = next->triangles + 3 * t, *b = first->triangles + 3 * t;
        if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
            return cli_fail(err,
                            "%s: triangle %zu is (%lu %lu %lu); in the first frame it is "
                            "(%lu %lu %lu) (frames must share one topology)",
                            path, t, (unsigned long)a[0], (unsigned long)a[1], (unsigned long)a[2],
                            (unsigned long)b[0], (unsigned long)b[1], (unsigned long)b[2]);
    }
    return 0;
}

// Positions of a later frame: same vertex count and triangles as frame 0.
int cli_load_next_frame(cli_part *part, const char *path, cli_progress *progress,
                        size_t *split_groups, cli_error *err) {
    meshio_mesh next;
    if (cli_read_mesh(path, &next, err, progress) != 0)
        return -1;
    int status = frame_topology_differs(path, &next, &part->file, err);
    if (status == 0) {
        int rc = selfcol_mesh_set_positions(part->mesh, next.positions, next.vertex_count);
        if (rc != SELFCOL_OK)
            status = cli_fail_mesh(err, path, rc, next.positions, next.vertex_count, NULL, 0);
    }
    // The weld was decided on the first frame. A welded vertex that moved
    // away from its group's representative is a seam that tore: count them.
    if (status == 0) {
        const uint32_t *file_tris = part->file.triangles;
        for (size_t i = 0; i < 3 * next.triangle_count; ++i) {
            uint32_t v = file_tris[i], r = part->welded_triangles[i];
            if (v != r && memcmp(next.positions + 3 * (size_t)v, next.positions + 3 * (size_t)r,
                                 3 * sizeof(double)) != 0) {
                ++*split_groups;
                break;
            }
        }
    }
    meshio_mesh_free(&next);
    return status;
}

// Usage errors that depend on several options. Returns 0 or the status.
static int check_usage(const cli_options *o, int sequence) {
    if (o->input_count == 0)
        return cli_usage_error("check ", "no mesh given%s", "");
    if (!sequence && o->input_count > 2)
        return cli_usage_error("check ",
                               "check takes one or two meshes; for frames of one mesh use --frames "
                               "or --range (got %s)",
                               "more");
    if (o->continuous && !sequence)
        return cli_usage_error("check ",
                               "--continuous checks the steps between frames: give them with "
                               "--frames or --range%s",
                               "");
    if (o->continuous && o->method_given &&
        (o->method == SELFCOL_METHOD_SEED || o->method == SELFCOL_METHOD_CONE))
        return cli_usage_error("check ",
                               "--continuous has no method %s (continuous queries: bvh, the "
                               "default, exact or exhaustive)",
                               cli_method_names[o->method]);
    if (o->continuous && (o->mark || o->png))
        return cli_usage_error("check ",
                               "--continuous writes no %s (only the summary, --json and --csv)",
                               o->mark ? "--mark" : "--png");
    return 0;
}

// The inputs of one check: the meshes (two at most; one for a sequence) and
// the frames of a sequence.
typedef struct check_inputs {
    int sequence, count;
    cli_part storage[2];
    cli_part *parts[2];
    const char *files[2];
    char **frame_names;
    long *frame_numbers;
    long frame_count;
    size_t split_frames; /* frames where a welded group came apart */
} check_inputs;

// Outputs first, so a bad output path fails before a long run: no two
// outputs (nor an output and an input) name one file, each can be written.
// Then the summary's stream, and the JSON and CSV files opened.
static int open_outputs(check_state *st, const check_inputs *in, cli_error *err) {
    const cli_options *o = st->o;
    const cli_output_file outputs[4] = {
        {"--json", o->json, 0}, {"--csv", o->csv, 0}, {"--mark", o->mark, 1}, {"--png", o->png, 1}};
    const long single_frame = 0;
    if (cli_check_outputs("check ", outputs, 4,
                          in->sequence ? (const char *const *)in->frame_names : o->inputs,
                          in->sequence ? in->frame_count : o->input_count,
                          in->sequence ? in->frame_numbers : &single_frame,
                          in->sequence ? in->frame_count : 1, err) != 0)
        return -1;
    int stdout_taken =
        (o->json && strcmp(o->json, "-") == 0) || (o->csv && strcmp(o->csv, "-") == 0);
    st->summary = o->quiet ? NULL : stdout_taken ? stderr : stdout;
    if (o->json && (st->json = cli_open_output(o->json, err)) == NULL)
        return -1;
    if (o->csv && (st->csv = cli_open_output(o->csv, err)) == NULL)
        return -1;
    if (st->csv && o->continuous)
        cli_write_step_csv_header(st->csv);
    else if (st->csv)
        cli_write_csv_header(st->csv);
    return 0;
}

// Reads the meshes (the first frame of a sequence), welds them and builds
// their hierarchies, timing each stage into st->info.
static int load_parts(check_state *st, check_inputs *in, cli_error *err) {
    const cli_options *o = st->o;
    cli_part *const *parts = in->parts;
    double t0 = cli_now();
    for (int i = 0; i < in->count; ++i) {
        parts[i]->path = in->sequence ? in->frame_names[0] : o->inputs[i];
        in->files[i] = parts[i]->path;
        if (cli_read_mesh(parts[i]->path, &parts[i]->file, err, st->progress) != 0)
            return -1;
    }
    st->info.seconds_load = cli_now() - t0;
    if (cli_context_create(o->threads, &st->context, err) != 0)
        return -1;
    for (int i = 0; i < in->count; ++i)
        if (cli_part_create(parts[i], o->no_weld, 1, st->context, &st->info.seconds_topology,
                            &st->info.seconds_hierarchy, err) != 0)
            return -1;
    parts[1]->vertex_offset = (uint32_t)parts[0]->file.vertex_count;
    parts[1]->triangle_offset = (uint32_t)parts[0]->file.triangle_count;
    if (in->count == 2 && (uint64_t)parts[0]->file.vertex_count + parts[1]->file.vertex_count >=
                              (uint64_t)UINT32_MAX - 1)
        return cli_fail(err, "the two meshes have too many vertices together");
    return 0;
}

// The query options, the run's description for the outputs, and the
// buffers the queries write into.
static int prepare_queries(check_state *st, check_inputs *in, cli_error *err) {
    const cli_options *o = st->o;
    int rc = selfcol_contacts_create(&st->contacts, NULL);
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s", selfcol_status_string(rc));
    selfcol_query_options_init(&st->query, SELFCOL_QUERY_OPTIONS_VERSION);
    st->query.method = o->method;
    st->query.narrow = o->narrow;
    st->info.mean_edge = combined_mean_edge(in->parts, in->count);
    st->info.distance_rel = o->distance_given ? -1.0 : o->distance_rel;
    if (cli_detection_distance(o, st->info.mean_edge, &st->info.distance, err) != 0)
        return -1;
    st->query.distance = st->info.distance;
    st->info.method = cli_method_names[o->method];
    st->info.narrow = cli_narrow_names[o->narrow];
    st->info.files = in->files;
    st->info.file_count = in->count;
    for (int i = 0; i < in->count; ++i) {
        st->info.vertices += in->parts[i]->file.vertex_count;
        st->info.triangles += in->parts[i]->file.triangle_count;
        st->info.edges += selfcol_mesh_count(in->parts[i]->mesh, SELFCOL_MESH_EDGES);
        st->info.merged_vertices += in->parts[i]->merged_vertices;
    }
    if (o->mark || o->png) {
        st->classes = malloc(st->info.triangles + 1);
        if (st->classes == NULL)
            return cli_fail(err, "out of memory");
    }
    print_summary_header(st, in->parts, in->count);
    if (o->continuous) {
        st->earliest = 1.0;
        rc = selfcol_sweep_create(&st->sweep, NULL);
        st->previous = malloc(3 * in->parts[0]->file.vertex_count * sizeof(double) + 1);
        if (rc != SELFCOL_OK || st->previous == NULL)
            return cli_fail(err, "out of memory");
        if (st->summary)
            fprintf(st->summary,
                    "  continuous: each step between consecutive frames, separation %g%s, "
                    "method %s\n",
                    o->distance_given ? o->distance : 0.0, o->distance_given ? "" : " (touching)",
                    cli_method_names[continuous_method(o)]);
    }
    return 0;
}

// Frame f of a sequence after the first: its positions into the mesh (the
// previous ones kept for --continuous) and the hierarchy refit.
static int advance_frame(check_state *st, check_inputs *in, long f, cli_error *err) {
    cli_part *part = in->parts[0];
    const char *name = in->frame_names[f];
    if (st->o->continuous)
        memcpy(st->previous, selfcol_mesh_positions(part->mesh),
               3 * part->file.vertex_count * sizeof(double));
    double start = cli_now();
    part->path = name;
    in->files[0] = name;
    if (cli_load_next_frame(part, name, st->progress, &in->split_frames, err))
        return -1;
    st->info.seconds_load = cli_now() - start;
    start = cli_now();
    int rc = cli_part_refit(part);
    st->info.seconds_refit = cli_now() - start;
    st->info.seconds_topology = st->info.seconds_hierarchy = 0.0;
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: %s", name, selfcol_status_string(rc));
    return 0;
}

// Every frame of a sequence (or step, with --continuous), then the
// sequence's summary lines.
static int check_sequence(check_state *st, check_inputs *in, cli_error *err) {
    const cli_options *o = st->o;
    for (long f = 0; f < in->frame_count; ++f) {
        if (f > 0 && advance_frame(st, in, f, err) != 0)
            return -1;
        cli_progress_update(st->progress, "frames", (double)f, (double)in->frame_count);
        if (o->continuous) {
            if (f > 0 &&
                check_step(st, in->parts[0], in->frame_numbers[f - 1], in->frame_numbers[f],
                           in->frame_names[f - 1], in->frame_names[f], err) != 0)
                return -1;
            continue;
        }
        if (check_frame(st, in->parts, 1, in->frame_numbers[f], err) != 0)
            return -1;
    }
    cli_progress_end(st->progress);
    if (st->summary && o->continuous) {
        fprintf(st->summary,
                "  %ld step(s): %ld with colliding pairs; least collision-free fraction "
                "%.6g\n",
                st->steps_checked, st->steps_colliding, st->earliest);
        cli_print_weld_warning(st->summary, in->split_frames);
    } else if (st->summary) {
        fprintf(st->summary, "  %ld frame(s): %ld with interferences, %ld with proximities\n",
                st->frames_checked, st->frames_intersecting, st->frames_near);
        cli_print_frame_list(st->summary, &st->intersecting_frames, in->frame_numbers,
                             in->frame_count);
        cli_print_weld_warning(st->summary, in->split_frames);
    }
    return 0;
}

// The result line, and the JSON and CSV files closed (a write error there
// is an error of the run).
static int finish_outputs(check_state *st, cli_error *err) {
    const cli_options *o = st->o;
    if (st->summary && o->continuous)
        fprintf(st->summary, "  result: %s (exit status %d)\n",
                st->steps_colliding ? "COLLIDES WITHIN A STEP" : "clean",
                st->found ? CLI_EXIT_FOUND : CLI_EXIT_CLEAN);
    else if (st->summary)
        fprintf(st->summary, "  result: %s (exit status %d)\n",
                st->frames_intersecting ? "INTERSECTS"
                : st->frames_near       ? "no interference, proximities found"
                                        : "clean",
                st->found ? CLI_EXIT_FOUND : CLI_EXIT_CLEAN);
    FILE *json = st->json, *csv = st->csv;
    st->json = st->csv = NULL;
    if (cli_close_output(json, o->json, err) != 0) {
        if (csv && csv != stdout)
            fclose(csv);
        return -1;
    }
    return cli_close_output(csv, o->csv, err);
}

static void free_check(check_state *st, check_inputs *in) {
    if (st->json && st->json != stdout)
        fclose(st->json);
    if (st->csv && st->csv != stdout)
        fclose(st->csv);
    selfcol_contacts_destroy(st->contacts);
    selfcol_sweep_destroy(st->sweep);
    free(st->previous);
    cli_sets_free(&st->sets);
    free(st->intersecting_frames.data);
    free(st->classes);
    cli_part_free(in->parts[0]);
    cli_part_free(in->parts[1]);
    selfcol_context_destroy(st->context); // after the parts that borrow it
    for (long i = 0; in->frame_names && i < in->frame_count; ++i)
        free(in->frame_names[i]);
    free(in->frame_names);
    free(in->frame_numbers);
}

// One check, from the frame list to the closed outputs. Returns 0, or -1
// with err set.
static int run_check(check_state *st, check_inputs *in, cli_error *err) {
    if (in->sequence &&
        cli_frame_list(st->o, &in->frame_names, &in->frame_numbers, &in->frame_count, err) != 0)
        return -1;
    if (open_outputs(st, in, err) != 0 || load_parts(st, in, err) != 0 ||
        prepare_queries(st, in, err) != 0)
        return -1;
    int rc =
        in->sequence ? check_sequence(st, in, err) : check_frame(st, in->parts, in->count, 0, err);
    if (rc != 0)
        return -1;
    return finish_outputs(st, err);
}

int cli_command_check(const cli_options *o) {
    int sequence = o->frames || o->range != NULL;
    int usage = check_usage(o, sequence);
    if (usage != 0)
        return usage;
    cli_options local = *o;
    local.frames = sequence;
    o = &local;

    cli_error err;
    err.message[0] = '\0';
    cli_progress progress;
    cli_progress_init(&progress, !o->quiet);
    check_state st;
    memset(&st, 0, sizeof st);
    st.o = o;
    st.progress = &progress;
    st.intersecting_frames.item_size = sizeof(long);
    cli_sets_init(&st.sets);
    check_inputs in;
    memset(&in, 0, sizeof in);
    in.sequence = sequence;
    in.count = sequence ? 1 : o->input_count;
    in.parts[0] = &in.storage[0];
    in.parts[1] = &in.storage[1];

    int exit_code = CLI_EXIT_ERROR;
    if (run_check(&st, &in, &err) == 0)
        exit_code = st.found ? CLI_EXIT_FOUND : CLI_EXIT_CLEAN;
    cli_progress_end(&progress);
    exit_code = cli_finish(exit_code, &err);
    free_check(&st, &in);
    return exit_code;
}
