// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Continuous queries (include/selfcol/sweep.h): the result handle, and the
// stages of a query. sweep.c checks the arguments, runs the broad phase of
// sweep_search.c (candidate primitive pairs whose swept boxes are within the
// separation), then the continuous narrow phase (narrow_sweep.h) over the
// candidates, and sorts the hits.
#ifndef SELFCOL_SWEEP_INTERNAL_H
#define SELFCOL_SWEEP_INTERNAL_H

#include <selfcol/sweep.h>

#include "base/cone.h"
#include "base/workspace.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contour.h"

// A candidate primitive pair, in the key of a hit: kind, meshes, elements.
typedef struct selfcol_sweep_candidate {
    uint8_t kind, first_mesh, second_mesh, unused;
    uint32_t first, second;
} selfcol_sweep_candidate;

// One worker of the broad phase (sweep_search.c): its counters, filter
// hints, traversal stack and the candidates it found, in the order of its
// tasks (`direct`: candidates go straight to the query instead, one worker).
typedef struct selfcol_sweep_worker {
    struct selfcol_sweep_query *q;
    int direct;
    // On the calling thread (building the front: its stack may grow); off
    // it, a full array stops the task instead (overflow), which the calling
    // thread grows and runs again: the sweep's allocator is only called from
    // the calling thread.
    int on_caller, overflow;
    uint64_t node_pairs, vf_candidates, ee_candidates, separated;
    unsigned hint[2]; // the direction that last showed a VF (0) or EE (1) pair apart
    uint32_t *stack;
    size_t stack_capacity;
    selfcol_sweep_candidate *found;
    size_t found_count, found_capacity;
} selfcol_sweep_worker;

// Where one task's candidates lie: worker, first index, count.
typedef struct selfcol_sweep_segment {
    uint32_t worker;
    uint32_t count;
    size_t first;
} selfcol_sweep_segment;

struct selfcol_sweep {
    selfcol_allocator allocator;
    selfcol_sweep_hit *hits, *hit_spare; // spare: the sort's destination
    size_t hit_count, hit_capacity, spare_capacity;
    selfcol_sweep_candidate *candidates;
    size_t candidate_count, candidate_capacity;
    double *boxes; // swept boxes (lo, hi) of triangles and nodes, both meshes
    size_t box_capacity;
    // The BVH broad phase's tasks: the front of node pairs (2 per task), the
    // segments of a round of tasks, the workers.
    uint32_t *front;
    size_t front_capacity;
    selfcol_sweep_segment *segments;
    uint32_t *pending; // tasks of the round still to run (segment_capacity)
    size_t segment_capacity;
    selfcol_sweep_worker *workers;
    unsigned worker_capacity;
    double *positions_at; // EARLIEST: positions at t_box, 3 V per mesh
    size_t positions_capacity;
    uint8_t *outcome; // ALL, per candidate: 0 apart, 1 hit, 3 unresolved hit
    double *toi;      // ALL, per candidate: its time of impact
    size_t outcome_capacity;
    // EXACT (sweep_cull.c), per node: the cone of its normals and the lower
    // bound of its altitudes over the step; the contour test's scratch.
    selfcol_cone *cull_cones;
    double *cull_altitudes;
    size_t cull_capacity;
    // Restricted queries (options.active_vertices), BVH and EXACT, per node
    // of both trees: 1 when a triangle below it has an active vertex.
    uint8_t *node_active;
    size_t node_active_capacity;
    selfcol_workspace work;
    selfcol_sweep_query_stats stats;
};

