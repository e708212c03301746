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
//
// On a context's threads (selfcol_context_refit), subtrees are refit side
// by side; see "Refit on threads" below.
#include "hierarchy/hierarchy.h"

#include "base/alloc.h"
#include "base/box.h"
#include "base/cone.h"
#include "base/parallel.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

const double selfcol_hierarchy__directions[SELFCOL_DIRECTIONS][3] = {
    {1, 1, 1},    {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1},
    {-1, -1, -1}, {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0}, {0, 0, 1},   {0, 0, -1}};

// |selfcol_hierarchy__directions[j]| of the 8 diagonals (the 6 axes: 1).
#define SQRT3 1.7320508075688772

// The next float toward -infinity (+infinity) of a finite f: what
// nextafterf(f, -INFINITY) gives, without a libm call per box bound (six per
// node at every refit). Finite floats are ordered like their magnitudes'
// bit patterns, so one step is one unit of the pattern away from zero or
// toward it; from +-0 the step is the smallest subnormal of the other sign.
static float float_below(float f) {
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    if ((bits & 0x7fffffffu) == 0)
        bits = 0x80000001u; // -smallest subnormal
    else
        bits = (bits & 0x80000000u) ? bits + 1u : bits - 1u;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static float float_above(float f) {
    return -float_below(-f);
}

// Outward rounding of a double bound to float, so float boxes stay
// conservative. x is finite and inside the float range (mesh coordinates
// are bounded by SELFCOL_MESH_MAX_COORDINATE).
static float round_down(double x) {
    float f = (float)x;
    return (double)f > x ? float_below(f) : f;
}

static float round_up(double x) {
    float f = (float)x;
    return (double)f < x ? float_above(f) : f;
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

// Bit j set when nrm . selfcol_hierarchy__directions[j] exceeds the margin
// 1e-9 |nrm| |direction j|. The directions' components are -1, 0 or 1, so
// each dot product is a signed sum of the normal's components: (+-n0 +- n1)
// +- n2 rounds exactly as the three products summed left to right would
// (products by +-1 and 0 are exact, negation commutes with rounding), and
// four sums give the eight diagonals, the opposite ones by sign.
static uint16_t direction_bits(const double nrm[3], double len) {
    const double diagonal = 1e-9 * len * SQRT3, axis = 1e-9 * len * 1.0;
    const double p = nrm[0] + nrm[1], q = nrm[0] - nrm[1];
    const double a = p + nrm[2], b = p - nrm[2], c = q + nrm[2], d = q - nrm[2];
    // Bits in the order of selfcol_hierarchy__directions.
    return (uint16_t)((a > diagonal) << 0 | (b > diagonal) << 1 | (c > diagonal) << 2 |
                      (d > diagonal) << 3 | (-d > diagonal) << 4 | (-c > diagonal) << 5 |
                      (-b > diagonal) << 6 | (-a > diagonal) << 7 | (nrm[0] > axis) << 8 |
                      (-nrm[0] > axis) << 9 | (nrm[1] > axis) << 10 | (-nrm[1] > axis) << 11 |
                      (nrm[2] > axis) << 12 | (-nrm[2] > axis) << 13);
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
            bits = direction_bits(nrm, len);
            // The exact normal is within err of the computed one: inside the
            // cone of selfcol_cone__of_normal.
            selfcol_cone one = selfcol_cone__of_normal(nrm, len, err);
            // Smallest altitude = twice the area over the longest side, with
            // the area bounded below through the same error bound.
            // Sides p1 - p0 = u, p2 - p1 and p0 - p2 = -v.
            double w[3] = {p[2][0] - p[1][0], p[2][1] - p[1][1], p[2][2] - p[1][2]};
            double l2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
            double e2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
            l2 = e2 > l2 ? e2 : l2;
            e2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            l2 = e2 > l2 ? e2 : l2;
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

// One node from its triangles (a leaf) or from its children's refit boxes,
// masks, altitudes and cones (an internal node).
static void refit_node(selfcol_hierarchy *h, size_t id) {
    selfcol_node *n = &h->nodes[id];
    if (n->child_count == 0) {
        refit_leaf(h, n, &h->min_altitude[id]);
        return;
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

// ---------------------------------------------------------------------------
// Refit on threads
//
// A node depends only on its children, so any order that refits children
// before parents gives the same floats; the threads only choose the order.
// The plan cuts the tree once, at creation: the first nodes of the
// breadth-first layout (the "cap") stay on the calling thread, and the
// subtrees hanging from the cap are tasks handed out by a counter, largest
// first (longest-processing-time order), each refit bottom-up by itself. A
// task needs no parent links and no stack: in the breadth-first layout the
// nodes of a subtree at one depth are contiguous (children of consecutive
// nodes are consecutive), so a task is a list of ranges, deepest first.
// Every node is written by one task; its children were written by the same
// task, or (for the cap) before the join.

// A worker refits at least this many triangles (starting a thread costs
// about what refitting a few hundred triangles does).
#define REFIT_MIN_TRIANGLES_PER_WORKER 4096u
// Tasks per worker: enough that the counter evens out unequal subtrees.
#define REFIT_TASKS_PER_WORKER 8u

void selfcol_hierarchy__free_plan(selfcol_hierarchy *h) {
    const selfcol_allocator *al = &h->allocator;
    size_t pairs = h->subtree_level_offset != NULL ? h->subtree_level_offset[h->subtree_count] : 0;
    selfcol_alloc__free_array(al, h->subtree_level, 2 * pairs, sizeof(uint32_t));
    selfcol_alloc__free_array(al, h->subtree_level_offset, h->subtree_count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, h->subtree_root, h->subtree_count, sizeof(uint32_t));
    h->subtree_level = h->subtree_level_offset = h->subtree_root = NULL;
    h->subtree_count = 0;
    h->cap = 0;
    h->refit_workers = 1;
    h->planned_threads = 0;
}

// The range of the nodes one level below [begin, end) (children of its
// internal nodes); empty when [begin, end) holds only leaves.
static void next_level(const selfcol_hierarchy *h, uint32_t *begin, uint32_t *end) {
    uint32_t lo = 0, hi = 0;
    for (uint32_t id = *begin; id < *end; ++id)
        if (h->nodes[id].child_count != 0) {
            lo = h->nodes[id].first_child;
            break;
        }
    for (uint32_t id = *end; id-- > *begin;)
        if (h->nodes[id].child_count != 0) {
            hi = h->nodes[id].first_child + h->nodes[id].child_count;
            break;
        }
    *begin = lo;
    *end = hi;
}

// Larger subtrees first; ties by root (any fixed order would do).
static int larger_subtree_first(const selfcol_hierarchy *h, uint32_t a, uint32_t b) {
    uint32_t ta = h->nodes[a].tri_count, tb = h->nodes[b].tri_count;
    return ta != tb ? ta > tb : a < b;
}

int selfcol_hierarchy__plan_refit(selfcol_hierarchy *h, unsigned threads) {
    const selfcol_allocator *al = &h->allocator;
    selfcol_hierarchy__free_plan(h);
    const size_t most = h->triangle_count / REFIT_MIN_TRIANGLES_PER_WORKER;
    const unsigned workers = threads < most ? threads : (unsigned)most;
    h->planned_threads = threads;
    if (workers < 2)
        return SELFCOL_OK;
    // The cap: the fewest first nodes whose children outside the cap (the
    // nodes [cap, end): breadth-first, they follow the cap) are enough tasks.
    const size_t target = (size_t)REFIT_TASKS_PER_WORKER * workers;
    size_t cap = 0, end = 1;
    while (cap < end && end - cap < target)
        end += h->nodes[cap++].child_count;
    if (cap == end)
        return SELFCOL_OK; // too few nodes to share: one thread
    const uint32_t count = (uint32_t)(end - cap);
    h->subtree_root = selfcol_alloc__array(al, count, sizeof(uint32_t));
    h->subtree_level_offset = selfcol_alloc__array(al, count + 1, sizeof(uint32_t));
    if (h->subtree_root == NULL || h->subtree_level_offset == NULL) {
        selfcol_alloc__free_array(al, h->subtree_root, count, sizeof(uint32_t));
        selfcol_alloc__free_array(al, h->subtree_level_offset, count + 1, sizeof(uint32_t));
        h->subtree_root = h->subtree_level_offset = NULL;
        return SELFCOL_ENOMEM;
    }
    // Roots, largest first (insertion sort: a few hundred at most).
    for (uint32_t t = 0; t < count; ++t) {
        uint32_t root = (uint32_t)cap + t, at = t;
        for (; at > 0 && larger_subtree_first(h, root, h->subtree_root[at - 1]); --at)
            h->subtree_root[at] = h->subtree_root[at - 1];
        h->subtree_root[at] = root;
    }
    // Levels per task, then the ranges, deepest first.
    size_t pairs = 0;
    h->subtree_level_offset[0] = 0;
    for (uint32_t t = 0; t < count; ++t) {
        uint32_t begin = h->subtree_root[t], stop = begin + 1;
        for (; begin < stop; next_level(h, &begin, &stop))
            ++pairs;
        h->subtree_level_offset[t + 1] = (uint32_t)pairs;
    }
    h->subtree_count = count;
    h->subtree_level = selfcol_alloc__array(al, 2 * pairs, sizeof(uint32_t));
    if (h->subtree_level == NULL) {
        selfcol_hierarchy__free_plan(h);
        return SELFCOL_ENOMEM;
    }
    for (uint32_t t = 0; t < count; ++t) {
        uint32_t begin = h->subtree_root[t], stop = begin + 1;
        for (uint32_t at = h->subtree_level_offset[t + 1]; begin < stop;
             next_level(h, &begin, &stop)) {
            --at;
            h->subtree_level[2 * at] = begin;
            h->subtree_level[2 * at + 1] = stop;
        }
    }
    h->cap = (uint32_t)cap;
    h->refit_workers = workers;
    return SELFCOL_OK;
}

typedef struct refit_job {
    selfcol_hierarchy *h;
    uint32_t next_task; // atomic
} refit_job;

static int refit_worker(void *context, unsigned worker) {
    (void)worker;
    refit_job *job = context;
    selfcol_hierarchy *h = job->h;
    for (;;) {
        uint32_t t = SELFCOL_ATOMIC_FETCH_ADD(&job->next_task, 1u);
        if (t >= h->subtree_count)
            return SELFCOL_OK;
        for (uint32_t l = h->subtree_level_offset[t]; l < h->subtree_level_offset[t + 1]; ++l)
            for (uint32_t id = h->subtree_level[2 * l + 1]; id-- > h->subtree_level[2 * l];)
                refit_node(h, id);
    }
}

int selfcol_hierarchy__refit(selfcol_hierarchy *h, const selfcol_executor *executor,
                             unsigned threads) {
    int status = SELFCOL_OK;
    if (threads > 1 && h->planned_threads != threads)
        status = selfcol_hierarchy__plan_refit(h, threads);
    if (status != SELFCOL_OK)
        h->planned_threads = 0; // no plan: the next refit on threads tries again
    size_t above = h->node_count;
    if (threads > 1 && h->refit_workers > 1) {
        refit_job job = {h, 0};
        // Workers that cannot be started leave their tasks to the others
        // (worker 0 runs here), so every subtree is refit before the join.
        (void)selfcol_parallel__run(executor, h->refit_workers, refit_worker, &job);
        above = h->cap;
    }
    for (size_t id = above; id-- > 0;)
        refit_node(h, id);
    h->refit_version = h->mesh->positions_version;
    return status;
}
