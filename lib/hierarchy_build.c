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
// triangles depth-first (every patch a contiguous range), each vertex and edge
// is given one owner triangle, triangles are flipped to orient each component
// consistently, and each node gets the list of its boundary half-edges,
// sorted by edge (the adjacency test of SEED/CONE and the contour test of
// EXACT read it) and its disk flag (see build_disks).
#include "alloc.h"
#include "hierarchy.h"

#include <float.h>
#include <string.h>

enum { LEAF_ROUNDS = 2, MAX_GROUP = 4 };

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

static double merged_half_perimeter(const double *a, const double *b) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
        double lo = a[k] < b[k] ? a[k] : b[k];
        double hi = a[3 + k] > b[3 + k] ? a[3 + k] : b[3 + k];
        sum += hi - lo;
    }
    return sum;
}

// Index of t in the ascending list a of n entries (t must be there).
static uint32_t position_in(const uint32_t *a, uint32_t n, uint32_t t) {
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (a[mid] < t)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

// The triangle after t in edge e's (ascending) list, or SELFCOL_INVALID_INDEX.
static uint32_t successor_on_edge(const selfcol_mesh *m, uint32_t e, uint32_t t) {
    const uint32_t first = m->edge_tri_offsets[e], n = m->edge_tri_offsets[e + 1] - first;
    uint32_t at = position_in(m->edge_tris + first, n, t);
    return at + 1 < n ? m->edge_tris[first + at + 1] : SELFCOL_INVALID_INDEX;
}

// Union-find root with path halving (over a vertex star).
static uint32_t star_root(uint32_t *uf, uint32_t x) {
    while (uf[x] != x) {
        uf[x] = uf[uf[x]];
        x = uf[x];
    }
    return x;
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
            uint32_t at = begin + position_in(m->edge_tris + begin, end - begin, (uint32_t)t);
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
        for (int c = 0; c < 3; ++c) {
            const double *p = selfcol_mesh__position(m, tri[0]);
            double lo = p[c], hi = p[c];
            for (int i = 1; i < 3; ++i) {
                double x = selfcol_mesh__position(m, tri[i])[c];
                lo = x < lo ? x : lo;
                hi = x > hi ? x : hi;
            }
            g->box[6 * t + (size_t)c] = lo;
            g->box[6 * t + 3 + (size_t)c] = hi;
        }
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
        double score = merged_half_perimeter(g->box + 6 * c, g->box + 6 * (size_t)u);
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
            for (int i = 0; i < 3; ++i) {
                box[i] = g->box[6 * c + i] < box[i] ? g->box[6 * c + i] : box[i];
                box[3 + i] =
                    g->box[6 * c + 3 + i] > box[3 + i] ? g->box[6 * c + 3 + i] : box[3 + i];
            }
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

// One owner triangle per vertex and per edge: its first incident triangle.
static void assign_owners(selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    memset(h->owned, 0, m->triangle_count);
    for (size_t v = 0; v < m->vertex_count; ++v) {
        if (m->vertex_tri_offsets[v + 1] == m->vertex_tri_offsets[v])
            continue;
        uint32_t t = m->vertex_tris[m->vertex_tri_offsets[v]];
        const uint32_t *tri = m->triangles + 3 * (size_t)t;
        int i = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
        h->owned[t] |= (uint8_t)SELFCOL_OWNS_VERTEX(i);
    }
    for (size_t e = 0; e < m->edge_count; ++e) {
        uint32_t t = m->edge_tris[m->edge_tri_offsets[e]];
        const uint32_t *te = m->triangle_edges + 3 * (size_t)t;
        int i = te[0] == e ? 0 : (te[1] == e ? 1 : 2);
        h->owned[t] |= (uint8_t)SELFCOL_OWNS_EDGE(i);
    }
}

// Direction of edge slot i of triangle t: +1 when it runs from the smaller to
// the larger vertex index.
static int slot_direction(const selfcol_mesh *m, uint32_t t, int i) {
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    return tri[i] < tri[(i + 1) % 3] ? 1 : -1;
}

static int slot_of_edge(const selfcol_mesh *m, uint32_t t, uint32_t e) {
    const uint32_t *te = m->triangle_edges + 3 * (size_t)t;
    return te[0] == e ? 0 : (te[1] == e ? 1 : 2);
}

// The curvature criterion compares normals, so it needs the triangles of a
// patch oriented consistently. Triangles are flipped (SELFCOL_TRIANGLE_FLIPPED
// in owned) by a breadth-first walk across manifold edges, so every
// orientable component comes out consistent whatever the file's winding; an
// edge that stays inconsistent (a Moebius band), a non-manifold edge and an
// edge of a repeated-index triangle are marked bad: no node containing both
// sides of a bad edge may be skipped for curvature. `queue` has F entries,
// `bad` one byte per edge.
static void orient(selfcol_hierarchy *h, uint32_t *queue, uint8_t *seen, uint8_t *bad) {
    const selfcol_mesh *m = h->mesh;
    const size_t F = m->triangle_count;
    memset(seen, 0, F);
    memset(bad, 0, m->edge_count);
    for (size_t e = 0; e < m->edge_count; ++e)
        if (m->edge_tri_offsets[e + 1] - m->edge_tri_offsets[e] > 2)
            bad[e] = 1;
    for (size_t t = 0; t < F; ++t)
        if (m->triangle_flags[t] & SELFCOL_TRIANGLE_REPEATED_INDEX)
            for (int i = 0; i < 3; ++i)
                if (m->triangle_edges[3 * t + (size_t)i] != SELFCOL_INVALID_INDEX)
                    bad[m->triangle_edges[3 * t + (size_t)i]] = 1;
    for (size_t start = 0; start < F; ++start) {
        if (seen[start])
            continue;
        size_t head = 0, tail = 0;
        queue[tail++] = (uint32_t)start;
        seen[start] = 1;
        while (head < tail) {
            uint32_t t = queue[head++];
            int flip_t = (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED) != 0;
            for (int i = 0; i < 3; ++i) {
                uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)i];
                if (e == SELFCOL_INVALID_INDEX || bad[e])
                    continue;
                uint32_t first = m->edge_tri_offsets[e];
                if (m->edge_tri_offsets[e + 1] - first != 2)
                    continue; // boundary edge
                uint32_t u =
                    m->edge_tris[first] == t ? m->edge_tris[first + 1] : m->edge_tris[first];
                int same = slot_direction(m, t, i) == slot_direction(m, u, slot_of_edge(m, u, e));
                int flip_u = flip_t ^ same; // consistent: opposite directions after flips
                if (!seen[u]) {
                    seen[u] = 1;
                    if (flip_u)
                        h->owned[u] |= (uint8_t)SELFCOL_TRIANGLE_FLIPPED;
                    queue[tail++] = u;
                } else if (((h->owned[u] & SELFCOL_TRIANGLE_FLIPPED) != 0) != flip_u) {
                    bad[e] = 1; // not orientable across this edge
                }
            }
        }
    }
}

