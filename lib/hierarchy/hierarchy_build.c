// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Automatic hierarchisation from the surface's topology (Volino & Magnenat
// Thalmann 1995, section 2.2), bottom-up:
// - the patch graph starts as the triangles' edge-adjacency (dual) graph;
// - each round matches every patch with an unmatched neighbour, choosing the
//   one whose merged box is most compact (smallest half-perimeter), and lets a
//   patch left alone join a neighbouring group of at most four; groups are
//   connected by construction, and the graph is contracted to the groups;
// - the first two rounds only group triangles into leaves of a few
//   triangles; every later round creates one node per group of two or more;
// - rounds stop when no patch has a neighbour: one root per edge-connected
//   component (or per part joined only through a vertex), and those roots
//   are joined pairwise under nodes that are not flagged connected.
// Each round costs O(patches + graph edges) and roughly halves the patch
// count, so the whole build is O(n). Nothing here compares all pairs.
//
// The nodes are then laid out breadth-first (children contiguous) and the
// triangles depth-first (every patch a contiguous range). This file holds the
// matching, the layout and the driver of the whole build; the later stages
// live next to it (hierarchy_build.h): each vertex and edge is given one
// owner triangle and triangles are flipped to orient each component
// consistently (hierarchy_orient.c), and each node gets the list of its
// boundary half-edges, sorted by edge (the adjacency test of SEED/CONE and
// the contour test of EXACT read it) and its disk flag
// (hierarchy_boundary.c).
#include "hierarchy/hierarchy_build.h"

#include "base/alloc.h"
#include "base/box.h"

#include <float.h>
#include <string.h>

enum { LEAF_ROUNDS = 2, MAX_GROUP = 4 };

// A leaf holds at most MAX_GROUP^LEAF_ROUNDS triangles: the bound the refit's
// per-leaf buffers are sized by.
typedef char leaf_size_matches_bound
    [MAX_GROUP * MAX_GROUP == SELFCOL_LEAF_MAX_TRIANGLES && LEAF_ROUNDS == 2 ? 1 : -1];

// The patch graph of one round.
typedef struct patch_graph {
    size_t count;
    uint32_t *adj_off; // count + 1
    uint32_t *adj;     // neighbours
    double *box;       // 6 per patch: lo xyz, hi xyz at build positions
    size_t adj_capacity;
} patch_graph;

// Tree under construction (before the breadth-first layout).
typedef struct build_node {
    uint32_t first; // first child in build->children, or first leaf triangle
    uint32_t count; // children (internal) or triangles (leaf)
    uint32_t parent;
    uint8_t leaf;
    uint8_t connected;
} build_node;

typedef struct builder {
    const selfcol_allocator *al;
    build_node *nodes;
    size_t node_count, node_capacity;
    uint32_t *children; // child lists, appended
    size_t child_count, child_capacity;
} builder;

static void *grow(const selfcol_allocator *al, void *old, size_t *capacity, size_t needed,
                  size_t item) {
    if (needed <= *capacity)
        return old;
    size_t cap = *capacity ? *capacity : 64;
    while (cap < needed)
        cap *= 2;
    void *p = selfcol_alloc__array(al, cap, item);
    if (p == NULL)
        return NULL;
    if (old != NULL)
        memcpy(p, old, *capacity * item);
    selfcol_alloc__free_array(al, old, *capacity, item);
    *capacity = cap;
    return p;
}

static int add_node(builder *b, build_node node, uint32_t *id) {
    size_t cap = b->node_capacity;
    build_node *n = grow(b->al, b->nodes, &cap, b->node_count + 1, sizeof *n);
    if (n == NULL)
        return SELFCOL_ENOMEM;
    b->nodes = n;
    b->node_capacity = cap;
    *id = (uint32_t)b->node_count;
    b->nodes[b->node_count++] = node;
    return SELFCOL_OK;
}

static int add_children(builder *b, const uint32_t *ids, size_t count) {
    size_t cap = b->child_capacity;
    uint32_t *c = grow(b->al, b->children, &cap, b->child_count + count, sizeof *c);
    if (c == NULL)
        return SELFCOL_ENOMEM;
    b->children = c;
    b->child_capacity = cap;
    memcpy(b->children + b->child_count, ids, count * sizeof *ids);
    b->child_count += count;
    return SELFCOL_OK;
}

