// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Continuous queries (include/selfcol/sweep.h): argument checks, the broad
// phase (sweep_search.c), the narrow phase over the candidates
// (narrow_sweep.h), and the hits sorted by key.
#include "continuous/sweep.h"

#include "base/alloc.h"
#include "base/core.h"
#include "base/parallel.h"
#include "base/problem.h"
#include "narrow/narrow.h"
#include "narrow/narrow_sweep.h"
#include "query/context.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

int selfcol_sweep_options_init(selfcol_sweep_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    // Versions 1 and 2 were 0.3's layouts (with threads).
    if (version < SELFCOL_SWEEP_OPTIONS_VERSION || version > SELFCOL_SWEEP_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->method = SELFCOL_METHOD_BVH;
    opts->kinds = SELFCOL_KIND_VF | SELFCOL_KIND_EE;
    opts->mode = SELFCOL_SWEEP_ALL;
    opts->separation = 0.0;
    opts->tolerance = SELFCOL_SWEEP_DEFAULT_TOLERANCE;
    return SELFCOL_OK;
}

static void reset_stats(selfcol_sweep *s) {
    memset(&s->stats, 0, sizeof s->stats);
    s->stats.version = SELFCOL_SWEEP_STATS_VERSION;
    s->stats.free_fraction = 1.0;
}

int selfcol_sweep_create(selfcol_sweep **out, const selfcol_allocator *allocator) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    selfcol_allocator al = {NULL, NULL, NULL};
    if (allocator != NULL)
        al = *allocator;
    SELFCOL_CHECK(selfcol_alloc__valid(&al));
    selfcol_sweep *s = selfcol_alloc__raw(&al, sizeof *s);
    if (s == NULL)
        return SELFCOL_ENOMEM;
    memset(s, 0, sizeof *s);
    s->allocator = al;
    selfcol_workspace__init(&s->work, &al);
    reset_stats(s);
    *out = s;
    return SELFCOL_OK;
}

void selfcol_sweep_destroy(selfcol_sweep *sweep) {
    if (sweep == NULL)
        return;
    const selfcol_allocator al = sweep->allocator;
    selfcol_alloc__free_array(&al, sweep->hits, sweep->hit_capacity, sizeof *sweep->hits);
    selfcol_alloc__free_array(&al, sweep->hit_spare, sweep->spare_capacity,
                              sizeof *sweep->hit_spare);
    selfcol_alloc__free_array(&al, sweep->candidates, sweep->candidate_capacity,
                              sizeof *sweep->candidates);
    selfcol_alloc__free_array(&al, sweep->boxes, sweep->box_capacity, sizeof *sweep->boxes);
    selfcol_sweep__free_workers(sweep);
    selfcol_alloc__free_array(&al, sweep->positions_at, sweep->positions_capacity,
                              sizeof *sweep->positions_at);
    selfcol_alloc__free_array(&al, sweep->outcome, sweep->outcome_capacity, sizeof *sweep->outcome);
    selfcol_alloc__free_array(&al, sweep->toi, sweep->outcome_capacity, sizeof *sweep->toi);
    selfcol_alloc__free_array(&al, sweep->cull_cones, sweep->cull_capacity,
                              sizeof *sweep->cull_cones);
    selfcol_alloc__free_array(&al, sweep->cull_altitudes, sweep->cull_capacity,
                              sizeof *sweep->cull_altitudes);
    selfcol_alloc__free_array(&al, sweep->node_active, sweep->node_active_capacity,
                              sizeof *sweep->node_active);
    selfcol_workspace__free(&sweep->work);
    selfcol_alloc__free(&al, sweep, sizeof *sweep);
}

int selfcol_sweep__push_candidate(selfcol_sweep *s, const selfcol_sweep_candidate *c) {
    if (s->candidate_count == s->candidate_capacity) {
        if (s->candidate_capacity > SIZE_MAX / 2 / sizeof *s->candidates)
            return SELFCOL_ENOMEM;
        const size_t cap = s->candidate_capacity < 1024 ? 1024 : 2 * s->candidate_capacity;
        selfcol_sweep_candidate *grown = selfcol_alloc__array(&s->allocator, cap, sizeof *grown);
        if (grown == NULL)
            return SELFCOL_ENOMEM;
        if (s->candidate_count > 0)
            memcpy(grown, s->candidates, s->candidate_count * sizeof *grown);
        selfcol_alloc__free_array(&s->allocator, s->candidates, s->candidate_capacity,
                                  sizeof *s->candidates);
        s->candidates = grown;
        s->candidate_capacity = cap;
    }
    s->candidates[s->candidate_count++] = *c;
    return SELFCOL_OK;
}

