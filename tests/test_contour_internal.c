// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Direct tests of the contour test of method EXACT (lib/query/contour.c):
// conditions (2) and (4) on hand-made boundary loops -- a pinch, a crossing,
// a fold-back in projection, a collinear overlap, collinear edges apart, a
// loop seen edge-on, and clearances just below, exactly at and just above d
// -- each decided against what the geometry says, and where a real contact
// exists, checked against the exhaustive reference. Then the whole
// criterion (self_skippable) on a flat disk: sound at every d of a sweep
// (never skips a patch in which EXHAUSTIVE finds a contact) and complete
// where the proof applies.
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "hierarchy/hierarchy.h"
#include "query/contour.h"
#include "test_alloc.h"

#include <selfcol/selfcol.h>

typedef struct patch {
    selfcol_mesh *mesh;
    selfcol_workspace scratch; // contour.c's work area
    selfcol_query_stats stats; // its counters
} patch;

static patch make_patch(const double *positions, size_t vertex_count, const uint32_t *triangles,
                        size_t triangle_count) {
    patch p;
    memset(&p, 0, sizeof p);
    assert_int_equal(
        selfcol_mesh_create(&p.mesh, vertex_count, positions, triangle_count, triangles, NULL),
        SELFCOL_OK);
    const selfcol_allocator standard = {NULL, NULL, NULL};
    selfcol_workspace__init(&p.scratch, &standard);
    return p;
}

static void free_patch(patch *p) {
    selfcol_workspace__free(&p->scratch);
    selfcol_mesh_destroy(p->mesh);
}

// The half-edge u -> w in contour.c's encoding; fails the test when the mesh
// has no such edge.
static uint32_t half_edge(const selfcol_mesh *m, uint32_t u, uint32_t w) {
    for (size_t e = 0; e < m->edge_count; ++e) {
        uint32_t lo = m->edges[2 * e], hi = m->edges[2 * e + 1];
        if (lo == u && hi == w)
            return (uint32_t)(e << 1);
        if (lo == w && hi == u)
            return (uint32_t)(e << 1) | 1u;
    }
    fail_msg("no edge %u-%u", u, w);
    return 0;
}

// The loop's half-edges, decided by both candidate searches, which must
// agree.
static int half_edges_clear(patch *p, const uint32_t *he, size_t n, const double v[3], double d) {
    int grid = selfcol_contour__loop_clear(p->mesh, he, n, v, d, SELFCOL_CONTOUR_GRID, &p->scratch,
                                           &p->stats);
    int all = selfcol_contour__loop_clear(p->mesh, he, n, v, d, SELFCOL_CONTOUR_ALL_PAIRS,
                                          &p->scratch, &p->stats);
    if (grid != all)
        fail_msg("%zu edges, d = %g: the grid says %d, all pairs %d", n, d, grid, all);
    return grid;
}

// 1 when the loop through vertices loop[0..n) (closing back to loop[0]) is
// clear along v at distance d.
static int loop_clear(patch *p, const uint32_t *loop, size_t n, const double v[3], double d) {
    uint32_t he[16];
    assert_true(n <= 16);
    for (size_t i = 0; i < n; ++i)
        he[i] = half_edge(p->mesh, loop[i], loop[(i + 1) % n]);
    return half_edges_clear(p, he, n, v, d);
}

static const double along_z[3] = {0.0, 0.0, 1.0};

// A flat square: clear while d is below the clearance 1 between a corner and
// the far sides, refused above; refused seen edge-on (its projection folds).
static void test_square(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3}, loop[] = {0, 1, 2, 3};
    patch p = make_patch(pos, 4, tri, 2);
    assert_int_equal(loop_clear(&p, loop, 4, along_z, 0.0), 1);
    assert_int_equal(loop_clear(&p, loop, 4, along_z, 0.5), 1);
    assert_int_equal(loop_clear(&p, loop, 4, along_z, 1.5), 0);
    const double along_x[3] = {1.0, 0.0, 0.0};
    assert_int_equal(loop_clear(&p, loop, 4, along_x, 0.0), 0);
    // Tilted by 60 degrees the square projects to a 1 x 0.5 rectangle: still
    // simple, but its clearance is 0.5.
    const double tilted[3] = {0.0, 0.8660254037844386, 0.5};
    assert_int_equal(loop_clear(&p, loop, 4, tilted, 0.0), 1);
    assert_int_equal(loop_clear(&p, loop, 4, tilted, 0.45), 1);
    assert_int_equal(loop_clear(&p, loop, 4, tilted, 0.55), 0);
    free_patch(&p);
}

