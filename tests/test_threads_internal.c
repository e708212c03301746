// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Internal stages on several threads, held to their one-thread results.
//
// Refits (selfcol_hierarchy_options.threads): every node's
// box, mask, cone and altitude bound must be those of a one-thread refit,
// byte for byte, frame after frame (and every box must hold its triangles:
// the validator); the plan must really share the tree (so the
// comparison is not one thread against itself), stay off small meshes, and
// fail cleanly when it cannot allocate.
//
// The record sort (selfcol_records__sort, on the query's threads): the
// order of one thread for every count, a stable sort of the keys, records
// with equal keys included, on started threads and on a pool's.
//
// A handle's pool (pool.h): every worker of a stage runs once, stage after
// stage on the same threads, with the first failing worker's status; a
// stage started from inside a stage runs on threads of its own.
//
// Run under ThreadSanitizer in CI.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "base/parallel.h"
#include "fixtures.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/context.h"
#include "query/records.h"
#include "test_alloc.h"

// A context of `threads` threads; NULL for one (the calls without one).
static selfcol_context *context_of(unsigned threads) {
    if (threads == 1)
        return NULL;
    selfcol_context_options o;
    selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION);
    o.threads = threads;
    selfcol_context *c = NULL;
    assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_OK);
    return c;
}

// A refit on `context` (NULL: the calling thread).
static int refit_on(selfcol_context *context, selfcol_hierarchy *h) {
    return context != NULL ? selfcol_context_refit(context, h) : selfcol_hierarchy_refit(h);
}

// A hierarchy, refit once on `context` (which plans the split for its threads).
static selfcol_hierarchy *create(const selfcol_mesh *m, selfcol_context *context) {
    selfcol_hierarchy *h = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    assert_int_equal(refit_on(context, h), SELFCOL_OK);
    return h;
}

static void assert_same_nodes(const selfcol_hierarchy *a, const selfcol_hierarchy *b) {
    assert_int_equal(a->node_count, b->node_count);
    assert_memory_equal(a->nodes, b->nodes, a->node_count * sizeof(selfcol_node));
    assert_memory_equal(a->min_altitude, b->min_altitude, a->node_count * sizeof(float));
}

// A 128 x 128 crumpled sheet (32,768 triangles: 8 workers of 4,096) and, in
// the same mesh, a few small sheets of other sizes, so that subtrees differ
// in size and the cap holds whole small components (leaves among them).
static void sheet_with_islands(fixture *s, double amplitude) {
    assert_int_equal(fixture_crumpled(s, 128, 128, 3, amplitude), 0);
    const unsigned sizes[3] = {3, 9, 30};
    for (int i = 0; i < 3; ++i) {
        fixture island;
        assert_int_equal(fixture_crumpled(&island, sizes[i], sizes[i] + 1, 5 + i, amplitude), 0);
        const double offset[3] = {140.0 + 40.0 * i, 0.0, 0.0};
        fixture_translate(&island, offset);
        assert_int_equal(fixture_append(s, &island), 0);
        fixture_free(&island);
    }
}

