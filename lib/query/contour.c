// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The exact curvature criterion (method EXACT): when may Self(P) -- or
// Pair(A, B), with P = A u B -- be skipped, i.e. when is there provably no
// contact between primitives of the triangle set P that share no vertex?
// Volino & Magnenat Thalmann (1995, 2.1) state the criterion for
// intersections: all normals in one open half-space of V, and the contour of
// P projected along V without self-intersection. We use it in this form,
// decide the contour part with exact predicates, and extend it to
// proximities.
//
// Conditions (all checked; any failure means "descend"):
//  (1) P is consistently oriented (each node ORIENTED: no interior
//      non-manifold or inconsistently oriented edge; for a pair, every edge
//      shared by A and B has opposite directions on the two sides), and
//      every triangle normal lies within angle theta < pi/2 of V. Each node's
//      cone (kept by the refit) bounds its normals rigorously, including the
//      rounding of the computed normal; for a pair, theta is the larger of
//      angle(V, axis_X) + theta_X over X in {A, B}, plus 1e-7 rad for the
//      rounding of the acos. So the projection pi along V maps every
//      triangle of P with positive orientation.
//  (2) The boundary chain dP of P (the half-edges of P whose edge has one
//      triangle in P, P on their left; for a pair, the two nodes' boundary
//      lists minus the shared edges, which cancel) is one closed loop that
//      visits no vertex twice and whose projection is a simple polygon: no
//      two non-consecutive boundary edges meet in projection, and two
//      consecutive ones meet only at their common vertex (exact predicates).
//  (3) d <= alpha = h cos(theta), h a lower bound of the altitudes of P's
//      triangles: a triangle tilted by at most theta from the projection
//      plane keeps at least cos(theta) of each altitude (its area scales by
//      cos(theta), its sides do not grow).
//  (4) d <= beta: no boundary vertex lies within projected distance d of a
//      boundary edge not incident to it.
//
// Why (1) and (2) rule out interferences. Consider the 2-chain sum of the
// projected triangles of P, each with multiplicity +1 by (1). Its boundary
// is pi(dP) (interior edges cancel by consistent orientation), so the
// number of triangles covering a point x off the projected edges equals the
// winding number of pi(dP) around x. By (2) pi(dP) is a simple closed
// polygon, whose winding numbers are 0 and either +1 or -1 inside; the
// coverage is never negative and somewhere positive, so it is 0 or 1: the
// projected triangles do not overlap. Two primitives of P that meet in space
// without sharing a vertex would project onto overlapping triangles (at the
// meeting point the stars of the two pieces both cover a neighbourhood
// side, or a boundary edge would touch the contour, which (2) excludes). No
// interference exists inside P. The argument needs no topology of P beyond
// (1): a pinched or multiply connected P fails (2) by itself.
//
// Why (3) and (4) rule out proximities. Projection does not increase
// distances, so it suffices that non-adjacent primitives of P are at least d
// apart in projection, where P is now an embedded planar triangulation T.
//  - Vertex v and a triangle or edge y not incident to it: follow the
//    segment from pi(v) to the closest point q of pi(y). Near pi(v), T is
//    the image of v's star in P. Either the segment leaves that star
//    through a side opposite v before reaching q (or q lies on such a side):
//    its length is at least the distance from v to that side, at least the
//    altitude from v, >= alpha >= d. Or it leaves T at pi(v) itself (v on
//    P's boundary, the segment pointing outward); it must re-enter T through
//    a boundary edge f to reach q, and f is not incident to v (a segment
//    from pi(v) meets an edge at pi(v) only at pi(v)); so its length is at
//    least dist(pi(v), pi(f)) >= beta >= d.
//  - Two edges with no common vertex: in the plane, the distance between two
//    disjoint segments is attained at an endpoint of one of them, which
//    reduces to the previous case.
// Every contact inside P is a VF or EE pair at projected distance < d, or an
// EF crossing: none exists.
//
// Costs: (2) and (4) share one pass over the b boundary edges: candidate
// pairs come from a hashed uniform grid (O(b) expected, no sorting), or for
// short boundaries from all b^2 / 2 pairs (cheaper there; the same pairs
// pass the box test either way), and the exact predicate runs only where a
// floating-point filter on the projected coordinates cannot decide. That
// the boundary is one loop is known without a pass: Self(P) is tried only
// on disks (SELFCOL_NODE_DISK), Pair(A, B) only on two disks whose shared
// edges form one path. Measured on a 1.3M-triangle icosphere at d = 0.1 x
// mean edge: ~140 ns per boundary edge, 62 tests and ~217k edges per query
// (stats: contour_seconds).
#include "query/contour.h"

