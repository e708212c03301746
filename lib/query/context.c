// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "query/context.h"

#include "base/alloc.h"
#include "base/core.h"
#include "base/problem.h"
#include "hierarchy/hierarchy.h"

#include <string.h>

int selfcol_context_options_init(selfcol_context_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_CONTEXT_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->threads = 1;
    return SELFCOL_OK;
}

// The options (NULL: the defaults) checked; `at` names a refused field.
static int context_options(selfcol_context_options *o, const selfcol_context_options *opts,
                           const selfcol_problem_at *at) {
    selfcol_context_options_init(o, SELFCOL_CONTEXT_OPTIONS_VERSION);
    if (opts != NULL) {
        const int version =
            selfcol_problem__version(at, opts->version, SELFCOL_CONTEXT_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
        *o = *opts;
    }
    SELFCOL_CHECK_ALLOCATOR(at, o->allocator);
    SELFCOL_CHECK_FIELD(at, o->threads >= 1 && o->threads <= SELFCOL_MAX_THREADS, "threads",
                        "= %u is not in 1 .. %d", o->threads, SELFCOL_MAX_THREADS);
    SELFCOL_CHECK_FIELD(at, (o->enqueue_task == NULL) == (o->finish_task == NULL),
                        o->enqueue_task == NULL ? "enqueue_task" : "finish_task",
                        "is NULL while %s is set: give both callbacks, or neither",
                        o->enqueue_task == NULL ? "finish_task" : "enqueue_task");
    return SELFCOL_OK;
}

int selfcol_context_options_check(const selfcol_context_options *opts,
                                  selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_context_options", ""};
    selfcol_context_options checked;
    return context_options(&checked, opts, &at);
}

int selfcol_context_create(selfcol_context **out, const selfcol_context_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    selfcol_context_options o;
    const int checked = context_options(&o, opts, NULL);
    if (checked != SELFCOL_OK)
        return checked;
    selfcol_context *c = selfcol_alloc__raw(&o.allocator, sizeof *c);
    if (c == NULL)
        return SELFCOL_ENOMEM;
    memset(c, 0, sizeof *c);
    c->allocator = o.allocator;
    c->threads = o.threads;
    c->executor.enqueue_task = o.enqueue_task;
    c->executor.finish_task = o.finish_task;
    c->executor.user_context = o.user_context;
    // Without a scheduler, the context's own threads run its stages (a
    // one-thread context has none: everything runs on the calling thread).
    if (o.threads > 1 && o.enqueue_task == NULL) {
        c->executor.pool = selfcol_pool__create(&c->allocator);
        if (c->executor.pool == NULL) {
            selfcol_alloc__free(&o.allocator, c, sizeof *c);
            return SELFCOL_ENOMEM;
        }
    }
    selfcol_workspace__init(&c->work, &c->allocator);
    *out = c;
    return SELFCOL_OK;
}

void selfcol_context_destroy(selfcol_context *context) {
    if (context == NULL)
        return;
    selfcol_allocator allocator = context->allocator;
    selfcol_pool__destroy(context->executor.pool); // joins its threads first
    for (unsigned w = 1; w < SELFCOL_MAX_THREADS; ++w) {
        selfcol_worker *worker = context->workers[w];
        if (worker == NULL)
            continue;
        selfcol_records__free(&worker->records);
        selfcol_workspace__free(&worker->work);
        selfcol_alloc__free(&allocator, worker, sizeof *worker);
    }
    selfcol_workspace__free(&context->work);
    selfcol_alloc__free(&allocator, context, sizeof *context);
}

size_t selfcol_context_byte_count(const selfcol_context *context) {
    if (context == NULL)
        return 0;
    size_t bytes = sizeof *context + selfcol_workspace__byte_count(&context->work);
    for (unsigned w = 1; w < SELFCOL_MAX_THREADS; ++w) {
        const selfcol_worker *worker = context->workers[w];
        if (worker != NULL)
            bytes += sizeof *worker + selfcol_records__byte_count(&worker->records) +
                     selfcol_workspace__byte_count(&worker->work);
    }
    return bytes;
}

selfcol_worker *selfcol_context__worker(selfcol_context *context, unsigned w) {
    selfcol_worker *worker = context->workers[w];
    if (worker == NULL) {
        worker = selfcol_alloc__raw(&context->allocator, sizeof *worker);
        if (worker == NULL)
            return NULL;
        selfcol_records__init(&worker->records, &context->allocator);
        selfcol_workspace__init(&worker->work, &context->allocator);
        context->workers[w] = worker;
    }
    selfcol_records__clear(&worker->records);
    return worker;
}

int selfcol_context__sort(selfcol_context *context, selfcol_records *out) {
    selfcol_records *pending[SELFCOL_MAX_THREADS];
    const unsigned count = context->pending_workers;
    context->pending_workers = 0;
    for (unsigned w = 0; w < count; ++w)
        pending[w] = &context->workers[w + 1]->records;
    return selfcol_records__sort(out, pending, count, &context->work, &context->executor,
                                 context->threads);
}

int selfcol_context_refit(selfcol_context *context, selfcol_hierarchy *hierarchy) {
    SELFCOL_CHECK(context != NULL && hierarchy != NULL);
    if (!selfcol_mesh__is(hierarchy->mesh, &hierarchy->mesh_identity))
        return SELFCOL_EMISMATCH;
    const int status = selfcol_hierarchy__refit(hierarchy, &context->executor, context->threads);
    SELFCOL_ASSERT(selfcol_hierarchy__validate(hierarchy, 1) != 0);
    return status;
}
