// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The pool's threads wait on one condition variable for a new stage (a
// generation number bumped under the lock); a stage names how many workers
// it wants, and the threads beyond that go back to sleep. The last worker to
// finish signals the calling thread. Every hand-over goes through the lock,
// so what a worker wrote is visible to the caller once the stage returns
// (and what the caller wrote before it, to the workers).
#include "base/pool.h"

#include "base/alloc.h"
#include "base/core.h"

#include <pthread.h>
#include <string.h>

typedef struct pool_thread {
    struct selfcol_pool *pool;
    unsigned index; // the worker it runs (1 ..)
    uint64_t seen;  // the last generation it looked at
    pthread_t thread;
} pool_thread;

struct selfcol_pool {
    selfcol_allocator allocator;
    pthread_mutex_t lock;
    pthread_cond_t wake; // a new stage, or quit
    pthread_cond_t done; // the last worker of a stage finished
    unsigned started;    // threads 1 .. started run
    int running;         // a stage is under way (a nested stage falls back)
    int quit;
    uint64_t generation;
    // The current stage, written under the lock before the wake.
    unsigned active;    // workers 0 .. active - 1 run
    unsigned remaining; // of workers 1 .. active - 1, those still running
    int (*work)(void *, unsigned);
    void *context;
    int status[SELFCOL_MAX_THREADS];
    pool_thread thread[SELFCOL_MAX_THREADS]; // [0] unused: the calling thread
};

static void *thread_main(void *arg) {
    pool_thread *self = arg;
    selfcol_pool *p = self->pool;
    pthread_mutex_lock(&p->lock);
    for (;;) {
        while (!p->quit && p->generation == self->seen)
            pthread_cond_wait(&p->wake, &p->lock);
        if (p->quit)
            break;
        self->seen = p->generation;
        if (self->index >= p->active)
            continue; // this stage wants fewer workers
        int (*work)(void *, unsigned) = p->work;
        void *context = p->context;
        pthread_mutex_unlock(&p->lock);
        const int status = work(context, self->index);
        pthread_mutex_lock(&p->lock);
        p->status[self->index] = status;
        if (--p->remaining == 0)
            pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

selfcol_pool *selfcol_pool__create(const selfcol_allocator *allocator) {
    selfcol_pool *p = selfcol_alloc__raw(allocator, sizeof *p);
    if (p == NULL)
        return NULL;
    memset(p, 0, sizeof *p);
    p->allocator = *allocator;
    if (pthread_mutex_init(&p->lock, NULL) != 0) {
        selfcol_alloc__free(allocator, p, sizeof *p);
        return NULL;
    }
    if (pthread_cond_init(&p->wake, NULL) != 0) {
        pthread_mutex_destroy(&p->lock);
        selfcol_alloc__free(allocator, p, sizeof *p);
        return NULL;
    }
    if (pthread_cond_init(&p->done, NULL) != 0) {
        pthread_cond_destroy(&p->wake);
        pthread_mutex_destroy(&p->lock);
        selfcol_alloc__free(allocator, p, sizeof *p);
        return NULL;
    }
    return p;
}

void selfcol_pool__destroy(selfcol_pool *pool) {
    if (pool == NULL)
        return;
    pthread_mutex_lock(&pool->lock);
    pool->quit = 1;
    pthread_cond_broadcast(&pool->wake);
    const unsigned started = pool->started;
    pthread_mutex_unlock(&pool->lock);
    for (unsigned t = 1; t <= started; ++t)
        pthread_join(pool->thread[t].thread, NULL);
    pthread_cond_destroy(&pool->done);
    pthread_cond_destroy(&pool->wake);
    pthread_mutex_destroy(&pool->lock);
    selfcol_allocator allocator = pool->allocator;
    selfcol_alloc__free(&allocator, pool, sizeof *pool);
}

int selfcol_pool__try_run(selfcol_pool *pool, unsigned workers,
                          int (*work)(void *context, unsigned worker), void *context, int *status) {
    if (workers > SELFCOL_MAX_THREADS)
        workers = SELFCOL_MAX_THREADS;
    pthread_mutex_lock(&pool->lock);
    if (pool->running) {
        pthread_mutex_unlock(&pool->lock);
        return 0;
    }
    // Threads up to workers - 1; a thread that cannot start caps the stage.
    while (pool->started + 1 < workers) {
        pool_thread *t = &pool->thread[pool->started + 1];
        t->pool = pool;
        t->index = pool->started + 1;
        t->seen = pool->generation;
        if (pthread_create(&t->thread, NULL, thread_main, t) != 0)
            break;
        pool->started++;
    }
    const unsigned active = workers < pool->started + 1 ? workers : pool->started + 1;
    pool->running = 1;
    pool->active = active;
    pool->remaining = active - 1;
    pool->work = work;
    pool->context = context;
    for (unsigned w = 0; w < active; ++w)
        pool->status[w] = SELFCOL_OK;
    pool->generation++;
    if (active > 1)
        pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->lock);

    const int first = work(context, 0);

    pthread_mutex_lock(&pool->lock);
    while (pool->remaining > 0)
        pthread_cond_wait(&pool->done, &pool->lock);
    pool->running = 0;
    pool->status[0] = first;
    int result = SELFCOL_OK;
    for (unsigned w = 0; w < active && result == SELFCOL_OK; ++w)
        result = pool->status[w];
    pthread_mutex_unlock(&pool->lock);
    *status = result;
    return 1;
}

unsigned selfcol_pool__threads(const selfcol_pool *pool) {
    return pool != NULL ? pool->started : 0u;
}
