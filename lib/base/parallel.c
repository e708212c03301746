// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Per-query worker threads: the items of one task of a caller's scheduler
// (context.h), a query context's pool (pool.c), or POSIX threads started
// for the stage. Starting and joining a thread costs tens of microseconds, against
// stages of milliseconds on the meshes where threads pay, but a query with
// many stages pays it many times: a query context keeps a pool. The
// library starts no thread unless the caller asks for more than one (the
// threads of the query, context, sweep, store and hierarchy options).
#include "base/parallel.h"

#include "base/core.h"

#include <selfcol/hierarchy.h>

#include <pthread.h>

typedef struct worker_start {
    int (*work)(void *, unsigned);
    void *context;
    unsigned index;
    int status;
} worker_start;

static void *worker_main(void *arg) {
    worker_start *w = arg;
    w->status = w->work(w->context, w->index);
    return NULL;
}

// A caller's scheduler runs the items: each records its own status.
typedef struct scheduled {
    int (*work)(void *, unsigned);
    void *context;
    int status[SELFCOL_MAX_THREADS];
} scheduled;

static void scheduled_range(uint32_t begin, uint32_t end, uint32_t worker, void *task_context) {
    (void)worker; // the item index names the worker's buffers, not the thread
    scheduled *job = task_context;
    for (uint32_t w = begin; w < end; ++w)
        job->status[w] = job->work(job->context, w);
}

static int run_scheduled(const selfcol_executor *executor, unsigned workers,
                         int (*work)(void *, unsigned), void *context) {
    scheduled job;
    job.work = work;
    job.context = context;
    for (unsigned w = 0; w < workers; ++w)
        job.status[w] = SELFCOL_OK;
    void *task = executor->enqueue_task(scheduled_range, workers, 1u, &job, executor->user_context);
    if (task != NULL)
        executor->finish_task(task, executor->user_context);
    for (unsigned w = 0; w < workers; ++w)
        if (job.status[w] != SELFCOL_OK)
            return job.status[w];
    return SELFCOL_OK;
}

int selfcol_parallel__run(const selfcol_executor *executor, unsigned workers,
                          int (*work)(void *context, unsigned worker), void *context) {
    if (workers > SELFCOL_MAX_THREADS)
        workers = SELFCOL_MAX_THREADS;
    if (workers <= 1)
        return work(context, 0);
    if (executor != NULL && executor->enqueue_task != NULL)
        return run_scheduled(executor, workers, work, context);
    int status;
    if (executor != NULL && executor->pool != NULL &&
        selfcol_pool__try_run(executor->pool, workers, work, context, &status))
        return status;
    worker_start start[SELFCOL_MAX_THREADS];
    pthread_t thread[SELFCOL_MAX_THREADS];
    int running[SELFCOL_MAX_THREADS] = {0};
    for (unsigned w = 1; w < workers; ++w) {
        start[w] = (worker_start){work, context, w, SELFCOL_OK};
        running[w] = pthread_create(&thread[w], NULL, worker_main, &start[w]) == 0;
    }
    status = work(context, 0);
    for (unsigned w = 1; w < workers; ++w) {
        if (!running[w])
            continue;
        pthread_join(thread[w], NULL);
        if (status == SELFCOL_OK)
            status = start[w].status;
    }
    return status;
}
