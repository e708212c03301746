// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Working memory, kept from call to call so that a steady state allocates
// nothing. zstd's ZSTD_cwksp is the model: what the stages of a query need
// while it runs (the traversal stack, contour.c's work area, the
// per-triangle frames and their stamps, the sort keys, the tasks handed to
// threads) lives here, apart from what the query returns (records.h). A
// query context (context.h) holds one for the calling thread and one per
// extra worker; a continuous query's handle holds its own (sweep.h).
#ifndef SELFCOL_WORKSPACE_H
#define SELFCOL_WORKSPACE_H

#include <selfcol/common.h>

#include <stddef.h>
#include <stdint.h>

// The buffers, one per use.
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

typedef struct selfcol_workspace {
    selfcol_allocator allocator;
    void *buffer[SELFCOL_SCRATCH_SLOTS];
    size_t bytes[SELFCOL_SCRATCH_SLOTS];
    uint32_t serial; // bumped by every hierarchy query: validates the leaf stamps
} selfcol_workspace;

// An empty workspace that allocates with `allocator` (copied).
void selfcol_workspace__init(selfcol_workspace *w, const selfcol_allocator *allocator);

// Frees every buffer; w is then empty.
void selfcol_workspace__free(selfcol_workspace *w);

// The bytes held.
size_t selfcol_workspace__byte_count(const selfcol_workspace *w);

// Buffer `slot` with at least `bytes` (aligned to SELFCOL_ALIGNMENT), kept
// and reused by later calls. When it has to grow, the first `keep` bytes of
// its old content are copied. NULL on allocation failure (the old buffer
// stays valid).
void *selfcol_workspace__buffer(selfcol_workspace *w, int slot, size_t bytes, size_t keep);

#endif // SELFCOL_WORKSPACE_H
