// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Calls on a context of several threads (context.h: since 0.4 the one
// place where threads are said) against the same calls without one (the
// calling thread). Queries: the records and the statistics apart from
// times must be those of one thread, byte for byte, for every hierarchy
// method, self and two-mesh, at d = 0 and at the standard d; an allocation
// failure inside a worker must give SELFCOL_ENOMEM, an empty set and no
// leak; context thread counts are bounded, and 0.3's option layouts (with
// threads) are refused by name; queries on one hierarchy from several
// threads at once hold to the README's contract. Continuous queries give
// the hits of one thread; store updates hold the records, regions and
// counters of one thread; refits on a context give the queries of one
// (their nodes: test_threads_internal).
#define _POSIX_C_SOURCE 200112L // posix_memalign
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <selfcol/selfcol.h>

#include "contact_keys.h"
#include "fixtures.h"
#include "world.h"

typedef struct built {
    selfcol_mesh *mesh;
    selfcol_hierarchy *hierarchy;
} built;

static built build(const fixture *s) {
    built b = {NULL, NULL};
    assert_int_equal(selfcol_mesh_create(&b.mesh, s->vertex_count, s->positions, s->triangle_count,
                                         s->triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&b.hierarchy, b.mesh, NULL), SELFCOL_OK);
    return b;
}

static void release(built *b) {
    selfcol_hierarchy_destroy(b->hierarchy);
    selfcol_mesh_destroy(b->mesh);
}

// A context of `threads` threads whose memory comes from `al` (NULL: malloc);
// NULL for one thread (the calls without a context). NULL and *status set
// when creation fails.
static selfcol_context *context_of(unsigned threads, const selfcol_allocator *al, int *status) {
    *status = SELFCOL_OK;
    if (threads == 1)
        return NULL;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = threads;
    if (al != NULL)
        co.allocator = *al;
    selfcol_context *context = NULL;
    *status = selfcol_context_create(&context, &co);
    return context;
}

// A query on a context of `threads` threads (one: the call without one),
// made for it with `al`'s memory (NULL: malloc).
static int query_with(const built *a, const built *b, selfcol_contacts *c, uint32_t method,
                      double d, unsigned threads, const selfcol_allocator *al) {
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.method = method;
    q.distance = d;
    int status;
    selfcol_context *context = context_of(threads, al, &status);
    if (status != SELFCOL_OK)
        return status;
    if (context == NULL)
        status = b == NULL ? selfcol_hierarchy_self_collide(a->hierarchy, c, &q)
                           : selfcol_hierarchy_collide(a->hierarchy, b->hierarchy, c, &q);
    else
        status = b == NULL ? selfcol_context_self_collide(context, a->hierarchy, c, &q)
                           : selfcol_context_collide(context, a->hierarchy, b->hierarchy, c, &q);
    selfcol_context_destroy(context);
    return status;
}

static int query(const built *a, const built *b, selfcol_contacts *c, uint32_t method, double d,
                 unsigned threads) {
    return query_with(a, b, c, method, d, threads, NULL);
}

