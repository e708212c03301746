// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Union-find over uint32_t parent arrays (parent[x] == x at a root), shared
// by the mesh's components, the hierarchy's triangle corners (fans) and the
// store's groups. Root lookup halves the path as it goes (Tarjan and van Leeuwen
// 1984); each caller links roots by its own rule (the store keeps the
// smaller index as the root, so groups are numbered by their first entry).
#ifndef SELFCOL_UNION_FIND_H
#define SELFCOL_UNION_FIND_H

#include <stdint.h>

static inline uint32_t selfcol_union_find__root(uint32_t *parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]]; // path halving
        x = parent[x];
    }
    return x;
}

#endif // SELFCOL_UNION_FIND_H
