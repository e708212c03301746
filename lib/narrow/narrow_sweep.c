// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Continuous narrow phase for linearly moving primitives: an inclusion-based
// root finder after Tight-Inclusion (Wang, Ferguson, Schneider, Jiang, Attene,
// Panozzo 2021, "A Large-scale Benchmark and an Inclusion-based Algorithm for
// Continuous Collision Detection", ACM TOG 40(5), sections 4 and 5), written
// from the paper. Guarantees and constants: narrow_sweep.h.
//
// The function. Every point moves as x(t) = x0 + t (x1 - x0). With parameters
// (t, u, v):
//   VF: F(t,u,v) = p(t) - a(t) - u (b(t) - a(t)) - v (c(t) - a(t)),
//       domain t, u, v in [0, 1], u + v <= 1 (the closed triangle);
//   EE: F(t,u,v) = a(t) + u (b(t) - a(t)) - c(t) - v (d(t) - c(t)),
//       domain [0, 1]^3 (the two closed segments).
// The primitives come within Euclidean distance delta at time t exactly when
// |F(t,u,v)| <= delta for some (u, v) of the domain, which implies
// |F_i| <= delta for each coordinate i.
//
// Inclusion. Each F_i is a polynomial of degree at most 1 in each of t, u, v
// separately (monomials 1, t, u, v, tu, tv). On a box B = prod_k [lo_k, hi_k],
// write each parameter as lo_k + l_k (hi_k - lo_k), l_k in [0, 1]; then
// F(t,u,v) = sum over the 8 corners c of w_c F(c), with the trilinear weights
// w_c = prod_k (l_k or 1 - l_k) >= 0, sum w_c = 1. So F(B) lies in the convex
// hull of the 8 corner values, and F_i(B) in [min_c F_i(c), max_c F_i(c)].
// A box where, for some i, that interval misses [-delta, delta] holds no time
// within delta and is discarded.
//
// Floating-point filter (cf. the paper's section 5.1, derived anew for the
// evaluation below). Binary64, round to nearest, u = 2^-53, FLT_EVAL_METHOD 0
// (SSE2 and every 64-bit target); fl(a op b) = (a op b)(1 + theta), |theta|
// <= u, barring underflow and overflow (below). Per coordinate i, let M be the
// largest |x_i| over the 8 input points; t, u, v are exact doubles in [0, 1]
// (box bounds are multiples of 2^-level, level <= MAX_LEVEL = 50 < 53, so
// exactly representable). Rule: if a and b are computed with errors alpha and
// beta, and the exact |a +- b| <= m, then fl(a +- b) is within
// (1 + u)(alpha + beta) + u m of the exact result; for an exact s in [0, 1]
// and |b| <= m, fl(s b) is within (1 + u) beta + u m of s b. To first order:
//   1. d = fl(x1 - x0), |x1 - x0| <= 2M:                  2 M u (once per query)
//   2. fl(t d), |t (x1 - x0)| <= 2M:                       2 + 2 = 4 M u
//   3. x(t) = fl(x0 + t d), |x(t)| <= M:                   4 + 1 = 5 M u
//   VF, q = fl(p - a), e1 = fl(b - a), e2 = fl(c - a) (all <= 2M):
//   4. q, e1, e2:                                          5 + 5 + 2 = 12 M u
//   5. fl(u e1), fl(v e2) (<= 2M):                         12 + 2 = 14 M u
//   6. r = fl(q - u e1) (<= 4M):                           12 + 14 + 4 = 30 M u
//   7. F = fl(r - v e2) (<= 6M):                           30 + 14 + 6 = 50 M u
//   EE, e1 = fl(b - a), e2 = fl(d - c):
//   4. e1, e2 (<= 2M):                                     12 M u
//   5. fl(u e1), fl(v e2) (<= 2M):                         14 M u
//   6. g = fl(a + u e1), h = fl(c + v e2) (<= 3M):         5 + 14 + 3 = 22 M u
//   7. F = fl(g - h) (<= 6M):                              22 + 22 + 6 = 50 M u
// Seven levels of (1 + u) factors multiply the first-order sum by less than
// (1 + 8u), so |F^_i(c) - F_i(c)| <= 50 (1 + 8u) M u < 51 M u. We take
//   eps_i = 2^-47 M + DBL_MIN   (2^-47 = 64 u),
// exact to compute (a power-of-two scaling; for M < 2^-975 it may round, by
// less than DBL_MIN). A contracted multiply-add (FMA) rounds once where the
// steps above round twice: its error is within the same bound. Underflow: a
// product may lose up to 2^-1075 absolutely (sums that underflow are exact),
// six products feed one coordinate, each propagated with a factor below 2:
// under 2^-1070, covered by DBL_MIN. Overflow: every intermediate is at most
// 12M (widths included), finite when M <= DBL_MAX / 16; beyond that, or for
// non-finite input, the answer is a conservative 1 (INVALID).
//
// A box is discarded when, for some i, min_c F^_i(c) > E_i or
// max_c F^_i(c) < -E_i, with E_i = fl(fl(eps_i + delta) (1 + 2^-50)) >=
// eps_i + delta (the sum may round down by a factor (1 - u), the product by
// another, and (1 - u)^2 (1 + 8u) > 1). Sound: a point of the box with
// |F_i| <= delta gives min_c F_i(c) <= delta, so min_c F^_i(c) <= delta +
// eps_i <= E_i (and symmetrically).
//
// Before the search, at delta = 0: the never-coplanar test (a cubic's
// Bernstein signs), then the separation filter piece by piece (eighths of
// the step, halved where needed); either proves the pair never touches
// (answer 0). Both are described and proved further down.
//
// Search. best = the least t_lo of a box accepted so far (none at first). A
// box taken for examination is
//   - dropped when t_lo >= best (its times cannot come before best), when
//     the filter discards it, or (delta = 0) when its times hold no moment
//     at which the four points are coplanar (times_never_coplanar());
//   - accepted when its whole inclusion lies within tolerance: for every
//     coordinate, [min_c F^_i, max_c F^_i] within [-(E_i + tau_i), E_i +
//     tau_i] (narrow_sweep.h; this subsumes Tight-Inclusion's "width below
//     tolerance" and its "inclusion inside the tolerance box"): best = t_lo.
//     Every point of the box, notably its corner (t_lo, u_lo, v_lo), which
//     lies in the domain, has |F_i| <= delta + tau_i + 2 eps_i: the
//     false-positive bound of narrow_sweep.h;
//   - else split in two: along t while t_hi > best (the box straddles best,
//     so its later half drops out), else along the parameter whose corner
//     values vary most (the largest |F^(hi) - F^(lo)| over the 4 box edges
//     along it and the 3 coordinates: F is linear along each edge, so that is
//     what halving it shrinks; a still pair never splits t and reports
//     t_lo = 0). VF children with u_lo + v_lo > 1 lie outside the triangle
//     and are dropped.
// Order: best-first, the least t_lo first (ties: the deeper box), from a
// binary heap on a stack array of HEAP_CAPACITY boxes; the first box accepted
// there ends the search, as nothing pending starts earlier. When the heap is
// full, the box taken (the least t_lo) is settled depth-first instead, on a
// second stack array (a split pushes two boxes for the one taken, one level
// deeper in one parameter: at most 3 MAX_LEVEL + 1 pending), its earlier
// half first (for u or v: the half whose earlier face looks closer to a
// contact, by face_gaps()), pruned at best; then the next heap box. At the end
// the answer is 1 with toi = best, or 0 when nothing was accepted.
// toi <= every time within delta: such a time t_r < best would lie in a chain
// of boxes, each containing it, never discarded, and with t_lo <= t_r < best
// when taken (best only decreases), so never dropped; the last of them was
// accepted, setting best <= t_r.
// Why both orders: best-first goes straight to the earliest contact when the
// contact set is small (a point), where depth-first can wander along a
// contact curve, improving best by small steps. But when the contact set is
// a segment of (u, v) at one time (a vertex sweeping through a collapsed
// triangle, collinear edges), best-first examines every box along the
// segment at each t resolution before accepting any; depth-first accepts one
// soon, and with the straddle rule the other boxes there then only need
// splitting in t, each halving discarding its earlier half.
// Budget: when MAX_CHECKS boxes were examined, the answer is 1 with toi = the
// least t_lo still pending (or best when less), still a lower bound
// (BUDGET); a box that cannot be split (every parameter at MAX_LEVEL) is
// accepted as if within tolerance, but reported as BUDGET.

