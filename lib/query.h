// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A collision query in progress: which meshes, which distance and contact
// kinds, which narrow phase, and where contacts go. Every search method
// (exhaustive.c, traverse.c) feeds primitive pairs to the
// selfcol_pairs__* functions of pairs.c, so exclusion rules, the narrow-phase
// choice and record filling exist once.
#ifndef SELFCOL_QUERY_H
#define SELFCOL_QUERY_H

#include "contacts.h"
#include "mesh.h"

typedef struct selfcol_query {
    const selfcol_mesh *mesh[2]; // mesh[1] == mesh[0] for a self query
    int self;
    double distance;
    uint32_t kinds;
    uint32_t narrow;
    double ccd_tolerance; // absolute tolerance for libccd (relative to the distance)
    selfcol_contacts *out;
} selfcol_query;

// Primitive-pair tests (pairs.c). Vertex v of mesh[mv] against triangle t of
// mesh[mt]; the caller guarantees (for self queries) that v is not a corner
// of t. A hit becomes a record.
int selfcol_pairs__test_vf(selfcol_query *q, int mv, uint32_t v, int mt, uint32_t t);
// Edge e of mesh[me] against edge f of mesh[mf]; no shared vertex for self.
int selfcol_pairs__test_ee(selfcol_query *q, int me, uint32_t e, int mf, uint32_t f);
// Edge e of mesh[me] against triangle t of mesh[mt]; no shared vertex for self.
int selfcol_pairs__test_ef(selfcol_query *q, int me, uint32_t e, int mt, uint32_t t);

// What the pair tests read of a triangle, computed once per query and
// triangle (lazily, for the leaves the traversal reaches): its box and its
// unnormalised normal (p1 - p0) x (p2 - p0) in the triangle's own winding,
// with the computed length and the scale of its rounding error (pairs.c).
typedef struct selfcol_tri_frame {
    double lo[3], hi[3];
    double normal[3];
    double length;
    double abs_max;
} selfcol_tri_frame;

void selfcol_pairs__frame(selfcol_tri_frame *frame, const selfcol_mesh *mesh, uint32_t triangle);

struct selfcol_hierarchy;

// One side of a traversal: the hierarchy and the frame data of its triangle
// slots (indexed like tri_order).
typedef struct selfcol_pair_source {
    const struct selfcol_hierarchy *hierarchy;
    const selfcol_tri_frame *frames;
} selfcol_pair_source;

// A candidate triangle pair, as slots of the two hierarchies' tri_order.
typedef struct selfcol_slot_pair {
    uint32_t a, b;
} selfcol_slot_pair;

// The narrow phase over a candidate list: every primitive pair the triangle
// pairs own, through the filter cascade, into records.
int selfcol_pairs__run(selfcol_query *q, const selfcol_pair_source source[2],
                       const selfcol_slot_pair *pairs, size_t count);

// The exhaustive reference (exhaustive.c).
int selfcol_exhaustive__run(selfcol_query *q);

// The hierarchy traversal (traverse.c) for methods BVH, SEED, CONE and
// EXACT; for a self query h1 == h0.
int selfcol_traverse__run(selfcol_query *q, const struct selfcol_hierarchy *h0,
                          const struct selfcol_hierarchy *h1, uint32_t method);

// EXACT's criterion (contour.c): 1 when Self(node id) provably holds no
// contact at distance d. Uses scratch slot 2 of `scratch_owner`.
int selfcol_contour__self_skippable(const struct selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_contacts *scratch_owner);

// The same for Pair(a, b) of two nodes of one hierarchy: 1 when no primitive
// of a has a contact with a primitive of b (judged on the union of the two
// patches, joined along shared edges). Uses scratch slot 2.
int selfcol_contour__pair_skippable(const struct selfcol_hierarchy *h, uint32_t a, uint32_t b,
                                    double d, selfcol_contacts *scratch_owner);

#endif // SELFCOL_QUERY_H
