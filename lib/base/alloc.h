// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Every allocation of the core goes through these functions, with the
// allocator of the handle that owns the memory (per-handle allocator hooks,
// docs/architecture.md). A bare malloc anywhere else in lib/ is a CI
// failure.
#ifndef SELFCOL_ALLOC_H
#define SELFCOL_ALLOC_H

#include <selfcol/common.h>

// Default alignment: enough for any scalar and for 32-byte SIMD loads.
#define SELFCOL_ALIGNMENT 32

// Returns 1 when the allocator is usable: both hooks set, or both NULL.
int selfcol_alloc__valid(const selfcol_allocator *allocator);

// Allocates size bytes (size 0 returns NULL without calling the hook).
void *selfcol_alloc__raw(const selfcol_allocator *allocator, size_t size);
// Allocates count * size bytes, NULL on overflow or failure (count 0: NULL).
void *selfcol_alloc__array(const selfcol_allocator *allocator, size_t count, size_t size);
// Frees ptr of size bytes as allocated; NULL is accepted.
void selfcol_alloc__free(const selfcol_allocator *allocator, void *ptr, size_t size);
// Frees an array allocated with selfcol_alloc__array(allocator, count, size).
void selfcol_alloc__free_array(const selfcol_allocator *allocator, void *ptr, size_t count,
                               size_t size);

// Grows an array of old_count elements (ptr, from selfcol_alloc__array; NULL
// when old_count is 0) to new_count >= old_count, keeping its first `used`
// elements; returns the new array, or NULL with ptr untouched and still
// owned by the caller. The default allocator grows in place through
// realloc (glibc moves a large block by remapping its pages: no copy and
// no page touched again); a caller's allocator gets a new block, a copy of
// the used elements and the old block's free.
void *selfcol_alloc__grow_array(const selfcol_allocator *allocator, void *ptr, size_t used,
                                size_t old_count, size_t new_count, size_t size);

#endif // SELFCOL_ALLOC_H
