// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Boundaries and disks, the build's last stage (hierarchy_build.h): every
// internal node gets the list of its patch's boundary half-edges, sorted by
// edge (the adjacency test of SEED/CONE in traverse.c and the contour test
// of EXACT in contour.c read it), and every node whose patch is a
// topological disk gets SELFCOL_NODE_DISK (EXACT's contour criterion applies
// only to disks). Two passes over the edges, climbing the tree from their
// triangles' leaves (the first counts each node's boundary and joins the
// triangles' corners across the edge, the second writes the lists), one over
// the slots (vertex counts) and one over the corners (fans: the sets the
// joins left at each vertex).
#include "base/alloc.h"
#include "base/union_find.h"
#include "hierarchy/hierarchy_build.h"

#include <string.h>

// The corner of triangle t at vertex v (t has v), as 3 t + slot.
static uint32_t corner_of(const selfcol_mesh *m, uint32_t t, uint32_t v) {
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    return 3 * t + (tri[0] == v ? 0u : (tri[1] == v ? 1u : 2u));
}

// Joins the sets of corners a and b (the smaller root stays).
static void join_corners(uint32_t *uf, uint32_t a, uint32_t b) {
    uint32_t ra = selfcol_union_find__root(uf, a), rb = selfcol_union_find__root(uf, b);
    if (ra != rb)
        uf[ra > rb ? ra : rb] = ra < rb ? ra : rb;
}

// Triangle t on edge e = (lo, hi): its slot i on e and the half-edge there,
// oriented with t (after the build's flip) so the patch containing t lies
// on its left, encoded as (e << 1) | reversed: reversed when it runs from
// the edge's larger vertex to its smaller one; corner[0] and corner[1] get
// t's corners (3 t + slot) at lo and at hi.
//
// The slot is the first i whose corners i and i + 1 are the edge's ends:
// the slot selfcol_hierarchy__slot_of_edge finds (triangle_edges[3 t + i]
// is e exactly when they are, a slot with a repeated index having no edge),
// read from the triangle's corners, which are needed anyway, instead of
// from its edges, a second line of memory per triangle (2 % of a build of
// cloth-ball 92).
static uint32_t half_edge_of(const selfcol_hierarchy *h, uint32_t t, uint32_t e, uint32_t lo,
                             uint32_t hi, uint32_t corner[2]) {
    const selfcol_mesh *m = h->mesh;
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    int i = 2;
    for (int k = 1; k >= 0; --k)
        if ((tri[k] == lo && tri[k + 1] == hi) || (tri[k] == hi && tri[k + 1] == lo))
            i = k;
    const int j = (i + 1) % 3;
    const int from_lo = tri[i] == lo;
    corner[0] = 3 * t + (uint32_t)(from_lo ? i : j);
    corner[1] = 3 * t + (uint32_t)(from_lo ? j : i);
    int reversed = !from_lo;
    if (h->owned[t] & SELFCOL_TRIANGLE_FLIPPED)
        reversed = !reversed;
    return (e << 1) | (uint32_t)reversed;
}

// The lowest common ancestor of nodes a and b.
static uint32_t common_ancestor(const uint32_t *parent, const uint32_t *depth, uint32_t a,
                                uint32_t b) {
    while (depth[a] > depth[b])
        a = parent[a];
    while (depth[b] > depth[a])
        b = parent[b];
    while (a != b) {
        a = parent[a];
        b = parent[b];
    }
    return a;
}

// One node on an edge's climb: counted (offset[n + 1]++) without bedge,
// else its half-edge written at offset[n]++ unless n is the climb's leaf
// (leaves keep no list).
static void on_boundary(uint32_t n, uint32_t he, int leaf, uint32_t *offset, uint32_t *bedge) {
    if (bedge == NULL)
        offset[n + 1]++;
    else if (!leaf)
        bedge[offset[n]++] = he;
}