// One continuous query in progress: what sweep_search.c reads.
typedef struct selfcol_sweep_query {
    const selfcol_hierarchy *hierarchy[2]; // hierarchy[1] == hierarchy[0] for a self query
    const selfcol_mesh *mesh[2];
    const double *start[2];        // t = 0 positions, 3 V each
    const double *vertex_boxes[2]; // swept box per vertex (lo, hi), set by the search
    int self;
    double separation;
    uint32_t kinds;
    selfcol_sweep *out;
    // Restricted to pairs with an active vertex (options.active_vertices;
    // self: [1] == [0]): `restricted`, per mesh its vertices' bytes (NULL:
    // none active) and, for the BVH search, its nodes' (node_active).
    int restricted;
    const uint8_t *active[2];
    uint8_t *node_active[2];
    // The broad phase covers the times [0, t_box]: end[m] holds mesh m's
    // positions at t_box (the mesh's own at t_box = 1), computed to within
    // eps of the exact x0 + t_box (x1 - x0) in every coordinate (0 at
    // t_box = 1). Its boxes are widened and its filter's separation raised
    // by that much (sweep.c, "EARLIEST").
    double t_box, eps;
    const double *end[2];
    // EARLIEST: candidates go to selfcol_sweep__earliest_pair at once (not
    // to the list); `earliest` is the least time found so far.
    int earliest_mode;
    double earliest;
    // EARLIEST: a restart pays only while the boxes' sweep over [0, t_box],
    // t_box times the mean vertex motion over the step, exceeds this length
    // (sweep.c, "EARLIEST").
    double motion_per_time, restart_sweep;
    // EXACT on a self query: patches proved free of contacts over the step
    // are skipped (sweep_cull.c).
    int cull;
    selfcol_contour_job cull_job;
    // The root finder's relative tolerance (options.tolerance): last, so
    // that the broad phase's fields keep their places.
    double tolerance;
} selfcol_sweep_query;

// What a broad phase returns, besides SELFCOL_OK and SELFCOL_ENOMEM, when
// EARLIEST's time has dropped well below t_box: the search stops, to be run
// again with boxes over [0, earliest].
#define SELFCOL_SWEEP__RESTART 1

// Room for n items in two arrays that share one capacity (their content is
// not kept: both are refilled after a call). SELFCOL_OK or SELFCOL_ENOMEM,
// which leaves the old arrays.
int selfcol_sweep__reserve_two(selfcol_sweep *s, size_t n, size_t *capacity, void **a,
                               size_t a_size, void **b, size_t b_size);

// Appends a candidate. SELFCOL_OK or SELFCOL_ENOMEM.
int selfcol_sweep__push_candidate(selfcol_sweep *s, const selfcol_sweep_candidate *c);

// EARLIEST: the root search of one candidate before q->earliest (sweep.c).
// SELFCOL_OK, or SELFCOL_SWEEP__RESTART when the time found is 0, or below
// a quarter of q->t_box while the boxes' sweep still exceeds
// q->restart_sweep (sweep.c, "EARLIEST").
int selfcol_sweep__earliest_pair(selfcol_sweep_query *q, const selfcol_sweep_candidate *c);

// EARLIEST: the root searches of n candidates (a round of the BVH broad
// phase, in task order) on `threads` workers of `executor`, in batches whose
// bound is the time found at the batch's start; the same answers as above
// for every thread count (sweep.c).
int selfcol_sweep__earliest_round(selfcol_sweep_query *q, const selfcol_sweep_candidate *c,
                                  size_t n, const struct selfcol_executor *executor,
                                  unsigned threads);

// Broad phases (sweep_search.c): fill q->out's candidates (the pairs whose
// swept boxes are near and that the separating-direction filter does not
// show apart) and the counters node_pairs, candidates and separated.
// q->out->boxes must hold 6 doubles per vertex (and, for BVH, per triangle
// and node) of each mesh. EXHAUSTIVE writes the candidates sorted by key.
// BVH runs its traversal's tasks on `threads` workers of `executor` (NULL:
// POSIX threads), with the same candidates, counters and EARLIEST time for
// every thread count (sweep_search.c, "Threads"); EXACT's culling keeps it
// on one.
int selfcol_sweep__exhaustive(selfcol_sweep_query *q);
int selfcol_sweep__bvh(selfcol_sweep_query *q, const struct selfcol_executor *executor,
                       unsigned threads);
// Frees the workers' arrays (selfcol_sweep_destroy).
void selfcol_sweep__free_workers(selfcol_sweep *s);

// EXACT (sweep_cull.c): the per-node cones and altitudes over [0, t_box] of
// a self query's hierarchy (SELFCOL_OK or SELFCOL_ENOMEM), then whether
// Self(id), or Pair(a, b) of two nodes, provably holds no pair of the
// contact set over the step (1) or may (0). Counted in the statistics.
int selfcol_sweep__cull_prepare(selfcol_sweep_query *q);
int selfcol_sweep__self_free(selfcol_sweep_query *q, uint32_t id);
int selfcol_sweep__pair_free(selfcol_sweep_query *q, uint32_t a, uint32_t b);

#endif // SELFCOL_SWEEP_INTERNAL_H
