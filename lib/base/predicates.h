// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Exact orientation predicates on double coordinates: a floating-point filter
// with a proven error bound, and an exact expansion-arithmetic fallback
// (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
// geometric predicates", for the error-free transformations and the bounds).
// Exact for every finite input whose intermediate products neither overflow
// nor underflow (coordinates of magnitude in [2^-300, 2^300], or zero).
#ifndef SELFCOL_PREDICATES_H
#define SELFCOL_PREDICATES_H

#include <math.h>

// The error bound A coefficient of orient3d (Shewchuk 1997): a determinant
// computed by selfcol_predicates__det3 from rows that are rounded
// differences is within this times its permanent of the exact determinant
// of those differences (predicates.c, where the coefficient is derived).
#define SELFCOL_PREDICATES_ORIENT3D_BOUND ((7.0 + 56.0 * 0x1p-53) * 0x1p-53)

// det[u; v; w] in floating point, expanded along the z column as Shewchuk's
// orient3d expands it, and its permanent (the same expression with every
// term in absolute value) in *permanent: the filter's computation, shared by
// orient3d's filter and by callers that bound a sum of such determinants
// (the continuous narrow phase's coplanarity filter).
static inline double selfcol_predicates__det3(const double u[3], const double v[3],
                                              const double w[3], double *permanent) {
    const double vxwy = v[0] * w[1], wxvy = w[0] * v[1];
    const double wxuy = w[0] * u[1], uxwy = u[0] * w[1];
    const double uxvy = u[0] * v[1], vxuy = v[0] * u[1];
    *permanent = (fabs(vxwy) + fabs(wxvy)) * fabs(u[2]) + (fabs(wxuy) + fabs(uxwy)) * fabs(v[2]) +
                 (fabs(uxvy) + fabs(vxuy)) * fabs(w[2]);
    return u[2] * (vxwy - wxvy) + v[2] * (wxuy - uxwy) + w[2] * (uxvy - vxuy);
}

// Sign (+1, 0, -1) of det[b - a, c - a] = (b-a) x (c-a): +1 when a, b, c turn
// counter-clockwise.
int selfcol_predicates__orient2d(const double a[2], const double b[2], const double c[2]);

// Sign (+1, 0, -1) of det[b - a; c - a; d - a] = ((b-a) x (c-a)) . (d-a):
// +1 when d lies on the side the normal of the counter-clockwise triangle
// a, b, c points to.
int selfcol_predicates__orient3d(const double a[3], const double b[3], const double c[3],
                                 const double d[3]);

// The floating-point filter of orient3d alone: +1 or -1 when it proves the
// sign, 0 when the sign is 0 or the filter cannot tell. A few nanoseconds;
// callers that can often decide from proven signs alone (see narrow.c's
// edge-triangle test) call it before paying for the exact path.
int selfcol_predicates__orient3d_filter(const double a[3], const double b[3], const double c[3],
                                        const double d[3]);

// Sign (+1, 0, -1) of ((b-a) x (c-a)) . v: the orientation of a, b, c
// projected along v onto a plane orthogonal to v, seen from +v (+1: counter-
// clockwise). Exact, as orient3d.
int selfcol_predicates__orient_along(const double a[3], const double b[3], const double c[3],
                                     const double v[3]);

// 1 when the three 3D points are exactly collinear (or coincide): all three
// axis-aligned projections are collinear.
int selfcol_predicates__collinear3d(const double a[3], const double b[3], const double c[3]);

#endif // SELFCOL_PREDICATES_H