#include "narrow/narrow_sweep.h"

#include "base/predicates.h"
#include "base/vec3.h"
#include "narrow/narrow.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

// Box bounds are multiples of 2^-level: exact doubles while level < 53.
#define MAX_LEVEL 50
// Boxes pending in the best-first phase at most (the heap array).
#define HEAP_CAPACITY 1024

enum { KIND_VF, KIND_EE };

// 2^-k for 0 <= k <= 1022, exactly (a normal double: its exponent field is
// 1023 - k, its fraction 0): what ldexp(1.0, -k) returns, without the call,
// which with its checks took 4 % of the fast-compression ribbon's steps with
// the Bullet adapter's continuous option (perf, benchmarks.md).
static inline double power_of_half(int k) {
    const uint64_t bits = (uint64_t)(1023 - k) << 52;
    double x;
    memcpy(&x, &bits, sizeof x);
    return x;
}

// One box of parameters (t, u, v): [lo_k, lo_k + 2^-level_k], with its
// heap key (box_key).
typedef struct sweep_box {
    double lo[3];
    int level[3];
    int t_checked; // 1: its times passed times_never_coplanar() (u, v splits keep them)
    uint64_t key;
} sweep_box;

// The stack budget of narrow_sweep.h counts boxes of at most 48 bytes.
typedef char sweep_box_fits_the_stack_budget[sizeof(sweep_box) <= 48 ? 1 : -1];

typedef struct sweep_query {
    int kind;
    double x0[4][3];       // VF: p, a, b, c; EE: a, b, c, d (at t = 0)
    double d[4][3];        // x1 - x0 (step 1 of the derivation)
    double threshold[3];   // E_i
    double accept[3];      // E_i + tau_i
    double coplanar_slack; // > 0: boxes' times checked for coplanarity (delta 0);
                           // the piece ends' rounding, 2^-40 M^3
    double coplanar_band;  // 3.5 max_i accept_i: times_never_coplanar's band per |X| |Y|
    double length_error;   // 2^-45 M: the piece ends' rounding in |X| and |Y|
} sweep_query;

// Heap order: the least t_lo first; at equal t_lo the deeper box (levels
// summed). As one integer: t_lo is a multiple of 2^-level_t < 1 with level_t
// <= MAX_LEVEL = 50, so t_lo 2^50 is an exact integer below 2^50, and the
// summed levels are at most 3 MAX_LEVEL < 256; key = t_lo 2^50 * 256 + (255
// - levels) orders boxes exactly as that rule does. The heap compares keys
// once per level of a sift (two doubles and two sums of three levels
// before: 7 % of the fast-compression ribbon's continuous steps, perf).
static uint64_t box_key(const sweep_box *box) {
    const int levels = box->level[0] + box->level[1] + box->level[2];
    return (uint64_t)(box->lo[0] * 0x1p50) << 8 | (uint64_t)(255 - levels);
}

static int box_before(const sweep_box *x, const sweep_box *y) {
    return x->key < y->key;
}

static void heap_push(sweep_box *heap, int *n, const sweep_box *box) {
    int i = (*n)++;
    while (i > 0) {
        int parent = (i - 1) / 2;
        if (!box_before(box, &heap[parent]))
            break;
        heap[i] = heap[parent];
        i = parent;
    }
    heap[i] = *box;
}

static sweep_box heap_pop(sweep_box *heap, int *n) {
    sweep_box top = heap[0];
    sweep_box last = heap[--(*n)];
    int i = 0;
    for (;;) {
        int child = 2 * i + 1;
        if (child >= *n)
            break;
        if (child + 1 < *n && box_before(&heap[child + 1], &heap[child]))
            ++child;
        if (!box_before(&heap[child], &last))
            break;
        heap[i] = heap[child];
        i = child;
    }
    if (*n > 0)
        heap[i] = last;
    return top;
}

// The 8 corner values F^(c) of a box (f[t][u][v][coordinate]), as
// per-coordinate ranges [fmin, fmax], and the variation of F^ along each
// parameter (var[k]).
static void evaluate(const sweep_query *q, const sweep_box *box, double f[2][2][2][3],
                     double fmin[3], double fmax[3], double var[3]) {
    double w[3];
    for (int k = 0; k < 3; ++k)
        w[k] = power_of_half(box->level[k]);
    const double uu[2] = {box->lo[1], box->lo[1] + w[1]};
    const double vv[2] = {box->lo[2], box->lo[2] + w[2]};
    for (int it = 0; it < 2; ++it) {
        const double t = it ? box->lo[0] + w[0] : box->lo[0];
        for (int i = 0; i < 3; ++i) {
            double x[4];
            for (int k = 0; k < 4; ++k)
                x[k] = q->x0[k][i] + t * q->d[k][i]; // steps 2 and 3
            if (q->kind == KIND_VF) {
                const double qv = x[0] - x[1], e1 = x[2] - x[1], e2 = x[3] - x[1];
                for (int iu = 0; iu < 2; ++iu) {
                    const double r = qv - uu[iu] * e1;
                    for (int iv = 0; iv < 2; ++iv)
                        f[it][iu][iv][i] = r - vv[iv] * e2;
                }
            } else {
                const double e1 = x[1] - x[0], e2 = x[3] - x[2];
                const double g[2] = {x[0] + uu[0] * e1, x[0] + uu[1] * e1};
                const double h[2] = {x[2] + vv[0] * e2, x[2] + vv[1] * e2};
                for (int iu = 0; iu < 2; ++iu)
                    for (int iv = 0; iv < 2; ++iv)
                        f[it][iu][iv][i] = g[iu] - h[iv];
            }
        }
    }
    for (int i = 0; i < 3; ++i) {
        fmin[i] = fmax[i] = f[0][0][0][i];
        var[i] = 0.0;
    }
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int i = 0; i < 3; ++i) {
                const double ft = fabs(f[1][a][b][i] - f[0][a][b][i]);
                const double fu = fabs(f[a][1][b][i] - f[a][0][b][i]);
                const double fv = fabs(f[a][b][1][i] - f[a][b][0][i]);
                var[0] = ft > var[0] ? ft : var[0];
                var[1] = fu > var[1] ? fu : var[1];
                var[2] = fv > var[2] ? fv : var[2];
                for (int c = 0; c < 2; ++c) {
                    const double y = f[a][b][c][i];
                    fmin[i] = y < fmin[i] ? y : fmin[i];
                    fmax[i] = y > fmax[i] ? y : fmax[i];
                }
            }
}

