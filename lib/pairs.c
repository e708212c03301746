// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Primitive-pair tests and record filling: the third stage of a query
// (dispatch in query.c -> candidates from traverse.c or exhaustive.c -> the
// tests here -> records in contacts.c).
//
// A candidate triangle pair (A, B) generates the primitive pairs made of a
// vertex or edge *owned* by one triangle and the other triangle (or an owned
// edge of the other): every vertex and edge has exactly one owner triangle
// and every triangle pair is listed at most once, so every primitive pair is
// tested at most once (traverse.c explains why ownership keeps the broad
// phase sound). For a self query, pairs sharing a vertex are dropped before
// any test.
//
// Filter cascade. Most candidate pairs of a folded cloth hold no contact
// (cloth-ball frame 92: 8% do), so before any closed form:
// 1. Separating planes. With s_j the signed distances of A's corners to B's
//    plane: when all three exceed d on one side, A lies beyond d of B's plane,
//    hence beyond d of B, and the pair holds no proximity and no crossing.
//    The same with the roles swapped. Six dot products decide it.
// 2. The same signed distances, per primitive: a vertex of A farther than d
//    from B's plane has no VF contact with B; an edge of A whose two ends are
//    strictly on one side of B's plane does not cross B; an edge of A beyond d
//    of B's plane on one side is farther than d from every edge of B.
// 3. Boxes inflated by d, per primitive, as the exhaustive reference does.
// 4. The closed forms of narrow.c (exact predicates for crossings), and a
//    record only for a hit.
// The filters are conservative with a derived rounding bound (see
// plane_distances), so they never reject a pair whose true distance is below
// d (1 + 2^-20): the contact sets stay exactly those of the exhaustive
// search, which the tests check on every scene.
#include "query.h"

#include "hierarchy.h"
#include "narrow.h"

#include <math.h>
#include <string.h>

// ---------------------------------------------------------------------------
// Records

static int push_record(const selfcol_query *q, selfcol_contact_kind kind, int m_first,
                       uint32_t first, int m_second, uint32_t second, const uint32_t a[2],
                       const uint32_t b[3], const selfcol_narrow_result *r) {
    selfcol_contact c;
    c.kind = (uint32_t)kind;
    c.first = first;
    c.second = second;
    // A self query reads both sides from mesh[0] == mesh[1]: both are mesh 0.
    c.first_mesh = q->self ? 0u : (uint32_t)m_first;
    c.second_mesh = q->self ? 0u : (uint32_t)m_second;
    c.a[0] = a[0];
    c.a[1] = a[1];
    c.b[0] = b[0];
    c.b[1] = b[1];
    c.b[2] = b[2];
    c.distance = r->distance;
    memcpy(c.wa, r->wa, sizeof c.wa);
    memcpy(c.wb, r->wb, sizeof c.wb);
    memcpy(c.direction, r->direction, sizeof c.direction);
    return selfcol_contacts__push(q->out, &c);
}

// ---------------------------------------------------------------------------
// One primitive pair by indices (the exhaustive reference's entry points).

static const uint32_t NO_THIRD = SELFCOL_INVALID_INDEX;

static int closed_vf(selfcol_query *q, int mv, uint32_t v, const double *p, int mt, uint32_t t,
                     const uint32_t *tri, const double *const corner[3]) {
    q->out->stats.vf_tests++;
    double dist = q->narrow == SELFCOL_NARROW_LIBCCD
                      ? selfcol_narrow_ccd__vf(p, corner[0], corner[1], corner[2], q->distance,
                                               q->ccd_tolerance, NULL)
                      : selfcol_narrow__vf(p, corner[0], corner[1], corner[2], NULL);
    if (!(dist < q->distance))
        return SELFCOL_OK;
    // A hit: the full result (weights, direction) only now.
    selfcol_narrow_result r;
    if (q->narrow == SELFCOL_NARROW_LIBCCD)
        selfcol_narrow_ccd__vf(p, corner[0], corner[1], corner[2], q->distance, q->ccd_tolerance,
                               &r);
    else
        selfcol_narrow__vf(p, corner[0], corner[1], corner[2], &r);
    q->out->stats.vf_contacts++;
    const uint32_t a[2] = {v, v};
    return push_record(q, SELFCOL_CONTACT_VF, mv, v, mt, t, a, tri, &r);
}

