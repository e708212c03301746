// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Query options and dispatch (lib/query/query.c) through the public API:
// - selfcol_query_options_init: versions, defaults, and a version-1 struct
//   written no further than its end (guard bytes);
// - every invalid field refused with SELFCOL_EINVAL (SELFCOL_EVERSION for
//   the version) by every method, self and two-mesh, and the distance's
//   upper bound SELFCOL_MESH_MAX_COORDINATE itself accepted (every pair is
//   then a contact: counted by hand);
// - NULL options are the defaults, record for record;
// - a two-mesh query on a mesh created at a destroyed mesh's address is
//   SELFCOL_EMISMATCH;
// - the kinds mask selects exactly the records of those kinds of the full
//   query, and no test of the others is made;
// - the libccd narrow phase finds the closed form's contact keys, within
//   its documented tolerance, with the same distances.
// Held elsewhere, not repeated here: EXHAUSTIVE's refusal of NaN, negative
// and infinite distances, unknown method, narrow and kinds, version 0
// (test_exhaustive.c); threads bounds and version-1 structs in a query
// (test_threads.c); the same mesh twice in selfcol_hierarchy_collide
// (test_exhaustive.c); a self query or refit on a mesh at a destroyed mesh's
// address (test_store.c).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "test_alloc.h"

#include "contact_keys.h"
#include "fixtures.h"
#include "world.h"

static selfcol_query_options options(uint32_t method, double d) {
    selfcol_query_options q;
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION), SELFCOL_OK);
    q.method = method;
    q.distance = d;
    return q;
}

static int query(const world *a, const world *b, const selfcol_query_options *q) {
    return b == NULL ? selfcol_hierarchy_self_collide(a->hierarchy, a->contacts, q)
                     : selfcol_hierarchy_collide(a->hierarchy, b->hierarchy, a->contacts, q);
}

static void query_ok(const world *a, const world *b, const selfcol_query_options *q) {
    int status = query(a, b, q);
    if (status != SELFCOL_OK)
        fail_msg("method %u: %s", q->method, selfcol_status_string(status));
}

static void test_options_init_checks_version_and_writes_only_its_version(void **state) {
    (void)state;
    selfcol_query_options q;
    assert_int_equal(selfcol_query_options_init(NULL, SELFCOL_QUERY_OPTIONS_VERSION),
                     SELFCOL_EINVAL);
    assert_int_equal(selfcol_query_options_init(&q, 0), SELFCOL_EVERSION);
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION + 1),
                     SELFCOL_EVERSION);
    // 0.3's layouts (version 2 had `threads`, which 0.4 moved to the
    // context) are refused and left unwritten; the current version writes
    // the defaults of every field.
    for (unsigned version = 1; version < SELFCOL_QUERY_OPTIONS_VERSION; ++version) {
        memset(&q, 0xA5, sizeof q);
        assert_int_equal(selfcol_query_options_init(&q, version), SELFCOL_EVERSION);
        const unsigned char *bytes = (const unsigned char *)&q;
        for (size_t i = 0; i < sizeof q; ++i)
            assert_int_equal(bytes[i], 0xA5);
    }
    memset(&q, 0xA5, sizeof q);
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION), SELFCOL_OK);
    assert_int_equal(q.version, SELFCOL_QUERY_OPTIONS_VERSION);
    assert_int_equal(q.method, SELFCOL_METHOD_EXACT);
    assert_int_equal(q.narrow, SELFCOL_NARROW_CLOSED_FORM);
    assert_int_equal(q.kinds, SELFCOL_KIND_ALL);
    assert_true(q.distance == 0.0);
}

// One invalid field at a time, from valid options.
typedef struct bad_field {
    const char *what;
    void (*spoil)(selfcol_query_options *q);
    int status;
} bad_field;

