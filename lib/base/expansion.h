// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Error-free transformations and nonoverlapping expansions (Shewchuk 1997,
// "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", section 2; the names are his), shared by the exact
// predicates (predicates.c) and the colliders' exact distances (collider.c).
// They need double operations rounded to double (FLT_EVAL_METHOD == 0) and
// no contraction into fused multiply-adds (-ffp-contract=off, the build's
// setting): a fused c - a in split() would not split. Two-Product is exact
// when neither the product nor its partial products overflow or underflow:
// each user states the range it relies on (predicates.c: R1 and R2).
#ifndef SELFCOL_EXPANSION_H
#define SELFCOL_EXPANSION_H

#include <float.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "expansion.h needs double operations rounded to double (FLT_EVAL_METHOD == 0)"
#endif

// Veltkamp's splitter for 53-bit doubles: 2^ceil(53/2) + 1.
#define EXPANSION_SPLITTER (0x1p27 + 1.0)

// Knuth's Two-Sum: s = fl(a + b) and e = (a + b) - s exactly, whatever the
// magnitudes of a and b, barring overflow. Also exact with gradual underflow:
// sums of doubles that land in the subnormal range are exact.
static inline void two_sum(double a, double b, double *s, double *e) {
    double x = a + b;
    double b_virtual = x - a;
    double a_virtual = x - b_virtual;
    double b_roundoff = b - b_virtual;
    double a_roundoff = a - a_virtual;
    *s = x;
    *e = a_roundoff + b_roundoff;
}

// Veltkamp's Split: a = hi + lo exactly, with hi and lo each of at most 26
// significant bits, so that products of halves are exact. The products and
// differences here must each be rounded separately: a fused c - a with
// c = splitter * a would not split.
static inline void split(double a, double *hi, double *lo) {
    double c = EXPANSION_SPLITTER * a;
    double big = c - a;
    double h = c - big;
    *hi = h;
    *lo = a - h;
}

// Dekker's Two-Product, b already split: p = fl(a * b) and e = a * b - p
// exactly. The four partial products are exact (26 x 26 bits) and each
// subtraction is exact by Dekker's argument.
static inline void two_product_presplit(double a, double b, double b_hi, double b_lo, double *p,
                                        double *e) {
    double x = a * b;
    double a_hi, a_lo;
    split(a, &a_hi, &a_lo);
    double err1 = x - a_hi * b_hi;
    double err2 = err1 - a_lo * b_hi;
    double err3 = err2 - a_hi * b_lo;
    *p = x;
    *e = a_lo * b_lo - err3;
}

static inline void two_product(double a, double b, double *p, double *e) {
    double b_hi, b_lo;
    split(b, &b_hi, &b_lo);
    two_product_presplit(a, b, b_hi, b_lo, p, e);
}

// Shewchuk's Grow-Expansion with zero elimination: e[0..n) is a nonoverlapping
// expansion, nonzero components sorted by increasing magnitude; it is
// replaced, in place, by such an expansion of e + b (at most n + 1
// components). Returns the new length. In place is safe: e[k] is written only
// after e[i] (i >= k) has been read. Dropping zero components keeps the
// expansion nonoverlapping and sorted.
static inline int grow_expansion(double *e, int n, double b) {
    if (b == 0.0)
        return n;
    double q = b;
    int k = 0;
    for (int i = 0; i < n; i++) {
        double s, h;
        two_sum(q, e[i], &s, &h);
        if (h != 0.0)
            e[k++] = h;
        q = s;
    }
    if (q != 0.0)
        e[k++] = q;
    return k;
}

// Sign of a nonoverlapping, zero-free, increasingly sorted expansion: the sign
// of its last (largest) component. If that component has its lowest set bit at
// 2^j, every other component lies entirely below 2^j in nonoverlapping bit
// ranges, so their sum is below 2^j <= |last| in magnitude and cannot cancel it.
static inline int expansion_sign(const double *e, int n) {
    if (n == 0)
        return 0;
    return e[n - 1] > 0.0 ? 1 : -1;
}

#endif // SELFCOL_EXPANSION_H
