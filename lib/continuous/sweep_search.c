// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The broad phase of continuous queries: primitive pairs whose swept boxes
// are within the separation delta. Both methods produce the same candidates.
//
// Why a swept box may stand for the primitive over the whole step: every
// point of a primitive at time t is a convex combination of its corners at
// time t (barycentric weights), and each corner at time t is a convex
// combination of its positions at t = 0 and t = 1 (linear motion). So the
// primitive at every t lies in the convex hull of its corners' start and end
// positions, hence in their axis-aligned box. Two primitives within delta at
// some t have boxes within delta on every axis, and selfcol_box__near rounds
// only a subtraction whose exact value is at most the other box's bound (a
// double), so rounding to nearest cannot push it above (box.h).
//
// The filters are nested: a node's swept box holds its triangles' swept
// boxes, a triangle's holds the boxes of its vertices and edges. The near
// test is monotone in the boxes, so a pair of primitives whose boxes are
// within delta also passes at every enclosing level: the hierarchy's
// traversal (BVH) finds exactly the pairs the exhaustive loop finds.
//
// Which primitive pairs a triangle pair generates: each vertex and each edge
// of the mesh is owned by one triangle (hierarchy.h, SELFCOL_OWNS_*), so
// visiting every unordered triangle pair once and testing what the two own
// generates each primitive pair exactly once, as the discrete traversal does.
#include "continuous/sweep.h"

#include "base/alloc.h"
#include "base/box.h"
#include "base/core.h"
#include "narrow/narrow_sweep.h"

#include <string.h>

// ---------------------------------------------------------------------------
// Swept boxes

// The swept box of every vertex of mesh m over [0, t_box] (6 doubles
// each), computed once per search: the pair tests read them instead of both
// position arrays. With t_box < 1 the end position is computed (within eps
// of the exact one, sweep.h): the box is widened by 2 eps, which rounds to at
// least eps since eps is at least 8 ulps of every coordinate (sweep.c).
static void vertex_boxes(const selfcol_sweep_query *q, int m, double *boxes) {
    const selfcol_mesh *mesh = q->mesh[m];
    const double widen = 2.0 * q->eps;
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        const double *p0 = q->start[m] + 3 * v, *p1 = q->end[m] + 3 * v;
        double *lo = boxes + 6 * v, *hi = lo + 3;
        for (int k = 0; k < 3; ++k) {
            lo[k] = (p0[k] < p1[k] ? p0[k] : p1[k]) - widen;
            hi[k] = (p0[k] < p1[k] ? p1[k] : p0[k]) + widen;
        }
    }
}

static void vertex_box(const selfcol_sweep_query *q, int m, uint32_t v, double lo[3],
                       double hi[3]) {
    const double *b = q->vertex_boxes[m] + 6 * (size_t)v;
    memcpy(lo, b, 3 * sizeof *lo);
    memcpy(hi, b + 3, 3 * sizeof *hi);
}

static void primitive_box(const selfcol_sweep_query *q, int m, const uint32_t *vertices, int count,
                          double lo[3], double hi[3]) {
    vertex_box(q, m, vertices[0], lo, hi);
    for (int i = 1; i < count; ++i) {
        double vlo[3], vhi[3];
        vertex_box(q, m, vertices[i], vlo, vhi);
        selfcol_box__merge(lo, hi, vlo, vhi);
    }
}

// The swept boxes of mesh m's triangles (6 doubles each, by triangle index).
static void triangle_boxes(const selfcol_sweep_query *q, int m, double *boxes) {
    const selfcol_mesh *mesh = q->mesh[m];
    for (size_t t = 0; t < mesh->triangle_count; ++t)
        primitive_box(q, m, mesh->triangles + 3 * t, 3, boxes + 6 * t, boxes + 6 * t + 3);
}

