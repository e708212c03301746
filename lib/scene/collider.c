// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Convex colliders (collider.h): a sphere (a point), a capsule (a segment),
// a box or a convex point set (a hull), swept by a ball of the radius. A
// triangle's distance to the collider is its distance to the core (point,
// segment, box or hull) minus the radius.
//
// Frames. Everything is computed in the collider's frame, local =
// rotation^T (x - position), the triangle's corners taken there exactly (as
// exact sums of products, the error-free transformations below) and only
// rounded relative to the triangle's first corner (and to the core's nearby
// part). The rounded world points of selfcol_collider__place() serve the
// broad phase only. (The rotation is taken as orthonormal: set_collider_pose
// accepts 1e-6 off, which would scale distances by up to 1 +- 1e-6; rotations
// from normalised quaternions are orthonormal to rounding.)
//
// Spheres, capsules and boxes: closed form.
// - sphere: the triangle's closest point to the centre (narrow__vf);
// - capsule: the closest points of the axis segment and the triangle
//   (narrow__segment_triangle), the segment first clipped to the triangle's
//   z range widened by 2 (radius + distance) (a far part cannot be nearer;
//   a long segment rounded in the triangle's frame would move its closest
//   point by rounding of its length);
// - box: the least of the triangle's corners against the box (per-axis
//   excess), the box's twelve edges (clipped likewise) against the triangle,
//   and 0 when a triangle edge crosses the box (slab test): the closest
//   points of two convex polytopes are a vertex against a face or an edge
//   against an edge, and they meet iff an edge of one crosses the other or a
//   corner of the triangle lies in the box.
// Each candidate gives a point x of the core (a double, exactly on it) and a
// point of the triangle (weights wb, proposed from the frame rounded relative
// to the triangle's first corner: the feet and edge points of Ericson 5.1.5
// and 5.1.9), and the vector D between them is summed exactly from the exact
// corner, the weights' offset and x, and rounded to a double-double. The
// proposals within rounding of the least are compared by |D|^2 - radius^2,
// summed exactly from the double-double D (no cancellation between |D| and
// radius, whatever their size), and the distance is
// (|D|^2 - radius^2) / (|D| + radius). Error (derived; measured by
// tests/test_collider_internal.c):
// - the triangle's edges and the weights' offset are rounded relative to the
//   triangle: a few 2^-53 x its longest edge L;
// - the weights come from a frame rounded by 2^-53 x its extent (the
//   distance from the core, L, and a clipped segment's reach): the closest
//   point of a nearby point, off by the square of that over |D|, at most
//   twice that rounding: about 2^-104 x (radius + distance), or
//   2^-52 x (L + 10 distance) when the radius is small;
// - D is rounded to a double-double: 2^-104 x |D| relative.
// So |error| <= 2^-50 (L + 4 distance) + 2^-99 (radius + distance), below
// tolerance / 2 within the limits: radius + distance <= 2^95 x tolerance
// (spheres, capsules; a box's rounding radius: its half-extents enter
// exactly, unlimited), distance <= 2^45 x tolerance, and L <= 2^47 x
// tolerance (2e21, 1.8e6 and 7e6 at the default tolerance of 1e-6 x d for
// d = 0.05); beyond them the narrow phase answers SELFCOL_ERANGE, never a
// wrong distance.
// The normal is D / |D| (the closest points', from the collider toward the
// triangle; rotated to the world) and wb the triangle's closest point: exact
// contracts, no SELFCOL_COLLIDER_APPROXIMATE. When the core meets the
// triangle (|D| = 0) the normal is the triangle's normal turned away from the
// collider's centre and wb the meeting point.
//
// Convex point sets: libccd (narrow_ccd.c's hull query: MPR's intersection
// test on the hull swept by rho, bisected on rho over [0, radius +
// distance]), in the triangle's frame: the hull's points are taken relative
// to the triangle's first corner exactly, then rounded, so the coordinates
// libccd sees are the size S of the query (the hull, the triangle and the
// distance between them), not their position. MPR's answers are good to
// about 2^-26 S (narrow_ccd.c, "Accuracy floor"), so a query with S above
// 2^25 x tolerance answers SELFCOL_ERANGE (as does selfcol_collider__range()
// for a hull whose diameter + radius + distance is above it). The normal is
// MPR's penetration direction just past the contact and the point MPR's
// contact position projected onto the triangle (SELFCOL_COLLIDER_APPROXIMATE).
#include "scene/collider.h"

#include "base/alloc.h"
#include "base/box.h"
#include "base/expansion.h"
#include "base/vec3.h"
#include "narrow/narrow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int size_ok(double x) {
    return isfinite(x) && x >= 0.0 && x <= SELFCOL_MESH_MAX_COORDINATE;
}

