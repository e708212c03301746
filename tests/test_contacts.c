// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact set handle (include/selfcol/contacts.h) on its own: creation
// and its options, what an empty or NULL handle answers, the records' order,
// the statistics' versions, and clear. The queries that fill it are held to
// the exact contact sets in test_hierarchy.c and test_exhaustive.c.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "fixtures.h"
#include "test_alloc.h"
#include "world.h"

static void test_create_checks_its_options(void **state) {
    (void)state;
    selfcol_contacts_options o;
    assert_int_equal(selfcol_contacts_options_init(NULL, SELFCOL_CONTACTS_OPTIONS_VERSION),
                     SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_options_init(&o, 0), SELFCOL_EVERSION);
    assert_int_equal(selfcol_contacts_options_init(&o, SELFCOL_CONTACTS_OPTIONS_VERSION + 1),
                     SELFCOL_EVERSION);
    assert_int_equal(selfcol_contacts_options_init(&o, SELFCOL_CONTACTS_OPTIONS_VERSION),
                     SELFCOL_OK);
    assert_int_equal(o.version, SELFCOL_CONTACTS_OPTIONS_VERSION);
    assert_null(o.allocator.alloc);
    assert_null(o.allocator.free);
    selfcol_contacts *c = (selfcol_contacts *)&o; // must be reset to NULL on failure
    assert_int_equal(selfcol_contacts_create(NULL, &o), SELFCOL_EINVAL);
    o.version = SELFCOL_CONTACTS_OPTIONS_VERSION + 1;
    assert_int_equal(selfcol_contacts_create(&c, &o), SELFCOL_EVERSION);
    assert_null(c);
    // An allocator with one hook only is refused.
    test_allocator_state st;
    memset(&st, 0, sizeof st);
    selfcol_contacts_options_init(&o, SELFCOL_CONTACTS_OPTIONS_VERSION);
    o.allocator = test_allocator(&st);
    o.allocator.free = NULL;
    assert_int_equal(selfcol_contacts_create(&c, &o), SELFCOL_EINVAL);
    assert_null(c);
    // Out of memory at creation: ENOMEM and nothing left behind.
    o.allocator = test_allocator(&st);
    st.fail_at = 1;
    assert_int_equal(selfcol_contacts_create(&c, &o), SELFCOL_ENOMEM);
    assert_null(c);
    assert_int_equal(st.live, 0);
    // With the hooks: every byte it holds comes from them and goes back.
    st.fail_at = 0;
    assert_int_equal(selfcol_contacts_create(&c, &o), SELFCOL_OK);
    assert_true(st.live > 0);
    assert_true(selfcol_contacts_byte_count(c) >= st.live_bytes / 2);
    selfcol_contacts_destroy(c);
    assert_int_equal(st.live, 0);
    assert_false(st.misaligned);
}

static void test_null_and_empty_handles_answer_plainly(void **state) {
    (void)state;
    assert_int_equal(selfcol_contacts_count(NULL), 0);
    assert_int_equal(selfcol_contacts_byte_count(NULL), 0);
    selfcol_contacts_destroy(NULL);
    selfcol_contacts_clear(NULL);
    const selfcol_contact *data = (const selfcol_contact *)state;
    size_t n = 7;
    assert_int_equal(selfcol_contacts_data(NULL, &data, &n), SELFCOL_EINVAL);
    selfcol_contacts *c;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_data(c, NULL, &n), SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_data(c, &data, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_data(c, &data, &n), SELFCOL_OK);
    assert_null(data);
    assert_int_equal(n, 0);
    assert_int_equal(selfcol_contacts_count(c), 0);
    assert_true(selfcol_contacts_byte_count(c) > 0);
    selfcol_query_stats s;
    s.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(NULL, &s), SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_stats(c, NULL), SELFCOL_EINVAL);
    s.version = 0;
    assert_int_equal(selfcol_contacts_stats(c, &s), SELFCOL_EVERSION);
    s.version = SELFCOL_QUERY_STATS_VERSION + 1;
    assert_int_equal(selfcol_contacts_stats(c, &s), SELFCOL_EVERSION);
    s.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(c, &s), SELFCOL_OK);
    assert_int_equal(s.vf_contacts + s.ee_contacts + s.ef_contacts, 0);
    selfcol_contacts_destroy(c);
}

