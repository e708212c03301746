// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bench-sequence: the same query frame after frame, fresh (refit +
// EXACT query, what a simulator pays without coherence) against coherent
// (selfcol_sequence, include/selfcol/sequence.h), on the same frames, one
// thread unless --threads says otherwise.
//
// Per case and frame, both run on the same positions, interleaved (their
// order alternates from frame to frame), --reps times over the whole
// sequence; a frame's time is the median over the repetitions, and a row
// gives the mean, median and largest frame time (the mean carries the
// rebuilds, so it is the number to compare). Every frame the two record
// arrays are compared bit for bit: misses and extras must be 0.
//
// Cases (d = 0.1 x mean edge, kinds VF + EE + EF):
//  - crumpled-20k-slow, crumpled-200k-slow: an n x n unit sheet crumpled by
//    fixture_crumpled at amplitude 5 (1 + 0.002 f), f = 0..frames-1 (the
//    folds deepen by 0.2 % per frame; the note gives the vertices' motion);
//  - crumpled-20k-local, crumpled-200k-local: the same sheets, but the
//    folds deepen only in the strip x < 0.2 of the sheet's width (fading
//    out to x = 0.3); the rest holds still, as most of a garment does while
//    a sleeve moves: the lists fail in a few cluster pairs, which partial
//    rebuilds query again (column partial_rebuilds);
//  - cloth-ball-92-93: the two real frames of ../shared/data (vertices move
//    1.4 mean edges on average): the coherent query must rebuild, and the
//    row shows what that costs against a fresh query.
//
// Usage: selfcol-bench-sequence [--case NAME] [--frames N] [--reps R]
//        [--threads T] [--skin-factor K] [--data DIR] [--header]
// Prints CSV rows (tools/bench/run.sh collects them into sequence.csv).
// With BENCH_SEQUENCE_STATS set in the environment, each frame of the first
// repetition also prints the coherent query's statistics to stderr (list
// pairs, pairs skipped, closed forms per kind, times, the contact set's
// bytes).
#include <selfcol/selfcol.h>

