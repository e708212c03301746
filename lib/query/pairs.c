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
// tested at most once. Ownership keeps the broad phase sound: a vertex
// within d of a triangle lies in its owner's box, so the owner's box is
// within d of the triangle's box too (and likewise for an edge). For a self
// query, pairs sharing a vertex are dropped before any test.
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
// 4. For an edge pair, the distance of the two lines (lines_apart).
// 5. The closed forms of narrow.c (exact predicates for crossings), and a
//    record only for a hit.
// The filters are conservative with a derived rounding bound (see
// plane_flags_scalar), so they never reject a pair whose true distance is
// below d (1 + 2^-20): the contact sets stay exactly those of the exhaustive
// search, which the tests check on every scene. Filters 1-3 are evaluated
// for a whole leaf row or triangle pair at once, as bit masks from two-lane
// SSE2 comparisons (four-lane AVX ones where the CPU has AVX, chosen per
// query), so that their outcomes cost no mispredicted branches;
// the one-lane code beside them is the reference the tests hold them to.
#include "query/pairs.h"

#include "base/box.h"
#include "hierarchy/hierarchy.h"
#include "narrow/narrow.h"

#include <math.h>
#include <string.h>

// The two-lane filters (plane flags, leaf rows) use SSE2, the baseline of
// every x86-64 CPU; elsewhere, or with SELFCOL_SCALAR defined, the one-lane
// references run, and they decide every pair the same way.
#if defined(__SSE2__) && !defined(SELFCOL_SCALAR)
#define SELFCOL_PAIRS_SSE2 1
#include <emmintrin.h>
#else
#define SELFCOL_PAIRS_SSE2 0
#endif

// Four-lane paths (AVX's 256-bit doubles), compiled beside the baseline for
// x86-64 with GCC or Clang and chosen at run time (selfcol_pairs__has_avx):
// the same operations per lane in the same order, so the same bits again.
// AVX and POPCNT only (no FMA): nothing can contract a product and a sum.
// The four-lane code calls no two-lane function: legacy SSE instructions
// right after AVX ones stall (measured: the rows' scalar tail as a call to
// the two-lane rows made the query 30 % slower).
#if SELFCOL_PAIRS_SSE2 && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SELFCOL_PAIRS_AVX 1
#include <immintrin.h>
#define SELFCOL_TARGET_AVX __attribute__((target("avx,popcnt")))
#else
#define SELFCOL_PAIRS_AVX 0
#endif

int selfcol_pairs__has_avx(void) {
#if SELFCOL_PAIRS_AVX
    // The CPU has AVX (and POPCNT, as every AVX CPU) and the OS saves its
    // registers (libgcc reads both).
    return __builtin_cpu_supports("avx") && __builtin_cpu_supports("popcnt");
#else
    return 0;
#endif
}

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
    return selfcol_records__push(q->out, &c);
}

// ---------------------------------------------------------------------------
// One primitive pair by indices (the exhaustive reference's entry points).

static const uint32_t NO_THIRD = SELFCOL_INVALID_INDEX;

static int closed_vf(selfcol_query *q, int mv, uint32_t v, const double *p, int mt, uint32_t t,
                     const uint32_t *tri, const double *const corner[3]) {
    q->out->stats.vf_tests++;
    // The closed form fills the result (weights, direction) in the same call
    // that measures the distance: about half the tests are hits, and a
    // second call for them cost more than the result does for the misses.
    // libccd's bisection is asked for the result only on a hit.
    selfcol_narrow_result r;
    double dist = q->narrow == SELFCOL_NARROW_LIBCCD
                      ? selfcol_narrow_ccd__vf(p, corner[0], corner[1], corner[2], q->distance,
                                               q->ccd_tolerance, NULL)
                      : selfcol_narrow__vf(p, corner[0], corner[1], corner[2], &r);
    if (!(dist < q->distance))
        return SELFCOL_OK;
    if (q->narrow == SELFCOL_NARROW_LIBCCD)
        selfcol_narrow_ccd__vf(p, corner[0], corner[1], corner[2], q->distance, q->ccd_tolerance,
                               &r);
    q->out->stats.vf_contacts++;
    const uint32_t a[2] = {v, v};
    return push_record(q, SELFCOL_CONTACT_VF, mv, v, mt, t, a, tri, &r);
}

// Relative widening of the distance threshold: the filters reject only what
// is farther than d (1 + 2^-20), far outside the rounding of the closed forms.
#define WIDEN (1.0 + 0x1p-20)

// n = u x v from rounded differences u, v, as every plane test here takes
// it: *abs_max gets max_k (|u_i v_j| + |u_j v_i|), the scale of its rounding
// error (plane_flags_scalar's bound); returns the computed |n|.
static double normal_of(const double u[3], const double v[3], double n[3], double *abs_max) {
    double m_max = 0.0;
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        const double x = u[i] * v[j], y = u[j] * v[i];
        n[k] = x - y;
        const double m = fabs(x) + fabs(y);
        m_max = m > m_max ? m : m_max;
    }
    *abs_max = m_max;
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// The threshold a signed offset s = D . n must pass (with its rounding
// margin) to be provably beyond d of the plane: d |n_exact| at most.
static double far_threshold(double d, double length, double abs_max) {
    return d * (length + 0x1p-46 * abs_max) * WIDEN;
}

// 1 when the lines of segments (p0, p1) and (q0, q1) are provably farther
// apart than d, so the segments are too. The lines' distance is that of q0
// from the plane through p0 spanned by u = p1 - p0 and v = q1 - q0: with
// n = u x v, |(q0 - p0) . n| / |n|. That is plane_flags' computation below
// with a normal from two rounded differences and a rounded offset, so its
// rounding bound holds term for term: |s - s_exact| < 2^-48 |D|_1 abs_max,
// and d |n_exact| < d (|n| + 2^-46 abs_max) (1 + 2^-20). Parallel lines
// (n_exact = 0) are never rejected: then |s| is within that bound. The
// cheap half of the EE test: most edge pairs that reach it and miss lie in
// two layers of cloth whose lines pass farther apart than d.
int selfcol_pairs__lines_apart(const double *p0, const double *p1, const double *q0,
                               const double *q1, double d) {
    double u[3], v[3], D[3], n[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = p1[k] - p0[k];
        v[k] = q1[k] - q0[k];
        D[k] = q0[k] - p0[k];
    }
    double abs_max;
    const double length = normal_of(u, v, n, &abs_max);
    const double t = far_threshold(d, length, abs_max);
    const double s = D[0] * n[0] + D[1] * n[1] + D[2] * n[2];
    const double e = 0x1p-48 * (fabs(D[0]) + fabs(D[1]) + fabs(D[2])) * abs_max;
    return fabs(s) - e > t;
}

