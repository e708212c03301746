// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Untangling of surfaces that cross, on plain arrays (no Bullet type), so
// that its rules are tested without a world: the local form of intersection
// contour minimisation (Volino and Magnenat-Thalmann 2006, "Resolving
// surface collisions through intersection contour minimization"). Where two
// surface parts cross, their intersection is a set of contour lines made of
// one segment per crossing triangle pair, whose ends are the points where an
// edge of one triangle pierces the other (the EF interferences). Moving the
// parts so that the contours get shorter undoes the crossing without knowing
// which side is right: a closed contour shrinks to nothing, one that ends on
// a border slides off it.
//
// For a point P where edge e (direction E) pierces triangle T (normal N),
// moving e's side by a displacement delta relative to T moves P along e in
// T's plane: dP/d(delta) = I - E N^T / (E . N). With g the gradient of the
// contour length at P (the sum of the unit vectors from its neighbours along
// the contour), the length changes at the rate
//   G = g - N (E . g) / (E . N)
// per unit displacement of e's side. Each point therefore moves e's nodes by
// -G and T's nodes by +G (barycentric, mass-weighted, as a response row),
// a fixed distance per step along that direction: the gradient's size is
// not used (it blows up where e grazes T's plane).
#ifndef SELFCOL_BULLET_UNTANGLE_HPP
#define SELFCOL_BULLET_UNTANGLE_HPP

#include "response.hpp"

#include <cstddef>
#include <cstdint>

namespace selfcol_bullet_detail {

struct contour_point {
    uint32_t node[5]; // the edge's two nodes, the triangle's three (response slots)
    double w[5];      // +(1 - t), +t for the edge; -barycentric for the triangle
    double p[3];      // where the edge pierces the triangle
    double edge[3];   // edge direction x1 - x0
    double normal[3]; // triangle normal (b1 - b0) x (b2 - b0)
    double g[3];      // contour-length gradient at p (accumulated by contour_link)
};

// A contour segment end: the crossing triangle pair (two ids, in increasing
// order, of the caller's choosing: unique per triangle) and the point.
struct contour_key {
    uint64_t lo, hi;
    uint32_t point;
};

// Where segment x0-x1 pierces triangle (b0, b1, b2): fills p, edge, normal,
// the weights (nodes left to the caller) and clears g. False when the
// segment does not cross the triangle's plane within [0, 1] or lies in it.
bool contour_point_make(const double x0[3], const double x1[3], const double b0[3],
                        const double b1[3], const double b2[3], contour_point &out);

// Sorts the keys and, for every triangle pair holding exactly two points
// (one contour segment), adds the segment's unit vectors to both points'
// gradients. Pairs with another count (degenerate touching) are skipped.
// Returns the number of segments.
size_t contour_link(contour_point *points, contour_key *keys, size_t key_count);

// Moves the nodes of every point with a usable gradient by `step` of
// relative displacement along -G (edge side) and +G (triangle side);
// pinned nodes (im = 0) stay. The points' moves are summed per node in
// `delta` (3 per node, node_count nodes, zeroed here) and a node's sum is
// scaled down to at most `step` long before it is applied: where many
// crossings share nodes (a surface collapsing on itself) their pushes add
// up, and uncapped they made the collapse run away. Returns the number of
// points that moved nodes.
size_t contour_push(const contour_point *points, size_t count, response_node *nodes,
                    size_t node_count, double *delta, double step);

} // namespace selfcol_bullet_detail

#endif
