// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The curvature criterion over a step (continuous queries, method EXACT):
// the seed's idea carried through time. A patch whose triangles' normals
// stay inside one open half-space at every t of the step, and whose
// projected boundary stays a simple polygon with clearance, holds no pair of
// primitives that comes within the separation at any t: Self(P) is skipped,
// and Pair(A, B) of two adjacent patches too (Volino & Magnenat Thalmann
// 1995, 2.1; over an interval as Provot 1997 and Tang et al. 2009's
// continuous normal cones).
//
// Why it holds. At each fixed t, contour.c's proof applies to the positions
// of that t once its four conditions hold there; so it suffices that they
// hold at every t in [0, t_box]:
//  (1) Normals. A corner moves as x(t) = x0 + t D, so a triangle's edge
//      vectors are u(t) = (1 - t) u0 + t u1 and v(t) = (1 - t) v0 + t v1,
//      and its normal n(t) = u(t) x v(t) is a quadratic in Bernstein form:
//          n(t) = (1 - t)^2 B0 + 2 t (1 - t) B1 + t^2 B2,
//          B0 = u0 x v0,  B1 = (u0 x v1 + u1 x v0) / 2,  B2 = u1 x v1,
//      with weights >= 0 that sum to 1. A cone of half-angle < pi/2 (convex)
//      that holds B0, B1 and B2 holds n(t) for every t, and n(t) . axis > 0
//      keeps it away from zero. The triangle's cone is built around its
//      three coefficients, each widened by a bound on its rounding (and on
//      the error of the end positions when t_box < 1, sweep.h); a node's cone
//      merges its children's (cone.h), as the refit does for one frame.
//  (3) Altitudes. |n(t)| >= n(t) . w >= min_k B_k . w for the triangle's
//      axis w, and every side is at most its longer length at the two ends
//      (|u(t)| is convex in t), so twice the area over the longest side
//      bounds every altitude at every t from below. A node keeps the least
//      over its triangles; contour.c asks d <= h cos(theta) as for a frame.
//  (2), (4) The boundary loop is checked once, at t = 0, with the clearance
//      raised by twice its deformation over the step (contour.c,
//      step_deformation, which proves the loop simple with clearance d at
//      every t).
// The orientation, connectivity and disk flags are topological: the same at
// every t. What is proved is about the exact motion, so the rounding of
// every computed quantity is bounded and added as it is in the refit.
//
// What it changes: the pairs EXACT skips can never come within the
// separation, so EXACT reports every pair that BVH and EXHAUSTIVE report
// truly (no false negative is added); it can only leave out pairs that the
// narrow phase would have reported as false positives within its tolerance.
#include "continuous/sweep.h"

#include "base/alloc.h"
#include "base/cone.h"
#include "base/core.h"
#include "query/contour.h"

#include <math.h>
#include <string.h>

// The criterion is tried on patches of at least this many triangles, as in
// the discrete traversal (traverse.c): smaller ones cost more to prove than
// their few pairs cost to test.
#define CULL_MIN_TRIANGLES 16

#define SQRT3 1.7320508075688774

static double norm3(const double x[3]) {
    return sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
}

// out = u x v, and a bound on its rounding (as in hierarchy_refit.c: each
// component is a difference of two products of rounded differences).
static double cross_with_error(const double u[3], const double v[3], double out[3]) {
    out[0] = u[1] * v[2] - u[2] * v[1];
    out[1] = u[2] * v[0] - u[0] * v[2];
    out[2] = u[0] * v[1] - u[1] * v[0];
    return 0x1p-50 * (fabs(u[1] * v[2]) + fabs(u[2] * v[1]) + fabs(u[2] * v[0]) +
                      fabs(u[0] * v[2]) + fabs(u[0] * v[1]) + fabs(u[1] * v[0]));
}

static const selfcol_cone NO_CONE = {{0.0, 0.0, 1.0}, SELFCOL_NO_CONE};

