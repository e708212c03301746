// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Closed-form narrow phase.
//
// Distances (VF, EE). Both are minima of a convex quadratic over a convex
// domain (the triangle, or [0,1]^2 for two segments). The minimum is either
// the unconstrained interior stationary point, when it lies in the domain, or
// lies on the domain's boundary, which is covered by point-segment distances
// (the three triangle edges for VF; the four endpoint-vs-segment pairs for EE,
// cf. Ericson, Real-Time Collision Detection, 2005, 5.1.5 and 5.1.9). We
// evaluate every candidate as an actual pair of points and keep the closest:
// - every candidate distance is the distance between two real points of the
//   primitives, so rounding can never report a pair closer than it is by more
//   than the rounding of one point evaluation;
// - degenerate input needs no special case: a zero-area triangle or parallel
//   segments make the interior system singular, the interior candidate is then
//   skipped, and the boundary candidates hold the true minimum (for parallel
//   segments the minimum is attained at an endpoint; a collapsed triangle is
//   the union of its edges).
//
// Interference (EF) is decided with the exact orientation predicates of
// predicates.c (sign of the Plücker-style volumes), so the set of crossing
// pairs does not depend on rounding; only the reported crossing point is
// computed in floating point.
#include "narrow/narrow.h"

#include "base/predicates.h"
#include "base/vec3.h"

#include <float.h>
#include <stddef.h>

// Closest point of segment (a, b) to p, as the parameter t in [0, 1] along it.
static double segment_parameter(const double p[3], const double a[3], const double b[3]) {
    double ab[3], ap[3];
    vec3_sub(ab, b, a);
    vec3_sub(ap, p, a);
    double len2 = vec3_dot(ab, ab);
    if (!(len2 > 0.0))
        return 0.0; // zero-length segment: every parameter gives the same point
    double t = vec3_dot(ap, ab) / len2;
    return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
}

// Any unit vector orthogonal to v (or (1, 0, 0) when v is zero).
static void any_perpendicular(double out[3], const double v[3]) {
    const double x[3] = {1.0, 0.0, 0.0}, y[3] = {0.0, 1.0, 0.0};
    double c[3];
    vec3_cross(c, v, fabs(v[0]) < fabs(v[1]) ? x : y);
    if (!vec3_normalize(out, c)) {
        out[0] = 1.0;
        out[1] = 0.0;
        out[2] = 0.0;
    }
}

// Direction from point q (second primitive) toward point p (first), or the
// fallback when they coincide.
static void set_direction(double out[3], const double p[3], const double q[3],
                          const double fallback[3]) {
    double d[3];
    vec3_sub(d, p, q);
    if (!vec3_normalize(out, d) && !vec3_normalize(out, fallback))
        any_perpendicular(out, fallback);
}

