// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Query contexts (include/selfcol/context.h): a context's queries give the
// records and counters of the calls without one, byte for byte, for every
// thread count and every scheduler a caller may plug in (one that runs the
// items inline in reverse order, one that defers them to finish_task, and a
// pool of POSIX threads that splits them into ranges); one context serves
// several hierarchies and contact sets in turn; a steady state allocates
// nothing; allocation failures give SELFCOL_ENOMEM and an empty result;
// options are checked. Run under ThreadSanitizer in CI (the pool).
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "fixtures.h"
#include "test_alloc.h"
#include "world.h"

typedef struct built {
    fixture shape;
    selfcol_mesh *mesh;
    selfcol_hierarchy *hierarchy;
} built;

// A crumpled sheet: folds that touch and cross, every contact kind.
static built crumpled(unsigned n, unsigned seed) {
    built b;
    memset(&b, 0, sizeof b);
    assert_int_equal(fixture_crumpled(&b.shape, n, n, seed, 5.0), 0);
    assert_int_equal(selfcol_mesh_create(&b.mesh, b.shape.vertex_count, b.shape.positions,
                                         b.shape.triangle_count, b.shape.triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&b.hierarchy, b.mesh, NULL), SELFCOL_OK);
    return b;
}

static void release(built *b) {
    selfcol_hierarchy_destroy(b->hierarchy);
    selfcol_mesh_destroy(b->mesh);
    fixture_free(&b->shape);
}

static selfcol_query_options options(uint32_t method, double distance) {
    selfcol_query_options o;
    selfcol_query_options_init(&o, SELFCOL_QUERY_OPTIONS_VERSION);
    o.method = method;
    o.distance = distance;
    return o;
}

static void assert_same_records(const selfcol_contacts *x, const selfcol_contacts *y) {
    const selfcol_contact *a = NULL, *b = NULL;
    size_t n = 0, m = 0;
    assert_int_equal(selfcol_contacts_data(x, &a, &n), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_data(y, &b, &m), SELFCOL_OK);
    assert_int_equal(n, m);
    if (n > 0)
        assert_memory_equal(a, b, n * sizeof *a);
}

// Same records, same counters.
static void assert_same(const selfcol_contacts *x, const selfcol_contacts *y) {
    assert_same_records(x, y);
    selfcol_query_stats sx = query_counters(x), sy = query_counters(y);
    assert_memory_equal(&sx, &sy, sizeof sx);
}

// ---------------------------------------------------------------------------
// Schedulers a caller could give

// Runs every item at once, last range first, in ranges of min_range.
static void *inline_reversed(selfcol_task_fn *task, uint32_t item_count, uint32_t min_range,
                             void *task_context, void *user_context) {
    int *tasks = user_context;
    ++*tasks;
    uint32_t step = min_range > 0 ? min_range : 1u;
    for (uint32_t end = item_count; end > 0;) {
        uint32_t begin = end > step ? end - step : 0;
        task(begin, end, 7u, task_context);
        end = begin;
    }
    return NULL;
}

static void never_finish(void *user_task, void *user_context) {
    (void)user_task;
    (void)user_context;
    fail_msg("finish_task called after enqueue_task returned NULL");
}

// Holds the task until finish_task, which runs it whole.
typedef struct deferred {
    selfcol_task_fn *task;
    uint32_t item_count;
    void *task_context;
    int pending, finished;
} deferred;

static void *defer(selfcol_task_fn *task, uint32_t item_count, uint32_t min_range,
                   void *task_context, void *user_context) {
    (void)min_range;
    deferred *d = user_context;
    assert_int_equal(d->pending, 0);
    d->task = task;
    d->item_count = item_count;
    d->task_context = task_context;
    d->pending = 1;
    return d;
}

static void finish_deferred(void *user_task, void *user_context) {
    deferred *d = user_context;
    assert_ptr_equal(user_task, d);
    assert_int_equal(d->pending, 1);
    d->task(0, d->item_count, 0u, d->task_context);
    d->pending = 0;
    d->finished++;
}

