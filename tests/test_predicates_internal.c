// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Tests of the exact orientation predicates (lib/base/predicates.c). Every sign is
// checked against a reference that shares no code or method with the library:
// an analytic formula for the Shewchuk-style grids, 128-bit integer arithmetic
// for inputs that scale to small integers, and a small sign-magnitude big
// integer (below) for arbitrary doubles. On the adversarial sets the test also
// counts how often the naive double determinant gets the sign wrong, and
// requires that count to be positive: the sets do reach the inputs where plain
// floating point fails.

// cmocka.h needs these first.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

#include "base/predicates.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

// Totals over the whole run, printed by main.
static unsigned long g_checked;     // predicate results compared with an exact reference
static unsigned long g_naive_wrong; // naive determinant signs that disagreed with it

// ---------------------------------------------------------------------------
// Deterministic random numbers (splitmix64).

static uint64_t rng_state;

static void rng_seed(uint64_t seed) {
    rng_state = seed;
}

static uint64_t rng_u64(void) {
    uint64_t z = (rng_state += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

// Uniform integer in [lo, hi] (hi - lo < 2^63; the modulo bias is irrelevant).
static int64_t rng_int(int64_t lo, int64_t hi) {
    return lo + (int64_t)(rng_u64() % (uint64_t)(hi - lo + 1));
}

// Uniform in [0, 1) with 53 random bits.
static double rng_unit(void) {
    return (double)(rng_u64() >> 11) * 0x1p-53;
}

static double rng_sign(void) {
    return (rng_u64() & 1) ? -1.0 : 1.0;
}

// Random double of magnitude in [2^emin, 2^(emax+1)], full random significand.
static double rng_wide(int emin, int emax) {
    return rng_sign() * ldexp(1.0 + rng_unit(), (int)rng_int(emin, emax));
}

// ---------------------------------------------------------------------------
// Small helpers.

static int sgn(double x) {
    return (x > 0.0) - (x < 0.0);
}

// x moved by k representable steps (k > 0 up, k < 0 down).
static double ulp_steps(double x, int k) {
    for (; k > 0; k--)
        x = nextafter(x, INFINITY);
    for (; k < 0; k++)
        x = nextafter(x, -INFINITY);
    return x;
}

static double naive_orient2d(const double a[2], const double b[2], const double c[2]) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// ((b - a) x (c - a)) . (d - a), evaluated the obvious way in doubles.
static double naive_orient3d(const double a[3], const double b[3], const double c[3],
                             const double d[3]) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
}

static int naive_collinear3d(const double a[3], const double b[3], const double c[3]) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return u[1] * v[2] - u[2] * v[1] == 0.0 && u[2] * v[0] - u[0] * v[2] == 0.0 &&
           u[0] * v[1] - u[1] * v[0] == 0.0;
}

static void copy3(double dst[3], const double src[3]) {
    dst[0] = src[0];
    dst[1] = src[1];
    dst[2] = src[2];
}

// Random permutation of n <= 4 points of dim coordinates, in place.
static void shuffle_points(double (*p)[3], int n) {
    for (int i = n - 1; i > 0; i--) {
        int j = (int)rng_int(0, i);
        double t[3];
        copy3(t, p[i]);
        copy3(p[i], p[j]);
        copy3(p[j], t);
    }
}

// ---------------------------------------------------------------------------
// Reference 1: 128-bit integers, for coordinates that become small integers
// once multiplied by a power of two `scale` (exact).

static int64_t scaled_int(double x, double scale, double limit) {
    double s = x * scale;
    assert_true(s == floor(s));
    assert_true(fabs(s) <= limit);
    return (int64_t)s;
}

// Coordinates times scale must be integers of magnitude <= 2^61: differences
// <= 2^62, products <= 2^124, their difference < 2^126.
static int ref_orient2d_i128(const double a[2], const double b[2], const double c[2],
                             double scale) {
    int64_t ax = scaled_int(a[0], scale, 0x1p61), ay = scaled_int(a[1], scale, 0x1p61);
    int64_t bx = scaled_int(b[0], scale, 0x1p61), by = scaled_int(b[1], scale, 0x1p61);
    int64_t cx = scaled_int(c[0], scale, 0x1p61), cy = scaled_int(c[1], scale, 0x1p61);
    i128 det = (i128)(bx - ax) * (cy - ay) - (i128)(by - ay) * (cx - ax);
    return (det > 0) - (det < 0);
}

// Coordinates times scale must be integers of magnitude <= 2^40: differences
// <= 2^41, triple products <= 2^123, the sum of six < 2^126.
static int ref_orient3d_i128(const double a[3], const double b[3], const double c[3],
                             const double d[3], double scale) {
    i128 u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        int64_t ak = scaled_int(a[k], scale, 0x1p40);
        u[k] = scaled_int(b[k], scale, 0x1p40) - ak;
        v[k] = scaled_int(c[k], scale, 0x1p40) - ak;
        w[k] = scaled_int(d[k], scale, 0x1p40) - ak;
    }
    i128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
               u[2] * (v[0] * w[1] - v[1] * w[0]);
    return (det > 0) - (det < 0);
}

// ---------------------------------------------------------------------------
// Reference 2: sign-magnitude big integers in base 2^32, for any doubles in the
// supported range. All coordinates of one query are scaled by a common power
// of two into integers (at most 653 bits for [2^-300, 2^300]); triple products
// then need at most ~1960 bits.

#define BIG_LIMBS 72

typedef struct big {
    int neg;
    int n;
    uint32_t d[BIG_LIMBS];
} big;

static void big_trim(big *x) {
    while (x->n > 0 && x->d[x->n - 1] == 0)
        x->n--;
    if (x->n == 0)
        x->neg = 0;
}

static int big_sign(const big *x) {
    return x->n == 0 ? 0 : (x->neg ? -1 : 1);
}

