// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// libccd narrow phase: the three queries of narrow.c answered with libccd's
// own algorithms, as an independent cross-check of the closed form.
//
// Shapes. A point, a segment and a triangle are the convex hulls of 1, 2 and
// 3 vertices. libccd sees them only through a support function (the vertex
// with the largest dot product with a direction) and a center (the vertex
// average, an interior point, which MPR needs), registered in a ccd_t.
//
// Proximities (VF, EE): distance by inflation. The first primitive swept by a
// ball of radius rho (support: hull support + rho * dir / |dir|) meets the
// second iff their distance is below rho. That yes/no question is asked to
// libccd's Minkowski Portal Refinement test, ccdMPRIntersect() (Snethen,
// "XenoCollide", Game Programming Gems 7, 2008): first at rho = radius (no:
// the distance is >= radius, HUGE_VAL), then by bisection on rho over
// [0, radius] until the bracket is `tolerance` wide. The distance is the
// bracket's midpoint, or 0 when no rho tested was separated.
//
// Why not GJK + EPA (ccdGJKIntersect, then ccdGJKPenetration's depth =
// radius - distance)? Measured on libccd 2.1 (Debian) with random pairs in
// [-1, 1]^3, radius 1, its EPA answers are not usable: the depth is wrong by
// more than 1e-3 of the radius for about 10% of the pairs (by more than 0.1
// of it for 3%, among them "touching" answers of depth ~1e-16 for pairs 0.2
// apart), and only 0.5% are within 1e-7 of the radius. Reading src/ccd.c
// explains it (the same flaws FCL fixed in its fork, FCL pull request 305):
// - expandPolytope() replaces only the nearest face by three faces instead of
//   every face the new support point sees, so the polytope stops being convex
//   and its "nearest face" is not the nearest boundary of the shape;
// - nextSupport() compares epa_tolerance with squared lengths (dot(v,
//   witness) - dist, where witness is not normalised, and a squared distance),
//   so a tolerance t stops EPA at ~sqrt(t); with t squared to fix the units,
//   EPA's loop (it has no iteration cap) ran without end on a random pair;
// - simplexToPolytope4() and doSimplex4() call a face "touching" when
//   ccdVec3PointTriDist2(origin, face) < DBL_EPSILON, and that function
//   evaluates the squared distance by an expanded quadratic that cancels
//   catastrophically (a face 1.6e-3 from the origin with coordinates 2e5
//   evaluates to exactly 0).
// The last flaw also makes ccdGJKIntersect() a poor yes/no test near the
// boundary: with the coordinates scaled as below, it still answers "yes" for
// pairs up to ~1e-6 of rho beyond rho (flat-faced configurations), whereas
// ccdMPRIntersect() had no wrong answer down to 1e-9 of rho on the same pairs.
// MPR penetration (ccdMPRPenetration) measures the depth along the ray from
// the center, not the minimal one (errors of the order of rho). So only the
// yes/no tests are used, MPR's for the proximities.
//
// Accuracy of the bisection. A "yes" of ccdMPRIntersect is a proof (the origin
// is inside a tetrahedron of support points) up to rounding; a "no" is either
// a proof (a support point short of the origin) or the portal reaching
// mpr_tolerance of the boundary with the origin between them, i.e. the
// distance is above rho - mpr_tolerance. The final bracket [lo, hi]
// (hi - lo <= tolerance) thus holds the distance within
// [lo - mpr_tolerance, hi], and the reported midpoint is within
// tolerance / 2 + mpr_tolerance. `tolerance` is split: the bisection stops at
// width `tolerance`, and mpr_tolerance = tolerance / 16, so the bound is
// 0.5625 tolerance (with mpr_tolerance = tolerance it would be 1.5 tolerance:
// measured 1.2). When no rho tested was separated (lo = 0) the distance is
// below hi <= tolerance and is reported as 0, so touching and crossing pairs
// get exactly 0. tests/test_narrow_ccd_internal.c prints the measured errors.
// From radius to tolerance = 1e-7 radius that is 24 bisection steps, so a pair
// within radius costs 25 MPR calls (about 12 support points each); a pair
// beyond radius costs one.
//
// Accuracy floor. MPR's portal normals are cross products of portal edges; when
// the Minkowski difference is thin (a needle triangle, nearly parallel edges)
// and rho is small, those edges are nearly parallel and the yes/no answers
// turn unreliable: distances below ~sqrt(DBL_EPSILON) S (S: the coordinates'
// magnitude) come out off by up to ~0.6 sqrt(DBL_EPSILON) S whatever the
// tolerance (measured on 20000 pairs per family at radii 1 .. 1e-7 S: 0.32 for
// needle triangles against the closed form, 0.56 for nearly parallel segments
// against quad precision), and a radius below that floor may miss such a pair
// altogether. Fat configurations stay within the tolerance down to radii of
// 1e-7 S.
//
// libccd's thresholds are absolute (ccdIsZero: |x| < DBL_EPSILON on squared
// lengths and cross products), so the query is presented to libccd in a local
// frame: translated to the second primitive's first vertex and scaled by a
// power of two (exact) that brings the radius to [512, 1024). There those
// thresholds are far below the rounding of the coordinates, at any mesh scale
// (unscaled, ccdMPRIntersect answered "yes" to every random pair scaled to a
// distance of 1e-6: discoverPortal() calls |v0 x v1|^2 < DBL_EPSILON "origin
// on the segment v0 v1").
//
// Closest points and direction. libccd 2.1 gives no reliable closest points or
// direction here (EPA's and MPR's are off as above; ccdGJKSeparate is EPA).
// So the weights and the direction of `out` are the closed form's
// (narrow.c); only the distance is libccd's. The tests check that the closed
// form's points are libccd's distance apart, within the band.
//
// Interference (EF) is libccd's GJK intersection test, ccdGJKIntersect(), on
// the segment and the triangle as given. It reports touching configurations as
// hits, but not by `tolerance`: libccd 2.1 compares squared lengths and
// squared cross products with DBL_EPSILON, so the touching threshold is
// absolute, about sqrt(DBL_EPSILON) = 1.5e-8 divided by the length of a
// Minkowski edge when that is below 1 (for a triangle of size 1e-4 a segment
// missing it by 0.1 of its size is a hit), and coplanar overlaps are found or
// missed depending on their orientation (its first search direction is fixed).
// tests/test_narrow_ccd_internal.c pins these behaviours down.
//
// Allocation: none. ccdMPRIntersect() and ccdGJKIntersect() keep their simplex
// on the stack (only libccd's EPA and penetration functions allocate).
//
// Termination. libccd 2.1's MPR loops (portal discovery and refinement) have
// no iteration cap, and its GJK runs up to ccd.max_iterations. Non-finite
// input is rejected before libccd is called, and every libccd call gets a
// budget of support-function calls (NARROW_CCD_SUPPORT_BUDGET); past it the
// support function answers with a point that ends the call. A proximity test
// cut short that way counts as "within rho" (the conservative answer: the pair
// is kept, its distance errs low). No input in the tests comes near the budget
// (libccd's MPR made at most ~110 support calls, 55 support points, per
// call); GJK (EF) stops at max_iterations, 202 calls, before it.
#include "narrow/narrow.h"

