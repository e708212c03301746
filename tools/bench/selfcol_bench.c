// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bench: the benchmark runner (issue 5). One named case (a scene at
// one size) per process, so that the peak resident memory of a row is that
// of its case alone; tools/bench/run.sh runs the cases of a subset one after
// the other and collects the CSV rows.
//
// For each case: the mesh is generated (tools/meshio/fixtures.c) or read
// (real frames from the Sample-Scalable-CCD-Data layout), the hierarchy is
// built once, and for each detection distance d = 0.1 and 0.5 x mean edge
// every method runs on the same mesh and d: EXHAUSTIVE (small sizes only), BVH,
// SEED, CONE, EXACT, BVH with the libccd narrow phase (small sizes), EXACT
// restricted to vertex-triangle proximities (EXACT-VF, Bullet's share of the
// work), and Bullet 3.24's own self-collision (bench_bullet.cpp). Each timed quantity is the median
// of `reps` runs after one warm-up run, with min and max. Every method's contact set is compared
// with a reference: EXHAUSTIVE when it ran, else EXACT (which the test suite and the smaller rows
// hold equal to EXHAUSTIVE); the `reference` column says which.
//
// The store-* cases (listed after the others) time the contact store
// instead: selfcol_store_update fed with EXACT's result of each frame of a
// crumpled-sheet sequence, or of two real frames (rows STORE-FIRST and
// STORE; see "Contact-store rows" below). `run.sh --only '^store-'` runs
// them alone.
//
// usage: selfcol-bench --list SUBSET        names of the cases of a subset
//        selfcol-bench --header             the CSV header line
//        selfcol-bench --case NAME --subset SUBSET [--data DIR]
//                                           rows of one case on stdout
//        selfcol-bench --case NAME --dump DIR [--data DIR]
//                                           the case's mesh and EXACT's contacts
//                                           as files, for bench_ipctk.py
// SUBSET is smoke, default or full; it sets the repetitions and the size
// limits of the slow methods.
#include <selfcol/selfcol.h>

#include "bench_bullet.h"
#include "fixtures.h"
// The library's own union-find (header-only, internal): one copy in the repository.
#include "../../lib/base/union_find.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#ifndef BENCH_DEFAULT_DATA_DIR
#define BENCH_DEFAULT_DATA_DIR "../shared/data"
#endif

enum { SMOKE = 1, DEFAULT = 2, FULL = 4, ALL = SMOKE | DEFAULT | FULL, BIG = DEFAULT | FULL };

// ---------------------------------------------------------------------------
// Scenes

typedef int (*generator)(fixture *s, const double *p, const char *data_dir, char *note, size_t n);

static int gen_flat(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_grid(s, (unsigned)p[0], (unsigned)p[0], 1.0);
}
static int gen_wrinkled(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_wrinkled(s, (unsigned)p[0], (unsigned)p[0], (unsigned)p[1], p[2]);
}
static int gen_crumpled(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_crumpled(s, (unsigned)p[0], (unsigned)p[0], (unsigned)p[1], 5.0);
}
// The crumpled sheet as a 1 m cloth (edges of 1 cm), left unscaled: the row
// that shows Bullet's size dead zone (see the `scale` rule in run_case).
static int gen_crumpled_1m(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    if (fixture_crumpled(s, (unsigned)p[0], (unsigned)p[0], (unsigned)p[1], 5.0) != 0)
        return -1;
    for (size_t i = 0; i < 3 * s->vertex_count; ++i)
        s->positions[i] /= p[0];
    return 0;
}
static int gen_hairpin(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_hairpin(s, (unsigned)p[0], p[1]);
}
static int gen_zfold(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_zfold(s, (unsigned)p[0], (unsigned)p[1], p[2], (unsigned)p[3], p[4]);
}
static int gen_ramp(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_ramp(s, (unsigned)p[0], (unsigned)p[1], p[2], p[3], p[4]);
}
static int gen_rolled(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_rolled(s, (unsigned)p[0], p[1], p[2], p[3], p[4]);
}
// Radius 2^level keeps the edges near unit length at every level.
static int gen_icosphere(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_icosphere(s, (unsigned)p[0], ldexp(1.0, (int)p[0]));
}
static int gen_uv_sphere(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    return fixture_uv_sphere(s, (unsigned)p[0], (unsigned)p[1], p[2]);
}
static int gen_sheet_pair(fixture *s, const double *p, const char *dd, char *note, size_t n) {
    (void)dd, (void)note, (void)n;
    fixture b;
    if (fixture_sheet_pair(s, &b, (unsigned)p[0], (unsigned)p[1], p[2], p[3]) != 0)
        return -1;
    int rc = fixture_append(s, &b);
    fixture_free(&b);
    return rc;
}

// Real frames, laid out as the public Sample-Scalable-CCD-Data repository
// keeps them: <data>/sample-scalable-ccd-data/<scene>/frames/<frame>.ply
// (some scenes prefix the frame number, e.g. balls16_18.ply; OBJ copies are
// accepted too). Returns 1 when the file is absent (the case is skipped).
static const char *frame_scene_names[] = {"cloth-ball", "cloth-funnel", "rod-twist"};

static int gen_frame(fixture *s, const double *p, const char *data_dir, char *note, size_t n) {
    const char *name = frame_scene_names[(int)p[0]];
    unsigned frame = (unsigned)p[1];
    char path[4096], err[640];
    // Frames are named <N>.ply (cloth-funnel) or <scene_with_underscores><N>.ply
    // (cloth-ball: cloth_ball92.ply) in the public dataset; try both.
    char prefix[64];
    snprintf(prefix, sizeof prefix, "%s", name);
    for (char *c = prefix; *c; ++c)
        if (*c == '-')
            *c = '_';
    const char *patterns[] = {"%s/sample-scalable-ccd-data/%s/frames/%s%u.ply",
                              "%s/sample-scalable-ccd-data/%s/frames/%s%u.obj"};
    for (int i = 0; i < 4; ++i) {
        snprintf(path, sizeof path, patterns[i % 2], data_dir, name, i < 2 ? "" : prefix, frame);
        FILE *f = fopen(path, "rb");
        if (f == NULL)
            continue;
        fclose(f);
        int rc = fixture_read(path, s, err, sizeof err); // PLY or OBJ (tools/meshio)
        if (rc != 0)
            fprintf(stderr, "selfcol-bench: %s\n", err);
        snprintf(note, n, "frame %s", path);
        return rc;
    }
    snprintf(note, n, "absent: %s/sample-scalable-ccd-data/%s/frames/{,%s}%u.{ply,obj}", data_dir,
             name, prefix, frame);
    return 1;
}

typedef struct bench_case {
    const char *name;
    const char *scene; // the scene family (the plots group by it)
    unsigned subsets;
    generator gen;
    double p[6];
    int raw; // 1: never scale the mesh (the dead-zone demonstration)
} bench_case;

// Sizes are chosen for about 1k, 2k, 10k, 20k, 100k, 200k and 1M triangles.
// The generators keep edges near unit length, far above Bullet's ~1.8 cm
// dead zone, so no scaling is needed for Bullet on them (the `scale`
// column says so); real frames are scaled x10 when their edges are short.
static const bench_case cases[] = {
    {"flat-1k", "flat", ALL, gen_flat, {22}, 0},
    {"flat-10k", "flat", BIG, gen_flat, {71}, 0},
    {"flat-100k", "flat", BIG, gen_flat, {224}, 0},
    {"flat-300k", "flat", BIG, gen_flat, {387}, 0},
    {"flat-1M", "flat", FULL, gen_flat, {707}, 0},
    {"wrinkled-1k", "wrinkled", BIG, gen_wrinkled, {22, 1, 1.0}, 0},
    {"wrinkled-20k", "wrinkled", BIG, gen_wrinkled, {100, 1, 1.0}, 0},
    {"wrinkled-200k", "wrinkled", FULL, gen_wrinkled, {316, 1, 1.0}, 0},
    {"crumpled-500", "crumpled", SMOKE, gen_crumpled, {16, 1}, 0},
    {"crumpled-2k", "crumpled", BIG, gen_crumpled, {32, 1}, 0},
    {"crumpled-20k-s1", "crumpled", BIG, gen_crumpled, {100, 1}, 0},
    {"crumpled-20k-s2", "crumpled", BIG, gen_crumpled, {100, 2}, 0},
    {"crumpled-20k-s3", "crumpled", BIG, gen_crumpled, {100, 3}, 0},
    {"crumpled-200k", "crumpled", BIG, gen_crumpled, {316, 1}, 0},
    {"crumpled-1M", "crumpled", FULL, gen_crumpled, {707, 1}, 0},
    {"crumpled-20k-1m-raw", "crumpled-1m-raw", BIG, gen_crumpled_1m, {100, 1}, 1},
    {"hairpin-1k", "hairpin", ALL, gen_hairpin, {250, 0.1}, 0},
    {"hairpin-10k", "hairpin", BIG, gen_hairpin, {2500, 0.1}, 0},
    {"zfold-2k", "zfold", BIG, gen_zfold, {40, 8, 0.1, 1, 0.25}, 0},
    {"zfold-20k", "zfold", BIG, gen_zfold, {170, 20, 0.1, 1, 0.25}, 0},
    {"ramp-600", "ramp", SMOKE, gen_ramp, {3, 48, 8.0, 1.0, -0.3}, 0},
    {"ramp-2k", "ramp", BIG, gen_ramp, {8, 64, 10.0, 1.0, -0.3}, 0},
    {"ramp-20k", "ramp", BIG, gen_ramp, {20, 256, 40.0, 1.0, -0.3}, 0},
    {"rolled-2k", "rolled", BIG, gen_rolled, {20, 2.25, 3.0, -0.15, 0.5}, 0},
    {"rolled-20k", "rolled", BIG, gen_rolled, {60, 3.0, 8.0, -0.15, 0.5}, 0},
    {"sphere-1k", "sphere", ALL, gen_icosphere, {3}, 0},
    {"sphere-5k", "sphere", BIG, gen_icosphere, {4}, 0},
    {"sphere-20k", "sphere", BIG, gen_icosphere, {5}, 0},
    {"sphere-80k", "sphere", BIG, gen_icosphere, {6}, 0},
    {"sphere-330k", "sphere", BIG, gen_icosphere, {7}, 0},
    {"sphere-1.3M", "sphere", FULL, gen_icosphere, {8}, 0},
    {"uv-sphere-4k", "uv-sphere", BIG, gen_uv_sphere, {32, 64, 10.0}, 0},
    {"sheet-pair-1k", "sheet-pair", BIG, gen_sheet_pair, {16, 1, 1.0471975511965976, 0.0}, 0},
    {"sheet-pair-10k", "sheet-pair", BIG, gen_sheet_pair, {50, 1, 1.0471975511965976, 0.0}, 0},
    {"cloth-ball-92", "cloth-ball", BIG, gen_frame, {0, 92}, 0},
    {"cloth-ball-93", "cloth-ball", BIG, gen_frame, {0, 93}, 0},
    {"cloth-ball-93-refit", "cloth-ball", BIG, gen_frame, {0, 93, 92}, 0},
    {"cloth-funnel-227", "cloth-funnel", BIG, gen_frame, {1, 227}, 0},
    {"cloth-funnel-228", "cloth-funnel", BIG, gen_frame, {1, 228}, 0},
    {"rod-twist-3036", "rod-twist", BIG, gen_frame, {2, 3036}, 0},
    {"rod-twist-3037", "rod-twist", BIG, gen_frame, {2, 3037}, 0},
};