// v / 2^lsb, which must be an integer.
static big big_from_double(double v, int lsb) {
    big x;
    x.neg = v < 0.0;
    x.n = 0;
    if (v == 0.0)
        return x;
    int e;
    double f = frexp(fabs(v), &e);
    uint64_t m = (uint64_t)ldexp(f, 53); // |v| = m 2^(e - 53), exactly
    int shift = e - 53 - lsb;
    assert_true(shift >= 0);
    int limb = shift / 32;
    assert_true(limb + 3 <= BIG_LIMBS);
    u128 t = (u128)m << (shift % 32);
    memset(x.d, 0, sizeof(uint32_t) * (size_t)limb);
    x.d[limb] = (uint32_t)t;
    x.d[limb + 1] = (uint32_t)(t >> 32);
    x.d[limb + 2] = (uint32_t)(t >> 64);
    x.n = limb + 3;
    big_trim(&x);
    return x;
}

static int big_cmp_mag(const big *a, const big *b) {
    if (a->n != b->n)
        return a->n < b->n ? -1 : 1;
    for (int i = a->n - 1; i >= 0; i--)
        if (a->d[i] != b->d[i])
            return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}

// a + b (negate_b == 0) or a - b (negate_b == 1).
static big big_addsub(const big *a, const big *b, int negate_b) {
    big r;
    int bneg = b->n == 0 ? 0 : b->neg ^ negate_b;
    if (a->n == 0 || b->n == 0 || a->neg == bneg) {
        int n = a->n > b->n ? a->n : b->n;
        assert_true(n + 1 <= BIG_LIMBS);
        uint64_t carry = 0;
        for (int i = 0; i < n; i++) {
            uint64_t s = carry + (i < a->n ? a->d[i] : 0) + (i < b->n ? b->d[i] : 0);
            r.d[i] = (uint32_t)s;
            carry = s >> 32;
        }
        r.d[n] = (uint32_t)carry;
        r.n = n + 1;
        r.neg = a->n == 0 ? bneg : a->neg;
    } else {
        const big *hi = a, *lo = b;
        r.neg = a->neg;
        if (big_cmp_mag(a, b) < 0) {
            hi = b;
            lo = a;
            r.neg = bneg;
        }
        int64_t borrow = 0;
        for (int i = 0; i < hi->n; i++) {
            int64_t s = (int64_t)hi->d[i] - (i < lo->n ? (int64_t)lo->d[i] : 0) - borrow;
            borrow = s < 0;
            r.d[i] = (uint32_t)(s + (borrow ? INT64_C(0x100000000) : 0));
        }
        r.n = hi->n;
    }
    big_trim(&r);
    return r;
}

static big big_mul(const big *a, const big *b) {
    big r;
    r.neg = a->neg ^ b->neg;
    r.n = 0;
    if (a->n == 0 || b->n == 0) {
        r.neg = 0;
        return r;
    }
    r.n = a->n + b->n;
    assert_true(r.n <= BIG_LIMBS);
    memset(r.d, 0, sizeof(uint32_t) * (size_t)r.n);
    for (int i = 0; i < a->n; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < b->n; j++) {
            uint64_t t = (uint64_t)a->d[i] * b->d[j] + r.d[i + j] + carry;
            r.d[i + j] = (uint32_t)t;
            carry = t >> 32;
        }
        r.d[i + b->n] = (uint32_t)carry;
    }
    big_trim(&r);
    return r;
}

// A power of two 2^lsb dividing every value (the weight of the last significand
// bit of the smallest exponent).
static int common_lsb(const double *values, int count) {
    int lsb = INT_MAX;
    for (int i = 0; i < count; i++) {
        if (values[i] == 0.0)
            continue;
        int e;
        (void)frexp(values[i], &e);
        if (e - 53 < lsb)
            lsb = e - 53;
    }
    return lsb == INT_MAX ? 0 : lsb;
}

// Exact differences p_k - q_k, k < dim, of points given as doubles.
static void big_diffs(big *out, const double *p, const double *q, int dim, int lsb) {
    for (int k = 0; k < dim; k++) {
        big bp = big_from_double(p[k], lsb), bq = big_from_double(q[k], lsb);
        out[k] = big_addsub(&bp, &bq, 1);
    }
}

static big big_cross_component(const big *u, const big *v, int i, int j) {
    big t1 = big_mul(&u[i], &v[j]), t2 = big_mul(&u[j], &v[i]);
    return big_addsub(&t1, &t2, 1);
}

static int ref_orient2d_big(const double a[2], const double b[2], const double c[2]) {
    double all[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    int lsb = common_lsb(all, 6);
    big u[2], v[2];
    big_diffs(u, b, a, 2, lsb);
    big_diffs(v, c, a, 2, lsb);
    big det = big_cross_component(u, v, 0, 1);
    return big_sign(&det);
}

// det[u; v; w] as u . (v x w): a different expansion from the library's.
static int ref_orient3d_big(const double a[3], const double b[3], const double c[3],
                            const double d[3]) {
    double all[12] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
    int lsb = common_lsb(all, 12);
    big u[3], v[3], w[3];
    big_diffs(u, b, a, 3, lsb);
    big_diffs(v, c, a, 3, lsb);
    big_diffs(w, d, a, 3, lsb);
    big sum;
    sum.neg = 0;
    sum.n = 0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        big cross = big_cross_component(v, w, j, k);
        big term = big_mul(&u[i], &cross);
        sum = big_addsub(&sum, &term, 0);
    }
    return big_sign(&sum);
}

static int ref_collinear3d_big(const double a[3], const double b[3], const double c[3]) {
    double all[9] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]};
    int lsb = common_lsb(all, 9);
    big u[3], v[3];
    big_diffs(u, b, a, 3, lsb);
    big_diffs(v, c, a, 3, lsb);
    for (int i = 0; i < 3; i++) {
        big comp = big_cross_component(u, v, (i + 1) % 3, (i + 2) % 3);
        if (big_sign(&comp) != 0)
            return 0;
    }
    return 1;
}

// ---------------------------------------------------------------------------
// Checking helpers: compare with the reference, count naive failures.

static void check2(const double a[2], const double b[2], const double c[2], int expected,
                   unsigned long *naive_wrong) {
    int got = selfcol_predicates__orient2d(a, b, c);
    if (got != expected)
        print_message("orient2d((%a, %a), (%a, %a), (%a, %a)) = %d, expected %d\n", a[0], a[1],
                      b[0], b[1], c[0], c[1], got, expected);
    assert_int_equal(got, expected);
    g_checked++;
    if (sgn(naive_orient2d(a, b, c)) != expected) {
        (*naive_wrong)++;
        g_naive_wrong++;
    }
}