#include "base/vec3.h"

#include <ccd/ccd.h>
#include <ccd/vec3.h>

#include <float.h>
#include <limits.h>
#include <math.h>

#ifndef CCD_DOUBLE
#error "selfcol needs libccd built with CCD_DOUBLE (ccd_real_t == double)"
#endif

// GJK's iteration cap (EF): GJK on polytopes decides in a handful of
// iterations (a segment and a triangle have 6 Minkowski vertices); the cap only
// guarantees termination on pathological input.
#define NARROW_CCD_MAX_ITERATIONS 100ul

// Support-function calls one libccd call may make (two per support point of
// the Minkowski difference): GJK asks one point per iteration plus one, MPR
// about 12 points (25 calls; at most ~110 calls measured); beyond this the
// call is cut short (see "Termination" above).
#define NARROW_CCD_SUPPORT_BUDGET (8ul * NARROW_CCD_MAX_ITERATIONS)

// The radius is scaled to [2^(FRAME_EXPONENT - 1), 2^FRAME_EXPONENT).
#define NARROW_CCD_FRAME_EXPONENT 10

// Scaled coordinates beyond 2^150 (2^140 radii) are out of range: libccd forms
// products of up to six coordinates (triple cross products, squared), which
// must stay finite. Such a query means a distance below the radius between
// primitives 1e42 times larger, far beyond double precision.
#define NARROW_CCD_FRAME_LIMIT 0x1p150

