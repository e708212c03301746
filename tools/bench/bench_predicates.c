// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Micro-benchmark of the exact predicates: nanoseconds per orient3d call on
// random points (decided by the floating-point filter) and on exactly coplanar
// points (decided by the exact expansion path), median of 5 runs. Built with
// the project as build/tools/bench_predicates (not run by the tests).
#if !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 199309L
#endif

#include "base/predicates.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

enum { SETS = 4096, RUNS = 5 };

typedef struct quad {
    double p[4][3];
} quad;

static uint64_t rng_state = 0x5e1fc011u;

static uint64_t rng_u64(void) {
    uint64_t z = (rng_state += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

// Uniform in [0, 1) with `bits` random bits.
static double rng_bits(int bits) {
    return (double)(rng_u64() >> (64 - bits)) / (double)(UINT64_C(1) << bits);
}

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static volatile long sink;

// How many sets orient3d calls exactly coplanar (a sanity check of the data).
static int count_zero(const quad *sets) {
    int zeros = 0;
    for (int i = 0; i < SETS; i++)
        zeros += selfcol_predicates__orient3d(sets[i].p[0], sets[i].p[1], sets[i].p[2],
                                              sets[i].p[3]) == 0;
    return zeros;
}

// Median over RUNS of the time per call, each run sweeping the sets `reps` times.
static double bench(const quad *sets, long reps) {
    double times[RUNS];
    long sum = 0;
    for (int run = 0; run < RUNS; run++) {
        sum = 0;
        double t0 = now_seconds();
        for (long r = 0; r < reps; r++)
            for (int i = 0; i < SETS; i++)
                sum += selfcol_predicates__orient3d(sets[i].p[0], sets[i].p[1], sets[i].p[2],
                                                    sets[i].p[3]);
        times[run] = (now_seconds() - t0) / ((double)reps * SETS) * 1e9;
        sink += sum;
    }
    qsort(times, RUNS, sizeof times[0], cmp_double);
    return times[RUNS / 2];
}

int main(void) {
    quad *random_sets = malloc(sizeof(quad) * SETS);
    quad *coplanar_small = malloc(sizeof(quad) * SETS);
    quad *coplanar_wide = malloc(sizeof(quad) * SETS);
    if (random_sets == NULL || coplanar_small == NULL || coplanar_wide == NULL)
        return 1;
    for (int i = 0; i < SETS; i++) {
        for (int j = 0; j < 4; j++) {
            for (int k = 0; k < 3; k++)
                random_sets[i].p[j][k] = 2.0 * rng_bits(53) - 1.0;
            // On the slanted plane z = x + y, so the permanent is not zero and
            // the filter cannot decide: x, y with 20 random bits (the naive
            // determinant is then exactly 0), or 51 bits in [1, 2) (x + y still
            // exact), which makes the expansions longer.
            double x = rng_bits(20), y = rng_bits(20);
            coplanar_small[i].p[j][0] = x;
            coplanar_small[i].p[j][1] = y;
            coplanar_small[i].p[j][2] = x + y;
            x = 1.0 + rng_bits(51);
            y = 1.0 + rng_bits(51);
            coplanar_wide[i].p[j][0] = x;
            coplanar_wide[i].p[j][1] = y;
            coplanar_wide[i].p[j][2] = x + y;
        }
    }
    double ns = bench(random_sets, 2000);
    printf("orient3d random points (filter path):          %7.2f ns/call\n", ns);
    ns = bench(coplanar_small, 50);
    printf("orient3d coplanar, 20-bit coordinates (exact): %7.2f ns/call (%d of %d zero)\n", ns,
           count_zero(coplanar_small), SETS);
    ns = bench(coplanar_wide, 50);
    printf("orient3d coplanar, 52-bit coordinates (exact): %7.2f ns/call (%d of %d zero)\n", ns,
           count_zero(coplanar_wide), SETS);
    free(random_sets);
    free(coplanar_small);
    free(coplanar_wide);
    return 0;
}
