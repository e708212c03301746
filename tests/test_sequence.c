// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries (include/selfcol/sequence.h): on every frame of several
// sequences (slow crumpling, rigid jumps, rotations, resets, two surfaces
// approaching, changed options) the sequence's records equal a fresh query's
// bit for bit, and the fresh EXACT query is checked against EXHAUSTIVE on
// some of those frames too; the reuse actually happens where the proof
// allows it; bad input and allocation failure are refused cleanly.
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

#include "fixtures.h"
#include "test_alloc.h"

// First difference between two record arrays, or -1 when equal bit for bit.
static long first_difference(const selfcol_contact *a, size_t na, const selfcol_contact *b,
                             size_t nb) {
    size_t n = na < nb ? na : nb;
    for (size_t i = 0; i < n; ++i)
        if (memcmp(&a[i], &b[i], sizeof a[i]) != 0)
            return (long)i;
    return na == nb ? -1 : (long)n;
}

static void assert_same_records(const selfcol_contacts *got, const selfcol_contacts *want,
                                const char *where, int frame) {
    const selfcol_contact *a, *b;
    size_t na, nb;
    assert_int_equal(selfcol_contacts_data(got, &a, &na), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_data(want, &b, &nb), SELFCOL_OK);
    long diff = first_difference(a, na, b, nb);
    if (diff >= 0)
        print_error("%s frame %d: %zu records against the fresh query's %zu, first "
                    "difference at %ld\n",
                    where, frame, na, nb, diff);
    assert_int_equal(diff, -1);
    selfcol_query_stats sa, sb;
    memset(&sa, 0, sizeof sa);
    memset(&sb, 0, sizeof sb);
    sa.version = sb.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(got, &sa), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_stats(want, &sb), SELFCOL_OK);
    assert_int_equal(sa.vf_contacts, sb.vf_contacts);
    assert_int_equal(sa.ee_contacts, sb.ee_contacts);
    assert_int_equal(sa.ef_contacts, sb.ef_contacts);
}

// A surface and two hierarchies: `fresh` refit every frame for the
// reference queries, `coherent` left to the sequence (never refit here).
typedef struct rig {
    selfcol_mesh *mesh;
    selfcol_hierarchy *fresh, *coherent;
    selfcol_context *context; // the queries' threads (rig_threads); NULL: the calling thread
} rig;

static void rig_make(rig *r, const fixture *f) {
    r->context = NULL;
    assert_int_equal(selfcol_mesh_create(&r->mesh, f->vertex_count, f->positions, f->triangle_count,
                                         f->triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&r->fresh, r->mesh, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&r->coherent, r->mesh, NULL), SELFCOL_OK);
}

static void rig_free(rig *r) {
    selfcol_context_destroy(r->context);
    selfcol_hierarchy_destroy(r->fresh);
    selfcol_hierarchy_destroy(r->coherent);
    selfcol_mesh_destroy(r->mesh);
}

static void rig_move(rig *r, const double *positions, size_t n) {
    assert_int_equal(selfcol_mesh_set_positions(r->mesh, positions, n), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_refit(r->fresh), SELFCOL_OK);
}

static selfcol_query_options query_options(uint32_t method, double distance, uint32_t kinds) {
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = method;
    o.distance = distance;
    o.kinds = kinds;
    return o;
}

// The rig's sequence and fresh queries on a context of `threads` (1: none).
static void rig_threads(rig *r, unsigned threads) {
    if (threads == 1)
        return;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = threads;
    assert_int_equal(selfcol_context_create(&r->context, &co), SELFCOL_OK);
}

// One frame of a self sequence against the fresh query (and, when asked,
// the fresh query against EXHAUSTIVE).
static void check_self_frame(rig *r, selfcol_sequence *seq, selfcol_contacts *got,
                             selfcol_contacts *want, const selfcol_query_options *o, int exhaustive,
                             const char *where, int frame) {
    if (r->context != NULL) {
        assert_int_equal(
            selfcol_context_sequence_self_collide(r->context, seq, r->coherent, got, o),
            SELFCOL_OK);
        assert_int_equal(selfcol_context_self_collide(r->context, r->fresh, want, o), SELFCOL_OK);
    } else {
        assert_int_equal(selfcol_sequence_self_collide(seq, r->coherent, got, o), SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_self_collide(r->fresh, want, o), SELFCOL_OK);
    }
    assert_same_records(got, want, where, frame);
    if (exhaustive) {
        selfcol_query_options e = *o;
        e.method = SELFCOL_METHOD_EXHAUSTIVE;
        assert_int_equal(selfcol_hierarchy_self_collide(r->fresh, want, &e), SELFCOL_OK);
        assert_same_records(got, want, where, frame);
    }
}