int selfcol_collider__check(const selfcol_scene_collider_desc *desc) {
    if (!size_ok(desc->radius))
        return SELFCOL_EINVAL;
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: return desc->radius > 0.0 ? SELFCOL_OK : SELFCOL_EINVAL;
    case SELFCOL_COLLIDER_CAPSULE:
        return desc->radius > 0.0 && size_ok(desc->half_height) ? SELFCOL_OK : SELFCOL_EINVAL;
    case SELFCOL_COLLIDER_BOX:
        for (int k = 0; k < 3; ++k)
            if (!size_ok(desc->half_extents[k]))
                return SELFCOL_EINVAL;
        return SELFCOL_OK;
    case SELFCOL_COLLIDER_CONVEX:
        if (desc->points == NULL || desc->point_count == 0 ||
            desc->point_count > SELFCOL_COLLIDER_MAX_POINTS)
            return SELFCOL_EINVAL;
        for (size_t i = 0; i < 3 * desc->point_count; ++i)
            if (!isfinite(desc->points[i]) || fabs(desc->points[i]) > SELFCOL_MESH_MAX_COORDINATE)
                return SELFCOL_EINVAL;
        return SELFCOL_OK;
    default: return SELFCOL_EINVAL;
    }
}

size_t selfcol_collider__point_count(const selfcol_scene_collider_desc *desc) {
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: return 1;
    case SELFCOL_COLLIDER_CAPSULE: return 2;
    case SELFCOL_COLLIDER_BOX: return 8;
    default: return desc->point_count;
    }
}

void selfcol_collider__local_points(const selfcol_scene_collider_desc *desc, double (*local)[3]) {
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: local[0][0] = local[0][1] = local[0][2] = 0.0; break;
    case SELFCOL_COLLIDER_CAPSULE:
        for (int i = 0; i < 2; ++i) {
            local[i][0] = local[i][1] = 0.0;
            local[i][2] = i ? desc->half_height : -desc->half_height;
        }
        break;
    case SELFCOL_COLLIDER_BOX:
        for (int i = 0; i < 8; ++i)
            for (int k = 0; k < 3; ++k)
                local[i][k] = (i >> k & 1) ? desc->half_extents[k] : -desc->half_extents[k];
        break;
    default: memcpy(local, desc->points, desc->point_count * sizeof *local); break;
    }
}

void selfcol_collider__place(selfcol_collider *c, const double position[3],
                             const double rotation[9]) {
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double *r = rotation != NULL ? rotation : identity;
    memcpy(c->position, position, sizeof c->position);
    memcpy(c->rotation, r, sizeof c->rotation);
    for (size_t i = 0; i < c->point_count; ++i) {
        const double *p = c->local[i];
        for (int k = 0; k < 3; ++k)
            c->world[i][k] =
                r[3 * k] * p[0] + r[3 * k + 1] * p[1] + r[3 * k + 2] * p[2] + position[k];
    }
    for (int k = 0; k < 3; ++k)
        c->lo[k] = c->hi[k] = c->world[0][k];
    for (size_t i = 1; i < c->point_count; ++i)
        selfcol_box__grow_point(c->lo, c->hi, c->world[i]);
    for (int k = 0; k < 3; ++k) {
        c->lo[k] -= c->radius;
        c->hi[k] += c->radius;
    }
}

static int grow(const selfcol_allocator *al, selfcol_collider_contact_buffer *out) {
    if (out->count < out->capacity)
        return SELFCOL_OK;
    size_t cap = out->capacity < 16 ? 16 : 2 * out->capacity;
    selfcol_collider_contact *p = selfcol_alloc__array(al, cap, sizeof *p);
    if (p == NULL)
        return SELFCOL_ENOMEM;
    if (out->count > 0)
        memcpy(p, out->items, out->count * sizeof *p);
    selfcol_alloc__free_array(al, out->items, out->capacity, sizeof *out->items);
    out->items = p;
    out->capacity = cap;
    return SELFCOL_OK;
}

static int by_triangle(const void *x, const void *y) {
    const uint32_t a = ((const selfcol_collider_contact *)x)->triangle;
    const uint32_t b = ((const selfcol_collider_contact *)y)->triangle;
    return (a > b) - (a < b);
}

// ---------------------------------------------------------------------------
// Exact sums (expansion.h's error-free transformations). Exactness range:
// coordinates and half-extents within the mesh contract (magnitudes in
// [2^-200, 2^200] or zero) and rotation entries of an orthonormal matrix:
// no product or partial product overflows, and an entry small enough for a
// partial product to underflow contributes far below the tolerance.

