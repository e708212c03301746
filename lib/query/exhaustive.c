// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The exhaustive reference: every vertex against every triangle, every edge
// against every edge and every triangle, O(n^2). It defines the exact contact
// sets of docs/contract.md section 1, and every faster method is judged against it.
//
// The only shortcut is an axis-aligned box rejection before each primitive
// test, and it is conservative: if dist(x, y) < d then, on every axis, the
// projections of x and y are closer than d, so their boxes overlap once one is
// inflated by d. It never removes a pair the narrow phase would report (apart
// from the documented relative 1e-9 band around d).
//
// Loops run in (first, second) order so the records come out sorted by
// (kind, first_mesh, first, second_mesh, second) without a sort.
#include "query/exhaustive.h"
#include "query/pairs.h"

#include "base/box.h"

typedef struct box {
    double lo[3];
    double hi[3];
} box;

// Boxes closer than d on every axis (d = 0: overlapping or touching).
static int boxes_near(const box *a, const box *b, double d) {
    return selfcol_box__near(a->lo, a->hi, b->lo, b->hi, d);
}

typedef struct mesh_boxes {
    box *triangles;
    box *edges;
} mesh_boxes;

static void compute_boxes(const selfcol_mesh *m, mesh_boxes *out) {
    for (size_t t = 0; t < m->triangle_count; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        const double *pts[3] = {selfcol_mesh__position(m, tri[0]),
                                selfcol_mesh__position(m, tri[1]),
                                selfcol_mesh__position(m, tri[2])};
        selfcol_box__of_points(out->triangles[t].lo, out->triangles[t].hi, pts, 3);
    }
    for (size_t e = 0; e < m->edge_count; ++e) {
        const double *pts[2] = {selfcol_mesh__position(m, m->edges[2 * e]),
                                selfcol_mesh__position(m, m->edges[2 * e + 1])};
        selfcol_box__of_points(out->edges[e].lo, out->edges[e].hi, pts, 2);
    }
}

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

// Vertices of mesh[mv] against triangles of mesh[mt].
static int run_vf(selfcol_query *q, int mv, int mt, const mesh_boxes *boxes) {
    const selfcol_mesh *meshv = q->mesh[mv], *mesht = q->mesh[mt];
    for (uint32_t v = 0; v < meshv->vertex_count; ++v) {
        if (selfcol_mesh__vertex_degree(meshv, v) == 0)
            continue; // not part of the surface
        const double *p = selfcol_mesh__position(meshv, v);
        for (uint32_t t = 0; t < mesht->triangle_count; ++t) {
            if (mesht->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
                continue; // its first occurrence stands for it (contacts.h)
            if (q->self && is_corner(v, mesht->triangles + 3 * (size_t)t))
                continue;
            q->out->stats.candidate_pairs++;
            const box *tb = &boxes[mt].triangles[t];
            if (!selfcol_box__point_near(p, tb->lo, tb->hi, q->distance))
                continue;
            int status = selfcol_pairs__test_vf(q, mv, v, mt, t);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    return SELFCOL_OK;
}

static int share_vertex_ee(const uint32_t *e, const uint32_t *f) {
    return e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1];
}

static int run_ee(selfcol_query *q, const mesh_boxes *boxes) {
    const selfcol_mesh *m0 = q->mesh[0], *m1 = q->mesh[1];
    for (uint32_t e = 0; e < m0->edge_count; ++e) {
        uint32_t f = q->self ? e + 1 : 0;
        for (; f < m1->edge_count; ++f) {
            if (q->self && share_vertex_ee(m0->edges + 2 * (size_t)e, m1->edges + 2 * (size_t)f))
                continue;
            q->out->stats.candidate_pairs++;
            if (!boxes_near(&boxes[0].edges[e], &boxes[1].edges[f], q->distance))
                continue;
            int status = selfcol_pairs__test_ee(q, 0, e, 1, f);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    return SELFCOL_OK;
}

// Edges of mesh[me] against triangles of mesh[mt].
static int run_ef(selfcol_query *q, int me, int mt, const mesh_boxes *boxes) {
    const selfcol_mesh *meshe = q->mesh[me], *mesht = q->mesh[mt];
    for (uint32_t e = 0; e < meshe->edge_count; ++e) {
        const uint32_t *ev = meshe->edges + 2 * (size_t)e;
        for (uint32_t t = 0; t < mesht->triangle_count; ++t) {
            if (mesht->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
                continue;
            const uint32_t *tri = mesht->triangles + 3 * (size_t)t;
            if (q->self && (is_corner(ev[0], tri) || is_corner(ev[1], tri)))
                continue;
            q->out->stats.candidate_pairs++;
            if (!boxes_near(&boxes[me].edges[e], &boxes[mt].triangles[t], 0.0))
                continue;
            int status = selfcol_pairs__test_ef(q, me, e, mt, t);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    return SELFCOL_OK;
}

int selfcol_exhaustive__run(selfcol_query *q) {
    const int mesh_count = q->self ? 1 : 2;
    size_t box_count = 0;
    for (int m = 0; m < mesh_count; ++m)
        box_count += q->mesh[m]->triangle_count + q->mesh[m]->edge_count;
    if (box_count > SIZE_MAX / sizeof(box))
        return SELFCOL_ENOMEM;
    box *scratch =
        selfcol_workspace__buffer(q->work, SELFCOL_SCRATCH_STACK, box_count * sizeof(box), 0);
    if (scratch == NULL)
        return SELFCOL_ENOMEM;
    mesh_boxes boxes[2];
    for (int m = 0; m < mesh_count; ++m) {
        boxes[m].triangles = scratch;
        boxes[m].edges = scratch + q->mesh[m]->triangle_count;
        scratch += q->mesh[m]->triangle_count + q->mesh[m]->edge_count;
        compute_boxes(q->mesh[m], &boxes[m]);
    }
    if (q->self)
        boxes[1] = boxes[0];

    int status = SELFCOL_OK;
    if (q->kinds & SELFCOL_KIND_VF) {
        status = run_vf(q, 0, 1, boxes);
        if (status == SELFCOL_OK && !q->self)
            status = run_vf(q, 1, 0, boxes);
    }
    if (status == SELFCOL_OK && (q->kinds & SELFCOL_KIND_EE))
        status = run_ee(q, boxes);
    if (status == SELFCOL_OK && (q->kinds & SELFCOL_KIND_EF)) {
        status = run_ef(q, 0, 1, boxes);
        if (status == SELFCOL_OK && !q->self)
            status = run_ef(q, 1, 0, boxes);
    }
    return status;
}