#include "fixtures.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, size_t n) {
    qsort(v, n, sizeof *v, compare_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static const char *header =
    "case,triangles,vertices,frames,reps,threads,d,method,skin,frame_ms_mean,frame_ms_median,"
    "frame_ms_max,rebuilds,fresh_frames,partial_rebuilds,near_pairs_mean,contacts_mean,misses,"
    "extras,struct_bytes,"
    "bytes_per_tri,motion_mean,motion_max,note";

// A sequence of frames over one topology.
typedef struct frames {
    char name[64];
    fixture topo;       // positions of frame 0
    size_t count;       // frames
    double *positions;  // count x 3 V
    double motion_mean; // mean over frames >= 1 and vertices of |x_f - x_{f-1}| / mean edge
    double motion_max;
} frames;

static void frames_free(frames *f) {
    fixture_free(&f->topo);
    free(f->positions);
}

static int crumpling(frames *f, unsigned n, size_t count, const char *name, int local) {
    fixture flat, crumpled;
    memset(&flat, 0, sizeof flat);
    memset(&crumpled, 0, sizeof crumpled);
    if (fixture_grid(&flat, n, n, 1.0) != 0 || fixture_crumpled(&crumpled, n, n, 1, 5.0) != 0) {
        fixture_free(&flat);
        fixture_free(&crumpled);
        return 0;
    }
    const size_t V = flat.vertex_count;
    f->positions = malloc(count * 3 * V * sizeof(double));
    if (f->positions == NULL) {
        fixture_free(&flat);
        fixture_free(&crumpled);
        return 0;
    }
    // A local sequence deepens the folds of the strip x < 0.2 of the sheet's
    // width only, fading out over 0.2 <= x < 0.3; the rest holds still.
    double width = 0.0;
    for (size_t v = 0; v < V; ++v)
        width = flat.positions[3 * v] > width ? flat.positions[3 * v] : width;
    for (size_t k = 0; k < count; ++k)
        for (size_t v = 0; v < V; ++v) {
            const double x = flat.positions[3 * v] / width;
            const double w = !local ? 1.0 : x < 0.2 ? 1.0 : x < 0.3 ? (0.3 - x) / 0.1 : 0.0;
            for (size_t i = 3 * v; i < 3 * v + 3; ++i)
                f->positions[k * 3 * V + i] =
                    flat.positions[i] +
                    (1.0 + 0.002 * w * (double)k) * (crumpled.positions[i] - flat.positions[i]);
        }
    fixture_free(&flat);
    f->topo = crumpled;
    f->count = count;
    snprintf(f->name, sizeof f->name, "%s", name);
    return 1;
}

static int real_pair(frames *f, const char *data) {
    char p0[4096], p1[4096], err[512];
    snprintf(p0, sizeof p0, "%s/sample-scalable-ccd-data/cloth-ball/frames/cloth_ball92.ply", data);
    snprintf(p1, sizeof p1, "%s/sample-scalable-ccd-data/cloth-ball/frames/cloth_ball93.ply", data);
    fixture second;
    memset(&second, 0, sizeof second);
    if (fixture_read(p0, &f->topo, err, sizeof err) != 0 ||
        fixture_read(p1, &second, err, sizeof err) != 0 ||
        second.vertex_count != f->topo.vertex_count) {
        fprintf(stderr, "bench-sequence: cloth-ball-92-93 skipped (%s)\n", err);
        fixture_free(&second);
        return 0;
    }
    const size_t V = f->topo.vertex_count;
    f->positions = malloc(2 * 3 * V * sizeof(double));
    if (f->positions == NULL) {
        fixture_free(&second);
        return 0;
    }
    memcpy(f->positions, f->topo.positions, 3 * V * sizeof(double));
    memcpy(f->positions + 3 * V, second.positions, 3 * V * sizeof(double));
    fixture_free(&second);
    f->count = 2;
    snprintf(f->name, sizeof f->name, "cloth-ball-92-93");
    return 1;
}

static void measure_motion(frames *f, double mean_edge) {
    const size_t V = f->topo.vertex_count;
    double sum = 0.0, most = 0.0;
    size_t n = 0;
    for (size_t k = 1; k < f->count; ++k)
        for (size_t v = 0; v < V; ++v) {
            const double *a = f->positions + (k - 1) * 3 * V + 3 * v;
            const double *b = a + 3 * V;
            const double m = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                  (b[2] - a[2]) * (b[2] - a[2])) /
                             mean_edge;
            sum += m;
            most = m > most ? m : most;
            n++;
        }
    f->motion_mean = n ? sum / (double)n : 0.0;
    f->motion_max = most;
}

static int check(int rc, const char *what) {
    if (rc != SELFCOL_OK)
        fprintf(stderr, "bench-sequence: %s: %s\n", what, selfcol_status_string(rc));
    return rc;
}

// Records of a and b compared bit for bit: misses (in b, not a) and extras.
static void differences(const selfcol_contacts *got, const selfcol_contacts *want,
                        unsigned long long *misses, unsigned long long *extras) {
    const selfcol_contact *a, *b;
    size_t na, nb;
    selfcol_contacts_data(got, &a, &na);
    selfcol_contacts_data(want, &b, &nb);
    size_t i = 0, j = 0;
    while (i < na || j < nb) {
        if (i < na && j < nb && memcmp(&a[i], &b[j], sizeof a[i]) == 0) {
            ++i, ++j;
            continue;
        }
        // Keys decide which side is ahead; equal keys with different bits
        // count as one miss and one extra.
        const uint32_t ka[5] = {i < na ? a[i].kind : UINT32_MAX, i < na ? a[i].first_mesh : 0,
                                i < na ? a[i].first : 0, i < na ? a[i].second_mesh : 0,
                                i < na ? a[i].second : 0};
        const uint32_t kb[5] = {j < nb ? b[j].kind : UINT32_MAX, j < nb ? b[j].first_mesh : 0,
                                j < nb ? b[j].first : 0, j < nb ? b[j].second_mesh : 0,
                                j < nb ? b[j].second : 0};
        int c = 0;
        for (int k = 0; k < 5 && c == 0; ++k)
            c = ka[k] < kb[k] ? -1 : ka[k] > kb[k];
        if (c <= 0 && i < na)
            ++*extras, ++i;
        if (c >= 0 && j < nb)
            ++*misses, ++j;
    }
}

