// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The colliders' narrow phase (collider.c; libccd's hull query of
// narrow_ccd.c for convex point sets) against references computed another
// way. A sphere is a point swept by its radius and a capsule a segment, so
// their distance to a triangle is narrow.c's point-triangle or
// segment-triangle distance minus the radius; a box is compared with the
// least over its 12 triangles of narrow.c's VF, EE and EF tests. Random
// triangles near each shape: the distance agrees within the tolerance;
// every triangle the reference puts within the distance is found and none
// beyond it; the normals agree.
//
// Colliders much larger than the distance (hardening 0.3, item 4): spheres
// of radius 1e3 .. 1e15 at a gap of 0.02 under a sheet (exact answers by a
// cancellation-free formula), a box of half-extent 1e45 and a capsule of
// half-height 1e14 at and around a sheet, and random triangles near
// spheres, capsules and boxes at scales 1 .. 1e9 against a reference that
// minimises the exact point-to-shape distance over the triangle in long
// double. Out of range (collider.c's limits) the narrow phase answers
// SELFCOL_ERANGE. Each of these failed before the closed forms (the numbers
// are in the commit message).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vec3.h"
#include "narrow/narrow.h"
#include "scene/collider.h"

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double uniform(double lo, double hi) {
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * (double)(rng_state >> 11) * 0x1p-53;
}

// A random triangle of size ~size near the point c.
static void random_triangle(double t[3][3], const double c[3], double spread, double size) {
    double centre[3];
    for (int k = 0; k < 3; ++k)
        centre[k] = c[k] + uniform(-spread, spread);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            t[i][k] = centre[k] + uniform(-size, size);
}

static selfcol_collider make(const selfcol_scene_collider_desc *desc, double (*local)[3],
                             double (*world)[3], const double position[3], const double rot[9]) {
    selfcol_collider c;
    memset(&c, 0, sizeof c);
    c.shape = desc->shape;
    c.radius = desc->radius;
    c.point_count = selfcol_collider__point_count(desc);
    c.local = local;
    c.world = world;
    selfcol_collider__local_points(desc, local);
    selfcol_collider__place(&c, position, rot);
    return c;
}

// The least distance from the hull core of a sphere (a point) or capsule (a
// segment) to the triangle: the closed form.
static double core_distance(const selfcol_collider *c, double t[3][3]) {
    selfcol_narrow_result r;
    if (c->point_count == 1)
        return selfcol_narrow__vf(c->world[0], t[0], t[1], t[2], &r);
    return selfcol_narrow__segment_triangle(c->world[0], c->world[1], t[0], t[1], t[2], &r);
}

// Distance from the core (point or segment) to a point.
static double core_distance_to_point(const selfcol_collider *c, const double p[3]) {
    selfcol_narrow_result r;
    if (c->point_count == 1)
        return sqrt(vec3_dist2(c->world[0], p));
    return selfcol_narrow__ee(c->world[0], c->world[1], p, p, &r);
}