// Climbs from the leaves n1 and n2 of a manifold edge's two triangles to
// their lowest common ancestor, or from the leaf n1 of a mesh-boundary
// edge's triangle (n2 = SELFCOL_INVALID_INDEX) to the root: the edge is on
// the boundary of every node passed, as half-edge he1 on n1's side and he2
// on n2's (on_boundary: counted, or written).
static void climb(const uint32_t *parent, const uint32_t *depth, uint32_t n1, uint32_t he1,
                  uint32_t n2, uint32_t he2, uint32_t *offset, uint32_t *bedge) {
    int leaf1 = 1, leaf2 = 1; // n1, n2 still the leaves
    if (n2 == SELFCOL_INVALID_INDEX) {
        for (; n1 != SELFCOL_INVALID_INDEX; n1 = parent[n1], leaf1 = 0)
            on_boundary(n1, he1, leaf1, offset, bedge);
        return;
    }
    while (n1 != n2) {
        if (depth[n1] >= depth[n2]) {
            on_boundary(n1, he1, leaf1, offset, bedge);
            leaf1 = 0;
            n1 = parent[n1];
        } else {
            on_boundary(n2, he2, leaf2, offset, bedge);
            leaf2 = 0;
            n2 = parent[n2];
        }
    }
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
//   leaves (counted once per node; see below). A vertex whose triangles do
//   not form one edge-connected fan (a bowtie: its corners joined across
//   its edges form more than one set) makes its ancestors non-disks.
// - With interior edges manifold (the ORIENTED flag), a patch of F triangles
//   and b boundary edges has E = (3F + b) / 2 edges; it is a disk iff it is
//   connected, oriented, manifold and V - E + F = 1 (an orientable connected
//   surface has chi = 2 - 2 genus - loops).
int selfcol_hierarchy__build_boundaries(selfcol_hierarchy *h, const uint32_t *parent,
                                        const uint32_t *depth, const uint32_t *leaf_of_tri) {
    const selfcol_mesh *m = h->mesh;
    const selfcol_allocator *al = &h->allocator;
    const size_t N = h->node_count;
    int status = SELFCOL_ENOMEM;
    // Each vertex's last leaf in the vertex-count sweep (below).
    uint32_t *last_leaf = selfcol_alloc__array(al, m->vertex_count + 1, sizeof(uint32_t));
    uint32_t *vcount = selfcol_alloc__array(al, N, sizeof(uint32_t));
    uint8_t *nondisk = selfcol_alloc__array(al, N, sizeof(uint8_t));
    const size_t corners = 3 * m->triangle_count;
    uint32_t *uf = selfcol_alloc__array(al, corners, sizeof(uint32_t)); // corner sets
    uint32_t *fans = selfcol_alloc__array(al, m->vertex_count, sizeof(uint32_t));
    uint32_t *offset = selfcol_alloc__array(al, N + 1, sizeof(uint32_t));
    // Each edge's half-edges (its first triangle's, then its second's, if
    // any), found by the counting pass for the writing one.
    uint32_t *edge_half = selfcol_alloc__array(al, 2 * m->edge_count + 1, sizeof(uint32_t));
    if (last_leaf == NULL || vcount == NULL || nondisk == NULL || uf == NULL || fans == NULL ||
        offset == NULL || edge_half == NULL)
        goto done;
    memset(nondisk, 0, N);
    memset(vcount, 0, N * sizeof(uint32_t));
    // A triangle's corners at one vertex (a repeated index) are one corner.
    for (uint32_t c = 0; c < corners; ++c)
        uf[c] = c;
    for (size_t t = 0; t < m->triangle_count; ++t)
        if (m->triangle_flags[t] & SELFCOL_TRIANGLE_REPEATED_INDEX) {
            const uint32_t *tri = m->triangles + 3 * t;
            for (uint32_t i = 0; i < 3; ++i)
                join_corners(uf, (uint32_t)(3 * t) + i, corner_of(m, (uint32_t)t, tri[i]));
        }
    // Each node's boundary count b goes to offset[n + 1] (climb); the
    // half-edges are written in a second pass, once the counts place them.
    memset(offset, 0, (N + 1) * sizeof(uint32_t));
    for (size_t e = 0; e < m->edge_count; ++e) {
        const uint32_t first = m->edge_tri_offsets[e], k = m->edge_tri_offsets[e + 1] - first;
        const uint32_t *tris = m->edge_tris + first;
        const uint32_t lo = m->edges[2 * e], hi = m->edges[2 * e + 1];
        if (k >= 3) {
            // Fans: the corners at each end of the edge of each triangle and
            // the next one in the edge's list are joined (a chain connects
            // the edge's triangles as all pairs would).
            for (uint32_t j = 0; j + 1 < k; ++j) {
                join_corners(uf, corner_of(m, tris[j], lo), corner_of(m, tris[j + 1], lo));
                join_corners(uf, corner_of(m, tris[j], hi), corner_of(m, tris[j + 1], hi));
            }
            for (uint32_t j = 0; j < k; ++j)
                mark_path(nondisk, parent, leaf_of_tri[tris[j]]);
            continue;
        }
        uint32_t c1[2], c2[2];
        edge_half[2 * e] = half_edge_of(h, tris[0], (uint32_t)e, lo, hi, c1);
        uint32_t n2 = SELFCOL_INVALID_INDEX;
        edge_half[2 * e + 1] = 0; // no second side (a mesh-boundary edge)
        if (k == 2) {
            edge_half[2 * e + 1] = half_edge_of(h, tris[1], (uint32_t)e, lo, hi, c2);
            join_corners(uf, c1[0], c2[0]);
            join_corners(uf, c1[1], c2[1]);
            n2 = leaf_of_tri[tris[1]];
        }
        climb(parent, depth, leaf_of_tri[tris[0]], 0, n2, 0, offset, NULL);
    }
    // Vertex counts. A vertex's leaves in depth-first order (the order of
    // their triangles' slots), L1 < ... < Lj: +1 at each and -1 at the
    // lowest common ancestor of each consecutive two. A node holding some of
    // them holds a contiguous run and the ancestors of the run's consecutive
    // pairs, but not those of pairs leaving the run (proper ancestors of the
    // node): its subtree sums to 1, and that of a node holding none to 0.
    // One reverse sweep sums the subtrees (children come after their
    // parents). One sweep over the slots in order meets every vertex's
    // leaves in that order: last_leaf[v] is the one before, so a vertex
    // costs its corners and the short climbs between neighbouring leaves,
    // with no sort of its star and no climb to the root.
    for (size_t v = 0; v < m->vertex_count; ++v)
        last_leaf[v] = SELFCOL_INVALID_INDEX;
    for (uint32_t slot = 0; slot < m->triangle_count; ++slot) {
        const uint32_t t = h->tri_order[slot], leaf = leaf_of_tri[t];
        const uint32_t *tri = m->triangles + 3 * (size_t)t;
        for (int i = 0; i < 3; ++i) {
            const uint32_t v = tri[i], previous = last_leaf[v];
            if (previous == leaf)
                continue; // a repeated corner, or v seen already in this leaf
            vcount[leaf]++;
            if (previous != SELFCOL_INVALID_INDEX)
                vcount[common_ancestor(parent, depth, previous, leaf)]--;
            last_leaf[v] = leaf;
        }
    }
    for (size_t id = N; id-- > 1;)
        vcount[parent[id]] += vcount[id];
    // A vertex whose corners form more than one set (a bowtie: its
    // triangles are not one edge-connected fan) makes its ancestors non-disks.
    memset(fans, 0, m->vertex_count * sizeof(uint32_t));
    for (uint32_t c = 0; c < corners; ++c)
        fans[m->triangles[c]] += uf[c] == c;
    for (uint32_t v = 0; v < m->vertex_count; ++v) {
        if (fans[v] <= 1)
            continue;
        const uint32_t *star = m->vertex_tris + m->vertex_tri_offsets[v];
        const uint32_t k = m->vertex_tri_offsets[v + 1] - m->vertex_tri_offsets[v];
        for (uint32_t j = 0; j < k; ++j)
            mark_path(nondisk, parent, leaf_of_tri[star[j]]);
    }
    // The lists, laid out by node. Edges are visited in increasing order, so
    // each node's list comes out sorted by edge. Leaves keep no list (a
    // quarter of all entries, ~6 bytes per triangle): their few triangles
    // give their boundary on demand (the adjacency test of traverse.c), and
    // EXACT's contour proof does not try nodes that small. Their counts still
    // decide SELFCOL_NODE_DISK.
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
    status = SELFCOL_ENOMEM;
    h->bedge_total = stored + 1;
    h->bedge = selfcol_alloc__array(al, stored + 1, sizeof(uint32_t));
    if (h->bedge == NULL)
        goto done;
    for (size_t e = 0; e < m->edge_count; ++e) {
        const uint32_t first = m->edge_tri_offsets[e], k = m->edge_tri_offsets[e + 1] - first;
        if (k >= 3)
            continue;
        const uint32_t *tris = m->edge_tris + first;
        climb(parent, depth, leaf_of_tri[tris[0]], edge_half[2 * e],
              k == 2 ? leaf_of_tri[tris[1]] : SELFCOL_INVALID_INDEX, edge_half[2 * e + 1], offset,
              h->bedge);
    }
    status = SELFCOL_OK;
done:
    selfcol_alloc__free_array(al, offset, N + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, edge_half, 2 * m->edge_count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, last_leaf, m->vertex_count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, vcount, N, sizeof(uint32_t));
    selfcol_alloc__free_array(al, nondisk, N, sizeof(uint8_t));
    selfcol_alloc__free_array(al, uf, corners, sizeof(uint32_t));
    selfcol_alloc__free_array(al, fans, m->vertex_count, sizeof(uint32_t));
    return status;
}