// Room for n hits in the array `which` (0: hits, kept; 1: the sort's spare).
static int reserve_hits(selfcol_sweep *s, int which, size_t n) {
    selfcol_sweep_hit **array = which == 0 ? &s->hits : &s->hit_spare;
    size_t *capacity = which == 0 ? &s->hit_capacity : &s->spare_capacity;
    if (n <= *capacity)
        return SELFCOL_OK;
    if (n > SIZE_MAX / 4 / sizeof **array)
        return SELFCOL_ENOMEM;
    const size_t cap = n + n / 2 + 64;
    selfcol_sweep_hit *grown = selfcol_alloc__array(&s->allocator, cap, sizeof *grown);
    if (grown == NULL)
        return SELFCOL_ENOMEM;
    if (which == 0 && s->hit_count > 0)
        memcpy(grown, s->hits, s->hit_count * sizeof *grown);
    selfcol_alloc__free_array(&s->allocator, *array, *capacity, sizeof *grown);
    *array = grown;
    *capacity = cap;
    return SELFCOL_OK;
}

// Room for n elements of `size` bytes in a scratch array whose content is
// not kept (each query refills it): a new block when it is too small, the
// old one freed. SELFCOL_OK, or SELFCOL_ENOMEM with the old array kept.
static int reserve_scratch(selfcol_sweep *s, void **array, size_t *capacity, size_t n,
                           size_t size) {
    if (n <= *capacity)
        return SELFCOL_OK;
    void *grown = selfcol_alloc__array(&s->allocator, n, size);
    if (grown == NULL)
        return SELFCOL_ENOMEM;
    selfcol_alloc__free_array(&s->allocator, *array, *capacity, size);
    *array = grown;
    *capacity = n;
    return SELFCOL_OK;
}

// Room for the swept boxes (doubles), and for n node flags of a restricted
// query.
static int reserve_boxes(selfcol_sweep *s, size_t doubles) {
    return reserve_scratch(s, (void **)&s->boxes, &s->box_capacity, doubles, sizeof *s->boxes);
}

static int reserve_node_active(selfcol_sweep *s, size_t n) {
    return reserve_scratch(s, (void **)&s->node_active, &s->node_active_capacity, n,
                           sizeof *s->node_active);
}

// ---------------------------------------------------------------------------
// Narrow phase

// The vertices of a candidate's primitives, as a hit lists them.
static void hit_of(const selfcol_sweep_query *q, const selfcol_sweep_candidate *c,
                   selfcol_sweep_hit *h) {
    const selfcol_mesh *mf = q->mesh[c->first_mesh], *ms = q->mesh[c->second_mesh];
    memset(h, 0, sizeof *h); // padding included: records compare and copy byte for byte
    h->kind = c->kind;
    h->first = c->first;
    h->second = c->second;
    h->first_mesh = c->first_mesh;
    h->second_mesh = c->second_mesh;
    if (c->kind == SELFCOL_CONTACT_VF) {
        h->a[0] = h->a[1] = c->first;
        memcpy(h->b, ms->triangles + 3 * (size_t)c->second, sizeof h->b);
    } else {
        memcpy(h->a, mf->edges + 2 * (size_t)c->first, sizeof h->a);
        memcpy(h->b, ms->edges + 2 * (size_t)c->second, 2 * sizeof *h->b);
        h->b[2] = SELFCOL_INVALID_INDEX;
    }
    h->flags = 0;
    h->toi = 1.0;
}

// The points of a hit's primitives at both ends, in the narrow phase's
// order (VF: p, a, b, c; EE: a, b, c, d).
static void hit_points(const selfcol_sweep_query *q, const selfcol_sweep_hit *h,
                       const double *start[4], const double *end[4]) {
    const int fm = (int)h->first_mesh, sm = (int)h->second_mesh;
    const int vf = h->kind == SELFCOL_CONTACT_VF;
    const uint32_t ids[4] = {h->a[0], vf ? h->b[0] : h->a[1], vf ? h->b[1] : h->b[0],
                             vf ? h->b[2] : h->b[1]};
    const int of[4] = {fm, vf ? sm : fm, sm, sm};
    for (int k = 0; k < 4; ++k) {
        start[k] = q->start[of[k]] + 3 * (size_t)ids[k];
        end[k] = selfcol_mesh__position(q->mesh[of[k]], ids[k]);
    }
}

static int root_before(const selfcol_sweep_query *q, const selfcol_sweep_hit *h, double t_max,
                       double *toi, selfcol_narrow_sweep_info *info) {
    const double *start[4], *end[4];
    hit_points(q, h, start, end);
    return h->kind == SELFCOL_CONTACT_VF
               ? selfcol_narrow_sweep__vf_before(start, end, q->separation, t_max, q->tolerance,
                                                 toi, info)
               : selfcol_narrow_sweep__ee_before(start, end, q->separation, t_max, q->tolerance,
                                                 toi, info);
}