static void check_rounded(uint32_t shape) {
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, shape, SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.radius = 0.5;
    desc.half_height = 0.7;
    double local[2][3], world[2][3], scratch[2][3];
    const double position[3] = {1.25, -3.5, 0.75};
    const double c30 = cos(0.5), s30 = sin(0.5);
    const double rot[9] = {1, 0, 0, 0, c30, -s30, 0, s30, c30};
    selfcol_collider c = make(&desc, local, world, position, rot);
    const double d = 0.05, tol = 1e-7;
    int within = 0, beyond = 0, penetrating = 0;
    double worst = 0.0;
    for (int trial = 0; trial < 3000; ++trial) {
        double t[3][3];
        random_triangle(t, position, 1.3, 0.4);
        const double exact = core_distance(&c, t) - c.radius; // < 0: penetrating
        selfcol_collider_contact got;
        const int hit =
            selfcol_collider__contacts_of_triangle(&c, t[0], t[1], t[2], d, tol, scratch, &got);
        if (exact < d - tol) {
            assert_true(hit);
            const double expect = exact > 0.0 ? exact : 0.0;
            worst = fmax(worst, fabs(got.distance - expect));
            assert_true(fabs(got.distance - expect) <= tol);
            assert_int_equal((got.flags & SELFCOL_COLLIDER_PENETRATING) != 0, got.distance == 0.0);
            assert_false(got.flags & SELFCOL_COLLIDER_APPROXIMATE);
            within++;
            penetrating += exact <= 0.0;
            // The closed-form normal: unit, from the core toward the
            // triangle's closest point (wb), which lies core + radius + distance away.
            if (exact > 1e-6) {
                double q[3] = {0, 0, 0}, back[3];
                for (int i = 0; i < 3; ++i)
                    for (int k = 0; k < 3; ++k)
                        q[k] += got.wb[i] * t[i][k];
                assert_true(fabs(vec3_dot(got.normal, got.normal) - 1.0) < 1e-9);
                for (int k = 0; k < 3; ++k)
                    back[k] = q[k] - (c.radius + exact) * got.normal[k];
                assert_true(core_distance_to_point(&c, back) < 1e-9);
            }
        } else if (exact > d + tol) {
            assert_false(hit);
            beyond++;
        }
    }
    print_message("%s: %d within d (%d penetrating), %d beyond; worst |libccd - closed form| "
                  "= %.3g (tolerance %.1g)\n",
                  shape == SELFCOL_COLLIDER_SPHERE ? "sphere" : "capsule", within, penetrating,
                  beyond, worst, tol);
    assert_true(within > 100 && beyond > 100 && penetrating > 10);
}

static void test_sphere_libccd_matches_closed_form(void **state) {
    (void)state;
    check_rounded(SELFCOL_COLLIDER_SPHERE);
}

static void test_capsule_libccd_matches_closed_form(void **state) {
    (void)state;
    check_rounded(SELFCOL_COLLIDER_CAPSULE);
}

