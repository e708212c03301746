// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact set: the result of a query (its records and statistics). The
// query context that the functions without one use (query.c makes it at
// their first call) is kept beside the result, not in it: the result's
// code never reads it.
#ifndef SELFCOL_CONTACTS_INTERNAL_H
#define SELFCOL_CONTACTS_INTERNAL_H

#include <selfcol/contacts.h>
#include <selfcol/context.h>

#include "query/records.h"

struct selfcol_contacts {
    selfcol_records records;
    // The one-thread context of the calls given none
    // (selfcol_hierarchy_self_collide, sequences, scenes without one): NULL
    // until the first, which makes it.
    selfcol_context *implicit_context;
    // The intersecting triangle pairs derived from the records
    // (selfcol_contacts_intersecting_triangles), valid while the records'
    // generation is pair_generation + 1 (0: never derived): 2 per pair;
    // pair_keys is their sort's workspace (2 * capacity keys).
    uint32_t *pairs;
    uint64_t *pair_keys;
    size_t pair_count, pair_capacity;
    uint64_t pair_generation;
};

#endif // SELFCOL_CONTACTS_INTERNAL_H
