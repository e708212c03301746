// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Convex colliders (collider.h). Every shape is one thing to libccd: the
// convex hull of its points swept by a ball of its radius (a sphere is one
// point, a capsule two, a box eight corners, a convex point set its points),
// so one support function serves all four. A triangle's distance to the
// collider is the distance to the hull minus the radius; narrow_ccd.c finds
// the hull distance by libccd's MPR test on the hull swept by rho, by
// bisection on rho over [0, radius + distance].
//
// The normal and the closest point on the triangle: for a sphere and a
// capsule, the closed form of the point (narrow__vf) or segment
// (narrow__segment_triangle) against the triangle, whose distance the libccd
// answer is cross-checked against in tests/test_scene.c; for boxes and
// convex point sets libccd gives no closest points (libccd 2.1 has no
// distance query, see narrow_ccd.c), so the normal is the MPR penetration
// direction just past the contact and the point is MPR's contact position
// projected onto the triangle (SELFCOL_COLLIDER_APPROXIMATE).
#include "collider.h"

#include "alloc.h"
#include "box.h"
#include "narrow.h"
#include "vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int size_ok(double x) {
    return isfinite(x) && x >= 0.0 && x <= SELFCOL_MESH_MAX_COORDINATE;
}

int selfcol_collider__check(const selfcol_scene_collider_desc *desc) {
    if (!size_ok(desc->radius))
        return SELFCOL_EINVAL;
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: return desc->radius > 0.0 ? SELFCOL_OK : SELFCOL_EINVAL;
    case SELFCOL_COLLIDER_CAPSULE:
        return desc->radius > 0.0 && size_ok(desc->half_height) ? SELFCOL_OK : SELFCOL_EINVAL;
    case SELFCOL_COLLIDER_BOX:
        for (int k = 0; k < 3; ++k)
            if (!size_ok(desc->half_extents[k]))
                return SELFCOL_EINVAL;
        return SELFCOL_OK;
    case SELFCOL_COLLIDER_CONVEX:
        if (desc->points == NULL || desc->point_count == 0 ||
            desc->point_count > SELFCOL_COLLIDER_MAX_POINTS)
            return SELFCOL_EINVAL;
        for (size_t i = 0; i < 3 * desc->point_count; ++i)
            if (!isfinite(desc->points[i]) || fabs(desc->points[i]) > SELFCOL_MESH_MAX_COORDINATE)
                return SELFCOL_EINVAL;
        return SELFCOL_OK;
    default: return SELFCOL_EINVAL;
    }
}

size_t selfcol_collider__point_count(const selfcol_scene_collider_desc *desc) {
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: return 1;
    case SELFCOL_COLLIDER_CAPSULE: return 2;
    case SELFCOL_COLLIDER_BOX: return 8;
    default: return desc->point_count;
    }
}

void selfcol_collider__local_points(const selfcol_scene_collider_desc *desc, double (*local)[3]) {
    switch (desc->shape) {
    case SELFCOL_COLLIDER_SPHERE: local[0][0] = local[0][1] = local[0][2] = 0.0; break;
    case SELFCOL_COLLIDER_CAPSULE:
        for (int i = 0; i < 2; ++i) {
            local[i][0] = local[i][1] = 0.0;
            local[i][2] = i ? desc->half_height : -desc->half_height;
        }
        break;
    case SELFCOL_COLLIDER_BOX:
        for (int i = 0; i < 8; ++i)
            for (int k = 0; k < 3; ++k)
                local[i][k] = (i >> k & 1) ? desc->half_extents[k] : -desc->half_extents[k];
        break;
    default: memcpy(local, desc->points, desc->point_count * sizeof *local); break;
    }
}

void selfcol_collider__place(selfcol_collider *c, const double position[3],
                             const double rotation[9]) {
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double *r = rotation != NULL ? rotation : identity;
    for (size_t i = 0; i < c->point_count; ++i) {
        const double *p = c->local[i];
        for (int k = 0; k < 3; ++k)
            c->world[i][k] =
                r[3 * k] * p[0] + r[3 * k + 1] * p[1] + r[3 * k + 2] * p[2] + position[k];
    }
    for (int k = 0; k < 3; ++k)
        c->lo[k] = c->hi[k] = c->world[0][k];
    for (size_t i = 1; i < c->point_count; ++i)
        selfcol_box__grow_point(c->lo, c->hi, c->world[i]);
    for (int k = 0; k < 3; ++k) {
        c->lo[k] -= c->radius;
        c->hi[k] += c->radius;
    }
}

