// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The exhaustive reference, through the public API, on scenes whose contact
// sets are derived by hand (from the construction, not from the library).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "contact_keys.h"
#include "fixtures.h"
#include "test_alloc.h"
#include "world.h"

static const selfcol_contact *run_self(world *w, double d, uint32_t narrow, size_t *count) {
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.distance = d;
    q.narrow = narrow;
    assert_int_equal(selfcol_hierarchy_self_collide(w->hierarchy, w->contacts, &q), SELFCOL_OK);
    const selfcol_contact *c;
    assert_int_equal(selfcol_contacts_data(w->contacts, &c, count), SELFCOL_OK);
    return c;
}

static size_t count_kind(const selfcol_contact *c, size_t n, uint32_t kind) {
    size_t k = 0;
    for (size_t i = 0; i < n; ++i)
        k += (c[i].kind == kind);
    return k;
}

// Flat grid: the closest non-adjacent primitives are a vertex and the diagonal
// of a neighbouring cell, h / sqrt(2) apart; nothing crosses.
static void test_exhaustive_flat_grid_has_no_contacts_below_half_diagonal(void **state) {
    (void)state;
    const double h = 0.25;
    fixture g;
    assert_int_equal(fixture_grid(&g, 8, 6, h), 0);
    world w;
    world_make(&w, &g);
    size_t n;
    run_self(&w, 0.1 * h, SELFCOL_NARROW_CLOSED_FORM, &n);
    assert_int_equal(n, 0);
    run_self(&w, 0.7 * h, SELFCOL_NARROW_CLOSED_FORM, &n);
    assert_int_equal(n, 0);
    // Just above h / sqrt(2) the vertex-diagonal pairs appear: each diagonal
    // (i,j)-(i+1,j+1) is that close to (i+1,j) and (i,j+1) when these are not
    // its triangle's corners -- i.e. to the corners of the neighbouring cells'
    // triangles; all reported pairs are at exactly h / sqrt(2).
    const selfcol_contact *c = run_self(&w, 0.71 * h, SELFCOL_NARROW_CLOSED_FORM, &n);
    assert_true(n > 0);
    assert_int_equal(count_kind(c, n, SELFCOL_CONTACT_EF), 0);
    for (size_t i = 0; i < n; ++i)
        assert_true(fabs(c[i].distance - h / sqrt(2.0)) < 1e-12);
    world_free(&w);
    fixture_free(&g);
}

static int has_corner(const uint32_t *tri, uint32_t v) {
    return tri[0] == v || tri[1] == v || tri[2] == v;
}

static int edges_touch(const uint32_t *e, const uint32_t *f) {
    return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
}