// The cone of triangle t's normals and a lower bound of its altitudes over
// the step (t = 0: start, t = 1: end, whose coordinates may be off by eps).
static void triangle_over_step(const selfcol_sweep_query *q, uint32_t t, selfcol_cone *cone,
                               double *altitude) {
    const selfcol_mesh *m = q->mesh[0];
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    const double *p0[3], *p1[3];
    for (int i = 0; i < 3; ++i) {
        p0[i] = q->start[0] + 3 * (size_t)tri[i];
        p1[i] = q->end[0] + 3 * (size_t)tri[i];
    }
    double u0[3], v0[3], u1[3], v1[3];
    for (int k = 0; k < 3; ++k) {
        u0[k] = p0[1][k] - p0[0][k];
        v0[k] = p0[2][k] - p0[0][k];
        u1[k] = p1[1][k] - p1[0][k];
        v1[k] = p1[2][k] - p1[0][k];
    }
    double b[3][3], err[3], c01[3], c10[3];
    err[0] = cross_with_error(u0, v0, b[0]);
    err[2] = cross_with_error(u1, v1, b[2]);
    const double e01 = cross_with_error(u0, v1, c01), e10 = cross_with_error(u1, v0, c10);
    for (int k = 0; k < 3; ++k)
        b[1][k] = 0.5 * (c01[k] + c10[k]);
    err[1] = 0.5 * (e01 + e10) + 0x1p-52 * (fabs(b[1][0]) + fabs(b[1][1]) + fabs(b[1][2]));
    // The end positions' error: each of u1, v1 is off by at most 2 sqrt(3)
    // eps, which moves each coefficient by at most that times the other
    // vector's length (plus the square of it).
    if (q->eps > 0.0) {
        const double shift = 2.0 * SQRT3 * q->eps;
        const double moved = shift * (norm3(u0) + norm3(v0) + norm3(u1) + norm3(v1) + 2.0 * shift);
        for (int i = 0; i < 3; ++i)
            err[i] += moved;
    }
    const double sign = (q->hierarchy[0]->owned[t] & SELFCOL_TRIANGLE_FLIPPED) ? -1.0 : 1.0;
    double axis[3] = {0.0, 0.0, 0.0}, len[3];
    for (int i = 0; i < 3; ++i) {
        len[i] = norm3(b[i]);
        if (!(len[i] > 0.0) || !(err[i] < 0.01 * len[i])) {
            *cone = NO_CONE;
            *altitude = 0.0;
            return;
        }
        for (int k = 0; k < 3; ++k) {
            b[i][k] *= sign;
            axis[k] += b[i][k] / len[i];
        }
    }
    const double axis_len = norm3(axis);
    if (!(axis_len > 0.0)) {
        *cone = NO_CONE;
        *altitude = 0.0;
        return;
    }
    double angle = 0.0, lowest = INFINITY;
    for (int k = 0; k < 3; ++k)
        axis[k] /= axis_len;
    for (int i = 0; i < 3; ++i) {
        // Within the angle to the computed coefficient plus the angle its
        // error subtends (selfcol_cone__of_normal's bound).
        const double a = selfcol_cone__angle_between(axis, b[i]) + 1.5 * err[i] / len[i] + 1e-12;
        angle = a > angle ? a : angle;
        const double along =
            b[i][0] * axis[0] + b[i][1] * axis[1] + b[i][2] * axis[2] - err[i] - 1e-15 * len[i];
        lowest = along < lowest ? along : lowest;
    }
    if (!(angle < SELFCOL_HALF_PI)) {
        *cone = NO_CONE;
        *altitude = 0.0;
        return;
    }
    memcpy(cone->axis, axis, sizeof axis);
    cone->angle = angle;
    double longest2 = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int end = 0; end < 2; ++end) {
            const double *const *p = end ? p1 : p0;
            double e2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                const double x = p[(i + 1) % 3][k] - p[i][k];
                e2 += x * x;
            }
            longest2 = e2 > longest2 ? e2 : longest2;
        }
    const double longest = sqrt(longest2) * (1.0 + 1e-12) + 2.0 * SQRT3 * q->eps;
    *altitude = lowest > 0.0 ? lowest / longest * (1.0 - 1e-12) : 0.0;
}

