// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Records of a query: a growable array of contacts and the statistics of
// the query that wrote them. The caller's result (contacts.c) holds one,
// and each extra worker of a threaded query writes into one of its
// context's (context.h), which the sort then takes in where they lie.
#ifndef SELFCOL_RECORDS_H
#define SELFCOL_RECORDS_H

#include <selfcol/contacts.h>

#include "base/parallel.h"
#include "base/workspace.h"

typedef struct selfcol_records {
    selfcol_allocator allocator;
    selfcol_contact *items;
    size_t count;
    size_t capacity;
    selfcol_contact *spare; // the sort's destination, swapped with items
    size_t spare_capacity;
    selfcol_query_stats stats; // always the latest version
    uint64_t generation; // bumped by every clear: what was derived from older records is stale
} selfcol_records;

// Empty records that allocate with `allocator` (copied).
void selfcol_records__init(selfcol_records *r, const selfcol_allocator *allocator);

// Frees the arrays; r is then empty.
void selfcol_records__free(selfcol_records *r);

// No records, zeroed statistics; the memory is kept.
void selfcol_records__clear(selfcol_records *r);

// Bytes of the arrays.
size_t selfcol_records__byte_count(const selfcol_records *r);

// Appends one record, growing geometrically. SELFCOL_OK or SELFCOL_ENOMEM.
int selfcol_records__push(selfcol_records *r, const selfcol_contact *contact);

// Sorts the records by (kind, first_mesh, first, second_mesh, second): an LSD
// radix sort of their keys, then one permutation of the records. O(n); no
// allocation once the spare buffer and `work`'s sort slot have grown. On up
// to `threads` workers of `executor` (one per 65536 records at most, 16384 with a pool or a
// scheduler), with the same order for every count. The records of the `pending_count` sets in
// `pending` are taken in too (read where they lie, no copy first): they end in r, sorted with its
// own, and those sets are left empty. SELFCOL_OK or SELFCOL_ENOMEM (the records are then left
// unsorted, and the pending ones are lost: the caller clears r).
int selfcol_records__sort(selfcol_records *r, selfcol_records *const *pending,
                          unsigned pending_count, selfcol_workspace *work,
                          const selfcol_executor *executor, unsigned threads);

// Adds a worker's counters (and contour time) to r's statistics; the
// worker's records stay where they are until a sort takes them in.
void selfcol_records__absorb_stats(selfcol_records *r, const selfcol_records *worker);

#endif // SELFCOL_RECORDS_H
