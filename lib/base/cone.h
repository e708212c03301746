// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Normal cones: a unit axis and a half-angle containing every unit normal of
// a patch, the finer bound that CONE and EXACT use where Volino & Magnenat
// Thalmann (1995, 2.2.2) sample 14 directions (SEED's masks). The refit
// builds a node's cone from its triangles' normals and merges its children's
// (hierarchy_refit.c), the traversal merges two nodes' cones to test their
// union (traverse.c), and EXACT projects along the axis of that union
// (contour.c). Everything here is in double; the nodes store the cones in
// float, widened by a margin (hierarchy_refit.c).
//
// A half-angle of pi/2 or more means that no open half-space contains the
// normals (SELFCOL_NO_CONE: no cone at all).
#ifndef SELFCOL_CONE_H
#define SELFCOL_CONE_H

#include <math.h>

#define SELFCOL_HALF_PI 1.5707963267948966
#define SELFCOL_NO_CONE 4.0f // any half-angle >= pi/2 means "no cone"

typedef struct selfcol_cone {
    double axis[3];
    double angle;
} selfcol_cone;

// Angle in [0, pi] between the directions of u and v (any lengths), as
// atan2(|u x v|, u . v): accurate to a few ulps at every angle. acos of the
// dot product is not: near 0 it turns a relative error e of the dot (from
// rounding, or from float axes whose length differs from 1 by ~6e-8) into an
// angle error of sqrt(2 e), and clamping a dot just above 1 reads any small
// angle as 0 (the hierarchy validator caught merged cones short by up to
// 5e-6 rad on cloth-ball frame 92 that way).
static inline double selfcol_cone__angle_between(const double u[3], const double v[3]) {
    double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
           z = u[0] * v[1] - u[1] * v[0];
    return atan2(sqrt(x * x + y * y + z * z), u[0] * v[0] + u[1] * v[1] + u[2] * v[2]);
}

// Half-angle of the smallest cone containing two cones of half-angles ta and
// tb whose axes are phi apart: the wider one when it contains the other,
// else (ta + phi + tb) / 2. selfcol_cone__merge and contour.c's joint axis
// make the same three cases (and need to know which one applies).
static inline double selfcol_cone__merged_angle(double ta, double phi, double tb) {
    return phi + tb <= ta ? ta : phi + ta <= tb ? tb : 0.5 * (ta + phi + tb);
}

// The cone of one triangle: n its computed normal, len = |n| > 0, err a
// bound on |computed normal - exact normal|. The exact normal is within err
// of the computed one: within an angle asin(err / len) < 1.5 err / len of it
// (err < len / 100); beyond that, no cone.
static inline selfcol_cone selfcol_cone__of_normal(const double n[3], double len, double err) {
    selfcol_cone c = {{n[0] / len, n[1] / len, n[2] / len},
                      err < 0.01 * len ? 1.5 * err / len + 1e-12 : SELFCOL_NO_CONE};
    return c;
}

// The unit vector, in double, along a node's float cone axis.
static inline void selfcol_cone__unit_axis(const float axis[3], double out[3]) {
    double len = 0.0;
    for (int k = 0; k < 3; ++k) {
        out[k] = axis[k];
        len += out[k] * out[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; ++k)
        out[k] /= len;
}

// The unit vector turned from u toward v by the angle `turn`, in the plane
// of the unit vectors u and v, which are phi > 0 apart (spherical linear
// interpolation, renormalised). out may be u.
void selfcol_cone__turn_axis(double out[3], const double u[3], const double v[3], double phi,
                             double turn);

// Replaces a by the smallest cone containing a and b (SELFCOL_NO_CONE when
// its half-angle reaches pi/2, or either is no cone).
void selfcol_cone__merge(selfcol_cone *a, const selfcol_cone *b);

#endif // SELFCOL_CONE_H