// Whether a hit is within the separation already at t = 0: the closed form
// says (SELFCOL_SWEEP_INITIAL).
static void flag_initial(const selfcol_sweep_query *q, selfcol_sweep_hit *h) {
    const double *start[4], *end[4];
    hit_points(q, h, start, end);
    selfcol_narrow_result r;
    const double d = h->kind == SELFCOL_CONTACT_VF
                         ? selfcol_narrow__vf(start[0], start[1], start[2], start[3], &r)
                         : selfcol_narrow__ee(start[0], start[1], start[2], start[3], &r);
    if (d <= q->separation)
        h->flags |= SELFCOL_SWEEP_INITIAL;
}

// ALL: the root search of every candidate over the whole step, each hit
// kept. The fraction is the least time of the resolved hits; an unresolved
// hit (its toi the earliest time its root finder left undecided, often 0:
// parallel edges sliding at the tolerance) is then asked again over [0,
// fraction of the others) only, as EARLIEST would, and lowers the fraction
// only if it may collide before it.
// Root searches shared among the query's threads (ALL's, and EARLIEST's
// batches): a counter hands out `grain` candidates at a time, and each
// search writes its candidate's outcome (0 apart, 1 hit, 3 unresolved hit)
// and time into per-candidate slots: no allocation, no order dependence
// (the hits are gathered afterwards in candidate order).
#define SWEEP_CHUNK 1024u

// With a progress callback, the chunks run in about this many rounds (of
// at least SWEEP_ROUND_MIN chunks), the callback called on the calling
// thread between rounds: starting a round's threads costs tens of
// microseconds against its thousand root searches or more.
#define SWEEP_ROUNDS 64u
#define SWEEP_ROUND_MIN 1u

typedef struct narrow_job {
    selfcol_sweep_query *q;
    const selfcol_sweep_candidate *c;    // s->outcome[i] and s->toi[i] are c[i]'s
    double bound;                        // every search is before this time
    uint64_t grain;                      // candidates per take
    uint64_t next;                       // atomic: the next candidate
    uint64_t end;                        // this round's last candidate + 1
    uint64_t boxes[SELFCOL_MAX_THREADS]; // root-finder boxes per worker
} narrow_job;

static int narrow_worker(void *context, unsigned worker) {
    narrow_job *job = context;
    selfcol_sweep *s = job->q->out;
    for (;;) {
        const uint64_t first = SELFCOL_ATOMIC_FETCH_ADD(&job->next, job->grain);
        if (first >= job->end)
            return SELFCOL_OK;
        const uint64_t end = first + job->grain < job->end ? first + job->grain : job->end;
        for (uint64_t i = first; i < end; ++i) {
            selfcol_sweep_hit h;
            hit_of(job->q, &job->c[i], &h);
            selfcol_narrow_sweep_info info;
            double toi = job->bound;
            const int hit = root_before(job->q, &h, job->bound, &toi, &info);
            job->boxes[worker] += (uint64_t)info.checks;
            s->outcome[i] =
                (uint8_t)(hit ? (info.outcome == SELFCOL_NARROW_SWEEP_ACCEPTED ? 1 : 3) : 0);
            s->toi[i] = toi;
        }
    }
}

int selfcol_sweep__reserve_two(selfcol_sweep *s, size_t n, size_t *capacity, void **a,
                               size_t a_size, void **b, size_t b_size) {
    if (n <= *capacity)
        return SELFCOL_OK;
    void *a_new = selfcol_alloc__array(&s->allocator, n, a_size);
    void *b_new = selfcol_alloc__array(&s->allocator, n, b_size);
    if (a_new == NULL || b_new == NULL) {
        selfcol_alloc__free_array(&s->allocator, a_new, n, a_size);
        selfcol_alloc__free_array(&s->allocator, b_new, n, b_size);
        return SELFCOL_ENOMEM;
    }
    selfcol_alloc__free_array(&s->allocator, *a, *capacity, a_size);
    selfcol_alloc__free_array(&s->allocator, *b, *capacity, b_size);
    *a = a_new;
    *b = b_new;
    *capacity = n;
    return SELFCOL_OK;
}

// Room for n outcomes and times (ALL's per-candidate arrays).
static int reserve_outcomes(selfcol_sweep *s, size_t n) {
    return selfcol_sweep__reserve_two(s, n, &s->outcome_capacity, (void **)&s->outcome,
                                      sizeof *s->outcome, (void **)&s->toi, sizeof *s->toi);
}