#include "base/cone.h"
#include "base/core.h"
#include "base/predicates.h"
#include "hierarchy/hierarchy.h"

#include <math.h>
#include <stdlib.h>

// Boundaries of at most this many edges look at every pair of edges instead
// of filling a grid. A folded 20k ribbon (the Bullet bench's last frame,
// d = 0.25 x mean edge) makes 1,754 tests of 25 edges on average; their time
// went from 6.7 ms (grid only) to 4.4 ms with all pairs up to 48 edges and
// about 3.8 ms up to 96 to 192 (beyond, the b^2 pairs cost more than the
// grid's hashing).
#define CONTOUR_ALL_PAIRS_MAX 96

// One boundary half-edge in the projection plane.
typedef struct projected_edge {
    double x0, y0, x1, y1;         // endpoints (from, to) in the plane basis (e1, e2)
    double lo_x, lo_y, hi_x, hi_y; // box, grown by the margin
    uint32_t from, to;             // mesh vertices
} projected_edge;

// One entry of the hashed grid: an edge whose box (grown by the margin)
// covers cell (ix, iy).
typedef struct cell_entry {
    int32_t ix, iy;
    uint32_t edge;
} cell_entry;

static int by_vertex(const void *pa, const void *pb) {
    uint32_t a = *(const uint32_t *)pa, b = *(const uint32_t *)pb;
    return a < b ? -1 : (a > b ? 1 : 0);
}

// Endpoints of an encoded boundary half-edge ((edge << 1) | reversed).
static uint32_t from_vertex(const selfcol_mesh *m, uint32_t half_edge) {
    return m->edges[2 * (size_t)(half_edge >> 1) + (half_edge & 1u)];
}

static uint32_t to_vertex(const selfcol_mesh *m, uint32_t half_edge) {
    return m->edges[2 * (size_t)(half_edge >> 1) + 1 - (half_edge & 1u)];
}

// 1 when point p is at distance >= sqrt(margin2) from segment ab in the
// plane (no square root, no division).
static int point_clear(double px, double py, double ax, double ay, double bx, double by,
                       double margin2) {
    double ux = bx - ax, uy = by - ay, wx = px - ax, wy = py - ay;
    double t = wx * ux + wy * uy, len2 = ux * ux + uy * uy;
    if (t <= 0.0)
        return wx * wx + wy * wy >= margin2;
    if (t >= len2) {
        double zx = px - bx, zy = py - by;
        return zx * zx + zy * zy >= margin2;
    }
    double cross = ux * wy - uy * wx;
    return cross * cross >= margin2 * len2;
}

// Sign of orient_along(a, b, c, v), decided from the projected coordinates
// when they prove it: `bound` covers the rounding of the coordinates and of
// the basis (see contour_clear); otherwise the exact predicate decides.
static int side(const double *pos, uint32_t ia, uint32_t ib, uint32_t ic, double ax, double ay,
                double bx, double by, double cx, double cy, const double v[3], double bound) {
    double o = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (o > bound)
        return 1;
    if (o < -bound)
        return -1;
    return selfcol_predicates__orient_along(pos + 3 * (size_t)ia, pos + 3 * (size_t)ib,
                                            pos + 3 * (size_t)ic, v);
}