static void method_past_exact(selfcol_query_options *q) {
    q->method = SELFCOL_METHOD_EXACT + 1;
}
static void method_max(selfcol_query_options *q) {
    q->method = UINT32_MAX;
}
static void narrow_unknown(selfcol_query_options *q) {
    q->narrow = SELFCOL_NARROW_LIBCCD + 1;
}
static void kinds_next_bit(selfcol_query_options *q) {
    q->kinds = SELFCOL_KIND_ALL | (SELFCOL_KIND_EF << 1);
}
static void kinds_top_bit(selfcol_query_options *q) {
    q->kinds = SELFCOL_KIND_VF | 0x80000000u;
}
static void distance_nan(selfcol_query_options *q) {
    q->distance = NAN;
}
static void distance_negative(selfcol_query_options *q) {
    q->distance = -0.1;
}
static void distance_tiny_negative(selfcol_query_options *q) {
    q->distance = -nextafter(0.0, 1.0); // the negative double nearest 0
}
static void distance_minus_infinity(selfcol_query_options *q) {
    q->distance = -INFINITY;
}
static void distance_infinity(selfcol_query_options *q) {
    q->distance = INFINITY;
}
static void distance_above_bound(selfcol_query_options *q) {
    q->distance = nextafter(SELFCOL_MESH_MAX_COORDINATE, INFINITY);
}
static void distance_max(selfcol_query_options *q) {
    q->distance = DBL_MAX;
}
static void version_of_0_3(selfcol_query_options *q) {
    q->version = 2; // 0.3's layout, with threads
}
static void version_zero(selfcol_query_options *q) {
    q->version = 0;
}
static void version_too_new(selfcol_query_options *q) {
    q->version = SELFCOL_QUERY_OPTIONS_VERSION + 1;
}

static void test_every_invalid_field_is_refused_by_every_method(void **state) {
    (void)state;
    const bad_field bad[] = {
        {"method past EXACT", method_past_exact, SELFCOL_EINVAL},
        {"method UINT32_MAX", method_max, SELFCOL_EINVAL},
        {"unknown narrow phase", narrow_unknown, SELFCOL_EINVAL},
        {"kinds with the bit after EF", kinds_next_bit, SELFCOL_EINVAL},
        {"kinds with the top bit", kinds_top_bit, SELFCOL_EINVAL},
        {"distance NaN", distance_nan, SELFCOL_EINVAL},
        {"distance -0.1", distance_negative, SELFCOL_EINVAL},
        {"distance -(least subnormal)", distance_tiny_negative, SELFCOL_EINVAL},
        {"distance -inf", distance_minus_infinity, SELFCOL_EINVAL},
        {"distance +inf", distance_infinity, SELFCOL_EINVAL},
        {"distance just above SELFCOL_MESH_MAX_COORDINATE", distance_above_bound, SELFCOL_EINVAL},
        {"distance DBL_MAX", distance_max, SELFCOL_EINVAL},
        {"version 2 (0.3's, with threads)", version_of_0_3, SELFCOL_EVERSION},
        {"version 0", version_zero, SELFCOL_EVERSION},
        {"version too new", version_too_new, SELFCOL_EVERSION},
    };
    fixture sa, sb;
    assert_int_equal(fixture_sheet_pair(&sa, &sb, 6, 4, 1.0, 0.0), 0);
    world a, b;
    world_make(&a, &sa);
    world_make(&b, &sb);
    for (uint32_t m = SELFCOL_METHOD_EXHAUSTIVE; m <= SELFCOL_METHOD_EXACT; ++m)
        for (int two = 0; two < 2; ++two) {
            selfcol_query_options good = options(m, 0.1);
            query_ok(&a, two ? &b : NULL, &good);
            for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
                selfcol_query_options q = good;
                bad[i].spoil(&q);
                int status = query(&a, two ? &b : NULL, &q);
                if (status != bad[i].status)
                    fail_msg("method %u, %s query, %s: %s", m, two ? "two-mesh" : "self",
                             bad[i].what, selfcol_status_string(status));
            }
        }
    // NULL handles.
    selfcol_query_options q = options(SELFCOL_METHOD_BVH, 0.1);
    assert_int_equal(selfcol_hierarchy_collide(NULL, b.hierarchy, a.contacts, &q), SELFCOL_EINVAL);
    assert_int_equal(selfcol_hierarchy_collide(a.hierarchy, NULL, a.contacts, &q), SELFCOL_EINVAL);
    assert_int_equal(selfcol_hierarchy_collide(a.hierarchy, b.hierarchy, NULL, &q), SELFCOL_EINVAL);
    world_free(&a);
    world_free(&b);
    fixture_free(&sa);
    fixture_free(&sb);
}