// Every method and thread count against one thread of the same method, and
// EXACT on 3 threads against the exhaustive search.
static void check_scene(const built *a, const built *b, const char *name) {
    const uint32_t methods[] = {SELFCOL_METHOD_BVH, SELFCOL_METHOD_SEED, SELFCOL_METHOD_CONE,
                                SELFCOL_METHOD_EXACT};
    const unsigned threads[] = {2, 3, 8};
    double edge = selfcol_mesh_mean_edge_length(a->mesh);
    const double distances[] = {0.0, 0.1 * edge};
    selfcol_contacts *one = NULL, *many = NULL, *reference = NULL;
    assert_int_equal(selfcol_contacts_create(&one, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&many, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&reference, NULL), SELFCOL_OK);
    size_t contacts_seen = 0;
    for (int di = 0; di < 2; ++di) {
        assert_int_equal(query(a, b, reference, SELFCOL_METHOD_EXHAUSTIVE, distances[di], 1),
                         SELFCOL_OK);
        for (int mi = 0; mi < 4; ++mi) {
            assert_int_equal(query(a, b, one, methods[mi], distances[di], 1), SELFCOL_OK);
            selfcol_query_stats st1 = query_counters(one);
            const selfcol_contact *x1;
            size_t n1;
            selfcol_contacts_data(one, &x1, &n1);
            contacts_seen += n1;
            for (int ti = 0; ti < 3; ++ti) {
                // Twice, so the second run reuses the workers' buffers.
                for (int repeat = 0; repeat < 2; ++repeat) {
                    assert_int_equal(query(a, b, many, methods[mi], distances[di], threads[ti]),
                                     SELFCOL_OK);
                    const selfcol_contact *xn;
                    size_t nn;
                    selfcol_contacts_data(many, &xn, &nn);
                    if (nn != n1 || (n1 > 0 && memcmp(x1, xn, n1 * sizeof *x1) != 0))
                        fail_msg("%s: method %u, d %g, %u threads: %zu records, one thread %zu "
                                 "(or different content)",
                                 name, methods[mi], distances[di], threads[ti], nn, n1);
                    selfcol_query_stats stn = query_counters(many);
                    if (memcmp(&st1, &stn, sizeof st1) != 0)
                        fail_msg("%s: method %u, d %g, %u threads: statistics differ", name,
                                 methods[mi], distances[di], threads[ti]);
                }
            }
            if (methods[mi] == SELFCOL_METHOD_EXACT || methods[mi] == SELFCOL_METHOD_BVH) {
                assert_int_equal(query(a, b, many, methods[mi], distances[di], 3), SELFCOL_OK);
                size_t ne, nr;
                contact_key *ke = contact_keys_of(many, &ne);
                contact_key *kr = contact_keys_of(reference, &nr);
                if (!contact_keys_equal(kr, nr, ke, ne))
                    fail_msg("%s: method %u on 3 threads differs from EXHAUSTIVE", name,
                             methods[mi]);
                free(ke);
                free(kr);
            }
        }
    }
    if (contacts_seen == 0)
        fail_msg("%s: no contacts (the scene must touch)", name);
    selfcol_contacts_destroy(one);
    selfcol_contacts_destroy(many);
    selfcol_contacts_destroy(reference);
}

static void test_threads_give_the_records_and_counters_of_one_thread(void **state) {
    (void)state;
    fixture s;
    // A crumpled sheet (many small folds), a z-fold, a one-sided band
    // pressed until it crosses itself.
    assert_int_equal(fixture_crumpled(&s, 40, 40, 7, 5.0), 0);
    built b = build(&s);
    check_scene(&b, NULL, "crumpled 40x40");
    release(&b);
    fixture_free(&s);
    assert_int_equal(fixture_zfold(&s, 24, 6, 0.05, 4, 0.0), 0);
    b = build(&s);
    check_scene(&b, NULL, "z-fold");
    release(&b);
    fixture_free(&s);
    assert_int_equal(fixture_moebius(&s, 60, 6, 6.0, 2.0, 3, 0.08), 0);
    b = build(&s);
    check_scene(&b, NULL, "squashed moebius band");
    release(&b);
    fixture_free(&s);
    // Two crossing sheets.
    fixture sa, sb;
    assert_int_equal(fixture_sheet_pair(&sa, &sb, 24, 5, 0.3, 0.0), 0);
    built ba = build(&sa), bb = build(&sb);
    check_scene(&ba, &bb, "sheet pair");
    release(&ba);
    release(&bb);
    fixture_free(&sa);
    fixture_free(&sb);
}

// An allocator that fails at its Nth call and counts live blocks, made safe
// for the workers' calls with a mutex.
typedef struct locked_allocator {
    pthread_mutex_t lock;
    long fail_at, calls, live;
} locked_allocator;