// How far the earlier face (t = t_lo) of each half of a box split along u
// (k = 1) or v (k = 2) is from meeting the threshold box: per half, the sum
// over the coordinates of the gap between [min, max] of its 4 corner values
// and [-E_i, E_i] (gap[0]: the lower half, gap[1]: the upper). F is linear
// along the split parameter, so the new corners are the averages of the old
// ones (up to rounding: this only orders the search, soundness does not
// depend on it). Along the other parameter (index j), the face's corners are
// the old lower ends y[0][j], the midpoints y[1][j] (shared by the halves)
// and the old upper ends y[2][j]; the lower half holds the first two, the
// upper the last two. Both halves at once, so each midpoint is computed once.
static void face_gaps(const sweep_query *q, double f[2][2][2][3], int k, double gap[2]) {
    gap[0] = gap[1] = 0.0;
    for (int i = 0; i < 3; ++i) {
        double y[3][2];
        for (int j = 0; j < 2; ++j) {
            y[0][j] = k == 1 ? f[0][0][j][i] : f[0][j][0][i];
            y[2][j] = k == 1 ? f[0][1][j][i] : f[0][j][1][i];
            y[1][j] = 0.5 * (y[0][j] + y[2][j]);
        }
        for (int half = 0; half < 2; ++half) {
            const double a = y[half][0], b = y[half][1], c = y[half + 1][0], d = y[half + 1][1];
            const double ab_lo = a < b ? a : b, cd_lo = c < d ? c : d;
            const double ab_hi = a > b ? a : b, cd_hi = c > d ? c : d;
            const double lo = ab_lo < cd_lo ? ab_lo : cd_lo, hi = ab_hi > cd_hi ? ab_hi : cd_hi;
            if (lo > q->threshold[i])
                gap[half] += lo - q->threshold[i];
            else if (hi < -q->threshold[i])
                gap[half] += -q->threshold[i] - hi;
        }
    }
}

// State shared by the two search orders.
typedef struct sweep_search {
    const sweep_query *q;
    double best;       // the least t_lo of an accepted box; t_max before
    int found;         // best comes from an accepted box
    int best_forced;   // best comes from a box that could not be split
    long checks;       // boxes evaluated
    int max_depth;     // deepest box evaluated (levels summed)
    double budget_toi; // when the budget runs out: the least t_lo undecided
} sweep_search;

static int finish(int answer, double t, int outcome, const sweep_search *st, double *toi,
                  selfcol_narrow_sweep_info *info) {
    if (toi != NULL)
        *toi = t;
    if (info != NULL) {
        info->outcome = outcome;
        info->checks = st->checks;
        info->max_depth = st->max_depth;
    }
    return answer;
}

static int times_never_coplanar(const sweep_query *q, const sweep_box *box);

// Evaluates one box (box.lo[0] < best). Returns -1 when it is accepted
// (*forced: because it could not be split), else the number of children
// (0: discarded), children[0] to be taken first.
static int examine(sweep_search *st, const sweep_box *box, sweep_box children[2], int *forced) {
    const sweep_query *q = st->q;
    double f[2][2][2][3], fmin[3], fmax[3], var[3];
    evaluate(q, box, f, fmin, fmax, var);
    ++st->checks;
    const int depth = box->level[0] + box->level[1] + box->level[2];
    st->max_depth = depth > st->max_depth ? depth : st->max_depth;
    int small = 1;
    for (int i = 0; i < 3; ++i) {
        if (fmin[i] > q->threshold[i] || fmax[i] < -q->threshold[i])
            return 0; // discarded
        if (!(fmin[i] >= -q->accept[i] && fmax[i] <= q->accept[i]))
            small = 0;
    }
    int t_checked = box->t_checked;
    if (!t_checked && q->coplanar_slack > 0.0) {
        if (times_never_coplanar(q, box))
            return 0;
        t_checked = 1;
    }
    *forced = 0;
    if (small)
        return -1;
    // The parameter to split: t while the box straddles the best time (its
    // later half then drops out), else the one that varies most.
    int split = -1;
    const double t_hi = box->lo[0] + power_of_half(box->level[0]);
    if (box->level[0] < MAX_LEVEL && t_hi > st->best)
        split = 0;
    else
        for (int k = 0; k < 3; ++k)
            if (box->level[k] < MAX_LEVEL && (split < 0 || var[k] > var[split]))
                split = k;
    if (split < 0) {
        *forced = 1; // too deep to split
        return -1;
    }
    // The half to take first: the earlier one for t; for u or v the one
    // whose earlier face looks closer to a contact.
    int first_upper = 0;
    if (split != 0) {
        double gap[2];
        face_gaps(q, f, split, gap);
        first_upper = gap[1] < gap[0];
    }
    sweep_box child = *box;
    child.t_checked = split == 0 ? 0 : t_checked;
    child.level[split] = box->level[split] + 1;
    const double mid = box->lo[split] + power_of_half(child.level[split]);
    int m = 0;
    for (int pass = 0; pass < 2; ++pass) {
        const int upper = pass == 0 ? first_upper : !first_upper;
        child.lo[split] = upper ? mid : box->lo[split];
        if (!(q->kind == KIND_VF && child.lo[1] + child.lo[2] > 1.0)) { // u_lo + v_lo is exact
            child.key = box_key(&child);
            children[m++] = child;
        }
    }
    return m;
}

// Settles one box depth-first, pruned at best, on a stack: a split pushes two
// boxes for the one taken, one level deeper in one parameter, so at most
// 3 MAX_LEVEL + 1 are pending. Returns 0 when the budget runs out
// (st->budget_toi: the least t_lo undecided, here or in the heap's n boxes).
static int depth_first(sweep_search *st, const sweep_box *start, const sweep_box *heap, int n) {
    sweep_box stack[3 * MAX_LEVEL + 2];
    int top = 0;
    stack[top++] = *start;
    while (top > 0) {
        const sweep_box box = stack[--top];
        if (box.lo[0] >= st->best)
            continue; // cannot improve on the time found
        if (st->checks >= SELFCOL_NARROW_SWEEP_MAX_CHECKS) {
            double t = box.lo[0] < st->best ? box.lo[0] : st->best;
            for (int k = 0; k < top; ++k)
                t = stack[k].lo[0] < t ? stack[k].lo[0] : t;
            if (n > 0 && heap[0].lo[0] < t)
                t = heap[0].lo[0];
            st->budget_toi = t;
            return 0;
        }
        sweep_box children[2];
        int forced = 0;
        const int m = examine(st, &box, children, &forced);
        if (m < 0) {
            st->best = box.lo[0];
            st->found = 1;
            st->best_forced = forced;
            continue;
        }
        for (int k = m - 1; k >= 0; --k)
            stack[top++] = children[k];
    }
    return 1;
}

