// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Collision queries: option checking and dispatch, the first stage of the
// pipeline (dispatch here -> candidates from traverse.c or exhaustive.c ->
// primitive-pair tests in pairs.c -> sorted records in contacts.c).
#include "query/query.h"
#include "query/exhaustive.h"
#include "query/traverse.h"

#include "base/core.h"
#include "base/problem.h"
#include "hierarchy/hierarchy.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

int selfcol_query_options_init(selfcol_query_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    // Versions 1 and 2 were 0.3's layouts (2 with threads).
    if (version < SELFCOL_QUERY_OPTIONS_VERSION || version > SELFCOL_QUERY_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->method = SELFCOL_METHOD_EXACT;
    opts->narrow = SELFCOL_NARROW_CLOSED_FORM;
    opts->kinds = SELFCOL_KIND_ALL;
    opts->distance = 0.0;
    return SELFCOL_OK;
}

int selfcol_query__options(selfcol_query_options *out, const selfcol_query_options *opts,
                           const selfcol_problem_at *at) {
    if (opts != NULL) {
        const int version = selfcol_problem__version_since(
            at, opts->version, SELFCOL_QUERY_OPTIONS_VERSION, SELFCOL_QUERY_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
    }
    selfcol_query_options_init(out, SELFCOL_QUERY_OPTIONS_VERSION);
    if (opts != NULL) {
        out->method = opts->method;
        out->narrow = opts->narrow;
        out->kinds = opts->kinds;
        out->distance = opts->distance;
    }
    SELFCOL_CHECK_FIELD(at, out->method <= SELFCOL_METHOD_EXACT, "method",
                        "= %u is not a selfcol_method (0 .. %d)", out->method,
                        (int)SELFCOL_METHOD_EXACT);
    SELFCOL_CHECK_FIELD(
        at, out->narrow == SELFCOL_NARROW_CLOSED_FORM || out->narrow == SELFCOL_NARROW_LIBCCD,
        "narrow", "= %u is not a selfcol_narrow (%d or %d)", out->narrow,
        (int)SELFCOL_NARROW_CLOSED_FORM, (int)SELFCOL_NARROW_LIBCCD);
    SELFCOL_CHECK_FIELD(at, (out->kinds & ~(uint32_t)SELFCOL_KIND_ALL) == 0, "kinds",
                        "= 0x%x has bits beyond SELFCOL_KIND_ALL (0x%x)", out->kinds,
                        (unsigned)SELFCOL_KIND_ALL);
    // The distance obeys the coordinates' contract (mesh.h): its square must
    // not overflow in the closed forms.
    SELFCOL_CHECK_FIELD(at,
                        isfinite(out->distance) && out->distance >= 0.0 &&
                            out->distance <= SELFCOL_MESH_MAX_COORDINATE,
                        "distance", "= %g is not a distance in 0 .. %g", out->distance,
                        SELFCOL_MESH_MAX_COORDINATE);
    return SELFCOL_OK;
}

int selfcol_query_options_check(const selfcol_query_options *opts,
                                selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_query_options", ""};
    selfcol_query_options checked;
    return selfcol_query__options(&checked, opts, &at);
}

selfcol_context *selfcol_query__implicit_context(selfcol_contacts *contacts) {
    if (contacts->implicit_context == NULL) {
        selfcol_context_options o;
        selfcol_context_options_init(&o, SELFCOL_CONTEXT_OPTIONS_VERSION);
        o.allocator = contacts->records.allocator;
        // One thread (the calls without a context run on the calling
        // thread), hence no pool: a caller may hold many contact sets (a
        // Python list of results, a scene's pairs).
        if (selfcol_context_create(&contacts->implicit_context, &o) != SELFCOL_OK)
            return NULL;
    }
    return contacts->implicit_context;
}

// The checks of every discrete query entry point; then the query.
static int run_query(selfcol_context *context, const selfcol_hierarchy *first,
                     const selfcol_hierarchy *second, selfcol_contacts *contacts,
                     const selfcol_query_options *given) {
    SELFCOL_CHECK(first != NULL && second != NULL && contacts != NULL);
    selfcol_query_options checked;
    int status = selfcol_query__options(&checked, given, NULL);
    if (status != SELFCOL_OK)
        return status;
    if (!selfcol_mesh__is(first->mesh, &first->mesh_identity) ||
        !selfcol_mesh__is(second->mesh, &second->mesh_identity))
        return SELFCOL_EMISMATCH;
    if (checked.method != SELFCOL_METHOD_EXHAUSTIVE &&
        (first->refit_version != first->mesh->positions_version ||
         second->refit_version != second->mesh->positions_version))
        return SELFCOL_ESTALE;
    if (context == NULL) {
        context = selfcol_query__implicit_context(contacts);
        if (context == NULL) {
            selfcol_contacts_clear(contacts);
            return SELFCOL_ENOMEM;
        }
    }
    return selfcol_query__run(context, first, second, &contacts->records, &checked, NULL);
}

int selfcol_query__run(selfcol_context *context, const selfcol_hierarchy *first,
                       const selfcol_hierarchy *second, selfcol_records *out,
                       const selfcol_query_options *opts, const selfcol_node_filter *filter) {
    double start = selfcol_core__seconds();
    selfcol_records__clear(out);
    context->pending_workers = 0;
    selfcol_query q;
    q.mesh[0] = first->mesh;
    q.mesh[1] = second->mesh;
    q.self = (first == second);
    q.distance = opts->distance;
    q.kinds = opts->kinds;
    q.narrow = opts->narrow;
    // libccd's tolerances are absolute: its distances (a bisection on the
    // inflation radius) are asked to 1e-7 of the detection distance.
    q.ccd_tolerance = 1e-7 * q.distance;
    q.out = out;
    q.work = &context->work;
    q.filter = filter;

    int status = opts->method == SELFCOL_METHOD_EXHAUSTIVE
                     ? selfcol_exhaustive__run(&q)
                     : selfcol_traverse__run(&q, first, second, opts->method, context);
    double sort_start = selfcol_core__seconds();
    if (status == SELFCOL_OK)
        status = selfcol_context__sort(context, out);
    context->pending_workers = 0;
    if (status != SELFCOL_OK) {
        selfcol_records__clear(out);
        return status;
    }
    double end = selfcol_core__seconds();
    out->stats.sort_seconds = end - sort_start;
    out->stats.total_seconds = end - start;
    return SELFCOL_OK;
}

int selfcol_hierarchy_self_collide(const selfcol_hierarchy *hierarchy, selfcol_contacts *contacts,
                                   const selfcol_query_options *opts) {
    return run_query(NULL, hierarchy, hierarchy, contacts, opts);
}

int selfcol_hierarchy_collide(const selfcol_hierarchy *first, const selfcol_hierarchy *second,
                              selfcol_contacts *contacts, const selfcol_query_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run_query(NULL, first, second, contacts, opts);
}

int selfcol_context_self_collide(selfcol_context *context, const selfcol_hierarchy *hierarchy,
                                 selfcol_contacts *contacts, const selfcol_query_options *opts) {
    SELFCOL_CHECK(context != NULL);
    return run_query(context, hierarchy, hierarchy, contacts, opts);
}

int selfcol_context_collide(selfcol_context *context, const selfcol_hierarchy *first,
                            const selfcol_hierarchy *second, selfcol_contacts *contacts,
                            const selfcol_query_options *opts) {
    SELFCOL_CHECK(context != NULL);
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run_query(context, first, second, contacts, opts);
}
