// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Exact orientation predicates on double coordinates.
//
// Each predicate first evaluates its determinant in plain double arithmetic and
// accepts the sign when the result exceeds a proven bound on the rounding error
// (the first, "A", error bounds of the orientation predicates in J. R.
// Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates", Discrete & Computational Geometry 18(3):305-363,
// 1997). Otherwise it evaluates the determinant exactly. The exact path is
// deliberately not Shewchuk's adaptive cascade: it expands the determinant
// into a sum of products of raw input coordinates, turns every product into
// doubles whose sum is that product exactly (Dekker's product), and
// accumulates all of them into one nonoverlapping expansion (Shewchuk's
// Grow-Expansion). Fewer cases, one proof, and the exact path is only taken
// near degeneracy.
//
// Assumptions (as in predicates.h): IEEE 754 binary64 with round-to-nearest-
// even, every operation rounded to double (FLT_EVAL_METHOD == 0: SSE2, not
// x87), no contraction into fused multiply-adds (-ffp-contract=off, also GCC's
// default in ISO C mode), no reassociation (no -ffast-math), and finite
// coordinates of magnitude in [2^-300, 2^300] or zero. The proofs below use
// only these facts about that range:
//   (R1) every nonzero coordinate is a multiple of 2^-352 (its last significand
//        bit is at least 2^(-300-52)), so every nonzero coordinate difference is
//        a multiple of 2^-352 too, hence at least 2^-352 in magnitude;
//   (R2) nothing overflows: differences are below 2^301, products of three
//        below 2^903, and the splitting constant adds only 2^27.
// Outside that range the answers are best effort.

#include "base/predicates.h"

#include "base/expansion.h"

#include <float.h>
#include <math.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "predicates.c needs double operations rounded to double (FLT_EVAL_METHOD == 0)"
#endif

// Shewchuk's epsilon: the bound on the relative error of one rounded operation,
// half an ulp of 1.
#define PRED_EPS 0x1p-53

// Shewchuk's error bound A coefficients for orient2d and orient3d: the sign of
// the floating-point determinant is correct when its magnitude exceeds the
// coefficient times the permanent (the same expression with every term taken
// in absolute value), the permanent and that product both computed in floating
// point, as here. The first-order terms are the error analysis proper (the last
// rounding of the determinant never changes its sign, hence 3 and 7 rather than
// 4 and 8); the second-order terms leave room for everything else, including
// the rounding of the permanent and of the bound (for orient2d, bounding each
// error relative to the computed values gives 3 eps + 9 eps^2 + O(eps^3) for
// the whole chain). Both coefficients are exact doubles: 3 + 2^-49 and
// 7 + 7 * 2^-50 fit in 53 bits.
#define ORIENT2D_BOUND ((3.0 + 16.0 * PRED_EPS) * PRED_EPS)
#define ORIENT3D_BOUND SELFCOL_PREDICATES_ORIENT3D_BOUND

// The orient3d filter is trusted only when its permanent is at least this; see
// the underflow argument in selfcol_predicates__orient3d.
#define ORIENT3D_FILTER_MIN 0x1p-900

// Adds p * q * r exactly to the expansion e[0..n): p * q = x + y (Two-Product),
// then x * r and y * r are each split again, giving four doubles whose sum is
// p * q * r exactly. Exactness in the assumed range: all the products below are
// Dekker products whose operands are multiples of 2^-352 (R1) or error terms of
// such products (multiples of 2^-704), so every exact intermediate is a multiple
// of 2^-1056, above the subnormal spacing 2^-1074; and the rounded products
// x * r, y * r are at least 2^-900 and 2^-1004 in magnitude (|y| >= 2^-704 when
// nonzero), in the normal range. So gradual underflow never loses a bit, and R2
// rules out overflow.
static int add_triple_product(double *e, int n, double p, double q, double r) {
    double x, y;
    two_product(p, q, &x, &y);
    double r_hi, r_lo;
    split(r, &r_hi, &r_lo);
    double x1, x0, y1, y0;
    two_product_presplit(x, r, r_hi, r_lo, &x1, &x0);
    two_product_presplit(y, r, r_hi, r_lo, &y1, &y0);
    n = grow_expansion(e, n, y0);
    n = grow_expansion(e, n, x0);
    n = grow_expansion(e, n, y1);
    return grow_expansion(e, n, x1);
}