// Edges e and f of the boundary (exact where it matters): 1 when they are
// compatible with a simple polygon and, for d > 0, every endpoint of one not
// incident to the other is at projected distance >= margin from it.
static int edges_clear(const double *pos, const projected_edge *e, const projected_edge *f,
                       const double v[3], double margin, int proximity, double bound) {
    const double margin2 = margin * margin;
    if (e->to == f->from || f->to == e->from) {
        // Consecutive: they may not fold back onto each other. The shared
        // vertex w, the other ends u (of the earlier edge) and x.
        const projected_edge *first = e->to == f->from ? e : f, *second = first == e ? f : e;
        if (side(pos, first->from, first->to, second->to, first->x0, first->y0, first->x1,
                 first->y1, second->x1, second->y1, v, bound) == 0) {
            double dot = (first->x0 - first->x1) * (second->x1 - second->x0) +
                         (first->y0 - first->y1) * (second->y1 - second->y0);
            if (dot > 0.0)
                return 0; // x lies back along w -> u
        }
        if (!proximity)
            return 1;
        // The far ends against the other edge.
        return point_clear(second->x1, second->y1, first->x0, first->y0, first->x1, first->y1,
                           margin2) &&
               point_clear(first->x0, first->y0, second->x0, second->y0, second->x1, second->y1,
                           margin2);
    }
    if (e->from == f->from || e->to == f->to)
        return 0; // a vertex visited twice by the boundary (a pinch)
    int o1 = side(pos, e->from, e->to, f->from, e->x0, e->y0, e->x1, e->y1, f->x0, f->y0, v, bound);
    int o2 = side(pos, e->from, e->to, f->to, e->x0, e->y0, e->x1, e->y1, f->x1, f->y1, v, bound);
    if (o1 * o2 <= 0) {
        int o3 =
            side(pos, f->from, f->to, e->from, f->x0, f->y0, f->x1, f->y1, e->x0, e->y0, v, bound);
        int o4 =
            side(pos, f->from, f->to, e->to, f->x0, f->y0, f->x1, f->y1, e->x1, e->y1, v, bound);
        if (o3 * o4 <= 0) {
            if (o1 != 0 || o2 != 0 || o3 != 0 || o4 != 0)
                return 0; // they cross or touch
            // Collinear in projection: apart only if their extents along the
            // line are (clearly) disjoint.
            double dx = e->x1 - e->x0, dy = e->y1 - e->y0;
            double a0 = 0.0, a1 = dx * dx + dy * dy;
            double b0 = (f->x0 - e->x0) * dx + (f->y0 - e->y0) * dy;
            double b1 = (f->x1 - e->x0) * dx + (f->y1 - e->y0) * dy;
            double blo = b0 < b1 ? b0 : b1, bhi = b0 < b1 ? b1 : b0;
            double slack = 1e-9 * a1 + margin * sqrt(a1);
            if (!(blo > a1 + slack || bhi < a0 - slack))
                return 0;
        }
    }
    if (!proximity)
        return 1;
    return point_clear(e->x0, e->y0, f->x0, f->y0, f->x1, f->y1, margin2) &&
           point_clear(e->x1, e->y1, f->x0, f->y0, f->x1, f->y1, margin2) &&
           point_clear(f->x0, f->y0, e->x0, e->y0, e->x1, e->y1, margin2) &&
           point_clear(f->x1, f->y1, e->x0, e->y0, e->x1, e->y1, margin2);
}

// The work area of contour_clear for b half-edges: the projected edges, the
// grid's bucket offsets and its entries (at most 4 per edge, see below).
static size_t work_bytes(size_t b) {
    size_t buckets = 1;
    while (buckets < 2 * b)
        buckets *= 2;
    return b * sizeof(projected_edge) + 9 * b * sizeof(cell_entry) +
           (buckets + 1) * sizeof(uint32_t);
}

static uint32_t cell_hash(int32_t ix, int32_t iy, uint32_t mask) {
    return ((uint32_t)ix * 0x9E3779B1u ^ (uint32_t)iy * 0x85EBCA77u) & mask;
}

// The boundary projected into the plane, with what both candidate searches
// below need: the margin (d plus the rounding of the projected coordinates),
// the filter bound of `side` and the grid cell size.
typedef struct projection {
    double margin, bound, cell;
    int proximity;
} projection;

