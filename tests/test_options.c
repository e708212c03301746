// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Options that name what they refuse (selfcol_*_options_check, common.h's
// selfcol_options_problem): for every options struct and every field its
// consumer refuses, the check returns the status the consumer returns for
// the same struct (the consumer is called too), names the field, and writes
// a sentence holding the struct, the field and the value; accepted options
// leave field and message empty; the problem's own arguments are checked.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "fixtures.h"

typedef struct world {
    fixture shape;
    selfcol_mesh *mesh;
    selfcol_hierarchy *hierarchy;
    selfcol_contacts *contacts;
    selfcol_sweep *sweep;
} world;

static int setup(void **state) {
    static world w;
    memset(&w, 0, sizeof w);
    if (fixture_grid(&w.shape, 6, 6, 1.0) != 0 ||
        selfcol_mesh_create(&w.mesh, w.shape.vertex_count, w.shape.positions,
                            w.shape.triangle_count, w.shape.triangles, NULL) != SELFCOL_OK ||
        selfcol_hierarchy_create(&w.hierarchy, w.mesh, NULL) != SELFCOL_OK ||
        selfcol_contacts_create(&w.contacts, NULL) != SELFCOL_OK ||
        selfcol_sweep_create(&w.sweep, NULL) != SELFCOL_OK)
        return -1;
    *state = &w;
    return 0;
}

static int teardown(void **state) {
    world *w = *state;
    selfcol_sweep_destroy(w->sweep);
    selfcol_contacts_destroy(w->contacts);
    selfcol_hierarchy_destroy(w->hierarchy);
    selfcol_mesh_destroy(w->mesh);
    fixture_free(&w->shape);
    return 0;
}

static selfcol_options_problem fresh_problem(void) {
    selfcol_options_problem p;
    memset(&p, 0x5a, sizeof p); // garbage, which the check must overwrite
    p.version = SELFCOL_OPTIONS_PROBLEM_VERSION;
    return p;
}

// The check's verdict: its status is `status`, and, refused, the field is
// `field` and the message holds "type.field" and `value`.
static void expect(int checked, const selfcol_options_problem *p, int status, const char *type,
                   const char *field, const char *value) {
    assert_int_equal(checked, status);
    assert_int_equal(p->status, status);
    if (status == SELFCOL_OK) {
        assert_string_equal(p->field, "");
        assert_string_equal(p->message, "");
        return;
    }
    assert_string_equal(p->field, field);
    char named[160];
    snprintf(named, sizeof named, "%s.%s ", type, field);
    assert_non_null(strstr(p->message, named));
    assert_ptr_equal(strstr(p->message, named), p->message); // it starts the sentence
    if (value != NULL)
        assert_non_null(strstr(p->message, value));
}

static void *dummy_alloc(void *user, size_t size, size_t alignment) {
    (void)user;
    (void)size;
    (void)alignment;
    return NULL;
}

static void dummy_finish(void *user_task, void *user_context) {
    (void)user_task;
    (void)user_context;
}

static void test_query_options_name_the_field(void **state) {
    world *w = *state;
    selfcol_options_problem p = fresh_problem();
    expect(selfcol_query_options_check(NULL, &p), &p, SELFCOL_OK, "", "", NULL);
    selfcol_query_options o;
    for (int k = 0; k < 6; ++k) {
        selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
        const char *field = NULL, *value = NULL;
        int want = SELFCOL_EINVAL;
        switch (k) {
        case 0:
            o.method = 9;
            field = "method";
            value = "= 9";
            break;
        case 1:
            o.narrow = 5;
            field = "narrow";
            value = "= 5";
            break;
        case 2:
            o.kinds = 0x100;
            field = "kinds";
            value = "0x100";
            break;
        case 3:
            o.distance = NAN;
            field = "distance";
            value = "nan";
            break;
        case 4:
            o.version = 2; // 0.3's layout, with threads (the context's since 0.4)
            field = "version";
            value = "older layout";
            want = SELFCOL_EVERSION;
            break;
        default:
            o.version = 0;
            field = "version";
            value = "= 0";
            want = SELFCOL_EVERSION;
        }
        p = fresh_problem();
        const int checked = selfcol_query_options_check(&o, &p);
        expect(checked, &p, want, "selfcol_query_options", field, value);
        // The query itself refuses them with the same status.
        assert_int_equal(selfcol_hierarchy_self_collide(w->hierarchy, w->contacts, &o), checked);
    }
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = 0.25;
    p = fresh_problem();
    expect(selfcol_query_options_check(&o, &p), &p, SELFCOL_OK, "", "", NULL);
    assert_int_equal(selfcol_hierarchy_self_collide(w->hierarchy, w->contacts, &o), SELFCOL_OK);
    o.version = SELFCOL_QUERY_OPTIONS_VERSION + 1;
    p = fresh_problem();
    expect(selfcol_query_options_check(&o, &p), &p, SELFCOL_EVERSION, "selfcol_query_options",
           "version", "newer than this library");
}