// Clears SELFCOL_NODE_ORIENTED on every node that contains both sides of a
// bad edge (the lowest common ancestor of the edge's leaves and its
// ancestors), and sets SELFCOL_NODE_BAD_BOUNDARY on the nodes that contain
// only some of its sides (the nodes below that ancestor on the way up).
static void mark_unoriented(selfcol_hierarchy *h, const uint8_t *bad, const uint32_t *parent,
                            const uint32_t *depth, const uint32_t *leaf_of_tri) {
    const selfcol_mesh *m = h->mesh;
    for (size_t id = 0; id < h->node_count; ++id)
        h->nodes[id].flags |= SELFCOL_NODE_ORIENTED;
    for (size_t e = 0; e < m->edge_count; ++e) {
        if (!bad[e])
            continue;
        uint32_t lca = leaf_of_tri[m->edge_tris[m->edge_tri_offsets[e]]];
        for (uint32_t j = m->edge_tri_offsets[e] + 1; j < m->edge_tri_offsets[e + 1]; ++j) {
            uint32_t other = leaf_of_tri[m->edge_tris[j]];
            // Every node climbed from holds some but not all of the edge's
            // triangles: the bad edge is on its boundary.
            while (lca != other) {
                if (depth[lca] >= depth[other]) {
                    h->nodes[lca].flags |= SELFCOL_NODE_BAD_BOUNDARY;
                    lca = parent[lca];
                } else {
                    h->nodes[other].flags |= SELFCOL_NODE_BAD_BOUNDARY;
                    other = parent[other];
                }
            }
        }
        h->nodes[lca].flags &= (uint8_t)~SELFCOL_NODE_ORIENTED;
    }
    // Children come after their parents: one reverse sweep propagates upward.
    for (size_t id = h->node_count; id-- > 1;)
        if (!(h->nodes[id].flags & SELFCOL_NODE_ORIENTED))
            h->nodes[parent[id]].flags &= (uint8_t)~SELFCOL_NODE_ORIENTED;
}

