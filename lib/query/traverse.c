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
#include "query/traverse.h"
#include "query/contour.h"
#include "query/pairs.h"

#include "base/box.h"
#include "base/cone.h"
#include "base/core.h"
#include "base/parallel.h"
#include "hierarchy/hierarchy.h"

#include <string.h>

typedef struct node_pair {
    uint32_t a, b;
} node_pair;

// Candidate triangle pairs go to the pair tests in batches of this many,
// while the frames of the leaves that produced them are still in cache
// (cloth-ball frame 92: testing one list of 674k pairs after the traversal
// took 153 ms, mostly waiting on memory).
#define PAIR_BATCH 512

// Threads. The first levels of the traversal run on the calling thread,
// breadth first, until this many node pairs per worker wait (or none do);
// the workers then take those pairs, largest first, from a shared counter
// and traverse each to the leaves on their own stacks, into their own
// records and statistics. Every node pair is visited exactly once whoever
// takes it, so the counters add up to those of one thread, and the records,
// sorted by their keys afterwards, are the same list.
#define TASKS_PER_WORKER 32

// A leaf's frames are published once per query: its stamp goes from an older
// serial to serial | FRAMES_BUSY (claimed by one worker) to serial (ready).
// Serials stay below FRAMES_BUSY.
#define FRAMES_BUSY 0x80000000u

// What the workers of one query share (read only while they run, apart from
// the atomic task counter, stop flag and leaf stamps).
typedef struct shared {
    const selfcol_hierarchy *h[2];
    uint32_t method;
    double distance;
    selfcol_tri_frame *frames[2]; // by slot; the same array twice for a self query
    selfcol_slot_boxes boxes[2];  // their boxes by slot, in the same buffer
    uint32_t *stamps[2];          // by node: serial of the query that computed its frames
    uint32_t serial;
    int concurrent; // more than one worker: stamps are claimed atomically
    int avx;        // the four-lane leaf tests (selfcol_pairs__has_avx)
    const node_pair *tasks;
    size_t task_count;
    size_t next_task; // atomic
    int stop;         // atomic: a worker failed
    const selfcol_query *query;
    selfcol_records *out[SELFCOL_MAX_THREADS];    // each worker's records
    selfcol_workspace *work[SELFCOL_MAX_THREADS]; // and working memory
    double narrow_seconds[SELFCOL_MAX_THREADS];
    double busy_seconds[SELFCOL_MAX_THREADS];
} shared;

// One worker's traversal.
typedef struct traversal {
    shared *s;
    selfcol_query q; // the query, with out = this worker's records and statistics
    node_pair *stack;
    size_t stack_size, stack_capacity;
    selfcol_slot_pair batch[PAIR_BATCH]; // candidate triangle pairs not yet tested
    size_t batch_count;
    double narrow_seconds;
} traversal;

static int push(traversal *t, uint32_t a, uint32_t b) {
    if (t->stack_size == t->stack_capacity) {
        size_t want = t->stack_capacity < 256 ? 256 : 2 * t->stack_capacity;
        node_pair *grown =
            selfcol_workspace__buffer(t->q.work, SELFCOL_SCRATCH_STACK, want * sizeof(node_pair),
                                      t->stack_size * sizeof(node_pair));
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        t->stack = grown;
        t->stack_capacity = t->q.work->bytes[SELFCOL_SCRATCH_STACK] / sizeof(node_pair);
    }
    t->stack[t->stack_size++] = (node_pair){a, b};
    return SELFCOL_OK;
}

// The pair tests over the batch (timed apart from the traversal).
static int flush_batch(traversal *t) {
    if (t->batch_count == 0)
        return SELFCOL_OK;
    double start = selfcol_core__seconds();
    const selfcol_tri_frame *const frames[2] = {t->s->frames[0], t->s->frames[1]};
    int status = t->s->avx ? selfcol_pairs__run_avx(&t->q, frames, t->batch, t->batch_count)
                           : selfcol_pairs__run(&t->q, frames, t->batch, t->batch_count);
    t->batch_count = 0;
    t->narrow_seconds += selfcol_core__seconds() - start;
    return status;
}