// What a case counts over its frames (rebuilds, near pairs, contacts: the
// first repetition's), and the records compared.
typedef struct tally {
    unsigned long long misses, extras, rebuilds, fresh_frames, partials;
    double near_sum, contacts_sum;
    size_t bytes; // the sequence's largest size
} tally;

// BENCH_SEQUENCE_STATS: the coherent query's counters of frame k.
static void print_frame_stats(size_t k, const selfcol_contacts *c) {
    selfcol_query_stats q;
    memset(&q, 0, sizeof q);
    q.version = SELFCOL_QUERY_STATS_VERSION;
    selfcol_contacts_stats(c, &q);
    fprintf(stderr,
            "frame %zu: candidates %llu filtered %llu vf %llu ee %llu ef %llu "
            "contacts %llu/%llu/%llu broad %.2f narrow %.2f ms, contact set %zu "
            "bytes\n",
            k, (unsigned long long)q.candidate_pairs, (unsigned long long)q.primitives_filtered,
            (unsigned long long)q.vf_tests, (unsigned long long)q.ee_tests,
            (unsigned long long)q.ef_tests, (unsigned long long)q.vf_contacts,
            (unsigned long long)q.ee_contacts, (unsigned long long)q.ef_contacts,
            1e3 * q.broad_seconds, 1e3 * q.narrow_seconds, selfcol_contacts_byte_count(c));
}

// The case's two CSV rows, FRESH and COHERENT: per frame the median over the
// repetitions of times[m] (frame-major, reps per frame), then their mean,
// median and largest.
static void print_rows(const frames *f, unsigned reps, unsigned threads, double d, double skin,
                       double *const times[2], double *per_frame, const tally *t,
                       size_t hierarchy_bytes) {
    const size_t V = f->topo.vertex_count, F = f->topo.triangle_count;
    const char *names[2] = {"FRESH", "COHERENT"};
    for (int m = 0; m < 2; ++m) {
        double frame_med[4096];
        const size_t n = f->count < 4096 ? f->count : 4096;
        double sum = 0.0, most = 0.0;
        for (size_t k = 0; k < n; ++k) {
            for (unsigned r = 0; r < reps; ++r)
                per_frame[r] = times[m][k * reps + r];
            frame_med[k] = median(per_frame, reps);
            sum += frame_med[k];
            most = frame_med[k] > most ? frame_med[k] : most;
        }
        const double mean = sum / (double)n;
        const double med = median(frame_med, n);
        const size_t struct_bytes = m == 0 ? hierarchy_bytes : t->bytes;
        printf("%s,%zu,%zu,%zu,%u,%u,%.9g,%s,%.9g,%.4f,%.4f,%.4f,%llu,%llu,%llu,%.1f,%.1f,%llu,"
               "%llu,%zu,%.1f,%.4f,%.4f,%s\n",
               f->name, F, V, f->count, reps, threads, d, names[m], m == 0 ? 0.0 : skin, 1e3 * mean,
               1e3 * med, 1e3 * most, m == 0 ? 0ULL : t->rebuilds, m == 0 ? 0ULL : t->fresh_frames,
               m == 0 ? 0ULL : t->partials, m == 0 ? 0.0 : t->near_sum / (double)f->count,
               t->contacts_sum / (double)f->count, t->misses, t->extras, struct_bytes,
               (double)struct_bytes / (double)F, f->motion_mean, f->motion_max,
               m == 0 ? "refit + EXACT query per frame"
                      : "selfcol_sequence per frame (rebuilds included); struct_bytes: "
                        "the sequence");
    }
}