static selfcol_sequence_run_stats run_stats(const selfcol_sequence *seq) {
    selfcol_sequence_run_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
    assert_int_equal(selfcol_sequence_stats(seq, &st), SELFCOL_OK);
    return st;
}

// x = flat + a (crumpled - flat): the crumple's amplitude grows with a.
static void blend(double *out, const fixture *flat, const fixture *crumpled, double a) {
    for (size_t i = 0; i < 3 * flat->vertex_count; ++i)
        out[i] = flat->positions[i] + a * (crumpled->positions[i] - flat->positions[i]);
}

// A sequence over an n x n sheet between flat and crumpled (seed,
// amplitude): the rig starts flat, and each frame blends the two.
typedef struct blend_run {
    fixture flat, crumpled;
    double *x;
    rig r;
    selfcol_sequence *seq;
    selfcol_contacts *got, *want;
} blend_run;

static void blend_run_open(blend_run *b, unsigned n, unsigned seed, double amplitude, double skin) {
    memset(b, 0, sizeof *b);
    assert_int_equal(fixture_grid(&b->flat, n, n, 1.0), 0);
    assert_int_equal(fixture_crumpled(&b->crumpled, n, n, seed, amplitude), 0);
    assert_int_equal(b->flat.vertex_count, b->crumpled.vertex_count);
    assert_memory_equal(b->flat.triangles, b->crumpled.triangles,
                        3 * b->flat.triangle_count * sizeof(uint32_t));
    b->x = malloc(3 * b->flat.vertex_count * sizeof *b->x);
    assert_non_null(b->x);
    rig_make(&b->r, &b->flat);
    selfcol_sequence_options so;
    selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    so.skin = skin;
    assert_int_equal(selfcol_sequence_create(&b->seq, &so), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&b->got, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&b->want, NULL), SELFCOL_OK);
}

// The frame at blend a, checked against the fresh query (and EXHAUSTIVE
// when asked); returns its contact count.
static size_t blend_run_frame(blend_run *b, double a, const selfcol_query_options *o,
                              int exhaustive, const char *where, int frame) {
    blend(b->x, &b->flat, &b->crumpled, a);
    rig_move(&b->r, b->x, b->flat.vertex_count);
    check_self_frame(&b->r, b->seq, b->got, b->want, o, exhaustive, where, frame);
    return selfcol_contacts_count(b->got);
}

static void blend_run_close(blend_run *b) {
    selfcol_contacts_destroy(b->got);
    selfcol_contacts_destroy(b->want);
    selfcol_sequence_destroy(b->seq);
    rig_free(&b->r);
    free(b->x);
    fixture_free(&b->flat);
    fixture_free(&b->crumpled);
}

// A sheet crumpling slowly until it folds onto itself and crosses, frame
// after frame, for each kind mask, method and thread count.
static void run_crumpling(uint32_t method, uint32_t kinds, unsigned threads, double skin) {
    blend_run b;
    blend_run_open(&b, 24, 7, 3.0, skin);
    rig_threads(&b.r, threads);
    const selfcol_query_options o = query_options(method, 0.1, kinds);
    const int frames = 80;
    uint64_t contacts_seen = 0;
    for (int k = 0; k <= frames; ++k)
        // The crumple from 60 % to 80 % of its amplitude: folded, crossing,
        // each vertex moving about a hundredth of an edge per frame.
        contacts_seen +=
            blend_run_frame(&b, 0.6 + 0.2 * k / frames, &o, k % 20 == 0, "crumpling", k);
    // The sheet folds and crosses: the sequence had something to find.
    assert_true(contacts_seen > 0);
    // Small steps: most frames come from the near list.
    selfcol_sequence_run_stats st = run_stats(b.seq);
    assert_int_equal(st.frames, frames + 1);
    assert_true((st.rebuilds + st.fresh_frames) * 3 < st.frames);
    assert_true(st.skin > 0.0);
    blend_run_close(&b);
}

static void test_crumpling_sheet_equals_fresh_exact(void **state) {
    (void)state;
    run_crumpling(SELFCOL_METHOD_EXACT, SELFCOL_KIND_ALL, 1, 0.0);
}

