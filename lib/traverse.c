// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Hierarchy traversal (Volino & Magnenat Thalmann 1995, section 2.2), in two
// stages so each can be timed and the narrow phase runs over a flat list:
//
// 1. Broad phase. A stack of node pairs; (a, a) means Self(a).
//    Self(node): skip it when the method uses curvature, the patch is
//      connected and all its normals lie in one open half-space (a non-empty
//      14-direction mask for SEED, a cone narrower than pi/2 for CONE);
//      otherwise push Self(child) for each child and Pair(ci, cj) for each
//      pair of children. A leaf's triangle pairs go to the list.
//    Pair(a, b): skip when the boxes are farther apart than d on some axis;
//      with curvature, skip when both patches are connected, adjacent (they
//      share a boundary edge) and their normals together lie in one open
//      half-space; otherwise split the larger node. Two leaves put their
//      triangle pairs (whose boxes are within d) on the list.
//    BVH uses the box test alone and is exact. EXACT skips Self(node), and
//    Pair(a, b) of adjacent nodes, only when contour.c proves the patch (or
//    the union of the two patches) free of contacts; it is exact too.
//
// 2. The candidate triangle pairs go to the pair tests of pairs.c.
//
// The box, normal and error scale of each triangle are computed once per
// query, when the traversal first reaches its leaf (a per-leaf stamp holds
// the query's serial), and laid out by slot so that a leaf pair reads
// contiguous memory; a flat sheet that EXACT culls near the root computes
// none of them.
#include "query.h"

#include "core.h"
#include "hierarchy.h"

#include <math.h>

#include <string.h>

typedef struct node_pair {
    uint32_t a, b;
} node_pair;

// Candidate triangle pairs go to the pair tests in batches of this many,
// while the frames of the leaves that produced them are still in cache
// (cloth-ball frame 92: testing one list of 674k pairs after the traversal
// took 153 ms, mostly waiting on memory).
#define PAIR_BATCH 512

typedef struct traversal {
    selfcol_query *q;
    const selfcol_hierarchy *h[2];
    uint32_t method;
    node_pair *stack;
    size_t stack_size, stack_capacity;
    selfcol_slot_pair batch[PAIR_BATCH]; // candidate triangle pairs not yet tested
    size_t batch_count;
    double narrow_seconds;
    selfcol_tri_frame *frames[2]; // by slot; the same array twice for a self query
    uint32_t *stamps[2];          // by node: serial of the query that computed its frames
    uint32_t serial;
} traversal;

static int push(traversal *t, uint32_t a, uint32_t b) {
    if (t->stack_size == t->stack_capacity) {
        size_t want = t->stack_capacity < 256 ? 256 : 2 * t->stack_capacity;
        node_pair *grown =
            selfcol_contacts__scratch(t->q->out, SELFCOL_SCRATCH_STACK, want * sizeof(node_pair),
                                      t->stack_size * sizeof(node_pair));
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        t->stack = grown;
        t->stack_capacity = t->q->out->scratch_bytes[SELFCOL_SCRATCH_STACK] / sizeof(node_pair);
    }
    t->stack[t->stack_size++] = (node_pair){a, b};
    return SELFCOL_OK;
}

// The pair tests over the batch (timed apart from the traversal).
static int flush_batch(traversal *t) {
    if (t->batch_count == 0)
        return SELFCOL_OK;
    double start = selfcol_core__seconds();
    const selfcol_tri_frame *const frames[2] = {t->frames[0], t->frames[1]};
    int status = selfcol_pairs__run(t->q, frames, t->batch, t->batch_count);
    t->batch_count = 0;
    t->narrow_seconds += selfcol_core__seconds() - start;
    return status;
}

static int boxes_apart(const selfcol_node *a, const selfcol_node *b, double d) {
    for (int k = 0; k < 3; ++k)
        if ((double)a->lo[k] - d > (double)b->hi[k] || (double)b->lo[k] - d > (double)a->hi[k])
            return 1;
    return 0;
}

// EXACT tries its contour proof only on nodes and node pairs of at least
// this many triangles: below, the narrow phase over the few triangle pairs
// costs about what the proof does (crumpled 20k sheet, d = 0.1 x mean edge:
// query 51.7 ms trying every node, 47.7 ms from 16 triangles; spheres and
// flat sheets are proven far above it).
#define CONTOUR_MIN_TRIANGLES 16
#define HALF_PI 1.5707963267948966

// All normals of the node in one open half-space, by the method's measure.
static const uint8_t SMOOTHABLE = SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED;

