// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The continuous narrow phase (narrow_sweep.c): hand-made motions with known
// answers, random motions built to touch at a known time in exact
// arithmetic, random motions against a sampled closed-form distance, and the
// sample queries of the CCD benchmark of Wang et al. 2021 (their ground truth,
// computed with exact rational arithmetic) when ../shared/data holds them:
// zero false negatives is asserted for every family, the false positives and
// the mean time per query are printed (never asserted: the time depends on the
// machine). The whole file runs in about 0.5 s in a Release build, 7 s under
// ASan+UBSan (Debug) and about 20 s under valgrind, which therefore also runs
// the full data pass (no valgrind-only subset).
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "narrow/narrow.h"
#include "narrow/narrow_sweep.h"

// ---------------------------------------------------------------- hand-made

// A vertex falling straight through the middle of a triangle that rises:
// p_z = 1 - 2t, triangle z = 0.6 t, crossing at t* = 1 / 2.6.
static void test_vertex_through_triangle_middle(void **state) {
    (void)state;
    const double a0[3] = {0, 0, 0}, b0[3] = {1, 0, 0}, c0[3] = {0, 1, 0};
    const double a1[3] = {0, 0, 0.6}, b1[3] = {1, 0, 0.6}, c1[3] = {0, 1, 0.6};
    const double p0[3] = {0.25, 0.25, 1}, p1[3] = {0.25, 0.25, -1};
    const double crossing = 1.0 / 2.6;
    double toi = -1.0;
    selfcol_narrow_sweep_info info;
    assert_int_equal(
        selfcol_narrow_sweep__vf_info(p0, a0, b0, c0, p1, a1, b1, c1, 0.0, &toi, &info), 1);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_ACCEPTED);
    assert_true(toi <= crossing);
    assert_true(toi >= crossing - 1e-5);
    // The same with the triangle still: t* = 1/2.
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a0, b0, c0, p1, a0, b0, c0, 0.0, &toi), 1);
    assert_true(toi <= 0.5 && toi >= 0.5 - 1e-5);
    // Falling beside the triangle (x + y > 1): no contact.
    const double q0[3] = {0.75, 0.75, 1}, q1[3] = {0.75, 0.75, -1};
    assert_int_equal(selfcol_narrow_sweep__vf(q0, a0, b0, c0, q1, a0, b0, c0, 0.0, &toi), 0);
}

// A vertex moving parallel to the triangle's plane, far above it.
static void test_vertex_parallel_far_away(void **state) {
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    const double p0[3] = {-3, 0.2, 10}, p1[3] = {3, 0.2, 10};
    double toi = -1.0;
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, c, p1, a, b, c, 0.0, &toi), 0);
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, c, p1, a, b, c, 9.9, &toi), 0);
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, c, p1, a, b, c, 10.1, &toi), 1);
    assert_true(toi >= 0.0 && toi <= 0.5); // above the triangle from t ~ 0.5 on
}

// The separation filter's in-plane directions: a vertex sliding beside a
// triangle in the triangle's own plane (as the vertices of one smooth sheet
// do, a ring or two apart), 0.21 beyond its long edge, in a rotated frame.
// Neither an axis nor the plane's normal separates them (the filter had only
// those until the in-plane normals were added, and answered 0 here); the
// long edge's in-plane normal does, at both ends of the step.
static void test_separation_in_the_plane(void **state) {
    (void)state;
    // A rotated orthonormal frame e[0], e[1], e[2].
    const double e[3][3] = {{0.2672612419124244, 0.5345224838248488, 0.8017837257372732},
                            {0.8728715609439696, 0.2182178902359924, -0.4364357804719848},
                            {-0.4082482904638631, 0.8164965809277261, -0.4082482904638631}};
    // p0, p1, a, b, c; and q, a point beyond the long edge for an edge (p0, q)
    const double local[6][2] = {{0.7, 0.6}, {0.6, 0.7}, {0, 0}, {1, 0}, {0, 1}, {0.9, 0.9}};
    double x[6][3];
    for (int k = 0; k < 6; ++k)
        for (int i = 0; i < 3; ++i)
            x[k][i] = 2.0 + local[k][0] * e[0][i] + local[k][1] * e[1][i];
    const double *start[4] = {x[0], x[2], x[3], x[4]}, *end[4] = {x[1], x[2], x[3], x[4]};
    // Apart by more than 0.1 over the whole step, not by more than 0.25.
    assert_int_equal(selfcol_narrow_sweep__separated(start, end, 0, 0.1), 1);
    assert_int_equal(selfcol_narrow_sweep__separated(start, end, 0, 0.25), 0);
    // No single axis or normal: the hint reports which direction did it.
    unsigned hint = 0;
    assert_int_equal(selfcol_narrow_sweep__separated_from(start, end, 0, 0.1, &hint), 1);
    assert_true(hint == 5 || hint == 6);
    // The root finder agrees, and so does the distance along the way.
    double toi = -1.0;
    assert_int_equal(
        selfcol_narrow_sweep__vf(x[0], x[2], x[3], x[4], x[1], x[2], x[3], x[4], 0.1, &toi), 0);
    for (int s = 0; s <= 16; ++s) {
        const double t = s / 16.0;
        double p[3];
        for (int i = 0; i < 3; ++i)
            p[i] = (1 - t) * x[0][i] + t * x[1][i];
        assert_true(selfcol_narrow__vf(p, x[2], x[3], x[4], NULL) > 0.2);
    }
    // The same for an edge beside another edge of one plane (not parallel:
    // parallel edges give no normal), still.
    const double *ee[4] = {x[0], x[5], x[3], x[4]};
    assert_int_equal(selfcol_narrow_sweep__separated(ee, ee, 1, 0.1), 1);
    hint = 0;
    assert_int_equal(selfcol_narrow_sweep__separated_from(ee, ee, 1, 0.1, &hint), 1);
    assert_true(hint == 5 || hint == 6);
}

