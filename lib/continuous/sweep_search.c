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
#include "base/parallel.h"
#include "narrow/narrow_sweep.h"

#include <stdint.h>
#include <string.h>

// ---------------------------------------------------------------------------
// Swept boxes

// The swept boxes of vertices begin .. end - 1 of mesh m over [0, t_box]
// (6 doubles each), computed once per search: the pair tests read them
// instead of both position arrays. With t_box < 1 the end position is
// computed (within eps of the exact one, sweep.h): the box is widened by
// 2 eps, which rounds to at least eps since eps is at least 8 ulps of every
// coordinate (sweep.c).
static void vertex_boxes(const selfcol_sweep_query *q, int m, double *boxes, size_t begin,
                         size_t end) {
    const double widen = 2.0 * q->eps;
    for (size_t v = begin; v < end; ++v) {
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

// Restricted queries (sweep.h, active_vertices): whether vertex v of mesh
// m is active, and whether a triangle of mesh m (its three vertices) has an
// active vertex.
static int vertex_active(const selfcol_sweep_query *q, int m, uint32_t v) {
    return q->active[m] != NULL && q->active[m][v] != 0;
}

static int corners_active(const selfcol_sweep_query *q, int m, const uint32_t *tri) {
    return q->active[m] != NULL &&
           (q->active[m][tri[0]] | q->active[m][tri[1]] | q->active[m][tri[2]]) != 0;
}

// The leaves among nodes begin .. end - 1 of hierarchy m: the swept boxes
// of their triangles (6 doubles each, by triangle index; the leaves hold
// every triangle once, hierarchy_validate.c) and their own boxes; in a
// restricted query, whether a triangle of the leaf has an active vertex.
static void leaf_boxes(const selfcol_sweep_query *q, int m, double *tri_boxes, double *boxes,
                       size_t begin, size_t end) {
    const selfcol_hierarchy *h = q->hierarchy[m];
    const uint32_t *triangles = q->mesh[m]->triangles;
    for (size_t i = begin; i < end; ++i) {
        const selfcol_node *n = &h->nodes[i];
        if (n->child_count != 0)
            continue;
        double *lo = boxes + 6 * i, *hi = lo + 3;
        const uint32_t *slot = h->tri_order + n->tri_begin;
        int active = 0;
        for (uint32_t k = 0; k < n->tri_count; ++k) {
            double *b = tri_boxes + 6 * (size_t)slot[k];
            const uint32_t *tri = triangles + 3 * (size_t)slot[k];
            primitive_box(q, m, tri, 3, b, b + 3);
            active |= q->restricted && corners_active(q, m, tri);
            if (k == 0) {
                memcpy(lo, b, 3 * sizeof *lo);
                memcpy(hi, b + 3, 3 * sizeof *hi);
            } else {
                selfcol_box__merge(lo, hi, b, b + 3);
            }
        }
        if (q->restricted)
            q->node_active[m][i] = (uint8_t)active;
    }
}

// The internal nodes' boxes from their children's. Nodes are stored
// breadth-first (children after their parent), so a reverse sweep sees
// every child before its parent.
static void internal_boxes(const selfcol_sweep_query *q, int m, double *boxes) {
    const selfcol_hierarchy *h = q->hierarchy[m];
    for (size_t i = h->node_count; i-- > 0;) {
        const selfcol_node *n = &h->nodes[i];
        if (n->child_count == 0)
            continue;
        double *lo = boxes + 6 * i, *hi = lo + 3;
        const double *c = boxes + 6 * (size_t)n->first_child;
        memcpy(lo, c, 3 * sizeof *lo);
        memcpy(hi, c + 3, 3 * sizeof *hi);
        for (uint32_t k = 1; k < n->child_count; ++k)
            selfcol_box__merge(lo, hi, c + 6 * k, c + 6 * k + 3);
        if (q->restricted) {
            uint8_t active = 0;
            for (uint32_t k = 0; k < n->child_count; ++k)
                active |= q->node_active[m][n->first_child + k];
            q->node_active[m][i] = active;
        }
    }
}

// The boxes of a search on the query's threads (each pass of EARLIEST
// makes them anew: on one thread, about 1 % of the query, but on 16 the
// largest serial part left). Two stages of chunks taken from a counter,
// the vertices, then the leaves (which read the vertices' boxes); the
// internal nodes, a quarter of the nodes and a few merges each, stay on the
// calling thread. Each box is a function of the positions alone: the same
// for every thread count.
#define BOX_CHUNK 4096u

typedef struct box_job {
    const selfcol_sweep_query *q;
    double *vertex[2], *tri[2], *node[2];
    int leaves;          // 0: the vertices' stage, 1: the leaves'
    size_t items[2];     // per mesh: vertices, or nodes
    uint32_t chunks[2];  // per mesh
    uint32_t next_chunk; // atomic
} box_job;

static int box_worker(void *context, unsigned worker) {
    (void)worker;
    box_job *job = context;
    for (;;) {
        uint32_t c = SELFCOL_ATOMIC_FETCH_ADD(&job->next_chunk, 1u);
        if (c >= job->chunks[0] + job->chunks[1])
            return SELFCOL_OK;
        const int m = c >= job->chunks[0];
        c -= m ? job->chunks[0] : 0u;
        const size_t begin = (size_t)c * BOX_CHUNK;
        const size_t end = begin + BOX_CHUNK < job->items[m] ? begin + BOX_CHUNK : job->items[m];
        if (job->leaves)
            leaf_boxes(job->q, m, job->tri[m], job->node[m], begin, end);
        else
            vertex_boxes(job->q, m, job->vertex[m], begin, end);
    }
}

static void box_stage(box_job *job, const selfcol_executor *executor, unsigned threads, int leaves,
                      int meshes) {
    job->leaves = leaves;
    job->next_chunk = 0;
    for (int m = 0; m < 2; ++m) {
        job->items[m] = m >= meshes ? 0
                        : leaves    ? job->q->hierarchy[m]->node_count
                                    : job->q->mesh[m]->vertex_count;
        job->chunks[m] = (uint32_t)((job->items[m] + BOX_CHUNK - 1) / BOX_CHUNK);
    }
    const uint32_t chunks = job->chunks[0] + job->chunks[1];
    const unsigned workers = chunks < threads ? chunks : threads;
    if (workers > 1)
        (void)selfcol_parallel__run(executor, workers, box_worker, job);
    else
        (void)box_worker(job, 0);
}

// ---------------------------------------------------------------------------
// Primitive pairs

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

static int share_vertex(const uint32_t *e, const uint32_t *f) {
    return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
}

// A worker off the calling thread found an array full (its task is run
// again once the calling thread has grown it). Internal to this file.
#define SWEEP_OVERFLOW 2

// Where a candidate goes: to the query at once (one worker: ALL's list, or
// EARLIEST's root search, which may ask for a restart), or to the worker's
// list, in the order found.
static int emit(selfcol_sweep_worker *w, const selfcol_sweep_candidate *c) {
    if (w->direct)
        return w->q->earliest_mode ? selfcol_sweep__earliest_pair(w->q, c)
                                   : selfcol_sweep__push_candidate(w->q->out, c);
    // A full list stops the task (run_round grows it on the calling thread
    // and runs the task again): workers never allocate.
    if (w->found_count == w->found_capacity)
        return SWEEP_OVERFLOW;
    w->found[w->found_count++] = *c;
    return SELFCOL_OK;
}

// The separating-direction filter of narrow_sweep.h on a pair whose swept
// boxes are near: counted, and kept out of the candidates when it shows the
// pair apart over the whole step.
static int apart(selfcol_sweep_worker *w, const uint32_t ids[4], const int meshes[4],
                 int edge_edge) {
    const selfcol_sweep_query *q = w->q;
    const double *start[4], *end[4];
    for (int k = 0; k < 4; ++k) {
        start[k] = q->start[meshes[k]] + 3 * (size_t)ids[k];
        end[k] = q->end[meshes[k]] + 3 * (size_t)ids[k];
    }
    // Over [0, t_box], each computed end is within eps of the exact one in
    // every coordinate, so every point of the computed motion is within
    // sqrt(3) eps of the exact motion's at the same time: a pair the
    // computed motion keeps beyond separation + 4 eps is beyond the
    // separation (sweep.h). The hint only orders the directions tried: the
    // answer does not depend on it.
    if (!selfcol_narrow_sweep__separated_from(start, end, edge_edge, q->separation + 4.0 * q->eps,
                                              &w->hint[edge_edge]))
        return 0;
    w->separated++;
    return 1;
}

// Vertex v of mesh mv against triangle t of mesh mt, when the pair belongs
// to the contact set (sweep.h): t is no duplicate, v no corner of t (self).
// tbox: t's swept box (lo, hi) when the caller has it, else NULL.
static int try_vf(selfcol_sweep_worker *w, int mv, uint32_t v, int mt, uint32_t t,
                  const double *tbox) {
    const selfcol_sweep_query *q = w->q;
    const selfcol_mesh *mesht = q->mesh[mt];
    if (mesht->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
        return SELFCOL_OK;
    const uint32_t *tri = mesht->triangles + 3 * (size_t)t;
    if (q->self && is_corner(v, tri))
        return SELFCOL_OK;
    if (q->restricted && !vertex_active(q, mv, v) && !corners_active(q, mt, tri))
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
    w->vf_candidates++;
    const uint32_t ids[4] = {v, tri[0], tri[1], tri[2]};
    const int meshes[4] = {mv, mt, mt, mt};
    if (apart(w, ids, meshes, 0))
        return SELFCOL_OK;
    const selfcol_sweep_candidate c = {SELFCOL_CONTACT_VF, (uint8_t)mv, (uint8_t)mt, 0, v, t};
    return emit(w, &c);
}

// Edge e of mesh 0 against edge f of mesh 1 (self: both of the one mesh,
// sharing no vertex; recorded with the lower index first).
static int try_ee(selfcol_sweep_worker *w, uint32_t e, uint32_t f) {
    const selfcol_sweep_query *q = w->q;
    const uint32_t *ev = q->mesh[0]->edges + 2 * (size_t)e;
    const uint32_t *fv = q->mesh[1]->edges + 2 * (size_t)f;
    if (q->self && share_vertex(ev, fv))
        return SELFCOL_OK;
    if (q->restricted && !vertex_active(q, 0, ev[0]) && !vertex_active(q, 0, ev[1]) &&
        !vertex_active(q, 1, fv[0]) && !vertex_active(q, 1, fv[1]))
        return SELFCOL_OK;
    double elo[3], ehi[3], flo[3], fhi[3];
    primitive_box(q, 0, ev, 2, elo, ehi);
    primitive_box(q, 1, fv, 2, flo, fhi);
    if (!selfcol_box__near(elo, ehi, flo, fhi, q->separation))
        return SELFCOL_OK;
    w->ee_candidates++;
    const uint32_t ids[4] = {ev[0], ev[1], fv[0], fv[1]};
    const int meshes[4] = {0, 0, q->self ? 0 : 1, q->self ? 0 : 1};
    if (apart(w, ids, meshes, 1))
        return SELFCOL_OK;
    selfcol_sweep_candidate c = {SELFCOL_CONTACT_EE, 0, 1, 0, e, f};
    if (q->self) {
        c.second_mesh = 0;
        c.first = e < f ? e : f;
        c.second = e < f ? f : e;
    }
    return emit(w, &c);
}

// A worker's counters into the query's statistics.
static void add_counters(selfcol_sweep *s, selfcol_sweep_worker *w) {
    s->stats.node_pairs += w->node_pairs;
    s->stats.vf_candidates += w->vf_candidates;
    s->stats.ee_candidates += w->ee_candidates;
    s->stats.separated += w->separated;
    w->node_pairs = w->vf_candidates = w->ee_candidates = w->separated = 0;
}

// ---------------------------------------------------------------------------
// EXHAUSTIVE: every pair, in key order, on one worker.

int selfcol_sweep__exhaustive(selfcol_sweep_query *q) {
    int status = SELFCOL_OK;
    const int meshes = q->self ? 1 : 2;
    double *at = q->out->boxes; // sized by sweep.c
    for (int m = 0; m < meshes; ++m) {
        q->vertex_boxes[m] = at;
        at += 6 * q->mesh[m]->vertex_count;
        vertex_boxes(q, m, at - 6 * q->mesh[m]->vertex_count, 0, q->mesh[m]->vertex_count);
    }
    if (q->self)
        q->vertex_boxes[1] = q->vertex_boxes[0];
    selfcol_sweep_worker w;
    memset(&w, 0, sizeof w);
    w.q = q;
    w.direct = 1;
    if (q->kinds & SELFCOL_KIND_VF)
        for (int mv = 0; mv < meshes && status == SELFCOL_OK; ++mv) {
            const int mt = q->self ? 0 : 1 - mv;
            const selfcol_mesh *meshv = q->mesh[mv];
            for (uint32_t v = 0; v < meshv->vertex_count && status == SELFCOL_OK; ++v) {
                if (selfcol_mesh__vertex_degree(meshv, v) == 0)
                    continue; // not part of the surface
                for (uint32_t t = 0; t < q->mesh[mt]->triangle_count && status == SELFCOL_OK; ++t)
                    status = try_vf(&w, mv, v, mt, t, NULL);
            }
        }
    if (q->kinds & SELFCOL_KIND_EE)
        for (uint32_t e = 0; e < q->mesh[0]->edge_count && status == SELFCOL_OK; ++e)
            for (uint32_t f = q->self ? e + 1 : 0;
                 f < q->mesh[1]->edge_count && status == SELFCOL_OK; ++f)
                status = try_ee(&w, e, f);
    add_counters(q->out, &w);
    q->out->stats.candidates = q->out->stats.vf_candidates + q->out->stats.ee_candidates;
    return status;
}

// ---------------------------------------------------------------------------
// BVH: the hierarchies' trees with swept boxes.

// The primitive pairs triangles ta (mesh 0) and tb (mesh 1) own; for a self
// query two distinct triangles of the mesh.
static int triangle_pair(selfcol_sweep_worker *w, uint32_t ta, uint32_t tb, const double *boxa,
                         const double *boxb) {
    const selfcol_sweep_query *q = w->q;
    const selfcol_mesh *ma = q->mesh[0], *mb = q->mesh[1];
    const uint8_t oa = q->hierarchy[0]->owned[ta], ob = q->hierarchy[1]->owned[tb];
    const uint32_t *tria = ma->triangles + 3 * (size_t)ta, *trib = mb->triangles + 3 * (size_t)tb;
    int status = SELFCOL_OK;
    const int mesh_b = q->self ? 0 : 1;
    if (q->kinds & SELFCOL_KIND_VF)
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (oa & SELFCOL_OWNS_VERTEX(i))
                status = try_vf(w, 0, tria[i], mesh_b, tb, boxb);
            if (status == SELFCOL_OK && (ob & SELFCOL_OWNS_VERTEX(i)))
                status = try_vf(w, mesh_b, trib[i], 0, ta, boxa);
        }
    if (q->kinds & SELFCOL_KIND_EE)
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(oa & SELFCOL_OWNS_EDGE(i)))
                continue;
            const uint32_t e = ma->triangle_edges[3 * (size_t)ta + (size_t)i];
            for (int j = 0; j < 3 && status == SELFCOL_OK; ++j)
                if (ob & SELFCOL_OWNS_EDGE(j))
                    status = try_ee(w, e, mb->triangle_edges[3 * (size_t)tb + (size_t)j]);
        }
    return status;
}

