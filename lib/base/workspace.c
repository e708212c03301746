// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "base/workspace.h"

#include "base/alloc.h"

#include <string.h>

void selfcol_workspace__init(selfcol_workspace *w, const selfcol_allocator *allocator) {
    memset(w, 0, sizeof *w);
    w->allocator = *allocator;
}

void selfcol_workspace__free(selfcol_workspace *w) {
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        selfcol_alloc__free(&w->allocator, w->buffer[i], w->bytes[i]);
    selfcol_allocator allocator = w->allocator;
    selfcol_workspace__init(w, &allocator);
}

size_t selfcol_workspace__byte_count(const selfcol_workspace *w) {
    size_t bytes = 0;
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        bytes += w->bytes[i];
    return bytes;
}

void *selfcol_workspace__buffer(selfcol_workspace *w, int slot, size_t bytes, size_t keep) {
    if (bytes <= w->bytes[slot])
        return w->buffer[slot];
    // Grow geometrically so a stack or list grown one step at a time costs
    // amortised O(1) per step.
    size_t size = w->bytes[slot] * 2 > bytes ? w->bytes[slot] * 2 : bytes;
    void *buffer = selfcol_alloc__raw(&w->allocator, size);
    if (buffer == NULL)
        return NULL;
    if (keep > 0)
        memcpy(buffer, w->buffer[slot], keep);
    selfcol_alloc__free(&w->allocator, w->buffer[slot], w->bytes[slot]);
    w->buffer[slot] = buffer;
    w->bytes[slot] = size;
    return buffer;
}