// The swept boxes of hierarchy m's nodes from its triangles' boxes. Nodes are
// stored breadth-first (children after their parent), so a reverse sweep
// sees every child before its parent.
static void node_boxes(const selfcol_sweep_query *q, int m, const double *tri_boxes,
                       double *boxes) {
    const selfcol_hierarchy *h = q->hierarchy[m];
    for (size_t i = h->node_count; i-- > 0;) {
        const selfcol_node *n = &h->nodes[i];
        double *lo = boxes + 6 * i, *hi = lo + 3;
        if (n->child_count == 0) {
            const uint32_t *slot = h->tri_order + n->tri_begin;
            const double *first = tri_boxes + 6 * (size_t)slot[0];
            memcpy(lo, first, 3 * sizeof *lo);
            memcpy(hi, first + 3, 3 * sizeof *hi);
            for (uint32_t k = 1; k < n->tri_count; ++k) {
                const double *b = tri_boxes + 6 * (size_t)slot[k];
                selfcol_box__merge(lo, hi, b, b + 3);
            }
        } else {
            const double *c = boxes + 6 * (size_t)n->first_child;
            memcpy(lo, c, 3 * sizeof *lo);
            memcpy(hi, c + 3, 3 * sizeof *hi);
            for (uint32_t k = 1; k < n->child_count; ++k)
                selfcol_box__merge(lo, hi, c + 6 * k, c + 6 * k + 3);
        }
    }
}

// ---------------------------------------------------------------------------
// Primitive pairs

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

static int share_vertex(const uint32_t *e, const uint32_t *f) {
    return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
}

// The separating-direction filter of narrow_sweep.h on a pair whose swept
// boxes are near: counted, and kept out of the candidates when it shows the
// pair apart over the whole step.
static int apart(selfcol_sweep_query *q, const uint32_t ids[4], const int meshes[4],
                 int edge_edge) {
    const double *start[4], *end[4];
    for (int k = 0; k < 4; ++k) {
        start[k] = q->start[meshes[k]] + 3 * (size_t)ids[k];
        end[k] = q->end[meshes[k]] + 3 * (size_t)ids[k];
    }
    // Over [0, t_box], each computed end is within eps of the exact one in
    // every coordinate, so every point of the computed motion is within
    // sqrt(3) eps of the exact motion's at the same time: a pair the
    // computed motion keeps beyond separation + 4 eps is beyond the
    // separation (sweep.h).
    // The broad phase runs on one thread: one direction hint per kind.
    if (!selfcol_narrow_sweep__separated_from(start, end, edge_edge, q->separation + 4.0 * q->eps,
                                              &q->separating_hint[edge_edge]))
        return 0;
    q->out->stats.separated++;
    return 1;
}

