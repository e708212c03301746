// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The narrow phase of every search method (pairs.c): primitive-pair tests,
// the per-query triangle frames, triangle-pair candidates and the filtered
// run over a candidate list.
#ifndef SELFCOL_PAIRS_H
#define SELFCOL_PAIRS_H

#include "hierarchy/hierarchy.h"
#include "query/query.h"

#include <math.h>

// Primitive-pair tests (pairs.c). Vertex v of mesh[mv] against triangle t of
// mesh[mt]; the caller guarantees (for self queries) that v is not a corner
// of t. A hit becomes a record.
int selfcol_pairs__test_vf(selfcol_query *q, int mv, uint32_t v, int mt, uint32_t t);
// Edge e of mesh[me] against edge f of mesh[mf]; no shared vertex for self.
int selfcol_pairs__test_ee(selfcol_query *q, int me, uint32_t e, int mf, uint32_t f);
// Edge e of mesh[me] against triangle t of mesh[mt]; no shared vertex for self.
int selfcol_pairs__test_ef(selfcol_query *q, int me, uint32_t e, int mt, uint32_t t);

// 1 when the lines of segments (p0, p1) and (q0, q1) are provably farther
// apart than d (1 + 2^-20), so no EE contact: the cheap reject before the
// closed form (pairs.c derives its rounding bound). Never 1 for a pair whose
// closed-form distance is below d (test_pairs_internal).
int selfcol_pairs__lines_apart(const double *p0, const double *p1, const double *q0,
                               const double *q1, double d);

// What the pair tests read of a triangle, computed once per query and
// triangle (lazily, for the leaves the traversal reaches) and laid out by
// hierarchy slot, so that a leaf pair reads contiguous memory instead of
// gathering from the mesh: its corners, box and unnormalised normal
// (p1 - p0) x (p2 - p0) in the triangle's own winding, with the computed
// length and the scale of its rounding error, and what it owns (pairs.c).
// The fields the triangle-pair candidate test reads (selfcol_pairs__candidate:
// xyz, normal, length, abs_max) come first, in 160 bytes, so that the test
// of a pair touches fewer of the other frame's cache lines.
typedef struct selfcol_tri_frame {
    // The corners axis by axis: xyz[k] = corners 0, 1, 2, 0, 1, so that
    // two- and four-lane loads at c and c + 1 hold the ends of edge slots c,
    // c + 1 (.. c + 3) (the lane filters of pairs.c).
    double xyz[3][5];
    double normal[3];
    double length;
    double abs_max;
    double lo[3], hi[3];
    double corner[3][3];   // the corners again, point by point
    uint32_t id;           // the triangle
    uint32_t corner_id[3]; // its vertices
    uint32_t edge[3];      // edge of slot i (corners i, i + 1) when owned
    uint8_t owned;         // SELFCOL_OWNS_* bits
    uint8_t edge_reversed; // bit i: edge i's record lists corner i + 1 first
    uint8_t duplicate;     // 1: SELFCOL_TRIANGLE_DUPLICATE (pairs with it are skipped)
} selfcol_tri_frame;

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

// 1 when this CPU runs the four-lane (AVX) paths (the _avx functions
// below); 0 where they are not compiled (not x86-64 with GCC or Clang, or
// SELFCOL_SCALAR) or the CPU or OS lacks AVX. The caller chooses once per
// query.
int selfcol_pairs__has_avx(void);

// The triangles' boxes by slot, axis by axis (lo[k][slot], hi[k][slot]: the
// frames' lo and hi), so that a leaf row's box tests load consecutive slots
// (a frame is 312 bytes; its box would cost a cache line per slot).
typedef struct selfcol_slot_boxes {
    double *lo[3], *hi[3];
} selfcol_slot_boxes;

// A duplicate triangle's box is stored empty (lo +inf, hi -inf), so no row
// finds it near: pairs with it hold no contact (hierarchy.h), and the rows
// then skip it without reading its frame.
static inline void selfcol_pairs__set_box(const selfcol_slot_boxes *b, uint32_t slot,
                                          const selfcol_tri_frame *f) {
    for (int k = 0; k < 3; ++k) {
        b->lo[k][slot] = f->duplicate ? HUGE_VAL : f->lo[k];
        b->hi[k][slot] = f->duplicate ? -HUGE_VAL : f->hi[k];
    }
}

// The slots s in [begin, end) whose triangle's box is within d of a's
// (selfcol_box__near on the boxes), written to out in increasing order;
// returns their count. Decided without a branch per slot: which slots of a
// leaf pass looks random to a branch predictor. out has room for end -
// begin + 4 slots (the four-lane version stores whole groups).
uint32_t selfcol_pairs__near_slots(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                   uint32_t begin, uint32_t end, double d, uint32_t *out);
// The same in four lanes (only where selfcol_pairs__has_avx()).
uint32_t selfcol_pairs__near_slots_avx(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                       uint32_t begin, uint32_t end, double d, uint32_t *out);

// The one-lane references of selfcol_pairs__candidate and
// selfcol_pairs__near_slots, always compiled: the SSE2 paths (x86-64's
// baseline) and the AVX ones must equal them bit for bit
// (test_pairs_internal); a build with SELFCOL_SCALAR defined uses them.
int selfcol_pairs__candidate_scalar(const selfcol_tri_frame *fa, const selfcol_tri_frame *fb,
                                    double d, uint32_t *flags);
uint32_t selfcol_pairs__near_slots_scalar(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                          uint32_t begin, uint32_t end, double d, uint32_t *out);

// A leaf row's candidates: for each of the `count` slots near[] of frames
// (in order), selfcol_pairs__candidate of a (at slot sa) and that slot; the
// pairs it keeps, with their flags, go to out in the same order (out has
// room for `count`). Returns how many it kept.
uint32_t selfcol_pairs__row_candidates(const selfcol_tri_frame *a, uint32_t sa,
                                       const selfcol_tri_frame *frames, const uint32_t *near,
                                       uint32_t count, double d, selfcol_slot_pair *out);
// The same in four lanes, without a branch per pair (only where
// selfcol_pairs__has_avx()).
uint32_t selfcol_pairs__row_candidates_avx(const selfcol_tri_frame *a, uint32_t sa,
                                           const selfcol_tri_frame *frames, const uint32_t *near,
                                           uint32_t count, double d, selfcol_slot_pair *out);

// The narrow phase over a candidate list: every primitive pair the triangle
// pairs own, through the per-primitive filters, into records. frames[0] and
// frames[1] are the two hierarchies' frame arrays (the same for self).
int selfcol_pairs__run(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                       const selfcol_slot_pair *pairs, size_t count);
// The same with the four-lane masks (only where selfcol_pairs__has_avx()).
int selfcol_pairs__run_avx(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                           const selfcol_slot_pair *pairs, size_t count);
// Its one-lane reference (the same records and statistics; test_pairs_internal).
int selfcol_pairs__run_scalar(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                              const selfcol_slot_pair *pairs, size_t count);

#endif // SELFCOL_PAIRS_H