// A pool of threads started for each task: item ranges of 2 go to 3
// threads, which take them from a shared counter (a job system's shape).
enum { POOL_THREADS = 3 };
typedef struct pool_task {
    selfcol_task_fn *task;
    uint32_t item_count;
    void *task_context;
    uint32_t next; // atomic
    unsigned tasks;
    pthread_t thread[POOL_THREADS];
    unsigned index[POOL_THREADS];
} pool_task;

typedef struct pool_run {
    pool_task *job;
    uint32_t worker;
} pool_run;

static pool_run pool_runs[POOL_THREADS];

static void *pool_main(void *arg) {
    pool_run *r = arg;
    pool_task *job = r->job;
    for (;;) {
        uint32_t begin = __atomic_fetch_add(&job->next, 2u, __ATOMIC_ACQ_REL);
        if (begin >= job->item_count)
            return NULL;
        uint32_t end = begin + 2u < job->item_count ? begin + 2u : job->item_count;
        job->task(begin, end, r->worker, job->task_context);
    }
}

static void *pool_enqueue(selfcol_task_fn *task, uint32_t item_count, uint32_t min_range,
                          void *task_context, void *user_context) {
    (void)min_range;
    pool_task *job = user_context;
    job->tasks++;
    job->task = task;
    job->item_count = item_count;
    job->task_context = task_context;
    job->next = 0;
    for (unsigned t = 0; t < POOL_THREADS; ++t) {
        pool_runs[t] = (pool_run){job, t};
        assert_int_equal(pthread_create(&job->thread[t], NULL, pool_main, &pool_runs[t]), 0);
    }
    return job;
}

static void pool_finish(void *user_task, void *user_context) {
    pool_task *job = user_context;
    assert_ptr_equal(user_task, job);
    for (unsigned t = 0; t < POOL_THREADS; ++t)
        pthread_join(job->thread[t], NULL);
}

static selfcol_context *make_context(unsigned threads, selfcol_enqueue_task_fn *enqueue,
                                     selfcol_finish_task_fn *finish, void *user) {
    selfcol_context_options o;
    assert_int_equal(selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION), SELFCOL_OK);
    o.threads = threads;
    o.enqueue_task = enqueue;
    o.finish_task = finish;
    o.user_context = user;
    selfcol_context *c = NULL;
    assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_OK);
    assert_non_null(c);
    return c;
}

// ---------------------------------------------------------------------------

// Every method, both distances, self and two-mesh: a context's query
// equals the call without one, whatever runs its items.
static void test_every_scheduler_gives_the_records_of_one_thread(void **state) {
    (void)state;
    built a = crumpled(24, 3), b = crumpled(20, 5);
    const double shift[3] = {0.5, 0.2, 0.0};
    // The second sheet over the first: a two-mesh query with contacts.
    selfcol_mesh_destroy(b.mesh);
    selfcol_hierarchy_destroy(b.hierarchy);
    fixture_translate(&b.shape, shift);
    assert_int_equal(selfcol_mesh_create(&b.mesh, b.shape.vertex_count, b.shape.positions,
                                         b.shape.triangle_count, b.shape.triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&b.hierarchy, b.mesh, NULL), SELFCOL_OK);

    int inline_tasks = 0;
    deferred later;
    memset(&later, 0, sizeof later);
    pool_task pool;
    memset(&pool, 0, sizeof pool);
    selfcol_context *contexts[] = {
        make_context(1, NULL, NULL, NULL),
        make_context(4, NULL, NULL, NULL),
        make_context(5, inline_reversed, never_finish, &inline_tasks),
        make_context(6, defer, finish_deferred, &later),
        make_context(8, pool_enqueue, pool_finish, &pool),
    };
    const size_t context_count = sizeof contexts / sizeof *contexts;
    const uint32_t methods[] = {SELFCOL_METHOD_BVH, SELFCOL_METHOD_EXACT,
                                SELFCOL_METHOD_EXHAUSTIVE};
    const double edge = selfcol_mesh_mean_edge_length(a.mesh);
    const double distances[] = {0.0, 0.1 * edge};
    selfcol_contacts *reference = NULL, *got = NULL;
    assert_int_equal(selfcol_contacts_create(&reference, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&got, NULL), SELFCOL_OK);
    size_t records = 0;
    for (size_t m = 0; m < sizeof methods / sizeof *methods; ++m)
        for (int k = 0; k < 2; ++k)
            for (int two = 0; two < 2; ++two) {
                selfcol_query_options o = options(methods[m], distances[k]);
                if (two)
                    assert_int_equal(
                        selfcol_hierarchy_collide(a.hierarchy, b.hierarchy, reference, &o),
                        SELFCOL_OK);
                else
                    assert_int_equal(selfcol_hierarchy_self_collide(a.hierarchy, reference, &o),
                                     SELFCOL_OK);
                records += selfcol_contacts_count(reference);
                for (size_t c = 0; c < context_count; ++c) {
                    if (two)
                        assert_int_equal(
                            selfcol_context_collide(contexts[c], a.hierarchy, b.hierarchy, got, &o),
                            SELFCOL_OK);
                    else
                        assert_int_equal(
                            selfcol_context_self_collide(contexts[c], a.hierarchy, got, &o),
                            SELFCOL_OK);
                    assert_same(reference, got);
                }
            }
    assert_true(records > 1000);   // contacts were found and compared
    assert_true(inline_tasks > 0); // the schedulers ran the threaded stages
    assert_true(later.finished > 0);
    assert_true(pool.tasks > 0);
    assert_int_equal(later.pending, 0);
    for (size_t c = 0; c < context_count; ++c) {
        assert_true(selfcol_context_byte_count(contexts[c]) > 0);
        selfcol_context_destroy(contexts[c]);
    }
    selfcol_contacts_destroy(reference);
    selfcol_contacts_destroy(got);
    release(&a);
    release(&b);
}