// EXACT tries its contour proof only on nodes and node pairs of at least
// this many triangles: below, the narrow phase over the few triangle pairs
// costs about what the proof does (crumpled 20k sheet, d = 0.1 x mean edge:
// query 51.7 ms trying every node, 47.7 ms from 16 triangles; spheres and
// flat sheets are proven far above it).
#define CONTOUR_MIN_TRIANGLES 16

// All normals of the node in one open half-space, by the method's measure.
static const uint8_t SMOOTHABLE = SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED;

static int smooth(uint32_t method, const selfcol_node *n) {
    if ((n->flags & SMOOTHABLE) != SMOOTHABLE)
        return 0;
    return method == SELFCOL_METHOD_CONE ? n->cone_angle < SELFCOL_HALF_PI : n->mask != 0;
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
    if (!(a->cone_angle < SELFCOL_HALF_PI && b->cone_angle < SELFCOL_HALF_PI))
        return 0;
    // The float axes as they are (not renormalised), widened exactly.
    const double ua[3] = {a->cone_axis[0], a->cone_axis[1], a->cone_axis[2]};
    const double ub[3] = {b->cone_axis[0], b->cone_axis[1], b->cone_axis[2]};
    double phi = selfcol_cone__angle_between(ua, ub);
    return selfcol_cone__merged_angle(a->cone_angle, phi, b->cone_angle) < SELFCOL_HALF_PI;
}

// The adjacency query of SEED and CONE's Pair(a, b), from the boundary
// lists the build keeps (hierarchy_boundary.c).

// 1 when triangle t is one of node n's (a leaf: a short scan).
static int leaf_holds(const selfcol_hierarchy *h, const selfcol_node *n, uint32_t t) {
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s)
        if (h->tri_order[s] == t)
            return 1;
    return 0;
}

// 1 when edge e is in the (sorted) boundary list of internal node n.
static int on_boundary_list(const selfcol_hierarchy *h, const selfcol_node *n, uint32_t e) {
    const uint32_t *list = h->bedge + n->boundary_begin;
    uint32_t lo = 0, hi = n->boundary_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if ((list[mid] >> 1) < e)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n->boundary_count && (list[lo] >> 1) == e;
}

// Leaf `leaf` against any node `other` (disjoint from it): some edge of the
// leaf's triangles has a triangle of `other` -- for an internal node, the
// edge is then on its boundary list.
static int leaf_adjacent(const selfcol_hierarchy *h, const selfcol_node *leaf,
                         const selfcol_node *other) {
    const selfcol_mesh *m = h->mesh;
    for (uint32_t s = leaf->tri_begin; s < leaf->tri_begin + leaf->tri_count; ++s) {
        uint32_t t = h->tri_order[s];
        for (int k = 0; k < 3; ++k) {
            uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)k];
            if (other->child_count > 0) {
                if (on_boundary_list(h, other, e))
                    return 1;
                continue;
            }
            // Manifold edges only, as in the boundary lists (an edge of
            // three or more triangles is on no list).
            uint32_t first = m->edge_tri_offsets[e];
            if (m->edge_tri_offsets[e + 1] - first != 2)
                continue;
            uint32_t across =
                m->edge_tris[first] == t ? m->edge_tris[first + 1] : m->edge_tris[first];
            if (leaf_holds(h, other, across))
                return 1;
        }
    }
    return 0;
}

// 1 when the two (disjoint) nodes' patches share a manifold edge: their
// sorted boundary lists meet, or for a leaf, an edge of its triangles has a
// triangle of the other node. Patches touching only at a vertex count as
// not adjacent, which only costs culling.
static int nodes_adjacent(const selfcol_hierarchy *h, const selfcol_node *a,
                          const selfcol_node *b) {
    if (a->child_count == 0)
        return leaf_adjacent(h, a, b);
    if (b->child_count == 0)
        return leaf_adjacent(h, b, a);
    // Both boundary lists are sorted by edge: a shared edge shows up as the
    // same edge in both (with opposite directions).
    const uint32_t *x = h->bedge + a->boundary_begin, *y = h->bedge + b->boundary_begin;
    const uint32_t *xe = x + a->boundary_count, *ye = y + b->boundary_count;
    while (x < xe && y < ye) {
        uint32_t ex = *x >> 1, ey = *y >> 1;
        if (ex == ey)
            return 1;
        if (ex < ey)
            ++x;
        else
            ++y;
    }
    return 0;
}

