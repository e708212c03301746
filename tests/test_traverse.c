// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The hierarchy traversal (lib/query/traverse.c) through the public API and the
// query statistics: what each method examines and culls, held to what can be
// derived by hand or by a brute force over the triangles' boxes, never to
// numbers copied from a run.
// - BVH examines exactly the triangle pairs whose boxes are within d (a
//   brute force over all pairs counts them), self and between two meshes;
// - SEED, CONE and EXACT only add culling to BVH's walk: they visit a subset
//   of its node pairs, and between two meshes (nothing adjacent) they walk
//   exactly as BVH does, counter for counter;
// - EXACT culls a flat sheet at its root (also turned about an oblique
//   axis), but opens one that holds contacts (d above the half diagonal),
//   where SEED and CONE, stopping at the root, miss them all;
// - two meshes whose boxes are farther apart than d stop at the root pair;
// - EXACT, like the other hierarchy methods, is stale until refit, and after
//   the refit of a sheet built flat and then crumpled it returns the
//   exhaustive set; EXACT between two meshes returns the exhaustive set.
// Held elsewhere, not repeated here: BVH and EXACT against EXHAUSTIVE on the
// self queries of every fixture, SEED and CONE misses (test_hierarchy.c),
// N threads = 1 thread, records and counters (test_threads.c), the filters'
// counters of version 4 (test_pairs.c).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "contact_keys.h"
#include "fixtures.h"
#include "world.h"

static const char *method_name(uint32_t method) {
    static const char *names[] = {"EXHAUSTIVE", "BVH", "SEED", "CONE", "EXACT"};
    return method < 5 ? names[method] : "?";
}

// One query: self when b is NULL, else a against b (contacts into a's set).
static int run(const world *a, const world *b, uint32_t method, double d) {
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = method;
    q.distance = d;
    return b == NULL ? selfcol_hierarchy_self_collide(a->hierarchy, a->contacts, &q)
                     : selfcol_hierarchy_collide(a->hierarchy, b->hierarchy, a->contacts, &q);
}

static void run_ok(const world *a, const world *b, uint32_t method, double d) {
    int status = run(a, b, method, d);
    if (status != SELFCOL_OK)
        fail_msg("%s query: %s", method_name(method), selfcol_status_string(status));
}

static selfcol_query_stats stats_of(const selfcol_contacts *c) {
    selfcol_query_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(c, &st), SELFCOL_OK);
    return st;
}

// The box of triangle t of s.
static void triangle_box(const fixture *s, size_t t, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int c = 0; c < 3; ++c) {
        const double *p = s->positions + 3 * s->triangles[3 * t + c];
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
}

// 1 when no axis separates the boxes by more than d.
static int boxes_near(const double alo[3], const double ahi[3], const double blo[3],
                      const double bhi[3], double d) {
    for (int k = 0; k < 3; ++k)
        if (alo[k] - d > bhi[k] || blo[k] - d > ahi[k])
            return 0;
    return 1;
}

// Brute force: the triangle pairs (unordered within one mesh; every pair of
// a triangle of a and one of b between two) whose boxes are within d.
static uint64_t near_triangle_pairs(const fixture *a, const fixture *b, double d) {
    const fixture *other = b ? b : a;
    uint64_t n = 0;
    for (size_t i = 0; i < a->triangle_count; ++i) {
        double alo[3], ahi[3];
        triangle_box(a, i, alo, ahi);
        for (size_t j = b ? 0 : i + 1; j < other->triangle_count; ++j) {
            double blo[3], bhi[3];
            triangle_box(other, j, blo, bhi);
            n += (uint64_t)boxes_near(alo, ahi, blo, bhi, d);
        }
    }
    return n;
}

// The keys of method's result equal EXHAUSTIVE's.
static void assert_exact(const world *a, const world *b, uint32_t method, double d,
                         const char *name) {
    size_t n_ref, n_got;
    run_ok(a, b, SELFCOL_METHOD_EXHAUSTIVE, d);
    contact_key *ref = contact_keys_of(a->contacts, &n_ref);
    run_ok(a, b, method, d);
    contact_key *got = contact_keys_of(a->contacts, &n_got);
    if (!contact_keys_equal(ref, n_ref, got, n_got))
        fail_msg("%s, d = %g: %s differs from EXHAUSTIVE (%zu vs %zu contacts)", name, d,
                 method_name(method), n_got, n_ref);
    free(ref);
    free(got);
}