// The distance's bound itself is valid (hierarchy.h refuses only what lies
// above it). At that distance every candidate pair is a contact: every
// vertex with every triangle it is not a corner of, every two edges without
// a common vertex (docs/contract.md section 1), counted here by hand; the
// hairpin's layers never cross, so no EF. Every exact method finds them
// (SEED and CONE skip smooth patches whatever d is).
static void test_distance_at_the_coordinate_bound_makes_every_pair_a_contact(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_hairpin(&s, 3, 0.2), 0);
    world w;
    world_make(&w, &s);
    uint64_t vf = 0, ee = 0;
    for (uint32_t v = 0; v < s.vertex_count; ++v)
        for (size_t t = 0; t < s.triangle_count; ++t) {
            const uint32_t *c = s.triangles + 3 * t;
            vf += c[0] != v && c[1] != v && c[2] != v;
        }
    const size_t edge_count = selfcol_mesh_count(w.mesh, SELFCOL_MESH_EDGES);
    const uint32_t *e = selfcol_mesh_edges(w.mesh);
    for (size_t i = 0; i < edge_count; ++i)
        for (size_t j = i + 1; j < edge_count; ++j)
            ee += e[2 * i] != e[2 * j] && e[2 * i] != e[2 * j + 1] && e[2 * i + 1] != e[2 * j] &&
                  e[2 * i + 1] != e[2 * j + 1];
    assert_true(vf > 0 && ee > 0);
    const uint32_t exact_methods[3] = {SELFCOL_METHOD_EXHAUSTIVE, SELFCOL_METHOD_BVH,
                                       SELFCOL_METHOD_EXACT};
    for (int mi = 0; mi < 3; ++mi) {
        const uint32_t m = exact_methods[mi];
        selfcol_query_options q = options(m, SELFCOL_MESH_MAX_COORDINATE);
        query_ok(&w, NULL, &q);
        selfcol_query_stats st = query_counters(w.contacts);
        if (st.vf_contacts != vf || st.ee_contacts != ee || st.ef_contacts != 0)
            fail_msg("method %u at d = SELFCOL_MESH_MAX_COORDINATE: VF %llu (every pair: %llu), "
                     "EE %llu (%llu), EF %llu (0)",
                     m, (unsigned long long)st.vf_contacts, (unsigned long long)vf,
                     (unsigned long long)st.ee_contacts, (unsigned long long)ee,
                     (unsigned long long)st.ef_contacts);
        assert_int_equal(selfcol_contacts_count(w.contacts), vf + ee);
        // Every distance is finite and far below d.
        const selfcol_contact *c;
        size_t n;
        selfcol_contacts_data(w.contacts, &c, &n);
        for (size_t i = 0; i < n; ++i)
            assert_true(isfinite(c[i].distance) && c[i].distance < 10.0);
    }
    world_free(&w);
    fixture_free(&s);
}