// Box: closed form over its 12 triangles (a triangle outside the box: the
// least VF/EE distance between the two triangle sets; crossing: an EF).
static double box_distance(double corners[8][3], double t[3][3], double normal[3]) {
    static const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                     {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                     {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    double best = HUGE_VAL;
    selfcol_narrow_result r;
    for (int f = 0; f < 12; ++f) {
        const double *b[3] = {corners[faces[f][0]], corners[faces[f][1]], corners[faces[f][2]]};
        for (int i = 0; i < 3; ++i) {
            double dd = selfcol_narrow__vf(t[i], b[0], b[1], b[2], &r); // triangle vertex vs box
            if (dd < best) {
                best = dd;
                memcpy(normal, r.direction, sizeof r.direction);
            }
            dd = selfcol_narrow__vf(b[i], t[0], t[1], t[2], &r); // box corner vs triangle
            if (dd < best) {
                best = dd;
                for (int k = 0; k < 3; ++k)
                    normal[k] = -r.direction[k];
            }
            for (int j = 0; j < 3; ++j) {
                dd = selfcol_narrow__ee(t[i], t[(i + 1) % 3], b[j], b[(j + 1) % 3], &r);
                if (dd < best) {
                    best = dd;
                    memcpy(normal, r.direction, sizeof r.direction);
                }
                if (selfcol_narrow__ef(t[i], t[(i + 1) % 3], b[0], b[1], b[2], &r) ||
                    selfcol_narrow__ef(b[j], b[(j + 1) % 3], t[0], t[1], t[2], &r))
                    best = 0.0;
            }
        }
    }
    return best;
}

static void test_box_libccd_matches_closed_form(void **state) {
    (void)state;
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_BOX,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.half_extents[0] = 0.6;
    desc.half_extents[1] = 0.3;
    desc.half_extents[2] = 0.45;
    double local[8][3], world[8][3], scratch[8][3];
    const double position[3] = {-2.0, 0.5, 4.0};
    const double c = cos(0.3), s = sin(0.3);
    const double rot[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    selfcol_collider col = make(&desc, local, world, position, rot);
    const double d = 0.05, tol = 1e-7;
    int within = 0, separated = 0;
    double worst = 0.0, worst_angle = 0.0, sum_angle = 0.0;
    for (int trial = 0; trial < 3000; ++trial) {
        double t[3][3], normal[3] = {0.0, 0.0, 0.0};
        random_triangle(t, position, 1.0, 0.4);
        double exact = box_distance(world, t, normal);
        // A triangle inside the box meets none of its faces: distance 0.
        double rel[3], loc[3];
        vec3_sub(rel, t[0], position);
        for (int k = 0; k < 3; ++k) // R^T rel: R's columns
            loc[k] = rot[k] * rel[0] + rot[3 + k] * rel[1] + rot[6 + k] * rel[2];
        if (fabs(loc[0]) < desc.half_extents[0] && fabs(loc[1]) < desc.half_extents[1] &&
            fabs(loc[2]) < desc.half_extents[2])
            exact = 0.0;
        selfcol_collider_contact got;
        const int hit =
            selfcol_collider__contacts_of_triangle(&col, t[0], t[1], t[2], d, tol, scratch, &got);
        if (exact < d - tol) {
            assert_true(hit);
            worst = fmax(worst, fabs(got.distance - exact));
            assert_true(fabs(got.distance - exact) <= tol);
            assert_false(got.flags & SELFCOL_COLLIDER_APPROXIMATE); // closed form
            within++;
            if (exact > 1e-3) { // separated: the normal is defined
                const double cosine = vec3_dot(got.normal, normal);
                const double angle = acos(fmin(1.0, fmax(-1.0, cosine)));
                worst_angle = fmax(worst_angle, angle);
                sum_angle += angle;
                separated++;
            }
        } else if (exact > d + tol) {
            assert_false(hit);
        }
    }
    print_message("box: %d within d; worst |collider - test's closed form| = %.3g; normal vs "
                  "the test's closed form over %d separated pairs: mean %.3g rad, worst %.3g rad\n",
                  within, worst, separated, sum_angle / (separated ? separated : 1), worst_angle);
    assert_true(within > 100 && separated > 50);
    // Both are closed forms now (the collider's, exact to rounding; the
    // test's, on the 12 box triangles): measured worst 2.1e-8 rad (mean
    // 4.4e-9; the test's own direction is rounded at distances ~1e-3). With
    // libccd's MPR it was worst 1.1e-3 rad, mean 2.4e-5.
    assert_true(worst_angle < 1e-6);
}

// ---------------------------------------------------------------------------
// Colliders much larger than the distance (hardening 0.3, item 4).

#define SHEET_N 6 // a SHEET_N x SHEET_N grid of squares, two triangles each, on [-1, 1]^2

// Triangle t (0 .. 2 SHEET_N^2 - 1) of the sheet at height z.
static void sheet_triangle(int t, double z, double tri[3][3]) {
    const int q = t / 2, i = q % SHEET_N, j = q / SHEET_N;
    const double h = 2.0 / SHEET_N;
    const double x0 = -1.0 + i * h, y0 = -1.0 + j * h;
    const double corners[4][2] = {{x0, y0}, {x0 + h, y0}, {x0 + h, y0 + h}, {x0, y0 + h}};
    const int pick[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int v = 0; v < 3; ++v) {
        tri[v][0] = corners[pick[t % 2][v]][0];
        tri[v][1] = corners[pick[t % 2][v]][1];
        tri[v][2] = z;
    }
}

// A sphere of radius R centred at (0, 0, -R) under the sheet at z = gap: the
// exact distance of each triangle is sqrt(l^2 + (R + gap)^2) - R, l its
// distance from the z axis (a 2D closed form), written without cancellation.
static void test_huge_spheres_over_sheet(void **state) {
    (void)state;
    const double radii[5] = {1e3, 1e7, 1e12, 1e14, 1e15};
    const double gap = 0.02, d = 0.05, tol = 1e-6 * d;
    for (int r = 0; r < 5; ++r) {
        const double R = radii[r];
        selfcol_scene_collider_desc desc;
        selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_SPHERE,
                                         SELFCOL_SCENE_COLLIDER_DESC_VERSION);
        desc.radius = R;
        double local[1][3], world[1][3], scratch[1][3];
        const double position[3] = {0.0, 0.0, -R};
        selfcol_collider c = make(&desc, local, world, position, NULL);
        double worst = 0.0;
        int penetrating = 0, missed = 0;
        for (int t = 0; t < 2 * SHEET_N * SHEET_N; ++t) {
            double tri[3][3], flat[3][3];
            sheet_triangle(t, gap, tri);
            sheet_triangle(t, 0.0, flat);
            selfcol_narrow_result nr;
            const double origin[3] = {0.0, 0.0, 0.0};
            const double l = selfcol_narrow__vf(origin, flat[0], flat[1], flat[2], &nr);
            const double H = R + gap; // the denominator only: relative accuracy
            const double exact = (l * l + gap * (2.0 * R + gap)) / (sqrt(l * l + H * H) + R);
            selfcol_collider_contact got;
            const int hit = selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d,
                                                                   tol, scratch, &got);
            assert_int_equal(hit, 1);
            if (hit != 1) {
                missed++;
                continue;
            }
            worst = fmax(worst, fabs(got.distance - exact));
            penetrating += (got.flags & SELFCOL_COLLIDER_PENETRATING) != 0;
            assert_true(fabs(got.distance - exact) <= tol);
            assert_false(got.flags & SELFCOL_COLLIDER_PENETRATING);
            assert_true(got.normal[2] > 0.999); // up, toward the sheet
        }
        print_message("sphere of radius %.0e at gap %.2g: worst error %.3g (tolerance %.1g), "
                      "%d penetrating, %d missed of %d\n",
                      R, gap, worst, tol, penetrating, missed, 2 * SHEET_N * SHEET_N);
    }
}

// A box of half-extent 1e45 whose top face is the plane z = 0 (centre at
// z = -1e45): the sheet 0.02 above is at distance 0.02 from every triangle,
// inside it every triangle penetrates, 0.06 above none is within d = 0.05.
// Also turned by an exact rotation (axes permuted), and a capsule of
// half-height 1e14 lying under the sheet.
static void test_huge_box_and_capsule_at_sheet(void **state) {
    (void)state;
    const double d = 0.05, tol = 1e-6 * d, h = 1e45;
    // Local z to world x, local x to world -z; with a box of extents
    // (h, h, h) both poses give the same box.
    const double turn[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
    const double *rotations[2] = {NULL, turn};
    for (int p = 0; p < 2; ++p) {
        selfcol_scene_collider_desc desc;
        selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_BOX,
                                         SELFCOL_SCENE_COLLIDER_DESC_VERSION);
        desc.half_extents[0] = desc.half_extents[1] = desc.half_extents[2] = h;
        double local[8][3], world[8][3], scratch[8][3];
        const double position[3] = {0.0, 0.0, -h};
        selfcol_collider c = make(&desc, local, world, position, rotations[p]);
        const double heights[3] = {0.02, -0.3, 0.06};
        for (int k = 0; k < 3; ++k) {
            int hits = 0, penetrating = 0;
            for (int t = 0; t < 2 * SHEET_N * SHEET_N; ++t) {
                double tri[3][3];
                sheet_triangle(t, heights[k], tri);
                selfcol_collider_contact got;
                const int hit = selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2],
                                                                       d, tol, scratch, &got);
                assert_true(hit == 0 || hit == 1);
                hits += hit;
                if (!hit)
                    continue;
                penetrating += (got.flags & SELFCOL_COLLIDER_PENETRATING) != 0;
                if (k == 0) {
                    assert_true(fabs(got.distance - 0.02) <= tol);
                    assert_true(got.normal[2] > 0.999);
                } else {
                    assert_true(got.distance == 0.0);
                }
            }
            const int all = 2 * SHEET_N * SHEET_N;
            print_message("box of half-extent 1e45 (%s), sheet at %g: %d of %d triangles within "
                          "d, %d penetrating\n",
                          p ? "turned" : "axis-aligned", heights[k], hits, all, penetrating);
            assert_int_equal(hits, k == 2 ? 0 : all);
            assert_int_equal(penetrating, k == 1 ? all : 0);
        }
    }
    // The capsule: axis along x (local z to world x), radius 0.5, axis at
    // z = -0.5: its surface touches z = 0 under the whole sheet.
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CAPSULE,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.radius = 0.5;
    desc.half_height = 1e14;
    double local[2][3], world[2][3], scratch[2][3];
    const double position[3] = {0.0, 0.0, -0.5};
    selfcol_collider c = make(&desc, local, world, position, turn);
    for (int t = 0; t < 2 * SHEET_N * SHEET_N; ++t) {
        double tri[3][3], flat[3][3];
        sheet_triangle(t, 0.02, tri);
        sheet_triangle(t, 0.0, flat);
        // Exact: the distance from the axis (the x axis at z = -0.5) is
        // sqrt(y^2 + 0.52^2), y the triangle's least |y|.
        double y = fmin(fabs(flat[0][1]), fmin(fabs(flat[1][1]), fabs(flat[2][1])));
        if (fmin(flat[0][1], fmin(flat[1][1], flat[2][1])) < 0.0 &&
            fmax(flat[0][1], fmax(flat[1][1], flat[2][1])) > 0.0)
            y = 0.0;
        const double exact = (y * y + 0.02 * (1.0 + 0.02)) / (sqrt(y * y + 0.52 * 0.52) + 0.5);
        selfcol_collider_contact got;
        const int hit = selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d, tol,
                                                               scratch, &got);
        if (exact < d - tol) {
            assert_int_equal(hit, 1);
            assert_true(fabs(got.distance - exact) <= tol);
        } else if (exact > d + tol) {
            assert_int_equal(hit, 0);
        }
    }
}