// The boundary half-edge of triangle t on edge e, oriented with t (after the
// build's flip) so the patch containing t lies on its left, encoded as
// (e << 1) | reversed: reversed when it runs from the edge's larger vertex to
// its smaller one.
static uint32_t half_edge_of(const selfcol_hierarchy *h, uint32_t t, uint32_t e) {
    const selfcol_mesh *m = h->mesh;
    int i = slot_of_edge(m, t, e);
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    int reversed = tri[i] > tri[(i + 1) % 3];
    if (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED)
        reversed = !reversed;
    return (e << 1) | (uint32_t)reversed;
}

typedef struct pair_list {
    uint32_t *node, *half_edge;
    size_t count, capacity;
} pair_list;

static int pair_add(const selfcol_allocator *al, pair_list *l, uint32_t node, uint32_t half_edge) {
    if (l->count == l->capacity) {
        size_t cap = l->capacity ? 2 * l->capacity : 1024;
        uint32_t *node_grown = selfcol_alloc__array(al, cap, sizeof(uint32_t));
        uint32_t *he_grown = selfcol_alloc__array(al, cap, sizeof(uint32_t));
        if (node_grown == NULL || he_grown == NULL) {
            selfcol_alloc__free_array(al, node_grown, cap, sizeof(uint32_t));
            selfcol_alloc__free_array(al, he_grown, cap, sizeof(uint32_t));
            return SELFCOL_ENOMEM; // the old arrays stay valid
        }
        if (l->count > 0) {
            memcpy(node_grown, l->node, l->count * sizeof(uint32_t));
            memcpy(he_grown, l->half_edge, l->count * sizeof(uint32_t));
        }
        selfcol_alloc__free_array(al, l->node, l->capacity, sizeof(uint32_t));
        selfcol_alloc__free_array(al, l->half_edge, l->capacity, sizeof(uint32_t));
        l->node = node_grown;
        l->half_edge = he_grown;
        l->capacity = cap;
    }
    l->node[l->count] = node;
    l->half_edge[l->count++] = half_edge;
    return SELFCOL_OK;
}

static void mark_path(uint8_t *mark, const uint32_t *parent, uint32_t node) {
    for (; node != SELFCOL_INVALID_INDEX && !mark[node]; node = parent[node])
        mark[node] = 1;
}

