// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The hierarchy's invariants, checked in full: what the traversal, the
// ownership rule and the contour proof take for granted. Run after every build
// and refit in SELFCOL_VALIDATE builds (the sanitizer job of CI), and by the
// tests directly. O(n) time for the structure and boxes, O(n x depth) for
// the normal cones; one byte per triangle of scratch.
#include "hierarchy/hierarchy.h"

#include "base/alloc.h"
#include "base/cone.h"
#include "base/core.h"
#include "base/vec3.h"

#include <math.h>
#include <string.h>

// Checks of the structure alone (valid after the build, before any refit).
static int structure_valid(const selfcol_hierarchy *h, uint8_t *seen) {
    const size_t F = h->triangle_count, N = h->node_count;
    if (N == 0 || h->nodes[0].tri_begin != 0 || h->nodes[0].tri_count != F)
        return 0;
    // tri_order is a permutation of the triangles.
    memset(seen, 0, F);
    for (size_t s = 0; s < F; ++s) {
        uint32_t t = h->tri_order[s];
        if (t >= F || seen[t])
            return 0;
        seen[t] = 1;
    }
    size_t leaves = 0;
    for (size_t id = 0; id < N; ++id) {
        const selfcol_node *n = &h->nodes[id];
        if ((size_t)n->tri_begin + n->tri_count > F || n->tri_count == 0)
            return 0;
        const uint8_t f = n->flags;
        // A disk is connected and oriented; the build never sets a flag
        // outside the four it knows.
        if ((f & ~(SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED | SELFCOL_NODE_BAD_BOUNDARY |
                   SELFCOL_NODE_DISK | SELFCOL_NODE_DUPLICATES)) ||
            ((f & SELFCOL_NODE_DISK) && (f & (SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED)) !=
                                            (SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED)))
            return 0;
        if (n->child_count == 0) {
            leaves++;
            if (n->boundary_count != 0 || n->tri_count > SELFCOL_LEAF_MAX_TRIANGLES)
                return 0;
            continue;
        }
        // Children: after their parent (breadth-first), contiguous, and their
        // triangle ranges tile the parent's in order.
        if (n->first_child <= id || (size_t)n->first_child + n->child_count > N ||
            n->child_count < 2)
            return 0;
        uint32_t next = n->tri_begin;
        for (uint32_t i = 0; i < n->child_count; ++i) {
            const selfcol_node *c = &h->nodes[n->first_child + i];
            if (c->tri_begin != next)
                return 0;
            next += c->tri_count;
            // An unoriented child makes its parent unoriented.
            if ((f & SELFCOL_NODE_ORIENTED) && !(c->flags & SELFCOL_NODE_ORIENTED))
                return 0;
        }
        if (next != n->tri_begin + n->tri_count)
            return 0;
        if ((size_t)n->boundary_begin + n->boundary_count > h->bedge_total)
            return 0;
    }
    return leaves == h->leaf_count;
}

// Boxes after a refit: a leaf's box holds its triangles' corners, a parent's
// box holds its children's boxes.
static int boxes_valid(const selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    for (size_t id = 0; id < h->node_count; ++id) {
        const selfcol_node *n = &h->nodes[id];
        for (int k = 0; k < 3; ++k)
            if (!(n->lo[k] <= n->hi[k]))
                return 0;
        if (n->child_count == 0) {
            for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s) {
                const uint32_t *tri = m->triangles + 3 * (size_t)h->tri_order[s];
                for (int i = 0; i < 3; ++i) {
                    const double *p = selfcol_mesh__position(m, tri[i]);
                    for (int k = 0; k < 3; ++k)
                        if (!((double)n->lo[k] <= p[k] && p[k] <= (double)n->hi[k]))
                            return 0;
                }
            }
            continue;
        }
        for (uint32_t i = 0; i < n->child_count; ++i) {
            const selfcol_node *c = &h->nodes[n->first_child + i];
            for (int k = 0; k < 3; ++k)
                if (c->lo[k] < n->lo[k] || c->hi[k] > n->hi[k])
                    return 0;
        }
    }
    return 1;
}

// Every node's normal cone holds the unit normal of each of its triangles
// (oriented as the build flipped them), and a node with a triangle of zero
// area has no cone. O(n x depth): this recomputes each normal once per node
// above it, independently of the refit's bounds.
static int cones_valid(const selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    for (size_t id = 0; id < h->node_count; ++id) {
        const selfcol_node *n = &h->nodes[id];
        if (!(n->cone_angle < SELFCOL_HALF_PI))
            continue;
        double axis[3];
        selfcol_cone__unit_axis(n->cone_axis, axis);
        // The stored angle already holds the refit's 1e-6 rad of slack;
        // 1e-12 in the cosine only absorbs this check's own rounding.
        const double lowest = cos((double)n->cone_angle) - 1e-12;
        for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s) {
            const uint32_t t = h->tri_order[s];
            const uint32_t *tri = m->triangles + 3 * (size_t)t;
            double normal[3];
            vec3_triangle_normal(normal, selfcol_mesh__position(m, tri[0]),
                                 selfcol_mesh__position(m, tri[1]),
                                 selfcol_mesh__position(m, tri[2]));
            double len = sqrt(vec3_dot(normal, normal));
            if (!(len > 0.0))
                return 0; // a zero-area triangle under a cone
            const double sign = (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED) ? -1.0 : 1.0;
            double dot = sign * vec3_dot(axis, normal) / len;
            if (!(dot >= lowest))
                return 0;
        }
    }
    return 1;
}

int selfcol_hierarchy__validate(const selfcol_hierarchy *h, int refit) {
    // The scratch comes from the system allocator, not the handle's: a
    // validation build must make the same calls to the caller's allocator
    // as any other (the tests count them).
    const selfcol_allocator system = {NULL, NULL, NULL};
    const size_t n = h->triangle_count ? h->triangle_count : 1;
    uint8_t *seen = selfcol_alloc__array(&system, n, sizeof(uint8_t));
    if (seen == NULL)
        return -1; // cannot tell
    int valid = structure_valid(h, seen) && (!refit || (boxes_valid(h) && cones_valid(h)));
    selfcol_alloc__free_array(&system, seen, n, sizeof(uint8_t));
    return valid;
}