// The smallest tolerance, relative to the radius: below ~2^-30 the bisection
// and MPR's refinement would chase rounding.
#define NARROW_CCD_MIN_RELATIVE_TOLERANCE 0x1p-30

// MPR's boundary tolerance is tolerance / NARROW_CCD_MPR_SHARE: its "no" may
// be wrong by that much (one-sided), on top of the bisection's +-tolerance / 2.
// It costs nothing measurable (MPR's support count is the same from
// tolerance to tolerance / 100).
#define NARROW_CCD_MPR_SHARE 16.0

// The convex hull of n (1..3) vertices, swept by a ball of radius `radius`
// (0: not swept). The coordinates are a copy (the local frame for the
// proximities, the caller's for EF). `supports` counts the support-function
// calls of the current libccd call, against the budget.
typedef struct hull_shape {
    double v[3][3];
    int n;
    // A hull of more points (colliders): n points here instead of in v.
    const double (*many)[3];
    double radius;
    double escape; // > every |coordinate| + radius: the cut-short distance
    unsigned long *supports;
} hull_shape;

// Unit vector along v, computed without overflow or underflow of |v|^2;
// returns 0 (out untouched) for a zero or non-finite v.
static int unit_vector(double out[3], const double v[3]) {
    double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    if (!(m > 0.0) || !isfinite(m))
        return 0;
    double s[3] = {v[0] / m, v[1] / m, v[2] / m};
    return vec3_normalize(out, s);
}

// libccd support function of the (swept) hull: the vertex maximising
// dot(vertex, dir), ties and NaN keeping the lowest index, plus radius * the
// unit direction (any unit vector, (1, 0, 0), for a zero direction: every
// point of the ball is then a support point).
//
// Past the budget it returns the vertex moved by `escape` against dir: libccd
// then sees a support point short of the origin and ends the call with "no
// intersection" (GJK's and MPR's first test of every new support point).
static void hull_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *out) {
    const hull_shape *s = obj;
    const double(*v)[3] = s->many != NULL ? s->many : (const double(*)[3])s->v;
    int best = 0;
    double best_dot = vec3_dot(v[0], dir->v);
    for (int i = 1; i < s->n; ++i) {
        double d = vec3_dot(v[i], dir->v);
        if (d > best_dot) {
            best_dot = d;
            best = i;
        }
    }
    out->v[0] = v[best][0];
    out->v[1] = v[best][1];
    out->v[2] = v[best][2];
    double u[3];
    if (++*s->supports > NARROW_CCD_SUPPORT_BUDGET) {
        if (unit_vector(u, dir->v)) // (a zero direction already ends MPR and GJK)
            for (int k = 0; k < 3; ++k)
                out->v[k] -= s->escape * u[k];
        return;
    }
    if (s->radius > 0.0) {
        // radius * dir / |dir|: one square root when |dir|^2 neither
        // overflows nor underflows (always, for libccd's directions), the
        // careful unit_vector() otherwise.
        double len2 = vec3_dot(dir->v, dir->v);
        if (len2 > 0x1p-900 && len2 < 0x1p900) {
            double f = s->radius / sqrt(len2);
            for (int k = 0; k < 3; ++k)
                out->v[k] += f * dir->v[k];
            return;
        }
        if (!unit_vector(u, dir->v)) {
            u[0] = 1.0;
            u[1] = 0.0;
            u[2] = 0.0;
        }
        for (int k = 0; k < 3; ++k)
            out->v[k] += s->radius * u[k];
    }
}

