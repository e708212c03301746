// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-cli track: a sequence of frames of one topology through the
// persistent contact store (include/selfcol/store.h). Per frame: positions,
// refit (the hierarchy is built on the first frame), the self query as check
// runs it, selfcol_store_update(), and one line (and one JSON object) with the
// store's counters; then which frames intersect and the worst one.
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <stdlib.h>
#include <string.h>

typedef struct track_state {
    const cli_options *o;
    FILE *jsonl; /* --jsonl, or NULL */
    FILE *lines; /* per-frame lines and summary: stdout, stderr, or NULL (--quiet) */
    cli_progress *progress;
    cli_part *part;
    selfcol_contacts *contacts;
    selfcol_store *store;
    selfcol_context *context; /* --threads N > 1 (the part borrows it); NULL: one thread */
    selfcol_query_options query;
    double distance, distance_rel, mean_edge; /* distance_rel < 0: --distance given */
    cli_sets sets;                            /* only to colour pictures as check does */
    unsigned char *classes;                   /* per triangle, for pictures; NULL without them */
    long frames_done, frames_intersecting, frames_with_contacts;
    meshio_array intersecting_frames; /* long: frame numbers with interferences */
    /* The worst frame: most interferences, then most contacts, then the first. */
    long worst;       /* position in the sequence; -1 before the first frame */
    long worst_frame; /* its frame number */
    uint64_t worst_interferences, worst_contacts, worst_crossed;
    double *worst_positions; /* --png-worst: its positions and triangle classes */
    unsigned char *worst_classes;
} track_state;

// Classes of the triangles for a picture (2 intersecting, 1 near a
// proximity), from the query's contacts exactly as check colours them.
static int classify(track_state *st, cli_error *err) {
    cli_part *pair[2] = {st->part, st->part};
    cli_sets_clear(&st->sets);
    memset(st->classes, 0, st->part->file.triangle_count);
    if (cli_sets_add(&st->sets, st->contacts, pair, st->classes) != 0)
        return cli_fail(err, "out of memory");
    return 0;
}

static int draw(track_state *st, const char *pattern, long frame, const double *positions,
                const unsigned char *classes, const char *option, cli_error *err) {
    char path[2048];
    if (cli_output_name(pattern, frame, path, sizeof path) != 0)
        return cli_fail(err, "%s: the file name is too long", option);
    return cli_write_png(path, positions, st->part->welded_triangles, st->part->file.triangle_count,
                         classes, &st->o->view, err);
}

static void write_json_line(track_state *st, long frame, const char *name,
                            const selfcol_store_update_stats *s, const size_t detected[3],
                            double query_seconds) {
    FILE *out = st->jsonl;
    fputs("{\"selfcol_version\":", out);
    cli_json_string(out, selfcol_version_string());
    fprintf(out, ",\"frame\":%ld,\"file\":", frame);
    cli_json_string(out, name);
    fprintf(out, ",\"distance\":%.17g", st->distance);
    fprintf(out,
            ",\"contacts\":%llu,\"regions\":%llu,\"new\":%llu,\"kept\":%llu,\"remnant\":%llu,"
            "\"dropped\":%llu,\"flipped\":%llu,\"corrected\":%llu,\"corrected_regions\":%llu,"
            "\"interferences\":%llu,\"crossed_regions\":%llu",
            (unsigned long long)s->contacts, (unsigned long long)s->regions,
            (unsigned long long)s->new_contacts, (unsigned long long)s->kept,
            (unsigned long long)s->remnant, (unsigned long long)s->dropped,
            (unsigned long long)s->flipped, (unsigned long long)s->corrected,
            (unsigned long long)s->corrected_regions, (unsigned long long)s->interferences,
            (unsigned long long)s->crossed_regions);
    fprintf(out, ",\"detected\":{\"vf\":%zu,\"ee\":%zu,\"ef\":%zu}", detected[0], detected[1],
            detected[2]);
    fprintf(out, ",\"query_ms\":%.6f,\"store_ms\":%.6f}\n", 1e3 * query_seconds, 1e3 * s->seconds);
}

