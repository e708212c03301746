// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The query context (include/selfcol/context.h): who runs a query's
// parallel stages, the calling thread's working memory, and each extra
// worker's records and working memory. A query writes its result into the
// caller's records (records.h) and its workers' records here; the sort
// then takes the workers' records in where they lie.
#ifndef SELFCOL_CONTEXT_INTERNAL_H
#define SELFCOL_CONTEXT_INTERNAL_H

#include <selfcol/context.h>

#include "base/parallel.h"
#include "base/workspace.h"
#include "query/records.h"

// An extra worker's own records and working memory (its traversal stack,
// its contour work area).
typedef struct selfcol_worker {
    selfcol_records records;
    selfcol_workspace work;
} selfcol_worker;

struct selfcol_context {
    selfcol_allocator allocator;
    unsigned threads; // 1..SELFCOL_MAX_THREADS
    selfcol_executor executor;
    // The calling thread's working memory, and the query-wide buffers (the
    // per-triangle frames and stamps, the tasks, the sort keys).
    selfcol_workspace work;
    // workers[w] for worker w >= 1, made at first use; workers[0] unused.
    selfcol_worker *workers[SELFCOL_MAX_THREADS];
    // Workers 1 .. pending_workers hold records of the running query that
    // selfcol_context__sort takes in; 0 after it.
    unsigned pending_workers;
    // The leaf tests' lanes: 0 the widest this CPU runs (pairs.h,
    // selfcol_pairs__has_avx), 1 the two-lane baseline even where AVX runs
    // (set by the tests, which hold the two paths' queries equal).
    int baseline_lanes;
};

// Worker w >= 1's records (cleared) and working memory, made at first use
// with the context's allocator. NULL on allocation failure.
selfcol_worker *selfcol_context__worker(selfcol_context *context, unsigned w);

// Sorts `out` (records.h) with the records of the pending workers taken in,
// on the context's threads; no worker is pending afterwards, whatever the
// status (SELFCOL_OK or SELFCOL_ENOMEM).
int selfcol_context__sort(selfcol_context *context, selfcol_records *out);

#endif // SELFCOL_CONTEXT_INTERNAL_H
