// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The exact curvature criterion (method EXACT): when may Self(P) be skipped,
// i.e. when is there provably no contact between primitives of the patch P
// that share no vertex? Volino & Magnenat Thalmann (1995, 2.1) state the
// criterion for intersections: all normals in one open half-space of V, and
// the contour of P projected along V without self-intersection. We use it in
// this form, and extend it to proximities.
//
// Conditions (all checked; any failure means "descend"):
//  (1) P is a topological disk (SELFCOL_NODE_DISK: connected, consistently
//      oriented, manifold, Euler characteristic 1), and every triangle
//      normal lies within the cone (axis V, half-angle theta < pi/2) kept by
//      the refit, whose per-triangle angles include a rigorous bound on the
//      rounding of the computed normal. So the projection pi along V maps
//      every triangle of P with positive orientation.
//  (2) The boundary of P (one closed loop of half-edges, P on their left) is
//      star-shaped around a point c in projection: every boundary half-edge
//      (u, w) has orient_along(c, u, w, V) > 0 (exact predicate), and their
//      angles around c add up to 2 pi (the loop winds once).
//  (3) d <= alpha = h cos(theta), h a lower bound of the altitudes of P's
//      triangles: a triangle tilted by at most theta from the projection
//      plane keeps at least cos(theta) of each altitude (its area scales by
//      cos(theta), its sides do not grow).
//  (4) d <= beta: no boundary vertex lies within projected distance d of a
//      boundary edge not incident to it.
//
// Why (1) and (2) rule out interferences. pi restricted to P is a PL map of
// a disk that preserves orientation on every triangle; for a point x not on
// the image of the boundary, the number of preimages (counted with their
// local degree, >= 1 each, more at a branch vertex) equals the winding
// number of the boundary's image around x. By (2) that image is a simple
// closed curve (a star-shaped polygon winding once), whose winding numbers
// are 0 or 1: so pi is one-to-one on P (continuity extends this to the
// boundary's image). Two points of P at the same place in space project to
// the same place, so P is embedded: an edge meets a triangle of P only where
// they share a vertex or an edge, which the contact sets exclude.
//
// Why (3) and (4) rule out proximities. Projection does not increase
// distances, so it suffices that non-adjacent primitives of P are at least d
// apart in projection, where P is an embedded planar triangulation T.
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
// Costs: (2) is O(b) for a boundary of b edges; (4) is a sweep over the
// boundary vertices sorted along one axis of the projection plane against
// the edges whose extent along that axis comes within d, O(b log b) for a
// compact boundary.
#include "query.h"

#include "hierarchy.h"
#include "predicates.h"

#include <math.h>
#include <stdlib.h>

#define HALF_PI 1.5707963267948966
#define TWO_PI 6.283185307179586

typedef struct projected {
    double x, y;    // coordinates in the projection plane
    uint32_t index; // vertex (for points) or half-edge (for edges)
} projected;

static int by_x(const void *pa, const void *pb) {
    const projected *a = pa, *b = pb;
    return a->x < b->x ? -1 : (a->x > b->x ? 1 : 0);
}

// Endpoints of an encoded boundary half-edge ((edge << 1) | reversed).
static uint32_t from_vertex(const selfcol_mesh *m, uint32_t half_edge) {
    return m->edges[2 * (size_t)(half_edge >> 1) + (half_edge & 1u)];
}

static uint32_t to_vertex(const selfcol_mesh *m, uint32_t half_edge) {
    return m->edges[2 * (size_t)(half_edge >> 1) + 1 - (half_edge & 1u)];
}

// Distance from point p to segment ab in the plane.
static double point_segment(double px, double py, double ax, double ay, double bx, double by) {
    double ux = bx - ax, uy = by - ay, wx = px - ax, wy = py - ay;
    double len2 = ux * ux + uy * uy;
    double t = len2 > 0.0 ? (wx * ux + wy * uy) / len2 : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double dx = wx - t * ux, dy = wy - t * uy;
    return sqrt(dx * dx + dy * dy);
}