static void check3(const double a[3], const double b[3], const double c[3], const double d[3],
                   int expected, unsigned long *naive_wrong) {
    int got = selfcol_predicates__orient3d(a, b, c, d);
    if (got != expected)
        print_message("orient3d((%a, %a, %a), (%a, %a, %a), (%a, %a, %a), (%a, %a, %a)) = %d, "
                      "expected %d\n",
                      a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2], got,
                      expected);
    assert_int_equal(got, expected);
    // The filter alone answers only when it is sure: its nonzero answers are
    // the exact sign.
    int filtered = selfcol_predicates__orient3d_filter(a, b, c, d);
    assert_true(filtered == 0 || filtered == expected);
    g_checked++;
    if (sgn(naive_orient3d(a, b, c, d)) != expected) {
        (*naive_wrong)++;
        g_naive_wrong++;
    }
}

static void check_collinear(const double a[3], const double b[3], const double c[3], int expected,
                            unsigned long *naive_wrong) {
    int got = selfcol_predicates__collinear3d(a, b, c);
    if (got != expected)
        print_message("collinear3d((%a, %a, %a), (%a, %a, %a), (%a, %a, %a)) = %d, expected %d\n",
                      a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], got, expected);
    assert_int_equal(got, expected);
    g_checked++;
    if (naive_collinear3d(a, b, c) != expected) {
        (*naive_wrong)++;
        g_naive_wrong++;
    }
}

// ---------------------------------------------------------------------------
// Generators.

// 3D integer points, |coordinates| <= 2^40, with b - a and c - a nearly
// parallel and d - a nearly in their span: det = (u x v) . e with |u x v| ~
// 2^49 while the permanent is ~2^112, far below the double error (~2^60).
// A quarter of them are exactly coplanar (e = 0).
static void gen_int_adversarial3(double p[4][3]) {
    static const int64_t ks[4] = {-2, -1, 1, 2};
    int64_t k = ks[rng_int(0, 3)], s = rng_int(-2, 2), t = rng_int(-2, 2);
    int coplanar = rng_int(0, 3) == 0;
    for (int i = 0; i < 3; i++) {
        int64_t a = rng_int(-(INT64_C(1) << 38), INT64_C(1) << 38);
        int64_t u = rng_int(-(INT64_C(1) << 36), INT64_C(1) << 36);
        int64_t v = k * u + rng_int(-4096, 4096);
        int64_t w = s * u + t * v + (coplanar ? 0 : rng_int(-1, 1));
        p[0][i] = (double)a;
        p[1][i] = (double)(a + u);
        p[2][i] = (double)(a + v);
        p[3][i] = (double)(a + w);
    }
    shuffle_points(p, 4);
}

// A double of magnitude in [1/16, 16], a multiple of 2^-56.
static double rng_dyadic16(void) {
    return rng_sign() * ldexp(1.0 + rng_unit(), (int)rng_int(-4, 3));
}

static int in_dyadic16(double x) {
    return x == 0.0 || (fabs(x) >= 0.0625 && fabs(x) <= 16.0);
}

// 2D near-collinear triples of multiples of 2^-56 in [-16, 16]: c is the
// rounded point a + t (b - a), moved by up to 3 ulps per coordinate.
static void gen_dyadic_near_collinear2(double p[3][3]) {
    for (;;) {
        double t = 3.0 * rng_unit() - 1.0;
        for (int k = 0; k < 2; k++) {
            p[0][k] = rng_dyadic16();
            p[1][k] = rng_dyadic16();
            p[2][k] = ulp_steps(p[0][k] + t * (p[1][k] - p[0][k]), (int)rng_int(-3, 3));
        }
        if (in_dyadic16(p[2][0]) && in_dyadic16(p[2][1]))
            break;
    }
    p[0][2] = p[1][2] = p[2][2] = 0.0;
    shuffle_points(p, 3);
}

// Points of clusters at three scales per axis: base in [1.25, 1.5) 2^e for e in
// {-300, 0, 299}, plus k ulps of the base's binade, so every coordinate stays
// in its binade and within [2^-300, 2^300]. `mode` 0: one scale per axis for
// all points; 1: a scale per point and axis among tiny and unit; 2: among all
// three. A third of the 3D sets are exactly coplanar (k_d = k_b + k_c - k_a, on
// every axis sharing one scale), likewise collinear in 2D.
static void gen_extreme(double p[4][3], int npoints, int mode) {
    static const int exps[3] = {-300, 0, 299};
    int range_bits = (int)rng_int(0, 24);
    int affine = mode == 0 && rng_int(0, 2) == 0;
    for (int axis = 0; axis < 3; axis++) {
        double base[3];
        for (int s = 0; s < 3; s++)
            base[s] = ldexp(1.25 + 0.25 * rng_unit(), exps[s]);
        int axis_scale = (int)rng_int(0, 2);
        int64_t k[4];
        for (int i = 0; i < npoints; i++)
            k[i] = rng_int(-(INT64_C(1) << range_bits), INT64_C(1) << range_bits);
        if (affine)
            k[npoints - 1] = npoints == 4 ? k[1] + k[2] - k[0] : 2 * k[1] - k[0];
        for (int i = 0; i < npoints; i++) {
            int s = mode == 0 ? axis_scale : (int)rng_int(0, mode == 1 ? 1 : 2);
            double ulp = ldexp(1.0, exps[s] - 52);
            p[i][axis] = base[s] + (double)k[i] * ulp; // exact: stays in the binade
        }
    }
}

// Does the library's filter see an outer product in the subnormal range while
// its permanent is large enough for the filter to be trusted? (The case the
// underflow argument in predicates.c covers.) Mirrors the filter's formula.
static int filter_underflows(const double a[3], const double b[3], const double c[3],
                             const double d[3]) {
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    double m[3] = {v[0] * w[1] - w[0] * v[1], w[0] * u[1] - u[0] * w[1], u[0] * v[1] - v[0] * u[1]};
    double s[3] = {fabs(v[0] * w[1]) + fabs(w[0] * v[1]), fabs(w[0] * u[1]) + fabs(u[0] * w[1]),
                   fabs(u[0] * v[1]) + fabs(v[0] * u[1])};
    double z[3] = {u[2], v[2], w[2]};
    double permanent = s[0] * fabs(z[0]) + s[1] * fabs(z[1]) + s[2] * fabs(z[2]);
    if (!(permanent >= 0x1p-900))
        return 0;
    for (int i = 0; i < 3; i++) {
        double t = z[i] * m[i];
        if (z[i] != 0.0 && m[i] != 0.0 && fabs(t) < DBL_MIN)
            return 1;
    }
    return 0;
}