// A hairpin (two layers 0.05 apart, unit cells) queried at d = 0.1: many
// VF and EE contacts between the layers.
static void hairpin_world(world *w) {
    fixture s;
    assert_int_equal(fixture_hairpin(&s, 12, 0.05), 0);
    world_make(w, &s);
    fixture_free(&s);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = 0.1;
    assert_int_equal(selfcol_hierarchy_self_collide(w->hierarchy, w->contacts, &q), SELFCOL_OK);
}

static int key_less(const selfcol_contact *a, const selfcol_contact *b) {
    if (a->kind != b->kind)
        return a->kind < b->kind;
    if (a->first_mesh != b->first_mesh)
        return a->first_mesh < b->first_mesh;
    if (a->first != b->first)
        return a->first < b->first;
    if (a->second_mesh != b->second_mesh)
        return a->second_mesh < b->second_mesh;
    return a->second < b->second;
}

static void test_records_are_sorted_by_key_without_repeats(void **state) {
    (void)state;
    world w;
    hairpin_world(&w);
    const selfcol_contact *c;
    size_t n;
    assert_int_equal(selfcol_contacts_data(w.contacts, &c, &n), SELFCOL_OK);
    assert_true(n > 20);
    assert_int_equal(n, selfcol_contacts_count(w.contacts));
    for (size_t i = 1; i < n; ++i)
        assert_true(key_less(&c[i - 1], &c[i])); // strictly: no pair twice
    selfcol_query_stats s;
    s.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &s), SELFCOL_OK);
    size_t per_kind[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i)
        per_kind[c[i].kind == SELFCOL_CONTACT_VF ? 0 : c[i].kind == SELFCOL_CONTACT_EE ? 1 : 2]++;
    assert_int_equal(s.vf_contacts, per_kind[0]);
    assert_int_equal(s.ee_contacts, per_kind[1]);
    assert_int_equal(s.ef_contacts, per_kind[2]);
    world_free(&w);
}

// Each version of the statistics writes its own fields and leaves the rest
// of the caller's struct alone.
static void test_stats_write_only_their_version(void **state) {
    (void)state;
    world w;
    hairpin_world(&w);
    selfcol_query_stats full;
    full.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &full), SELFCOL_OK);
    assert_true(full.nodes_visited > 0); // version 2
    for (unsigned v = 1; v <= SELFCOL_QUERY_STATS_VERSION; ++v) {
        selfcol_query_stats s;
        memset(&s, 0xab, sizeof s);
        s.version = v;
        assert_int_equal(selfcol_contacts_stats(w.contacts, &s), SELFCOL_OK);
        assert_int_equal(s.version, v);
        assert_int_equal(s.vf_contacts, full.vf_contacts);
        const uint64_t untouched = 0xababababababababull;
        if (v < 2)
            assert_true(s.nodes_visited == untouched);
        else
            assert_true(s.nodes_visited == full.nodes_visited);
        if (v < 3)
            assert_true(s.contour_tests == untouched);
        if (v < 4)
            assert_true(s.pairs_separated == untouched);
        else
            assert_true(s.pairs_separated == full.pairs_separated);
    }
    world_free(&w);
}

static void test_clear_empties_and_keeps_the_memory(void **state) {
    (void)state;
    world w;
    hairpin_world(&w);
    const selfcol_contact *c;
    size_t n;
    selfcol_contacts_data(w.contacts, &c, &n);
    assert_true(n > 0);
    selfcol_contact first = c[0];
    const size_t bytes = selfcol_contacts_byte_count(w.contacts);
    selfcol_contacts_clear(w.contacts);
    assert_int_equal(selfcol_contacts_count(w.contacts), 0);
    assert_int_equal(selfcol_contacts_data(w.contacts, &c, &n), SELFCOL_OK);
    assert_null(c);
    assert_int_equal(n, 0);
    assert_int_equal(selfcol_contacts_byte_count(w.contacts), bytes);
    selfcol_query_stats s;
    s.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(w.contacts, &s), SELFCOL_OK);
    assert_int_equal(s.vf_contacts + s.ee_contacts + s.ef_contacts + s.candidate_pairs, 0);
    // The next query fills it again with the same records.
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = 0.1;
    assert_int_equal(selfcol_hierarchy_self_collide(w.hierarchy, w.contacts, &q), SELFCOL_OK);
    selfcol_contacts_data(w.contacts, &c, &n);
    assert_true(n > 0);
    assert_memory_equal(&c[0], &first, sizeof first);
    world_free(&w);
}