// libccd center function (MPR's interior point): the vertex average, which
// lies in the hull; the sweep does not move it.
static void hull_center(const void *obj, ccd_vec3_t *out) {
    const hull_shape *s = obj;
    const double(*v)[3] = s->many != NULL ? s->many : (const double(*)[3])s->v;
    double c[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < s->n; ++i) {
        c[0] += v[i][0];
        c[1] += v[i][1];
        c[2] += v[i][2];
    }
    out->v[0] = c[0] / s->n;
    out->v[1] = c[1] / s->n;
    out->v[2] = c[2] / s->n;
}

static void ccd_setup(ccd_t *ccd, double tolerance) {
    CCD_INIT(ccd);
    ccd->support1 = hull_support;
    ccd->support2 = hull_support;
    ccd->center1 = hull_center;
    ccd->center2 = hull_center;
    ccd->max_iterations = NARROW_CCD_MAX_ITERATIONS;
    ccd->dist_tolerance = tolerance;
    ccd->mpr_tolerance = tolerance;
    ccd->epa_tolerance = tolerance;
}

static int all_finite(int n, const double *const pts[]) {
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(pts[i][k]))
                return 0;
    return 1;
}

// ---------------------------------------------------------------------------
// Proximity by inflation.

// A proximity query in libccd's frame: the first primitive (na vertices, to be
// swept) and the second (nb vertices), translated to the second's first vertex
// and scaled by 2^exponent so that the radius lies in [512, 1024).
typedef struct proximity {
    hull_shape first, second;
    double radius;    // scaled
    double tolerance; // scaled
    int exponent;
    unsigned long supports;
    ccd_t ccd;
} proximity;

// Sets up the frame; returns 0 when the query is out of range (non-finite
// input, radius <= 0, or coordinates beyond NARROW_CCD_FRAME_LIMIT radii).
static int proximity_setup(proximity *q, int na, const double *const a[], int nb,
                           const double *const b[], double radius, double tolerance) {
    const double *all[5] = {a[0], a[na > 1], b[0], b[nb > 1], b[nb - 1]};
    if (!(radius > 0.0) || !isfinite(radius) || !all_finite(5, all))
        return 0;
    int e;
    (void)frexp(radius, &e);
    q->exponent = NARROW_CCD_FRAME_EXPONENT - e;
    q->radius = ldexp(radius, q->exponent);
    double limit = 0.0;
    q->first.n = na;
    q->second.n = nb;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            q->first.v[i][k] = ldexp(a[i < na ? i : na - 1][k] - b[0][k], q->exponent);
            q->second.v[i][k] = ldexp(b[i < nb ? i : nb - 1][k] - b[0][k], q->exponent);
            limit = fmax(limit, fmax(fabs(q->first.v[i][k]), fabs(q->second.v[i][k])));
        }
    if (!(limit <= NARROW_CCD_FRAME_LIMIT))
        return 0;
    double tol = ldexp(tolerance, q->exponent);
    q->tolerance = tol >= NARROW_CCD_MIN_RELATIVE_TOLERANCE * q->radius
                       ? tol
                       : NARROW_CCD_MIN_RELATIVE_TOLERANCE * q->radius;
    q->first.many = q->second.many = NULL;
    q->first.radius = 0.0;
    q->second.radius = 0.0;
    q->first.escape = q->second.escape = 4.0 * (limit + q->radius);
    q->first.supports = q->second.supports = &q->supports;
    ccd_setup(&q->ccd, q->tolerance);
    q->ccd.mpr_tolerance = q->tolerance / NARROW_CCD_MPR_SHARE;
    return 1;
}

// Is the distance below rho (scaled)? libccd's MPR test on the first shape
// swept by rho; a call cut short by the support budget answers yes.
static int within(proximity *q, double rho) {
    q->first.radius = rho;
    q->supports = 0;
    int hit = ccdMPRIntersect(&q->first, &q->second, &q->ccd);
    return hit || q->supports > NARROW_CCD_SUPPORT_BUDGET;
}