// Exact sign of (b - a) x (c - a). By multilinearity (rows with a repeated
// point vanish),
//   det[b - a; c - a] = det[b; c] - det[a; c] + det[a; b],
// with det[p; q] = p0 q1 - p1 q0: six products of raw coordinates, each made
// exact as two doubles (products of two coordinates are at least 2^-600 and
// their error terms multiples of 2^-704: no underflow loss), summed exactly.
static int orient2d_exact(const double a[2], const double b[2], const double c[2]) {
    const double *rows[3][2] = {{b, c}, {c, a}, {a, b}}; // det[c; a] = -det[a; c]
    double e[12];
    int n = 0;
    for (int t = 0; t < 3; t++) {
        const double *p = rows[t][0], *q = rows[t][1];
        double x, y;
        two_product(p[0], q[1], &x, &y);
        n = grow_expansion(e, n, y);
        n = grow_expansion(e, n, x);
        two_product(-p[1], q[0], &x, &y); // negation is exact
        n = grow_expansion(e, n, y);
        n = grow_expansion(e, n, x);
    }
    return expansion_sign(e, n);
}

// Exact sign of det[b - a; c - a; d - a]. By multilinearity,
//   det[b - a; c - a; d - a] = det[b; c; d] - det[a; c; d] + det[a; b; d] - det[a; b; c]
//                            = det[b; c; d] + det[c; a; d] + det[a; b; d] + det[b; a; c]
// (swapping two rows flips the sign), and
//   det[p; q; r] = sum over (i, j, k) in {(0,1,2), (1,2,0), (2,0,1)} of
//                  p_i q_j r_k - p_i q_k r_j:
// 24 triple products of raw coordinates, each exact as four doubles, so the
// expansion never exceeds 96 components.
static int orient3d_exact(const double a[3], const double b[3], const double c[3],
                          const double d[3]) {
    const double *rows[4][3] = {{b, c, d}, {c, a, d}, {a, b, d}, {b, a, c}};
    double e[96];
    int n = 0;
    for (int t = 0; t < 4; t++) {
        const double *p = rows[t][0], *q = rows[t][1], *r = rows[t][2];
        for (int i = 0; i < 3; i++) {
            int j = i == 2 ? 0 : i + 1;
            int k = j == 2 ? 0 : j + 1;
            n = add_triple_product(e, n, p[i], q[j], r[k]);
            n = add_triple_product(e, n, -p[i], q[k], r[j]);
        }
    }
    return expansion_sign(e, n);
}

// ---------------------------------------------------------------------------
// Predicates.

// The filter is Shewchuk's orient2d bound A test with a as the base point (his pc):
// detleft = (b0 - a0)(c1 - a1), detright = (b1 - a1)(c0 - a0), and the sign of
// det = detleft - detright is trusted when |det| > (3 + 16 eps) eps detsum,
// detsum = |detleft| + |detright|. Within the assumed range no operation of the
// filter underflows (nonzero differences are at least 2^-352 by R1, so nonzero
// products are at least 2^-704), so Shewchuk's relative-error analysis applies
// as is. For the same reason a zero detsum means both products are exactly
// zero (a rounded difference is zero only when the difference is), hence an
// exactly zero determinant: axis-aligned degenerate input needs no exact path.
int selfcol_predicates__orient2d(const double a[2], const double b[2], const double c[2]) {
    double detleft = (b[0] - a[0]) * (c[1] - a[1]);
    double detright = (b[1] - a[1]) * (c[0] - a[0]);
    double det = detleft - detright;
    double detsum = fabs(detleft) + fabs(detright);
    double errbound = ORIENT2D_BOUND * detsum;
    if (det > errbound)
        return 1;
    if (-det > errbound)
        return -1;
    if (detsum == 0.0)
        return 0;
    return orient2d_exact(a, b, c);
}

