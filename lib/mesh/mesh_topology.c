// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Topology of a triangle mesh, built once in O(V + F) time and memory (plus a
// sort of each vertex's few outgoing edges):
// - unique edges by bucketing the 3F half-edges on their smaller vertex
//   (a counting sort), then ordering each bucket by the larger vertex; edge ids
//   come out sorted by (lo, hi) with no global comparison sort;
// - edge -> triangles and vertex -> triangles as CSR arrays, ascending;
// - connected components (triangles sharing a vertex) by union-find on the
//   vertices, with path halving;
// - duplicate triangles (same sorted vertex triple) by looking only at the
//   triangles of one of their edges, which a duplicate must share.
#include "base/alloc.h"
#include "base/union_find.h"
#include "mesh/mesh.h"

#include <stdlib.h>
#include <string.h>

// A half-edge waiting in its lo-vertex bucket: the other vertex and the slot
// (3 t + i) it came from.
typedef struct half_edge {
    uint32_t hi;
    uint32_t slot;
} half_edge;

static int half_edge_less(const half_edge *x, const half_edge *y) {
    return x->hi < y->hi || (x->hi == y->hi && x->slot < y->slot);
}

static int half_edge_compare(const void *a, const void *b) {
    const half_edge *x = a, *y = b;
    return half_edge_less(x, y) ? -1 : (half_edge_less(y, x) ? 1 : 0);
}

// Buckets are usually tiny (a vertex owns about three edges, six slots):
// each item's place is the number of items before it in the order (no two
// are equal: their slots differ), counted without a branch (an insertion
// sort's comparisons mispredicted about as often as they ran); qsort for
// high-valence vertices (fans) to stay O(k log k).
#define BUCKET_RANKED 16
static void sort_bucket(half_edge *items, size_t count) {
    if (count > BUCKET_RANKED) {
        qsort(items, count, sizeof *items, half_edge_compare);
        return;
    }
    uint64_t key[BUCKET_RANKED];
    half_edge copy[BUCKET_RANKED];
    for (size_t i = 0; i < count; ++i) {
        key[i] = (uint64_t)items[i].hi << 32 | items[i].slot;
        copy[i] = items[i];
    }
    for (size_t i = 0; i < count; ++i) {
        size_t rank = 0;
        for (size_t j = 0; j < count; ++j)
            rank += key[j] < key[i];
        items[rank] = copy[i];
    }
}

static void sort3(uint32_t out[3], const uint32_t *t) {
    uint32_t a = t[0], b = t[1], c = t[2], x;
    if (a > b) {
        x = a;
        a = b;
        b = x;
    }
    if (b > c) {
        x = b;
        b = c;
        c = x;
    }
    if (a > b) {
        x = a;
        a = b;
        b = x;
    }
    out[0] = a;
    out[1] = b;
    out[2] = c;
}

// Counting sort of the half-edges by their smaller vertex into half
// (bucket_start: V + 1 offsets); flags repeated-index triangles and leaves
// their degenerate slots' triangle_edges invalid.
static void sort_half_edges(selfcol_mesh *m, uint32_t *bucket_start, half_edge *half) {
    const size_t V = m->vertex_count, F = m->triangle_count;
    memset(bucket_start, 0, (V + 1) * sizeof(uint32_t));
    for (size_t t = 0; t < F; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        m->triangle_flags[t] = 0;
        for (int i = 0; i < 3; ++i) {
            uint32_t u = tri[i], w = tri[(i + 1) % 3];
            if (u == w) {
                m->triangle_flags[t] |= SELFCOL_TRIANGLE_REPEATED_INDEX;
                continue;
            }
            bucket_start[(u < w ? u : w) + 1]++;
        }
    }
    for (size_t v = 0; v < V; ++v)
        bucket_start[v + 1] += bucket_start[v];
    for (size_t t = 0; t < F; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        for (int i = 0; i < 3; ++i) {
            uint32_t u = tri[i], w = tri[(i + 1) % 3];
            m->triangle_edges[3 * t + (size_t)i] = SELFCOL_INVALID_INDEX;
            if (u == w)
                continue;
            uint32_t lo = u < w ? u : w, hi = u < w ? w : u;
            // bucket_start[lo] is used as the fill cursor; restored below.
            half[bucket_start[lo]++] = (half_edge){hi, (uint32_t)(3 * t + (size_t)i)};
        }
    }
    for (size_t v = V; v > 0; --v)
        bucket_start[v] = bucket_start[v - 1];
    bucket_start[0] = 0;
}