// The frames of a leaf's triangles, computed at its first visit in this
// query. With several workers, the first to reach the leaf claims it and the
// others wait for its stamp (a leaf holds a few triangles: the wait is short
// and rare).
static void ensure_frames(traversal *t, int side, uint32_t id) {
    shared *s = t->s;
    uint32_t *stamp = &s->stamps[side][id];
    if (!s->concurrent) {
        if (*stamp == s->serial)
            return;
        *stamp = s->serial;
    } else {
        uint32_t seen = SELFCOL_ATOMIC_LOAD(stamp);
        if (seen == s->serial)
            return;
        if (seen == (s->serial | FRAMES_BUSY) ||
            !SELFCOL_ATOMIC_CAS(stamp, &seen, s->serial | FRAMES_BUSY)) {
            while (SELFCOL_ATOMIC_LOAD(stamp) != s->serial) {
            }
            return;
        }
    }
    const selfcol_hierarchy *h = s->h[side];
    const selfcol_node *n = &h->nodes[id];
    for (uint32_t slot = n->tri_begin; slot < n->tri_begin + n->tri_count; ++slot) {
        selfcol_pairs__frame(&s->frames[side][slot], h, slot);
        selfcol_pairs__set_box(&s->boxes[side], slot, &s->frames[side][slot]);
    }
    if (s->concurrent)
        SELFCOL_ATOMIC_STORE(stamp, s->serial);
}

// Triangle pairs of two leaves (or of one leaf with itself) whose boxes are
// within d and neither of which lies beyond d of the other's plane.
static int leaf_pair(traversal *t, uint32_t a_id, uint32_t b_id, int same) {
    const shared *s = t->s;
    const selfcol_node *a = &s->h[0]->nodes[a_id], *b = &s->h[1]->nodes[b_id];
    const double d = s->distance;
    ensure_frames(t, 0, a_id);
    ensure_frames(t, 1, b_id);
    const selfcol_tri_frame *fa = s->frames[0], *fb = s->frames[1];
    selfcol_query_stats *st = &t->q.out->stats;
    const uint32_t b_end = b->tri_begin + b->tri_count;
    uint32_t near[SELFCOL_LEAF_MAX_TRIANGLES + 4]; // pairs.h: room for a whole last group
    for (uint32_t sa = a->tri_begin; sa < a->tri_begin + a->tri_count; ++sa) {
        if (fa[sa].duplicate)
            continue; // owns nothing and is no contact's triangle
        // The row's box tests at once (pairs.h), then the pairs that passed.
        const uint32_t row = same ? sa + 1 : b->tri_begin;
        const uint32_t near_count =
            s->avx ? selfcol_pairs__near_slots_avx(&fa[sa], &s->boxes[1], row, b_end, d, near)
                   : selfcol_pairs__near_slots(&fa[sa], &s->boxes[1], row, b_end, d, near);
        // The row's candidates (never a duplicate: selfcol_pairs__set_box)
        // into the batch, which has room for a whole row.
        if (t->batch_count + SELFCOL_LEAF_MAX_TRIANGLES > PAIR_BATCH) {
            const int status = flush_batch(t);
            if (status != SELFCOL_OK)
                return status;
        }
        selfcol_slot_pair *to = t->batch + t->batch_count;
        const uint32_t kept =
            s->avx ? selfcol_pairs__row_candidates_avx(&fa[sa], sa, fb, near, near_count, d, to)
                   : selfcol_pairs__row_candidates(&fa[sa], sa, fb, near, near_count, d, to);
        t->batch_count += kept;
        st->triangle_pairs += near_count;
        st->pairs_separated += near_count - kept;
    }
    return SELFCOL_OK;
}