static int run_case(frames *f, unsigned reps, unsigned threads, double skin_factor) {
    const size_t V = f->topo.vertex_count, F = f->topo.triangle_count;
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *fresh_h = NULL, *coherent_h = NULL;
    selfcol_contacts *fresh_c = NULL, *coherent_c = NULL;
    selfcol_sequence *seq = NULL;
    int rc = check(selfcol_mesh_create(&mesh, V, f->positions, F, f->topo.triangles, NULL), "mesh");
    if (rc == SELFCOL_OK)
        rc = check(selfcol_hierarchy_create(&fresh_h, mesh, NULL), "hierarchy");
    if (rc == SELFCOL_OK)
        rc = check(selfcol_hierarchy_create(&coherent_h, mesh, NULL), "hierarchy");
    if (rc == SELFCOL_OK)
        rc = check(selfcol_contacts_create(&fresh_c, NULL), "contacts");
    if (rc == SELFCOL_OK)
        rc = check(selfcol_contacts_create(&coherent_c, NULL), "contacts");
    const double mean_edge = rc == SELFCOL_OK ? selfcol_mesh_mean_edge_length(mesh) : 1.0;
    const double d = 0.1 * mean_edge;
    selfcol_sequence_options so;
    selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    so.skin = skin_factor * d;
    if (rc == SELFCOL_OK)
        rc = check(selfcol_sequence_create(&seq, &so), "sequence");
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = SELFCOL_METHOD_EXACT;
    o.distance = d;
    // --threads T > 1: both sides on a context of T threads (NULL: one).
    selfcol_context *ctx = NULL;
    if (rc == SELFCOL_OK && threads > 1) {
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.threads = threads;
        rc = check(selfcol_context_create(&ctx, &co), "context");
    }
    measure_motion(f, mean_edge);

    double *fresh_t = calloc(f->count * reps, sizeof(double));
    double *coherent_t = calloc(f->count * reps, sizeof(double));
    double *per_frame = calloc(reps > f->count ? reps : f->count, sizeof(double));
    if (fresh_t == NULL || coherent_t == NULL || per_frame == NULL)
        rc = SELFCOL_ENOMEM;
    tally t;
    memset(&t, 0, sizeof t);
    for (unsigned rep = 0; rc == SELFCOL_OK && rep < reps; ++rep) {
        selfcol_sequence_reset(seq);
        for (size_t k = 0; rc == SELFCOL_OK && k < f->count; ++k) {
            rc = check(selfcol_mesh_set_positions(mesh, f->positions + k * 3 * V, V), "positions");
            for (int turn = 0; turn < 2 && rc == SELFCOL_OK; ++turn) {
                const int coherent_first = (int)((k + rep) % 2);
                if (turn == (coherent_first ? 0 : 1)) {
                    const double t0 = now();
                    rc = check(ctx != NULL
                                   ? selfcol_context_sequence_self_collide(ctx, seq, coherent_h,
                                                                           coherent_c, &o)
                                   : selfcol_sequence_self_collide(seq, coherent_h, coherent_c, &o),
                               "sequence query");
                    coherent_t[k * reps + rep] = now() - t0;
                } else {
                    const double t0 = now();
                    rc = check(ctx != NULL ? selfcol_context_refit(ctx, fresh_h)
                                           : selfcol_hierarchy_refit(fresh_h),
                               "refit");
                    if (rc == SELFCOL_OK)
                        rc = check(ctx != NULL
                                       ? selfcol_context_self_collide(ctx, fresh_h, fresh_c, &o)
                                       : selfcol_hierarchy_self_collide(fresh_h, fresh_c, &o),
                                   "query");
                    fresh_t[k * reps + rep] = now() - t0;
                }
            }
            if (rc != SELFCOL_OK)
                break;
            differences(coherent_c, fresh_c, &t.misses, &t.extras);
            if (getenv("BENCH_SEQUENCE_STATS") != NULL && rep == 0)
                print_frame_stats(k, coherent_c);
            selfcol_sequence_run_stats st;
            st.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
            selfcol_sequence_stats(seq, &st);
            if (rep == 0) {
                t.rebuilds += st.last_answer == SELFCOL_SEQUENCE_REBUILT;
                t.fresh_frames += st.last_answer == SELFCOL_SEQUENCE_FRESH;
                t.partials = st.partial_rebuilds; // since the repetition's reset
                t.near_sum += (double)st.near_pairs;
                t.contacts_sum += (double)selfcol_contacts_count(fresh_c);
            }
            const size_t b = selfcol_sequence_byte_count(seq);
            t.bytes = b > t.bytes ? b : t.bytes;
        }
    }
    if (rc == SELFCOL_OK) {
        double *times[2] = {fresh_t, coherent_t};
        print_rows(f, reps, threads, d, so.skin, times, per_frame, &t,
                   selfcol_hierarchy_byte_count(fresh_h));
    }
    free(fresh_t);
    free(coherent_t);
    free(per_frame);
    selfcol_sequence_destroy(seq);
    selfcol_context_destroy(ctx);
    selfcol_contacts_destroy(fresh_c);
    selfcol_contacts_destroy(coherent_c);
    selfcol_hierarchy_destroy(fresh_h);
    selfcol_hierarchy_destroy(coherent_h);
    selfcol_mesh_destroy(mesh);
    return rc == SELFCOL_OK && t.misses == 0 && t.extras == 0 ? 0 : 1;
}