static void *locked_alloc(void *user, size_t size, size_t alignment) {
    locked_allocator *a = user;
    pthread_mutex_lock(&a->lock);
    long call = ++a->calls;
    int fail = a->fail_at != 0 && call == a->fail_at;
    if (!fail)
        a->live++;
    pthread_mutex_unlock(&a->lock);
    if (fail)
        return NULL;
    void *p = NULL;
    if (posix_memalign(&p, alignment < sizeof(void *) ? sizeof(void *) : alignment, size) != 0)
        fail_msg("posix_memalign");
    return p;
}

static void locked_free(void *user, void *ptr, size_t size) {
    (void)size;
    locked_allocator *a = user;
    if (ptr == NULL)
        return;
    free(ptr);
    pthread_mutex_lock(&a->lock);
    a->live--;
    pthread_mutex_unlock(&a->lock);
}

static void test_threads_allocation_failure_in_a_worker(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 30, 30, 3, 5.0), 0);
    built b = build(&s);
    double d = 0.1 * selfcol_mesh_mean_edge_length(b.mesh);
    size_t expected;
    {
        selfcol_contacts *c = NULL;
        assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
        assert_int_equal(query(&b, NULL, c, SELFCOL_METHOD_EXHAUSTIVE, d, 1), SELFCOL_OK);
        expected = selfcol_contacts_count(c);
        selfcol_contacts_destroy(c);
    }
    assert_true(expected > 0);
    int failures = 0;
    for (long fail_at = 1;; ++fail_at) {
        locked_allocator a;
        pthread_mutex_init(&a.lock, NULL);
        a.fail_at = fail_at;
        a.calls = a.live = 0;
        selfcol_contacts_options co;
        selfcol_contacts_options_init(&co, SELFCOL_CONTACTS_OPTIONS_VERSION);
        co.allocator.alloc = locked_alloc;
        co.allocator.free = locked_free;
        co.allocator.user = &a;
        selfcol_contacts *c = NULL;
        int status = selfcol_contacts_create(&c, &co);
        // The context's workers' buffers and the records both come from a.
        if (status == SELFCOL_OK)
            status = query_with(&b, NULL, c, SELFCOL_METHOD_EXACT, d, 4, &co.allocator);
        if (status == SELFCOL_OK) {
            assert_int_equal(selfcol_contacts_count(c), expected);
            selfcol_contacts_destroy(c);
            assert_int_equal(a.live, 0);
            pthread_mutex_destroy(&a.lock);
            if (a.calls < fail_at)
                break; // the failure point lies past the last allocation
            continue;
        }
        assert_int_equal(status, SELFCOL_ENOMEM);
        failures++;
        if (c != NULL) {
            assert_int_equal(selfcol_contacts_count(c), 0);
            // The same handle works once memory is back.
            a.fail_at = 0;
            assert_int_equal(query_with(&b, NULL, c, SELFCOL_METHOD_EXACT, d, 4, &co.allocator),
                             SELFCOL_OK);
            assert_int_equal(selfcol_contacts_count(c), expected);
            selfcol_contacts_destroy(c);
        }
        assert_int_equal(a.live, 0);
        pthread_mutex_destroy(&a.lock);
    }
    assert_true(failures > 5); // the query allocates in the workers too
    release(&b);
    fixture_free(&s);
}