// ---------------------------------------------------------------------------
// Hand-computed cases.

static void test_predicates_orient2d_hand_cases(void **state) {
    (void)state;
    const double o[2] = {0, 0}, x[2] = {1, 0}, y[2] = {0, 1};
    assert_int_equal(selfcol_predicates__orient2d(o, x, y), 1);  // counter-clockwise
    assert_int_equal(selfcol_predicates__orient2d(o, y, x), -1); // clockwise
    const double p[2] = {0.5, 0.5}, q[2] = {12, 12}, r[2] = {24, 24};
    assert_int_equal(selfcol_predicates__orient2d(p, q, r), 0); // collinear
    const double h[2] = {2, 0}, f[2] = {5, 0};
    assert_int_equal(selfcol_predicates__orient2d(x, h, f), 0); // collinear, axis-aligned
    assert_int_equal(selfcol_predicates__orient2d(p, p, q), 0); // repeated point
    assert_int_equal(selfcol_predicates__orient2d(q, q, q), 0); // all coincide
    // (b - a) x (c - a) = 1 * 2^-300: tiny but positive.
    const double t[2] = {2, 0x1p-300};
    assert_int_equal(selfcol_predicates__orient2d(o, x, t), 1);
    // 12 (py - px) for the line y = x: one ulp above (0.5, 0.5) is to the left.
    const double above[2] = {0.5, nextafter(0.5, 1.0)}, below[2] = {0.5, nextafter(0.5, 0.0)};
    assert_int_equal(selfcol_predicates__orient2d(above, q, r), 1);
    assert_int_equal(selfcol_predicates__orient2d(below, q, r), -1);
    // Huge and tiny in range.
    const double big0[2] = {0x1p299, 0x1p299}, big1[2] = {0x1.8p299, 0x1.8p299},
                 big2[2] = {0x1.cp299, 0x1.cp299};
    assert_int_equal(selfcol_predicates__orient2d(big0, big1, big2), 0);
}

static void test_predicates_orient3d_hand_cases(void **state) {
    (void)state;
    const double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    const double mz[3] = {0, 0, -1};
    // ((b-a) x (c-a)) . (d-a) = (e1 x e2) . e3 = 1.
    assert_int_equal(selfcol_predicates__orient3d(o, x, y, z), 1);
    assert_int_equal(selfcol_predicates__orient3d(o, x, y, mz), -1);
    assert_int_equal(selfcol_predicates__orient3d(o, y, x, z), -1);
    const double xy[3] = {1, 1, 0}, below[3] = {0.25, 0.25, -1};
    assert_int_equal(selfcol_predicates__orient3d(o, x, y, xy), 0); // coplanar, axis-aligned
    assert_int_equal(selfcol_predicates__orient3d(o, x, y, below), -1);
    assert_int_equal(selfcol_predicates__orient3d(o, o, y, z), 0); // repeated point
    assert_int_equal(selfcol_predicates__orient3d(x, x, x, x), 0); // all coincide
    const double two[3] = {2, 0, 0};
    assert_int_equal(selfcol_predicates__orient3d(o, x, two, z), 0); // a, b, c collinear
    // Coplanar on the slanted plane z = x + y, with non-integer coordinates.
    const double p0[3] = {0.5, 0.25, 0.75}, p1[3] = {1.5, 2.25, 3.75}, p2[3] = {-3.125, 1, -2.125},
                 p3[3] = {7, -3.5, 3.5}, p4[3] = {7, -3.5, 0x1.c000000000001p1};
    assert_int_equal(selfcol_predicates__orient3d(p0, p1, p2, p3), 0);
    // p4 is p3 moved up by one ulp (2^-51) in z. The normal is
    // (p1 - p0) x (p2 - p0) = (1, 2, 3) x (-3.625, 0.75, -2.875) = (-8, -8, 8),
    // so the determinant is 8 * 2^-51 > 0.
    assert_int_equal(selfcol_predicates__orient3d(p0, p1, p2, p4), 1);
    assert_int_equal(selfcol_predicates__orient3d(p0, p2, p1, p4), -1);
    // Shewchuk-style: a point near (0.5, 0.5, 35) against the plane
    // x + y + z = 36 through (12,12,12), (24,24,-12), (-12,24,24), whose normal
    // (b-a) x (c-a) is (432, 432, 432).
    const double a[3] = {12, 12, 12}, b[3] = {24, 24, -12}, c[3] = {-12, 24, 24};
    const double on[3] = {0.5, 0.5, 35}, up[3] = {0.5, nextafter(0.5, 1.0), 35},
                 down[3] = {0.5, 0.5, nextafter(35.0, 0.0)};
    assert_int_equal(selfcol_predicates__orient3d(a, b, c, on), 0);
    assert_int_equal(selfcol_predicates__orient3d(a, b, c, up), 1);
    assert_int_equal(selfcol_predicates__orient3d(a, b, c, down), -1);
    // Extreme magnitudes of the supported range.
    const double t0[3] = {0x1p-300, 0x1p-300, 0x1p-300}, t1[3] = {0x1.8p-300, 0x1p-300, 0x1p-300},
                 t2[3] = {0x1p-300, 0x1.8p-300, 0x1p-300}, t3[3] = {0x1p-300, 0x1p-300, 0x1.8p-300};
    assert_int_equal(selfcol_predicates__orient3d(t0, t1, t2, t3), 1);
    const double h0[3] = {0x1p299, 0x1p299, 0x1p299}, h1[3] = {0x1.8p299, 0x1p299, 0x1p299},
                 h2[3] = {0x1p299, 0x1.8p299, 0x1p299}, h3[3] = {0x1p299, 0x1p299, 0x1.8p299};
    assert_int_equal(selfcol_predicates__orient3d(h0, h1, h3, h2), -1);
}