// Vertex v of mesh mv against triangle t of mesh mt, when the pair belongs
// to the contact set (sweep.h): t is no duplicate, v no corner of t (self).
// tbox: t's swept box (lo, hi) when the caller has it, else NULL.
static int try_vf(selfcol_sweep_query *q, int mv, uint32_t v, int mt, uint32_t t,
                  const double *tbox) {
    const selfcol_mesh *mesht = q->mesh[mt];
    if (mesht->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
        return SELFCOL_OK;
    const uint32_t *tri = mesht->triangles + 3 * (size_t)t;
    if (q->self && is_corner(v, tri))
        return SELFCOL_OK;
    double tlo[3], thi[3];
    if (tbox == NULL) {
        primitive_box(q, mt, tri, 3, tlo, thi);
    } else {
        memcpy(tlo, tbox, sizeof tlo);
        memcpy(thi, tbox + 3, sizeof thi);
    }
    const double *vbox = q->vertex_boxes[mv] + 6 * (size_t)v;
    if (!selfcol_box__near(vbox, vbox + 3, tlo, thi, q->separation))
        return SELFCOL_OK;
    q->out->stats.vf_candidates++;
    const uint32_t ids[4] = {v, tri[0], tri[1], tri[2]};
    const int meshes[4] = {mv, mt, mt, mt};
    if (apart(q, ids, meshes, 0))
        return SELFCOL_OK;
    const selfcol_sweep_candidate c = {SELFCOL_CONTACT_VF, (uint8_t)mv, (uint8_t)mt, 0, v, t};
    return q->earliest_mode ? selfcol_sweep__earliest_pair(q, &c)
                            : selfcol_sweep__push_candidate(q->out, &c);
}

// Edge e of mesh 0 against edge f of mesh 1 (self: both of the one mesh,
// sharing no vertex; recorded with the lower index first).
static int try_ee(selfcol_sweep_query *q, uint32_t e, uint32_t f) {
    const uint32_t *ev = q->mesh[0]->edges + 2 * (size_t)e;
    const uint32_t *fv = q->mesh[1]->edges + 2 * (size_t)f;
    if (q->self && share_vertex(ev, fv))
        return SELFCOL_OK;
    double elo[3], ehi[3], flo[3], fhi[3];
    primitive_box(q, 0, ev, 2, elo, ehi);
    primitive_box(q, 1, fv, 2, flo, fhi);
    if (!selfcol_box__near(elo, ehi, flo, fhi, q->separation))
        return SELFCOL_OK;
    q->out->stats.ee_candidates++;
    const uint32_t ids[4] = {ev[0], ev[1], fv[0], fv[1]};
    const int meshes[4] = {0, 0, q->self ? 0 : 1, q->self ? 0 : 1};
    if (apart(q, ids, meshes, 1))
        return SELFCOL_OK;
    selfcol_sweep_candidate c = {SELFCOL_CONTACT_EE, 0, 1, 0, e, f};
    if (q->self) {
        c.second_mesh = 0;
        c.first = e < f ? e : f;
        c.second = e < f ? f : e;
    }
    return q->earliest_mode ? selfcol_sweep__earliest_pair(q, &c)
                            : selfcol_sweep__push_candidate(q->out, &c);
}

// ---------------------------------------------------------------------------
// EXHAUSTIVE: every pair, in key order.

int selfcol_sweep__exhaustive(selfcol_sweep_query *q) {
    int status = SELFCOL_OK;
    const int meshes = q->self ? 1 : 2;
    double *at = q->out->boxes; // sized by sweep.c
    for (int m = 0; m < meshes; ++m) {
        q->vertex_boxes[m] = at;
        at += 6 * q->mesh[m]->vertex_count;
        vertex_boxes(q, m, at - 6 * q->mesh[m]->vertex_count);
    }
    if (q->self)
        q->vertex_boxes[1] = q->vertex_boxes[0];
    if (q->kinds & SELFCOL_KIND_VF)
        for (int mv = 0; mv < meshes && status == SELFCOL_OK; ++mv) {
            const int mt = q->self ? 0 : 1 - mv;
            const selfcol_mesh *meshv = q->mesh[mv];
            for (uint32_t v = 0; v < meshv->vertex_count && status == SELFCOL_OK; ++v) {
                if (selfcol_mesh__vertex_degree(meshv, v) == 0)
                    continue; // not part of the surface
                for (uint32_t t = 0; t < q->mesh[mt]->triangle_count && status == SELFCOL_OK; ++t)
                    status = try_vf(q, mv, v, mt, t, NULL);
            }
        }
    if (q->kinds & SELFCOL_KIND_EE)
        for (uint32_t e = 0; e < q->mesh[0]->edge_count && status == SELFCOL_OK; ++e)
            for (uint32_t f = q->self ? e + 1 : 0;
                 f < q->mesh[1]->edge_count && status == SELFCOL_OK; ++f)
                status = try_ee(q, e, f);
    q->out->stats.candidates = q->out->stats.vf_candidates + q->out->stats.ee_candidates;
    return status;
}

// ---------------------------------------------------------------------------
// BVH: the hierarchies' trees with swept boxes.

// The primitive pairs triangles ta (mesh 0) and tb (mesh 1) own; for a self
// query two distinct triangles of the mesh.
static int triangle_pair(selfcol_sweep_query *q, uint32_t ta, uint32_t tb, const double *boxa,
                         const double *boxb) {
    const selfcol_mesh *ma = q->mesh[0], *mb = q->mesh[1];
    const uint8_t oa = q->hierarchy[0]->owned[ta], ob = q->hierarchy[1]->owned[tb];
    const uint32_t *tria = ma->triangles + 3 * (size_t)ta, *trib = mb->triangles + 3 * (size_t)tb;
    int status = SELFCOL_OK;
    const int mesh_b = q->self ? 0 : 1;
    if (q->kinds & SELFCOL_KIND_VF)
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (oa & SELFCOL_OWNS_VERTEX(i))
                status = try_vf(q, 0, tria[i], mesh_b, tb, boxb);
            if (status == SELFCOL_OK && (ob & SELFCOL_OWNS_VERTEX(i)))
                status = try_vf(q, mesh_b, trib[i], 0, ta, boxa);
        }
    if (q->kinds & SELFCOL_KIND_EE)
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(oa & SELFCOL_OWNS_EDGE(i)))
                continue;
            const uint32_t e = ma->triangle_edges[3 * (size_t)ta + (size_t)i];
            for (int j = 0; j < 3 && status == SELFCOL_OK; ++j)
                if (ob & SELFCOL_OWNS_EDGE(j))
                    status = try_ee(q, e, mb->triangle_edges[3 * (size_t)tb + (size_t)j]);
        }
    return status;
}

