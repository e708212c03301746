// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Refit: boxes, curvature masks and normal cones from the current positions,
// leaves first, then every internal node from its children (children have
// larger indices, so one reverse sweep suffices). O(n), no allocation.
//
// Masks (Volino & Magnenat Thalmann 1995, 2.2.2): bit j of a triangle is set
// when its normal has a positive dot product with sample direction j; a
// node's mask is the AND of its triangles'. A non-empty mask means every
// normal of the patch lies in one open half-space. The test asks for a
// positive margin (a relative 1e-9 of |n| |dir|) so that rounding in the
// normal can never set a bit the exact normal would not; zero-area triangles
// have no normal and no bits.
//
// Cones: a node keeps an axis and a half-angle containing every unit normal
// of its patch; two cones merge into the smallest cone containing both
// (the axis turns in the plane of the two axes; cone.c). A half-angle of
// pi/2 or more means no half-space contains the normals.
#include "hierarchy.h"

#include "box.h"
#include "cone.h"

#include <math.h>

const double selfcol_hierarchy__directions[SELFCOL_DIRECTIONS][3] = {
    {1, 1, 1},    {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1},
    {-1, -1, -1}, {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1}};

// |selfcol_hierarchy__directions[j]|: sqrt(3) for the 8 diagonals, 1 for the
// 6 axes.
#define SQRT3 1.7320508075688772
static const double direction_length[SELFCOL_DIRECTIONS] = {
    SQRT3, SQRT3, SQRT3, SQRT3, SQRT3, SQRT3, SQRT3, SQRT3, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};

// Outward rounding of a double bound to float, so float boxes stay
// conservative.
static float round_down(double x) {
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}

static float round_up(double x) {
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

static void store_cone(selfcol_node *n, const selfcol_cone *c) {
    for (int k = 0; k < 3; ++k)
        n->cone_axis[k] = (float)c->axis[k];
    // Widen by a small margin for the float axis and the merges' rounding.
    n->cone_angle = c->angle >= SELFCOL_NO_CONE ? SELFCOL_NO_CONE : (float)(c->angle + 1e-6);
}

// A node's cone in double, with its float axis made unit again (the merge's
// rotation assumes unit axes).
static void load_cone(selfcol_cone *c, const selfcol_node *n) {
    if (!(n->cone_angle < SELFCOL_HALF_PI)) {
        c->axis[0] = c->axis[1] = 0.0;
        c->axis[2] = 1.0;
        c->angle = SELFCOL_NO_CONE;
        return;
    }
    selfcol_cone__unit_axis(n->cone_axis, c->axis);
    c->angle = n->cone_angle;
}

// The index of the vector of n[0..count) with the smallest dot product with
// the unit vector `axis` (the one farthest from it in angle), and that dot
// product in *lowest.
static size_t farthest_from(const double axis[3], const double (*n)[3], size_t count,
                            double *lowest) {
    size_t far = 0;
    *lowest = 2.0;
    for (size_t i = 0; i < count; ++i) {
        double dot = axis[0] * n[i][0] + axis[1] * n[i][1] + axis[2] * n[i][2];
        if (dot < *lowest)
            *lowest = dot, far = i;
    }
    return far;
}

// A cone around the leaf's unit normals n[0..count) (each known to within
// the angle slack): of two axes -- the normalised sum, and the bisector of
// the two normals farthest apart (the smallest cone when the others lie
// within it) -- the one whose farthest normal is nearer, and as half-angle
// that normal's angle plus the slack. Dot products choose, one atan2 per
// leaf measures (dots that tie to rounding differ in angle by ~1e-8 rad, far
// inside the 1e-6 rad store_cone adds). Merging triangle by triangle cost an
// acos and three sines per triangle: a quarter of a refit of a folded 20k
// ribbon.
static selfcol_cone leaf_cone(const double (*n)[3], size_t count, double slack) {
    selfcol_cone c = {{0, 0, 1}, SELFCOL_NO_CONE};
    double axes[2][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    size_t far_i = 0, far_j = 0;
    double closest = 2.0;
    for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k)
            axes[0][k] += n[i][k];
        for (size_t j = i + 1; j < count; ++j) {
            double dot = n[i][0] * n[j][0] + n[i][1] * n[j][1] + n[i][2] * n[j][2];
            if (dot < closest)
                closest = dot, far_i = i, far_j = j;
        }
    }
    for (int k = 0; k < 3; ++k)
        axes[1][k] = n[far_i][k] + n[far_j][k];
    double best = -2.0;
    size_t worst = 0;
    for (int a = 0; a < 2; ++a) {
        double len =
            sqrt(axes[a][0] * axes[a][0] + axes[a][1] * axes[a][1] + axes[a][2] * axes[a][2]);
        if (!(len > 1e-6))
            continue; // (nearly) opposite normals: no axis here
        for (int k = 0; k < 3; ++k)
            axes[a][k] /= len;
        double lowest;
        size_t far = farthest_from(axes[a], n, count, &lowest);
        if (lowest > best) {
            best = lowest;
            worst = far;
            for (int k = 0; k < 3; ++k)
                c.axis[k] = axes[a][k];
        }
    }
    if (!(best > 0.0))
        return c; // no open half-space around either axis holds them
    c.angle = selfcol_cone__angle_between(c.axis, n[worst]) + slack;
    if (!(c.angle < SELFCOL_HALF_PI))
        c.angle = SELFCOL_NO_CONE;
    return c;
}