// ---------------------------------------------------------------------------
// Subset limits: how many repetitions, and up to which size the O(n^2)
// reference, libccd and Bullet (O(F^2) build) run.

typedef struct limits {
    unsigned reps;
    size_t exhaustive, libccd, bullet;
    unsigned store_runs; // runs of each contact-store sequence (fresh store each)
} limits;

static limits limits_of(unsigned subset) {
    limits l;
    switch (subset) {
    case SMOKE:
        l.reps = 2, l.exhaustive = 2000, l.libccd = 2000, l.bullet = 2000, l.store_runs = 2;
        break;
    case FULL:
        l.reps = 7, l.exhaustive = 20500, l.libccd = 20500, l.bullet = 200000, l.store_runs = 5;
        break;
    default:
        l.reps = 5, l.exhaustive = 5200, l.libccd = 5200, l.bullet = 20500, l.store_runs = 3;
        break;
    }
    return l;
}

// ---------------------------------------------------------------------------
// Timing

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct timing {
    double med, min, max;
    unsigned reps;
} timing;

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static timing summarize(double *t, unsigned n) {
    timing r = {0, 0, 0, n};
    if (n == 0)
        return r;
    qsort(t, n, sizeof *t, cmp_double);
    r.min = t[0];
    r.max = t[n - 1];
    r.med = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
    return r;
}

// A run slower than this after the warm-up gets 3 repetitions instead of
// `reps`, so that the O(n^2) rows of the full subset stay affordable.
#define SLOW_SECONDS 2.0
enum { MAX_REPS = 16 };

static unsigned reps_after_warmup(double warmup_seconds, unsigned reps) {
    return warmup_seconds > SLOW_SECONDS && reps > 3 ? 3 : reps;
}

// ---------------------------------------------------------------------------
// Contact sets

typedef struct key {
    uint32_t kind, first, second;
} key;

static int cmp_key(const void *a, const void *b) {
    const key *x = a, *y = b;
    if (x->kind != y->kind)
        return x->kind < y->kind ? -1 : 1;
    if (x->first != y->first)
        return x->first < y->first ? -1 : 1;
    return (x->second > y->second) - (x->second < y->second);
}

typedef struct keyset {
    key *k;
    size_t n;
} keyset;

static int keys_of(const selfcol_contacts *c, keyset *out) {
    const selfcol_contact *data;
    size_t n;
    selfcol_contacts_data(c, &data, &n);
    out->k = malloc((n ? n : 1) * sizeof(key));
    if (out->k == NULL)
        return -1;
    for (size_t i = 0; i < n; ++i) {
        out->k[i].kind = data[i].kind;
        out->k[i].first = data[i].first;
        out->k[i].second = data[i].second;
    }
    qsort(out->k, n, sizeof(key), cmp_key);
    out->n = n;
    return 0;
}

// misses[kind]: in ref, not in got; extras[kind]: in got, not in ref.
static void compare(const keyset *ref, const keyset *got, uint64_t misses[3], uint64_t extras[3]) {
    size_t i = 0, j = 0;
    memset(misses, 0, 3 * sizeof *misses);
    memset(extras, 0, 3 * sizeof *extras);
    while (i < ref->n || j < got->n) {
        int c = i == ref->n ? 1 : j == got->n ? -1 : cmp_key(&ref->k[i], &got->k[j]);
        if (c == 0)
            ++i, ++j;
        else if (c < 0)
            misses[ref->k[i++].kind]++;
        else
            extras[got->k[j++].kind]++;
    }
}

// ---------------------------------------------------------------------------
// Rows

typedef struct row {
    const char *method, *narrow, *reference;
    timing refit, query;
    double broad_med, narrow_med, sort_med; // stage medians of the query, seconds
    double build_ms;
    selfcol_query_stats st;
    uint64_t found[3], ref[3], miss[3], extra[3];
    uint64_t raw_contacts;
    size_t struct_bytes;
    unsigned threads; // of the context the row ran on (one: none; Bullet: 1)
    // Contact-store rows (method STORE, STORE-FIRST; 0 on the other rows):
    // selfcol_store_update's wall time, per held VF/EE contact, and the
    // update's counters (means over the updates of the row).
    timing update;
    double ns_per_contact, bytes_per_contact;
    double held, regions, st_new, st_kept, st_remnant, st_dropped, st_flipped, st_corrected;
    char note[256];
} row;

typedef struct context {
    const char *subset, *case_name, *scene_name;
    size_t triangles, vertices, edges;
    double scale, d_factor, d, mean_edge;
    long peak_rss_kb;
} context;

static const char *header =
    "subset,case,scene,triangles,vertices,edges,scale,d_factor,d,method,narrow,reference,reps,"
    "build_ms,refit_ms,refit_min_ms,refit_max_ms,query_ms,query_min_ms,query_max_ms,frame_ms,"
    "triangle_pairs,candidate_pairs,vf_tests,ee_tests,ef_tests,nodes_visited,culled_box,"
    "culled_curvature,culled_adjacency,contour_tests,contour_refused,contour_ms,broad_ms,narrow_ms,"
    "sort_ms,pairs_separated,primitives_filtered,vf,ee,ef,contacts,"
    "raw_contacts,ref_vf,ref_ee,ref_ef,"
    "miss_vf,miss_ee,miss_ef,misses,extra_vf,extra_ee,extra_ef,extras,struct_bytes,"
    "bytes_per_tri,peak_rss_kb,threads,"
    "store_update_ms,store_update_min_ms,store_update_max_ms,store_ns_per_contact,store_contacts,"
    "store_regions,store_new,store_kept,store_remnant,store_dropped,store_flipped,store_corrected,"
    "store_bytes_per_contact,note";

static void print_row(const context *cx, const row *r) {
    const selfcol_query_stats *s = &r->st;
    uint64_t found = r->found[0] + r->found[1] + r->found[2];
    uint64_t misses = r->miss[0] + r->miss[1] + r->miss[2];
    uint64_t extras = r->extra[0] + r->extra[1] + r->extra[2];
    printf("%s,%s,%s,%zu,%zu,%zu,%g,%g,%.9g,%s,%s,%s,%u,", cx->subset, cx->case_name,
           cx->scene_name, cx->triangles, cx->vertices, cx->edges, cx->scale, cx->d_factor, cx->d,
           r->method, r->narrow, r->reference, r->query.reps);
    printf("%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,", r->build_ms, 1e3 * r->refit.med,
           1e3 * r->refit.min, 1e3 * r->refit.max, 1e3 * r->query.med, 1e3 * r->query.min,
           1e3 * r->query.max, 1e3 * (r->refit.med + r->query.med));
    printf("%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,", (unsigned long long)s->triangle_pairs,
           (unsigned long long)s->candidate_pairs, (unsigned long long)s->vf_tests,
           (unsigned long long)s->ee_tests, (unsigned long long)s->ef_tests,
           (unsigned long long)s->nodes_visited, (unsigned long long)s->culled_box,
           (unsigned long long)s->culled_curvature, (unsigned long long)s->culled_adjacency);
    // Stats version 3: EXACT's contour test (0 for the other methods).
    printf("%llu,%llu,%.4f,", (unsigned long long)s->contour_tests,
           (unsigned long long)s->contour_refused, 1e3 * s->contour_seconds);
    // Stats version 4: the stages of the query (medians over the timed
    // repetitions, like query_ms) and the narrow phase's filters.
    printf("%.4f,%.4f,%.4f,%llu,%llu,", 1e3 * r->broad_med, 1e3 * r->narrow_med, 1e3 * r->sort_med,
           (unsigned long long)s->pairs_separated, (unsigned long long)s->primitives_filtered);
    printf("%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,", (unsigned long long)r->found[0],
           (unsigned long long)r->found[1], (unsigned long long)r->found[2],
           (unsigned long long)found, (unsigned long long)r->raw_contacts,
           (unsigned long long)r->ref[0], (unsigned long long)r->ref[1],
           (unsigned long long)r->ref[2]);
    printf("%llu,%llu,%llu,%llu,%llu,%llu,%llu,%llu,", (unsigned long long)r->miss[0],
           (unsigned long long)r->miss[1], (unsigned long long)r->miss[2],
           (unsigned long long)misses, (unsigned long long)r->extra[0],
           (unsigned long long)r->extra[1], (unsigned long long)r->extra[2],
           (unsigned long long)extras);
    printf("%zu,%.2f,%ld,%u,", r->struct_bytes,
           cx->triangles ? (double)r->struct_bytes / (double)cx->triangles : 0.0, cx->peak_rss_kb,
           r->threads ? r->threads : 1u);
    printf("%.4f,%.4f,%.4f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,", 1e3 * r->update.med,
           1e3 * r->update.min, 1e3 * r->update.max, r->ns_per_contact, r->held, r->regions,
           r->st_new, r->st_kept, r->st_remnant, r->st_dropped, r->st_flipped, r->st_corrected,
           r->bytes_per_contact);
    printf("\"%s\"\n", r->note);
    fflush(stdout);
}

