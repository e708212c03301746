// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Axis-aligned boxes, as (lo, hi) coordinate triples, inlined into every
// user: the box of a few points, growing one box by another, the build's
// compactness score, and the "within d" tests of the broad phase
// (traverse.c, pairs.c) and of the exhaustive reference (exhaustive.c).
//
// The tests may only reject what is provably farther apart than d: if two
// sets are closer than d, so are their projections on every axis, hence
// their boxes are within d on every axis. Each test keeps the one rounding
// its callers' proofs were written for, and tests that round differently
// stay separate functions:
// - box against box (selfcol_box__near): lo_a - d > hi_b rejects, d
//   subtracted from a lower bound;
// - point against box (selfcol_box__point_near): p < lo - d or p > hi + d
//   rejects, d moved to the box's side. For a point this is not
//   selfcol_box__near of a degenerate box, which would round p - d > hi
//   instead of p > hi + d;
// - the hierarchy's float node boxes (rounded outward by the refit,
//   hierarchy_refit.c) against each other (selfcol_box__near_float): widened
//   to double (exactly) before d is subtracted in double, never in float.
// Minima and maxima are taken by comparison; by the mesh's contract every
// coordinate is finite, so the only freedom left is which of +0 and -0 a tie
// keeps, which no comparison and no addition of d can tell apart.
//
// Not here, on purpose: hierarchy_validate.c checks the boxes with its own
// comparisons (a validator that shared this code would also share its
// mistakes), and contour.c's grid keeps 2D boxes of projected edges, grown
// by its margin and relative to the grid's origin.
#ifndef SELFCOL_BOX_H
#define SELFCOL_BOX_H

// Grows the box (lo, hi) to contain the point p.
static inline void selfcol_box__grow_point(double lo[3], double hi[3], const double p[3]) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = p[k] < lo[k] ? p[k] : lo[k];
        hi[k] = p[k] > hi[k] ? p[k] : hi[k];
    }
}

// The box of points[0 .. count), count >= 1.
static inline void selfcol_box__of_points(double lo[3], double hi[3], const double *const *points,
                                          int count) {
    for (int k = 0; k < 3; ++k)
        lo[k] = hi[k] = points[0][k];
    for (int i = 1; i < count; ++i)
        selfcol_box__grow_point(lo, hi, points[i]);
}

// Grows the box (lo, hi) to contain the box (blo, bhi).
static inline void selfcol_box__merge(double lo[3], double hi[3], const double blo[3],
                                      const double bhi[3]) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = blo[k] < lo[k] ? blo[k] : lo[k];
        hi[k] = bhi[k] > hi[k] ? bhi[k] : hi[k];
    }
}

// The same on float boxes (the hierarchy's nodes: exact, a float minimum is
// one of its arguments).
static inline void selfcol_box__merge_float(float lo[3], float hi[3], const float blo[3],
                                            const float bhi[3]) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = blo[k] < lo[k] ? blo[k] : lo[k];
        hi[k] = bhi[k] > hi[k] ? bhi[k] : hi[k];
    }
}

// Half-perimeter (sum of the three extents) of the box containing boxes a
// and b: the build's measure of how compact a merged patch is.
static inline double selfcol_box__merged_half_perimeter(const double alo[3], const double ahi[3],
                                                        const double blo[3], const double bhi[3]) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        double lo = alo[k] < blo[k] ? alo[k] : blo[k];
        double hi = ahi[k] > bhi[k] ? ahi[k] : bhi[k];
        sum += hi - lo;
    }
    return sum;
}

// 1 when boxes a and b are within d of each other on every axis (d = 0:
// overlapping or touching). With an early exit: the exhaustive reference
// runs it on every primitive pair, most of them apart on the first axis (a
// branch-free form made that search 1.5x slower; the traversal's leaf pairs,
// which used one, run as fast with this).
static inline int selfcol_box__near(const double alo[3], const double ahi[3], const double blo[3],
                                    const double bhi[3], double d) {
    for (int k = 0; k < 3; ++k)
        if (alo[k] - d > bhi[k] || blo[k] - d > ahi[k])
            return 0;
    return 1;
}

// The same for float boxes, each coordinate widened to double before d is
// subtracted.
static inline int selfcol_box__near_float(const float alo[3], const float ahi[3],
                                          const float blo[3], const float bhi[3], double d) {
    for (int k = 0; k < 3; ++k)
        if ((double)alo[k] - d > (double)bhi[k] || (double)blo[k] - d > (double)ahi[k])
            return 0;
    return 1;
}

// 1 when the point p is within d of the box on every axis:
// lo - d <= p <= hi + d.
static inline int selfcol_box__point_near(const double p[3], const double lo[3], const double hi[3],
                                          double d) {
    for (int k = 0; k < 3; ++k)
        if (p[k] < lo[k] - d || p[k] > hi[k] + d)
            return 0;
    return 1;
}

#endif // SELFCOL_BOX_H