double selfcol_narrow__vf(const double p[3], const double a[3], const double b[3],
                          const double c[3], selfcol_narrow_result *out) {
    const double *corner[3] = {a, b, c};
    double best2 = DBL_MAX;
    double w[3] = {1.0, 0.0, 0.0};
    double closest[3] = {a[0], a[1], a[2]};

    // Boundary candidates: the three edges.
    for (int i = 0; i < 3; ++i) {
        const double *e0 = corner[i], *e1 = corner[(i + 1) % 3];
        double t = segment_parameter(p, e0, e1);
        double q[3];
        vec3_lerp(q, e0, e1, t);
        double d2 = vec3_dist2(p, q);
        if (d2 < best2) {
            best2 = d2;
            w[i] = 1.0 - t;
            w[(i + 1) % 3] = t;
            w[(i + 2) % 3] = 0.0;
            closest[0] = q[0];
            closest[1] = q[1];
            closest[2] = q[2];
        }
    }

    // Interior candidate: orthogonal projection onto the plane, when its
    // barycentric coordinates (ratios of sub-triangle areas) are all >= 0.
    // The frame is based at an endpoint of the shortest edge: on a needle
    // triangle the two long edges are nearly parallel and their cross product
    // loses most of its digits, while short x long keeps them.
    int i0 = 0;
    double shortest = HUGE_VAL;
    for (int i = 0; i < 3; ++i) {
        double l2 = vec3_dist2(corner[i], corner[(i + 1) % 3]);
        if (l2 < shortest) {
            shortest = l2;
            i0 = i;
        }
    }
    const int i1 = (i0 + 1) % 3, i2 = (i0 + 2) % 3;
    const double *o = corner[i0];
    double u[3], v[3], op[3], n[3];
    vec3_sub(u, corner[i1], o);
    vec3_sub(v, corner[i2], o);
    vec3_sub(op, p, o);
    vec3_cross(n, u, v);
    double nn = vec3_dot(n, n);
    if (nn > 0.0) {
        double t1[3], t2[3];
        vec3_cross(t1, op, v);
        vec3_cross(t2, u, op);
        double s = vec3_dot(t1, n) / nn; // weight of corner i1
        double t = vec3_dot(t2, n) / nn; // weight of corner i2
        if (s >= 0.0 && t >= 0.0 && s + t <= 1.0) {
            double q[3];
            for (int k = 0; k < 3; ++k)
                q[k] = o[k] + s * u[k] + t * v[k];
            double d2 = vec3_dist2(p, q);
            if (d2 < best2) {
                best2 = d2;
                w[i0] = 1.0 - s - t;
                w[i1] = s;
                w[i2] = t;
                closest[0] = q[0];
                closest[1] = q[1];
                closest[2] = q[2];
            }
        }
    }

    double dist = sqrt(best2);
    if (out != NULL) {
        out->distance = dist;
        out->wa[0] = 1.0;
        out->wa[1] = 0.0;
        out->wb[0] = w[0];
        out->wb[1] = w[1];
        out->wb[2] = w[2];
        // Fallback for a touching point: the normal, or for a zero-area
        // triangle a vector orthogonal to the line it collapses to.
        double fallback[3] = {n[0], n[1], n[2]};
        if (!(nn > 0.0)) {
            int longest = 0;
            for (int i = 1; i < 3; ++i)
                if (vec3_dist2(corner[i], corner[(i + 1) % 3]) >
                    vec3_dist2(corner[longest], corner[(longest + 1) % 3]))
                    longest = i;
            double line[3];
            vec3_sub(line, corner[(longest + 1) % 3], corner[longest]);
            any_perpendicular(fallback, line);
        }
        set_direction(out->direction, p, closest, fallback);
    }
    return dist;
}