// The distance (in the caller's units) when below the radius, else HUGE_VAL.
static double proximity_distance(proximity *q) {
    if (!within(q, q->radius))
        return HUGE_VAL;
    double lo = 0.0, hi = q->radius;
    while (hi - lo > q->tolerance) {
        double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi))
            break; // rounding level
        if (within(q, mid))
            hi = mid;
        else
            lo = mid;
    }
    // Never separated: within the tolerance of touching, reported as touching.
    double d = lo > 0.0 ? 0.5 * (lo + hi) : 0.0;
    return ldexp(d, -q->exponent);
}

// ---------------------------------------------------------------------------
// The queries.

double selfcol_narrow_ccd__vf(const double p[3], const double a[3], const double b[3],
                              const double c[3], double radius, double tolerance,
                              selfcol_narrow_result *out) {
    const double *first[1] = {p}, *second[3] = {a, b, c};
    proximity q;
    if (!proximity_setup(&q, 1, first, 3, second, radius, tolerance))
        return HUGE_VAL;
    double dist = proximity_distance(&q);
    if (out != NULL && dist < HUGE_VAL) {
        selfcol_narrow__vf(p, a, b, c, out);
        out->distance = dist;
    }
    return dist;
}

double selfcol_narrow_ccd__ee(const double p0[3], const double p1[3], const double q0[3],
                              const double q1[3], double radius, double tolerance,
                              selfcol_narrow_result *out) {
    const double *first[2] = {p0, p1}, *second[2] = {q0, q1};
    proximity q;
    if (!proximity_setup(&q, 2, first, 2, second, radius, tolerance))
        return HUGE_VAL;
    double dist = proximity_distance(&q);
    if (out != NULL && dist < HUGE_VAL) {
        selfcol_narrow__ee(p0, p1, q0, q1, out);
        out->distance = dist;
    }
    return dist;
}

int selfcol_narrow_ccd__ef(const double p0[3], const double p1[3], const double a[3],
                           const double b[3], const double c[3], double tolerance,
                           selfcol_narrow_result *out) {
    const double *pts[5] = {p0, p1, a, b, c};
    if (!all_finite(5, pts))
        return 0;
    unsigned long supports = 0;
    hull_shape S = {{{0.0}}, 2, NULL, 0.0, 0.0, &supports};
    hull_shape T = {{{0.0}}, 3, NULL, 0.0, 0.0, &supports};
    for (int k = 0; k < 3; ++k) {
        S.v[0][k] = p0[k];
        S.v[1][k] = p1[k];
        T.v[0][k] = a[k];
        T.v[1][k] = b[k];
        T.v[2][k] = c[k];
    }
    S.escape = T.escape = 4.0 * vec3_max_abs(5, pts) + 1.0;
    ccd_t ccd;
    ccd_setup(&ccd, tolerance);
    if (!ccdGJKIntersect(&S, &T, &ccd) || supports > NARROW_CCD_SUPPORT_BUDGET)
        return 0;
    if (out == NULL)
        return 1;

    // The reported point: where the segment crosses the triangle when the
    // exact test agrees that it does; otherwise libccd accepted a touching
    // configuration (an endpoint on the triangle, a coplanar overlap, a
    // crossing within rounding outside an edge, a zero-area triangle), whose
    // closest pair of points is an endpoint against the triangle or the
    // segment against an edge of it.
    selfcol_narrow__segment_triangle(p0, p1, a, b, c, out);
    out->distance = 0.0;
    // EF records carry the triangle's normal (contacts.h); keep the closed
    // form's fallback when the triangle has no area.
    double ab[3], ac[3], n[3];
    vec3_sub(ab, b, a);
    vec3_sub(ac, c, a);
    vec3_cross(n, ab, ac);
    vec3_normalize(out->direction, n);
    return 1;
}

