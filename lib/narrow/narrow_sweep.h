// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Continuous narrow phase: linearly moving primitives, with no false
// negatives. The first building block of continuous collision detection;
// internal, not public API.
//
// Every point moves linearly from its t = 0 position (suffix 0) to its t = 1
// position (suffix 1). The functions answer "may the two primitives come
// within the separation delta at some t in [0, 1]?" by an inclusion-based root
// finder in the spirit of Tight-Inclusion (Wang, Ferguson, Schneider, Jiang,
// Attene, Panozzo 2021, "A Large-scale Benchmark and an Inclusion-based
// Algorithm for Continuous Collision Detection", ACM TOG 40(5)); the method and
// its floating-point error bound are derived in narrow_sweep.c.
//
// Guarantees, for finite input and delta >= 0 (a negative or NaN delta is
// taken as 0):
//
// - No false negatives. When the primitives come within Euclidean distance
//   delta (delta = 0: they touch) at some t in [0, 1], the answer is 1, and
//   *toi <= the earliest such t (a conservative time of impact), in [0, 1].
//   This holds in floating point: every rounding of the evaluation is covered
//   by a derived bound (narrow_sweep.c), for coordinates of magnitude up to
//   DBL_MAX / 16; larger or non-finite coordinates return 1 with *toi = 0.
//
// - Bounded false positives. An answer 1 reached by the tolerance test (the
//   usual way, info->outcome == SELFCOL_NARROW_SWEEP_ACCEPTED) means that at
//   t = *toi two points of the primitives differ by at most
//   delta + tau_i + 2 eps_i in each coordinate i (up to a relative 2^-49,
//   the rounding of that sum), so their Euclidean distance is at most the
//   norm of that vector, below sqrt(3) (delta + tau + 4 eps), where
//     tau_i = max(tau, 2 eps_i), tau = SELFCOL_NARROW_SWEEP_TOLERANCE * L
//         (the _before functions: their tolerance argument times L),
//     L = the largest extent, over the three axes, of the bounding box of the
//         8 input points (the relative tolerance is scale- and
//         translation-invariant),
//     eps_i = 2^-47 M_i + DBL_MIN, M_i = the largest |coordinate i| of the 8
//         points (the rounding bound of narrow_sweep.c), eps = max eps_i.
//   The sqrt(3) comes from testing each coordinate against delta (an
//   axis-aligned box around the origin) rather than a ball: within delta in
//   Euclidean distance implies within delta in every coordinate, not the
//   converse.
//
// - Bounded work: at most SELFCOL_NARROW_SWEEP_MAX_CHECKS boxes are evaluated,
//   with fixed arrays on the stack (about 55 KiB: 1,176 boxes of 48 bytes;
//   no allocation). When they run out the answer is a conservative 1 with
//   *toi the earliest t still undecided (info->outcome ==
//   SELFCOL_NARROW_SWEEP_BUDGET): no distance bound then.
//
// toi may be NULL. Thread-safe (no state).
#ifndef SELFCOL_NARROW_SWEEP_H
#define SELFCOL_NARROW_SWEEP_H

#include <selfcol/sweep.h>

// Relative co-domain tolerance (times L, see above): the public default of
// selfcol_sweep_options.tolerance, Tight-Inclusion's 1e-6 (absolute there,
// on unit-scale scenes).
#define SELFCOL_NARROW_SWEEP_TOLERANCE SELFCOL_SWEEP_DEFAULT_TOLERANCE
// Boxes evaluated per query at most (Tight-Inclusion's default is 1e6).
#define SELFCOL_NARROW_SWEEP_MAX_CHECKS 100000

// How an answer was reached, for tests and statistics.
enum {
    // answer 0: every box was proven root-free, or (delta = 0) every piece
    // of the step was shown apart by a separating direction (narrow_sweep.c)
    SELFCOL_NARROW_SWEEP_SEPARATED = 0,
    SELFCOL_NARROW_SWEEP_ACCEPTED = 1, // answer 1: a box met the tolerance
    SELFCOL_NARROW_SWEEP_BUDGET = 2,   // answer 1: box budget or depth ran out
    SELFCOL_NARROW_SWEEP_INVALID = 3,  // answer 1: non-finite or huge coordinates
    SELFCOL_NARROW_SWEEP_WITNESS = 4,  // answer 1 (may_touch only): a point within tolerance
    // answer 0 (delta = 0 only): the four points are coplanar at no time of
    // the step (narrow_sweep.c, never_coplanar), so they never touch
    SELFCOL_NARROW_SWEEP_NEVER_COPLANAR = 5
};

