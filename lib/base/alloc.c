// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The default allocator over-allocates and aligns by hand: C99 has no
// aligned_alloc, and posix_memalign is not C99. The offset to the block is kept
// just before the aligned pointer.
#include "base/alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static void *default_alloc(size_t size, size_t alignment) {
    if (size > SIZE_MAX - alignment - sizeof(size_t))
        return NULL;
    unsigned char *block = malloc(size + alignment + sizeof(size_t));
    if (block == NULL)
        return NULL;
    uintptr_t start = (uintptr_t)(block + sizeof(size_t));
    uintptr_t aligned = (start + (alignment - 1)) & ~(uintptr_t)(alignment - 1);
    size_t offset = (size_t)(aligned - (uintptr_t)block);
    unsigned char *result = block + offset;
    ((size_t *)(void *)result)[-1] = offset;
    return result;
}

// realloc keeps the block's bytes but not necessarily their alignment: the
// used bytes move to the new block's aligned start when it differs.
static void *default_grow(void *ptr, size_t used_bytes, size_t size, size_t alignment) {
    if (size > SIZE_MAX - alignment - sizeof(size_t))
        return NULL;
    const size_t offset = ((size_t *)ptr)[-1];
    unsigned char *block =
        realloc((unsigned char *)ptr - offset, size + alignment + sizeof(size_t));
    if (block == NULL)
        return NULL;
    uintptr_t start = (uintptr_t)(block + sizeof(size_t));
    uintptr_t aligned = (start + (alignment - 1)) & ~(uintptr_t)(alignment - 1);
    const size_t moved = (size_t)(aligned - (uintptr_t)block);
    if (moved != offset)
        memmove(block + moved, block + offset, used_bytes);
    unsigned char *result = block + moved;
    ((size_t *)(void *)result)[-1] = moved;
    return result;
}

static void default_free(void *ptr) {
    unsigned char *p = ptr;
    size_t offset = ((size_t *)ptr)[-1];
    free(p - offset);
}

int selfcol_alloc__valid(const selfcol_allocator *allocator) {
    if (allocator == NULL)
        return 1;
    return (allocator->alloc == NULL) == (allocator->free == NULL);
}

void *selfcol_alloc__raw(const selfcol_allocator *allocator, size_t size) {
    if (size == 0)
        return NULL;
    if (allocator != NULL && allocator->alloc != NULL)
        return allocator->alloc(allocator->user, size, SELFCOL_ALIGNMENT);
    return default_alloc(size, SELFCOL_ALIGNMENT);
}

void *selfcol_alloc__array(const selfcol_allocator *allocator, size_t count, size_t size) {
    if (count == 0 || size == 0 || count > SIZE_MAX / size)
        return NULL;
    return selfcol_alloc__raw(allocator, count * size);
}

void selfcol_alloc__free(const selfcol_allocator *allocator, void *ptr, size_t size) {
    if (ptr == NULL)
        return;
    if (allocator != NULL && allocator->free != NULL)
        allocator->free(allocator->user, ptr, size);
    else
        default_free(ptr);
}

void selfcol_alloc__free_array(const selfcol_allocator *allocator, void *ptr, size_t count,
                               size_t size) {
    selfcol_alloc__free(allocator, ptr, count * size);
}

void *selfcol_alloc__grow_array(const selfcol_allocator *allocator, void *ptr, size_t used,
                                size_t old_count, size_t new_count, size_t size) {
    if (new_count == 0 || size == 0 || new_count > SIZE_MAX / size || used > old_count ||
        old_count > new_count)
        return NULL;
    if (ptr != NULL && (allocator == NULL || allocator->alloc == NULL))
        return default_grow(ptr, used * size, new_count * size, SELFCOL_ALIGNMENT);
    void *grown = selfcol_alloc__array(allocator, new_count, size);
    if (grown == NULL)
        return NULL;
    if (used > 0)
        memcpy(grown, ptr, used * size);
    selfcol_alloc__free_array(allocator, ptr, old_count, size);
    return grown;
}
