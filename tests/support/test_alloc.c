// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "test_alloc.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

// Header stored before the aligned block: where the real block starts and the
// size the library asked for (checked again at free).
typedef struct block_header {
    void *raw;
    size_t size;
} block_header;

static void *hook_alloc(void *user, size_t size, size_t alignment) {
    test_allocator_state *state = user;
    state->calls++;
    if (state->fail_at > 0 && state->calls == state->fail_at)
        return NULL;
    unsigned char *raw = test_malloc(size + alignment + sizeof(block_header));
    if (raw == NULL)
        return NULL;
    uintptr_t start = (uintptr_t)(raw + sizeof(block_header));
    uintptr_t aligned = (start + alignment - 1) & ~(uintptr_t)(alignment - 1);
    block_header *h = (block_header *)(aligned - sizeof(block_header));
    h->raw = raw;
    h->size = size;
    state->live++;
    state->live_bytes += size;
    if (state->live_bytes > state->peak_bytes)
        state->peak_bytes = state->live_bytes;
    return (void *)aligned;
}

static void hook_free(void *user, void *ptr, size_t size) {
    test_allocator_state *state = user;
    block_header *h = (block_header *)((unsigned char *)ptr - sizeof(block_header));
    if (h->size != size)
        state->misaligned = 1;
    state->live--;
    state->live_bytes -= h->size;
    test_free(h->raw);
}

selfcol_allocator test_allocator(test_allocator_state *state) {
    selfcol_allocator a;
    a.alloc = hook_alloc;
    a.free = hook_free;
    a.user = state;
    return a;
}

static void *pool_alloc(void *user, size_t size, size_t alignment) {
    reuse_pool *p = user;
    for (int i = p->count - 1; i >= 0; --i)
        if (p->size[i] == size) {
            void *b = p->block[i];
            memmove(&p->block[i], &p->block[i + 1], (size_t)(p->count - i - 1) * sizeof(void *));
            memmove(&p->size[i], &p->size[i + 1], (size_t)(p->count - i - 1) * sizeof(size_t));
            p->count--;
            return b;
        }
    (void)alignment; // malloc's alignment covers every request of the library
    return malloc(size);
}

static void pool_free(void *user, void *ptr, size_t size) {
    reuse_pool *p = user;
    if (p->count == 64) {
        free(ptr);
        return;
    }
    p->block[p->count] = ptr;
    p->size[p->count] = size;
    p->count++;
}

selfcol_allocator reuse_pool_allocator(reuse_pool *pool) {
    selfcol_allocator a = {pool_alloc, pool_free, pool};
    return a;
}

void reuse_pool_release(reuse_pool *pool) {
    for (int i = 0; i < pool->count; ++i)
        free(pool->block[i]);
    pool->count = 0;
}