static void test_hierarchy_options_name_the_field(void **state) {
    world *w = *state;
    selfcol_hierarchy_options o;
    for (int k = 0; k < 4; ++k) {
        selfcol_hierarchy_options_init(&o, SELFCOL_HIERARCHY_OPTIONS_VERSION);
        const char *field = NULL, *value = NULL;
        int want = SELFCOL_EINVAL;
        switch (k) {
        case 0:
            o.version = 2; // 0.3's layout, with threads (the context's since 0.4)
            field = "version";
            value = "older layout";
            want = SELFCOL_EVERSION;
            break;
        case 1:
            o.allocator.alloc = dummy_alloc;
            field = "allocator";
            value = "half set";
            break;
        case 2:
            o.version = 0;
            field = "version";
            want = SELFCOL_EVERSION;
            break;
        default: field = ""; want = SELFCOL_OK;
        }
        selfcol_options_problem p = fresh_problem();
        const int checked = selfcol_hierarchy_options_check(&o, &p);
        expect(checked, &p, want, "selfcol_hierarchy_options", field, value);
        selfcol_hierarchy *h = NULL;
        assert_int_equal(selfcol_hierarchy_create(&h, w->mesh, &o), checked);
        selfcol_hierarchy_destroy(h);
    }
}

static void test_store_options_name_the_field(void **state) {
    (void)state;
    selfcol_store_options o;
    for (int k = 0; k < 6; ++k) {
        selfcol_store_options_init(&o, SELFCOL_STORE_OPTIONS_VERSION);
        const char *field = NULL, *value = NULL;
        int want = SELFCOL_EINVAL;
        switch (k) {
        case 0:
            o.consistency = 2;
            field = "consistency";
            value = "= 2";
            break;
        case 1:
            o.first_orientation = -2;
            field = "first_orientation";
            value = "= -2";
            break;
        case 2:
            o.second_orientation = 3;
            field = "second_orientation";
            value = "= 3";
            break;
        case 3:
            o.version = 2; // 0.3's layout, with threads (the context's since 0.4)
            field = "version";
            value = "older layout";
            want = SELFCOL_EVERSION;
            break;
        case 4:
            o.allocator.alloc = dummy_alloc;
            field = "allocator";
            break;
        default: field = ""; want = SELFCOL_OK;
        }
        selfcol_options_problem p = fresh_problem();
        const int checked = selfcol_store_options_check(&o, &p);
        expect(checked, &p, want, "selfcol_store_options", field, value);
        selfcol_store *s = NULL;
        assert_int_equal(selfcol_store_create(&s, &o), checked);
        selfcol_store_destroy(s);
    }
}

static void test_sequence_and_context_options_name_the_field(void **state) {
    (void)state;
    selfcol_sequence_options so;
    selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    so.skin = -1.0;
    selfcol_options_problem p = fresh_problem();
    int checked = selfcol_sequence_options_check(&so, &p);
    expect(checked, &p, SELFCOL_EINVAL, "selfcol_sequence_options", "skin", "= -1");
    selfcol_sequence *seq = NULL;
    assert_int_equal(selfcol_sequence_create(&seq, &so), checked);
    so.skin = 0.5;
    p = fresh_problem();
    expect(selfcol_sequence_options_check(&so, &p), &p, SELFCOL_OK, "", "", NULL);

    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.finish_task = dummy_finish; // never called: refused first
    p = fresh_problem();
    checked = selfcol_context_options_check(&co, &p);
    expect(checked, &p, SELFCOL_EINVAL, "selfcol_context_options", "enqueue_task",
           "finish_task is set");
    selfcol_context *c = NULL;
    assert_int_equal(selfcol_context_create(&c, &co), checked);
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = 0;
    p = fresh_problem();
    checked = selfcol_context_options_check(&co, &p);
    expect(checked, &p, SELFCOL_EINVAL, "selfcol_context_options", "threads", "= 0");
    assert_int_equal(selfcol_context_create(&c, &co), checked);
}