// Every triangle pair of two leaves (self: a == b, the unordered pairs of
// distinct triangles of one leaf), each behind its triangles' swept boxes.
static int leaf_pair(selfcol_sweep_query *q, const double *const tri_boxes[2], const double *node_b,
                     uint32_t a, uint32_t b) {
    const selfcol_hierarchy *ha = q->hierarchy[0], *hb = q->hierarchy[1];
    const selfcol_node *na = &ha->nodes[a], *nb = &hb->nodes[b];
    const int same = q->self && a == b;
    int status = SELFCOL_OK;
    for (uint32_t i = 0; i < na->tri_count && status == SELFCOL_OK; ++i) {
        const uint32_t ta = ha->tri_order[na->tri_begin + i];
        const double *boxa = tri_boxes[0] + 6 * (size_t)ta;
        if (!same && !selfcol_box__near(boxa, boxa + 3, node_b, node_b + 3, q->separation))
            continue; // ta is apart from all of b (b's box holds its triangles')
        for (uint32_t j = same ? i + 1 : 0; j < nb->tri_count && status == SELFCOL_OK; ++j) {
            const uint32_t tb = hb->tri_order[nb->tri_begin + j];
            const double *boxb = tri_boxes[1] + 6 * (size_t)tb;
            if (selfcol_box__near(boxa, boxa + 3, boxb, boxb + 3, q->separation))
                status = triangle_pair(q, ta, tb, boxa, boxb);
        }
    }
    return status;
}

static int push_pair(selfcol_sweep *s, size_t *top, uint32_t a, uint32_t b) {
    if (*top + 2 > s->stack_capacity) {
        const size_t cap = s->stack_capacity < 256 ? 256 : 2 * s->stack_capacity;
        uint32_t *grown = selfcol_alloc__array(&s->allocator, cap, sizeof *grown);
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        if (*top > 0)
            memcpy(grown, s->stack, *top * sizeof *grown);
        selfcol_alloc__free_array(&s->allocator, s->stack, s->stack_capacity, sizeof *s->stack);
        s->stack = grown;
        s->stack_capacity = cap;
    }
    s->stack[(*top)++] = a;
    s->stack[(*top)++] = b;
    return SELFCOL_OK;
}