// One context, several hierarchies and contact sets in turn: each answer is
// its own (the per-leaf frames of one hierarchy never serve another).
static void test_one_context_serves_many_hierarchies(void **state) {
    (void)state;
    built shapes[3] = {crumpled(16, 1), crumpled(22, 2), crumpled(16, 9)};
    selfcol_context *context = make_context(3, NULL, NULL, NULL);
    selfcol_contacts *alone = NULL, *shared[3] = {NULL, NULL, NULL};
    assert_int_equal(selfcol_contacts_create(&alone, NULL), SELFCOL_OK);
    for (int i = 0; i < 3; ++i)
        assert_int_equal(selfcol_contacts_create(&shared[i], NULL), SELFCOL_OK);
    for (int round = 0; round < 2; ++round)
        for (int i = 0; i < 3; ++i) {
            const selfcol_query_options o =
                options(SELFCOL_METHOD_EXACT, 0.1 * selfcol_mesh_mean_edge_length(shapes[i].mesh));
            assert_int_equal(
                selfcol_context_self_collide(context, shapes[i].hierarchy, shared[i], &o),
                SELFCOL_OK);
            assert_int_equal(selfcol_hierarchy_self_collide(shapes[i].hierarchy, alone, &o),
                             SELFCOL_OK);
            assert_same(alone, shared[i]);
            assert_true(selfcol_contacts_count(shared[i]) > 0);
        }
    // A result keeps its records after the context served another query.
    const selfcol_contact *first = NULL;
    size_t n = 0;
    assert_int_equal(selfcol_contacts_data(shared[0], &first, &n), SELFCOL_OK);
    assert_true(n > 0);
    for (int i = 0; i < 3; ++i)
        selfcol_contacts_destroy(shared[i]);
    selfcol_contacts_destroy(alone);
    selfcol_context_destroy(context);
    for (int i = 0; i < 3; ++i)
        release(&shapes[i]);
}

