// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Contacts as canonical, index-order-free keys, to compare contact sets that
// come from different numberings of one surface or from different queries.
#ifndef SELFCOL_TEST_CONTACT_KEYS_H
#define SELFCOL_TEST_CONTACT_KEYS_H

#include <selfcol/selfcol.h>

// kind, then the first primitive's vertices (sorted, a vertex repeated), then
// the second's (sorted; an edge padded with UINT32_MAX).
typedef struct contact_key {
    uint32_t k[6];
} contact_key;

// Writes the keys of n contacts to out (sorted). Vertex v of mesh m becomes
// map[v] (identity when map is NULL) plus offset[m].
void contact_keys(const selfcol_contact *c, size_t n, const uint32_t *map, const uint32_t offset[2],
                  contact_key *out);

// Sorts keys.
void contact_keys_sort(contact_key *keys, size_t n);

// Keys of the contacts a handle holds (vertex indices as recorded, no offset),
// sorted; the caller frees them. Fails the running cmocka test on ENOMEM.
contact_key *contact_keys_of(const selfcol_contacts *contacts, size_t *n);

// 1 when the two sorted key lists are equal; otherwise prints the first
// difference (with print_error) and returns 0.
int contact_keys_equal(const contact_key *a, size_t na, const contact_key *b, size_t nb);

#endif
