// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Small 3-vector helpers on double[3], inlined into every user.
#ifndef SELFCOL_VEC3_H
#define SELFCOL_VEC3_H

#include <math.h>

static inline void vec3_sub(double out[3], const double a[3], const double b[3]) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}

static inline void vec3_add(double out[3], const double a[3], const double b[3]) {
    out[0] = a[0] + b[0];
    out[1] = a[1] + b[1];
    out[2] = a[2] + b[2];
}

static inline double vec3_dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void vec3_cross(double out[3], const double a[3], const double b[3]) {
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

// (b - a) x (c - a): twice the area times the unit normal of the
// counter-clockwise triangle a, b, c.
static inline void vec3_triangle_normal(double out[3], const double a[3], const double b[3],
                                        const double c[3]) {
    double u[3], w[3];
    vec3_sub(u, b, a);
    vec3_sub(w, c, a);
    vec3_cross(out, u, w);
}

// out = a + t * (b - a)
static inline void vec3_lerp(double out[3], const double a[3], const double b[3], double t) {
    out[0] = a[0] + t * (b[0] - a[0]);
    out[1] = a[1] + t * (b[1] - a[1]);
    out[2] = a[2] + t * (b[2] - a[2]);
}

static inline double vec3_dist2(const double a[3], const double b[3]) {
    double d[3];
    vec3_sub(d, a, b);
    return vec3_dot(d, d);
}

// Normalises v into out; returns 0 (and leaves out untouched) for a zero or
// non-finite length.
static inline int vec3_normalize(double out[3], const double v[3]) {
    double len = sqrt(vec3_dot(v, v));
    if (!(len > 0.0) || !isfinite(len))
        return 0;
    out[0] = v[0] / len;
    out[1] = v[1] / len;
    out[2] = v[2] / len;
    return 1;
}

// The largest coordinate magnitude of n points (the scale of a query's
// rounding errors).
static inline double vec3_max_abs(int n, const double *const pts[]) {
    double m = 0.0;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            m = fmax(m, fabs(pts[i][k]));
    return m;
}

#endif // SELFCOL_VEC3_H
