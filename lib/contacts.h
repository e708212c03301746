// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact set: a growable array of records, the statistics of the last
// query, and a scratch buffer that queries reuse from frame to frame (no
// allocation in steady state).
#ifndef SELFCOL_CONTACTS_INTERNAL_H
#define SELFCOL_CONTACTS_INTERNAL_H

#include <selfcol/contacts.h>

// Scratch buffers kept by the contact set for the queries that fill it.
enum {
    SELFCOL_SCRATCH_STACK = 0,   // traversal stack; the exhaustive search's boxes
    SELFCOL_SCRATCH_CONTOUR = 1, // contour.c's work area
    SELFCOL_SCRATCH_FRAMES0 = 2, // per-triangle frame data, first hierarchy (by slot)
    SELFCOL_SCRATCH_FRAMES1 = 3, // the same, second hierarchy of a two-mesh query
    SELFCOL_SCRATCH_STAMPS0 = 4, // per-leaf: query serial at which its frames were computed
    SELFCOL_SCRATCH_STAMPS1 = 5,
    SELFCOL_SCRATCH_SORT = 6,  // radix-sort keys (two halves)
    SELFCOL_SCRATCH_TASKS = 7, // node pairs handed to the worker threads
    SELFCOL_SCRATCH_SLOTS = 8
};

struct selfcol_contacts {
    selfcol_allocator allocator;
    selfcol_contact *items;
    size_t count;
    size_t capacity;
    void *scratch[SELFCOL_SCRATCH_SLOTS];
    size_t scratch_bytes[SELFCOL_SCRATCH_SLOTS];
    selfcol_contact *spare; // the sort's destination, swapped with items
    size_t spare_capacity;
    uint32_t serial; // bumped by every hierarchy query: validates the leaf stamps
    // Records, statistics and scratch of the extra worker threads of a query
    // (selfcol_query_options.threads), kept so a steady state allocates nothing.
    struct selfcol_contacts **workers; // workers[w - 1] for worker w >= 1
    unsigned worker_count;
    selfcol_query_stats stats; // always the latest version
};

// Appends one record, growing geometrically. SELFCOL_OK or SELFCOL_ENOMEM.
int selfcol_contacts__push(selfcol_contacts *contacts, const selfcol_contact *contact);

// Returns scratch buffer `slot` with at least bytes (aligned to
// SELFCOL_ALIGNMENT), kept and reused by later calls. When it has to grow,
// the first `keep` bytes of its old content are copied. NULL on allocation
// failure (the old buffer stays valid).
void *selfcol_contacts__scratch(selfcol_contacts *contacts, int slot, size_t bytes, size_t keep);

// Sorts the records by (kind, first_mesh, first, second_mesh, second): an LSD
// radix sort of their keys, then one permutation of the records. O(n); no
// allocation once the spare buffer has grown. SELFCOL_OK or SELFCOL_ENOMEM
// (the records are then left unsorted).
int selfcol_contacts__sort(selfcol_contacts *contacts);

// The contact set of worker thread w >= 1 of the queries that fill c, created
// at first use with c's allocator and emptied here. NULL on allocation failure.
selfcol_contacts *selfcol_contacts__worker(selfcol_contacts *c, unsigned w);

// Appends worker's records to c and adds its counters (and contour time) to
// c's statistics. SELFCOL_OK or SELFCOL_ENOMEM (c then keeps its own records).
int selfcol_contacts__absorb(selfcol_contacts *c, const selfcol_contacts *worker);

#endif // SELFCOL_CONTACTS_INTERNAL_H