// NULL options run the defaults: the records and the counters of an
// explicitly initialised struct, self and between two meshes.
static void test_null_options_are_the_defaults(void **state) {
    (void)state;
    fixture sa, sb;
    assert_int_equal(fixture_sheet_pair(&sa, &sb, 10, 4, 1.0, 0.0), 0);
    assert_int_equal(fixture_append(&sa, &sb), 0); // a: both sheets, crossing each other
    world a, b, defaults;
    world_make(&a, &sa);
    world_make(&b, &sb);
    world_make(&defaults, &sb); // only its contact set is used
    selfcol_query_options q;
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION), SELFCOL_OK);
    for (int two = 0; two < 2; ++two) {
        world *other = two ? &b : NULL;
        // NULL into a's set, the initialised struct into defaults' set.
        int status = two ? selfcol_hierarchy_collide(a.hierarchy, b.hierarchy, a.contacts, NULL)
                         : selfcol_hierarchy_self_collide(a.hierarchy, a.contacts, NULL);
        assert_int_equal(status, SELFCOL_OK);
        status =
            two ? selfcol_hierarchy_collide(a.hierarchy, other->hierarchy, defaults.contacts, &q)
                : selfcol_hierarchy_self_collide(a.hierarchy, defaults.contacts, &q);
        assert_int_equal(status, SELFCOL_OK);
        const selfcol_contact *x, *y;
        size_t nx, ny;
        selfcol_contacts_data(a.contacts, &x, &nx);
        selfcol_contacts_data(defaults.contacts, &y, &ny);
        assert_true(nx > 0); // the sheets cross: EF at d = 0
        assert_int_equal(nx, ny);
        assert_memory_equal(x, y, nx * sizeof *x);
        selfcol_query_stats sx = query_counters(a.contacts), sy = query_counters(defaults.contacts);
        assert_memory_equal(&sx, &sy, sizeof sx);
        // The default distance is 0: interferences only; the default method
        // is EXACT, which culls (self) by curvature.
        assert_int_equal(sx.vf_contacts + sx.ee_contacts, 0);
        assert_true(sx.ef_contacts > 0);
        assert_true(sx.nodes_visited > 0);
        if (!two)
            assert_true(sx.contour_tests > 0);
    }
    world_free(&a);
    world_free(&b);
    world_free(&defaults);
    fixture_free(&sa);
    fixture_free(&sb);
}