// Hairpin: two layers `gap` apart, the top exactly above the bottom. Away
// from the fold (columns <= n - 2) the contacts follow from the construction:
// a vertex is near exactly the other layer's triangles around its twin; an
// edge is near exactly the other-layer edges whose twins touch it. Nothing
// crosses anywhere.
static void test_exhaustive_hairpin_matches_hand_derived_pairs(void **state) {
    (void)state;
    const unsigned n = 6;
    const double gap = 0.1, d = 0.11;
    fixture s;
    assert_int_equal(fixture_hairpin(&s, n, gap), 0);
    world w;
    world_make(&w, &s);
    size_t count;
    const selfcol_contact *c = run_self(&w, d, SELFCOL_NARROW_CLOSED_FORM, &count);
    assert_int_equal(count_kind(c, count, SELFCOL_CONTACT_EF), 0);

    // VF: far vertices.
    size_t checked_vf = 0;
    for (uint32_t v = 0; v < s.vertex_count; ++v) {
        if (fixture_hairpin_column(n, v) > n - 2)
            continue;
        uint32_t twin = fixture_hairpin_twin(n, v);
        for (uint32_t t = 0; t < s.triangle_count; ++t) {
            int expected = has_corner(s.triangles + 3 * t, twin);
            int found = 0;
            for (size_t i = 0; i < count; ++i)
                if (c[i].kind == SELFCOL_CONTACT_VF && c[i].first == v && c[i].second == t) {
                    found = 1;
                    assert_true(fabs(c[i].distance - gap) < 1e-12);
                    assert_true(fabs(fabs(c[i].direction[2]) - 1.0) < 1e-12);
                    assert_int_equal(c[i].a[0], v);
                    assert_memory_equal(c[i].b, s.triangles + 3 * t, 3 * sizeof(uint32_t));
                }
            if (expected != found)
                fail_msg("VF vertex %u triangle %u: expected %d found %d", v, t, expected, found);
            checked_vf += (size_t)expected;
        }
    }
    // Far columns i = 0..n-2 of a layer: vertex (i,0) lies on 2 + 3 [i > 0]
    // triangles, (i,1) on 1 + 3 [i > 0], so each layer's twins carry
    // 3 + 6 (n - 2) triangles.
    assert_int_equal(checked_vf, 2 * (3 + 6 * (n - 2)));

    // EE: far edges.
    const uint32_t *edges = selfcol_mesh_edges(w.mesh);
    size_t E = selfcol_mesh_count(w.mesh, SELFCOL_MESH_EDGES);
    size_t checked_ee = 0;
    for (uint32_t e = 0; e < E; ++e) {
        const uint32_t *ev = edges + 2 * e;
        if (fixture_hairpin_column(n, ev[0]) > n - 2 || fixture_hairpin_column(n, ev[1]) > n - 2)
            continue;
        for (uint32_t f = 0; f < E; ++f) {
            const uint32_t *fv = edges + 2 * f;
            int same_layer = (ev[0] < 2 * (n + 1)) == (fv[0] < 2 * (n + 1)) &&
                             (fv[0] < 2 * (n + 1)) == (fv[1] < 2 * (n + 1));
            uint32_t twin[2] = {fixture_hairpin_twin(n, fv[0]), fixture_hairpin_twin(n, fv[1])};
            int expected = !same_layer && (fv[0] < 2 * (n + 1)) == (fv[1] < 2 * (n + 1)) &&
                           edges_touch(ev, twin);
            int found = 0;
            for (size_t i = 0; i < count; ++i)
                if (c[i].kind == SELFCOL_CONTACT_EE && ((c[i].first == e && c[i].second == f) ||
                                                        (c[i].first == f && c[i].second == e))) {
                    found = 1;
                    assert_true(c[i].first < c[i].second);
                    assert_true(fabs(c[i].distance - gap) < 1e-12);
                    assert_int_equal(c[i].b[2], SELFCOL_INVALID_INDEX);
                }
            if (expected != found)
                fail_msg("EE edge %u edge %u: expected %d found %d", e, f, expected, found);
            checked_ee += (size_t)expected;
        }
    }
    assert_true(checked_ee > 0);

    // Statistics agree with the records.
    selfcol_query_stats st;
    st.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &st), SELFCOL_OK);
    assert_int_equal(st.vf_contacts, count_kind(c, count, SELFCOL_CONTACT_VF));
    assert_int_equal(st.ee_contacts, count_kind(c, count, SELFCOL_CONTACT_EE));
    assert_int_equal(st.ef_contacts, 0);
    assert_true(st.vf_tests >= st.vf_contacts && st.candidate_pairs >= st.vf_tests);
    assert_true(st.total_seconds >= 0.0);
    world_free(&w);
    fixture_free(&s);
}

// Two unit squares crossing: A in z = 0 split along (0,2); B in x = 0.1 split
// along (4,6). Hand-derived crossings (edge, triangle), with edges numbered
// (0,1) (0,2) (0,3) (1,2) (2,3) (4,5) (4,6) (4,7) (5,6) (6,7):
//   A's diagonal (0,2) crosses B0 at (0.1, 0.1, 0), below B's diagonal z = 2y;
//   B's (4,6) crosses A0 at (0.1, 0, 0); (4,7) crosses A0 at (0.1, -0.5, 0);
//   (5,6) crosses A1 at (0.1, 0.5, 0).
static const double squares_positions[] = {-1,  -1,   0,  1,   -1,  0,  1,   1,   0, -1,  1,    0,
                                           0.1, -0.5, -1, 0.1, 0.5, -1, 0.1, 0.5, 1, 0.1, -0.5, 1};
static const uint32_t squares_triangles[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};

