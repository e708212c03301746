// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Narrow phase: primitive-pair queries. Two implementations with one shape:
// closed form (narrow.c, the default) and libccd (narrow_ccd.c).
#ifndef SELFCOL_NARROW_H
#define SELFCOL_NARROW_H

#include <stddef.h>

// Result of a primitive query, in the convention of selfcol_contact:
// closest point on the first primitive = wa[0] p0 + wa[1] p1 (a vertex: wa = {1, 0}),
// closest point on the second = wb[0] b0 + wb[1] b1 + wb[2] b2 (an edge: wb[2] = 0),
// direction = unit vector from the second closest point toward the first.
typedef struct selfcol_narrow_result {
    double distance;
    double wa[2];
    double wb[3];
    double direction[3];
} selfcol_narrow_result;

// Vertex p against triangle (a, b, c); any triangle, degenerate ones included.
// Returns the distance; fills out when out != NULL.
double selfcol_narrow__vf(const double p[3], const double a[3], const double b[3],
                          const double c[3], selfcol_narrow_result *out);

// Segment (p0, p1) against segment (q0, q1); zero-length and parallel included.
double selfcol_narrow__ee(const double p0[3], const double p1[3], const double q0[3],
                          const double q1[3], selfcol_narrow_result *out);

// Does segment (p0, p1) cross triangle (a, b, c)? Decided exactly (see
// contacts.h for the definition). Returns 1 or 0; on 1 fills out (distance 0,
// the crossing point as weights, direction = triangle unit normal).
int selfcol_narrow__ef(const double p0[3], const double p1[3], const double a[3], const double b[3],
                       const double c[3], selfcol_narrow_result *out);

// Closest points of segment (p0, p1) and triangle (a, b, c): 0 with the
// crossing point when the segment crosses the triangle (selfcol_narrow__ef),
// else the nearest of the two endpoints against the triangle and the segment
// against the three edges. Fills out (weights on the segment and on the
// triangle, direction from the triangle toward the segment) and returns the
// distance.
double selfcol_narrow__segment_triangle(const double p0[3], const double p1[3], const double a[3],
                                        const double b[3], const double c[3],
                                        selfcol_narrow_result *out);

// libccd backend, same conventions, for the cross-check. libccd 2.1 has no
// distance query (ccdGJKDist2 exists only in FCL's fork), and its GJK + EPA
// penetration depth is wrong on the shapes needed here (see narrow_ccd.c), so
// proximities use libccd's yes/no MPR test, ccdMPRIntersect, on the first
// primitive swept by a ball of radius rho: asked at rho = radius (no: the
// functions return HUGE_VAL and leave out untouched), then by bisection on rho
// down to `tolerance` (absolute, mesh units). The distance is within
// `tolerance` of the truth (0 when below it); the weights and direction come
// from the closest points. No allocation.
//
// The EF test is ccdGJKIntersect on the segment and the triangle. libccd 2.1
// decides touching with fixed DBL_EPSILON tests on squared lengths and ignores
// `tolerance` there, so it also reports touching and near-touching
// configurations (about 1.5e-8 at unit scale, more for small triangles) that
// the exact test does not call crossing.
double selfcol_narrow_ccd__vf(const double p[3], const double a[3], const double b[3],
                              const double c[3], double radius, double tolerance,
                              selfcol_narrow_result *out);
double selfcol_narrow_ccd__ee(const double p0[3], const double p1[3], const double q0[3],
                              const double q1[3], double radius, double tolerance,
                              selfcol_narrow_result *out);
int selfcol_narrow_ccd__ef(const double p0[3], const double p1[3], const double a[3],
                           const double b[3], const double c[3], double tolerance,
                           selfcol_narrow_result *out);

// The convex hull of n >= 1 points against triangle (a, b, c), by the same
// inflation and bisection as the proximities: the distance when below
// radius (within tolerance; 0 when they touch or overlap), else HUGE_VAL.
// scratch holds n points (the local frame). When normal is not NULL and the
// distance is below radius, normal receives libccd's MPR penetration
// direction just past the contact (unit, from the hull toward the triangle;
// all zero if MPR found none) and point MPR's contact position. No
// allocation.
double selfcol_narrow_ccd__hull_triangle(const double (*points)[3], size_t n, const double a[3],
                                         const double b[3], const double c[3], double radius,
                                         double tolerance, double (*scratch)[3], double normal[3],
                                         double point[3]);

#endif // SELFCOL_NARROW_H