static void test_predicates_collinear3d_hand_cases(void **state) {
    (void)state;
    const double o[3] = {0, 0, 0}, d1[3] = {1, 1, 1}, d2[3] = {2, 2, 2};
    assert_int_equal(selfcol_predicates__collinear3d(o, d1, d2), 1);
    assert_int_equal(selfcol_predicates__collinear3d(d2, o, d1), 1);
    const double x1[3] = {1, 0, 0}, x5[3] = {5, 0, 0}, y1[3] = {0, 1, 0};
    assert_int_equal(selfcol_predicates__collinear3d(o, x1, x5), 1); // axis-aligned
    assert_int_equal(selfcol_predicates__collinear3d(o, x1, y1), 0);
    const double r[3] = {1, 2, 3}, s[3] = {7, -1, 4};
    assert_int_equal(selfcol_predicates__collinear3d(r, r, s), 1); // repeated point
    assert_int_equal(selfcol_predicates__collinear3d(r, s, r), 1);
    assert_int_equal(selfcol_predicates__collinear3d(r, r, r), 1); // all coincide
    // Each projection on its own: collinear in two projections, not the third.
    const double pxy1[3] = {1, 1, 0}, pxy2[3] = {2, 2, 1}; // xy collinear only
    assert_int_equal(selfcol_predicates__collinear3d(o, pxy1, pxy2), 0);
    const double pyz1[3] = {0, 1, 1}, pyz2[3] = {0, 2, 3}; // xy and zx collinear, yz not
    assert_int_equal(selfcol_predicates__collinear3d(o, pyz1, pyz2), 0);
    const double pzx1[3] = {1, 0, 1}, pzx2[3] = {3, 0, 2}; // xy and yz collinear, zx not
    assert_int_equal(selfcol_predicates__collinear3d(o, pzx1, pzx2), 0);
    const double pt1[3] = {1, 1, 0}, pt2[3] = {2, 2, 0x1p-300}; // off by 2^-300 in z
    assert_int_equal(selfcol_predicates__collinear3d(o, pt1, pt2), 0);
}

// ---------------------------------------------------------------------------
// Near-degenerate sets with exact references.

// Shewchuk's figure: p = (0.5 + i ulp, 0.5 + j ulp) against the line through
// (12, 12) and (24, 24). orient2d(p, q, r) = 12 (py - px) exactly, so the
// sign is sign(py - px) (a difference computed exactly: Sterbenz). Also
// checked against the 128-bit reference (coordinates times 2^54 are integers
// below 2^59), in the three cyclic orders and one reversed.
static void test_predicates_orient2d_shewchuk_grid(void **state) {
    (void)state;
    enum { N = 128 };
    double vals[2 * N];
    for (int i = 0; i < 2 * N; i++)
        vals[i] = ulp_steps(0.5, i - N);
    const double q[2] = {12, 12}, r[2] = {24, 24};
    unsigned long naive = 0, count = 0, zeros = 0;
    for (int i = 0; i < 2 * N; i++) {
        for (int j = 0; j < 2 * N; j++) {
            const double p[2] = {vals[i], vals[j]};
            int expected = sgn(p[1] - p[0]);
            assert_int_equal(ref_orient2d_i128(p, q, r, 0x1p54), expected);
            check2(p, q, r, expected, &naive);
            check2(q, r, p, expected, &naive);
            check2(r, p, q, expected, &naive);
            check2(q, p, r, -expected, &naive);
            count += 4;
            zeros += expected == 0;
        }
    }
    print_message(
        "orient2d Shewchuk grid: %lu checks, %lu exact zeros, naive sign wrong %lu times\n", count,
        zeros, naive);
    assert_true(naive > 0);
}

// The 3D analogue: p = (0.5 + i ulp, 0.5 + j ulp, 35 + k ulp) against the plane
// x + y + z = 36 through a = (12,12,12), b = (24,24,-12), c = (-12,24,24),
// where det[b-a; c-a; p-a] = 432 (px + py + pz - 36). The three offsets from
// (0.5, 0.5, 35) are exact (Sterbenz) multiples of 2^-54 below 2^-43, so their
// sum is exact too. Checked against the big-integer reference as well.
static void test_predicates_orient3d_plane_grid(void **state) {
    (void)state;
    enum { N = 16 };
    double xs[2 * N], zs[2 * N];
    for (int i = 0; i < 2 * N; i++) {
        xs[i] = ulp_steps(0.5, i - N);
        zs[i] = ulp_steps(35.0, i - N);
    }
    const double a[3] = {12, 12, 12}, b[3] = {24, 24, -12}, c[3] = {-12, 24, 24};
    unsigned long naive = 0, count = 0, zeros = 0;
    for (int i = 0; i < 2 * N; i++) {
        for (int j = 0; j < 2 * N; j++) {
            for (int k = 0; k < 2 * N; k++) {
                const double p[3] = {xs[i], xs[j], zs[k]};
                int expected = sgn((p[0] - 0.5) + (p[1] - 0.5) + (p[2] - 35.0));
                if ((i + j + k) % 8 == 0)
                    assert_int_equal(ref_orient3d_big(a, b, c, p), expected);
                check3(a, b, c, p, expected, &naive);  // p as the apex
                check3(p, a, b, c, -expected, &naive); // p as the base point: odd permutation
                count += 2;
                zeros += expected == 0;
            }
        }
    }
    print_message("orient3d plane grid: %lu checks, %lu exact zeros, naive sign wrong %lu times\n",
                  count, zeros, naive);
    assert_true(naive > 0);
    assert_true(zeros > 0);
}

static void test_predicates_orient3d_integer_adversarial(void **state) {
    (void)state;
    rng_seed(0x5e1fc011);
    unsigned long naive = 0, zeros = 0;
    enum { COUNT = 60000 };
    for (int n = 0; n < COUNT; n++) {
        double p[4][3];
        gen_int_adversarial3(p);
        int expected = ref_orient3d_i128(p[0], p[1], p[2], p[3], 1.0);
        check3(p[0], p[1], p[2], p[3], expected, &naive);
        zeros += expected == 0;
    }
    print_message("orient3d integer adversarial: %d checks, %lu exact zeros, naive sign wrong %lu "
                  "times\n",
                  COUNT, zeros, naive);
    assert_true(naive > 0);
    assert_true(zeros > 0);
}

