// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Cross-check of the two narrow phases: the closed form (narrow.c) against the
// libccd backend (narrow_ccd.c), on random pairs (uniform in [-1, 1]^3, plus
// near-contact and degenerate ones) and on hand-made pairs.
//
// The libccd proximities (VF, EE) answer "distance, if below radius": every
// pair is asked at several radii, with tolerance = REL_TOL * radius as
// lib/query/query.c asks (libccd's bisection on the inflation radius, see
// narrow_ccd.c).
//
// Agreement bands, for a pair whose largest coordinate magnitude is S, at
// radius r, tolerance tol = REL_TOL * r:
//
// - Distances (VF, EE): BAND = tol + 1e-12 S.
//   libccd's distance is within tol / 2 + tol / 16 of the true one when
//   positive (the final bisection bracket, plus MPR's one-sided boundary
//   tolerance; see narrow_ccd.c), and 0 means below tol, up to the rounding
//   of its yes/no tests, which work on coordinates of magnitude ~S: a few
//   DBL_EPSILON S. The closed form is within rounding (~1e-16 S) of the true
//   distance. 1e-12 S covers both roundings with a wide margin and is far
//   below tol for every radius here.
//   The same band bounds the gap between libccd's distance and the distance of
//   the points rebuilt from its weights (those come from a closest-point
//   helper, exact up to rounding).
//   Presence: a pair whose closed-form distance is below r - BAND must be
//   found (a finite answer, within BAND); one above r + BAND must return
//   HUGE_VAL (and leave `out` alone); in between, either, but a finite answer
//   must still be within BAND. Disagreements in between are counted.
//
// - Thin configurations: libccd's MPR test is ill-conditioned when the
//   Minkowski difference is thin (a needle triangle, nearly parallel edges)
//   and the radius tested is small: its portal normals come from cross
//   products of nearly parallel edges. Its distance is then off by up to
//   ~0.6 sqrt(DBL_EPSILON) S when the distance is below that, whatever the
//   tolerance (measured on 20000 pairs of the families below: 0.32 for
//   needles, 0.56 for nearly parallel segments). Needle triangles get
//   BAND + sqrt(DBL_EPSILON) S (thin_band()); nearly parallel segments nearly
//   touching get BAND + 4 sqrt(DBL_EPSILON) S, which also covers the closed
//   form's accuracy limit there; see near_parallel_band().
//
// - Interference (EF): libccd 2.1's ccdGJKIntersect() ignores `tol`. It calls
//   "touching" |AB x AO|^2 < DBL_EPSILON for a simplex segment AB and
//   dist^2 < DBL_EPSILON for a simplex triangle (AO: from a simplex point to
//   the origin of the Minkowski difference), i.e. a configuration is touching
//   when its distance is below sqrt(DBL_EPSILON) * max(1, 1 / l), where l is
//   the length of a segment between two Minkowski vertices: this is absolute
//   (not scaled with the mesh) and grows for short edges. So
//   EF_BAND = 2e-9 + 1e-9 S + 2 sqrt(DBL_EPSILON) max(1, 1 / l_min), with
//   l_min the smallest non-zero distance between the 6 Minkowski vertices
//   p_i - t_j (2e-9 + 1e-9 S: a rounding allowance far above the rounding of
//   the crossing points, whose reconstruction must also agree within it).
//   The answers must agree when the segment-triangle distance exceeds EF_BAND
//   (then neither may report a hit), and when the closed form reports a
//   crossing with both endpoints farther than EF_BAND from the plane (then
//   libccd must report it too). Between the two, libccd reports touching
//   configurations (distance 0 or within its threshold) as hits or not,
//   inconsistently: counted and printed, not asserted.
//
// Every random set has a fixed seed; a disagreement prints its input exactly.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "base/vec3.h"
#include "narrow/narrow.h"

#include <float.h>
#include <math.h>

// libccd's tolerance relative to the radius, as lib/query/query.c passes it.
#define REL_TOL 1e-7
#define N_RANDOM 2000
#define WEIGHT_SLACK 1e-12

// The radii every random proximity pair is asked at: about 2/3, 1/6 and 1/100
// of the uniform pairs are within them (the near-contact ones are within all).
static const double RADII[3] = {1.0, 0.3, 0.03};

// The radius of the hand-made pairs, above all their distances.
#define R_HAND 8.0

// ---------------------------------------------------------------------------
// Small helpers.

typedef struct rng {
    uint64_t state;
} rng;

// splitmix64: deterministic, portable.
static uint64_t rng_next(rng *r) {
    uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

// Uniform in [0, 1).
static double rng_unit(rng *r) {
    return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

// Uniform in [-1, 1).
static double rng_sym(rng *r) {
    return 2.0 * rng_unit(r) - 1.0;
}

static void rng_point(rng *r, double p[3]) {
    p[0] = rng_sym(r);
    p[1] = rng_sym(r);
    p[2] = rng_sym(r);
}

// 10^(-lo .. -hi), log-uniform.
static double rng_tiny(rng *r, double lo, double hi) {
    return pow(10.0, -(lo + (hi - lo) * rng_unit(r)));
}

static double norm3(const double a[3]) {
    return sqrt(vec3_dot(a, a));
}

static double dist3(const double a[3], const double b[3]) {
    double d[3];
    vec3_sub(d, a, b);
    return norm3(d);
}

// Distance band at radius r for coordinates of magnitude scale (top of file).
static double dist_band(double radius, double scale) {
    return REL_TOL * radius + 1e-12 * scale;
}

// EF band: see the top of the file (its BAND part with the EF tolerance).
static double ef_band(const double p0[3], const double p1[3], const double a[3], const double b[3],
                      const double c[3]) {
    const double *seg[2] = {p0, p1}, *tri[3] = {a, b, c};
    const double *pts[5] = {p0, p1, a, b, c};
    double mink[6][3], lmin = HUGE_VAL;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 3; ++j)
            vec3_sub(mink[3 * i + j], seg[i], tri[j]);
    for (int i = 0; i < 6; ++i)
        for (int j = i + 1; j < 6; ++j) {
            double l = dist3(mink[i], mink[j]);
            if (l > 0.0)
                lmin = fmin(lmin, l);
        }
    return 2e-9 + 1e-9 * vec3_max_abs(5, pts) + 2.0 * sqrt(DBL_EPSILON) * fmax(1.0, 1.0 / lmin);
}

static void combine2(double o[3], const double w[2], const double *p0, const double *p1) {
    for (int k = 0; k < 3; ++k)
        o[k] = w[0] * p0[k] + w[1] * p1[k];
}

static void combine3(double o[3], const double w[3], const double *a, const double *b,
                     const double *c) {
    for (int k = 0; k < 3; ++k)
        o[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
}

static void check_weights(const double *w, int n) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        assert_true(w[i] >= -WEIGHT_SLACK && w[i] <= 1.0 + WEIGHT_SLACK);
        sum += w[i];
    }
    assert_true(fabs(sum - 1.0) <= WEIGHT_SLACK);
}

// The common checks of a result whose closest points are p (first primitive)
// and q (second), rebuilt from the weights: they are `distance` apart within
// `band`; the direction is a unit vector, and along p - q when the distance is
// clearly above rounding.
static void check_points(const selfcol_narrow_result *r, const double p[3], const double q[3],
                         double band) {
    double d[3];
    vec3_sub(d, p, q);
    double len = norm3(d);
    assert_true(fabs(len - r->distance) <= band);
    assert_true(fabs(norm3(r->direction) - 1.0) <= 1e-12);
    if (r->distance > 1e-6) {
        for (int k = 0; k < 3; ++k)
            assert_true(fabs(r->direction[k] - d[k] / len) <= 1e-6);
    }
}