static void test_crumpling_sheet_equals_fresh_bvh_two_threads(void **state) {
    (void)state;
    run_crumpling(SELFCOL_METHOD_BVH, SELFCOL_KIND_ALL, 2, 0.0);
}

static void test_each_kind_alone_equals_fresh(void **state) {
    (void)state;
    run_crumpling(SELFCOL_METHOD_EXACT, SELFCOL_KIND_VF, 1, 0.0);
    run_crumpling(SELFCOL_METHOD_EXACT, SELFCOL_KIND_EE, 1, 0.0);
    run_crumpling(SELFCOL_METHOD_EXACT, SELFCOL_KIND_EF, 1, 0.0);
}

static void test_a_wider_skin_equals_fresh(void **state) {
    (void)state;
    run_crumpling(SELFCOL_METHOD_EXACT, SELFCOL_KIND_ALL, 1, 0.4);
}

// A sheet crumpling fast (its folds deepen by a whole amplitude in 12
// frames): a list would not last, the frames are fresh queries, and the
// records still equal the fresh query's.
static void test_fast_deformation_answers_fresh(void **state) {
    (void)state;
    blend_run b;
    blend_run_open(&b, 20, 9, 3.0, 0.0);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);
    for (int k = 0; k <= 12; ++k)
        blend_run_frame(&b, k / 12.0, &o, k % 6 == 0, "fast", k);
    selfcol_sequence_run_stats st = run_stats(b.seq);
    assert_int_equal(st.frames, 13);
    assert_true(st.fresh_frames >= 10);
    blend_run_close(&b);
}

// Interferences only (d = 0): the automatic skin is a tenth of an edge.
static void test_zero_distance_equals_fresh(void **state) {
    (void)state;
    blend_run b;
    blend_run_open(&b, 20, 3, 3.0, 0.0);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.0, SELFCOL_KIND_ALL);
    uint64_t crossings = 0;
    for (int k = 0; k <= 60; ++k)
        crossings += blend_run_frame(&b, k / 60.0, &o, k % 30 == 0, "zero distance", k);
    assert_true(crossings > 0);
    selfcol_sequence_run_stats st = run_stats(b.seq);
    assert_true(fabs(st.skin - 0.1 * selfcol_mesh_mean_edge_length(b.r.mesh)) <= 0.05 * st.skin);
    blend_run_close(&b);
}

static void rotate_z(double *x, size_t V, double angle) {
    const double c = cos(angle), s = sin(angle);
    for (size_t v = 0; v < V; ++v) {
        const double a = x[3 * v], b = x[3 * v + 1];
        x[3 * v] = c * a - s * b;
        x[3 * v + 1] = s * a + c * b;
    }
}