#define EXACT_MAX_TERMS 32

// The exact sum of n <= EXACT_MAX_TERMS doubles, rounded to hi + lo
// (relative error about 2^-104): Shewchuk's Grow-Expansion (zero-free) into
// a nonoverlapping expansion, Compress, then the largest component (within
// an ulp of the sum) plus the rest.
static void exact_sum(const double *x, int n, double *hi, double *lo) {
    double e[EXACT_MAX_TERMS + 1], g[EXACT_MAX_TERMS + 1];
    int m = 0;
    for (int i = 0; i < n; ++i)
        m = grow_expansion(e, m, x[i]);
    if (m == 0) {
        *hi = *lo = 0.0;
        return;
    }
    int bottom = m - 1;
    double q = e[m - 1];
    for (int i = m - 2; i >= 0; --i) {
        double sum, err;
        two_sum(q, e[i], &sum, &err);
        if (err != 0.0) {
            g[bottom--] = sum;
            q = err;
        } else {
            q = sum;
        }
    }
    g[bottom] = q;
    int top = 0;
    for (int i = bottom + 1; i < m; ++i) {
        double sum, err;
        two_sum(g[i], q, &sum, &err);
        if (err != 0.0)
            e[top++] = err;
        q = sum;
    }
    double rest = 0.0;
    for (int i = 0; i < top; ++i)
        rest += e[i];
    *hi = q;
    *lo = rest;
}

static double exact_round(const double *x, int n) {
    double hi, lo;
    exact_sum(x, n, &hi, &lo);
    return hi;
}

// ---------------------------------------------------------------------------
// The triangle in the collider's frame.

#define FRAME_TERMS 12

typedef struct tri_frame {
    double terms[3][3][FRAME_TERMS]; // corner i, axis k: exact, as a sum
    int count[3][3];
    double v[3][3];        // the corners, rounded
    double e[3][3];        // corner i - corner 0, rounded (e[0] = 0)
    double vlo[3], vhi[3]; // the box of v
} tri_frame;

// Axis k of rotation^T (x - position), exactly, as at most FRAME_TERMS
// doubles (a sphere is not turned: translation only).
static int frame_terms(const selfcol_collider *c, const double x[3], int k, double *out) {
    double yh[3], yl[3];
    if (c->shape == SELFCOL_COLLIDER_SPHERE) {
        two_sum(x[k], -c->position[k], &out[0], &out[1]);
        return 2;
    }
    for (int j = 0; j < 3; ++j)
        two_sum(x[j], -c->position[j], &yh[j], &yl[j]);
    int n = 0;
    for (int j = 0; j < 3; ++j) {
        const double r = c->rotation[3 * j + k]; // rotation^T
        two_product(r, yh[j], &out[n], &out[n + 1]);
        two_product(r, yl[j], &out[n + 2], &out[n + 3]);
        n += 4;
    }
    return n;
}

static void frame_of_triangle(const selfcol_collider *c, const double *a, const double *b,
                              const double *cc, tri_frame *f) {
    const double *corner[3] = {a, b, cc};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            f->count[i][k] = frame_terms(c, corner[i], k, f->terms[i][k]);
            f->v[i][k] = exact_round(f->terms[i][k], f->count[i][k]);
        }
    for (int k = 0; k < 3; ++k) {
        f->e[0][k] = 0.0;
        for (int i = 1; i < 3; ++i) {
            double t[2 * FRAME_TERMS];
            int n = 0;
            for (int j = 0; j < f->count[i][k]; ++j)
                t[n++] = f->terms[i][k][j];
            for (int j = 0; j < f->count[0][k]; ++j)
                t[n++] = -f->terms[0][k][j];
            f->e[i][k] = exact_round(t, n);
        }
        f->vlo[k] = fmin(f->v[0][k], fmin(f->v[1][k], f->v[2][k]));
        f->vhi[k] = fmax(f->v[0][k], fmax(f->v[1][k], f->v[2][k]));
    }
}

// x (a point of the frame, a double) relative to corner 0, rounded.
static void relative(const tri_frame *f, const double x[3], double out[3]) {
    for (int k = 0; k < 3; ++k) {
        double t[FRAME_TERMS + 1];
        int n = 0;
        t[n++] = x[k];
        for (int j = 0; j < f->count[0][k]; ++j)
            t[n++] = -f->terms[0][k][j];
        out[k] = exact_round(t, n);
    }
}

// A candidate pair of closest points: D = (triangle point) - (core point),
// as double-doubles, and the triangle point's weights.
typedef struct candidate {
    double dh[3], dl[3];
    double wb[3];
    int meets; // the core meets the triangle: D = 0
} candidate;