int selfcol_sweep__cull_prepare(selfcol_sweep_query *q) {
    selfcol_sweep *s = q->out;
    const selfcol_hierarchy *h = q->hierarchy[0];
    if (h->node_count > s->cull_capacity) {
        selfcol_cone *cones = selfcol_alloc__array(&s->allocator, h->node_count, sizeof *cones);
        double *altitudes = selfcol_alloc__array(&s->allocator, h->node_count, sizeof *altitudes);
        if (cones == NULL || altitudes == NULL) {
            selfcol_alloc__free_array(&s->allocator, cones, h->node_count, sizeof *cones);
            selfcol_alloc__free_array(&s->allocator, altitudes, h->node_count, sizeof *altitudes);
            return SELFCOL_ENOMEM;
        }
        selfcol_alloc__free_array(&s->allocator, s->cull_cones, s->cull_capacity,
                                  sizeof *s->cull_cones);
        selfcol_alloc__free_array(&s->allocator, s->cull_altitudes, s->cull_capacity,
                                  sizeof *s->cull_altitudes);
        s->cull_cones = cones;
        s->cull_altitudes = altitudes;
        s->cull_capacity = h->node_count;
    }
    const double start = selfcol_core__seconds();
    // Children come after their parent (breadth-first storage): a reverse
    // sweep sees every child first.
    for (size_t i = h->node_count; i-- > 0;) {
        const selfcol_node *n = &h->nodes[i];
        selfcol_cone acc = NO_CONE;
        double lowest = INFINITY;
        const uint32_t parts = n->child_count == 0 ? n->tri_count : n->child_count;
        for (uint32_t k = 0; k < parts; ++k) {
            selfcol_cone part;
            double altitude;
            if (n->child_count == 0) {
                triangle_over_step(q, h->tri_order[n->tri_begin + k], &part, &altitude);
            } else {
                part = s->cull_cones[n->first_child + k];
                altitude = s->cull_altitudes[n->first_child + k];
            }
            if (k == 0)
                acc = part;
            else
                selfcol_cone__merge(&acc, &part);
            lowest = altitude < lowest ? altitude : lowest;
        }
        s->cull_cones[i] = acc;
        s->cull_altitudes[i] = lowest;
    }
    q->cull_job.work = &s->work;
    q->cull_job.positions = q->start[0];
    q->cull_job.end = q->end[0];
    q->cull_job.end_error = q->eps;
    s->stats.cull_seconds += selfcol_core__seconds() - start;
    return SELFCOL_OK;
}

// The job's counters go to the statistics after each test.
static int counted(selfcol_sweep_query *q, int free_of_contacts) {
    selfcol_sweep *s = q->out;
    s->stats.cull_tests += q->cull_job.tests;
    s->stats.cull_seconds += q->cull_job.seconds;
    s->stats.patches_culled += (uint64_t)free_of_contacts;
    q->cull_job.tests = 0;
    q->cull_job.refused = 0;
    q->cull_job.seconds = 0.0;
    return free_of_contacts;
}

int selfcol_sweep__self_free(selfcol_sweep_query *q, uint32_t id) {
    const selfcol_hierarchy *h = q->hierarchy[0];
    if (h->nodes[id].tri_count < CULL_MIN_TRIANGLES ||
        !(q->out->cull_cones[id].angle < SELFCOL_HALF_PI))
        return 0;
    return counted(q, selfcol_contour__patch_clear(h, id, &q->out->cull_cones[id],
                                                   q->out->cull_altitudes[id], q->separation,
                                                   &q->cull_job));
}

int selfcol_sweep__pair_free(selfcol_sweep_query *q, uint32_t a, uint32_t b) {
    const selfcol_hierarchy *h = q->hierarchy[0];
    const selfcol_sweep *s = q->out;
    if (h->nodes[a].tri_count + h->nodes[b].tri_count < CULL_MIN_TRIANGLES ||
        !(s->cull_cones[a].angle < SELFCOL_HALF_PI) || !(s->cull_cones[b].angle < SELFCOL_HALF_PI))
        return 0;
    return counted(q, selfcol_contour__patches_clear(
                          h, a, b, &s->cull_cones[a], s->cull_altitudes[a], &s->cull_cones[b],
                          s->cull_altitudes[b], q->separation, &q->cull_job));
}
