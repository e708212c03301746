// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A collision query in progress: which meshes, which distance and contact
// kinds, which narrow phase, and where contacts go. Every search method
// (exhaustive.h, traverse.h) feeds primitive pairs to the selfcol_pairs__*
// functions of pairs.h, so exclusion rules, the narrow-phase choice and
// record filling exist once; EXACT's criterion is contour.h.
#ifndef SELFCOL_QUERY_H
#define SELFCOL_QUERY_H

#include "base/problem.h"
#include <selfcol/hierarchy.h>

#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/context.h"

// A restriction of a hierarchy traversal to some node pairs (the sequence's
// partial rebuild, sequence.c). keep(context, a, b) says whether node pair
// (a, b) of the two hierarchies (a == b in a self query: Self(a)) may hold a
// triangle pair the caller wants; the traversal drops the pairs it refuses,
// with everything under them. A refusal must hold for every pair of
// descendants too. Dropping node pairs only drops candidate triangle pairs,
// so the records are exactly those of the unrestricted query that come from
// triangle pairs under kept node pairs. EXHAUSTIVE ignores the filter (its
// records are then a superset, which such a caller must accept).
typedef struct selfcol_node_filter {
    int (*keep)(const void *context, uint32_t a, uint32_t b);
    const void *context;
} selfcol_node_filter;

typedef struct selfcol_query {
    const selfcol_mesh *mesh[2]; // mesh[1] == mesh[0] for a self query
    int self;
    double distance;
    uint32_t kinds;
    uint32_t narrow;
    double ccd_tolerance;              // absolute tolerance for libccd (relative to the distance)
    selfcol_records *out;              // this worker's records and statistics
    selfcol_workspace *work;           // this worker's working memory
    const selfcol_node_filter *filter; // NULL: every node pair
} selfcol_query;

// Reads a caller's query options (NULL: the defaults) as their version says
// into a copy of the current version, and checks every field: SELFCOL_OK,
// SELFCOL_EVERSION or SELFCOL_EINVAL. Every user of query options (queries,
// scenes, adapters through scenes) goes through it; `at` names a refused
// field (problem.h; NULL: the status only).
int selfcol_query__options(selfcol_query_options *out, const selfcol_query_options *opts,
                           const selfcol_problem_at *at);

// A query with options already checked by selfcol_query__options, restricted
// by `filter` (NULL: none), on the context's threads and working memory:
// what selfcol_hierarchy_self_collide (first
// == second) and selfcol_hierarchy_collide do after their checks. The sorted
// records go to `out` (cleared first); on failure it is left empty.
int selfcol_query__run(selfcol_context *context, const selfcol_hierarchy *first,
                       const selfcol_hierarchy *second, selfcol_records *out,
                       const selfcol_query_options *checked, const selfcol_node_filter *filter);

// The context that calls given none use for `contacts` (contacts.h): its
// own, made at the first call with the contact set's allocator, on one
// thread. NULL without memory.
selfcol_context *selfcol_query__implicit_context(selfcol_contacts *contacts);

#endif // SELFCOL_QUERY_H
