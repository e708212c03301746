// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Per-query worker threads (POSIX threads). Starting and joining a thread
// costs tens of microseconds, against queries of milliseconds on the meshes
// where threads pay; the library starts none unless the caller asks for more
// than one thread (selfcol_query_options.threads).
#include "parallel.h"

#include "core.h"

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

int selfcol_parallel__run(unsigned workers, int (*work)(void *context, unsigned worker),
                          void *context) {
    if (workers > SELFCOL_MAX_THREADS)
        workers = SELFCOL_MAX_THREADS;
    worker_start start[SELFCOL_MAX_THREADS];
    pthread_t thread[SELFCOL_MAX_THREADS];
    int running[SELFCOL_MAX_THREADS] = {0};
    for (unsigned w = 1; w < workers; ++w) {
        start[w] = (worker_start){work, context, w, SELFCOL_OK};
        running[w] = pthread_create(&thread[w], NULL, worker_main, &start[w]) == 0;
    }
    int status = work(context, 0);
    for (unsigned w = 1; w < workers; ++w) {
        if (!running[w])
            continue;
        pthread_join(thread[w], NULL);
        if (status == SELFCOL_OK)
            status = start[w].status;
    }
    return status;
}
