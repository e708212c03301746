// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries (sequence.c): the clusters, their displacement boxes,
// and the check of the proof in sequence.c (spread against what each
// cluster pair allows).
#include "frames/sequence_state.h"

#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"

#include <math.h>
#include <string.h>

// ---------------------------------------------------------------------------
// Clusters

// Clusters of mesh m from the hierarchy's triangle order (once per setup:
// any partition of the triangles serves the proof, so a hierarchy rebuilt
// over the same mesh keeps them valid), then their boxes at the reference.
// `stamps` has room for V uint32_t.
int selfcol_sequence__build_clusters(selfcol_sequence *s, int m, const selfcol_hierarchy *h,
                                     uint32_t *stamps) {
    const selfcol_mesh *mesh = h->mesh;
    cluster_set *c = &s->clusters[m];
    if (!c->ready) {
        const size_t F = mesh->triangle_count;
        const unsigned K = F < CLUSTERS ? (unsigned)F : CLUSTERS;
        if (selfcol_sequence__reserve(&s->allocator, &c->offsets, (K + 1) * sizeof(uint32_t)) !=
                SELFCOL_OK ||
            selfcol_sequence__reserve(&s->allocator, &c->vertices, 3 * F * sizeof(uint32_t)) !=
                SELFCOL_OK ||
            selfcol_sequence__reserve(&s->allocator, &c->ref_box, 6 * (size_t)K * sizeof(double)) !=
                SELFCOL_OK ||
            selfcol_sequence__reserve(&s->allocator, &c->disp_box,
                                      6 * (size_t)K * sizeof(double)) != SELFCOL_OK ||
            selfcol_sequence__reserve(&s->allocator, &c->of_triangle, F) != SELFCOL_OK)
            return SELFCOL_ENOMEM;
        c->count = K;
        uint32_t *offsets = c->offsets.data, *vertices = c->vertices.data;
        uint8_t *of_triangle = c->of_triangle.data;
        memset(stamps, 0, mesh->vertex_count * sizeof *stamps);
        uint32_t n = 0;
        for (unsigned k = 0; k < K; ++k) {
            offsets[k] = n;
            const size_t begin = F * k / K, end = F * (k + 1) / K;
            for (size_t slot = begin; slot < end; ++slot) {
                of_triangle[h->tri_order[slot]] = (uint8_t)k;
                const uint32_t *tri = mesh->triangles + 3 * (size_t)h->tri_order[slot];
                for (int i = 0; i < 3; ++i) {
                    if (stamps[tri[i]] == k + 1)
                        continue;
                    stamps[tri[i]] = k + 1;
                    vertices[n++] = tri[i];
                }
            }
        }
        offsets[K] = n;
        c->ready = 1;
    }
    const uint32_t *offsets = c->offsets.data, *vertices = c->vertices.data;
    const double *ref = s->reference[m].data;
    double *box = c->ref_box.data;
    for (unsigned k = 0; k < c->count; ++k) {
        double *lo = box + 6 * (size_t)k, *hi = lo + 3;
        lo[0] = lo[1] = lo[2] = INFINITY;
        hi[0] = hi[1] = hi[2] = -INFINITY;
        for (uint32_t i = offsets[k]; i < offsets[k + 1]; ++i) {
            const double *x = ref + 3 * (size_t)vertices[i];
            for (int a = 0; a < 3; ++a) {
                lo[a] = x[a] < lo[a] ? x[a] : lo[a];
                hi[a] = x[a] > hi[a] ? x[a] : hi[a];
            }
        }
    }
    return SELFCOL_OK;
}