static int closed_ee(selfcol_query *q, int me, uint32_t e, const uint32_t *ev,
                     const double *const p[2], int mf, uint32_t f, const uint32_t *fv,
                     const double *const r2[2]) {
    if (selfcol_pairs__lines_apart(p[0], p[1], r2[0], r2[1], q->distance)) {
        q->out->stats.primitives_filtered++;
        return SELFCOL_OK;
    }
    q->out->stats.ee_tests++;
    selfcol_narrow_result r; // filled with the distance by the closed form (closed_vf)
    double dist =
        q->narrow == SELFCOL_NARROW_LIBCCD
            ? selfcol_narrow_ccd__ee(p[0], p[1], r2[0], r2[1], q->distance, q->ccd_tolerance, NULL)
            : selfcol_narrow__ee(p[0], p[1], r2[0], r2[1], &r);
    if (!(dist < q->distance))
        return SELFCOL_OK;
    if (q->narrow == SELFCOL_NARROW_LIBCCD)
        selfcol_narrow_ccd__ee(p[0], p[1], r2[0], r2[1], q->distance, q->ccd_tolerance, &r);
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

void selfcol_pairs__frame(selfcol_tri_frame *f, const selfcol_hierarchy *h, uint32_t slot) {
    const selfcol_mesh *m = h->mesh;
    const uint32_t t = h->tri_order[slot];
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    f->id = t;
    f->owned = h->owned[t];
    f->duplicate = (m->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE) != 0;
    f->edge_reversed = 0;
    for (int i = 0; i < 3; ++i) {
        f->corner_id[i] = tri[i];
        memcpy(f->corner[i], selfcol_mesh__position(m, tri[i]), sizeof f->corner[i]);
        for (int k = 0; k < 3; ++k)
            f->xyz[k][i] = f->corner[i][k];
        f->edge[i] = SELFCOL_INVALID_INDEX;
        if (f->owned & SELFCOL_OWNS_EDGE(i)) {
            f->edge[i] = m->triangle_edges[3 * (size_t)t + (size_t)i];
            // The mesh lists an edge's ends (lo, hi) (mesh.h), and an owned
            // edge has two distinct ends: reversed when corner i is the hi
            // end, read without the edge array (a random read per edge).
            if (tri[i] > tri[(i + 1) % 3])
                f->edge_reversed |= (uint8_t)(1u << i);
        }
    }
    for (int k = 0; k < 3; ++k) {
        f->xyz[k][3] = f->corner[0][k];
        f->xyz[k][4] = f->corner[1][k];
    }
    const double *corner[3] = {f->corner[0], f->corner[1], f->corner[2]};
    selfcol_box__of_points(f->lo, f->hi, corner, 3);
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = f->corner[1][k] - f->corner[0][k];
        v[k] = f->corner[2][k] - f->corner[0][k];
    }
    f->length = normal_of(u, v, f->normal, &f->abs_max);
}

// ---------------------------------------------------------------------------
// Triangle pairs

// Flags of the three corners of `other` against the plane of `self`, 3 bits
// each (bit j for corner j): FAR_POS / FAR_NEG when the corner is provably
// beyond d on the positive / negative side, SIDE_POS / SIDE_NEG when it is
// provably strictly on that side.
//
// Rounding bound. n = u x v is computed from rounded differences, each
// component as fl(fl(u_i v_j) - fl(u_j v_i)): |dn_k| <= 5 eps N_k with
// N_k = |u_i v_j| + |u_j v_i| <= abs_max (eps = 2^-53). Then
// s = fl((x - a) . n) with a rounded difference D = x - a: |ds| <=
// 9 eps sum_k |D_k| N_k < 2^-48 |D|_1 abs_max. The exact threshold d |n| is
// at most d (|n|_computed + 2^-46 abs_max) (1 + 2^-20).
enum { FAR_POS = 0, FAR_NEG = 3, SIDE_POS = 6, SIDE_NEG = 9, FLAG_BITS = 12 };

static uint32_t plane_flags_scalar(const selfcol_tri_frame *self, const selfcol_tri_frame *other,
                                   double d) {
    const double a[3] = {self->xyz[0][0], self->xyz[1][0], self->xyz[2][0]}; // corner 0
    const double t = far_threshold(d, self->length, self->abs_max);
    uint32_t out = 0;
    for (int j = 0; j < 3; ++j) {
        const double *x = other->corner[j];
        double D0 = x[0] - a[0], D1 = x[1] - a[1], D2 = x[2] - a[2];
        double s = D0 * self->normal[0] + D1 * self->normal[1] + D2 * self->normal[2];
        double e = 0x1p-48 * (fabs(D0) + fabs(D1) + fabs(D2)) * self->abs_max;
        out |= (uint32_t)(s - e > t) << (FAR_POS + j);
        out |= (uint32_t)(s + e < -t) << (FAR_NEG + j);
        out |= (uint32_t)(s - e > 0.0) << (SIDE_POS + j);
        out |= (uint32_t)(s + e < 0.0) << (SIDE_NEG + j);
    }
    return out;
}

#if SELFCOL_PAIRS_SSE2
// plane_flags_scalar two corners at a time (corners 0, 1, then 2 and a
// copy of 0), with the same operations in the same order, so bit for bit the same
// flags: SSE2's double lanes round as the scalar unit does, and the build
// never contracts a product and a sum into one rounding (-ffp-contract=off).
static inline uint32_t plane_flags(const selfcol_tri_frame *self, const selfcol_tri_frame *other,
                                   double d) {
    const double a[3] = {self->xyz[0][0], self->xyz[1][0], self->xyz[2][0]}; // corner 0
    const double t = far_threshold(d, self->length, self->abs_max);
    const __m128d a0 = _mm_set1_pd(a[0]), a1 = _mm_set1_pd(a[1]), a2 = _mm_set1_pd(a[2]);
    const __m128d n0 = _mm_set1_pd(self->normal[0]), n1 = _mm_set1_pd(self->normal[1]),
                  n2 = _mm_set1_pd(self->normal[2]);
    const __m128d scale = _mm_set1_pd(0x1p-48), abs_max = _mm_set1_pd(self->abs_max);
    const __m128d far = _mm_set1_pd(t), far_neg = _mm_set1_pd(-t), zero = _mm_setzero_pd();
    const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
    uint32_t out = 0;
    for (int half = 0; half < 2; ++half) {
        const __m128d D0 = _mm_sub_pd(_mm_loadu_pd(&other->xyz[0][2 * half]), a0);
        const __m128d D1 = _mm_sub_pd(_mm_loadu_pd(&other->xyz[1][2 * half]), a1);
        const __m128d D2 = _mm_sub_pd(_mm_loadu_pd(&other->xyz[2][2 * half]), a2);
        const __m128d s =
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(D0, n0), _mm_mul_pd(D1, n1)), _mm_mul_pd(D2, n2));
        const __m128d sum =
            _mm_add_pd(_mm_add_pd(_mm_and_pd(D0, magnitude), _mm_and_pd(D1, magnitude)),
                       _mm_and_pd(D2, magnitude));
        const __m128d e = _mm_mul_pd(_mm_mul_pd(scale, sum), abs_max);
        const __m128d below = _mm_sub_pd(s, e), above = _mm_add_pd(s, e);
        const uint32_t lanes = half ? 1u : 3u; // the copy of corner 0 adds nothing
        const uint32_t shift = 2u * (uint32_t)half;
        out |= ((uint32_t)_mm_movemask_pd(_mm_cmpgt_pd(below, far)) & lanes) << (FAR_POS + shift);
        out |= ((uint32_t)_mm_movemask_pd(_mm_cmplt_pd(above, far_neg)) & lanes)
               << (FAR_NEG + shift);
        out |= ((uint32_t)_mm_movemask_pd(_mm_cmpgt_pd(below, zero)) & lanes) << (SIDE_POS + shift);
        out |= ((uint32_t)_mm_movemask_pd(_mm_cmplt_pd(above, zero)) & lanes) << (SIDE_NEG + shift);
    }
    return out;
}
#else
#define plane_flags plane_flags_scalar
#endif