// The query's start, displacements and per-coordinate thresholds (E_i and
// E_i + tau_i, the derivation above). Returns 0 for non-finite or huge
// coordinates (the conservative answer 1, INVALID).
static int prepare(sweep_query *q, int kind, const double *const start[4],
                   const double *const end[4], double delta, double tolerance) {
    q->kind = kind;
    double extent = 0.0, mall = 0.0;
    for (int i = 0; i < 3; ++i) {
        double m = 0.0, lo = HUGE_VAL, hi = -HUGE_VAL;
        for (int k = 0; k < 4; ++k) {
            const double x[2] = {start[k][i], end[k][i]};
            for (int s = 0; s < 2; ++s) {
                // !(|x| <= bound) also catches NaN.
                if (!(fabs(x[s]) <= DBL_MAX / 16.0))
                    return 0;
                m = fabs(x[s]) > m ? fabs(x[s]) : m;
                lo = x[s] < lo ? x[s] : lo;
                hi = x[s] > hi ? x[s] : hi;
            }
            q->x0[k][i] = start[k][i];
            q->d[k][i] = end[k][i] - start[k][i]; // step 1
        }
        mall = m > mall ? m : mall;
        const double eps = ldexp(m, -47) + DBL_MIN;
        q->threshold[i] = (eps + delta) * (1.0 + ldexp(1.0, -50));
        q->accept[i] = 2.0 * eps; // tau_i: raised to tau below
        extent = hi - lo > extent ? hi - lo : extent;
    }
    const double tau = tolerance * extent;
    double accept_max = 0.0;
    for (int i = 0; i < 3; ++i) {
        q->accept[i] = q->threshold[i] + (tau > q->accept[i] ? tau : q->accept[i]);
        accept_max = q->accept[i] > accept_max ? q->accept[i] : accept_max;
    }
    q->coplanar_slack = q->coplanar_band = q->length_error = 0.0;
    if (delta == 0.0 && mall >= 0x1p-250 && mall <= 0x1p300) {
        q->coplanar_slack = 0x1p-40 * mall * mall * mall;
        q->coplanar_band = 3.5 * accept_max;
        q->length_error = 0x1p-45 * mall;
    }
    return 1;
}

// ---------------------------------------------------------------------------
// Never coplanar (delta = 0 only): two primitives that touch at time t have
// their four points coplanar then. With X, Y, Z the differences
//   VF: X = b - a, Y = c - a, Z = p - a;   EE: X = b - a, Y = d - c, Z = c - a
// (the points as start[] lists them), coplanarity is f(t) = (X x Y) . Z = 0,
// and f is a cubic in t: each difference moves linearly, and the triple
// product is linear in each. Its Bernstein coefficients on [0, 1] are
//   c0 = f(X0, Y0, Z0),  c3 = f(X1, Y1, Z1),
//   3 c1 = f(X1, Y0, Z0) + f(X0, Y1, Z0) + f(X0, Y0, Z1),
//   3 c2 = f(X0, Y1, Z1) + f(X1, Y0, Z1) + f(X1, Y1, Z0),
// (index 0: start, 1: end), and f(t) = sum_k c_k B_k(t) with B_k >= 0
// summing to 1 (the Bernstein basis of degree 3): when the four have one
// strict sign, f has no root in [0, 1], and the primitives never touch.
// Rounding: each triple product of rounded differences is computed as
// Shewchuk's orient3d computes its determinant (one rounded subtraction per
// entry, then the products), so its error is within (7 + 56 u) u of its
// permanent (the same expression on absolute values; Shewchuk 1997,
// "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates", o3derrboundA); summing three adds at most 2.2 u of their
// permanents' sum. The test asks each coefficient to exceed 2e-15 times its
// permanents' sum (more than the 1.03e-15 that SELFCOL_PREDICATES_ORIENT3D_BOUND
// plus 2.2 u needs), and gives no answer where a permanent is below 2^-800
// (products could underflow) or not finite. It spares the root search the
// pairs that never become coplanar: on the continuous-collision benchmark
// 5,880 of 7,279 queries, on the real rod-twist step 43 % of ALL's root
// boxes, on cloth-ball 5 % (benchmarks.md, continuous queries).
#define SELFCOL_COPLANAR_ERROR 2e-15

// (X x Y) . Z = det[X; Y; Z] = det of the matrix with columns X, Y, Z, with
// its permanent: selfcol_predicates__det3 on the rows (X_i, Y_i, Z_i).
static double triple(const double x[3], const double y[3], const double z[3], double *permanent) {
    const double u[3] = {x[0], y[0], z[0]}, v[3] = {x[1], y[1], z[1]}, w[3] = {x[2], y[2], z[2]};
    return selfcol_predicates__det3(u, v, w, permanent);
}

static int cubic_one_sign(int kind, const double *const start[4], const double *const end[4],
                          double slack, double band, double length_error) {
    double x[2][3], y[2][3], z[2][3];
    for (int s = 0; s < 2; ++s) {
        const double *const *q = s == 0 ? start : end;
        for (int i = 0; i < 3; ++i) {
            if (kind == KIND_VF) {
                x[s][i] = q[2][i] - q[1][i];
                y[s][i] = q[3][i] - q[1][i];
                z[s][i] = q[0][i] - q[1][i];
            } else {
                x[s][i] = q[1][i] - q[0][i];
                y[s][i] = q[3][i] - q[2][i];
                z[s][i] = q[2][i] - q[0][i];
            }
        }
    }
    if (band > 0.0) {
        double xx = 0.0, yy = 0.0;
        for (int e = 0; e < 2; ++e) {
            const double lx = vec3_dot(x[e], x[e]), ly = vec3_dot(y[e], y[e]);
            xx = lx > xx ? lx : xx;
            yy = ly > yy ? ly : yy;
        }
        slack += band * (sqrt(xx) + length_error) * (sqrt(yy) + length_error);
    }
    double c[4], permanent[4], p1, p2, p3;
    c[0] = triple(x[0], y[0], z[0], &permanent[0]);
    c[1] = triple(x[1], y[0], z[0], &p1) + triple(x[0], y[1], z[0], &p2) +
           triple(x[0], y[0], z[1], &p3);
    permanent[1] = p1 + p2 + p3;
    c[2] = triple(x[0], y[1], z[1], &p1) + triple(x[1], y[0], z[1], &p2) +
           triple(x[1], y[1], z[0], &p3);
    permanent[2] = p1 + p2 + p3;
    c[3] = triple(x[1], y[1], z[1], &permanent[3]);
    int positive = 1, negative = 1;
    for (int k = 0; k < 4; ++k) {
        // !(p >= min && p <= max) also catches NaN.
        if (!(permanent[k] >= 0x1p-800 && permanent[k] <= DBL_MAX))
            return 0;
        const double bound =
            SELFCOL_COPLANAR_ERROR * permanent[k] + (k == 1 || k == 2 ? 3.0 : 1.0) * slack;
        positive = positive && c[k] > bound;
        negative = negative && c[k] < -bound;
    }
    return positive || negative;
}