static void check_vf_result(const selfcol_narrow_result *r, const double p[3], const double a[3],
                            const double b[3], const double c[3], double band) {
    double q[3];
    assert_true(r->wa[0] == 1.0 && r->wa[1] == 0.0);
    check_weights(r->wb, 3);
    combine3(q, r->wb, a, b, c);
    check_points(r, p, q, band);
}

static void check_ee_result(const selfcol_narrow_result *r, const double p0[3], const double p1[3],
                            const double q0[3], const double q1[3], double band) {
    double p[3], q[3];
    check_weights(r->wa, 2);
    check_weights(r->wb, 2);
    assert_true(r->wb[2] == 0.0);
    combine2(p, r->wa, p0, p1);
    combine2(q, r->wb, q0, q1);
    check_points(r, p, q, band);
}

// A hit: distance 0, the two rebuilt points within `band` of each other.
static void check_ef_result(const selfcol_narrow_result *r, const double p0[3], const double p1[3],
                            const double a[3], const double b[3], const double c[3], double band) {
    double p[3], q[3];
    assert_true(r->distance == 0.0);
    check_weights(r->wa, 2);
    check_weights(r->wb, 3);
    combine2(p, r->wa, p0, p1);
    combine3(q, r->wb, a, b, c);
    assert_true(dist3(p, q) <= band);
    assert_true(fabs(norm3(r->direction) - 1.0) <= 1e-12);
}

// Agreement figures of one random run.
typedef struct figures {
    int pairs;       // queries (pair x radius)
    int within;      // closed form below radius - band: libccd must find them
    int beyond;      // closed form above radius + band: libccd must not
    int near_radius; // in between
    int near_found;  // ... of which libccd found
    double max_diff; // max |d_ccd - d_closed| over the found pairs
    double min_rel;  // min (d_ccd - d_closed) / tol
    double max_rel;  // max (d_ccd - d_closed) / tol
    int hits_closed, hits_ccd, agree_hits, in_band, in_band_ccd_only;
    double max_touch_dist;  // max segment-triangle distance of a libccd-only hit
    double max_miss_height; // max min-endpoint-plane distance of a libccd-only miss
} figures;

static void print_pair(int n, const double *const pts[]) {
    for (int i = 0; i < n; ++i)
        print_message("  {%a, %a, %a}\n", pts[i][0], pts[i][1], pts[i][2]);
}

// Both backends on one proximity pair at one radius (see the bands at the top).
// On a disagreement, prints the n input points exactly (hex floats).
static void compare_distance(figures *f, double dc, double dg, double radius, double band, int n,
                             const double *const pts[]) {
    f->pairs++;
    int must_find = dc<radius - band, must_miss = dc> radius + band;
    f->within += must_find;
    f->beyond += must_miss;
    if (!must_find && !must_miss) {
        f->near_radius++;
        f->near_found += dg < HUGE_VAL;
    }
    if ((must_find && !(dg < HUGE_VAL)) || (must_miss && dg != HUGE_VAL)) {
        print_message("presence disagreement at radius %.17g: closed %.17g ccd %.17g, input:\n",
                      radius, dc, dg);
        print_pair(n, pts);
    }
    if (must_miss) {
        assert_true(dg == HUGE_VAL);
        return;
    }
    if (must_find)
        assert_true(dg < HUGE_VAL);
    if (!(dg < HUGE_VAL))
        return;
    double diff = fabs(dc - dg), tol = REL_TOL * radius;
    f->max_diff = fmax(f->max_diff, diff);
    f->min_rel = fmin(f->min_rel, (dg - dc) / tol);
    f->max_rel = fmax(f->max_rel, (dg - dc) / tol);
    if (diff > band) {
        print_message("distance disagreement at radius %.17g: closed %.17g ccd %.17g, input:\n",
                      radius, dc, dg);
        print_pair(n, pts);
    }
    assert_true(diff <= band);
    // The libccd backend takes its closest points and direction from the
    // closed form (narrow_ccd.c), so comparing directions would compare the
    // closed form with itself; check_*_result checks that those points are
    // libccd's distance apart instead.
}

// `out` must be left alone when the answer is HUGE_VAL.
static const selfcol_narrow_result SENTINEL = {
    -1.0, {-1.0, -1.0}, {-1.0, -1.0, -1.0}, {-1.0, -1.0, -1.0}};

static int untouched(const selfcol_narrow_result *r) {
    return r->distance == -1.0 && r->wa[0] == -1.0 && r->wa[1] == -1.0 && r->wb[0] == -1.0 &&
           r->wb[1] == -1.0 && r->wb[2] == -1.0 && r->direction[0] == -1.0 &&
           r->direction[1] == -1.0 && r->direction[2] == -1.0;
}

// ---------------------------------------------------------------------------
// One pair of each kind at one radius, both backends, all the checks.

// extra: added to the band (see thin_band).
static void run_vf(figures *f, const double p[3], const double a[3], const double b[3],
                   const double c[3], double radius, double extra) {
    const double *pts[4] = {p, a, b, c};
    double band = dist_band(radius, vec3_max_abs(4, pts)) + extra, tol = REL_TOL * radius;
    selfcol_narrow_result rc, rg = SENTINEL;
    double dc = selfcol_narrow__vf(p, a, b, c, &rc);
    double dg = selfcol_narrow_ccd__vf(p, a, b, c, radius, tol, &rg);
    assert_true(dc == rc.distance);
    assert_true(dg == selfcol_narrow_ccd__vf(p, a, b, c, radius, tol, NULL));
    check_vf_result(&rc, p, a, b, c, 1e-12 * vec3_max_abs(4, pts) + extra);
    if (dg < HUGE_VAL) {
        assert_true(dg == rg.distance && dg >= 0.0 && dg < radius);
        check_vf_result(&rg, p, a, b, c, band);
    } else {
        assert_true(untouched(&rg));
    }
    compare_distance(f, dc, dg, radius, band, 4, pts);
}

// extra: added to the band (see near_parallel_band).
static void run_ee(figures *f, const double p0[3], const double p1[3], const double q0[3],
                   const double q1[3], double radius, double extra) {
    const double *pts[4] = {p0, p1, q0, q1};
    double band = dist_band(radius, vec3_max_abs(4, pts)) + extra, tol = REL_TOL * radius;
    selfcol_narrow_result rc, rg = SENTINEL;
    double dc = selfcol_narrow__ee(p0, p1, q0, q1, &rc);
    double dg = selfcol_narrow_ccd__ee(p0, p1, q0, q1, radius, tol, &rg);
    assert_true(dc == rc.distance);
    assert_true(dg == selfcol_narrow_ccd__ee(p0, p1, q0, q1, radius, tol, NULL));
    check_ee_result(&rc, p0, p1, q0, q1, 1e-12 * vec3_max_abs(4, pts) + extra);
    if (dg < HUGE_VAL) {
        assert_true(dg == rg.distance && dg >= 0.0 && dg < radius);
        check_ee_result(&rg, p0, p1, q0, q1, band);
    } else {
        assert_true(untouched(&rg));
    }
    compare_distance(f, dc, dg, radius, band, 4, pts);
}

static void run_vf_radii(figures *f, const double p[3], const double a[3], const double b[3],
                         const double c[3], double extra) {
    for (int i = 0; i < 3; ++i)
        run_vf(f, p, a, b, c, RADII[i], extra);
}

static void run_ee_radii(figures *f, const double p0[3], const double p1[3], const double q0[3],
                         const double q1[3], double extra) {
    for (int i = 0; i < 3; ++i)
        run_ee(f, p0, p1, q0, q1, RADII[i], extra);
}