static int all_far(uint32_t flags) {
    return ((flags >> FAR_POS) & 7u) == 7u || ((flags >> FAR_NEG) & 7u) == 7u;
}

typedef uint32_t (*plane_flags_fn)(const selfcol_tri_frame *, const selfcol_tri_frame *, double);

// The separation test with either implementation of the plane flags.
static inline int candidate_with(plane_flags_fn flags_of, const selfcol_tri_frame *fa,
                                 const selfcol_tri_frame *fb, double d, uint32_t *flags) {
    uint32_t of_a = flags_of(fb, fa, d); // a's corners against b's plane
    if (all_far(of_a))
        return 0;
    uint32_t of_b = flags_of(fa, fb, d);
    if (all_far(of_b))
        return 0;
    *flags = of_a | (of_b << FLAG_BITS);
    return 1;
}

int selfcol_pairs__candidate(const selfcol_tri_frame *fa, const selfcol_tri_frame *fb, double d,
                             uint32_t *flags) {
    return candidate_with(plane_flags, fa, fb, d, flags);
}

int selfcol_pairs__candidate_scalar(const selfcol_tri_frame *fa, const selfcol_tri_frame *fb,
                                    double d, uint32_t *flags) {
    return candidate_with(plane_flags_scalar, fa, fb, d, flags);
}

uint32_t selfcol_pairs__row_candidates(const selfcol_tri_frame *a, uint32_t sa,
                                       const selfcol_tri_frame *frames, const uint32_t *near,
                                       uint32_t count, double d, selfcol_slot_pair *out) {
    uint32_t kept = 0;
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t flags;
        if (selfcol_pairs__candidate(a, &frames[near[i]], d, &flags))
            out[kept++] = (selfcol_slot_pair){sa, near[i], flags};
    }
    return kept;
}

#if SELFCOL_PAIRS_AVX
// plane_flags_scalar for the three corners at once (lanes: corners 0, 1, 2
// and a copy of 0, xyz[k][0 .. 3]), term for term.
SELFCOL_TARGET_AVX static inline uint32_t
plane_flags_avx(const selfcol_tri_frame *self, const selfcol_tri_frame *other, double d) {
    const double a[3] = {self->xyz[0][0], self->xyz[1][0], self->xyz[2][0]}; // corner 0
    const double t = far_threshold(d, self->length, self->abs_max);
    const __m256d D0 = _mm256_sub_pd(_mm256_loadu_pd(other->xyz[0]), _mm256_set1_pd(a[0]));
    const __m256d D1 = _mm256_sub_pd(_mm256_loadu_pd(other->xyz[1]), _mm256_set1_pd(a[1]));
    const __m256d D2 = _mm256_sub_pd(_mm256_loadu_pd(other->xyz[2]), _mm256_set1_pd(a[2]));
    const __m256d s =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(D0, _mm256_set1_pd(self->normal[0])),
                                    _mm256_mul_pd(D1, _mm256_set1_pd(self->normal[1]))),
                      _mm256_mul_pd(D2, _mm256_set1_pd(self->normal[2])));
    const __m256d magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    const __m256d sum =
        _mm256_add_pd(_mm256_add_pd(_mm256_and_pd(D0, magnitude), _mm256_and_pd(D1, magnitude)),
                      _mm256_and_pd(D2, magnitude));
    const __m256d e =
        _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0x1p-48), sum), _mm256_set1_pd(self->abs_max));
    const __m256d below = _mm256_sub_pd(s, e), above = _mm256_add_pd(s, e);
    const __m256d zero = _mm256_setzero_pd();
    const uint32_t far_pos =
        (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(below, _mm256_set1_pd(t), _CMP_GT_OQ));
    const uint32_t far_neg =
        (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(above, _mm256_set1_pd(-t), _CMP_LT_OQ));
    const uint32_t side_pos = (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(below, zero, _CMP_GT_OQ));
    const uint32_t side_neg = (uint32_t)_mm256_movemask_pd(_mm256_cmp_pd(above, zero, _CMP_LT_OQ));
    return (far_pos & 7u) << FAR_POS | (far_neg & 7u) << FAR_NEG | (side_pos & 7u) << SIDE_POS |
           (side_neg & 7u) << SIDE_NEG;
}

// The row without a branch per pair: both planes' flags always (a second
// pass costs less than the mispredicted early exit it replaces: about half
// the pairs of cloth-ball 92 are separated, in no pattern), each pair
// written and the count advanced by its outcome.
SELFCOL_TARGET_AVX uint32_t selfcol_pairs__row_candidates_avx(const selfcol_tri_frame *a,
                                                              uint32_t sa,
                                                              const selfcol_tri_frame *frames,
                                                              const uint32_t *near, uint32_t count,
                                                              double d, selfcol_slot_pair *out) {
    uint32_t kept = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const selfcol_tri_frame *b = &frames[near[i]];
        const uint32_t of_a = plane_flags_avx(b, a, d), of_b = plane_flags_avx(a, b, d);
        out[kept] = (selfcol_slot_pair){sa, near[i], of_a | (of_b << FLAG_BITS)};
        kept += (uint32_t) !(all_far(of_a) | all_far(of_b));
    }
    return kept;
}
#else
uint32_t selfcol_pairs__row_candidates_avx(const selfcol_tri_frame *a, uint32_t sa,
                                           const selfcol_tri_frame *frames, const uint32_t *near,
                                           uint32_t count, double d, selfcol_slot_pair *out) {
    return selfcol_pairs__row_candidates(a, sa, frames, near, count, d, out);
}
#endif

// ---------------------------------------------------------------------------
// Leaf rows

uint32_t selfcol_pairs__near_slots_scalar(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                          uint32_t begin, uint32_t end, double d, uint32_t *out) {
    const double *lo0 = b->lo[0], *lo1 = b->lo[1], *lo2 = b->lo[2];
    const double *hi0 = b->hi[0], *hi1 = b->hi[1], *hi2 = b->hi[2];
    uint32_t count = 0;
    for (uint32_t s = begin; s < end; ++s) {
        const double lo[3] = {lo0[s], lo1[s], lo2[s]}, hi[3] = {hi0[s], hi1[s], hi2[s]};
        // Every slot is written; the count advances by the test's outcome.
        out[count] = s;
        count += (uint32_t)selfcol_box__near(a->lo, a->hi, lo, hi, d);
    }
    return count;
}