// Projects the boundary chain he[0..b) along the unit vector v into `pe`.
// 0 when the projection cannot be used (degenerate or non-finite).
static int project_boundary(const selfcol_mesh *m, const double *pos, const uint32_t *he, size_t b,
                            const double v[3], double d, projected_edge *pe, projection *out) {
    // An orthonormal basis (e1, e2) of the projection plane.
    double helper[3] = {fabs(v[0]) < 0.6 ? 1.0 : 0.0, fabs(v[0]) < 0.6 ? 0.0 : 1.0, 0.0};
    double e1[3] = {helper[1] * v[2] - helper[2] * v[1], helper[2] * v[0] - helper[0] * v[2],
                    helper[0] * v[1] - helper[1] * v[0]};
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; ++k)
        e1[k] /= l1;
    double e2[3] = {v[1] * e1[2] - v[2] * e1[1], v[2] * e1[0] - v[0] * e1[2],
                    v[0] * e1[1] - v[1] * e1[0]};

    double scale = 0.0, longest = 0.0;
    double min_x = INFINITY, min_y = INFINITY;
    for (size_t i = 0; i < b; ++i) {
        projected_edge *e = &pe[i];
        e->from = from_vertex(m, he[i]);
        e->to = to_vertex(m, he[i]);
        const double *u = pos + 3 * (size_t)e->from, *w = pos + 3 * (size_t)e->to;
        for (int k = 0; k < 3; ++k)
            scale = fabs(u[k]) > scale ? fabs(u[k]) : scale;
        e->x0 = u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2];
        e->y0 = u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2];
        e->x1 = w[0] * e1[0] + w[1] * e1[1] + w[2] * e1[2];
        e->y1 = w[0] * e2[0] + w[1] * e2[1] + w[2] * e2[2];
        double dx = fabs(e->x1 - e->x0), dy = fabs(e->y1 - e->y0);
        longest = dx > longest ? dx : longest;
        longest = dy > longest ? dy : longest;
        min_x = e->x0 < min_x ? e->x0 : min_x;
        min_y = e->y0 < min_y ? e->y0 : min_y;
    }
    // The margin covers d and the rounding of the projected coordinates.
    out->proximity = d > 0.0;
    out->margin = (out->proximity ? d * (1.0 + 1e-9) : 0.0) + 1e-12 * scale;
    out->cell = 0.5 * (longest + 2.0 * out->margin) * (1.0 + 1e-9);
    if (!(out->cell > 0.0) || !isfinite(out->cell))
        return 0;
    // Filter bound of `side`: the projected coordinates (dot products with
    // a unit basis) carry an error of at most ~6e-16 scale each, coordinate
    // differences are at most 3.5 scale, and e1 x e2 differs from v by
    // ~5e-16; together under 4e-14 scale^2 on a 2D orientation. 1e-13 keeps
    // a factor 2.5 of safety.
    out->bound = 1e-13 * scale * scale;
    // Grown boxes, relative to the lowest corner (so grid cell indices are
    // >= 0).
    const double margin = out->margin, ox = min_x - margin, oy = min_y - margin;
    for (size_t i = 0; i < b; ++i) {
        projected_edge *e = &pe[i];
        e->lo_x = (e->x0 < e->x1 ? e->x0 : e->x1) - margin - ox;
        e->hi_x = (e->x0 < e->x1 ? e->x1 : e->x0) + margin - ox;
        e->lo_y = (e->y0 < e->y1 ? e->y0 : e->y1) - margin - oy;
        e->hi_y = (e->y0 < e->y1 ? e->y1 : e->y0) + margin - oy;
    }
    return 1;
}

static int boxes_apart(const projected_edge *e, const projected_edge *f) {
    return e->hi_x < f->lo_x || f->hi_x < e->lo_x || e->hi_y < f->lo_y || f->hi_y < e->lo_y;
}

// Every pair of edges whose grown boxes meet, by looking at all b (b - 1) / 2
// pairs: for the short boundaries most tests see (a crumpled 20k ribbon:
// 25 edges on average), cheaper than filling a grid.
static int clear_all_pairs(const double *pos, const projected_edge *pe, size_t b, const double v[3],
                           const projection *p) {
    for (size_t i = 0; i < b; ++i) {
        const projected_edge *e = &pe[i];
        for (size_t j = i + 1; j < b; ++j) {
            const projected_edge *f = &pe[j];
            if (boxes_apart(e, f))
                continue;
            if (!edges_clear(pos, e, f, v, p->margin, p->proximity, p->bound))
                return 0;
        }
    }
    return 1;
}