static void test_refit_threads_give_the_nodes_of_one_thread(void **state) {
    (void)state;
    fixture s;
    sheet_with_islands(&s, 3.0);
    selfcol_mesh *m = NULL;
    assert_int_equal(
        selfcol_mesh_create(&m, s.vertex_count, s.positions, s.triangle_count, s.triangles, NULL),
        SELFCOL_OK);
    enum { COUNTS = 4 };
    const unsigned threads[COUNTS] = {1, 2, 3, 8};
    selfcol_hierarchy *h[COUNTS];
    selfcol_context *context[COUNTS];
    for (int i = 0; i < COUNTS; ++i) {
        context[i] = context_of(threads[i]);
        h[i] = create(m, context[i]);
    }
    // The plan shares the tree: one task list, several workers, most nodes
    // below the cap.
    assert_int_equal(h[0]->refit_workers, 1);
    assert_int_equal(h[0]->subtree_count, 0);
    for (int i = 1; i < COUNTS; ++i) {
        assert_int_equal(h[i]->refit_workers, threads[i]);
        assert_true(h[i]->subtree_count >= 8 * threads[i]);
        assert_true(h[i]->cap < h[i]->node_count / 8);
        assert_true(selfcol_hierarchy_byte_count(h[i]) > selfcol_hierarchy_byte_count(h[0]));
        assert_true(selfcol_hierarchy_byte_count(h[i]) < 64 * s.triangle_count);
        // Every node below the cap belongs to exactly one task.
        size_t covered = 0;
        for (uint32_t l = 0; l < h[i]->subtree_level_offset[h[i]->subtree_count]; ++l)
            covered += h[i]->subtree_level[2 * l + 1] - h[i]->subtree_level[2 * l];
        assert_int_equal(covered + h[i]->cap, h[i]->node_count);
    }
    for (int i = 1; i < COUNTS; ++i)
        assert_same_nodes(h[0], h[i]); // the first refit (the plan's)
    // Frames: the crumple deepens, then a large jump (the sheet flattened).
    const double amplitudes[5] = {3.2, 3.6, 4.4, 5.0, 0.5};
    for (int f = 0; f < 5; ++f) {
        fixture next;
        sheet_with_islands(&next, amplitudes[f]);
        assert_int_equal(next.vertex_count, s.vertex_count);
        assert_int_equal(selfcol_mesh_set_positions(m, next.positions, next.vertex_count),
                         SELFCOL_OK);
        for (int i = 0; i < COUNTS; ++i) {
            assert_int_equal(refit_on(context[i], h[i]), SELFCOL_OK);
            assert_int_equal(selfcol_hierarchy__validate(h[i], 1), 1);
        }
        for (int i = 1; i < COUNTS; ++i)
            assert_same_nodes(h[0], h[i]);
        fixture_free(&next);
    }
    // One hierarchy refit on contexts of other counts in turn: re-planned
    // each time, the same nodes.
    for (int i = COUNTS; i-- > 0;) {
        assert_int_equal(refit_on(context[i], h[1]), SELFCOL_OK);
        assert_int_equal(h[1]->refit_workers, threads[i] > 1 ? threads[i] : 2);
        assert_same_nodes(h[0], h[1]);
    }
    for (int i = 0; i < COUNTS; ++i) {
        selfcol_hierarchy_destroy(h[i]);
        selfcol_context_destroy(context[i]);
    }
    selfcol_mesh_destroy(m);
    fixture_free(&s);
}

static void test_refit_plan_bounds_and_allocation_failure(void **state) {
    (void)state;
    // Fewer than 2 x 4,096 triangles: no plan, whatever the threads.
    fixture small;
    assert_int_equal(fixture_crumpled(&small, 60, 60, 1, 2.0), 0); // 7,200 triangles
    selfcol_mesh *m = NULL;
    assert_int_equal(selfcol_mesh_create(&m, small.vertex_count, small.positions,
                                         small.triangle_count, small.triangles, NULL),
                     SELFCOL_OK);
    selfcol_context *most = context_of(SELFCOL_MAX_THREADS);
    selfcol_hierarchy *h = create(m, most);
    assert_int_equal(h->refit_workers, 1);
    assert_null(h->subtree_root);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    fixture_free(&small);

    // 8,192 triangles: two workers at most, whatever the threads asked.
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 64, 64, 1, 2.0), 0);
    assert_int_equal(s.triangle_count, 8192);
    assert_int_equal(
        selfcol_mesh_create(&m, s.vertex_count, s.positions, s.triangle_count, s.triangles, NULL),
        SELFCOL_OK);
    h = create(m, most);
    assert_int_equal(h->refit_workers, 2);
    selfcol_hierarchy *one = create(m, NULL);
    assert_same_nodes(one, h);
    selfcol_hierarchy_destroy(one);
    selfcol_hierarchy_destroy(h);

    // Every allocation of a creation and of its first refit on two threads
    // (the plan's) may fail: SELFCOL_ENOMEM and nothing left allocated; a
    // failed plan still leaves the hierarchy refit (on the calling thread)
    // and the next refit plans again; until one succeeds with the plan made.
    selfcol_context *two = context_of(2);
    int succeeded = 0;
    for (long fail_at = 1; fail_at < 200 && !succeeded; ++fail_at) {
        test_allocator_state st = {0};
        st.fail_at = fail_at;
        selfcol_hierarchy_options o;
        selfcol_hierarchy_options_init(&o, SELFCOL_HIERARCHY_OPTIONS_VERSION);
        o.allocator = test_allocator(&st);
        h = NULL;
        int status = selfcol_hierarchy_create(&h, m, &o);
        if (status == SELFCOL_OK) {
            status = selfcol_context_refit(two, h);
            assert_int_equal(h->refit_version, m->positions_version); // refit either way
            if (status == SELFCOL_OK) {
                succeeded = 1;
                assert_int_equal(h->refit_workers, 2);
                assert_true(st.calls < fail_at); // no failed allocation was skipped
            } else {
                assert_int_equal(status, SELFCOL_ENOMEM);
                assert_int_equal(h->refit_workers, 1);
                st.fail_at = 0; // memory back: the next refit plans
                assert_int_equal(selfcol_context_refit(two, h), SELFCOL_OK);
                assert_int_equal(h->refit_workers, 2);
            }
            selfcol_hierarchy_destroy(h);
        } else {
            assert_int_equal(status, SELFCOL_ENOMEM);
            assert_null(h);
        }
        assert_int_equal(st.live, 0);
        assert_int_equal(st.misaligned, 0);
    }
    assert_true(succeeded);
    selfcol_context_destroy(two);
    selfcol_context_destroy(most);
    selfcol_mesh_destroy(m);
    fixture_free(&s);
}