// The intersecting triangle pairs, against a derivation written here from
// the records and the mesh's own edge -> triangle lists: the README's two
// crossing triangles, a crumpled sheet crossing itself, two meshes; the
// pairs follow a new query; NULL arguments.
static int pair_less(const void *x, const void *y) {
    const uint32_t *a = x, *b = y;
    return a[0] != b[0] ? (a[0] < b[0] ? -1 : 1) : (a[1] != b[1] ? (a[1] < b[1] ? -1 : 1) : 0);
}

// By brute force: every EF record's edge triangles against its triangle,
// (mesh 0 triangle, mesh 1 triangle) or (low, high), sorted, unique.
static size_t expected_pairs(const selfcol_contacts *c, const selfcol_mesh *m0,
                             const selfcol_mesh *m1, uint32_t **out) {
    const selfcol_contact *r = NULL;
    size_t n = 0, k = 0;
    assert_int_equal(selfcol_contacts_data(c, &r, &n), SELFCOL_OK);
    uint32_t *p = malloc((64 * n + 1) * sizeof *p);
    assert_non_null(p);
    for (size_t i = 0; i < n; ++i) {
        if (r[i].kind != SELFCOL_CONTACT_EF)
            continue;
        const selfcol_mesh *me = r[i].first_mesh ? m1 : m0;
        const uint32_t *tris = NULL;
        size_t m = 0;
        assert_int_equal(selfcol_mesh_edge_triangles(me, r[i].first, &tris, &m), SELFCOL_OK);
        for (size_t j = 0; j < m; ++j) {
            uint32_t a = tris[j], b = r[i].second;
            if (m0 == m1 && a > b) {
                uint32_t t = a;
                a = b;
                b = t;
            } else if (m0 != m1 && r[i].first_mesh) {
                uint32_t t = a;
                a = b;
                b = t;
            }
            p[2 * k] = a;
            p[2 * k + 1] = b;
            ++k;
        }
    }
    qsort(p, k, 2 * sizeof *p, pair_less);
    size_t unique = 0;
    for (size_t i = 0; i < k; ++i)
        if (unique == 0 || pair_less(&p[2 * i], &p[2 * (unique - 1)]) != 0) {
            p[2 * unique] = p[2 * i];
            p[2 * unique + 1] = p[2 * i + 1];
            ++unique;
        }
    *out = p;
    return unique;
}

static void check_pairs(selfcol_contacts *c, const selfcol_mesh *m0, const selfcol_mesh *m1,
                        size_t *total) {
    uint32_t *want = NULL;
    const size_t n = expected_pairs(c, m0, m1, &want);
    const uint32_t *got = (const uint32_t *)1;
    size_t count = 99;
    assert_int_equal(selfcol_contacts_intersecting_triangles(c, m0, m1, &got, &count), SELFCOL_OK);
    assert_int_equal(count, n);
    if (n > 0)
        assert_memory_equal(got, want, 2 * n * sizeof *want);
    else
        assert_null(got);
    *total += n;
    free(want);
}

// Two crumpled sheets, the second over the first: each crosses itself, and
// they cross each other.
static void crossing_sheets(world *first, world *second, unsigned n) {
    fixture a = {0}, b = {0};
    assert_int_equal(fixture_crumpled(&a, n, n, 3, 5.0), 0);
    assert_int_equal(fixture_crumpled(&b, 2 * n / 3, 4 * n / 5, 5, 5.0), 0);
    const double shift[3] = {0.4, 0.3, 0.0};
    fixture_translate(&b, shift);
    world_make(first, &a);
    world_make(second, &b);
    fixture_free(&a);
    fixture_free(&b);
}