// Jumps: a rigid translation keeps the near list (the deformation is 0); a
// quarter turn, a reset to the flat sheet and a return to the folded one
// rebuild; every frame equals the fresh query.
static void test_jumps_rebuild_or_reuse_as_proven(void **state) {
    (void)state;
    fixture base = {0};
    assert_int_equal(fixture_crumpled(&base, 20, 20, 11, 2.5), 0);
    fixture flat = {0};
    assert_int_equal(fixture_grid(&flat, 20, 20, 1.0), 0);
    const size_t V = base.vertex_count;
    double *x = malloc(3 * V * sizeof *x);
    assert_non_null(x);
    rig r;
    rig_make(&r, &base);
    selfcol_sequence *seq;
    assert_int_equal(selfcol_sequence_create(&seq, NULL), SELFCOL_OK);
    selfcol_contacts *got, *want;
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&want, NULL), SELFCOL_OK);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);

    memcpy(x, base.positions, 3 * V * sizeof *x);
    rig_move(&r, x, V);
    // A first frame is fresh; the same positions again deform nothing: a
    // list pays, and is built.
    check_self_frame(&r, seq, got, want, &o, 1, "jump start", 0);
    assert_true(selfcol_contacts_count(got) > 0);
    selfcol_sequence_run_stats st = run_stats(seq);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
    assert_int_equal(st.last_reason, 0);
    assert_int_equal(st.near_pairs, 0);
    check_self_frame(&r, seq, got, want, &o, 0, "still", 1);
    st = run_stats(seq);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_REBUILT);
    assert_int_equal(st.last_reason, 2);
    assert_true(st.near_pairs >= selfcol_contacts_count(got));

    // Teleport by a rigid translation of 1000 edges: answered from the list.
    for (size_t v = 0; v < V; ++v) {
        x[3 * v] += 1000.0;
        x[3 * v + 1] -= 250.0;
        x[3 * v + 2] += 62.5;
    }
    rig_move(&r, x, V);
    check_self_frame(&r, seq, got, want, &o, 0, "translated", 2);
    st = run_stats(seq);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FROM_LIST);
    assert_true(st.deformation_ratio < 1.0);

    // A quarter turn moves points relative to each other, far more than a
    // list allows per frame: a fresh query.
    rotate_z(x, V, 1.5707963267948966);
    rig_move(&r, x, V);
    check_self_frame(&r, seq, got, want, &o, 1, "rotated", 3);
    st = run_stats(seq);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
    assert_int_equal(st.last_reason, 2);
    assert_true(st.deformation_ratio > 1.0);

    // Reset to the flat sheet (nothing near), then back to the fold: fresh
    // twice; then still again: rebuilt, then from the list.
    rig_move(&r, flat.positions, V);
    check_self_frame(&r, seq, got, want, &o, 1, "reset", 4);
    assert_int_equal(run_stats(seq).last_answer, SELFCOL_SEQUENCE_FRESH);
    rig_move(&r, base.positions, V);
    check_self_frame(&r, seq, got, want, &o, 1, "folded again", 5);
    assert_int_equal(run_stats(seq).last_answer, SELFCOL_SEQUENCE_FRESH);
    check_self_frame(&r, seq, got, want, &o, 0, "still", 6);
    assert_int_equal(run_stats(seq).last_answer, SELFCOL_SEQUENCE_REBUILT);
    check_self_frame(&r, seq, got, want, &o, 0, "still", 7);
    assert_int_equal(run_stats(seq).last_answer, SELFCOL_SEQUENCE_FROM_LIST);
    st = run_stats(seq);
    assert_int_equal(st.frames, 8);
    assert_int_equal(st.rebuilds, 2);
    assert_int_equal(st.fresh_frames, 4);

    // Other options start afresh (reason 1), and still equal the fresh query.
    const selfcol_query_options o2 =
        query_options(SELFCOL_METHOD_BVH, 0.05, SELFCOL_KIND_VF | SELFCOL_KIND_EF);
    check_self_frame(&r, seq, got, want, &o2, 1, "options", 8);
    st = run_stats(seq);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
    assert_int_equal(st.last_reason, 1);
    check_self_frame(&r, seq, got, want, &o2, 1, "options, still", 9);
    assert_int_equal(run_stats(seq).last_answer, SELFCOL_SEQUENCE_REBUILT);
    // Reset forgets everything.
    selfcol_sequence_reset(seq);
    check_self_frame(&r, seq, got, want, &o2, 0, "after reset", 10);
    st = run_stats(seq);
    assert_int_equal(st.frames, 1);
    assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
    assert_int_equal(st.last_reason, 0);

    selfcol_contacts_destroy(got);
    selfcol_contacts_destroy(want);
    selfcol_sequence_destroy(seq);
    rig_free(&r);
    free(x);
    fixture_free(&base);
    fixture_free(&flat);
}

// How much of vertex v moves in the local sequences below: all of it in the
// strip x < 0.2 of the sheet's width, none beyond 0.3, a ramp between.
static double local_weight(const fixture *flat, size_t v, double width) {
    const double x = flat->positions[3 * v] / width;
    return x < 0.2 ? 1.0 : x < 0.3 ? (0.3 - x) / 0.1 : 0.0;
}