// n records with keys drawn from small ranges (so that many repeat), their
// push order in `distance`, fields past the key drawn too.
static selfcol_records *random_records(size_t n, uint32_t seed) {
    selfcol_records *c = malloc(sizeof *c);
    assert_non_null(c);
    const selfcol_allocator standard = {NULL, NULL, NULL};
    selfcol_records__init(c, &standard);
    uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1u;
    for (size_t i = 0; i < n; ++i) {
        uint32_t draw[4];
        for (int k = 0; k < 4; ++k) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            draw[k] = (uint32_t)(state >> 33);
        }
        selfcol_contact r;
        memset(&r, 0, sizeof r);
        r.kind = draw[0] % 3;
        r.first_mesh = (draw[0] >> 2) & 1u;
        r.second_mesh = (draw[0] >> 3) & 1u;
        // Wide enough for every digit of the sort to vary, narrow enough
        // for keys to repeat.
        r.first = draw[1] % 3000u * 997u;
        r.second = draw[2] % 50u << (draw[3] % 28u);
        r.a[0] = draw[3];
        r.distance = (double)i;
        assert_int_equal(selfcol_records__push(c, &r), SELFCOL_OK);
    }
    return c;
}

// Sorts r on `threads` workers of `executor` (NULL: POSIX threads started
// per stage), with a workspace of its own.
static void sort_records_on(selfcol_records *r, unsigned threads,
                            const selfcol_executor *executor) {
    selfcol_workspace work;
    selfcol_workspace__init(&work, &r->allocator);
    assert_int_equal(selfcol_records__sort(r, NULL, 0, &work, executor, threads), SELFCOL_OK);
    selfcol_workspace__free(&work);
}

static void sort_records(selfcol_records *r, unsigned threads) {
    sort_records_on(r, threads, NULL);
}

static void free_records(selfcol_records *r) {
    selfcol_records__free(r);
    free(r);
}

static int key_order(const selfcol_contact *a, const selfcol_contact *b) {
    const uint32_t ka[5] = {a->kind, a->first_mesh, a->first, a->second_mesh, a->second};
    const uint32_t kb[5] = {b->kind, b->first_mesh, b->first, b->second_mesh, b->second};
    for (int i = 0; i < 5; ++i)
        if (ka[i] != kb[i])
            return ka[i] < kb[i] ? -1 : 1;
    return 0;
}