// Sorts each bucket by its larger vertex; equal ones are one edge. Returns
// the number of edges.
static size_t count_edges(size_t V, const uint32_t *bucket_start, half_edge *half) {
    size_t edge_count = 0;
    for (size_t v = 0; v < V; ++v) {
        half_edge *items = half + bucket_start[v];
        size_t count = bucket_start[v + 1] - bucket_start[v];
        sort_bucket(items, count);
        for (size_t i = 0; i < count; ++i)
            if (i == 0 || items[i].hi != items[i - 1].hi)
                edge_count++;
    }
    return edge_count;
}

// Assigns edge ids (edges, triangle_edges) and counts each edge's distinct
// triangles into edge_tri_offsets (the two slots of a repeated-index
// triangle (a, a, b) on edge (a, b) are adjacent in the bucket order, so
// one look back removes the repeat). Returns the number of entries.
//
// Also counts the misoriented edges: two-triangle edges that the two
// triangles do not traverse once in each direction (the signed count of the
// slots using the edge, +1 from lower to higher index, is not 0). An edge's
// slots are consecutive here, and the slot's own triangle says which way
// it runs.
static size_t number_edges(selfcol_mesh *m, const uint32_t *bucket_start, const half_edge *half) {
    size_t e = 0, tri_entries = 0;
    int direction = 0; // of the current edge's slots
    m->misoriented_edges = 0;
    m->edge_tri_offsets[0] = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const half_edge *items = half + bucket_start[v];
        size_t count = bucket_start[v + 1] - bucket_start[v];
        for (size_t i = 0; i < count; ++i) {
            int new_edge = (i == 0 || items[i].hi != items[i - 1].hi);
            if (new_edge) {
                if (e > 0)
                    m->misoriented_edges +=
                        m->edge_tri_offsets[e] - m->edge_tri_offsets[e - 1] == 2 && direction != 0;
                direction = 0;
                m->edges[2 * e] = (uint32_t)v;
                m->edges[2 * e + 1] = items[i].hi;
                m->edge_tri_offsets[e + 1] = m->edge_tri_offsets[e];
                e++;
            }
            m->triangle_edges[items[i].slot] = (uint32_t)(e - 1);
            direction += m->triangles[items[i].slot] == (uint32_t)v ? 1 : -1;
            if (new_edge || items[i].slot / 3 != items[i - 1].slot / 3) {
                m->edge_tri_offsets[e]++;
                tri_entries++;
            }
        }
    }
    if (e > 0)
        m->misoriented_edges +=
            m->edge_tri_offsets[e] - m->edge_tri_offsets[e - 1] == 2 && direction != 0;
    return tri_entries;
}

// Each edge's triangles (edge_tris, in number_edges' order), and the
// boundary and non-manifold edge counts.
static void list_edge_triangles(selfcol_mesh *m, const uint32_t *bucket_start,
                                const half_edge *half) {
    size_t k = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        const half_edge *items = half + bucket_start[v];
        size_t count = bucket_start[v + 1] - bucket_start[v];
        for (size_t i = 0; i < count; ++i) {
            int new_edge = (i == 0 || items[i].hi != items[i - 1].hi);
            if (new_edge || items[i].slot / 3 != items[i - 1].slot / 3)
                m->edge_tris[k++] = items[i].slot / 3;
        }
    }
    m->boundary_edges = m->nonmanifold_edges = 0;
    for (size_t e = 0; e < m->edge_count; ++e) {
        uint32_t n = m->edge_tri_offsets[e + 1] - m->edge_tri_offsets[e];
        m->boundary_edges += (n == 1);
        m->nonmanifold_edges += (n >= 3);
    }
}

static int build_edges(selfcol_mesh *m) {
    const selfcol_allocator *al = &m->allocator;
    const size_t V = m->vertex_count, F = m->triangle_count;
    int status = SELFCOL_ENOMEM;
    uint32_t *bucket_start = selfcol_alloc__array(al, V + 1, sizeof(uint32_t));
    half_edge *half = selfcol_alloc__array(al, 3 * F, sizeof(half_edge));
    m->triangle_edges = selfcol_alloc__array(al, 3 * F, sizeof(uint32_t));
    m->triangle_flags = selfcol_alloc__array(al, F, sizeof(uint8_t));
    if (bucket_start == NULL || half == NULL || m->triangle_edges == NULL ||
        m->triangle_flags == NULL)
        goto done;
    sort_half_edges(m, bucket_start, half);
    const size_t edge_count = count_edges(V, bucket_start, half);
    m->edge_count = edge_count;
    m->edges = selfcol_alloc__array(al, 2 * edge_count, sizeof(uint32_t));
    m->edge_tri_offsets = selfcol_alloc__array(al, edge_count + 1, sizeof(uint32_t));
    if (m->edge_tri_offsets == NULL || (edge_count > 0 && m->edges == NULL))
        goto done;
    const size_t tri_entries = number_edges(m, bucket_start, half);
    m->edge_tri_total = tri_entries;
    m->edge_tris = selfcol_alloc__array(al, tri_entries, sizeof(uint32_t));
    if (tri_entries > 0 && m->edge_tris == NULL)
        goto done;
    list_edge_triangles(m, bucket_start, half);
    status = SELFCOL_OK;
done:
    selfcol_alloc__free_array(al, half, 3 * F, sizeof(half_edge));
    selfcol_alloc__free_array(al, bucket_start, V + 1, sizeof(uint32_t));
    return status;
}