// One node pair: culled, tested as leaves, or split onto the stack.
static int visit(traversal *t, node_pair p) {
    const shared *s = t->s;
    selfcol_query_stats *st = &t->q.out->stats;
    const int self = t->q.self;
    const uint32_t method = s->method;
    const double d = s->distance;
    // SEED and CONE cull adjacent pairs by joint curvature; EXACT by the
    // joint curvature and contour criterion of contour.c.
    const int curvature = self && (method == SELFCOL_METHOD_SEED || method == SELFCOL_METHOD_CONE);
    const int exact_pairs = self && method == SELFCOL_METHOD_EXACT;
    const selfcol_node *a = &s->h[0]->nodes[p.a], *b = &s->h[1]->nodes[p.b];
    int status = SELFCOL_OK;
    st->nodes_visited++;
    if ((a->flags | b->flags) & SELFCOL_NODE_DUPLICATES)
        return SELFCOL_OK; // repeated triangles only: no contact can come of them
    if (t->q.filter != NULL && !t->q.filter->keep(t->q.filter->context, p.a, p.b))
        return SELFCOL_OK; // the caller wants nothing under this pair (query.h)
    if (self && p.a == p.b) {
        if (method == SELFCOL_METHOD_EXACT
                ? a->tri_count >= CONTOUR_MIN_TRIANGLES &&
                      selfcol_contour__self_skippable(s->h[0], p.a, d, t->q.work, &t->q.out->stats)
                : curvature && smooth(method, a)) {
            st->culled_curvature++;
            return SELFCOL_OK;
        }
        if (a->child_count == 0)
            return leaf_pair(t, p.a, p.a, 1);
        for (uint32_t i = 0; i < a->child_count && status == SELFCOL_OK; ++i) {
            uint32_t ci = a->first_child + i;
            status = push(t, ci, ci);
            for (uint32_t j = i + 1; j < a->child_count && status == SELFCOL_OK; ++j)
                status = push(t, ci, a->first_child + j);
        }
        return status;
    }
    if (!selfcol_box__near_float(a->lo, a->hi, b->lo, b->hi, d)) {
        st->culled_box++;
        return SELFCOL_OK;
    }
    if (curvature ? jointly_smooth(method, a, b) && nodes_adjacent(s->h[0], a, b)
                  : exact_pairs && a->tri_count + b->tri_count >= CONTOUR_MIN_TRIANGLES &&
                        selfcol_contour__pair_skippable(s->h[0], p.a, p.b, d, t->q.work,
                                                        &t->q.out->stats)) {
        st->culled_adjacency++;
        return SELFCOL_OK;
    }
    if (a->child_count == 0 && b->child_count == 0)
        return leaf_pair(t, p.a, p.b, 0);
    // Split the node with more triangles (a leaf is never split).
    int split_a = b->child_count == 0 || (a->child_count > 0 && a->tri_count >= b->tri_count);
    const selfcol_node *n = split_a ? a : b;
    for (uint32_t i = 0; i < n->child_count && status == SELFCOL_OK; ++i)
        status = split_a ? push(t, n->first_child + i, p.b) : push(t, p.a, n->first_child + i);
    return status;
}

// Depth first until the stack is empty.
static int drain(traversal *t) {
    int status = SELFCOL_OK;
    while (status == SELFCOL_OK && t->stack_size > 0) {
        node_pair p = t->stack[--t->stack_size];
        status = visit(t, p);
    }
    return status;
}

static void traversal_init(traversal *t, shared *s, selfcol_records *out, selfcol_workspace *work) {
    t->s = s;
    t->q = *s->query;
    t->q.out = out;
    t->q.work = work;
    t->stack = NULL;
    t->stack_size = t->stack_capacity = 0;
    t->batch_count = 0;
    t->narrow_seconds = 0.0;
}

static uint32_t triangles_of(const shared *s, node_pair p) {
    uint32_t ta = s->h[0]->nodes[p.a].tri_count;
    return p.a == p.b && s->h[0] == s->h[1] ? ta : ta + s->h[1]->nodes[p.b].tri_count;
}