static int never_coplanar(int kind, const double *const start[4], const double *const end[4]) {
    return cubic_one_sign(kind, start, end, 0.0, 0.0, 0.0);
}

static void points_at(const sweep_query *q, double t, double x[4][3]);

// Coplanar moments box by box (delta = 0). The search accepts a box only
// when every point of it has |F_i| <= accept_i + eps_i (the computed corner
// values within accept_i, the exact ones within eps_i more, F trilinear), so
// |F| <= 2 sqrt(3) max_i accept_i there. The coplanarity f = (X x Y) . Z is
// (X x Y) . F up to sign (VF: F = Z - u X - v Y; EE: F = u X - v Y - Z), so
// at such a point |f| <= |X| |Y| |F|, and on [t_lo, t_hi] |X| and |Y| are at
// most their larger values at the two ends (they move linearly). A box whose
// times keep |f| above band = 3.5 max accept_i (|X|max + err) (|Y|max + err)
// therefore holds no point the search could accept, nor does any box inside
// it: it is discarded, and the hits are those of the search without it (only
// a budget-limited search can end differently, having examined fewer boxes).
// Shown by the Bernstein coefficients of f on the piece [t_lo, t_hi] (every
// point still moves linearly, from x(t_lo) to x(t_hi)) all beyond the band
// (3 band for the middle two, computed as 3 c1 and 3 c2), plus their
// rounding: the relative 2e-15 above, and the piece ends' own error. They
// are computed, fl(x0 + t d), within 5 M u of the exact points (steps 1 to 3
// of the derivation at the top, t exact; M the largest |coordinate| of the 8
// input points), so X, Y, Z are within 10 M u of the exact differences (err
// = 2^-45 M >= 10 sqrt(3) M u bounds that in length), every coordinate at
// most 2 M (1 + 5u); a triple product, six products of three coordinates,
// moves by at most 720 M^3 u to first order, a middle coefficient by 2,160
// M^3 u, under the slack 2^-40 M^3 = 8,192 M^3 u. Set only for 2^-250 <= M
// <= 2^300 (no underflow or overflow of M^3). Only a box made by a split
// along t is tested: a u or v split keeps its parent's times (t_checked).
// Measured (2026-11-29, ALL, one thread): rod-twist 3036 -> 3037 root boxes
// 29.2 M -> 17.4 M, narrow 2.89 -> 1.97 s; cloth-ball 92 -> 93 74.2 M ->
// 52.8 M, 7.70 -> 6.46 s; the same hits but for budget-limited ones.
static int times_never_coplanar(const sweep_query *q, const sweep_box *box) {
    double lo[4][3], hi[4][3];
    points_at(q, box->lo[0], lo);
    points_at(q, box->lo[0] + power_of_half(box->level[0]), hi);
    const double *const start[4] = {lo[0], lo[1], lo[2], lo[3]};
    const double *const end[4] = {hi[0], hi[1], hi[2], hi[3]};
    return cubic_one_sign(q->kind, start, end, q->coplanar_slack, q->coplanar_band,
                          q->length_error);
}

static int separated_piecewise(const sweep_query *q, const double *const start[4],
                               const double *const end[4], int edge_edge);

// The search, after the filters of delta = 0 (try_pieces: with the pieces;
// may_touch, which tried them already, passes 0).
static int sweep_filtered(int kind, const double *const start[4], const double *const end[4],
                          double delta, double t_max, double tolerance, int try_pieces, double *toi,
                          selfcol_narrow_sweep_info *info) {
    sweep_query q;
    // Boxes starting at or after t_max are never examined: a box holds the
    // times [t_lo, t_hi], so a root at t < t_max lies in a box with t_lo <
    // t_max, which stays. Boxes start below 1, so t_max = 1 drops nothing.
    if (!(t_max <= 1.0))
        t_max = 1.0; // above 1 or NaN
    sweep_search st = {&q, t_max, 0, 0, 0, 0, 0.0};
    if (!(delta >= 0.0))
        delta = 0.0; // negative or NaN
    if (!(tolerance > 0.0 && tolerance <= 1.0))
        tolerance = SELFCOL_NARROW_SWEEP_TOLERANCE; // out of range or NaN
    if (!prepare(&q, kind, start, end, delta, tolerance))
        return finish(1, 0.0, SELFCOL_NARROW_SWEEP_INVALID, &st, toi, info);
    if (delta == 0.0 && never_coplanar(kind, start, end))
        return finish(0, 1.0, SELFCOL_NARROW_SWEEP_NEVER_COPLANAR, &st, toi, info);
    // Apart piece by piece (delta 0; its proof and measurements below, with
    // may_touch's stages): a few separating tests per eighth of the step
    // settle pairs that pass near each other without touching, which the
    // search proves apart only box by box (rod-twist 3036 -> 3037, ALL: root
    // boxes 37.6 M -> 29.2 M, the same hits; benchmarks.md).
    if (delta == 0.0 && try_pieces && separated_piecewise(&q, start, end, kind == KIND_EE))
        return finish(0, 1.0, SELFCOL_NARROW_SWEEP_SEPARATED, &st, toi, info);

    // Best-first while the heap has room.
    sweep_box heap[HEAP_CAPACITY];
    int n = 0;
    // The root box covers [0, 2^-k], the shortest such interval holding [0,
    // t_max): the halves it would otherwise split off first start at or
    // after t_max and would be dropped unexamined. (A search of the earliest
    // time over many pairs, with t_max already small, then starts at the
    // times that matter instead of bisecting down to them.)
    int root_level = 0;
    while (root_level < MAX_LEVEL && ldexp(1.0, -(root_level + 1)) >= t_max)
        ++root_level;
    sweep_box root = {{0.0, 0.0, 0.0}, {root_level, 0, 0}, root_level == 0, 0};
    root.key = box_key(&root);
    heap_push(heap, &n, &root);
    while (n > 0) {
        const sweep_box box = heap_pop(heap, &n);
        if (box.lo[0] >= st.best)
            break; // every pending box starts at or after the time found
        if (n + 2 > HEAP_CAPACITY) {
            // Full: settle this box depth-first (it has the least t_lo).
            if (!depth_first(&st, &box, heap, n))
                return finish(1, st.budget_toi, SELFCOL_NARROW_SWEEP_BUDGET, &st, toi, info);
            continue;
        }
        if (st.checks >= SELFCOL_NARROW_SWEEP_MAX_CHECKS)
            return finish(1, box.lo[0], SELFCOL_NARROW_SWEEP_BUDGET, &st, toi, info);
        sweep_box children[2];
        int forced = 0;
        const int m = examine(&st, &box, children, &forced);
        if (m < 0) {
            // Accepted, and no pending box starts earlier.
            st.best = box.lo[0];
            st.found = 1;
            st.best_forced = forced;
            break;
        }
        for (int k = 0; k < m; ++k)
            heap_push(heap, &n, &children[k]);
    }
    if (st.found)
        return finish(1, st.best,
                      st.best_forced ? SELFCOL_NARROW_SWEEP_BUDGET : SELFCOL_NARROW_SWEEP_ACCEPTED,
                      &st, toi, info);
    return finish(0, 1.0, SELFCOL_NARROW_SWEEP_SEPARATED, &st, toi, info);
}

