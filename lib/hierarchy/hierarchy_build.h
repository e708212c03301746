// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The stages of the hierarchy build after the matching, and what the three
// files of the build share. selfcol_hierarchy__build (hierarchy_build.c)
// matches the triangles into a tree and lays it out, then calls, in order:
// selfcol_hierarchy__assign_owners and selfcol_hierarchy__orient
// (hierarchy_orient.c), then selfcol_hierarchy__build_boundaries
// (hierarchy_boundary.c). The tree is described to the later stages by three
// arrays of the layout, by final node index: parent (SELFCOL_INVALID_INDEX at
// the root), depth (0 at the root), and leaf_of_tri, the leaf of each
// triangle.
#ifndef SELFCOL_HIERARCHY_BUILD_H
#define SELFCOL_HIERARCHY_BUILD_H

#include "hierarchy/hierarchy.h"

// One owner triangle per vertex and per edge (SELFCOL_OWNS_* in owned).
void selfcol_hierarchy__assign_owners(selfcol_hierarchy *hierarchy);

// Flips triangles (SELFCOL_TRIANGLE_FLIPPED in owned) to orient every
// orientable component consistently, then sets SELFCOL_NODE_ORIENTED and
// SELFCOL_NODE_BAD_BOUNDARY on the nodes. queue and seen are scratch of one
// entry per triangle. SELFCOL_OK or SELFCOL_ENOMEM (nothing changed then).
int selfcol_hierarchy__orient(selfcol_hierarchy *hierarchy, const uint32_t *parent,
                              const uint32_t *depth, const uint32_t *leaf_of_tri, uint32_t *queue,
                              uint8_t *seen);

// The boundary half-edge lists of the internal nodes (bedge) and
// SELFCOL_NODE_DISK; needs the flips and flags of selfcol_hierarchy__orient.
// SELFCOL_OK or SELFCOL_ENOMEM.
int selfcol_hierarchy__build_boundaries(selfcol_hierarchy *hierarchy, const uint32_t *parent,
                                        const uint32_t *depth, const uint32_t *leaf_of_tri);

// Index of t in the ascending list a of n entries (t must be there).
static inline uint32_t selfcol_hierarchy__position_in(const uint32_t *a, uint32_t n, uint32_t t) {
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (a[mid] < t)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

// The slot (0, 1, 2) of edge e in triangle t (e must be one of its edges).
static inline int selfcol_hierarchy__slot_of_edge(const selfcol_mesh *m, uint32_t t, uint32_t e) {
    const uint32_t *te = m->triangle_edges + 3 * (size_t)t;
    return te[0] == e ? 0 : (te[1] == e ? 1 : 2);
}

#endif // SELFCOL_HIERARCHY_BUILD_H
