// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "hierarchy/hierarchy.h"

#include "base/alloc.h"
#include "base/core.h"
#include "base/problem.h"

#include <stddef.h>
#include <string.h>

int selfcol_hierarchy_options_init(selfcol_hierarchy_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    // Versions 1 and 2 were 0.3's layouts (2 with threads).
    if (version < SELFCOL_HIERARCHY_OPTIONS_VERSION || version > SELFCOL_HIERARCHY_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

// The options read as their version says (NULL: the defaults) and checked;
// `at` names a refused field (problem.h; NULL: the status only).
static int hierarchy_options(const selfcol_hierarchy_options *opts, selfcol_allocator *allocator,
                             const selfcol_problem_at *at) {
    const selfcol_allocator none = {NULL, NULL, NULL};
    *allocator = none;
    if (opts != NULL) {
        const int version =
            selfcol_problem__version_since(at, opts->version, SELFCOL_HIERARCHY_OPTIONS_VERSION,
                                           SELFCOL_HIERARCHY_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
        *allocator = opts->allocator;
    }
    SELFCOL_CHECK_ALLOCATOR(at, *allocator);
    return SELFCOL_OK;
}

int selfcol_hierarchy_options_check(const selfcol_hierarchy_options *opts,
                                    selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_hierarchy_options", ""};
    selfcol_allocator allocator;
    return hierarchy_options(opts, &allocator, &at);
}

int selfcol_hierarchy_create(selfcol_hierarchy **out, const selfcol_mesh *mesh,
                             const selfcol_hierarchy_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK(mesh != NULL);
    selfcol_allocator allocator;
    const int checked = hierarchy_options(opts, &allocator, NULL);
    if (checked != SELFCOL_OK)
        return checked;
    selfcol_hierarchy *h = selfcol_alloc__raw(&allocator, sizeof *h);
    if (h == NULL)
        return SELFCOL_ENOMEM;
    memset(h, 0, sizeof *h);
    h->allocator = allocator;
    h->mesh = mesh;
    h->mesh_identity = mesh->identity;
    h->triangle_count = mesh->triangle_count;
    h->refit_workers = 1;
    const int status = selfcol_hierarchy__build(h);
    if (status != SELFCOL_OK) {
        selfcol_hierarchy_destroy(h);
        return status;
    }
    (void)selfcol_hierarchy__refit(h, NULL, 1); // one thread: nothing to plan
    SELFCOL_ASSERT(selfcol_hierarchy__validate(h, 1) != 0);
    *out = h;
    return SELFCOL_OK;
}

void selfcol_hierarchy_destroy(selfcol_hierarchy *hierarchy) {
    if (hierarchy == NULL)
        return;
    selfcol_allocator allocator = hierarchy->allocator;
    size_t F = hierarchy->triangle_count;
    selfcol_alloc__free_array(&allocator, hierarchy->nodes, hierarchy->node_count,
                              sizeof(selfcol_node));
    selfcol_alloc__free_array(&allocator, hierarchy->tri_order, F, sizeof(uint32_t));
    selfcol_alloc__free_array(&allocator, hierarchy->owned, F, sizeof(uint8_t));
    selfcol_alloc__free_array(&allocator, hierarchy->bedge, hierarchy->bedge_total,
                              sizeof(uint32_t));
    selfcol_alloc__free_array(&allocator, hierarchy->min_altitude, hierarchy->node_count,
                              sizeof(float));
    selfcol_hierarchy__free_plan(hierarchy);
    selfcol_alloc__free(&allocator, hierarchy, sizeof *hierarchy);
}

const selfcol_mesh *selfcol_hierarchy_mesh(const selfcol_hierarchy *hierarchy) {
    return hierarchy != NULL ? hierarchy->mesh : NULL;
}

int selfcol_hierarchy_refit(selfcol_hierarchy *hierarchy) {
    SELFCOL_CHECK(hierarchy != NULL);
    if (!selfcol_mesh__is(hierarchy->mesh, &hierarchy->mesh_identity))
        return SELFCOL_EMISMATCH;
    (void)selfcol_hierarchy__refit(hierarchy, NULL, 1); // one thread: nothing to plan
    SELFCOL_ASSERT(selfcol_hierarchy__validate(hierarchy, 1) != 0);
    return SELFCOL_OK;
}

size_t selfcol_hierarchy_count(const selfcol_hierarchy *hierarchy,
                               selfcol_hierarchy_quantity quantity) {
    if (hierarchy == NULL)
        return 0;
    switch (quantity) {
    case SELFCOL_HIERARCHY_NODES: return hierarchy->node_count;
    case SELFCOL_HIERARCHY_LEAVES: return hierarchy->leaf_count;
    case SELFCOL_HIERARCHY_DEPTH: return hierarchy->depth;
    }
    return 0;
}

size_t selfcol_hierarchy_byte_count(const selfcol_hierarchy *hierarchy) {
    if (hierarchy == NULL)
        return 0;
    size_t F = hierarchy->triangle_count;
    return sizeof *hierarchy + hierarchy->node_count * sizeof(selfcol_node) +
           F * (sizeof(uint32_t) + sizeof(uint8_t)) + hierarchy->bedge_total * sizeof(uint32_t) +
           hierarchy->node_count * sizeof(float) +
           (hierarchy->subtree_count == 0
                ? 0
                : (2 * (size_t)hierarchy->subtree_count + 1 +
                   2 * (size_t)hierarchy->subtree_level_offset[hierarchy->subtree_count]) *
                      sizeof(uint32_t));
}
