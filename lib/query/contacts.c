// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "query/contacts.h"

#include "base/alloc.h"
#include "base/core.h"
#include "mesh/mesh.h"

#include <stddef.h>
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
    selfcol_records__init(&c->records, &allocator);
    *out = c;
    return SELFCOL_OK;
}

void selfcol_contacts_destroy(selfcol_contacts *contacts) {
    if (contacts == NULL)
        return;
    selfcol_allocator allocator = contacts->records.allocator;
    selfcol_context_destroy(contacts->implicit_context);
    selfcol_alloc__free_array(&allocator, contacts->pairs, 2 * contacts->pair_capacity,
                              sizeof(uint32_t));
    selfcol_alloc__free_array(&allocator, contacts->pair_keys, 2 * contacts->pair_capacity,
                              sizeof(uint64_t));
    selfcol_records__free(&contacts->records);
    selfcol_alloc__free(&allocator, contacts, sizeof *contacts);
}

void selfcol_contacts_clear(selfcol_contacts *contacts) {
    if (contacts != NULL)
        selfcol_records__clear(&contacts->records);
}

size_t selfcol_contacts_count(const selfcol_contacts *contacts) {
    return contacts != NULL ? contacts->records.count : 0;
}

int selfcol_contacts_data(const selfcol_contacts *contacts, const selfcol_contact **data_out,
                          size_t *count_out) {
    SELFCOL_CHECK(contacts != NULL && data_out != NULL && count_out != NULL);
    *data_out = contacts->records.count > 0 ? contacts->records.items : NULL;
    *count_out = contacts->records.count;
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
        offsetof(selfcol_query_stats, contour_tests),
        offsetof(selfcol_query_stats, pairs_separated), sizeof(selfcol_query_stats)};
    unsigned int version = stats->version;
    memcpy(stats, &contacts->records.stats, size_of_version[version]);
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_contacts_byte_count(const selfcol_contacts *contacts) {
    if (contacts == NULL)
        return 0;
    size_t bytes = sizeof *contacts + selfcol_records__byte_count(&contacts->records) +
                   contacts->pair_capacity * 2 * (sizeof(uint32_t) + sizeof(uint64_t));
    return bytes + selfcol_context_byte_count(contacts->implicit_context);
}

// ---------------------------------------------------------------------------
// Intersecting triangle pairs (contacts.h)

// Keys (a << 32 | b) sorted by an LSD radix sort of 11-bit digits (16 kB of
// counts on the stack), a pass whose digit is the same for every key
// skipped (a mesh under 2048 triangles needs 2 of the 6): O(n), into
// `keys` (other: n more).
#define PAIR_DIGIT_BITS 11
#define PAIR_DIGITS (1u << PAIR_DIGIT_BITS)
static void sort_keys(uint64_t *keys, uint64_t *other, size_t n) {
    size_t count[PAIR_DIGITS];
    for (int shift = 0; shift < 64; shift += PAIR_DIGIT_BITS) {
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; ++i)
            count[(keys[i] >> shift) & (PAIR_DIGITS - 1u)]++;
        if (count[(keys[0] >> shift) & (PAIR_DIGITS - 1u)] == n)
            continue;
        size_t sum = 0;
        for (size_t d = 0; d < PAIR_DIGITS; ++d) {
            const size_t here = count[d];
            count[d] = sum;
            sum += here;
        }
        for (size_t i = 0; i < n; ++i)
            other[count[(keys[i] >> shift) & (PAIR_DIGITS - 1u)]++] = keys[i];
        memcpy(keys, other, n * sizeof *keys);
    }
}

static int reserve_pairs(selfcol_contacts *c, size_t n) {
    if (n <= c->pair_capacity)
        return SELFCOL_OK;
    const selfcol_allocator *al = &c->records.allocator;
    size_t cap = c->pair_capacity * 2 > n ? c->pair_capacity * 2 : n;
    if (cap > SIZE_MAX / (2 * sizeof(uint64_t)))
        return SELFCOL_ENOMEM;
    uint32_t *pairs = selfcol_alloc__array(al, 2 * cap, sizeof *pairs);
    uint64_t *keys = selfcol_alloc__array(al, 2 * cap, sizeof *keys);
    if (pairs == NULL || keys == NULL) {
        selfcol_alloc__free_array(al, pairs, 2 * cap, sizeof *pairs);
        selfcol_alloc__free_array(al, keys, 2 * cap, sizeof *keys);
        return SELFCOL_ENOMEM;
    }
    selfcol_alloc__free_array(al, c->pairs, 2 * c->pair_capacity, sizeof *c->pairs);
    selfcol_alloc__free_array(al, c->pair_keys, 2 * c->pair_capacity, sizeof *c->pair_keys);
    c->pairs = pairs;
    c->pair_keys = keys;
    c->pair_capacity = cap;
    return SELFCOL_OK;
}