double selfcol_narrow__ee(const double p0[3], const double p1[3], const double q0[3],
                          const double q1[3], selfcol_narrow_result *out) {
    double best2 = DBL_MAX;
    double s_best = 0.0, t_best = 0.0;

    // Boundary candidates: each endpoint against the other segment.
    const double *ends[4] = {p0, p1, q0, q1};
    for (int i = 0; i < 4; ++i) {
        double s, t;
        if (i < 2) {
            s = (double)i;
            t = segment_parameter(ends[i], q0, q1);
        } else {
            t = (double)(i - 2);
            s = segment_parameter(ends[i], p0, p1);
        }
        double pa[3], qb[3];
        vec3_lerp(pa, p0, p1, s);
        vec3_lerp(qb, q0, q1, t);
        double d2 = vec3_dist2(pa, qb);
        if (d2 < best2) {
            best2 = d2;
            s_best = s;
            t_best = t;
        }
    }

    // Interior candidate: the stationary point of |p(s) - q(t)|^2 when the
    // lines are not parallel. With n = d1 x d2 and w = q0 - p0, the closest
    // points satisfy p(s) - q(t) = lambda n, which gives
    //   s = ((w x d2) . n) / |n|^2,   t = ((w x d1) . n) / |n|^2.
    // Taking |n|^2 from the cross product (rather than a e - b^2) loses a
    // factor 1/sin(angle) less on nearly parallel segments. The solution is
    // then clamped and refined by two projections (t from s, then s from t;
    // Ericson 5.1.9), which turns what rounding is left into a pair of real
    // points that are as close as the projections can make them.
    double d1[3], d2v[3], w[3], n[3];
    vec3_sub(d1, p1, p0);
    vec3_sub(d2v, q1, q0);
    vec3_sub(w, q0, p0);
    vec3_cross(n, d1, d2v);
    double nn = vec3_dot(n, n);
    if (nn > 0.0) {
        double c1[3];
        vec3_cross(c1, w, d2v);
        double s = vec3_dot(c1, n) / nn;
        s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
        double pa[3], qb[3];
        vec3_lerp(pa, p0, p1, s);
        double t = segment_parameter(pa, q0, q1);
        vec3_lerp(qb, q0, q1, t);
        s = segment_parameter(qb, p0, p1);
        vec3_lerp(pa, p0, p1, s);
        double dd = vec3_dist2(pa, qb);
        if (dd < best2) {
            best2 = dd;
            s_best = s;
            t_best = t;
        }
    }

    double dist = sqrt(best2);
    if (out != NULL) {
        double pa[3], qb[3], normal[3];
        vec3_lerp(pa, p0, p1, s_best);
        vec3_lerp(qb, q0, q1, t_best);
        vec3_cross(normal, d1, d2v);
        if (!(vec3_dot(normal, normal) > 0.0))
            any_perpendicular(normal, vec3_dot(d1, d1) > 0.0 ? d1 : d2v);
        out->distance = dist;
        out->wa[0] = 1.0 - s_best;
        out->wa[1] = s_best;
        out->wb[0] = 1.0 - t_best;
        out->wb[1] = t_best;
        out->wb[2] = 0.0;
        set_direction(out->direction, pa, qb, normal);
    }
    return dist;
}

