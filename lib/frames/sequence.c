// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries over a sequence of frames (include/selfcol/sequence.h):
// a Verlet list (the neighbour lists of molecular dynamics, kept with a
// "skin") whose validity is proven from the surface's deformation rather
// than its displacement.
//
// Proof. Let the reference be the positions at the last rebuild, R = d + s,
// and D(v) = x(v) - x_ref(v). A point p of a primitive is a convex
// combination of its vertices, so D(p) is the same combination of their D
// and lies in the box of D over any vertex set holding them. Take a primitive
// pair (P, Q) of the query's kinds that is not in the near list:
//  - VF, EE: the closed form at the reference said dist >= R, so the true
//    distance was at least R (1 - 1e-9) (contacts.h's relative band);
//  - EF: the edge e did not cross t, and its ends' VF distances to t and its
//    EE distances to t's edges were all >= R; a segment that does not meet a
//    triangle is nearest to it at one of its ends or at one of the
//    triangle's edges, so dist(e, t) >= R (1 - 1e-9) too.
// Let I be a cluster holding a triangle of P (all of P's vertices are in I's
// vertex set) and J one holding Q's. Now
//   dist_now(P, Q) >= dist_ref(P, Q) - max |D(p) - D(q)|
//                  >= max(R (1 - 1e-9), gap_ref(I, J)) - spread(I, J),
// where gap_ref is the distance between the clusters' boxes at the
// reference and spread(I, J) the largest distance between a point of I's
// displacement box and one of J's (per axis max(hi_I - lo_J, hi_J - lo_I)).
// When spread(I, J) <= max(s, gap_ref(I, J) - d) - 1e-6 R for every pair of
// clusters, dist_now(P, Q) > d (1 + 1e-9): the fresh query, whose closed
// forms err by less than that band, does not report (P, Q) either. So the
// fresh query's records are exactly those of the near list's pairs that the
// same closed forms, called here on the same positions through the same
// functions (pairs.h), report now; the list is kept in record order, so they
// come out sorted.
//
// A rebuild runs the ordinary query (the caller's exact method) at distance
// R with the closed-form narrow phase, lists its VF and EE records (those
// kinds asked) and, for EF, the edge-triangle pairs the proof needs: its EF
// records, and for each VF record (v, t) the edges at v, for each EE record
// (e, f) the pairs (e, t) with t at f and (f, t') with t' at e (no shared
// vertex for a self query, no repeated triangle).
//
// Partial rebuilds. When the check fails, usually only a few cluster pairs
// fail (crumpling 20k sheet: 86 of 8,256, holding 7 % of the list), so only
// the pairs whose spread has used PARTIAL_SHARE of what they allow are
// queried again; the others keep their near pairs. Every cluster takes the
// current positions x1 as its new reference, and a kept pair (I, J) keeps
// the proof of its old reference x0 through a carry: with D0 = x - x0, D1 =
// x - x1 and Delta = x1 - x0 = D0 - D1, for p in I and q in J
//   |D0(p) - D0(q)| <= |D1(p) - D1(q)| + |Delta(p) - Delta(q)|,
// so spread0(I, J) <= spread1(I, J) + carry(I, J), the carry being the
// pair's spread at the rebuild (carries add up over several rebuilds). Each
// cluster pair therefore keeps what it allows (`allowed`, from the gap at
// its own reference) and its carry, and the check and the per-pair skip use
// spread + carry. The pairs queried again get carry 0 and the allowance of
// the new reference. A kept pair may take the new allowance too where it is
// larger: that happens only when gap1 - d exceeds the skin, and then
// spread1 <= spread1 + carry <= gap1 - d - margin proves by the first
// argument, from x1 alone, that no pair of (I, J) is within d.
// The query of a partial rebuild is the ordinary one restricted to the node
// pairs that can hold what the re-queried pairs need (query.h's node
// filter). A near pair belongs to the cluster pair of its primitives' owner
// triangles: a vertex's or an edge's first triangle (tag_clusters), which is
// also its owner in the pair tests (hierarchy_orient.c), and they generate a
// VF or EE record from the triangle pair of its primitives' owners, an EF
// record from the edge's owner and the triangle. A pair (P, Q) owned by
// (I, J) is so found from a triangle pair in I x J. An EF candidate (e, t)
// owned by (I, J) comes from the records (v, t) of e's ends, (e, f) of t's
// edges and (f, t') for t' at e, and (e, t) itself, whose owner triangles
// share a vertex with e's owner (in I) and with t (in J). So the query keeps
// a node pair (A, B) when A holds a triangle that shares a vertex with a
// triangle of I, and B one with J, for some re-queried (I, J) (node_masks);
// its records that belong to kept pairs are dropped.
#include "frames/sequence.h"

#include "base/alloc.h"
#include "base/box.h"
#include "base/core.h"
#include "base/parallel.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/pairs.h"
#include "query/query.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Clusters per mesh: contiguous runs of the hierarchy's triangle order (its
// depth-first leaf order keeps them compact). The check costs the clusters'
// displacement boxes (one pass over the vertices) and CLUSTERS^2 / 2 box
// pairs.
#define CLUSTERS 128 // at most 256: a cluster's index is a byte (near_pair.tag)

// Relative margin of the check (the proof above).
#define MARGIN 1e-6

// A rebuild pays when the new list is expected to last this many frames
// (run()'s policy).
#define REBUILD_LIFE 3.0

// A partial rebuild queries again the cluster pairs whose spread has used
// this share of what they allow (the pair that failed and those about to).
#define PARTIAL_SHARE 0.5

// ... unless those pairs hold more than this share of the near list: then
// the surface deforms all over, and a full rebuild costs less (no filter,
// no merge) and leaves no carries (crumpling 20k sheet, 40 frames: 43.5
// against 42.2 ms a frame with partial rebuilds only).
#define PARTIAL_MOST 0.5

// Sets of clusters as bits: words per set.
#define MASK_WORDS ((CLUSTERS + 63) / 64)

// The computed spread and gap err by a few ulps of their size: 1e-12
// relative covers it many times over.
#define ROUND (1.0 + 1e-12)

// What the sequence holds: nothing; a reference (positions and clusters)
// from a fresh frame; or a reference and its near list.
enum { STATE_NONE = 0, STATE_TRACKING = 1, STATE_LIST = 2 };

// One pair of the near list: kind and meshes in `tag` (kind << 2 |
// first_mesh << 1 | second_mesh, then the clusters of the first and second
// primitive in bits 8-15 and 16-23), the primitives as in selfcol_contact,
// and a lower bound of their distance at the reference (EF: of the edge's
// distance to the triangle, 0 when it crossed). A pair whose bound, less
// the spread of its two clusters' displacements, still exceeds d (0 for
// EF) cannot be a contact now (the proof above, for this one pair): it is
// skipped without a closed form.
typedef struct near_pair {
    uint32_t tag;
    uint32_t first, second;
    float near;
} near_pair;

#define TAG_KIND(tag) ((tag) >> 2 & 3u)
#define TAG_FIRST_MESH(tag) ((tag) >> 1 & 1u)
#define TAG_SECOND_MESH(tag) ((tag)&1u)
#define TAG_FIRST_CLUSTER(tag) ((tag) >> 8 & 0xffu)
#define TAG_SECOND_CLUSTER(tag) ((tag) >> 16 & 0xffu)

// A growable array: bytes held.
typedef struct buffer {
    void *data;
    size_t bytes;
} buffer;