// Query, store update and outputs of one frame (its positions are set and
// the hierarchy is current).
static int track_frame(track_state *st, long index, long frame, const char *name, cli_error *err) {
    const cli_options *o = st->o;
    double start = cli_now();
    int rc = cli_part_self_collide(st->part, 1, st->contacts, &st->query);
    double query_seconds = cli_now() - start;
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: query failed: %s", name, selfcol_status_string(rc));
    const selfcol_contact *c;
    size_t n;
    size_t detected[3] = {0, 0, 0}; /* VF, EE, EF as the query reported them */
    if (selfcol_contacts_data(st->contacts, &c, &n) != SELFCOL_OK)
        return cli_fail(err, "%s: cannot read the contacts", name);
    for (size_t i = 0; i < n; ++i)
        if (c[i].kind <= SELFCOL_CONTACT_EF)
            detected[c[i].kind]++;
    rc = st->context != NULL ? selfcol_context_store_update(st->context, st->store, st->part->mesh,
                                                            NULL, st->contacts)
                             : selfcol_store_update(st->store, st->part->mesh, NULL, st->contacts);
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: store update failed: %s", name, selfcol_status_string(rc));
    selfcol_store_update_stats s;
    memset(&s, 0, sizeof s);
    s.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    rc = selfcol_store_stats(st->store, &s);
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: store statistics: %s", name, selfcol_status_string(rc));

    if (st->jsonl)
        write_json_line(st, frame, name, &s, detected, query_seconds);
    if (st->lines) {
        cli_progress_end(st->progress);
        fprintf(st->lines,
                "  frame %ld (%s): contacts %llu, regions %llu, new %llu, remnant %llu, flipped "
                "%llu, corrected %llu (%llu regions), interferences %llu, crossed regions %llu; "
                "query %.1f ms, store %.1f ms\n",
                frame, name, (unsigned long long)s.contacts, (unsigned long long)s.regions,
                (unsigned long long)s.new_contacts, (unsigned long long)s.remnant,
                (unsigned long long)s.flipped, (unsigned long long)s.corrected,
                (unsigned long long)s.corrected_regions, (unsigned long long)s.interferences,
                (unsigned long long)s.crossed_regions, 1e3 * query_seconds, 1e3 * s.seconds);
    }
    st->frames_done++;
    st->frames_with_contacts += s.contacts > 0;
    if (s.interferences > 0) {
        st->frames_intersecting++;
        if (meshio_array_reserve(&st->intersecting_frames, 1) != 0)
            return cli_fail(err, "out of memory");
        ((long *)st->intersecting_frames.data)[st->intersecting_frames.count++] = frame;
    }
    int worse = st->worst < 0 || s.interferences > st->worst_interferences ||
                (s.interferences == st->worst_interferences && s.contacts > st->worst_contacts);
    if (worse) {
        st->worst = index;
        st->worst_frame = frame;
        st->worst_interferences = s.interferences;
        st->worst_contacts = s.contacts;
        st->worst_crossed = s.crossed_regions;
    }
    int classified = 0;
    if (o->png != NULL) {
        if (classify(st, err) != 0)
            return -1;
        classified = 1;
        if (draw(st, o->png, frame, selfcol_mesh_positions(st->part->mesh), st->classes, "--png",
                 err) != 0)
            return -1;
    }
    if (o->png_worst != NULL && worse) {
        if (!classified && classify(st, err) != 0)
            return -1;
        memcpy(st->worst_positions, selfcol_mesh_positions(st->part->mesh),
               3 * st->part->file.vertex_count * sizeof(double));
        memcpy(st->worst_classes, st->classes, st->part->file.triangle_count);
    }
    return 0;
}