// After a first frame, queries through a context allocate nothing (one
// thread: the test allocator counts without atomics), neither in the
// context nor in the result; all is freed at the end.
static void test_steady_state_allocates_nothing(void **state) {
    (void)state;
    built s = crumpled(24, 4);
    test_allocator_state context_alloc, result_alloc;
    memset(&context_alloc, 0, sizeof context_alloc);
    memset(&result_alloc, 0, sizeof result_alloc);
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.allocator = test_allocator(&context_alloc);
    selfcol_context *context = NULL;
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
    selfcol_contacts_options ro;
    selfcol_contacts_options_init(&ro, SELFCOL_CONTACTS_OPTIONS_VERSION);
    ro.allocator = test_allocator(&result_alloc);
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_contacts_create(&c, &ro), SELFCOL_OK);
    const selfcol_query_options o =
        options(SELFCOL_METHOD_EXACT, 0.1 * selfcol_mesh_mean_edge_length(s.mesh));
    assert_int_equal(selfcol_context_self_collide(context, s.hierarchy, c, &o), SELFCOL_OK);
    assert_true(selfcol_contacts_count(c) > 0);
    const long context_calls = context_alloc.calls, result_calls = result_alloc.calls;
    assert_true(context_calls > 0);
    for (int frame = 0; frame < 3; ++frame)
        assert_int_equal(selfcol_context_self_collide(context, s.hierarchy, c, &o), SELFCOL_OK);
    assert_int_equal(context_alloc.calls, context_calls);
    assert_int_equal(result_alloc.calls, result_calls);
    // The result holds no working memory: its bytes are its records'.
    assert_true(selfcol_contacts_byte_count(c) <
                selfcol_contacts_count(c) * sizeof(selfcol_contact) * 4 + 4096);
    selfcol_contacts_destroy(c);
    selfcol_context_destroy(context);
    assert_int_equal(context_alloc.live, 0);
    assert_int_equal(result_alloc.live, 0);
    assert_int_equal(context_alloc.misaligned, 0);
    release(&s);
}