typedef struct selfcol_narrow_sweep_info {
    int outcome;   // SELFCOL_NARROW_SWEEP_*
    long checks;   // boxes evaluated
    int max_depth; // deepest subdivision level (summed over t, u, v) evaluated
} selfcol_narrow_sweep_info;

// Vertex p against triangle (a, b, c), the triangle taken as a closed set
// (degenerate triangles included). Returns 1 or 0 as above.
int selfcol_narrow_sweep__vf(const double p0[3], const double a0[3], const double b0[3],
                             const double c0[3], const double p1[3], const double a1[3],
                             const double b1[3], const double c1[3], double delta, double *toi);

// Edge (a, b) against edge (c, d), closed segments (zero-length and parallel
// included). Returns 1 or 0 as above.
int selfcol_narrow_sweep__ee(const double a0[3], const double b0[3], const double c0[3],
                             const double d0[3], const double a1[3], const double b1[3],
                             const double c1[3], const double d1[3], double delta, double *toi);

// The same two, reporting how the answer was reached (info may be NULL).
int selfcol_narrow_sweep__vf_info(const double p0[3], const double a0[3], const double b0[3],
                                  const double c0[3], const double p1[3], const double a1[3],
                                  const double b1[3], const double c1[3], double delta, double *toi,
                                  selfcol_narrow_sweep_info *info);
int selfcol_narrow_sweep__ee_info(const double a0[3], const double b0[3], const double c0[3],
                                  const double d0[3], const double a1[3], const double b1[3],
                                  const double c1[3], const double d1[3], double delta, double *toi,
                                  selfcol_narrow_sweep_info *info);

// The same two over [0, t_max) only, for a search of the earliest time over
// many pairs: no box starting at or after t_max is examined, so the answer is
// 1 only with *toi < t_max, and 0 means no contact before t_max (within the
// guarantees above), and with the relative tolerance `tolerance` in place of
// SELFCOL_NARROW_SWEEP_TOLERANCE (outside (0, 1] or NaN: that default): a
// larger one accepts boxes sooner, so the search evaluates fewer boxes,
// with the false-positive bound above for that tolerance and no false
// negative whatever it is. t_max = 1 and the default tolerance give exactly
// the functions above (no box starts at 1); t_max > 1 or NaN is taken as 1.
// The points are given as arrays: start[k] and end[k] of point k, in the
// argument order of the functions above (VF: p, a, b, c; EE: a, b, c, d).
int selfcol_narrow_sweep__vf_before(const double *const start[4], const double *const end[4],
                                    double delta, double t_max, double tolerance, double *toi,
                                    selfcol_narrow_sweep_info *info);
int selfcol_narrow_sweep__ee_before(const double *const start[4], const double *const end[4],
                                    double delta, double t_max, double tolerance, double *toi,
                                    selfcol_narrow_sweep_info *info);

// A cheap sufficient test of separation over the whole step (no false
// negatives: 1 only when the primitives never come within delta, proof in
// narrow_sweep.c): a fixed direction -- an axis, the reference normal at
// t = 0 or t = 1, or one of that plane's in-plane normals (normal x edge)
// -- along which they are more than delta apart at both ends, the same way
// round. 0 means "not shown", not "collide". Points as in the _before
// functions; edge_edge 0 for VF (p; a, b, c), 1 for EE (a, b; c, d).
int selfcol_narrow_sweep__separated(const double *const start[4], const double *const end[4],
                                    int edge_edge, double delta);

// The same test trying direction *hint first (0-2: the axes, 3 and 4: the
// reference normals at t = 0 and t = 1, 5 and 6: their in-plane normals),
// then the others; *hint becomes the direction that showed the pair apart.
// Neighbouring candidates tend to be apart along the same direction, so a
// caller testing many keeps one hint.
int selfcol_narrow_sweep__separated_from(const double *const start[4], const double *const end[4],
                                         int edge_edge, double delta, unsigned *hint);

// "May the primitives touch (delta = 0) at some t in [0, 1]?", for callers
// that need no time of impact: the guarantees of the _before functions with
// t_max = 1 (no false negatives; an answer 1 has the same false-positive
// bound), usually far cheaper. The separation test first (0), then a witness
// point found near a coplanarity time and checked by the search's own
// acceptance test (1, outcome WITNESS), else the search. Points and edge_edge
// as in the functions above; info may be NULL. Proof in narrow_sweep.c.
int selfcol_narrow_sweep__may_touch(const double *const start[4], const double *const end[4],
                                    int edge_edge, selfcol_narrow_sweep_info *info);

#endif // SELFCOL_NARROW_SWEEP_H