// Every triangle pair of two leaves (self: a == b, the unordered pairs of
// distinct triangles of one leaf), each behind its triangles' swept boxes.
static int leaf_pair(selfcol_sweep_worker *w, const double *const tri_boxes[2],
                     const double *node_b, uint32_t a, uint32_t b) {
    const selfcol_sweep_query *q = w->q;
    const selfcol_hierarchy *ha = q->hierarchy[0], *hb = q->hierarchy[1];
    const selfcol_node *na = &ha->nodes[a], *nb = &hb->nodes[b];
    const int same = q->self && a == b;
    // Restricted: pairs of two triangles without an active vertex are skipped
    // (their primitive pairs have none), all of ta's when b has none.
    const int b_active = !q->restricted || q->node_active[1][b];
    const uint32_t *tris_a = q->mesh[0]->triangles, *tris_b = q->mesh[1]->triangles;
    int status = SELFCOL_OK;
    for (uint32_t i = 0; i < na->tri_count && status == SELFCOL_OK; ++i) {
        const uint32_t ta = ha->tri_order[na->tri_begin + i];
        const double *boxa = tri_boxes[0] + 6 * (size_t)ta;
        const int ta_active = !q->restricted || corners_active(q, 0, tris_a + 3 * (size_t)ta);
        if (!ta_active && !b_active)
            continue;
        if (!same && !selfcol_box__near(boxa, boxa + 3, node_b, node_b + 3, q->separation))
            continue; // ta is apart from all of b (b's box holds its triangles')
        for (uint32_t j = same ? i + 1 : 0; j < nb->tri_count && status == SELFCOL_OK; ++j) {
            const uint32_t tb = hb->tri_order[nb->tri_begin + j];
            const double *boxb = tri_boxes[1] + 6 * (size_t)tb;
            if (!ta_active && !corners_active(q, 1, tris_b + 3 * (size_t)tb))
                continue;
            if (selfcol_box__near(boxa, boxa + 3, boxb, boxb + 3, q->separation))
                status = triangle_pair(w, ta, tb, boxa, boxb);
        }
    }
    return status;
}