static void test_exhaustive_crossing_squares_report_the_crossing_edges(void **state) {
    (void)state;
    fixture s = {8, 4, (double *)squares_positions, (uint32_t *)squares_triangles};
    world w;
    world_make(&w, &s);
    size_t n;
    const selfcol_contact *c = run_self(&w, 0.0, SELFCOL_NARROW_CLOSED_FORM, &n);
    const uint32_t expected[4][2] = {{1, 2}, {6, 0}, {7, 0}, {8, 1}};
    const double crossing[4][3] = {{0.1, 0.1, 0}, {0.1, 0, 0}, {0.1, -0.5, 0}, {0.1, 0.5, 0}};
    assert_int_equal(n, 4);
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(c[i].kind, SELFCOL_CONTACT_EF);
        assert_int_equal(c[i].first, expected[i][0]);
        assert_int_equal(c[i].second, expected[i][1]);
        assert_true(c[i].distance == 0.0);
        // Both weight sets reconstruct the crossing point.
        for (int k = 0; k < 3; ++k) {
            double on_edge = c[i].wa[0] * squares_positions[3 * c[i].a[0] + k] +
                             c[i].wa[1] * squares_positions[3 * c[i].a[1] + k];
            double on_tri = 0.0;
            for (int j = 0; j < 3; ++j)
                on_tri += c[i].wb[j] * squares_positions[3 * c[i].b[j] + k];
            assert_true(fabs(on_edge - crossing[i][k]) < 1e-12);
            assert_true(fabs(on_tri - crossing[i][k]) < 1e-12);
        }
    }
    // libccd's narrow phase finds the same crossings here (all far from touching).
    c = run_self(&w, 0.0, SELFCOL_NARROW_LIBCCD, &n);
    assert_int_equal(n, 4);
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(c[i].first, expected[i][0]);
        assert_int_equal(c[i].second, expected[i][1]);
    }
    world_free(&w);
}

// The same two squares as two meshes: the same crossings, with per-mesh
// indices and mesh ids.
static void test_exhaustive_two_meshes_match_the_combined_self_query(void **state) {
    (void)state;
    const uint32_t tris_local[] = {0, 1, 2, 0, 2, 3};
    selfcol_mesh *a = NULL, *b = NULL;
    selfcol_hierarchy *ha = NULL, *hb = NULL;
    selfcol_contacts *contacts = NULL;
    assert_int_equal(selfcol_mesh_create(&a, 4, squares_positions, 2, tris_local, NULL), 0);
    assert_int_equal(selfcol_mesh_create(&b, 4, squares_positions + 12, 2, tris_local, NULL), 0);
    assert_int_equal(selfcol_hierarchy_create(&ha, a, NULL), 0);
    assert_int_equal(selfcol_hierarchy_create(&hb, b, NULL), 0);
    assert_int_equal(selfcol_contacts_create(&contacts, NULL), 0);
    selfcol_query_options exhaustive;
    selfcol_query_options_init(&exhaustive, SELFCOL_QUERY_OPTIONS_VERSION);
    exhaustive.method = SELFCOL_METHOD_EXHAUSTIVE;
    assert_int_equal(selfcol_hierarchy_collide(ha, hb, contacts, &exhaustive), SELFCOL_OK);
    const selfcol_contact *c;
    size_t n;
    selfcol_contacts_data(contacts, &c, &n);
    // (first_mesh, first edge, second_mesh, second triangle), local numbering.
    const uint32_t expected[4][4] = {{0, 1, 1, 0}, {1, 1, 0, 0}, {1, 2, 0, 0}, {1, 3, 0, 1}};
    assert_int_equal(n, 4);
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(c[i].kind, SELFCOL_CONTACT_EF);
        assert_int_equal(c[i].first_mesh, expected[i][0]);
        assert_int_equal(c[i].first, expected[i][1]);
        assert_int_equal(c[i].second_mesh, expected[i][2]);
        assert_int_equal(c[i].second, expected[i][3]);
    }
    assert_int_equal(selfcol_hierarchy_collide(ha, ha, contacts, NULL), SELFCOL_EINVAL);
    selfcol_hierarchy *ha2 = NULL;
    assert_int_equal(selfcol_hierarchy_create(&ha2, a, NULL), 0);
    assert_int_equal(selfcol_hierarchy_collide(ha, ha2, contacts, NULL), SELFCOL_EINVAL);
    selfcol_hierarchy_destroy(ha2);

    // Between two meshes shared-index rules do not apply: a square against a
    // copy of itself touches wherever the copies meet (distance 0): each
    // vertex with the copy's triangles at that corner (2 + 1 + 2 + 1 per
    // direction) and every edge pair except the opposite sides (25 - 4);
    // coplanar copies never cross.
    selfcol_mesh *a2 = NULL;
    assert_int_equal(selfcol_mesh_create(&a2, 4, squares_positions, 2, tris_local, NULL), 0);
    assert_int_equal(selfcol_hierarchy_create(&ha2, a2, NULL), 0);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.distance = 1e-3;
    assert_int_equal(selfcol_hierarchy_collide(ha, ha2, contacts, &q), SELFCOL_OK);
    selfcol_contacts_data(contacts, &c, &n);
    assert_int_equal(count_kind(c, n, SELFCOL_CONTACT_EF), 0);
    assert_int_equal(count_kind(c, n, SELFCOL_CONTACT_VF), 12);
    assert_int_equal(count_kind(c, n, SELFCOL_CONTACT_EE), 21);
    selfcol_hierarchy_destroy(ha2);
    selfcol_mesh_destroy(a2);

    selfcol_contacts_destroy(contacts);
    selfcol_hierarchy_destroy(hb);
    selfcol_hierarchy_destroy(ha);
    selfcol_mesh_destroy(b);
    selfcol_mesh_destroy(a);
}

