// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Closed-form narrow phase: hand-computed cases, degenerate input, and
// properties on random input checked against dense sampling.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "narrow/narrow.h"

static const double EPS = 1e-12;

static void point_of_triangle(double out[3], const double *a, const double *b, const double *c,
                              const double w[3]) {
    for (int k = 0; k < 3; ++k)
        out[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
}

static void point_of_segment(double out[3], const double *a, const double *b, const double w[2]) {
    for (int k = 0; k < 3; ++k)
        out[k] = w[0] * a[k] + w[1] * b[k];
}

static double dist(const double *a, const double *b) {
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

// The result's weights are a convex combination, rebuild points at the
// reported distance, and the direction is the unit vector between them.
static void check_vf_result(const double *p, const double *a, const double *b, const double *c,
                            const selfcol_narrow_result *r) {
    double q[3];
    assert_true(r->wb[0] >= -EPS && r->wb[1] >= -EPS && r->wb[2] >= -EPS);
    assert_true(fabs(r->wb[0] + r->wb[1] + r->wb[2] - 1.0) < EPS);
    point_of_triangle(q, a, b, c, r->wb);
    assert_true(fabs(dist(p, q) - r->distance) < 1e-9);
    double len = sqrt(r->direction[0] * r->direction[0] + r->direction[1] * r->direction[1] +
                      r->direction[2] * r->direction[2]);
    assert_true(fabs(len - 1.0) < 1e-12);
    if (r->distance > 1e-9)
        for (int k = 0; k < 3; ++k)
            assert_true(fabs(q[k] + r->distance * r->direction[k] - p[k]) < 1e-9);
}

static void test_narrow_vf_hand_computed_regions(void **state) {
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
    selfcol_narrow_result r;
    // Above the interior: distance = height, weights = barycentric.
    const double p1[3] = {0.5, 0.5, 3};
    assert_true(fabs(selfcol_narrow__vf(p1, a, b, c, &r) - 3.0) < EPS);
    assert_true(fabs(r.wb[0] - 0.5) < EPS && fabs(r.wb[1] - 0.25) < EPS &&
                fabs(r.wb[2] - 0.25) < EPS);
    assert_true(fabs(r.direction[2] - 1.0) < EPS);
    check_vf_result(p1, a, b, c, &r);
    // Beyond corner b: distance to b.
    const double p2[3] = {3, -1, 0};
    assert_true(fabs(selfcol_narrow__vf(p2, a, b, c, &r) - sqrt(2.0)) < EPS);
    assert_true(fabs(r.wb[1] - 1.0) < EPS);
    check_vf_result(p2, a, b, c, &r);
    // Beyond the hypotenuse b-c, below the plane: sqrt(0.5^2 + 0.5^2 + 1).
    const double p3[3] = {1.5, 1.5, -1};
    assert_true(fabs(selfcol_narrow__vf(p3, a, b, c, &r) - sqrt(1.5)) < EPS);
    assert_true(fabs(r.wb[1] - 0.5) < EPS && fabs(r.wb[2] - 0.5) < EPS);
    check_vf_result(p3, a, b, c, &r);
    // In the plane, inside: distance 0, direction = the unit normal.
    const double p4[3] = {0.5, 0.5, 0};
    assert_true(selfcol_narrow__vf(p4, a, b, c, &r) == 0.0);
    assert_true(fabs(fabs(r.direction[2]) - 1.0) < EPS);
}

static void test_narrow_vf_degenerate_triangles(void **state) {
    (void)state;
    selfcol_narrow_result r;
    // Collinear corners: the triangle is the segment (0,0,0)-(2,0,0).
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {2, 0, 0};
    const double p[3] = {1.5, 1, 0};
    assert_true(fabs(selfcol_narrow__vf(p, a, b, c, &r) - 1.0) < EPS);
    check_vf_result(p, a, b, c, &r);
    // All corners equal: distance to the point.
    const double q[3] = {1, 2, 2};
    assert_true(fabs(selfcol_narrow__vf(q, a, a, a, &r) - 3.0) < EPS);
    check_vf_result(q, a, a, a, &r);
    // Point on the degenerate triangle: distance 0, direction still unit.
    const double s[3] = {0.5, 0, 0};
    assert_true(selfcol_narrow__vf(s, a, b, c, &r) == 0.0);
    check_vf_result(s, a, b, c, &r);
    // A sliver: nearly collinear corners; the distance stays exact enough.
    const double d[3] = {1, 1e-13, 0};
    const double t[3] = {1, 0, 1};
    assert_true(fabs(selfcol_narrow__vf(t, a, d, c, &r) - 1.0) < 1e-9);
    check_vf_result(t, a, d, c, &r);
}

static void test_narrow_ee_hand_computed_cases(void **state) {
    (void)state;
    selfcol_narrow_result r;
    // Skew perpendicular segments crossing at height 1.
    const double p0[3] = {-1, 0, 0}, p1[3] = {1, 0, 0}, q0[3] = {0, -1, 1}, q1[3] = {0, 1, 1};
    assert_true(fabs(selfcol_narrow__ee(p0, p1, q0, q1, &r) - 1.0) < EPS);
    assert_true(fabs(r.wa[1] - 0.5) < EPS && fabs(r.wb[1] - 0.5) < EPS);
    assert_true(r.wb[2] == 0.0);
    assert_true(fabs(r.direction[2] + 1.0) < EPS); // from q (above) toward p (below)
    // Parallel, overlapping: distance between the lines.
    const double s0[3] = {0, 0, 0}, s1[3] = {2, 0, 0}, t0[3] = {1, 1, 0}, t1[3] = {3, 1, 0};
    assert_true(fabs(selfcol_narrow__ee(s0, s1, t0, t1, &r) - 1.0) < EPS);
    // Collinear, disjoint: gap between the ends.
    const double u0[3] = {3, 0, 0}, u1[3] = {5, 0, 0};
    assert_true(fabs(selfcol_narrow__ee(s0, s1, u0, u1, &r) - 1.0) < EPS);
    assert_true(fabs(r.wa[1] - 1.0) < EPS && fabs(r.wb[0] - 1.0) < EPS);
    // Zero-length segment against a segment, and two points.
    const double z[3] = {1, 2, 0};
    assert_true(fabs(selfcol_narrow__ee(z, z, s0, s1, &r) - 2.0) < EPS);
    assert_true(fabs(selfcol_narrow__ee(z, z, s0, s0, &r) - sqrt(5.0)) < EPS);
    // Intersecting segments: distance 0 with a unit normal direction.
    const double x0[3] = {1, -1, 0}, x1[3] = {1, 1, 0};
    assert_true(selfcol_narrow__ee(s0, s1, x0, x1, &r) == 0.0);
    assert_true(fabs(fabs(r.direction[2]) - 1.0) < EPS);
    // Endpoint of one in the interior of the other (a T).
    const double y0[3] = {1, 0, 0}, y1[3] = {1, 1, 0};
    assert_true(selfcol_narrow__ee(s0, s1, y0, y1, &r) == 0.0);
}

static void test_narrow_ef_documented_configurations(void **state) {
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
    selfcol_narrow_result r;
    const double below[3] = {0.5, 0.5, -1}, above[3] = {0.5, 0.5, 1};
    assert_int_equal(selfcol_narrow__ef(below, above, a, b, c, &r), 1);
    assert_true(fabs(r.wa[1] - 0.5) < EPS);
    assert_true(fabs(r.wb[0] - 0.5) < EPS && fabs(r.wb[1] - 0.25) < EPS);
    assert_true(fabs(fabs(r.direction[2]) - 1.0) < EPS);
    // Through an edge's interior and through a corner: crossing (closed triangle).
    const double e0[3] = {1, 0, -1}, e1[3] = {1, 0, 1};
    assert_int_equal(selfcol_narrow__ef(e0, e1, a, b, c, &r), 1);
    const double v0[3] = {0, 0, -1}, v1[3] = {0, 0, 1};
    assert_int_equal(selfcol_narrow__ef(v0, v1, a, b, c, &r), 1);
    // Just outside the edge: no crossing, decided exactly at one ulp.
    const double o0[3] = {1, -0x1p-60, -1}, o1[3] = {1, -0x1p-60, 1};
    assert_int_equal(selfcol_narrow__ef(o0, o1, a, b, c, NULL), 0);
    // Endpoint on the plane (touching): not a crossing.
    const double on[3] = {0.5, 0.5, 0};
    assert_int_equal(selfcol_narrow__ef(on, above, a, b, c, NULL), 0);
    // Coplanar segment through the triangle: not a crossing.
    const double c0[3] = {-1, 0.5, 0}, c1[3] = {3, 0.5, 0};
    assert_int_equal(selfcol_narrow__ef(c0, c1, a, b, c, NULL), 0);
    // Both endpoints on one side, and a miss beside the triangle.
    const double high[3] = {0.5, 0.5, 2};
    assert_int_equal(selfcol_narrow__ef(above, high, a, b, c, NULL), 0);
    const double m0[3] = {3, 3, -1}, m1[3] = {3, 3, 1};
    assert_int_equal(selfcol_narrow__ef(m0, m1, a, b, c, NULL), 0);
    // A zero-area triangle is never crossed.
    const double d2[3] = {4, 0, 0};
    const double t0[3] = {1, 0, -1}, t1[3] = {1, 0, 1};
    assert_int_equal(selfcol_narrow__ef(t0, t1, a, b, d2, NULL), 0);
    // Orientation of the triangle or the segment does not matter.
    assert_int_equal(selfcol_narrow__ef(above, below, a, b, c, NULL), 1);
    assert_int_equal(selfcol_narrow__ef(below, above, a, c, b, NULL), 1);
}

static double frand(unsigned *seed) {
    *seed = *seed * 1664525u + 1013904223u;
    return (double)(*seed >> 8) / (double)(1u << 24) * 2.0 - 1.0;
}

static void random_point(double p[3], unsigned *seed) {
    for (int k = 0; k < 3; ++k)
        p[k] = frand(seed);
}

// Dense sampling gives an upper bound of the true minimum; our distance is
// realised by actual points (a lower bound holds by construction), so it must
// not exceed the sampled minimum.
static void test_narrow_vf_never_above_sampled_minimum(void **state) {
    (void)state;
    unsigned seed = 12345u;
    const int samples = 60;
    for (int it = 0; it < 300; ++it) {
        double p[3], a[3], b[3], c[3];
        random_point(p, &seed);
        random_point(a, &seed);
        random_point(b, &seed);
        random_point(c, &seed);
        if (it % 10 == 0) // degenerate: c on segment ab
            for (int k = 0; k < 3; ++k)
                c[k] = 0.5 * (a[k] + b[k]);
        selfcol_narrow_result r;
        double d = selfcol_narrow__vf(p, a, b, c, &r);
        check_vf_result(p, a, b, c, &r);
        double best = HUGE_VAL;
        for (int i = 0; i <= samples; ++i)
            for (int j = 0; i + j <= samples; ++j) {
                double w[3] = {(double)i / samples, (double)j / samples, 0};
                w[2] = 1.0 - w[0] - w[1];
                double q[3];
                point_of_triangle(q, a, b, c, w);
                double e = dist(p, q);
                best = e < best ? e : best;
            }
        assert_true(d <= best + 1e-12);
        // Invariance under translation and corner permutation.
        double o[3] = {10.0, -3.0, 0.5}, pt[3], at[3], bt[3], ct[3];
        for (int k = 0; k < 3; ++k) {
            pt[k] = p[k] + o[k];
            at[k] = a[k] + o[k];
            bt[k] = b[k] + o[k];
            ct[k] = c[k] + o[k];
        }
        assert_true(fabs(selfcol_narrow__vf(pt, at, bt, ct, NULL) - d) < 1e-9);
        assert_true(fabs(selfcol_narrow__vf(p, c, a, b, NULL) - d) < 1e-12);
    }
}

static void test_narrow_ee_symmetric_and_never_above_sampled_minimum(void **state) {
    (void)state;
    unsigned seed = 777u;
    const int samples = 200;
    for (int it = 0; it < 300; ++it) {
        double p0[3], p1[3], q0[3], q1[3];
        random_point(p0, &seed);
        random_point(p1, &seed);
        random_point(q0, &seed);
        random_point(q1, &seed);
        if (it % 7 == 0) // parallel
            for (int k = 0; k < 3; ++k)
                q1[k] = q0[k] + 0.5 * (p1[k] - p0[k]);
        if (it % 11 == 0) // zero length
            for (int k = 0; k < 3; ++k)
                p1[k] = p0[k];
        selfcol_narrow_result r;
        double d = selfcol_narrow__ee(p0, p1, q0, q1, &r);
        double pa[3], qb[3];
        point_of_segment(pa, p0, p1, r.wa);
        point_of_segment(qb, q0, q1, r.wb);
        assert_true(fabs(dist(pa, qb) - d) < 1e-12);
        assert_true(r.wa[0] >= 0 && r.wa[1] >= 0 && r.wb[0] >= 0 && r.wb[1] >= 0);
        double best = HUGE_VAL;
        for (int i = 0; i <= samples; ++i) {
            double s = (double)i / samples, x[3];
            for (int k = 0; k < 3; ++k)
                x[k] = p0[k] + s * (p1[k] - p0[k]);
            // Exact closest point of q-segment to x by sampling too.
            for (int j = 0; j <= samples; ++j) {
                double t = (double)j / samples, y[3];
                for (int k = 0; k < 3; ++k)
                    y[k] = q0[k] + t * (q1[k] - q0[k]);
                double e = dist(x, y);
                best = e < best ? e : best;
            }
        }
        assert_true(d <= best + 1e-12);
        assert_true(fabs(selfcol_narrow__ee(q0, q1, p0, p1, NULL) - d) < 1e-12);
        assert_true(fabs(selfcol_narrow__ee(p1, p0, q1, q0, NULL) - d) < 1e-12);
    }
}

// Inputs that broke earlier versions (found by the libccd cross-check against
// a quad-precision reference): a needle triangle whose short edge is opposite
// the first corner, and nearly parallel, nearly touching segments.
static void test_narrow_closed_form_regressions(void **state) {
    (void)state;
    const double p[3] = {0x1.4d1824bab9d83p-1, -0x1.aa8fdaaa650d3p-1, -0x1.50038b5d3a1c4p-2};
    const double a[3] = {-0x1.680a75bf24d26p-1, 0x1.de7c033a38674p-1, 0x1.1bcdc4d18e28p-1};
    const double b[3] = {0x1.8331e6d5760cdp-1, -0x1.f133dffadf822p-1, -0x1.968b18b624d2dp-2};
    const double c[3] = {0x1.8331e5ff07b26p-1, -0x1.f133e0e3ae11p-1, -0x1.968b178ad16bp-2};
    double d = selfcol_narrow__vf(p, a, b, c, NULL);
    print_message("needle VF: %.6g (reference 3.4314e-11)\n", d);
    assert_true(fabs(d - 3.4314e-11) < 1e-14);
    assert_true(fabs(selfcol_narrow__vf(p, b, c, a, NULL) - d) < 1e-14);

    const double p0[3] = {-0x1.cfb2acc6bf422p-1, -0x1.8374bfa13c404p-1, 0x1.1dd2bcf8920dcp-1};
    const double p1[3] = {0x1.bae94958f20dp-1, 0x1.af4fca67c986p-1, -0x1.a045c2ff868ep-1};
    const double q0[3] = {-0x1.29909cf83a41bp-1, -0x1.dad551ac1daf4p-2, 0x1.3a55994c03608p-2};
    const double q1[3] = {0x1.9fbd7963bebdep-1, 0x1.96c50d82de9d4p-1, -0x1.8b3b3b2eae0a1p-1};
    d = selfcol_narrow__ee(p0, p1, q0, q1, NULL);
    print_message("near-parallel EE: %.6g (reference 1.6137e-11)\n", d);
    assert_true(fabs(d - 1.6137e-11) < 1e-13);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_narrow_vf_hand_computed_regions),
        cmocka_unit_test(test_narrow_vf_degenerate_triangles),
        cmocka_unit_test(test_narrow_ee_hand_computed_cases),
        cmocka_unit_test(test_narrow_ef_documented_configurations),
        cmocka_unit_test(test_narrow_vf_never_above_sampled_minimum),
        cmocka_unit_test(test_narrow_ee_symmetric_and_never_above_sampled_minimum),
        cmocka_unit_test(test_narrow_closed_form_regressions),
    };
    return cmocka_run_group_tests_name("narrow_internal", tests, NULL, NULL);
}