// Each allocation of a first query fails in turn: SELFCOL_ENOMEM, an empty
// result, nothing leaked, and the next query succeeds with the same records.
static void test_allocation_failures(void **state) {
    (void)state;
    built s = crumpled(16, 6);
    const selfcol_query_options o =
        options(SELFCOL_METHOD_EXACT, 0.1 * selfcol_mesh_mean_edge_length(s.mesh));
    selfcol_contacts *reference = NULL;
    assert_int_equal(selfcol_contacts_create(&reference, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(s.hierarchy, reference, &o), SELFCOL_OK);
    int failures = 0;
    for (long fail = 1;; ++fail) {
        test_allocator_state alloc;
        memset(&alloc, 0, sizeof alloc);
        selfcol_context_options co;
        selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
        co.allocator = test_allocator(&alloc);
        selfcol_context *context = NULL;
        assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
        selfcol_contacts *c = NULL;
        assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
        alloc.fail_at = alloc.calls + fail;
        int status = selfcol_context_self_collide(context, s.hierarchy, c, &o);
        const int failed = alloc.calls >= alloc.fail_at;
        alloc.fail_at = 0;
        if (status == SELFCOL_OK) {
            // A contour proof without memory refuses (contour.h) and the
            // traversal goes deeper: the same records, other counters.
            if (failed) {
                assert_same_records(reference, c);
                selfcol_contacts_destroy(c);
                selfcol_context_destroy(context);
                assert_int_equal(alloc.live, 0);
                continue;
            }
            assert_same(reference, c);
            selfcol_contacts_destroy(c);
            selfcol_context_destroy(context);
            assert_int_equal(alloc.live, 0);
            break;
        }
        assert_int_equal(status, SELFCOL_ENOMEM);
        assert_int_equal(selfcol_contacts_count(c), 0);
        ++failures;
        assert_int_equal(selfcol_context_self_collide(context, s.hierarchy, c, &o), SELFCOL_OK);
        assert_same(reference, c);
        selfcol_contacts_destroy(c);
        selfcol_context_destroy(context);
        assert_int_equal(alloc.live, 0);
    }
    assert_true(failures >= 3); // frames, stamps, stack at least
    selfcol_contacts_destroy(reference);
    release(&s);
}

static void test_options_are_checked(void **state) {
    (void)state;
    selfcol_context_options o;
    assert_int_equal(selfcol_context_options_init(NULL, 1), SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_options_init(&o, 0), SELFCOL_EVERSION);
    assert_int_equal(selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION + 1),
                     SELFCOL_EVERSION);
    assert_int_equal(selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION), SELFCOL_OK);
    assert_int_equal(o.threads, 1u);
    assert_null(o.enqueue_task);
    selfcol_context *c = (selfcol_context *)&o; // must be reset to NULL on failure
    assert_int_equal(selfcol_context_create(NULL, &o), SELFCOL_EINVAL);
    const unsigned bad_threads[] = {0u, SELFCOL_MAX_THREADS + 1u};
    for (int i = 0; i < 2; ++i) {
        o.threads = bad_threads[i];
        assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_EINVAL);
        assert_null(c);
    }
    o.threads = SELFCOL_MAX_THREADS;
    o.enqueue_task = inline_reversed; // without finish_task
    assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_EINVAL);
    o.enqueue_task = NULL;
    o.finish_task = never_finish; // without enqueue_task
    assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_EINVAL);
    o.finish_task = NULL;
    o.version = SELFCOL_CONTEXT_OPTIONS_VERSION + 1;
    assert_int_equal(selfcol_context_create(&c, &o), SELFCOL_EVERSION);
    assert_int_equal(selfcol_context_create(&c, NULL), SELFCOL_OK); // defaults
    assert_int_equal(selfcol_context_byte_count(NULL), 0u);
    selfcol_context_destroy(NULL);

    // The queries' own checks still hold, and a context is required.
    built s = crumpled(8, 1);
    selfcol_contacts *contacts = NULL;
    assert_int_equal(selfcol_contacts_create(&contacts, NULL), SELFCOL_OK);
    selfcol_query_options q = options(SELFCOL_METHOD_EXACT, 0.01);
    assert_int_equal(selfcol_context_self_collide(NULL, s.hierarchy, contacts, &q), SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_self_collide(c, NULL, contacts, &q), SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_self_collide(c, s.hierarchy, NULL, &q), SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_collide(c, s.hierarchy, s.hierarchy, contacts, &q),
                     SELFCOL_EINVAL); // one mesh: that is a self query
    q.distance = -1.0;
    assert_int_equal(selfcol_context_self_collide(c, s.hierarchy, contacts, &q), SELFCOL_EINVAL);
    q.distance = 0.01;
    // Moved positions without a refit: stale.
    double *moved = malloc(3 * s.shape.vertex_count * sizeof *moved);
    assert_non_null(moved);
    memcpy(moved, s.shape.positions, 3 * s.shape.vertex_count * sizeof *moved);
    moved[0] += 1e-3;
    assert_int_equal(selfcol_mesh_set_positions(s.mesh, moved, s.shape.vertex_count), SELFCOL_OK);
    assert_int_equal(selfcol_context_self_collide(c, s.hierarchy, contacts, &q), SELFCOL_ESTALE);
    free(moved);
    selfcol_contacts_destroy(contacts);
    selfcol_context_destroy(c);
    release(&s);
}

// Continuous queries through a context: ALL's root searches on the
// context's workers and scheduler give the hits of one thread, self and
// two-mesh, and EARLIEST its fraction.
static void assert_same_hits(const selfcol_sweep *x, const selfcol_sweep *y) {
    const selfcol_sweep_hit *a = NULL, *b = NULL;
    size_t n = 0, m = 0;
    assert_int_equal(selfcol_sweep_hits(x, &a, &n), SELFCOL_OK);
    assert_int_equal(selfcol_sweep_hits(y, &b, &m), SELFCOL_OK);
    assert_int_equal(n, m);
    if (n > 0)
        assert_memory_equal(a, b, n * sizeof *a);
    selfcol_sweep_query_stats sx, sy;
    memset(&sx, 0, sizeof sx);
    memset(&sy, 0, sizeof sy);
    sx.version = sy.version = SELFCOL_SWEEP_STATS_VERSION;
    assert_int_equal(selfcol_sweep_stats(x, &sx), SELFCOL_OK);
    assert_int_equal(selfcol_sweep_stats(y, &sy), SELFCOL_OK);
    sx.broad_seconds = sx.narrow_seconds = sx.total_seconds = 0.0;
    sy.broad_seconds = sy.narrow_seconds = sy.total_seconds = 0.0;
    sx.cull_seconds = sy.cull_seconds = 0.0;
    assert_memory_equal(&sx, &sy, sizeof sx);
}