static long peak_rss_kb(void) {
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss : -1;
}

// ---------------------------------------------------------------------------
// One method on the hierarchy: warm-up, reps timed queries, contacts, stats.

// A context of `threads` threads (the library's one place for threads),
// NULL for one: the rows' queries, refits and store updates on more than
// one thread go through it, its threads kept between reps.
static selfcol_context *bench_context(unsigned threads) {
    if (threads <= 1)
        return NULL;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = threads;
    selfcol_context *c = NULL;
    if (selfcol_context_create(&c, &co) != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: no context of %u threads\n", threads);
        exit(1);
    }
    return c;
}

static int run_method(selfcol_hierarchy *h, selfcol_contacts *c, uint32_t method, uint32_t narrow,
                      uint32_t kinds, double d, unsigned threads, unsigned reps, row *r,
                      keyset *keys) {
    timing *t = &r->query;
    selfcol_query_stats *st = &r->st;
    double stage[3][MAX_REPS];
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = method;
    o.narrow = narrow;
    o.kinds = kinds;
    o.distance = d;
    r->threads = threads;
    selfcol_context *threads_ctx = bench_context(threads);
#define RUN_QUERY()                                                                                \
    (threads_ctx != NULL ? selfcol_context_self_collide(threads_ctx, h, c, &o)                     \
                         : selfcol_hierarchy_self_collide(h, c, &o))
    double t0 = now();
    int rc = RUN_QUERY();
    double warm = now() - t0;
    double times[MAX_REPS];
    unsigned n = reps_after_warmup(warm, reps);
    for (unsigned i = 0; rc == SELFCOL_OK && i < n; ++i) {
        t0 = now();
        rc = RUN_QUERY();
        times[i] = now() - t0;
        st->version = SELFCOL_QUERY_STATS_VERSION;
        selfcol_contacts_stats(c, st);
        stage[0][i] = st->broad_seconds;
        stage[1][i] = st->narrow_seconds;
        stage[2][i] = st->sort_seconds;
    }
#undef RUN_QUERY
    selfcol_context_destroy(threads_ctx);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: query: %s\n", selfcol_status_string(rc));
        return rc;
    }
    *t = summarize(times, n);
    r->broad_med = summarize(stage[0], n).med;
    r->narrow_med = summarize(stage[1], n).med;
    r->sort_med = summarize(stage[2], n).med;
    st->version = SELFCOL_QUERY_STATS_VERSION;
    selfcol_contacts_stats(c, st);
    return keys_of(c, keys);
}

static void count_kinds(const keyset *k, uint64_t out[3]) {
    out[0] = out[1] = out[2] = 0;
    for (size_t i = 0; i < k->n; ++i)
        out[k->k[i].kind]++;
}

static const char *method_name(uint32_t m) {
    static const char *names[] = {"EXHAUSTIVE", "BVH", "SEED", "CONE", "EXACT"};
    return m < 5 ? names[m] : "?";
}

// Bullet rows: refit and self-collision times, its unique node-face pairs
// against the reference VF set (it finds no EE or EF contact: all of those
// count as misses).
static void bullet_rows(bench_bullet *bb, context *cx, const keyset *ref, const char *ref_name,
                        double build_ms, size_t tree_bytes, unsigned reps) {
    row r;
    memset(&r, 0, sizeof r);
    r.method = "BULLET";
    r.narrow = "bullet";
    r.reference = ref_name;
    r.build_ms = build_ms;
    r.struct_bytes = tree_bytes;
    bench_bullet_set_distance(bb, cx->d * cx->scale);
    double refit[MAX_REPS], query[MAX_REPS];
    bench_bullet_refit(bb); // warm-up
    double warm = bench_bullet_self_collide(bb);
    unsigned n = reps_after_warmup(warm, reps);
    for (unsigned i = 0; i < n; ++i) {
        refit[i] = bench_bullet_refit(bb);
        query[i] = bench_bullet_self_collide(bb);
    }
    r.refit = summarize(refit, n);
    r.query = summarize(query, n);
    uint64_t *pairs = NULL;
    size_t raw = 0;
    size_t unique = bench_bullet_contacts(bb, &raw, &pairs);
    if (unique == (size_t)-1) {
        fprintf(stderr, "selfcol-bench: out of memory\n");
        return;
    }
    keyset got;
    got.n = unique;
    got.k = malloc((unique ? unique : 1) * sizeof(key));
    if (got.k == NULL) {
        free(pairs);
        return;
    }
    for (size_t i = 0; i < unique; ++i) {
        got.k[i].kind = SELFCOL_CONTACT_VF;
        got.k[i].first = (uint32_t)(pairs[i] >> 32);
        got.k[i].second = (uint32_t)(pairs[i] & 0xffffffffu);
    }
    free(pairs);
    qsort(got.k, got.n, sizeof(key), cmp_key);
    count_kinds(&got, r.found);
    count_kinds(ref, r.ref);
    compare(ref, &got, r.miss, r.extra);
    r.raw_contacts = raw;
    snprintf(r.note, sizeof r.note,
             "Bullet %s VF only; struct_bytes = heap kept by initializeFaceTree%s",
             bench_bullet_version(),
             cx->scale != 1.0 ? "; mesh scaled for its size dead zone" : "");
    cx->peak_rss_kb = peak_rss_kb();
    print_row(cx, &r);
    free(got.k);
}

// ---------------------------------------------------------------------------

// Number of edge-connected pieces of the surface (triangles joined through
// shared edges). Bullet 3.24's bottom-up face-tree build only merges
// edge-adjacent nodes and loops forever when more than one piece is left,
// so Bullet rows are skipped on such meshes.
static size_t edge_pieces(const selfcol_mesh *mesh) {
    size_t nt = selfcol_mesh_count(mesh, SELFCOL_MESH_TRIANGLES);
    size_t ne = selfcol_mesh_count(mesh, SELFCOL_MESH_EDGES);
    uint32_t *parent = malloc((nt ? nt : 1) * sizeof *parent);
    if (parent == NULL)
        return 0;
    for (size_t t = 0; t < nt; ++t)
        parent[t] = (uint32_t)t;
    for (size_t e = 0; e < ne; ++e) {
        const uint32_t *tris;
        size_t n;
        if (selfcol_mesh_edge_triangles(mesh, (uint32_t)e, &tris, &n) != SELFCOL_OK)
            continue;
        for (size_t i = 1; i < n; ++i) {
            uint32_t a = selfcol_union_find__root(parent, tris[0]),
                     b = selfcol_union_find__root(parent, tris[i]);
            if (a != b)
                parent[a] = b;
        }
    }
    size_t pieces = 0;
    for (size_t t = 0; t < nt; ++t)
        pieces += parent[t] == t;
    free(parent);
    return pieces;
}

static double median_build(const selfcol_mesh *mesh, unsigned reps, selfcol_hierarchy **keep) {
    double times[MAX_REPS];
    unsigned n = 0;
    *keep = NULL;
    for (unsigned i = 0; i < reps && i < MAX_REPS; ++i) {
        selfcol_hierarchy *h = NULL;
        double t0 = now();
        int rc = selfcol_hierarchy_create(&h, mesh, NULL);
        double t = now() - t0;
        if (rc != SELFCOL_OK) {
            fprintf(stderr, "selfcol-bench: hierarchy: %s\n", selfcol_status_string(rc));
            return -1.0;
        }
        times[n++] = t;
        if (*keep == NULL)
            *keep = h;
        else
            selfcol_hierarchy_destroy(h);
        if (t > SLOW_SECONDS / 4 && n >= 1)
            break; // large meshes: one build is enough to time
    }
    return summarize(times, n).med;
}