// Distance between a segment and a triangle, from the closed form: 0 for a
// crossing, else the closest pair involves a segment endpoint or a triangle
// edge. (The libccd proximities answer only below a radius; the VF/EE
// cross-check above covers the closed form's distances.)
static double segment_triangle_distance(const double p0[3], const double p1[3], const double a[3],
                                        const double b[3], const double c[3], int crossing) {
    if (crossing)
        return 0.0;
    double d = selfcol_narrow__vf(p0, a, b, c, NULL);
    d = fmin(d, selfcol_narrow__vf(p1, a, b, c, NULL));
    d = fmin(d, selfcol_narrow__ee(p0, p1, a, b, NULL));
    d = fmin(d, selfcol_narrow__ee(p0, p1, b, c, NULL));
    d = fmin(d, selfcol_narrow__ee(p0, p1, c, a, NULL));
    return d;
}

// Distances of p0 and p1 to the plane of (a, b, c); both +inf without a plane.
static void plane_distances(const double p0[3], const double p1[3], const double a[3],
                            const double b[3], const double c[3], double h[2]) {
    double ab[3], ac[3], n[3], r[3];
    vec3_sub(ab, b, a);
    vec3_sub(ac, c, a);
    vec3_cross(n, ab, ac);
    double nl = norm3(n);
    if (!(nl > 0.0)) {
        h[0] = h[1] = HUGE_VAL;
        return;
    }
    vec3_sub(r, p0, a);
    h[0] = fabs(vec3_dot(r, n)) / nl;
    vec3_sub(r, p1, a);
    h[1] = fabs(vec3_dot(r, n)) / nl;
}

// Runs both EF tests; returns the libccd answer. EF ignores the tolerance
// (any value may be passed); the rounding part of its band is
// 2e-9 + 1e-9 S.
static int run_ef(figures *f, const double p0[3], const double p1[3], const double a[3],
                  const double b[3], const double c[3]) {
    const double *pts[5] = {p0, p1, a, b, c};
    double band = 2e-9 + 1e-9 * vec3_max_abs(5, pts);
    double eband = ef_band(p0, p1, a, b, c);
    selfcol_narrow_result rc, rg;
    int hc = selfcol_narrow__ef(p0, p1, a, b, c, &rc);
    int hg = selfcol_narrow_ccd__ef(p0, p1, a, b, c, 1e-9, &rg);
    assert_int_equal(hg, selfcol_narrow_ccd__ef(p0, p1, a, b, c, 1e-9, NULL));
    if (hc)
        check_ef_result(&rc, p0, p1, a, b, c, band);
    if (hg)
        check_ef_result(&rg, p0, p1, a, b, c, eband);

    double dist = segment_triangle_distance(p0, p1, a, b, c, hc);
    double h[2];
    plane_distances(p0, p1, a, b, c, h);
    f->pairs++;
    f->hits_closed += hc;
    f->hits_ccd += hg;
    f->agree_hits += hc && hg;
    if (dist > eband) {
        assert_int_equal(hc, 0);
        assert_int_equal(hg, 0);
    }
    if (hc && h[0] > eband && h[1] > eband) {
        assert_int_equal(hg, 1);
        // A transversal crossing: the crossing point is unique.
        double xc[3], xg[3];
        combine2(xc, rc.wa, p0, p1);
        combine2(xg, rg.wa, p0, p1);
        assert_true(dist3(xc, xg) <= eband);
    }
    if (hc != hg) {
        f->in_band++;
        f->in_band_ccd_only += hg;
        if (hg)
            f->max_touch_dist = fmax(f->max_touch_dist, dist);
        else
            f->max_miss_height = fmax(f->max_miss_height, fmin(h[0], h[1]));
    }
    return hg;
}

// ---------------------------------------------------------------------------
// Random pairs.

// A random triangle; every 16th collinear (c on the line ab, up to rounding)
// and every 16th with a repeated corner (exactly zero area).
static void random_triangle(rng *r, unsigned i, double a[3], double b[3], double c[3]) {
    rng_point(r, a);
    rng_point(r, b);
    rng_point(r, c);
    if (i % 16 == 1) {
        double t = 3.0 * rng_unit(r) - 1.0;
        for (int k = 0; k < 3; ++k)
            c[k] = a[k] + t * (b[k] - a[k]);
    } else if (i % 16 == 2) {
        c[0] = a[0];
        c[1] = a[1];
        c[2] = a[2];
    }
}

// A random point of triangle (a, b, c).
static void interior_point(rng *r, const double a[3], const double b[3], const double c[3],
                           double x[3]) {
    double s = rng_unit(r), t = rng_unit(r);
    if (s + t > 1.0) {
        s = 1.0 - s;
        t = 1.0 - t;
    }
    for (int k = 0; k < 3; ++k)
        x[k] = a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]);
}

// Unit normal of (a, b, c); 0 when it is nearly degenerate (|ab x ac| <= 1e-3).
static int unit_normal(double n[3], const double a[3], const double b[3], const double c[3]) {
    double ab[3], ac[3];
    vec3_sub(ab, b, a);
    vec3_sub(ac, c, a);
    vec3_cross(n, ab, ac);
    double l = norm3(n);
    if (!(l > 1e-3))
        return 0;
    n[0] /= l;
    n[1] /= l;
    n[2] /= l;
    return 1;
}

static figures new_figures(void) {
    figures f = {0};
    f.min_rel = HUGE_VAL;
    f.max_rel = -HUGE_VAL;
    return f;
}

static void print_distance_figures(const char *kind, const figures *f) {
    print_message("%s: %d queries (radii 1, 0.3, 0.03; tol = 1e-7 radius): %d within radius - "
                  "band, all found; %d beyond radius + band, all HUGE_VAL; %d inside the band "
                  "around the radius (%d found). Found pairs: max |d_ccd - d_closed| = %.3g, "
                  "(d_ccd - d_closed) / tol in [%.3f, %.3f]\n",
                  kind, f->pairs, f->within, f->beyond, f->near_radius, f->near_found, f->max_diff,
                  f->min_rel, f->max_rel);
}

static void test_narrow_ccd_random_vf(void **state) {
    (void)state;
    rng r = {0x5eed0001u};
    figures f = new_figures();
    for (unsigned i = 0; i < N_RANDOM; ++i) {
        double p[3], a[3], b[3], c[3], n[3];
        random_triangle(&r, i, a, b, c);
        rng_point(&r, p);
        if (i % 16 == 3 && unit_normal(n, a, b, c)) {
            // Near contact: above an interior point, at 1e-1 .. 1e-13.
            double h = rng_tiny(&r, 1.0, 13.0) * (rng_unit(&r) < 0.5 ? -1.0 : 1.0);
            interior_point(&r, a, b, c, p);
            for (int k = 0; k < 3; ++k)
                p[k] += h * n[k];
        } else if (i % 16 == 4) {
            // Near an edge, in the plane, just outside.
            double t = rng_unit(&r), e[3], ab[3], ac[3], nn[3];
            vec3_sub(ab, b, a);
            vec3_sub(ac, c, a);
            vec3_cross(nn, ab, ac);
            vec3_cross(e, ab, nn); // in-plane, away from c
            double l = norm3(e);
            if (l > 0.0) {
                double h = rng_tiny(&r, 1.0, 13.0) / l;
                for (int k = 0; k < 3; ++k)
                    p[k] = a[k] + t * ab[k] + h * e[k];
            }
        } else if (i % 16 == 5) {
            p[0] = a[0]; // on a corner
            p[1] = a[1];
            p[2] = a[2];
        }
        run_vf_radii(&f, p, a, b, c, 0.0);
    }
    print_distance_figures("VF", &f);
}

