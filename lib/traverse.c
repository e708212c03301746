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
// 2. Narrow phase. Each triangle pair generates the primitive pairs made of a
//    vertex or edge *owned* by one triangle and the other triangle (or an
//    owned edge of the other): every vertex and edge has exactly one owner
//    triangle, and every triangle pair is listed at most once, so every
//    primitive pair is tested at most once. For a self query, pairs sharing a
//    vertex are dropped before any test. Ownership keeps the broad phase
//    sound: a vertex within d of a triangle lies in its owner's box, so the
//    owner's box is within d of the triangle's box too.
#include "query.h"

#include "core.h"
#include "hierarchy.h"

#include <math.h>

typedef struct node_pair {
    uint32_t a, b;
} node_pair;

typedef struct traversal {
    selfcol_query *q;
    const selfcol_hierarchy *h[2];
    uint32_t method;
    node_pair *stack;
    size_t stack_size, stack_capacity;
    node_pair *pairs; // triangle pairs (t0 of mesh 0, t1 of mesh 1)
    size_t pair_count, pair_capacity;
} traversal;

static int push(traversal *t, int list, uint32_t a, uint32_t b) {
    node_pair **items = list ? &t->pairs : &t->stack;
    size_t *size = list ? &t->pair_count : &t->stack_size;
    size_t *capacity = list ? &t->pair_capacity : &t->stack_capacity;
    if (*size == *capacity) {
        size_t want = *capacity < 256 ? 256 : 2 * *capacity;
        node_pair *grown = selfcol_contacts__scratch(t->q->out, list, want * sizeof(node_pair),
                                                     *size * sizeof(node_pair));
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        *items = grown;
        *capacity = t->q->out->scratch_bytes[list] / sizeof(node_pair);
    }
    (*items)[(*size)++] = (node_pair){a, b};
    return SELFCOL_OK;
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

static void triangle_box(const selfcol_mesh *m, uint32_t t, double lo[3], double hi[3]) {
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    for (int k = 0; k < 3; ++k) {
        double a = m->positions[3 * (size_t)tri[0] + k], b = m->positions[3 * (size_t)tri[1] + k];
        double c = m->positions[3 * (size_t)tri[2] + k];
        lo[k] = a < b ? (a < c ? a : c) : (b < c ? b : c);
        hi[k] = a > b ? (a > c ? a : c) : (b > c ? b : c);
    }
}

// Boxes of a leaf's triangles, computed once per leaf pair (leaves hold a
// handful of triangles; larger ones fall back to computing boxes per pair).
#define LEAF_BOXES 32

static int leaf_pair(traversal *t, const selfcol_node *a, const selfcol_node *b, int same) {
    const selfcol_mesh *m0 = t->h[0]->mesh, *m1 = t->h[1]->mesh;
    const double d = t->q->distance;
    double box_b[LEAF_BOXES][6];
    const int cached = b->tri_count <= LEAF_BOXES;
    for (uint32_t j = 0; cached && j < b->tri_count; ++j)
        triangle_box(m1, t->h[1]->tri_order[b->tri_begin + j], box_b[j], box_b[j] + 3);
    for (uint32_t i = 0; i < a->tri_count; ++i) {
        uint32_t ta = t->h[0]->tri_order[a->tri_begin + i];
        double alo[3], ahi[3];
        if (same && cached) {
            for (int k = 0; k < 3; ++k) {
                alo[k] = box_b[i][k];
                ahi[k] = box_b[i][3 + k];
            }
        } else {
            triangle_box(m0, ta, alo, ahi);
        }
        for (uint32_t j = same ? i + 1 : 0; j < b->tri_count; ++j) {
            uint32_t tb = t->h[1]->tri_order[b->tri_begin + j];
            double computed[6];
            const double *box = cached ? box_b[j] : computed;
            if (!cached)
                triangle_box(m1, tb, computed, computed + 3);
            int apart = 0;
            for (int k = 0; k < 3; ++k)
                apart |= (alo[k] - d > box[3 + k]) | (box[k] - d > ahi[k]);
            if (apart)
                continue;
            int status = push(t, 1, ta, tb);
            if (status != SELFCOL_OK)
                return status;
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
    int status = push(t, 0, 0, 0);
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
                status = leaf_pair(t, a, a, 1);
                continue;
            }
            for (uint32_t i = 0; i < a->child_count && status == SELFCOL_OK; ++i) {
                uint32_t ci = a->first_child + i;
                status = push(t, 0, ci, ci);
                for (uint32_t j = i + 1; j < a->child_count && status == SELFCOL_OK; ++j)
                    status = push(t, 0, ci, a->first_child + j);
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
            status = leaf_pair(t, a, b, 0);
            continue;
        }
        // Split the node with more triangles (a leaf is never split).
        int split_a = b->child_count == 0 || (a->child_count > 0 && a->tri_count >= b->tri_count);
        const selfcol_node *s = split_a ? a : b;
        for (uint32_t i = 0; i < s->child_count && status == SELFCOL_OK; ++i)
            status =
                split_a ? push(t, 0, s->first_child + i, p.b) : push(t, 0, p.a, s->first_child + i);
    }
    return status;
}

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

typedef struct box3 {
    double lo[3], hi[3];
} box3;

static void segment_box(box3 *b, const double *p, const double *q) {
    for (int k = 0; k < 3; ++k) {
        b->lo[k] = p[k] < q[k] ? p[k] : q[k];
        b->hi[k] = p[k] > q[k] ? p[k] : q[k];
    }
}

static int near(const box3 *a, const box3 *b, double d) {
    for (int k = 0; k < 3; ++k)
        if (a->lo[k] - d > b->hi[k] || b->lo[k] - d > a->hi[k])
            return 0;
    return 1;
}

static int point_near(const double *p, const box3 *b, double d) {
    for (int k = 0; k < 3; ++k)
        if (p[k] < b->lo[k] - d || p[k] > b->hi[k] + d)
            return 0;
    return 1;
}

// One triangle of a pair, with what the primitive tests need: its corners,
// its box, and the vertices and edges it owns (with the edges' boxes).
typedef struct triangle_view {
    uint32_t id;
    const uint32_t *corner; // the triangle's three vertex indices
    box3 box;
    uint32_t vertex[3]; // owned vertices
    int vertex_count;
    uint32_t edge[3];            // owned edges
    const uint32_t *edge_end[3]; // their two vertices
    box3 edge_box[3];
    int edge_count;
} triangle_view;

static void view_triangle(triangle_view *v, const selfcol_hierarchy *h, uint32_t t) {
    const selfcol_mesh *m = h->mesh;
    const uint8_t owned = h->owned[t];
    v->id = t;
    v->corner = m->triangles + 3 * (size_t)t;
    triangle_box(m, t, v->box.lo, v->box.hi);
    v->vertex_count = v->edge_count = 0;
    for (int i = 0; i < 3; ++i) {
        if (owned & SELFCOL_OWNS_VERTEX(i))
            v->vertex[v->vertex_count++] = v->corner[i];
        if (owned & SELFCOL_OWNS_EDGE(i)) {
            uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)i];
            const uint32_t *ends = m->edges + 2 * (size_t)e;
            v->edge[v->edge_count] = e;
            v->edge_end[v->edge_count] = ends;
            segment_box(&v->edge_box[v->edge_count], selfcol_mesh__position(m, ends[0]),
                        selfcol_mesh__position(m, ends[1]));
            v->edge_count++;
        }
    }
}