// Breadth first on the calling thread until `want` node pairs wait on the
// stack (or none); leaves met on the way are tested here. The waiting pairs
// are left in `tasks` (the calling thread's scratch), largest first, and
// their count returned in *count.
static int seed_tasks(traversal *t, size_t want, node_pair **tasks, size_t *count) {
    int status = push(t, 0, 0);
    while (status == SELFCOL_OK && t->stack_size > 0 && t->stack_size < want) {
        size_t level = t->stack_size;
        node_pair *copy = selfcol_workspace__buffer(t->q.work, SELFCOL_SCRATCH_TASKS,
                                                    level * sizeof(node_pair), 0);
        if (copy == NULL)
            return SELFCOL_ENOMEM;
        memcpy(copy, t->stack, level * sizeof(node_pair));
        t->stack_size = 0;
        for (size_t i = 0; i < level && status == SELFCOL_OK; ++i)
            status = visit(t, copy[i]);
    }
    if (status != SELFCOL_OK)
        return status;
    size_t n = t->stack_size;
    node_pair *list =
        selfcol_workspace__buffer(t->q.work, SELFCOL_SCRATCH_TASKS, n * sizeof(node_pair), 0);
    if (list == NULL && n > 0)
        return SELFCOL_ENOMEM;
    // Largest first (insertion sort of a few hundred pairs), so that no
    // worker starts a big subtree when the others are about to finish.
    for (size_t i = 0; i < n; ++i) {
        node_pair p = t->stack[i];
        uint32_t size = triangles_of(t->s, p);
        size_t j = i;
        for (; j > 0 && triangles_of(t->s, list[j - 1]) < size; --j)
            list[j] = list[j - 1];
        list[j] = p;
    }
    t->stack_size = 0;
    *tasks = list;
    *count = n;
    return SELFCOL_OK;
}

// A worker: take node pairs from the shared list until none is left.
static int worker_run(void *context, unsigned w) {
    shared *s = context;
    double start = selfcol_core__seconds();
    traversal t;
    traversal_init(&t, s, s->out[w], s->work[w]);
    int status = SELFCOL_OK;
    while (status == SELFCOL_OK && !SELFCOL_ATOMIC_LOAD(&s->stop)) {
        size_t i = SELFCOL_ATOMIC_FETCH_ADD(&s->next_task, (size_t)1);
        if (i >= s->task_count)
            break;
        status = push(&t, s->tasks[i].a, s->tasks[i].b);
        if (status == SELFCOL_OK)
            status = drain(&t);
    }
    if (status == SELFCOL_OK)
        status = flush_batch(&t);
    if (status != SELFCOL_OK)
        SELFCOL_ATOMIC_STORE(&s->stop, 1);
    s->narrow_seconds[w] = t.narrow_seconds;
    s->busy_seconds[w] = selfcol_core__seconds() - start;
    return status;
}

// Zeroed stamps for `count` nodes in scratch `slot` (fresh memory is zeroed
// once; later queries tell old stamps from new by the serial).
static uint32_t *stamps_for(selfcol_workspace *work, int slot, size_t count) {
    const int fresh = work->bytes[slot] < count * sizeof(uint32_t);
    uint32_t *stamps = selfcol_workspace__buffer(work, slot, count * sizeof(uint32_t), 0);
    if (stamps != NULL && fresh)
        memset(stamps, 0, work->bytes[slot]);
    return stamps;
}

// The workers' counters go into the caller's records; their own records
// stay where they are, and the sort that follows reads them in place
// (context.h: pending_workers): copying them first into one set was a
// serial pass over all but 1/N of the records.
static void gather(shared *s, selfcol_context *context, unsigned workers) {
    selfcol_records *c = s->out[0];
    double broad = 0.0, narrow = 0.0;
    for (unsigned w = 0; w < workers; ++w) {
        narrow += s->narrow_seconds[w];
        broad += s->busy_seconds[w] - s->narrow_seconds[w];
        if (w > 0)
            selfcol_records__absorb_stats(c, s->out[w]);
    }
    context->pending_workers = workers - 1;
    c->stats.broad_seconds += broad;
    c->stats.narrow_seconds += narrow;
}