static int sweep(int kind, const double *const start[4], const double *const end[4], double delta,
                 double t_max, double tolerance, double *toi, selfcol_narrow_sweep_info *info) {
    return sweep_filtered(kind, start, end, delta, t_max, tolerance, 1, toi, info);
}

int selfcol_narrow_sweep__vf_info(const double p0[3], const double a0[3], const double b0[3],
                                  const double c0[3], const double p1[3], const double a1[3],
                                  const double b1[3], const double c1[3], double delta, double *toi,
                                  selfcol_narrow_sweep_info *info) {
    const double *const start[4] = {p0, a0, b0, c0};
    const double *const end[4] = {p1, a1, b1, c1};
    return sweep(KIND_VF, start, end, delta, 1.0, SELFCOL_NARROW_SWEEP_TOLERANCE, toi, info);
}

int selfcol_narrow_sweep__ee_info(const double a0[3], const double b0[3], const double c0[3],
                                  const double d0[3], const double a1[3], const double b1[3],
                                  const double c1[3], const double d1[3], double delta, double *toi,
                                  selfcol_narrow_sweep_info *info) {
    const double *const start[4] = {a0, b0, c0, d0};
    const double *const end[4] = {a1, b1, c1, d1};
    return sweep(KIND_EE, start, end, delta, 1.0, SELFCOL_NARROW_SWEEP_TOLERANCE, toi, info);
}

int selfcol_narrow_sweep__vf(const double p0[3], const double a0[3], const double b0[3],
                             const double c0[3], const double p1[3], const double a1[3],
                             const double b1[3], const double c1[3], double delta, double *toi) {
    return selfcol_narrow_sweep__vf_info(p0, a0, b0, c0, p1, a1, b1, c1, delta, toi, NULL);
}

int selfcol_narrow_sweep__ee(const double a0[3], const double b0[3], const double c0[3],
                             const double d0[3], const double a1[3], const double b1[3],
                             const double c1[3], const double d1[3], double delta, double *toi) {
    return selfcol_narrow_sweep__ee_info(a0, b0, c0, d0, a1, b1, c1, d1, delta, toi, NULL);
}

int selfcol_narrow_sweep__vf_before(const double *const start[4], const double *const end[4],
                                    double delta, double t_max, double tolerance, double *toi,
                                    selfcol_narrow_sweep_info *info) {
    return sweep(KIND_VF, start, end, delta, t_max, tolerance, toi, info);
}

int selfcol_narrow_sweep__ee_before(const double *const start[4], const double *const end[4],
                                    double delta, double t_max, double tolerance, double *toi,
                                    selfcol_narrow_sweep_info *info) {
    return sweep(KIND_EE, start, end, delta, t_max, tolerance, toi, info);
}

// ---------------------------------------------------------------------------
// A cheap separation filter: a fixed direction that separates the primitives
// at both ends of the step, the same way round.
//
// Proof. Project on any fixed vector n. A point of primitive A at time t is a
// convex combination (fixed weights) of A's vertices at time t, so its
// projection is at most hi_A(t) = max_k n . a_k(t); each n . a_k(t) is linear
// in t (linear motion), so hi_A is convex; likewise lo_B(t) = min_k n . b_k(t)
// is concave. hi_A - lo_B is then convex, and its maximum over [0, 1] is at
// t = 0 or t = 1. If hi_A - lo_B < -g at both ends, it is below -g for every
// t, and every point of A is then more than g / |n| from every point of B
// along n, hence in space. With g = delta |n| the primitives never come
// within delta. The same holds with the roles swapped (A above B).
//
// Rounding. Each projection fl(n . x) is within gamma_3 sum_i |n_i| |x_i| <=
// 2^-51 |n|_1 M of n . x (Higham, Accuracy and Stability of Numerical
// Algorithms, 2nd ed., section 3.1; gamma_3 = 3u / (1 - 3u) < 2^-51, M the
// largest |coordinate| of the 8 points), plus 3 x 2^-1074 for underflow. The
// computed gap fl(lo_B - hi_A) is within 2^-52 x 2 |n|_1 M (its magnitude is
// at most that) of the difference of the computed projections. So the exact
// gap exceeds the computed one minus |n|_1 M (2 x 2^-51 + 2^-51) < |n|_1 M
// 2^-49. The test asks for computed gap > delta |n|_1 (1 + 2^-48) + |n|_1 M
// 2^-48 + DBL_MIN, with |n|_1 >= |n|_2 computed to within 2u: more than the
// exact requirement delta |n|_2 plus every error above.
// error: the M 2^-48 term (a caller whose points carry rounding errors of
// their own passes more, see separated_piecewise()).
static int separated_along(const double *const start[4], const double *const end[4], int na,
                           const double n[3], double delta, double error) {
    const double norm1 = fabs(n[0]) + fabs(n[1]) + fabs(n[2]);
    if (!(norm1 > 0.0))
        return 0;
    const double slack = delta * norm1 * (1.0 + ldexp(1.0, -48)) + norm1 * error + DBL_MIN;
    int below = 1, above = 1; // A below B (resp. above) by more than the slack at both ends
    for (int end_i = 0; end_i < 2; ++end_i) {
        const double *const *x = end_i == 0 ? start : end;
        double hi_a = -HUGE_VAL, lo_a = HUGE_VAL, hi_b = -HUGE_VAL, lo_b = HUGE_VAL;
        for (int k = 0; k < 4; ++k) {
            const double p = n[0] * x[k][0] + n[1] * x[k][1] + n[2] * x[k][2];
            if (k < na) {
                hi_a = p > hi_a ? p : hi_a;
                lo_a = p < lo_a ? p : lo_a;
            } else {
                hi_b = p > hi_b ? p : hi_b;
                lo_b = p < lo_b ? p : lo_b;
            }
        }
        below = below && lo_b - hi_a > slack;
        above = above && lo_a - hi_b > slack;
    }
    return below || above;
}

// Direction k of the filter: the axes (k = 0, 1, 2), the reference normal
// at either end (k = 3: t = 0, k = 4: t = 1): the triangle's (b - a) x
// (c - a), or the edges' (b - a) x (d - c); then, at either end (k = 5:
// t = 0, k = 6: t = 1), the in-plane normals of that plane, n x e for each
// edge e of the triangle (three directions), or for each of the two edges
// (two). Any fixed vector does for the proof above; the in-plane ones
// separate what the others cannot: primitives of one smooth sheet a ring or
// two apart, which lie nearly in each other's plane (measured on the
// continuous rows before they were added: 70 % of the VF pairs and 54 % of
// the EE pairs no other direction separated on rod-twist 3036 -> 3037, 84 %
// and 61 % on cloth-funnel 227 -> 228; each went to the root finder, at
// 100-170 boxes a search).
#define SEPARATING_DIRECTIONS 7u

