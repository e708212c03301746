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
// (the axis turns in the plane of the two axes). A half-angle of pi/2 or more
// means no half-space contains the normals.
#include "hierarchy.h"

#include <math.h>

#define NO_CONE 4.0f // any half-angle >= pi/2 means "no cone"
#define HALF_PI 1.5707963267948966

const double selfcol_hierarchy__directions[SELFCOL_DIRECTIONS][3] = {
    {1, 1, 1},    {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1},
    {-1, -1, -1}, {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1}};

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

typedef struct cone {
    double axis[3];
    double angle;
} cone;

static void cone_merge(cone *a, const cone *b) {
    if (a->angle >= NO_CONE || b->angle >= NO_CONE) {
        a->angle = NO_CONE;
        return;
    }
    double c = a->axis[0] * b->axis[0] + a->axis[1] * b->axis[1] + a->axis[2] * b->axis[2];
    double phi = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
    if (phi + b->angle <= a->angle)
        return;
    if (phi + a->angle <= b->angle) {
        *a = *b;
        return;
    }
    double angle = 0.5 * (a->angle + phi + b->angle);
    if (angle >= HALF_PI || !(phi > 0.0)) {
        a->angle = NO_CONE;
        return;
    }
    // Rotate a's axis toward b's by (angle - a->angle) in their common plane.
    double t = (angle - a->angle) / phi;
    double s0 = sin((1.0 - t) * phi) / sin(phi), s1 = sin(t * phi) / sin(phi);
    double len = 0.0;
    for (int k = 0; k < 3; ++k) {
        a->axis[k] = s0 * a->axis[k] + s1 * b->axis[k];
        len += a->axis[k] * a->axis[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; ++k)
        a->axis[k] /= len;
    a->angle = angle;
}

static void store_cone(selfcol_node *n, const cone *c) {
    for (int k = 0; k < 3; ++k)
        n->cone_axis[k] = (float)c->axis[k];
    // Widen by a small margin for the float axis and the merges' rounding.
    n->cone_angle = c->angle >= NO_CONE ? NO_CONE : (float)(c->angle + 1e-6);
}

static void load_cone(cone *c, const selfcol_node *n) {
    for (int k = 0; k < 3; ++k)
        c->axis[k] = n->cone_axis[k];
    c->angle = n->cone_angle;
}

static void refit_leaf(const selfcol_hierarchy *h, selfcol_node *n, float *altitude_out) {
    const selfcol_mesh *m = h->mesh;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    uint16_t mask = (1u << SELFCOL_DIRECTIONS) - 1u;
    cone acc = {{0, 0, 1}, NO_CONE};
    double min_altitude = INFINITY;
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s) {
        const uint32_t *tri = m->triangles + 3 * (size_t)h->tri_order[s];
        const double *p[3] = {selfcol_mesh__position(m, tri[0]), selfcol_mesh__position(m, tri[1]),
                              selfcol_mesh__position(m, tri[2])};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < 3; ++i) {
                lo[k] = p[i][k] < lo[k] ? p[i][k] : lo[k];
                hi[k] = p[i][k] > hi[k] ? p[i][k] : hi[k];
            }
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
                double dn = sqrt(fabs(d[0]) + fabs(d[1]) + fabs(d[2])); // |d|
                if (nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] > 1e-9 * len * dn)
                    bits |= (uint16_t)(1u << j);
            }
            // The exact normal is within err of the computed one: within an
            // angle asin(err / len) < 1.5 err / len of it (err < len / 100).
            cone one = {{nrm[0] / len, nrm[1] / len, nrm[2] / len},
                        err < 0.01 * len ? 1.5 * err / len + 1e-12 : NO_CONE};
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
            if (s == n->tri_begin)
                acc = one;
            else
                cone_merge(&acc, &one);
        } else {
            acc.angle = NO_CONE;
            min_altitude = 0.0;
        }
        mask &= bits;
        if (len == 0.0)
            acc.angle = NO_CONE;
    }
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
        cone acc;
        load_cone(&acc, c);
        for (uint32_t i = 1; i < n->child_count; ++i) {
            const selfcol_node *ci = &h->nodes[n->first_child + i];
            for (int k = 0; k < 3; ++k) {
                n->lo[k] = ci->lo[k] < n->lo[k] ? ci->lo[k] : n->lo[k];
                n->hi[k] = ci->hi[k] > n->hi[k] ? ci->hi[k] : n->hi[k];
            }
            n->mask &= ci->mask;
            float alt = h->min_altitude[n->first_child + i];
            if (alt < h->min_altitude[id])
                h->min_altitude[id] = alt;
            cone other;
            load_cone(&other, ci);
            cone_merge(&acc, &other);
        }
        store_cone(n, &acc);
    }
    h->refit_version = h->mesh->positions_version;
}