int selfcol_traverse__run(selfcol_query *q, const selfcol_hierarchy *h0,
                          const selfcol_hierarchy *h1, uint32_t method, selfcol_context *context) {
    shared s;
    memset(&s, 0, sizeof s);
    s.h[0] = h0;
    s.h[1] = h1;
    s.method = method;
    s.distance = q->distance;
    s.query = q;
    s.avx = !context->baseline_lanes && selfcol_pairs__has_avx();
    selfcol_records *c = q->out;
    selfcol_workspace *work = &context->work;
    const int sides = q->self ? 1 : 2;
    for (int side = 0; side < sides; ++side) {
        const selfcol_hierarchy *h = side ? h1 : h0;
        // The frames, then their boxes' six arrays (pairs.h).
        const size_t n = h->mesh->triangle_count;
        const size_t per_triangle = sizeof(selfcol_tri_frame) + 6 * sizeof(double);
        if (n > SIZE_MAX / per_triangle)
            return SELFCOL_ENOMEM;
        s.frames[side] = selfcol_workspace__buffer(
            work, side ? SELFCOL_SCRATCH_FRAMES1 : SELFCOL_SCRATCH_FRAMES0, n * per_triangle, 0);
        if (s.frames[side] != NULL) {
            double *box = (double *)(void *)(s.frames[side] + n);
            for (int k = 0; k < 3; ++k) {
                s.boxes[side].lo[k] = box + (size_t)k * n;
                s.boxes[side].hi[k] = box + (size_t)(3 + k) * n;
            }
        }
        s.stamps[side] = stamps_for(work, side ? SELFCOL_SCRATCH_STAMPS1 : SELFCOL_SCRATCH_STAMPS0,
                                    h->node_count);
        if (s.frames[side] == NULL || s.stamps[side] == NULL)
            return SELFCOL_ENOMEM;
    }
    if (q->self) {
        s.frames[1] = s.frames[0];
        s.boxes[1] = s.boxes[0];
        s.stamps[1] = s.stamps[0];
    }
    // A new serial invalidates every stamp; at wrap-around they are cleared.
    if (++work->serial >= FRAMES_BUSY) {
        for (int side = 0; side < sides; ++side)
            memset(s.stamps[side], 0,
                   work->bytes[side ? SELFCOL_SCRATCH_STAMPS1 : SELFCOL_SCRATCH_STAMPS0]);
        work->serial = 1;
    }
    s.serial = work->serial;

    const double start = selfcol_core__seconds();
    unsigned workers = context->threads; // 1..SELFCOL_MAX_THREADS
    traversal calling;
    traversal *main_traversal = &calling;
    traversal_init(main_traversal, &s, c, work);
    int status;
    if (workers == 1) {
        status = push(main_traversal, 0, 0);
        if (status == SELFCOL_OK)
            status = drain(main_traversal);
        if (status == SELFCOL_OK)
            status = flush_batch(main_traversal);
        c->stats.narrow_seconds = main_traversal->narrow_seconds;
        c->stats.broad_seconds = selfcol_core__seconds() - start - main_traversal->narrow_seconds;
        return status;
    }

    node_pair *tasks = NULL;
    status = seed_tasks(main_traversal, TASKS_PER_WORKER * (size_t)workers, &tasks, &s.task_count);
    if (status == SELFCOL_OK)
        status = flush_batch(main_traversal);
    c->stats.narrow_seconds = main_traversal->narrow_seconds;
    c->stats.broad_seconds = selfcol_core__seconds() - start - main_traversal->narrow_seconds;
    if (status != SELFCOL_OK || s.task_count == 0)
        return status;
    if (s.task_count < workers)
        workers = (unsigned)s.task_count;
    s.tasks = tasks;
    s.out[0] = c;
    s.work[0] = work;
    for (unsigned w = 1; w < workers; ++w) {
        selfcol_worker *worker = selfcol_context__worker(context, w);
        if (worker == NULL)
            return SELFCOL_ENOMEM;
        s.out[w] = &worker->records;
        s.work[w] = &worker->work;
    }
    s.concurrent = 1;
    // A worker whose thread did not start left its records empty and its
    // times 0; the others took its share of the tasks.
    status = selfcol_parallel__run(&context->executor, workers, worker_run, &s);
    if (status == SELFCOL_OK)
        gather(&s, context, workers);
    return status;
}
