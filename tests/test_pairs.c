// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The narrow phase's filter cascade (pairs.c) and the record sort, through
// the public API: the hierarchy methods must report exactly the exhaustive
// search's contacts on pairs placed at the detection distance itself (where a
// filter that rejected too much would first show), across scales and far
// from the origin, and the records must come out sorted with the
// statistics of version 4 consistent.
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

// A small deterministic generator (xorshift64*), so failures reproduce.
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double uniform(void) {
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1p-53;
}

typedef struct pair_meshes {
    double xyz[18];
    uint32_t tri[6];
} pair_meshes;

// Two triangles near each other: A random in the unit cube, B a random
// triangle moved so that it nearly touches A (a gap of about `gap`), all
// scaled by `scale` and moved by `offset`.
static void make_pair(pair_meshes *p, double scale, double offset, double gap) {
    for (int i = 0; i < 9; ++i)
        p->xyz[i] = uniform();
    double normal_hint[3] = {uniform() - 0.5, uniform() - 0.5, uniform() - 0.5};
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k)
            p->xyz[9 + 3 * v + k] =
                p->xyz[3 * v + k] + 0.5 * (uniform() - 0.5) + gap * normal_hint[k];
    for (int i = 0; i < 18; ++i)
        p->xyz[i] = p->xyz[i] * scale + offset;
    for (int i = 0; i < 6; ++i)
        p->tri[i] = (uint32_t)i;
}

static void assert_sorted(const selfcol_contacts *c) {
    const selfcol_contact *x;
    size_t n;
    selfcol_contacts_data(c, &x, &n);
    for (size_t i = 1; i < n; ++i) {
        const uint32_t a[5] = {x[i - 1].kind, x[i - 1].first_mesh, x[i - 1].first,
                               x[i - 1].second_mesh, x[i - 1].second};
        const uint32_t b[5] = {x[i].kind, x[i].first_mesh, x[i].first, x[i].second_mesh,
                               x[i].second};
        int order = 0;
        for (int k = 0; k < 5 && order == 0; ++k)
            order = a[k] < b[k] ? -1 : (a[k] > b[k] ? 1 : 0);
        assert_true(order < 0);
    }
}