// The same pairs from a hashed uniform grid whose cells are at least half as
// wide as every projected edge plus twice the margin: each edge's grown box
// covers at most 3 x 3 cells, and two edges whose grown boxes meet share a
// cell (cell indices are a monotone function of the coordinates); a pair is
// examined in one cell only (the lowest cell of the overlap of their cell
// ranges). O(b) expected, no sorting.
static int clear_by_grid(const double *pos, const projected_edge *pe, size_t b, const double v[3],
                         const projection *p, void *grid_work) {
    const double inverse = 1.0 / p->cell;
    uint32_t buckets = 1;
    while (buckets < 2 * b)
        buckets *= 2;
    const uint32_t mask = buckets - 1;
    cell_entry *entries = grid_work;
    uint32_t *offset = (uint32_t *)(entries + 9 * b);
    for (uint32_t k = 0; k <= buckets; ++k)
        offset[k] = 0;
    // Pass 1 counts the entries per bucket, pass 2 places them (counting sort).
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            uint32_t sum = 0;
            for (uint32_t k = 0; k <= buckets; ++k) {
                uint32_t c = offset[k];
                offset[k] = sum;
                sum += c;
            }
        }
        for (size_t i = 0; i < b; ++i) {
            const projected_edge *e = &pe[i];
            // Truncation is floor here: the coordinates are >= 0 up to a
            // rounding, and the same expression serves every use below.
            int32_t ix0 = (int32_t)(e->lo_x * inverse), ix1 = (int32_t)(e->hi_x * inverse);
            int32_t iy0 = (int32_t)(e->lo_y * inverse), iy1 = (int32_t)(e->hi_y * inverse);
            if (ix1 > ix0 + 2 || iy1 > iy0 + 2)
                return 0; // cannot happen with the cell size above; stay safe
            for (int32_t ix = ix0; ix <= ix1; ++ix)
                for (int32_t iy = iy0; iy <= iy1; ++iy) {
                    uint32_t k = cell_hash(ix, iy, mask);
                    if (pass == 0)
                        offset[k]++;
                    else
                        entries[offset[k]++] = (cell_entry){ix, iy, (uint32_t)i};
                }
        }
    }
    // After pass 2, offset[k] is the end of bucket k and the start of k + 1.
    uint32_t begin = 0;
    for (uint32_t k = 0; k < buckets; ++k) {
        uint32_t end = offset[k];
        for (uint32_t a = begin; a < end; ++a) {
            const cell_entry *ep = &entries[a];
            const projected_edge *e = &pe[ep->edge];
            for (uint32_t q = a + 1; q < end; ++q) {
                const cell_entry *eq = &entries[q];
                if (eq->ix != ep->ix || eq->iy != ep->iy)
                    continue; // another cell in the same bucket
                const projected_edge *f = &pe[eq->edge];
                if (boxes_apart(e, f))
                    continue;
                // Examine the pair in the lowest cell both cover only.
                int32_t cx = (int32_t)((e->lo_x > f->lo_x ? e->lo_x : f->lo_x) * inverse);
                int32_t cy = (int32_t)((e->lo_y > f->lo_y ? e->lo_y : f->lo_y) * inverse);
                if (cx != ep->ix || cy != ep->iy)
                    continue;
                if (!edges_clear(pos, e, f, v, p->margin, p->proximity, p->bound))
                    return 0;
            }
        }
        begin = end;
    }
    return 1;
}

// Conditions (2) and (4) for the boundary chain he[0..b) projected along
// the unit vector v, with the positions `pos`; the caller has shown that the
// chain is one loop (a disk's boundary, or two disks' boundaries joined
// along one path). A pinch (a vertex visited twice) shows up here as two
// edges into one vertex. Both candidate searches examine the same edge
// pairs (those whose grown boxes meet), so the strategy changes the time,
// never the answer.
static int contour_clear(const selfcol_mesh *m, const double *pos, const uint32_t *he, size_t b,
                         const double v[3], double d, void *work, int strategy) {
    if (b < 3)
        return 0;
    projected_edge *pe = work;
    projection p;
    if (!project_boundary(m, pos, he, b, v, d, pe, &p))
        return 0;
    if (strategy == SELFCOL_CONTOUR_ALL_PAIRS ||
        (strategy == SELFCOL_CONTOUR_AUTO && b <= CONTOUR_ALL_PAIRS_MAX))
        return clear_all_pairs(pos, pe, b, v, &p);
    return clear_by_grid(pos, pe, b, v, &p, pe + b);
}