// SELFCOL_NODE_DUPLICATES, bottom-up: nodes are laid out breadth-first, so
// every child comes after its parent.
static void mark_duplicate_nodes(selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    for (size_t id = h->node_count; id-- > 0;) {
        selfcol_node *n = &h->nodes[id];
        int all = 1;
        if (n->child_count == 0) {
            for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count && all; ++s)
                all = (m->triangle_flags[h->tri_order[s]] & SELFCOL_TRIANGLE_DUPLICATE) != 0;
        } else {
            for (uint32_t c = 0; c < n->child_count && all; ++c)
                all = (h->nodes[n->first_child + c].flags & SELFCOL_NODE_DUPLICATES) != 0;
        }
        if (all)
            n->flags |= SELFCOL_NODE_DUPLICATES;
    }
}

// The dual graph: triangles sharing an edge are neighbours. On a manifold
// edge that is its two triangles; on a non-manifold edge of k triangles
// (a "book" of pages, or k copies of one triangle) each is joined to the
// next one in the edge's list only: a chain connects the fan as all k (k - 1)
// pairs would, at 2 (k - 1) entries. Each triangle thus gets at most two
// neighbours per edge, six in all, so the graph has at most 6 F entries and
// is built in O(F) (all pairs cost O(k^2) memory and, deduplicated by scan,
// O(k^3) time: 98 s for 4000 copies of one triangle).
static int dual_graph(const selfcol_mesh *m, const selfcol_allocator *al, patch_graph *g) {
    const size_t F = m->triangle_count;
    if (F > (UINT32_MAX - 1) / 6)
        return SELFCOL_ERANGE; // adjacency offsets are 32-bit
    g->count = F;
    g->adj_off = selfcol_alloc__array(al, F + 1, sizeof(uint32_t));
    g->box = selfcol_alloc__array(al, 6 * F, sizeof(double));
    g->adj = selfcol_alloc__array(al, 6 * F + 1, sizeof(uint32_t));
    g->adj_capacity = 6 * F + 1;
    if (g->adj_off == NULL || g->box == NULL || g->adj == NULL)
        return SELFCOL_ENOMEM;
    size_t k = 0;
    for (size_t t = 0; t < F; ++t) {
        g->adj_off[t] = (uint32_t)k;
        const uint32_t *te = m->triangle_edges + 3 * t;
        for (int i = 0; i < 3; ++i) {
            uint32_t e = te[i];
            if (e == SELFCOL_INVALID_INDEX || (i > 0 && e == te[i - 1]) || (i == 2 && e == te[0]))
                continue;
            // t's place in the edge's list (distinct triangles, ascending:
            // a binary search, so a k-fan costs O(k log k)), and its chain
            // neighbours there.
            const uint32_t begin = m->edge_tri_offsets[e], end = m->edge_tri_offsets[e + 1];
            uint32_t at = begin + selfcol_hierarchy__position_in(m->edge_tris + begin, end - begin,
                                                                 (uint32_t)t);
            const uint32_t next[2] = {at > begin ? m->edge_tris[at - 1] : SELFCOL_INVALID_INDEX,
                                      at + 1 < end ? m->edge_tris[at + 1] : SELFCOL_INVALID_INDEX};
            for (int j = 0; j < 2; ++j) {
                uint32_t u = next[j];
                if (u == SELFCOL_INVALID_INDEX || u == (uint32_t)t)
                    continue;
                int seen = 0; // two triangles may share two edges (at most 6 entries to scan)
                for (size_t q = g->adj_off[t]; q < k && !seen; ++q)
                    seen = g->adj[q] == u;
                if (!seen)
                    g->adj[k++] = u;
            }
        }
        const uint32_t *tri = m->triangles + 3 * t;
        const double *corner[3] = {selfcol_mesh__position(m, tri[0]),
                                   selfcol_mesh__position(m, tri[1]),
                                   selfcol_mesh__position(m, tri[2])};
        selfcol_box__of_points(g->box + 6 * t, g->box + 6 * t + 3, corner, 3);
    }
    g->adj_off[F] = (uint32_t)k;
    return SELFCOL_OK;
}

