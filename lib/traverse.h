// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#ifndef SELFCOL_TRAVERSE_H
#define SELFCOL_TRAVERSE_H

#include "hierarchy.h"
#include "query.h"

// The hierarchy traversal (traverse.c) for methods BVH, SEED, CONE and
// EXACT; for a self query h1 == h0. With threads > 1, the traversal and pair
// tests run on up to that many threads (the records then need sorting, as
// always).
int selfcol_traverse__run(selfcol_query *q, const selfcol_hierarchy *h0,
                          const selfcol_hierarchy *h1, uint32_t method, unsigned threads);

#endif // SELFCOL_TRAVERSE_H
