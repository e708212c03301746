// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A selfcol_allocator backed by cmocka's test_malloc/test_free, so cmocka
// reports leaks and overruns, aligning by hand (test_malloc only aligns to
// sizeof(size_t)); it can be told to fail at the Nth allocation to drive every
// SELFCOL_ENOMEM path.
#ifndef SELFCOL_TEST_ALLOC_H
#define SELFCOL_TEST_ALLOC_H

#include <selfcol/common.h>

typedef struct test_allocator_state {
    long fail_at; // 1-based allocation number that fails; 0: never
    long calls;   // allocations attempted so far
    long live;    // allocations not yet freed
    size_t live_bytes;
    size_t peak_bytes; // largest live_bytes seen (reset it to measure one call)
    int misaligned;    // set if a free came with a size different from its alloc
} test_allocator_state;

// Returns an allocator bound to state (which the caller zero-initialises).
selfcol_allocator test_allocator(test_allocator_state *state);

// A pooling allocator that hands the last freed block of a size straight
// back (a stack, as size-class free lists and often glibc behave), so that a
// mesh created after one is destroyed lives at the destroyed mesh's address.
// 64 slots hold every block one mesh frees, so none of them falls through to
// free() and the reuse does not depend on the build. Zero-initialise it.
typedef struct reuse_pool {
    void *block[64];
    size_t size[64];
    int count;
} reuse_pool;

selfcol_allocator reuse_pool_allocator(reuse_pool *pool);
// Frees the blocks the pool holds.
void reuse_pool_release(reuse_pool *pool);

#endif