// Doubles an array of `size`-byte elements (to at least `least`), its first
// `used` kept: on the calling thread (a worker never grows one).
static int grow_array(selfcol_sweep *s, void **array, size_t *capacity, size_t used, size_t size,
                      size_t least) {
    const size_t cap = *capacity < least ? least : 2 * *capacity;
    if (cap > SIZE_MAX / 2 / size)
        return SELFCOL_ENOMEM;
    void *grown = selfcol_alloc__array(&s->allocator, cap, size);
    if (grown == NULL)
        return SELFCOL_ENOMEM;
    if (used > 0)
        memcpy(grown, *array, used * size);
    selfcol_alloc__free_array(&s->allocator, *array, *capacity, size);
    *array = grown;
    *capacity = cap;
    return SELFCOL_OK;
}

// Appends node pair (a, b) to an array of pairs (*top entries, 2 per
// pair), grown on the sweep's allocator when `grow` (the calling thread),
// else SWEEP_OVERFLOW when full.
static int push_pair(selfcol_sweep *s, int grow, uint32_t **array, size_t *capacity, size_t *top,
                     uint32_t a, uint32_t b) {
    if (*top + 2 > *capacity) {
        if (!grow)
            return SWEEP_OVERFLOW;
        const int status = grow_array(s, (void **)array, capacity, *top, sizeof **array, 256);
        if (status != SELFCOL_OK)
            return status;
    }
    (*array)[(*top)++] = a;
    (*array)[(*top)++] = b;
    return SELFCOL_OK;
}

