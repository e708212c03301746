// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bench-sweep: continuous queries (sweep.h) over one simulation step
// of each real scene (../shared/data/sample-scalable-ccd-data: cloth-funnel
// 227 -> 228, rod-twist 3036 -> 3037, cloth-ball 92 -> 93) and of a slowly
// crumpling 200k-triangle sheet, separation 0. Per case and row (ALL: every
// colliding pair, on one thread and on two; EARLIEST: the collision-free
// fraction only, one thread), the median over --reps runs (rows interleaved)
// of the whole query,
// its broad phase (swept boxes, candidates and the separating-direction
// filter) and its narrow phase (root finding), with the counters.
//
// --dump DIR also writes each step as DIR/<case>.step for
// tools/bench/bench_ipctk_sweep.py (ipc-toolkit's continuous check on the
// same positions): "nv nf\n", then 3 nv start doubles, 3 nv end doubles and
// 3 nf int32 indices, native byte order.
//
// usage: selfcol-bench-sweep [--data DIR] [--reps N] [--only NAME] [--dump DIR] [--smoke]
//        [--earliest] [--threads N] [--tolerance T]
// --earliest runs the EARLIEST rows only (the ALL rows take seconds each);
// --threads N runs the rows marked "2 threads" on N (2 to 64) instead;
// --tolerance T sets selfcol_sweep_options.tolerance (default 1e-6, the
// library's: the committed rows and ipc-toolkit's 1e-6 are at it).
#include <selfcol/selfcol.h>

#include "fixtures.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct bench_step {
    char name[64];
    fixture start, end;
} bench_step;

static int load_real(bench_step *b, const char *data, const char *name, const char *dir,
                     const char *f0, const char *f1) {
    char p0[4096], p1[4096], err[512];
    snprintf(p0, sizeof p0, "%s/sample-scalable-ccd-data/%s/frames/%s", data, dir, f0);
    snprintf(p1, sizeof p1, "%s/sample-scalable-ccd-data/%s/frames/%s", data, dir, f1);
    if (fixture_read(p0, &b->start, err, sizeof err) != 0) {
        fprintf(stderr, "bench-sweep: %s skipped (%s)\n", name, err);
        return 0;
    }
    if (fixture_read(p1, &b->end, err, sizeof err) != 0 ||
        b->end.vertex_count != b->start.vertex_count) {
        fprintf(stderr, "bench-sweep: %s skipped (second frame)\n", name);
        fixture_free(&b->start);
        return 0;
    }
    snprintf(b->name, sizeof b->name, "%s", name);
    return 1;
}

// A crumpled n x n sheet whose folds deepen a little in one step (amplitude
// 3.0 -> 3.05: vertices move up to about a fifth of an edge).
static int load_crumple(bench_step *b, unsigned n, const char *name) {
    if (fixture_crumpled(&b->start, n, n, 1, 3.0) != 0)
        return 0;
    if (fixture_crumpled(&b->end, n, n, 1, 3.05) != 0) {
        fixture_free(&b->start);
        return 0;
    }
    snprintf(b->name, sizeof b->name, "%s", name);
    return 1;
}

static void dump(const bench_step *b, const char *dir) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.step", dir, b->name);
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "bench-sweep: cannot write %s\n", path);
        exit(1);
    }
    fprintf(f, "%zu %zu\n", b->end.vertex_count, b->end.triangle_count);
    fwrite(b->start.positions, sizeof(double), 3 * b->start.vertex_count, f);
    fwrite(b->end.positions, sizeof(double), 3 * b->end.vertex_count, f);
    for (size_t i = 0; i < 3 * b->end.triangle_count; ++i) {
        const int32_t x = (int32_t)b->end.triangles[i];
        fwrite(&x, sizeof x, 1, f);
    }
    fclose(f);
}

