// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "hierarchy.h"

#include "alloc.h"
#include "core.h"

#include <string.h>

int selfcol_hierarchy_options_init(selfcol_hierarchy_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_HIERARCHY_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

int selfcol_hierarchy_create(selfcol_hierarchy **out, const selfcol_mesh *mesh,
                             const selfcol_hierarchy_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK(mesh != NULL);
    SELFCOL_CHECK_VERSION(opts, SELFCOL_HIERARCHY_OPTIONS_VERSION);
    selfcol_allocator allocator = {NULL, NULL, NULL};
    if (opts != NULL)
        allocator = opts->allocator;
    SELFCOL_CHECK(selfcol_alloc__valid(&allocator));
    selfcol_hierarchy *h = selfcol_alloc__raw(&allocator, sizeof *h);
    if (h == NULL)
        return SELFCOL_ENOMEM;
    h->allocator = allocator;
    h->mesh = mesh;
    *out = h;
    return SELFCOL_OK;
}

void selfcol_hierarchy_destroy(selfcol_hierarchy *hierarchy) {
    if (hierarchy == NULL)
        return;
    selfcol_allocator allocator = hierarchy->allocator;
    selfcol_alloc__free(&allocator, hierarchy, sizeof *hierarchy);
}

const selfcol_mesh *selfcol_hierarchy_mesh(const selfcol_hierarchy *hierarchy) {
    return hierarchy != NULL ? hierarchy->mesh : NULL;
}

size_t selfcol_hierarchy_byte_count(const selfcol_hierarchy *hierarchy) {
    return hierarchy != NULL ? sizeof *hierarchy : 0;
}