// The boxes the traversal reads.
typedef struct bvh_boxes {
    const double *tri[2], *nodes[2];
} bvh_boxes;

// One step of the traversal on node pair (a, b): the pair's tests, then its
// leaf pairs (to w) or its children (pushed with `push` onto the array).
// Self queries: a == b stands for the node against itself, its children each
// against themselves and against each other.
static int visit(selfcol_sweep_worker *w, const bvh_boxes *bx, uint32_t a, uint32_t b,
                 uint32_t **array, size_t *capacity, size_t *top) {
    selfcol_sweep_query *q = w->q;
    selfcol_sweep *s = q->out;
    const selfcol_hierarchy *ha = q->hierarchy[0], *hb = q->hierarchy[1];
    const selfcol_node *na = &ha->nodes[a], *nb = &hb->nodes[b];
    int status = SELFCOL_OK;
    if (q->self && a == b) {
        if (na->flags & SELFCOL_NODE_DUPLICATES)
            return SELFCOL_OK; // owns nothing, no contact's triangle (hierarchy.h)
        if (q->restricted && !q->node_active[0][a])
            return SELFCOL_OK; // no active vertex below (sweep.h)
        if (q->cull && selfcol_sweep__self_free(q, a))
            return SELFCOL_OK; // curvature and contour over the step (sweep_cull.c)
        if (na->child_count == 0)
            return leaf_pair(w, bx->tri, NULL, a, a);
        for (uint32_t i = 0; i < na->child_count && status == SELFCOL_OK; ++i)
            for (uint32_t j = i; j < na->child_count && status == SELFCOL_OK; ++j)
                status = push_pair(s, w->on_caller, array, capacity, top, na->first_child + i,
                                   na->first_child + j);
        return status;
    }
    if (q->restricted && !q->node_active[0][a] && !q->node_active[1][b])
        return SELFCOL_OK; // no active vertex below either
    w->node_pairs++;
    const double *ba = bx->nodes[0] + 6 * (size_t)a, *bb = bx->nodes[1] + 6 * (size_t)b;
    if ((na->flags & SELFCOL_NODE_DUPLICATES) || (nb->flags & SELFCOL_NODE_DUPLICATES) ||
        !selfcol_box__near(ba, ba + 3, bb, bb + 3, q->separation))
        return SELFCOL_OK;
    if (q->cull && selfcol_sweep__pair_free(q, a, b))
        return SELFCOL_OK; // adjacent patches, jointly free over the step
    if (na->child_count == 0 && nb->child_count == 0)
        return leaf_pair(w, bx->tri, bb, a, b);
    // Descend into the node with more triangles (an internal one).
    const int split_a =
        nb->child_count == 0 || (na->child_count > 0 && na->tri_count >= nb->tri_count);
    const selfcol_node *n = split_a ? na : nb;
    for (uint32_t i = 0; i < n->child_count && status == SELFCOL_OK; ++i)
        status = split_a ? push_pair(s, w->on_caller, array, capacity, top, n->first_child + i, b)
                         : push_pair(s, w->on_caller, array, capacity, top, a, n->first_child + i);
    return status;
}