#if SELFCOL_PAIRS_SSE2
// Two slots at a time: the six comparisons of selfcol_box__near per lane
// (a_lo - d > b_hi or b_lo - d > a_hi on some axis: apart), one mask.
uint32_t selfcol_pairs__near_slots(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                   uint32_t begin, uint32_t end, double d, uint32_t *out) {
    const __m128d dd = _mm_set1_pd(d);
    __m128d a_lo_d[3], a_hi[3];
    const double *lo[3], *hi[3];
    for (int k = 0; k < 3; ++k) {
        a_lo_d[k] = _mm_set1_pd(a->lo[k] - d);
        a_hi[k] = _mm_set1_pd(a->hi[k]);
        lo[k] = b->lo[k];
        hi[k] = b->hi[k];
    }
    uint32_t count = 0, s = begin;
    for (; s + 1 < end; s += 2) {
        __m128d apart = _mm_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m128d b_lo = _mm_loadu_pd(&lo[k][s]), b_hi = _mm_loadu_pd(&hi[k][s]);
            apart = _mm_or_pd(apart, _mm_cmpgt_pd(a_lo_d[k], b_hi));
            apart = _mm_or_pd(apart, _mm_cmpgt_pd(_mm_sub_pd(b_lo, dd), a_hi[k]));
        }
        const uint32_t near = ~(uint32_t)_mm_movemask_pd(apart);
        out[count] = s;
        count += near & 1u;
        out[count] = s + 1;
        count += (near >> 1) & 1u;
    }
    if (s < end)
        count += selfcol_pairs__near_slots_scalar(a, b, s, end, d, out + count);
    return count;
}
#else
uint32_t selfcol_pairs__near_slots(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                   uint32_t begin, uint32_t end, double d, uint32_t *out) {
    return selfcol_pairs__near_slots_scalar(a, b, begin, end, d, out);
}
#endif

#if SELFCOL_PAIRS_AVX
// The lanes of each 4-bit mask in increasing order (then zeros): the
// compaction of a row's near slots without a branch per slot.
static const uint32_t lanes_of_mask[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0},
    {1, 2, 0, 0}, {0, 1, 2, 0}, {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0},
    {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};

// Lane masks of vmaskmovpd: the first n of four lanes.
static const int64_t first_lanes[5][4] = {
    {0, 0, 0, 0}, {-1, 0, 0, 0}, {-1, -1, 0, 0}, {-1, -1, -1, 0}, {-1, -1, -1, -1}};

// Four slots at a time, as the two-lane version. The last group of a row
// that ends inside one is loaded with a lane mask (vmaskmovpd reads no
// masked lane): the slots past the row's end belong to another leaf, whose
// boxes another worker may be writing (traverse.c, ensure_frames). (Copying
// the row's last slots into a local group instead cost 15 % of the query:
// the four-lane load of four single stores cannot be forwarded.)
SELFCOL_TARGET_AVX uint32_t selfcol_pairs__near_slots_avx(const selfcol_tri_frame *a,
                                                          const selfcol_slot_boxes *b,
                                                          uint32_t begin, uint32_t end, double d,
                                                          uint32_t *out) {
    const __m256d dd = _mm256_set1_pd(d);
    __m256d a_lo_d[3], a_hi[3];
    const double *lo[3], *hi[3];
    for (int k = 0; k < 3; ++k) {
        a_lo_d[k] = _mm256_set1_pd(a->lo[k] - d);
        a_hi[k] = _mm256_set1_pd(a->hi[k]);
        lo[k] = b->lo[k];
        hi[k] = b->hi[k];
    }
    uint32_t count = 0;
    for (uint32_t s = begin; s < end; s += 4) {
        const uint32_t lanes = end - s < 4 ? end - s : 4;
        const __m256i mask = _mm256_loadu_si256((const __m256i *)(const void *)first_lanes[lanes]);
        __m256d apart = _mm256_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m256d b_lo = _mm256_maskload_pd(lo[k] + s, mask),
                          b_hi = _mm256_maskload_pd(hi[k] + s, mask);
            apart = _mm256_or_pd(apart, _mm256_cmp_pd(a_lo_d[k], b_hi, _CMP_GT_OQ));
            apart =
                _mm256_or_pd(apart, _mm256_cmp_pd(_mm256_sub_pd(b_lo, dd), a_hi[k], _CMP_GT_OQ));
        }
        const uint32_t near = ~(uint32_t)_mm256_movemask_pd(apart) & ((1u << lanes) - 1u);
        const __m128i slots = _mm_add_epi32(_mm_set1_epi32((int)s),
                                            _mm_loadu_si128((const __m128i *)lanes_of_mask[near]));
        _mm_storeu_si128((__m128i *)(void *)(out + count), slots);
        count += (uint32_t)__builtin_popcount(near);
    }
    return count;
}
#else
uint32_t selfcol_pairs__near_slots_avx(const selfcol_tri_frame *a, const selfcol_slot_boxes *b,
                                       uint32_t begin, uint32_t end, double d, uint32_t *out) {
    return selfcol_pairs__near_slots(a, b, begin, end, d, out);
}
#endif

static int shares_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

// Box of segment (p[0], p[1]) within d of the box (lo, hi) on every axis.
static int segment_near(const double *const p[2], const double *lo, const double *hi, double d) {
    double slo[3], shi[3];
    selfcol_box__of_points(slo, shi, p, 2);
    return selfcol_box__near(slo, shi, lo, hi, d);
}

// 1 when both ends of edge slot i (corners i and i + 1) have the flag at `bit`.
static int edge_has(uint32_t flags, int bit, int i) {
    return ((flags >> (bit + i)) & 1u) && ((flags >> (bit + (i + 1) % 3)) & 1u);
}

// Edge slot i of a triangle: its index, and its two ends in record order.
static void edge_ends(const selfcol_tri_frame *f, int i, uint32_t ev[2], const double *p[2]) {
    const int j = (i + 1) % 3;
    const int rev = (f->edge_reversed >> i) & 1;
    ev[0] = f->corner_id[rev ? j : i];
    ev[1] = f->corner_id[rev ? i : j];
    p[0] = f->corner[rev ? j : i];
    p[1] = f->corner[rev ? i : j];
}