static void refit_leaf(const selfcol_hierarchy *h, selfcol_node *n, float *altitude_out) {
    const selfcol_mesh *m = h->mesh;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    uint16_t mask = (1u << SELFCOL_DIRECTIONS) - 1u;
    double min_altitude = INFINITY;
    // Unit normals for leaf_cone, and whether every triangle has a usable
    // cone (the build bounds a leaf's size; the validator checks it).
    double unit[SELFCOL_LEAF_MAX_TRIANGLES][3];
    double slack = 0.0;
    int coned = n->tri_count <= SELFCOL_LEAF_MAX_TRIANGLES;
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s) {
        const uint32_t *tri = m->triangles + 3 * (size_t)h->tri_order[s];
        const double *p[3] = {selfcol_mesh__position(m, tri[0]), selfcol_mesh__position(m, tri[1]),
                              selfcol_mesh__position(m, tri[2])};
        for (int i = 0; i < 3; ++i)
            selfcol_box__grow_point(lo, hi, p[i]);
        double u[3], v[3], nrm[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = p[1][k] - p[0][k];
            v[k] = p[2][k] - p[0][k];
        }
        nrm[0] = u[1] * v[2] - u[2] * v[1];
        nrm[1] = u[2] * v[0] - u[0] * v[2];
        nrm[2] = u[0] * v[1] - u[1] * v[0];
        // Bound on |computed normal - exact normal|: each component is a
        // difference of two products of rounded differences, so its error is
        // below 4 eps (|p1| + |p2|) to first order; 8 eps covers the rest.
        double err = 0x1p-50 * (fabs(u[1] * v[2]) + fabs(u[2] * v[1]) + fabs(u[2] * v[0]) +
                                fabs(u[0] * v[2]) + fabs(u[0] * v[1]) + fabs(u[1] * v[0]));
        if (h->owned[h->tri_order[s]] & SELFCOL_TRIANGLE_FLIPPED)
            for (int k = 0; k < 3; ++k)
                nrm[k] = -nrm[k];
        double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
        uint16_t bits = 0;
        if (len > 0.0) {
            for (int j = 0; j < SELFCOL_DIRECTIONS; ++j) {
                const double *d = selfcol_hierarchy__directions[j];
                if (nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] >
                    1e-9 * len * direction_length[j])
                    bits |= (uint16_t)(1u << j);
            }
            // The exact normal is within err of the computed one: inside the
            // cone of selfcol_cone__of_normal.
            selfcol_cone one = selfcol_cone__of_normal(nrm, len, err);
            // Smallest altitude = twice the area over the longest side, with
            // the area bounded below through the same error bound.
            double l2 = 0.0;
            for (int i = 0; i < 3; ++i) {
                double e2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    double x = p[(i + 1) % 3][k] - p[i][k];
                    e2 += x * x;
                }
                l2 = e2 > l2 ? e2 : l2;
            }
            double altitude = (len - err) / (sqrt(l2) * (1.0 + 1e-12)) * (1.0 - 1e-12);
            min_altitude = altitude < min_altitude ? altitude : min_altitude;
            if (one.angle >= SELFCOL_NO_CONE)
                coned = 0;
            if (coned) {
                for (int k = 0; k < 3; ++k)
                    unit[s - n->tri_begin][k] = one.axis[k];
                slack = one.angle > slack ? one.angle : slack;
            }
        } else {
            coned = 0;
            min_altitude = 0.0;
        }
        mask &= bits;
    }
    const selfcol_cone none = {{0, 0, 1}, SELFCOL_NO_CONE};
    const selfcol_cone acc =
        coned ? leaf_cone((const double(*)[3])unit, n->tri_count, slack) : none;
    for (int k = 0; k < 3; ++k) {
        n->lo[k] = round_down(lo[k]);
        n->hi[k] = round_up(hi[k]);
    }
    n->mask = mask;
    store_cone(n, &acc);
    *altitude_out = min_altitude > 0.0 ? round_down(min_altitude) : 0.0f;
}

void selfcol_hierarchy__refit(selfcol_hierarchy *h) {
    for (size_t id = h->node_count; id-- > 0;) {
        selfcol_node *n = &h->nodes[id];
        if (n->child_count == 0) {
            refit_leaf(h, n, &h->min_altitude[id]);
            continue;
        }
        const selfcol_node *c = &h->nodes[n->first_child];
        *n = (selfcol_node){.first_child = n->first_child,
                            .tri_begin = n->tri_begin,
                            .tri_count = n->tri_count,
                            .boundary_begin = n->boundary_begin,
                            .boundary_count = n->boundary_count,
                            .child_count = n->child_count,
                            .flags = n->flags};
        for (int k = 0; k < 3; ++k) {
            n->lo[k] = c->lo[k];
            n->hi[k] = c->hi[k];
        }
        n->mask = c->mask;
        h->min_altitude[id] = h->min_altitude[n->first_child];
        selfcol_cone acc;
        load_cone(&acc, c);
        for (uint32_t i = 1; i < n->child_count; ++i) {
            const selfcol_node *ci = &h->nodes[n->first_child + i];
            selfcol_box__merge_float(n->lo, n->hi, ci->lo, ci->hi);
            n->mask &= ci->mask;
            float alt = h->min_altitude[n->first_child + i];
            if (alt < h->min_altitude[id])
                h->min_altitude[id] = alt;
            selfcol_cone other;
            load_cone(&other, ci);
            selfcol_cone__merge(&acc, &other);
        }
        store_cone(n, &acc);
    }
    h->refit_version = h->mesh->positions_version;
}