typedef struct cluster_set {
    int ready; // the clusters of the current setup are built
    unsigned count;
    buffer of_triangle; // uint8_t per triangle: its cluster
    buffer offsets;     // count + 1 uint32_t into vertices
    buffer vertices;    // uint32_t, each cluster's vertex set
    buffer ref_box;     // 6 doubles per cluster: lo, hi of the reference positions
    buffer disp_box;    // 6 doubles per cluster: lo, hi of the displacements now
} cluster_set;

struct selfcol_sequence {
    selfcol_allocator allocator;
    double skin_option; // 0: automatic

    // What the reference and near list were taken for (valid unless state
    // is STATE_NONE).
    int state;
    uint64_t frames_since_reference;
    int self;
    selfcol_mesh_identity identity[2];
    double distance, skin, reach;
    uint32_t kinds, narrow, method;

    buffer reference[2]; // 3 V doubles per mesh
    cluster_set clusters[2];
    buffer pairs; // near_pair, in record order
    // Per cluster pair (first mesh's x second's; both orders for a self
    // query): its spread since its reference plus its carry, rounded up; its
    // carry from the references before (partial rebuilds), rounded up; what
    // it allows, from the gap at its own reference, rounded down (0: nothing).
    buffer spread, carry, allowed;
    size_t pair_count;
    buffer masks; // uint64_t: a partial rebuild's node masks (partial_filter)
    // A partial rebuild's choice: per cluster of the first mesh, its
    // re-queried partners in the second (partial_filter).
    uint64_t partners[CLUSTERS * MASK_WORDS];
    // The last query was a partial rebuild (selfcol_sequence__check_partial).
    int partial_checkable;
    buffer stamps; // rebuild: a uint32_t per vertex (the clusters' vertex sets)

    selfcol_sequence_run_stats stats;
};

// At least `bytes` in b, growing geometrically; the first `keep` bytes of
// the old content are copied.
static int reserve_keep(const selfcol_allocator *a, buffer *b, size_t bytes, size_t keep) {
    if (bytes <= b->bytes)
        return SELFCOL_OK;
    size_t want = b->bytes + b->bytes / 2;
    want = want > bytes ? want : bytes;
    void *grown = selfcol_alloc__raw(a, want);
    if (grown == NULL)
        return SELFCOL_ENOMEM;
    if (keep > 0)
        memcpy(grown, b->data, keep);
    selfcol_alloc__free(a, b->data, b->bytes);
    b->data = grown;
    b->bytes = want;
    return SELFCOL_OK;
}

static int reserve(const selfcol_allocator *a, buffer *b, size_t bytes) {
    return reserve_keep(a, b, bytes, 0);
}

static void release(const selfcol_allocator *a, buffer *b) {
    selfcol_alloc__free(a, b->data, b->bytes);
    b->data = NULL;
    b->bytes = 0;
}