// The coplanarity filter (delta = 0): a vertex that stays on one side of
// the triangle's plane is answered without a root search, whatever its
// distance; one that goes through the plane beside the triangle, or touches
// it, is not (the pieces or the search decide); with delta > 0 the filter is off.
static void test_never_coplanar_filter(void **state) {
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    const double p0[3] = {0.2, 0.2, 1e-3}, p1[3] = {0.3, 0.2, 1e-9}; // down to 1e-9 above
    double toi = -1.0;
    selfcol_narrow_sweep_info info;
    assert_int_equal(selfcol_narrow_sweep__vf_info(p0, a, b, c, p1, a, b, c, 0.0, &toi, &info), 0);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_NEVER_COPLANAR);
    assert_true(info.checks == 0);
    // Through the plane beside the triangle: no contact, shown apart before
    // any box (the separation filter piece by piece: the z axis on the
    // pieces above or below the plane, the vector between the closest
    // points on the piece where the vertex passes it).
    const double q0[3] = {0.75, 0.75, 1}, q1[3] = {0.75, 0.75, -1};
    assert_int_equal(selfcol_narrow_sweep__vf_info(q0, a, b, c, q1, a, b, c, 0.0, &toi, &info), 0);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_SEPARATED);
    assert_int_equal(info.checks, 0);
    // With delta > 0 the pieces are not tried: the search proves it, box by box.
    assert_int_equal(selfcol_narrow_sweep__vf_info(q0, a, b, c, q1, a, b, c, 0.1, &toi, &info), 0);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_SEPARATED);
    assert_true(info.checks > 0);
    // Onto the triangle at the step's end: coplanar at t = 1, a contact.
    const double r1[3] = {0.3, 0.2, 0.0};
    assert_int_equal(selfcol_narrow_sweep__vf_info(p0, a, b, c, r1, a, b, c, 0.0, &toi, &info), 1);
    assert_true(toi <= 1.0 && toi >= 1.0 - 1e-5);
    // delta > 0: the filter does not apply (1e-9 above is within 1e-8).
    assert_int_equal(selfcol_narrow_sweep__vf_info(p0, a, b, c, p1, a, b, c, 1e-8, &toi, &info), 1);
    // Two edges in parallel planes 1e-12 apart, sliding across each other.
    const double e0[3] = {-1, 0, 0}, e1[3] = {1, 0, 0};
    const double g0[3] = {3, -1, 1e-12}, g1[3] = {3, 1, 1e-12};
    const double h0[3] = {-3, -1, 1e-12}, h1[3] = {-3, 1, 1e-12};
    assert_int_equal(
        selfcol_narrow_sweep__ee_info(e0, e1, g0, g1, e0, e1, h0, h1, 0.0, &toi, &info), 0);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_NEVER_COPLANAR);
}

// Edge a (along x) falls through edge b (along y): they cross at t* = 1/2.
static void test_edges_crossing(void **state) {
    (void)state;
    const double a0[3] = {-1, 0, 1}, b0[3] = {1, 0, 1}, a1[3] = {-1, 0, -1}, b1[3] = {1, 0, -1};
    const double c[3] = {0, -1, 0}, d[3] = {0, 1, 0};
    double toi = -1.0;
    assert_int_equal(selfcol_narrow_sweep__ee(a0, b0, c, d, a1, b1, c, d, 0.0, &toi), 1);
    assert_true(toi <= 0.5 && toi >= 0.5 - 1e-5);
    // Edge b moved to x = 5: edge a passes beside it.
    const double c5[3] = {5, -1, 0}, d5[3] = {5, 1, 0};
    assert_int_equal(selfcol_narrow_sweep__ee(a0, b0, c5, d5, a1, b1, c5, d5, 0.0, &toi), 0);
}

// A near miss by 1e-3: delta = 0 misses it, delta = 2e-3 catches it.
static void test_delta_catches_near_miss(void **state) {
    (void)state;
    double toi = -1.0;
    // Vertex sliding over the triangle at height 1e-3: x = -1 + 4t, y = 0.2,
    // above the triangle for x in [0, 0.8], t in [0.25, 0.45].
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    const double p0[3] = {-1, 0.2, 1e-3}, p1[3] = {3, 0.2, 1e-3};
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, c, p1, a, b, c, 0.0, &toi), 0);
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, c, p1, a, b, c, 2e-3, &toi), 1);
    assert_true(toi <= 0.25 + 1e-12 && toi >= 0.0);
    // Edge sliding over another edge at height 1e-3 (crossing it at t = 1/2).
    const double e0[3] = {-2, -1, 1e-3}, f0[3] = {-2, 1, 1e-3};
    const double e1[3] = {2, -1, 1e-3}, f1[3] = {2, 1, 1e-3};
    const double g[3] = {-1, 0, 0}, h[3] = {1, 0, 0};
    assert_int_equal(selfcol_narrow_sweep__ee(e0, f0, g, h, e1, f1, g, h, 0.0, &toi), 0);
    assert_int_equal(selfcol_narrow_sweep__ee(e0, f0, g, h, e1, f1, g, h, 2e-3, &toi), 1);
    assert_true(toi <= 0.25 + 1e-12); // within x in [-1, 1] from t = 1/4
}