// BVH culls by boxes only, and its node boxes hold their triangles' boxes:
// it must examine every triangle pair whose boxes are within d, and no other
// (each once). Every examined pair is either separated by a plane or tested.
static void check_bvh_pairs(const fixture *sa, const fixture *sb, const char *name) {
    world a, b;
    world_make(&a, sa);
    if (sb)
        world_make(&b, sb);
    const double mean = selfcol_mesh_mean_edge_length(a.mesh);
    const double factors[3] = {0.0, 0.1, 0.5};
    for (int di = 0; di < 3; ++di) {
        const double d = factors[di] * mean;
        run_ok(&a, sb ? &b : NULL, SELFCOL_METHOD_BVH, d);
        selfcol_query_stats st = stats_of(a.contacts);
        const uint64_t expected = near_triangle_pairs(sa, sb, d);
        if (st.triangle_pairs != expected)
            fail_msg("%s, d = %.1f x mean edge: BVH examined %llu triangle pairs, the boxes of "
                     "%llu are within d",
                     name, factors[di], (unsigned long long)st.triangle_pairs,
                     (unsigned long long)expected);
        assert_true(expected > 0);
        assert_true(st.pairs_separated <= st.triangle_pairs);
        assert_true(st.nodes_visited > st.culled_box);
        // Box culling only.
        assert_int_equal(st.culled_curvature, 0);
        assert_int_equal(st.culled_adjacency, 0);
    }
    if (sb)
        world_free(&b);
    world_free(&a);
}

static void test_bvh_examines_exactly_the_pairs_whose_boxes_meet(void **state) {
    (void)state;
    fixture s, t;
    assert_int_equal(fixture_crumpled(&s, 14, 10, 1, 5.0), 0);
    check_bvh_pairs(&s, NULL, "crumpled 14x10");
    fixture_free(&s);
    assert_int_equal(fixture_zfold(&s, 10, 4, 0.1, 1, 0.25), 0);
    check_bvh_pairs(&s, NULL, "z-fold");
    fixture_free(&s);
    assert_int_equal(fixture_hairpin(&s, 12, 0.05), 0);
    check_bvh_pairs(&s, NULL, "hairpin");
    fixture_free(&s);
    assert_int_equal(fixture_grid(&s, 12, 9, 1.0), 0);
    check_bvh_pairs(&s, NULL, "flat grid");
    fixture_free(&s);
    assert_int_equal(fixture_sheet_pair(&s, &t, 10, 4, 1.0, 0.0), 0);
    check_bvh_pairs(&s, &t, "crossing sheets");
    check_bvh_pairs(&t, &s, "crossing sheets, swapped");
    fixture_free(&s);
    fixture_free(&t);
}

// SEED, CONE and EXACT walk BVH's tree and only return early where they
// cull: the node pairs they visit, the triangle pairs they examine and the
// primitive tests they make are subsets of BVH's.
static void check_subset_of_bvh(const fixture *s, const char *name) {
    world w;
    world_make(&w, s);
    const double mean = selfcol_mesh_mean_edge_length(w.mesh);
    const double factors[2] = {0.1, 0.5};
    for (int di = 0; di < 2; ++di) {
        const double d = factors[di] * mean;
        run_ok(&w, NULL, SELFCOL_METHOD_BVH, d);
        const selfcol_query_stats bvh = stats_of(w.contacts);
        for (uint32_t m = SELFCOL_METHOD_SEED; m <= SELFCOL_METHOD_EXACT; ++m) {
            run_ok(&w, NULL, m, d);
            const selfcol_query_stats st = stats_of(w.contacts);
            if (st.nodes_visited > bvh.nodes_visited || st.triangle_pairs > bvh.triangle_pairs ||
                st.culled_box > bvh.culled_box || st.vf_tests > bvh.vf_tests ||
                st.ee_tests > bvh.ee_tests || st.ef_tests > bvh.ef_tests)
                fail_msg("%s, d = %.1f x mean edge: %s examined more than BVH (nodes %llu vs "
                         "%llu, triangle pairs %llu vs %llu)",
                         name, factors[di], method_name(m), (unsigned long long)st.nodes_visited,
                         (unsigned long long)bvh.nodes_visited,
                         (unsigned long long)st.triangle_pairs,
                         (unsigned long long)bvh.triangle_pairs);
            assert_true(st.pairs_separated <= st.triangle_pairs);
            assert_true(st.culled_box + st.culled_curvature + st.culled_adjacency <=
                        st.nodes_visited);
            // What it skipped, it skipped by its criteria: fewer nodes than
            // BVH only if something was culled by curvature or adjacency.
            if (st.nodes_visited < bvh.nodes_visited)
                assert_true(st.culled_curvature + st.culled_adjacency > 0);
        }
    }
    world_free(&w);
}