static void test_threads_option_bounds_and_old_structs(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_hairpin(&s, 8, 0.01), 0);
    built b = build(&s);
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    selfcol_context_options co;
    assert_int_equal(selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION),
                     SELFCOL_OK);
    assert_int_equal(co.threads, 1); // the documented default
    selfcol_context *context = (selfcol_context *)&co;
    co.threads = 0;
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_EINVAL);
    assert_null(context);
    co.threads = SELFCOL_MAX_THREADS + 1;
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_EINVAL);
    assert_null(context);
    co.threads = SELFCOL_MAX_THREADS; // more threads than work: still right
    assert_int_equal(selfcol_context_create(&context, &co), SELFCOL_OK);
    selfcol_query_options q;
    assert_int_equal(selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION), SELFCOL_OK);
    q.distance = 0.02;
    assert_int_equal(selfcol_hierarchy_self_collide(b.hierarchy, c, &q), SELFCOL_OK);
    const size_t n = selfcol_contacts_count(c);
    assert_true(n > 0);
    assert_int_equal(selfcol_context_self_collide(context, b.hierarchy, c, &q), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_count(c), n);
    selfcol_context_destroy(context);
    // 0.3's layouts, which had `threads` (query options version 2) or ended
    // where it began (version 1), are refused by name, by init and by the
    // calls: since 0.4 a thread count is the context's.
    for (unsigned version = 1; version < SELFCOL_QUERY_OPTIONS_VERSION; ++version) {
        assert_int_equal(selfcol_query_options_init(&q, version), SELFCOL_EVERSION);
        q.version = version;
        assert_int_equal(selfcol_hierarchy_self_collide(b.hierarchy, c, &q), SELFCOL_EVERSION);
        selfcol_options_problem p;
        memset(&p, 0, sizeof p);
        p.version = SELFCOL_OPTIONS_PROBLEM_VERSION;
        assert_int_equal(selfcol_query_options_check(&q, &p), SELFCOL_EVERSION);
        assert_string_equal(p.field, "version");
        assert_non_null(strstr(p.message, "older layout"));
    }
    selfcol_contacts_destroy(c);
    release(&b);
    fixture_free(&s);
}

// The thread-safety contract (README): queries on one hierarchy from several
// threads at once, each into its own contact set, the mesh left alone; each
// query itself on two threads. Run under ThreadSanitizer in CI.
typedef struct concurrent_query {
    const built *b;
    double distance;
    uint32_t method;
    selfcol_contacts *contacts;
    int status;
} concurrent_query;

static void *run_concurrent(void *arg) {
    concurrent_query *cq = arg;
    for (int repeat = 0; repeat < 3 && cq->status == SELFCOL_OK; ++repeat)
        cq->status = query(cq->b, NULL, cq->contacts, cq->method, cq->distance, 2);
    return NULL;
}

static void test_threads_concurrent_queries_on_one_hierarchy(void **state) {
    (void)state;
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 30, 30, 11, 5.0), 0);
    built b = build(&s);
    double d = 0.1 * selfcol_mesh_mean_edge_length(b.mesh);
    enum { QUERIES = 4 };
    concurrent_query cq[QUERIES];
    pthread_t thread[QUERIES];
    for (int i = 0; i < QUERIES; ++i) {
        cq[i] = (concurrent_query){&b, d, i % 2 ? SELFCOL_METHOD_BVH : SELFCOL_METHOD_EXACT, NULL,
                                   SELFCOL_OK};
        assert_int_equal(selfcol_contacts_create(&cq[i].contacts, NULL), SELFCOL_OK);
    }
    for (int i = 0; i < QUERIES; ++i)
        assert_int_equal(pthread_create(&thread[i], NULL, run_concurrent, &cq[i]), 0);
    for (int i = 0; i < QUERIES; ++i)
        assert_int_equal(pthread_join(thread[i], NULL), 0);
    selfcol_contacts *reference = NULL;
    assert_int_equal(selfcol_contacts_create(&reference, NULL), SELFCOL_OK);
    assert_int_equal(query(&b, NULL, reference, SELFCOL_METHOD_EXHAUSTIVE, d, 1), SELFCOL_OK);
    size_t nr;
    contact_key *kr = contact_keys_of(reference, &nr);
    assert_true(nr > 0);
    for (int i = 0; i < QUERIES; ++i) {
        assert_int_equal(cq[i].status, SELFCOL_OK);
        size_t n;
        contact_key *k = contact_keys_of(cq[i].contacts, &n);
        assert_true(contact_keys_equal(kr, nr, k, n));
        free(k);
        selfcol_contacts_destroy(cq[i].contacts);
    }
    free(kr);
    selfcol_contacts_destroy(reference);
    release(&b);
    fixture_free(&s);
}

