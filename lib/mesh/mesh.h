// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The mesh object: positions plus the topology built once at creation.
#ifndef SELFCOL_MESH_INTERNAL_H
#define SELFCOL_MESH_INTERNAL_H

#include <selfcol/mesh.h>

#include <math.h>

// Largest triangle count: slot ids (3 t + i) and CSR offsets are uint32_t.
#define SELFCOL_MESH_MAX_TRIANGLES ((size_t)(UINT32_MAX - 1) / 3)
#define SELFCOL_MESH_MAX_VERTICES ((size_t)UINT32_MAX - 1)

// What tells one mesh from another where an address cannot: a freed mesh's
// address may be handed to the next mesh created. Handles that remember a
// mesh between calls (a store, a hierarchy) keep its identity and compare it
// at every call: a different vertex, triangle or edge count means another
// mesh (and indices that would be out of range), the fingerprint of the
// triangle indices tells apart meshes with the same counts, and the creation
// time meshes with the same topology.
typedef struct selfcol_mesh_identity {
    size_t vertex_count;
    size_t triangle_count;
    size_t edge_count;
    uint64_t fingerprint; // of the counts and the triangle indices (mesh.c)
    uint64_t created;     // creation time, ns of the monotonic clock (mesh.c)
} selfcol_mesh_identity;

struct selfcol_mesh {
    selfcol_allocator allocator;
    selfcol_mesh_identity identity;
    size_t vertex_count;
    size_t triangle_count;
    size_t edge_count;

    double *positions;          // 3 V, current frame
    uint64_t positions_version; // bumped by every accepted set_positions
    uint32_t *triangles;        // 3 F, as given

    uint32_t *edges;              // 2 E, (lo, hi), sorted
    uint32_t *triangle_edges;     // 3 F, slot i = edge (t[i], t[i+1]); INVALID if collapsed
    uint32_t *edge_tri_offsets;   // E + 1
    uint32_t *edge_tris;          // edge -> triangles, ascending
    uint32_t *vertex_tri_offsets; // V + 1
    uint32_t *vertex_tris;        // vertex -> triangles, ascending
    uint32_t *triangle_component; // F
    uint8_t *triangle_flags;      // F: REPEATED_INDEX | DUPLICATE

    size_t edge_tri_total;   // entries of edge_tris
    size_t vertex_tri_total; // entries of vertex_tris
    size_t boundary_edges;
    size_t nonmanifold_edges;
    size_t boundary_loops;
    size_t misoriented_edges;
    size_t components;
    size_t unreferenced_vertices;
    size_t repeated_index_triangles;
    size_t duplicate_triangles;
};

// Builds every topology array of a mesh whose vertex_count, triangle_count and
// triangles are set. Returns SELFCOL_OK, SELFCOL_ENOMEM or SELFCOL_ERANGE; on
// failure the arrays built so far stay in the mesh for destroy to free.
/** Whether x meets the coordinate contract (mesh.h): finite, and 0 or of
 *  magnitude in [SELFCOL_MESH_MIN_COORDINATE, SELFCOL_MESH_MAX_COORDINATE]. */
static inline int selfcol_mesh__coordinate_in_contract(double x) {
    double a = fabs(x); // NaN fails both comparisons below
    return a == 0.0 || (a >= SELFCOL_MESH_MIN_COORDINATE && a <= SELFCOL_MESH_MAX_COORDINATE);
}

/** Whether all 3 x vertex_count coordinates meet the contract: the check of
 *  the positions a mesh does not hold (the start of a step, for sweeps and
 *  swept store updates), the same as the mesh's own. */
int selfcol_mesh__positions_in_contract(const double *xyz, size_t vertex_count);

int selfcol_mesh__build_topology(selfcol_mesh *mesh);

// Frees the topology arrays (used by destroy).
void selfcol_mesh__free_topology(selfcol_mesh *mesh);

// 1 when mesh is the one whose identity was kept (same counts and fingerprint).
static inline int selfcol_mesh__is(const selfcol_mesh *mesh, const selfcol_mesh_identity *id) {
    const selfcol_mesh_identity *m = &mesh->identity;
    return m->vertex_count == id->vertex_count && m->triangle_count == id->triangle_count &&
           m->edge_count == id->edge_count && m->fingerprint == id->fingerprint &&
           m->created == id->created;
}

// Position of vertex v.
static inline const double *selfcol_mesh__position(const selfcol_mesh *mesh, uint32_t v) {
    return mesh->positions + 3 * (size_t)v;
}

// Number of triangles around vertex v (0: the vertex takes part in no contact).
static inline uint32_t selfcol_mesh__vertex_degree(const selfcol_mesh *mesh, uint32_t v) {
    return mesh->vertex_tri_offsets[v + 1] - mesh->vertex_tri_offsets[v];
}

#endif // SELFCOL_MESH_INTERNAL_H
