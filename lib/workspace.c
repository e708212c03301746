// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "workspace.h"

#include "alloc.h"

#include <selfcol/contacts.h>

#include <string.h>

void selfcol_workspace__init(selfcol_workspace *w, const selfcol_allocator *allocator) {
    memset(w, 0, sizeof *w);
    w->allocator = *allocator;
}

void selfcol_workspace__free(selfcol_workspace *w) {
    for (unsigned i = 0; i < w->worker_count; ++i)
        selfcol_contacts_destroy(w->workers[i]);
    selfcol_alloc__free_array(&w->allocator, w->workers, w->worker_count, sizeof *w->workers);
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        selfcol_alloc__free(&w->allocator, w->buffer[i], w->bytes[i]);
    selfcol_allocator allocator = w->allocator;
    selfcol_workspace__init(w, &allocator);
}

size_t selfcol_workspace__byte_count(const selfcol_workspace *w) {
    size_t bytes = w->worker_count * sizeof *w->workers;
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        bytes += w->bytes[i];
    for (unsigned i = 0; i < w->worker_count; ++i)
        bytes += selfcol_contacts_byte_count(w->workers[i]);
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

struct selfcol_contacts *selfcol_workspace__worker(selfcol_workspace *w, unsigned index) {
    if (index > w->worker_count) {
        selfcol_contacts **grown = selfcol_alloc__array(&w->allocator, index, sizeof *grown);
        if (grown == NULL)
            return NULL;
        for (unsigned i = 0; i < index; ++i)
            grown[i] = i < w->worker_count ? w->workers[i] : NULL;
        selfcol_alloc__free_array(&w->allocator, w->workers, w->worker_count, sizeof *grown);
        w->workers = grown;
        w->worker_count = index;
    }
    if (w->workers[index - 1] == NULL) {
        selfcol_contacts_options opts;
        selfcol_contacts_options_init(&opts, SELFCOL_CONTACTS_OPTIONS_VERSION);
        opts.allocator = w->allocator;
        if (selfcol_contacts_create(&w->workers[index - 1], &opts) != SELFCOL_OK)
            return NULL;
    }
    selfcol_contacts_clear(w->workers[index - 1]);
    return w->workers[index - 1];
}