// Boundary half-edges of every node, and SELFCOL_NODE_DISK.
// - A manifold edge is on the boundary of the nodes below the lowest common
//   ancestor of its two triangles' leaves (each side with its own triangle's
//   orientation); a mesh-boundary edge on the boundary of every ancestor of
//   its triangle's leaf. A non-manifold edge makes every node holding one of
//   its triangles a non-disk.
// - Vertex counts: a vertex belongs to every ancestor of its triangles'
//   leaves (each counted once with a stamp). A vertex whose triangles do not
//   form one edge-connected fan (a bowtie) makes its ancestors non-disks.
// - With interior edges manifold (the ORIENTED flag), a patch of F triangles
//   and b boundary edges has E = (3F + b) / 2 edges; it is a disk iff it is
//   connected, oriented, manifold and V - E + F = 1 (an orientable connected
//   surface has chi = 2 - 2 genus - loops).
static int build_disks(selfcol_hierarchy *h, const uint32_t *parent, const uint32_t *depth,
                       const uint32_t *leaf_of_tri) {
    const selfcol_mesh *m = h->mesh;
    const selfcol_allocator *al = &h->allocator;
    const size_t N = h->node_count;
    int status = SELFCOL_ENOMEM;
    pair_list l;
    memset(&l, 0, sizeof l);
    uint32_t *stamp = selfcol_alloc__array(al, N, sizeof(uint32_t));
    uint32_t *vcount = selfcol_alloc__array(al, N, sizeof(uint32_t));
    uint8_t *nondisk = selfcol_alloc__array(al, N, sizeof(uint8_t));
    size_t max_degree = 1;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        size_t k = m->vertex_tri_offsets[v + 1] - m->vertex_tri_offsets[v];
        max_degree = k > max_degree ? k : max_degree;
    }
    uint32_t *uf = selfcol_alloc__array(al, max_degree, sizeof(uint32_t));
    uint32_t *offset = selfcol_alloc__array(al, N + 1, sizeof(uint32_t));
    if (stamp == NULL || vcount == NULL || nondisk == NULL || uf == NULL || offset == NULL)
        goto done;
    memset(nondisk, 0, N);
    memset(vcount, 0, N * sizeof(uint32_t));
    for (size_t e = 0; e < m->edge_count; ++e) {
        uint32_t first = m->edge_tri_offsets[e], k = m->edge_tri_offsets[e + 1] - first;
        const uint32_t *tris = m->edge_tris + first;
        if (k >= 3) {
            for (uint32_t j = 0; j < k; ++j)
                mark_path(nondisk, parent, leaf_of_tri[tris[j]]);
            continue;
        }
        if (k == 1) {
            uint32_t he = half_edge_of(h, tris[0], (uint32_t)e);
            for (uint32_t n = leaf_of_tri[tris[0]]; n != SELFCOL_INVALID_INDEX; n = parent[n])
                if ((status = pair_add(al, &l, n, he)) != SELFCOL_OK)
                    goto done;
            continue;
        }
        uint32_t n1 = leaf_of_tri[tris[0]], n2 = leaf_of_tri[tris[1]];
        uint32_t he1 = half_edge_of(h, tris[0], (uint32_t)e);
        uint32_t he2 = half_edge_of(h, tris[1], (uint32_t)e);
        while (n1 != n2) {
            if (depth[n1] >= depth[n2]) {
                if ((status = pair_add(al, &l, n1, he1)) != SELFCOL_OK)
                    goto done;
                n1 = parent[n1];
            } else {
                if ((status = pair_add(al, &l, n2, he2)) != SELFCOL_OK)
                    goto done;
                n2 = parent[n2];
            }
        }
    }
    status = SELFCOL_ENOMEM;
    memset(stamp, 0xff, N * sizeof(uint32_t));
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        const uint32_t *star = m->vertex_tris + m->vertex_tri_offsets[v];
        uint32_t k = m->vertex_tri_offsets[v + 1] - m->vertex_tri_offsets[v];
        for (uint32_t j = 0; j < k; ++j)
            for (uint32_t n = leaf_of_tri[star[j]]; n != SELFCOL_INVALID_INDEX && stamp[n] != v;
                 n = parent[n]) {
                stamp[n] = v;
                vcount[n]++;
            }
        // Fan connectivity: union the star's triangles across their edges at
        // v. Each triangle is joined to its successor in each such edge's
        // list (a chain connects the edge's triangles as all pairs would),
        // found in the ascending star by binary search, with path halving:
        // O(k log k) for a star of k triangles, also when k pages share one
        // edge (all pairs with linear searches took O(k^3)).
        for (uint32_t j = 0; j < k; ++j)
            uf[j] = j;
        uint32_t components = k;
        for (uint32_t j = 0; j < k; ++j) {
            const uint32_t *te = m->triangle_edges + 3 * (size_t)star[j];
            for (int i = 0; i < 3; ++i) {
                uint32_t e = te[i];
                if (e == SELFCOL_INVALID_INDEX ||
                    (m->edges[2 * e] != v && m->edges[2 * e + 1] != v))
                    continue;
                uint32_t next = successor_on_edge(m, e, star[j]);
                if (next == SELFCOL_INVALID_INDEX)
                    continue;
                uint32_t ra = star_root(uf, j), rb = star_root(uf, position_in(star, k, next));
                if (ra != rb) {
                    uf[ra > rb ? ra : rb] = ra < rb ? ra : rb;
                    components--;
                }
            }
        }
        if (components > 1)
            for (uint32_t j = 0; j < k; ++j)
                mark_path(nondisk, parent, leaf_of_tri[star[j]]);
    }
    // Counting sort of the half-edges by node. Edges were visited in
    // increasing order, so each node's slice comes out sorted by edge.
    // Leaves keep no list (a quarter of all entries, ~6 bytes per
    // triangle): their few triangles give their boundary on demand
    // (selfcol_hierarchy__adjacent), and EXACT's contour proof does not
    // try nodes that small. Their counts still decide SELFCOL_NODE_DISK.
    memset(offset, 0, (N + 1) * sizeof(uint32_t));
    for (size_t i = 0; i < l.count; ++i)
        offset[l.node[i] + 1]++;
    size_t stored = 0;
    for (size_t n = 0; n < N; ++n) {
        selfcol_node *node = &h->nodes[n];
        uint64_t b = offset[n + 1], F = node->tri_count;
        int disk = !nondisk[n] && (3 * F + b) % 2 == 0 &&
                   (int64_t)vcount[n] - (int64_t)((3 * F + b) / 2) + (int64_t)F == 1;
        const uint8_t need = SELFCOL_NODE_CONNECTED | SELFCOL_NODE_ORIENTED;
        if (disk && (node->flags & need) == need)
            node->flags |= SELFCOL_NODE_DISK;
        node->boundary_begin = (uint32_t)stored;
        node->boundary_count = node->child_count == 0 ? 0 : (uint32_t)b;
        offset[n] = (uint32_t)stored; // from here on: the write position
        stored += node->boundary_count;
    }
    h->bedge_total = stored + 1;
    h->bedge = selfcol_alloc__array(al, stored + 1, sizeof(uint32_t));
    if (h->bedge == NULL)
        goto done;
    for (size_t i = 0; i < l.count; ++i)
        if (h->nodes[l.node[i]].child_count > 0)
            h->bedge[offset[l.node[i]]++] = l.half_edge[i];
    status = SELFCOL_OK;