static void print_header(const track_state *st) {
    FILE *s = st->lines;
    const cli_part *p = st->part;
    fprintf(s, "selfcol-cli %s track  %s\n", selfcol_version_string(), p->path);
    fprintf(s, "  %s %s: %zu vertices (%zu welded), %zu triangles, %zu edges\n",
            meshio_format_name(p->file.format), p->file.format_detail, p->file.vertex_count,
            p->merged_vertices, p->file.triangle_count,
            selfcol_mesh_count(p->mesh, SELFCOL_MESH_EDGES));
    if (st->distance_rel >= 0)
        fprintf(s, "  detection distance d = %g (%g x mean edge length %g)\n", st->distance,
                st->distance_rel, st->mean_edge);
    else
        fprintf(s, "  detection distance d = %g (mean edge length %g)\n", st->distance,
                st->mean_edge);
    fprintf(s, "  method %s, narrow phase %s; store: remnance %lu, consistency %s\n",
            cli_method_names[st->o->method], cli_narrow_names[st->o->narrow],
            (unsigned long)st->o->remnance, st->o->no_consistency ? "off" : "on");
}

// The track's store, query options, distance and picture buffers, from the
// first frame's part. Returns 0, or -1 with err set.
static int track_setup(track_state *st, cli_error *err) {
    const cli_options *o = st->o;
    int rc = selfcol_contacts_create(&st->contacts, NULL);
    if (rc == SELFCOL_OK) {
        selfcol_store_options so;
        selfcol_store_options_init(&so, SELFCOL_STORE_OPTIONS_VERSION);
        so.remnance_frames = o->remnance;
        so.consistency = o->no_consistency ? 0 : 1;
        rc = selfcol_store_create(&st->store, &so);
    }
    if (rc != SELFCOL_OK) {
        cli_fail(err, "%s", selfcol_status_string(rc));
        return -1;
    }
    selfcol_query_options_init(&st->query, SELFCOL_QUERY_OPTIONS_VERSION);
    st->query.method = o->method;
    st->query.narrow = o->narrow;
    st->query.kinds = SELFCOL_KIND_ALL;
    st->mean_edge = selfcol_mesh_mean_edge_length(st->part->mesh);
    st->distance_rel = o->distance_given ? -1.0 : o->distance_rel;
    if (cli_detection_distance(o, st->mean_edge, &st->distance, err) != 0)
        return -1;
    st->query.distance = st->distance;
    if (o->png || o->png_worst) {
        st->classes = malloc(st->part->file.triangle_count + 1);
        if (st->classes == NULL) {
            cli_fail(err, "out of memory");
            return -1;
        }
    }
    if (o->png_worst) {
        st->worst_positions = malloc(3 * st->part->file.vertex_count * sizeof(double) + 1);
        st->worst_classes = malloc(st->part->file.triangle_count + 1);
        if (st->worst_positions == NULL || st->worst_classes == NULL) {
            cli_fail(err, "out of memory");
            return -1;
        }
    }
    return 0;
}

// The human summary after the last frame.
static void print_summary(const track_state *st, char *const *frame_names,
                          const long *frame_numbers, long frame_count, size_t split_frames) {
    FILE *s = st->lines;
    fprintf(s, "  %ld frame(s): %ld with interferences\n", st->frames_done,
            st->frames_intersecting);
    cli_print_frame_list(s, &st->intersecting_frames, frame_numbers, frame_count);
    if (st->frames_intersecting > 0)
        fprintf(s, "  worst frame: %ld (%s), %llu interferences, %llu crossed region(s)\n",
                st->worst_frame, frame_names[st->worst],
                (unsigned long long)st->worst_interferences, (unsigned long long)st->worst_crossed);
    cli_print_weld_warning(s, split_frames);
    fprintf(s, "  result: %s (exit status %d)\n",
            st->frames_intersecting    ? "INTERSECTS"
            : st->frames_with_contacts ? "no interference, contacts found"
                                       : "clean",
            st->frames_intersecting ? CLI_EXIT_FOUND : CLI_EXIT_CLEAN);
}

