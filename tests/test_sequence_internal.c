// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The partial rebuilds of sequence.c against full rebuilds: after every
// query a partial rebuild answered, the near pairs of the cluster pairs it
// queried again must be those a full rebuild at the same positions lists
// for them, bounds included (selfcol_sequence__check_partial). The records
// themselves are held equal to fresh queries by test_sequence.c.
#include "frames/sequence.h"

#include <selfcol/selfcol.h>

#include "fixtures.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

static selfcol_sequence_run_stats run_stats(const selfcol_sequence *seq) {
    selfcol_sequence_run_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
    assert_int_equal(selfcol_sequence_stats(seq, &st), SELFCOL_OK);
    return st;
}

// Weight of vertex v's motion: 1 in the strip x < 0.2 of the width, 0 beyond
// 0.3, a ramp between (as in test_sequence.c).
static double local_weight(const fixture *flat, size_t v, double width) {
    const double x = flat->positions[3 * v] / width;
    return x < 0.2 ? 1.0 : x < 0.3 ? (0.3 - x) / 0.1 : 0.0;
}

static double width_of(const fixture *f) {
    double width = 0.0;
    for (size_t v = 0; v < f->vertex_count; ++v)
        width = fmax(width, f->positions[3 * v]);
    return width;
}

// After a query: when it was a partial rebuild, its lists must match;
// otherwise the check refuses. Returns 1 for a checked partial rebuild.
static int check_after(selfcol_sequence *seq, uint64_t *partials, selfcol_hierarchy *first,
                       selfcol_hierarchy *second, selfcol_contacts *scratch, int frame) {
    const selfcol_sequence_run_stats st = run_stats(seq);
    const int partial = st.partial_rebuilds > *partials;
    *partials = st.partial_rebuilds;
    const int got = selfcol_sequence__check_partial(seq, first, second, scratch);
    if (!partial) {
        assert_int_equal(got, SELFCOL_EINVAL);
        return 0;
    }
    if (got != 1)
        fail_msg("frame %d: the partial rebuild's pairs differ from a full rebuild's (%d)", frame,
                 got);
    return 1;
}

// The records of `got` against a fresh query of h (a hierarchy of its own,
// so that the sequence's is never refit here) at the same positions.
static void assert_as_fresh(selfcol_hierarchy *h, const selfcol_contacts *got,
                            selfcol_contacts *scratch, const selfcol_query_options *o, int frame) {
    assert_int_equal(selfcol_hierarchy_refit(h), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(h, scratch, o), SELFCOL_OK);
    const selfcol_contact *a, *b;
    size_t na, nb;
    assert_int_equal(selfcol_contacts_data(got, &a, &na), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_data(scratch, &b, &nb), SELFCOL_OK);
    size_t same = 0;
    while (same < na && same < nb && a[same].kind == b[same].kind &&
           a[same].first == b[same].first && a[same].second == b[same].second &&
           a[same].distance == b[same].distance)
        ++same;
    if (same != na || same != nb)
        fail_msg("frame %d: %zu records against the fresh query's %zu, first difference at %zu",
                 frame, na, nb, same);
    selfcol_contacts_clear(scratch);
}

// trim: after every query, the near list's buffer is cut to its pairs
// (selfcol_sequence__trim_list), so every partial rebuild grows it with the
// kept pairs in front; the records are then also held equal to a fresh
// query's on every frame.
static void run_self(uint32_t method, unsigned threads, int trim) {
    fixture flat = {0}, crumpled = {0};
    assert_int_equal(fixture_grid(&flat, 40, 40, 1.0), 0);
    assert_int_equal(fixture_crumpled(&crumpled, 40, 40, 3, 3.0), 0);
    const size_t V = flat.vertex_count;
    const double width = width_of(&flat);
    double *x = malloc(3 * V * sizeof *x);
    assert_non_null(x);
    selfcol_mesh *mesh;
    assert_int_equal(
        selfcol_mesh_create(&mesh, V, flat.positions, flat.triangle_count, flat.triangles, NULL),
        SELFCOL_OK);
    selfcol_hierarchy *h, *fresh;
    assert_int_equal(selfcol_hierarchy_create(&h, mesh, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&fresh, mesh, NULL), SELFCOL_OK);
    selfcol_sequence *seq;
    assert_int_equal(selfcol_sequence_create(&seq, NULL), SELFCOL_OK);
    selfcol_contacts *got, *scratch;
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&scratch, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = method;
    o.distance = 0.1;
    selfcol_context *context = NULL; // the sequence's threads (one: none)
    if (threads > 1) {
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.threads = threads;
        assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
    }
    uint64_t partials = 0;
    int checked = 0;
    for (int k = 0; k <= 90; ++k) {
        for (size_t v = 0; v < V; ++v) {
            const double a = 0.6 + 0.05 * local_weight(&flat, v, width) * k / 90.0;
            for (size_t i = 3 * v; i < 3 * v + 3; ++i)
                x[i] = flat.positions[i] + a * (crumpled.positions[i] - flat.positions[i]);
        }
        assert_int_equal(selfcol_mesh_set_positions(mesh, x, V), SELFCOL_OK);
        assert_int_equal(context != NULL
                             ? selfcol_context_sequence_self_collide(context, seq, h, got, &o)
                             : selfcol_sequence_self_collide(seq, h, got, &o),
                         SELFCOL_OK);
        checked += check_after(seq, &partials, h, h, scratch, k);
        if (trim) {
            assert_as_fresh(fresh, got, scratch, &o, k);
            assert_int_equal(selfcol_sequence__trim_list(seq), SELFCOL_OK);
        }
    }
    assert_true(checked >= 3);
    selfcol_context_destroy(context);
    selfcol_contacts_destroy(got);
    selfcol_contacts_destroy(scratch);
    selfcol_sequence_destroy(seq);
    selfcol_hierarchy_destroy(h);
    selfcol_hierarchy_destroy(fresh);
    selfcol_mesh_destroy(mesh);
    free(x);
    fixture_free(&flat);
    fixture_free(&crumpled);
}