// A bowtie: two triangles sharing only vertex 0. The loop visits vertex 0
// twice (a pinch): refused even at d = 0, and even with one wing lifted off
// the plane (the pinch is in the loop, not in the projection).
static void test_pinch(void **state) {
    (void)state;
    for (int lifted = 0; lifted < 2; ++lifted) {
        const double z = lifted ? 1.0 : 0.0;
        const double pos[] = {0, 0, 0, 1, 1, 0, -1, 1, 0, -1, -1, z, 1, -1, z};
        const uint32_t tri[] = {0, 1, 2, 0, 3, 4}, loop[] = {0, 1, 2, 0, 3, 4};
        patch p = make_patch(pos, 5, tri, 2);
        assert_int_equal(loop_clear(&p, loop, 6, along_z, 0.0), 0);
        free_patch(&p);
    }
}

// A loop whose projection crosses itself (a figure eight): refused. Lifting
// two of its corners does not help: the crossing is in the projection.
static void test_crossing(void **state) {
    (void)state;
    for (int lifted = 0; lifted < 2; ++lifted) {
        const double z = lifted ? 0.5 : 0.0;
        const double pos[] = {0, 0, 0, 2, 2, 0, 0, 2, z, 2, 0, z};
        const uint32_t tri[] = {0, 1, 2, 0, 2, 3}, loop[] = {0, 1, 2, 3};
        patch p = make_patch(pos, 4, tri, 2);
        assert_int_equal(loop_clear(&p, loop, 4, along_z, 0.0), 0);
        free_patch(&p);
    }
}

// A triangle standing on its base: along z its third corner projects onto
// the base, so the loop folds back on itself (consecutive edges collinear
// and pointing back; decided by the exact predicate, the projected
// orientation is exactly 0). Seen from the side (along y) it is a proper
// triangle.
static void test_fold_back(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 2, 0, 0, 1, 0, 1};
    const uint32_t tri[] = {0, 1, 2}, loop[] = {0, 1, 2};
    patch p = make_patch(pos, 3, tri, 1);
    assert_int_equal(loop_clear(&p, loop, 3, along_z, 0.0), 0);
    const double along_y[3] = {0.0, 1.0, 0.0};
    assert_int_equal(loop_clear(&p, loop, 3, along_y, 0.0), 1);
    free_patch(&p);
}

// Consecutive collinear edges that continue straight on (a vertex in the
// middle of a side) are fine: a pentagon with a flat corner is clear.
static void test_straight_continuation(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0};
    const uint32_t tri[] = {0, 1, 4, 1, 2, 3, 1, 3, 4}, loop[] = {0, 1, 2, 3, 4};
    patch p = make_patch(pos, 5, tri, 3);
    assert_int_equal(loop_clear(&p, loop, 5, along_z, 0.0), 1);
    assert_int_equal(loop_clear(&p, loop, 5, along_z, 0.9), 1);
    assert_int_equal(loop_clear(&p, loop, 5, along_z, 1.1), 0);
    free_patch(&p);
}

// Two edges at different heights that are collinear and overlap in
// projection (x in [0, 2] and [1, 4] on y = 0): refused at d = 0.
static void test_collinear_overlap(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 2, 0, 0, 2, -1, 0, 4, -1, 1, 4, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 2, 2, 3, 4, 4, 5, 6, 6, 7, 0};
    const uint32_t loop[] = {0, 1, 2, 3, 4, 5, 6, 7};
    patch p = make_patch(pos, 8, tri, 4);
    assert_int_equal(loop_clear(&p, loop, 8, along_z, 0.0), 0);
    free_patch(&p);
}