// D = corner i + offset - x, exactly summed then rounded to double-doubles.
static void difference(const tri_frame *f, int i, const double offset[3], const double x[3],
                       candidate *out) {
    for (int k = 0; k < 3; ++k) {
        double t[FRAME_TERMS + 2];
        int n = 0;
        for (int j = 0; j < f->count[i][k]; ++j)
            t[n++] = f->terms[i][k][j];
        t[n++] = offset[k];
        t[n++] = -x[k];
        exact_sum(t, n, &out->dh[k], &out->dl[k]);
    }
}

// |D|^2 - radius^2, summed exactly from the double-double D, rounded.
static double excess(const candidate *c, double radius) {
    if (c->meets)
        return -radius * radius;
    double t[20];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
        two_product(c->dh[k], c->dh[k], &t[n], &t[n + 1]);
        two_product(2.0 * c->dh[k], c->dl[k], &t[n + 2], &t[n + 3]);
        two_product(c->dl[k], c->dl[k], &t[n + 4], &t[n + 5]);
        n += 6;
    }
    two_product(-radius, radius, &t[n], &t[n + 1]);
    return exact_round(t, n + 2);
}

static double size_of(const double v[3]) {
    return fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
}

// Candidate closest pairs of a core segment x0 x1 (along axis `axis` of the
// frame, exact doubles; a point when x0 = x1) and the triangle, proposed
// from the frame rounded relative to corner 0 (r0, r1 and the edges e):
// every pair is a point of the core (a double exactly on it: its parameter
// s) and a point of the triangle (weights), and the closest pair is among
// them (Ericson 5.1.5 and 5.1.9: the triangle's interior foot of an
// endpoint, an endpoint against an edge, the segment against an edge at
// their interior stationary point, a corner against the segment).
typedef struct proposal {
    double s, wb[3], approx;
} proposal;

#define MAX_PROPOSALS 16

static int add_proposal(proposal *p, int n, double s, double w0, double w1, double w2,
                        const double r0[3], const double r1[3], const tri_frame *f) {
    proposal *q = &p[n];
    q->s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    q->wb[0] = w0;
    q->wb[1] = w1;
    q->wb[2] = w2;
    double d[3];
    for (int k = 0; k < 3; ++k)
        d[k] = w1 * f->e[1][k] + w2 * f->e[2][k] - (r0[k] + q->s * (r1[k] - r0[k]));
    q->approx = vec3_dot(d, d);
    return n + 1;
}

static double clamp01(double t) {
    return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
}

// Point p (rounded, relative) against the triangle: its foot inside, and the
// closest point of each edge.
static int point_proposals(proposal *out, int n, double s, const double p[3], const double r0[3],
                           const double r1[3], const tri_frame *f) {
    const double *e1 = f->e[1], *e2 = f->e[2];
    const double a11 = vec3_dot(e1, e1), a12 = vec3_dot(e1, e2), a22 = vec3_dot(e2, e2);
    const double b1 = vec3_dot(p, e1), b2 = vec3_dot(p, e2);
    const double det = a11 * a22 - a12 * a12;
    if (det > 0.0) {
        const double u = (b1 * a22 - b2 * a12) / det, v = (b2 * a11 - b1 * a12) / det;
        if (u >= 0.0 && v >= 0.0 && u + v <= 1.0)
            n = add_proposal(out, n, s, 1.0 - u - v, u, v, r0, r1, f);
    }
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        double ed[3], pd[3];
        vec3_sub(ed, f->e[j], f->e[i]);
        vec3_sub(pd, p, f->e[i]);
        const double len2 = vec3_dot(ed, ed);
        const double t = len2 > 0.0 ? clamp01(vec3_dot(pd, ed) / len2) : 0.0;
        double w[3] = {0.0, 0.0, 0.0};
        w[i] = 1.0 - t;
        w[j] = t;
        n = add_proposal(out, n, s, w[0], w[1], w[2], r0, r1, f);
    }
    return n;
}

