// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// EXACT's contour criterion (contour.c): conditions (2) and (4) of the
// curvature criterion on projected boundary loops.
#ifndef SELFCOL_CONTOUR_H
#define SELFCOL_CONTOUR_H

#include "hierarchy.h"
#include "query.h"

// Conditions (2) and (4) of EXACT's criterion alone (contour.c), for the
// direct tests: 1 when the closed loop of boundary half-edges
// ((edge << 1) | reversed, in loop order) projected along the unit vector v
// is a simple polygon whose vertices are at least d from every edge not
// incident to them (conservatively: a clearance within about 1e-9 d refuses).
// 0 also without memory. Uses scratch slot SELFCOL_SCRATCH_CONTOUR.
// `strategy` picks how the candidate edge pairs are found; every strategy
// examines the same pairs, so the answer never depends on it (the tests
// compare them).
enum {
    SELFCOL_CONTOUR_AUTO = 0,      // all pairs for short boundaries, else the grid
    SELFCOL_CONTOUR_GRID = 1,      // a hashed uniform grid, O(b) expected
    SELFCOL_CONTOUR_ALL_PAIRS = 2, // every pair of edges, O(b^2)
};
int selfcol_contour__loop_clear(const selfcol_mesh *m, const uint32_t *half_edges, size_t count,
                                const double v[3], double d, int strategy,
                                selfcol_contacts *scratch_owner);

// EXACT's criterion (contour.c): 1 when Self(node id) provably holds no
// contact at distance d. Uses scratch slot SELFCOL_SCRATCH_CONTOUR of `scratch_owner`.
int selfcol_contour__self_skippable(const selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_contacts *scratch_owner);

// The same for Pair(a, b) of two nodes of one hierarchy: 1 when no primitive
// of a has a contact with a primitive of b (judged on the union of the two
// patches, joined along shared edges). Uses the same scratch slot.
int selfcol_contour__pair_skippable(const selfcol_hierarchy *h, uint32_t a, uint32_t b, double d,
                                    selfcol_contacts *scratch_owner);

#endif // SELFCOL_CONTOUR_H