// Whether visiting (a, b) would only push children: an internal pair (the
// front expands these; leaf pairs stay tasks).
static int expands(const selfcol_sweep_query *q, uint32_t a, uint32_t b) {
    const selfcol_node *na = &q->hierarchy[0]->nodes[a], *nb = &q->hierarchy[1]->nodes[b];
    return na->child_count > 0 || nb->child_count > 0;
}

// A task's expected work: the triangles below its two nodes (one for a
// node against itself).
static uint64_t task_size(const selfcol_sweep_query *q, uint32_t a, uint32_t b) {
    const uint64_t ta = q->hierarchy[0]->nodes[a].tri_count;
    return q->self && a == b ? ta : ta + q->hierarchy[1]->nodes[b].tri_count;
}

// One task: the depth-first traversal below node pair (a, b).
static int run_task(selfcol_sweep_worker *w, const bvh_boxes *bx, uint32_t a, uint32_t b) {
    size_t top = 0;
    int status = push_pair(w->q->out, w->on_caller, &w->stack, &w->stack_capacity, &top, a, b);
    while (top > 0 && status == SELFCOL_OK) {
        const uint32_t tb = w->stack[--top], ta = w->stack[--top];
        status = visit(w, bx, ta, tb, &w->stack, &w->stack_capacity, &top);
    }
    return status;
}