// Continuous queries (sweep.h) on a context: the broad phase and the root
// searches of ALL shared among 2, 3 and 8 threads give the hits and
// counters of one thread, on a crumple
// whose folds deepen fast (thousands of candidates, hundreds of hits).
static void test_threads_sweep_gives_the_hits_of_one_thread(void **state) {
    (void)state;
    fixture from, to;
    assert_int_equal(fixture_crumpled(&from, 24, 24, 5, 2.0), 0);
    assert_int_equal(fixture_crumpled(&to, 24, 24, 5, 4.5), 0);
    selfcol_mesh *m;
    selfcol_hierarchy *h;
    assert_int_equal(selfcol_mesh_create(&m, to.vertex_count, to.positions, to.triangle_count,
                                         to.triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    selfcol_sweep *one, *many;
    assert_int_equal(selfcol_sweep_create(&one, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_sweep_create(&many, NULL), SELFCOL_OK);
    selfcol_sweep_options o;
    selfcol_sweep_options_init(&o, SELFCOL_SWEEP_OPTIONS_VERSION);
    assert_int_equal(selfcol_hierarchy_self_sweep(h, from.positions, one, &o), SELFCOL_OK);
    const selfcol_sweep_hit *h1, *hn;
    size_t n1, nn;
    assert_int_equal(selfcol_sweep_hits(one, &h1, &n1), SELFCOL_OK);
    assert_true(n1 > 100);
    selfcol_sweep_query_stats s1, sn;
    s1.version = sn.version = SELFCOL_SWEEP_STATS_VERSION;
    selfcol_sweep_stats(one, &s1);
    const unsigned counts[3] = {2, 3, 8};
    for (int k = 0; k < 3; ++k) {
        int status;
        selfcol_context *context = context_of(counts[k], NULL, &status);
        assert_int_equal(status, SELFCOL_OK);
        assert_int_equal(selfcol_context_self_sweep(context, h, from.positions, many, &o),
                         SELFCOL_OK);
        selfcol_context_destroy(context);
        assert_int_equal(selfcol_sweep_hits(many, &hn, &nn), SELFCOL_OK);
        assert_int_equal(nn, n1);
        for (size_t i = 0; i < n1; ++i) {
            assert_int_equal(hn[i].kind, h1[i].kind);
            assert_int_equal(hn[i].first, h1[i].first);
            assert_int_equal(hn[i].second, h1[i].second);
            assert_int_equal(hn[i].flags, h1[i].flags);
            assert_true(hn[i].toi == h1[i].toi);
        }
        selfcol_sweep_stats(many, &sn);
        assert_true(sn.free_fraction == s1.free_fraction);
        assert_int_equal(sn.candidates, s1.candidates);
        assert_int_equal(sn.narrow_boxes, s1.narrow_boxes);
        assert_int_equal(sn.hits, s1.hits);
    }
    // 0.3's layouts (with threads) are refused: the threads are the context's.
    assert_int_equal(selfcol_sweep_options_init(&o, 2), SELFCOL_EVERSION);
    o.version = 2;
    assert_int_equal(selfcol_hierarchy_self_sweep(h, from.positions, many, &o), SELFCOL_EVERSION);
    selfcol_sweep_destroy(one);
    selfcol_sweep_destroy(many);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    fixture_free(&from);
    fixture_free(&to);
}

// Store updates on a context (selfcol_context_store_update): every record,
// region and counter (times aside) of a store updated on 2, 3 or 8 threads is that of
// one thread, byte for byte, over a sequence that adds, keeps, drops and
// remembers contacts (the sheet crumples, then eases back: remnants), on
// one mesh and on two. The sheets hold more than 4 chunks' worth of
// contacts, so every thread count splits them differently.
typedef struct store_run {
    selfcol_store *store;
    selfcol_store_contact *records;
    size_t count;
} store_run;

static void copy_store(store_run *r, selfcol_store_region **regions, size_t *region_count,
                       selfcol_store_update_stats *st) {
    r->count = selfcol_store_contact_count(r->store);
    free(r->records);
    r->records = malloc((r->count + 1) * sizeof *r->records);
    assert_non_null(r->records);
    assert_int_equal(selfcol_store_copy_contacts(r->store, 0, r->count, r->records), SELFCOL_OK);
    const selfcol_store_region *reg;
    assert_int_equal(selfcol_store_regions(r->store, &reg, region_count), SELFCOL_OK);
    *regions = malloc((*region_count + 1) * sizeof **regions);
    assert_non_null(*regions);
    if (*region_count > 0)
        memcpy(*regions, reg, *region_count * sizeof *reg);
    memset(st, 0, sizeof *st);
    st->version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    assert_int_equal(selfcol_store_stats(r->store, st), SELFCOL_OK);
    st->seconds = 0.0;
}

static void check_store_threads(const built *a, const built *b, const fixture *crumpled,
                                const fixture *flat, const char *name) {
    const unsigned threads[] = {1, 2, 3, 8};
    enum { RUNS = sizeof threads / sizeof threads[0] };
    store_run run[RUNS];
    selfcol_context *context[RUNS]; // NULL for one thread: the calls without one
    for (int k = 0; k < RUNS; ++k) {
        run[k].records = NULL;
        assert_int_equal(selfcol_store_create(&run[k].store, NULL), SELFCOL_OK);
        int status;
        context[k] = context_of(threads[k], NULL, &status);
        assert_int_equal(status, SELFCOL_OK);
    }
    selfcol_contacts *c = NULL;
    assert_int_equal(selfcol_contacts_create(&c, NULL), SELFCOL_OK);
    const double d = 0.1 * selfcol_mesh_mean_edge_length(a->mesh);
    const double factors[] = {1.0, 1.04, 1.08, 1.0, 0.9, 0.9, 1.1};
    double *positions = malloc(3 * crumpled->vertex_count * sizeof *positions);
    assert_non_null(positions);
    size_t most = 0, remnants = 0, dropped = 0, flipped = 0;
    for (size_t f = 0; f < sizeof factors / sizeof factors[0]; ++f) {
        for (size_t i = 0; i < 3 * crumpled->vertex_count; ++i)
            positions[i] =
                flat->positions[i] + factors[f] * (crumpled->positions[i] - flat->positions[i]);
        const built *moved[2] = {a, b};
        for (int m = 0; m < (b != NULL ? 2 : 1); ++m) {
            if (m == 1) // the second sheet: the first, 1.5 mean edges higher
                for (size_t i = 0; i < crumpled->vertex_count; ++i)
                    positions[3 * i + 2] += 15.0 * d;
            assert_int_equal(
                selfcol_mesh_set_positions(moved[m]->mesh, positions, crumpled->vertex_count),
                SELFCOL_OK);
            assert_int_equal(selfcol_hierarchy_refit(moved[m]->hierarchy), SELFCOL_OK);
        }
        assert_int_equal(query(a, b, c, SELFCOL_METHOD_EXACT, d, 1), SELFCOL_OK);
        selfcol_store_region *reg1 = NULL;
        size_t regions1 = 0;
        selfcol_store_update_stats st1;
        for (int k = 0; k < RUNS; ++k) {
            const selfcol_mesh *second = b != NULL ? b->mesh : NULL;
            assert_int_equal(
                context[k] != NULL
                    ? selfcol_context_store_update(context[k], run[k].store, a->mesh, second, c)
                    : selfcol_store_update(run[k].store, a->mesh, second, c),
                SELFCOL_OK);
            selfcol_store_region *reg;
            size_t regions;
            selfcol_store_update_stats st;
            copy_store(&run[k], &reg, &regions, &st);
            if (k == 0) {
                reg1 = reg;
                regions1 = regions;
                st1 = st;
                most = run[0].count > most ? run[0].count : most;
                remnants += st.remnant;
                dropped += st.dropped;
                flipped += st.flipped;
                continue;
            }
            if (run[k].count != run[0].count ||
                memcmp(run[k].records, run[0].records, run[0].count * sizeof *run[0].records))
                fail_msg("%s, frame %zu: %u threads hold other records than one thread", name, f,
                         threads[k]);
            if (regions != regions1 || memcmp(reg, reg1, regions * sizeof *reg) != 0)
                fail_msg("%s, frame %zu: %u threads give other regions", name, f, threads[k]);
            if (memcmp(&st, &st1, sizeof st) != 0)
                fail_msg("%s, frame %zu: %u threads give other counters", name, f, threads[k]);
            free(reg);
        }
        free(reg1);
    }
    // The sequence did what it is for: more contacts than 4 chunks of the
    // store's smallest (4096), remnants, drops and crossings.
    if (most < 4 * 4096 || remnants == 0 || dropped == 0 || flipped == 0)
        fail_msg("%s: %zu contacts at most, %zu remnants, %zu dropped, %zu flipped", name, most,
                 remnants, dropped, flipped);
    for (int k = 0; k < RUNS; ++k) {
        free(run[k].records);
        selfcol_store_destroy(run[k].store);
        selfcol_context_destroy(context[k]);
    }
    free(positions);
    selfcol_contacts_destroy(c);
}

static void test_threads_store_updates_give_the_store_of_one_thread(void **state) {
    (void)state;
    fixture crumpled, flat;
    assert_int_equal(fixture_crumpled(&crumpled, 70, 70, 2, 5.0), 0);
    assert_int_equal(fixture_grid(&flat, 70, 70, 1.0), 0);
    built a = build(&crumpled), b = build(&crumpled);
    check_store_threads(&a, NULL, &crumpled, &flat, "self");
    check_store_threads(&a, &b, &crumpled, &flat, "two meshes");
    release(&a);
    release(&b);
    fixture_free(&crumpled);
    fixture_free(&flat);
}

// 0.3's store and hierarchy option layouts (with threads) are refused by
// name; a store and a refit on a context of more threads than the work
// shares (one per 4,096 triangles) are right all the same: a refit on 64
// threads gives the queries of one thread's.
static void test_threads_store_and_refit_bounds_and_old_structs(void **state) {
    (void)state;
    selfcol_store_options so;
    selfcol_store *st = NULL;
    for (unsigned version = 1; version < SELFCOL_STORE_OPTIONS_VERSION; ++version) {
        assert_int_equal(selfcol_store_options_init(&so, version), SELFCOL_EVERSION);
        selfcol_store_options_init(&so, SELFCOL_STORE_OPTIONS_VERSION);
        so.version = version;
        assert_int_equal(selfcol_store_create(&st, &so), SELFCOL_EVERSION);
        assert_null(st);
    }
    selfcol_hierarchy_options ho;
    for (unsigned version = 1; version < SELFCOL_HIERARCHY_OPTIONS_VERSION; ++version)
        assert_int_equal(selfcol_hierarchy_options_init(&ho, version), SELFCOL_EVERSION);
    fixture s;
    assert_int_equal(fixture_crumpled(&s, 64, 64, 2, 3.0), 0); // 8,192 triangles: 2 workers
    selfcol_mesh *m = NULL;
    assert_int_equal(
        selfcol_mesh_create(&m, s.vertex_count, s.positions, s.triangle_count, s.triangles, NULL),
        SELFCOL_OK);
    selfcol_hierarchy_options_init(&ho, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    ho.version = 2;
    selfcol_hierarchy *h = NULL;
    assert_int_equal(selfcol_hierarchy_create(&h, m, &ho), SELFCOL_EVERSION);
    assert_null(h);
    assert_int_equal(selfcol_hierarchy_create(&h, m, NULL), SELFCOL_OK);
    selfcol_hierarchy *one = NULL;
    assert_int_equal(selfcol_hierarchy_create(&one, m, NULL), SELFCOL_OK);
    int status;
    selfcol_context *context = context_of(SELFCOL_MAX_THREADS, NULL, &status);
    assert_int_equal(status, SELFCOL_OK);
    fixture next;
    assert_int_equal(fixture_crumpled(&next, 64, 64, 2, 3.5), 0);
    assert_int_equal(selfcol_mesh_set_positions(m, next.positions, next.vertex_count), SELFCOL_OK);
    assert_int_equal(selfcol_context_refit(context, h), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_refit(one), SELFCOL_OK);
    assert_int_equal(selfcol_context_refit(NULL, h), SELFCOL_EINVAL);
    assert_int_equal(selfcol_context_refit(context, NULL), SELFCOL_EINVAL);
    selfcol_contacts *a = NULL, *b = NULL;
    assert_int_equal(selfcol_contacts_create(&a, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&b, NULL), SELFCOL_OK);
    selfcol_query_options q;
    selfcol_query_options_init(&q, SELFCOL_QUERY_OPTIONS_VERSION);
    q.distance = 0.1 * selfcol_mesh_mean_edge_length(m);
    assert_int_equal(selfcol_hierarchy_self_collide(h, a, &q), SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_self_collide(one, b, &q), SELFCOL_OK);
    const selfcol_contact *xa = NULL, *xb = NULL;
    size_t na = 0, nb = 0;
    assert_int_equal(selfcol_contacts_data(a, &xa, &na), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_data(b, &xb, &nb), SELFCOL_OK);
    assert_true(na > 0);
    assert_int_equal(na, nb);
    assert_memory_equal(xa, xb, na * sizeof *xa);
    // A store updated on that context (more threads than chunks) holds what
    // one updated on the calling thread does.
    selfcol_store *s1 = NULL, *s64 = NULL;
    assert_int_equal(selfcol_store_create(&s1, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_store_create(&s64, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_store_update(s1, m, NULL, b), SELFCOL_OK);
    assert_int_equal(selfcol_context_store_update(context, s64, m, NULL, b), SELFCOL_OK);
    assert_int_equal(selfcol_context_store_update(NULL, s64, m, NULL, b), SELFCOL_EINVAL);
    assert_int_equal(selfcol_store_contact_count(s1), selfcol_store_contact_count(s64));
    assert_true(selfcol_store_contact_count(s1) > 0);
    selfcol_store_destroy(s1);
    selfcol_store_destroy(s64);
    selfcol_contacts_destroy(a);
    selfcol_contacts_destroy(b);
    selfcol_context_destroy(context);
    selfcol_hierarchy_destroy(one);
    selfcol_hierarchy_destroy(h);
    selfcol_mesh_destroy(m);
    fixture_free(&next);
    fixture_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_threads_give_the_records_and_counters_of_one_thread),
        cmocka_unit_test(test_threads_allocation_failure_in_a_worker),
        cmocka_unit_test(test_threads_option_bounds_and_old_structs),
        cmocka_unit_test(test_threads_concurrent_queries_on_one_hierarchy),
        cmocka_unit_test(test_threads_sweep_gives_the_hits_of_one_thread),
        cmocka_unit_test(test_threads_store_updates_give_the_store_of_one_thread),
        cmocka_unit_test(test_threads_store_and_refit_bounds_and_old_structs),
    };
    return cmocka_run_group_tests_name("threads", tests, NULL, NULL);
}