static void free_graph(const selfcol_allocator *al, patch_graph *g) {
    selfcol_alloc__free_array(al, g->adj_off, g->count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, g->adj, g->adj_capacity, sizeof(uint32_t));
    selfcol_alloc__free_array(al, g->box, 6 * g->count, sizeof(double));
    memset(g, 0, sizeof *g);
}

// The neighbour of patch c whose merged box with c is the most compact,
// among the unmatched ones (joining == 0) or among the matched ones whose
// group has room (joining == 1); SELFCOL_INVALID_INDEX when there is none.
static uint32_t best_neighbour(const patch_graph *g, size_t c, const uint32_t *partner,
                               const uint32_t *group, const uint32_t *group_size, int joining) {
    const uint32_t NONE = SELFCOL_INVALID_INDEX;
    uint32_t best = NONE;
    double best_score = DBL_MAX;
    for (uint32_t j = g->adj_off[c]; j < g->adj_off[c + 1]; ++j) {
        uint32_t u = g->adj[j];
        int eligible = joining ? partner[u] != NONE && partner[u] != (uint32_t)c &&
                                     group_size[group[u]] < MAX_GROUP
                               : partner[u] == NONE;
        if (!eligible)
            continue;
        const double *cb = g->box + 6 * c, *ub = g->box + 6 * (size_t)u;
        double score = selfcol_box__merged_half_perimeter(cb, cb + 3, ub, ub + 3);
        if (score < best_score) {
            best_score = score;
            best = u;
        }
    }
    return best;
}

// One matching round: group[c] receives the group of patch c; returns the
// number of groups. group_size is scratch of g->count entries.
static size_t match_round(const patch_graph *g, uint32_t *group, uint32_t *group_size,
                          uint32_t *partner) {
    const uint32_t NONE = SELFCOL_INVALID_INDEX;
    for (size_t c = 0; c < g->count; ++c)
        partner[c] = NONE;
    size_t groups = 0;
    for (size_t c = 0; c < g->count; ++c) {
        if (partner[c] != NONE)
            continue;
        uint32_t best = best_neighbour(g, c, partner, group, group_size, 0);
        if (best != NONE) {
            partner[c] = best;
            partner[best] = (uint32_t)c;
            group[c] = group[best] = (uint32_t)groups;
            group_size[groups++] = 2;
        }
    }
    // Patches left alone: join the most compact neighbouring group with room,
    // else start their own.
    for (size_t c = 0; c < g->count; ++c) {
        if (partner[c] != NONE)
            continue;
        uint32_t best = best_neighbour(g, c, partner, group, group_size, 1);
        partner[c] = (uint32_t)c; // handled
        if (best != NONE) {
            group[c] = group[best];
            group_size[group[c]]++;
        } else {
            group[c] = (uint32_t)groups;
            group_size[groups++] = 1;
        }
    }
    return groups;
}

// Contracts g to its groups into out (adjacency deduplicated with a stamp).
static int contract(const selfcol_allocator *al, const patch_graph *g, const uint32_t *group,
                    size_t groups, patch_graph *out, uint32_t *stamp, uint32_t *order,
                    uint32_t *order_off) {
    out->count = groups;
    out->adj_off = selfcol_alloc__array(al, groups + 1, sizeof(uint32_t));
    out->adj = selfcol_alloc__array(al, g->adj_off[g->count] + 1, sizeof(uint32_t));
    out->adj_capacity = g->adj_off[g->count] + 1;
    out->box = selfcol_alloc__array(al, 6 * groups, sizeof(double));
    if (out->adj_off == NULL || out->adj == NULL || out->box == NULL)
        return SELFCOL_ENOMEM;
    // Members of each group, by counting sort.
    memset(order_off, 0, (groups + 1) * sizeof(uint32_t));
    for (size_t c = 0; c < g->count; ++c)
        order_off[group[c] + 1]++;
    for (size_t h = 0; h < groups; ++h)
        order_off[h + 1] += order_off[h];
    for (size_t c = 0; c < g->count; ++c)
        order[order_off[group[c]]++] = (uint32_t)c;
    for (size_t h = groups; h > 0; --h)
        order_off[h] = order_off[h - 1];
    order_off[0] = 0;
    for (size_t h = 0; h < groups; ++h)
        stamp[h] = SELFCOL_INVALID_INDEX;
    size_t k = 0;
    for (size_t h = 0; h < groups; ++h) {
        out->adj_off[h] = (uint32_t)k;
        double *box = out->box + 6 * h;
        for (int i = 0; i < 3; ++i) {
            box[i] = DBL_MAX;
            box[3 + i] = -DBL_MAX;
        }
        stamp[h] = (uint32_t)h; // no self loop
        for (uint32_t m = order_off[h]; m < order_off[h + 1]; ++m) {
            uint32_t c = order[m];
            const double *member = g->box + 6 * (size_t)c;
            selfcol_box__merge(box, box + 3, member, member + 3);
            for (uint32_t j = g->adj_off[c]; j < g->adj_off[c + 1]; ++j) {
                uint32_t u = group[g->adj[j]];
                if (stamp[u] != (uint32_t)h) {
                    stamp[u] = (uint32_t)h;
                    out->adj[k++] = u;
                }
            }
        }
    }
    out->adj_off[groups] = (uint32_t)k;
    return SELFCOL_OK;
}

