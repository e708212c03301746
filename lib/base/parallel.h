// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Who runs a query's parallel stages: a caller's scheduler, a query
// context's pool of threads (pool.h: kept asleep between stages and joined
// when the context is destroyed; the library keeps no global state), or
// threads started and joined inside the stage; and the few atomic
// operations the shared per-query data needs.
#ifndef SELFCOL_PARALLEL_H
#define SELFCOL_PARALLEL_H

#include <selfcol/context.h>

#include "base/pool.h"

#include <stdint.h>

// Who runs a parallel stage's work items: a caller's scheduler
// (selfcol_context_options' enqueue_task and finish_task), or, with
// enqueue_task NULL, a query context's pool (NULL: POSIX threads started
// and joined by the stage).
typedef struct selfcol_executor {
    selfcol_enqueue_task_fn *enqueue_task;
    selfcol_finish_task_fn *finish_task;
    void *user_context;
    selfcol_pool *pool;
} selfcol_executor;

// Runs work(context, w) for w = 0 .. workers - 1 and returns when all have
// run. Without a scheduler: worker 0 on the calling thread, the others on
// the executor's pool, or (`executor` NULL, no pool, or a pool already
// running a stage) on threads started here and joined before returning; a
// worker whose thread cannot be started is not run (callers share their work
// through a task counter, so the others take its part). With a scheduler:
// one task of `workers` items, each item one worker. A worker never waits
// for one that has not started (at most, briefly, for one running at the
// same time: traverse.c's leaf stamps), so a scheduler may run them in any
// order, on any threads or one after another. At
// most SELFCOL_MAX_THREADS workers. Returns the first non-zero status of the
// workers, in worker order.
int selfcol_parallel__run(const selfcol_executor *executor, unsigned workers,
                          int (*work)(void *context, unsigned worker), void *context);

// GCC/Clang atomic builtins (the library is C99; C11 <stdatomic.h> is not
// assumed). Acquire/release orders are enough for the patterns used: a task
// counter, a stop flag, and per-leaf publish-once stamps.
#define SELFCOL_ATOMIC_LOAD(p) __atomic_load_n((p), __ATOMIC_ACQUIRE)
#define SELFCOL_ATOMIC_STORE(p, v) __atomic_store_n((p), (v), __ATOMIC_RELEASE)
#define SELFCOL_ATOMIC_FETCH_ADD(p, v) __atomic_fetch_add((p), (v), __ATOMIC_ACQ_REL)
#define SELFCOL_ATOMIC_CAS(p, expected, desired)                                                   \
    __atomic_compare_exchange_n((p), (expected), (desired), 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)

#endif // SELFCOL_PARALLEL_H
