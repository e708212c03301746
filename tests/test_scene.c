// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Scenes (include/selfcol/scene.h), through the public API: which pairs each
// kind is tested in; a static surface is never refit (statistics) and may
// not move; a closed body is never voted, its outward normals give every
// contact's side (whatever the majority, and whichever way it is wound);
// cloth against a capsule collider finds the triangles cloth against a
// finely triangulated capsule finds, with the same distances within the
// triangulation's sagitta; collider and pose errors; no allocation in a
// steady state, and every allocation failure reported and leak-free; the
// step's start given by the caller tells a crossing from a pass-around on the
// path since the last update.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "fixtures.h"
#include "test_alloc.h"

// A store's records, copied into a new array (the caller frees it); the
// meshes have not moved since the scene's update, as the copy requires.
static selfcol_store_contact *copy_records(const selfcol_store *store, size_t *count_out) {
    const size_t n = selfcol_store_contact_count(store);
    selfcol_store_contact *c = malloc((n > 0 ? n : 1) * sizeof *c);
    assert_non_null(c);
    assert_int_equal(selfcol_store_copy_contacts(store, 0, n, c), SELFCOL_OK);
    *count_out = n;
    return c;
}

static selfcol_mesh *mesh_of(const fixture *s) {
    selfcol_mesh *m = NULL;
    assert_int_equal(selfcol_mesh_create(&m, s->vertex_count, s->positions, s->triangle_count,
                                         s->triangles, NULL),
                     SELFCOL_OK);
    return m;
}

// Query options at distance d, the other fields at their defaults.
static selfcol_query_options query_at(double d) {
    selfcol_query_options q;
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION), SELFCOL_OK);
    q.distance = d;
    return q;
}

// Scene options pointing to q and to store and sequence options of their
// own (written with their defaults).
static void point_to(selfcol_scene_options *o, const selfcol_query_options *q,
                     selfcol_store_options *st, selfcol_sequence_options *sq) {
    assert_int_equal(selfcol_store_options_init(st, SELFCOL_STORE_OPTIONS_VERSION), SELFCOL_OK);
    assert_int_equal(selfcol_sequence_options_init(sq, SELFCOL_SEQUENCE_OPTIONS_VERSION),
                     SELFCOL_OK);
    o->query = q;
    o->store = st;
    o->sequence = sq;
}

static selfcol_scene *make_scene(double d, const selfcol_allocator *al) {
    selfcol_scene_options o;
    assert_int_equal(selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION), SELFCOL_OK);
    const selfcol_query_options q = query_at(d);
    o.query = &q;
    if (al != NULL)
        o.allocator = *al;
    selfcol_scene *sc = NULL;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_OK);
    return sc;
}

static uint32_t add(selfcol_scene *sc, const selfcol_mesh *m, uint32_t kind, int self,
                    int orientation) {
    selfcol_scene_surface_options so;
    assert_int_equal(
        selfcol_scene_surface_options_init(&so, kind, SELFCOL_SCENE_SURFACE_OPTIONS_VERSION),
        SELFCOL_OK);
    if (self >= 0)
        so.self_collision = self;
    so.orientation = orientation;
    uint32_t id = 99;
    assert_int_equal(selfcol_scene_add_surface(sc, m, &so, &id), SELFCOL_OK);
    return id;
}

static selfcol_scene_update_stats stats_of(const selfcol_scene *sc) {
    selfcol_scene_update_stats st;
    st.version = SELFCOL_SCENE_UPDATE_STATS_VERSION;
    assert_int_equal(selfcol_scene_stats(sc, &st), SELFCOL_OK);
    return st;
}

static const selfcol_store *store_of(const selfcol_scene *sc, uint32_t a, uint32_t b) {
    const selfcol_store *st = (const selfcol_store *)1;
    assert_int_equal(selfcol_scene_store(sc, a, b, &st), SELFCOL_OK);
    return st;
}

// ---------------------------------------------------------------------------

static void test_pairs_by_kind(void **state) {
    (void)state;
    fixture g[6];
    memset(g, 0, sizeof g);
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(fixture_grid(&g[i], 4, 4, 1.0), 0);
        const double off[3] = {0.0, 0.0, 0.3 * i};
        fixture_translate(&g[i], off);
    }
    assert_int_equal(fixture_icosphere(&g[4], 1, 1.0), 0);
    assert_int_equal(fixture_icosphere(&g[5], 1, 1.0), 0);
    const double aside[3] = {-10.0, 0.0, 0.0}, far[3] = {100.0, 0.0, 0.0};
    fixture_translate(&g[4], aside);
    fixture_translate(&g[5], far);
    selfcol_mesh *m[6];
    for (int i = 0; i < 6; ++i)
        m[i] = mesh_of(&g[i]);
    selfcol_scene *sc = make_scene(0.05, NULL);
    const uint32_t cloth = add(sc, m[0], SELFCOL_SURFACE_CLOTH, -1, 0);
    const uint32_t cloth_noself = add(sc, m[1], SELFCOL_SURFACE_CLOTH, 0, 0);
    const uint32_t static1 = add(sc, m[2], SELFCOL_SURFACE_STATIC, -1, 1);
    const uint32_t static2 = add(sc, m[3], SELFCOL_SURFACE_STATIC, -1, 0);
    const uint32_t body = add(sc, m[4], SELFCOL_SURFACE_BODY, -1, 0);
    const uint32_t body_self = add(sc, m[5], SELFCOL_SURFACE_BODY, 1, 0);
    assert_int_equal(cloth, 0);
    assert_int_equal(body_self, 5);

    // Self pairs: cloth with self-collision and the body that asked for it.
    assert_non_null(store_of(sc, cloth, cloth));
    assert_null(store_of(sc, cloth_noself, cloth_noself));
    assert_null(store_of(sc, static1, static1));
    assert_null(store_of(sc, body, body));
    assert_non_null(store_of(sc, body_self, body_self));
    // Cross pairs: all but static against static.
    assert_null(store_of(sc, static1, static2));
    size_t tested = 0;
    for (uint32_t a = 0; a < 6; ++a)
        for (uint32_t b = a; b < 6; ++b)
            tested += store_of(sc, a, b) != NULL;
    assert_int_equal(tested, 2 + (15 - 1)); // 2 self pairs, 15 cross pairs minus static-static
    const selfcol_store *s;
    assert_int_equal(selfcol_scene_store(sc, 3, 2, &s), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_store(sc, 0, 6, &s), SELFCOL_EINVAL);

    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_scene_update_stats st = stats_of(sc);
    assert_int_equal(st.surfaces, 6);
    assert_int_equal(st.refits, 4); // two cloths, two bodies; never the static surfaces
    assert_int_equal(st.builds, 6);
    assert_int_equal(st.pairs_queried + st.pairs_apart, tested);
    assert_true(st.pairs_apart >= 5); // the far body is apart from the five others
    // The stacked grids 0.3 apart with d = 0.05: no contacts between them.
    assert_int_equal(st.interferences, 0);

    selfcol_scene_destroy(sc);
    for (int i = 0; i < 6; ++i) {
        selfcol_mesh_destroy(m[i]);
        fixture_free(&g[i]);
    }
}