// Degenerate motions: touching all along, zero-length and collinear edges, a
// collapsed triangle, non-finite input.
static void test_degenerate_motions(void **state) {
    (void)state;
    double toi = -1.0;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    const double on[3] = {0.2, 0.2, 0};
    // A vertex resting on a still triangle: contact at t = 0.
    assert_int_equal(selfcol_narrow_sweep__vf(on, a, b, c, on, a, b, c, 0.0, &toi), 1);
    assert_true(toi == 0.0);
    // Collapsed triangle (a segment) swept through by a vertex.
    const double m[3] = {0.5, 0, 0};
    const double p0[3] = {0.25, -1, 0}, p1[3] = {0.25, 1, 0};
    assert_int_equal(selfcol_narrow_sweep__vf(p0, a, b, m, p1, a, b, m, 0.0, &toi), 1);
    assert_true(toi <= 0.5 && toi >= 0.5 - 1e-5);
    // Collinear overlapping edges sliding along each other.
    const double s0[3] = {2, 0, 0}, s1[3] = {3, 0, 0}, s2[3] = {0, 0, 0}, s3[3] = {1, 0, 0};
    assert_int_equal(selfcol_narrow_sweep__ee(s0, s1, a, b, s2, s3, a, b, 0.0, &toi), 1);
    assert_true(toi <= 0.5 && toi >= 0.5 - 1e-5); // first touch at t = 1/2
    // Parallel edges one apart, never closer.
    const double u0[3] = {0, 1, 0}, u1[3] = {1, 1, 0};
    assert_int_equal(selfcol_narrow_sweep__ee(u0, u1, a, b, u0, u1, a, b, 0.0, &toi), 0);
    // Zero-length edge (a point) crossing an edge.
    const double z0[3] = {0.5, -1, 0}, z1[3] = {0.5, 1, 0};
    assert_int_equal(selfcol_narrow_sweep__ee(z0, z0, a, b, z1, z1, a, b, 0.0, &toi), 1);
    assert_true(toi <= 0.5 && toi >= 0.5 - 1e-5);
    // Non-finite input: conservatively 1 at t = 0.
    const double bad[3] = {NAN, 0, 0};
    selfcol_narrow_sweep_info info;
    assert_int_equal(selfcol_narrow_sweep__vf_info(bad, a, b, c, p1, a, b, c, 0.0, &toi, &info), 1);
    assert_int_equal(info.outcome, SELFCOL_NARROW_SWEEP_INVALID);
    assert_true(toi == 0.0);
}

// ----------------------------------------------------- random vs sampling

static uint64_t rng_state = 0x9E3779B97F4A7C15u;

static double uniform(double lo, double hi) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return lo + (hi - lo) * (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static void lerp(double out[3], const double x0[3], const double x1[3], double t) {
    for (int i = 0; i < 3; ++i)
        out[i] = x0[i] + t * (x1[i] - x0[i]);
}

// ----------------------------------------------- exact contacts by design

// An integer in [-n, n], times 4 (so that halves and quarters stay exact).
static double random_multiple_of_4(int n) {
    return 4.0 * floor(uniform(-(double)n, (double)n + 1.0));
}

// Random motions that touch exactly at t* = 11/32, built in integers so
// that every coordinate, every position at t* and the contact point are
// exact doubles (t* inside the early boxes, not on their ends): VF with the vertex at barycentric
// (1/2, 1/4, 1/4) of the triangle, EE with both edges' midpoints at one point. Each point moves by
// a random multiple of 32 through its position at t*, often much larger
// than the triangle (so that the four points are coplanar at other times
// too, with the primitives apart, where the search drops boxes by the
// coplanarity test), then the whole pair is scaled by a power of two and
// offset by a large integer (exact). Every pair must be reported, with toi
// <= t*: the search drops boxes whose times keep the points away from
// coplanar (narrow_sweep.c, "Coplanar moments box by box"), which must
// never drop the contact's.
static void test_exact_contacts_are_found(void **state) {
    (void)state;
    rng_state = 0x2545F4914F6CDD1Du;
    const double scales[3] = {1.0, 0x1p-20, 0x1p12};
    const double offsets[3] = {0.0, 1048576.0, -3.0 * 65536.0};
    long reported = 0, total = 0;
    for (int rep = 0; rep < 1500; ++rep) {
        const int edge_edge = rep % 2;
        const double scale = scales[rep % 3], offset = offsets[(rep / 3) % 3];
        const double contact = 11.0 / 32.0;
        double mid[4][3]; // positions at t = contact
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i)
                mid[k + 1][i] = random_multiple_of_4(64);
        for (int i = 0; i < 3; ++i)
            mid[0][i] = edge_edge ? mid[1][i] + mid[2][i] - mid[3][i] // d: midpoints meet
                                  : 0.5 * mid[1][i] + 0.25 * mid[2][i] + 0.25 * mid[3][i];
        double start[4][3], end[4][3];
        const int reach = rep % 4 == 0 ? 1024 : 64; // some much faster than the pair's size
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < 3; ++i) {
                const double move = 8.0 * random_multiple_of_4(reach); // 32 n
                start[k][i] = (mid[k][i] - contact * move) * scale + offset;
                end[k][i] = (mid[k][i] + (1.0 - contact) * move) * scale + offset;
            }
        double toi = -1.0;
        int answer;
        if (edge_edge) // a, b, c, d: mid[1], mid[2] against mid[3], mid[0]
            answer = selfcol_narrow_sweep__ee(start[1], start[2], start[3], start[0], end[1],
                                              end[2], end[3], end[0], 0.0, &toi);
        else // p = mid[0] against the triangle mid[1..3]
            answer = selfcol_narrow_sweep__vf(start[0], start[1], start[2], start[3], end[0],
                                              end[1], end[2], end[3], 0.0, &toi);
        ++total;
        if (!answer || !(toi <= contact))
            fail_msg("%s pair %d (scale %g, offset %g): answer %d, toi %.17g; its contact is at "
                     "t = 11/32",
                     edge_edge ? "EE" : "VF", rep, scale, offset, answer, toi);
        reported += answer;
    }
    print_message("exact contacts: %ld of %ld reported, toi <= 11/32\n", reported, total);
}