static int closed_ee(selfcol_query *q, int me, uint32_t e, const uint32_t *ev,
                     const double *const p[2], int mf, uint32_t f, const uint32_t *fv,
                     const double *const r2[2]) {
    q->out->stats.ee_tests++;
    double dist = q->narrow == SELFCOL_NARROW_LIBCCD
                      ? selfcol_narrow_ccd__ee(p[0], p[1], r2[0], r2[1], q->distance,
                                               q->ccd_tolerance, NULL)
                      : selfcol_narrow__ee(p[0], p[1], r2[0], r2[1], NULL);
    if (!(dist < q->distance))
        return SELFCOL_OK;
    selfcol_narrow_result r;
    if (q->narrow == SELFCOL_NARROW_LIBCCD)
        selfcol_narrow_ccd__ee(p[0], p[1], r2[0], r2[1], q->distance, q->ccd_tolerance, &r);
    else
        selfcol_narrow__ee(p[0], p[1], r2[0], r2[1], &r);
    q->out->stats.ee_contacts++;
    const uint32_t b[3] = {fv[0], fv[1], NO_THIRD};
    return push_record(q, SELFCOL_CONTACT_EE, me, e, mf, f, ev, b, &r);
}

static int closed_ef(selfcol_query *q, int me, uint32_t e, const uint32_t *ev,
                     const double *const p[2], int mt, uint32_t t, const uint32_t *tri,
                     const double *const corner[3]) {
    q->out->stats.ef_tests++;
    selfcol_narrow_result r;
    int hit = q->narrow == SELFCOL_NARROW_LIBCCD
                  ? selfcol_narrow_ccd__ef(p[0], p[1], corner[0], corner[1], corner[2],
                                           q->ccd_tolerance, &r)
                  : selfcol_narrow__ef(p[0], p[1], corner[0], corner[1], corner[2], &r);
    if (!hit)
        return SELFCOL_OK;
    q->out->stats.ef_contacts++;
    return push_record(q, SELFCOL_CONTACT_EF, me, e, mt, t, ev, tri, &r);
}

static void corners_of(const selfcol_mesh *m, const uint32_t *tri, const double *out[3]) {
    for (int i = 0; i < 3; ++i)
        out[i] = selfcol_mesh__position(m, tri[i]);
}

int selfcol_pairs__test_vf(selfcol_query *q, int mv, uint32_t v, int mt, uint32_t t) {
    const uint32_t *tri = q->mesh[mt]->triangles + 3 * (size_t)t;
    const double *corner[3];
    corners_of(q->mesh[mt], tri, corner);
    return closed_vf(q, mv, v, selfcol_mesh__position(q->mesh[mv], v), mt, t, tri, corner);
}

int selfcol_pairs__test_ee(selfcol_query *q, int me, uint32_t e, int mf, uint32_t f) {
    const uint32_t *ev = q->mesh[me]->edges + 2 * (size_t)e;
    const uint32_t *fv = q->mesh[mf]->edges + 2 * (size_t)f;
    const double *p[2] = {selfcol_mesh__position(q->mesh[me], ev[0]),
                          selfcol_mesh__position(q->mesh[me], ev[1])};
    const double *r[2] = {selfcol_mesh__position(q->mesh[mf], fv[0]),
                          selfcol_mesh__position(q->mesh[mf], fv[1])};
    return closed_ee(q, me, e, ev, p, mf, f, fv, r);
}