static int build_vertex_triangles(selfcol_mesh *m) {
    const selfcol_allocator *al = &m->allocator;
    const size_t V = m->vertex_count, F = m->triangle_count;
    m->vertex_tri_offsets = selfcol_alloc__array(al, V + 1, sizeof(uint32_t));
    if (m->vertex_tri_offsets == NULL)
        return SELFCOL_ENOMEM;
    uint32_t *off = m->vertex_tri_offsets;
    memset(off, 0, (V + 1) * sizeof(uint32_t));
    for (size_t t = 0; t < F; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        off[tri[0] + 1]++;
        if (tri[1] != tri[0])
            off[tri[1] + 1]++;
        if (tri[2] != tri[0] && tri[2] != tri[1])
            off[tri[2] + 1]++;
    }
    m->unreferenced_vertices = 0;
    for (size_t v = 0; v < V; ++v) {
        m->unreferenced_vertices += (off[v + 1] == 0);
        off[v + 1] += off[v];
    }
    m->vertex_tri_total = off[V];
    m->vertex_tris = selfcol_alloc__array(al, off[V], sizeof(uint32_t));
    if (m->vertex_tris == NULL)
        return SELFCOL_ENOMEM;
    // Fill with off[v] as the cursor, in triangle order (so ascending), then
    // shift the offsets back.
    for (size_t t = 0; t < F; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        m->vertex_tris[off[tri[0]]++] = (uint32_t)t;
        if (tri[1] != tri[0])
            m->vertex_tris[off[tri[1]]++] = (uint32_t)t;
        if (tri[2] != tri[0] && tri[2] != tri[1])
            m->vertex_tris[off[tri[2]]++] = (uint32_t)t;
    }
    for (size_t v = V; v > 0; --v)
        off[v] = off[v - 1];
    off[0] = 0;
    return SELFCOL_OK;
}

// Boundary loops: the connected sets of boundary edges, two boundary edges
// being connected when they share a vertex (so a loop that touches itself,
// or two loops meeting at a vertex, count once). Union-find over the
// boundary vertices in the caller's V-entry scratch `parent`: the sets
// number the boundary vertices minus the unions that joined two sets.
static void count_boundary_loops(selfcol_mesh *m, uint32_t *parent) {
    for (size_t v = 0; v < m->vertex_count; ++v)
        parent[v] = SELFCOL_INVALID_INDEX;
    size_t boundary_vertices = 0, unions = 0;
    for (size_t e = 0; e < m->edge_count; ++e) {
        if (m->edge_tri_offsets[e + 1] - m->edge_tri_offsets[e] != 1)
            continue;
        for (int k = 0; k < 2; ++k) {
            uint32_t v = m->edges[2 * e + (size_t)k];
            if (parent[v] == SELFCOL_INVALID_INDEX) {
                parent[v] = v;
                boundary_vertices++;
            }
        }
        uint32_t a = selfcol_union_find__root(parent, m->edges[2 * e]),
                 b = selfcol_union_find__root(parent, m->edges[2 * e + 1]);
        if (a != b) {
            parent[a < b ? b : a] = a < b ? a : b;
            unions++;
        }
    }
    m->boundary_loops = boundary_vertices - unions;
}

