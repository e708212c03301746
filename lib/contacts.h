// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact set: a growable array of records and the statistics of the
// last query, plus the workspace (workspace.h) that the queries filling it
// reuse from frame to frame (no allocation in steady state).
#ifndef SELFCOL_CONTACTS_INTERNAL_H
#define SELFCOL_CONTACTS_INTERNAL_H

#include <selfcol/contacts.h>

#include "workspace.h"

struct selfcol_contacts {
    selfcol_allocator allocator;
    selfcol_contact *items;
    size_t count;
    size_t capacity;
    selfcol_contact *spare; // the sort's destination, swapped with items
    size_t spare_capacity;
    selfcol_workspace work;    // of the queries that fill this set
    selfcol_query_stats stats; // always the latest version
};

// Appends one record, growing geometrically. SELFCOL_OK or SELFCOL_ENOMEM.
int selfcol_contacts__push(selfcol_contacts *contacts, const selfcol_contact *contact);

// Sorts the records by (kind, first_mesh, first, second_mesh, second): an LSD
// radix sort of their keys, then one permutation of the records. O(n); no
// allocation once the spare buffer has grown. On up to `threads` threads
// (one per 65536 records at most), with the same order for every count.
// The records of the first contacts->work.pending_workers worker sets are
// taken in too (read where they lie, no copy first): they end in contacts,
// sorted with its own, and the worker sets empty.
// SELFCOL_OK or SELFCOL_ENOMEM (the records are then left unsorted, and
// the pending ones are lost: the caller clears the set).
int selfcol_contacts__sort(selfcol_contacts *contacts, unsigned threads);

// Adds a worker's counters (and contour time) to c's statistics; its
// records stay in the worker set until selfcol_contacts__sort takes them in
// (the workspace's pending_workers).
void selfcol_contacts__absorb_stats(selfcol_contacts *c, const selfcol_contacts *worker);

#endif // SELFCOL_CONTACTS_INTERNAL_H