// Two surfaces: a crumpled n x n sheet lifted by `lift` sinks through a flat
// one by `sink` per frame, everywhere or (local) in the strip of
// local_weight only; with `swap`, the meshes change order at frame 50 (the
// sequence starts afresh). Every frame equals the fresh query, and
// EXHAUSTIVE every 25 frames; returns the sequence's counters.
static selfcol_sequence_run_stats run_two_surfaces(unsigned n, double lift, double sink, int local,
                                                   int swap, const char *where) {
    fixture a = {0}, b = {0};
    assert_int_equal(fixture_grid(&a, n, n, 1.0), 0);
    assert_int_equal(fixture_crumpled(&b, n, n, 5, 1.0), 0);
    const double offset[3] = {0.3, 0.2, lift};
    fixture_translate(&b, offset);
    rig ra, rb;
    rig_make(&ra, &a);
    rig_make(&rb, &b);
    const size_t V = b.vertex_count;
    double width = 0.0;
    for (size_t v = 0; v < V; ++v)
        width = fmax(width, a.positions[3 * v]);
    double *x = malloc(3 * V * sizeof *x);
    assert_non_null(x);
    selfcol_sequence *seq;
    assert_int_equal(selfcol_sequence_create(&seq, NULL), SELFCOL_OK);
    selfcol_contacts *got, *want;
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&want, NULL), SELFCOL_OK);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);
    uint64_t seen = 0;
    for (int k = 0; k <= 100; ++k) {
        memcpy(x, b.positions, 3 * V * sizeof *x);
        for (size_t v = 0; v < V; ++v)
            x[3 * v + 2] -= sink * k * (local ? local_weight(&a, v, width) : 1.0);
        rig_move(&rb, x, V);
        const int swapped = swap && k >= 50;
        rig *first = swapped ? &rb : &ra, *second = swapped ? &ra : &rb;
        assert_int_equal(selfcol_sequence_collide(seq, first->coherent, second->coherent, got, &o),
                         SELFCOL_OK);
        assert_int_equal(selfcol_hierarchy_collide(first->fresh, second->fresh, want, &o),
                         SELFCOL_OK);
        assert_same_records(got, want, where, k);
        if (k % 25 == 0) {
            selfcol_query_options e = o;
            e.method = SELFCOL_METHOD_EXHAUSTIVE;
            assert_int_equal(selfcol_hierarchy_collide(first->fresh, second->fresh, want, &e),
                             SELFCOL_OK);
            assert_same_records(got, want, where, k);
        }
        seen += selfcol_contacts_count(got);
    }
    assert_true(seen > 0);
    const selfcol_sequence_run_stats st = run_stats(seq);
    selfcol_contacts_destroy(got);
    selfcol_contacts_destroy(want);
    selfcol_sequence_destroy(seq);
    rig_free(&ra);
    rig_free(&rb);
    free(x);
    fixture_free(&a);
    fixture_free(&b);
    return st;
}

// A crumpled sheet sinking slowly through a flat one.
static void test_two_surfaces_equal_fresh(void **state) {
    (void)state;
    const selfcol_sequence_run_stats st = run_two_surfaces(16, 2.5, 0.02, 0, 0, "two surfaces");
    // The other surface stays still: the motion relative to it counts, so
    // the list is rebuilt now and then (a fifth of the skin per frame: a
    // list lasts about 5 frames), not every frame.
    assert_true(st.rebuilds > 1);
    assert_true((st.rebuilds + st.fresh_frames) * 2 < st.frames);
}

// A sheet whose folds deepen in one strip only (the rest holds still), and
// two surfaces of which one sinks at one end only: the lists fail in a few
// cluster pairs, which a partial rebuild queries again while the others
// keep their pairs through carries (sequence.c, "Partial rebuilds"); every
// frame equals the fresh query (and EXHAUSTIVE now and then).
// Frame k of 90 of the local crumpling: from 60 % of the crumple, deepening
// to 65 % in the strip.
static void local_frame(double *x, const fixture *flat, const fixture *crumpled, double width,
                        int k) {
    for (size_t v = 0; v < flat->vertex_count; ++v) {
        const double a = 0.6 + 0.05 * local_weight(flat, v, width) * k / 90.0;
        for (size_t i = 3 * v; i < 3 * v + 3; ++i)
            x[i] = flat->positions[i] + a * (crumpled->positions[i] - flat->positions[i]);
    }
}

static void run_local_crumpling(uint32_t method, unsigned threads) {
    blend_run b;
    blend_run_open(&b, 40, 3, 3.0, 0.0);
    rig_threads(&b.r, threads);
    const selfcol_query_options o = query_options(method, 0.1, SELFCOL_KIND_ALL);
    const size_t V = b.flat.vertex_count;
    double width = 0.0;
    for (size_t v = 0; v < V; ++v)
        width = fmax(width, b.flat.positions[3 * v]);
    const int frames = 90;
    uint64_t contacts_seen = 0;
    for (int k = 0; k <= frames; ++k) {
        local_frame(b.x, &b.flat, &b.crumpled, width, k);
        rig_move(&b.r, b.x, V);
        check_self_frame(&b.r, b.seq, b.got, b.want, &o, k % 45 == 0, "local crumpling", k);
        contacts_seen += selfcol_contacts_count(b.got);
    }
    assert_true(contacts_seen > 0);
    selfcol_sequence_run_stats st = run_stats(b.seq);
    assert_int_equal(st.frames, frames + 1);
    // Several partial rebuilds, so that carries add up over more than one.
    assert_true(st.partial_rebuilds >= 3);
    assert_true(st.partial_rebuilds <= st.rebuilds);
    assert_true((st.rebuilds + st.fresh_frames) * 3 < st.frames);
    blend_run_close(&b);
}