static void test_exhaustive_kinds_mask_selects_contact_kinds(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_hairpin(&s, 4, 0.1), 0);
    world w;
    world_make(&w, &s);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.distance = 0.11;
    size_t all_vf, all_ee, n;
    const selfcol_contact *c;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_OK);
    selfcol_contacts_data(w.contacts, &c, &n);
    all_vf = count_kind(c, n, SELFCOL_CONTACT_VF);
    all_ee = count_kind(c, n, SELFCOL_CONTACT_EE);
    assert_true(all_vf > 0 && all_ee > 0);
    q.kinds = SELFCOL_KIND_EE;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_OK);
    selfcol_contacts_data(w.contacts, &c, &n);
    assert_int_equal(n, all_ee);
    assert_int_equal(count_kind(c, n, SELFCOL_CONTACT_EE), all_ee);
    q.kinds = 0;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_count(w.contacts), 0);
    world_free(&w);
    fixture_free(&s);
}

static void test_exhaustive_rejects_bad_query_options(void **state) {
    (void)state;
    fixture g;
    assert_int_equal(fixture_grid(&g, 2, 2, 1.0), 0);
    world w;
    world_make(&w, &g);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    // The documented defaults (hierarchy.h).
    assert_int_equal(q.version, SELFCOL_QUERY_OPTIONS_VERSION);
    assert_int_equal(q.method, SELFCOL_METHOD_EXACT);
    assert_int_equal(q.narrow, SELFCOL_NARROW_CLOSED_FORM);
    assert_int_equal(q.kinds, SELFCOL_KIND_ALL);
    assert_true(q.distance == 0.0);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.distance = NAN;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.distance = -1.0;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.distance = INFINITY;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.distance = 0.1;
    q.method = 999;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.narrow = 7;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.narrow = SELFCOL_NARROW_CLOSED_FORM;
    q.kinds = 1u << 5;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EINVAL);
    q.kinds = SELFCOL_KIND_ALL;
    q.version = 0;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_EVERSION);
    assert_int_equal(selfcol_hierarchy_self_collide(NULL, w.contacts, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, NULL, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, NULL), SELFCOL_OK);
    selfcol_query_stats st;
    st.version = 0;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &st), SELFCOL_EVERSION);
    st.version = SELFCOL_QUERY_STATS_VERSION + 1;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &st), SELFCOL_EVERSION);
    // A caller built against an older version gets only the fields of that
    // version: the bytes after them stay untouched.
    const size_t known[2] = {offsetof(selfcol_query_stats, nodes_visited),
                             offsetof(selfcol_query_stats, contour_tests)};
    for (unsigned version = 1; version <= 2; ++version) {
        memset(&st, 0xab, sizeof st);
        st.version = version;
        assert_int_equal(selfcol_contacts_stats(w.contacts, &st), SELFCOL_OK);
        assert_int_equal(st.version, version);
        const unsigned char *bytes = (const unsigned char *)&st;
        for (size_t i = known[version - 1]; i < sizeof st; ++i)
            assert_int_equal(bytes[i], 0xab);
    }
    world_free(&w);
    fixture_free(&g);
}

