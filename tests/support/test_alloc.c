// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "test_alloc.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

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