static void test_predicates_orient2d_dyadic_adversarial(void **state) {
    (void)state;
    rng_seed(0xd1ad1c);
    unsigned long naive = 0, zeros = 0;
    enum { COUNT = 40000 };
    for (int n = 0; n < COUNT; n++) {
        double p[3][3];
        gen_dyadic_near_collinear2(p);
        int expected = ref_orient2d_i128(p[0], p[1], p[2], 0x1p56);
        assert_int_equal(ref_orient2d_big(p[0], p[1], p[2]), expected);
        check2(p[0], p[1], p[2], expected, &naive);
        zeros += expected == 0;
    }
    print_message("orient2d dyadic adversarial: %d checks, %lu exact zeros, naive sign wrong %lu "
                  "times\n",
                  COUNT, zeros, naive);
    assert_true(naive > 0);
}

// Random doubles over 2^-20 .. 2^21, in general position (the filter decides)
// and near-coplanar (d = the rounded a + s (b - a) + t (c - a), sometimes moved
// by a few ulps), against the big-integer reference.
static void test_predicates_orient3d_random_wide_range(void **state) {
    (void)state;
    rng_seed(0x31de);
    unsigned long naive = 0, zeros = 0;
    enum { COUNT = 30000 };
    for (int n = 0; n < COUNT; n++) {
        double p[4][3];
        int mode = (int)rng_int(0, 3);
        double scale = ldexp(1.0, (int)rng_int(-20, 20));
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++)
                p[i][k] =
                    i == 0 || mode != 3 ? rng_wide(-20, 20) : p[0][k] + scale * rng_wide(-30, 0);
        double s = 3.0 * rng_unit() - 1.0, t = 3.0 * rng_unit() - 1.0;
        for (int k = 0; k < 3; k++) {
            if (mode == 0)
                p[3][k] = rng_wide(-20, 20);
            else
                p[3][k] = p[0][k] + s * (p[1][k] - p[0][k]) + t * (p[2][k] - p[0][k]);
            if (mode == 2)
                p[3][k] = ulp_steps(p[3][k], (int)rng_int(-2, 2));
        }
        shuffle_points(p, 4);
        int expected = ref_orient3d_big(p[0], p[1], p[2], p[3]);
        check3(p[0], p[1], p[2], p[3], expected, &naive);
        zeros += expected == 0;
    }
    print_message("orient3d random wide range: %d checks, %lu exact zeros, naive sign wrong %lu "
                  "times\n",
                  COUNT, zeros, naive);
}

static void test_predicates_orient2d_random_wide_range(void **state) {
    (void)state;
    rng_seed(0x2d2d);
    unsigned long naive = 0;
    enum { COUNT = 20000 };
    for (int n = 0; n < COUNT; n++) {
        double p[3][3];
        int mode = (int)rng_int(0, 2);
        double t = 3.0 * rng_unit() - 1.0;
        for (int k = 0; k < 2; k++) {
            p[0][k] = rng_wide(-20, 20);
            p[1][k] = rng_wide(-20, 20);
            p[2][k] = mode == 0 ? rng_wide(-20, 20) : p[0][k] + t * (p[1][k] - p[0][k]);
            if (mode == 2)
                p[2][k] = ulp_steps(p[2][k], (int)rng_int(-2, 2));
        }
        shuffle_points(p, 3);
        int expected = ref_orient2d_big(p[0], p[1], p[2]);
        check2(p[0], p[1], p[2], expected, &naive);
    }
    print_message("orient2d random wide range: %d checks, naive sign wrong %lu times\n", COUNT,
                  naive);
}

// Clusters near 2^-300, 1 and 2^299, mixed across axes and points: exercises
// the no-underflow/no-overflow ends of the supported range, and in particular
// the orient3d filter with outer products in the subnormal range.
static void test_predicates_extreme_magnitudes(void **state) {
    (void)state;
    rng_seed(0xe87);
    unsigned long naive3 = 0, naive2 = 0, zeros = 0, underflowing = 0;
    enum { COUNT = 12000 };
    for (int n = 0; n < COUNT; n++) {
        double p[4][3];
        gen_extreme(p, 4, n % 3);
        int expected = ref_orient3d_big(p[0], p[1], p[2], p[3]);
        check3(p[0], p[1], p[2], p[3], expected, &naive3);
        zeros += expected == 0;
        underflowing += (unsigned long)filter_underflows(p[0], p[1], p[2], p[3]);

        gen_extreme(p, 3, n % 3);
        expected = ref_orient2d_big(p[0], p[1], p[2]);
        check2(p[0], p[1], p[2], expected, &naive2);
    }
    print_message("extreme magnitudes: %d + %d checks, %lu exact 3D zeros, %lu with a subnormal "
                  "filter product under a trusted permanent, naive sign wrong %lu (3D) and %lu "
                  "(2D) times\n",
                  COUNT, COUNT, zeros, underflowing, naive3, naive2);
    assert_true(zeros > 0);
    assert_true(underflowing > 0);
    assert_true(naive3 > 0);
}

// ---------------------------------------------------------------------------
// Properties.

static void test_predicates_orient2d_permutations(void **state) {
    (void)state;
    rng_seed(0x9e2);
    for (int n = 0; n < 4000; n++) {
        double p[3][3];
        gen_dyadic_near_collinear2(p);
        const double *a = p[0], *b = p[1], *c = p[2];
        int s = selfcol_predicates__orient2d(a, b, c);
        // Cyclic permutations keep the sign, transpositions flip it.
        assert_int_equal(selfcol_predicates__orient2d(b, c, a), s);
        assert_int_equal(selfcol_predicates__orient2d(c, a, b), s);
        assert_int_equal(selfcol_predicates__orient2d(b, a, c), -s);
        assert_int_equal(selfcol_predicates__orient2d(a, c, b), -s);
        assert_int_equal(selfcol_predicates__orient2d(c, b, a), -s);
    }
}