static void test_local_crumpling_rebuilds_in_part_exact(void **state) {
    (void)state;
    run_local_crumpling(SELFCOL_METHOD_EXACT, 1);
}

static void test_local_crumpling_rebuilds_in_part_bvh_two_threads(void **state) {
    (void)state;
    run_local_crumpling(SELFCOL_METHOD_BVH, 2);
}

static void test_two_surfaces_one_end_sinking(void **state) {
    (void)state;
    // The sheets cross from the start, so contacts are held everywhere while
    // only one end moves: partial rebuilds, in both orders of the meshes.
    const selfcol_sequence_run_stats st = run_two_surfaces(32, 0.0, 0.01, 1, 1, "one end sinking");
    assert_int_equal(st.fresh_frames, 2);
    assert_true(st.partial_rebuilds >= 6);
}

// SEED and CONE (approximate skips, nothing a near list could reproduce)
// are answered by their own fresh query every frame, between frames of an
// exact method that the sequence answers from its list; after them the
// exact method starts afresh.
static void test_approximate_methods_answer_fresh(void **state) {
    (void)state;
    blend_run b;
    blend_run_open(&b, 16, 5, 3.0, 0.0);
    const uint32_t methods[8] = {SELFCOL_METHOD_EXACT, SELFCOL_METHOD_EXACT, SELFCOL_METHOD_EXACT,
                                 SELFCOL_METHOD_SEED,  SELFCOL_METHOD_CONE,  SELFCOL_METHOD_CONE,
                                 SELFCOL_METHOD_EXACT, SELFCOL_METHOD_EXACT};
    size_t total = 0;
    for (int frame = 0; frame < 8; ++frame) {
        const selfcol_query_options o = query_options(methods[frame], 0.1, SELFCOL_KIND_ALL);
        total += blend_run_frame(&b, 1.0 + 0.0005 * frame, &o, 0, "approximate", frame);
        const selfcol_sequence_run_stats st = run_stats(b.seq);
        assert_int_equal(st.frames, (uint64_t)frame + 1);
        if (methods[frame] != SELFCOL_METHOD_EXACT) {
            assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
            assert_int_equal(st.last_reason, 3);
            assert_int_equal(st.near_pairs, 0);
        } else if (frame == 0 || frame == 6) {
            // A first frame: no reference (after SEED and CONE none is kept).
            assert_int_equal(st.last_answer, SELFCOL_SEQUENCE_FRESH);
            assert_int_equal(st.last_reason, 0);
        }
    }
    assert_true(total > 0);
    assert_true(run_stats(b.seq).fresh_frames >= 5); // frames 0, 3, 4, 5 and 6 at least
    blend_run_close(&b);
}