// ---------------------------------------------------------------------------
// Threads
//
// The traversal is cut into tasks: the front of node pairs reached by
// expanding the root pair breadth-first, in a fixed order, until it holds
// FRONT_TASKS pairs or only leaf pairs (the same front for every thread
// count). Workers take tasks from a counter and write each task's candidates
// to their own list; a segment per task says where. The candidates are then
// read in task order: ALL's list, or EARLIEST's root searches. EARLIEST runs
// the tasks in rounds of ROUND_TASKS, its root searches between rounds (in
// task order, on the workers in batches bounded by the time found at each
// batch's start: sweep.c, selfcol_sweep__earliest_round), and a restart is
// decided between rounds: the same candidates, counters and time for every
// thread count. A serial traversal restarting mid-pass at the first
// candidate below a quarter of t_box did less work on its first passes; a
// round is the granularity here.
#define FRONT_TASKS 2048u
#define ROUND_TASKS 128u

typedef struct bvh_job {
    selfcol_sweep_query *q;
    const bvh_boxes *bx;
    const uint32_t *tasks; // the tasks to run (indices into the front)
    uint64_t count;        // how many
    uint64_t next;         // atomic: the next of them
    uint64_t first;        // the round's first task (segment 0)
    int stop;              // atomic: a worker failed (ENOMEM)
} bvh_job;

static int bvh_worker(void *context, unsigned worker) {
    bvh_job *job = context;
    selfcol_sweep *s = job->q->out;
    selfcol_sweep_worker *w = &s->workers[worker];
    for (;;) {
        if (SELFCOL_ATOMIC_LOAD(&job->stop) || w->overflow)
            return SELFCOL_OK;
        const uint64_t k = SELFCOL_ATOMIC_FETCH_ADD(&job->next, 1);
        if (k >= job->count)
            return SELFCOL_OK;
        const uint32_t task = job->tasks[k];
        selfcol_sweep_segment *seg = &s->segments[task - job->first];
        const selfcol_sweep_worker before = *w;
        const int status = run_task(w, job->bx, s->front[2 * task], s->front[2 * task + 1]);
        if (status == SWEEP_OVERFLOW) {
            // Undone: the task stays pending, its counters and candidates
            // taken back; this worker stops until its arrays have grown.
            w->found_count = before.found_count;
            w->node_pairs = before.node_pairs;
            w->vf_candidates = before.vf_candidates;
            w->ee_candidates = before.ee_candidates;
            w->separated = before.separated;
            w->overflow = 1;
            return SELFCOL_OK;
        }
        if (status != SELFCOL_OK) {
            SELFCOL_ATOMIC_STORE(&job->stop, 1);
            return status;
        }
        seg->worker = worker;
        seg->first = before.found_count;
        seg->count = (uint32_t)(w->found_count - before.found_count);
    }
}

// Runs tasks [first, end) on the workers. A task that found a worker's
// array full runs again after the calling thread has grown that array,
// until every task has run: the workers never allocate (the sweep's
// allocator is only called from the calling thread, sweep.h), and once the
// arrays have grown to a scene's needs a round runs once.
static int run_round(selfcol_sweep_query *q, const bvh_boxes *bx, const selfcol_executor *executor,
                     unsigned threads, size_t first, size_t end) {
    selfcol_sweep *s = q->out;
    size_t count = end - first;
    for (size_t t = 0; t < count; ++t) {
        s->pending[t] = (uint32_t)(first + t);
        s->segments[t].count = UINT32_MAX; // not run
    }
    // On threads, the largest tasks first (by triangles, stable), so that
    // none starts a big subtree when the others are about to finish the
    // round. Each task writes its own segment: the order they run in
    // changes no result.
    if (threads > 1)
        for (size_t t = 1; t < count; ++t) {
            const uint32_t task = s->pending[t];
            const uint64_t size = task_size(q, s->front[2 * task], s->front[2 * task + 1]);
            size_t j = t;
            for (; j > 0 && task_size(q, s->front[2 * s->pending[j - 1]],
                                      s->front[2 * s->pending[j - 1] + 1]) < size;
                 --j)
                s->pending[j] = s->pending[j - 1];
            s->pending[j] = task;
        }
    for (unsigned i = 0; i < threads; ++i)
        s->workers[i].found_count = 0;
    while (count > 0) {
        bvh_job job;
        memset(&job, 0, sizeof job);
        job.q = q;
        job.bx = bx;
        job.tasks = s->pending;
        job.count = count;
        job.first = first;
        const unsigned workers = count < threads ? (unsigned)count : threads;
        int status = selfcol_parallel__run(executor, workers, bvh_worker, &job);
        if (status != SELFCOL_OK)
            return status;
        for (unsigned i = 0; i < threads; ++i) {
            selfcol_sweep_worker *w = &s->workers[i];
            if (!w->overflow)
                continue;
            w->overflow = 0;
            status = grow_array(s, (void **)&w->found, &w->found_capacity, w->found_count,
                                sizeof *w->found, 1024);
            if (status == SELFCOL_OK)
                status =
                    grow_array(s, (void **)&w->stack, &w->stack_capacity, 0, sizeof *w->stack, 256);
            if (status != SELFCOL_OK)
                return status;
        }
        size_t left = 0;
        for (size_t t = 0; t < end - first; ++t)
            if (s->segments[t].count == UINT32_MAX)
                s->pending[left++] = (uint32_t)(first + t);
        count = left;
    }
    return SELFCOL_OK;
}

