// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// EXACT's contour criterion (contour.c): conditions (2) and (4) of the
// curvature criterion on projected boundary loops.
#ifndef SELFCOL_CONTOUR_H
#define SELFCOL_CONTOUR_H

#include "base/cone.h"
#include "base/workspace.h"
#include "hierarchy/hierarchy.h"
#include "query/query.h"

// One use of the criterion: where the loop's positions are, the scratch it
// may use, and what it counts. A discrete query's job reads the mesh's
// positions; a continuous query's (sweep_cull.c) reads the step's start
// positions and, through `end`, proves the loop clear at every time of the
// step (contour.c, step_deformation).
typedef struct selfcol_contour_job {
    selfcol_workspace *work; // scratch slot SELFCOL_SCRATCH_CONTOUR
    const double *positions; // 3 per vertex: the loop is projected here
    const double *end;       // NULL for one frame; else the step's end positions
    double end_error;        // bound on the error of each coordinate of end
    uint64_t tests, refused; // contour tests run and refused (added to)
    double seconds;          // their time (added to)
} selfcol_contour_job;

// Conditions (2) and (4) of EXACT's criterion alone (contour.c), for the
// direct tests: 1 when the closed loop of boundary half-edges
// ((edge << 1) | reversed, in loop order) projected along the unit vector v
// is a simple polygon whose vertices are at least d from every edge not
// incident to them (conservatively: a clearance within about 1e-9 d refuses).
// 0 also without memory. Uses scratch slot SELFCOL_SCRATCH_CONTOUR.
// `strategy` picks how the candidate edge pairs are found; every strategy
// examines the same pairs, so the answer never depends on it (the tests
// compare them).
enum {
    SELFCOL_CONTOUR_AUTO = 0,      // all pairs for short boundaries, else the grid
    SELFCOL_CONTOUR_GRID = 1,      // a hashed uniform grid, O(b) expected
    SELFCOL_CONTOUR_ALL_PAIRS = 2, // every pair of edges, O(b^2)
};
int selfcol_contour__loop_clear(const selfcol_mesh *m, const uint32_t *half_edges, size_t count,
                                const double v[3], double d, int strategy, selfcol_workspace *work,
                                selfcol_query_stats *stats);

// EXACT's criterion (contour.c): 1 when Self(node id) provably holds no
// contact at distance d. Uses scratch slot SELFCOL_SCRATCH_CONTOUR of `work`;
// adds its tests, refusals and time to `stats`.
int selfcol_contour__self_skippable(const selfcol_hierarchy *h, uint32_t id, double d,
                                    selfcol_workspace *work, selfcol_query_stats *stats);

// The criterion for Self(node id) with the given cone of its normals and
// lower bound of its altitudes (both valid at every time the job covers):
// conditions (1) and (3) from them, (2) and (4) on the node's boundary loop.
int selfcol_contour__patch_clear(const selfcol_hierarchy *h, uint32_t id, const selfcol_cone *cone,
                                 double min_altitude, double d, selfcol_contour_job *job);

// The same for Pair(a, b) of two adjacent nodes: the joint axis from the two
// cones, (2) and (4) on the joint boundary loop.
int selfcol_contour__patches_clear(const selfcol_hierarchy *h, uint32_t ia, uint32_t ib,
                                   const selfcol_cone *cone_a, double altitude_a,
                                   const selfcol_cone *cone_b, double altitude_b, double d,
                                   selfcol_contour_job *job);

// The same for Pair(a, b) of two nodes of one hierarchy: 1 when no primitive
// of a has a contact with a primitive of b (judged on the union of the two
// patches, joined along shared edges). Uses the same scratch slot.
int selfcol_contour__pair_skippable(const selfcol_hierarchy *h, uint32_t a, uint32_t b, double d,
                                    selfcol_workspace *work, selfcol_query_stats *stats);

#endif // SELFCOL_CONTOUR_H