// ---------------------------------------------------------------------------
// A convex hull of many points against a triangle (the scene's colliders).
//
// The frame is the triangle's: translated to a and scaled by a power of two
// that brings the query's size S (the largest |coordinate| there of the
// hull's points and the triangle's corners, or the radius if larger) to
// [512, 1024). The caller passes the points already relative to the
// triangle (collider.c takes them there exactly), so S is the size of the
// hull, the triangle and the gap between them, not their position. MPR's
// yes/no answers are good to about 2^-26 S on thin configurations (see
// "Accuracy floor" above), so the query is refused (NAN) when tolerance <
// NARROW_CCD_HULL_MIN_RELATIVE_TOLERANCE x S; within it the bisection stops
// at width tolerance / 2 and MPR's tolerance is 1/16 of that, so the answer
// is within tolerance / 4 + tolerance / 32 + 0.6 x 2^-26 S < 0.6 tolerance.

// tolerance / S below this: NAN (collider.h's COLLIDER_HULL_LIMIT agrees).
#define NARROW_CCD_HULL_MIN_RELATIVE_TOLERANCE 0x1p-25

double selfcol_narrow_ccd__hull_triangle(const double (*points)[3], size_t n, const double a[3],
                                         const double b[3], const double c[3], double radius,
                                         double tolerance, double (*scratch)[3], double normal[3],
                                         double point[3]) {
    const double *tri[3] = {a, b, c};
    if (n == 0 || n > INT_MAX || !(radius > 0.0) || !isfinite(radius) || !all_finite(3, tri))
        return HUGE_VAL;
    double size = radius;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            if (!isfinite(points[i][k]))
                return HUGE_VAL;
            size = fmax(size, fabs(points[i][k] - a[k]));
        }
    for (int i = 1; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            size = fmax(size, fabs(tri[i][k] - a[k]));
    if (!isfinite(size))
        return HUGE_VAL;
    if (!(tolerance >= NARROW_CCD_HULL_MIN_RELATIVE_TOLERANCE * size))
        return NAN;
    proximity q;
    int e;
    (void)frexp(size, &e);
    q.exponent = NARROW_CCD_FRAME_EXPONENT - e;
    q.radius = ldexp(radius, q.exponent);
    q.tolerance = ldexp(0.5 * tolerance, q.exponent);
    // (points may be scratch: each coordinate is read before it is written;
    // a product by a normal power of two is ldexp, to the rounding of
    // subnormal results, far below S)
    const double scale = ldexp(1.0, q.exponent);
    const int by_product = q.exponent >= -1000 && q.exponent <= 1000;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            scratch[i][k] =
                by_product ? (points[i][k] - a[k]) * scale : ldexp(points[i][k] - a[k], q.exponent);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            q.second.v[i][k] = ldexp(tri[i][k] - a[k], q.exponent);
    q.first.many = (const double(*)[3])scratch;
    q.first.n = (int)n;
    q.second.many = NULL;
    q.second.n = 3;
    q.first.radius = q.second.radius = 0.0;
    q.first.escape = q.second.escape = 8.0 * 1024.0 + 4.0 * q.radius;
    q.first.supports = q.second.supports = &q.supports;
    ccd_setup(&q.ccd, q.tolerance);
    q.ccd.mpr_tolerance = q.tolerance / NARROW_CCD_MPR_SHARE;
    double dist = proximity_distance(&q);
    if (dist < HUGE_VAL && normal != NULL) {
        // MPR's penetration of the triangle into the hull swept just past
        // the contact (the bracket's upper end, or the first radius whose
        // sweep meets it): libccd moves obj2, the triangle, along dir to
        // separate them, so dir points from the hull toward the triangle.
        double rho = ldexp(dist, q.exponent) + q.tolerance;
        ccd_real_t depth = 0.0;
        ccd_vec3_t dir, pos;
        q.first.radius = rho;
        q.supports = 0;
        if (ccdMPRPenetration(&q.first, &q.second, &q.ccd, &depth, &dir, &pos) == 0 &&
            unit_vector(normal, dir.v)) {
            for (int k = 0; k < 3; ++k)
                point[k] = ldexp(pos.v[k], -q.exponent) + a[k];
        } else {
            normal[0] = normal[1] = normal[2] = 0.0; // no direction found
            for (int k = 0; k < 3; ++k)
                point[k] = a[k];
        }
    }
    return dist;
}