static void test_culling_methods_visit_a_subset_of_bvh(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 20, 14, 3, 5.0), 0);
    check_subset_of_bvh(&s, "crumpled 20x14");
    fixture_free(&s);
    assert_int_equal(fixture_wrinkled(&s, 24, 20, 2, 1.0), 0);
    check_subset_of_bvh(&s, "wrinkled 24x20");
    fixture_free(&s);
    assert_int_equal(fixture_zfold(&s, 16, 4, 0.1, 2, 0.0), 0);
    check_subset_of_bvh(&s, "z-fold");
    fixture_free(&s);
    assert_int_equal(fixture_ramp(&s, 3, 28, 3.0, 1.0, -0.3), 0);
    check_subset_of_bvh(&s, "ramp");
    fixture_free(&s);
}

// Between two meshes no patch is adjacent to one of the other and no node
// is paired with itself: every method walks exactly as BVH does.
static void test_two_mesh_queries_walk_as_bvh_for_every_method(void **state) {
    (void)state;
    fixture sa, sb;
    assert_int_equal(fixture_draped_cloth(&sa, 12, 3.0, 2.0, 0.05, 0.12), 0);
    assert_int_equal(fixture_icosphere(&sb, 2, 2.0), 0);
    world a, b;
    world_make(&a, &sa);
    world_make(&b, &sb);
    const double d = 0.1 * selfcol_mesh_mean_edge_length(a.mesh);
    run_ok(&a, &b, SELFCOL_METHOD_BVH, d);
    selfcol_query_stats bvh = stats_of(a.contacts);
    assert_true(bvh.culled_box > 0 && bvh.triangle_pairs > 0);
    assert_true(selfcol_contacts_count(a.contacts) > 0);
    for (uint32_t m = SELFCOL_METHOD_SEED; m <= SELFCOL_METHOD_EXACT; ++m) {
        run_ok(&a, &b, m, d);
        selfcol_query_stats st = stats_of(a.contacts);
        assert_int_equal(st.nodes_visited, bvh.nodes_visited);
        assert_int_equal(st.culled_box, bvh.culled_box);
        assert_int_equal(st.culled_curvature, 0);
        assert_int_equal(st.culled_adjacency, 0);
        assert_int_equal(st.triangle_pairs, bvh.triangle_pairs);
        assert_int_equal(st.pairs_separated, bvh.pairs_separated);
        assert_int_equal(st.primitives_filtered, bvh.primitives_filtered);
        assert_int_equal(st.vf_tests, bvh.vf_tests);
        assert_int_equal(st.ee_tests, bvh.ee_tests);
        assert_int_equal(st.ef_tests, bvh.ef_tests);
        assert_int_equal(st.contour_tests, 0);
    }
    world_free(&a);
    world_free(&b);
    fixture_free(&sa);
    fixture_free(&sb);
}

// Rotation by angle about the unit axis k.
static void rotate(fixture *s, const double k[3], double angle) {
    const double c = cos(angle), sn = sin(angle);
    for (size_t v = 0; v < s->vertex_count; ++v) {
        double *p = s->positions + 3 * v;
        double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
        double x[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2],
                       k[0] * p[1] - k[1] * p[0]};
        for (int j = 0; j < 3; ++j)
            p[j] = p[j] * c + x[j] * sn + k[j] * kp * (1.0 - c);
    }
}

static int key_compare(const void *pa, const void *pb) {
    const contact_key *a = pa, *b = pb;
    for (int i = 0; i < 6; ++i)
        if (a->k[i] != b->k[i])
            return a->k[i] < b->k[i] ? -1 : 1;
    return 0;
}