static void test_self_exact(void **state) {
    (void)state;
    run_self(SELFCOL_METHOD_EXACT, 1, 0);
}

static void test_self_bvh_two_threads(void **state) {
    (void)state;
    run_self(SELFCOL_METHOD_BVH, 2, 0);
}

static void test_partial_rebuild_grows_the_list_keeping_its_pairs(void **state) {
    (void)state;
    run_self(SELFCOL_METHOD_EXACT, 1, 1);
}

// A flat sheet through which a crumpled one sinks at one end; both orders
// of the meshes.
static void test_two_surfaces(void **state) {
    (void)state;
    fixture a = {0}, b = {0};
    assert_int_equal(fixture_grid(&a, 32, 32, 1.0), 0);
    assert_int_equal(fixture_crumpled(&b, 32, 32, 5, 1.0), 0);
    const double lift[3] = {0.3, 0.2, 0.0};
    fixture_translate(&b, lift);
    const size_t V = b.vertex_count;
    const double width = width_of(&a);
    double *x = malloc(3 * V * sizeof *x);
    assert_non_null(x);
    selfcol_mesh *ma, *mb;
    assert_int_equal(
        selfcol_mesh_create(&ma, a.vertex_count, a.positions, a.triangle_count, a.triangles, NULL),
        SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&mb, V, b.positions, b.triangle_count, b.triangles, NULL),
                     SELFCOL_OK);
    selfcol_hierarchy *ha, *hb;
    assert_int_equal(selfcol_hierarchy_create(&ha, ma, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&hb, mb, NULL), SELFCOL_OK);
    selfcol_sequence *seq;
    assert_int_equal(selfcol_sequence_create(&seq, NULL), SELFCOL_OK);
    selfcol_contacts *got, *scratch;
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&scratch, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = 0.1;
    uint64_t partials = 0;
    int checked = 0;
    for (int k = 0; k <= 100; ++k) {
        memcpy(x, b.positions, 3 * V * sizeof *x);
        for (size_t v = 0; v < V; ++v)
            x[3 * v + 2] -= 0.01 * k * local_weight(&a, v, width);
        assert_int_equal(selfcol_mesh_set_positions(mb, x, V), SELFCOL_OK);
        selfcol_hierarchy *first = k < 50 ? ha : hb, *second = k < 50 ? hb : ha;
        assert_int_equal(selfcol_sequence_collide(seq, first, second, got, &o), SELFCOL_OK);
        checked += check_after(seq, &partials, first, second, scratch, k);
    }
    assert_true(checked >= 6);
    selfcol_contacts_destroy(got);
    selfcol_contacts_destroy(scratch);
    selfcol_sequence_destroy(seq);
    selfcol_hierarchy_destroy(ha);
    selfcol_hierarchy_destroy(hb);
    selfcol_mesh_destroy(ma);
    selfcol_mesh_destroy(mb);
    free(x);
    fixture_free(&a);
    fixture_free(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_self_exact),
        cmocka_unit_test(test_self_bvh_two_threads),
        cmocka_unit_test(test_two_surfaces),
        cmocka_unit_test(test_partial_rebuild_grows_the_list_keeping_its_pairs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
