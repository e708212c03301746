// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Micro-benchmark of the narrow phase: nanoseconds per query of the closed
// form (narrow.c) and of the libccd backend (narrow_ccd.c), for VF, EE and EF,
// on a fixed random set (coordinates uniform in [-1, 1]^3, fixed seed).
//
// The libccd proximities depend on the radius: a pair beyond it costs one MPR
// test, a pair within it a bisection (25 MPR tests at tolerance 1e-7 radius,
// as lib/query/query.c asks). So VF and EE run at the median closed-form distance of
// the set (half the pairs within), over all pairs, then over the pairs within
// and the pairs beyond that radius separately. The closed form does not depend
// on the radius. EF asks for the result, as a contact query does on a hit.
//
// Each measurement first calibrates how many queries fill about
// SECONDS_PER_RUN, runs them once to warm up, then 5 times; the table shows
// the median of the 5.
//
// Built with the project as build/tools/bench_narrow (not run by the tests).
#define _POSIX_C_SOURCE 199309L

#include "narrow/narrow.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define DISTINCT (1u << 16) // distinct random pairs, cycled through
#define RUNS 5
#define REL_TOL 1e-7 // libccd tolerance relative to the radius (lib/query/query.c)

// splitmix64, uniform in [-1, 1).
static double next_coordinate(uint64_t *state) {
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return 2.0 * ((double)(z >> 11) * (1.0 / 9007199254740992.0)) - 1.0;
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

// Five points per pair: VF uses p, a, b, c; EE p0, p1, q0, q1; EF p0, p1, a, b, c.
static double (*points)[5][3];

// Keeps the results alive so the calls cannot be optimised away.
static volatile double sink;

typedef enum { VF, EE, EF } kind;

// One measurement: a kind, a backend, a radius, and the pairs to cycle through.
typedef struct job {
    kind k;
    int use_ccd;
    double radius;
    const uint32_t *pairs; // indices into points
    size_t count;
} job;

// Runs `queries` queries of a job; returns the seconds taken.
static double run(const job *j, size_t queries) {
    double acc = 0.0, tol = REL_TOL * j->radius;
    double t0 = now_seconds();
    for (size_t i = 0; i < queries; ++i) {
        double(*q)[3] = points[j->pairs[i % j->count]];
        switch (j->k) {
        case VF: {
            double d = j->use_ccd
                           ? selfcol_narrow_ccd__vf(q[0], q[1], q[2], q[3], j->radius, tol, NULL)
                           : selfcol_narrow__vf(q[0], q[1], q[2], q[3], NULL);
            acc += d < HUGE_VAL ? d : 1.0;
            break;
        }
        case EE: {
            double d = j->use_ccd
                           ? selfcol_narrow_ccd__ee(q[0], q[1], q[2], q[3], j->radius, tol, NULL)
                           : selfcol_narrow__ee(q[0], q[1], q[2], q[3], NULL);
            acc += d < HUGE_VAL ? d : 1.0;
            break;
        }
        case EF: {
            selfcol_narrow_result r;
            int hit = j->use_ccd ? selfcol_narrow_ccd__ef(q[0], q[1], q[2], q[3], q[4], tol, &r)
                                 : selfcol_narrow__ef(q[0], q[1], q[2], q[3], q[4], &r);
            acc += hit ? 1.0 + r.wa[0] : 0.0;
            break;
        }
        }
    }
    double t1 = now_seconds();
    sink = acc;
    return t1 - t0;
}

static int compare_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

// Median ns/query of RUNS runs of about `seconds` each, after a warm-up run.
static double measure(const job *j, double seconds) {
    size_t queries = 1024;
    double t = run(j, queries);
    while (t < 0.01 && queries < ((size_t)1 << 40)) { // calibrate
        queries *= 4;
        t = run(j, queries);
    }
    double want = seconds / t * (double)queries;
    queries = want > 1024.0 ? (size_t)want : 1024;
    (void)run(j, queries); // warm-up
    double times[RUNS];
    for (int i = 0; i < RUNS; ++i)
        times[i] = run(j, queries);
    qsort(times, RUNS, sizeof times[0], compare_double);
    return 1e9 * times[RUNS / 2] / (double)queries;
}

static double distance(kind k, uint32_t i) {
    double(*q)[3] = points[i];
    return k == VF ? selfcol_narrow__vf(q[0], q[1], q[2], q[3], NULL)
                   : selfcol_narrow__ee(q[0], q[1], q[2], q[3], NULL);
}

static uint32_t *all, *within, *beyond;
static double dist[DISTINCT], sorted[DISTINCT];

static void row(const char *name, double closed, const job *j, double seconds) {
    double ccd = measure(j, seconds);
    printf("%-22s %12.1f %12.1f %8.1fx\n", name, closed, ccd, ccd / closed);
}

int main(int argc, char **argv) {
    double seconds = 0.2;
    if (argc > 1) {
        seconds = strtod(argv[1], NULL);
        if (!(seconds > 0.0 && seconds < 100.0)) {
            fprintf(stderr, "usage: %s [seconds per run]\n", argv[0]);
            return 2;
        }
    }
    points = malloc(sizeof *points * DISTINCT);
    all = malloc(sizeof *all * DISTINCT);
    within = malloc(sizeof *within * DISTINCT);
    beyond = malloc(sizeof *beyond * DISTINCT);
    if (points == NULL || all == NULL || within == NULL || beyond == NULL) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    uint64_t state = 0x5eedbe4cull;
    for (uint32_t i = 0; i < DISTINCT; ++i) {
        all[i] = i;
        for (int j = 0; j < 5; ++j)
            for (int c = 0; c < 3; ++c)
                points[i][j][c] = next_coordinate(&state);
    }

    // Share of EF pairs that cross, for context.
    size_t crossings = 0;
    for (uint32_t i = 0; i < DISTINCT; ++i)
        crossings += (size_t)selfcol_narrow__ef(points[i][0], points[i][1], points[i][2],
                                                points[i][3], points[i][4], NULL);

    printf("%u distinct pairs (uniform in [-1,1]^3), ~%.2g s per run, median of %d runs after "
           "a warm-up; libccd tolerance = %g radius\n",
           DISTINCT, seconds, RUNS, REL_TOL);
    printf("%-22s %12s %12s %9s\n", "query", "closed ns/q", "libccd ns/q", "ratio");
    static const char *const names[2] = {"VF", "EE"};
    for (int k = VF; k <= EE; ++k) {
        for (uint32_t i = 0; i < DISTINCT; ++i)
            sorted[i] = dist[i] = distance((kind)k, i);
        qsort(sorted, DISTINCT, sizeof sorted[0], compare_double);
        double radius = sorted[DISTINCT / 2];
        size_t nw = 0, nb = 0;
        for (uint32_t i = 0; i < DISTINCT; ++i) {
            if (dist[i] < radius)
                within[nw++] = i;
            else
                beyond[nb++] = i;
        }
        job closed = {(kind)k, 0, radius, all, DISTINCT};
        double tc = measure(&closed, seconds);
        char name[64];
        job j_all = {(kind)k, 1, radius, all, DISTINCT};
        snprintf(name, sizeof name, "%s r=%.3f all", names[k], radius);
        row(name, tc, &j_all, seconds);
        job j_in = {(kind)k, 1, radius, within, nw};
        snprintf(name, sizeof name, "%s  within (%.0f%%)", names[k], 100.0 * (double)nw / DISTINCT);
        row(name, tc, &j_in, seconds);
        job j_out = {(kind)k, 1, radius, beyond, nb};
        snprintf(name, sizeof name, "%s  beyond (%.0f%%)", names[k], 100.0 * (double)nb / DISTINCT);
        row(name, tc, &j_out, seconds);
    }
    job ef_closed = {EF, 0, 1.0, all, DISTINCT}, ef_ccd = {EF, 1, 1.0, all, DISTINCT};
    char name[64];
    snprintf(name, sizeof name, "EF (%.1f%% cross)", 100.0 * (double)crossings / DISTINCT);
    row(name, measure(&ef_closed, seconds), &ef_ccd, seconds);
    free(points);
    free(all);
    free(within);
    free(beyond);
    return 0;
}