// ---------------------------------------------------------------------------
// Randomised: sphere, capsule and box at several scales against an
// independent reference: the least over the triangle of the exact distance
// of a point to the shape (sphere: to the centre; capsule: to the axis
// segment; box: per-axis excess in the box's frame), minimised by nested
// golden-section search in long double (the distance of a point to a convex
// set is convex over the triangle, so the nested minimum is the minimum).

typedef long double ld;

typedef struct reference_shape {
    uint32_t shape;
    ld centre[3], rot[9], half[3], radius; // half: box half extents; capsule: {0, 0, hh}
} reference_shape;

static ld point_distance(const reference_shape *s, const ld y[3]) {
    ld rel[3], loc[3];
    for (int k = 0; k < 3; ++k)
        rel[k] = y[k] - s->centre[k];
    for (int k = 0; k < 3; ++k) // rotation^T rel
        loc[k] = s->rot[k] * rel[0] + s->rot[3 + k] * rel[1] + s->rot[6 + k] * rel[2];
    ld e2 = 0.0L;
    for (int k = 0; k < 3; ++k) {
        ld e = fabsl(loc[k]) - s->half[k];
        if (e > 0.0L)
            e2 += e * e;
    }
    return sqrtl(e2) - s->radius;
}

static ld along_triangle(const reference_shape *s, double t[3][3], ld u, ld v) {
    ld y[3];
    for (int k = 0; k < 3; ++k)
        y[k] = (ld)t[0][k] + u * ((ld)t[1][k] - (ld)t[0][k]) + v * ((ld)t[2][k] - (ld)t[1][k]);
    return point_distance(s, y);
}

