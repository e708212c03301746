// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-bench-threads: how one frame's discrete query scales with threads
// (issue 38's thread-scaling rows). The EXACT query at d = 0.1 x mean edge
// and the refit run at each thread count, interleaved rep by rep so that a
// machine's drift spreads over every count alike; every count keeps its own
// contact set (its workspace stays warm, as in a simulation), and every
// count's records are compared with one thread's, byte for byte.
//
// usage: selfcol-bench-threads [--data DIR] [--mesh FILE] [--threads LIST] [--reps N]
// LIST is comma-separated (default 1,2); the mesh defaults to cloth-ball
// frame 92 of the shared data. Prints a Markdown table: per count, the
// query's median (min-max), its speed-up over one thread, the workers'
// busy time (broad + narrow, summed over threads) over threads x the
// traversal's wall time, the sort, and the refit.
#include <selfcol/selfcol.h>

#include "fixtures.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_COUNTS 16
#define MAX_REPS 64

static double seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int by_value(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(const double *v, int n, double *lo, double *hi) {
    double s[MAX_REPS];
    memcpy(s, v, (size_t)n * sizeof *s);
    qsort(s, (size_t)n, sizeof *s, by_value);
    if (lo != NULL)
        *lo = s[0];
    if (hi != NULL)
        *hi = s[n - 1];
    return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

static int parse_counts(const char *list, unsigned *counts) {
    int n = 0;
    const char *p = list;
    while (*p != '\0') {
        char *end;
        long t = strtol(p, &end, 10);
        if (end == p || t < 1 || t > 64 || n == MAX_COUNTS || (*end != ',' && *end != '\0'))
            return -1;
        counts[n++] = (unsigned)t;
        p = *end == ',' ? end + 1 : end;
    }
    return n;
}

static void fail(const char *what, int status) {
    fprintf(stderr, "bench-threads: %s failed (%s)\n", what, selfcol_status_string(status));
    exit(1);
}

int main(int argc, char **argv) {
    const char *data = BENCH_DEFAULT_DATA_DIR, *mesh_path = NULL, *list = "1,2";
    int reps = 5;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--data") == 0 && i + 1 < argc)
            data = argv[++i];
        else if (strcmp(argv[i], "--mesh") == 0 && i + 1 < argc)
            mesh_path = argv[++i];
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
            list = argv[++i];
        else if (strcmp(argv[i], "--reps") == 0 && i + 1 < argc)
            reps = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: selfcol-bench-threads [--data DIR] [--mesh FILE] "
                            "[--threads LIST] [--reps N]\n");
            return 2;
        }
    }
    unsigned counts[MAX_COUNTS];
    const int n = parse_counts(list, counts);
    if (n < 1 || reps < 1 || reps > MAX_REPS) {
        fprintf(stderr,
                "bench-threads: --threads takes 1 to %d counts of 1 to 64, --reps 1 "
                "to %d\n",
                MAX_COUNTS, MAX_REPS);
        return 2;
    }
    char path[4096], err[512];
    if (mesh_path == NULL)
        snprintf(path, sizeof path,
                 "%s/sample-scalable-ccd-data/cloth-ball/frames/cloth_ball92.ply", data);
    else
        snprintf(path, sizeof path, "%s", mesh_path);
    fixture s;
    if (fixture_read(path, &s, err, sizeof err) != 0) {
        fprintf(stderr, "bench-threads: %s\n", err);
        return 1;
    }
    selfcol_mesh *mesh;
    int status = selfcol_mesh_create(&mesh, s.vertex_count, s.positions, s.triangle_count,
                                     s.triangles, NULL);
    if (status != SELFCOL_OK)
        fail("mesh", status);
    selfcol_hierarchy *h[MAX_COUNTS];
    selfcol_contacts *c[MAX_COUNTS];
    selfcol_context *ctx[MAX_COUNTS]; // each count's context (its threads kept between reps)
    for (int k = 0; k < n; ++k) {
        if ((status = selfcol_hierarchy_create(&h[k], mesh, NULL)) != SELFCOL_OK)
            fail("hierarchy", status);
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.threads = counts[k];
        if ((status = selfcol_context_create(&ctx[k], &co)) != SELFCOL_OK)
            fail("context", status);
        if ((status = selfcol_contacts_create(&c[k], NULL)) != SELFCOL_OK)
            fail("contact set", status);
    }
    const double d = 0.1 * selfcol_mesh_mean_edge_length(mesh);
    static double query[MAX_COUNTS][MAX_REPS], busy[MAX_COUNTS][MAX_REPS];
    static double sort[MAX_COUNTS][MAX_REPS], refit[MAX_COUNTS][MAX_REPS];
    // One untimed query per count first: the workspaces grow to size.
    for (int rep = -1; rep < reps; ++rep)
        for (int k = 0; k < n; ++k) {
            selfcol_query_options o;
            selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
            o.distance = d;
            o.method = SELFCOL_METHOD_EXACT;
            if ((status = selfcol_mesh_set_positions(mesh, s.positions, s.vertex_count)) !=
                SELFCOL_OK)
                fail("set_positions", status);
            const double before = seconds();
            if ((status = selfcol_context_refit(ctx[k], h[k])) != SELFCOL_OK)
                fail("refit", status);
            const double refit_s = seconds() - before;
            if ((status = selfcol_context_self_collide(ctx[k], h[k], c[k], &o)) != SELFCOL_OK)
                fail("query", status);
            selfcol_query_stats st;
            st.version = SELFCOL_QUERY_STATS_VERSION;
            selfcol_contacts_stats(c[k], &st);
            if (rep < 0)
                continue;
            query[k][rep] = 1e3 * st.total_seconds;
            // The traversal's wall time is the query's less its sort.
            const double walk = st.total_seconds - st.sort_seconds;
            busy[k][rep] =
                walk > 0 ? (st.broad_seconds + st.narrow_seconds) / (counts[k] * walk) : 0.0;
            sort[k][rep] = 1e3 * st.sort_seconds;
            refit[k][rep] = 1e3 * refit_s;
        }
    const selfcol_contact *ref;
    size_t ref_count;
    selfcol_contacts_data(c[0], &ref, &ref_count);
    const char *name = strrchr(path, '/') != NULL ? strrchr(path, '/') + 1 : path;
    printf("%s: %zu triangles, d = %.6g, EXACT, medians of %d (interleaved)\n\n", name,
           s.triangle_count, d, reps);
    printf("| threads | query ms (min-max) | speed-up | busy | sort ms | refit ms | contacts | "
           "same as first |\n|---|---|---|---|---|---|---|---|\n");
    const double first = median(query[0], reps, NULL, NULL);
    for (int k = 0; k < n; ++k) {
        double lo, hi;
        const double q = median(query[k], reps, &lo, &hi);
        const selfcol_contact *got;
        size_t got_count;
        selfcol_contacts_data(c[k], &got, &got_count);
        const int same = got_count == ref_count &&
                         (ref_count == 0 || memcmp(got, ref, ref_count * sizeof *ref) == 0);
        printf("| %u | %.1f (%.1f-%.1f) | %.2fx | %.0f %% | %.1f | %.1f | %zu | %s |\n", counts[k],
               q, lo, hi, first / q, 100.0 * median(busy[k], reps, NULL, NULL),
               median(sort[k], reps, NULL, NULL), median(refit[k], reps, NULL, NULL), got_count,
               same ? "yes" : "NO");
        if (!same)
            status = 1;
    }
    for (int k = 0; k < n; ++k) {
        selfcol_contacts_destroy(c[k]);
        selfcol_context_destroy(ctx[k]);
        selfcol_hierarchy_destroy(h[k]);
    }
    selfcol_mesh_destroy(mesh);
    fixture_free(&s);
    return status == SELFCOL_OK ? 0 : 1;
}
