// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Convex colliders of a scene (include/selfcol/scene.h): the convex hull of
// a few points swept by a ball, placed by a pose, and their contacts with
// the triangles of a surface (broad phase on the surface's hierarchy; narrow
// phase in closed form for spheres, capsules and boxes, by libccd in
// narrow_ccd.c for convex point sets; see collider.c for the accuracy).
#ifndef SELFCOL_COLLIDER_H
#define SELFCOL_COLLIDER_H

#include <selfcol/scene.h>

#include "hierarchy/hierarchy.h"

typedef struct selfcol_collider {
    uint32_t shape;
    double radius;
    size_t point_count;
    double (*local)[3];  // point_count, the shape's frame
    double (*world)[3];  // point_count, after the pose
    double lo[3], hi[3]; // box of the world points grown by the radius
    // The pose (selfcol_collider__place): the closed forms and libccd's frame
    // work from these, never from the rounded world points.
    double position[3];
    double rotation[9]; // row-major; the identity when placed with NULL
} selfcol_collider;

// The hull's local points of a valid description (point_count of them,
// written into `local`, which holds selfcol_collider__point_count(desc)).
size_t selfcol_collider__point_count(const selfcol_scene_collider_desc *desc);
// SELFCOL_OK or SELFCOL_EINVAL (the checks of selfcol_scene_add_collider()).
int selfcol_collider__check(const selfcol_scene_collider_desc *desc);
void selfcol_collider__local_points(const selfcol_scene_collider_desc *desc, double (*local)[3]);

// Places the collider (rotation row-major, NULL: identity); the caller has
// checked the pose.
void selfcol_collider__place(selfcol_collider *c, const double position[3],
                             const double rotation[9]);

// Can the narrow phase answer this collider within `tolerance` at
// `distance`? SELFCOL_OK or SELFCOL_ERANGE (the limits of collider.c: every
// shape needs radius + distance <= 2^95 x tolerance and distance <= 2^45 x
// tolerance; a convex point set also its diameter + radius + distance <=
// 2^25 x tolerance). Depends on the shape only, not on the pose.
int selfcol_collider__range(const selfcol_collider *c, double distance, double tolerance);

// The contact of one triangle (corners a, b, c) with the collider, ids
// unset: 1, 0 when it is farther than `distance`, or SELFCOL_ERANGE when the
// answer cannot be given within `tolerance` (selfcol_collider__range(), or a
// triangle whose longest edge exceeds 2^47 x tolerance, or for a convex
// point set the triangle and the collider spanning more than 2^25 x
// tolerance in the triangle's frame).
int selfcol_collider__contacts_of_triangle(const selfcol_collider *col, const double *a,
                                           const double *b, const double *c, double distance,
                                           double tolerance, double (*scratch)[3],
                                           selfcol_collider_contact *out);

// A growable array of collider contacts (geometric growth: a steady state
// allocates nothing).
typedef struct selfcol_collider_contact_buffer {
    selfcol_collider_contact *items;
    size_t count, capacity;
} selfcol_collider_contact_buffer;

// Finds the triangles of hierarchy h within `distance` of collider c and
// appends their contacts (with the collider and surface ids), sorted by
// triangle, to out. `stack` holds h's node count entries and `scratch` c's
// point count. Adds the triangles given to the narrow phase to *candidates.
// SELFCOL_OK, SELFCOL_ERANGE (see selfcol_collider__contacts_of_triangle())
// or SELFCOL_ENOMEM (out keeps what it held before the call on error).
int selfcol_collider__contacts(const selfcol_collider *c, uint32_t collider_id,
                               const selfcol_hierarchy *h, uint32_t surface_id, double distance,
                               double tolerance, uint32_t *stack, double (*scratch)[3],
                               const selfcol_allocator *allocator,
                               selfcol_collider_contact_buffer *out, uint64_t *candidates);

#endif // SELFCOL_COLLIDER_H