// One trial: the self query over the two triangles (one mesh, two
// components) and the two-mesh query, at distance d, with every method,
// against EXHAUSTIVE. Returns the number of contacts of the self query.
static size_t check_trial(const pair_meshes *p, double d) {
    selfcol_mesh *both = NULL, *ma = NULL, *mb = NULL;
    assert_int_equal(selfcol_mesh_create(&both, 6, p->xyz, 2, p->tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&ma, 3, p->xyz, 1, p->tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&mb, 3, p->xyz + 9, 1, p->tri, NULL), SELFCOL_OK);
    selfcol_hierarchy *hb = NULL, *ha = NULL, *hm = NULL;
    assert_int_equal(selfcol_hierarchy_create(&hb, both, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&ha, ma, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&hm, mb, NULL), SELFCOL_OK);
    selfcol_contacts *ref = NULL, *got = NULL;
    assert_int_equal(selfcol_contacts_create(&ref, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.distance = d;
    size_t self_contacts = 0;
    for (int two = 0; two < 2; ++two) {
        o.method = SELFCOL_METHOD_EXHAUSTIVE;
        assert_int_equal(two ? selfcol_hierarchy_collide(ha, hm, ref, &o)
                             : selfcol_hierarchy_self_collide(hb, ref, &o),
                         SELFCOL_OK);
        size_t nr;
        contact_key *kr = contact_keys_of(ref, &nr);
        if (!two)
            self_contacts = nr;
        const uint32_t methods[2] = {SELFCOL_METHOD_BVH, SELFCOL_METHOD_EXACT};
        for (int m = 0; m < 2; ++m) {
            o.method = methods[m];
            assert_int_equal(two ? selfcol_hierarchy_collide(ha, hm, got, &o)
                                 : selfcol_hierarchy_self_collide(hb, got, &o),
                             SELFCOL_OK);
            size_t ng;
            contact_key *kg = contact_keys_of(got, &ng);
            if (!contact_keys_equal(kr, nr, kg, ng))
                fail_msg("method %u, %s query, d = %.17g: %zu contacts, EXHAUSTIVE %zu", methods[m],
                         two ? "two-mesh" : "self", d, ng, nr);
            assert_sorted(got);
            free(kg);
        }
        free(kr);
    }
    selfcol_contacts_destroy(got);
    selfcol_contacts_destroy(ref);
    selfcol_hierarchy_destroy(hm);
    selfcol_hierarchy_destroy(ha);
    selfcol_hierarchy_destroy(hb);
    selfcol_mesh_destroy(mb);
    selfcol_mesh_destroy(ma);
    selfcol_mesh_destroy(both);
    return self_contacts;
}

// The distances the exhaustive search finds at a generous d: each one, and
// its neighbours one ulp below and above, becomes a detection distance of its
// own, so that every contact sits exactly on the threshold in some trial.
static void test_pairs_filters_agree_with_exhaustive_at_the_threshold(void **state) {
    (void)state;
    const double scales[] = {1.0, 1e-4, 1e4};
    const double offsets[] = {0.0, 1e3, -1e5};
    size_t trials = 0, on_threshold = 0;
    for (int s = 0; s < 3; ++s) {
        for (int o = 0; o < 3; ++o) {
            for (int r = 0; r < 12; ++r) {
                pair_meshes p;
                make_pair(&p, scales[s], offsets[o] * scales[s], 0.05 + 0.1 * uniform());
                // Every contact distance at a generous d.
                selfcol_mesh *m = NULL;
                selfcol_hierarchy *h = NULL;
                selfcol_contacts *c = NULL;
                assert_int_equal(selfcol_mesh_create(&m, 6, p.xyz, 2, p.tri, NULL), SELFCOL_OK);
                assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
                assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
                selfcol_query_options q;
                selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
                q.method = SELFCOL_METHOD_EXHAUSTIVE;
                q.distance = 0.5 * scales[s];
                assert_int_equal(selfcol_hierarchy_self_collide(h, c, &q), SELFCOL_OK);
                const selfcol_contact *x;
                size_t n;
                selfcol_contacts_data(c, &x, &n);
                double distances[32];
                size_t count = 0;
                for (size_t i = 0; i < n && count < 32; ++i)
                    if (x[i].distance > 0.0)
                        distances[count++] = x[i].distance;
                selfcol_contacts_destroy(c);
                selfcol_hierarchy_destroy(h);
                selfcol_mesh_destroy(m);
                for (size_t i = 0; i < count; ++i) {
                    const double d[3] = {nextafter(distances[i], 0.0), distances[i],
                                         nextafter(distances[i], INFINITY)};
                    for (int k = 0; k < 3; ++k) {
                        check_trial(&p, d[k]);
                        trials++;
                    }
                    on_threshold++;
                }
                check_trial(&p, 0.0); // crossings only
                trials++;
            }
        }
    }
    print_message("%zu trials, %zu contact distances used as d\n", trials, on_threshold);
    assert_true(on_threshold > 100); // the scenes do put contacts on the threshold
}

// Statistics of version 4: every candidate pair is either separated or
// tested, filtered primitives are not counted as tests, and the sort time is
// part of the total. A caller of version 3 gets nothing past its struct.
static void test_pairs_stats_v4_are_consistent(void **state) {
    (void)state;
    // A strip folded into a flat loop: its layers 0.06 apart, farther than d
    // but with boxes within d (separated pairs), touching at the two bends.
    enum { N = 40 };
    double xyz[2 * (N + 1) * 3];
    uint32_t tri[2 * N * 3];
    for (int i = 0; i <= N; ++i) {
        double angle = 2.0 * 3.14159265358979 * i / N;
        for (int j = 0; j < 2; ++j) {
            double *v = xyz + 3 * (2 * i + j);
            v[0] = cos(angle);
            v[1] = sin(angle) * 0.03 + 0.01 * i / N;
            v[2] = j * 0.3;
        }
    }
    for (int i = 0; i < N; ++i) {
        uint32_t a = (uint32_t)(2 * i), b = a + 1, c = a + 2, e = a + 3;
        uint32_t *t = tri + 6 * i;
        t[0] = a, t[1] = c, t[2] = b, t[3] = b, t[4] = c, t[5] = e;
    }
    selfcol_mesh *m = NULL;
    selfcol_hierarchy *h = NULL;
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_mesh_create(&m, 2 * (N + 1), xyz, 2 * N, tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = SELFCOL_METHOD_BVH;
    o.distance = 0.05;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    selfcol_query_stats st;
    memset(&st, 0xAB, sizeof st);
    st.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(c, &st), SELFCOL_OK);
    assert_true(st.triangle_pairs > 0);
    assert_true(st.pairs_separated > 0);
    assert_true(st.pairs_separated < st.triangle_pairs);
    assert_true(st.vf_contacts <= st.vf_tests && st.ee_contacts <= st.ee_tests &&
                st.ef_contacts <= st.ef_tests);
    assert_true(st.vf_contacts + st.ee_contacts + st.ef_contacts == selfcol_contacts_count(c));
    assert_true(st.sort_seconds >= 0.0 && st.sort_seconds <= st.total_seconds);
    // The same contacts as EXHAUSTIVE, whose tests include what the filters
    // spared: the hierarchy made fewer closed-form tests.
    size_t n_bvh;
    contact_key *k_bvh = contact_keys_of(c, &n_bvh);
    uint64_t tests_bvh = st.vf_tests + st.ee_tests + st.ef_tests;
    o.method = SELFCOL_METHOD_EXHAUSTIVE;
    assert_int_equal(selfcol_hierarchy_self_collide(h, c, &o), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_stats(c, &st), SELFCOL_OK);
    size_t n_ref;
    contact_key *k_ref = contact_keys_of(c, &n_ref);
    assert_true(contact_keys_equal(k_ref, n_ref, k_bvh, n_bvh));
    assert_true(n_ref > 0);
    assert_true(tests_bvh < st.vf_tests + st.ee_tests + st.ef_tests);
    assert_int_equal(st.pairs_separated, 0); // no candidates pairs in the reference
    free(k_ref);
    free(k_bvh);
    // A version-3 caller: the v4 fields stay as the caller left them.
    selfcol_query_stats old;
    memset(&old, 0xCD, sizeof old);
    old.version = 3;
    assert_int_equal(selfcol_contacts_stats(c, &old), SELFCOL_OK);
    const unsigned char *tail = (const unsigned char *)&old.pairs_separated;
    for (size_t i = 0; i < sizeof old - offsetof(selfcol_query_stats, pairs_separated); ++i)
        assert_int_equal(tail[i], 0xCD);
    selfcol_contacts_destroy(c);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pairs_filters_agree_with_exhaustive_at_the_threshold),
        cmocka_unit_test(test_pairs_stats_v4_are_consistent),
    };
    return cmocka_run_group_tests_name("pairs", tests, NULL, NULL);
}