// Over a step: mu, a bound on how far the loop deforms in projection. Why
// conditions (2) and (4) checked once, at t = 0 and with clearance d + 2 mu,
// hold at every t of the step. Vertex x moves from x0 to x0 + t D_x.
// Translating the whole projected loop by -t pi(c), for any fixed c, changes
// neither its simplicity nor its distances; after it, every vertex is within
// t |D_x - c| <= mu of its place at t = 0, with mu the largest |D_x - c| over
// the loop's vertices, and so is every point of every edge (a convex
// combination of its ends). So at every t:
//  - a vertex and an edge not incident to it are at least (d + 2 mu) - 2 mu
//    = d apart: (4) holds;
//  - two edges with no common vertex that met at t would have had two points
//    within 2 mu at t = 0, so an endpoint of one within 2 mu of the other
//    (the distance between two disjoint segments of the plane is attained at
//    an endpoint), which the clearance d + 2 mu > 2 mu excludes (for d = 0
//    and mu = 0 nothing moves: the frame's test itself);
//  - two consecutive edges can only meet beyond their common vertex by
//    folding onto each other, which puts the far end of the shorter within
//    2 mu of the other edge at t = 0: excluded in the same way.
// Only the displacements' components across v matter (pi drops the one
// along v); c is the centre of their box, so mu is at most half its
// diagonal. The rounding of the displacements and of their projection (a
// few ulps of the largest component) and the error `end_error` of each end
// coordinate are added (sqrt(3) per point).
static double step_deformation(const selfcol_contour_job *job, const selfcol_mesh *m,
                               const uint32_t *he, size_t b, const double v[3]) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double largest = 0.0;
    for (size_t i = 0; i < b; ++i) {
        const uint32_t x = from_vertex(m, he[i]);
        double dx[3];
        for (int k = 0; k < 3; ++k)
            dx[k] = job->end[3 * (size_t)x + k] - job->positions[3 * (size_t)x + k];
        const double along = dx[0] * v[0] + dx[1] * v[1] + dx[2] * v[2];
        for (int k = 0; k < 3; ++k) {
            const double dk = dx[k] - along * v[k];
            lo[k] = dk < lo[k] ? dk : lo[k];
            hi[k] = dk > hi[k] ? dk : hi[k];
            largest = fabs(dk) > largest ? fabs(dk) : largest;
        }
    }
    double diagonal2 = 0.0;
    for (int k = 0; k < 3; ++k)
        diagonal2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return (0.5 * sqrt(diagonal2) * (1.0 + 1e-12) + 0x1p-49 * largest + job->end_error) *
           1.7320508075688774;
}

// contour_clear on the job's positions (and, over a step, with the
// clearance of step_deformation), counted and timed in the job.
static int counted_contour(selfcol_contour_job *job, const selfcol_mesh *m, const uint32_t *he,
                           size_t b, const double v[3], double d, void *work, int strategy) {
    double start = selfcol_core__seconds();
    double clearance = d;
    if (job->end != NULL && b > 0)
        clearance = d + 2.0 * step_deformation(job, m, he, b, v) * (1.0 + 1e-9);
    int clear = isfinite(clearance) &&
                contour_clear(m, job->positions, he, b, v, clearance, work, strategy);
    job->tests++;
    job->refused += !clear;
    job->seconds += selfcol_core__seconds() - start;
    return clear;
}

// Scratch for contour_clear over b half-edges, plus `extra` half-edge slots
// (the caller's) after it. NULL without memory.
static void *work_area(selfcol_workspace *work, size_t b, size_t extra) {
    return selfcol_workspace__buffer(work, SELFCOL_SCRATCH_CONTOUR,
                                     work_bytes(b) + extra * sizeof(uint32_t), 0);
}

// A discrete query's job: the mesh's positions, the worker's scratch.
static selfcol_contour_job frame_job(const selfcol_mesh *m, selfcol_workspace *work) {
    selfcol_contour_job job = {work, m->positions, NULL, 0.0, 0, 0, 0.0};
    return job;
}

static int counted_in(selfcol_query_stats *stats, const selfcol_contour_job *job, int clear) {
    stats->contour_tests += job->tests;
    stats->contour_refused += job->refused;
    stats->contour_seconds += job->seconds;
    return clear;
}

int selfcol_contour__loop_clear(const selfcol_mesh *m, const uint32_t *half_edges, size_t count,
                                const double v[3], double d, int strategy, selfcol_workspace *work,
                                selfcol_query_stats *stats) {
    selfcol_contour_job job = frame_job(m, work);
    void *area = work_area(job.work, count, 0);
    if (area == NULL)
        return 0;
    return counted_in(stats, &job,
                      counted_contour(&job, m, half_edges, count, v, d, area, strategy));
}