// A cloth lowered onto a static floor over three updates: the static
// hierarchy is never refit, the floor's declared orientation (+1, normals up)
// gives the sides without a vote; moving the floor's mesh is refused.
static void test_static_never_refit(void **state) {
    (void)state;
    fixture floor_s = {0}, cloth_s = {0};
    assert_int_equal(fixture_grid(&floor_s, 6, 6, 1.0), 0);
    assert_int_equal(fixture_grid(&cloth_s, 8, 8, 0.5), 0);
    const double up[3] = {1.2, 1.1, 0.2};
    fixture_translate(&cloth_s, up);
    selfcol_mesh *floor_m = mesh_of(&floor_s), *cloth_m = mesh_of(&cloth_s);
    selfcol_scene *sc = make_scene(0.1, NULL);
    const uint32_t cloth = add(sc, cloth_m, SELFCOL_SURFACE_CLOTH, -1, 0);
    const uint32_t fl = add(sc, floor_m, SELFCOL_SURFACE_STATIC, -1, +1);
    for (int frame = 0; frame < 3; ++frame) {
        const double down[3] = {0.0, 0.0, -0.06};
        fixture_translate(&cloth_s, down);
        assert_int_equal(
            selfcol_mesh_set_positions(cloth_m, cloth_s.positions, cloth_s.vertex_count),
            SELFCOL_OK);
        assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
        const selfcol_scene_update_stats st = stats_of(sc);
        assert_int_equal(st.refits, 1);
        assert_int_equal(st.builds, 2);
    }
    // Cloth at z = 0.02 over the floor: contacts, all oriented, none voted,
    // all on the right side (the cloth is above the floor, its normals' side).
    const selfcol_store *store = store_of(sc, cloth, fl);
    assert_non_null(store);
    selfcol_store_update_stats ss;
    ss.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    assert_int_equal(selfcol_store_stats(store, &ss), SELFCOL_OK);
    assert_true(ss.contacts > 0);
    assert_int_equal(ss.voted, 0);
    assert_int_equal(ss.oriented, ss.contacts);
    size_t n;
    selfcol_store_contact *c = copy_records(store, &n);
    for (size_t i = 0; i < n; ++i) {
        assert_true(c[i].flags & SELFCOL_STORE_ORIENTED);
        assert_true(c[i].signed_distance >= 0.0);
    }
    free(c);
    // Issue "hardening 0.3", item 7: the floor given the very positions it
    // has is not a move (every later update was ESTALE for good before).
    assert_int_equal(selfcol_mesh_set_positions(floor_m, floor_s.positions, floor_s.vertex_count),
                     SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    // The floor moves: refused, nothing updated.
    const double lift[3] = {0.0, 0.0, 0.01};
    fixture_translate(&floor_s, lift);
    assert_int_equal(selfcol_mesh_set_positions(floor_m, floor_s.positions, floor_s.vertex_count),
                     SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_ESTALE);
    // Moved on purpose: set the positions, then rebuild the surface. The
    // floor drops below the cloth's reach: the pair's contacts age out by
    // remnance, the store is the same one.
    const double drop[3] = {0.0, 0.0, -1.0};
    fixture_translate(&floor_s, drop);
    assert_int_equal(selfcol_mesh_set_positions(floor_m, floor_s.positions, floor_s.vertex_count),
                     SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_ESTALE);
    assert_int_equal(selfcol_scene_rebuild_surface(sc, fl), SELFCOL_OK);
    assert_int_equal(stats_of(sc).builds, 3);
    assert_ptr_equal(store_of(sc, cloth, fl), store);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    assert_int_equal(selfcol_store_stats(store, &ss), SELFCOL_OK);
    assert_int_equal(ss.new_contacts + ss.kept, 0); // the floor is 1 below: nothing detected
    assert_true(ss.remnant > 0);                    // held by remnance: the memory kept
    assert_int_equal(selfcol_scene_rebuild_surface(sc, 7), SELFCOL_EINVAL);

    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(cloth_m);
    selfcol_mesh_destroy(floor_m);
    fixture_free(&cloth_s);
    fixture_free(&floor_s);
}

// Removing a surface destroys its pairs' stores only: the others keep their
// contacts and their memory, ids stay, and a later surface gets a new id
// (the Bullet adapter's attach and detach rely on this).
static void test_remove_surface_keeps_the_other_stores(void **state) {
    (void)state;
    fixture low = {0}, high = {0}, far_s = {0};
    assert_int_equal(fixture_grid(&low, 6, 6, 1.0), 0);
    assert_int_equal(fixture_grid(&high, 6, 6, 1.0), 0);
    assert_int_equal(fixture_grid(&far_s, 4, 4, 1.0), 0);
    const double lift[3] = {0.13, 0.07, 0.05}, away[3] = {10.0, 0.0, 0.0};
    fixture_translate(&high, lift);
    fixture_translate(&far_s, away);
    selfcol_mesh *ml = mesh_of(&low), *mh = mesh_of(&high), *mf = mesh_of(&far_s);
    selfcol_scene *sc = make_scene(0.1, NULL);
    const uint32_t l = add(sc, ml, SELFCOL_SURFACE_CLOTH, -1, 0);
    const uint32_t f = add(sc, mf, SELFCOL_SURFACE_CLOTH, -1, 0);
    const uint32_t h = add(sc, mh, SELFCOL_SURFACE_CLOTH, -1, 0);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_store *pair = store_of(sc, l, h);
    assert_non_null(pair);
    const size_t before = selfcol_store_contact_count(pair);
    assert_true(before > 0);

    assert_int_equal(selfcol_scene_remove_surface(sc, f), SELFCOL_OK);
    assert_int_equal(selfcol_scene_remove_surface(sc, f), SELFCOL_EINVAL); // already removed
    selfcol_mesh_destroy(mf); // the scene no longer reads it
    assert_null(store_of(sc, l, f));
    assert_null(store_of(sc, f, h));
    assert_ptr_equal(store_of(sc, l, h), pair); // the same store, contacts held
    assert_int_equal(selfcol_store_contact_count(pair), before);
    assert_int_equal(stats_of(sc).surfaces, 2);

    // The upper sheet pushed through the lower one between two updates: the
    // store remembers the sides, so the contacts flip (a rebuilt scene would
    // have forgotten them).
    const double through[3] = {0.0, 0.0, -0.1};
    fixture_translate(&high, through);
    assert_int_equal(selfcol_mesh_set_positions(mh, high.positions, high.vertex_count), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    selfcol_store_update_stats ss;
    ss.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    assert_int_equal(selfcol_store_stats(pair, &ss), SELFCOL_OK);
    assert_true(ss.flipped > 0);
    assert_true(ss.kept > 0);

    fixture again = {0};
    assert_int_equal(fixture_grid(&again, 3, 3, 1.0), 0);
    fixture_translate(&again, away);
    selfcol_mesh *ma = mesh_of(&again);
    assert_int_equal(add(sc, ma, SELFCOL_SURFACE_CLOTH, -1, 0), 3); // ids are never reused
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    assert_int_equal(stats_of(sc).surfaces, 3);
    assert_ptr_equal(store_of(sc, l, h), pair);

    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(ml);
    selfcol_mesh_destroy(mh);
    selfcol_mesh_destroy(ma);
    fixture_free(&low);
    fixture_free(&high);
    fixture_free(&far_s);
    fixture_free(&again);
}

// 1 when p lies strictly inside the convex closed mesh (below every face
// plane, counter-clockwise outward).
static int inside_convex(const fixture *s, const double p[3]) {
    for (size_t t = 0; t < s->triangle_count; ++t) {
        const double *a = s->positions + 3 * s->triangles[3 * t];
        const double *b = s->positions + 3 * s->triangles[3 * t + 1];
        const double *c = s->positions + 3 * s->triangles[3 * t + 2];
        double u[3], w[3], n[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = b[k] - a[k];
            w[k] = c[k] - a[k];
        }
        n[0] = u[1] * w[2] - u[2] * w[1];
        n[1] = u[2] * w[0] - u[0] * w[2];
        n[2] = u[0] * w[1] - u[1] * w[0];
        if ((p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2] >= 0.0)
            return 0;
    }
    return 1;
}

// A cloth cap pushed into a sphere so that most of its contacts are inside:
// as a body, the sphere's normals make every inside contact wrong-sided
// (negative signed distance) and nothing is voted; the same sphere declared
// as cloth is voted, and its majority (inside) wins. Winding the body inward
// changes nothing.
static void run_body(int inward, int as_cloth, double *signed_out, size_t *count_out,
                     uint64_t *voted_out, int *inside_wrong_out) {
    fixture sphere = {0}, cap = {0};
    assert_int_equal(fixture_icosphere(&sphere, 3, 1.0), 0);
    if (inward)
        for (size_t t = 0; t < sphere.triangle_count; ++t) {
            uint32_t tmp = sphere.triangles[3 * t + 1];
            sphere.triangles[3 * t + 1] = sphere.triangles[3 * t + 2];
            sphere.triangles[3 * t + 2] = tmp;
        }
    assert_int_equal(fixture_grid(&cap, 12, 12, 0.04), 0);
    const double place[3] = {-0.24, -0.24, 0.975};
    fixture_translate(&cap, place);
    selfcol_mesh *ms = mesh_of(&sphere), *mc = mesh_of(&cap);
    selfcol_scene *sc = make_scene(0.03, NULL);
    const uint32_t cloth = add(sc, mc, SELFCOL_SURFACE_CLOTH, 0, 0);
    const uint32_t body =
        add(sc, ms, as_cloth ? SELFCOL_SURFACE_CLOTH : SELFCOL_SURFACE_BODY, 0, 0);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_store *store = store_of(sc, cloth, body);
    selfcol_store_update_stats ss;
    ss.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    assert_int_equal(selfcol_store_stats(store, &ss), SELFCOL_OK);
    *voted_out = ss.voted;
    size_t n;
    selfcol_store_contact *c = copy_records(store, &n);
    *count_out = 0;
    int inside_wrong = 1;
    for (size_t i = 0; i < n; ++i) {
        if (c[i].kind != SELFCOL_CONTACT_VF || c[i].first_mesh != 0)
            continue; // cloth vertices against sphere triangles
        signed_out[(*count_out)++] = c[i].signed_distance;
        if (!inward && inside_convex(&sphere, cap.positions + 3 * c[i].first) &&
            !(c[i].signed_distance < 0.0))
            inside_wrong = 0;
        if (!as_cloth) {
            assert_true(c[i].flags & SELFCOL_STORE_ORIENTED);
            assert_int_equal(c[i].right_side, inward ? -1 : +1);
        }
    }
    free(c);
    *inside_wrong_out = inside_wrong;
    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(ms);
    selfcol_mesh_destroy(mc);
    fixture_free(&sphere);
    fixture_free(&cap);
}

static void test_body_never_voted(void **state) {
    (void)state;
    enum { MAX = 4096 };
    double *outward = calloc(MAX, sizeof(double)), *inward = calloc(MAX, sizeof(double));
    double *voted_run = calloc(MAX, sizeof(double));
    size_t n_out, n_in, n_voted;
    uint64_t voted_out, voted_in, voted_cloth;
    int inside_wrong_out, inside_wrong_in, inside_wrong_cloth;
    run_body(0, 0, outward, &n_out, &voted_out, &inside_wrong_out);
    run_body(1, 0, inward, &n_in, &voted_in, &inside_wrong_in);
    run_body(0, 1, voted_run, &n_voted, &voted_cloth, &inside_wrong_cloth);
    assert_true(n_out > 20);
    assert_int_equal(voted_out, 0);
    assert_int_equal(voted_in, 0);
    assert_true(inside_wrong_out); // every cloth vertex inside the body is wrong-sided
    // Winding does not matter: the same contacts, the same signed distances.
    assert_int_equal(n_in, n_out);
    size_t negative = 0;
    for (size_t i = 0; i < n_out; ++i) {
        if (fabs(outward[i] - inward[i]) > 1e-12)
            print_message("contact %zu: %.17g vs %.17g\n", i, outward[i], inward[i]);
        assert_true(fabs(outward[i] - inward[i]) <= 1e-12);
        negative += outward[i] < 0.0;
    }
    assert_true(2 * negative > n_out); // most of the cap is inside: a vote would keep it there
    // Declared as cloth, the sphere is voted, and the inside majority wins.
    assert_int_equal(n_voted, n_out);
    assert_true(voted_cloth > 0);
    size_t negative_voted = 0;
    for (size_t i = 0; i < n_voted; ++i)
        negative_voted += voted_run[i] < 0.0;
    assert_true(negative_voted < negative);
    free(outward);
    free(inward);
    free(voted_run);
}

// ---------------------------------------------------------------------------
// Capsule collider against a triangulated capsule.

// A closed capsule along x (axis from -h to +h, radius r), outward, with
// `segments` around and `rings` latitude steps per hemisphere.
static void capsule_mesh(fixture *s, double r, double h, unsigned segments, unsigned rings) {
    const unsigned ring_count = 2 * rings; // latitude rings, poles apart
    s->vertex_count = 2 + (size_t)ring_count * segments;
    s->triangle_count = 2 * (size_t)segments * ring_count;
    s->positions = calloc(3 * s->vertex_count, sizeof(double));
    s->triangles = calloc(3 * s->triangle_count, sizeof(uint32_t));
    assert_non_null(s->positions);
    assert_non_null(s->triangles);
    const double pi = 3.14159265358979323846;
    // Vertex 0: pole at -x; 1..: rings; last: pole at +x.
    s->positions[0] = -h - r;
    for (unsigned k = 0; k < ring_count; ++k) {
        // Rings 0..rings-1 on the -x hemisphere (the last at its equator),
        // rings..2 rings-1 on the +x one (the first at its equator).
        const double theta =
            k < rings ? (k + 1) * (pi / 2) / rings : pi / 2 + (k - rings) * (pi / 2) / rings;
        const double x = (k < rings ? -h : h) - r * cos(theta);
        for (unsigned j = 0; j < segments; ++j) {
            const double phi = 2 * pi * j / segments;
            double *p = s->positions + 3 * (1 + (size_t)k * segments + j);
            p[0] = x;
            p[1] = r * sin(theta) * cos(phi);
            p[2] = r * sin(theta) * sin(phi);
        }
    }
    const uint32_t last = (uint32_t)s->vertex_count - 1;
    s->positions[3 * last] = h + r;
    uint32_t *t = s->triangles;
#define V(k, j) (1u + (uint32_t)(k)*segments + (uint32_t)((j) % segments))
    for (unsigned j = 0; j < segments; ++j) { // fans: outward = counter-clockwise from outside
        *t++ = 0;
        *t++ = V(0, j + 1);
        *t++ = V(0, j);
        *t++ = last;
        *t++ = V(ring_count - 1, j);
        *t++ = V(ring_count - 1, j + 1);
    }
    for (unsigned k = 0; k + 1 < ring_count; ++k)
        for (unsigned j = 0; j < segments; ++j) {
            *t++ = V(k, j);
            *t++ = V(k, j + 1);
            *t++ = V(k + 1, j);
            *t++ = V(k + 1, j);
            *t++ = V(k, j + 1);
            *t++ = V(k + 1, j + 1);
        }
#undef V
    s->triangle_count = (size_t)(t - s->triangles) / 3;
}

// Distance from the capsule's axis segment to p, minus r (the true surface).
static double capsule_gap(double r, double h, const double p[3]) {
    const double x = p[0] < -h ? -h : p[0] > h ? h : p[0];
    return sqrt((p[0] - x) * (p[0] - x) + p[1] * p[1] + p[2] * p[2]) - r;
}

static void test_capsule_collider_matches_triangulated_capsule(void **state) {
    (void)state;
    const double r = 0.5, h = 0.6, d = 0.02;
    fixture caps = {0}, cloth_s = {0};
    capsule_mesh(&caps, r, h, 96, 24);
    // The sagitta: how far inside the true surface the mesh's faces reach,
    // measured on a barycentric grid of every triangle.
    double sagitta = 0.0;
    for (size_t t = 0; t < caps.triangle_count; ++t)
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; i + j <= 8; ++j) {
                double p[3];
                for (int k = 0; k < 3; ++k)
                    p[k] = (i * caps.positions[3 * caps.triangles[3 * t] + k] +
                            j * caps.positions[3 * caps.triangles[3 * t + 1] + k] +
                            (8 - i - j) * caps.positions[3 * caps.triangles[3 * t + 2] + k]) /
                           8.0;
                sagitta = fmax(sagitta, -capsule_gap(r, h, p));
            }
    assert_true(sagitta > 0.0 && sagitta < 0.1 * d);
    // A rippled cloth over the capsule's top, touching and crossing it a little.
    assert_int_equal(fixture_grid(&cloth_s, 40, 16, 0.05), 0);
    for (size_t v = 0; v < cloth_s.vertex_count; ++v) {
        double *p = cloth_s.positions + 3 * v;
        p[0] -= 1.0;
        p[1] -= 0.4;
        p[2] = r + 0.004 - 0.03 * p[1] * p[1] + 0.008 * sin(7.0 * p[0]);
    }
    selfcol_mesh *cloth_m = mesh_of(&cloth_s), *caps_m = mesh_of(&caps);

    // Cloth against the collider.
    selfcol_scene *sc = make_scene(d, NULL);
    add(sc, cloth_m, SELFCOL_SURFACE_CLOTH, 0, 0);
    selfcol_scene_collider_desc desc;
    assert_int_equal(selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CAPSULE,
                                                      SELFCOL_SCENE_COLLIDER_DESC_VERSION),
                     SELFCOL_OK);
    desc.radius = r;
    desc.half_height = h;
    uint32_t cid;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, &cid), SELFCOL_OK);
    // Local axis z -> world x: rows of R map local to world.
    const double rot[9] = {0, 0, 1, 0, 1, 0, -1, 0, 0};
    const double origin[3] = {0, 0, 0};
    assert_int_equal(selfcol_scene_set_collider_pose(sc, cid, origin, rot), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_collider_contact *cc;
    size_t ncc;
    assert_int_equal(selfcol_scene_collider_contacts(sc, &cc, &ncc), SELFCOL_OK);

    // Cloth against the triangulated capsule (EXHAUSTIVE, the reference):
    // per cloth triangle, the least distance of its VF/EE/EF contacts.
    selfcol_hierarchy *hc, *hk;
    assert_int_equal(selfcol_hierarchy_create(&hc, cloth_m, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&hk, caps_m, NULL), SELFCOL_OK);
    selfcol_contacts *found;
    assert_int_equal(selfcol_contacts_create(&found, NULL), SELFCOL_OK);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = d;
    q.method = SELFCOL_METHOD_EXHAUSTIVE; // the reference contact sets
    assert_int_equal(selfcol_hierarchy_collide(hc, hk, found, &q), SELFCOL_OK);
    const size_t nt = cloth_s.triangle_count;
    double *mesh_dist = malloc(nt * sizeof(double)), *coll_dist = malloc(nt * sizeof(double));
    for (size_t t = 0; t < nt; ++t)
        mesh_dist[t] = coll_dist[t] = HUGE_VAL;
    const selfcol_contact *rec;
    size_t nrec;
    assert_int_equal(selfcol_contacts_data(found, &rec, &nrec), SELFCOL_OK);
    for (size_t i = 0; i < nrec; ++i) {
        const selfcol_contact *k = &rec[i];
        for (size_t t = 0; t < nt; ++t) {
            const uint32_t *tri = cloth_s.triangles + 3 * t;
            int involved = 0;
            if (k->kind == SELFCOL_CONTACT_VF && k->first_mesh == 0)
                involved = tri[0] == k->first || tri[1] == k->first || tri[2] == k->first;
            else if (k->kind == SELFCOL_CONTACT_VF ||
                     (k->kind == SELFCOL_CONTACT_EF && k->second_mesh == 0))
                involved = k->second == t;
            else // EE, or EF with a cloth edge: the edge is one of the triangle's
                for (int e = 0; e < 3; ++e) {
                    const uint32_t a = tri[e], b = tri[(e + 1) % 3];
                    involved |= (k->a[0] == a && k->a[1] == b) || (k->a[0] == b && k->a[1] == a);
                }
            if (involved)
                mesh_dist[t] = fmin(mesh_dist[t], k->distance);
        }
    }
    for (size_t i = 0; i < ncc; ++i) {
        assert_int_equal(cc[i].collider, cid);
        assert_int_equal(cc[i].surface, 0);
        assert_true(i == 0 || cc[i].triangle > cc[i - 1].triangle);
        coll_dist[cc[i].triangle] = cc[i].distance;
    }
    const double tol = 1e-6 * d + 1e-12;
    size_t both = 0, penetrating = 0;
    for (size_t t = 0; t < nt; ++t) {
        if (mesh_dist[t] < HUGE_VAL) {
            // Every triangle near the mesh is near the capsule, at most the
            // sagitta closer (the true surface lies outside the faces).
            assert_true(coll_dist[t] < HUGE_VAL);
            assert_true(coll_dist[t] <= mesh_dist[t] + tol);
            assert_true(coll_dist[t] == 0.0 || coll_dist[t] >= mesh_dist[t] - sagitta - tol);
            both++;
            penetrating += coll_dist[t] == 0.0;
        } else if (coll_dist[t] < HUGE_VAL) {
            // Near the capsule only: within the sagitta of the distance.
            assert_true(coll_dist[t] >= d - sagitta - tol);
        }
    }
    print_message("capsule: %zu cloth triangles near both (%zu penetrating), %zu collider "
                  "contacts, sagitta %.3g\n",
                  both, penetrating, ncc, sagitta);
    assert_true(both > 50 && penetrating > 5);

    free(mesh_dist);
    free(coll_dist);
    selfcol_contacts_destroy(found);
    selfcol_hierarchy_destroy(hc);
    selfcol_hierarchy_destroy(hk);
    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(cloth_m);
    selfcol_mesh_destroy(caps_m);
    fixture_free(&cloth_s);
    fixture_free(&caps);
}

