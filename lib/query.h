// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A collision query in progress: which meshes, which distance and contact
// kinds, which narrow phase, and where contacts go. Every search method
// (exhaustive.c, traverse.c) feeds primitive pairs to the
// selfcol_pairs__* functions of pairs.c, so exclusion rules, the narrow-phase
// choice and record filling exist once.
#ifndef SELFCOL_QUERY_H
#define SELFCOL_QUERY_H

#include <selfcol/hierarchy.h>

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

// Reads a caller's query options (NULL: the defaults) as their version says
// into a copy of the current version, and checks every field: SELFCOL_OK,
// SELFCOL_EVERSION or SELFCOL_EINVAL. Every user of query options (queries,
// scenes, adapters through scenes) goes through it.
int selfcol_query__options(selfcol_query_options *out, const selfcol_query_options *opts);

// Primitive-pair tests (pairs.c). Vertex v of mesh[mv] against triangle t of
// mesh[mt]; the caller guarantees (for self queries) that v is not a corner
// of t. A hit becomes a record.
int selfcol_pairs__test_vf(selfcol_query *q, int mv, uint32_t v, int mt, uint32_t t);
// Edge e of mesh[me] against edge f of mesh[mf]; no shared vertex for self.
int selfcol_pairs__test_ee(selfcol_query *q, int me, uint32_t e, int mf, uint32_t f);
// Edge e of mesh[me] against triangle t of mesh[mt]; no shared vertex for self.
int selfcol_pairs__test_ef(selfcol_query *q, int me, uint32_t e, int mt, uint32_t t);

// What the pair tests read of a triangle, computed once per query and
// triangle (lazily, for the leaves the traversal reaches) and laid out by
// hierarchy slot, so that a leaf pair reads contiguous memory instead of
// gathering from the mesh: its corners, box and unnormalised normal
// (p1 - p0) x (p2 - p0) in the triangle's own winding, with the computed
// length and the scale of its rounding error, and what it owns (pairs.c).
typedef struct selfcol_tri_frame {
    double corner[3][3];
    double lo[3], hi[3];
    double normal[3];
    double length;
    double abs_max;
    uint32_t id;           // the triangle
    uint32_t corner_id[3]; // its vertices
    uint32_t edge[3];      // edge of slot i (corners i, i + 1) when owned
    uint8_t owned;         // SELFCOL_OWNS_* bits
    uint8_t edge_reversed; // bit i: edge i's record lists corner i + 1 first
} selfcol_tri_frame;

struct selfcol_hierarchy;

void selfcol_pairs__frame(selfcol_tri_frame *frame, const struct selfcol_hierarchy *h,
                          uint32_t slot);

// A candidate triangle pair, as slots of the two hierarchies' tri_order,
// with the plane flags of pairs.c (which corners of each triangle are
// provably beyond d of, or strictly on one side of, the other's plane).
typedef struct selfcol_slot_pair {
    uint32_t a, b;
    uint32_t flags; // 4 x 3 bits for a's corners against b's plane, then 4 x 3 for b's
} selfcol_slot_pair;

// Separation test of triangles fa and fb at distance d: 0 when one lies
// beyond d of the other's plane (the pair holds no contact), else 1 with
// *flags set for selfcol_pairs__run.
int selfcol_pairs__candidate(const selfcol_tri_frame *fa, const selfcol_tri_frame *fb, double d,
                             uint32_t *flags);

// The narrow phase over a candidate list: every primitive pair the triangle
// pairs own, through the per-primitive filters, into records. frames[0] and
// frames[1] are the two hierarchies' frame arrays (the same for self).
int selfcol_pairs__run(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                       const selfcol_slot_pair *pairs, size_t count);

// The exhaustive reference (exhaustive.c).
int selfcol_exhaustive__run(selfcol_query *q);

// The hierarchy traversal (traverse.c) for methods BVH, SEED, CONE and
// EXACT; for a self query h1 == h0. With threads > 1, the traversal and pair
// tests run on up to that many threads (the records then need sorting, as
// always).
int selfcol_traverse__run(selfcol_query *q, const struct selfcol_hierarchy *h0,
                          const struct selfcol_hierarchy *h1, uint32_t method, unsigned threads);

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
int selfcol_contour__self_skippable(const struct selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_contacts *scratch_owner);

// The same for Pair(a, b) of two nodes of one hierarchy: 1 when no primitive
// of a has a contact with a primitive of b (judged on the union of the two
// patches, joined along shared edges). Uses the same scratch slot.
int selfcol_contour__pair_skippable(const struct selfcol_hierarchy *h, uint32_t a, uint32_t b,
                                    double d, selfcol_contacts *scratch_owner);

#endif // SELFCOL_QUERY_H