// Allocation failure inside a query (scratch boxes, growth of the records):
// SELFCOL_ENOMEM, an empty contact set, no leak; a later query with memory
// available succeeds and finds the same contacts as an unconstrained run.
static void test_exhaustive_query_survives_allocation_failure(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_hairpin(&s, 12, 0.1), 0);
    world w;
    world_make(&w, &s);
    size_t expected;
    run_self(&w, 0.11, SELFCOL_NARROW_CLOSED_FORM, &expected);
    assert_true(expected > 64); // enough records to force a growth step

    long failures = 0;
    for (long n = 1;; ++n) {
        test_allocator_state st = {0};
        st.fail_at = n;
        selfcol_contacts_options opts;
        selfcol_contacts_options_init(&opts, SELFCOL_CONTACTS_OPTIONS_VERSION);
        opts.allocator = test_allocator(&st);
        selfcol_contacts *contacts = NULL;
        int status = selfcol_contacts_create(&contacts, &opts);
        if (status == SELFCOL_ENOMEM) {
            assert_null(contacts);
            failures++;
            continue;
        }
        assert_int_equal(status, SELFCOL_OK);
        selfcol_query_options q;
        selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
        q.method = SELFCOL_METHOD_EXHAUSTIVE;
        q.distance = 0.11;
        status = selfcol_hierarchy_self_collide(w.hierarchy, contacts, &q);
        if (status == SELFCOL_OK) {
            assert_int_equal(selfcol_contacts_count(contacts), expected);
            selfcol_contacts_destroy(contacts);
            assert_int_equal(st.live, 0);
            break;
        }
        assert_int_equal(status, SELFCOL_ENOMEM);
        assert_int_equal(selfcol_contacts_count(contacts), 0);
        // The same handle recovers once memory is back.
        st.fail_at = 0;
        assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, contacts, &q), SELFCOL_OK);
        assert_int_equal(selfcol_contacts_count(contacts), expected);
        selfcol_contacts_destroy(contacts);
        assert_int_equal(st.live, 0);
        assert_false(st.misaligned);
        failures++;
    }
    assert_true(failures >= 3); // handle, scratch, first and later record blocks
    world_free(&w);
    fixture_free(&s);
}

// Statistics: for a self query, the VF candidates are exactly the pairs
// (referenced vertex, triangle not incident to it).
static void test_exhaustive_counts_candidate_pairs(void **state) {
    (void)state;
    fixture g;
    assert_int_equal(fixture_grid(&g, 5, 4, 1.0), 0);
    world w;
    world_make(&w, &g);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.kinds = SELFCOL_KIND_VF;
    q.distance = 0.1;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_OK);
    uint64_t expected = 0;
    for (uint32_t v = 0; v < g.vertex_count; ++v) {
        uint64_t incident = 0;
        for (uint32_t t = 0; t < g.triangle_count; ++t)
            incident += (uint64_t)has_corner(g.triangles + 3 * t, v);
        expected += g.triangle_count - incident;
    }
    selfcol_query_stats st;
    st.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &st), SELFCOL_OK);
    assert_int_equal(st.candidate_pairs, expected);
    assert_int_equal(st.ee_tests + st.ef_tests, 0);
    world_free(&w);
    fixture_free(&g);
}

// Keys of the contacts currently in w (see contact_keys.h); caller frees.
static contact_key *keys_of(const selfcol_contacts *contacts, const uint32_t *map, uint32_t offset1,
                            size_t *n) {
    const selfcol_contact *c;
    selfcol_contacts_data(contacts, &c, n);
    contact_key *keys = malloc((*n + 1) * sizeof *keys);
    assert_non_null(keys);
    const uint32_t offset[2] = {0, offset1};
    contact_keys(c, *n, map, offset, keys);
    return keys;
}

// Renumbering the vertices, reordering the triangles and rotating each
// triangle's corners describes the same surface: the contact sets must map
// onto each other exactly (exclusion rules, edge numbering and loop order are
// all index-dependent, so this catches any dependence on them).
static void test_exhaustive_is_invariant_under_renumbering(void **state) {
    (void)state;
    size_t total_ef = 0;
    for (unsigned seed = 1; seed <= 3; ++seed) {
        fixture s;
        assert_int_equal(fixture_crumpled(&s, 14, 10, seed, 5.0), 0);
        world w;
        world_make(&w, &s);
        const double d = (seed == 2 ? 0.5 : 0.1) * selfcol_mesh_mean_edge_length(w.mesh);
        size_t n0, n1;
        run_self(&w, d, SELFCOL_NARROW_CLOSED_FORM, &n0);
        // The mesh holds its own copy, so the scene can be renumbered now;
        // the original contacts are then keyed in the new numbering.
        uint32_t *new_of_old = NULL;
        assert_int_equal(fixture_shuffle(&s, seed, &new_of_old), 0);
        contact_key *before = keys_of(w.contacts, new_of_old, 0, &n0);
        world_free(&w);
        world_make(&w, &s);
        const selfcol_contact *c = run_self(&w, d, SELFCOL_NARROW_CLOSED_FORM, &n1);
        total_ef += count_kind(c, n1, SELFCOL_CONTACT_EF);
        contact_key *after = keys_of(w.contacts, NULL, 0, &n1);
        assert_true(n0 > 0);
        assert_true(contact_keys_equal(before, n0, after, n1));
        free(before);
        free(after);
        free(new_of_old);
        world_free(&w);
        fixture_free(&s);
    }
    assert_true(total_ef > 0); // the crumpled sheets really cross themselves
}