int selfcol_pairs__test_ef(selfcol_query *q, int me, uint32_t e, int mt, uint32_t t) {
    const uint32_t *ev = q->mesh[me]->edges + 2 * (size_t)e;
    const uint32_t *tri = q->mesh[mt]->triangles + 3 * (size_t)t;
    const double *p[2] = {selfcol_mesh__position(q->mesh[me], ev[0]),
                          selfcol_mesh__position(q->mesh[me], ev[1])};
    const double *corner[3];
    corners_of(q->mesh[mt], tri, corner);
    return closed_ef(q, me, e, ev, p, mt, t, tri, corner);
}

// ---------------------------------------------------------------------------
// Per-triangle frame data

void selfcol_pairs__frame(selfcol_tri_frame *f, const selfcol_mesh *m, uint32_t t) {
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    const double *p0 = selfcol_mesh__position(m, tri[0]), *p1 = selfcol_mesh__position(m, tri[1]),
                 *p2 = selfcol_mesh__position(m, tri[2]);
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
        double a = p0[k], b = p1[k], c = p2[k];
        f->lo[k] = a < b ? (a < c ? a : c) : (b < c ? b : c);
        f->hi[k] = a > b ? (a > c ? a : c) : (b > c ? b : c);
        u[k] = b - a;
        v[k] = c - a;
    }
    double abs_max = 0.0;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        double x = u[i] * v[j], y = u[j] * v[i];
        f->normal[k] = x - y;
        double s = fabs(x) + fabs(y);
        abs_max = s > abs_max ? s : abs_max;
    }
    f->length = sqrt(f->normal[0] * f->normal[0] + f->normal[1] * f->normal[1] +
                     f->normal[2] * f->normal[2]);
    f->abs_max = abs_max;
}

// ---------------------------------------------------------------------------
// Triangle pairs

// One side of a pair: the triangle, its corners and the signed distances of
// the *other* triangle's corners to its plane.
typedef struct pair_side {
    int mesh;
    uint32_t id;
    const uint32_t *corner_id;
    const double *corner[3];
    uint8_t owned;
    const selfcol_tri_frame *frame;
} pair_side;

// Relative widening of the distance threshold: the filters reject only what
// is farther than d (1 + 2^-20), far outside the rounding of the closed forms.
#define WIDEN (1.0 + 0x1p-20)

// Signed distances s[j] (times |n|) of the corners of `other` to the plane of
// `self`, and flags: far_pos[j] / far_neg[j] when corner j is provably beyond
// d on the positive / negative side, side_pos[j] / side_neg[j] when it is
// provably strictly on that side.
//
// Rounding bound. n = u x v is computed from rounded differences, each
// component as fl(fl(u_i v_j) - fl(u_j v_i)): |dn_k| <= 5 eps N_k with
// N_k = |u_i v_j| + |u_j v_i| <= abs_max (eps = 2^-53). Then
// s = fl((x - a) . n) with a rounded difference D = x - a: |ds| <=
// 9 eps sum_k |D_k| N_k < 2^-48 |D|_1 abs_max. The exact threshold d |n| is
// at most d (|n|_computed + 2^-46 abs_max) (1 + 2^-20).
typedef struct plane_flags {
    unsigned far_pos, far_neg, side_pos, side_neg; // bit j for corner j
} plane_flags;

static plane_flags plane_distances(const pair_side *self, const pair_side *other, double d) {
    const selfcol_tri_frame *f = self->frame;
    const double *a = self->corner[0];
    const double t = d * (f->length + 0x1p-46 * f->abs_max) * WIDEN;
    plane_flags out = {0, 0, 0, 0};
    for (int j = 0; j < 3; ++j) {
        const double *x = other->corner[j];
        double D0 = x[0] - a[0], D1 = x[1] - a[1], D2 = x[2] - a[2];
        double s = D0 * f->normal[0] + D1 * f->normal[1] + D2 * f->normal[2];
        double e = 0x1p-48 * (fabs(D0) + fabs(D1) + fabs(D2)) * f->abs_max;
        out.far_pos |= (unsigned)(s - e > t) << j;
        out.far_neg |= (unsigned)(s + e < -t) << j;
        out.side_pos |= (unsigned)(s - e > 0.0) << j;
        out.side_neg |= (unsigned)(s + e < 0.0) << j;
    }
    return out;
}

