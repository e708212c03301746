// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The continuous narrow phase (lib/narrow/narrow_sweep.h) on queries read from
// stdin, for exact_ccd.py: each line "vf" or "ee" and 24 numbers (four
// points at t = 0, then the same four at t = 1; VF: p, a, b, c; EE: a, b, c,
// d); each answer a line "hit toi" (toi printed exactly, as %.17g).
#include "narrow/narrow_sweep.h"

#include <stdio.h>
#include <string.h>

int main(void) {
    char kind[8];
    double x[24];
    while (scanf("%7s", kind) == 1) {
        for (int i = 0; i < 24; ++i)
            if (scanf("%lf", &x[i]) != 1) {
                fprintf(stderr, "narrow_sweep_driver: malformed query\n");
                return 2;
            }
        double toi = 1.0;
        int hit;
        if (strcmp(kind, "vf") == 0) {
            hit = selfcol_narrow_sweep__vf(x, x + 3, x + 6, x + 9, x + 12, x + 15, x + 18, x + 21,
                                           0.0, &toi);
        } else if (strcmp(kind, "ee") == 0) {
            hit = selfcol_narrow_sweep__ee(x, x + 3, x + 6, x + 9, x + 12, x + 15, x + 18, x + 21,
                                           0.0, &toi);
        } else {
            fprintf(stderr, "narrow_sweep_driver: unknown kind %s\n", kind);
            return 2;
        }
        printf("%d %.17g\n", hit, hit ? toi : 1.0);
    }
    return 0;
}