int selfcol_sweep__bvh(selfcol_sweep_query *q) {
    selfcol_sweep *s = q->out;
    const int meshes = q->self ? 1 : 2;
    double *tri_boxes[2], *nodes[2];
    double *at = s->boxes; // sized by sweep.c
    for (int m = 0; m < meshes; ++m) {
        q->vertex_boxes[m] = at;
        at += 6 * q->mesh[m]->vertex_count;
        vertex_boxes(q, m, at - 6 * q->mesh[m]->vertex_count);
    }
    if (q->self)
        q->vertex_boxes[1] = q->vertex_boxes[0];
    for (int m = 0; m < meshes; ++m) {
        tri_boxes[m] = at;
        at += 6 * q->mesh[m]->triangle_count;
        nodes[m] = at;
        at += 6 * q->hierarchy[m]->node_count;
        triangle_boxes(q, m, tri_boxes[m]);
        node_boxes(q, m, tri_boxes[m], nodes[m]);
    }
    if (q->self) {
        tri_boxes[1] = tri_boxes[0];
        nodes[1] = nodes[0];
    }
    const double *const tri_read[2] = {tri_boxes[0], tri_boxes[1]};
    const selfcol_hierarchy *ha = q->hierarchy[0], *hb = q->hierarchy[1];
    if (ha->node_count == 0 || hb->node_count == 0)
        return SELFCOL_OK; // an empty mesh
    if (q->cull) {
        const int status = selfcol_sweep__cull_prepare(q);
        if (status != SELFCOL_OK)
            return status;
    }
    // Node pairs (a, b): a of hierarchy 0, b of hierarchy 1. In a self query
    // a == b stands for the node against itself: its children each against
    // themselves and against each other.
    size_t top = 0;
    int status = push_pair(s, &top, 0, 0);
    while (top > 0 && status == SELFCOL_OK) {
        const uint32_t b = s->stack[--top], a = s->stack[--top];
        const selfcol_node *na = &ha->nodes[a], *nb = &hb->nodes[b];
        if (q->self && a == b) {
            if (na->flags & SELFCOL_NODE_DUPLICATES)
                continue; // owns nothing, no contact's triangle (hierarchy.h)
            if (q->cull && selfcol_sweep__self_free(q, a))
                continue; // curvature and contour over the step (sweep_cull.c)
            if (na->child_count == 0) {
                status = leaf_pair(q, tri_read, NULL, a, a);
                continue;
            }
            for (uint32_t i = 0; i < na->child_count && status == SELFCOL_OK; ++i)
                for (uint32_t j = i; j < na->child_count && status == SELFCOL_OK; ++j)
                    status = push_pair(s, &top, na->first_child + i, na->first_child + j);
            continue;
        }
        s->stats.node_pairs++;
        const double *ba = nodes[0] + 6 * (size_t)a, *bb = nodes[1] + 6 * (size_t)b;
        if ((na->flags & SELFCOL_NODE_DUPLICATES) || (nb->flags & SELFCOL_NODE_DUPLICATES) ||
            !selfcol_box__near(ba, ba + 3, bb, bb + 3, q->separation))
            continue;
        if (q->cull && selfcol_sweep__pair_free(q, a, b))
            continue; // adjacent patches, jointly free over the step
        if (na->child_count == 0 && nb->child_count == 0) {
            status = leaf_pair(q, tri_read, bb, a, b);
            continue;
        }
        // Descend into the node with more triangles (an internal one).
        const int split_a =
            nb->child_count == 0 || (na->child_count > 0 && na->tri_count >= nb->tri_count);
        const selfcol_node *n = split_a ? na : nb;
        for (uint32_t i = 0; i < n->child_count && status == SELFCOL_OK; ++i)
            status = split_a ? push_pair(s, &top, n->first_child + i, b)
                             : push_pair(s, &top, a, n->first_child + i);
    }
    s->stats.candidates = s->stats.vf_candidates + s->stats.ee_candidates;
    return status;
}