static int narrow_all(selfcol_sweep_query *q, const selfcol_executor *executor, unsigned threads,
                      const selfcol_sweep_options *o) {
    selfcol_sweep *s = q->out;
    if (s->candidate_count > s->outcome_capacity &&
        reserve_outcomes(s, s->candidate_capacity) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    narrow_job job;
    memset(&job, 0, sizeof job);
    job.q = q;
    job.c = s->candidates;
    job.bound = 1.0;
    job.grain = SWEEP_CHUNK;
    const uint64_t chunks = (s->candidate_count + SWEEP_CHUNK - 1) / SWEEP_CHUNK;
    const unsigned workers = chunks < threads ? (unsigned)(chunks > 0 ? chunks : 1) : threads;
    // Every chunk in one round, or rounds with the progress callback between.
    uint64_t round = chunks > 0 ? chunks : 1;
    if (o->progress != NULL) {
        round = chunks / SWEEP_ROUNDS;
        round = round > SWEEP_ROUND_MIN ? round : SWEEP_ROUND_MIN;
    }
    uint64_t first = 0;
    do {
        const uint64_t end_chunk = first + round < chunks ? first + round : chunks;
        job.next = first * SWEEP_CHUNK;
        job.end = end_chunk * SWEEP_CHUNK < s->candidate_count ? end_chunk * SWEEP_CHUNK
                                                               : s->candidate_count;
        int status = selfcol_parallel__run(executor, workers, narrow_worker, &job);
        if (status != SELFCOL_OK)
            return status;
        const double done = chunks > 0 ? (double)end_chunk / (double)chunks : 1.0;
        if (o->progress != NULL && o->progress(o->progress_payload, done) != 0)
            return SELFCOL_EUSER;
        first = end_chunk;
    } while (first < chunks);
    for (unsigned w = 0; w < workers; ++w)
        s->stats.narrow_boxes += job.boxes[w];
    double earliest = 1.0;
    for (size_t i = 0; i < s->candidate_count; ++i) {
        if (s->outcome[i] == 0)
            continue;
        selfcol_sweep_hit h;
        hit_of(q, &s->candidates[i], &h);
        h.toi = s->toi[i];
        if (s->outcome[i] == 3)
            h.flags |= SELFCOL_SWEEP_UNRESOLVED;
        if (h.toi == 0.0)
            flag_initial(q, &h);
        if (reserve_hits(s, 0, s->hit_count + 1) != SELFCOL_OK)
            return SELFCOL_ENOMEM;
        s->hits[s->hit_count++] = h;
        s->stats.hits++;
        s->stats.initial += (h.flags & SELFCOL_SWEEP_INITIAL) != 0;
        s->stats.unresolved += (h.flags & SELFCOL_SWEEP_UNRESOLVED) != 0;
        if (!(h.flags & SELFCOL_SWEEP_UNRESOLVED))
            earliest = h.toi < earliest ? h.toi : earliest;
    }
    // Every unresolved hit against the same bound: the result does not
    // depend on the hits' order (BVH's differs from EXHAUSTIVE's).
    const double resolved = earliest;
    for (size_t i = 0; i < s->hit_count; ++i) {
        if (!(s->hits[i].flags & SELFCOL_SWEEP_UNRESOLVED))
            continue;
        selfcol_narrow_sweep_info info;
        double toi = resolved;
        if (root_before(q, &s->hits[i], resolved, &toi, &info) && toi < earliest)
            earliest = toi;
        s->stats.narrow_boxes += (uint64_t)info.checks;
    }
    s->stats.free_fraction = earliest;
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// EARLIEST
//
// Only the least time matters, so each candidate is searched at once, over
// [0, earliest so far) only, and once that time falls below a quarter of the
// span the broad phase's boxes were swept over, the search starts again
// with boxes swept over [0, earliest] alone: far fewer node pairs and
// candidates. A restart pays only while the boxes' sweep is a real part of
// their size: once t_box times the mean vertex motion is below
// RESTART_SWEEP mean edges, the boxes are nearly the static ones, whose
// overlaps (every pair of neighbouring triangles) a new pass would test
// again, so the pass runs to its end with its boxes. On cloth-ball 92 -> 93
// (fraction 4e-6, vertices moving 1.4 mean edges) that leaves 4 passes
// instead of 8, and 0.88M candidates instead of 1.79M: the last three
// passes of the old policy each tested most of the ~680k neighbour pairs.
// The last pass runs to its end with boxes over [0, t_box], t_box >= the
// final fraction, so every pair that could come within the separation
// before the fraction was a candidate of that pass and was searched before
// it: the fraction is as conservative as ALL's.
//
// The positions at t_box < 1 are computed as fl(x0 + fl(t_box fl(x1 - x0))),
// within 8 u M of the exact ones (u = 2^-53, M the largest |coordinate| of
// the step: three roundings, the middle one of a value up to 2M), below
// eps = 2^-49 M + DBL_MIN; sweep_search.c widens its boxes and raises its
// filter's separation by that. The root finder always gets the exact start
// and end.

// EARLIEST's rule for one root search's answer: a hit earlier than the time
// found so far (or the first hit) becomes the hit; then a restart is asked
// when the time is 0 (nothing is earlier: run_earliest stops) or below a
// quarter of t_box while the boxes' sweep still pays.
static int take_earliest(selfcol_sweep_query *q, const selfcol_sweep_candidate *c, int hit,
                         int resolved, double toi) {
    selfcol_sweep *s = q->out;
    if (!hit || (s->hit_count > 0 && !(toi < q->earliest)))
        return SELFCOL_OK;
    selfcol_sweep_hit h;
    hit_of(q, c, &h);
    h.toi = toi;
    if (!resolved)
        h.flags |= SELFCOL_SWEEP_UNRESOLVED;
    if (toi == 0.0)
        flag_initial(q, &h);
    s->hits[0] = h; // room reserved by run_earliest
    s->hit_count = 1;
    q->earliest = toi;
    if (toi == 0.0)
        return SELFCOL_SWEEP__RESTART;
    const int pays = q->t_box * q->motion_per_time > q->restart_sweep;
    return toi < 0.25 * q->t_box && pays ? SELFCOL_SWEEP__RESTART : SELFCOL_OK;
}

int selfcol_sweep__earliest_pair(selfcol_sweep_query *q, const selfcol_sweep_candidate *c) {
    selfcol_sweep *s = q->out;
    selfcol_sweep_hit h;
    hit_of(q, c, &h);
    const double start = selfcol_core__seconds();
    selfcol_narrow_sweep_info info;
    double toi = q->earliest;
    const int hit = root_before(q, &h, q->earliest, &toi, &info);
    s->stats.narrow_seconds += selfcol_core__seconds() - start;
    s->stats.narrow_boxes += (uint64_t)info.checks;
    return take_earliest(q, c, hit, info.outcome == SELFCOL_NARROW_SWEEP_ACCEPTED, toi);
}

// EARLIEST's root searches of a round of the BVH broad phase (its candidates
// in task order, sweep_search.c), on the workers, in batches of
// EARLIEST_BATCH: every candidate of a batch is searched before the time
// found when the batch starts, then the batch's answers are taken in order
// by the rule of selfcol_sweep__earliest_pair (a hit earlier than the time
// found so far becomes the hit; a restart is asked as there). The bound of a
// batch does not depend on the threads, so neither do the hit, the time and
// the counters; a batch searches a little more than one candidate at a time
// would (its later candidates are bounded by its start's time, not by its
// earlier ones' hits).
#define EARLIEST_BATCH 256u
#define EARLIEST_GRAIN 8u

int selfcol_sweep__earliest_round(selfcol_sweep_query *q, const selfcol_sweep_candidate *c,
                                  size_t n, const selfcol_executor *executor, unsigned threads) {
    selfcol_sweep *s = q->out;
    if (n == 0)
        return SELFCOL_OK;
    int status = reserve_outcomes(s, n < EARLIEST_BATCH ? n : EARLIEST_BATCH);
    if (status != SELFCOL_OK)
        return status;
    const double start = selfcol_core__seconds();
    for (size_t at = 0; at < n && status == SELFCOL_OK; at += EARLIEST_BATCH) {
        narrow_job job;
        memset(&job, 0, sizeof job);
        job.q = q;
        job.c = c + at;
        job.bound = q->earliest;
        job.grain = EARLIEST_GRAIN;
        job.end = n - at < EARLIEST_BATCH ? n - at : EARLIEST_BATCH;
        const uint64_t grains = (job.end + EARLIEST_GRAIN - 1) / EARLIEST_GRAIN;
        const unsigned workers = grains < threads ? (unsigned)grains : threads;
        status = selfcol_parallel__run(executor, workers, narrow_worker, &job);
        for (unsigned w = 0; w < workers; ++w)
            s->stats.narrow_boxes += job.boxes[w];
        for (size_t i = 0; i < job.end && status == SELFCOL_OK; ++i)
            status = take_earliest(q, &job.c[i], s->outcome[i] != 0, s->outcome[i] == 1, s->toi[i]);
    }
    s->stats.narrow_seconds += selfcol_core__seconds() - start;
    return status;
}

// Below this sweep, in mean edges, the boxes are nearly the static ones:
// a restart would repeat the pass for few fewer candidates.
#define RESTART_SWEEP 0.01

static double largest_coordinate(const double *x, size_t n) {
    double m = 0.0;
    for (size_t i = 0; i < n; ++i)
        m = fabs(x[i]) > m ? fabs(x[i]) : m;
    return m;
}

// The mean distance a vertex travels over the step.
static double mean_motion(const double *x0, const double *x1, size_t vertices) {
    double sum = 0.0;
    for (size_t v = 0; v < vertices; ++v) {
        const double *a = x0 + 3 * v, *b = x1 + 3 * v;
        const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
        sum += sqrt(dx * dx + dy * dy + dz * dz);
    }
    return vertices > 0 ? sum / (double)vertices : 0.0;
}

static int run_earliest(selfcol_sweep_query *q, uint32_t method, const selfcol_executor *executor,
                        unsigned threads) {
    selfcol_sweep *s = q->out;
    const int meshes = q->self ? 1 : 2;
    size_t coordinates = 0;
    double m = 0.0, motion = 0.0, edge = 0.0;
    for (int k = 0; k < meshes; ++k) {
        const size_t n = 3 * q->mesh[k]->vertex_count;
        coordinates += n;
        const double a = largest_coordinate(q->start[k], n);
        const double b = largest_coordinate(q->mesh[k]->positions, n);
        m = a > m ? a : m;
        m = b > m ? b : m;
        motion += mean_motion(q->start[k], q->mesh[k]->positions, q->mesh[k]->vertex_count);
        edge += selfcol_mesh_mean_edge_length(q->mesh[k]);
    }
    q->motion_per_time = motion / meshes;
    q->restart_sweep = RESTART_SWEEP * edge / meshes;
    if (reserve_hits(s, 0, 1) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    if (reserve_scratch(s, (void **)&s->positions_at, &s->positions_capacity, coordinates,
                        sizeof *s->positions_at) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    q->earliest_mode = 1;
    q->earliest = 1.0;
    double t_box = 1.0;
    for (;;) {
        q->t_box = t_box;
        if (t_box < 1.0) {
            q->eps = ldexp(m, -49) + DBL_MIN;
            double *at = s->positions_at;
            for (int k = 0; k < meshes; ++k) {
                const size_t n = 3 * q->mesh[k]->vertex_count;
                const double *x0 = q->start[k], *x1 = q->mesh[k]->positions;
                for (size_t i = 0; i < n; ++i)
                    at[i] = x0[i] + t_box * (x1[i] - x0[i]);
                q->end[k] = at;
                at += n;
            }
            if (q->self)
                q->end[1] = q->end[0];
        }
        s->stats.passes++;
        const int status = method == SELFCOL_METHOD_EXHAUSTIVE
                               ? selfcol_sweep__exhaustive(q)
                               : selfcol_sweep__bvh(q, executor, threads);
        if (status != SELFCOL_SWEEP__RESTART) {
            if (status != SELFCOL_OK)
                return status;
            break;
        }
        if (q->earliest == 0.0)
            break; // nothing is earlier
        t_box = q->earliest;
    }
    if (s->hit_count == 1) {
        const selfcol_sweep_hit *h = &s->hits[0];
        s->stats.hits = 1;
        s->stats.initial = (h->flags & SELFCOL_SWEEP_INITIAL) != 0;
        s->stats.unresolved = (h->flags & SELFCOL_SWEEP_UNRESOLVED) != 0;
    }
    s->stats.free_fraction = q->earliest;
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// Sorting the hits: LSD radix by (kind, first_mesh, first, second_mesh,
// second), a byte a pass, passes whose digit is the same for every hit
// skipped (most of them: meshes, kinds and high index bytes).

static uint32_t hit_digit(const selfcol_sweep_hit *h, int pass) {
    if (pass < 4)
        return (h->second >> (8 * pass)) & 0xffu;
    if (pass == 4)
        return h->second_mesh;
    if (pass < 9)
        return (h->first >> (8 * (pass - 5))) & 0xffu;
    return h->kind << 1 | h->first_mesh;
}

static int sort_hits(selfcol_sweep *s) {
    const size_t n = s->hit_count;
    if (n < 2)
        return SELFCOL_OK;
    if (reserve_hits(s, 1, n) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    size_t count[256];
    for (int pass = 0; pass < 10; ++pass) {
        const uint32_t d0 = hit_digit(&s->hits[0], pass);
        size_t same = 1;
        while (same < n && hit_digit(&s->hits[same], pass) == d0)
            ++same;
        if (same == n)
            continue;
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; ++i)
            count[hit_digit(&s->hits[i], pass)]++;
        size_t sum = 0;
        for (size_t b = 0; b < 256; ++b) {
            const size_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; ++i)
            s->hit_spare[count[hit_digit(&s->hits[i], pass)]++] = s->hits[i];
        selfcol_sweep_hit *t = s->hits;
        s->hits = s->hit_spare;
        s->hit_spare = t;
        const size_t c = s->hit_capacity;
        s->hit_capacity = s->spare_capacity;
        s->spare_capacity = c;
    }
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// Queries

// The options read as their version says (NULL: the defaults) and checked;
// `at` names a refused field (problem.h; NULL: the status only).
static int sweep_options(selfcol_sweep_options *o, const selfcol_sweep_options *opts,
                         const selfcol_problem_at *at) {
    selfcol_sweep_options_init(o, SELFCOL_SWEEP_OPTIONS_VERSION);
    if (opts != NULL) {
        const int version = selfcol_problem__version_since(
            at, opts->version, SELFCOL_SWEEP_OPTIONS_VERSION, SELFCOL_SWEEP_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
        *o = *opts;
    }
    o->version = SELFCOL_SWEEP_OPTIONS_VERSION;
    SELFCOL_CHECK_FIELD(at,
                        o->method == SELFCOL_METHOD_EXACT || o->method == SELFCOL_METHOD_BVH ||
                            o->method == SELFCOL_METHOD_EXHAUSTIVE,
                        "method",
                        "= %u is not EXACT, BVH or EXHAUSTIVE (SEED and CONE have no "
                        "continuous query)",
                        o->method);
    SELFCOL_CHECK_FIELD(
        at, o->kinds != 0 && (o->kinds & ~(uint32_t)(SELFCOL_KIND_VF | SELFCOL_KIND_EE)) == 0,
        "kinds", "= 0x%x is not a nonempty mask of SELFCOL_KIND_VF and SELFCOL_KIND_EE", o->kinds);
    SELFCOL_CHECK_FIELD(at, o->mode == SELFCOL_SWEEP_ALL || o->mode == SELFCOL_SWEEP_EARLIEST,
                        "mode", "= %u is not a selfcol_sweep_mode (%d or %d)", o->mode,
                        (int)SELFCOL_SWEEP_ALL, (int)SELFCOL_SWEEP_EARLIEST);
    SELFCOL_CHECK_FIELD(at,
                        isfinite(o->separation) && o->separation >= 0.0 &&
                            o->separation <= SELFCOL_MESH_MAX_COORDINATE,
                        "separation", "= %g is not a distance in 0 .. %g", o->separation,
                        SELFCOL_MESH_MAX_COORDINATE);
    SELFCOL_CHECK_FIELD(at, o->tolerance >= 1e-12 && o->tolerance <= 0.1, "tolerance",
                        "= %g is not a relative tolerance in 1e-12 .. 0.1", o->tolerance);
    return SELFCOL_OK;
}

int selfcol_sweep_options_check(const selfcol_sweep_options *opts,
                                selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_sweep_options", ""};
    selfcol_sweep_options checked;
    return sweep_options(&checked, opts, &at);
}

// A continuous query; with a context (NULL: the calling thread), its
// parallel stages run on the context's workers and scheduler.
static int run_sweep(const selfcol_context *context, const selfcol_hierarchy *first,
                     const double *first_start, const selfcol_hierarchy *second,
                     const double *second_start, selfcol_sweep *result,
                     const selfcol_sweep_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && first_start != NULL && second_start != NULL &&
                  result != NULL);
    selfcol_sweep_options o;
    const int checked = sweep_options(&o, opts, NULL);
    if (checked != SELFCOL_OK)
        return checked;
    if (!selfcol_mesh__is(first->mesh, &first->mesh_identity) ||
        !selfcol_mesh__is(second->mesh, &second->mesh_identity))
        return SELFCOL_EMISMATCH;
    const int self = first == second;
    SELFCOL_CHECK(self ? first_start == second_start : first->mesh != second->mesh);
    SELFCOL_CHECK(selfcol_mesh__positions_in_contract(first_start, first->mesh->vertex_count));
    SELFCOL_CHECK(self ||
                  selfcol_mesh__positions_in_contract(second_start, second->mesh->vertex_count));

    const double start_time = selfcol_core__seconds();
    result->hit_count = 0;
    result->candidate_count = 0;
    reset_stats(result);
    selfcol_sweep_query q;
    memset(&q, 0, sizeof q);
    q.hierarchy[0] = first;
    q.hierarchy[1] = second;
    q.mesh[0] = first->mesh;
    q.mesh[1] = second->mesh;
    q.start[0] = first_start;
    q.start[1] = second_start;
    q.self = self;
    q.separation = o.separation;
    q.tolerance = o.tolerance;
    q.kinds = o.kinds;
    q.out = result;
    q.t_box = 1.0;
    q.end[0] = first->mesh->positions;
    q.end[1] = second->mesh->positions;
    q.cull = self && o.method == SELFCOL_METHOD_EXACT;
    q.active[0] = o.active_vertices[0];
    q.active[1] = self ? o.active_vertices[0] : o.active_vertices[1];
    q.restricted = q.active[0] != NULL || q.active[1] != NULL;
    size_t doubles = 0, nodes = 0;
    for (int m = 0; m < (self ? 1 : 2); ++m) {
        doubles += 6 * q.mesh[m]->vertex_count;
        if (o.method != SELFCOL_METHOD_EXHAUSTIVE) {
            doubles += 6 * (q.mesh[m]->triangle_count + q.hierarchy[m]->node_count);
            nodes += q.hierarchy[m]->node_count;
        }
    }
    int status = reserve_boxes(result, doubles);
    if (status == SELFCOL_OK && q.restricted)
        status = reserve_node_active(result, nodes);
    double narrow_start = start_time;
    // Who runs the broad phase's tasks and ALL's root searches.
    const selfcol_executor *executor = context != NULL ? &context->executor : NULL;
    const unsigned threads = context != NULL ? context->threads : 1;
    if (status == SELFCOL_OK && o.mode == SELFCOL_SWEEP_EARLIEST) {
        status = run_earliest(&q, o.method, executor, threads);
    } else if (status == SELFCOL_OK) {
        result->stats.passes = 1;
        status = o.method == SELFCOL_METHOD_EXHAUSTIVE ? selfcol_sweep__exhaustive(&q)
                                                       : selfcol_sweep__bvh(&q, executor, threads);
        narrow_start = selfcol_core__seconds();
        if (status == SELFCOL_OK)
            status = narrow_all(&q, executor, threads, &o);
        if (status == SELFCOL_OK)
            status = sort_hits(result);
        result->stats.narrow_seconds = selfcol_core__seconds() - narrow_start;
    }
    if (status != SELFCOL_OK) {
        result->hit_count = 0;
        result->candidate_count = 0;
        reset_stats(result);
        return status;
    }
    const double end_time = selfcol_core__seconds();
    result->stats.total_seconds = end_time - start_time;
    result->stats.broad_seconds = result->stats.total_seconds - result->stats.narrow_seconds;
    return SELFCOL_OK;
}

int selfcol_hierarchy_self_sweep(const selfcol_hierarchy *hierarchy, const double *start_positions,
                                 selfcol_sweep *result, const selfcol_sweep_options *opts) {
    return run_sweep(NULL, hierarchy, start_positions, hierarchy, start_positions, result, opts);
}

int selfcol_context_self_sweep(selfcol_context *context, const selfcol_hierarchy *hierarchy,
                               const double *start_positions, selfcol_sweep *result,
                               const selfcol_sweep_options *opts) {
    SELFCOL_CHECK(context != NULL);
    return run_sweep(context, hierarchy, start_positions, hierarchy, start_positions, result, opts);
}

int selfcol_context_sweep(selfcol_context *context, const selfcol_hierarchy *first,
                          const double *first_start, const selfcol_hierarchy *second,
                          const double *second_start, selfcol_sweep *result,
                          const selfcol_sweep_options *opts) {
    SELFCOL_CHECK(context != NULL && first != second);
    return run_sweep(context, first, first_start, second, second_start, result, opts);
}

int selfcol_hierarchy_sweep(const selfcol_hierarchy *first, const double *first_start,
                            const selfcol_hierarchy *second, const double *second_start,
                            selfcol_sweep *result, const selfcol_sweep_options *opts) {
    SELFCOL_CHECK(first != second);
    return run_sweep(NULL, first, first_start, second, second_start, result, opts);
}

int selfcol_sweep_hits(const selfcol_sweep *sweep, const selfcol_sweep_hit **data_out,
                       size_t *count_out) {
    SELFCOL_CHECK(sweep != NULL && data_out != NULL && count_out != NULL);
    *data_out = sweep->hit_count > 0 ? sweep->hits : NULL;
    *count_out = sweep->hit_count;
    return SELFCOL_OK;
}

int selfcol_sweep_stats(const selfcol_sweep *sweep, selfcol_sweep_query_stats *stats) {
    SELFCOL_CHECK(sweep != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_SWEEP_STATS_VERSION)
        return SELFCOL_EVERSION;
    const unsigned version = stats->version;
    // Version 1 ends before the culling's counters.
    memcpy(stats, &sweep->stats,
           version == 1 ? offsetof(selfcol_sweep_query_stats, patches_culled) : sizeof *stats);
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_sweep_byte_count(const selfcol_sweep *sweep) {
    if (sweep == NULL)
        return 0;
    return sizeof *sweep + (sweep->hit_capacity + sweep->spare_capacity) * sizeof *sweep->hits +
           sweep->candidate_capacity * sizeof *sweep->candidates +
           sweep->box_capacity * sizeof *sweep->boxes +
           sweep->front_capacity * sizeof *sweep->front +
           sweep->segment_capacity * sizeof *sweep->segments +
           sweep->worker_capacity * sizeof *sweep->workers +
           sweep->positions_capacity * sizeof *sweep->positions_at +
           sweep->outcome_capacity * (sizeof *sweep->outcome + sizeof *sweep->toi) +
           sweep->cull_capacity * (sizeof *sweep->cull_cones + sizeof *sweep->cull_altitudes) +
           sweep->node_active_capacity * sizeof *sweep->node_active +
           selfcol_workspace__byte_count(&sweep->work);
}