static void test_narrow_ccd_random_ee(void **state) {
    (void)state;
    rng r = {0x5eed0002u};
    figures f = new_figures();
    for (unsigned i = 0; i < N_RANDOM; ++i) {
        double p0[3], p1[3], q0[3], q1[3];
        rng_point(&r, p0);
        rng_point(&r, p1);
        rng_point(&r, q0);
        rng_point(&r, q1);
        if (i % 16 == 1) {
            // Parallel (up to rounding), the second one shifted.
            double t = 2.0 * rng_sym(&r);
            for (int k = 0; k < 3; ++k)
                q1[k] = q0[k] + t * (p1[k] - p0[k]);
        } else if (i % 16 == 2) {
            q1[0] = q0[0]; // zero-length second edge
            q1[1] = q0[1];
            q1[2] = q0[2];
        } else if (i % 16 == 3) {
            p1[0] = p0[0]; // zero-length first edge
            p1[1] = p0[1];
            p1[2] = p0[2];
        } else if (i % 16 == 4) {
            // Near contact: interior points s, t at a distance along the common
            // normal, 1e-1 .. 1e-13 (both signs).
            double d1[3], d2[3], n[3];
            vec3_sub(d1, p1, p0);
            vec3_sub(d2, q1, q0);
            vec3_cross(n, d1, d2);
            double l = norm3(n);
            if (l > 1e-3) {
                double s = rng_unit(&r), t = rng_unit(&r);
                double h = rng_tiny(&r, 1.0, 13.0) * (rng_unit(&r) < 0.5 ? -1.0 : 1.0);
                double shift[3];
                for (int k = 0; k < 3; ++k)
                    shift[k] = (p0[k] + s * d1[k]) - (q0[k] + t * d2[k]) + h * n[k] / l;
                for (int k = 0; k < 3; ++k) {
                    q0[k] += shift[k];
                    q1[k] += shift[k];
                }
            }
        } else if (i % 16 == 5) {
            q0[0] = p1[0]; // sharing an endpoint
            q0[1] = p1[1];
            q0[2] = p1[2];
        }
        run_ee_radii(&f, p0, p1, q0, q1, 0.0);
    }
    print_distance_figures("EE", &f);
}
static void test_narrow_ccd_random_ef(void **state) {
    (void)state;
    rng r = {0x5eed0003u};
    figures f = new_figures();
    for (unsigned i = 0; i < N_RANDOM; ++i) {
        double p0[3], p1[3], a[3], b[3], c[3], n[3];
        random_triangle(&r, i, a, b, c);
        rng_point(&r, p0);
        rng_point(&r, p1);
        if (i % 16 == 3) {
            p1[0] = p0[0]; // zero-length edge
            p1[1] = p0[1];
            p1[2] = p0[2];
        } else if (i % 16 == 4 && unit_normal(n, a, b, c)) {
            // Near contact: an endpoint 1e-1 .. 1e-13 off the plane, above an
            // interior point, the other one on either side.
            double x[3], h = rng_tiny(&r, 1.0, 13.0) * (rng_unit(&r) < 0.5 ? -1.0 : 1.0);
            interior_point(&r, a, b, c, x);
            for (int k = 0; k < 3; ++k)
                p0[k] = x[k] + h * n[k];
        } else if (i % 16 == 5 && unit_normal(n, a, b, c)) {
            // Near an edge: crossing the plane 1e-1 .. 1e-13 inside or outside
            // the edge ab.
            double ab[3], e[3], t = rng_unit(&r);
            vec3_sub(ab, b, a);
            vec3_cross(e, ab, n);
            double l = norm3(e);
            double h = rng_tiny(&r, 1.0, 13.0) * (rng_unit(&r) < 0.5 ? -1.0 : 1.0) / l;
            double up = 0.1 + rng_unit(&r), down = 0.1 + rng_unit(&r);
            for (int k = 0; k < 3; ++k) {
                double x = a[k] + t * ab[k] + h * e[k];
                p0[k] = x + up * n[k];
                p1[k] = x - down * n[k];
            }
        }
        run_ef(&f, p0, p1, a, b, c);
    }
    print_message("EF: %d pairs, %d crossings (closed form), %d hits (libccd), %d both; "
                  "%d disagreements, all inside the band: %d libccd-only hits (max distance "
                  "%.3g), %d libccd-only misses (max endpoint-plane distance %.3g)\n",
                  f.pairs, f.hits_closed, f.hits_ccd, f.agree_hits, f.in_band, f.in_band_ccd_only,
                  f.max_touch_dist, f.in_band - f.in_band_ccd_only, f.max_miss_height);
}

// Extra band for thin configurations (see the top of the file).
static double thin_band(int n, const double *const pts[]) {
    return sqrt(DBL_EPSILON) * vec3_max_abs(n, pts);
}

// Needle triangles (two corners 1e-2 .. 1e-12 apart), corners in every
// order, the point near the triangle: the barycentric frame of the interior
// candidate (closed form, closest-point helper) must not be made of the two
// long, nearly parallel edges; libccd's MPR test is ill-conditioned there.
static void test_narrow_ccd_random_vf_needles(void **state) {
    (void)state;
    rng r = {0x5eed0005u};
    figures f = new_figures();
    for (unsigned i = 0; i < N_RANDOM; ++i) {
        double p[3], t[3][3], n[3];
        rng_point(&r, t[0]);
        rng_point(&r, t[1]);
        double gap = rng_tiny(&r, 2.0, 12.0);
        for (int k = 0; k < 3; ++k)
            t[2][k] = t[0][k] + gap * rng_sym(&r);
        double l0 = rng_unit(&r), l1 = rng_unit(&r), l2 = rng_unit(&r), sum = l0 + l1 + l2;
        double h = rng_tiny(&r, 1.0, 14.0) * (rng_unit(&r) < 0.5 ? -1.0 : 1.0);
        int have_normal = unit_normal(n, t[0], t[1], t[2]);
        for (int k = 0; k < 3; ++k) {
            p[k] = (l0 * t[0][k] + l1 * t[1][k] + l2 * t[2][k]) / sum;
            p[k] += have_normal ? h * n[k] : h * rng_sym(&r);
        }
        unsigned rot = i % 3;
        const double *pts[4] = {p, t[0], t[1], t[2]};
        run_vf_radii(&f, p, t[rot], t[(rot + 1) % 3], t[(rot + 2) % 3], thin_band(4, pts));
    }
    print_distance_figures("VF needles", &f);
}

// Extra band for nearly parallel segments nearly touching. The closest pair
// solves a 2x2 system of condition ~1/angle^2, which in double precision
// places the pair, along the segments, only within ~min(DBL_EPSILON / angle,
// angle) * length <= sqrt(DBL_EPSILON) * length, and that error enters the
// distance linearly when the distance is below it: a limit for the closed form
// and the libccd backend's closest-point helper, measured on 1e6 pairs of the
// family below against quad precision at 1.72 sqrt(DBL_EPSILON) S (closed form
// refined by one projection step). libccd's MPR test is ill-conditioned on the
// same thin Minkowski differences: 0.56 sqrt(DBL_EPSILON) S measured.
static double near_parallel_band(const double p0[3], const double p1[3], const double q0[3],
                                 const double q1[3]) {
    const double *pts[4] = {p0, p1, q0, q1};
    return 4.0 * sqrt(DBL_EPSILON) * vec3_max_abs(4, pts);
}

// Nearly parallel segments (angle 1e-2 .. 1e-12) at 1e-1 .. 1e-13 from each
// other: the interior stationary point is ill-conditioned.
static void test_narrow_ccd_random_ee_near_parallel(void **state) {
    (void)state;
    rng r = {0x5eed0006u};
    figures f = new_figures();
    for (unsigned i = 0; i < N_RANDOM; ++i) {
        double p0[3], p1[3], q0[3], q1[3];
        rng_point(&r, p0);
        rng_point(&r, p1);
        rng_point(&r, q0);
        double tilt = rng_tiny(&r, 2.0, 12.0), len = 0.2 + rng_unit(&r);
        for (int k = 0; k < 3; ++k)
            q1[k] = q0[k] + len * (p1[k] - p0[k]) + tilt * rng_sym(&r);
        // Move q so that an interior point of it comes near one of p.
        double s = rng_unit(&r), t = rng_unit(&r), h = rng_tiny(&r, 1.0, 13.0);
        for (int k = 0; k < 3; ++k) {
            double shift = (p0[k] + s * (p1[k] - p0[k])) - (q0[k] + t * (q1[k] - q0[k]));
            q0[k] += shift + h * rng_sym(&r);
            q1[k] += shift + h * rng_sym(&r);
        }
        run_ee_radii(&f, p0, p1, q0, q1, near_parallel_band(p0, p1, q0, q1));
    }
    print_distance_figures("EE near-parallel", &f);
}