// Generates or reads the case's mesh into s and, for a refit case (p[2] =
// an earlier frame of the same scene), the earlier frame into prev (else
// prev is left empty). Returns 0, 1 when the case is skipped, -1 when it
// fails (both said on stderr).
static int load_case(const bench_case *bc, const char *data_dir, fixture *s, fixture *prev,
                     char *note, size_t note_size, int *refit_case) {
    memset(s, 0, sizeof *s);
    memset(prev, 0, sizeof *prev);
    int g = bc->gen(s, bc->p, data_dir, note, note_size);
    if (g == 1) {
        fprintf(stderr, "selfcol-bench: %s skipped (%s)\n", bc->name, note);
        return 1;
    }
    if (g != 0) {
        fprintf(stderr, "selfcol-bench: %s: cannot generate or read the scene\n", bc->name);
        return -1;
    }
    // A refit case: the mesh and its hierarchy are made on the earlier frame,
    // as a simulation would, then refit once to this frame; d comes from the
    // earlier frame (a sequence's d is its first frame's, as in selfcol-cli).
    *refit_case = bc->gen == gen_frame && bc->p[2] > 0;
    if (*refit_case) {
        const double pp[6] = {bc->p[0], bc->p[2], 0, 0, 0, 0};
        char prev_note[512];
        if (gen_frame(prev, pp, data_dir, prev_note, sizeof prev_note) != 0 ||
            prev->vertex_count != s->vertex_count || prev->triangle_count != s->triangle_count ||
            memcmp(prev->triangles, s->triangles, 3 * s->triangle_count * sizeof *s->triangles) !=
                0) {
            fprintf(stderr, "selfcol-bench: %s skipped (%s: not the same topology or absent)\n",
                    bc->name, prev_note);
            fixture_free(prev);
            fixture_free(s);
            return 1;
        }
    }
    return 0;
}

// The case's library mesh (on the earlier frame for a refit case) and the
// mesh columns of cx. Bullet rejects triangles with edges under ~1.8 cm (an
// absolute epsilon on a length^4); short-edged meshes are scaled by powers
// of 10 until the mean edge is at least 5 cm (a 1 m cloth of 20k faces:
// x10), for selfcol and Bullet alike (s and prev are scaled in place). Raw
// cases keep their size to show what happens. Returns the mesh, or NULL
// (said on stderr).
static selfcol_mesh *make_mesh(const bench_case *bc, fixture *s, fixture *prev, int refit_case,
                               context *cx) {
    selfcol_mesh *mesh = NULL;
    int rc =
        selfcol_mesh_create(&mesh, s->vertex_count, refit_case ? prev->positions : s->positions,
                            s->triangle_count, s->triangles, NULL);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: %s: mesh: %s\n", bc->name, selfcol_status_string(rc));
        return NULL;
    }
    cx->triangles = s->triangle_count;
    cx->vertices = s->vertex_count;
    cx->edges = selfcol_mesh_count(mesh, SELFCOL_MESH_EDGES);
    cx->mean_edge = selfcol_mesh_mean_edge_length(mesh);
    cx->scale = 1.0;
    while (!bc->raw && cx->mean_edge * cx->scale < 0.05)
        cx->scale *= 10.0;
    if (cx->scale == 1.0)
        return mesh;
    for (size_t i = 0; i < 3 * s->vertex_count; ++i)
        s->positions[i] *= cx->scale;
    for (size_t i = 0; refit_case && i < 3 * prev->vertex_count; ++i)
        prev->positions[i] *= cx->scale;
    rc = selfcol_mesh_set_positions(mesh, refit_case ? prev->positions : s->positions,
                                    s->vertex_count);
    cx->mean_edge *= cx->scale;
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: %s: %s\n", bc->name, selfcol_status_string(rc));
        selfcol_mesh_destroy(mesh);
        return NULL;
    }
    return mesh;
}

// Refit: positions unchanged, the cost of a frame's refit all the same; on
// `threads` threads (a context's, planned by the untimed first refit).
static timing time_refit(selfcol_hierarchy *h, unsigned threads, unsigned reps) {
    double refit_t[MAX_REPS];
    selfcol_context *threads_ctx = bench_context(threads);
#define REFIT()                                                                                    \
    (threads_ctx != NULL ? selfcol_context_refit(threads_ctx, h) : selfcol_hierarchy_refit(h))
    REFIT();
    for (unsigned i = 0; i < reps; ++i) {
        double t0 = now();
        REFIT();
        refit_t[i] = now() - t0;
    }
#undef REFIT
    selfcol_context_destroy(threads_ctx);
    return summarize(refit_t, reps);
}

// Cases from this size on get two-thread rows.
#define TWO_THREAD_ROWS_MIN_TRIANGLES 20000

// What the rows of one case share.
typedef struct case_run {
    const bench_case *bc;
    limits lim;
    context cx;
    const char *note; /* "frame PATH" for real frames */
    selfcol_hierarchy *h;
    selfcol_contacts *c;
    double build_s;
    size_t hier_bytes;
    timing refit;
    timing refit_two_threads; /* on a context of 2 threads (two-thread rows) */
    bench_bullet *bb;         /* NULL: no Bullet rows */
    double bullet_build_s;
    size_t bullet_bytes;
} case_run;

#ifdef SELFCOL_BENCH_BULLET
// Bullet: one body and one face-tree build per case, reused for both d.
static void make_bullet_body(case_run *run, const fixture *s, const selfcol_mesh *mesh) {
    const char *name = run->bc->name;
    size_t pieces = edge_pieces(mesh);
    if (s->triangle_count <= run->lim.bullet && pieces != 1)
        fprintf(stderr,
                "selfcol-bench: %s: no Bullet rows: %zu edge-connected pieces (Bullet 3.24's "
                "initializeFaceTree never terminates on more than one)\n",
                name, pieces);
    if (s->triangle_count <= run->lim.bullet && pieces == 1) {
        fprintf(stderr, "selfcol-bench: %s: Bullet face-tree build (%zu faces)...\n", name,
                s->triangle_count);
        run->bb = bench_bullet_create(s->vertex_count, s->positions, s->triangle_count,
                                      s->triangles, run->cx.edges, selfcol_mesh_edges(mesh),
                                      &run->bullet_build_s, &run->bullet_bytes);
        if (run->bb == NULL)
            fprintf(stderr, "selfcol-bench: %s: Bullet body failed\n", name);
    }
}
#endif

// One method of a case at run->cx.d.
typedef struct method_spec {
    uint32_t method, narrow, kinds;
    unsigned threads;
    int run;
} method_spec;

// Runs one method and prints its row, its contacts compared with the
// reference: the first method run becomes the reference (*ref, *ref_name).
// Returns 0 or 1.
static int method_row(case_run *run, const method_spec *m, keyset *ref, const char **ref_name) {
    context *cx = &run->cx;
    row r;
    memset(&r, 0, sizeof r);
    keyset got = {NULL, 0};
    fprintf(stderr, "selfcol-bench: %s d=%.1fx %s%s (%u thread(s))\n", run->bc->name, cx->d_factor,
            method_name(m->method), m->narrow == SELFCOL_NARROW_LIBCCD ? " (libccd)" : "",
            m->threads);
    if (run_method(run->h, run->c, m->method, m->narrow, m->kinds, cx->d, m->threads, run->lim.reps,
                   &r, &got) != 0)
        return 1;
    if (*ref_name == NULL) {
        // The first method run is the reference: EXHAUSTIVE if it ran, else
        // EXACT (proven equal on the smaller rows).
        *ref = got;
        *ref_name = method_name(m->method);
        got.k = malloc((ref->n ? ref->n : 1) * sizeof(key));
        if (got.k == NULL)
            return 1;
        memcpy(got.k, ref->k, ref->n * sizeof(key));
        got.n = ref->n;
    }
    const int vf_only = m->kinds == SELFCOL_KIND_VF;
    r.method = vf_only ? "EXACT-VF" : method_name(m->method);
    r.narrow = m->narrow == SELFCOL_NARROW_LIBCCD ? "libccd" : "closed-form";
    r.reference = *ref_name;
    r.refit = m->threads == 2 ? run->refit_two_threads : run->refit;
    r.build_ms = 1e3 * run->build_s;
    r.struct_bytes = m->method == SELFCOL_METHOD_EXHAUSTIVE ? 0 : run->hier_bytes;
    // The reference is sorted by kind, VF first: its VF set is a prefix.
    keyset ref_used = *ref;
    if (vf_only)
        for (ref_used.n = 0; ref_used.n < ref->n && ref->k[ref_used.n].kind == SELFCOL_CONTACT_VF;)
            ref_used.n++;
    count_kinds(&got, r.found);
    count_kinds(&ref_used, r.ref);
    compare(&ref_used, &got, r.miss, r.extra);
    if (m->method == SELFCOL_METHOD_EXHAUSTIVE) {
        // No hierarchy: its frame is the query alone.
        r.refit.med = r.refit.min = r.refit.max = 0.0;
        r.build_ms = 0.0;
    }
    if (strncmp(run->note, "frame", 5) == 0)
        snprintf(r.note, sizeof r.note, "%.255s", run->note);
    cx->peak_rss_kb = peak_rss_kb();
    print_row(cx, &r);
    free(got.k);
    return 0;
}