static void test_sweep_options_name_the_field(void **state) {
    world *w = *state;
    const double *start = selfcol_mesh_positions(w->mesh);
    selfcol_sweep_options o;
    for (int k = 0; k < 8; ++k) {
        selfcol_sweep_options_init(&o, SELFCOL_SWEEP_OPTIONS_VERSION);
        const char *field = NULL, *value = NULL;
        int want = SELFCOL_EINVAL;
        switch (k) {
        case 0:
            o.method = SELFCOL_METHOD_SEED;
            field = "method";
            value = "SEED";
            break;
        case 1:
            o.kinds = SELFCOL_KIND_EF;
            field = "kinds";
            break;
        case 2:
            o.mode = 7;
            field = "mode";
            value = "= 7";
            break;
        case 3:
            o.separation = INFINITY;
            field = "separation";
            value = "inf";
            break;
        case 4:
            o.version = 2; // 0.3's layout, with threads (the context's since 0.4)
            field = "version";
            value = "older layout";
            want = SELFCOL_EVERSION;
            break;
        case 5:
            o.tolerance = 0.5;
            field = "tolerance";
            value = "0.5";
            break;
        case 6:
            o.tolerance = NAN;
            field = "tolerance";
            value = "nan";
            break;
        default: field = ""; want = SELFCOL_OK;
        }
        selfcol_options_problem p = fresh_problem();
        const int checked = selfcol_sweep_options_check(&o, &p);
        expect(checked, &p, want, "selfcol_sweep_options", field, value);
        assert_int_equal(selfcol_hierarchy_self_sweep(w->hierarchy, start, w->sweep, &o), checked);
    }
}

static void test_scene_options_name_nested_fields(void **state) {
    (void)state;
    selfcol_options_problem p = fresh_problem();
    expect(selfcol_scene_options_check(NULL, &p), &p, SELFCOL_EINVAL, "selfcol_scene_create",
           "opts", "NULL");
    selfcol_scene_options o;
    selfcol_query_options q;
    selfcol_store_options st;
    selfcol_sequence_options sq;
    for (int k = 0; k < 11; ++k) {
        selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
        selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
        selfcol_store_options_init(&st, SELFCOL_STORE_OPTIONS_VERSION);
        selfcol_sequence_options_init(&sq, SELFCOL_SEQUENCE_OPTIONS_VERSION);
        q.distance = 0.1;
        o.query = &q;
        o.store = &st;
        o.sequence = &sq;
        const char *field = NULL, *value = NULL;
        int want = SELFCOL_EINVAL;
        switch (k) {
        case 0:
            q.distance = 0.0;
            field = "query->distance";
            value = "distance > 0";
            break;
        case 1:
            q.version = 2; // 0.3's layout, with threads
            field = "query->version";
            value = "older layout";
            want = SELFCOL_EVERSION;
            break;
        case 2:
            st.first_orientation = 1;
            field = "store->first_orientation";
            break;
        case 3:
            st.remnance_frames = 1, st.consistency = 5;
            field = "store->consistency";
            break;
        case 4:
            sq.skin = NAN;
            field = "sequence->skin";
            value = "nan";
            break;
        case 5:
            o.collider_tolerance = -1.0;
            field = "collider_tolerance";
            break;
        case 6:
            o.coherent = 2;
            field = "coherent";
            break;
        case 7:
            st.version = 0;
            field = "store->version";
            want = SELFCOL_EVERSION;
            break;
        case 8:
            o.query = NULL; // a scene has no default distance
            field = "query";
            value = "NULL";
            break;
        case 9:
            o.store = NULL; // NULL store and sequence options: their defaults
            o.sequence = NULL;
            field = "";
            want = SELFCOL_OK;
            break;
        default: field = ""; want = SELFCOL_OK;
        }
        p = fresh_problem();
        const int checked = selfcol_scene_options_check(&o, &p);
        expect(checked, &p, want, "selfcol_scene_options", field, value);
        selfcol_scene *s = NULL;
        assert_int_equal(selfcol_scene_create(&s, &o), checked);
        selfcol_scene_destroy(s);
    }
}

static void test_the_problem_is_checked_too(void **state) {
    (void)state;
    assert_int_equal(selfcol_query_options_check(NULL, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_store_options_check(NULL, NULL), SELFCOL_EINVAL);
    selfcol_options_problem p = fresh_problem();
    p.version = 0;
    assert_int_equal(selfcol_query_options_check(NULL, &p), SELFCOL_EVERSION);
    p.version = SELFCOL_OPTIONS_PROBLEM_VERSION + 1;
    assert_int_equal(selfcol_sweep_options_check(NULL, &p), SELFCOL_EVERSION);
    // A long sentence is cut, still terminated.
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = -1e300;
    p = fresh_problem();
    assert_int_equal(selfcol_query_options_check(&o, &p), SELFCOL_EINVAL);
    assert_true(strlen(p.message) < sizeof p.message);
    assert_non_null(strstr(p.message, "-1e+300"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_query_options_name_the_field),
        cmocka_unit_test(test_hierarchy_options_name_the_field),
        cmocka_unit_test(test_store_options_name_the_field),
        cmocka_unit_test(test_sequence_and_context_options_name_the_field),
        cmocka_unit_test(test_sweep_options_name_the_field),
        cmocka_unit_test(test_scene_options_name_nested_fields),
        cmocka_unit_test(test_the_problem_is_checked_too),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