// Pairs on which the closed form was seen off by more than the band, with
// their distances computed in quad precision (__float128, same candidates).
// Both are thin configurations, where libccd's MPR test has its accuracy
// floor (sqrt(DBL_EPSILON) S, see the top of the file): asked at radius 1e-6
// (tolerance 1e-15, far below that floor), libccd's distance is within it.
static void expect_thin(double d, double reference, int n, const double *const pts[]) {
    print_message(
        "  libccd at radius 1e-6: %.17g (reference %.17g, off by %.3g sqrt(DBL_EPSILON) S)\n", d,
        reference, fabs(d - reference) / thin_band(n, pts));
    assert_true(fabs(d - reference) <= thin_band(n, pts));
}

static void test_narrow_ccd_closed_form_regressions(void **state) {
    (void)state;
    figures f = new_figures();
    // Nearly parallel segments, true distance 1.6137e-11 (closed form at the
    // time of writing: 5.1e-6).
    const double p0[3] = {-0x1.cfb2acc6bf422p-1, -0x1.8374bfa13c404p-1, 0x1.1dd2bcf8920dcp-1};
    const double p1[3] = {0x1.bae94958f20dp-1, 0x1.af4fca67c986p-1, -0x1.a045c2ff868ep-1};
    const double q0[3] = {-0x1.29909cf83a41bp-1, -0x1.dad551ac1daf4p-2, 0x1.3a55994c03608p-2};
    const double q1[3] = {0x1.9fbd7963bebdep-1, 0x1.96c50d82de9d4p-1, -0x1.8b3b3b2eae0a1p-1};
    const double *e1[4] = {p0, p1, q0, q1};
    print_message("near-parallel EE, closed form %.17g\n",
                  selfcol_narrow__ee(p0, p1, q0, q1, NULL));
    expect_thin(selfcol_narrow_ccd__ee(p0, p1, q0, q1, 1e-6, 1e-15, NULL), 1.6137346564072178e-11,
                4, e1);
    run_ee_radii(&f, p0, p1, q0, q1, near_parallel_band(p0, p1, q0, q1));
    // Another one, true distance 3.997e-13 (closed form: 2.57e-7).
    const double r0[3] = {-0x1.91a83665d0998p-3, -0x1.9ab63df30b9cap-1, 0x1.7ad89cdf25db4p-2};
    const double r1[3] = {-0x1.9c66ec4300988p-3, 0x1.392f86bb7ff6p-3, 0x1.7ae5eff8dba0cp-2};
    const double s0[3] = {-0x1.97f91048de774p-3, -0x1.eea0f64eb4973p-3, 0x1.7ae02dc0a619dp-2};
    const double s1[3] = {-0x1.a04096d42be4cp-3, 0x1.fccee05947c57p-2, 0x1.7aeb53941b42p-2};
    const double *e2[4] = {r0, r1, s0, s1};
    print_message("near-parallel EE, closed form %.17g\n",
                  selfcol_narrow__ee(r0, r1, s0, s1, NULL));
    expect_thin(selfcol_narrow_ccd__ee(r0, r1, s0, s1, 1e-6, 1e-15, NULL), 3.997036352042026e-13, 4,
                e2);
    run_ee_radii(&f, r0, r1, s0, s1, near_parallel_band(r0, r1, s0, s1));
    // A needle triangle whose short edge (length ~1e-8) is opposite its first
    // corner; the point is 3.43e-11 from it, above its interior (closed form:
    // 1.58e-8 in this corner order, right in the next one).
    const double p[3] = {0x1.4d1824bab9d83p-1, -0x1.aa8fdaaa650d3p-1, -0x1.50038b5d3a1c4p-2};
    const double a[3] = {-0x1.680a75bf24d26p-1, 0x1.de7c033a38674p-1, 0x1.1bcdc4d18e28p-1};
    const double b[3] = {0x1.8331e6d5760cdp-1, -0x1.f133dffadf822p-1, -0x1.968b18b624d2dp-2};
    const double c[3] = {0x1.8331e5ff07b26p-1, -0x1.f133e0e3ae11p-1, -0x1.968b178ad16bp-2};
    const double *v[4] = {p, a, b, c};
    print_message("needle VF, closed form %.17g\n", selfcol_narrow__vf(p, a, b, c, NULL));
    expect_thin(selfcol_narrow_ccd__vf(p, a, b, c, 1e-6, 1e-15, NULL), 3.4313635727897646e-11, 4,
                v);
    run_vf_radii(&f, p, b, c, a, thin_band(4, v)); // the short edge at the first corner
    run_vf_radii(&f, p, a, b, c, thin_band(4, v));
}

// The tolerance is the accuracy of the distance: the bisection stops at a
// bracket that wide, and libccd's MPR gets a sixteenth of it (narrow_ccd.c),
// so |d_ccd - d| <= 0.5625 tol when d_ccd > 0, and d < tol when d_ccd = 0
// (plus rounding). A tolerance below 2^-30 radius (zero, negative or NaN
// included) counts as 2^-30 radius.
static void test_narrow_ccd_tolerance(void **state) {
    (void)state;
    const double radius = 1.0, tols[5] = {1e-2, 1e-4, 0.0, -1.0, NAN};
    rng r = {0x5eed0004u};
    for (int j = 0; j < 5; ++j) {
        double tol = tols[j] > 0x1p-30 * radius ? tols[j] : 0x1p-30 * radius;
        double max_err = 0.0;
        for (unsigned i = 0; i < 300; ++i) {
            double p[3], a[3], b[3], c[3], q[3];
            rng_point(&r, p);
            rng_point(&r, a);
            rng_point(&r, b);
            rng_point(&r, c);
            rng_point(&r, q);
            double dc = selfcol_narrow__vf(p, a, b, c, NULL);
            double dg = selfcol_narrow_ccd__vf(p, a, b, c, radius, tols[j], NULL);
            if (dc < radius - tol) {
                assert_true(fabs(dg - dc) <= (dg > 0.0 ? 0.5625 : 1.0) * tol + 1e-12);
                max_err = fmax(max_err, fabs(dg - dc) / tol);
            }
            dc = selfcol_narrow__ee(p, q, a, b, NULL);
            dg = selfcol_narrow_ccd__ee(p, q, a, b, radius, tols[j], NULL);
            if (dc < radius - tol) {
                assert_true(fabs(dg - dc) <= (dg > 0.0 ? 0.5625 : 1.0) * tol + 1e-12);
                max_err = fmax(max_err, fabs(dg - dc) / tol);
            }
        }
        print_message("tolerance %g (effective %g): max |d_ccd - d_closed| = %.3f tol\n", tols[j],
                      tol, max_err);
    }
    // A tolerance as large as the radius: every pair found is "touching".
    const double O3[3] = {0.0, 0.0, 0.0}, X3[3] = {1.0, 0.0, 0.0}, Y3[3] = {0.0, 1.0, 0.0};
    const double up[3] = {0.2, 0.2, 0.25};
    assert_true(selfcol_narrow_ccd__vf(up, O3, X3, Y3, 1.0, 1.0, NULL) == 0.0);
}

// ---------------------------------------------------------------------------
// Hand-made pairs, with their exact answers.

static const double O[3] = {0.0, 0.0, 0.0}, X[3] = {1.0, 0.0, 0.0}, Y[3] = {0.0, 1.0, 0.0};