static int segment_proposals(proposal *out, const double r0[3], const double r1[3],
                             const tri_frame *f) {
    int n = point_proposals(out, 0, 0.0, r0, r0, r1, f);
    double dir[3];
    vec3_sub(dir, r1, r0);
    const double len2 = vec3_dot(dir, dir);
    if (!(len2 > 0.0))
        return n;
    n = point_proposals(out, n, 1.0, r1, r0, r1, f);
    for (int i = 0; i < 3; ++i) {
        double w[3] = {0.0, 0.0, 0.0}, pd[3];
        w[i] = 1.0;
        vec3_sub(pd, f->e[i], r0); // the corner against the segment
        n = add_proposal(out, n, vec3_dot(pd, dir) / len2, w[0], w[1], w[2], r0, r1, f);
        // The segment against edge i j at their interior stationary point.
        const int j = (i + 1) % 3;
        double ed[3];
        vec3_sub(ed, f->e[j], f->e[i]);
        const double a = len2, b = vec3_dot(dir, ed), c = vec3_dot(ed, ed);
        const double d = vec3_dot(dir, pd), e = vec3_dot(ed, pd);
        const double det = a * c - b * b;
        if (det > 0.0) {
            const double s = (d * c - b * e) / det, t = (d * b - a * e) / det;
            if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0) {
                double v[3] = {0.0, 0.0, 0.0};
                v[i] = 1.0 - t;
                v[j] = t;
                n = add_proposal(out, n, s, v[0], v[1], v[2], r0, r1, f);
            }
        }
    }
    return n;
}

// The closest pair of segment x0 x1 (see above) and the triangle: the
// proposals within rounding of the least are evaluated exactly, and the
// least by |D|^2 - radius^2 (exact) is kept.
static void segment_candidate(const tri_frame *f, const double x0[3], const double x1[3], int axis,
                              double radius, candidate *out) {
    double r0[3], r1[3];
    relative(f, x0, r0);
    relative(f, x1, r1);
    const double zero[3] = {0.0, 0.0, 0.0};
    if (selfcol_narrow__ef(r0, r1, zero, f->e[1], f->e[2], NULL)) {
        selfcol_narrow_result r;
        selfcol_narrow__segment_triangle(r0, r1, zero, f->e[1], f->e[2], &r);
        memset(out, 0, sizeof *out);
        memcpy(out->wb, r.wb, sizeof out->wb);
        out->meets = 1;
        return;
    }
    proposal p[MAX_PROPOSALS];
    const int n = segment_proposals(p, r0, r1, f);
    double least = HUGE_VAL;
    for (int i = 0; i < n; ++i)
        least = fmin(least, p[i].approx);
    const double m = size_of(r0) + size_of(r1) + size_of(f->e[1]) + size_of(f->e[2]);
    const double margin = 0x1p-46 * m * m;
    double best = HUGE_VAL;
    for (int i = 0; i < n; ++i) {
        if (!(p[i].approx <= least + margin))
            continue;
        double x[3] = {x0[0], x0[1], x0[2]}, off[3];
        if (x1[axis] != x0[axis]) { // a point of the segment, exactly on it
            const double lo = x0[axis], hi = x1[axis];
            const double z = lo + p[i].s * (hi - lo);
            x[axis] = z < lo ? lo : (z > hi ? hi : z);
        }
        for (int k = 0; k < 3; ++k)
            off[k] = p[i].wb[1] * f->e[1][k] + p[i].wb[2] * f->e[2][k];
        candidate c;
        difference(f, 0, off, x, &c);
        memcpy(c.wb, p[i].wb, sizeof c.wb);
        c.meets = 0;
        const double value = excess(&c, radius);
        if (value < best) {
            best = value;
            *out = c;
        }
    }
}

// The clipped part [lo, hi] of [-h, h] that can be within `reach` of the
// triangle along axis k (its box widened, with a margin for the rounding of
// v): 0 when none.
static int clip(const tri_frame *f, int k, double h, double reach, double *lo, double *hi) {
    double a = f->vlo[k] - reach, b = f->vhi[k] + reach;
    a -= fabs(a) * 0x1p-50;
    b += fabs(b) * 0x1p-50;
    *lo = a > -h ? a : -h;
    *hi = b < h ? b : h;
    return *lo <= *hi;
}

static void keep(candidate *best, const candidate *c, double radius) {
    if (excess(c, radius) < excess(best, radius))
        *best = *c;
}

// Does segment (p, p + dir) in the frame relative to corner 0 cross the box
// lo..hi (relative, rounded)? On 1, *t is a parameter inside.
static int slab(const double p[3], const double dir[3], const double lo[3], const double hi[3],
                double *t) {
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        if (dir[k] == 0.0) {
            if (p[k] < lo[k] || p[k] > hi[k])
                return 0;
            continue;
        }
        double a = (lo[k] - p[k]) / dir[k], b = (hi[k] - p[k]) / dir[k];
        if (a > b) {
            const double s = a;
            a = b;
            b = s;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
        if (t0 > t1)
            return 0;
    }
    *t = 0.5 * (t0 + t1);
    return 1;
}