static int separated_by(const double *const start[4], const double *const end[4], int edge_edge,
                        unsigned k, double delta, double error) {
    const int na = edge_edge ? 2 : 1;
    if (k < 3) {
        const double n[3] = {k == 0, k == 1, k == 2};
        return separated_along(start, end, na, n, delta, error);
    }
    const double *const *x = k == 3 || k == 5 ? start : end;
    const double *o = edge_edge ? x[0] : x[1];
    const double *p = edge_edge ? x[1] : x[2];
    const double *q0 = edge_edge ? x[2] : x[1];
    const double *q1 = x[3];
    double u[3], w[3], n[3];
    for (int i = 0; i < 3; ++i) {
        u[i] = p[i] - o[i];
        w[i] = q1[i] - q0[i];
    }
    vec3_cross(n, u, w);
    if (k < 5)
        return separated_along(start, end, na, n, delta, error);
    double in_plane[3];
    if (edge_edge) {
        vec3_cross(in_plane, n, u);
        if (separated_along(start, end, na, in_plane, delta, error))
            return 1;
        vec3_cross(in_plane, n, w);
        return separated_along(start, end, na, in_plane, delta, error);
    }
    // The triangle's edges: b - a (u), c - b, a - c (w reversed: the sign of
    // a direction does not matter, the test tries both ways round).
    double v[3];
    for (int i = 0; i < 3; ++i)
        v[i] = x[3][i] - x[2][i];
    const double *const edges[3] = {u, v, w};
    for (int e = 0; e < 3; ++e) {
        vec3_cross(in_plane, n, edges[e]);
        if (separated_along(start, end, na, in_plane, delta, error))
            return 1;
    }
    return 0;
}

int selfcol_narrow_sweep__separated_from(const double *const start[4], const double *const end[4],
                                         int edge_edge, double delta, unsigned *hint) {
    if (!(delta >= 0.0))
        delta = 0.0;
    double m = 0.0;
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) {
            const double a = fabs(start[k][i]), b = fabs(end[k][i]);
            if (!(a <= DBL_MAX / 16.0 && b <= DBL_MAX / 16.0))
                return 0; // non-finite or huge: no claim
            m = a > m ? a : m;
            m = b > m ? b : m;
        }
    if (m > 0x1p200)
        return 0; // the products below could overflow
    const double error = m * ldexp(1.0, -48);
    const unsigned first = *hint < SEPARATING_DIRECTIONS ? *hint : 0;
    if (separated_by(start, end, edge_edge, first, delta, error))
        return 1;
    for (unsigned k = 0; k < SEPARATING_DIRECTIONS; ++k)
        if (k != first && separated_by(start, end, edge_edge, k, delta, error)) {
            *hint = k;
            return 1;
        }
    return 0;
}

int selfcol_narrow_sweep__separated(const double *const start[4], const double *const end[4],
                                    int edge_edge, double delta) {
    unsigned hint = 0;
    return selfcol_narrow_sweep__separated_from(start, end, edge_edge, delta, &hint);
}

// ---------------------------------------------------------------------------
// A yes/no question over the whole step, delta = 0: "may the primitives touch
// at some t in [0, 1]?", for callers that need no time of impact (the contact
// store's crossing test). Four stages, cheapest first:
//
// 1. The separation filter above: 1 there proves they never touch (answer 0).
//
// 2. A witness. The search answers 1 when it accepts a box, which shows a
//    parameter point (t, u, v) of the domain with |F^_i| <= E_i + tau_i, hence
//    |F_i| <= tau_i + 2 eps_i (narrow_sweep.h). Any point of the domain with
//    that property supports the same answer with the same bound, and a
//    primitive pair that passes through itself has one near every crossing:
//    there, the four points are coplanar (the triple product
//      VF: ((b - a) x (c - a)) . (p - a),  EE: ((b - a) x (d - c)) . (c - a),
//    a cubic in t, changes sign) and the closest points lie inside the
//    primitives. So: find the sign changes of the triple product on 8 equal
//    steps of t, bisect each to the precision of a double, take the closest
//    points of the two primitives at that time (narrow.c's closed forms,
//    moved into the closed domain), and evaluate F^ there with the steps of
//    evaluate(): the rounding bound eps_i holds for any doubles t, u, v in
//    [0, 1] (the derivation uses only that they are doubles of [0, 1]), so
//    the test |F^_i| <= E_i + tau_i is the search's own acceptance test at a
//    single point. Only that last test matters for soundness; the root and
//    the closest points only choose where to look.
//    The difference from the search: a pair whose closest approach is below
//    tau (relative 1e-6 of the extent) without touching may get 1 here where
//    the search could prove 0. Both are within the documented false-positive
//    bound, so callers see the guarantee of _before, never a false negative.
//
// 3. The separation filter piece by piece (separated_piecewise() below):
//    pairs whose sign changed without contact, which no one direction holds
//    apart over the whole step.
//
// 4. Otherwise the search itself (delta 0, t_max 1).
//
// Measured on cloth-ball 92 -> 93 (selfcol_store_update_swept, 54,027 sign
// changes, one thread): stage 1 settles 11,850 pairs, stage 2 23,186, stage
// 3 18,861, and 130 reach the search. The search alone spent about 130 us on
// each pair that does cross (bisecting to the tolerance around the earliest
// contact) and 10 us on each it proved apart: 3.44 s for the update, against
// 0.27 s with the stages (1.7 x selfcol_store_update, which does no
// continuous test).

// F^(t, u, v), by the evaluation steps of evaluate() (steps 2 to 7 of the
// derivation above).
static void value_at(const sweep_query *q, double t, double u, double v, double f[3]) {
    for (int i = 0; i < 3; ++i) {
        double x[4];
        for (int k = 0; k < 4; ++k)
            x[k] = q->x0[k][i] + t * q->d[k][i];
        if (q->kind == KIND_VF) {
            const double qv = x[0] - x[1], e1 = x[2] - x[1], e2 = x[3] - x[1];
            f[i] = (qv - u * e1) - v * e2;
        } else {
            const double e1 = x[1] - x[0], e2 = x[3] - x[2];
            f[i] = (x[0] + u * e1) - (x[2] + v * e2);
        }
    }
}