// All 24 orderings: the sign follows the parity of the permutation.
static void check_orient3d_permutations(double p[4][3]) {
    int base = selfcol_predicates__orient3d(p[0], p[1], p[2], p[3]);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            for (int k = 0; k < 4; k++) {
                if (i == j || i == k || j == k)
                    continue;
                int l = 6 - i - j - k;
                int order[4] = {i, j, k, l}, inversions = 0;
                for (int x = 0; x < 4; x++)
                    for (int y = x + 1; y < 4; y++)
                        inversions += order[x] > order[y];
                int expected = inversions % 2 ? -base : base;
                assert_int_equal(selfcol_predicates__orient3d(p[i], p[j], p[k], p[l]), expected);
            }
}

static void test_predicates_orient3d_permutations(void **state) {
    (void)state;
    rng_seed(0x9e3);
    for (int n = 0; n < 1500; n++) {
        double p[4][3];
        gen_int_adversarial3(p);
        check_orient3d_permutations(p);
        gen_extreme(p, 4, n % 3);
        check_orient3d_permutations(p);
    }
}

// Translation by integers keeps integer inputs exact, so the sign must not
// change; neither may scaling by powers of two. Negating every coordinate
// flips the sign in 3D (det scales by (-1)^3), not in 2D; swapping two axes
// flips both.
static void test_predicates_translation_scaling_reflection(void **state) {
    (void)state;
    rng_seed(0x7a5);
    for (int n = 0; n < 5000; n++) {
        double p[4][3], q[4][3];
        gen_int_adversarial3(p);
        int s = selfcol_predicates__orient3d(p[0], p[1], p[2], p[3]);
        double offset[3];
        for (int k = 0; k < 3; k++)
            offset[k] = (double)rng_int(-(INT64_C(1) << 45), INT64_C(1) << 45);
        double scale = ldexp(1.0, (int)rng_int(-200, 200));
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                q[i][k] = p[i][k] + offset[k]; // integers below 2^46: exact
        assert_int_equal(selfcol_predicates__orient3d(q[0], q[1], q[2], q[3]), s);
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                q[i][k] = p[i][k] * scale;
        assert_int_equal(selfcol_predicates__orient3d(q[0], q[1], q[2], q[3]), s);
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                q[i][k] = -p[i][k];
        assert_int_equal(selfcol_predicates__orient3d(q[0], q[1], q[2], q[3]), -s);
        for (int i = 0; i < 4; i++) {
            q[i][0] = p[i][1];
            q[i][1] = p[i][0];
            q[i][2] = p[i][2];
        }
        assert_int_equal(selfcol_predicates__orient3d(q[0], q[1], q[2], q[3]), -s);

        // 2D on the same data (xy projections of three of the points).
        int s2 = selfcol_predicates__orient2d(p[0], p[1], p[2]);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 2; k++)
                q[i][k] = p[i][k] + offset[k];
        assert_int_equal(selfcol_predicates__orient2d(q[0], q[1], q[2]), s2);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 2; k++)
                q[i][k] = -p[i][k] * scale;
        assert_int_equal(selfcol_predicates__orient2d(q[0], q[1], q[2]), s2);
        for (int i = 0; i < 3; i++) {
            q[i][0] = p[i][1];
            q[i][1] = p[i][0];
        }
        assert_int_equal(selfcol_predicates__orient2d(q[0], q[1], q[2]), -s2);
    }
}

// Lifting a, b, c to the plane z = z0 and d above it: det[u, 0; v, 0; w, h] =
// h (u x v), so orient3d equals orient2d of the xy triple.
static void test_predicates_orient3d_matches_orient2d_lifted(void **state) {
    (void)state;
    rng_seed(0x11f7);
    for (int n = 0; n < 20000; n++) {
        double p[3][3];
        gen_dyadic_near_collinear2(p);
        double z0 = n % 2 ? 0.0 : rng_wide(-10, 10);
        double a[3] = {p[0][0], p[0][1], z0}, b[3] = {p[1][0], p[1][1], z0},
               c[3] = {p[2][0], p[2][1], z0};
        double d[3] = {rng_wide(-10, 10), rng_wide(-10, 10), z0 + fabs(z0) + 1.0};
        int s = selfcol_predicates__orient2d(p[0], p[1], p[2]);
        assert_int_equal(selfcol_predicates__orient3d(a, b, c, d), s);
        d[2] = z0 - fabs(z0) - 1.0;
        assert_int_equal(selfcol_predicates__orient3d(a, b, c, d), -s);
    }
}

// ---------------------------------------------------------------------------
// collinear3d.

// Exactly collinear triples with coordinates that look like arbitrary reals:
// a has a full random 52-bit fraction in [1.25, 1.75) 2^e, dir is a multiple of
// the binade's ulp below 2^24 ulps, and b = a + dir, c = a + k dir stay in the
// binade, so they are exact. Then each coordinate of c moved by one ulp.
static void test_predicates_collinear3d_exact_constructions(void **state) {
    (void)state;
    rng_seed(0xc011);
    unsigned long naive = 0, collinear = 0, count = 0;
    static const int ks[6] = {-3, -2, -1, 2, 3, 4};
    for (int n = 0; n < 10000; n++) {
        int e = n % 2 ? 0 : 19;
        double ulp = ldexp(1.0, e - 52);
        double a[3], dir[3], b[3], c[3];
        int k = ks[rng_int(0, 5)];
        for (int i = 0; i < 3; i++) {
            a[i] = ldexp(1.25 + 0.5 * rng_unit(), e);
            dir[i] = (double)rng_int(-(1 << 24), 1 << 24) * ulp;
            if (rng_int(0, 5) == 0)
                dir[i] = 0.0; // axis-parallel lines too
            b[i] = a[i] + dir[i];
            c[i] = a[i] + k * (b[i] - a[i]);
            assert_true(b[i] - a[i] == dir[i]); // exact, checked
            assert_true(c[i] - a[i] == k * dir[i]);
        }
        assert_int_equal(ref_collinear3d_big(a, b, c), 1);
        check_collinear(a, b, c, 1, &naive);
        check_collinear(c, a, b, 1, &naive);
        check_collinear(b, c, a, 1, &naive);
        count += 3;
        collinear += 3;
        for (int i = 0; i < 3; i++) {
            double cp[3];
            copy3(cp, c);
            cp[i] = nextafter(c[i], rng_int(0, 1) ? INFINITY : -INFINITY);
            int expected = ref_collinear3d_big(a, b, cp);
            check_collinear(a, b, cp, expected, &naive);
            check_collinear(cp, b, a, expected, &naive);
            count += 2;
            collinear += 2u * (unsigned long)expected;
        }
    }
    print_message("collinear3d constructions: %lu checks, %lu collinear, naive wrong %lu times\n",
                  count, collinear, naive);
}