// Random pairs moving within [-1, 1]^3, some sharing a scale s far from 1
// and an offset; the closed-form distance sampled at 65 times is the
// reference: a sampled time closer than delta - margin must be reported, with
// toi no later; an ACCEPTED answer must be within the header's bound at toi.
// Twice: with the default tolerance, and with a coarse one (1e-3, the _before
// functions' argument), which must keep both guarantees with its own bound
// and evaluate fewer boxes.
static void random_motions(double tolerance, long *checks) {
    const int samples = 64;
    int reported = 0, sampled_close = 0, separated = 0;
    *checks = 0;
    rng_state = 0x9E3779B97F4A7C15u; // the same pairs for both tolerances
    for (int trial = 0; trial < 2000; ++trial) {
        const int vf = trial % 2;
        const double scale = trial % 3 == 0 ? 1e-3 : (trial % 3 == 1 ? 1.0 : 1e3);
        const double offset = trial % 5 == 0 ? 10.0 * scale : 0.0;
        double x[8][3];
        for (int k = 0; k < 8; ++k)
            for (int i = 0; i < 3; ++i)
                x[k][i] = offset + scale * uniform(-1.0, 1.0);
        const double delta = trial % 4 == 0 ? 0.0 : scale * uniform(0.0, 0.3);
        double toi = -1.0;
        selfcol_narrow_sweep_info info;
        const double *const start[4] = {x[0], x[1], x[2], x[3]};
        const double *const end[4] = {x[4], x[5], x[6], x[7]};
        int hit;
        if (tolerance == SELFCOL_NARROW_SWEEP_TOLERANCE)
            hit = vf ? selfcol_narrow_sweep__vf_info(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7],
                                                     delta, &toi, &info)
                     : selfcol_narrow_sweep__ee_info(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7],
                                                     delta, &toi, &info);
        else
            hit =
                vf ? selfcol_narrow_sweep__vf_before(start, end, delta, 1.0, tolerance, &toi, &info)
                   : selfcol_narrow_sweep__ee_before(start, end, delta, 1.0, tolerance, &toi,
                                                     &info);
        *checks += info.checks;
        reported += hit;
        assert_true(!hit || (toi >= 0.0 && toi <= 1.0));
        const int apart = selfcol_narrow_sweep__separated(start, end, !vf, delta);
        separated += apart;
        const double margin = 1e-9 * scale;
        for (int s = 0; s <= samples; ++s) {
            const double t = (double)s / samples;
            double y[4][3];
            for (int k = 0; k < 4; ++k)
                lerp(y[k], x[k], x[k + 4], t);
            const double dist = vf ? selfcol_narrow__vf(y[0], y[1], y[2], y[3], NULL)
                                   : selfcol_narrow__ee(y[0], y[1], y[2], y[3], NULL);
            if (dist <= delta - margin) {
                ++sampled_close;
                if (!hit || toi > t)
                    fail_msg("trial %d (%s): distance %.17g <= delta %.17g at t = %g, "
                             "answer %d, toi %.17g",
                             trial, vf ? "VF" : "EE", dist, delta, t, hit, toi);
                if (apart)
                    fail_msg("trial %d (%s): shown apart, but the distance is %.17g <= delta "
                             "%.17g at t = %g",
                             trial, vf ? "VF" : "EE", dist, delta, t);
                break;
            }
        }
        if (hit && info.outcome == SELFCOL_NARROW_SWEEP_ACCEPTED) {
            // Bound of narrow_sweep.h at toi (its eps terms are below
            // 1e-12 scale here).
            double extent = 0.0;
            for (int i = 0; i < 3; ++i) {
                double l = HUGE_VAL, h = -HUGE_VAL;
                for (int k = 0; k < 8; ++k) {
                    l = x[k][i] < l ? x[k][i] : l;
                    h = x[k][i] > h ? x[k][i] : h;
                }
                extent = h - l > extent ? h - l : extent;
            }
            const double bound = sqrt(3.0) * (delta + tolerance * extent) + 1e-12 * scale;
            double y[4][3];
            for (int k = 0; k < 4; ++k)
                lerp(y[k], x[k], x[k + 4], toi);
            const double dist = vf ? selfcol_narrow__vf(y[0], y[1], y[2], y[3], NULL)
                                   : selfcol_narrow__ee(y[0], y[1], y[2], y[3], NULL);
            if (dist > bound)
                fail_msg("trial %d (%s): accepted at toi %.17g where the distance is %.17g > "
                         "bound %.17g",
                         trial, vf ? "VF" : "EE", toi, dist, bound);
        }
    }
    print_message("random motions, tolerance %g: 2000 pairs, %d reported, %d with a sampled time "
                  "within delta, %d shown apart by the separation filter, %ld boxes\n",
                  tolerance, reported, sampled_close, separated, *checks);
    assert_true(sampled_close > 100); // the families do exercise contacts
    assert_true(separated > 100);     // and the filter does say something
}

