// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "contact_keys.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdlib.h>

static void sort_small(uint32_t *v, int n) {
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && v[j] < v[j - 1]; --j) {
            uint32_t t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
}

static int key_compare(const void *pa, const void *pb) {
    const contact_key *a = pa, *b = pb;
    for (int i = 0; i < 6; ++i)
        if (a->k[i] != b->k[i])
            return a->k[i] < b->k[i] ? -1 : 1;
    return 0;
}

void contact_keys(const selfcol_contact *c, size_t n, const uint32_t *map, const uint32_t offset[2],
                  contact_key *out) {
    for (size_t i = 0; i < n; ++i) {
        uint32_t *k = out[i].k;
        k[0] = c[i].kind;
        for (int j = 0; j < 2; ++j)
            k[1 + j] = (map ? map[c[i].a[j]] : c[i].a[j]) + offset[c[i].first_mesh];
        int nb = c[i].kind == SELFCOL_CONTACT_EE ? 2 : 3;
        for (int j = 0; j < 3; ++j)
            k[3 + j] =
                j < nb ? (map ? map[c[i].b[j]] : c[i].b[j]) + offset[c[i].second_mesh] : UINT32_MAX;
        sort_small(k + 1, 2);
        sort_small(k + 3, nb);
        // An edge-edge pair is unordered.
        if (c[i].kind == SELFCOL_CONTACT_EE && (k[3] < k[1] || (k[3] == k[1] && k[4] < k[2]))) {
            uint32_t t0 = k[1], t1 = k[2];
            k[1] = k[3];
            k[2] = k[4];
            k[3] = t0;
            k[4] = t1;
        }
    }
    contact_keys_sort(out, n);
}

contact_key *contact_keys_of(const selfcol_contacts *contacts, size_t *n) {
    const selfcol_contact *c;
    assert_int_equal(selfcol_contacts_data(contacts, &c, n), SELFCOL_OK);
    contact_key *keys = malloc((*n + 1) * sizeof *keys);
    assert_non_null(keys);
    const uint32_t offset[2] = {0, 0};
    contact_keys(c, *n, NULL, offset, keys);
    return keys;
}

void contact_keys_sort(contact_key *keys, size_t n) {
    qsort(keys, n, sizeof *keys, key_compare);
}

int contact_keys_equal(const contact_key *a, size_t na, const contact_key *b, size_t nb) {
    size_t i = 0, j = 0;
    while (i < na || j < nb) {
        int cmp = i == na ? 1 : j == nb ? -1 : key_compare(&a[i], &b[j]);
        if (cmp != 0) {
            const contact_key *k = cmp < 0 ? &a[i] : &b[j];
            print_error("contact kind %u (%u %u | %u %u %u) only in the %s set (%zu vs %zu)\n",
                        k->k[0], k->k[1], k->k[2], k->k[3], k->k[4], k->k[5],
                        cmp < 0 ? "first" : "second", na, nb);
            return 0;
        }
        ++i;
        ++j;
    }
    return 1;
}
