// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#ifndef SELFCOL_TRAVERSE_H
#define SELFCOL_TRAVERSE_H

#include "hierarchy/hierarchy.h"
#include "query/query.h"

// The hierarchy traversal (traverse.c) for methods BVH, SEED, CONE and
// EXACT; for a self query h1 == h0. With the context's threads > 1, the
// traversal and pair tests run on up to that many of its workers, whose
// records the context's sort then takes in (context.h: pending_workers).
int selfcol_traverse__run(selfcol_query *q, const selfcol_hierarchy *h0,
                          const selfcol_hierarchy *h1, uint32_t method, selfcol_context *context);

#endif // SELFCOL_TRAVERSE_H