static void test_random_motions_against_sampled_distance(void **state) {
    (void)state;
    long fine, coarse;
    random_motions(SELFCOL_NARROW_SWEEP_TOLERANCE, &fine);
    random_motions(1e-3, &coarse);
    assert_true(coarse < fine);
}

// ------------------------------------------------------------- may_touch

static int may_touch(const double *p0, const double *a0, const double *b0, const double *c0,
                     const double *p1, const double *a1, const double *b1, const double *c1,
                     int edge_edge, int *outcome) {
    const double *const start[4] = {p0, a0, b0, c0};
    const double *const end[4] = {p1, a1, b1, c1};
    selfcol_narrow_sweep_info info = {-1, 0, 0};
    const int answer = selfcol_narrow_sweep__may_touch(start, end, edge_edge, &info);
    *outcome = info.outcome;
    return answer;
}

// The yes/no question of the contact store: crossings answered by a witness,
// sign changes without contact (a vertex passing beside a triangle, edges
// turning past each other) proven apart, degenerate and non-finite input
// answered like the search.
static void test_may_touch_hand_made(void **state) {
    (void)state;
    int outcome;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    // Straight through the middle: a witness.
    const double p0[3] = {0.25, 0.25, 1}, p1[3] = {0.25, 0.25, -1};
    assert_int_equal(may_touch(p0, a, b, c, p1, a, b, c, 0, &outcome), 1);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_WITNESS);
    // Through the plane beside the triangle (x + y = 1.5): the side of the
    // plane changes, the vertex never touches.
    const double q0[3] = {0.75, 0.75, 1}, q1[3] = {0.75, 0.75, -1};
    assert_int_equal(may_touch(q0, a, b, c, q1, a, b, c, 0, &outcome), 0);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_SEPARATED);
    // A vertex crossing the plane beside the corner b, from beyond it in x to
    // beyond it in y (the gap to the triangle turns by 90 degrees).
    const double r0[3] = {1.2, 0.0, 0.5}, r1[3] = {1.0, 0.2, -0.5};
    assert_int_equal(may_touch(r0, a, b, c, r1, a, b, c, 0, &outcome), 0);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_SEPARATED);
    // Edge a falls through edge b (x = 0): a witness; moved to x = 5: apart.
    const double e0[3] = {-1, 0, 1}, f0[3] = {1, 0, 1}, e1[3] = {-1, 0, -1}, f1[3] = {1, 0, -1};
    const double g[3] = {0, -1, 0}, h[3] = {0, 1, 0}, g5[3] = {5, -1, 0}, h5[3] = {5, 1, 0};
    assert_int_equal(may_touch(e0, f0, g, h, e1, f1, g, h, 1, &outcome), 1);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_WITNESS);
    assert_int_equal(may_touch(e0, f0, g5, h5, e1, f1, g5, h5, 1, &outcome), 0);
    // An edge turning past a still edge 0.1 above it, parallel at t = 1/2:
    // the reference normal (their cross product) flips, the gap does not.
    const double k0[3] = {-1, -0.5, 0.1}, l0[3] = {1, 0.5, 0.1};
    const double k1[3] = {-1, 0.5, 0.1}, l1[3] = {1, -0.5, 0.1};
    const double m0[3] = {-1, 0, 0}, n0[3] = {1, 0, 0};
    assert_int_equal(may_touch(k0, l0, m0, n0, k1, l1, m0, n0, 1, &outcome), 0);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_SEPARATED);
    // Lowered onto the edge (z = 0): it touches all along the turn.
    const double k0z[3] = {-1, -0.5, 0}, l0z[3] = {1, 0.5, 0};
    const double k1z[3] = {-1, 0.5, 0}, l1z[3] = {1, -0.5, 0};
    assert_int_equal(may_touch(k0z, l0z, m0, n0, k1z, l1z, m0, n0, 1, &outcome), 1);
    // Collinear overlapping edges sliding along each other (no coplanarity
    // sign change to bisect: the search answers).
    const double s0[3] = {2, 0, 0}, s1[3] = {3, 0, 0}, s2[3] = {0, 0, 0}, s3[3] = {1, 0, 0};
    assert_int_equal(may_touch(s0, s1, a, b, s2, s3, a, b, 1, &outcome), 1);
    // A vertex resting on a still triangle.
    const double on[3] = {0.2, 0.2, 0};
    assert_int_equal(may_touch(on, a, b, c, on, a, b, c, 0, &outcome), 1);
    // Non-finite input: conservatively 1.
    const double bad[3] = {NAN, 0, 0};
    assert_int_equal(may_touch(bad, a, b, c, p1, a, b, c, 0, &outcome), 1);
    assert_int_equal(outcome, SELFCOL_NARROW_SWEEP_INVALID);
}