static const uint8_t DISK_PATCH =
    SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED | SELFCOL_NODE_DISK;

int selfcol_contour__patch_clear(const selfcol_hierarchy *h, uint32_t id, const selfcol_cone *cone,
                                 double min_altitude, double d, selfcol_contour_job *job) {
    const selfcol_node *n = &h->nodes[id];
    if ((n->flags & DISK_PATCH) != DISK_PATCH || !(cone->angle < SELFCOL_HALF_PI))
        return 0;
    // (3): altitudes.
    if (!(d <= min_altitude * cos(cone->angle)))
        return 0;
    const size_t b = n->boundary_count;
    if (b < 3)
        return 0;
    void *work = work_area(job->work, b, 0);
    if (work == NULL)
        return 0; // no memory: do not skip (still exact)
    // A disk's boundary is one loop.
    return counted_contour(job, h->mesh, h->bedge + n->boundary_begin, b, cone->axis, d, work,
                           SELFCOL_CONTOUR_AUTO);
}

// A node's cone as the refit keeps it (float axis, and a half-angle that
// already covers the axis's rounding: hierarchy_refit.c).
static selfcol_cone node_cone(const selfcol_node *n) {
    selfcol_cone c;
    selfcol_cone__unit_axis(n->cone_axis, c.axis);
    c.angle = n->cone_angle;
    return c;
}

int selfcol_contour__self_skippable(const selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_workspace *work, selfcol_query_stats *stats) {
    const selfcol_node *n = &h->nodes[id];
    if ((n->flags & DISK_PATCH) != DISK_PATCH || !(n->cone_angle < SELFCOL_HALF_PI))
        return 0;
    const selfcol_cone cone = node_cone(n);
    selfcol_contour_job job = frame_job(h->mesh, work);
    return counted_in(stats, &job,
                      selfcol_contour__patch_clear(h, id, &cone, h->min_altitude[id], d, &job));
}