// The box's candidates. 0 when nothing of the box is within reach.
static int box_candidate(const selfcol_collider *col, const tri_frame *f, double reach,
                         candidate *best) {
    const double radius = col->radius;
    const double *h = col->local[7]; // (+h0, +h1, +h2)
    int any = 0;
    candidate c;
    // The triangle's corners against the box: per-axis excess, exactly.
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            double t[FRAME_TERMS + 1];
            int n = 0;
            for (int j = 0; j < f->count[i][k]; ++j)
                t[n++] = f->terms[i][k][j];
            t[n] = -h[k];
            exact_sum(t, n + 1, &c.dh[k], &c.dl[k]);
            if (c.dh[k] > 0.0)
                continue;
            t[n] = h[k];
            exact_sum(t, n + 1, &c.dh[k], &c.dl[k]);
            if (c.dh[k] < 0.0)
                continue;
            c.dh[k] = c.dl[k] = 0.0;
        }
        c.wb[0] = i == 0;
        c.wb[1] = i == 1;
        c.wb[2] = i == 2;
        c.meets = c.dh[0] == 0.0 && c.dh[1] == 0.0 && c.dh[2] == 0.0;
        if (!any) {
            *best = c;
            any = 1;
        } else {
            keep(best, &c, radius);
        }
    }
    if (best->meets)
        return 1;
    // A triangle edge crossing the box, relative to corner 0.
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        double t[FRAME_TERMS + 1];
        int n = 0;
        for (int j = 0; j < f->count[0][k]; ++j)
            t[n++] = -f->terms[0][k][j];
        t[n] = -h[k];
        lo[k] = exact_round(t, n + 1);
        t[n] = h[k];
        hi[k] = exact_round(t, n + 1);
    }
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        double dir[3], at;
        vec3_sub(dir, f->e[j], f->e[i]);
        if (slab(f->e[i], dir, lo, hi, &at)) {
            memset(&c, 0, sizeof c);
            c.wb[i] = 1.0 - at;
            c.wb[j] = at;
            c.meets = 1;
            *best = c;
            return 1;
        }
    }
    // The twelve edges, each clipped to what can be within reach.
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        double lo_k, hi_k;
        if (!clip(f, k, h[k], reach, &lo_k, &hi_k))
            continue;
        for (int s = 0; s < 4; ++s) {
            double x0[3], x1[3];
            x0[i] = x1[i] = s & 1 ? h[i] : -h[i];
            x0[j] = x1[j] = s & 2 ? h[j] : -h[j];
            double a, b;
            if (!clip(f, i, h[i], reach, &a, &b) || x0[i] < a || x0[i] > b)
                continue;
            if (!clip(f, j, h[j], reach, &a, &b) || x0[j] < a || x0[j] > b)
                continue;
            x0[k] = lo_k;
            x1[k] = hi_k;
            segment_candidate(f, x0, x1, k, radius, &c);
            keep(best, &c, radius);
            if (best->meets)
                return 1;
        }
    }
    return 1;
}

// The world direction of v (frame), unit; 0 when v is zero.
static int world_direction(const selfcol_collider *c, const double v[3], double out[3]) {
    double w[3], m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(m > 0.0))
        return 0;
    const double s[3] = {v[0] / m, v[1] / m, v[2] / m};
    if (c->shape == SELFCOL_COLLIDER_SPHERE) {
        memcpy(w, s, sizeof w);
    } else {
        for (int k = 0; k < 3; ++k)
            w[k] = vec3_dot(c->rotation + 3 * k, s);
    }
    return vec3_normalize(out, w);
}

// The triangle's longest edge (max norm) in the frame.
static double triangle_size(const tri_frame *f) {
    double d[3];
    vec3_sub(d, f->e[2], f->e[1]);
    return fmax(size_of(d), fmax(size_of(f->e[1]), size_of(f->e[2])));
}

#define COLLIDER_RADIUS_LIMIT 0x1p95   // (radius + distance) / tolerance
#define COLLIDER_DISTANCE_LIMIT 0x1p45 // distance / tolerance
#define COLLIDER_TRIANGLE_LIMIT 0x1p47 // longest edge / tolerance
#define COLLIDER_HULL_LIMIT 0x1p25     // libccd: query size / tolerance

// A bound on the diameter of the convex point set (twice the largest
// distance from the points' mean), + radius.
static double hull_size(const selfcol_collider *c) {
    double m[3] = {0.0, 0.0, 0.0}, far = 0.0;
    for (size_t i = 0; i < c->point_count; ++i)
        for (int k = 0; k < 3; ++k)
            m[k] += c->local[i][k] / (double)c->point_count;
    for (size_t i = 0; i < c->point_count; ++i)
        far = fmax(far, sqrt(vec3_dist2(c->local[i], m)));
    return 2.0 * far + c->radius;
}

