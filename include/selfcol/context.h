// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file context.h
 * @defgroup context Query contexts
 * A query context: the working memory, the worker threads' record buffers
 * and the scheduling of the queries it serves, kept by the caller from
 * frame to frame (zstd's compression context is the model). A contact set
 * (contacts.h) is then only the result.
 *
 * The one place where threads are said (since 0.4): every call that can run
 * on threads has a form taking a context (the discrete queries, the
 * continuous ones, refits, store updates, coherent sequences), and runs on
 * the context's threads or scheduler; the forms without one run on the
 * calling thread. A scene and the Bullet adapter run on a context set on
 * them (selfcol_scene_set_context(), selfcol_bullet_options.threads).
 *
 * One context serves any number of hierarchies and contact sets, one query
 * at a time: two threads that query at once need a context each. After the
 * first queries of a scene have grown its buffers, a query allocates
 * nothing.
 *
 * Threads: a context runs each parallel stage of a query (the traversal,
 * the records' sort) as `threads` work items. By default they run on POSIX
 * threads that the context starts at its first parallel stage and keeps
 * asleep between stages and queries (a continuous query runs about a
 * hundred stages, each of which would otherwise start and join its
 * threads); selfcol_context_destroy() joins them.
 * A caller with its own scheduler (a game engine's job system, Bullet's
 * btITaskScheduler, TBB) gives enqueue_task and finish_task instead, and
 * the items run wherever that scheduler puts them; Box2D v3's task
 * callbacks are the model. The records are the same, in the same order,
 * for every thread count and every scheduler.
 *
 * The discrete queries without a context (selfcol_hierarchy_self_collide()
 * and the others) keep a one-thread context inside the contact set they
 * fill, made at their first call: they allocate nothing more in steady
 * state either. Continuous queries (sweep.h) keep their working memory in
 * their selfcol_sweep, and stores and sequences in themselves; through a
 * context they take its workers and scheduler.
 *
 * The contacts' allocator may be called from a discrete query's workers
 * (each pushes records on its own thread): with more than one thread it
 * must be thread-safe. The allocators of sweeps, stores, sequences and
 * hierarchies are only called from the calling thread.
 * @{
 */
#ifndef SELFCOL_CONTEXT_H
#define SELFCOL_CONTEXT_H

#include "common.h"
#include "contacts.h"
#include "hierarchy.h"
#include "sequence.h"
#include "store.h"
#include "sweep.h"

SELFCOL_BEGIN_DECLS

/* selfcol_context, the opaque query context, is declared in common.h. */

/**
 * A unit of parallel work: runs items begin .. end - 1 of a task.
 * @param begin first item
 * @param end one past the last item
 * @param worker the scheduler's index of the thread running it
 *        (selfcol does not depend on it: any value is accepted)
 * @param task_context the task_context given to enqueue_task
 */
typedef void selfcol_task_fn(uint32_t begin, uint32_t end, uint32_t worker, void *task_context);

/**
 * Hands a task of item_count items to the caller's scheduler. The scheduler
 * calls task on ranges that cover every item exactly once (any split, any
 * order, ranges of at least min_range items except the last), on any
 * threads. It may run them all before it returns; it then returns NULL and
 * finish_task is not called. Otherwise it returns a handle that
 * finish_task receives. Items may be run in any order, on any threads, or
 * one after another on one thread: an item never waits for one that has
 * not started. (An item may wait a moment for data that another item,
 * running at the same time, is computing: a scheduler must not suspend an
 * item to run another on the same thread, as fibers switching inside a
 * task would.)
 * @return NULL when every item already ran, else the scheduler's handle
 */
typedef void *selfcol_enqueue_task_fn(selfcol_task_fn *task, uint32_t item_count,
                                      uint32_t min_range, void *task_context, void *user_context);

/** Waits until every item of the task behind user_task has run. */
typedef void selfcol_finish_task_fn(void *user_task, void *user_context);

/** Options for selfcol_context_create(). Initialise with selfcol_context_options_init(). */
typedef struct selfcol_context_options {
    unsigned int version;        /**< SELFCOL_CONTEXT_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free; may be called from the workers */
    /** Work items per parallel stage, 1 .. SELFCOL_MAX_THREADS (default 1:
     *  everything on the calling thread). With a scheduler, the number of
     *  threads it runs at once is the useful value. */
    unsigned int threads;
    /** The caller's scheduler: both NULL (default: POSIX threads the
     *  context keeps, joined by selfcol_context_destroy()) or both set. */
    selfcol_enqueue_task_fn *enqueue_task;
    selfcol_finish_task_fn *finish_task;
    void *user_context; /**< passed to enqueue_task and finish_task */
} selfcol_context_options;

#define SELFCOL_CONTEXT_OPTIONS_VERSION 1

/**
 * Writes the defaults into opts.
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_context_options_init(selfcol_context_options *opts, unsigned int version);

/**
 * Names what selfcol_context_create() refuses in opts, if anything: the field, its
 * value and what is accepted (common.h, selfcol_options_problem).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as selfcol_context_create()
 *         for these options; SELFCOL_EINVAL for a NULL problem,
 *         SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_context_options_check(const selfcol_context_options *opts,
                                              selfcol_options_problem *problem);

/**
 * Creates a context. It allocates its buffers at the first queries.
 * @param[out] out the new handle; NULL on failure. Free it with selfcol_context_destroy().
 * @param[in] opts options, or NULL for the defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (threads outside 1..SELFCOL_MAX_THREADS,
 *         one scheduler callback without the other, an incomplete allocator);
 *         SELFCOL_EVERSION; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_context_create(selfcol_context **out, const selfcol_context_options *opts);

/** Destroys a context. Accepts NULL. */
SELFCOL_API void selfcol_context_destroy(selfcol_context *context);

/** Bytes held by the context (its working memory and the workers' buffers); 0 for NULL. */
SELFCOL_API size_t selfcol_context_byte_count(const selfcol_context *context);

/**
 * selfcol_hierarchy_self_collide() on the context's threads and working
 * memory: the same records in contacts, and the same statistics apart from
 * times, for every thread count and scheduler.
 * @return as selfcol_hierarchy_self_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_self_collide(selfcol_context *context,
                                             const selfcol_hierarchy *hierarchy,
                                             selfcol_contacts *contacts,
                                             const selfcol_query_options *opts);

/**
 * selfcol_hierarchy_collide() on the context's threads and working memory.
 * @return as selfcol_hierarchy_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_collide(selfcol_context *context, const selfcol_hierarchy *first,
                                        const selfcol_hierarchy *second, selfcol_contacts *contacts,
                                        const selfcol_query_options *opts);

/**
 * selfcol_hierarchy_self_sweep() on the context's workers and scheduler:
 * the broad phase of SELFCOL_METHOD_BVH (its traversal's tasks, in both
 * modes) and the root searches (ALL's, and EARLIEST's in batches of the BVH
 * method). The hits, the fraction and the counters (apart from times) are
 * the same for every thread count. SELFCOL_METHOD_EXACT's culling keeps its
 * broad phase on the calling thread, and EXHAUSTIVE runs there entirely.
 * The sweep's allocator is only called from the calling thread (the workers
 * write into arrays the calling thread grew; a worker that finds one full
 * leaves its task to be run again after the calling thread grows it).
 * @return as selfcol_hierarchy_self_sweep(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_self_sweep(selfcol_context *context,
                                           const selfcol_hierarchy *hierarchy,
                                           const double *start_positions, selfcol_sweep *result,
                                           const selfcol_sweep_options *opts);

/**
 * selfcol_hierarchy_sweep() on the context's workers and scheduler, as
 * selfcol_context_self_sweep().
 * @return as selfcol_hierarchy_sweep(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_sweep(selfcol_context *context, const selfcol_hierarchy *first,
                                      const double *first_start, const selfcol_hierarchy *second,
                                      const double *second_start, selfcol_sweep *result,
                                      const selfcol_sweep_options *opts);

/**
 * selfcol_hierarchy_refit() on the context's threads: subtrees below a cap
 * near the root are refit side by side (never more than one worker per 4096
 * triangles), the cap after them. The boxes, masks and cones are identical
 * for every thread count. The first refit at a new thread count plans the
 * split (an allocation kept by the hierarchy); later ones at that count
 * allocate nothing (refits alternating between two counts plan each time).
 * @return as selfcol_hierarchy_refit(); SELFCOL_EINVAL also for a NULL
 *         context; SELFCOL_ENOMEM (planning; the hierarchy is then refit on
 *         the calling thread, and the call still fails).
 */
SELFCOL_API int selfcol_context_refit(selfcol_context *context, selfcol_hierarchy *hierarchy);

/**
 * selfcol_store_update() on the context's threads: the merge (in chunks of
 * keys, with each contact's exact side, a remnant's geometry and what its
 * links compare), the sort of the contacts' vertex pairs and the regions'
 * union-find are shared among them (only above 4096 records per thread);
 * the links the vote follows and the vote stay on the calling thread, in
 * the same order, so the store is the same for every thread count.
 * @return as selfcol_store_update(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_store_update(selfcol_context *context, selfcol_store *store,
                                             const selfcol_mesh *first, const selfcol_mesh *second,
                                             const selfcol_contacts *detected);

/**
 * selfcol_store_update_swept() on the context's threads, as
 * selfcol_context_store_update().
 * @return as selfcol_store_update_swept(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_store_update_swept(selfcol_context *context, selfcol_store *store,
                                                   const selfcol_mesh *first,
                                                   const selfcol_mesh *second,
                                                   const selfcol_contacts *detected,
                                                   const double *first_start,
                                                   const double *second_start);

/**
 * selfcol_sequence_self_collide() on the context's threads and working
 * memory: its fresh queries and rebuilds, and the evaluation of its near
 * list. The same records as without, for every thread count.
 * @return as selfcol_sequence_self_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_sequence_self_collide(selfcol_context *context,
                                                      selfcol_sequence *sequence,
                                                      selfcol_hierarchy *hierarchy,
                                                      selfcol_contacts *contacts,
                                                      const selfcol_query_options *opts);

/**
 * selfcol_sequence_collide() on the context's threads and working memory.
 * @return as selfcol_sequence_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int
selfcol_context_sequence_collide(selfcol_context *context, selfcol_sequence *sequence,
                                 selfcol_hierarchy *first, selfcol_hierarchy *second,
                                 selfcol_contacts *contacts, const selfcol_query_options *opts);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_CONTEXT_H */