// The rows of a case at d = factor x mean edge: every method that runs at
// its size, then Bullet's. Returns 0 or 1.
static int rows_at_distance(case_run *run, double factor) {
    context *cx = &run->cx;
    cx->d_factor = factor;
    cx->d = factor * cx->mean_edge;
    const size_t triangles = cx->triangles;
    // EXACT-VF asks for vertex-triangle proximities only: the work Bullet
    // does (it has no edge-edge test and reports no crossing), so that the
    // two compare like for like; it is held to the reference's VF set alone.
    // EXACT on two threads too, from 20k triangles (below, a query takes a
    // few milliseconds and one thread is the setting that matters); its
    // refit is that of a hierarchy refitting on two threads.
    const int exhaustive = triangles <= run->lim.exhaustive;
    const int two_threads = triangles >= TWO_THREAD_ROWS_MIN_TRIANGLES;
    const method_spec methods[] = {
        {SELFCOL_METHOD_EXHAUSTIVE, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 1, exhaustive},
        {SELFCOL_METHOD_EXACT, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 1, 1},
        {SELFCOL_METHOD_EXACT, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 2, two_threads},
        {SELFCOL_METHOD_BVH, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 1, 1},
        {SELFCOL_METHOD_SEED, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 1, 1},
        {SELFCOL_METHOD_CONE, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_ALL, 1, 1},
        {SELFCOL_METHOD_BVH, SELFCOL_NARROW_LIBCCD, SELFCOL_KIND_ALL, 1,
         triangles <= run->lim.libccd},
        {SELFCOL_METHOD_EXACT, SELFCOL_NARROW_CLOSED_FORM, SELFCOL_KIND_VF, 1, 1},
    };
    keyset ref = {NULL, 0};
    const char *ref_name = NULL;
    int status = 0;
    for (size_t mi = 0; mi < sizeof methods / sizeof methods[0] && status == 0; ++mi)
        if (methods[mi].run)
            status = method_row(run, &methods[mi], &ref, &ref_name);
    if (status == 0 && run->bb != NULL) {
        fprintf(stderr, "selfcol-bench: %s d=%.1fx Bullet\n", run->bc->name, cx->d_factor);
        bullet_rows(run->bb, cx, &ref, ref_name, 1e3 * run->bullet_build_s, run->bullet_bytes,
                    run->lim.reps);
    }
    // Future rows (the Bullet adapter) go here: same mesh, same d, compared
    // with the same reference. The contact store has cases of its own
    // (store_cases): it needs a sequence of frames.
    free(ref.k);
    return status;
}

static int run_case(const bench_case *bc, unsigned subset, const char *subset_name,
                    const char *data_dir) {
    case_run run;
    memset(&run, 0, sizeof run);
    run.bc = bc;
    run.lim = limits_of(subset);
    fixture s, prev;
    char note[512] = "";
    int refit_case = 0;
    int loaded = load_case(bc, data_dir, &s, &prev, note, sizeof note, &refit_case);
    if (loaded != 0)
        return loaded < 0 ? 1 : 0;
    run.note = note;
    run.cx.subset = subset_name;
    run.cx.case_name = bc->name;
    run.cx.scene_name = bc->scene;
    selfcol_mesh *mesh = make_mesh(bc, &s, &prev, refit_case, &run.cx);
    if (mesh == NULL) {
        fixture_free(&prev);
        fixture_free(&s);
        return 1;
    }
    run.build_s = median_build(mesh, subset == SMOKE ? 1 : 3, &run.h);
    if (run.h == NULL || selfcol_contacts_create(&run.c, NULL) != SELFCOL_OK) {
        selfcol_hierarchy_destroy(run.h);
        selfcol_mesh_destroy(mesh);
        fixture_free(&prev);
        fixture_free(&s);
        return 1;
    }
    run.hier_bytes = selfcol_hierarchy_byte_count(run.h);
    int status = 0;
    if (refit_case && selfcol_mesh_set_positions(mesh, s.positions, s.vertex_count) != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: %s: set_positions failed\n", bc->name);
        status = 1;
    }
    fixture_free(&prev);
    run.refit = time_refit(run.h, 1, run.lim.reps);
    // The two-thread rows' refit: the same tree refit on a context of two
    // threads (the same boxes: the one-thread refits ignore its plan).
    if (run.cx.triangles >= TWO_THREAD_ROWS_MIN_TRIANGLES)
        run.refit_two_threads = time_refit(run.h, 2, run.lim.reps);
#ifdef SELFCOL_BENCH_BULLET
    make_bullet_body(&run, &s, mesh);
#endif
    const double factors[2] = {0.1, 0.5};
    for (int fi = 0; fi < 2 && status == 0; ++fi)
        status = rows_at_distance(&run, factors[fi]);
    bench_bullet_destroy(run.bb);
    selfcol_contacts_destroy(run.c);
    selfcol_hierarchy_destroy(run.h);
    selfcol_mesh_destroy(mesh);
    fixture_free(&s);
    return status;
}