// Workers 0 .. n - 1, their arrays kept across queries.
static int reserve_workers(selfcol_sweep *s, selfcol_sweep_query *q, unsigned n) {
    if (n > s->worker_capacity) {
        selfcol_sweep_worker *grown = selfcol_alloc__array(&s->allocator, n, sizeof *grown);
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        memset(grown, 0, n * sizeof *grown);
        if (s->worker_capacity > 0)
            memcpy(grown, s->workers, s->worker_capacity * sizeof *grown);
        selfcol_alloc__free_array(&s->allocator, s->workers, s->worker_capacity, sizeof *grown);
        s->workers = grown;
        s->worker_capacity = n;
    }
    for (unsigned i = 0; i < n; ++i) {
        selfcol_sweep_worker *w = &s->workers[i];
        w->q = q;
        w->direct = 0;
        w->on_caller = 0;
        w->overflow = 0;
        w->found_count = 0;
        w->node_pairs = w->vf_candidates = w->ee_candidates = w->separated = 0;
    }
    return SELFCOL_OK;
}

void selfcol_sweep__free_workers(selfcol_sweep *s) {
    for (unsigned i = 0; i < s->worker_capacity; ++i) {
        selfcol_sweep_worker *w = &s->workers[i];
        selfcol_alloc__free_array(&s->allocator, w->stack, w->stack_capacity, sizeof *w->stack);
        selfcol_alloc__free_array(&s->allocator, w->found, w->found_capacity, sizeof *w->found);
    }
    selfcol_alloc__free_array(&s->allocator, s->workers, s->worker_capacity, sizeof *s->workers);
    selfcol_alloc__free_array(&s->allocator, s->front, s->front_capacity, sizeof *s->front);
    selfcol_alloc__free_array(&s->allocator, s->segments, s->segment_capacity, sizeof *s->segments);
    selfcol_alloc__free_array(&s->allocator, s->pending, s->segment_capacity, sizeof *s->pending);
    s->workers = NULL;
    s->front = NULL;
    s->segments = NULL;
    s->pending = NULL;
    s->worker_capacity = 0;
    s->front_capacity = s->segment_capacity = 0;
}

// The front: breadth-first from the root pair, in order, each internal pair
// visited (tested, its children appended) while the front is short; leaf
// pairs and the rest stay as tasks. Counted on worker 0.
static int build_front(selfcol_sweep_worker *w0, const bvh_boxes *bx, size_t *tasks) {
    selfcol_sweep *s = w0->q->out;
    size_t top = 0, scratch_top = 0;
    int status = push_pair(s, 1, &s->front, &s->front_capacity, &top, 0, 0);
    // The front array itself is the queue: each pass over it expands its
    // internal pairs once, in order.
    while (status == SELFCOL_OK && top / 2 < FRONT_TASKS) {
        int expanded = 0;
        const size_t end = top;
        size_t kept = 0;
        for (size_t i = 0; i < end && status == SELFCOL_OK; i += 2) {
            const uint32_t a = s->front[i], b = s->front[i + 1];
            if (!expands(w0->q, a, b)) {
                s->front[kept++] = a; // a leaf pair: a task as it is
                s->front[kept++] = b;
                continue;
            }
            scratch_top = 0; // the worker's stack as scratch: no allocation once grown
            status = visit(w0, bx, a, b, &w0->stack, &w0->stack_capacity, &scratch_top);
            for (size_t k = 0; k < scratch_top && status == SELFCOL_OK; k += 2)
                status = push_pair(s, 1, &s->front, &s->front_capacity, &top, w0->stack[k],
                                   w0->stack[k + 1]);
            expanded = 1;
        }
        if (status != SELFCOL_OK)
            break;
        // The pairs of this pass now lie in [0, kept) (leaves kept) and
        // [end, top) (children): close the gap, in order.
        memmove(s->front + kept, s->front + end, (top - end) * sizeof *s->front);
        top = kept + (top - end);
        if (!expanded)
            break;
    }
    *tasks = top / 2;
    return status;
}