static void test_sort_threads_give_the_order_of_one_thread(void **state) {
    (void)state;
    // 4 x 65,536 records and a few: 4 chunks at most; the sizes just below
    // and at a chunk's bound too.
    const size_t sizes[3] = {262147, 131072, 131071};
    const unsigned threads[4] = {2, 3, 4, 8};
    for (int z = 0; z < 3; ++z) {
        selfcol_records *one = random_records(sizes[z], 7);
        sort_records(one, 1);
        const selfcol_contact *x = one->items;
        const size_t n = one->count;
        assert_int_equal(n, sizes[z]);
        // Sorted by key; equal keys in push order (stable).
        for (size_t i = 1; i < n; ++i) {
            int order = key_order(&x[i - 1], &x[i]);
            assert_true(order < 0 || (order == 0 && x[i - 1].distance < x[i].distance));
        }
        for (int t = 0; t < 4; ++t) {
            selfcol_records *many = random_records(sizes[z], 7);
            sort_records(many, threads[t]);
            const selfcol_contact *y = many->items;
            const size_t m = many->count;
            assert_int_equal(m, n);
            assert_memory_equal(x, y, n * sizeof *x);
            free_records(many);
        }
        // On a pool, whose chunks are four times smaller (16 of them for
        // 262,147 records).
        const selfcol_allocator standard = {NULL, NULL, NULL};
        selfcol_executor pooled = {NULL, NULL, NULL, selfcol_pool__create(&standard)};
        assert_non_null(pooled.pool);
        for (unsigned t = 5; t <= 16; t += 11) {
            selfcol_records *many = random_records(sizes[z], 7);
            sort_records_on(many, t, &pooled);
            assert_int_equal(many->count, n);
            assert_memory_equal(x, many->items, n * sizeof *x);
            free_records(many);
        }
        assert_true(selfcol_pool__threads(pooled.pool) >= 4);
        selfcol_pool__destroy(pooled.pool);
        free_records(one);
    }
}

// A stage of the pool tests: every worker counts its runs; workers listed
// in fail[] return their status.
typedef struct stage {
    unsigned runs[SELFCOL_MAX_THREADS]; // atomic
    int fail[SELFCOL_MAX_THREADS];
    const selfcol_executor *nested; // non-NULL: worker 1 runs a stage of 3 on it
    struct stage *inner;
} stage;

static int stage_worker(void *context, unsigned w) {
    stage *s = context;
    SELFCOL_ATOMIC_FETCH_ADD(&s->runs[w], 1u);
    if (w == 1 && s->nested != NULL) {
        const int status = selfcol_parallel__run(s->nested, 3, stage_worker, s->inner);
        if (status != SELFCOL_OK)
            return status;
    }
    return s->fail[w];
}

static void test_pool_runs_every_worker_of_every_stage(void **state) {
    (void)state;
    const selfcol_allocator standard = {NULL, NULL, NULL};
    selfcol_executor pooled = {NULL, NULL, NULL, selfcol_pool__create(&standard)};
    assert_non_null(pooled.pool);
    assert_int_equal(selfcol_pool__threads(pooled.pool), 0);
    // Stages of changing widths on the same threads: each worker of a stage
    // runs exactly once, the others not at all.
    unsigned most = 0;
    for (unsigned round = 0; round < 300; ++round) {
        const unsigned workers = 2 + (round * 7u) % 15u; // 2 .. 16
        most = workers > most ? workers : most;
        stage s;
        memset(&s, 0, sizeof s);
        assert_int_equal(selfcol_parallel__run(&pooled, workers, stage_worker, &s), SELFCOL_OK);
        for (unsigned w = 0; w < SELFCOL_MAX_THREADS; ++w)
            assert_int_equal(s.runs[w], w < workers ? 1u : 0u);
        assert_int_equal(selfcol_pool__threads(pooled.pool), most - 1);
    }
    // The first failing worker in worker order names the status, whichever
    // finishes first.
    stage failing;
    memset(&failing, 0, sizeof failing);
    failing.fail[5] = SELFCOL_EINVAL;
    failing.fail[2] = SELFCOL_ENOMEM;
    assert_int_equal(selfcol_parallel__run(&pooled, 8, stage_worker, &failing), SELFCOL_ENOMEM);
    for (unsigned w = 0; w < 8; ++w)
        assert_int_equal(failing.runs[w], 1u);
    // A stage started inside a stage (worker 1) runs on threads of its own:
    // both finish, each worker once.
    stage outer, inner;
    memset(&outer, 0, sizeof outer);
    memset(&inner, 0, sizeof inner);
    outer.nested = &pooled;
    outer.inner = &inner;
    assert_int_equal(selfcol_parallel__run(&pooled, 4, stage_worker, &outer), SELFCOL_OK);
    for (unsigned w = 0; w < SELFCOL_MAX_THREADS; ++w) {
        assert_int_equal(outer.runs[w], w < 4 ? 1u : 0u);
        assert_int_equal(inner.runs[w], w < 3 ? 1u : 0u);
    }
    // More workers than the library's most are capped, as without a pool.
    stage wide;
    memset(&wide, 0, sizeof wide);
    assert_int_equal(selfcol_parallel__run(&pooled, SELFCOL_MAX_THREADS + 5, stage_worker, &wide),
                     SELFCOL_OK);
    for (unsigned w = 0; w < SELFCOL_MAX_THREADS; ++w)
        assert_int_equal(wide.runs[w], 1u);
    selfcol_pool__destroy(pooled.pool);
    selfcol_pool__destroy(NULL);
}