// The exhaustive reference's EE contact between edges {u0, u1} and {w0, w1}
// of mesh m at distance d: 1 when found.
static int exhaustive_has_ee(const selfcol_mesh *m, double d, uint32_t u0, uint32_t u1, uint32_t w0,
                             uint32_t w1) {
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = SELFCOL_METHOD_EXHAUSTIVE;
    o.distance = d;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    int found = 0;
    const selfcol_contact *data = NULL;
    size_t count = 0;
    assert_int_equal(selfcol_contacts_data(c, &data, &count), SELFCOL_OK);
    for (size_t i = 0; i < count; ++i) {
        const selfcol_contact *k = &data[i];
        if (k->kind != SELFCOL_CONTACT_EE)
            continue;
        const int first = k->a[0] == u0 && k->a[1] == u1, second = k->b[0] == w0 && k->b[1] == w1;
        found |= first && second;
        found |= (k->a[0] == w0 && k->a[1] == w1) && (k->b[0] == u0 && k->b[1] == u1);
    }
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    return found;
}

// A flat polygon with two collinear boundary edges apart by a gap of 1
// (x in [0, 1] and [2, 4] on y = 0), every other clearance also 1.
// Below 1 the loop is clear (the collinear pair is told apart by its
// extents); at exactly 1 no contact exists (contacts need distance < d) but
// the test refuses by its documented relative margin of ~1e-9; above 1 it
// must refuse, and the exhaustive reference indeed reports the EE contact
// of the two collinear edges there and only there.
static void test_collinear_apart_and_clearance_at_d(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, -1, 0, 4, -1, 0, 4, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 7, 1, 5, 6, 1, 6, 7, 1, 2, 3, 1, 3, 5, 5, 3, 4};
    const uint32_t loop[] = {0, 1, 2, 3, 4, 5, 6, 7};
    patch p = make_patch(pos, 8, tri, 6);
    assert_int_equal(loop_clear(&p, loop, 8, along_z, 0.0), 1);
    assert_int_equal(loop_clear(&p, loop, 8, along_z, 0.999999), 1);
    assert_int_equal(loop_clear(&p, loop, 8, along_z, 1.0), 0);
    assert_int_equal(loop_clear(&p, loop, 8, along_z, 1.000001), 0);
    assert_int_equal(exhaustive_has_ee(p.mesh, 1.0, 0, 1, 4, 5), 0);
    assert_int_equal(exhaustive_has_ee(p.mesh, 1.000001, 0, 1, 4, 5), 1);
    free_patch(&p);
}

// The scratch comes from the caller's workspace: without memory the test
// refuses (never a false "clear"), and works again once memory returns.
static void test_no_memory_refuses(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t tri[] = {0, 1, 2, 0, 2, 3}, loop[] = {0, 1, 2, 3};
    patch p = make_patch(pos, 4, tri, 2);
    selfcol_workspace__free(&p.scratch);
    test_allocator_state alloc = {0};
    const selfcol_allocator counted = test_allocator(&alloc);
    selfcol_workspace__init(&p.scratch, &counted);
    uint32_t he[4];
    for (size_t i = 0; i < 4; ++i)
        he[i] = half_edge(p.mesh, loop[i], loop[(i + 1) % 4]);
    alloc.fail_at = alloc.calls + 1;
    assert_int_equal(selfcol_contour__loop_clear(p.mesh, he, 4, along_z, 0.0, SELFCOL_CONTOUR_AUTO,
                                                 &p.scratch, &p.stats),
                     0);
    alloc.fail_at = 0;
    assert_int_equal(selfcol_contour__loop_clear(p.mesh, he, 4, along_z, 0.0, SELFCOL_CONTOUR_AUTO,
                                                 &p.scratch, &p.stats),
                     1);
    free_patch(&p);
    assert_int_equal(alloc.live, 0);
}

// Condition (4) between edges that are neither consecutive nor collinear:
// a notch from the top whose tip (vertex 4, at (1.6, 0.5)) comes within 0.5
// of the bottom edge 0 -> 1. Every other vertex is at least 0.79 from the
// edges not incident to it, so the loop is clear below 0.5 and refused above.
static void test_vertex_near_a_far_edge(void **state) {
    (void)state;
    const double pos[] = {0, 0, 0, 3, 0, 0, 3, 3, 0, 2, 3, 0, 1.6, 0.5, 0, 1.2, 3, 0, 0, 3, 0};
    const uint32_t tri[] = {0, 1, 4, 1, 2, 3, 1, 3, 4, 0, 4, 5, 0, 5, 6};
    const uint32_t loop[] = {0, 1, 2, 3, 4, 5, 6};
    patch p = make_patch(pos, 7, tri, 5);
    assert_int_equal(loop_clear(&p, loop, 7, along_z, 0.0), 1);
    assert_int_equal(loop_clear(&p, loop, 7, along_z, 0.45), 1);
    assert_int_equal(loop_clear(&p, loop, 7, along_z, 0.55), 0);
    free_patch(&p);
}