static void test_intersecting_triangles(void **state) {
    (void)state;
    // The README's example: edges (3, 4) and (3, 5) cross triangle 0.
    const double V[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, -0.5, 0.3, 0.2, 0.5, 0.2, 0.3, 0.5};
    const uint32_t F[] = {0, 1, 2, 3, 4, 5};
    selfcol_mesh *m = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_mesh_create(&m, 6, V, 2, F, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = 0.05;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    const uint32_t *pairs = NULL;
    size_t n = 0;
    assert_int_equal(selfcol_contacts_intersecting_triangles(c, m, m, &pairs, &n), SELFCOL_OK);
    assert_int_equal(n, 1);
    assert_int_equal(pairs[0], 0);
    assert_int_equal(pairs[1], 1);
    // A query that finds no crossing: no pairs (the old ones are not kept).
    o.kinds = SELFCOL_KIND_VF;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_intersecting_triangles(c, m, m, &pairs, &n), SELFCOL_OK);
    assert_int_equal(n, 0);
    assert_null(pairs);
    assert_int_equal(selfcol_contacts_intersecting_triangles(NULL, m, m, &pairs, &n),
                     SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_intersecting_triangles(c, NULL, m, &pairs, &n),
                     SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_intersecting_triangles(c, m, m, NULL, &n), SELFCOL_EINVAL);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);

    // A crumpled sheet crossing itself, then two sheets through each other.
    world wa, wb;
    crossing_sheets(&wa, &wb, 30);
    selfcol_mesh *ma = wa.mesh, *mb = wb.mesh;
    selfcol_hierarchy *ha = wa.hierarchy, *hb = wb.hierarchy;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = 0.01;
    size_t total = 0;
    assert_int_equal(selfcol_hierarchy_self_collide(ha, c, &o), SELFCOL_OK);
    check_pairs(c, ma, ma, &total);
    const size_t self_pairs = total;
    assert_true(self_pairs > 10);
    check_pairs(c, ma, ma, &total); // the kept pairs, answered again
    assert_int_equal(selfcol_hierarchy_collide(ha, hb, c, &o), SELFCOL_OK);
    check_pairs(c, ma, mb, &total);
    assert_true(total > 2 * self_pairs); // the two sheets cross too
    assert_int_equal(selfcol_hierarchy_collide(hb, ha, c, &o), SELFCOL_OK);
    check_pairs(c, mb, ma, &total);
    // Without memory for the pairs: SELFCOL_ENOMEM, then the pairs once it returns.
    test_allocator_state alloc = {0};
    selfcol_contacts_options co;
    selfcol_contacts_options_init(&co, SELFCOL_CONTACTS_OPTIONS_VERSION);
    co.allocator = test_allocator(&alloc);
    selfcol_contacts *counted = NULL;
    assert_int_equal(selfcol_contacts_create(&counted, &co), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(ha, counted, &o), SELFCOL_OK);
    alloc.fail_at = alloc.calls + 1;
    assert_int_equal(selfcol_contacts_intersecting_triangles(counted, ma, ma, &pairs, &n),
                     SELFCOL_ENOMEM);
    alloc.fail_at = 0;
    assert_int_equal(selfcol_contacts_intersecting_triangles(counted, ma, ma, &pairs, &n),
                     SELFCOL_OK);
    assert_int_equal(n, self_pairs);
    selfcol_contacts_destroy(counted);
    assert_int_equal(alloc.live, 0);
    world_free(&wa);
    world_free(&wb);
    selfcol_contacts_destroy(c);
}

