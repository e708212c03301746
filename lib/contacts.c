// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "contacts.h"

#include "alloc.h"
#include "core.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

int selfcol_contacts_options_init(selfcol_contacts_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_CONTACTS_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

int selfcol_contacts_create(selfcol_contacts **out, const selfcol_contacts_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK_VERSION(opts, SELFCOL_CONTACTS_OPTIONS_VERSION);
    selfcol_allocator allocator = {NULL, NULL, NULL};
    if (opts != NULL)
        allocator = opts->allocator;
    SELFCOL_CHECK(selfcol_alloc__valid(&allocator));
    selfcol_contacts *c = selfcol_alloc__raw(&allocator, sizeof *c);
    if (c == NULL)
        return SELFCOL_ENOMEM;
    memset(c, 0, sizeof *c);
    c->allocator = allocator;
    c->stats.version = SELFCOL_QUERY_STATS_VERSION;
    *out = c;
    return SELFCOL_OK;
}

void selfcol_contacts_destroy(selfcol_contacts *contacts) {
    if (contacts == NULL)
        return;
    selfcol_allocator allocator = contacts->allocator;
    selfcol_alloc__free_array(&allocator, contacts->items, contacts->capacity,
                              sizeof(selfcol_contact));
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        selfcol_alloc__free(&allocator, contacts->scratch[i], contacts->scratch_bytes[i]);
    selfcol_alloc__free(&allocator, contacts, sizeof *contacts);
}

void selfcol_contacts_clear(selfcol_contacts *contacts) {
    if (contacts == NULL)
        return;
    contacts->count = 0;
    memset(&contacts->stats, 0, sizeof contacts->stats);
    contacts->stats.version = SELFCOL_QUERY_STATS_VERSION;
}

size_t selfcol_contacts_count(const selfcol_contacts *contacts) {
    return contacts != NULL ? contacts->count : 0;
}

int selfcol_contacts_data(const selfcol_contacts *contacts, const selfcol_contact **data_out,
                          size_t *count_out) {
    SELFCOL_CHECK(contacts != NULL && data_out != NULL && count_out != NULL);
    *data_out = contacts->count > 0 ? contacts->items : NULL;
    *count_out = contacts->count;
    return SELFCOL_OK;
}

int selfcol_contacts_stats(const selfcol_contacts *contacts, selfcol_query_stats *stats) {
    SELFCOL_CHECK(contacts != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_QUERY_STATS_VERSION)
        return SELFCOL_EVERSION;
    // Each version appends fields: copy only the prefix the caller's version
    // knows (its struct may be shorter than ours).
    static const size_t size_of_version[SELFCOL_QUERY_STATS_VERSION + 1] = {
        0, offsetof(selfcol_query_stats, nodes_visited),
        offsetof(selfcol_query_stats, contour_tests), sizeof(selfcol_query_stats)};
    unsigned int version = stats->version;
    memcpy(stats, &contacts->stats, size_of_version[version]);
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_contacts_byte_count(const selfcol_contacts *contacts) {
    if (contacts == NULL)
        return 0;
    size_t bytes = sizeof *contacts + contacts->capacity * sizeof(selfcol_contact);
    for (int i = 0; i < SELFCOL_SCRATCH_SLOTS; ++i)
        bytes += contacts->scratch_bytes[i];
    return bytes;
}

int selfcol_contacts__push(selfcol_contacts *c, const selfcol_contact *contact) {
    if (c->count == c->capacity) {
        size_t capacity = c->capacity < 64 ? 64 : 2 * c->capacity;
        selfcol_contact *items =
            selfcol_alloc__array(&c->allocator, capacity, sizeof(selfcol_contact));
        if (items == NULL)
            return SELFCOL_ENOMEM;
        if (c->count > 0)
            memcpy(items, c->items, c->count * sizeof(selfcol_contact));
        selfcol_alloc__free_array(&c->allocator, c->items, c->capacity, sizeof(selfcol_contact));
        c->items = items;
        c->capacity = capacity;
    }
    c->items[c->count++] = *contact;
    return SELFCOL_OK;
}

void *selfcol_contacts__scratch(selfcol_contacts *c, int slot, size_t bytes, size_t keep) {
    if (bytes <= c->scratch_bytes[slot])
        return c->scratch[slot];
    // Grow geometrically so a stack or list grown one step at a time costs
    // amortised O(1) per step.
    size_t size = c->scratch_bytes[slot] * 2 > bytes ? c->scratch_bytes[slot] * 2 : bytes;
    void *buffer = selfcol_alloc__raw(&c->allocator, size);
    if (buffer == NULL)
        return NULL;
    if (keep > 0)
        memcpy(buffer, c->scratch[slot], keep);
    selfcol_alloc__free(&c->allocator, c->scratch[slot], c->scratch_bytes[slot]);
    c->scratch[slot] = buffer;
    c->scratch_bytes[slot] = size;
    return buffer;
}

static int contact_compare(const void *pa, const void *pb) {
    const selfcol_contact *a = pa, *b = pb;
    const uint32_t ka[5] = {a->kind, a->first_mesh, a->first, a->second_mesh, a->second};
    const uint32_t kb[5] = {b->kind, b->first_mesh, b->first, b->second_mesh, b->second};
    for (int i = 0; i < 5; ++i)
        if (ka[i] != kb[i])
            return ka[i] < kb[i] ? -1 : 1;
    return 0;
}

void selfcol_contacts__sort(selfcol_contacts *c) {
    for (size_t i = 1; i < c->count; ++i) {
        if (contact_compare(&c->items[i - 1], &c->items[i]) > 0) {
            qsort(c->items, c->count, sizeof(selfcol_contact), contact_compare);
            return;
        }
    }
}