static int grow(const selfcol_allocator *al, selfcol_collider_contact_buffer *out) {
    if (out->count < out->capacity)
        return SELFCOL_OK;
    size_t cap = out->capacity < 16 ? 16 : 2 * out->capacity;
    selfcol_collider_contact *p = selfcol_alloc__array(al, cap, sizeof *p);
    if (p == NULL)
        return SELFCOL_ENOMEM;
    if (out->count > 0)
        memcpy(p, out->items, out->count * sizeof *p);
    selfcol_alloc__free_array(al, out->items, out->capacity, sizeof *out->items);
    out->items = p;
    out->capacity = cap;
    return SELFCOL_OK;
}

static int by_triangle(const void *x, const void *y) {
    const uint32_t a = ((const selfcol_collider_contact *)x)->triangle;
    const uint32_t b = ((const selfcol_collider_contact *)y)->triangle;
    return (a > b) - (a < b);
}

int selfcol_collider__contacts_of_triangle(const selfcol_collider *col, const double *a,
                                           const double *b, const double *c, double distance,
                                           double tolerance, double (*scratch)[3],
                                           selfcol_collider_contact *out) {
    double normal[3], point[3];
    const int closed_form =
        col->shape == SELFCOL_COLLIDER_SPHERE || col->shape == SELFCOL_COLLIDER_CAPSULE;
    const double hull = selfcol_narrow_ccd__hull_triangle(
        (const double(*)[3])col->world, col->point_count, a, b, c, col->radius + distance,
        tolerance, scratch, closed_form ? NULL : normal, point);
    if (!(hull <= col->radius + distance))
        return 0;
    memset(out, 0, sizeof *out);
    out->distance = hull > col->radius ? hull - col->radius : 0.0;
    if (out->distance == 0.0)
        out->flags |= SELFCOL_COLLIDER_PENETRATING;
    selfcol_narrow_result r;
    if (closed_form) {
        if (col->point_count == 1)
            selfcol_narrow__vf(col->world[0], a, b, c, &r);
        else
            selfcol_narrow__segment_triangle(col->world[0], col->world[1], a, b, c, &r);
        for (int k = 0; k < 3; ++k)
            out->normal[k] = -r.direction[k]; // r: from the triangle toward the hull
    } else {
        out->flags |= SELFCOL_COLLIDER_APPROXIMATE;
        memcpy(out->normal, normal, sizeof normal);
        selfcol_narrow__vf(point, a, b, c, &r); // MPR's point, onto the triangle
    }
    memcpy(out->wb, r.wb, sizeof out->wb);
    return 1;
}

int selfcol_collider__contacts(const selfcol_collider *c, uint32_t collider_id,
                               const selfcol_hierarchy *h, uint32_t surface_id, double distance,
                               double tolerance, uint32_t *stack, double (*scratch)[3],
                               const selfcol_allocator *allocator,
                               selfcol_collider_contact_buffer *out, uint64_t *candidates) {
    if (h->node_count == 0)
        return SELFCOL_OK;
    const selfcol_mesh *mesh = h->mesh;
    const size_t start = out->count;
    size_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const selfcol_node *node = &h->nodes[stack[--top]];
        // The float box is rounded outward: a conservative test.
        const double nlo[3] = {node->lo[0], node->lo[1], node->lo[2]};
        const double nhi[3] = {node->hi[0], node->hi[1], node->hi[2]};
        if (!selfcol_box__near(nlo, nhi, c->lo, c->hi, distance))
            continue;
        if (node->child_count > 0) {
            for (uint32_t i = 0; i < node->child_count; ++i)
                stack[top++] = node->first_child + i;
            continue;
        }
        for (uint32_t s = node->tri_begin; s < node->tri_begin + node->tri_count; ++s) {
            const uint32_t t = h->tri_order[s];
            const uint32_t *tri = mesh->triangles + 3 * (size_t)t;
            const double *p[3] = {selfcol_mesh__position(mesh, tri[0]),
                                  selfcol_mesh__position(mesh, tri[1]),
                                  selfcol_mesh__position(mesh, tri[2])};
            double tlo[3], thi[3];
            selfcol_box__of_points(tlo, thi, p, 3);
            if (!selfcol_box__near(tlo, thi, c->lo, c->hi, distance))
                continue;
            ++*candidates;
            selfcol_collider_contact contact;
            if (!selfcol_collider__contacts_of_triangle(c, p[0], p[1], p[2], distance, tolerance,
                                                        scratch, &contact))
                continue;
            if (grow(allocator, out) != SELFCOL_OK) {
                out->count = start;
                return SELFCOL_ENOMEM;
            }
            contact.collider = collider_id;
            contact.surface = surface_id;
            contact.triangle = t;
            out->items[out->count++] = contact;
        }
    }
    if (out->count > start) // (items is NULL until the first contact)
        qsort(out->items + start, out->count - start, sizeof *out->items, by_triangle);
    return SELFCOL_OK;
}