// Points p = (0.5 + i ulp, 0.5 + j ulp, 0.5 + k ulp) against the line through
// (12,12,12) and (24,24,24): collinear iff px == py == pz. The naive cross
// product rounds the differences p - (12,12,12) and calls many of the others
// collinear.
static void test_predicates_collinear3d_grid(void **state) {
    (void)state;
    enum { N = 12 };
    double vals[2 * N];
    for (int i = 0; i < 2 * N; i++)
        vals[i] = ulp_steps(0.5, i - N);
    const double q[3] = {12, 12, 12}, r[3] = {24, 24, 24};
    unsigned long naive = 0, count = 0;
    for (int i = 0; i < 2 * N; i++)
        for (int j = 0; j < 2 * N; j++)
            for (int k = 0; k < 2 * N; k++) {
                const double p[3] = {vals[i], vals[j], vals[k]};
                int expected = p[0] == p[1] && p[1] == p[2];
                if ((i + j + k) % 5 == 0)
                    assert_int_equal(ref_collinear3d_big(p, q, r), expected);
                check_collinear(p, q, r, expected, &naive);
                check_collinear(q, r, p, expected, &naive);
                count += 2;
            }
    print_message("collinear3d grid: %lu checks, naive wrong %lu times\n", count, naive);
    assert_true(naive > 0);
}

// Random near-collinear triples (c = the rounded a + t (b - a)), exactly
// collinear or not as the reference says; and collinear a, b, c make every
// orient3d(a, b, c, d) zero.
static void test_predicates_collinear3d_random(void **state) {
    (void)state;
    rng_seed(0xc012);
    unsigned long naive = 0, collinear = 0;
    enum { COUNT = 15000 };
    for (int n = 0; n < COUNT; n++) {
        double a[3], b[3], c[3], d[3];
        double t = (double)rng_int(-4, 4) * (n % 2 ? 1.0 : 0.125 * rng_unit());
        for (int i = 0; i < 3; i++) {
            a[i] = rng_wide(-8, 8);
            b[i] = n % 3 ? rng_wide(-8, 8) : a[i]; // a third with a == b
            c[i] = a[i] + t * (b[i] - a[i]);
            d[i] = rng_wide(-8, 8);
        }
        int expected = ref_collinear3d_big(a, b, c);
        check_collinear(a, b, c, expected, &naive);
        collinear += (unsigned long)expected;
        if (expected) {
            assert_int_equal(selfcol_predicates__orient3d(a, b, c, d), 0);
            assert_int_equal(selfcol_predicates__orient3d(d, c, a, b), 0);
        }
    }
    print_message("collinear3d random: %d checks, %lu collinear, naive wrong %lu times\n", COUNT,
                  collinear, naive);
    assert_true(collinear > 0 && collinear < COUNT);
}

// orient_along(a, b, c, v) is orient3d(a, b, c, a + v) whenever a + v is
// exact (integer coordinates), including exact zeros and near-degenerate
// integer configurations where the filter must defer to the exact path.
static void test_predicates_orient_along_matches_orient3d(void **state) {
    (void)state;
    rng_seed(0xa10a9);
    unsigned long zeros = 0;
    for (int n = 0; n < 40000; n++) {
        double p[4][3];
        gen_int_adversarial3(p);
        double v[3] = {p[3][0] - p[0][0], p[3][1] - p[0][1], p[3][2] - p[0][2]};
        int expected = selfcol_predicates__orient3d(p[0], p[1], p[2], p[3]);
        assert_int_equal(selfcol_predicates__orient_along(p[0], p[1], p[2], v), expected);
        zeros += expected == 0;
    }
    // Projection along an axis is the 2D orientation of the dropped axis.
    const double a[3] = {0.1, 0.2, 5}, b[3] = {0.3, 0.2, -7}, c[3] = {0.1, 0.7, 1e9};
    const double z[3] = {0, 0, 1}, mz[3] = {0, 0, -1}, x[3] = {1, 0, 0};
    assert_int_equal(selfcol_predicates__orient_along(a, b, c, z), 1);
    assert_int_equal(selfcol_predicates__orient_along(a, b, c, mz), -1);
    const double c2[3] = {0.5, 0.2, 3};
    assert_int_equal(selfcol_predicates__orient_along(a, b, c2, z), 0); // collinear in xy
    (void)x;
    print_message("orient_along: 40000 integer cases, %lu exact zeros\n", zeros);
    assert_true(zeros > 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predicates_orient2d_hand_cases),
        cmocka_unit_test(test_predicates_orient3d_hand_cases),
        cmocka_unit_test(test_predicates_collinear3d_hand_cases),
        cmocka_unit_test(test_predicates_orient2d_shewchuk_grid),
        cmocka_unit_test(test_predicates_orient3d_plane_grid),
        cmocka_unit_test(test_predicates_orient3d_integer_adversarial),
        cmocka_unit_test(test_predicates_orient2d_dyadic_adversarial),
        cmocka_unit_test(test_predicates_orient3d_random_wide_range),
        cmocka_unit_test(test_predicates_orient2d_random_wide_range),
        cmocka_unit_test(test_predicates_extreme_magnitudes),
        cmocka_unit_test(test_predicates_orient2d_permutations),
        cmocka_unit_test(test_predicates_orient3d_permutations),
        cmocka_unit_test(test_predicates_translation_scaling_reflection),
        cmocka_unit_test(test_predicates_orient3d_matches_orient2d_lifted),
        cmocka_unit_test(test_predicates_collinear3d_exact_constructions),
        cmocka_unit_test(test_predicates_collinear3d_grid),
        cmocka_unit_test(test_predicates_collinear3d_random),
        cmocka_unit_test(test_predicates_orient_along_matches_orient3d),
    };
    int failed = cmocka_run_group_tests_name("predicates_internal", tests, NULL, NULL);
    print_message("predicates_internal: %lu results checked against exact references, naive "
                  "double arithmetic wrong on %lu of them\n",
                  g_checked, g_naive_wrong);
    return failed;
}