int selfcol_sequence_options_init(selfcol_sequence_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_SEQUENCE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

int selfcol_sequence_create(selfcol_sequence **out, const selfcol_sequence_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK_VERSION(opts, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    selfcol_sequence_options o;
    selfcol_sequence_options_init(&o, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    if (opts != NULL) {
        o.allocator = opts->allocator;
        o.skin = opts->skin;
    }
    SELFCOL_CHECK(selfcol_alloc__valid(&o.allocator));
    SELFCOL_CHECK(isfinite(o.skin) && o.skin >= 0.0 && o.skin <= SELFCOL_MESH_MAX_COORDINATE);
    selfcol_sequence *s = selfcol_alloc__raw(&o.allocator, sizeof *s);
    if (s == NULL)
        return SELFCOL_ENOMEM;
    memset(s, 0, sizeof *s);
    s->allocator = o.allocator;
    s->skin_option = o.skin;
    s->stats.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
    *out = s;
    return SELFCOL_OK;
}

void selfcol_sequence_destroy(selfcol_sequence *s) {
    if (s == NULL)
        return;
    const selfcol_allocator a = s->allocator;
    for (int m = 0; m < 2; ++m) {
        release(&a, &s->reference[m]);
        release(&a, &s->clusters[m].offsets);
        release(&a, &s->clusters[m].vertices);
        release(&a, &s->clusters[m].ref_box);
        release(&a, &s->clusters[m].disp_box);
        release(&a, &s->clusters[m].of_triangle);
    }
    release(&a, &s->pairs);
    release(&a, &s->spread);
    release(&a, &s->carry);
    release(&a, &s->allowed);
    release(&a, &s->masks);
    release(&a, &s->stamps);
    selfcol_alloc__free(&a, s, sizeof *s);
}

void selfcol_sequence_reset(selfcol_sequence *s) {
    if (s == NULL)
        return;
    s->state = STATE_NONE;
    memset(&s->stats, 0, sizeof s->stats);
    s->stats.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
}

int selfcol_sequence_stats(const selfcol_sequence *s, selfcol_sequence_run_stats *stats) {
    SELFCOL_CHECK(s != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_SEQUENCE_RUN_STATS_VERSION)
        return SELFCOL_EVERSION;
    *stats = s->stats;
    return SELFCOL_OK;
}

size_t selfcol_sequence_byte_count(const selfcol_sequence *s) {
    if (s == NULL)
        return 0;
    size_t bytes = sizeof *s + s->pairs.bytes + s->stamps.bytes + s->spread.bytes + s->carry.bytes +
                   s->allowed.bytes + s->masks.bytes;
    for (int m = 0; m < 2; ++m) {
        const cluster_set *c = &s->clusters[m];
        bytes += s->reference[m].bytes + c->offsets.bytes + c->vertices.bytes + c->ref_box.bytes +
                 c->disp_box.bytes + c->of_triangle.bytes;
    }
    return bytes;
}

// ---------------------------------------------------------------------------
// Clusters

// Clusters of mesh m from the hierarchy's triangle order (once per setup:
// any partition of the triangles serves the proof, so a hierarchy rebuilt
// over the same mesh keeps them valid), then their boxes at the reference.
// `stamps` has room for V uint32_t.
static int build_clusters(selfcol_sequence *s, int m, const selfcol_hierarchy *h,
                          uint32_t *stamps) {
    const selfcol_mesh *mesh = h->mesh;
    cluster_set *c = &s->clusters[m];
    if (!c->ready) {
        const size_t F = mesh->triangle_count;
        const unsigned K = F < CLUSTERS ? (unsigned)F : CLUSTERS;
        if (reserve(&s->allocator, &c->offsets, (K + 1) * sizeof(uint32_t)) != SELFCOL_OK ||
            reserve(&s->allocator, &c->vertices, 3 * F * sizeof(uint32_t)) != SELFCOL_OK ||
            reserve(&s->allocator, &c->ref_box, 6 * (size_t)K * sizeof(double)) != SELFCOL_OK ||
            reserve(&s->allocator, &c->disp_box, 6 * (size_t)K * sizeof(double)) != SELFCOL_OK ||
            reserve(&s->allocator, &c->of_triangle, F) != SELFCOL_OK)
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
static double allowance(const selfcol_sequence *s, unsigned i, unsigned j) {
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
static double deformation_ratio(selfcol_sequence *s, const selfcol_mesh *const mesh[2],
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
            const double fresh = allowance(s, i, j);
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

// ---------------------------------------------------------------------------
// The near list

static uint32_t tag_of(uint32_t kind, uint32_t first_mesh, uint32_t second_mesh) {
    return kind << 2 | first_mesh << 1 | second_mesh;
}

// A float at most x >= 0.
static float float_below(double x) {
    float f = (float)x;
    return (double)f > x ? nextafterf(f, 0.0f) : f;
}

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

// EF candidates derived from one record of the reach set (the proof above).
static size_t ef_candidates(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                            const selfcol_contact *r, near_pair *out) {
    size_t n = 0;
    const int self = s->self;
    // The record's distance bounds the candidate's from above; the smallest
    // over its repeats is its distance (sort_unique), since every component
    // below R is a record.
    const float near = float_below(r->distance);
    if (r->kind == SELFCOL_CONTACT_EF) {
        out[n++] = (near_pair){tag_of(SELFCOL_CONTACT_EF, r->first_mesh, r->second_mesh), r->first,
                               r->second, 0.0f};
    } else if (r->kind == SELFCOL_CONTACT_VF) {
        // Every edge at vertex v against triangle t.
        const selfcol_mesh *mv = mesh[r->first_mesh], *mt = mesh[r->second_mesh];
        const uint32_t v = r->first;
        const uint32_t *tri = mt->triangles + 3 * (size_t)r->second;
        const uint32_t tag = tag_of(SELFCOL_CONTACT_EF, r->first_mesh, r->second_mesh);
        for (uint32_t k = mv->vertex_tri_offsets[v]; k < mv->vertex_tri_offsets[v + 1]; ++k) {
            const uint32_t u = mv->vertex_tris[k];
            for (int i = 0; i < 3; ++i) {
                const uint32_t e = mv->triangle_edges[3 * (size_t)u + (size_t)i];
                if (e == SELFCOL_INVALID_INDEX)
                    continue;
                const uint32_t *ev = mv->edges + 2 * (size_t)e;
                if (ev[0] != v && ev[1] != v)
                    continue;
                if (self && (is_corner(ev[0], tri) || is_corner(ev[1], tri)))
                    continue;
                out[n++] = (near_pair){tag, e, r->second, near};
            }
        }
    } else {
        // (e, t) for t at f, and (f, t') for t' at e.
        for (int side = 0; side < 2; ++side) {
            const uint32_t me = side == 0 ? r->first_mesh : r->second_mesh;
            const uint32_t mt = side == 0 ? r->second_mesh : r->first_mesh;
            const uint32_t e = side == 0 ? r->first : r->second;
            const uint32_t f = side == 0 ? r->second : r->first;
            const selfcol_mesh *M = mesh[mt];
            const uint32_t *ev = mesh[me]->edges + 2 * (size_t)e;
            for (uint32_t k = M->edge_tri_offsets[f]; k < M->edge_tri_offsets[f + 1]; ++k) {
                const uint32_t t = M->edge_tris[k];
                if (M->triangle_flags[t] & SELFCOL_TRIANGLE_DUPLICATE)
                    continue;
                const uint32_t *tri = M->triangles + 3 * (size_t)t;
                if (self && (is_corner(ev[0], tri) || is_corner(ev[1], tri)))
                    continue;
                out[n++] = (near_pair){tag_of(SELFCOL_CONTACT_EF, me, mt), e, t, near};
            }
        }
    }
    return n;
}

// Most EF candidates one record yields: the triangles at a vertex times 3
// (VF), or the triangles at both edges (EE).
static size_t ef_bound(const selfcol_mesh *const mesh[2], const selfcol_contact *r) {
    if (r->kind == SELFCOL_CONTACT_EF)
        return 1;
    if (r->kind == SELFCOL_CONTACT_VF) {
        const selfcol_mesh *mv = mesh[r->first_mesh];
        return 3 *
               (size_t)(mv->vertex_tri_offsets[r->first + 1] - mv->vertex_tri_offsets[r->first]);
    }
    const selfcol_mesh *m0 = mesh[r->first_mesh], *m1 = mesh[r->second_mesh];
    return (size_t)(m1->edge_tri_offsets[r->second + 1] - m1->edge_tri_offsets[r->second]) +
           (size_t)(m0->edge_tri_offsets[r->first + 1] - m0->edge_tri_offsets[r->first]);
}

// Sorts the n EF candidates at p and drops repeats; returns how many are
// left, or (size_t)-1 when the keys' buffer cannot grow. An LSD radix sort
// on 64-bit keys: the first mesh (which also decides the second, and the
// tag's order), the edge (32 bits) and the triangle (below 2^31:
// SELFCOL_MESH_MAX_TRIANGLES), 11-bit digits, skipping digits every key
// shares. The keys live in the sort buffer of the contact set the rebuild's
// query ran in (which has just sorted the reach set's records there).
#define RADIX_BITS 11
#define RADIX_MASK ((1u << RADIX_BITS) - 1u)
typedef struct sort_item {
    uint64_t key;
    float near;
    uint32_t unused;
} sort_item;

static size_t sort_unique(const selfcol_sequence *s, selfcol_workspace *work, near_pair *p,
                          size_t n) {
    if (n == 0)
        return 0;
    if (n > SIZE_MAX / (2 * sizeof(sort_item)))
        return (size_t)-1;
    sort_item *item =
        selfcol_workspace__buffer(work, SELFCOL_SCRATCH_SORT, 2 * n * sizeof(sort_item), 0);
    if (item == NULL)
        return (size_t)-1;
    sort_item *other = item + n;
    uint64_t all_or = 0, all_and = ~(uint64_t)0;
    for (size_t i = 0; i < n; ++i) {
        const uint64_t first_mesh = TAG_FIRST_MESH(p[i].tag);
        item[i].key = first_mesh << 63 | (uint64_t)p[i].first << 31 | p[i].second;
        item[i].near = p[i].near;
        item[i].unused = 0;
        all_or |= item[i].key;
        all_and &= item[i].key;
    }
    for (int shift = 0; shift < 64; shift += RADIX_BITS) {
        if ((((all_or ^ all_and) >> shift) & RADIX_MASK) == 0)
            continue; // every key has this digit
        size_t count[RADIX_MASK + 1];
        memset(count, 0, sizeof count);
        for (size_t i = 0; i < n; ++i)
            count[(item[i].key >> shift) & RADIX_MASK]++;
        size_t sum = 0;
        for (size_t b = 0; b <= RADIX_MASK; ++b) {
            const size_t k = count[b];
            count[b] = sum;
            sum += k;
        }
        for (size_t i = 0; i < n; ++i)
            other[count[(item[i].key >> shift) & RADIX_MASK]++] = item[i];
        sort_item *swap = item;
        item = other;
        other = swap;
    }
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
        if (m > 0 && item[i].key == item[i - 1].key) {
            if (item[i].near < p[m - 1].near)
                p[m - 1].near = item[i].near; // the repeats' least
            continue;
        }
        const uint32_t first_mesh = (uint32_t)(item[i].key >> 63);
        const uint32_t second_mesh = s->self ? 0u : 1u - first_mesh;
        p[m++] = (near_pair){tag_of(SELFCOL_CONTACT_EF, first_mesh, second_mesh),
                             (uint32_t)(item[i].key >> 31), (uint32_t)(item[i].key & 0x7fffffffu),
                             item[i].near};
    }
    return m;
}

// The near list from the reach set's records (`rec`, n of them, sorted).
// The EF candidates are gathered behind the VF and EE pairs and compacted
// (sorted, repeats dropped) whenever the buffer fills, so the list needs
// about twice its final size, not the repeats' (each crossing pair is
// derived from up to five records).
static int build_list(selfcol_sequence *s, buffer *into, size_t offset, size_t *pair_count,
                      const selfcol_mesh *const mesh[2], const selfcol_contact *rec, size_t n,
                      selfcol_workspace *work) {
    const selfcol_allocator *a = &s->allocator;
    const size_t before = offset * sizeof(near_pair); // kept when `into` grows
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        count += rec[i].kind != SELFCOL_CONTACT_EF && (s->kinds & (1u << rec[i].kind));
    if (reserve_keep(a, into, (offset + 3 * count + 1024) * sizeof(near_pair), before) !=
        SELFCOL_OK)
        return SELFCOL_ENOMEM;
    near_pair *list = (near_pair *)into->data + offset;
    // VF then EE, in the records' order (kind first, so already sorted).
    count = 0;
    for (size_t i = 0; i < n; ++i) {
        const selfcol_contact *r = &rec[i];
        if (r->kind != SELFCOL_CONTACT_EF && (s->kinds & (1u << r->kind)))
            list[count++] = (near_pair){tag_of(r->kind, r->first_mesh, r->second_mesh), r->first,
                                        r->second, float_below(r->distance)};
    }
    if (s->kinds & SELFCOL_KIND_EF) {
        size_t m = 0, compacted = 0; // EF candidates behind the list; of them, sorted
        for (size_t i = 0; i < n; ++i) {
            const size_t need = ef_bound(mesh, &rec[i]);
            const size_t room = into->bytes / sizeof(near_pair) - offset - count;
            if (m + need > room) {
                if (m > compacted) {
                    m = compacted = sort_unique(s, work, list + count, m);
                    if (m == (size_t)-1)
                        return SELFCOL_ENOMEM;
                }
                // Still short, or nearly full of distinct pairs: grow to
                // twice what is kept.
                if (m + need > room || 4 * m > 3 * room) {
                    const size_t keep = before + (count + m) * sizeof(near_pair);
                    if (reserve_keep(a, into, before + (count + 2 * (m + need)) * sizeof(near_pair),
                                     keep) != SELFCOL_OK)
                        return SELFCOL_ENOMEM;
                    list = (near_pair *)into->data + offset;
                }
            }
            m += ef_candidates(s, mesh, &rec[i], list + count + m);
        }
        m = sort_unique(s, work, list + count, m);
        if (m == (size_t)-1)
            return SELFCOL_ENOMEM;
        count += m;
    }
    *pair_count = count;
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// Evaluation of the near list at the current positions

typedef struct evaluation {
    const selfcol_sequence *s;
    selfcol_query base;
    selfcol_records *out[SELFCOL_MAX_THREADS];
    unsigned workers;
    size_t chunks;     // of EVALUATION_CHUNK pairs
    size_t next_chunk; // atomic: the workers take chunks from it
} evaluation;

// With threads, the workers take runs of this many pairs from a shared
// counter (a worker whose thread could not start takes none, and the others
// do its part); the records are sorted afterwards.
#define EVALUATION_CHUNK 512

static int evaluate_range(const evaluation *e, selfcol_records *out, size_t begin, size_t end) {
    selfcol_query q = e->base;
    q.out = out;
    const selfcol_sequence *s = e->s;
    const near_pair *list = s->pairs.data;
    const float *pair_spread = s->spread.data;
    const size_t K1 = s->clusters[s->self ? 0 : 1].count;
    const double d = q.distance;
    // A pair is skipped when its reference distance less its clusters'
    // spread exceeds d (0 for EF) by the proof's margin, which covers the
    // closed forms' 1e-9 relative band and the floats' rounding (both
    // rounded the safe way).
    const double margin = MARGIN * s->reach;
    const double beyond[3] = {d + margin, d + margin, margin}; // by kind
    int status = SELFCOL_OK;
    for (size_t i = begin; i < end && status == SELFCOL_OK; ++i) {
        const near_pair *p = &list[i];
        const uint32_t kind = TAG_KIND(p->tag);
        const int m1 = (int)TAG_FIRST_MESH(p->tag), m2 = (int)TAG_SECOND_MESH(p->tag);
        const selfcol_mesh *M1 = q.mesh[m1], *M2 = q.mesh[m2];
        out->stats.candidate_pairs++;
        const uint32_t c1 = TAG_FIRST_CLUSTER(p->tag), c2 = TAG_SECOND_CLUSTER(p->tag);
        const float spread_now = m1 == 0 ? pair_spread[c1 * K1 + c2] : pair_spread[c2 * K1 + c1];
        if ((double)p->near - (double)spread_now > beyond[kind]) {
            out->stats.primitives_filtered++;
            continue;
        }
        // The exhaustive reference's box filters (exhaustive.c), then the
        // same primitive tests as every method.
        double lo[3], hi[3], plo[3], phi[3];
        if (kind == SELFCOL_CONTACT_VF) {
            const uint32_t *tri = M2->triangles + 3 * (size_t)p->second;
            const double *c[3] = {selfcol_mesh__position(M2, tri[0]),
                                  selfcol_mesh__position(M2, tri[1]),
                                  selfcol_mesh__position(M2, tri[2])};
            selfcol_box__of_points(lo, hi, c, 3);
            if (!selfcol_box__point_near(selfcol_mesh__position(M1, p->first), lo, hi, d)) {
                out->stats.primitives_filtered++;
                continue;
            }
            status = selfcol_pairs__test_vf(&q, m1, p->first, m2, p->second);
        } else {
            const uint32_t *ev = M1->edges + 2 * (size_t)p->first;
            const double *pe[2] = {selfcol_mesh__position(M1, ev[0]),
                                   selfcol_mesh__position(M1, ev[1])};
            selfcol_box__of_points(plo, phi, pe, 2);
            if (kind == SELFCOL_CONTACT_EE) {
                const uint32_t *fv = M2->edges + 2 * (size_t)p->second;
                const double *pf[2] = {selfcol_mesh__position(M2, fv[0]),
                                       selfcol_mesh__position(M2, fv[1])};
                selfcol_box__of_points(lo, hi, pf, 2);
                if (!selfcol_box__near(plo, phi, lo, hi, d)) {
                    out->stats.primitives_filtered++;
                    continue;
                }
                status = selfcol_pairs__test_ee(&q, m1, p->first, m2, p->second);
            } else {
                const uint32_t *tri = M2->triangles + 3 * (size_t)p->second;
                const double *c[3] = {selfcol_mesh__position(M2, tri[0]),
                                      selfcol_mesh__position(M2, tri[1]),
                                      selfcol_mesh__position(M2, tri[2])};
                selfcol_box__of_points(lo, hi, c, 3);
                if (!selfcol_box__near(plo, phi, lo, hi, 0.0)) {
                    out->stats.primitives_filtered++;
                    continue;
                }
                status = selfcol_pairs__test_ef(&q, m1, p->first, m2, p->second);
            }
        }
    }
    return status;
}

static int evaluate_worker(void *context, unsigned w) {
    evaluation *e = context;
    const size_t n = e->s->pair_count;
    int status = SELFCOL_OK;
    for (;;) {
        const size_t k = SELFCOL_ATOMIC_FETCH_ADD(&e->next_chunk, (size_t)1);
        if (k >= e->chunks || status != SELFCOL_OK)
            break;
        const size_t begin = k * EVALUATION_CHUNK;
        const size_t end = n - begin < EVALUATION_CHUNK ? n : begin + EVALUATION_CHUNK;
        status = evaluate_range(e, e->out[w], begin, end);
    }
    return status;
}

// The near list's records at the current positions, in order, into out,
// on the threads of the context of the calls given none (query.h).
static int evaluate(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                    const selfcol_query_options *o, selfcol_contacts *contacts) {
    selfcol_context *context = selfcol_query__implicit_context(contacts, o->threads);
    if (context == NULL)
        return SELFCOL_ENOMEM;
    selfcol_records *out = &contacts->records;
    evaluation e;
    e.s = s;
    e.base.mesh[0] = mesh[0];
    e.base.mesh[1] = mesh[1];
    e.base.self = s->self;
    e.base.distance = o->distance;
    e.base.kinds = o->kinds;
    e.base.narrow = o->narrow;
    e.base.ccd_tolerance = 1e-7 * o->distance; // as query.c
    e.base.out = out;
    e.base.work = &context->work;
    e.base.filter = NULL;
    // At most a worker per chunk.
    unsigned workers = o->threads;
    e.chunks = (s->pair_count + EVALUATION_CHUNK - 1) / EVALUATION_CHUNK;
    if (e.chunks < workers)
        workers = e.chunks > 0 ? (unsigned)e.chunks : 1u;
    e.workers = workers;
    e.next_chunk = 0;
    e.out[0] = out;
    for (unsigned w = 1; w < workers; ++w) {
        selfcol_worker *worker = selfcol_context__worker(context, w);
        if (worker == NULL)
            return SELFCOL_ENOMEM;
        e.out[w] = &worker->records;
    }
    if (workers <= 1)
        return evaluate_range(&e, out, 0, s->pair_count); // in list order: sorted
    int status = selfcol_parallel__run(&context->executor, workers, evaluate_worker, &e);
    if (status != SELFCOL_OK)
        return status;
    // Chunks went to whichever worker took them: the sort restores the
    // record order, reading the workers' records where they lie.
    for (unsigned w = 1; w < workers; ++w)
        selfcol_records__absorb_stats(out, e.out[w]);
    context->pending_workers = workers - 1;
    return selfcol_context__sort(context, out);
}

// ---------------------------------------------------------------------------
// Queries

static double automatic_skin(double distance, const selfcol_mesh *const mesh[2], int self) {
    if (distance > 0.0)
        return distance;
    double sum = selfcol_mesh_mean_edge_length(mesh[0]);
    if (!self)
        sum = 0.5 * (sum + selfcol_mesh_mean_edge_length(mesh[1]));
    return 0.1 * sum;
}

// Takes the query's setup (meshes, options); forgets any reference.
static void setup(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                  const selfcol_query_options *o) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    s->skin = s->reach = 0.0;
    s->state = STATE_NONE;
    s->clusters[0].ready = s->clusters[1].ready = 0;
    s->self = h[0] == h[1];
    for (int m = 0; m < 2; ++m)
        s->identity[m] = mesh[m]->identity;
    s->distance = o->distance;
    s->kinds = o->kinds;
    s->narrow = o->narrow;
    s->method = o->method;
}

// The skin for a new reference (the automatic one follows the mean edge).
static void choose_skin(selfcol_sequence *s, selfcol_hierarchy *const h[2]) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    const double skin =
        s->skin_option > 0.0 ? s->skin_option : automatic_skin(s->distance, mesh, s->self);
    double reach = s->distance + skin;
    if (!(reach <= SELFCOL_MESH_MAX_COORDINATE))
        reach = SELFCOL_MESH_MAX_COORDINATE;
    s->skin = reach - s->distance;
    s->reach = reach;
}

static int same_setup(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                      const selfcol_query_options *o) {
    return s->state != STATE_NONE && s->self == (h[0] == h[1]) &&
           selfcol_mesh__is(h[0]->mesh, &s->identity[0]) &&
           selfcol_mesh__is(h[1]->mesh, &s->identity[1]) && s->distance == o->distance &&
           s->kinds == o->kinds && s->narrow == o->narrow && s->method == o->method;
}

// What cluster pair (i, j) allows at the current reference as a float
// rounded down; 0 when it allows nothing.
static float float_allowance(const selfcol_sequence *s, unsigned i, unsigned j) {
    const double allowed = allowance(s, i, j);
    return allowed > 0.0 ? float_below(allowed) : 0.0f;
}

// The current positions become the reference: copied, with the clusters
// and their boxes (the caller has chosen the skin for them).
static int take_reference(selfcol_sequence *s, selfcol_hierarchy *const h[2]) {
    const int meshes = s->self ? 1 : 2;
    size_t stamp_bytes = 0;
    int status = SELFCOL_OK;
    for (int m = 0; m < meshes && status == SELFCOL_OK; ++m) {
        const selfcol_mesh *mesh = h[m]->mesh;
        const size_t V = mesh->vertex_count;
        stamp_bytes = V * sizeof(uint32_t) > stamp_bytes ? V * sizeof(uint32_t) : stamp_bytes;
        status = reserve(&s->allocator, &s->reference[m], 3 * V * sizeof(double));
        if (status == SELFCOL_OK)
            memcpy(s->reference[m].data, mesh->positions, 3 * V * sizeof(double));
    }
    if (status == SELFCOL_OK)
        status = reserve(&s->allocator, &s->stamps, stamp_bytes);
    for (int m = 0; m < meshes && status == SELFCOL_OK; ++m)
        status = build_clusters(s, m, h[m], s->stamps.data);
    // No displacement yet: every cluster pair's spread and carry are 0, and
    // each allows what the new reference gives it.
    const size_t K0 = s->clusters[0].count, K1 = s->clusters[s->self ? 0 : 1].count;
    const size_t bytes = (K0 * K1 + 1) * sizeof(float);
    if (status == SELFCOL_OK)
        status = reserve(&s->allocator, &s->spread, bytes);
    if (status == SELFCOL_OK)
        status = reserve(&s->allocator, &s->carry, bytes);
    if (status == SELFCOL_OK)
        status = reserve(&s->allocator, &s->allowed, bytes);
    if (status != SELFCOL_OK)
        return status;
    memset(s->spread.data, 0, bytes);
    memset(s->carry.data, 0, bytes);
    float *allowed = s->allowed.data;
    for (unsigned i = 0; i < K0; ++i)
        for (unsigned j = 0; j < K1; ++j)
            allowed[i * K1 + j] = float_allowance(s, i, j);
    return SELFCOL_OK;
}

// Writes the clusters of each near pair's primitives into its tag (after
// take_reference: a vertex or an edge goes to the cluster of its first
// triangle, whose vertex set holds it).
static void tag_clusters(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                         near_pair *list, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        near_pair *p = &list[i];
        const uint32_t kind = TAG_KIND(p->tag);
        const uint32_t m1 = TAG_FIRST_MESH(p->tag), m2 = TAG_SECOND_MESH(p->tag);
        const selfcol_mesh *M1 = mesh[m1], *M2 = mesh[m2];
        const uint8_t *of1 = s->clusters[s->self ? 0 : m1].of_triangle.data;
        const uint8_t *of2 = s->clusters[s->self ? 0 : m2].of_triangle.data;
        const uint32_t t1 = kind == SELFCOL_CONTACT_VF
                                ? M1->vertex_tris[M1->vertex_tri_offsets[p->first]]
                                : M1->edge_tris[M1->edge_tri_offsets[p->first]];
        const uint32_t t2 =
            kind == SELFCOL_CONTACT_EE ? M2->edge_tris[M2->edge_tri_offsets[p->second]] : p->second;
        p->tag = (p->tag & 0xffu) | (uint32_t)of1[t1] << 8 | (uint32_t)of2[t2] << 16;
    }
}

// The working memory of the context that filled `scratch` (made by its
// first query, query.h): its sort slot serves the list's builds.
static selfcol_workspace *scratch_work(selfcol_contacts *scratch) {
    return &scratch->implicit_context->work;
}

// The ordinary query of the hierarchies (a self query when they are one).
static int query(selfcol_hierarchy *const h[2], selfcol_contacts *out,
                 const selfcol_query_options *o) {
    return h[0] == h[1] ? selfcol_hierarchy_self_collide(h[0], out, o)
                        : selfcol_hierarchy_collide(h[0], h[1], out, o);
}

// Refits the hierarchies that are stale (none for EXHAUSTIVE).
static int refit_stale(selfcol_hierarchy *const h[2], uint32_t method) {
    const int meshes = h[0] == h[1] ? 1 : 2;
    for (int m = 0; m < meshes; ++m) {
        if (method != SELFCOL_METHOD_EXHAUSTIVE &&
            h[m]->refit_version != h[m]->mesh->positions_version) {
            int status = selfcol_hierarchy_refit(h[m]);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    return SELFCOL_OK;
}

// Rebuilds the near list at the current positions; the reach set's records
// pass through `scratch` (the caller's contact set, cleared afterwards: its
// records and context are reused instead of a second set's).
static int rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                   const selfcol_query_options *o, selfcol_contacts *scratch) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    // The reach set: the caller's exact method at distance R, closed forms
    // (libccd's distances are approximate), every kind the list needs.
    int status = refit_stale(h, o->method);
    choose_skin(s, h);
    selfcol_query_options r = *o;
    r.distance = s->reach;
    r.narrow = SELFCOL_NARROW_CLOSED_FORM;
    if (o->kinds & SELFCOL_KIND_EF)
        r.kinds = SELFCOL_KIND_ALL;
    if (status == SELFCOL_OK)
        status = query(h, scratch, &r);
    if (status == SELFCOL_OK)
        status = build_list(s, &s->pairs, 0, &s->pair_count, mesh, scratch->records.items,
                            scratch->records.count, scratch_work(scratch));
    selfcol_contacts_clear(scratch);
    if (status == SELFCOL_OK)
        status = take_reference(s, h);
    if (status == SELFCOL_OK)
        tag_clusters(s, mesh, s->pairs.data, s->pair_count);
    return status;
}

// ---------------------------------------------------------------------------
// Partial rebuilds (the proof above)

// Which node pairs a partial rebuild's query keeps: per node of each
// hierarchy, the clusters having a triangle that shares a vertex with one
// of the node's triangles (MASK_WORDS words each), and per cluster of the
// first mesh, its re-queried partners in the second (the first for a self
// query, where the relation is symmetric).
typedef struct partial_filter {
    const uint64_t *node_mask[2];
    const uint64_t *partners;
    uint64_t rows[MASK_WORDS]; // the clusters of the first mesh with a re-queried partner
} partial_filter;

static unsigned lowest_bit(uint64_t bits) {
#if defined(__GNUC__) || defined(__clang__)
    return (unsigned)__builtin_ctzll(bits);
#else
    unsigned k = 0;
    while (!(bits & 1u)) {
        bits >>= 1;
        ++k;
    }
    return k;
#endif
}

static int keep_node_pair(const void *context, uint32_t a, uint32_t b) {
    const partial_filter *f = context;
    const uint64_t *ma = f->node_mask[0] + MASK_WORDS * (size_t)a;
    const uint64_t *mb = f->node_mask[1] + MASK_WORDS * (size_t)b;
    for (unsigned w = 0; w < MASK_WORDS; ++w) {
        for (uint64_t bits = ma[w] & f->rows[w]; bits != 0; bits &= bits - 1) {
            const uint64_t *row = f->partners + MASK_WORDS * (64 * (size_t)w + lowest_bit(bits));
            for (unsigned x = 0; x < MASK_WORDS; ++x)
                if (row[x] & mb[x])
                    return 1;
        }
    }
    return 0;
}

// The node masks of mesh m's hierarchy (breadth-first layout: children
// follow their parent, so one reverse sweep ORs them up).
static void node_masks(const selfcol_sequence *s, int m, const selfcol_hierarchy *h,
                       uint64_t *mask) {
    const selfcol_mesh *mesh = h->mesh;
    const uint8_t *of = s->clusters[m].of_triangle.data;
    for (size_t n = h->node_count; n-- > 0;) {
        const selfcol_node *node = &h->nodes[n];
        uint64_t *out = mask + MASK_WORDS * n;
        memset(out, 0, MASK_WORDS * sizeof *out);
        for (uint32_t c = 0; c < node->child_count; ++c)
            for (unsigned w = 0; w < MASK_WORDS; ++w)
                out[w] |= mask[MASK_WORDS * ((size_t)node->first_child + c) + w];
        if (node->child_count > 0)
            continue;
        for (uint32_t slot = node->tri_begin; slot < node->tri_begin + node->tri_count; ++slot) {
            const uint32_t *tri = mesh->triangles + 3 * (size_t)h->tri_order[slot];
            for (int i = 0; i < 3; ++i) {
                const uint32_t v = tri[i];
                for (uint32_t k = mesh->vertex_tri_offsets[v]; k < mesh->vertex_tri_offsets[v + 1];
                     ++k) {
                    const unsigned c = of[mesh->vertex_tris[k]];
                    out[c / 64] |= (uint64_t)1 << (c % 64);
                }
            }
        }
    }
}

// Whether near pair p belongs to a re-queried cluster pair.
static int requeried(const near_pair *p, const uint64_t *partners) {
    const uint32_t c1 = TAG_FIRST_CLUSTER(p->tag), c2 = TAG_SECOND_CLUSTER(p->tag);
    const int first = TAG_FIRST_MESH(p->tag) == 0;
    const uint32_t i = first ? c1 : c2, j = first ? c2 : c1;
    return (int)(partners[MASK_WORDS * (size_t)i + j / 64] >> (j % 64) & 1u);
}

// Keeps the pairs of list that are (want == 1) or are not (want == 0)
// re-queried, in order; returns how many.
static size_t keep_requeried(near_pair *list, size_t count, const uint64_t *partners, int want) {
    size_t kept = 0;
    for (size_t i = 0; i < count; ++i)
        if (requeried(&list[i], partners) == want)
            list[kept++] = list[i];
    return kept;
}

// The near list's order: that of the records (contacts.c's keys).
static int near_less(const near_pair *a, const near_pair *b) {
    if (TAG_KIND(a->tag) != TAG_KIND(b->tag))
        return TAG_KIND(a->tag) < TAG_KIND(b->tag);
    if (TAG_FIRST_MESH(a->tag) != TAG_FIRST_MESH(b->tag))
        return TAG_FIRST_MESH(a->tag) < TAG_FIRST_MESH(b->tag);
    if (a->first != b->first)
        return a->first < b->first;
    if (TAG_SECOND_MESH(a->tag) != TAG_SECOND_MESH(b->tag))
        return TAG_SECOND_MESH(a->tag) < TAG_SECOND_MESH(b->tag);
    return a->second < b->second;
}

// What partial_rebuild returns when it declines (PARTIAL_MOST): nothing
// was changed, and the caller rebuilds in full.
#define PARTIAL_DECLINED 1

// Re-queries the cluster pairs whose spread (this frame's check) has used
// PARTIAL_SHARE of what they allow; every cluster takes the current
// positions as its reference, the others carry their spread. `scratch` as
// for rebuild().
static int partial_rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                           const selfcol_query_options *o, selfcol_contacts *scratch) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    const int meshes = s->self ? 1 : 2;
    const size_t K0 = s->clusters[0].count, K1 = s->clusters[s->self ? 0 : 1].count;
    // Which pairs go again (a symmetric choice for a self query: the
    // tables are).
    partial_filter f;
    memset(&f, 0, sizeof f);
    uint64_t *partners = s->partners;
    f.partners = partners;
    memset(partners, 0, sizeof s->partners);
    float *pair_spread = s->spread.data, *carry = s->carry.data, *allowed = s->allowed.data;
    for (unsigned i = 0; i < K0; ++i) {
        for (unsigned j = 0; j < K1; ++j) {
            if ((double)pair_spread[i * K1 + j] >= PARTIAL_SHARE * (double)allowed[i * K1 + j]) {
                partners[MASK_WORDS * i + j / 64] |= (uint64_t)1 << (j % 64);
                f.rows[i / 64] |= (uint64_t)1 << (i % 64);
            }
        }
    }
    size_t held = 0;
    const near_pair *list = s->pairs.data;
    for (size_t i = 0; i < s->pair_count; ++i)
        held += (size_t)requeried(&list[i], partners);
    if ((double)held > PARTIAL_MOST * (double)s->pair_count)
        return PARTIAL_DECLINED;
    const size_t nodes0 = h[0]->node_count, nodes1 = s->self ? 0 : h[1]->node_count;
    int status =
        reserve(&s->allocator, &s->masks, (nodes0 + nodes1) * MASK_WORDS * sizeof(uint64_t));
    if (status != SELFCOL_OK)
        return status;
    uint64_t *mask0 = s->masks.data;
    f.node_mask[0] = mask0;
    f.node_mask[1] = s->self ? mask0 : mask0 + MASK_WORDS * nodes0;
    // The others carry this frame's spread.
    for (unsigned i = 0; i < K0; ++i)
        for (unsigned j = 0; j < K1; ++j)
            carry[i * K1 + j] =
                partners[MASK_WORDS * i + j / 64] >> (j % 64) & 1u ? 0.0f : pair_spread[i * K1 + j];
    // The new reference, and the allowances from it (re-queried pairs; kept
    // pairs where it allows more). This frame's spread since the reference
    // is 0: what remains is the carry.
    for (int m = 0; m < meshes && status == SELFCOL_OK; ++m) {
        memcpy(s->reference[m].data, mesh[m]->positions,
               3 * mesh[m]->vertex_count * sizeof(double));
        status = build_clusters(s, m, h[m], s->stamps.data); // the boxes
    }
    if (status != SELFCOL_OK)
        return status;
    for (unsigned i = 0; i < K0; ++i) {
        for (unsigned j = 0; j < K1; ++j) {
            const float now = float_allowance(s, i, j);
            float *was = &allowed[i * K1 + j];
            *was = partners[MASK_WORDS * i + j / 64] >> (j % 64) & 1u || now > *was ? now : *was;
        }
    }
    memcpy(pair_spread, carry, K0 * K1 * sizeof(float));

    // The reach query, restricted; its records that belong to re-queried
    // pairs make their new near pairs.
    status = refit_stale(h, o->method);
    for (int m = 0; m < meshes; ++m)
        node_masks(s, m, h[m], m == 0 ? mask0 : mask0 + MASK_WORDS * nodes0);
    selfcol_query_options r = *o;
    r.distance = s->reach;
    r.narrow = SELFCOL_NARROW_CLOSED_FORM;
    if (o->kinds & SELFCOL_KIND_EF)
        r.kinds = SELFCOL_KIND_ALL;
    const selfcol_node_filter filter = {keep_node_pair, &f};
    size_t added = 0;
    selfcol_context *context = selfcol_query__implicit_context(scratch, r.threads);
    if (status == SELFCOL_OK && context == NULL)
        status = SELFCOL_ENOMEM;
    if (status == SELFCOL_OK)
        status = selfcol_query__run(context, h[0], h[1], &scratch->records, &r, &filter);
    // The kept pairs stay at the front of the list's buffer and the new
    // ones are built behind them, in the slack that build_list leaves for EF
    // candidates. (On failure the caller drops the list: state is
    // STATE_NONE.)
    const size_t kept = keep_requeried(s->pairs.data, s->pair_count, partners, 0);
    if (status == SELFCOL_OK)
        status = build_list(s, &s->pairs, kept, &added, mesh, scratch->records.items,
                            scratch->records.count, scratch_work(scratch));
    selfcol_contacts_clear(scratch);
    if (status != SELFCOL_OK)
        return status;
    near_pair *merged = s->pairs.data;
    tag_clusters(s, mesh, merged + kept, added);
    added = keep_requeried(merged + kept, added, partners, 1);
    // Both runs are in record order (and disjoint). The new one is copied
    // into the query's sort scratch (the context of the caller's contact
    // set, sized for its records already), and the two merge from the back
    // into the list: a write at i + j - 1 never reaches a kept pair not yet
    // read (below i) while new pairs remain (j >= 1).
    near_pair *fresh = selfcol_workspace__buffer(scratch_work(scratch), SELFCOL_SCRATCH_SORT,
                                                 added * sizeof(near_pair), 0);
    if (added > 0 && fresh == NULL)
        return SELFCOL_ENOMEM;
    if (added > 0)
        memcpy(fresh, merged + kept, added * sizeof(near_pair));
    size_t i = kept, j = added, k = kept + added;
    while (j > 0)
        merged[--k] = i > 0 && near_less(&fresh[j - 1], &merged[i - 1]) ? merged[--i] : fresh[--j];
    s->pair_count = kept + added;
    s->partial_checkable = 1;
    return SELFCOL_OK;
}

int selfcol_sequence__trim_list(selfcol_sequence *s) {
    SELFCOL_CHECK(s != NULL);
    buffer exact = {NULL, 0};
    const size_t count = s->pair_count > 0 ? s->pair_count : 1;
    if (reserve(&s->allocator, &exact, count * sizeof(near_pair)) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    if (s->pair_count > 0)
        memcpy(exact.data, s->pairs.data, s->pair_count * sizeof(near_pair));
    release(&s->allocator, &s->pairs);
    s->pairs = exact;
    return SELFCOL_OK;
}

int selfcol_sequence__check_partial(selfcol_sequence *s, selfcol_hierarchy *first,
                                    selfcol_hierarchy *second, selfcol_contacts *scratch) {
    SELFCOL_CHECK(s != NULL && first != NULL && second != NULL && scratch != NULL);
    SELFCOL_CHECK(s->partial_checkable && s->state == STATE_LIST);
    selfcol_hierarchy *const h[2] = {first, second};
    const selfcol_mesh *const mesh[2] = {first->mesh, second->mesh};
    selfcol_query_options r;
    selfcol_query_options_init(&r, SELFCOL_QUERY_OPTIONS_VERSION);
    r.method = s->method;
    r.distance = s->reach;
    r.kinds = s->kinds & SELFCOL_KIND_EF ? SELFCOL_KIND_ALL : s->kinds;
    buffer full = {NULL, 0};
    size_t n = 0;
    int status = query(h, scratch, &r);
    if (status == SELFCOL_OK)
        status = build_list(s, &full, 0, &n, mesh, scratch->records.items, scratch->records.count,
                            scratch_work(scratch));
    selfcol_contacts_clear(scratch);
    if (status != SELFCOL_OK) {
        release(&s->allocator, &full);
        return status;
    }
    near_pair *want = full.data;
    tag_clusters(s, mesh, want, n);
    n = keep_requeried(want, n, s->partners, 1);
    const near_pair *list = s->pairs.data;
    size_t k = 0;
    int same = 1;
    for (size_t i = 0; i < s->pair_count && same; ++i) {
        if (!requeried(&list[i], s->partners))
            continue;
        same = k < n && list[i].tag == want[k].tag && list[i].first == want[k].first &&
               list[i].second == want[k].second && list[i].near == want[k].near;
        ++k;
    }
    same = same && k == n;
    release(&s->allocator, &full);
    return same;
}

// What the query does this frame (run()).
enum { ANSWER_LIST = 0, ANSWER_REBUILT = 1, ANSWER_FRESH = 2 };

// SEED and CONE skip contacts by an approximate criterion, which no near
// list can reproduce: every frame is their own fresh query, and leaves no
// reference (the next frame with an exact method is a first frame).
static int approximate(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                       selfcol_contacts *contacts, const selfcol_query_options *o) {
    s->state = STATE_NONE;
    selfcol_contacts_clear(contacts);
    int status = refit_stale(h, o->method);
    if (status == SELFCOL_OK)
        status = query(h, contacts, o);
    if (status != SELFCOL_OK)
        return status;
    s->stats.frames++;
    s->stats.fresh_frames++;
    s->stats.last_answer = ANSWER_FRESH;
    s->stats.last_reason = 3;
    s->stats.near_pairs = 0;
    s->stats.deformation_ratio = 0.0;
    return SELFCOL_OK;
}

static int run(selfcol_sequence *s, selfcol_hierarchy *first, selfcol_hierarchy *second,
               selfcol_contacts *contacts, const selfcol_query_options *given) {
    SELFCOL_CHECK(s != NULL && first != NULL && second != NULL && contacts != NULL);
    selfcol_query_options o;
    int status = selfcol_query__options(&o, given);
    if (status != SELFCOL_OK)
        return status;
    if (!selfcol_mesh__is(first->mesh, &first->mesh_identity) ||
        !selfcol_mesh__is(second->mesh, &second->mesh_identity))
        return SELFCOL_EMISMATCH;
    selfcol_hierarchy *const h[2] = {first, second};
    const selfcol_mesh *const mesh[2] = {first->mesh, second->mesh};
    if (o.method != SELFCOL_METHOD_EXACT && o.method != SELFCOL_METHOD_BVH &&
        o.method != SELFCOL_METHOD_EXHAUSTIVE)
        return approximate(s, h, contacts, &o);

    const double start = selfcol_core__seconds();
    selfcol_contacts_clear(contacts);
    // The policy. A list answers while the check holds. When it fails, the
    // check's ratio over the frames since the reference is the surface's
    // deformation per frame, in units of what a list allows: a new list
    // would last about 1 / rate frames. A rebuild costs a query at d + s
    // (about two fresh queries on folded cloth), so below REBUILD_LIFE
    // frames a fresh query at d is cheaper: it answers the frame and its
    // positions become the reference against which the next frame's rate
    // is measured. The first frame has no rate: it is fresh. A list that
    // fails is rebuilt in part (partial_rebuild): only its cluster pairs
    // near or past their bound are queried again.
    uint32_t reason = 0;
    double ratio = 0.0, rate = INFINITY;
    if (!same_setup(s, h, &o)) {
        reason = s->state != STATE_NONE ? 1u : 0u;
        setup(s, h, &o);
    } else {
        // Above this, a new list would not pay; a list needs every pair's
        // spread (for its skips, and for a partial rebuild).
        const double n = (double)(s->frames_since_reference + 1);
        const double stop = s->state == STATE_LIST ? INFINITY : n / REBUILD_LIFE;
        double since;
        ratio = deformation_ratio(s, mesh, stop, &since);
        s->frames_since_reference++;
        rate = since / n;
        reason = 2;
    }
    int answer;
    if (s->state == STATE_LIST && ratio < 1.0)
        answer = ANSWER_LIST;
    else
        answer = rate * REBUILD_LIFE <= 1.0 ? ANSWER_REBUILT : ANSWER_FRESH;

    double rebuild_seconds = 0.0;
    int partial = answer == ANSWER_REBUILT && s->state == STATE_LIST;
    s->partial_checkable = 0;
    if (answer == ANSWER_REBUILT) {
        s->state = STATE_NONE;
        if (partial)
            status = partial_rebuild(s, h, &o, contacts);
        if (!partial || status == PARTIAL_DECLINED) {
            partial = 0;
            status = rebuild(s, h, &o, contacts);
        }
        if (status == SELFCOL_OK) {
            s->state = STATE_LIST;
            s->frames_since_reference = 0;
        }
        rebuild_seconds = selfcol_core__seconds() - start;
    }
    const double narrow_start = selfcol_core__seconds();
    if (status == SELFCOL_OK && answer != ANSWER_FRESH)
        status = evaluate(s, mesh, &o, contacts);
    if (status == SELFCOL_OK && answer == ANSWER_FRESH) {
        s->state = STATE_NONE;
        status = refit_stale(h, o.method);
        if (status == SELFCOL_OK)
            status = query(h, contacts, &o);
        // The contacts' statistics are the fresh query's own.
        const selfcol_query_stats kept = contacts->records.stats;
        choose_skin(s, h);
        if (status == SELFCOL_OK)
            status = take_reference(s, h);
        contacts->records.stats = kept;
        if (status == SELFCOL_OK) {
            s->state = STATE_TRACKING;
            s->frames_since_reference = 0;
        }
    }
    const double end = selfcol_core__seconds();
    if (status != SELFCOL_OK) {
        s->state = STATE_NONE;
        selfcol_contacts_clear(contacts);
        return status;
    }
    if (answer != ANSWER_FRESH) {
        contacts->records.stats.broad_seconds = narrow_start - start;
        contacts->records.stats.narrow_seconds = end - narrow_start;
    }
    contacts->records.stats.total_seconds = end - start;
    s->stats.frames++;
    s->stats.last_answer = (uint32_t)answer;
    if (answer != ANSWER_LIST)
        s->stats.last_reason = reason;
    if (answer == ANSWER_REBUILT) {
        s->stats.rebuilds++;
        s->stats.partial_rebuilds += (uint64_t)partial;
        s->stats.rebuild_seconds = rebuild_seconds;
    }
    s->stats.fresh_frames += answer == ANSWER_FRESH;
    s->stats.near_pairs = s->state == STATE_LIST ? s->pair_count : 0;
    s->stats.skin = s->skin;
    s->stats.deformation_ratio = ratio;
    return SELFCOL_OK;
}

int selfcol_sequence_self_collide(selfcol_sequence *sequence, selfcol_hierarchy *hierarchy,
                                  selfcol_contacts *contacts, const selfcol_query_options *opts) {
    return run(sequence, hierarchy, hierarchy, contacts, opts);
}

int selfcol_sequence_collide(selfcol_sequence *sequence, selfcol_hierarchy *first,
                             selfcol_hierarchy *second, selfcol_contacts *contacts,
                             const selfcol_query_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run(sequence, first, second, contacts, opts);
}