// A hierarchy whose mesh was destroyed and replaced, at the same address,
// by another mesh: a two-mesh query is SELFCOL_EMISMATCH in either order,
// whatever the method (the self query and the refit: test_store.c).
static void test_two_mesh_query_on_a_replaced_mesh_is_a_mismatch(void **state) {
    (void)state;
    reuse_pool pool;
    memset(&pool, 0, sizeof pool);
    selfcol_mesh_options mo;
    selfcol_mesh_options_init(&mo, SELFCOL_MESH_OPTIONS_VERSION);
    mo.allocator = reuse_pool_allocator(&pool);
    fixture big, small, other;
    assert_int_equal(fixture_grid(&big, 8, 8, 1.0), 0);
    assert_int_equal(fixture_grid(&small, 3, 3, 1.0), 0);
    assert_int_equal(fixture_grid(&other, 4, 4, 1.0), 0);
    selfcol_mesh *m = NULL, *replaced = NULL;
    assert_int_equal(selfcol_mesh_create(&m, big.vertex_count, big.positions, big.triangle_count,
                                         big.triangles, &mo),
                     SELFCOL_OK);
    selfcol_hierarchy *h = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    world o;
    world_make(&o, &other);
    selfcol_query_options q = options(SELFCOL_METHOD_BVH, 0.1);
    assert_int_equal(selfcol_hierarchy_collide(h, o.hierarchy, o.contacts, &q), SELFCOL_OK);
    selfcol_mesh_destroy(m);
    assert_int_equal(selfcol_mesh_create(&replaced, small.vertex_count, small.positions,
                                         small.triangle_count, small.triangles, &mo),
                     SELFCOL_OK);
    assert_ptr_equal(replaced, m); // the pool handed the block back
    for (uint32_t method = SELFCOL_METHOD_EXHAUSTIVE; method <= SELFCOL_METHOD_EXACT; ++method) {
        q.method = method;
        assert_int_equal(selfcol_hierarchy_collide(h, o.hierarchy, o.contacts, &q),
                         SELFCOL_EMISMATCH);
        assert_int_equal(selfcol_hierarchy_collide(o.hierarchy, h, o.contacts, &q),
                         SELFCOL_EMISMATCH);
    }
    // The same topology with other positions, at the same address again: still
    // another mesh (its identity holds its creation time), for the self query,
    // the refit and the two-mesh query alike.
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(replaced);
    assert_int_equal(selfcol_mesh_create(&m, big.vertex_count, big.positions, big.triangle_count,
                                         big.triangles, &mo),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    selfcol_mesh_destroy(m);
    for (size_t i = 0; i < big.vertex_count; ++i)
        big.positions[3 * i + 2] = 0.3 * sin((double)i);
    assert_int_equal(selfcol_mesh_create(&replaced, big.vertex_count, big.positions,
                                         big.triangle_count, big.triangles, &mo),
                     SELFCOL_OK);
    assert_ptr_equal(replaced, m);
    q.method = SELFCOL_METHOD_BVH;
    assert_int_equal(selfcol_hierarchy_self_collide(h, o.contacts, &q), SELFCOL_EMISMATCH);
    assert_int_equal(selfcol_hierarchy_refit(h), SELFCOL_EMISMATCH);
    assert_int_equal(selfcol_hierarchy_collide(h, o.hierarchy, o.contacts, &q), SELFCOL_EMISMATCH);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(replaced);
    reuse_pool_release(&pool);
    world_free(&o);
    fixture_free(&big);
    fixture_free(&small);
    fixture_free(&other);
}

// Every mask of kinds gives exactly the records of those kinds in the full
// query, byte for byte and in order, for every exact method, self and
// between two meshes; the kinds left out are neither found nor tested.
static void check_masks(const world *a, const world *b, double d, const char *name) {
    for (uint32_t m = SELFCOL_METHOD_EXHAUSTIVE; m <= SELFCOL_METHOD_EXACT; ++m) {
        if (m == SELFCOL_METHOD_SEED || m == SELFCOL_METHOD_CONE)
            continue; // not exact: their contact sets are not the contract's
        selfcol_query_options q = options(m, d);
        query_ok(a, b, &q);
        const selfcol_contact *all;
        size_t n_all;
        selfcol_contacts_data(a->contacts, &all, &n_all);
        selfcol_contact *full = malloc((n_all + 1) * sizeof *full);
        assert_non_null(full);
        if (n_all > 0)
            memcpy(full, all, n_all * sizeof *full);
        size_t per_kind[3] = {0, 0, 0};
        for (size_t i = 0; i < n_all; ++i)
            per_kind[full[i].kind]++;
        for (int k = 0; k < 3; ++k)
            if (per_kind[k] == 0)
                fail_msg("%s, method %u: no contact of kind %d (the scene must have all three)",
                         name, m, k);
        for (uint32_t mask = 0; mask <= SELFCOL_KIND_ALL; ++mask) {
            q.kinds = mask;
            query_ok(a, b, &q);
            const selfcol_contact *got;
            size_t n_got;
            selfcol_contacts_data(a->contacts, &got, &n_got);
            size_t j = 0;
            for (size_t i = 0; i < n_all; ++i) {
                if (!(mask & (1u << full[i].kind)))
                    continue;
                if (j >= n_got || memcmp(&full[i], &got[j], sizeof full[i]) != 0)
                    fail_msg("%s, method %u, kinds 0x%x: record %zu of the full query (kind %u, "
                             "%u | %u) differs or is missing",
                             name, m, mask, i, full[i].kind, full[i].first, full[i].second);
                ++j;
            }
            if (j != n_got)
                fail_msg("%s, method %u, kinds 0x%x: %zu records, %zu expected", name, m, mask,
                         n_got, j);
            selfcol_query_stats st = query_counters(a->contacts);
            if (!(mask & SELFCOL_KIND_VF))
                assert_int_equal(st.vf_tests + st.vf_contacts, 0);
            if (!(mask & SELFCOL_KIND_EE))
                assert_int_equal(st.ee_tests + st.ee_contacts, 0);
            if (!(mask & SELFCOL_KIND_EF))
                assert_int_equal(st.ef_tests + st.ef_contacts, 0);
        }
        free(full);
    }
}

static void test_kinds_mask_selects_exactly_those_kinds(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 14, 10, 2, 5.0), 0);
    world w;
    world_make(&w, &s);
    check_masks(&w, NULL, 0.3 * selfcol_mesh_mean_edge_length(w.mesh), "crumpled 14x10");
    world_free(&w);
    fixture_free(&s);
    fixture sa, sb;
    assert_int_equal(fixture_sheet_pair(&sa, &sb, 10, 4, 1.0, 0.0), 0);
    world a, b;
    world_make(&a, &sa);
    world_make(&b, &sb);
    check_masks(&a, &b, 0.3 * selfcol_mesh_mean_edge_length(a.mesh), "crossing sheets");
    world_free(&a);
    world_free(&b);
    fixture_free(&sa);
    fixture_free(&sb);
}