// The radius decides: just above the distance the pair is found, just below
// it is not (and `out` is left alone); a radius <= 0 or not finite finds
// nothing.
static void test_narrow_ccd_radius(void **state) {
    (void)state;
    const double up[3] = {0.2, 0.2, 0.25}, s0[3] = {0.2, -1.0, 0.25}, s1[3] = {0.2, 1.0, 0.25};
    const double h = 0.25;
    for (int k = -1; k <= 1; k += 2) {
        double radius = h * (1.0 + k * 1e-5), tol = REL_TOL * radius;
        selfcol_narrow_result rv = SENTINEL, re = SENTINEL;
        double dv = selfcol_narrow_ccd__vf(up, O, X, Y, radius, tol, &rv);
        double de = selfcol_narrow_ccd__ee(s0, s1, O, X, radius, tol, &re);
        if (k < 0) {
            assert_true(dv == HUGE_VAL && untouched(&rv));
            assert_true(de == HUGE_VAL && untouched(&re));
        } else {
            assert_true(fabs(dv - h) <= dist_band(radius, 1.0) && rv.distance == dv);
            assert_true(fabs(de - h) <= dist_band(radius, 1.0) && re.distance == de);
            assert_true(fabs(rv.direction[2] - 1.0) <= 1e-12);
            assert_true(fabs(re.direction[2] - 1.0) <= 1e-12);
        }
    }
    // At the radius exactly: either answer, a found one within the band.
    double dv = selfcol_narrow_ccd__vf(up, O, X, Y, h, REL_TOL * h, NULL);
    assert_true(dv == HUGE_VAL || fabs(dv - h) <= dist_band(h, 1.0));
    // Random triangles with the point above an interior point at the radius
    // times 1 +- 1e-6 (outside the band: must agree), 1 +- 3e-8 and 1 (inside
    // it: counted).
    rng rg = {0x5eed0008u};
    figures f = new_figures();
    const double rel[5] = {-1e-6, -3e-8, 0.0, 3e-8, 1e-6};
    for (unsigned i = 0; i < 200; ++i) {
        double a[3], b[3], c[3], n[3], p[3];
        rng_point(&rg, a);
        rng_point(&rg, b);
        rng_point(&rg, c);
        if (!unit_normal(n, a, b, c))
            continue;
        interior_point(&rg, a, b, c, p);
        double radius = RADII[i % 3], height = radius * (1.0 + rel[i % 5]);
        for (int k = 0; k < 3; ++k)
            p[k] += height * n[k];
        run_vf(&f, p, a, b, c, radius, 0.0);
    }
    print_message("at the radius: %d queries, %d within radius - band (all found), %d beyond "
                  "radius + band (all HUGE_VAL), %d inside the band (%d found)\n",
                  f.pairs, f.within, f.beyond, f.near_radius, f.near_found);
    const double bad[4] = {0.0, -1.0, NAN, INFINITY};
    for (int i = 0; i < 4; ++i) {
        selfcol_narrow_result r = SENTINEL;
        assert_true(selfcol_narrow_ccd__vf(up, O, X, Y, bad[i], 1e-9, &r) == HUGE_VAL);
        assert_true(selfcol_narrow_ccd__ee(s0, s1, O, X, bad[i], 1e-9, &r) == HUGE_VAL);
        assert_true(selfcol_narrow_ccd__vf(O, O, X, Y, bad[i], 1e-9, &r) == HUGE_VAL);
        assert_true(untouched(&r));
    }
}

// The answer does not depend on the mesh's scale or position (libccd is given
// the query in a frame scaled to the radius, narrow_ccd.c): random pairs
// scaled by 1e-6 .. 1e6 and moved away from the origin agree with the closed
// form within the band of their scale.
static void test_narrow_ccd_scale(void **state) {
    (void)state;
    const double scales[4] = {1e-6, 1e-3, 1e3, 1e6};
    rng r = {0x5eed0007u};
    figures f = new_figures();
    for (unsigned i = 0; i < 400; ++i) {
        double s = scales[i % 4], shift = (i & 4) ? 10.0 * s : 0.0, pts[5][3];
        for (int j = 0; j < 5; ++j) {
            rng_point(&r, pts[j]);
            for (int k = 0; k < 3; ++k)
                pts[j][k] = s * pts[j][k] + shift;
        }
        run_vf(&f, pts[0], pts[1], pts[2], pts[3], 0.3 * s, 0.0);
        run_ee(&f, pts[0], pts[4], pts[1], pts[2], 0.3 * s, 0.0);
    }
    assert_true(f.max_rel <= 0.5625 && f.min_rel >= -0.5625);
    print_message("scaled 1e-6 .. 1e6: %d queries, (d_ccd - d_closed) / tol in [%.3f, %.3f]\n",
                  f.pairs, f.min_rel, f.max_rel);
}

static void expect_vf(const double p[3], const double a[3], const double b[3], const double c[3],
                      double d, const double q[3]) {
    figures f = new_figures();
    run_vf(&f, p, a, b, c, R_HAND, 0.0);
    selfcol_narrow_result r;
    double dg = selfcol_narrow_ccd__vf(p, a, b, c, R_HAND, REL_TOL * R_HAND, &r);
    assert_true(fabs(dg - d) <= dist_band(R_HAND, 1.0));
    double x[3];
    combine3(x, r.wb, a, b, c);
    assert_true(dist3(x, q) <= 1e-12);
}

static void test_narrow_ccd_vf_cases(void **state) {
    (void)state;
    const double above[3] = {0.2, 0.2, 1.0}, above_q[3] = {0.2, 0.2, 0.0};
    expect_vf(above, O, X, Y, 1.0, above_q); // above the interior
    const double corner[3] = {-1.0, -1.0, 0.5};
    expect_vf(corner, O, X, Y, 1.5, O); // nearest the corner a
    const double edge[3] = {0.5, -1.0, 1.0}, edge_q[3] = {0.5, 0.0, 0.0};
    expect_vf(edge, O, X, Y, sqrt(2.0), edge_q); // nearest the edge ab
    const double hyp[3] = {1.0, 1.0, 0.0}, hyp_q[3] = {0.5, 0.5, 0.0};
    expect_vf(hyp, O, X, Y, sqrt(0.5), hyp_q); // in the plane, beyond the edge bc
    const double near[3] = {0.25, 0.25, 1e-12}, near_q[3] = {0.25, 0.25, 0.0};
    expect_vf(near, O, X, Y, 1e-12, near_q); // 1e-12 above
    // On the triangle: distance 0, direction = the unit normal (0, 0, 1).
    const double on[3] = {0.25, 0.25, 0.0};
    selfcol_narrow_result r;
    assert_true(selfcol_narrow_ccd__vf(on, O, X, Y, R_HAND, REL_TOL * R_HAND, &r) == 0.0);
    assert_true(fabs(fabs(r.direction[2]) - 1.0) <= 1e-15);
    assert_true(selfcol_narrow_ccd__vf(O, O, X, Y, R_HAND, REL_TOL * R_HAND, &r) ==
                0.0); // on a corner
    assert_true(fabs(r.wb[0] - 1.0) <= 1e-15);
    expect_vf(on, O, X, Y, 0.0, on);
    // 1e-12 above, at a radius where the tolerance resolves it.
    double d = selfcol_narrow_ccd__vf(near, O, X, Y, 1e-11, 1e-18, &r);
    assert_true(fabs(d - 1e-12) <= 1e-18 && fabs(r.direction[2] - 1.0) <= 1e-12);
}