static int build_components(selfcol_mesh *m) {
    const selfcol_allocator *al = &m->allocator;
    const size_t V = m->vertex_count, F = m->triangle_count;
    m->triangle_component = selfcol_alloc__array(al, F, sizeof(uint32_t));
    uint32_t *parent = selfcol_alloc__array(al, V, sizeof(uint32_t));
    if (m->triangle_component == NULL || parent == NULL) {
        selfcol_alloc__free_array(al, parent, V, sizeof(uint32_t));
        return SELFCOL_ENOMEM;
    }
    for (size_t v = 0; v < V; ++v)
        parent[v] = (uint32_t)v;
    for (size_t t = 0; t < F; ++t) {
        const uint32_t *tri = m->triangles + 3 * t;
        uint32_t r0 = selfcol_union_find__root(parent, tri[0]);
        for (int i = 1; i < 3; ++i) {
            uint32_t r = selfcol_union_find__root(parent, tri[i]);
            if (r != r0) {
                // Union toward the smaller index keeps trees shallow enough
                // with path halving (amortised near-constant per operation).
                if (r < r0) {
                    parent[r0] = r;
                    r0 = r;
                } else {
                    parent[r] = r0;
                }
            }
        }
    }
    // Number components by their lowest triangle, through a root -> label table.
    uint32_t *label = selfcol_alloc__array(al, V, sizeof(uint32_t));
    if (label == NULL) {
        selfcol_alloc__free_array(al, parent, V, sizeof(uint32_t));
        return SELFCOL_ENOMEM;
    }
    memset(label, 0xff, V * sizeof(uint32_t));
    size_t components = 0;
    for (size_t t = 0; t < F; ++t) {
        uint32_t root = selfcol_union_find__root(parent, m->triangles[3 * t]);
        if (label[root] == SELFCOL_INVALID_INDEX)
            label[root] = (uint32_t)components++;
        m->triangle_component[t] = label[root];
    }
    selfcol_alloc__free_array(al, label, V, sizeof(uint32_t));
    m->components = components;
    count_boundary_loops(m, parent);
    selfcol_alloc__free_array(al, parent, V, sizeof(uint32_t));
    return SELFCOL_OK;
}

static void find_duplicates(selfcol_mesh *m) {
    const size_t F = m->triangle_count;
    m->duplicate_triangles = 0;
    m->repeated_index_triangles = 0;
    for (size_t t = 0; t < F; ++t) {
        if (m->triangle_flags[t] & SELFCOL_TRIANGLE_REPEATED_INDEX)
            m->repeated_index_triangles++;
        uint32_t key[3];
        sort3(key, m->triangles + 3 * t);
        // A duplicate shares every vertex, hence every edge: scan the
        // triangles of one edge, or of the vertex when there is no edge
        // (a triangle (a, a, a)).
        const uint32_t *cand;
        size_t count;
        uint32_t e = SELFCOL_INVALID_INDEX;
        for (int i = 0; i < 3 && e == SELFCOL_INVALID_INDEX; ++i)
            e = m->triangle_edges[3 * t + (size_t)i];
        if (e != SELFCOL_INVALID_INDEX) {
            cand = m->edge_tris + m->edge_tri_offsets[e];
            count = m->edge_tri_offsets[e + 1] - m->edge_tri_offsets[e];
        } else {
            cand = m->vertex_tris + m->vertex_tri_offsets[key[0]];
            count = m->vertex_tri_offsets[key[0] + 1] - m->vertex_tri_offsets[key[0]];
        }
        for (size_t i = 0; i < count && cand[i] < t; ++i) {
            uint32_t other[3];
            sort3(other, m->triangles + 3 * (size_t)cand[i]);
            if (other[0] == key[0] && other[1] == key[1] && other[2] == key[2]) {
                m->triangle_flags[t] |= SELFCOL_TRIANGLE_DUPLICATE;
                m->duplicate_triangles++;
                break;
            }
        }
    }
}

int selfcol_mesh__build_topology(selfcol_mesh *m) {
    int status = build_edges(m);
    if (status == SELFCOL_OK)
        status = build_vertex_triangles(m);
    if (status == SELFCOL_OK)
        status = build_components(m);
    if (status == SELFCOL_OK) {
        find_duplicates(m);
    }
    return status;
}

void selfcol_mesh__free_topology(selfcol_mesh *m) {
    const selfcol_allocator *al = &m->allocator;
    selfcol_alloc__free_array(al, m->edges, 2 * m->edge_count, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->triangle_edges, 3 * m->triangle_count, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->edge_tri_offsets, m->edge_count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->edge_tris, m->edge_tri_total, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->vertex_tri_offsets, m->vertex_count + 1, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->vertex_tris, m->vertex_tri_total, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->triangle_component, m->triangle_count, sizeof(uint32_t));
    selfcol_alloc__free_array(al, m->triangle_flags, m->triangle_count, sizeof(uint8_t));
    m->edges = m->triangle_edges = m->edge_tri_offsets = m->edge_tris = NULL;
    m->vertex_tri_offsets = m->vertex_tris = m->triangle_component = NULL;
    m->triangle_flags = NULL;
}
