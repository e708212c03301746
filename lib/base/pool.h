// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A query context's worker threads, kept asleep between its parallel stages.
// Starting and joining POSIX threads for every stage costs tens of
// microseconds per thread, serially on the calling thread (16 workers: 786
// us a stage on the 2-core machine, 95 us on a pool), and a continuous
// EARLIEST query runs about a hundred stages (its rounds). On the 16-core
// machine, where a thread starts in a few microseconds, the pool measured
// within that machine's noise (docs/benchmarks.md, "Threads"). zstd's
// multi-threaded compression context keeps its thread pool (POOL_ctx) the
// same way. A pool belongs to a query context (the one handle whose
// lifetime the caller manages for that purpose: contact sets, sweeps,
// stores and hierarchies may be held by the hundred, and keep no thread),
// is used by one thread at a time as its context is, starts its threads at
// the first stage that needs them, and joins them when the context is
// destroyed: there is no global state.
#ifndef SELFCOL_POOL_H
#define SELFCOL_POOL_H

#include <selfcol/common.h>

typedef struct selfcol_pool selfcol_pool;

// A pool with no thread yet, allocated with `allocator` (copied). NULL on
// failure.
selfcol_pool *selfcol_pool__create(const selfcol_allocator *allocator);

// Wakes and joins the threads, then frees the pool. Accepts NULL.
void selfcol_pool__destroy(selfcol_pool *pool);

// Runs work(context, w) for w = 0 .. workers - 1 (workers >= 2, at most
// SELFCOL_MAX_THREADS): worker 0 on the calling thread, the others on the
// pool's threads, started here the first time they are needed; returns 1
// when every worker has returned, their first non-zero status in worker
// order in *status. A worker whose thread cannot be started is not run (the
// callers' workers share their work through a task counter: parallel.h).
// Returns 0, having run nothing, when the pool is already running a stage
// (a worker that starts a stage of its own): the caller then starts
// threads for it (selfcol_parallel__run).
int selfcol_pool__try_run(selfcol_pool *pool, unsigned workers,
                          int (*work)(void *context, unsigned worker), void *context, int *status);

// Threads started so far (0 .. SELFCOL_MAX_THREADS - 1).
unsigned selfcol_pool__threads(const selfcol_pool *pool);

#endif // SELFCOL_POOL_H