// A flat unit grid is one disk whose normals are all equal, its projected
// boundary a rectangle, its least altitude the half diagonal 1 / sqrt(2) =
// 0.707 and its mean edge (2 + sqrt(2)) / 3 = 1.14, so below d = 0.5 x mean
// edge = 0.57 EXACT proves it free at the root: one node visited, culled by
// curvature, no triangle pair, no test. BVH cannot: it examines every pair
// of triangles whose boxes meet (adjacent triangles' boxes touch).
static void test_exact_culls_a_flat_grid_at_the_root(void **state) {
    (void)state;
    const double axis[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
    for (int turned = 0; turned < 2; ++turned) {
        fixture s;
        assert_int_equal(fixture_grid(&s, 16, 16, 1.0), 0);
        if (turned)
            rotate(&s, axis, 0.7);
        world w;
        world_make(&w, &s);
        const double mean = selfcol_mesh_mean_edge_length(w.mesh);
        assert_true(fabs(mean - (2.0 + sqrt(2.0)) / 3.0) < 0.05);
        const double factors[3] = {0.0, 0.1, 0.5};
        for (int di = 0; di < 3; ++di) {
            const double d = factors[di] * mean;
            run_ok(&w, NULL, SELFCOL_METHOD_EXACT, d);
            selfcol_query_stats st = stats_of(w.contacts);
            if (st.nodes_visited != 1 || st.culled_curvature != 1)
                fail_msg("flat grid%s, d = %.1f x mean edge: EXACT visited %llu nodes, culled "
                         "%llu by curvature (the root alone expected)",
                         turned ? " (turned)" : "", factors[di],
                         (unsigned long long)st.nodes_visited,
                         (unsigned long long)st.culled_curvature);
            assert_int_equal(st.triangle_pairs, 0);
            assert_int_equal(st.pairs_separated, 0);
            assert_int_equal(st.vf_tests + st.ee_tests + st.ef_tests, 0);
            assert_int_equal(st.contour_tests, 1);
            assert_int_equal(st.contour_refused, 0);
            assert_int_equal(selfcol_contacts_count(w.contacts), 0);

            run_ok(&w, NULL, SELFCOL_METHOD_BVH, d);
            st = stats_of(w.contacts);
            assert_int_equal(st.culled_curvature, 0);
            assert_true(st.nodes_visited > 1);
            assert_int_equal(st.triangle_pairs, near_triangle_pairs(&s, NULL, d));
            assert_true(st.triangle_pairs >= s.triangle_count); // each has a neighbour
            assert_int_equal(selfcol_contacts_count(w.contacts), 0);
        }
        world_free(&w);
        fixture_free(&s);
    }
}

// Above the half diagonal the flat grid holds contacts: in every cell,
// split along (i, j)-(i+1, j+1), the corner (i, j+1) is 1 / sqrt(2) from
// the triangle (i, j), (i+1, j), (i+1, j+1), and the corner (i+1, j) from
// the triangle (i, j), (i+1, j+1), (i, j+1). At d = 0.8 EXACT must open the
// sheet and return the exhaustive set, these VF pairs among it; SEED and
// CONE, whose criterion ignores d, stop at the root and miss them all (their
// documented limit: proximities inside a smooth patch).
static void test_exact_opens_a_flat_grid_that_holds_contacts(void **state) {
    (void)state;
    const unsigned nx = 8, ny = 6;
    fixture s;
    assert_int_equal(fixture_grid(&s, nx, ny, 1.0), 0);
    world w;
    world_make(&w, &s);
    const double d = 0.8;
    assert_exact(&w, NULL, SELFCOL_METHOD_EXACT, d, "flat grid 8x6");
    selfcol_query_stats st = stats_of(w.contacts);
    assert_true(st.nodes_visited > 1);
    assert_true(st.triangle_pairs > 0);
    size_t n;
    contact_key *keys = contact_keys_of(w.contacts, &n);
#define V(i, j) ((uint32_t)((i) * (ny + 1) + (j)))
    for (unsigned i = 0; i < nx; ++i)
        for (unsigned j = 0; j < ny; ++j) {
            const uint32_t pairs[2][4] = {{V(i, j + 1), V(i, j), V(i + 1, j), V(i + 1, j + 1)},
                                          {V(i + 1, j), V(i, j), V(i + 1, j + 1), V(i, j + 1)}};
            for (int p = 0; p < 2; ++p) {
                contact_key k;
                selfcol_contact c;
                memset(&c, 0, sizeof c);
                c.kind = SELFCOL_CONTACT_VF;
                c.a[0] = c.a[1] = pairs[p][0];
                memcpy(c.b, pairs[p] + 1, sizeof c.b);
                const uint32_t offset[2] = {0, 0};
                contact_keys(&c, 1, NULL, offset, &k);
                if (bsearch(&k, keys, n, sizeof k, key_compare) == NULL)
                    fail_msg("cell (%u, %u): VF (%u | %u %u %u) missing", i, j, pairs[p][0],
                             pairs[p][1], pairs[p][2], pairs[p][3]);
            }
        }
#undef V
    assert_true(n >= 2 * nx * ny);
    free(keys);
    for (uint32_t m = SELFCOL_METHOD_SEED; m <= SELFCOL_METHOD_CONE; ++m) {
        run_ok(&w, NULL, m, d);
        st = stats_of(w.contacts);
        assert_int_equal(st.nodes_visited, 1);
        assert_int_equal(st.culled_curvature, 1);
        assert_int_equal(selfcol_contacts_count(w.contacts), 0);
    }
    world_free(&w);
    fixture_free(&s);
}

// Two meshes whose boxes are farther apart than d on some axis: the root
// pair is the only node pair visited, culled by its boxes, nothing examined,
// for every method and either order. Brought within d of each other the
// root pair must be opened.
static void test_far_apart_meshes_stop_at_the_root_pair(void **state) {
    (void)state;
    fixture sa, sb;
    assert_int_equal(fixture_crumpled(&sa, 12, 9, 7, 5.0), 0);
    assert_int_equal(fixture_crumpled(&sb, 9, 12, 8, 5.0), 0);
    double alo[3], ahi[3], blo[3], bhi[3];
    for (int k = 0; k < 3; ++k) {
        alo[k] = blo[k] = INFINITY;
        ahi[k] = bhi[k] = -INFINITY;
    }
    for (size_t v = 0; v < sa.vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            alo[k] = fmin(alo[k], sa.positions[3 * v + k]);
            ahi[k] = fmax(ahi[k], sa.positions[3 * v + k]);
        }
    for (size_t v = 0; v < sb.vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            blo[k] = fmin(blo[k], sb.positions[3 * v + k]);
            bhi[k] = fmax(bhi[k], sb.positions[3 * v + k]);
        }
    const double d = 0.5;
    // b's lowest z 3 d above a's highest: apart along z only.
    const double lift[3] = {0.0, 0.0, ahi[2] - blo[2] + 3.0 * d};
    fixture_translate(&sb, lift);
    world a, b;
    world_make(&a, &sa);
    world_make(&b, &sb);
    for (uint32_t m = SELFCOL_METHOD_BVH; m <= SELFCOL_METHOD_EXACT; ++m)
        for (int order = 0; order < 2; ++order) {
            const world *first = order ? &b : &a, *second = order ? &a : &b;
            run_ok(first, second, m, d);
            selfcol_query_stats st = stats_of(first->contacts);
            if (st.nodes_visited != 1 || st.culled_box != 1)
                fail_msg("%s: %llu node pairs visited, %llu culled by box (the root pair alone "
                         "expected)",
                         method_name(m), (unsigned long long)st.nodes_visited,
                         (unsigned long long)st.culled_box);
            assert_int_equal(st.triangle_pairs, 0);
            assert_int_equal(st.vf_tests + st.ee_tests + st.ef_tests, 0);
            assert_int_equal(selfcol_contacts_count(first->contacts), 0);
        }
    // Now 0.5 d apart along z: the root boxes are within d.
    const double lower[3] = {0.0, 0.0, -2.5 * d};
    fixture_translate(&sb, lower);
    assert_int_equal(selfcol_mesh_set_positions(b.mesh, sb.positions, sb.vertex_count), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_refit(b.hierarchy), SELFCOL_OK);
    for (uint32_t m = SELFCOL_METHOD_BVH; m <= SELFCOL_METHOD_EXACT; ++m) {
        run_ok(&a, &b, m, d);
        selfcol_query_stats st = stats_of(a.contacts);
        assert_true(st.nodes_visited > 1);
        assert_exact(&a, &b, m, d, "crumpled sheets 0.5 d apart");
    }
    world_free(&a);
    world_free(&b);
    fixture_free(&sa);
    fixture_free(&sb);
}

// A sheet built flat (which EXACT culls at the root) and then crumpled:
// every hierarchy method, EXACT included, refuses the moved mesh until the
// refit, self and against another mesh; after it EXACT returns the
// exhaustive set of the new positions (its culling follows the refit, not
// the build).
static void test_exact_is_stale_until_refit_then_exact_again(void **state) {
    (void)state;
    const unsigned nx = 14, ny = 10;
    fixture flat, crumpled, other;
    assert_int_equal(fixture_crumpled(&flat, nx, ny, 5, 0.0), 0);
    assert_int_equal(fixture_crumpled(&crumpled, nx, ny, 5, 5.0), 0);
    assert_int_equal(fixture_grid(&other, 4, 4, 1.0), 0);
    world w, o;
    world_make(&w, &flat);
    world_make(&o, &other);
    const double d = 0.1 * selfcol_mesh_mean_edge_length(w.mesh);
    run_ok(&w, NULL, SELFCOL_METHOD_EXACT, d);
    assert_int_equal(stats_of(w.contacts).nodes_visited, 1); // flat: culled at the root
    assert_int_equal(selfcol_mesh_set_positions(w.mesh, crumpled.positions, crumpled.vertex_count),
                     SELFCOL_OK);
    for (uint32_t m = SELFCOL_METHOD_BVH; m <= SELFCOL_METHOD_EXACT; ++m) {
        assert_int_equal(run(&w, NULL, m, d), SELFCOL_ESTALE);
        assert_int_equal(run(&w, &o, m, d), SELFCOL_ESTALE);
        assert_int_equal(run(&o, &w, m, d), SELFCOL_ESTALE);
    }
    run_ok(&w, NULL, SELFCOL_METHOD_EXHAUSTIVE, d);
    assert_true(selfcol_contacts_count(w.contacts) > 0);
    assert_int_equal(selfcol_hierarchy_refit(w.hierarchy), SELFCOL_OK);
    assert_exact(&w, NULL, SELFCOL_METHOD_EXACT, d, "crumpled after a flat build");
    assert_exact(&w, NULL, SELFCOL_METHOD_EXACT, 0.5 * selfcol_mesh_mean_edge_length(w.mesh),
                 "crumpled after a flat build");
    assert_true(stats_of(w.contacts).nodes_visited > 1);
    world_free(&w);
    world_free(&o);
    fixture_free(&flat);
    fixture_free(&crumpled);
    fixture_free(&other);
}

// EXACT between two meshes is the exhaustive set (test_hierarchy.c holds
// BVH, SEED and CONE there).
static void test_exact_between_two_meshes_is_exhaustive(void **state) {
    (void)state;
    fixture pairs[3][2];
    assert_int_equal(fixture_draped_cloth(&pairs[0][0], 12, 3.0, 2.0, 0.05, 0.12), 0);
    assert_int_equal(fixture_icosphere(&pairs[0][1], 2, 2.0), 0);
    assert_int_equal(fixture_crumpled(&pairs[1][0], 12, 9, 7, 5.0), 0);
    assert_int_equal(fixture_crumpled(&pairs[1][1], 9, 12, 8, 5.0), 0);
    const double shift[3] = {2.5, 1.5, 0.5};
    fixture_translate(&pairs[1][1], shift);
    assert_int_equal(fixture_sheet_pair(&pairs[2][0], &pairs[2][1], 10, 4, 1.0, 0.0), 0);
    const char *names[3] = {"cloth over sphere", "two crumpled sheets", "crossing sheets"};
    for (int i = 0; i < 3; ++i) {
        world a, b;
        world_make(&a, &pairs[i][0]);
        world_make(&b, &pairs[i][1]);
        const double mean = selfcol_mesh_mean_edge_length(a.mesh);
        assert_exact(&a, &b, SELFCOL_METHOD_EXACT, 0.0, names[i]);
        assert_exact(&a, &b, SELFCOL_METHOD_EXACT, 0.1 * mean, names[i]);
        assert_exact(&a, &b, SELFCOL_METHOD_EXACT, 0.5 * mean, names[i]);
        assert_true(selfcol_contacts_count(a.contacts) > 0);
        assert_exact(&b, &a, SELFCOL_METHOD_EXACT, 0.5 * mean, names[i]);
        world_free(&a);
        world_free(&b);
        fixture_free(&pairs[i][0]);
        fixture_free(&pairs[i][1]);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bvh_examines_exactly_the_pairs_whose_boxes_meet),
        cmocka_unit_test(test_culling_methods_visit_a_subset_of_bvh),
        cmocka_unit_test(test_two_mesh_queries_walk_as_bvh_for_every_method),
        cmocka_unit_test(test_exact_culls_a_flat_grid_at_the_root),
        cmocka_unit_test(test_exact_opens_a_flat_grid_that_holds_contacts),
        cmocka_unit_test(test_far_apart_meshes_stop_at_the_root_pair),
        cmocka_unit_test(test_exact_is_stale_until_refit_then_exact_again),
        cmocka_unit_test(test_exact_between_two_meshes_is_exhaustive),
    };
    return cmocka_run_group_tests_name("traverse", tests, NULL, NULL);
}
