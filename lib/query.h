// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A collision query in progress: which meshes, which distance and contact
// kinds, which narrow phase, and where contacts go. Every search method
// (exhaustive.h, traverse.h) feeds primitive pairs to the selfcol_pairs__*
// functions of pairs.h, so exclusion rules, the narrow-phase choice and
// record filling exist once; EXACT's criterion is contour.h.
#ifndef SELFCOL_QUERY_H
#define SELFCOL_QUERY_H

#include <selfcol/hierarchy.h>

#include "contacts.h"
#include "mesh.h"

typedef struct selfcol_query {
    const selfcol_mesh *mesh[2]; // mesh[1] == mesh[0] for a self query
    int self;
    double distance;
    uint32_t kinds;
    uint32_t narrow;
    double ccd_tolerance; // absolute tolerance for libccd (relative to the distance)
    selfcol_contacts *out;
} selfcol_query;

// Reads a caller's query options (NULL: the defaults) as their version says
// into a copy of the current version, and checks every field: SELFCOL_OK,
// SELFCOL_EVERSION or SELFCOL_EINVAL. Every user of query options (queries,
// scenes, adapters through scenes) goes through it.
int selfcol_query__options(selfcol_query_options *out, const selfcol_query_options *opts);

#endif // SELFCOL_QUERY_H