// Lays the build tree out breadth-first into h->nodes (children contiguous)
// and the triangles depth-first into h->tri_order (every patch a contiguous
// range); fills parent and depth (by final node index) and leaf_of_tri.
static int layout(selfcol_hierarchy *h, const builder *b, uint32_t root, const uint32_t *leaf_tris,
                  uint32_t *parent, uint32_t *depth, uint32_t *leaf_of_tri) {
    const selfcol_allocator *al = &h->allocator;
    const size_t N = b->node_count;
    h->nodes = selfcol_alloc__array(al, N, sizeof(selfcol_node));
    if (h->nodes == NULL)
        return SELFCOL_ENOMEM;
    h->node_count = N; // destroy frees nodes with this size, whatever fails next
    uint32_t *build_of = selfcol_alloc__array(al, N, sizeof(uint32_t)); // BFS queue
    if (build_of == NULL)
        return SELFCOL_ENOMEM;
    memset(h->nodes, 0, N * sizeof(selfcol_node));
    size_t head = 0, tail = 0;
    build_of[tail++] = root;
    parent[0] = SELFCOL_INVALID_INDEX;
    depth[0] = 0;
    h->depth = 0;
    h->leaf_count = 0;
    while (head < tail) {
        uint32_t id = (uint32_t)head++;
        const build_node *bn = &b->nodes[build_of[id]];
        selfcol_node *n = &h->nodes[id];
        n->flags = bn->connected ? SELFCOL_NODE_CONNECTED : 0;
        h->depth = depth[id] > h->depth ? depth[id] : h->depth;
        if (bn->leaf) {
            h->leaf_count++;
            n->tri_count = bn->count;
            continue;
        }
        n->child_count = (uint8_t)bn->count;
        n->first_child = (uint32_t)tail;
        for (uint32_t i = 0; i < bn->count; ++i) {
            parent[tail] = id;
            depth[tail] = depth[id] + 1;
            build_of[tail++] = b->children[bn->first + i];
        }
    }
    // Patch sizes bottom-up (children come after their parent), then ranges
    // top-down: a node's children split its range in order, which is exactly
    // a depth-first numbering of the triangles.
    for (size_t id = N; id-- > 0;) {
        selfcol_node *n = &h->nodes[id];
        if (n->child_count == 0)
            continue;
        n->tri_count = 0;
        for (uint32_t i = 0; i < n->child_count; ++i)
            n->tri_count += h->nodes[n->first_child + i].tri_count;
    }
    h->nodes[0].tri_begin = 0;
    for (size_t id = 0; id < N; ++id) {
        selfcol_node *n = &h->nodes[id];
        if (n->child_count == 0) {
            const build_node *bn = &b->nodes[build_of[id]];
            for (uint32_t i = 0; i < bn->count; ++i) {
                uint32_t t = leaf_tris[bn->first + i];
                h->tri_order[n->tri_begin + i] = t;
                leaf_of_tri[t] = (uint32_t)id;
            }
            continue;
        }
        uint32_t begin = n->tri_begin;
        for (uint32_t i = 0; i < n->child_count; ++i) {
            h->nodes[n->first_child + i].tri_begin = begin;
            begin += h->nodes[n->first_child + i].tri_count;
        }
    }
    selfcol_alloc__free_array(al, build_of, N, sizeof(uint32_t));
    return SELFCOL_OK;
}

