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
    // The context of the calls given none (selfcol_hierarchy_self_collide,
    // sequences, scenes): NULL until the first, which makes one (owned), or
    // one a scene lent (selfcol_scene_set_context: borrowed, its threads and
    // scheduler used as they are).
    selfcol_context *implicit_context;
    int context_borrowed;
};

// Lends `context` (NULL: none) to the calls filling `contacts` without one;
// a context the set made itself is freed first.
void selfcol_contacts__lend_context(selfcol_contacts *contacts, selfcol_context *context);

#endif // SELFCOL_CONTACTS_INTERNAL_H