int selfcol_contacts_intersecting_triangles(selfcol_contacts *contacts, const selfcol_mesh *first,
                                            const selfcol_mesh *second, const uint32_t **pairs_out,
                                            size_t *count_out) {
    SELFCOL_CHECK(contacts != NULL && first != NULL && second != NULL && pairs_out != NULL &&
                  count_out != NULL);
    *pairs_out = NULL;
    *count_out = 0;
    const selfcol_records *r = &contacts->records;
    if (contacts->pair_generation != r->generation + 1) {
        const selfcol_mesh *const mesh[2] = {first, second};
        const int self = first == second;
        // Candidates first: one per triangle on each crossing edge.
        size_t n = 0;
        for (size_t i = 0; i < r->count; ++i) {
            const selfcol_contact *e = &r->items[i];
            if (e->kind != SELFCOL_CONTACT_EF)
                continue;
            const selfcol_mesh *me = mesh[e->first_mesh & 1u], *mt = mesh[e->second_mesh & 1u];
            SELFCOL_CHECK(e->first < me->edge_count && e->second < mt->triangle_count);
            n += me->edge_tri_offsets[e->first + 1] - me->edge_tri_offsets[e->first];
        }
        if (reserve_pairs(contacts, n) != SELFCOL_OK)
            return SELFCOL_ENOMEM;
        uint64_t *keys = contacts->pair_keys;
        size_t k = 0;
        for (size_t i = 0; i < r->count; ++i) {
            const selfcol_contact *e = &r->items[i];
            if (e->kind != SELFCOL_CONTACT_EF)
                continue;
            const selfcol_mesh *me = mesh[e->first_mesh & 1u];
            for (uint32_t j = me->edge_tri_offsets[e->first];
                 j < me->edge_tri_offsets[e->first + 1]; ++j) {
                uint64_t a = me->edge_tris[j], b = e->second;
                if (self ? a == b : 0)
                    continue;
                if (self ? a > b : e->first_mesh != 0) { // (triangle of mesh 0, of mesh 1)
                    const uint64_t t = a;
                    a = b;
                    b = t;
                }
                keys[k++] = a << 32 | b;
            }
        }
        if (k > 1)
            sort_keys(keys, keys + contacts->pair_capacity, k);
        size_t unique = 0;
        for (size_t i = 0; i < k; ++i)
            if (unique == 0 || keys[i] != keys[unique - 1])
                keys[unique++] = keys[i];
        for (size_t i = 0; i < unique; ++i) {
            contacts->pairs[2 * i] = (uint32_t)(keys[i] >> 32);
            contacts->pairs[2 * i + 1] = (uint32_t)keys[i];
        }
        contacts->pair_count = unique;
        contacts->pair_generation = r->generation + 1;
    }
    *pairs_out = contacts->pair_count > 0 ? contacts->pairs : NULL;
    *count_out = contacts->pair_count;
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// Triangle classes (contacts.h)

static void raise_to(uint8_t *classes, uint32_t t, uint8_t c) {
    if (classes[t] < c)
        classes[t] = c;
}

static void raise_edge_faces(const selfcol_mesh *m, uint8_t *classes, uint32_t e, uint8_t c) {
    for (uint32_t j = m->edge_tri_offsets[e]; j < m->edge_tri_offsets[e + 1]; ++j)
        raise_to(classes, m->edge_tris[j], c);
}

int selfcol_contacts_triangle_classes(const selfcol_contacts *contacts, const selfcol_mesh *first,
                                      const selfcol_mesh *second, uint8_t *first_classes,
                                      uint8_t *second_classes) {
    SELFCOL_CHECK(contacts != NULL && first != NULL && second != NULL && first_classes != NULL);
    const int self = first == second;
    SELFCOL_CHECK(self || second_classes != NULL);
    const selfcol_mesh *const mesh[2] = {first, second};
    uint8_t *const classes[2] = {first_classes, self ? first_classes : second_classes};
    const selfcol_records *r = &contacts->records;
    for (size_t i = 0; i < r->count; ++i) {
        const selfcol_contact *c = &r->items[i];
        const unsigned mf = c->first_mesh & 1u, ms = c->second_mesh & 1u;
        const selfcol_mesh *a = mesh[mf], *b = mesh[ms];
        if (c->kind == SELFCOL_CONTACT_VF) {
            SELFCOL_CHECK(c->first < a->vertex_count && c->second < b->triangle_count);
            raise_to(classes[ms], c->second, SELFCOL_TRIANGLE_NEAR);
            for (uint32_t j = a->vertex_tri_offsets[c->first];
                 j < a->vertex_tri_offsets[c->first + 1]; ++j)
                raise_to(classes[mf], a->vertex_tris[j], SELFCOL_TRIANGLE_NEAR);
        } else if (c->kind == SELFCOL_CONTACT_EE) {
            SELFCOL_CHECK(c->first < a->edge_count && c->second < b->edge_count);
            raise_edge_faces(a, classes[mf], c->first, SELFCOL_TRIANGLE_NEAR);
            raise_edge_faces(b, classes[ms], c->second, SELFCOL_TRIANGLE_NEAR);
        } else {
            SELFCOL_CHECK(c->first < a->edge_count && c->second < b->triangle_count);
            raise_to(classes[ms], c->second, SELFCOL_TRIANGLE_INTERSECTING);
            raise_edge_faces(a, classes[mf], c->first, SELFCOL_TRIANGLE_INTERSECTING);
        }
    }
    return SELFCOL_OK;
}