// Room for n segments and pending tasks.
static int reserve_segments(selfcol_sweep *s, size_t n) {
    return selfcol_sweep__reserve_two(s, n, &s->segment_capacity, (void **)&s->segments,
                                      sizeof *s->segments, (void **)&s->pending,
                                      sizeof *s->pending);
}

// A round's candidates in task order: to ALL's list, or to EARLIEST's root
// searches on the workers (which may ask for a restart: the rest of the
// round is dropped), through the list too (cleared first: EARLIEST keeps no
// candidates).
static int take_round(selfcol_sweep_query *q, size_t tasks, const selfcol_executor *executor,
                      unsigned threads) {
    selfcol_sweep *s = q->out;
    if (q->earliest_mode)
        s->candidate_count = 0;
    for (size_t t = 0; t < tasks; ++t) {
        const selfcol_sweep_segment *seg = &s->segments[t];
        const selfcol_sweep_candidate *c = s->workers[seg->worker].found + seg->first;
        for (uint32_t k = 0; k < seg->count; ++k) {
            const int status = selfcol_sweep__push_candidate(s, &c[k]);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    if (!q->earliest_mode)
        return SELFCOL_OK;
    const int status =
        selfcol_sweep__earliest_round(q, s->candidates, s->candidate_count, executor, threads);
    s->candidate_count = 0;
    return status;
}

int selfcol_sweep__bvh(selfcol_sweep_query *q, const selfcol_executor *executor, unsigned threads) {
    selfcol_sweep *s = q->out;
    const int meshes = q->self ? 1 : 2;
    double *tri_boxes[2], *nodes[2];
    double *at = s->boxes; // sized by sweep.c
    box_job boxes;
    memset(&boxes, 0, sizeof boxes);
    boxes.q = q;
    for (int m = 0; m < meshes; ++m) {
        q->vertex_boxes[m] = boxes.vertex[m] = at;
        at += 6 * q->mesh[m]->vertex_count;
    }
    if (q->self)
        q->vertex_boxes[1] = q->vertex_boxes[0];
    for (int m = 0; m < meshes; ++m) {
        tri_boxes[m] = at;
        at += 6 * q->mesh[m]->triangle_count;
        nodes[m] = at;
        at += 6 * q->hierarchy[m]->node_count;
    }
    for (int m = 0; m < meshes; ++m) {
        boxes.tri[m] = tri_boxes[m];
        boxes.node[m] = nodes[m];
    }
    if (q->restricted) { // sized by sweep.c
        q->node_active[0] = s->node_active;
        q->node_active[1] = q->self ? s->node_active : s->node_active + q->hierarchy[0]->node_count;
    }
    box_stage(&boxes, executor, threads, 0, meshes);
    box_stage(&boxes, executor, threads, 1, meshes);
    for (int m = 0; m < meshes; ++m)
        internal_boxes(q, m, nodes[m]);
    if (q->self) {
        tri_boxes[1] = tri_boxes[0];
        nodes[1] = nodes[0];
    }
    const bvh_boxes bx = {{tri_boxes[0], tri_boxes[1]}, {nodes[0], nodes[1]}};
    const selfcol_hierarchy *ha = q->hierarchy[0], *hb = q->hierarchy[1];
    if (ha->node_count == 0 || hb->node_count == 0)
        return SELFCOL_OK; // an empty mesh
    if (q->cull) {
        const int status = selfcol_sweep__cull_prepare(q);
        if (status != SELFCOL_OK)
            return status;
        threads = 1; // the contour test's scratch is the query's (sweep_cull.c)
    }
    int status = reserve_workers(s, q, threads > 0 ? threads : 1);
    size_t tasks = 0;
    if (status == SELFCOL_OK) {
        s->workers[0].on_caller = 1; // the front is built on the calling thread
        status = build_front(&s->workers[0], &bx, &tasks);
        s->workers[0].on_caller = 0;
    }
    const size_t round = q->earliest_mode ? ROUND_TASKS : (tasks > 0 ? tasks : 1);
    if (status == SELFCOL_OK)
        status = reserve_segments(s, round);
    for (size_t first = 0; first < tasks && status == SELFCOL_OK; first += round) {
        const size_t end = first + round < tasks ? first + round : tasks;
        status = run_round(q, &bx, executor, threads, first, end);
        if (status == SELFCOL_OK)
            status = take_round(q, end - first, executor, threads);
    }
    for (unsigned i = 0; i < threads && i < s->worker_capacity; ++i)
        add_counters(s, &s->workers[i]);
    s->stats.candidates = s->stats.vf_candidates + s->stats.ee_candidates;
    return status;
}
