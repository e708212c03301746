// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries (sequence.c): the near list, built from a rebuild's
// records (the EF candidates the proof needs included), and its evaluation
// at the current positions through the query's own closed forms.
#include "frames/sequence_state.h"

#include "base/box.h"
#include "base/core.h"
#include "base/parallel.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/pairs.h"
#include "query/query.h"

#include <math.h>
#include <string.h>

// ---------------------------------------------------------------------------
// The near list

static uint32_t tag_of(uint32_t kind, uint32_t first_mesh, uint32_t second_mesh) {
    return kind << 2 | first_mesh << 1 | second_mesh;
}

// A float at most x >= 0.
float selfcol_sequence__float_below(double x) {
    float f = (float)x;
    return (double)f > x ? nextafterf(f, 0.0f) : f;
}

static int is_corner(uint32_t v, const uint32_t *tri) {
    return v == tri[0] || v == tri[1] || v == tri[2];
}

// EF candidates derived from one record of the reach set (the proof above).
static size_t ef_candidates(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                            const uint8_t *const owned[2], const selfcol_contact *r,
                            near_pair *out) {
    size_t n = 0;
    const int self = s->self;
    // The record's distance bounds the candidate's from above; the smallest
    // over its repeats is its distance (sort_unique), since every component
    // below R is a record.
    const float near = selfcol_sequence__float_below(r->distance);
    if (r->kind == SELFCOL_CONTACT_EF) {
        out[n++] = (near_pair){tag_of(SELFCOL_CONTACT_EF, r->first_mesh, r->second_mesh), r->first,
                               r->second, 0.0f};
    } else if (r->kind == SELFCOL_CONTACT_VF) {
        // Every edge at vertex v against triangle t, each once: from the
        // triangle that owns it (the hierarchy's owner, its first triangle,
        // is one of v's since the edge has v), not from both of its sides.
        const selfcol_mesh *mv = mesh[r->first_mesh], *mt = mesh[r->second_mesh];
        const uint8_t *own = owned[r->first_mesh];
        const uint32_t v = r->first;
        const uint32_t *tri = mt->triangles + 3 * (size_t)r->second;
        const uint32_t tag = tag_of(SELFCOL_CONTACT_EF, r->first_mesh, r->second_mesh);
        for (uint32_t k = mv->vertex_tri_offsets[v]; k < mv->vertex_tri_offsets[v + 1]; ++k) {
            const uint32_t u = mv->vertex_tris[k];
            for (int i = 0; i < 3; ++i) {
                if (!(own[u] & SELFCOL_OWNS_EDGE(i)))
                    continue;
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
// on 64-bit keys: the first mesh (bit 63; it also decides the second, and
// the tag's order), then the edge, then the triangle in its lowest w bits,
// w the width of the largest triangle index here (below 2^31:
// SELFCOL_MESH_MAX_TRIANGLES), so that the varying bits are contiguous;
// 11-bit digits, skipping digits every key shares (a 20k-triangle sheet:
// 3 passes where a fixed 31-bit field took 5). The keys live in the sort
// buffer of the contact set the rebuild's query ran in (which has just
// sorted the reach set's records there).
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
    uint32_t largest = 0;
    for (size_t i = 0; i < n; ++i)
        largest = p[i].second > largest ? p[i].second : largest;
    int w = 1;
    while (w < 31 && (largest >> w) != 0)
        ++w;
    const uint64_t low = ((uint64_t)1 << w) - 1u;
    uint64_t all_or = 0, all_and = ~(uint64_t)0;
    for (size_t i = 0; i < n; ++i) {
        const uint64_t first_mesh = TAG_FIRST_MESH(p[i].tag);
        item[i].key = first_mesh << 63 | (uint64_t)p[i].first << w | p[i].second;
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
                             (uint32_t)((item[i].key & ~((uint64_t)1 << 63)) >> w),
                             (uint32_t)(item[i].key & low), item[i].near};
    }
    return m;
}

// The near list from the reach set's records (`rec`, n of them, sorted).
// The EF candidates are gathered behind the VF and EE pairs and compacted
// (sorted, repeats dropped) whenever the buffer fills, so the list needs
// about twice its final size, not the repeats' (each crossing pair is
// derived from up to five records).
int selfcol_sequence__build_list(selfcol_sequence *s, buffer *into, size_t offset,
                                 size_t *pair_count, selfcol_hierarchy *const h[2],
                                 const selfcol_contact *rec, size_t n, selfcol_workspace *work) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    const uint8_t *const owned[2] = {h[0]->owned, h[1]->owned};
    const selfcol_allocator *a = &s->allocator;
    const size_t before = offset * sizeof(near_pair); // kept when `into` grows
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        count += rec[i].kind != SELFCOL_CONTACT_EF && (s->kinds & (1u << rec[i].kind));
    if (selfcol_sequence__reserve_keep(a, into, (offset + 3 * count + 1024) * sizeof(near_pair),
                                       before) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    near_pair *list = (near_pair *)into->data + offset;
    // VF then EE, in the records' order (kind first, so already sorted).
    count = 0;
    for (size_t i = 0; i < n; ++i) {
        const selfcol_contact *r = &rec[i];
        if (r->kind != SELFCOL_CONTACT_EF && (s->kinds & (1u << r->kind)))
            list[count++] = (near_pair){tag_of(r->kind, r->first_mesh, r->second_mesh), r->first,
                                        r->second, selfcol_sequence__float_below(r->distance)};
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
                    if (selfcol_sequence__reserve_keep(
                            a, into, before + (count + 2 * (m + need)) * sizeof(near_pair), keep) !=
                        SELFCOL_OK)
                        return SELFCOL_ENOMEM;
                    list = (near_pair *)into->data + offset;
                }
            }
            m += ef_candidates(s, mesh, owned, &rec[i], list + count + m);
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
// on the threads of the running call's context (one thread without one).
int selfcol_sequence__evaluate(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                               const selfcol_query_options *o, selfcol_contacts *contacts) {
    selfcol_context *context = selfcol_sequence__context(s, contacts);
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
    unsigned workers = context->threads;
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