// The build's working arrays (F entries each, order_off F + 1), the patch
// graphs of the current and next round, and the nodes made so far.
typedef struct build_work {
    const selfcol_allocator *al;
    size_t F;
    patch_graph g, next;
    builder b;
    uint32_t *group, *group_size, *partner, *stamp, *order, *order_off, *tri_patch, *node_of;
} build_work;

// The next round's graph becomes the current one.
static void next_round(build_work *w) {
    free_graph(w->al, &w->g);
    w->g = w->next;
    memset(&w->next, 0, sizeof w->next);
}

// Leaf rounds: group triangles into patches of a few triangles (tri_patch:
// each triangle's patch).
static int leaf_rounds(build_work *w) {
    for (size_t t = 0; t < w->F; ++t)
        w->tri_patch[t] = (uint32_t)t;
    for (int round = 0; round < LEAF_ROUNDS && w->g.adj_off[w->g.count] > 0; ++round) {
        size_t groups = match_round(&w->g, w->group, w->group_size, w->partner);
        for (size_t t = 0; t < w->F; ++t)
            w->tri_patch[t] = w->group[w->tri_patch[t]];
        int status =
            contract(w->al, &w->g, w->group, groups, &w->next, w->stamp, w->order, w->order_off);
        if (status != SELFCOL_OK)
            return status;
        next_round(w);
    }
    return SELFCOL_OK;
}

// One leaf per patch, its triangles listed in leaf order (a counting sort
// into tri_patch); node_of: each patch's leaf.
static int add_leaves(build_work *w) {
    uint32_t *order = w->order, *order_off = w->order_off;
    const size_t patches = w->g.count;
    memset(order_off, 0, (patches + 1) * sizeof(uint32_t));
    for (size_t t = 0; t < w->F; ++t)
        order_off[w->tri_patch[t] + 1]++;
    for (size_t p = 0; p < patches; ++p)
        order_off[p + 1] += order_off[p];
    for (size_t t = 0; t < w->F; ++t)
        order[order_off[w->tri_patch[t]]++] = (uint32_t)t;
    for (size_t p = patches; p > 0; --p)
        order_off[p] = order_off[p - 1];
    order_off[0] = 0;
    for (size_t p = 0; p < patches; ++p) {
        build_node leaf = {order_off[p], order_off[p + 1] - order_off[p], 0, 1, 1};
        int status = add_node(&w->b, leaf, &w->node_of[p]);
        if (status != SELFCOL_OK)
            return status;
    }
    // `order` now holds the leaves' triangles; keep it aside in tri_patch.
    memcpy(w->tri_patch, order, w->F * sizeof(uint32_t));
    return SELFCOL_OK;
}

// Internal rounds: one node per group of two or more patches, until no
// patch has a neighbour (node_of: each remaining patch's node).
static int internal_rounds(build_work *w) {
    while (w->g.adj_off[w->g.count] > 0) {
        size_t groups = match_round(&w->g, w->group, w->group_size, w->partner);
        int status =
            contract(w->al, &w->g, w->group, groups, &w->next, w->stamp, w->order, w->order_off);
        if (status != SELFCOL_OK)
            return status;
        for (size_t gi = 0; gi < groups; ++gi) {
            uint32_t first = w->order_off[gi], count = w->order_off[gi + 1] - w->order_off[gi];
            if (count == 1) {
                w->partner[gi] = w->node_of[w->order[first]];
                continue;
            }
            uint32_t ids[MAX_GROUP];
            for (uint32_t i = 0; i < count; ++i)
                ids[i] = w->node_of[w->order[first + i]];
            build_node inner = {(uint32_t)w->b.child_count, count, 0, 0, 1};
            if ((status = add_children(&w->b, ids, count)) != SELFCOL_OK ||
                (status = add_node(&w->b, inner, &w->partner[gi])) != SELFCOL_OK)
                return status;
        }
        memcpy(w->node_of, w->partner, groups * sizeof(uint32_t));
        next_round(w);
    }
    return SELFCOL_OK;
}