// The four points at time t, fl(x0 + t d): steps 1 to 3 of the derivation,
// within 5 M u of the exact points.
static void points_at(const sweep_query *q, double t, double x[4][3]) {
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i)
            x[k][i] = q->x0[k][i] + t * q->d[k][i];
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The triple product at time t (its sign changes where the points become
// coplanar).
static double coplanarity(const sweep_query *q, double t) {
    double x[4][3], e1[3], e2[3], w[3], n[3];
    points_at(q, t, x);
    const int vf = q->kind == KIND_VF;
    for (int i = 0; i < 3; ++i) {
        e1[i] = vf ? x[2][i] - x[1][i] : x[1][i] - x[0][i];
        e2[i] = vf ? x[3][i] - x[1][i] : x[3][i] - x[2][i];
        w[i] = vf ? x[0][i] - x[1][i] : x[2][i] - x[0][i];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return dot3(n, w);
}

static double clamp01(double x) {
    return x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0; // NaN -> 0
}

// The primitives' closest parameters (u, v) at time t (narrow.c's closed
// forms, plain floating point), as exact doubles of the closed domain.
static void closest_at(const sweep_query *q, double t, double *u_out, double *v_out) {
    double x[4][3];
    points_at(q, t, x);
    selfcol_narrow_result r;
    double u, v;
    if (q->kind == KIND_VF) {
        selfcol_narrow__vf(x[0], x[1], x[2], x[3], &r);
        u = clamp01(r.wb[1]);
        v = clamp01(r.wb[2]);
        // u + v <= 1 exactly: fl((1 - u)(1 - 2^-52)) <= 1 - u for u in
        // [0, 1], as (1 + 2^-53)^2 (1 - 2^-52) < 1.
        const double room = (1.0 - u) * (1.0 - 0x1p-52);
        v = v < room ? v : room;
    } else {
        selfcol_narrow__ee(x[0], x[1], x[2], x[3], &r);
        u = clamp01(r.wa[1]);
        v = clamp01(r.wb[1]);
    }
    *u_out = u;
    *v_out = v;
}

// Whether the closest points at time t are a witness: the acceptance test on
// F^ there.
static int witness_at(const sweep_query *q, double t) {
    double u, v, f[3];
    closest_at(q, t, &u, &v);
    value_at(q, t, u, v, f);
    for (int i = 0; i < 3; ++i)
        if (!(fabs(f[i]) <= q->accept[i]))
            return 0;
    return 1;
}

// Stage 2 above: a witness near a sign change of the triple product.
static int find_witness(const sweep_query *q) {
    enum { STEPS = 8 };
    double t_left = 0.0, f_left = coplanarity(q, 0.0);
    for (int k = 1; k <= STEPS; ++k) {
        const double t_right = (double)k / STEPS;
        const double f_right = coplanarity(q, t_right);
        if (f_left == 0.0 && witness_at(q, t_left))
            return 1;
        if ((f_left < 0.0 && f_right > 0.0) || (f_left > 0.0 && f_right < 0.0)) {
            double lo = t_left, hi = t_right;
            const int rising = f_left < 0.0;
            for (int it = 0; it < 64; ++it) {
                const double mid = 0.5 * (lo + hi);
                if (!(mid > lo && mid < hi))
                    break;
                const double fm = coplanarity(q, mid);
                if ((fm < 0.0) == rising)
                    lo = mid;
                else
                    hi = mid;
            }
            if (witness_at(q, lo) || witness_at(q, hi))
                return 1;
        }
        t_left = t_right;
        f_left = f_right;
    }
    return f_left == 0.0 && witness_at(q, 1.0);
}

// Stage 1 again, piece by piece: the step cut into PIECES equal intervals of
// t, each tested like the whole step (a sign change without contact is often
// a pair that turned past another, such as nearly parallel edges, where no
// one direction holds them apart for the whole step but one does for each
// part of it). On [t_k, t_k+1] every point still moves linearly, from x(t_k)
// to x(t_k+1), so the proof above applies to each piece, and the pieces
// cover [0, 1]. The piece ends are computed, fl(x0 + t d): within 5 M u <
// M 2^-50 of the exact points (steps 1 to 3 of the derivation at the top,
// with t exact), which moves each projection by at most |n|_1 M 2^-50 and
// a gap by twice that; so the slack's M term grows from 2^-48 to 2^-47 >
// 2^-48 + 2^-49. Directions per piece: the axes, the reference normals at its
// two ends, and the vector between the closest points at its middle. A piece
// none of them separates is halved, down to 1/256 of the step; the answer is
// 0 only when every piece was separated.

// One piece [t_lo, t_hi] (exact doubles), its end points lo and hi computed.
static int piece_apart(const sweep_query *q, int edge_edge, double t_lo, double t_hi,
                       double lo[4][3], double hi[4][3], double error) {
    const double *const start[4] = {lo[0], lo[1], lo[2], lo[3]};
    const double *const end[4] = {hi[0], hi[1], hi[2], hi[3]};
    for (unsigned k = 0; k < 5; ++k)
        if (separated_by(start, end, edge_edge, k, 0.0, error))
            return 1;
    double u, v, n[3];
    const double t_mid = 0.5 * (t_lo + t_hi);
    closest_at(q, t_mid, &u, &v);
    value_at(q, t_mid, u, v, n);
    return separated_along(start, end, edge_edge ? 2 : 1, n, 0.0, error);
}

static int separated_piecewise(const sweep_query *q, const double *const start[4],
                               const double *const end[4], int edge_edge) {
    enum { PIECES = 8, MAX_SPLITS = 5 };
    double m = 0.0; // M: the largest |coordinate| of the 8 input points
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) {
            const double a = fabs(start[k][i]), b = fabs(end[k][i]);
            m = a > m ? a : m;
            m = b > m ? b : m;
        }
    if (!(m <= 0x1p200))
        return 0; // the products could overflow (prepare() caught non-finite)
    const double error = m * ldexp(1.0, -47);
    // Pieces pending, latest first: [t, t + 2^-level] (exact doubles).
    double t_stack[MAX_SPLITS + 2];
    int level_stack[MAX_SPLITS + 2];
    for (int piece = 0; piece < PIECES; ++piece) {
        int top = 0;
        t_stack[top] = (double)piece / PIECES;
        level_stack[top++] = 3;
        while (top > 0) {
            --top;
            const double t_lo = t_stack[top], t_hi = t_lo + power_of_half(level_stack[top]);
            double lo[4][3], hi[4][3];
            points_at(q, t_lo, lo);
            points_at(q, t_hi, hi);
            if (piece_apart(q, edge_edge, t_lo, t_hi, lo, hi, error))
                continue;
            if (level_stack[top] >= 3 + MAX_SPLITS)
                return 0;
            const int level = level_stack[top] + 1;
            t_stack[top] = t_lo + power_of_half(level);
            level_stack[top++] = level;
            t_stack[top] = t_lo;
            level_stack[top++] = level;
        }
    }
    return 1;
}

int selfcol_narrow_sweep__may_touch(const double *const start[4], const double *const end[4],
                                    int edge_edge, selfcol_narrow_sweep_info *info) {
    if (selfcol_narrow_sweep__separated(start, end, edge_edge, 0.0)) {
        if (info != NULL)
            *info = (selfcol_narrow_sweep_info){SELFCOL_NARROW_SWEEP_SEPARATED, 0, 0};
        return 0;
    }
    sweep_query q;
    const int valid =
        prepare(&q, edge_edge ? KIND_EE : KIND_VF, start, end, 0.0, SELFCOL_NARROW_SWEEP_TOLERANCE);
    if (valid && find_witness(&q)) {
        if (info != NULL)
            *info = (selfcol_narrow_sweep_info){SELFCOL_NARROW_SWEEP_WITNESS, 0, 0};
        return 1;
    }
    if (valid && separated_piecewise(&q, start, end, edge_edge)) {
        if (info != NULL)
            *info = (selfcol_narrow_sweep_info){SELFCOL_NARROW_SWEEP_SEPARATED, 0, 0};
        return 0;
    }
    return sweep_filtered(edge_edge ? KIND_EE : KIND_VF, start, end, 0.0, 1.0,
                          SELFCOL_NARROW_SWEEP_TOLERANCE, 0, NULL, info);
}