int selfcol_contour__patches_clear(const selfcol_hierarchy *h, uint32_t ia, uint32_t ib,
                                   const selfcol_cone *cone_a, double altitude_a,
                                   const selfcol_cone *cone_b, double altitude_b, double d,
                                   selfcol_contour_job *job) {
    const selfcol_node *na = &h->nodes[ia], *nb = &h->nodes[ib];
    // Leaves keep no boundary list (hierarchy_boundary.c): not tried.
    if (na->child_count == 0 || nb->child_count == 0)
        return 0;
    if ((na->flags & nb->flags & DISK_PATCH) != DISK_PATCH || !(cone_a->angle < SELFCOL_HALF_PI) ||
        !(cone_b->angle < SELFCOL_HALF_PI))
        return 0;
    const double ta = cone_a->angle, tb = cone_b->angle;
    const double *ua = cone_a->axis, *ub = cone_b->axis;
    // Cheap rejections first (most pairs a crumpled sheet visits fail
    // here). (3) needs d <= h cos(theta) for the joint half-angle theta
    // around whatever V is chosen below, so theta <= theta_max =
    // acos(d / h). And theta >= ta, tb, and theta >= (ta + phi + tb) / 2
    // for every V (angle(V, ua) + angle(V, ub) >= phi): so phi <= 2
    // theta_max - ta - tb is necessary. A prefilter only, on the dot
    // product (with slack for its rounding); the rigorous half-angle is
    // computed below. On the Bullet bench's folded 20k ribbon it turns
    // away 16k of the 23k pairs that passed the weaker test it replaces
    // (phi < pi - ta - tb), before their 6 trigonometric calls.
    const double h_min = altitude_a < altitude_b ? altitude_a : altitude_b;
    if (!(d <= h_min))
        return 0;
    const double theta_max = h_min > 0.0 ? acos(d / h_min) : SELFCOL_HALF_PI;
    if (!(ta <= theta_max && tb <= theta_max))
        return 0;
    double v[3];
    const double room = 2.0 * theta_max - ta - tb; // in [0, pi] when phi may fit
    if (!(room >= 0.0) || !(ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2] > cos(room) - 1e-9))
        return 0;
    // (1): a projection direction V inside the smallest cone around both
    // cones, and a rigorous half-angle around V. V is the axis
    // selfcol_cone__merge gives, in its cases, except that a phi <= 1e-9
    // takes a's axis (theta below bounds the normals around any V).
    double phi = selfcol_cone__angle_between(ua, ub);
    if (phi + tb <= ta || !(phi > 1e-9)) {
        for (int k = 0; k < 3; ++k)
            v[k] = ua[k];
    } else if (phi + ta <= tb) {
        for (int k = 0; k < 3; ++k)
            v[k] = ub[k];
    } else {
        double half = 0.5 * (ta + phi + tb);
        if (!(half < SELFCOL_HALF_PI))
            return 0;
        selfcol_cone__turn_axis(v, ua, ub, phi, half - ta);
    }
    double theta_a = selfcol_cone__angle_between(v, ua) + ta,
           theta_b = selfcol_cone__angle_between(v, ub) + tb;
    double theta = (theta_a > theta_b ? theta_a : theta_b) + 1e-7;
    if (!(theta < SELFCOL_HALF_PI))
        return 0;
    // (3)
    if (!(d <= h_min * cos(theta)))
        return 0;

    // (2) and (4) on the joint boundary: both lists are sorted by edge; a
    // shared edge must appear with opposite directions and drops out.
    const size_t ba = na->boundary_count, bb = nb->boundary_count, cap = ba + bb;
    void *work = work_area(job->work, cap, 2 * cap);
    if (work == NULL)
        return 0;
    uint32_t *joint = (uint32_t *)((char *)work + work_bytes(cap));
    uint32_t *path = joint + cap; // endpoints of the shared edges
    const uint32_t *x = h->bedge + na->boundary_begin, *y = h->bedge + nb->boundary_begin;
    size_t i = 0, j = 0, b = 0, shared = 0;
    while (i < ba || j < bb) {
        if (j == bb || (i < ba && (x[i] >> 1) < (y[j] >> 1))) {
            joint[b++] = x[i++];
        } else if (i == ba || (y[j] >> 1) < (x[i] >> 1)) {
            joint[b++] = y[j++];
        } else {
            if ((x[i] ^ y[j]) != 1u)
                return 0; // same direction on both sides: not consistently oriented
            path[2 * shared] = from_vertex(h->mesh, x[i]);
            path[2 * shared + 1] = to_vertex(h->mesh, x[i]);
            ++i, ++j, ++shared;
        }
    }
    // The joint boundary is one loop when both patches are disks (one
    // boundary loop each) and the shared edges, a subset of each loop, form
    // one path: s edges on s + 1 distinct vertices (several paths have more,
    // the whole loop as many).
    if (shared == 0)
        return 0; // not adjacent: two loops can never be one
    if (2 * shared <= 32) {
        // Insertion sort: the shared path is short between most patches.
        for (size_t k = 1; k < 2 * shared; ++k) {
            uint32_t x = path[k];
            size_t j = k;
            for (; j > 0 && path[j - 1] > x; --j)
                path[j] = path[j - 1];
            path[j] = x;
        }
    } else {
        qsort(path, 2 * shared, sizeof *path, by_vertex);
    }
    size_t distinct = 1;
    for (size_t k = 1; k < 2 * shared; ++k)
        distinct += path[k] != path[k - 1];
    if (distinct != shared + 1) {
        job->tests++;
        job->refused++;
        return 0;
    }
    return counted_contour(job, h->mesh, joint, b, v, d, work, SELFCOL_CONTOUR_AUTO);
}

int selfcol_contour__pair_skippable(const selfcol_hierarchy *h, uint32_t ia, uint32_t ib, double d,
                                    selfcol_workspace *work, selfcol_query_stats *stats) {
    const selfcol_node *na = &h->nodes[ia], *nb = &h->nodes[ib];
    // The cheapest refusals before the axes are unpacked.
    if (na->child_count == 0 || nb->child_count == 0 ||
        (na->flags & nb->flags & DISK_PATCH) != DISK_PATCH || !(na->cone_angle < SELFCOL_HALF_PI) ||
        !(nb->cone_angle < SELFCOL_HALF_PI) ||
        !(d <= h->min_altitude[ia] && d <= h->min_altitude[ib]))
        return 0;
    const selfcol_cone ca = node_cone(na), cb = node_cone(nb);
    selfcol_contour_job job = frame_job(h->mesh, work);
    return counted_in(stats, &job,
                      selfcol_contour__patches_clear(h, ia, ib, &ca, h->min_altitude[ia], &cb,
                                                     h->min_altitude[ib], d, &job));
}