// Random pairs, half of them made to cross (the second primitive's end
// position moved so that a point of the first passes through it at a random
// time), against the search on the same input: the same answer for every
// pair of this seed (they can differ only for a pair that comes within the
// tolerance without touching, which random data of this size does not
// produce), and every stage exercised.
static void test_may_touch_against_search(void **state) {
    (void)state;
    int stage[5] = {0, 0, 0, 0, 0}, touching = 0;
    const int trials = 4000;
    for (int trial = 0; trial < trials; ++trial) {
        const int vf = trial % 2, crossing = (trial / 2) % 2;
        const double scale = trial % 3 == 0 ? 1e-3 : (trial % 3 == 1 ? 1.0 : 1e3);
        double x[8][3];
        for (int k = 0; k < 8; ++k)
            for (int i = 0; i < 3; ++i)
                x[k][i] = scale * uniform(-1.0, 1.0);
        if (crossing) {
            // At time t*, move everything so that the first primitive's point
            // at weights w meets the second's at weights w' (shift the second
            // primitive's end positions by the gap / t*).
            const double t_star = uniform(0.1, 0.9);
            const double wa = uniform(0.05, 0.95), wb = uniform(0.05, 0.45),
                         wc = uniform(0.05, 0.45);
            double y[4][3], pa[3], pb[3];
            for (int k = 0; k < 4; ++k)
                lerp(y[k], x[k], x[k + 4], t_star);
            for (int i = 0; i < 3; ++i) {
                if (vf) {
                    pa[i] = y[0][i];
                    pb[i] = (1 - wb - wc) * y[1][i] + wb * y[2][i] + wc * y[3][i];
                } else {
                    pa[i] = (1 - wa) * y[0][i] + wa * y[1][i];
                    pb[i] = (1 - wb) * y[2][i] + wb * y[3][i];
                }
            }
            for (int k = vf ? 1 : 2; k < 4; ++k)
                for (int i = 0; i < 3; ++i)
                    x[k + 4][i] += (pa[i] - pb[i]) / t_star;
        }
        const double *const start[4] = {x[0], x[1], x[2], x[3]};
        const double *const end[4] = {x[4], x[5], x[6], x[7]};
        selfcol_narrow_sweep_info info;
        const int answer = selfcol_narrow_sweep__may_touch(start, end, !vf, &info);
        double toi;
        const int reference =
            vf ? selfcol_narrow_sweep__vf_before(start, end, 0.0, 1.0,
                                                 SELFCOL_NARROW_SWEEP_TOLERANCE, &toi, NULL)
               : selfcol_narrow_sweep__ee_before(start, end, 0.0, 1.0,
                                                 SELFCOL_NARROW_SWEEP_TOLERANCE, &toi, NULL);
        if (answer != reference)
            fail_msg("trial %d (%s, %s): may_touch %d (outcome %d), the search %d", trial,
                     vf ? "VF" : "EE", crossing ? "crossing" : "random", answer, info.outcome,
                     reference);
        if (crossing && !answer)
            fail_msg("trial %d (%s): made to cross, answered 0", trial, vf ? "VF" : "EE");
        touching += answer;
        stage[info.outcome]++;
    }
    print_message(
        "may_touch: %d pairs, %d may touch; separated %d, witness %d, search accepted %d\n", trials,
        touching, stage[SELFCOL_NARROW_SWEEP_SEPARATED], stage[SELFCOL_NARROW_SWEEP_WITNESS],
        stage[SELFCOL_NARROW_SWEEP_ACCEPTED]);
    assert_true(touching >= trials / 4);
    assert_true(stage[SELFCOL_NARROW_SWEEP_SEPARATED] > trials / 10);
    assert_true(stage[SELFCOL_NARROW_SWEEP_WITNESS] > trials / 5);
}

// ------------------------------------------------- benchmark sample queries

// One query: 8 points (the file's row order) and its ground truth.
typedef struct sample_query {
    double x[8][3];
    int truth;
} sample_query;

typedef struct query_list {
    sample_query *q;
    size_t n, cap;
} query_list;

// Counts of the conversion of the file's rationals to doubles.
static long conversions, inexact_conversions;