#define GOLDEN 0.6180339887498948482L

// min over v in [0, u] of the distance at (u, v).
static ld inner_min(const reference_shape *s, double t[3][3], ld u) {
    ld lo = 0.0L, hi = u;
    ld best = fminl(along_triangle(s, t, u, lo), along_triangle(s, t, u, hi));
    ld x1 = hi - GOLDEN * (hi - lo), x2 = lo + GOLDEN * (hi - lo);
    ld f1 = along_triangle(s, t, u, x1), f2 = along_triangle(s, t, u, x2);
    for (int it = 0; it < 48; ++it) {
        if (f1 < f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - GOLDEN * (hi - lo);
            f1 = along_triangle(s, t, u, x1);
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + GOLDEN * (hi - lo);
            f2 = along_triangle(s, t, u, x2);
        }
    }
    return fminl(best, fminl(f1, f2));
}

static ld reference_distance(const reference_shape *s, double t[3][3]) {
    ld lo = 0.0L, hi = 1.0L;
    ld best = fminl(inner_min(s, t, lo), inner_min(s, t, hi));
    ld x1 = hi - GOLDEN * (hi - lo), x2 = lo + GOLDEN * (hi - lo);
    ld f1 = inner_min(s, t, x1), f2 = inner_min(s, t, x2);
    for (int it = 0; it < 48; ++it) {
        if (f1 < f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - GOLDEN * (hi - lo);
            f1 = inner_min(s, t, x1);
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + GOLDEN * (hi - lo);
            f2 = inner_min(s, t, x2);
        }
    }
    best = fminl(best, fminl(f1, f2));
    return best > 0.0L ? best : 0.0L;
}

