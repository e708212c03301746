// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries (sequence.c, whose proof this extends): partial
// rebuilds. When the check fails, usually only a few cluster pairs
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
#include "frames/sequence_state.h"

#include "base/core.h"
#include "hierarchy/hierarchy.h"
#include "query/contacts.h"
#include "query/query.h"

#include <string.h>

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

// Re-queries the cluster pairs whose spread (this frame's check) has used
// PARTIAL_SHARE of what they allow; every cluster takes the current
// positions as its reference, the others carry their spread. `scratch` as
// for rebuild().
int selfcol_sequence__partial_rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
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
    int status = selfcol_sequence__reserve(&s->allocator, &s->masks,
                                           (nodes0 + nodes1) * MASK_WORDS * sizeof(uint64_t));
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
        status = selfcol_sequence__build_clusters(s, m, h[m], s->stamps.data); // the boxes
    }
    if (status != SELFCOL_OK)
        return status;
    for (unsigned i = 0; i < K0; ++i) {
        for (unsigned j = 0; j < K1; ++j) {
            const float now = selfcol_sequence__float_allowance(s, i, j);
            float *was = &allowed[i * K1 + j];
            *was = partners[MASK_WORDS * i + j / 64] >> (j % 64) & 1u || now > *was ? now : *was;
        }
    }
    memcpy(pair_spread, carry, K0 * K1 * sizeof(float));

    // The reach query, restricted; its records that belong to re-queried
    // pairs make their new near pairs.
    status = selfcol_sequence__refit_stale(s, h, o->method);
    for (int m = 0; m < meshes; ++m)
        node_masks(s, m, h[m], m == 0 ? mask0 : mask0 + MASK_WORDS * nodes0);
    selfcol_query_options r = *o;
    r.distance = s->reach;
    r.narrow = SELFCOL_NARROW_CLOSED_FORM;
    if (o->kinds & SELFCOL_KIND_EF)
        r.kinds = SELFCOL_KIND_ALL;
    const selfcol_node_filter filter = {keep_node_pair, &f};
    size_t added = 0;
    selfcol_context *context = selfcol_sequence__context(s, scratch);
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
        status = selfcol_sequence__build_list(s, &s->pairs, kept, &added, h, scratch->records.items,
                                              scratch->records.count,
                                              selfcol_sequence__scratch_work(s, scratch));
    selfcol_contacts_clear(scratch);
    if (status != SELFCOL_OK)
        return status;
    near_pair *merged = s->pairs.data;
    selfcol_sequence__tag_clusters(s, mesh, merged + kept, added);
    added = keep_requeried(merged + kept, added, partners, 1);
    // Both runs are in record order (and disjoint). The new one is copied
    // into the query's sort scratch (the context of the caller's contact
    // set, sized for its records already), and the two merge from the back
    // into the list: a write at i + j - 1 never reaches a kept pair not yet
    // read (below i) while new pairs remain (j >= 1).
    near_pair *fresh =
        selfcol_workspace__buffer(selfcol_sequence__scratch_work(s, scratch), SELFCOL_SCRATCH_SORT,
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
    if (selfcol_sequence__reserve(&s->allocator, &exact, count * sizeof(near_pair)) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    if (s->pair_count > 0)
        memcpy(exact.data, s->pairs.data, s->pair_count * sizeof(near_pair));
    selfcol_sequence__release(&s->allocator, &s->pairs);
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
    int status = selfcol_sequence__query(s, h, scratch, &r);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__build_list(s, &full, 0, &n, h, scratch->records.items,
                                              scratch->records.count,
                                              selfcol_sequence__scratch_work(s, scratch));
    selfcol_contacts_clear(scratch);
    if (status != SELFCOL_OK) {
        selfcol_sequence__release(&s->allocator, &full);
        return status;
    }
    near_pair *want = full.data;
    selfcol_sequence__tag_clusters(s, mesh, want, n);
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
    selfcol_sequence__release(&s->allocator, &full);
    return same;
}