static int key_cmp(const contact_key *a, const contact_key *b) {
    for (int k = 0; k < 6; ++k)
        if (a->k[k] != b->k[k])
            return a->k[k] < b->k[k] ? -1 : 1;
    return 0;
}

// 1 when every key of a (sorted) is in b (sorted); else prints the first
// that is not.
static int keys_subset(const contact_key *a, size_t na, const contact_key *b, size_t nb,
                       const char *what) {
    size_t j = 0;
    for (size_t i = 0; i < na; ++i) {
        while (j < nb && key_cmp(&b[j], &a[i]) < 0)
            ++j;
        if (j == nb || key_cmp(&b[j], &a[i]) != 0) {
            print_error("%s: kind %u (%u %u | %u %u %u) missing\n", what, a[i].k[0], a[i].k[1],
                        a[i].k[2], a[i].k[3], a[i].k[4], a[i].k[5]);
            return 0;
        }
    }
    return 1;
}

// libccd's narrow phase decides proximities to 1e-7 d (hierarchy.h): its
// set lies between the closed form's at d (1 - 1e-6) and at d (1 + 1e-6),
// its interferences are the closed form's (no edge merely touches a
// triangle on these generic surfaces), and a contact found by both has the
// same distance within that tolerance. BVH and EXACT, self and two-mesh.
static void check_ccd(const world *a, const world *b, double d, const char *name) {
    const uint32_t methods[2] = {SELFCOL_METHOD_BVH, SELFCOL_METHOD_EXACT};
    for (int mi = 0; mi < 2; ++mi) {
        selfcol_query_options q = options(methods[mi], d * (1.0 - 1e-6));
        query_ok(a, b, &q);
        size_t n_inner, n_outer, n_ccd;
        contact_key *inner = contact_keys_of(a->contacts, &n_inner);
        q.distance = d * (1.0 + 1e-6);
        query_ok(a, b, &q);
        contact_key *outer = contact_keys_of(a->contacts, &n_outer);
        const selfcol_contact *cf;
        size_t n_cf;
        selfcol_contacts_data(a->contacts, &cf, &n_cf);
        selfcol_contact *closed = malloc((n_cf + 1) * sizeof *closed);
        assert_non_null(closed);
        if (n_cf > 0)
            memcpy(closed, cf, n_cf * sizeof *closed);
        q.distance = d;
        q.narrow = SELFCOL_NARROW_LIBCCD;
        query_ok(a, b, &q);
        contact_key *ccd = contact_keys_of(a->contacts, &n_ccd);
        if (!keys_subset(inner, n_inner, ccd, n_ccd, "closed form at d (1 - 1e-6) in libccd"))
            fail_msg("%s, method %u: libccd misses a contact of the closed form", name,
                     methods[mi]);
        if (!keys_subset(ccd, n_ccd, outer, n_outer, "libccd in closed form at d (1 + 1e-6)"))
            fail_msg("%s, method %u: libccd reports a contact the closed form does not", name,
                     methods[mi]);
        assert_true(n_inner > 0);
        size_t ef_closed = 0, ef_ccd = 0;
        for (size_t i = 0; i < n_outer; ++i)
            ef_closed += outer[i].k[0] == SELFCOL_CONTACT_EF;
        for (size_t i = 0; i < n_ccd; ++i)
            ef_ccd += ccd[i].k[0] == SELFCOL_CONTACT_EF;
        assert_int_equal(ef_ccd, ef_closed);
        // Distances, matched by record key (both sets are sorted by it).
        const selfcol_contact *c;
        size_t n;
        selfcol_contacts_data(a->contacts, &c, &n);
        size_t j = 0, matched = 0;
        for (size_t i = 0; i < n; ++i) {
            while (
                j < n_cf &&
                (closed[j].kind < c[i].kind ||
                 (closed[j].kind == c[i].kind &&
                  (closed[j].first_mesh < c[i].first_mesh ||
                   (closed[j].first_mesh == c[i].first_mesh &&
                    (closed[j].first < c[i].first || (closed[j].first == c[i].first &&
                                                      (closed[j].second_mesh < c[i].second_mesh ||
                                                       (closed[j].second_mesh == c[i].second_mesh &&
                                                        closed[j].second < c[i].second)))))))))
                ++j;
            assert_true(j < n_cf);
            assert_int_equal(closed[j].kind, c[i].kind);
            assert_int_equal(closed[j].first, c[i].first);
            assert_int_equal(closed[j].second, c[i].second);
            if (fabs(closed[j].distance - c[i].distance) > 2e-6 * d)
                fail_msg("%s, method %u: kind %u (%u | %u): libccd distance %.17g, closed form "
                         "%.17g",
                         name, methods[mi], c[i].kind, c[i].first, c[i].second, c[i].distance,
                         closed[j].distance);
            ++matched;
        }
        assert_int_equal(matched, n_ccd);
        free(inner);
        free(outer);
        free(ccd);
        free(closed);
    }
}