int main(int argc, char **argv) {
    const char *only = NULL, *data = BENCH_DEFAULT_DATA_DIR;
    unsigned reps = 3, threads = 1;
    long frame_count = 40;
    double skin_factor = 1.0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--header") == 0) {
            printf("%s\n", header);
            return 0;
        } else if (strcmp(argv[i], "--case") == 0 && i + 1 < argc) {
            only = argv[++i];
        } else if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
            frame_count = atol(argv[++i]);
        } else if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc) {
            reps = (unsigned)atoi(argv[++i]);
        } else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
            threads = (unsigned)atoi(argv[++i]);
        } else if (strcmp(argv[i], "--skin-factor") == 0 && i + 1 < argc) {
            skin_factor = atof(argv[++i]);
        } else if (strcmp(argv[i], "--data") == 0 && i + 1 < argc) {
            data = argv[++i];
        } else {
            fprintf(stderr,
                    "usage: %s [--case NAME] [--frames N] [--reps R] [--threads T] "
                    "[--skin-factor K] [--data DIR] [--header]\n",
                    argv[0]);
            return 2;
        }
    }
    if (frame_count < 2 || frame_count > 4096 || reps < 1 || reps > 99 || threads < 1 ||
        threads > SELFCOL_MAX_THREADS || !(skin_factor >= 0.0)) {
        fprintf(stderr, "bench-sequence: frames 2..4096, reps 1..99, threads 1..%d, skin >= 0\n",
                SELFCOL_MAX_THREADS);
        return 2;
    }
    static const char *const names[] = {"crumpled-2k-slow",   "crumpled-20k-slow",
                                        "crumpled-200k-slow", "cloth-ball-92-93",
                                        "crumpled-20k-local", "crumpled-200k-local"};
    static const unsigned sizes[] = {32, 100, 316, 0, 100, 316};
    int status = 0, ran = 0;
    for (size_t c = 0; c < sizeof names / sizeof names[0]; ++c) {
        if (only == NULL ? c == 0 : strcmp(only, names[c]) != 0)
            continue; // the 2k case only when asked (the smoke run)
        frames f;
        memset(&f, 0, sizeof f);
        const int ok = sizes[c] ? crumpling(&f, sizes[c], (size_t)frame_count, names[c], c >= 4)
                                : real_pair(&f, data);
        if (!ok) {
            if (sizes[c] != 0)
                status = 1;
            continue;
        }
        status |= run_case(&f, reps, threads, skin_factor);
        frames_free(&f);
        ran = 1;
    }
    if (only != NULL && !ran && status == 0)
        fprintf(stderr, "bench-sequence: case %s not run\n", only);
    return status;
}