// A rotation from three angles (row-major).
static void random_rotation(double r[9]) {
    const double a = uniform(-3.1, 3.1), b = uniform(-1.5, 1.5), g = uniform(-3.1, 3.1);
    const double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b), cg = cos(g), sg = sin(g);
    const double z[9] = {ca, -sa, 0, sa, ca, 0, 0, 0, 1};
    const double y[9] = {cb, 0, sb, 0, 1, 0, -sb, 0, cb};
    const double x[9] = {1, 0, 0, 0, cg, -sg, 0, sg, cg};
    double zy[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            zy[3 * i + j] = 0.0;
            for (int k = 0; k < 3; ++k)
                zy[3 * i + j] += z[3 * i + k] * y[3 * k + j];
        }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            r[3 * i + j] = 0.0;
            for (int k = 0; k < 3; ++k)
                r[3 * i + j] += zy[3 * i + k] * x[3 * k + j];
        }
}

static void check_random_at_scale(uint32_t shape, double scale, double *worst_out) {
    const double d = 0.05, tol = 1e-6 * d;
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, shape, SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    double rot[9];
    random_rotation(rot);
    const double position[3] = {uniform(-2, 2) * scale, uniform(-2, 2) * scale,
                                uniform(-2, 2) * scale};
    reference_shape ref;
    memset(&ref, 0, sizeof ref);
    ref.shape = shape;
    if (shape == SELFCOL_COLLIDER_SPHERE) {
        desc.radius = scale;
    } else if (shape == SELFCOL_COLLIDER_CAPSULE) {
        desc.radius = 0.3 * scale;
        desc.half_height = scale;
        ref.half[2] = scale;
    } else {
        desc.radius = 0.01;
        desc.half_extents[0] = scale;
        desc.half_extents[1] = 0.7 * scale;
        desc.half_extents[2] = 0.4 * scale;
        for (int k = 0; k < 3; ++k)
            ref.half[k] = desc.half_extents[k];
    }
    ref.radius = desc.radius;
    for (int k = 0; k < 3; ++k)
        ref.centre[k] = position[k];
    for (int k = 0; k < 9; ++k) // (a sphere is not turned: the rotation is not exactly orthonormal)
        ref.rot[k] = shape == SELFCOL_COLLIDER_SPHERE ? (k % 4 == 0) : rot[k];
    double local[8][3], world[8][3], scratch[8][3];
    selfcol_collider c = make(&desc, local, world, position, rot);
    int within = 0, beyond = 0, penetrating = 0;
    for (int trial = 0; trial < 80; ++trial) {
        // A point on the core's surface (local frame) and the outward normal.
        double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        if (shape == SELFCOL_COLLIDER_BOX) {
            const int k = trial % 3;
            const double side = trial & 1 ? 1.0 : -1.0;
            for (int j = 0; j < 3; ++j)
                p[j] = uniform(-1.05, 1.05) * desc.half_extents[j];
            p[k] = side * desc.half_extents[k];
            n[k] = side;
        } else {
            for (int k = 0; k < 3; ++k)
                n[k] = uniform(-1, 1);
            double len = sqrt(vec3_dot(n, n));
            for (int k = 0; k < 3; ++k)
                n[k] /= len;
            if (shape == SELFCOL_COLLIDER_CAPSULE) {
                // On the cylinder (n across the axis) or on a cap.
                p[2] = uniform(-1.2, 1.2) * desc.half_height;
                if (fabs(p[2]) <= desc.half_height) {
                    n[2] = 0.0;
                } else {
                    p[2] = p[2] > 0.0 ? desc.half_height : -desc.half_height;
                    n[2] = p[2] > 0.0 ? fabs(n[2]) : -fabs(n[2]);
                }
                len = sqrt(vec3_dot(n, n));
                for (int k = 0; k < 3; ++k)
                    n[k] /= len;
            }
        }
        // Two tangents, then the triangle: tangent within 0.5 at height
        // -0.02 .. 0.1 over the surface, tilted for a third of the trials.
        double t1[3], t2[3], any[3] = {0.3, -0.5, 0.8};
        vec3_cross(t1, n, any);
        vec3_normalize(t1, t1);
        vec3_cross(t2, n, t1);
        const double lift = uniform(-0.02, 0.1), tilt = trial % 3 == 0 ? 0.3 : 0.02;
        double loc[3][3], tri[3][3];
        for (int i = 0; i < 3; ++i) {
            const double x = uniform(-0.5, 0.5), y = uniform(-0.5, 0.5), z = uniform(-tilt, tilt);
            for (int k = 0; k < 3; ++k)
                loc[i][k] = p[k] + (desc.radius + lift + z) * n[k] + x * t1[k] + y * t2[k];
        }
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) // world = rot loc + position
                tri[i][k] = rot[3 * k] * loc[i][0] + rot[3 * k + 1] * loc[i][1] +
                            rot[3 * k + 2] * loc[i][2] + position[k];
        const double exact = (double)reference_distance(&ref, tri);
        selfcol_collider_contact got;
        const int hit = selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d, tol,
                                                               scratch, &got);
        if (exact < d - tol) {
            assert_int_equal(hit, 1);
            if (hit != 1)
                continue;
            *worst_out = fmax(*worst_out, fabs(got.distance - exact));
            if (fabs(got.distance - exact) > tol)
                print_message("scale %.0e shape %u: got %.17g exact %.17g\n", scale, shape,
                              got.distance, exact);
            assert_true(fabs(got.distance - exact) <= tol);
            within++;
            penetrating += exact == 0.0;
        } else if (exact > d + tol) {
            assert_int_equal(hit, 0);
            beyond++;
        }
    }
    if (!(within > 20 && beyond > 10 && penetrating > 0))
        print_message("counts %d %d %d\n", within, beyond, penetrating);
    assert_true(within > 20 && beyond > 10 && penetrating > 0);
}

