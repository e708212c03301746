// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The normal cones' merge and its axis (cone.h): the two helpers too large to
// inline, called once per child at a refit and once per pair EXACT tries.
#include "base/cone.h"

void selfcol_cone__turn_axis(double out[3], const double u[3], const double v[3], double phi,
                             double turn) {
    double t = turn / phi;
    double sin_phi = sin(phi); // once: libm calls are not merged (errno)
    double s0 = sin((1.0 - t) * phi) / sin_phi, s1 = sin(t * phi) / sin_phi;
    double len = 0.0;
    for (int k = 0; k < 3; ++k) {
        out[k] = s0 * u[k] + s1 * v[k];
        len += out[k] * out[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; ++k)
        out[k] /= len;
}

// Two cones merge into the smallest cone containing both: when neither
// contains the other, its half-angle is (a + phi + b) / 2 and its axis turns
// from a's toward b's in the plane of the two axes.
void selfcol_cone__merge(selfcol_cone *a, const selfcol_cone *b) {
    if (a->angle >= SELFCOL_NO_CONE || b->angle >= SELFCOL_NO_CONE) {
        a->angle = SELFCOL_NO_CONE;
        return;
    }
    double phi = selfcol_cone__angle_between(a->axis, b->axis);
    if (phi + b->angle <= a->angle)
        return;
    if (phi + a->angle <= b->angle) {
        *a = *b;
        return;
    }
    double angle = 0.5 * (a->angle + phi + b->angle);
    if (angle >= SELFCOL_HALF_PI || !(phi > 0.0)) {
        a->angle = SELFCOL_NO_CONE;
        return;
    }
    // Rotate a's axis toward b's by (angle - a->angle) in their common plane.
    selfcol_cone__turn_axis(a->axis, a->axis, b->axis, phi, angle - a->angle);
    a->angle = angle;
}