static void test_sweeps_through_a_context(void **state) {
    (void)state;
    // A sheet crumpling from one amplitude to a stronger one over the step,
    // and a second sheet moving through it.
    fixture from; // the start of the step; it ends at crumpled()'s amplitude
    memset(&from, 0, sizeof from);
    assert_int_equal(fixture_crumpled(&from, 20, 20, 8, 2.0), 0);
    built a = crumpled(20, 8), b = crumpled(14, 2);
    const double shift[3] = {0.3, 0.1, -3.0};
    const size_t Vb = b.shape.vertex_count;
    double *b_start = malloc(3 * Vb * sizeof *b_start);
    assert_non_null(b_start);
    for (size_t i = 0; i < 3 * Vb; ++i)
        b_start[i] = b.shape.positions[i] + shift[i % 3];
    int inline_tasks = 0;
    pool_task pool;
    memset(&pool, 0, sizeof pool);
    selfcol_context *contexts[] = {make_context(3, NULL, NULL, NULL),
                                   make_context(5, inline_reversed, never_finish, &inline_tasks),
                                   make_context(8, pool_enqueue, pool_finish, &pool)};
    selfcol_sweep *reference = NULL, *got = NULL;
    assert_int_equal(selfcol_sweep_create(&reference, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_sweep_create(&got, NULL), SELFCOL_OK);
    size_t hits = 0;
    for (int mode = 0; mode < 2; ++mode)
        for (int two = 0; two < 2; ++two) {
            selfcol_sweep_options o;
            selfcol_sweep_options_init(&o, SELFCOL_SWEEP_OPTIONS_VERSION);
            o.mode = mode ? SELFCOL_SWEEP_EARLIEST : SELFCOL_SWEEP_ALL;
            o.separation = 0.01;
            if (two)
                assert_int_equal(selfcol_hierarchy_sweep(a.hierarchy, from.positions, b.hierarchy,
                                                         b_start, reference, &o),
                                 SELFCOL_OK);
            else
                assert_int_equal(
                    selfcol_hierarchy_self_sweep(a.hierarchy, from.positions, reference, &o),
                    SELFCOL_OK);
            const selfcol_sweep_hit *h = NULL;
            size_t n = 0;
            assert_int_equal(selfcol_sweep_hits(reference, &h, &n), SELFCOL_OK);
            hits += n;
            for (size_t c = 0; c < sizeof contexts / sizeof *contexts; ++c) {
                if (two)
                    assert_int_equal(selfcol_context_sweep(contexts[c], a.hierarchy, from.positions,
                                                           b.hierarchy, b_start, got, &o),
                                     SELFCOL_OK);
                else
                    assert_int_equal(selfcol_context_self_sweep(contexts[c], a.hierarchy,
                                                                from.positions, got, &o),
                                     SELFCOL_OK);
                assert_same_hits(reference, got);
            }
        }
    assert_true(hits > 100);       // hits were found and compared
    assert_true(inline_tasks > 0); // ALL's root searches ran on the schedulers
    assert_true(pool.tasks > 0);
    selfcol_sweep_options o;
    selfcol_sweep_options_init(&o, SELFCOL_SWEEP_OPTIONS_VERSION);
    assert_int_equal(selfcol_context_self_sweep(NULL, a.hierarchy, from.positions, got, &o),
                     SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_sweep(contexts[0], a.hierarchy, from.positions, a.hierarchy,
                                           from.positions, got, &o),
                     SELFCOL_EINVAL);
    for (size_t c = 0; c < sizeof contexts / sizeof *contexts; ++c)
        selfcol_context_destroy(contexts[c]);
    selfcol_sweep_destroy(reference);
    selfcol_sweep_destroy(got);
    free(b_start);
    fixture_free(&from);
    release(&a);
    release(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_scheduler_gives_the_records_of_one_thread),
        cmocka_unit_test(test_one_context_serves_many_hierarchies),
        cmocka_unit_test(test_steady_state_allocates_nothing),
        cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_sweeps_through_a_context),
        cmocka_unit_test(test_options_are_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