// For two disjoint surfaces A and B in one mesh, self(A u B) is exactly
// self(A), self(B) and the contacts between A and B: the self path (with its
// shared-vertex exclusions) and the two-mesh path (without them) must agree.
static void test_exhaustive_self_of_union_is_selves_plus_between(void **state) {
    (void)state;
    fixture a, b, u;
    assert_int_equal(fixture_crumpled(&a, 12, 9, 7, 5.0), 0);
    assert_int_equal(fixture_crumpled(&b, 9, 12, 8, 5.0), 0);
    const double shift[3] = {2.5, 1.5, 0.5};
    fixture_translate(&b, shift);
    assert_int_equal(fixture_crumpled(&u, 12, 9, 7, 5.0), 0);
    assert_int_equal(fixture_append(&u, &b), 0);
    world wa, wb, wu;
    world_make(&wa, &a);
    world_make(&wb, &b);
    world_make(&wu, &u);
    const double d = 0.25 * selfcol_mesh_mean_edge_length(wu.mesh);
    size_t nu, na, nb, nab;
    run_self(&wu, d, SELFCOL_NARROW_CLOSED_FORM, &nu);
    contact_key *ku = keys_of(wu.contacts, NULL, 0, &nu);
    run_self(&wa, d, SELFCOL_NARROW_CLOSED_FORM, &na);
    contact_key *ka = keys_of(wa.contacts, NULL, 0, &na);
    run_self(&wb, d, SELFCOL_NARROW_CLOSED_FORM, &nb);
    uint32_t va = (uint32_t)a.vertex_count;
    const selfcol_contact *cb;
    selfcol_contacts_data(wb.contacts, &cb, &nb);
    contact_key *kb = malloc((nb + 1) * sizeof *kb);
    assert_non_null(kb);
    const uint32_t offset_b[2] = {va, va};
    contact_keys(cb, nb, NULL, offset_b, kb);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = SELFCOL_METHOD_EXHAUSTIVE;
    q.distance = d;
    assert_int_equal(selfcol_hierarchy_collide(wa.hierarchy, wb.hierarchy, wa.contacts, &q),
                     SELFCOL_OK);
    contact_key *kab = keys_of(wa.contacts, NULL, va, &nab);
    assert_true(nab > 0 && na > 0 && nb > 0);
    contact_key *all = malloc((na + nb + nab + 1) * sizeof *all);
    assert_non_null(all);
    memcpy(all, ka, na * sizeof *all);
    memcpy(all + na, kb, nb * sizeof *all);
    memcpy(all + na + nb, kab, nab * sizeof *all);
    contact_keys_sort(all, na + nb + nab);
    assert_true(contact_keys_equal(ku, nu, all, na + nb + nab));
    free(all);
    free(ka);
    free(kb);
    free(kab);
    free(ku);
    world_free(&wa);
    world_free(&wb);
    world_free(&wu);
    fixture_free(&a);
    fixture_free(&b);
    fixture_free(&u);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exhaustive_flat_grid_has_no_contacts_below_half_diagonal),
        cmocka_unit_test(test_exhaustive_hairpin_matches_hand_derived_pairs),
        cmocka_unit_test(test_exhaustive_crossing_squares_report_the_crossing_edges),
        cmocka_unit_test(test_exhaustive_two_meshes_match_the_combined_self_query),
        cmocka_unit_test(test_exhaustive_kinds_mask_selects_contact_kinds),
        cmocka_unit_test(test_exhaustive_rejects_bad_query_options),
        cmocka_unit_test(test_exhaustive_query_survives_allocation_failure),
        cmocka_unit_test(test_exhaustive_counts_candidate_pairs),
        cmocka_unit_test(test_exhaustive_is_invariant_under_renumbering),
        cmocka_unit_test(test_exhaustive_self_of_union_is_selves_plus_between),
    };
    return cmocka_run_group_tests_name("exhaustive", tests, NULL, NULL);
}