// Triangle classes, against a marking written here from the records and the
// mesh's public adjacency: a crumpled sheet (self) and two sheets (both
// arrays); classes only go up across calls; NULL arguments.
static void mark_by_hand(const selfcol_contacts *c, const selfcol_mesh *m0, const selfcol_mesh *m1,
                         uint8_t *k0, uint8_t *k1) {
    const selfcol_contact *r = NULL;
    size_t n = 0;
    assert_int_equal(selfcol_contacts_data(c, &r, &n), SELFCOL_OK);
    const selfcol_mesh *mesh[2] = {m0, m1};
    uint8_t *k[2] = {k0, m0 == m1 ? k0 : k1};
    for (size_t i = 0; i < n; ++i) {
        const int f = (int)r[i].first_mesh, g = (int)r[i].second_mesh;
        const uint32_t *tris = NULL;
        size_t m = 0;
        const uint8_t level = r[i].kind == SELFCOL_CONTACT_EF ? 2 : 1;
        if (r[i].kind != SELFCOL_CONTACT_EE && k[g][r[i].second] < level)
            k[g][r[i].second] = level;
        if (r[i].kind == SELFCOL_CONTACT_VF)
            assert_int_equal(selfcol_mesh_vertex_triangles(mesh[f], r[i].first, &tris, &m),
                             SELFCOL_OK);
        else
            assert_int_equal(selfcol_mesh_edge_triangles(mesh[f], r[i].first, &tris, &m),
                             SELFCOL_OK);
        for (size_t j = 0; j < m; ++j)
            if (k[f][tris[j]] < level)
                k[f][tris[j]] = level;
        if (r[i].kind == SELFCOL_CONTACT_EE) {
            assert_int_equal(selfcol_mesh_edge_triangles(mesh[g], r[i].second, &tris, &m),
                             SELFCOL_OK);
            for (size_t j = 0; j < m; ++j)
                if (k[g][tris[j]] < 1)
                    k[g][tris[j]] = 1;
        }
    }
}

static void test_triangle_classes(void **state) {
    (void)state;
    world wa, wb;
    crossing_sheets(&wa, &wb, 24);
    selfcol_mesh *ma = wa.mesh, *mb = wb.mesh;
    selfcol_hierarchy *ha = wa.hierarchy, *hb = wb.hierarchy;
    selfcol_contacts *c = wa.contacts;
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = 0.05;
    const size_t na = selfcol_mesh_count(ma, SELFCOL_MESH_TRIANGLES);
    const size_t nb = selfcol_mesh_count(mb, SELFCOL_MESH_TRIANGLES);
    uint8_t *got_a = calloc(na, 1), *got_b = calloc(nb, 1);
    uint8_t *want_a = calloc(na, 1), *want_b = calloc(nb, 1);
    assert_true(got_a && got_b && want_a && want_b);
    assert_int_equal(selfcol_hierarchy_self_collide(ha, c, &o), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_triangle_classes(c, ma, ma, got_a, NULL), SELFCOL_OK);
    mark_by_hand(c, ma, ma, want_a, NULL);
    assert_memory_equal(got_a, want_a, na);
    size_t marked[3] = {0, 0, 0};
    for (size_t t = 0; t < na; ++t)
        marked[got_a[t]]++;
    assert_true(marked[1] > 0 && marked[2] > 0); // both classes met
    // A second query adds to the same arrays (classes only go up).
    assert_int_equal(selfcol_hierarchy_collide(ha, hb, c, &o), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_triangle_classes(c, ma, mb, got_a, got_b), SELFCOL_OK);
    mark_by_hand(c, ma, mb, want_a, want_b);
    assert_memory_equal(got_a, want_a, na);
    assert_memory_equal(got_b, want_b, nb);
    assert_int_equal(selfcol_contacts_triangle_classes(NULL, ma, ma, got_a, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_triangle_classes(c, ma, mb, got_a, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_contacts_triangle_classes(c, ma, ma, NULL, NULL), SELFCOL_EINVAL);
    free(got_a);
    free(got_b);
    free(want_a);
    free(want_b);
    world_free(&wa);
    world_free(&wb);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_checks_its_options),
        cmocka_unit_test(test_null_and_empty_handles_answer_plainly),
        cmocka_unit_test(test_records_are_sorted_by_key_without_repeats),
        cmocka_unit_test(test_stats_write_only_their_version),
        cmocka_unit_test(test_clear_empties_and_keeps_the_memory),
        cmocka_unit_test(test_intersecting_triangles),
        cmocka_unit_test(test_triangle_classes),
    };
    return cmocka_run_group_tests_name("contacts", tests, NULL, NULL);
}