// Deterministic pseudo-random numbers in [0, 1).
static double next_uniform(uint64_t *state) {
    *state = *state * 6364136223846793005u + 1442695040888963407u;
    return (double)(*state >> 11) * 0x1p-53;
}

// The fan's whole criterion where the loop is clear: every normal within
// theta < pi/2 of v (1) and d <= (smallest altitude) cos(theta) (3). Then
// the exhaustive reference must find no contact in the fan. 1 when it was
// checked.
static int fan_proof_is_sound(patch *p, const double *pos, const uint32_t *tri, size_t n,
                              const double v[3], double d) {
    double lowest_cos = 1.0, lowest_altitude = INFINITY;
    for (size_t t = 0; t < n; ++t) {
        const double *a = &pos[3 * tri[3 * t]], *b = &pos[3 * tri[3 * t + 1]],
                     *c = &pos[3 * tri[3 * t + 2]];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
               w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double nrm[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                         u[0] * w[1] - u[1] * w[0]};
        double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        double cosine = (nrm[0] * v[0] + nrm[1] * v[1] + nrm[2] * v[2]) / len;
        lowest_cos = cosine < lowest_cos ? cosine : lowest_cos;
        const double *corner[3] = {a, b, c};
        for (int i = 0; i < 3; ++i) {
            const double *e0 = corner[(i + 1) % 3], *e1 = corner[(i + 2) % 3];
            double side =
                sqrt((e1[0] - e0[0]) * (e1[0] - e0[0]) + (e1[1] - e0[1]) * (e1[1] - e0[1]) +
                     (e1[2] - e0[2]) * (e1[2] - e0[2]));
            lowest_altitude = len / side < lowest_altitude ? len / side : lowest_altitude;
        }
    }
    // A margin of 1e-6 keeps this check away from the criterion's own
    // rounding bounds.
    if (!(lowest_cos > 1e-6) || !(d <= lowest_altitude * lowest_cos * (1.0 - 1e-6)))
        return 0;
    selfcol_hierarchy *h = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, p->mesh, NULL), SELFCOL_OK);
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = SELFCOL_METHOD_EXHAUSTIVE;
    o.distance = d;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    if (selfcol_contacts_count(c) != 0)
        fail_msg("%zu-edge fan proven clear at d = %g, but the reference finds %zu contacts", n, d,
                 selfcol_contacts_count(c));
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    return 1;
}

// The grid and the all-pairs search decide the same on random loops: the
// boundaries of fans around a centre whose rim wanders in angle (enough to
// cross itself now and then), radius and height, from 3 to 300 edges (both
// sides of the size at which AUTO switches), at d from 0 to a few edge
// lengths, along tilted directions. Both answers occur, so the comparison
// covers refusals as well as proofs. Where the loop is clear and the rest of
// the criterion holds too, the exhaustive reference confirms the proof.
static void test_grid_and_all_pairs_agree_on_random_loops(void **state) {
    (void)state;
    enum { MAX_RIM = 300 };
    static double pos[3 * (MAX_RIM + 1)];
    static uint32_t tri[3 * MAX_RIM], he[MAX_RIM];
    uint64_t rng = 12345;
    size_t clear = 0, refused = 0, confirmed = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const size_t n = 3 + (size_t)(next_uniform(&rng) * (trial % 4 == 0 ? MAX_RIM - 3 : 60));
        const double step = 2.0 * 3.141592653589793 / (double)n;
        const double wander = next_uniform(&rng) * 1.6, bumps = next_uniform(&rng) * 0.6,
                     height = next_uniform(&rng) * 0.5;
        pos[0] = pos[1] = pos[2] = 0.0; // the centre
        for (size_t i = 0; i < n; ++i) {
            double angle = step * ((double)i + wander * (next_uniform(&rng) - 0.5));
            double radius = 1.0 + bumps * (next_uniform(&rng) - 0.5);
            double *x = &pos[3 * (i + 1)];
            x[0] = radius * cos(angle);
            x[1] = radius * sin(angle);
            x[2] = height * (next_uniform(&rng) - 0.5);
            tri[3 * i] = 0;
            tri[3 * i + 1] = (uint32_t)(i + 1);
            tri[3 * i + 2] = (uint32_t)((i + 1) % n + 1);
        }
        patch p = make_patch(pos, n + 1, tri, n);
        for (size_t i = 0; i < n; ++i)
            he[i] = half_edge(p.mesh, (uint32_t)(i + 1), (uint32_t)((i + 1) % n + 1));
        const double v[3] = {0.3 * (next_uniform(&rng) - 0.5), 0.3 * (next_uniform(&rng) - 0.5),
                             1.0};
        const double length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        const double unit[3] = {v[0] / length, v[1] / length, v[2] / length};
        const double distances[] = {0.0, 0.05 * step, 0.3 * step, 2.0 * step};
        for (size_t k = 0; k < sizeof distances / sizeof *distances; ++k) {
            if (half_edges_clear(&p, he, n, unit, distances[k])) {
                ++clear;
                confirmed += fan_proof_is_sound(&p, pos, tri, n, unit, distances[k]);
            } else
                ++refused;
        }
        free_patch(&p);
    }
    assert_true(clear > 100);
    assert_true(refused > 100);
    assert_true(confirmed > 50);
}