// Does long double carry more bits than double here? Not under valgrind,
// which computes x87 long double in double precision: the reference's own
// rounding then grows to about 1e-7 at scale 1e9 (measured: 8.3e-8), above
// the tolerance it checks, so the largest scale runs only where the
// reference has its extended precision (natively and under ASan).
static int long_double_is_extended(void) {
    volatile ld one = 1.0L, tiny = 0x1p-60L;
    return one + tiny != one;
}

static void test_random_against_reference(void **state) {
    (void)state;
    const uint32_t shapes[3] = {SELFCOL_COLLIDER_SPHERE, SELFCOL_COLLIDER_CAPSULE,
                                SELFCOL_COLLIDER_BOX};
    const char *names[3] = {"sphere", "capsule", "box"};
    const double scales[4] = {1.0, 1e3, 1e6, 1e9};
    const int scale_count = long_double_is_extended() ? 4 : 3;
    if (scale_count < 4)
        print_message("long double has double precision here (valgrind?): the reference is "
                      "too coarse at scale 1e9, which is skipped\n");
    for (int s = 0; s < 3; ++s)
        for (int k = 0; k < scale_count; ++k) {
            double worst = 0.0;
            check_random_at_scale(shapes[s], scales[k], &worst);
            print_message("%s at scale %.0e: worst |error| %.3g (tolerance %.1g)\n", names[s],
                          scales[k], worst, 5e-8);
        }
}