done:
    selfcol_alloc__free_array(al, l.node, l.capacity, sizeof(uint32_t));
    selfcol_alloc__free_array(al, l.half_edge, l.capacity, sizeof(uint32_t));
    selfcol_alloc__free_array(al, offset, N + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, stamp, N, sizeof(uint32_t));
    selfcol_alloc__free_array(al, vcount, N, sizeof(uint32_t));
    selfcol_alloc__free_array(al, nondisk, N, sizeof(uint8_t));
    selfcol_alloc__free_array(al, uf, max_degree, sizeof(uint32_t));
    return status;
}

int selfcol_hierarchy__build(selfcol_hierarchy *h) {
    const selfcol_mesh *m = h->mesh;
    const selfcol_allocator *al = &h->allocator;
    const size_t F = m->triangle_count;
    // Boundary half-edges are stored as (edge << 1) | direction.
    if (m->edge_count >= ((size_t)1 << 31))
        return SELFCOL_ERANGE;
    int status = SELFCOL_ENOMEM;
    patch_graph g, next;
    memset(&g, 0, sizeof g);
    memset(&next, 0, sizeof next);
    builder b;
    memset(&b, 0, sizeof b);
    b.al = al;
    uint32_t *group = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *group_size = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *partner = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *stamp = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *order = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *order_off = selfcol_alloc__array(al, F + 1, sizeof(uint32_t));
    uint32_t *tri_patch = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *node_of = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *parent = NULL, *depth = NULL;
    size_t tree_size = 0;
    if (group == NULL || group_size == NULL || partner == NULL || stamp == NULL || order == NULL ||
        order_off == NULL || tri_patch == NULL || node_of == NULL)
        goto done;
    if ((status = dual_graph(m, al, &g)) != SELFCOL_OK)
        goto done;
    status = SELFCOL_ENOMEM;

    // Leaf rounds: group triangles into patches of a few triangles.
    for (size_t t = 0; t < F; ++t)
        tri_patch[t] = (uint32_t)t;
    for (int round = 0; round < LEAF_ROUNDS && g.adj_off[g.count] > 0; ++round) {
        size_t groups = match_round(&g, group, group_size, partner);
        for (size_t t = 0; t < F; ++t)
            tri_patch[t] = group[tri_patch[t]];
        if ((status = contract(al, &g, group, groups, &next, stamp, order, order_off)) != 0)
            goto done;
        free_graph(al, &g);
        g = next;
        memset(&next, 0, sizeof next);
        status = SELFCOL_ENOMEM;
    }
    // One leaf per patch; its triangles listed in leaf order (counting sort).
    memset(order_off, 0, (g.count + 1) * sizeof(uint32_t));
    for (size_t t = 0; t < F; ++t)
        order_off[tri_patch[t] + 1]++;
    for (size_t p = 0; p < g.count; ++p)
        order_off[p + 1] += order_off[p];
    for (size_t t = 0; t < F; ++t)
        order[order_off[tri_patch[t]]++] = (uint32_t)t;
    for (size_t p = g.count; p > 0; --p)
        order_off[p] = order_off[p - 1];
    order_off[0] = 0;
    for (size_t p = 0; p < g.count; ++p) {
        build_node leaf = {order_off[p], order_off[p + 1] - order_off[p], 0, 1, 1};
        if ((status = add_node(&b, leaf, &node_of[p])) != SELFCOL_OK)
            goto done;
    }
    // `order` now holds the leaves' triangles; keep it aside in tri_patch.
    memcpy(tri_patch, order, F * sizeof(uint32_t));

    // Internal rounds: one node per group of two or more.
    while (g.adj_off[g.count] > 0) {
        size_t groups = match_round(&g, group, group_size, partner);
        if ((status = contract(al, &g, group, groups, &next, stamp, order, order_off)) != 0)
            goto done;
        for (size_t gi = 0; gi < groups; ++gi) {
            uint32_t first = order_off[gi], count = order_off[gi + 1] - order_off[gi];
            if (count == 1) {
                partner[gi] = node_of[order[first]];
                continue;
            }
            uint32_t ids[MAX_GROUP];
            for (uint32_t i = 0; i < count; ++i)
                ids[i] = node_of[order[first + i]];
            build_node inner = {(uint32_t)b.child_count, count, 0, 0, 1};
            if ((status = add_children(&b, ids, count)) != SELFCOL_OK ||
                (status = add_node(&b, inner, &partner[gi])) != SELFCOL_OK)
                goto done;
        }
        memcpy(node_of, partner, groups * sizeof(uint32_t));
        free_graph(al, &g);
        g = next;
        memset(&next, 0, sizeof next);
    }
    // Join the roots of the separate parts pairwise (not connected patches).
    size_t roots = g.count;
    while (roots > 1) {
        size_t out = 0;
        for (size_t i = 0; i < roots; i += 2) {
            if (i + 1 == roots) {
                node_of[out++] = node_of[i];
                continue;
            }
            uint32_t ids[2] = {node_of[i], node_of[i + 1]};
            build_node join = {(uint32_t)b.child_count, 2, 0, 0, 0};
            if ((status = add_children(&b, ids, 2)) != SELFCOL_OK ||
                (status = add_node(&b, join, &node_of[out++])) != SELFCOL_OK)
                goto done;
        }
        roots = out;
    }

    tree_size = b.node_count;
    h->tri_order = selfcol_alloc__array(al, F, sizeof(uint32_t));
    h->owned = selfcol_alloc__array(al, F, sizeof(uint8_t));
    parent = selfcol_alloc__array(al, tree_size, sizeof(uint32_t));
    depth = selfcol_alloc__array(al, tree_size, sizeof(uint32_t));
    status = SELFCOL_ENOMEM;
    if (h->tri_order == NULL || h->owned == NULL || parent == NULL || depth == NULL)
        goto done;
    // group is free now: reuse it as leaf_of_tri.
    if ((status = layout(h, &b, node_of[0], tri_patch, parent, depth, group)) != SELFCOL_OK)
        goto done;
    assign_owners(h);
    // partner and stamp are free now: a BFS queue and the per-edge bad flags
    // (edges may outnumber triangles: allocate that one).
    {
        uint8_t *bad = selfcol_alloc__array(al, m->edge_count + 1, sizeof(uint8_t));
        if (bad == NULL) {
            status = SELFCOL_ENOMEM;
            goto done;
        }
        orient(h, partner, (uint8_t *)stamp, bad);
        mark_unoriented(h, bad, parent, depth, group);
        selfcol_alloc__free_array(al, bad, m->edge_count + 1, sizeof(uint8_t));
    }
    status = build_disks(h, parent, depth, group);
    if (status == SELFCOL_OK) {
        h->min_altitude = selfcol_alloc__array(al, h->node_count, sizeof(float));
        status = h->min_altitude != NULL ? SELFCOL_OK : SELFCOL_ENOMEM;
    }
done:
    free_graph(al, &g);
    free_graph(al, &next);
    selfcol_alloc__free_array(al, b.nodes, b.node_capacity, sizeof(build_node));
    selfcol_alloc__free_array(al, b.children, b.child_capacity, sizeof(uint32_t));
    selfcol_alloc__free_array(al, parent, tree_size, sizeof(uint32_t));
    selfcol_alloc__free_array(al, depth, tree_size, sizeof(uint32_t));
    selfcol_alloc__free_array(al, group, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, group_size, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, partner, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, stamp, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, order, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, order_off, F + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, tri_patch, F, sizeof(uint32_t));
    selfcol_alloc__free_array(al, node_of, F, sizeof(uint32_t));
    return status;
}