static int smooth(uint32_t method, const selfcol_node *n) {
    if ((n->flags & SMOOTHABLE) != SMOOTHABLE)
        return 0;
    return method == SELFCOL_METHOD_CONE ? n->cone_angle < HALF_PI : n->mask != 0;
}

// The same for the union of two nodes.
static int jointly_smooth(uint32_t method, const selfcol_node *a, const selfcol_node *b) {
    // The union of two oriented patches is consistently oriented unless a
    // bad edge joins them, and such an edge marks both sides.
    if ((a->flags & b->flags & SMOOTHABLE) != SMOOTHABLE ||
        ((a->flags | b->flags) & SELFCOL_NODE_BAD_BOUNDARY))
        return 0;
    if (method != SELFCOL_METHOD_CONE)
        return (a->mask & b->mask) != 0;
    if (!(a->cone_angle < HALF_PI && b->cone_angle < HALF_PI))
        return 0;
    double c = 0.0;
    for (int k = 0; k < 3; ++k)
        c += (double)a->cone_axis[k] * (double)b->cone_axis[k];
    double phi = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
    double lo = phi + b->cone_angle <= a->cone_angle ? a->cone_angle
                : phi + a->cone_angle <= b->cone_angle
                    ? b->cone_angle
                    : 0.5 * (a->cone_angle + phi + b->cone_angle);
    return lo < HALF_PI;
}

// The frames of a leaf's triangles, computed at its first visit in this query.
static void ensure_frames(traversal *t, int side, uint32_t id) {
    if (t->stamps[side][id] == t->serial)
        return;
    t->stamps[side][id] = t->serial;
    const selfcol_hierarchy *h = t->h[side];
    const selfcol_node *n = &h->nodes[id];
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s)
        selfcol_pairs__frame(&t->frames[side][s], h, s);
}

// Triangle pairs of two leaves (or of one leaf with itself) whose boxes are
// within d and neither of which lies beyond d of the other's plane.
static int leaf_pair(traversal *t, uint32_t a_id, uint32_t b_id, int same) {
    const selfcol_node *a = &t->h[0]->nodes[a_id], *b = &t->h[1]->nodes[b_id];
    const double d = t->q->distance;
    ensure_frames(t, 0, a_id);
    ensure_frames(t, 1, b_id);
    const selfcol_tri_frame *fa = t->frames[0], *fb = t->frames[1];
    for (uint32_t sa = a->tri_begin; sa < a->tri_begin + a->tri_count; ++sa) {
        const double *alo = fa[sa].lo, *ahi = fa[sa].hi;
        for (uint32_t sb = same ? sa + 1 : b->tri_begin; sb < b->tri_begin + b->tri_count; ++sb) {
            const double *blo = fb[sb].lo, *bhi = fb[sb].hi;
            int apart = 0;
            for (int k = 0; k < 3; ++k)
                apart |= (alo[k] - d > bhi[k]) | (blo[k] - d > ahi[k]);
            if (apart)
                continue;
            t->q->out->stats.triangle_pairs++;
            uint32_t flags;
            if (!selfcol_pairs__candidate(&fa[sa], &fb[sb], d, &flags)) {
                t->q->out->stats.pairs_separated++;
                continue;
            }
            t->batch[t->batch_count++] = (selfcol_slot_pair){sa, sb, flags};
            if (t->batch_count == PAIR_BATCH) {
                int status = flush_batch(t);
                if (status != SELFCOL_OK)
                    return status;
            }
        }
    }
    return SELFCOL_OK;
}