// Duplicate triangles (hardening 0.3, item 6) are no contact's triangle,
// collider contacts included: a sheet whose every triangle is repeated
// (reversed, and then once more) under a sphere gives exactly the contacts
// of the sheet alone, all naming first occurrences.
static void test_collider_contacts_name_no_duplicate(void **state) {
    (void)state;
    fixture s = {0};
    assert_int_equal(fixture_grid(&s, 12, 12, 0.05), 0);
    const size_t n = s.triangle_count;
    uint32_t *tris = malloc(3 * 3 * n * sizeof *tris);
    memcpy(tris, s.triangles, 3 * n * sizeof *tris);
    for (size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            tris[3 * (n + t) + k] = s.triangles[3 * t + 2 - k];
            tris[3 * (2 * n + t) + k] = s.triangles[3 * t + k];
        }
    selfcol_mesh *alone = mesh_of(&s), *copied = NULL;
    assert_int_equal(selfcol_mesh_create(&copied, s.vertex_count, s.positions, 3 * n, tris, NULL),
                     SELFCOL_OK);
    selfcol_scene_collider_desc desc;
    assert_int_equal(selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_SPHERE,
                                                      SELFCOL_SCENE_COLLIDER_DESC_VERSION),
                     SELFCOL_OK);
    desc.radius = 0.2;
    const double centre[3] = {0.3, 0.3, -0.19}; // the sheet crosses its top
    size_t counts[2] = {0, 0};
    for (int pass = 0; pass < 2; ++pass) {
        selfcol_scene *sc = make_scene(0.02, NULL);
        add(sc, pass ? copied : alone, SELFCOL_SURFACE_CLOTH, 0, 0);
        uint32_t cid;
        assert_int_equal(selfcol_scene_add_collider(sc, &desc, &cid), SELFCOL_OK);
        assert_int_equal(selfcol_scene_set_collider_pose(sc, cid, centre, NULL), SELFCOL_OK);
        assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
        const selfcol_collider_contact *cc;
        assert_int_equal(selfcol_scene_collider_contacts(sc, &cc, &counts[pass]), SELFCOL_OK);
        for (size_t i = 0; i < counts[pass]; ++i)
            assert_true(cc[i].triangle < n);
        selfcol_scene_destroy(sc);
    }
    assert_true(counts[0] > 10);
    assert_int_equal(counts[1], counts[0]);
    selfcol_mesh_destroy(alone);
    selfcol_mesh_destroy(copied);
    free(tris);
    fixture_free(&s);
}