static void test_libccd_agrees_with_the_closed_form(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 12, 10, 4, 5.0), 0);
    world w;
    world_make(&w, &s);
    const double mean = selfcol_mesh_mean_edge_length(w.mesh);
    check_ccd(&w, NULL, 0.1 * mean, "crumpled 12x10");
    check_ccd(&w, NULL, 0.3 * mean, "crumpled 12x10");
    world_free(&w);
    fixture_free(&s);
    fixture sa, sb;
    assert_int_equal(fixture_sheet_pair(&sa, &sb, 8, 4, 1.0, 0.0), 0);
    world a, b;
    world_make(&a, &sa);
    world_make(&b, &sb);
    check_ccd(&a, &b, 0.3 * selfcol_mesh_mean_edge_length(a.mesh), "crossing sheets");
    world_free(&a);
    world_free(&b);
    fixture_free(&sa);
    fixture_free(&sb);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_options_init_checks_version_and_writes_only_its_version),
        cmocka_unit_test(test_every_invalid_field_is_refused_by_every_method),
        cmocka_unit_test(test_distance_at_the_coordinate_bound_makes_every_pair_a_contact),
        cmocka_unit_test(test_null_options_are_the_defaults),
        cmocka_unit_test(test_two_mesh_query_on_a_replaced_mesh_is_a_mismatch),
        cmocka_unit_test(test_kinds_mask_selects_exactly_those_kinds),
        cmocka_unit_test(test_libccd_agrees_with_the_closed_form),
    };
    return cmocka_run_group_tests_name("query", tests, NULL, NULL);
}