// A pool is allocated with its handle's allocator: a failure is NULL.
static void test_pool_allocation_failure(void **state) {
    (void)state;
    test_allocator_state counter;
    memset(&counter, 0, sizeof counter);
    counter.fail_at = 1;
    const selfcol_allocator failing = test_allocator(&counter);
    assert_null(selfcol_pool__create(&failing));
    counter.fail_at = 0;
    selfcol_pool *p = selfcol_pool__create(&failing);
    assert_non_null(p);
    stage s;
    memset(&s, 0, sizeof s);
    const selfcol_executor pooled = {NULL, NULL, NULL, p};
    assert_int_equal(selfcol_parallel__run(&pooled, 3, stage_worker, &s), SELFCOL_OK);
    selfcol_pool__destroy(p);
    assert_int_equal(counter.live, 0);
    assert_int_equal(counter.misaligned, 0);
}

// Which handles keep threads: a query context of more than one thread
// does, between its queries; one of one thread, like the one a contact set
// makes for the calls without a context, keeps none (a caller may hold
// many contact sets). Both give one thread's records.
static void test_only_query_contexts_keep_their_threads(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 64, 64, 2, 3.0), 0);
    selfcol_mesh *m = NULL;
    assert_int_equal(
        selfcol_mesh_create(&m, s.vertex_count, s.positions, s.triangle_count, s.triangles, NULL),
        SELFCOL_OK);
    selfcol_hierarchy *h = create(m, NULL);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = 0.1 * selfcol_mesh_mean_edge_length(m);
    selfcol_contacts *implicit = NULL, *through = NULL;
    assert_int_equal(selfcol_contacts_create(&implicit, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&through, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(h, implicit, &q), SELFCOL_OK);
    assert_non_null(implicit->implicit_context);
    assert_null(implicit->implicit_context->executor.pool);
    assert_int_equal(implicit->implicit_context->threads, 1);
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    selfcol_context *single = NULL; // one thread: nothing to keep
    assert_int_equal(selfcol_context_create(&single, &co), SELFCOL_OK);
    assert_null(single->executor.pool);
    selfcol_context_destroy(single);
    co.threads = 4;
    selfcol_context *context = NULL;
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
    assert_non_null(context->executor.pool);
    assert_int_equal(selfcol_pool__threads(context->executor.pool), 0); // none until needed
    for (int round = 0; round < 3; ++round) {
        assert_int_equal(selfcol_context_self_collide(context, h, through, &q), SELFCOL_OK);
        assert_int_equal(selfcol_pool__threads(context->executor.pool), 3); // kept, not added
    }
    assert_true(selfcol_contacts_count(implicit) > 0);
    assert_int_equal(selfcol_contacts_count(through), selfcol_contacts_count(implicit));
    assert_memory_equal(through->records.items, implicit->records.items,
                        selfcol_contacts_count(implicit) * sizeof(selfcol_contact));
    selfcol_context_destroy(context);
    selfcol_contacts_destroy(through);
    selfcol_contacts_destroy(implicit);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    fixture_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_only_query_contexts_keep_their_threads),
        cmocka_unit_test(test_refit_threads_give_the_nodes_of_one_thread),
        cmocka_unit_test(test_refit_plan_bounds_and_allocation_failure),
        cmocka_unit_test(test_sort_threads_give_the_order_of_one_thread),
        cmocka_unit_test(test_pool_runs_every_worker_of_every_stage),
        cmocka_unit_test(test_pool_allocation_failure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