// ---------------------------------------------------------------------------
// Errors

// Coherent and fresh scenes side by side over a crumpling sheet falling
// onto a second one: after every update each store holds the same records
// (the sequences answer exactly as fresh queries; their reuse is
// test_sequence.c's business).
// A caller's scheduler (context.h) that runs a task's items at once, last
// first: a scene lent a context on it must give the same stores.
static void *run_reversed(selfcol_task_fn *task, uint32_t item_count, uint32_t min_range,
                          void *task_context, void *user_context) {
    (void)min_range;
    ++*(int *)user_context;
    for (uint32_t i = item_count; i > 0; --i)
        task(i - 1, i, 0u, task_context);
    return NULL;
}

static void nothing_to_finish(void *user_task, void *user_context) {
    (void)user_task;
    (void)user_context;
    fail_msg("no task was left to finish");
}

// Coherent updates equal fresh ones, and so do those of a coherent scene
// on a lent context (selfcol_scene_set_context) with a caller's scheduler.
static void test_coherent_updates_equal_fresh_ones(void **state) {
    (void)state;
    fixture flat = {0}, crumpled = {0}, floor = {0};
    assert_int_equal(fixture_grid(&flat, 14, 14, 1.0), 0);
    assert_int_equal(fixture_crumpled(&crumpled, 14, 14, 4, 3.0), 0);
    assert_int_equal(fixture_grid(&floor, 16, 16, 1.0), 0);
    const double below[3] = {-1.0, -1.0, -4.0};
    fixture_translate(&floor, below);
    const size_t V = flat.vertex_count;
    double *x = malloc(3 * V * sizeof *x);
    assert_non_null(x);
    selfcol_mesh *cloth = mesh_of(&flat), *ground = mesh_of(&floor);
    int scheduled = 0;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = 4;
    co.enqueue_task = run_reversed;
    co.finish_task = nothing_to_finish;
    co.user_context = &scheduled;
    selfcol_context *context = NULL;
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
    selfcol_scene *sc[3];
    for (int k = 0; k < 3; ++k) {
        selfcol_scene_options o;
        selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
        const selfcol_query_options q = query_at(0.1);
        o.query = &q;
        o.coherent = k != 1;
        assert_int_equal(selfcol_scene_create(&sc[k], &o), SELFCOL_OK);
        if (k == 2)
            assert_int_equal(selfcol_scene_set_context(sc[k], context), SELFCOL_OK);
        assert_int_equal(add(sc[k], cloth, SELFCOL_SURFACE_CLOTH, -1, 0), 0);
        assert_int_equal(add(sc[k], ground, SELFCOL_SURFACE_CLOTH, 0, 0), 1);
    }
    size_t held = 0;
    for (int f = 0; f <= 40; ++f) {
        const double a = 0.6 + 0.4 * f / 40.0;
        for (size_t i = 0; i < 3 * V; ++i)
            x[i] = flat.positions[i] + a * (crumpled.positions[i] - flat.positions[i]) -
                   (i % 3 == 2 ? 0.05 * f : 0.0);
        assert_int_equal(selfcol_mesh_set_positions(cloth, x, V), SELFCOL_OK);
        for (int k = 0; k < 3; ++k)
            assert_int_equal(selfcol_scene_update(sc[k]), SELFCOL_OK);
        const uint32_t pairs[2][2] = {{0, 0}, {0, 1}};
        for (int p = 0; p < 2; ++p) {
            size_t n0, n1;
            selfcol_store_contact *c0 =
                copy_records(store_of(sc[0], pairs[p][0], pairs[p][1]), &n0);
            for (int k = 1; k < 3; ++k) {
                selfcol_store_contact *c1 =
                    copy_records(store_of(sc[k], pairs[p][0], pairs[p][1]), &n1);
                assert_int_equal(n0, n1);
                if (n0 > 0)
                    assert_memory_equal(c0, c1, n0 * sizeof *c0);
                free(c1);
            }
            held += n0;
            free(c0);
        }
    }
    assert_true(held > 0);
    // The coherent scene holds its sequences; the fresh one none.
    assert_true(selfcol_scene_byte_count(sc[0]) >
                selfcol_scene_byte_count(sc[1]) + 3 * V * sizeof(double));
    assert_true(scheduled > 0); // the lent context's scheduler ran the threaded stages
    assert_int_equal(selfcol_scene_set_context(NULL, context), SELFCOL_EINVAL);
    // Given back: the scene's own context again, the same stores.
    assert_int_equal(selfcol_scene_set_context(sc[2], NULL), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc[2]), SELFCOL_OK);
    for (int k = 0; k < 3; ++k)
        selfcol_scene_destroy(sc[k]);
    selfcol_context_destroy(context);
    selfcol_mesh_destroy(cloth);
    selfcol_mesh_destroy(ground);
    free(x);
    fixture_free(&flat);
    fixture_free(&crumpled);
    fixture_free(&floor);
}