// Beyond what the arithmetic can answer within the tolerance the narrow phase
// says SELFCOL_ERANGE instead of a wrong answer: a sphere of radius 1e30 at
// d = 0.05 (the limit is 2^95 x tolerance, 2e21 here), a convex point set
// 1e3 across (libccd: 2^25 x tolerance, 1.7 here), a tolerance below 2^-45 d,
// a triangle longer than 2^47 x tolerance. Within the limits a convex box
// agrees with the closed-form box.
static void test_out_of_range_is_refused(void **state) {
    (void)state;
    const double d = 0.05, tol = 1e-6 * d;
    double tri[3][3];
    sheet_triangle(0, 0.02, tri);
    selfcol_collider_contact got;
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_SPHERE,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.radius = 1e30;
    double local[8][3], world[8][3], scratch[8][3];
    const double below[3] = {0.0, 0.0, -1e30};
    selfcol_collider c = make(&desc, local, world, below, NULL);
    assert_int_equal(selfcol_collider__range(&c, d, tol), SELFCOL_ERANGE);
    assert_int_equal(
        selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d, tol, scratch, &got),
        SELFCOL_ERANGE);

    // A tolerance below 2^-45 d; a triangle 1e7 long at tolerance 5e-8.
    desc.radius = 1.0;
    c = make(&desc, local, world, below, NULL);
    assert_int_equal(selfcol_collider__range(&c, d, 0x1p-46 * d), SELFCOL_ERANGE);
    assert_int_equal(selfcol_collider__range(&c, d, tol), SELFCOL_OK);
    const double big[3][3] = {{0, 0, -1e30 + 1.02}, {1e7, 0, -1e30 + 1.02}, {0, 1e7, -1e30 + 1.02}};
    assert_int_equal(
        selfcol_collider__contacts_of_triangle(&c, big[0], big[1], big[2], d, tol, scratch, &got),
        SELFCOL_ERANGE);

    double corners[24];
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k)
            corners[3 * i + k] = (i >> k & 1) ? 500.0 : -500.0;
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CONVEX,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.points = corners;
    desc.point_count = 8;
    const double under[3] = {0.0, 0.0, -500.0};
    c = make(&desc, local, world, under, NULL);
    assert_int_equal(selfcol_collider__range(&c, d, tol), SELFCOL_ERANGE);
    assert_int_equal(
        selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d, tol, scratch, &got),
        SELFCOL_ERANGE);

    // A convex box of half-extent 0.25 against the closed-form box.
    for (int i = 0; i < 24; ++i)
        corners[i] = corners[i] > 0.0 ? 0.25 : -0.25;
    const double near[3] = {0.0, 0.0, -0.25};
    c = make(&desc, local, world, near, NULL);
    assert_int_equal(selfcol_collider__range(&c, d, tol), SELFCOL_OK);
    for (int t = 0; t < 2 * SHEET_N * SHEET_N; ++t) {
        sheet_triangle(t, 0.02, tri);
        // Only the triangles over the box's top face are at 0.02.
        const int over = fabs(tri[0][0]) <= 0.25 && fabs(tri[1][0]) <= 0.25 &&
                         fabs(tri[2][0]) <= 0.25 && fabs(tri[0][1]) <= 0.25 &&
                         fabs(tri[1][1]) <= 0.25 && fabs(tri[2][1]) <= 0.25;
        const int hit = selfcol_collider__contacts_of_triangle(&c, tri[0], tri[1], tri[2], d, tol,
                                                               scratch, &got);
        assert_true(hit == 0 || hit == 1);
        if (over) {
            assert_int_equal(hit, 1);
            assert_true(fabs(got.distance - 0.02) <= tol);
        }
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_libccd_matches_closed_form),
        cmocka_unit_test(test_capsule_libccd_matches_closed_form),
        cmocka_unit_test(test_box_libccd_matches_closed_form),
        cmocka_unit_test(test_huge_spheres_over_sheet),
        cmocka_unit_test(test_huge_box_and_capsule_at_sheet),
        cmocka_unit_test(test_random_against_reference),
        cmocka_unit_test(test_out_of_range_is_refused),
    };
    return cmocka_run_group_tests_name("collider", tests, NULL, NULL);
}