// Vertices owned by triangle a (mesh ma) against triangle b (mesh mb), and
// edges owned by a against b. Each primitive test is preceded by the same
// conservative box rejection as the exhaustive reference.
static int one_way(traversal *t, int ma, const triangle_view *a, int mb, const triangle_view *b) {
    const selfcol_mesh *A = t->q->mesh[ma];
    const int self = t->q->self;
    const double d = t->q->distance;
    int status = SELFCOL_OK;
    if (t->q->kinds & SELFCOL_KIND_VF)
        for (int i = 0; i < a->vertex_count && status == SELFCOL_OK; ++i)
            if (!(self && is_corner(a->vertex[i], b->corner)) &&
                point_near(selfcol_mesh__position(A, a->vertex[i]), &b->box, d))
                status = selfcol_query__test_vf(t->q, ma, a->vertex[i], mb, b->id);
    if (t->q->kinds & SELFCOL_KIND_EF)
        for (int k = 0; k < a->edge_count && status == SELFCOL_OK; ++k) {
            const uint32_t *ev = a->edge_end[k];
            if (!(self && (is_corner(ev[0], b->corner) || is_corner(ev[1], b->corner))) &&
                near(&a->edge_box[k], &b->box, 0.0))
                status = selfcol_query__test_ef(t->q, ma, a->edge[k], mb, b->id);
        }
    return status;
}

static int triangle_pair(traversal *t, const triangle_view *a, const triangle_view *b) {
    int status = one_way(t, 0, a, 1, b);
    if (status == SELFCOL_OK)
        status = one_way(t, 1, b, 0, a);
    if (status != SELFCOL_OK || !(t->q->kinds & SELFCOL_KIND_EE))
        return status;
    const double d = t->q->distance;
    for (int i = 0; i < a->edge_count && status == SELFCOL_OK; ++i) {
        if (!near(&a->edge_box[i], &b->box, d))
            continue;
        const uint32_t e = a->edge[i], *ev = a->edge_end[i];
        for (int j = 0; j < b->edge_count && status == SELFCOL_OK; ++j) {
            const uint32_t f = b->edge[j], *fv = b->edge_end[j];
            if (t->q->self &&
                (ev[0] == fv[0] || ev[0] == fv[1] || ev[1] == fv[0] || ev[1] == fv[1]))
                continue;
            if (!near(&a->edge_box[i], &b->edge_box[j], d))
                continue;
            if (t->q->self)
                status = e < f ? selfcol_query__test_ee(t->q, 0, e, 0, f)
                               : selfcol_query__test_ee(t->q, 0, f, 0, e);
            else
                status = selfcol_query__test_ee(t->q, 0, e, 1, f);
        }
    }
    return status;
}

int selfcol_traverse__run(selfcol_query *q, const selfcol_hierarchy *h0,
                          const selfcol_hierarchy *h1, uint32_t method) {
    traversal t = {q, {h0, h1}, method, NULL, 0, 0, NULL, 0, 0};
    double start = selfcol_core__seconds();
    int status = broad_phase(&t);
    double middle = selfcol_core__seconds();
    q->out->stats.broad_seconds = middle - start;
    q->out->stats.triangle_pairs = t.pair_count;
    // Pairs come grouped by their first triangle (leaf_pair's outer loop):
    // its view is reused while it repeats.
    triangle_view first, second;
    first.id = SELFCOL_INVALID_INDEX;
    for (size_t i = 0; i < t.pair_count && status == SELFCOL_OK; ++i) {
        if (t.pairs[i].a != first.id)
            view_triangle(&first, h0, t.pairs[i].a);
        view_triangle(&second, h1, t.pairs[i].b);
        status = triangle_pair(&t, &first, &second);
    }
    q->out->stats.narrow_seconds = selfcol_core__seconds() - middle;
    return status;
}