// The scene reads the structs its options point to when it is made and
// keeps copies: the caller's structs may change or go away afterwards. A
// scene whose query, store and sequence options were overwritten with
// garbage after creation holds the stores of one made with the defaults;
// NULL store and sequence options are those defaults.
static void test_options_are_copied(void **state) {
    (void)state;
    fixture cloth_s = {0}, ball = {0};
    assert_int_equal(fixture_draped_cloth(&cloth_s, 24, 1.2, 1.0, 0.01, 0.03), 0);
    assert_int_equal(fixture_icosphere(&ball, 2, 1.0), 0);
    selfcol_mesh *mc = mesh_of(&cloth_s), *mb = mesh_of(&ball);
    selfcol_scene *plain = make_scene(0.02, NULL); // store and sequence NULL
    selfcol_scene_options o;
    selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
    selfcol_query_options q = query_at(0.02);
    selfcol_store_options st;
    selfcol_sequence_options sq;
    point_to(&o, &q, &st, &sq);
    selfcol_scene *copied = NULL;
    assert_int_equal(selfcol_scene_create(&copied, &o), SELFCOL_OK);
    memset(&q, 0xff, sizeof q);
    memset(&st, 0xff, sizeof st);
    memset(&sq, 0xff, sizeof sq);
    selfcol_scene *both[2] = {plain, copied};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(add(both[k], mc, SELFCOL_SURFACE_CLOTH, -1, 0), 0);
        assert_int_equal(add(both[k], mb, SELFCOL_SURFACE_BODY, -1, 0), 1);
        assert_int_equal(selfcol_scene_update(both[k]), SELFCOL_OK);
    }
    const selfcol_scene_update_stats a = stats_of(plain), b = stats_of(copied);
    assert_true(a.contacts > 0); // the cloth lies on the ball within d
    assert_int_equal(a.contacts, b.contacts);
    assert_int_equal(a.interferences, b.interferences);
    assert_int_equal(a.pairs_queried, b.pairs_queried);
    for (uint32_t first = 0; first < 2; ++first)
        for (uint32_t second = first; second < 2; ++second) {
            const selfcol_store *x = store_of(plain, first, second);
            const selfcol_store *y = store_of(copied, first, second);
            assert_int_equal(x == NULL, y == NULL);
            if (x != NULL)
                assert_int_equal(selfcol_store_contact_count(x), selfcol_store_contact_count(y));
        }
    selfcol_scene_destroy(plain);
    selfcol_scene_destroy(copied);
    selfcol_mesh_destroy(mc);
    selfcol_mesh_destroy(mb);
    fixture_free(&cloth_s);
    fixture_free(&ball);
}