static int broad_phase(traversal *t) {
    selfcol_query_stats *st = &t->q->out->stats;
    const int self = t->q->self;
    // SEED and CONE cull adjacent pairs by joint curvature; EXACT by the
    // joint curvature and contour criterion of contour.c.
    const int curvature =
        self && (t->method == SELFCOL_METHOD_SEED || t->method == SELFCOL_METHOD_CONE);
    const int exact_pairs = self && t->method == SELFCOL_METHOD_EXACT;
    const selfcol_node *n0 = t->h[0]->nodes, *n1 = t->h[1]->nodes;
    int status = push(t, 0, 0);
    while (status == SELFCOL_OK && t->stack_size > 0) {
        node_pair p = t->stack[--t->stack_size];
        const selfcol_node *a = &n0[p.a], *b = &n1[p.b];
        st->nodes_visited++;
        if (self && p.a == p.b) {
            if (t->method == SELFCOL_METHOD_EXACT
                    ? a->tri_count >= CONTOUR_MIN_TRIANGLES &&
                          selfcol_contour__self_skippable(t->h[0], p.a, t->q->distance, t->q->out)
                    : curvature && smooth(t->method, a)) {
                st->culled_curvature++;
                continue;
            }
            if (a->child_count == 0) {
                status = leaf_pair(t, p.a, p.a, 1);
                continue;
            }
            for (uint32_t i = 0; i < a->child_count && status == SELFCOL_OK; ++i) {
                uint32_t ci = a->first_child + i;
                status = push(t, ci, ci);
                for (uint32_t j = i + 1; j < a->child_count && status == SELFCOL_OK; ++j)
                    status = push(t, ci, a->first_child + j);
            }
            continue;
        }
        if (boxes_apart(a, b, t->q->distance)) {
            st->culled_box++;
            continue;
        }
        if (curvature
                ? jointly_smooth(t->method, a, b) && selfcol_hierarchy__adjacent(t->h[0], a, b)
                : exact_pairs && a->tri_count + b->tri_count >= CONTOUR_MIN_TRIANGLES &&
                      selfcol_contour__pair_skippable(t->h[0], p.a, p.b, t->q->distance,
                                                      t->q->out)) {
            st->culled_adjacency++;
            continue;
        }
        if (a->child_count == 0 && b->child_count == 0) {
            status = leaf_pair(t, p.a, p.b, 0);
            continue;
        }
        // Split the node with more triangles (a leaf is never split).
        int split_a = b->child_count == 0 || (a->child_count > 0 && a->tri_count >= b->tri_count);
        const selfcol_node *s = split_a ? a : b;
        for (uint32_t i = 0; i < s->child_count && status == SELFCOL_OK; ++i)
            status = split_a ? push(t, s->first_child + i, p.b) : push(t, p.a, s->first_child + i);
    }
    return status;
}

// Zeroed stamps for `count` nodes in scratch `slot` (fresh memory is zeroed
// once; later queries tell old stamps from new by the serial).
static uint32_t *stamps_for(selfcol_contacts *c, int slot, size_t count) {
    const int fresh = c->scratch_bytes[slot] < count * sizeof(uint32_t);
    uint32_t *stamps = selfcol_contacts__scratch(c, slot, count * sizeof(uint32_t), 0);
    if (stamps != NULL && fresh)
        memset(stamps, 0, c->scratch_bytes[slot]);
    return stamps;
}

int selfcol_traverse__run(selfcol_query *q, const selfcol_hierarchy *h0,
                          const selfcol_hierarchy *h1, uint32_t method) {
    traversal t;
    memset(&t, 0, sizeof t);
    t.q = q;
    t.h[0] = h0;
    t.h[1] = h1;
    t.method = method;
    selfcol_contacts *c = q->out;
    const int sides = q->self ? 1 : 2;
    for (int side = 0; side < sides; ++side) {
        const selfcol_hierarchy *h = side ? h1 : h0;
        if (h->mesh->triangle_count > SIZE_MAX / sizeof(selfcol_tri_frame))
            return SELFCOL_ENOMEM;
        t.frames[side] =
            selfcol_contacts__scratch(c, side ? SELFCOL_SCRATCH_FRAMES1 : SELFCOL_SCRATCH_FRAMES0,
                                      h->mesh->triangle_count * sizeof(selfcol_tri_frame), 0);
        t.stamps[side] =
            stamps_for(c, side ? SELFCOL_SCRATCH_STAMPS1 : SELFCOL_SCRATCH_STAMPS0, h->node_count);
        if (t.frames[side] == NULL || t.stamps[side] == NULL)
            return SELFCOL_ENOMEM;
    }
    if (q->self) {
        t.frames[1] = t.frames[0];
        t.stamps[1] = t.stamps[0];
    }
    // A new serial invalidates every stamp; at wrap-around they are cleared.
    if (++c->serial == 0) {
        for (int side = 0; side < sides; ++side)
            memset(t.stamps[side], 0,
                   c->scratch_bytes[side ? SELFCOL_SCRATCH_STAMPS1 : SELFCOL_SCRATCH_STAMPS0]);
        c->serial = 1;
    }
    t.serial = c->serial;

    double start = selfcol_core__seconds();
    int status = broad_phase(&t);
    if (status == SELFCOL_OK)
        status = flush_batch(&t);
    q->out->stats.narrow_seconds = t.narrow_seconds;
    q->out->stats.broad_seconds = selfcol_core__seconds() - start - t.narrow_seconds;
    return status;
}
