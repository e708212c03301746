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
 * threads); selfcol_context_destroy() joins them. The calls without a
 * context start and join theirs within the call.
 * A caller with its own scheduler (a game engine's job system, Bullet's
 * btITaskScheduler, TBB) gives enqueue_task and finish_task instead, and
 * the items run wherever that scheduler puts them; Box2D v3's task
 * callbacks are the model. The records are the same, in the same order,
 * for every thread count and every scheduler.
 *
 * The functions without a context (selfcol_hierarchy_self_collide() and
 * the others taking selfcol_query_options.threads) keep one inside the
 * contact set they fill, made at their first call: they allocate nothing
 * more in steady state either. Continuous queries (sweep.h) keep their
 * working memory in their selfcol_sweep; through a context they take its
 * workers and scheduler.
 * @{
 */
#ifndef SELFCOL_CONTEXT_H
#define SELFCOL_CONTEXT_H

#include "common.h"
#include "contacts.h"
#include "hierarchy.h"
#include "sweep.h"

SELFCOL_BEGIN_DECLS

/** Opaque query context. */
typedef struct selfcol_context selfcol_context;

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
 * memory: the same records in contacts. The options' threads field is not
 * read (the context's applies).
 * @return as selfcol_hierarchy_self_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_self_collide(selfcol_context *context,
                                             const selfcol_hierarchy *hierarchy,
                                             selfcol_contacts *contacts,
                                             const selfcol_query_options *opts);

/**
 * selfcol_hierarchy_collide() on the context's threads and working memory.
 * The options' threads field is not read.
 * @return as selfcol_hierarchy_collide(); SELFCOL_EINVAL also for a NULL context.
 */
SELFCOL_API int selfcol_context_collide(selfcol_context *context, const selfcol_hierarchy *first,
                                        const selfcol_hierarchy *second, selfcol_contacts *contacts,
                                        const selfcol_query_options *opts);

/**
 * selfcol_hierarchy_self_sweep() with SELFCOL_SWEEP_ALL's root searches on
 * the context's workers and scheduler (the broad phase and
 * SELFCOL_SWEEP_EARLIEST on the calling thread, as without). The options'
 * threads field is not read; the hits are the same.
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

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_CONTEXT_H */