// Displacement boxes of mesh m's clusters at the current positions.
static void displacement_boxes(selfcol_sequence *s, int m, const selfcol_mesh *mesh) {
    cluster_set *c = &s->clusters[m];
    const uint32_t *offsets = c->offsets.data, *vertices = c->vertices.data;
    const double *ref = s->reference[m].data, *now = mesh->positions;
    double *box = c->disp_box.data;
    for (unsigned k = 0; k < c->count; ++k) {
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t i = offsets[k]; i < offsets[k + 1]; ++i) {
            const size_t v = 3 * (size_t)vertices[i];
            for (int a = 0; a < 3; ++a) {
                const double D = now[v + (size_t)a] - ref[v + (size_t)a];
                lo[a] = D < lo[a] ? D : lo[a];
                hi[a] = D > hi[a] ? D : hi[a];
            }
        }
        memcpy(box + 6 * (size_t)k, lo, sizeof lo);
        memcpy(box + 6 * (size_t)k + 3, hi, sizeof hi);
    }
}

// Largest distance between a point of box a and one of box b (6 doubles each).
static double spread(const double *a, const double *b) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double x = a[3 + k] - b[k], y = b[3 + k] - a[k];
        const double w = x > y ? x : y;
        sum += w * w;
    }
    return sqrt(sum);
}

// Distance between box a and box b.
static double gap(const double *a, const double *b) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double x = b[k] - a[3 + k], y = a[k] - b[3 + k];
        const double w = x > y ? x : y;
        sum += w > 0.0 ? w * w : 0.0;
    }
    return sqrt(sum);
}

// What cluster pair (i, j) allows at the current reference: the gap of
// their reference boxes less d, or the skin when that is more, less the
// proof's margin (the proof above).
double selfcol_sequence__allowance(const selfcol_sequence *s, unsigned i, unsigned j) {
    const double *r0 = s->clusters[0].ref_box.data;
    const double *r1 = s->clusters[s->self ? 0 : 1].ref_box.data;
    const double apart = gap(r0 + 6 * (size_t)i, r1 + 6 * (size_t)j) / ROUND - s->distance;
    return (apart > s->skin ? apart : s->skin) - MARGIN * s->reach;
}

// The check of the proof above over every pair of clusters: the largest
// ratio of a pair's spread (plus its carry) to what the pair allows (the
// near list holds while it is below 1; INFINITY when some pair allows
// nothing). It fills the spread of every pair for the list's per-pair skips
// and for a partial rebuild. *since gets the largest ratio of a pair's
// spread since the reference to what a list taken at the reference would
// allow it, which measures how fast the surface deforms (run()); the check
// stops once that exceeds stop_above (the caller then needs no more).
double selfcol_sequence__deformation_ratio(selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                                           double stop_above, double *since) {
    const int meshes = s->self ? 1 : 2;
    for (int m = 0; m < meshes; ++m)
        displacement_boxes(s, m, mesh[m]);
    const cluster_set *c0 = &s->clusters[0], *c1 = &s->clusters[s->self ? 0 : 1];
    const double *d0 = c0->disp_box.data, *d1 = c1->disp_box.data;
    float *pair_spread = s->spread.data;
    const float *carry = s->carry.data, *allowed = s->allowed.data;
    const size_t K1 = c1->count;
    double worst = 0.0, fastest = 0.0;
    *since = INFINITY;
    for (unsigned i = 0; i < c0->count; ++i) {
        for (unsigned j = s->self ? i : 0; j < c1->count; ++j) {
            const size_t ij = i * K1 + j;
            const double moved = spread(d0 + 6 * (size_t)i, d1 + 6 * (size_t)j) * ROUND;
            const double fresh = selfcol_sequence__allowance(s, i, j);
            if (!(fresh > 0.0) || !(allowed[ij] > 0.0f))
                return INFINITY;
            // Rounded up to a float (a relative 2^-24 at most).
            const float up = (float)((moved + (double)carry[ij]) * (1.0 + 1e-6));
            pair_spread[ij] = up;
            if (s->self)
                pair_spread[(size_t)j * K1 + i] = up;
            const double r = (double)up / (double)allowed[ij], rate = moved / fresh;
            if (isnan(r) || isnan(rate))
                return INFINITY; // cannot happen below the coordinate bound; never trusted
            worst = r > worst ? r : worst;
            fastest = rate > fastest ? rate : fastest;
            if (fastest > stop_above) {
                *since = fastest;
                return worst;
            }
        }
    }
    *since = fastest;
    return worst;
}