// The filter is Shewchuk's orient3d bound A test with a as the base point (his pd)
// and u = b - a, v = c - a, w = d - a in the roles of his a - d, b - d, c - d:
// expansion of det[u; v; w] along the z column,
//   det = uz (vx wy - wx vy) + vz (wx uy - ux wy) + wz (ux vy - vx uy),
// trusted when |det| > (7 + 56 eps) eps permanent.
//
// Underflow. Within the assumed range the 2x2 minor products are at least
// 2^-704 when nonzero (R1), but the six outer products (uz times a minor in
// det, |uz| times a sum of minor magnitudes in the permanent) can fall into the
// subnormal range (e.g. nearly coincident points near 2^-300), where rounding
// has an absolute error of up to 2^-1075 instead of a relative one. Additions
// into the subnormal range are exact, and nothing else underflows. Write the
// actual computation as the relative-error-only computation Shewchuk analyses
// (the same rounding factors, the underflowed products replaced by their exact
// values) plus those absolute errors: the determinant moves by less than
// 2^-1073 and the bound by less than 2^-1119. Requiring permanent >= 2^-900
// makes the bound at least 2^-951, so a double |det| above it exceeds it by at
// least one ulp of the bound, >= 2^-1003: far more than both perturbations, so
// the relative-error-only |det| also exceeds its bound and Shewchuk's argument
// gives the sign. Smaller permanents take the exact path.
//
// A zero permanent means every outer term is exactly zero (a zero factor, or
// both minor products zero, which means a zero factor in each: no product
// underflows to zero, as nonzero outer products are at least 2^-1056 and round
// to nonzero), hence an exactly zero determinant: coplanar axis-aligned input
// needs no exact path.
//
// Stage-A filter on det[u; v; w] for rows that are (rounded) differences,
// expanded along the z column as in Shewchuk's orient3d: the proven sign, 0
// for an exactly zero determinant, or 2 when the exact path is needed.
static int det3_filtered(const double u[3], const double v[3], const double w[3]) {
    double permanent;
    const double det = selfcol_predicates__det3(u, v, w, &permanent);
    if (permanent >= ORIENT3D_FILTER_MIN) {
        double errbound = ORIENT3D_BOUND * permanent;
        if (det > errbound)
            return 1;
        if (-det > errbound)
            return -1;
    } else if (permanent == 0.0) {
        return 0;
    }
    return 2;
}

static int orient3d_filtered(const double a[3], const double b[3], const double c[3],
                             const double d[3]) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    return det3_filtered(u, v, w);
}

int selfcol_predicates__orient3d(const double a[3], const double b[3], const double c[3],
                                 const double d[3]) {
    int sign = orient3d_filtered(a, b, c, d);
    return sign != 2 ? sign : orient3d_exact(a, b, c, d);
}

int selfcol_predicates__orient3d_filter(const double a[3], const double b[3], const double c[3],
                                        const double d[3]) {
    int sign = orient3d_filtered(a, b, c, d);
    return sign != 2 ? sign : 0;
}

// Exact sign of ((b - a) x (c - a)) . v = det[b - a; c - a; v]. By
// multilinearity in the first two rows,
//   det[b - a; c - a; v] = det[b; c; v] + det[c; a; v] + det[a; b; v],
// 18 triple products of raw inputs, each exact as four doubles (v's
// components obey the same range assumption as coordinates).
static int orient_along_exact(const double a[3], const double b[3], const double c[3],
                              const double v[3]) {
    const double *rows[3][2] = {{b, c}, {c, a}, {a, b}};
    double e[72];
    int n = 0;
    for (int t = 0; t < 3; t++) {
        const double *p = rows[t][0], *q = rows[t][1];
        for (int i = 0; i < 3; i++) {
            int j = i == 2 ? 0 : i + 1;
            int k = j == 2 ? 0 : j + 1;
            n = add_triple_product(e, n, p[i], q[j], v[k]);
            n = add_triple_product(e, n, -p[i], q[k], v[j]);
        }
    }
    return expansion_sign(e, n);
}

// The filter is orient3d's with the third difference replaced by v itself:
// one rounding fewer per term, so orient3d's bound (and its underflow guard)
// holds a fortiori.
int selfcol_predicates__orient_along(const double a[3], const double b[3], const double c[3],
                                     const double v[3]) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    int sign = det3_filtered(u, w, v);
    return sign != 2 ? sign : orient_along_exact(a, b, c, v);
}

// The three components of (b - a) x (c - a) are the orient2d determinants of
// the yz, zx and xy projections; the points are collinear iff all vanish.
int selfcol_predicates__collinear3d(const double a[3], const double b[3], const double c[3]) {
    for (int axis = 0; axis < 3; axis++) {
        int i = axis, j = axis == 2 ? 0 : axis + 1;
        double pa[2] = {a[i], a[j]};
        double pb[2] = {b[i], b[j]};
        double pc[2] = {c[i], c[j]};
        if (selfcol_predicates__orient2d(pa, pb, pc) != 0)
            return 0;
    }
    return 1;
}