static int shares_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

static int point_near(const double *p, const selfcol_tri_frame *f, double d) {
    for (int k = 0; k < 3; ++k)
        if (p[k] < f->lo[k] - d || p[k] > f->hi[k] + d)
            return 0;
    return 1;
}

// Box of segment (p, q) within d of the box (lo, hi) on every axis.
static int segment_near(const double *p, const double *q, const double *lo, const double *hi,
                        double d) {
    for (int k = 0; k < 3; ++k) {
        double l = p[k] < q[k] ? p[k] : q[k], h = p[k] > q[k] ? p[k] : q[k];
        if (l - d > hi[k] || lo[k] - d > h)
            return 0;
    }
    return 1;
}

// Bits of the two ends of edge slot i (corners i and i + 1).
static unsigned edge_bits(int i) {
    return (1u << i) | (1u << ((i + 1) % 3));
}

// Vertices and edges owned by a, against triangle b. `of_a` are the flags of
// a's corners against b's plane.
static int one_way(selfcol_query *q, const pair_side *a, const pair_side *b,
                   const plane_flags *of_a) {
    const double d = q->distance;
    const int self = q->self;
    const selfcol_mesh *ma = q->mesh[a->mesh];
    int status = SELFCOL_OK;
    if (q->kinds & SELFCOL_KIND_VF) {
        const unsigned far = of_a->far_pos | of_a->far_neg;
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(a->owned & SELFCOL_OWNS_VERTEX(i)))
                continue;
            const uint32_t v = a->corner_id[i];
            if (self && shares_corner(v, b->corner_id))
                continue;
            if ((far >> i) & 1u || !point_near(a->corner[i], b->frame, d)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            status = closed_vf(q, a->mesh, v, a->corner[i], b->mesh, b->id, b->corner_id,
                               b->corner);
        }
    }
    if (q->kinds & SELFCOL_KIND_EF) {
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(a->owned & SELFCOL_OWNS_EDGE(i)))
                continue;
            const uint32_t e = ma->triangle_edges[3 * (size_t)a->id + (size_t)i];
            const uint32_t *ev = ma->edges + 2 * (size_t)e;
            if (self && (shares_corner(ev[0], b->corner_id) || shares_corner(ev[1], b->corner_id)))
                continue;
            const unsigned ends = edge_bits(i);
            const double *p[2] = {a->corner[i], a->corner[(i + 1) % 3]};
            if ((of_a->side_pos & ends) == ends || (of_a->side_neg & ends) == ends ||
                !segment_near(p[0], p[1], b->frame->lo, b->frame->hi, 0.0)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            // The edge's vertices in the order of its record (smaller first).
            if (ev[0] != a->corner_id[i]) {
                const double *swap = p[0];
                p[0] = p[1];
                p[1] = swap;
            }
            status = closed_ef(q, a->mesh, e, ev, p, b->mesh, b->id, b->corner_id, b->corner);
        }
    }
    return status;
}