static void test_narrow_ccd_vf_degenerate(void **state) {
    (void)state;
    const double two[3] = {2.0, 0.0, 0.0}, p[3] = {0.5, 1.0, 0.0}, q[3] = {0.5, 0.0, 0.0};
    expect_vf(p, O, X, two, 1.0, q); // collinear corners
    expect_vf(p, O, two, X, 1.0, q);
    expect_vf(p, O, X, X, 1.0, q); // repeated corner
    const double far[3] = {3.0, 4.0, 0.0};
    expect_vf(far, O, O, O, 5.0, O); // a point triangle
    expect_vf(far, X, X, X, sqrt(20.0), X);
    expect_vf(X, X, X, X, 0.0, X); // all four points coincide
    // A point on a collinear triangle: distance 0; no normal, so the direction
    // is some unit vector (orthogonal to the triangle's line here).
    selfcol_narrow_result r;
    const double mid[3] = {1.5, 0.0, 0.0};
    assert_true(selfcol_narrow_ccd__vf(mid, O, X, two, R_HAND, REL_TOL * R_HAND, &r) == 0.0);
    assert_true(fabs(norm3(r.direction) - 1.0) <= 1e-15 && fabs(r.direction[0]) <= 1e-15);
}

static void expect_ee(const double p0[3], const double p1[3], const double q0[3],
                      const double q1[3], double d) {
    figures f = new_figures();
    const double tol = REL_TOL * R_HAND, band = dist_band(R_HAND, 3.0);
    run_ee(&f, p0, p1, q0, q1, R_HAND, 0.0);
    assert_true(fabs(selfcol_narrow_ccd__ee(p0, p1, q0, q1, R_HAND, tol, NULL) - d) <= band);
    assert_true(fabs(selfcol_narrow_ccd__ee(q0, q1, p0, p1, R_HAND, tol, NULL) - d) <= band);
    assert_true(fabs(selfcol_narrow_ccd__ee(p1, p0, q1, q0, R_HAND, tol, NULL) - d) <= band);
}

static void test_narrow_ccd_ee_cases(void **state) {
    (void)state;
    const double tol = REL_TOL * R_HAND;
    const double mx[3] = {-1.0, 0.0, 0.0}, my[3] = {0.0, -1.0, 0.0};
    const double a[3] = {0.5, 1.0, 0.0}, b[3] = {1.5, 1.0, 0.0};
    expect_ee(O, X, a, b, 1.0); // parallel, overlapping in projection
    const double c[3] = {2.0, 1.0, 0.0}, e[3] = {3.0, 1.0, 0.0};
    expect_ee(O, X, c, e, sqrt(2.0)); // parallel, endpoint to endpoint
    expect_ee(mx, X, my, Y, 0.0);     // crossing
    const double s0[3] = {0.0, -1.0, 1.0}, s1[3] = {0.0, 1.0, 1.0};
    expect_ee(mx, X, s0, s1, 1.0); // skew, interior closest points
    selfcol_narrow_result r;
    selfcol_narrow_ccd__ee(mx, X, s0, s1, R_HAND, tol, &r);
    assert_true(fabs(r.wa[0] - 0.5) <= 1e-12 && fabs(r.wb[0] - 0.5) <= 1e-12);
    assert_true(fabs(r.direction[2] + 1.0) <= 1e-12); // from the second edge to the first
    // Crossing edges: distance 0, direction = the unit common normal.
    assert_true(selfcol_narrow_ccd__ee(mx, X, my, Y, R_HAND, tol, &r) == 0.0);
    assert_true(fabs(fabs(r.direction[2]) - 1.0) <= 1e-15);
    const double t0[3] = {0.0, 0.0, 1e-12}, t1[3] = {0.0, 1.0, 1e-12};
    expect_ee(mx, X, t0, t1, 1e-12); // T-junction 1e-12 apart
}

static void test_narrow_ccd_ee_degenerate(void **state) {
    (void)state;
    const double two[3] = {2.0, 0.0, 0.0}, half[3] = {0.5, 0.0, 0.0}, three[3] = {3.0, 0.0, 0.0};
    expect_ee(O, two, half, three, 0.0); // collinear, overlapping
    expect_ee(O, X, two, three, 1.0);    // collinear, disjoint
    const double p[3] = {0.5, 2.0, 0.0};
    expect_ee(p, p, O, X, 2.0);        // zero-length first edge
    expect_ee(O, X, p, p, 2.0);        // zero-length second edge
    expect_ee(p, p, O, O, sqrt(4.25)); // two points
    expect_ee(X, X, X, X, 0.0);        // the same point twice
    // Collinear overlap: distance 0; the direction is orthogonal to the line.
    selfcol_narrow_result r;
    assert_true(selfcol_narrow_ccd__ee(O, two, half, three, R_HAND, REL_TOL * R_HAND, &r) == 0.0);
    assert_true(fabs(r.direction[0]) <= 1e-15 && fabs(norm3(r.direction) - 1.0) <= 1e-15);
}

// Runs the cross-check on a hand-made EF pair, then checks both answers.
static void expect_ef(const double p0[3], const double p1[3], const double a[3], const double b[3],
                      const double c[3], int closed, int ccd) {
    figures f = new_figures();
    int hg = run_ef(&f, p0, p1, a, b, c);
    int hc = selfcol_narrow__ef(p0, p1, a, b, c, NULL);
    if (hc != closed || hg != ccd)
        print_message("EF (%g %g %g)-(%g %g %g) vs (%g %g %g) (%g %g %g) (%g %g %g): "
                      "closed %d (expected %d), libccd %d (expected %d)\n",
                      p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], a[0], a[1], a[2], b[0], b[1], b[2],
                      c[0], c[1], c[2], hc, closed, hg, ccd);
    assert_int_equal(hc, closed);
    assert_int_equal(hg, ccd);
}

static void test_narrow_ccd_ef_cases(void **state) {
    (void)state;
    const double in0[3] = {0.2, 0.2, -1.0}, in1[3] = {0.2, 0.2, 1.0};
    expect_ef(in0, in1, O, X, Y, 1, 1); // through the interior
    selfcol_narrow_result r;
    assert_int_equal(selfcol_narrow_ccd__ef(in0, in1, O, X, Y, 1e-9, &r), 1);
    assert_true(fabs(r.wa[0] - 0.5) <= 1e-15 && fabs(r.wb[0] - 0.6) <= 1e-15);
    assert_true(fabs(r.wb[1] - 0.2) <= 1e-15 && fabs(r.wb[2] - 0.2) <= 1e-15);
    assert_true(r.direction[2] == 1.0);
    const double e0[3] = {0.5, 0.0, -1.0}, e1[3] = {0.5, 0.0, 1.0};
    expect_ef(e0, e1, O, X, Y, 1, 1); // through an edge
    const double v0[3] = {0.0, 0.0, -1.0}, v1[3] = {0.0, 0.0, 1.0};
    expect_ef(v0, v1, O, X, Y, 1, 1); // through a corner
    const double sl0[3] = {0.1, 0.1, -1.0}, sl1[3] = {0.4, 0.25, 2.0};
    expect_ef(sl0, sl1, O, X, Y, 1, 1); // slanted, through the interior
    const double m0[3] = {-1e-3, 0.5, -1.0}, m1[3] = {-1e-3, 0.5, 1.0};
    expect_ef(m0, m1, O, X, Y, 0, 0); // misses the edge by 1e-3
    const double f0[3] = {0.2, 0.2, 0.5}, f1[3] = {0.3, 0.1, 2.0};
    expect_ef(f0, f1, O, X, Y, 0, 0); // above, separate
}