// --dump DIR: writes the case's mesh (after the same scaling as run_case)
// and EXACT's VF and EE contact keys at both d, for reference runners
// outside this process (tools/bench/bench_ipctk.py):
//   DIR/NAME.mesh        "V F scale mean_edge scene", V lines "x y z", F lines "a b c"
//   DIR/NAME-dK.keys     "d", then one "kind first second" line per contact
// EF contacts are written too (kind 2): the reference runner counts them
// as misses when it reports no crossings.
static int dump_case(const bench_case *bc, const char *data_dir, const char *dir) {
    fixture s;
    memset(&s, 0, sizeof s);
    char note[512] = "", path[4096];
    int g = bc->gen(&s, bc->p, data_dir, note, sizeof note);
    if (g == 1) {
        fprintf(stderr, "selfcol-bench: %s skipped (%s)\n", bc->name, note);
        return 0;
    }
    if (g != 0)
        return 1;
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    int rc = selfcol_mesh_create(&mesh, s.vertex_count, s.positions, s.triangle_count, s.triangles,
                                 NULL);
    double mean_edge = rc == SELFCOL_OK ? selfcol_mesh_mean_edge_length(mesh) : 0.0;
    double scale = 1.0;
    while (rc == SELFCOL_OK && !bc->raw && mean_edge * scale < 0.05)
        scale *= 10.0;
    if (rc == SELFCOL_OK && scale != 1.0) {
        for (size_t i = 0; i < 3 * s.vertex_count; ++i)
            s.positions[i] *= scale;
        rc = selfcol_mesh_set_positions(mesh, s.positions, s.vertex_count);
        mean_edge *= scale;
    }
    if (rc == SELFCOL_OK)
        rc = selfcol_hierarchy_create(&h, mesh, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_contacts_create(&c, NULL);
    FILE *f = NULL;
    if (rc == SELFCOL_OK) {
        snprintf(path, sizeof path, "%s/%s.mesh", dir, bc->name);
        f = fopen(path, "w");
        rc = f ? SELFCOL_OK : SELFCOL_ERROR;
    }
    if (rc == SELFCOL_OK) {
        fprintf(f, "%zu %zu %.17g %.17g %s\n", s.vertex_count, s.triangle_count, scale, mean_edge,
                bc->scene);
        for (size_t v = 0; v < s.vertex_count; ++v)
            fprintf(f, "%.17g %.17g %.17g\n", s.positions[3 * v], s.positions[3 * v + 1],
                    s.positions[3 * v + 2]);
        for (size_t t = 0; t < s.triangle_count; ++t)
            fprintf(f, "%u %u %u\n", s.triangles[3 * t], s.triangles[3 * t + 1],
                    s.triangles[3 * t + 2]);
        rc = fclose(f) == 0 ? SELFCOL_OK : SELFCOL_ERROR;
    }
    const double factors[2] = {0.1, 0.5};
    for (int fi = 0; fi < 2 && rc == SELFCOL_OK; ++fi) {
        selfcol_query_options o;
        selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
        o.method = SELFCOL_METHOD_EXACT;
        o.distance = factors[fi] * mean_edge;
        rc = selfcol_hierarchy_self_collide(h, c, &o);
        const selfcol_contact *data;
        size_t n = 0;
        if (rc == SELFCOL_OK)
            rc = selfcol_contacts_data(c, &data, &n);
        snprintf(path, sizeof path, "%s/%s-d%g.keys", dir, bc->name, factors[fi]);
        if (rc == SELFCOL_OK && (f = fopen(path, "w")) == NULL)
            rc = SELFCOL_ERROR;
        if (rc == SELFCOL_OK) {
            fprintf(f, "%.17g\n", o.distance);
            for (size_t i = 0; i < n; ++i)
                fprintf(f, "%u %u %u\n", data[i].kind, data[i].first, data[i].second);
            rc = fclose(f) == 0 ? SELFCOL_OK : SELFCOL_ERROR;
        }
    }
    if (rc != SELFCOL_OK)
        fprintf(stderr, "selfcol-bench: %s: dump failed (%s)\n", bc->name,
                selfcol_status_string(rc));
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(mesh);
    fixture_free(&s);
    return rc == SELFCOL_OK ? 0 : 1;
}

// ---------------------------------------------------------------------------
// Contact-store rows: the cost of selfcol_store_update (merge, sides,
// regions and the vote) per held contact, fed with EXACT's query result of
// each frame at d = 0.1 x mean edge (all kinds, closed form, one thread: the
// settings of the EXACT rows), default store options (remnance 4,
// consistency on). Two kinds of case:
//   sequence (p = grid n, seed, frames, step): the crumpled n x n sheet
//     (fixture_crumpled, amplitude 5) with its crumple growing frame to frame:
//     frame f = 0 .. frames - 1 has the positions grid + (1 + step f) x
//     (crumpled - grid), i.e. the crumpled sheet of amplitude 5 (1 + step f),
//     one topology. Each run updates a fresh store with every frame in order
//     (positions set, hierarchy refit, query, update). Row STORE-FIRST:
//     update 1 (the store's arrays grow); row STORE: updates 3 .. frames of
//     every run (steady state: update 2 sizes the arrays for the held plus
//     detected contacts; they double again only when those pass a power of
//     two, and the note counts the updates where they did).
//   pair (p = real scene index, frame a, frame b): STORE-FIRST is frame a's
//     update on a fresh store; STORE is frame b's update on a store holding
//     frame a's contacts, its arrays already grown (after one untimed a, b
//     pair the store is cleared, which keeps its memory, before each timed
//     pair). The b update on a fresh store goes in the note.
// Times are medians over the samples (updates x runs) with min and max;
// ns per contact is the median over samples of update time / VF+EE contacts
// held after the update, bytes per contact likewise with
// selfcol_store_byte_count; the counters are means over the row's updates.
// query_ms and refit_ms are the same frames' EXACT query and refit, so that
// the store's share of a frame shows; struct_bytes is the store's largest
// byte count; raw_contacts the records the query fed it.

typedef struct store_case {
    const char *name, *scene;
    unsigned subsets;
    int pair;    // 0: crumpled sequence, 1: two real frames
    double p[4]; // see above
} store_case;

static const store_case store_cases[] = {
    {"store-crumpled-2k", "crumpled", SMOKE, 0, {32, 1, 5, 0.01}},
    {"store-crumpled-200k", "crumpled", BIG, 0, {316, 1, 12, 0.01}},
    {"store-cloth-ball-93", "cloth-ball", BIG, 1, {0, 92, 93}},
};

typedef struct store_sample {
    double refit, query, update; // seconds
    selfcol_store_update_stats st;
    uint64_t held[3];  // VF, EE, EF records held after the update
    uint64_t detected; // records of the query fed to it
    size_t bytes;      // selfcol_store_byte_count after it
    int grew;          // the byte count grew in this update
    uint64_t digest;   // FNV-1a of the held records and the regions (store_digest)
} store_sample;

// FNV-1a over n bytes, continuing from h.
static uint64_t fnv1a(uint64_t h, const void *data, size_t n) {
    const unsigned char *b = data;
    for (size_t i = 0; i < n; ++i)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

// One timed update (selfcol_store_update_swept from `start` when not NULL),
// on `context`'s threads (NULL: one); the sample's refit and query are the
// caller's.
static int store_measure(selfcol_context *threads_ctx, selfcol_store *store,
                         const selfcol_mesh *mesh, const selfcol_contacts *detected,
                         const double *start, store_sample *sm) {
    const size_t before = selfcol_store_byte_count(store);
    double t0 = now();
    int rc;
    if (threads_ctx != NULL)
        rc = start != NULL ? selfcol_context_store_update_swept(threads_ctx, store, mesh, NULL,
                                                                detected, start, NULL)
                           : selfcol_context_store_update(threads_ctx, store, mesh, NULL, detected);
    else
        rc = start != NULL ? selfcol_store_update_swept(store, mesh, NULL, detected, start, NULL)
                           : selfcol_store_update(store, mesh, NULL, detected);
    sm->update = now() - t0;
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: store update: %s\n", selfcol_status_string(rc));
        return rc;
    }
    sm->st.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    selfcol_store_stats(store, &sm->st);
    // The held records by kind, copied in blocks (untimed: a copy computes
    // each record's geometry).
    enum { BLOCK = 4096 };
    static selfcol_store_contact e[BLOCK];
    const size_t n = selfcol_store_contact_count(store);
    sm->held[0] = sm->held[1] = sm->held[2] = 0;
    // The digest: every field of every held record (copied whole: the
    // struct has no padding, 14 words then doubles) and every region, so
    // that a change to the store's code that should not change its result
    // is checked on the bench's frames (the log's digest, before and after).
    uint64_t digest = 0xcbf29ce484222325ull;
    for (size_t at = 0; at < n; at += BLOCK) {
        const size_t k = n - at < BLOCK ? n - at : BLOCK;
        rc = selfcol_store_copy_contacts(store, at, k, e);
        if (rc != SELFCOL_OK) {
            fprintf(stderr, "selfcol-bench: store copy: %s\n", selfcol_status_string(rc));
            return rc;
        }
        for (size_t i = 0; i < k; ++i)
            sm->held[e[i].kind < 3 ? e[i].kind : 2]++;
        digest = fnv1a(digest, e, k * sizeof *e);
    }
    const selfcol_store_region *regions;
    size_t region_count;
    rc = selfcol_store_regions(store, &regions, &region_count);
    if (rc != SELFCOL_OK) {
        fprintf(stderr, "selfcol-bench: store regions: %s\n", selfcol_status_string(rc));
        return rc;
    }
    sm->digest = fnv1a(digest, regions, region_count * sizeof *regions);
    const selfcol_contact *d;
    size_t m;
    selfcol_contacts_data(detected, &d, &m);
    sm->detected = m;
    sm->bytes = selfcol_store_byte_count(store);
    sm->grew = sm->bytes > before;
    return SELFCOL_OK;
}

static void store_log(const char *name, const char *what, const store_sample *sm) {
    fprintf(stderr,
            "selfcol-bench: %s %s: detected %llu, held VF %llu EE %llu EF %llu, new %llu kept "
            "%llu remnant %llu dropped %llu flipped %llu corrected %llu, regions %llu; update "
            "%.2f ms, query %.1f ms, store %zu bytes%s, digest %016llx\n",
            name, what, (unsigned long long)sm->detected, (unsigned long long)sm->held[0],
            (unsigned long long)sm->held[1], (unsigned long long)sm->held[2],
            (unsigned long long)sm->st.new_contacts, (unsigned long long)sm->st.kept,
            (unsigned long long)sm->st.remnant, (unsigned long long)sm->st.dropped,
            (unsigned long long)sm->st.flipped, (unsigned long long)sm->st.corrected,
            (unsigned long long)sm->st.regions, 1e3 * sm->update, 1e3 * sm->query, sm->bytes,
            sm->grew ? " (grew)" : "", (unsigned long long)sm->digest);
}

enum { S_REFIT, S_QUERY, S_UPDATE, S_NS, S_BYTES };

static double sample_value(const store_sample *sm, int what) {
    const double held = (double)sm->st.contacts;
    switch (what) {
    case S_REFIT: return sm->refit;
    case S_QUERY: return sm->query;
    case S_UPDATE: return sm->update;
    case S_NS: return held > 0 ? 1e9 * sm->update / held : 0.0;
    default: return held > 0 ? (double)sm->bytes / held : 0.0;
    }
}

// One STORE or STORE-FIRST row from n samples of updates on `threads`.
static int store_row(context *cx, const char *method, unsigned threads, const store_sample *sm,
                     size_t n, const char *note) {
    double *t = malloc((n ? n : 1) * sizeof *t);
    if (t == NULL || n == 0) {
        free(t);
        return 1;
    }
    row r;
    memset(&r, 0, sizeof r);
    r.method = method;
    r.narrow = "closed-form";
    r.reference = "none";
    r.threads = threads;
    timing *out[3] = {&r.refit, &r.query, &r.update};
    for (int w = S_REFIT; w <= S_BYTES; ++w) {
        for (size_t i = 0; i < n; ++i)
            t[i] = sample_value(&sm[i], w);
        timing m = summarize(t, (unsigned)n);
        if (w <= S_UPDATE)
            *out[w] = m;
        else if (w == S_NS)
            r.ns_per_contact = m.med;
        else
            r.bytes_per_contact = m.med;
    }
    free(t);
    double held[3] = {0, 0, 0}, detected = 0;
    for (size_t i = 0; i < n; ++i) {
        const selfcol_store_update_stats *st = &sm[i].st;
        for (int k = 0; k < 3; ++k)
            held[k] += (double)sm[i].held[k];
        detected += (double)sm[i].detected;
        r.held += (double)st->contacts;
        r.regions += (double)st->regions;
        r.st_new += (double)st->new_contacts;
        r.st_kept += (double)st->kept;
        r.st_remnant += (double)st->remnant;
        r.st_dropped += (double)st->dropped;
        r.st_flipped += (double)st->flipped;
        r.st_corrected += (double)st->corrected;
        if (sm[i].bytes > r.struct_bytes)
            r.struct_bytes = sm[i].bytes;
    }
    const double inv = 1.0 / (double)n;
    for (int k = 0; k < 3; ++k)
        r.found[k] = (uint64_t)llround(held[k] * inv);
    r.raw_contacts = (uint64_t)llround(detected * inv);
    r.held *= inv, r.regions *= inv, r.st_new *= inv, r.st_kept *= inv, r.st_remnant *= inv;
    r.st_dropped *= inv, r.st_flipped *= inv, r.st_corrected *= inv;
    snprintf(r.note, sizeof r.note, "%.255s", note);
    cx->peak_rss_kb = peak_rss_kb();
    print_row(cx, &r);
    return 0;
}

static void store_options(selfcol_query_options *o, double d) {
    selfcol_query_options_init(o, SELFCOL_QUERY_OPTIONS_VERSION);
    o->method = SELFCOL_METHOD_EXACT;
    o->narrow = SELFCOL_NARROW_CLOSED_FORM;
    o->kinds = SELFCOL_KIND_ALL;
    o->distance = d;
}

// A store with default options (its threads are the update's context's).
static int store_create(selfcol_store **store) {
    return selfcol_store_create(store, NULL);
}

static void store_context(context *cx, const store_case *sc, const char *subset_name,
                          const fixture *s, const selfcol_mesh *mesh, double scale) {
    memset(cx, 0, sizeof *cx);
    cx->subset = subset_name;
    cx->case_name = sc->name;
    cx->scene_name = sc->scene;
    cx->triangles = s->triangle_count;
    cx->vertices = s->vertex_count;
    cx->edges = selfcol_mesh_count(mesh, SELFCOL_MESH_EDGES);
    cx->scale = scale;
    cx->mean_edge = selfcol_mesh_mean_edge_length(mesh);
    cx->d_factor = 0.1;
    cx->d = 0.1 * cx->mean_edge;
}

static int count_grew(const store_sample *sm, size_t n) {
    int g = 0;
    for (size_t i = 0; i < n; ++i)
        g += sm[i].grew;
    return g;
}

static int run_store_sequence(const store_case *sc, unsigned subset, const char *subset_name) {
    const limits lim = limits_of(subset);
    const unsigned n = (unsigned)sc->p[0], seed = (unsigned)sc->p[1], frames = (unsigned)sc->p[2];
    const double step = sc->p[3];
    const unsigned runs = lim.store_runs;
    fixture s, g;
    memset(&s, 0, sizeof s);
    memset(&g, 0, sizeof g);
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    selfcol_store *store = NULL, *store2 = NULL;
    selfcol_context *two = bench_context(2); // store2's updates
    store_sample *first = calloc(runs, sizeof *first);
    store_sample *steady = calloc((size_t)runs * (frames - 2), sizeof *steady);
    store_sample *steady2 = calloc((size_t)runs * (frames - 2), sizeof *steady2);
    double *pos = NULL;
    int rc = frames >= 3 && first && steady && steady2 ? SELFCOL_OK : SELFCOL_ENOMEM;
    if (rc == SELFCOL_OK &&
        (fixture_crumpled(&s, n, n, seed, 5.0) != 0 || fixture_grid(&g, n, n, 1.0) != 0))
        rc = SELFCOL_ENOMEM;
    if (rc == SELFCOL_OK && (pos = malloc(3 * s.vertex_count * sizeof *pos)) == NULL)
        rc = SELFCOL_ENOMEM;
    // Frame f: the grid plus (1 + step f) times the amplitude-5 displacement.
    for (size_t i = 0; rc == SELFCOL_OK && i < 3 * s.vertex_count; ++i)
        pos[i] = g.positions[i] + (s.positions[i] - g.positions[i]);
    if (rc == SELFCOL_OK)
        rc = selfcol_mesh_create(&mesh, s.vertex_count, pos, s.triangle_count, s.triangles, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_hierarchy_create(&h, mesh, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_contacts_create(&c, NULL);
    context cx;
    selfcol_query_options o;
    if (rc == SELFCOL_OK) {
        store_context(&cx, sc, subset_name, &s, mesh, 1.0);
        store_options(&o, cx.d);
        rc = selfcol_hierarchy_self_collide(h, c, &o); // warm-up
    }
    size_t ns = 0;
    for (unsigned run = 0; rc == SELFCOL_OK && run < runs; ++run) {
        rc = store_create(&store);
        if (rc == SELFCOL_OK)
            rc = store_create(&store2);
        for (unsigned f = 0; rc == SELFCOL_OK && f < frames; ++f) {
            const double k = 1.0 + step * f;
            for (size_t i = 0; i < 3 * s.vertex_count; ++i)
                pos[i] = g.positions[i] + k * (s.positions[i] - g.positions[i]);
            store_sample sm;
            memset(&sm, 0, sizeof sm);
            rc = selfcol_mesh_set_positions(mesh, pos, s.vertex_count);
            double t0 = now();
            if (rc == SELFCOL_OK)
                rc = selfcol_hierarchy_refit(h);
            double t1 = now();
            if (rc == SELFCOL_OK)
                rc = selfcol_hierarchy_self_collide(h, c, &o);
            sm.refit = t1 - t0;
            sm.query = now() - t1;
            store_sample sm2 = sm;
            if (rc == SELFCOL_OK)
                rc = store_measure(NULL, store, mesh, c, NULL, &sm);
            if (rc == SELFCOL_OK) // the same update on two threads, right after
                rc = store_measure(two, store2, mesh, c, NULL, &sm2);
            if (rc == SELFCOL_OK && sm2.digest != sm.digest) {
                fprintf(stderr, "selfcol-bench: %s frame %u: the store on 2 threads differs\n",
                        sc->name, f);
                rc = SELFCOL_ERROR;
            }
            if (rc != SELFCOL_OK)
                break;
            if (run == 0) {
                char what[64];
                snprintf(what, sizeof what, "frame %u (amplitude %.4g)", f, 5.0 * k);
                store_log(sc->name, what, &sm);
            }
            if (f == 0)
                first[run] = sm;
            else if (f >= 2) {
                steady2[ns] = sm2;
                steady[ns++] = sm;
            }
        }
        selfcol_store_destroy(store);
        selfcol_store_destroy(store2);
        store = store2 = NULL;
    }
    selfcol_context_destroy(two);
    int status = rc == SELFCOL_OK ? 0 : 1;
    if (rc != SELFCOL_OK)
        fprintf(stderr, "selfcol-bench: %s: %s\n", sc->name, selfcol_status_string(rc));
    if (status == 0) {
        char note[256];
        snprintf(note, sizeof note,
                 "crumpled %ux%u seed %u; update 1 of %u runs (fresh store; arrays grow)", n, n,
                 seed, runs);
        status |= store_row(&cx, "STORE-FIRST", 1, first, runs, note);
        snprintf(note, sizeof note,
                 "crumpled %ux%u seed %u; amplitude 5(1+%g f) f=0..%u; updates 3..%u x %u runs; "
                 "counters: means; arrays grew in %d of %zu",
                 n, n, seed, step, frames - 1, frames, runs, count_grew(steady, ns), ns);
        status |= store_row(&cx, "STORE", 1, steady, ns, note);
        snprintf(note, sizeof note,
                 "as STORE, a second store on 2 threads updated right after it, each frame");
        status |= store_row(&cx, "STORE", 2, steady2, ns, note);
    }
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(mesh);
    free(pos);
    free(first);
    free(steady);
    free(steady2);
    fixture_free(&s);
    fixture_free(&g);
    return status;
}

static int run_store_pair(const store_case *sc, unsigned subset, const char *subset_name,
                          const char *data_dir) {
    const limits lim = limits_of(subset);
    const unsigned reps = lim.reps;
    fixture a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    char note_a[512] = "", note_b[512] = "";
    const double pa[6] = {sc->p[0], sc->p[1], 0, 0, 0, 0}, pb[6] = {sc->p[0], sc->p[2], 0, 0, 0, 0};
    int ga = gen_frame(&a, pa, data_dir, note_a, sizeof note_a);
    int gb = ga == 0 ? gen_frame(&b, pb, data_dir, note_b, sizeof note_b) : 1;
    if (ga != 0 || gb != 0 || a.vertex_count != b.vertex_count ||
        a.triangle_count != b.triangle_count ||
        memcmp(a.triangles, b.triangles, 3 * a.triangle_count * sizeof *a.triangles) != 0) {
        fprintf(stderr,
                "selfcol-bench: %s skipped (%s%s%s: absent, unreadable or not one topology)\n",
                sc->name, note_a, note_b[0] ? "; " : "", note_b);
        fixture_free(&a);
        fixture_free(&b);
        return ga < 0 || gb < 0 ? 1 : 0;
    }
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *ca = NULL, *cb = NULL;
    selfcol_store *store = NULL;
    store_sample first[MAX_REPS], fresh[MAX_REPS], steady[MAX_REPS], steady2[MAX_REPS],
        swept[MAX_REPS];
    double qa[MAX_REPS], qb[MAX_REPS], refit[MAX_REPS];
    memset(first, 0, sizeof first);
    memset(fresh, 0, sizeof fresh);
    memset(steady, 0, sizeof steady);
    memset(steady2, 0, sizeof steady2);
    memset(swept, 0, sizeof swept);
    int rc = selfcol_mesh_create(&mesh, a.vertex_count, a.positions, a.triangle_count, a.triangles,
                                 NULL);
    // The scale rule of run_case (mean edge at least 5 cm), so that these rows
    // run on the mesh of the other cloth-ball rows.
    double scale = 1.0;
    const double mean_edge = rc == SELFCOL_OK ? selfcol_mesh_mean_edge_length(mesh) : 0.0;
    while (rc == SELFCOL_OK && mean_edge * scale < 0.05)
        scale *= 10.0;
    for (size_t i = 0; scale != 1.0 && i < 3 * a.vertex_count; ++i)
        a.positions[i] *= scale, b.positions[i] *= scale;
    if (rc == SELFCOL_OK)
        rc = selfcol_mesh_set_positions(mesh, a.positions, a.vertex_count);
    if (rc == SELFCOL_OK)
        rc = selfcol_hierarchy_create(&h, mesh, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_contacts_create(&ca, NULL);
    if (rc == SELFCOL_OK)
        rc = selfcol_contacts_create(&cb, NULL);
    context cx;
    selfcol_query_options o;
    if (rc == SELFCOL_OK) {
        store_context(&cx, sc, subset_name, &a, mesh, scale);
        store_options(&o, cx.d);
        fprintf(stderr, "selfcol-bench: %s: queries of frames %g and %g\n", sc->name, sc->p[1],
                sc->p[2]);
    }
    // Frame a's query (the hierarchy is built on it), then frame b's after a
    // refit (as cloth-ball-93-refit): one warm-up and reps timed runs each.
    for (unsigned i = 0; rc == SELFCOL_OK && i <= reps; ++i) {
        double t0 = now();
        rc = selfcol_hierarchy_self_collide(h, ca, &o);
        if (i > 0)
            qa[i - 1] = now() - t0;
    }
    if (rc == SELFCOL_OK)
        rc = selfcol_mesh_set_positions(mesh, b.positions, b.vertex_count);
    for (unsigned i = 0; rc == SELFCOL_OK && i <= reps; ++i) {
        double t0 = now();
        rc = selfcol_hierarchy_refit(h);
        if (i > 0)
            refit[i - 1] = now() - t0;
    }
    for (unsigned i = 0; rc == SELFCOL_OK && i <= reps; ++i) {
        double t0 = now();
        rc = selfcol_hierarchy_self_collide(h, cb, &o);
        if (i > 0)
            qb[i - 1] = now() - t0;
    }
    // a then b on a fresh store, reps times: STORE-FIRST, and b's growth.
    for (unsigned i = 0; rc == SELFCOL_OK && i < reps; ++i) {
        rc = store_create(&store);
        if (rc == SELFCOL_OK)
            rc = selfcol_mesh_set_positions(mesh, a.positions, a.vertex_count);
        if (rc == SELFCOL_OK)
            rc = store_measure(NULL, store, mesh, ca, NULL, &first[i]);
        if (rc == SELFCOL_OK)
            rc = selfcol_mesh_set_positions(mesh, b.positions, b.vertex_count);
        if (rc == SELFCOL_OK)
            rc = store_measure(NULL, store, mesh, cb, NULL, &fresh[i]);
        first[i].query = qa[i], first[i].refit = refit[i];
        fresh[i].query = qb[i], fresh[i].refit = refit[i];
        selfcol_store_destroy(store);
        store = NULL;
    }
    // b on a store holding a, its arrays grown: one untimed pair, then clear
    // (memory kept), a, timed b, reps times; on one thread, on two, and with
    // the step's start (selfcol_store_update_swept from a's positions, one
    // thread), in turn (one store each).
    selfcol_store *stores[3] = {NULL, NULL, NULL};
    selfcol_context *two = bench_context(2); // stores[1]'s updates
    store_sample *samples[3] = {steady, steady2, swept};
    for (int t = 0; t < 3 && rc == SELFCOL_OK; ++t)
        rc = store_create(&stores[t]);
    for (unsigned i = 0; rc == SELFCOL_OK && i <= reps; ++i) {
        for (int t = 0; t < 3 && rc == SELFCOL_OK; ++t) {
            store_sample warm;
            selfcol_store_clear(stores[t]);
            rc = selfcol_mesh_set_positions(mesh, a.positions, a.vertex_count);
            if (rc == SELFCOL_OK)
                rc = t == 1 ? selfcol_context_store_update(two, stores[t], mesh, NULL, ca)
                            : selfcol_store_update(stores[t], mesh, NULL, ca);
            if (rc == SELFCOL_OK)
                rc = selfcol_mesh_set_positions(mesh, b.positions, b.vertex_count);
            if (rc == SELFCOL_OK)
                rc = store_measure(t == 1 ? two : NULL, stores[t], mesh, cb,
                                   t == 2 ? a.positions : NULL, i > 0 ? &samples[t][i - 1] : &warm);
            if (i > 0)
                samples[t][i - 1].query = qb[i - 1], samples[t][i - 1].refit = refit[i - 1];
        }
    }
    for (int t = 0; t < 3; ++t)
        selfcol_store_destroy(stores[t]);
    selfcol_context_destroy(two);
    int status = rc == SELFCOL_OK ? 0 : 1;
    if (rc != SELFCOL_OK)
        fprintf(stderr, "selfcol-bench: %s: %s\n", sc->name, selfcol_status_string(rc));
    if (status == 0) {
        char what[64], note[256];
        snprintf(what, sizeof what, "frame %g, fresh store", sc->p[1]);
        store_log(sc->name, what, &first[0]);
        snprintf(what, sizeof what, "frame %g after %g, fresh store", sc->p[2], sc->p[1]);
        store_log(sc->name, what, &fresh[0]);
        snprintf(what, sizeof what, "frame %g after %g, grown store", sc->p[2], sc->p[1]);
        store_log(sc->name, what, &steady[0]);
        snprintf(what, sizeof what, "frame %g after %g, swept from %g", sc->p[2], sc->p[1],
                 sc->p[1]);
        store_log(sc->name, what, &swept[0]);
        for (unsigned i = 0; i < reps; ++i)
            if (steady2[i].digest != steady[i].digest || fresh[i].digest != steady[i].digest) {
                fprintf(stderr,
                        "selfcol-bench: %s: the stores of frame %g differ (fresh, "
                        "grown, 2 threads)\n",
                        sc->name, sc->p[2]);
                status = 1;
            }
        double t[MAX_REPS];
        for (unsigned i = 0; i < reps; ++i)
            t[i] = fresh[i].update;
        const timing tf = summarize(t, reps);
        snprintf(note, sizeof note, "frame %g update on a fresh store; %u reps", sc->p[1], reps);
        status |= store_row(&cx, "STORE-FIRST", 1, first, reps, note);
        snprintf(note, sizeof note,
                 "frame %g update after %g (store cleared between reps: arrays grown); on a "
                 "fresh store %.2f ms",
                 sc->p[2], sc->p[1], 1e3 * tf.med);
        status |= store_row(&cx, "STORE", 1, steady, reps, note);
        snprintf(note, sizeof note, "as STORE on 2 threads, alternating with it");
        status |= store_row(&cx, "STORE", 2, steady2, reps, note);
        snprintf(note, sizeof note,
                 "as STORE, with frame %g's positions as the step's start "
                 "(selfcol_store_update_swept), alternating with it",
                 sc->p[1]);
        status |= store_row(&cx, "STORE-SWEPT", 1, swept, reps, note);
    }
    selfcol_contacts_destroy(ca);
    selfcol_contacts_destroy(cb);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(mesh);
    fixture_free(&a);
    fixture_free(&b);
    return status;
}

#ifndef SELFCOL_BENCH_BULLET
// Without Bullet the runner still links: no Bullet rows.
bench_bullet *bench_bullet_create(size_t vertex_count, const double *xyz, size_t triangle_count,
                                  const uint32_t *triangles, size_t edge_count,
                                  const uint32_t *edges, double *build_seconds,
                                  size_t *tree_bytes) {
    (void)vertex_count, (void)xyz, (void)triangle_count, (void)triangles, (void)edge_count;
    (void)edges, (void)build_seconds, (void)tree_bytes;
    return NULL;
}
void bench_bullet_set_distance(bench_bullet *b, double d) {
    (void)b, (void)d;
}
double bench_bullet_refit(bench_bullet *b) {
    return (void)b, 0.0;
}
double bench_bullet_self_collide(bench_bullet *b) {
    return (void)b, 0.0;
}
size_t bench_bullet_contacts(bench_bullet *b, size_t *raw, uint64_t **pairs) {
    (void)b, (void)raw, (void)pairs;
    return (size_t)-1;
}
void bench_bullet_destroy(bench_bullet *b) {
    (void)b;
}
const char *bench_bullet_version(void) {
    return "absent";
}
#endif

static unsigned subset_of(const char *name) {
    if (name == NULL)
        return 0;
    return strcmp(name, "smoke") == 0     ? SMOKE
           : strcmp(name, "default") == 0 ? DEFAULT
           : strcmp(name, "full") == 0    ? FULL
                                          : 0;
}

int main(int argc, char **argv) {
    const char *list = NULL, *case_name = NULL, *subset_name = NULL, *data_dir = NULL;
    const char *dump_dir = NULL;
    int want_header = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--list") == 0 && i + 1 < argc)
            list = argv[++i];
        else if (strcmp(argv[i], "--case") == 0 && i + 1 < argc)
            case_name = argv[++i];
        else if (strcmp(argv[i], "--subset") == 0 && i + 1 < argc)
            subset_name = argv[++i];
        else if (strcmp(argv[i], "--data") == 0 && i + 1 < argc)
            data_dir = argv[++i];
        else if (strcmp(argv[i], "--dump") == 0 && i + 1 < argc)
            dump_dir = argv[++i];
        else if (strcmp(argv[i], "--header") == 0)
            want_header = 1;
        else if (strcmp(argv[i], "--bullet") == 0) {
#ifdef SELFCOL_BENCH_BULLET
            printf("%s\n", bench_bullet_version());
            return 0;
#else
            printf("absent\n");
            return 1;
#endif
        } else {
            fprintf(stderr,
                    "usage: %s --list SUBSET | --header | --bullet | --case NAME --subset SUBSET "
                    "[--data DIR] | --case NAME --dump DIR [--data DIR]\n",
                    argv[0]);
            return 2;
        }
    }
    if (want_header) {
        printf("%s\n", header);
        return 0;
    }
    if (list != NULL) {
        unsigned sub = subset_of(list);
        if (sub == 0) {
            fprintf(stderr, "selfcol-bench: unknown subset '%s'\n", list);
            return 2;
        }
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
            if (cases[i].subsets & sub)
                printf("%s\n", cases[i].name);
        for (size_t i = 0; i < sizeof store_cases / sizeof store_cases[0]; ++i)
            if (store_cases[i].subsets & sub)
                printf("%s\n", store_cases[i].name);
        return 0;
    }
    if (data_dir == NULL)
        data_dir =
            getenv("SELFCOL_SHARED_DATA") ? getenv("SELFCOL_SHARED_DATA") : BENCH_DEFAULT_DATA_DIR;
    if (dump_dir != NULL && case_name != NULL) {
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
            if (strcmp(cases[i].name, case_name) == 0)
                return dump_case(&cases[i], data_dir, dump_dir);
        fprintf(stderr, "selfcol-bench: unknown case '%s'\n", case_name);
        return 2;
    }
    unsigned sub = subset_of(subset_name);
    if (case_name == NULL || sub == 0) {
        fprintf(stderr, "selfcol-bench: --case NAME and --subset smoke|default|full needed\n");
        return 2;
    }
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        if (strcmp(cases[i].name, case_name) == 0)
            return run_case(&cases[i], sub, subset_name, data_dir);
    for (size_t i = 0; i < sizeof store_cases / sizeof store_cases[0]; ++i) {
        const store_case *sc = &store_cases[i];
        if (strcmp(sc->name, case_name) == 0)
            return sc->pair ? run_store_pair(sc, sub, subset_name, data_dir)
                            : run_store_sequence(sc, sub, subset_name);
    }
    fprintf(stderr, "selfcol-bench: unknown case '%s'\n", case_name);
    return 2;
}