static int edges_both_ways(selfcol_query *q, const pair_side *a, const pair_side *b,
                           const plane_flags *of_a, const plane_flags *of_b) {
    const double d = q->distance;
    const int self = q->self;
    const selfcol_mesh *ma = q->mesh[a->mesh], *mb = q->mesh[b->mesh];
    int status = SELFCOL_OK;
    for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
        if (!(a->owned & SELFCOL_OWNS_EDGE(i)))
            continue;
        const unsigned ends_a = edge_bits(i);
        // An edge of a beyond d of b's plane, both ends on one side, is beyond
        // d of every edge of b.
        const int a_far =
            (of_a->far_pos & ends_a) == ends_a || (of_a->far_neg & ends_a) == ends_a;
        const uint32_t e = ma->triangle_edges[3 * (size_t)a->id + (size_t)i];
        const uint32_t *ev = ma->edges + 2 * (size_t)e;
        const double *p[2] = {a->corner[i], a->corner[(i + 1) % 3]};
        if (ev[0] != a->corner_id[i]) {
            p[0] = a->corner[(i + 1) % 3];
            p[1] = a->corner[i];
        }
        for (int j = 0; j < 3 && status == SELFCOL_OK; ++j) {
            if (!(b->owned & SELFCOL_OWNS_EDGE(j)))
                continue;
            const uint32_t f = mb->triangle_edges[3 * (size_t)b->id + (size_t)j];
            const uint32_t *fv = mb->edges + 2 * (size_t)f;
            if (self && (ev[0] == fv[0] || ev[0] == fv[1] || ev[1] == fv[0] || ev[1] == fv[1]))
                continue;
            const unsigned ends_b = edge_bits(j);
            const double *r[2] = {b->corner[j], b->corner[(j + 1) % 3]};
            if (fv[0] != b->corner_id[j]) {
                r[0] = b->corner[(j + 1) % 3];
                r[1] = b->corner[j];
            }
            double lo[3], hi[3];
            for (int k = 0; k < 3; ++k) {
                lo[k] = r[0][k] < r[1][k] ? r[0][k] : r[1][k];
                hi[k] = r[0][k] > r[1][k] ? r[0][k] : r[1][k];
            }
            if (a_far || (of_b->far_pos & ends_b) == ends_b ||
                (of_b->far_neg & ends_b) == ends_b || !segment_near(p[0], p[1], lo, hi, d)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            if (self && f < e)
                status = closed_ee(q, b->mesh, f, fv, r, a->mesh, e, ev, p);
            else
                status = closed_ee(q, a->mesh, e, ev, p, b->mesh, f, fv, r);
        }
    }
    return status;
}

static void load_side(pair_side *s, const selfcol_pair_source *src, int mesh, uint32_t slot) {
    const selfcol_hierarchy *h = src->hierarchy;
    const selfcol_mesh *m = h->mesh;
    s->mesh = mesh;
    s->id = h->tri_order[slot];
    s->corner_id = m->triangles + 3 * (size_t)s->id;
    corners_of(m, s->corner_id, s->corner);
    s->owned = h->owned[s->id];
    s->frame = &src->frames[slot];
}

int selfcol_pairs__run(selfcol_query *q, const selfcol_pair_source source[2],
                       const selfcol_slot_pair *pairs, size_t count) {
    const double d = q->distance;
    int status = SELFCOL_OK;
    pair_side a, b;
    a.id = SELFCOL_INVALID_INDEX;
    uint32_t a_slot = SELFCOL_INVALID_INDEX;
    for (size_t k = 0; k < count && status == SELFCOL_OK; ++k) {
        // Pairs come grouped by their first triangle: its side is reused.
        if (pairs[k].a != a_slot) {
            a_slot = pairs[k].a;
            load_side(&a, &source[0], 0, a_slot);
        }
        load_side(&b, &source[1], 1, pairs[k].b);
        plane_flags of_a = plane_distances(&b, &a, d); // a's corners against b's plane
        if (of_a.far_pos == 7u || of_a.far_neg == 7u) {
            q->out->stats.pairs_separated++;
            continue;
        }
        plane_flags of_b = plane_distances(&a, &b, d);
        if (of_b.far_pos == 7u || of_b.far_neg == 7u) {
            q->out->stats.pairs_separated++;
            continue;
        }
        status = one_way(q, &a, &b, &of_a);
        if (status == SELFCOL_OK)
            status = one_way(q, &b, &a, &of_b);
        if (status == SELFCOL_OK && (q->kinds & SELFCOL_KIND_EE))
            status = edges_both_ways(q, &a, &b, &of_a, &of_b);
    }
    return status;
}