static void test_refuses_bad_input(void **state) {
    (void)state;
    selfcol_sequence_options so;
    assert_int_equal(selfcol_sequence_options_init(NULL, 1), SELFCOL_EINVAL);
    assert_int_equal(selfcol_sequence_options_init(&so, 0), SELFCOL_EVERSION);
    assert_int_equal(selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION + 1),
                     SELFCOL_EVERSION);
    assert_int_equal(selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION),
                     SELFCOL_OK);
    assert_true(so.skin == 0.0);
    selfcol_sequence *seq = (selfcol_sequence *)&so;
    assert_int_equal(selfcol_sequence_create(NULL, &so), SELFCOL_EINVAL);
    so.skin = -1.0;
    assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_EINVAL);
    assert_null(seq);
    so.skin = NAN;
    assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_EINVAL);
    so.skin = INFINITY;
    assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_EINVAL);
    so.skin = 0.0;
    so.version = 0;
    assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_EVERSION);
    so.version = SELFCOL_SEQUENCE_OPTIONS_VERSION;

    fixture f = {0};
    assert_int_equal(fixture_crumpled(&f, 8, 8, 1, 2.0), 0);
    rig r, r2;
    rig_make(&r, &f);
    rig_make(&r2, &f);
    selfcol_contacts *c;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_OK);
    selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);
    o.method = 99;
    assert_int_equal(selfcol_sequence_self_collide(seq, r.coherent, c, &o), SELFCOL_EINVAL);
    o.method = SELFCOL_METHOD_EXACT;
    o.distance = NAN;
    assert_int_equal(selfcol_sequence_self_collide(seq, r.coherent, c, &o), SELFCOL_EINVAL);
    o.distance = 0.1;
    assert_int_equal(selfcol_sequence_self_collide(NULL, r.coherent, c, &o), SELFCOL_EINVAL);
    assert_int_equal(selfcol_sequence_self_collide(seq, NULL, c, &o), SELFCOL_EINVAL);
    assert_int_equal(selfcol_sequence_self_collide(seq, r.coherent, NULL, &o), SELFCOL_EINVAL);
    // Two hierarchies of one mesh are not two surfaces.
    assert_int_equal(selfcol_sequence_collide(seq, r.coherent, r.fresh, c, &o), SELFCOL_EINVAL);
    // Nothing was answered.
    assert_int_equal(run_stats(seq).frames, 0);
    selfcol_sequence_run_stats st;
    st.version = 0;
    assert_int_equal(selfcol_sequence_stats(seq, &st), SELFCOL_EVERSION);
    assert_int_equal(selfcol_sequence_stats(NULL, &st), SELFCOL_EINVAL);
    assert_int_equal(selfcol_sequence_byte_count(NULL), 0);
    selfcol_sequence_destroy(NULL);
    selfcol_sequence_reset(NULL);
    // NULL options: the defaults (EXACT, d = 0), as the fresh query's.
    selfcol_contacts *want;
    assert_int_equal(selfcol_contacts_create(&want, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_sequence_self_collide(seq, r.coherent, c, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(r.fresh, want, NULL), SELFCOL_OK);
    assert_same_records(c, want, "defaults", 0);
    assert_true(selfcol_sequence_byte_count(seq) > sizeof(double) * 3 * f.vertex_count);
    selfcol_contacts_destroy(want);
    selfcol_contacts_destroy(c);
    selfcol_sequence_destroy(seq);
    rig_free(&r);
    rig_free(&r2);
    fixture_free(&f);
}

// Sequence options whose allocator counts into st (emptied) and fails the
// allocation numbered st->fail_at (test_allocator).
static selfcol_sequence_options counted_options(test_allocator_state *st) {
    memset(st, 0, sizeof *st);
    selfcol_sequence_options so;
    selfcol_sequence_options_init(&so, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    so.allocator = test_allocator(st);
    return so;
}

// Out of memory at every allocation of creation and of the first (rebuild)
// and second queries: ENOMEM, nothing leaked, and the next query with memory
// answers right.
static void test_allocation_failure_is_clean(void **state) {
    (void)state;
    fixture f = {0};
    assert_int_equal(fixture_crumpled(&f, 10, 10, 2, 2.5), 0);
    rig r;
    rig_make(&r, &f);
    selfcol_contacts *c, *want;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&want, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_refit(r.fresh), SELFCOL_OK);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);
    assert_int_equal(selfcol_hierarchy_self_collide(r.fresh, want, &o), SELFCOL_OK);
    assert_true(selfcol_contacts_count(want) > 0);
    int failures = 0;
    for (long fail = 1;; ++fail) {
        test_allocator_state st;
        const selfcol_sequence_options so = counted_options(&st);
        st.fail_at = fail;
        selfcol_sequence *seq = NULL;
        int status = selfcol_sequence_create(&seq, &so);
        if (status == SELFCOL_OK) {
            status = selfcol_sequence_self_collide(seq, r.coherent, c, &o);
            if (status == SELFCOL_ENOMEM) {
                assert_int_equal(selfcol_contacts_count(c), 0);
                st.fail_at = 0;
                assert_int_equal(selfcol_sequence_self_collide(seq, r.coherent, c, &o), SELFCOL_OK);
                assert_same_records(c, want, "after ENOMEM", (int)fail);
            } else {
                assert_int_equal(status, SELFCOL_OK);
                assert_same_records(c, want, "no failure", (int)fail);
            }
            selfcol_sequence_destroy(seq);
        } else {
            assert_int_equal(status, SELFCOL_ENOMEM);
            assert_null(seq);
        }
        assert_int_equal(st.live, 0);
        assert_false(st.misaligned);
        if (st.calls < fail)
            break; // every allocation has failed once
        failures++;
    }
    assert_true(failures >= 3);
    selfcol_contacts_destroy(c);
    selfcol_contacts_destroy(want);
    rig_free(&r);
    fixture_free(&f);
}