// Joins the roots of the separate parts pairwise (not connected patches):
// the root ends in node_of[0].
static int join_roots(build_work *w) {
    size_t roots = w->g.count;
    while (roots > 1) {
        size_t out = 0;
        for (size_t i = 0; i < roots; i += 2) {
            if (i + 1 == roots) {
                w->node_of[out++] = w->node_of[i];
                continue;
            }
            uint32_t ids[2] = {w->node_of[i], w->node_of[i + 1]};
            build_node join = {(uint32_t)w->b.child_count, 2, 0, 0, 0};
            int status;
            if ((status = add_children(&w->b, ids, 2)) != SELFCOL_OK ||
                (status = add_node(&w->b, join, &w->node_of[out++])) != SELFCOL_OK)
                return status;
        }
        roots = out;
    }
    return SELFCOL_OK;
}

// The tree laid out into h, then owners, orientation, boundaries.
static int finish(selfcol_hierarchy *h, build_work *w, uint32_t *parent, uint32_t *depth) {
    // group is free now: reuse it as leaf_of_tri.
    int status = layout(h, &w->b, w->node_of[0], w->tri_patch, parent, depth, w->group);
    if (status != SELFCOL_OK)
        return status;
    mark_duplicate_nodes(h);
    selfcol_hierarchy__assign_owners(h);
    // partner and stamp are free now: a BFS queue and the seen flags of the
    // orientation walk.
    status = selfcol_hierarchy__orient(h, parent, depth, w->group, w->partner, (uint8_t *)w->stamp);
    if (status != SELFCOL_OK)
        return status;
    status = selfcol_hierarchy__build_boundaries(h, parent, depth, w->group);
    if (status != SELFCOL_OK)
        return status;
    h->min_altitude = selfcol_alloc__array(w->al, h->node_count, sizeof(float));
    return h->min_altitude != NULL ? SELFCOL_OK : SELFCOL_ENOMEM;
}

int selfcol_hierarchy__build(selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    const selfcol_allocator *al = &h->allocator;
    const size_t F = m->triangle_count;
    // Boundary half-edges are stored as (edge << 1) | direction.
    if (m->edge_count >= ((size_t)1 << 31))
        return SELFCOL_ERANGE;
    build_work w;
    memset(&w, 0, sizeof w);
    w.al = al;
    w.F = F;
    w.b.al = al;
    w.group = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.group_size = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.partner = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.stamp = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.order = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.order_off = selfcol_alloc__array(al, F + 1, sizeof(uint32_t));
    w.tri_patch = selfcol_alloc__array(al, F, sizeof(uint32_t));
    w.node_of = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *parent = NULL, *depth = NULL;
    size_t tree_size = 0;
    int status = SELFCOL_ENOMEM;
    if (w.group != NULL && w.group_size != NULL && w.partner != NULL && w.stamp != NULL &&
        w.order != NULL && w.order_off != NULL && w.tri_patch != NULL && w.node_of != NULL)
        status = dual_graph(m, al, &w.g);
    if (status == SELFCOL_OK)
        status = leaf_rounds(&w);
    if (status == SELFCOL_OK)
        status = add_leaves(&w);
    if (status == SELFCOL_OK)
        status = internal_rounds(&w);
    if (status == SELFCOL_OK)
        status = join_roots(&w);
    if (status == SELFCOL_OK) {
        tree_size = w.b.node_count;
        h->tri_order = selfcol_alloc__array(al, F, sizeof(uint32_t));
        h->owned = selfcol_alloc__array(al, F, sizeof(uint8_t));
        parent = selfcol_alloc__array(al, tree_size, sizeof(uint32_t));
        depth = selfcol_alloc__array(al, tree_size, sizeof(uint32_t));
        status = h->tri_order != NULL && h->owned != NULL && parent != NULL && depth != NULL
                     ? finish(h, &w, parent, depth)
                     : SELFCOL_ENOMEM;
    }
    free_graph(al, &w.g);
    free_graph(al, &w.next);
    selfcol_alloc__free_array(al, w.b.nodes, w.b.node_capacity, sizeof(build_node));
    selfcol_alloc__free_array(al, w.b.children, w.b.child_capacity, sizeof(uint32_t));
    selfcol_alloc__free_array(al, parent, tree_size, sizeof(uint32_t));
    selfcol_alloc__free_array(al, depth, tree_size, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.group, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.group_size, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.partner, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.stamp, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.order, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.order_off, F + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.tri_patch, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, w.node_of, F, sizeof(uint32_t));
    return status;
}