// The limits every shape shares (see the top of the file).
static int shared_range(double radius, double distance, double tolerance) {
    return radius + distance <= COLLIDER_RADIUS_LIMIT * tolerance &&
           distance <= COLLIDER_DISTANCE_LIMIT * tolerance;
}

int selfcol_collider__range(const selfcol_collider *c, double distance, double tolerance) {
    if (!shared_range(c->radius, distance, tolerance))
        return SELFCOL_ERANGE;
    if (c->shape == SELFCOL_COLLIDER_CONVEX &&
        !(hull_size(c) + distance <= COLLIDER_HULL_LIMIT * tolerance))
        return SELFCOL_ERANGE;
    return SELFCOL_OK;
}

// The convex point set: libccd in the triangle's frame.
static int convex_contact(const selfcol_collider *col, const double *a, const double *b,
                          const double *c, double distance, double tolerance, double (*scratch)[3],
                          selfcol_collider_contact *out) {
    // The hull's points relative to a: rotation local + position - a, with
    // position - a exact (two_sum): rounded by about 2^-53 x (the result +
    // 3 |local|), far below the tolerance when the local points are not
    // 2^45 x tolerance from their origin; otherwise summed exactly from the
    // products.
    double dh[3], dl[3], far = 0.0;
    for (int k = 0; k < 3; ++k)
        two_sum(col->position[k], -a[k], &dh[k], &dl[k]);
    for (size_t i = 0; i < col->point_count; ++i)
        far = fmax(far, size_of(col->local[i]));
    const int cheap = far * 0x1p-45 <= tolerance;
    for (size_t i = 0; i < col->point_count; ++i)
        for (int k = 0; k < 3; ++k) {
            const double *r = col->rotation + 3 * k, *l = col->local[i];
            if (cheap) {
                scratch[i][k] = (r[0] * l[0] + r[1] * l[1] + r[2] * l[2] + dh[k]) + dl[k];
                continue;
            }
            double t[8];
            for (int j = 0; j < 3; ++j)
                two_product(r[j], l[j], &t[2 * j], &t[2 * j + 1]);
            t[6] = dh[k];
            t[7] = dl[k];
            scratch[i][k] = exact_round(t, 8);
        }
    const double zero[3] = {0.0, 0.0, 0.0};
    double rb[3], rc[3], normal[3], point[3];
    vec3_sub(rb, b, a);
    vec3_sub(rc, c, a);
    const double hull = selfcol_narrow_ccd__hull_triangle(
        (const double(*)[3])scratch, col->point_count, zero, rb, rc, col->radius + distance,
        tolerance, scratch, normal, point);
    if (isnan(hull))
        return SELFCOL_ERANGE;
    if (!(hull <= col->radius + distance))
        return 0;
    memset(out, 0, sizeof *out);
    out->distance = hull > col->radius ? hull - col->radius : 0.0;
    if (out->distance == 0.0)
        out->flags |= SELFCOL_COLLIDER_PENETRATING;
    out->flags |= SELFCOL_COLLIDER_APPROXIMATE;
    memcpy(out->normal, normal, sizeof normal);
    selfcol_narrow_result r;
    selfcol_narrow__vf(point, zero, rb, rc, &r); // MPR's point, onto the triangle
    memcpy(out->wb, r.wb, sizeof out->wb);
    return 1;
}