static void test_errors(void **state) {
    (void)state;
    selfcol_scene_options o;
    selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
    assert_null(o.query);
    assert_null(o.store);
    assert_null(o.sequence);
    assert_int_equal(o.coherent, 1);
    selfcol_scene *sc = (selfcol_scene *)1;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL); // no query options
    assert_null(sc);
    selfcol_query_options q = query_at(0.0);
    o.query = &q;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL); // no distance
    q.distance = 0.1;
    q.kinds = 0;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    q.kinds = SELFCOL_KIND_ALL;
    q.version = 2; // 0.3's query options, with threads
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    q.version = SELFCOL_QUERY_OPTIONS_VERSION;
    o.version = 99;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    // 0.4: versions 1 (0.2's copied fields) and 2 (0.3's embedded options)
    // are other layouts, refused; the options pointed to are checked as
    // their own versions say.
    o.version = 1;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    o.version = 2;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    assert_int_equal(selfcol_scene_options_init(&o, 1), SELFCOL_EVERSION);
    assert_int_equal(selfcol_scene_options_init(&o, 2), SELFCOL_EVERSION);
    selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
    selfcol_store_options sto;
    selfcol_sequence_options sq;
    point_to(&o, &q, &sto, &sq);
    q.version = 0;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    q.version = SELFCOL_QUERY_OPTIONS_VERSION;
    sto.version = 99;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    sto.version = SELFCOL_STORE_OPTIONS_VERSION;
    q.narrow = 7;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    q.narrow = SELFCOL_NARROW_CLOSED_FORM;
    sto.consistency = 2;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    sto.consistency = 1;
    sto.first_orientation = 1; // a surface's orientation comes from its kind
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    sto.first_orientation = 0;
    sto.allocator.user = &o; // the scene's allocator serves its stores
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    sto.allocator.user = NULL;
    o.coherent = 2;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    o.coherent = 1;
    sq.skin = -1.0; // the sequences' options are checked too
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    sq.skin = 0.0;
    sq.allocator.user = &o; // the scene's allocator serves its sequences
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EINVAL);
    sq.allocator.user = NULL;
    sq.version = 0;
    assert_int_equal(selfcol_scene_create(&sc, &o), SELFCOL_EVERSION);
    sq.version = SELFCOL_SEQUENCE_OPTIONS_VERSION;
    assert_null(sc);
    assert_int_equal(selfcol_scene_create(&sc, NULL), SELFCOL_EINVAL);
    sc = make_scene(0.1, NULL);

    // Surfaces.
    fixture grid = {0}, ball = {0};
    assert_int_equal(fixture_grid(&grid, 3, 3, 1.0), 0);
    assert_int_equal(fixture_icosphere(&ball, 1, 1.0), 0);
    selfcol_mesh *mg = mesh_of(&grid), *mb = mesh_of(&ball);
    selfcol_scene_surface_options so;
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_BODY,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    assert_int_equal(selfcol_scene_add_surface(sc, mg, &so, NULL), SELFCOL_EINVAL); // open body
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_STATIC,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    so.self_collision = 1;
    assert_int_equal(selfcol_scene_add_surface(sc, mg, &so, NULL), SELFCOL_EINVAL);
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_CLOTH,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    so.orientation = 1; // only a static surface declares one
    assert_int_equal(selfcol_scene_add_surface(sc, mg, &so, NULL), SELFCOL_EINVAL);
    so.orientation = 0;
    so.kind = 7;
    assert_int_equal(selfcol_scene_add_surface(sc, mg, &so, NULL), SELFCOL_EINVAL);
    assert_int_equal(
        selfcol_scene_surface_options_init(&so, 7, SELFCOL_SCENE_SURFACE_OPTIONS_VERSION),
        SELFCOL_EINVAL);
    add(sc, mg, SELFCOL_SURFACE_CLOTH, -1, 0);
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_CLOTH,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    assert_int_equal(selfcol_scene_add_surface(sc, mg, &so, NULL), SELFCOL_EINVAL); // twice
    add(sc, mb, SELFCOL_SURFACE_BODY, -1, 0);

    // Colliders.
    selfcol_scene_collider_desc desc;
    assert_int_equal(
        selfcol_scene_collider_desc_init(&desc, 9, SELFCOL_SCENE_COLLIDER_DESC_VERSION),
        SELFCOL_EINVAL);
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_SPHERE,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL); // radius 0
    desc.radius = NAN;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL);
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CAPSULE,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.radius = 0.2;
    desc.half_height = -1.0;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL);
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_BOX,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.half_extents[1] = INFINITY;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL);
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CONVEX,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL); // no points
    const double pts[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    desc.points = pts;
    desc.point_count = 4;
    uint32_t tet;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, &tet), SELFCOL_OK);
    desc.point_count = SELFCOL_COLLIDER_MAX_POINTS + 1;
    assert_int_equal(selfcol_scene_add_collider(sc, &desc, NULL), SELFCOL_EINVAL);

    // Poses.
    const double at[3] = {0.0, 0.0, 3.0};
    const double scaled[9] = {2, 0, 0, 0, 1, 0, 0, 0, 1};
    const double mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double bad_at[3] = {0.0, NAN, 0.0};
    const double huge_at[3] = {1e61, 0.0, 0.0};
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, at, scaled), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, at, mirror), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, bad_at, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, huge_at, NULL), SELFCOL_ERANGE);
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet + 1, at, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, at, NULL), SELFCOL_OK);
    // The tetrahedron at z = 3 touches nothing.
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_collider_contact *cc;
    size_t n;
    assert_int_equal(selfcol_scene_collider_contacts(sc, &cc, &n), SELFCOL_OK);
    assert_int_equal(n, 0);
    assert_null(cc);
    // Moved onto the ball's top (the ball at the origin, radius 1): contacts.
    const double onto[3] = {0.0, 0.0, 0.99};
    assert_int_equal(selfcol_scene_set_collider_pose(sc, tet, onto, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    assert_int_equal(selfcol_scene_collider_contacts(sc, &cc, &n), SELFCOL_OK);
    assert_true(n > 0);
    for (size_t i = 0; i < n; ++i) {
        assert_int_equal(cc[i].surface, 1);
        assert_true(cc[i].flags & SELFCOL_COLLIDER_APPROXIMATE);
    }
    assert_int_equal(selfcol_scene_update(NULL), SELFCOL_EINVAL);
    selfcol_scene_update_stats st;
    sto.version = 0;
    assert_int_equal(selfcol_scene_stats(sc, &st), SELFCOL_EVERSION);
    assert_true(selfcol_scene_byte_count(sc) > 0);
    assert_int_equal(selfcol_scene_byte_count(NULL), 0);

    selfcol_scene_destroy(sc);
    selfcol_scene_destroy(NULL);
    selfcol_mesh_destroy(mg);
    selfcol_mesh_destroy(mb);
    fixture_free(&grid);
    fixture_free(&ball);
}

// ---------------------------------------------------------------------------
// The step's start (selfcol_scene_set_surface_start)

// Triangle A (z = 0, x + y <= 1) and a small triangle B around the point
// p, both cloth, self-collision off: only the pair A-B is queried.
static void small_triangle(double out[9], double x, double y, double z) {
    const double corners[9] = {x, y, z, x + 0.05, y, z, x, y + 0.05, z};
    memcpy(out, corners, sizeof corners);
}

typedef struct start_run {
    uint64_t flipped, passed_around;
} start_run;

// B goes from `first` (update 1) to `last` (update 2); with `start` not
// NULL the scene is told that update 2's step began there.
static start_run run_start(const double first[3], const double *start, const double last[3]) {
    const double a_pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t tri[3] = {0, 1, 2};
    double b_pos[9], b_start[9];
    small_triangle(b_pos, first[0], first[1], first[2]);
    selfcol_mesh *ma = NULL, *mb = NULL;
    assert_int_equal(selfcol_mesh_create(&ma, 3, a_pos, 1, tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&mb, 3, b_pos, 1, tri, NULL), SELFCOL_OK);
    selfcol_scene *sc = make_scene(0.5, NULL);
    const uint32_t ia = add(sc, ma, SELFCOL_SURFACE_CLOTH, 0, 0);
    const uint32_t ib = add(sc, mb, SELFCOL_SURFACE_CLOTH, 0, 0);
    // The first update has no path (no last positions yet); the starts given
    // before it make the scene keep the positions of every update from then.
    if (start != NULL) {
        assert_int_equal(selfcol_scene_set_surface_start(sc, ib, b_pos), SELFCOL_OK);
        assert_int_equal(selfcol_scene_set_surface_start(sc, ia, a_pos), SELFCOL_OK);
    }
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    assert_true(selfcol_store_contact_count(store_of(sc, ia, ib)) > 0);
    small_triangle(b_pos, last[0], last[1], last[2]);
    assert_int_equal(selfcol_mesh_set_positions(mb, b_pos, 3), SELFCOL_OK);
    if (start != NULL) {
        small_triangle(b_start, start[0], start[1], start[2]);
        assert_int_equal(selfcol_scene_set_surface_start(sc, ib, b_start), SELFCOL_OK);
        assert_int_equal(selfcol_scene_set_surface_start(sc, ia, a_pos), SELFCOL_OK);
    }
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    const selfcol_scene_update_stats st = stats_of(sc);
    assert_true(st.contacts > 0);
    start_run r = {st.flipped, st.passed_around};
    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(ma);
    selfcol_mesh_destroy(mb);
    return r;
}

static void test_surface_start(void **state) {
    (void)state;
    // B passes A's plane beside it (x + y > 1), never touching: with the
    // start, every sign change passed around; without it, each is a crossing.
    const double beside_above[3] = {1.2, 0.2, 0.1}, beside_below[3] = {1.2, 0.2, -0.1};
    const start_run known = run_start(beside_above, beside_above, beside_below);
    const start_run guessed = run_start(beside_above, NULL, beside_below);
    print_message("beside: with the start %llu flipped, %llu passed around; without it %llu "
                  "flipped\n",
                  (unsigned long long)known.flipped, (unsigned long long)known.passed_around,
                  (unsigned long long)guessed.flipped);
    assert_true(guessed.flipped > 0);
    assert_int_equal(known.flipped, 0);
    assert_int_equal(known.passed_around, guessed.flipped);

    // The path has two segments: B above A's middle at update 1, pushed
    // straight through A (the caller's response, say: the step's start
    // below A), then moved beside A, still below. The crossing is on the
    // first segment (B's corners through A: flipped); the other sign changes
    // (B's edges past A's, A's corners past B's plane) never touched.
    const double above_middle[3] = {0.2, 0.2, 0.1}, below_middle[3] = {0.2, 0.2, -0.1};
    const start_run pushed = run_start(above_middle, below_middle, beside_below);
    const start_run plain = run_start(above_middle, NULL, beside_below);
    print_message("pushed through: %llu flipped, %llu passed around; without the start %llu "
                  "flipped\n",
                  (unsigned long long)pushed.flipped, (unsigned long long)pushed.passed_around,
                  (unsigned long long)plain.flipped);
    assert_int_equal(pushed.flipped, 3); // B's three corners, through A's middle
    assert_int_equal(pushed.flipped + pushed.passed_around, plain.flipped);
    // A store told only the step's start (one segment, below -> beside)
    // calls the same sign changes passed around: the reason the scene keeps
    // the positions of the last update.
    {
        const double a_pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const uint32_t tri[3] = {0, 1, 2};
        double b_pos[9], b_start[9];
        small_triangle(b_pos, 0.2, 0.2, 0.1);
        selfcol_mesh *ma = NULL, *mb = NULL;
        assert_int_equal(selfcol_mesh_create(&ma, 3, a_pos, 1, tri, NULL), SELFCOL_OK);
        assert_int_equal(selfcol_mesh_create(&mb, 3, b_pos, 1, tri, NULL), SELFCOL_OK);
        selfcol_hierarchy *ha = NULL, *hb = NULL;
        assert_int_equal(selfcol_hierarchy_create(&ha, ma, NULL), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_create(&hb, mb, NULL), SELFCOL_OK);
        selfcol_query_options q;
        selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
        q.distance = 0.5;
        q.kinds = SELFCOL_KIND_VF | SELFCOL_KIND_EE | SELFCOL_KIND_EF;
        selfcol_contacts *c = NULL;
        selfcol_store *store = NULL;
        assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
        assert_int_equal(selfcol_store_create(&store, NULL), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_collide(ha, hb, c, &q), SELFCOL_OK);
        assert_int_equal(selfcol_store_update(store, ma, mb, c), SELFCOL_OK);
        small_triangle(b_start, 0.2, 0.2, -0.1);
        small_triangle(b_pos, 1.2, 0.2, -0.1);
        assert_int_equal(selfcol_mesh_set_positions(mb, b_pos, 3), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_refit(hb), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_collide(ha, hb, c, &q), SELFCOL_OK);
        assert_int_equal(selfcol_store_update_swept(store, ma, mb, c, a_pos, b_start), SELFCOL_OK);
        selfcol_store_update_stats ss;
        ss.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
        assert_int_equal(selfcol_store_stats(store, &ss), SELFCOL_OK);
        assert_int_equal(ss.flipped, 0);
        assert_int_equal(ss.passed_around, plain.flipped);
        selfcol_store_destroy(store);
        selfcol_contacts_destroy(c);
        selfcol_hierarchy_destroy(ha);
        selfcol_hierarchy_destroy(hb);
        selfcol_mesh_destroy(ma);
        selfcol_mesh_destroy(mb);
    }

    // The starts are consumed by the update: one more update without one
    // judges as before (beside -> above again: a sign change, flipped).
    // Errors: a static surface, a removed or unknown one, NULL, NaN.
    const double a_pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t tri[3] = {0, 1, 2};
    double b_pos[9];
    small_triangle(b_pos, 1.2, 0.2, 0.1);
    selfcol_mesh *ma = NULL, *mb = NULL, *mf = NULL;
    assert_int_equal(selfcol_mesh_create(&ma, 3, a_pos, 1, tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&mb, 3, b_pos, 1, tri, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_mesh_create(&mf, 3, a_pos, 1, tri, NULL), SELFCOL_OK);
    selfcol_scene *sc = make_scene(0.5, NULL);
    const uint32_t ia = add(sc, ma, SELFCOL_SURFACE_CLOTH, 0, 0);
    const uint32_t ib = add(sc, mb, SELFCOL_SURFACE_CLOTH, 0, 0);
    const uint32_t is = add(sc, mf, SELFCOL_SURFACE_STATIC, 0, 0);
    const double *pa = a_pos;
    assert_int_equal(selfcol_scene_set_surface_start(sc, ib, b_pos), SELFCOL_OK);
    assert_int_equal(selfcol_scene_set_surface_start(sc, ia, pa), SELFCOL_OK);
    assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
    for (int frame = 0; frame < 3; ++frame) {
        double from[9];
        memcpy(from, b_pos, sizeof from);
        small_triangle(b_pos, 1.2, 0.2, frame % 2 ? 0.1 : -0.1);
        assert_int_equal(selfcol_mesh_set_positions(mb, b_pos, 3), SELFCOL_OK);
        if (frame < 2) {
            assert_int_equal(selfcol_scene_set_surface_start(sc, ib, from), SELFCOL_OK);
            assert_int_equal(selfcol_scene_set_surface_start(sc, ia, pa), SELFCOL_OK);
        }
        assert_int_equal(selfcol_scene_update(sc), SELFCOL_OK);
        const selfcol_scene_update_stats st = stats_of(sc);
        if (frame < 2)
            assert_true(st.flipped == 0 && st.passed_around > 0);
        else
            assert_true(st.flipped > 0 && st.passed_around == 0);
    }
    assert_int_equal(selfcol_scene_set_surface_start(sc, is, a_pos), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_surface_start(sc, 7, a_pos), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_surface_start(sc, ia, NULL), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_set_surface_start(NULL, ia, a_pos), SELFCOL_EINVAL);
    double bad[9];
    memcpy(bad, a_pos, sizeof bad);
    bad[4] = NAN;
    assert_int_equal(selfcol_scene_set_surface_start(sc, ia, bad), SELFCOL_EINVAL);
    assert_int_equal(selfcol_scene_remove_surface(sc, ib), SELFCOL_OK);
    assert_int_equal(selfcol_scene_set_surface_start(sc, ib, b_pos), SELFCOL_EINVAL);
    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(ma);
    selfcol_mesh_destroy(mb);
    selfcol_mesh_destroy(mf);
}

// ---------------------------------------------------------------------------
// Memory

// A cloth over a sphere body with a capsule collider, run for `frames`
// updates with the allocator of `al`; returns the first error.
static int run_scene(const selfcol_allocator *al, int frames, long *calls_after_three,
                     test_allocator_state *counter, uint64_t *contacts_out) {
    fixture cloth_s = {0}, ball = {0};
    assert_int_equal(fixture_draped_cloth(&cloth_s, 24, 1.2, 1.0, 0.01, 0.03), 0);
    assert_int_equal(fixture_icosphere(&ball, 2, 1.0), 0);
    selfcol_mesh *mc = mesh_of(&cloth_s), *mb = mesh_of(&ball);
    selfcol_scene_options o;
    selfcol_scene_options_init(&o, SELFCOL_SCENE_OPTIONS_VERSION);
    const selfcol_query_options q = query_at(0.02);
    o.query = &q;
    o.allocator = *al;
    selfcol_scene *sc = NULL;
    int status = selfcol_scene_create(&sc, &o);
    selfcol_scene_surface_options so;
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_CLOTH,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    if (status == SELFCOL_OK)
        status = selfcol_scene_add_surface(sc, mc, &so, NULL);
    selfcol_scene_surface_options_init(&so, SELFCOL_SURFACE_BODY,
                                       SELFCOL_SCENE_SURFACE_OPTIONS_VERSION);
    if (status == SELFCOL_OK)
        status = selfcol_scene_add_surface(sc, mb, &so, NULL);
    selfcol_scene_collider_desc desc;
    selfcol_scene_collider_desc_init(&desc, SELFCOL_COLLIDER_CAPSULE,
                                     SELFCOL_SCENE_COLLIDER_DESC_VERSION);
    desc.radius = 0.2;
    desc.half_height = 0.5;
    uint32_t cid = 0;
    if (status == SELFCOL_OK)
        status = selfcol_scene_add_collider(sc, &desc, &cid);
    // Each update is told its step's start (the cloth's previous positions).
    double *start = malloc(3 * cloth_s.vertex_count * sizeof *start);
    assert_non_null(start);
    for (int f = 0; f < frames && status == SELFCOL_OK; ++f) {
        const double at[3] = {0.05 * (f % 2), 0.0, 1.05};
        status = selfcol_scene_set_collider_pose(sc, cid, at, NULL);
        memcpy(start, cloth_s.positions, 3 * cloth_s.vertex_count * sizeof *start);
        for (size_t v = 0; v < cloth_s.vertex_count && status == SELFCOL_OK; ++v)
            cloth_s.positions[3 * v + 2] += f % 2 ? 0.002 : -0.002; // two states, alternating
        if (status == SELFCOL_OK)
            status = selfcol_mesh_set_positions(mc, cloth_s.positions, cloth_s.vertex_count);
        if (status == SELFCOL_OK)
            status = selfcol_scene_set_surface_start(sc, 0, start);
        if (status == SELFCOL_OK)
            status = selfcol_scene_update(sc);
        if (f == 2 && calls_after_three != NULL)
            *calls_after_three = counter->calls;
    }
    if (status == SELFCOL_OK) {
        const selfcol_scene_update_stats st = stats_of(sc);
        assert_true(st.contacts > 0 && st.collider_contacts > 0);
        *contacts_out = st.contacts + st.interferences + st.collider_contacts;
    }
    selfcol_scene_destroy(sc);
    selfcol_mesh_destroy(mc);
    selfcol_mesh_destroy(mb);
    free(start);
    fixture_free(&cloth_s);
    fixture_free(&ball);
    return status;
}

static void test_memory(void **state) {
    (void)state;
    // Steady state: the cloth and the collider alternate between two
    // states; once three updates have grown the stores (which hold the
    // union of both states' contacts by then), the contact buffers and the
    // queries' scratch, the fourth to sixth updates allocate nothing.
    test_allocator_state counter;
    memset(&counter, 0, sizeof counter);
    selfcol_allocator al = test_allocator(&counter);
    long after_three = -1;
    uint64_t found = 0, reference = 0;
    assert_int_equal(run_scene(&al, 6, &after_three, &counter, &found), SELFCOL_OK);
    assert_int_equal(counter.live, 0);
    assert_true(after_three > 0);
    assert_int_equal(counter.calls, after_three); // destroy frees, never allocates

    // Every allocation of a three-update run failing in turn: ENOMEM, never
    // a leak or a crash. The one exception is documented: EXACT's contour
    // proof treats a failed scratch allocation as "cannot skip" and stays
    // exact, so the run ends OK with the same contacts.
    memset(&counter, 0, sizeof counter);
    al = test_allocator(&counter);
    assert_int_equal(run_scene(&al, 3, NULL, &counter, &reference), SELFCOL_OK);
    const long total = counter.calls;
    for (long k = 1; k <= total; ++k) {
        test_allocator_state failing;
        memset(&failing, 0, sizeof failing);
        failing.fail_at = k;
        selfcol_allocator fal = test_allocator(&failing);
        found = 0;
        const int status = run_scene(&fal, 3, NULL, &failing, &found);
        if (status == SELFCOL_OK)
            assert_int_equal(found, reference);
        else
            assert_int_equal(status, SELFCOL_ENOMEM);
        assert_int_equal(failing.live, 0);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pairs_by_kind),
        cmocka_unit_test(test_static_never_refit),
        cmocka_unit_test(test_remove_surface_keeps_the_other_stores),
        cmocka_unit_test(test_body_never_voted),
        cmocka_unit_test(test_capsule_collider_matches_triangulated_capsule),
        cmocka_unit_test(test_collider_contacts_name_no_duplicate),
        cmocka_unit_test(test_coherent_updates_equal_fresh_ones),
        cmocka_unit_test(test_surface_start),
        cmocka_unit_test(test_options_are_copied),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_memory),
    };
    return cmocka_run_group_tests_name("scene", tests, NULL, NULL);
}