// num / den as a double. Every denominator of the data set is a power of two
// and every value a double (checked here, counted otherwise): strtod rounds
// the numerator correctly (glibc), which is exact when it has at most 53
// significant bits; the power of two is recognised exactly (its "%.0f" image
// must reproduce the string), and the scaling by it (ldexp) is exact barring
// underflow. Anything else falls back to a long double division, rounded
// twice (to long double, then to double): within 1 ulp, counted as inexact.
static double rational_to_double(const char *num, const char *den) {
    ++conversions;
    char *end = NULL;
    const double n = strtod(num, &end);
    const double d = strtod(den, NULL);
    int e = 0;
    char image[64];
    if (d > 0.0 && frexp(d, &e) == 0.5) {
        snprintf(image, sizeof image, "%.0f", d);
        if (strcmp(image, den) == 0) {
            const double x = ldexp(n, 1 - e);
            snprintf(image, sizeof image, "%.0f", n);
            if (strcmp(image, num) != 0 || ldexp(x, e - 1) != n)
                ++inexact_conversions;
            return x;
        }
    }
    ++inexact_conversions;
    return (double)(strtold(num, NULL) / strtold(den, NULL));
}

// Reads one data_*.csv file (8 rows a query, 7 columns) into list.
static void read_queries(const char *path, query_list *list) {
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char line[1024];
    int row = 0;
    sample_query cur;
    while (fgets(line, sizeof line, f) != NULL) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0')
            continue;
        char *field[7] = {NULL};
        int nf = 0;
        for (char *p = line; nf < 7;) {
            field[nf++] = p;
            p = strchr(p, ',');
            if (p == NULL)
                break;
            *p++ = '\0';
        }
        if (nf != 7)
            fail_msg("%s: a row with %d fields", path, nf);
        for (int i = 0; i < 3; ++i)
            cur.x[row][i] = rational_to_double(field[2 * i], field[2 * i + 1]);
        const int truth = atoi(field[6]);
        if (row == 0)
            cur.truth = truth;
        else if (truth != cur.truth)
            fail_msg("%s: rows of one query disagree on the truth", path);
        if (++row == 8) {
            if (list->n == list->cap) {
                list->cap = list->cap ? 2 * list->cap : 256;
                list->q = realloc(list->q, list->cap * sizeof *list->q);
                assert_non_null(list->q);
            }
            list->q[list->n++] = cur;
            row = 0;
        }
    }
    if (row != 0)
        fail_msg("%s: %d rows left over", path, row);
    fclose(f);
}

static int is_csv(const struct dirent *e) {
    const size_t len = strlen(e->d_name);
    return len > 4 && strcmp(e->d_name + len - 4, ".csv") == 0;
}

static int is_entry(const struct dirent *e) {
    return e->d_name[0] != '.';
}

// Every CSV of dir (sorted), into list. 0 when dir is absent.
static int read_folder(const char *dir, query_list *list) {
    struct dirent **names = NULL;
    const int count = scandir(dir, &names, is_csv, alphasort);
    if (count < 0)
        return 0;
    for (int i = 0; i < count; ++i) {
        char path[4096 + 512];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]->d_name);
        read_queries(path, list);
        free(names[i]);
    }
    free(names);
    return 1;
}