int cli_command_track(const cli_options *o) {
    if (o->input_count == 0)
        return cli_usage_error("track ", "no frame given%s", "");
    cli_error err;
    err.message[0] = '\0';
    int exit_code = CLI_EXIT_ERROR;
    cli_progress progress;
    cli_progress_init(&progress, !o->quiet);
    cli_part part;
    memset(&part, 0, sizeof part);
    track_state st;
    memset(&st, 0, sizeof st);
    st.o = o;
    st.progress = &progress;
    st.part = &part;
    st.worst = -1;
    st.intersecting_frames.item_size = sizeof(long);
    cli_sets_init(&st.sets);
    char **frame_names = NULL;
    long *frame_numbers = NULL;
    long frame_count = 0;
    size_t split_frames = 0;
    int rc;

    if (cli_frame_list(o, &frame_names, &frame_numbers, &frame_count, &err) != 0)
        goto done;
    // Before any file is opened or any frame read: no two outputs (nor an
    // output and a frame) name one file, and every output can be written.
    const cli_output_file outputs[3] = {
        {"--jsonl", o->jsonl, 0}, {"--png", o->png, 1}, {"--png-worst", o->png_worst, 1}};
    if (cli_check_outputs("track ", outputs, 3, (const char *const *)frame_names, frame_count,
                          frame_numbers, frame_count, &err) != 0)
        goto done;
    // The JSON lines take standard output when asked to; the human lines
    // then go to standard error (as check's summary does).
    if (o->jsonl && (st.jsonl = cli_open_output(o->jsonl, &err)) == NULL)
        goto done;
    st.lines = o->quiet ? NULL : st.jsonl == stdout ? stderr : stdout;

    part.path = frame_names[0];
    if (cli_read_mesh(part.path, &part.file, &err, &progress) != 0)
        goto done;
    double seconds_topology = 0.0, seconds_hierarchy = 0.0;
    if (cli_context_create(o->threads, &st.context, &err) != 0 ||
        cli_part_create(&part, o->no_weld, 1, st.context, &seconds_topology, &seconds_hierarchy,
                        &err) != 0)
        goto done;

    if (track_setup(&st, &err) != 0)
        goto done;
    if (st.lines)
        print_header(&st);

    for (long f = 0; f < frame_count; ++f) {
        if (f > 0) {
            if (cli_load_next_frame(&part, frame_names[f], &progress, &split_frames, &err) != 0)
                goto done;
            rc = cli_part_refit(&part);
            if (rc != SELFCOL_OK) {
                cli_fail(&err, "%s: %s", frame_names[f], selfcol_status_string(rc));
                goto done;
            }
        }
        cli_progress_update(&progress, "frames", (double)f, (double)frame_count);
        if (track_frame(&st, f, frame_numbers[f], frame_names[f], &err) != 0)
            goto done;
    }
    cli_progress_end(&progress);
    if (o->png_worst && draw(&st, o->png_worst, st.worst_frame, st.worst_positions,
                             st.worst_classes, "--png-worst", &err) != 0)
        goto done;

    if (st.lines)
        print_summary(&st, frame_names, frame_numbers, frame_count, split_frames);
    if (cli_close_output(st.jsonl, o->jsonl, &err) != 0) {
        st.jsonl = NULL;
        goto done;
    }
    st.jsonl = NULL;
    exit_code = st.frames_intersecting ? CLI_EXIT_FOUND : CLI_EXIT_CLEAN;
done:
    cli_progress_end(&progress);
    exit_code = cli_finish(exit_code, &err);
    if (st.jsonl && st.jsonl != stdout)
        fclose(st.jsonl);
    selfcol_store_destroy(st.store);
    selfcol_contacts_destroy(st.contacts);
    cli_sets_free(&st.sets);
    free(st.intersecting_frames.data);
    free(st.classes);
    free(st.worst_positions);
    free(st.worst_classes);
    cli_part_free(&part);
    selfcol_context_destroy(st.context); // after the part that borrows it
    for (long i = 0; frame_names && i < frame_count; ++i)
        free(frame_names[i]);
    free(frame_names);
    free(frame_numbers);
    return exit_code;
}