// Touching configurations: the closed form never calls them crossings
// (contacts.h); libccd's GJK intersection reports most of them, not all.
// These assert what libccd 2.1 does, as documentation.
static void test_narrow_ccd_ef_touching(void **state) {
    (void)state;
    const double on[3] = {0.2, 0.2, 0.0}, up[3] = {0.2, 0.2, 1.0};
    expect_ef(on, up, O, X, Y, 0, 1); // an endpoint on the interior
    expect_ef(O, up, O, X, Y, 0, 1);  // an endpoint on a corner
    const double in0[3] = {0.1, 0.1, 0.0}, in1[3] = {0.2, 0.2, 0.0};
    expect_ef(in0, in1, O, X, Y, 0, 1); // coplanar, inside
    expect_ef(on, on, O, X, Y, 0, 1);   // zero-length, on the interior
    // Coplanar and crossing the whole triangle: the answer depends on the
    // orientation, because GJK's simplex is flat and libccd's first search
    // direction is fixed (1, 0, 0): along x it is missed, along y found.
    const double cx0[3] = {-1.0, 0.2, 0.0}, cx1[3] = {2.0, 0.2, 0.0};
    expect_ef(cx0, cx1, O, X, Y, 0, 0);
    const double cy0[3] = {0.2, -1.0, 0.0}, cy1[3] = {0.2, 2.0, 0.0};
    expect_ef(cy0, cy1, O, X, Y, 0, 1);
    // Within libccd's fixed threshold (about 1.5e-8 for unit-size shapes,
    // ignoring `tolerance`): 1e-9 away is a hit, 1e-8 and beyond are not.
    const double n0[3] = {-1e-9, 0.5, -1.0}, n1[3] = {-1e-9, 0.5, 1.0};
    expect_ef(n0, n1, O, X, Y, 0, 1);
    const double a9[3] = {0.2, 0.2, 1e-9};
    expect_ef(a9, up, O, X, Y, 0, 1);
    const double n80[3] = {-1e-8, 0.5, -1.0}, n81[3] = {-1e-8, 0.5, 1.0};
    expect_ef(n80, n81, O, X, Y, 0, 0);
    const double a7[3] = {0.2, 0.2, 1e-7};
    expect_ef(a7, up, O, X, Y, 0, 0);
}

// The threshold is absolute and grows for short edges: for a triangle of
// size 1e-4, segments missing it by 1e-3 and even 1e-1 of its size are hits.
static void test_narrow_ccd_ef_scale(void **state) {
    (void)state;
    const double s = 1e-4;
    const double a[3] = {0.0, 0.0, 0.0}, b[3] = {s, 0.0, 0.0}, c[3] = {0.0, s, 0.0};
    const double in0[3] = {0.2 * s, 0.2 * s, -s}, in1[3] = {0.2 * s, 0.2 * s, s};
    expect_ef(in0, in1, a, b, c, 1, 1);
    const double m0[3] = {-1e-3 * s, 0.2 * s, -s}, m1[3] = {-1e-3 * s, 0.2 * s, s};
    expect_ef(m0, m1, a, b, c, 0, 1);
    const double m2[3] = {-0.1 * s, 0.2 * s, -s}, m3[3] = {-0.1 * s, 0.2 * s, s};
    expect_ef(m2, m3, a, b, c, 0, 1);
    const double far0[3] = {-2.0 * s, 0.2 * s, -s}, far1[3] = {-2.0 * s, 0.2 * s, s};
    expect_ef(far0, far1, a, b, c, 0, 0);
    // Large coordinates: a relative 1e-6 miss is not touching.
    const double L = 1e4;
    const double la[3] = {0.0, 0.0, 0.0}, lb[3] = {L, 0.0, 0.0}, lc[3] = {0.0, L, 0.0};
    const double l0[3] = {0.2 * L, 0.2 * L, -L}, l1[3] = {0.2 * L, 0.2 * L, L};
    expect_ef(l0, l1, la, lb, lc, 1, 1);
    const double lm0[3] = {-1e-6 * L, 0.2 * L, -L}, lm1[3] = {-1e-6 * L, 0.2 * L, L};
    expect_ef(lm0, lm1, la, lb, lc, 0, 0);
}

// A zero-area triangle has no plane, so the closed form never reports a
// crossing; libccd reports a segment meeting it (a touching contact).
static void test_narrow_ccd_ef_degenerate(void **state) {
    (void)state;
    const double two[3] = {2.0, 0.0, 0.0};
    const double s0[3] = {0.5, -1.0, -1.0}, s1[3] = {0.5, 1.0, 1.0};
    expect_ef(s0, s1, O, X, two, 0, 1); // collinear triangle, met
    const double m1[3] = {0.5, 1.0, 0.0};
    expect_ef(s0, m1, O, X, two, 0, 0); // collinear triangle, missed
    const double v0[3] = {0.0, 0.0, -1.0}, v1[3] = {0.0, 0.0, 1.0};
    expect_ef(v0, v1, O, O, O, 0, 1); // point triangle, met
    // Everything at one point: libccd says no. Its first support point is the
    // origin itself, the next search direction is then zero, and GJK stops
    // with "no intersection".
    expect_ef(O, O, O, O, O, 0, 0);
    selfcol_narrow_result r;
    assert_int_equal(selfcol_narrow_ccd__ef(s0, s1, O, X, two, 1e-9, &r), 1);
    assert_true(fabs(r.direction[0]) <= 1e-15); // orthogonal to the triangle's line
}

// Non-finite input: no answer (HUGE_VAL, no crossing) and, above all, no
// endless loop inside libccd (its MPR loops have no iteration cap).
static void test_narrow_ccd_nonfinite(void **state) {
    (void)state;
    const double nan3[3] = {NAN, NAN, NAN}, inf3[3] = {INFINITY, -INFINITY, 0.0};
    selfcol_narrow_result r = SENTINEL;
    assert_true(selfcol_narrow_ccd__vf(nan3, O, X, Y, 1.0, 1e-7, &r) == HUGE_VAL);
    assert_true(selfcol_narrow_ccd__vf(O, inf3, X, Y, 1.0, 1e-7, &r) == HUGE_VAL);
    assert_true(selfcol_narrow_ccd__ee(nan3, X, O, Y, 1.0, 1e-7, &r) == HUGE_VAL);
    assert_true(selfcol_narrow_ccd__ee(inf3, X, O, Y, 1.0, 1e-7, &r) == HUGE_VAL);
    assert_true(untouched(&r));
    assert_int_equal(selfcol_narrow_ccd__ef(nan3, X, O, X, Y, 1e-9, &r), 0);
    assert_int_equal(selfcol_narrow_ccd__ef(inf3, X, O, X, Y, 1e-9, &r), 0);
    assert_int_equal(selfcol_narrow_ccd__ef(O, X, nan3, X, Y, 1e-9, &r), 0);
    // Finite but out of range: coordinates beyond 2^140 radii.
    const double huge[3] = {1e300, 0.0, 0.0};
    assert_true(selfcol_narrow_ccd__vf(O, huge, X, Y, 1e-300, 1e-307, &r) == HUGE_VAL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_narrow_ccd_random_vf),
        cmocka_unit_test(test_narrow_ccd_random_ee),
        cmocka_unit_test(test_narrow_ccd_random_ef),
        cmocka_unit_test(test_narrow_ccd_random_vf_needles),
        cmocka_unit_test(test_narrow_ccd_random_ee_near_parallel),
        cmocka_unit_test(test_narrow_ccd_closed_form_regressions),
        cmocka_unit_test(test_narrow_ccd_tolerance),
        cmocka_unit_test(test_narrow_ccd_radius),
        cmocka_unit_test(test_narrow_ccd_scale),
        cmocka_unit_test(test_narrow_ccd_vf_cases),
        cmocka_unit_test(test_narrow_ccd_vf_degenerate),
        cmocka_unit_test(test_narrow_ccd_ee_cases),
        cmocka_unit_test(test_narrow_ccd_ee_degenerate),
        cmocka_unit_test(test_narrow_ccd_ef_cases),
        cmocka_unit_test(test_narrow_ccd_ef_touching),
        cmocka_unit_test(test_narrow_ccd_ef_scale),
        cmocka_unit_test(test_narrow_ccd_ef_degenerate),
        cmocka_unit_test(test_narrow_ccd_nonfinite),
    };
    return cmocka_run_group_tests_name("narrow_ccd_internal", tests, NULL, NULL);
}