int selfcol_contour__self_skippable(const selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_contacts *scratch_owner) {
    const selfcol_node *n = &h->nodes[id];
    const uint8_t need = SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED | SELFCOL_NODE_DISK;
    if ((n->flags & need) != need || !(n->cone_angle < HALF_PI))
        return 0;
    // (3): altitudes. The float axis differs from the exact cone's by far less
    // than the 1e-6 rad the refit added to the angle.
    double cos_theta = cos((double)n->cone_angle);
    if (!(d <= (double)h->min_altitude[id] * cos_theta))
        return 0;

    const selfcol_mesh *m = h->mesh;
    const uint32_t *he = h->bedge + n->boundary_begin;
    const size_t b = n->boundary_count;
    if (b < 3)
        return 0;
    double axis[3] = {n->cone_axis[0], n->cone_axis[1], n->cone_axis[2]};
    // An orthonormal basis (e1, e2) of the projection plane.
    double len = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double a[3] = {axis[0] / len, axis[1] / len, axis[2] / len};
    double helper[3] = {fabs(a[0]) < 0.6 ? 1.0 : 0.0, fabs(a[0]) < 0.6 ? 0.0 : 1.0, 0.0};
    double e1[3] = {helper[1] * a[2] - helper[2] * a[1], helper[2] * a[0] - helper[0] * a[2],
                    helper[0] * a[1] - helper[1] * a[0]};
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int k = 0; k < 3; ++k)
        e1[k] /= l1;
    double e2[3] = {a[1] * e1[2] - a[2] * e1[1], a[2] * e1[0] - a[0] * e1[2],
                    a[0] * e1[1] - a[1] * e1[0]};

    // (2): star-shaped around the centroid of the boundary vertices.
    double c[3] = {0.0, 0.0, 0.0}, scale = 0.0;
    for (size_t i = 0; i < b; ++i) {
        const double *p = selfcol_mesh__position(m, from_vertex(m, he[i]));
        for (int k = 0; k < 3; ++k) {
            c[k] += p[k];
            scale = fabs(p[k]) > scale ? fabs(p[k]) : scale;
        }
    }
    for (int k = 0; k < 3; ++k)
        c[k] /= (double)b;
    double cx = c[0] * e1[0] + c[1] * e1[1] + c[2] * e1[2];
    double cy = c[0] * e2[0] + c[1] * e2[1] + c[2] * e2[2];
    double turned = 0.0;
    for (size_t i = 0; i < b; ++i) {
        const double *u = selfcol_mesh__position(m, from_vertex(m, he[i]));
        const double *w = selfcol_mesh__position(m, to_vertex(m, he[i]));
        if (selfcol_predicates__orient_along(c, u, w, axis) <= 0)
            return 0;
        double ux = u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2] - cx;
        double uy = u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2] - cy;
        double wx = w[0] * e1[0] + w[1] * e1[1] + w[2] * e1[2] - cx;
        double wy = w[0] * e2[0] + w[1] * e2[1] + w[2] * e2[2] - cy;
        turned += atan2(ux * wy - uy * wx, ux * wx + uy * wy);
    }
    // Each angle is in (0, pi), so the sum is 2 pi times the winding number,
    // far from any other multiple even after rounding.
    if (!(fabs(turned - TWO_PI) < 1.0))
        return 0;
    if (!(d > 0.0))
        return 1; // (4) is vacuous: no proximity is below 0

    // (4): boundary clearance, with a margin for the rounding of the
    // projected coordinates.
    // Sweep along e1: vertices in increasing x; an edge is active while its
    // x-extent comes within `margin` of the sweep position.
    projected *pts = selfcol_contacts__scratch(
        scratch_owner, 2, 2 * b * sizeof(projected) + b * sizeof(uint32_t), 0);
    if (pts == NULL)
        return 0; // no memory: do not skip (still exact)
    projected *edges = pts + b; // x: smaller x of the edge, y: larger x
    uint32_t *active = (uint32_t *)(edges + b);
    for (size_t i = 0; i < b; ++i) {
        const double *u = selfcol_mesh__position(m, from_vertex(m, he[i]));
        const double *w = selfcol_mesh__position(m, to_vertex(m, he[i]));
        double ux = u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2];
        double wx = w[0] * e1[0] + w[1] * e1[1] + w[2] * e1[2];
        pts[i].x = ux;
        pts[i].y = u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2];
        pts[i].index = (uint32_t)i;
        edges[i].x = ux < wx ? ux : wx;
        edges[i].y = ux < wx ? wx : ux;
        edges[i].index = (uint32_t)i;
    }
    qsort(pts, b, sizeof *pts, by_x);
    qsort(edges, b, sizeof *edges, by_x);
    const double margin = d * (1.0 + 1e-9) + 1e-12 * scale;
    size_t next = 0, active_count = 0;
    for (size_t i = 0; i < b; ++i) {
        const projected *p = &pts[i];
        uint32_t v = from_vertex(m, he[p->index]);
        while (next < b && edges[next].x <= p->x + margin)
            active[active_count++] = (uint32_t)next++;
        size_t kept = 0;
        for (size_t j = 0; j < active_count; ++j) {
            const projected *e = &edges[active[j]];
            if (e->y < p->x - margin)
                continue; // left behind for good: later vertices have larger x
            active[kept++] = active[j];
            uint32_t k = e->index;
            uint32_t from = from_vertex(m, he[k]), to = to_vertex(m, he[k]);
            if (from == v || to == v)
                continue;
            const double *q0 = selfcol_mesh__position(m, from), *q1 = selfcol_mesh__position(m, to);
            double ax = q0[0] * e1[0] + q0[1] * e1[1] + q0[2] * e1[2];
            double ay = q0[0] * e2[0] + q0[1] * e2[1] + q0[2] * e2[2];
            double bx = q1[0] * e1[0] + q1[1] * e1[1] + q1[2] * e1[2];
            double by = q1[0] * e2[0] + q1[1] * e2[1] + q1[2] * e2[2];
            if (point_segment(p->x, p->y, ax, ay, bx, by) < margin)
                return 0;
        }
        active_count = kept;
    }
    return 1;
}