static int by_value(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#define MAX_REPS 64

static void run(const bench_step *b, int reps, int earliest_only, unsigned many, double tolerance) {
    selfcol_mesh *m;
    selfcol_hierarchy *h;
    selfcol_sweep *r;
    if (selfcol_mesh_create(&m, b->end.vertex_count, b->end.positions, b->end.triangle_count,
                            b->end.triangles, NULL) != SELFCOL_OK ||
        selfcol_hierarchy_create(&h, m, NULL) != SELFCOL_OK ||
        selfcol_sweep_create(&r, NULL) != SELFCOL_OK) {
        fprintf(stderr, "bench-sweep: %s: setup failed\n", b->name);
        exit(1);
    }
    // Rows: ALL and EARLIEST (one thread) with each method, EXACT's ALL on
    // `many` threads (--threads, default 2), and BVH's EARLIEST on `many`
    // (its broad phase's tasks; EXACT's culling keeps EARLIEST on one). BVH is the box-only search
    // that EXACT refines with the curvature criterion over the step
    // (sweep_cull.c).
    enum { ROWS = 6 };
    char many_all[40], many_earliest[40];
    snprintf(many_all, sizeof many_all, "ALL, EXACT, %u threads", many);
    snprintf(many_earliest, sizeof many_earliest, "EARLIEST, BVH, %u threads", many);
    const char *const row_name[ROWS] = {"ALL, BVH",      "ALL, EXACT",      many_all,
                                        "EARLIEST, BVH", "EARLIEST, EXACT", many_earliest};
    static const uint32_t row_method[ROWS] = {SELFCOL_METHOD_BVH,   SELFCOL_METHOD_EXACT,
                                              SELFCOL_METHOD_EXACT, SELFCOL_METHOD_BVH,
                                              SELFCOL_METHOD_EXACT, SELFCOL_METHOD_BVH};
    double total[ROWS][MAX_REPS], broad[ROWS][MAX_REPS], narrow[ROWS][MAX_REPS];
    selfcol_sweep_query_stats last[ROWS];
    const int first_row = earliest_only ? 3 : 0;
    // The `many`-thread rows run on a context of that many threads (its
    // threads kept between reps); the others on the calling thread.
    selfcol_context *many_context = NULL;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = many;
    if (selfcol_context_create(&many_context, &co) != SELFCOL_OK) {
        fprintf(stderr, "bench-sweep: no context of %u threads\n", many);
        exit(1);
    }
    for (int rep = 0; rep < reps; ++rep)
        for (int mode = first_row; mode < ROWS; ++mode) {
            selfcol_sweep_options o;
            selfcol_sweep_options_init(&o, SELFCOL_SWEEP_OPTIONS_VERSION);
            o.method = row_method[mode];
            o.mode = mode >= 3 ? SELFCOL_SWEEP_EARLIEST : SELFCOL_SWEEP_ALL;
            o.tolerance = tolerance;
            const int status =
                mode == 2 || mode == 5
                    ? selfcol_context_self_sweep(many_context, h, b->start.positions, r, &o)
                    : selfcol_hierarchy_self_sweep(h, b->start.positions, r, &o);
            if (status != SELFCOL_OK) {
                fprintf(stderr, "bench-sweep: %s: query failed\n", b->name);
                exit(1);
            }
            last[mode].version = SELFCOL_SWEEP_STATS_VERSION;
            selfcol_sweep_stats(r, &last[mode]);
            total[mode][rep] = 1e3 * last[mode].total_seconds;
            broad[mode][rep] = 1e3 * last[mode].broad_seconds;
            narrow[mode][rep] = 1e3 * last[mode].narrow_seconds;
        }
    for (int mode = first_row; mode < ROWS; ++mode) {
        const selfcol_sweep_query_stats *s = &last[mode];
        double sorted[MAX_REPS];
        memcpy(sorted, total[mode], (size_t)reps * sizeof *sorted);
        const double med = median(sorted, reps);
        const double hi = sorted[reps - 1];
        printf("| %s | %zu | %s | %.1f (%.1f-%.1f) | %.1f | %.1f | %llu | %.1f | %llu | %llu | "
               "%llu | %llu | %.3g |\n",
               b->name, b->end.triangle_count, row_name[mode], med, sorted[0], hi,
               median(broad[mode], reps), median(narrow[mode], reps),
               (unsigned long long)s->patches_culled, 1e3 * s->cull_seconds,
               (unsigned long long)s->candidates, (unsigned long long)s->separated,
               (unsigned long long)s->narrow_boxes, (unsigned long long)s->hits, s->free_fraction);
    }
    fflush(stdout);
    selfcol_context_destroy(many_context);
    selfcol_sweep_destroy(r);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
}

int main(int argc, char **argv) {
    const char *data = BENCH_DEFAULT_DATA_DIR, *only = NULL, *dump_dir = NULL;
    int reps = 5, smoke = 0, earliest_only = 0, many = 2;
    double tolerance = SELFCOL_SWEEP_DEFAULT_TOLERANCE;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--data") == 0 && i + 1 < argc)
            data = argv[++i];
        else if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc)
            reps = atoi(argv[++i]);
        else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc)
            only = argv[++i];
        else if (strcmp(argv[i], "--dump") == 0 && i + 1 < argc)
            dump_dir = argv[++i];
        else if (strcmp(argv[i], "--smoke") == 0)
            smoke = 1;
        else if (strcmp(argv[i], "--earliest") == 0)
            earliest_only = 1;
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
            many = atoi(argv[++i]);
        else if (strcmp(argv[i], "--tolerance") == 0 && i + 1 < argc)
            tolerance = atof(argv[++i]);
        else {
            fprintf(stderr, "usage: selfcol-bench-sweep [--data DIR] [--reps N] [--only NAME] "
                            "[--dump DIR] [--smoke] [--earliest] [--threads N] "
                            "[--tolerance T]\n");
            return 2;
        }
    }
    if (many < 2 || many > 64) {
        fprintf(stderr, "bench-sweep: --threads (of the many-thread rows) must be 2 to 64\n");
        return 2;
    }
    selfcol_sweep_options checked;
    selfcol_sweep_options_init(&checked, SELFCOL_SWEEP_OPTIONS_VERSION);
    checked.tolerance = tolerance;
    selfcol_options_problem problem;
    problem.version = SELFCOL_OPTIONS_PROBLEM_VERSION;
    if (selfcol_sweep_options_check(&checked, &problem) != SELFCOL_OK) {
        fprintf(stderr, "bench-sweep: --tolerance: %s\n", problem.message);
        return 2;
    }
    if (reps < 1 || reps > MAX_REPS) {
        fprintf(stderr, "bench-sweep: --reps must be 1 to %d\n", MAX_REPS);
        return 2;
    }
    printf("| case | triangles | mode | query ms (min-max) | broad ms | narrow ms | patches culled "
           "| cull ms | candidates | separated | root boxes | hits | free fraction |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < 5; ++c) {
        bench_step b;
        memset(&b, 0, sizeof b);
        int ok = 0;
        if (smoke) {
            if (c > 0)
                break;
            ok = load_crumple(&b, 24, "crumpled-1k-step");
        } else if (c == 0) {
            ok = load_real(&b, data, "cloth-funnel-227", "cloth-funnel", "227.ply", "228.ply");
        } else if (c == 1) {
            ok = load_real(&b, data, "rod-twist-3036", "rod-twist", "3036.ply", "3037.ply");
        } else if (c == 2) {
            ok = load_real(&b, data, "cloth-ball-92", "cloth-ball", "cloth_ball92.ply",
                           "cloth_ball93.ply");
        } else if (c == 3) {
            ok = load_crumple(&b, 316, "crumpled-200k-step");
        } else {
            break;
        }
        if (!ok)
            continue;
        if (only == NULL || strcmp(only, b.name) == 0) {
            if (dump_dir != NULL)
                dump(&b, dump_dir);
            run(&b, reps, earliest_only, (unsigned)many, tolerance);
        }
        fixture_free(&b.start);
        fixture_free(&b.end);
    }
    return 0;
}