// Every allocation of a partial rebuild fails in turn: the query returns
// SELFCOL_ENOMEM with no records, and the next one answers right (afresh).
static void test_allocation_failure_in_a_partial_rebuild_is_clean(void **state) {
    (void)state;
    blend_run b;
    blend_run_open(&b, 40, 3, 3.0, 0.0);
    const size_t V = b.flat.vertex_count;
    double width = 0.0;
    for (size_t v = 0; v < V; ++v)
        width = fmax(width, b.flat.positions[3 * v]);
    const selfcol_query_options o = query_options(SELFCOL_METHOD_EXACT, 0.1, SELFCOL_KIND_ALL);
    // The first frame answered by a partial rebuild.
    int partial_frame = -1;
    for (int k = 0; k <= 90 && partial_frame < 0; ++k) {
        local_frame(b.x, &b.flat, &b.crumpled, width, k);
        rig_move(&b.r, b.x, V);
        assert_int_equal(selfcol_sequence_self_collide(b.seq, b.r.coherent, b.got, &o), SELFCOL_OK);
        if (run_stats(b.seq).partial_rebuilds > 0)
            partial_frame = k;
    }
    assert_true(partial_frame > 0);
    int failures = 0;
    for (long fail = 1;; ++fail) {
        test_allocator_state st;
        const selfcol_sequence_options so = counted_options(&st);
        selfcol_sequence *seq = NULL;
        assert_int_equal(selfcol_sequence_create(&seq, &so), SELFCOL_OK);
        for (int k = 0; k < partial_frame; ++k) {
            local_frame(b.x, &b.flat, &b.crumpled, width, k);
            rig_move(&b.r, b.x, V);
            assert_int_equal(selfcol_sequence_self_collide(seq, b.r.coherent, b.got, &o),
                             SELFCOL_OK);
        }
        local_frame(b.x, &b.flat, &b.crumpled, width, partial_frame);
        rig_move(&b.r, b.x, V);
        assert_int_equal(selfcol_hierarchy_self_collide(b.r.fresh, b.want, &o), SELFCOL_OK);
        st.fail_at = st.calls + fail;
        const int status = selfcol_sequence_self_collide(seq, b.r.coherent, b.got, &o);
        const int done = st.calls < st.fail_at; // no allocation left to fail
        if (done) {
            assert_int_equal(status, SELFCOL_OK);
            assert_int_equal(run_stats(seq).partial_rebuilds, 1);
            assert_same_records(b.got, b.want, "partial, no failure", (int)fail);
        } else {
            assert_int_equal(status, SELFCOL_ENOMEM);
            assert_int_equal(selfcol_contacts_count(b.got), 0);
            st.fail_at = 0;
            assert_int_equal(selfcol_sequence_self_collide(seq, b.r.coherent, b.got, &o),
                             SELFCOL_OK);
            assert_same_records(b.got, b.want, "partial, after ENOMEM", (int)fail);
            failures++;
        }
        selfcol_sequence_destroy(seq);
        assert_int_equal(st.live, 0);
        assert_false(st.misaligned);
        if (done)
            break;
    }
    // The node masks at least (the new pairs are built in the list's own
    // buffer, which grows only when its slack is short:
    // test_sequence_internal.c makes it grow).
    assert_true(failures >= 1);
    blend_run_close(&b);
}

int main(void) {
    const struct CMUnitTest sequence[] = {
        cmocka_unit_test(test_crumpling_sheet_equals_fresh_exact),
        cmocka_unit_test(test_crumpling_sheet_equals_fresh_bvh_two_threads),
        cmocka_unit_test(test_each_kind_alone_equals_fresh),
        cmocka_unit_test(test_a_wider_skin_equals_fresh),
        cmocka_unit_test(test_zero_distance_equals_fresh),
        cmocka_unit_test(test_fast_deformation_answers_fresh),
        cmocka_unit_test(test_jumps_rebuild_or_reuse_as_proven),
        cmocka_unit_test(test_two_surfaces_equal_fresh),
        cmocka_unit_test(test_local_crumpling_rebuilds_in_part_exact),
        cmocka_unit_test(test_local_crumpling_rebuilds_in_part_bvh_two_threads),
        cmocka_unit_test(test_two_surfaces_one_end_sinking),
        cmocka_unit_test(test_approximate_methods_answer_fresh),
        cmocka_unit_test(test_refuses_bad_input),
        cmocka_unit_test(test_allocation_failure_is_clean),
        cmocka_unit_test(test_allocation_failure_in_a_partial_rebuild_is_clean),
    };
    return cmocka_run_group_tests_name("sequence", sequence, NULL, NULL);
}