// The whole criterion on a flat U: a 9 x 6 unit grid without the cells of
// column 4 above row 0, so two arms face each other across a slot of width
// 1; a disk, consistently oriented, normals all +z. At every d of a sweep a
// skip is allowed only if the exhaustive reference finds no contact; below
// every altitude (1/sqrt 2) and the slot's width the proof goes through.
static void test_self_skippable_is_sound_on_a_flat_u(void **state) {
    (void)state;
    enum { NX = 9, NY = 6 };
    double pos[3 * (NX + 1) * (NY + 1)];
    uint32_t tri[6 * NX * NY];
    // t counts triangles; each cell adds two.
    size_t t = 0;
    for (unsigned i = 0; i <= NX; ++i)
        for (unsigned j = 0; j <= NY; ++j) {
            double *x = &pos[3 * (i * (NY + 1) + j)];
            x[0] = i, x[1] = j, x[2] = 0.0;
        }
    for (uint32_t i = 0; i < NX; ++i)
        for (uint32_t j = 0; j < NY; ++j) {
            if (i == 4 && j >= 1)
                continue; // the slot
            const uint32_t a = i * (NY + 1) + j, b = a + NY + 1;
            const uint32_t cell[6] = {a, b, b + 1, a, b + 1, a + 1};
            for (int k = 0; k < 6; ++k)
                tri[3 * t + k] = cell[k];
            t += 2;
        }
    patch p = make_patch(pos, (NX + 1) * (NY + 1), tri, t);
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, p.mesh, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    assert_true(h->nodes[0].child_count > 0);
    const double sweep[] = {0.0, 0.1, 0.3, 0.5, 0.7, 0.70711, 0.8, 0.99, 1.0, 1.01, 1.5, 3.0};
    for (size_t i = 0; i < sizeof sweep / sizeof *sweep; ++i) {
        selfcol_query_options o;
        selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
        o.method = SELFCOL_METHOD_EXHAUSTIVE;
        o.distance = sweep[i];
        assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
        const int skippable = selfcol_contour__self_skippable(h, 0, sweep[i], &p.scratch, &p.stats);
        if (skippable && selfcol_contacts_count(c) != 0)
            fail_msg("d = %g: skipped, but %zu contacts exist", sweep[i],
                     selfcol_contacts_count(c));
        if (sweep[i] <= 0.5)
            assert_int_equal(skippable, 1);
    }
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    free_patch(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square),
        cmocka_unit_test(test_pinch),
        cmocka_unit_test(test_crossing),
        cmocka_unit_test(test_fold_back),
        cmocka_unit_test(test_straight_continuation),
        cmocka_unit_test(test_collinear_overlap),
        cmocka_unit_test(test_collinear_apart_and_clearance_at_d),
        cmocka_unit_test(test_no_memory_refuses),
        cmocka_unit_test(test_vertex_near_a_far_edge),
        cmocka_unit_test(test_grid_and_all_pairs_agree_on_random_loops),
        cmocka_unit_test(test_self_skippable_is_sound_on_a_flat_u),
    };
    return cmocka_run_group_tests_name("contour", tests, NULL, NULL);
}