int selfcol_narrow__ef(const double p0[3], const double p1[3], const double a[3], const double b[3],
                       const double c[3], selfcol_narrow_result *out) {
    // First the five signs the filter can prove cheaply: when they already
    // show the endpoints on one side of the plane, or the line passing beside
    // the triangle (two lateral volumes of opposite signs), the answer is no
    // and no exact evaluation is paid for. That is the common case between
    // neighbouring, nearly coplanar triangles of a smooth surface, where the
    // plane tests alone would all need the exact path.
    int f0 = selfcol_predicates__orient3d_filter(a, b, c, p0);
    int f1 = selfcol_predicates__orient3d_filter(a, b, c, p1);
    if (f0 != 0 && f0 == f1)
        return 0;
    int g_ab = selfcol_predicates__orient3d_filter(p0, p1, a, b);
    int g_bc = selfcol_predicates__orient3d_filter(p0, p1, b, c);
    int g_ca = selfcol_predicates__orient3d_filter(p0, p1, c, a);
    if ((g_ab > 0 || g_bc > 0 || g_ca > 0) && (g_ab < 0 || g_bc < 0 || g_ca < 0))
        return 0;

    // Endpoints strictly on opposite sides of the plane (exact). A zero-area
    // triangle gives 0 for both and never crosses.
    int o0 = f0 != 0 ? f0 : selfcol_predicates__orient3d(a, b, c, p0);
    int o1 = f1 != 0 ? f1 : selfcol_predicates__orient3d(a, b, c, p1);
    if (o0 == 0 || o1 == 0 || o0 == o1)
        return 0;
    // The line p0p1 meets the closed triangle iff the three volumes
    // [p0, p1, a, b], [p0, p1, b, c], [p0, p1, c, a] do not have strictly
    // opposite signs (the line passes on the same side of all three edges).
    int s_ab = g_ab != 0 ? g_ab : selfcol_predicates__orient3d(p0, p1, a, b);
    int s_bc = g_bc != 0 ? g_bc : selfcol_predicates__orient3d(p0, p1, b, c);
    int s_ca = g_ca != 0 ? g_ca : selfcol_predicates__orient3d(p0, p1, c, a);
    int pos = (s_ab > 0) + (s_bc > 0) + (s_ca > 0);
    int neg = (s_ab < 0) + (s_bc < 0) + (s_ca < 0);
    if (pos > 0 && neg > 0)
        return 0;
    if (out == NULL)
        return 1;

    // Crossing point, in floating point: the segment parameter from the signed
    // plane distances, the barycentric weights from the same volumes (the
    // weight of a corner is proportional to the volume over the opposite edge).
    double ab[3], ac[3], n[3], r0[3], r1[3];
    vec3_sub(ab, b, a);
    vec3_sub(ac, c, a);
    vec3_cross(n, ab, ac);
    vec3_sub(r0, p0, a);
    vec3_sub(r1, p1, a);
    double h0 = vec3_dot(r0, n), h1 = vec3_dot(r1, n);
    double t = (h0 != h1) ? h0 / (h0 - h1) : 0.5;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);

    double dp[3], va[3], vb[3], vc[3], cr[3];
    vec3_sub(dp, p1, p0);
    vec3_sub(va, a, p0);
    vec3_sub(vb, b, p0);
    vec3_sub(vc, c, p0);
    vec3_cross(cr, dp, vb);
    double w_a = vec3_dot(cr, vc); // volume [p0, p1, b, c]
    vec3_cross(cr, dp, vc);
    double w_b = vec3_dot(cr, va); // volume [p0, p1, c, a]
    vec3_cross(cr, dp, va);
    double w_c = vec3_dot(cr, vb); // volume [p0, p1, a, b]
    double sum = w_a + w_b + w_c;
    if (sum != 0.0 && isfinite(sum)) {
        w_a /= sum;
        w_b /= sum;
        w_c /= sum;
    } else {
        w_a = w_b = w_c = 1.0 / 3.0;
    }
    // Rounding may push a weight slightly negative at an edge: clamp.
    w_a = w_a < 0.0 ? 0.0 : w_a;
    w_b = w_b < 0.0 ? 0.0 : w_b;
    w_c = w_c < 0.0 ? 0.0 : w_c;
    sum = w_a + w_b + w_c;
    out->distance = 0.0;
    out->wa[0] = 1.0 - t;
    out->wa[1] = t;
    out->wb[0] = w_a / sum;
    out->wb[1] = w_b / sum;
    out->wb[2] = w_c / sum;
    if (!vec3_normalize(out->direction, n))
        any_perpendicular(out->direction, dp);
    return 1;
}

double selfcol_narrow__segment_triangle(const double p0[3], const double p1[3], const double a[3],
                                        const double b[3], const double c[3],
                                        selfcol_narrow_result *out) {
    if (selfcol_narrow__ef(p0, p1, a, b, c, out))
        return 0.0;
    const double *tri[3] = {a, b, c};
    selfcol_narrow_result r;
    double best = HUGE_VAL;
    for (int i = 0; i < 2; ++i) { // an endpoint against the triangle
        double d = selfcol_narrow__vf(i ? p1 : p0, a, b, c, &r);
        if (d < best) {
            best = d;
            *out = r;
            out->wa[0] = i ? 0.0 : 1.0;
            out->wa[1] = i ? 1.0 : 0.0;
        }
    }
    for (int i = 0; i < 3; ++i) { // the segment against an edge
        int j = (i + 1) % 3;
        double d = selfcol_narrow__ee(p0, p1, tri[i], tri[j], &r);
        if (d < best) {
            best = d;
            *out = r;
            out->wb[i] = r.wb[0];
            out->wb[j] = r.wb[1];
            out->wb[3 - i - j] = 0.0;
        }
    }
    return best;
}