// Vertices and edges owned by a (of mesh ma), against triangle b (of mesh
// mb). `of_a` are the flags of a's corners against b's plane.
static int one_way(selfcol_query *q, int ma, const selfcol_tri_frame *a, int mb,
                   const selfcol_tri_frame *b, uint32_t of_a) {
    const double d = q->distance;
    const int self = q->self;
    int status = SELFCOL_OK;
    const double *corner_b[3] = {b->corner[0], b->corner[1], b->corner[2]};
    if (q->kinds & SELFCOL_KIND_VF) {
        const uint32_t far = ((of_a >> FAR_POS) | (of_a >> FAR_NEG)) & 7u;
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(a->owned & SELFCOL_OWNS_VERTEX(i)))
                continue;
            const uint32_t v = a->corner_id[i];
            if (self && shares_corner(v, b->corner_id))
                continue;
            if ((far >> i) & 1u || !selfcol_box__point_near(a->corner[i], b->lo, b->hi, d)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            status = closed_vf(q, ma, v, a->corner[i], mb, b->id, b->corner_id, corner_b);
        }
    }
    if (q->kinds & SELFCOL_KIND_EF) {
        for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
            if (!(a->owned & SELFCOL_OWNS_EDGE(i)))
                continue;
            uint32_t ev[2];
            const double *p[2];
            edge_ends(a, i, ev, p);
            if (self && (shares_corner(ev[0], b->corner_id) || shares_corner(ev[1], b->corner_id)))
                continue;
            // Both ends strictly on one side of b's plane: no crossing.
            if (edge_has(of_a, SIDE_POS, i) || edge_has(of_a, SIDE_NEG, i) ||
                !segment_near(p, b->lo, b->hi, 0.0)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            status = closed_ef(q, ma, a->edge[i], ev, p, mb, b->id, b->corner_id, corner_b);
        }
    }
    return status;
}

static int edges_both_ways(selfcol_query *q, int ma, const selfcol_tri_frame *a, int mb,
                           const selfcol_tri_frame *b, uint32_t of_a, uint32_t of_b) {
    const double d = q->distance;
    const int self = q->self;
    int status = SELFCOL_OK;
    for (int i = 0; i < 3 && status == SELFCOL_OK; ++i) {
        if (!(a->owned & SELFCOL_OWNS_EDGE(i)))
            continue;
        // An edge of a beyond d of b's plane, both ends on one side, is beyond
        // d of every edge of b.
        if (edge_has(of_a, FAR_POS, i) || edge_has(of_a, FAR_NEG, i)) {
            for (int j = 0; j < 3; ++j)
                q->out->stats.primitives_filtered += (b->owned & SELFCOL_OWNS_EDGE(j)) != 0;
            continue;
        }
        uint32_t ev[2];
        const double *p[2];
        edge_ends(a, i, ev, p);
        const uint32_t e = a->edge[i];
        for (int j = 0; j < 3 && status == SELFCOL_OK; ++j) {
            if (!(b->owned & SELFCOL_OWNS_EDGE(j)))
                continue;
            uint32_t fv[2];
            const double *r[2];
            edge_ends(b, j, fv, r);
            if (self && (ev[0] == fv[0] || ev[0] == fv[1] || ev[1] == fv[0] || ev[1] == fv[1]))
                continue;
            double lo[3], hi[3];
            selfcol_box__of_points(lo, hi, r, 2);
            if (edge_has(of_b, FAR_POS, j) || edge_has(of_b, FAR_NEG, j) ||
                !segment_near(p, lo, hi, d)) {
                q->out->stats.primitives_filtered++;
                continue;
            }
            const uint32_t f = b->edge[j];
            if (self && f < e)
                status = closed_ee(q, mb, f, fv, r, ma, e, ev, p);
            else
                status = closed_ee(q, ma, e, ev, p, mb, f, fv, r);
        }
    }
    return status;
}

int selfcol_pairs__run_scalar(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                              const selfcol_slot_pair *pairs, size_t count) {
    int status = SELFCOL_OK;
    const uint32_t mask = (1u << FLAG_BITS) - 1u;
    for (size_t k = 0; k < count && status == SELFCOL_OK; ++k) {
        const selfcol_tri_frame *a = &frames[0][pairs[k].a], *b = &frames[1][pairs[k].b];
        const uint32_t of_a = pairs[k].flags & mask, of_b = pairs[k].flags >> FLAG_BITS;
        status = one_way(q, 0, a, 1, b, of_a);
        if (status == SELFCOL_OK)
            status = one_way(q, 1, b, 0, a, of_b);
        if (status == SELFCOL_OK && (q->kinds & SELFCOL_KIND_EE))
            status = edges_both_ways(q, 0, a, 1, b, of_a, of_b);
    }
    return status;
}

// ---------------------------------------------------------------------------
// The primitive pairs of a triangle pair as bit masks (two lanes)
//
// selfcol_pairs__run_scalar decides each primitive pair with its own
// branches, and on a folded cloth their outcomes look random to a branch
// predictor (cloth-ball 92: about half of the query's mispredicted branches
// were there). Here every filter is evaluated for all of a triangle pair's
// primitives at once, as bits (corner c, edge slot i, edge pair 3 i + j),
// from two-lane comparisons of the same values, and only the primitive
// pairs that pass every filter are visited, by their set bits. The
// comparisons are term for term those of the one-lane filters (box.h's
// formulas on the same rounded values), so the same pairs reach the closed
// forms and the statistics are the same.

#if SELFCOL_PAIRS_SSE2
// Bit i of the result is bit (i + 1) mod 3 of s (s a 3-bit corner mask).
static inline uint32_t next3(uint32_t s) {
    return ((s >> 1) | (s << 2)) & 7u;
}

// Of a 3 x 3 mask (bit 3 i + j), rows i + 1 moved to i and columns j + 1 to j.
static inline uint32_t next_rows(uint32_t m) {
    return (m >> 3) | ((m & 7u) << 6);
}
static inline uint32_t next_columns(uint32_t m) {
    return ((m >> 1) & 0xDBu) | ((m << 2) & 0x124u);
}