static double now_ns(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

// Per (family, kind) results.
typedef struct family_result {
    long queries, positives, false_negatives, false_positives, budget;
    long separated,
        separated_wrongly;  // selfcol_narrow_sweep__separated: said apart, of which truth 1
    long may_touch_wrongly; // selfcol_narrow_sweep__may_touch: 0 for a truth 1
    long never_coplanar;    // answered by the coplanarity filter (answer 0)
    long max_checks;
    double ns;
} family_result;

static void run_queries(const query_list *list, int vf, const char *family, family_result *r) {
    memset(r, 0, sizeof *r);
    int *answer = calloc(list->n + 1, sizeof *answer);
    int *outcome = calloc(list->n + 1, sizeof *outcome);
    long *checks = calloc(list->n + 1, sizeof *checks);
    double *toi = calloc(list->n + 1, sizeof *toi);
    assert_true(answer != NULL && outcome != NULL && checks != NULL && toi != NULL);
    const double start = now_ns();
    for (size_t k = 0; k < list->n; ++k) {
        const double(*x)[3] = (const double(*)[3])list->q[k].x;
        selfcol_narrow_sweep_info info;
        answer[k] = vf ? selfcol_narrow_sweep__vf_info(x[0], x[1], x[2], x[3], x[4], x[5], x[6],
                                                       x[7], 0.0, &toi[k], &info)
                       : selfcol_narrow_sweep__ee_info(x[0], x[1], x[2], x[3], x[4], x[5], x[6],
                                                       x[7], 0.0, &toi[k], &info);
        outcome[k] = info.outcome;
        checks[k] = info.checks;
        r->never_coplanar += info.outcome == SELFCOL_NARROW_SWEEP_NEVER_COPLANAR;
    }
    r->ns = now_ns() - start;
    // The cheap separation filter must never call a colliding query apart.
    for (size_t k = 0; k < list->n; ++k) {
        const double(*x)[3] = (const double(*)[3])list->q[k].x;
        const double *const start[4] = {x[0], x[1], x[2], x[3]};
        const double *const end[4] = {x[4], x[5], x[6], x[7]};
        // The store's yes/no question: no false negative either.
        if (list->q[k].truth && !selfcol_narrow_sweep__may_touch(start, end, !vf, NULL)) {
            ++r->may_touch_wrongly;
            print_message("MAY_TOUCH SAYS APART, BUT COLLIDES: %s %s query %zu\n", family,
                          vf ? "VF" : "EE", k);
        }
        if (selfcol_narrow_sweep__separated(start, end, !vf, 0.0)) {
            ++r->separated;
            if (list->q[k].truth) {
                ++r->separated_wrongly;
                print_message("SEPARATED BUT COLLIDES: %s %s query %zu\n", family, vf ? "VF" : "EE",
                              k);
            }
        }
    }
    for (size_t k = 0; k < list->n; ++k) {
        ++r->queries;
        r->positives += list->q[k].truth;
        r->max_checks = checks[k] > r->max_checks ? checks[k] : r->max_checks;
        if (answer[k] && !(toi[k] >= 0.0 && toi[k] <= 1.0))
            fail_msg("%s %s query %zu: toi %g outside [0, 1]", family, vf ? "VF" : "EE", k, toi[k]);
        if (list->q[k].truth && !answer[k]) {
            ++r->false_negatives;
            print_message("FALSE NEGATIVE: %s %s query %zu\n", family, vf ? "VF" : "EE", k);
        }
        if (!list->q[k].truth && answer[k]) {
            ++r->false_positives;
            r->budget += outcome[k] == SELFCOL_NARROW_SWEEP_BUDGET;
        }
    }
    free(answer);
    free(outcome);
    free(checks);
    free(toi);
}

static void test_ccd_sample_queries_when_present(void **state) {
    (void)state;
    const char *root = SELFCOL_SHARED_DATA_DIR "/ccd-sample-queries";
    struct dirent **families = NULL;
    const int nfam = scandir(root, &families, is_entry, alphasort);
    if (nfam < 0) {
        print_message("%s absent: skipped\n", root);
        skip();
    }
    long total_fn = 0, total[2] = {0, 0}, total_fp[2] = {0, 0}, total_pos[2] = {0, 0};
    long total_separated = 0, total_separated_wrongly = 0, total_may_touch_wrongly = 0;
    long total_never_coplanar = 0;
    double total_ns[2] = {0.0, 0.0};
    print_message("%-28s %4s %7s %6s %4s %5s %9s %9s %9s\n", "family", "kind", "queries", "truth1",
                  "FN", "FP", "FPbudget", "maxboxes", "ns/query");
    for (int fi = 0; fi < nfam; ++fi) {
        for (int vf = 1; vf >= 0; --vf) {
            char dir[4096];
            snprintf(dir, sizeof dir, "%s/%s/%s", root, families[fi]->d_name,
                     vf ? "vertex-face" : "edge-edge");
            query_list list = {NULL, 0, 0};
            if (!read_folder(dir, &list))
                continue; // not a family folder (visualization/, files)
            family_result r;
            run_queries(&list, vf, families[fi]->d_name, &r);
            free(list.q);
            print_message("%-28s %4s %7ld %6ld %4ld %5ld %9ld %9ld %9.0f\n", families[fi]->d_name,
                          vf ? "VF" : "EE", r.queries, r.positives, r.false_negatives,
                          r.false_positives, r.budget, r.max_checks,
                          r.queries ? r.ns / (double)r.queries : 0.0);
            total_fn += r.false_negatives;
            total_separated += r.separated;
            total_never_coplanar += r.never_coplanar;
            total_separated_wrongly += r.separated_wrongly;
            total_may_touch_wrongly += r.may_touch_wrongly;
            total[vf] += r.queries;
            total_fp[vf] += r.false_positives;
            total_pos[vf] += r.positives;
            total_ns[vf] += r.ns;
        }
        free(families[fi]);
    }
    free(families);
    for (int vf = 1; vf >= 0; --vf)
        print_message("%s: %ld queries (%ld truth 1), %ld false positives, %.0f ns/query\n",
                      vf ? "VF" : "EE", total[vf], total_pos[vf], total_fp[vf],
                      total[vf] ? total_ns[vf] / (double)total[vf] : 0.0);
    print_message("rationals: %ld converted, %ld not exactly\n", conversions, inexact_conversions);
    print_message("separation filter: %ld queries shown apart, %ld of them colliding\n",
                  total_separated, total_separated_wrongly);
    print_message("coplanarity filter: %ld queries never coplanar (answer 0; a false negative "
                  "among them would count above)\n",
                  total_never_coplanar);
    if (total[0] + total[1] == 0) {
        print_message("%s holds no queries: skipped\n", root);
        skip();
    }
    assert_int_equal(total_fn, 0);
    assert_int_equal(total_separated_wrongly, 0);
    assert_int_equal(total_may_touch_wrongly, 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vertex_through_triangle_middle),
        cmocka_unit_test(test_vertex_parallel_far_away),
        cmocka_unit_test(test_separation_in_the_plane),
        cmocka_unit_test(test_never_coplanar_filter),
        cmocka_unit_test(test_edges_crossing),
        cmocka_unit_test(test_delta_catches_near_miss),
        cmocka_unit_test(test_degenerate_motions),
        cmocka_unit_test(test_exact_contacts_are_found),
        cmocka_unit_test(test_random_motions_against_sampled_distance),
        cmocka_unit_test(test_may_touch_hand_made),
        cmocka_unit_test(test_may_touch_against_search),
        cmocka_unit_test(test_ccd_sample_queries_when_present),
    };
    return cmocka_run_group_tests_name("narrow_sweep", tests, NULL, NULL);
}