int selfcol_collider__contacts_of_triangle(const selfcol_collider *col, const double *a,
                                           const double *b, const double *c, double distance,
                                           double tolerance, double (*scratch)[3],
                                           selfcol_collider_contact *out) {
    // (A convex point set's own limit is checked per query by libccd's frame,
    // which is the stricter: selfcol_collider__range() is O(points).)
    if (!shared_range(col->radius, distance, tolerance))
        return SELFCOL_ERANGE;
    if (col->shape == SELFCOL_COLLIDER_CONVEX)
        return convex_contact(col, a, b, c, distance, tolerance, scratch, out);
    tri_frame f;
    frame_of_triangle(col, a, b, c, &f);
    if (!(triangle_size(&f) <= COLLIDER_TRIANGLE_LIMIT * tolerance))
        return SELFCOL_ERANGE;
    const double radius = col->radius;
    const double reach = 2.0 * (radius + distance); // generous: a margin for rounding
    candidate best;
    if (col->shape == SELFCOL_COLLIDER_SPHERE) {
        const double zero[3] = {0.0, 0.0, 0.0};
        segment_candidate(&f, zero, zero, 0, radius, &best);
    } else if (col->shape == SELFCOL_COLLIDER_CAPSULE) {
        const double hh = col->local[1][2];
        double x0[3] = {0.0, 0.0, 0.0}, x1[3] = {0.0, 0.0, 0.0};
        if (!clip(&f, 2, hh, reach, &x0[2], &x1[2]))
            return 0;
        segment_candidate(&f, x0, x1, 2, radius, &best);
    } else {
        if (!box_candidate(col, &f, reach, &best))
            return 0;
    }
    double dist = 0.0;
    if (!best.meets) {
        const double d2 = vec3_dot(best.dh, best.dh);
        if (!(d2 > 0.0))
            best.meets = 1;
        else if (radius > 0.0)
            dist = excess(&best, radius) / (sqrt(d2) + radius);
        else
            dist = sqrt(d2 + 2.0 * vec3_dot(best.dh, best.dl));
    }
    if (!(dist <= distance))
        return 0;
    memset(out, 0, sizeof *out);
    out->distance = dist > 0.0 ? dist : 0.0;
    if (out->distance == 0.0)
        out->flags |= SELFCOL_COLLIDER_PENETRATING;
    memcpy(out->wb, best.wb, sizeof out->wb);
    if (best.meets || !world_direction(col, best.dh, out->normal)) {
        // The triangle's normal, away from the collider's centre.
        double n[3], centre[3];
        vec3_cross(n, f.e[1], f.e[2]);
        for (int k = 0; k < 3; ++k)
            centre[k] = f.v[0][k] + (f.e[1][k] + f.e[2][k]) / 3.0;
        if (vec3_dot(n, centre) < 0.0)
            for (int k = 0; k < 3; ++k)
                n[k] = -n[k];
        if (!world_direction(col, n, out->normal) && !world_direction(col, centre, out->normal)) {
            const double up[3] = {0.0, 0.0, 1.0};
            world_direction(col, up, out->normal);
        }
    }
    return 1;
}

int selfcol_collider__contacts(const selfcol_collider *c, uint32_t collider_id,
                               const selfcol_hierarchy *h, uint32_t surface_id, double distance,
                               double tolerance, uint32_t *stack, double (*scratch)[3],
                               const selfcol_allocator *allocator,
                               selfcol_collider_contact_buffer *out, uint64_t *candidates) {
    if (h->node_count == 0)
        return SELFCOL_OK;
    if (selfcol_collider__range(c, distance, tolerance) != SELFCOL_OK)
        return SELFCOL_ERANGE;
    const selfcol_mesh *mesh = h->mesh;
    const size_t start = out->count;
    size_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const selfcol_node *node = &h->nodes[stack[--top]];
        // The float box is rounded outward: a conservative test.
        const double nlo[3] = {node->lo[0], node->lo[1], node->lo[2]};
        const double nhi[3] = {node->hi[0], node->hi[1], node->hi[2]};
        if (!selfcol_box__near(nlo, nhi, c->lo, c->hi, distance))
            continue;
        if (node->flags & SELFCOL_NODE_DUPLICATES)
            continue; // copies only: no contact names a copy (contacts.h)
        if (node->child_count > 0) {
            for (uint32_t i = 0; i < node->child_count; ++i)
                stack[top++] = node->first_child + i;
            continue;
        }
        for (uint32_t s = node->tri_begin; s < node->tri_begin + node->tri_count; ++s) {
            const uint32_t t = h->tri_order[s];
            if (mesh->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
                continue; // its first occurrence answers for it
            const uint32_t *tri = mesh->triangles + 3 * (size_t)t;
            const double *p[3] = {selfcol_mesh__position(mesh, tri[0]),
                                  selfcol_mesh__position(mesh, tri[1]),
                                  selfcol_mesh__position(mesh, tri[2])};
            double tlo[3], thi[3];
            selfcol_box__of_points(tlo, thi, p, 3);
            if (!selfcol_box__near(tlo, thi, c->lo, c->hi, distance))
                continue;
            ++*candidates;
            selfcol_collider_contact contact;
            const int found = selfcol_collider__contacts_of_triangle(c, p[0], p[1], p[2], distance,
                                                                     tolerance, scratch, &contact);
            if (found < 0) {
                out->count = start;
                return found;
            }
            if (found == 0)
                continue;
            if (grow(allocator, out) != SELFCOL_OK) {
                out->count = start;
                return SELFCOL_ENOMEM;
            }
            contact.collider = collider_id;
            contact.surface = surface_id;
            contact.triangle = t;
            out->items[out->count++] = contact;
        }
    }
    if (out->count > start) // (items is NULL until the first contact)
        qsort(out->items + start, out->count - start, sizeof *out->items, by_triangle);
    return SELFCOL_OK;
}