// Set bits of a mask below 2^9, without a branch (a loop over the bits
// would mispredict as the filters' outcomes do).
static inline uint32_t bit_count(uint32_t m) {
    m = m - ((m >> 1) & 0x55555555u);
    m = (m & 0x33333333u) + ((m >> 2) & 0x33333333u);
    return (((m + (m >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
}

static inline int lowest_bit(uint32_t m) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctz(m);
#else
    int i = 0;
    while (!((m >> i) & 1u))
        ++i;
    return i;
#endif
}

// a's corners against b's box: *outside_d gets the corners outside it
// inflated by d (selfcol_box__point_near fails: VF), *apart the edge slots
// whose box misses it (selfcol_box__near with d = 0 fails: EF; an edge's
// box misses on an axis when both ends lie beyond the same side).
static inline void corners_against_box(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                       double d, uint32_t *outside_d, uint32_t *apart) {
    __m128d out0 = _mm_setzero_pd(), out1 = _mm_setzero_pd();
    __m128d apart0 = _mm_setzero_pd(), apart1 = _mm_setzero_pd();
    for (int k = 0; k < 3; ++k) {
        const __m128d lo = _mm_set1_pd(b->lo[k]), hi = _mm_set1_pd(b->hi[k]);
        const __m128d lo_d = _mm_set1_pd(b->lo[k] - d), hi_d = _mm_set1_pd(b->hi[k] + d);
        const __m128d c01 = _mm_loadu_pd(&a->xyz[k][0]), c12 = _mm_loadu_pd(&a->xyz[k][1]);
        const __m128d c20 = _mm_loadu_pd(&a->xyz[k][2]), c01n = _mm_loadu_pd(&a->xyz[k][3]);
        out0 = _mm_or_pd(out0, _mm_or_pd(_mm_cmpgt_pd(c01, hi_d), _mm_cmplt_pd(c01, lo_d)));
        out1 = _mm_or_pd(out1, _mm_or_pd(_mm_cmpgt_pd(c20, hi_d), _mm_cmplt_pd(c20, lo_d)));
        apart0 =
            _mm_or_pd(apart0, _mm_or_pd(_mm_and_pd(_mm_cmpgt_pd(c01, hi), _mm_cmpgt_pd(c12, hi)),
                                        _mm_and_pd(_mm_cmplt_pd(c01, lo), _mm_cmplt_pd(c12, lo))));
        apart1 =
            _mm_or_pd(apart1, _mm_or_pd(_mm_and_pd(_mm_cmpgt_pd(c20, hi), _mm_cmpgt_pd(c01n, hi)),
                                        _mm_and_pd(_mm_cmplt_pd(c20, lo), _mm_cmplt_pd(c01n, lo))));
    }
    *outside_d = ((uint32_t)_mm_movemask_pd(out0) | (uint32_t)_mm_movemask_pd(out1) << 2) & 7u;
    *apart = ((uint32_t)_mm_movemask_pd(apart0) | (uint32_t)_mm_movemask_pd(apart1) << 2) & 7u;
}

// Which of a's owned vertices (VF) and edges (EF) are tested against b, and
// how many owned ones the filters dropped (primitives_filtered). of_a: a's
// corner flags against b's plane; shared: a's corners that are b's.
typedef void (*corner_box_fn)(const selfcol_tri_frame *, const selfcol_tri_frame *, double,
                              uint32_t *, uint32_t *);

// With either lane width's corners_against_box (inlined with a constant
// `against_box`).
static inline void one_way_masks_with(corner_box_fn against_box, const selfcol_tri_frame *a,
                                      const selfcol_tri_frame *b, uint32_t of_a, uint32_t shared,
                                      double d, uint32_t kinds, uint32_t *vf, uint32_t *ef,
                                      uint64_t *filtered) {
    // First the filters of the plane flags (bits only), then the box tests
    // for what is left, if anything is.
    uint32_t vf_eligible = 0, vf_left = 0, ef_eligible = 0, ef_left = 0;
    if (kinds & SELFCOL_KIND_VF) {
        vf_eligible = a->owned & 7u & ~shared;
        vf_left = vf_eligible & ~(((of_a >> FAR_POS) | (of_a >> FAR_NEG)) & 7u);
    }
    if (kinds & SELFCOL_KIND_EF) {
        ef_eligible = (a->owned >> 3) & 7u & ~(shared | next3(shared));
        const uint32_t pos = (of_a >> SIDE_POS) & 7u, neg = (of_a >> SIDE_NEG) & 7u;
        ef_left = ef_eligible & ~((pos & next3(pos)) | (neg & next3(neg)));
    }
    uint32_t outside_d = 7u, apart = 7u;
    if ((vf_left | ef_left) != 0)
        against_box(a, b, d, &outside_d, &apart);
    *vf = vf_left & ~outside_d;
    *ef = ef_left & ~apart;
    *filtered += bit_count(vf_eligible & ~*vf) + bit_count(ef_eligible & ~*ef);
}

static inline void one_way_masks(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                 uint32_t of_a, uint32_t shared, double d, uint32_t kinds,
                                 uint32_t *vf, uint32_t *ef, uint64_t *filtered) {
    one_way_masks_with(corners_against_box, a, b, of_a, shared, d, kinds, vf, ef, filtered);
}

// The boxes of a triangle's edge slots, axis by axis, two slots per vector:
// [0] slots 0 and 1, [1] slot 2 (and a copy): lo - d and hi, as box.h's
// selfcol_box__of_points and selfcol_box__near compute them.
static inline void edge_boxes(const selfcol_tri_frame *f, double d, __m128d lo_d[3][2],
                              __m128d hi[3][2]) {
    const __m128d dd = _mm_set1_pd(d);
    for (int k = 0; k < 3; ++k)
        for (int h = 0; h < 2; ++h) {
            const __m128d p = _mm_loadu_pd(&f->xyz[k][2 * h]);
            const __m128d q = _mm_loadu_pd(&f->xyz[k][2 * h + 1]);
            // min: p < q ? p : q; max: p > q ? p : q (SSE2's minpd/maxpd).
            lo_d[k][h] = _mm_sub_pd(_mm_min_pd(p, q), dd);
            hi[k][h] = _mm_max_pd(p, q);
        }
}

// Edge pairs (bit 3 i + j: slot i of a, slot j of b) tested, and the owned
// pairs dropped: an edge of a beyond d of b's plane (both ends on one side)
// is beyond d of every edge of b (counted against all of b's owned edges);
// otherwise a pair is dropped when the edges share a vertex (self, not
// counted), when b's edge is beyond d of a's plane, or when their boxes are
// farther apart than d.
// The bit part of edge_pair_masks, either lane width: the edge pairs left
// once a's far edges and the shared vertices are out (a's far edges
// counted), and in *far_columns the pairs with an edge of b beyond d of a's
// plane, dropped with the box test's.
static inline uint32_t edge_pairs_eligible(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                           uint32_t of_a, uint32_t of_b, uint32_t matches,
                                           uint32_t *far_columns, uint64_t *filtered) {
    const uint32_t owned_a = (a->owned >> 3) & 7u, owned_b = (b->owned >> 3) & 7u;
    const uint32_t fp_a = (of_a >> FAR_POS) & 7u, fn_a = (of_a >> FAR_NEG) & 7u;
    const uint32_t fp_b = (of_b >> FAR_POS) & 7u, fn_b = (of_b >> FAR_NEG) & 7u;
    const uint32_t far_a = (fp_a & next3(fp_a)) | (fn_a & next3(fn_a));
    const uint32_t far_b = (fp_b & next3(fp_b)) | (fn_b & next3(fn_b));
    const uint32_t live_a = owned_a & ~far_a;
    *filtered += bit_count(owned_a & far_a) * bit_count(owned_b);
    // Rows: a's live edges; columns: b's owned edges.
    const uint32_t rows =
        ((live_a & 1u) * 7u) | ((live_a & 2u) * (7u << 2)) | ((live_a & 4u) * (7u << 4));
    const uint32_t columns = owned_b * 0x49u;
    *far_columns = far_b * 0x49u;
    const uint32_t shared =
        matches | next_rows(matches) | next_columns(matches) | next_rows(next_columns(matches));
    return rows & columns & ~shared;
}

static inline uint32_t edge_pair_masks(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                       uint32_t of_a, uint32_t of_b, uint32_t matches, double d,
                                       uint64_t *filtered) {
    uint32_t far_columns;
    const uint32_t eligible =
        edge_pairs_eligible(a, b, of_a, of_b, matches, &far_columns, filtered);
    if (eligible == 0)
        return 0;
    __m128d a_lo_d[3][2], a_hi[3][2], b_lo_d[3][2], b_hi[3][2];
    edge_boxes(a, d, a_lo_d, a_hi);
    edge_boxes(b, d, b_lo_d, b_hi);
    double blo[3][4], bhi[3][4]; // b's slot j on axis k: [k][j]
    for (int k = 0; k < 3; ++k) {
        _mm_storeu_pd(&blo[k][0], b_lo_d[k][0]);
        _mm_storeu_pd(&blo[k][2], b_lo_d[k][1]);
        _mm_storeu_pd(&bhi[k][0], b_hi[k][0]);
        _mm_storeu_pd(&bhi[k][2], b_hi[k][1]);
    }
    uint32_t apart = 0;
    for (int j = 0; j < 3; ++j) {
        __m128d x0 = _mm_setzero_pd(), x1 = _mm_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m128d lo = _mm_set1_pd(blo[k][j]), hi = _mm_set1_pd(bhi[k][j]);
            x0 = _mm_or_pd(x0,
                           _mm_or_pd(_mm_cmpgt_pd(a_lo_d[k][0], hi), _mm_cmpgt_pd(lo, a_hi[k][0])));
            x1 = _mm_or_pd(x1,
                           _mm_or_pd(_mm_cmpgt_pd(a_lo_d[k][1], hi), _mm_cmpgt_pd(lo, a_hi[k][1])));
        }
        const uint32_t m0 = (uint32_t)_mm_movemask_pd(x0), m1 = (uint32_t)_mm_movemask_pd(x1);
        apart |= ((m0 & 1u) << j) | (((m0 >> 1) & 1u) << (3 + j)) | ((m1 & 1u) << (6 + j));
    }
    const uint32_t tested = eligible & ~far_columns & ~apart;
    *filtered += bit_count(eligible & ~tested);
    return tested;
}

// The set bits of vf and ef: a's vertices and edges against triangle b.
static int one_way_tests(selfcol_query *q, int ma, const selfcol_tri_frame *a, int mb,
                         const selfcol_tri_frame *b, uint32_t vf, uint32_t ef) {
    const double *corner_b[3] = {b->corner[0], b->corner[1], b->corner[2]};
    int status = SELFCOL_OK;
    for (; vf != 0 && status == SELFCOL_OK; vf &= vf - 1) {
        const int i = lowest_bit(vf);
        status = closed_vf(q, ma, a->corner_id[i], a->corner[i], mb, b->id, b->corner_id, corner_b);
    }
    for (; ef != 0 && status == SELFCOL_OK; ef &= ef - 1) {
        const int i = lowest_bit(ef);
        uint32_t ev[2];
        const double *p[2];
        edge_ends(a, i, ev, p);
        status = closed_ef(q, ma, a->edge[i], ev, p, mb, b->id, b->corner_id, corner_b);
    }
    return status;
}

static int edge_pair_tests(selfcol_query *q, const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                           uint32_t tested) {
    int status = SELFCOL_OK;
    for (; tested != 0 && status == SELFCOL_OK; tested &= tested - 1) {
        const int bit = lowest_bit(tested), i = bit / 3, j = bit % 3;
        uint32_t ev[2], fv[2];
        const double *p[2], *r[2];
        edge_ends(a, i, ev, p);
        edge_ends(b, j, fv, r);
        const uint32_t e = a->edge[i], f = b->edge[j];
        if (q->self && f < e)
            status = closed_ee(q, 1, f, fv, r, 0, e, ev, p);
        else
            status = closed_ee(q, 0, e, ev, p, 1, f, fv, r);
    }
    return status;
}

// What the filters leave of a triangle pair: a's vertices and edges tested
// against b (vf_ab, ef_ab), b's against a, and the edge pairs (ee).
typedef struct pair_masks {
    uint32_t vf_ab, ef_ab, vf_ba, ef_ba, ee;
} pair_masks;

// Bit 3 i + j: corner i of a is corner j of b (a self query; 0 otherwise).
static inline uint32_t corner_matches(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                      uint32_t self_mask) {
    uint32_t matches = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            matches |= (uint32_t)(a->corner_id[i] == b->corner_id[j]) << (3 * i + j);
    return matches & self_mask;
}

// a's corners shared with b, and b's with a, from the matches.
static inline void shared_corners(uint32_t matches, uint32_t *shared_a, uint32_t *shared_b) {
    *shared_a = (uint32_t)((matches & 7u) != 0) | (uint32_t)((matches & 070u) != 0) << 1 |
                (uint32_t)((matches & 0700u) != 0) << 2;
    *shared_b = (matches | (matches >> 3) | (matches >> 6)) & 7u;
}

static inline uint32_t two_lane_masks(const selfcol_tri_frame *a, const selfcol_tri_frame *b,
                                      uint32_t of_a, uint32_t of_b, uint32_t self_mask, double d,
                                      uint32_t kinds, pair_masks *m, uint64_t *filtered) {
    const uint32_t matches = corner_matches(a, b, self_mask);
    uint32_t shared_a, shared_b;
    shared_corners(matches, &shared_a, &shared_b);
    one_way_masks(a, b, of_a, shared_a, d, kinds, &m->vf_ab, &m->ef_ab, filtered);
    one_way_masks(b, a, of_b, shared_b, d, kinds, &m->vf_ba, &m->ef_ba, filtered);
    m->ee = kinds & SELFCOL_KIND_EE ? edge_pair_masks(a, b, of_a, of_b, matches, d, filtered) : 0;
    return m->vf_ab | m->ef_ab | m->vf_ba | m->ef_ba | m->ee;
}

typedef uint32_t (*masks_fn)(const selfcol_tri_frame *, const selfcol_tri_frame *, uint32_t,
                             uint32_t, uint32_t, double, uint32_t, pair_masks *, uint64_t *);

// The filtered run with either implementation of the masks (inlined with a
// constant `masks`), then the tests of what is left.
static inline int run_with(masks_fn masks, selfcol_query *q,
                           const selfcol_tri_frame *const frames[2], const selfcol_slot_pair *pairs,
                           size_t count) {
    int status = SELFCOL_OK;
    const uint32_t mask = (1u << FLAG_BITS) - 1u;
    const double d = q->distance;
    const uint32_t kinds = q->kinds;
    const uint32_t self_mask = q->self ? ~0u : 0u; // vertices are shared within one mesh only
    uint64_t filtered = 0;
    for (size_t k = 0; k < count && status == SELFCOL_OK; ++k) {
        const selfcol_tri_frame *a = &frames[0][pairs[k].a], *b = &frames[1][pairs[k].b];
        const uint32_t of_a = pairs[k].flags & mask, of_b = pairs[k].flags >> FLAG_BITS;
        pair_masks m;
        if (masks(a, b, of_a, of_b, self_mask, d, kinds, &m, &filtered) == 0)
            continue;
        status = one_way_tests(q, 0, a, 1, b, m.vf_ab, m.ef_ab);
        if (status == SELFCOL_OK)
            status = one_way_tests(q, 1, b, 0, a, m.vf_ba, m.ef_ba);
        if (status == SELFCOL_OK)
            status = edge_pair_tests(q, a, b, m.ee);
    }
    q->out->stats.primitives_filtered += filtered;
    return status;
}

int selfcol_pairs__run(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                       const selfcol_slot_pair *pairs, size_t count) {
    return run_with(two_lane_masks, q, frames, pairs, count);
}

#if SELFCOL_PAIRS_AVX
// corners_against_box in one pass: lanes corners 0, 1, 2 (and a copy of 0);
// edge slot i's ends are lanes i of xyz[k][0 ..] and xyz[k][1 ..].
SELFCOL_TARGET_AVX static inline void corners_against_box_avx(const selfcol_tri_frame *a,
                                                              const selfcol_tri_frame *b, double d,
                                                              uint32_t *outside_d,
                                                              uint32_t *apart) {
    __m256d out = _mm256_setzero_pd(), sep = _mm256_setzero_pd();
    for (int k = 0; k < 3; ++k) {
        const __m256d lo = _mm256_set1_pd(b->lo[k]), hi = _mm256_set1_pd(b->hi[k]);
        const __m256d lo_d = _mm256_set1_pd(b->lo[k] - d), hi_d = _mm256_set1_pd(b->hi[k] + d);
        const __m256d c = _mm256_loadu_pd(&a->xyz[k][0]), next = _mm256_loadu_pd(&a->xyz[k][1]);
        out = _mm256_or_pd(out, _mm256_or_pd(_mm256_cmp_pd(c, hi_d, _CMP_GT_OQ),
                                             _mm256_cmp_pd(c, lo_d, _CMP_LT_OQ)));
        sep = _mm256_or_pd(sep, _mm256_or_pd(_mm256_and_pd(_mm256_cmp_pd(c, hi, _CMP_GT_OQ),
                                                           _mm256_cmp_pd(next, hi, _CMP_GT_OQ)),
                                             _mm256_and_pd(_mm256_cmp_pd(c, lo, _CMP_LT_OQ),
                                                           _mm256_cmp_pd(next, lo, _CMP_LT_OQ))));
    }
    *outside_d = (uint32_t)_mm256_movemask_pd(out) & 7u;
    *apart = (uint32_t)_mm256_movemask_pd(sep) & 7u;
}

// one_way_masks with the one-pass box test.
SELFCOL_TARGET_AVX static inline void one_way_masks_avx(const selfcol_tri_frame *a,
                                                        const selfcol_tri_frame *b, uint32_t of_a,
                                                        uint32_t shared, double d, uint32_t kinds,
                                                        uint32_t *vf, uint32_t *ef,
                                                        uint64_t *filtered) {
    one_way_masks_with(corners_against_box_avx, a, b, of_a, shared, d, kinds, vf, ef, filtered);
}

// edge_pair_masks with a's three edge boxes in one vector per axis.
SELFCOL_TARGET_AVX static inline uint32_t
edge_pair_masks_avx(const selfcol_tri_frame *a, const selfcol_tri_frame *b, uint32_t of_a,
                    uint32_t of_b, uint32_t matches, double d, uint64_t *filtered) {
    uint32_t far_columns;
    const uint32_t eligible =
        edge_pairs_eligible(a, b, of_a, of_b, matches, &far_columns, filtered);
    if (eligible == 0)
        return 0;
    const __m256d dd = _mm256_set1_pd(d);
    __m256d a_lo_d[3], a_hi[3];
    double blo[3][4], bhi[3][4]; // b's slot j on axis k: [k][j] (lo less d)
    for (int k = 0; k < 3; ++k) {
        const __m256d p = _mm256_loadu_pd(&a->xyz[k][0]), q = _mm256_loadu_pd(&a->xyz[k][1]);
        a_lo_d[k] = _mm256_sub_pd(_mm256_min_pd(p, q), dd);
        a_hi[k] = _mm256_max_pd(p, q);
        const __m256d r = _mm256_loadu_pd(&b->xyz[k][0]), t = _mm256_loadu_pd(&b->xyz[k][1]);
        _mm256_storeu_pd(blo[k], _mm256_sub_pd(_mm256_min_pd(r, t), dd));
        _mm256_storeu_pd(bhi[k], _mm256_max_pd(r, t));
    }
    uint32_t apart = 0;
    for (int j = 0; j < 3; ++j) {
        __m256d x = _mm256_setzero_pd();
        for (int k = 0; k < 3; ++k) {
            const __m256d lo = _mm256_set1_pd(blo[k][j]), hi = _mm256_set1_pd(bhi[k][j]);
            x = _mm256_or_pd(x, _mm256_or_pd(_mm256_cmp_pd(a_lo_d[k], hi, _CMP_GT_OQ),
                                             _mm256_cmp_pd(lo, a_hi[k], _CMP_GT_OQ)));
        }
        const uint32_t m = (uint32_t)_mm256_movemask_pd(x);
        apart |= ((m & 1u) << j) | (((m >> 1) & 1u) << (3 + j)) | (((m >> 2) & 1u) << (6 + j));
    }
    const uint32_t tested = eligible & ~far_columns & ~apart;
    *filtered += bit_count(eligible & ~tested);
    return tested;
}

SELFCOL_TARGET_AVX static inline uint32_t four_lane_masks(const selfcol_tri_frame *a,
                                                          const selfcol_tri_frame *b, uint32_t of_a,
                                                          uint32_t of_b, uint32_t self_mask,
                                                          double d, uint32_t kinds, pair_masks *m,
                                                          uint64_t *filtered) {
    const uint32_t matches = corner_matches(a, b, self_mask);
    uint32_t shared_a, shared_b;
    shared_corners(matches, &shared_a, &shared_b);
    one_way_masks_avx(a, b, of_a, shared_a, d, kinds, &m->vf_ab, &m->ef_ab, filtered);
    one_way_masks_avx(b, a, of_b, shared_b, d, kinds, &m->vf_ba, &m->ef_ba, filtered);
    m->ee =
        kinds & SELFCOL_KIND_EE ? edge_pair_masks_avx(a, b, of_a, of_b, matches, d, filtered) : 0;
    // The tests that follow run two-lane (legacy SSE) code: leave no upper
    // lane dirty (see the four-lane paths' comment).
    _mm256_zeroupper();
    return m->vf_ab | m->ef_ab | m->vf_ba | m->ef_ba | m->ee;
}

SELFCOL_TARGET_AVX int selfcol_pairs__run_avx(selfcol_query *q,
                                              const selfcol_tri_frame *const frames[2],
                                              const selfcol_slot_pair *pairs, size_t count) {
    return run_with(four_lane_masks, q, frames, pairs, count);
}
#else
int selfcol_pairs__run_avx(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                           const selfcol_slot_pair *pairs, size_t count) {
    return selfcol_pairs__run(q, frames, pairs, count);
}
#endif
#else
int selfcol_pairs__run(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                       const selfcol_slot_pair *pairs, size_t count) {
    return selfcol_pairs__run_scalar(q, frames, pairs, count);
}

int selfcol_pairs__run_avx(selfcol_query *q, const selfcol_tri_frame *const frames[2],
                           const selfcol_slot_pair *pairs, size_t count) {
    return selfcol_pairs__run_scalar(q, frames, pairs, count);
}
#endif