// 1 when triangle t is one of node n's (a leaf: a short scan).
static int leaf_holds(const selfcol_hierarchy *h, const selfcol_node *n, uint32_t t) {
    for (uint32_t s = n->tri_begin; s < n->tri_begin + n->tri_count; ++s)
        if (h->tri_order[s] == t)
            return 1;
    return 0;
}

// 1 when edge e is in the (sorted) boundary list of internal node n.
static int on_boundary_list(const selfcol_hierarchy *h, const selfcol_node *n, uint32_t e) {
    const uint32_t *list = h->bedge + n->boundary_begin;
    uint32_t lo = 0, hi = n->boundary_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if ((list[mid] >> 1) < e)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n->boundary_count && (list[lo] >> 1) == e;
}

// Leaf `leaf` against any node `other` (disjoint from it): some edge of the
// leaf's triangles has a triangle of `other` -- for an internal node, the
// edge is then on its boundary list.
static int leaf_adjacent(const selfcol_hierarchy *h, const selfcol_node *leaf,
                         const selfcol_node *other) {
    const selfcol_mesh *m = h->mesh;
    for (uint32_t s = leaf->tri_begin; s < leaf->tri_begin + leaf->tri_count; ++s) {
        uint32_t t = h->tri_order[s];
        for (int k = 0; k < 3; ++k) {
            uint32_t e = m->triangle_edges[3 * (size_t)t + (size_t)k];
            if (other->child_count > 0) {
                if (on_boundary_list(h, other, e))
                    return 1;
                continue;
            }
            // Manifold edges only, as in the boundary lists (an edge of
            // three or more triangles is on no list).
            uint32_t first = m->edge_tri_offsets[e];
            if (m->edge_tri_offsets[e + 1] - first != 2)
                continue;
            uint32_t across =
                m->edge_tris[first] == t ? m->edge_tris[first + 1] : m->edge_tris[first];
            if (leaf_holds(h, other, across))
                return 1;
        }
    }
    return 0;
}

int selfcol_hierarchy__adjacent(const selfcol_hierarchy *h, const selfcol_node *a,
                                const selfcol_node *b) {
    if (a->child_count == 0)
        return leaf_adjacent(h, a, b);
    if (b->child_count == 0)
        return leaf_adjacent(h, b, a);
    // Both boundary lists are sorted by edge: a shared edge shows up as the
    // same edge in both (with opposite directions).
    const uint32_t *x = h->bedge + a->boundary_begin, *y = h->bedge + b->boundary_begin;
    const uint32_t *xe = x + a->boundary_count, *ye = y + b->boundary_count;
    while (x < xe && y < ye) {
        uint32_t ex = *x >> 1, ey = *y >> 1;
        if (ex == ey)
            return 1;
        if (ex < ey)
            ++x;
        else
            ++y;
    }
    return 0;
}
