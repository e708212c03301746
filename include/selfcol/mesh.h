// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file mesh.h
 * @defgroup mesh Triangle meshes
 * A `selfcol_mesh` holds the positions and the topology of one triangle surface.
 *
 * What is accepted, and handled:
 * - non-manifold edges (three or more triangles on one edge), boundaries,
 *   several connected components, vertices referenced by no triangle (they
 *   take part in no contact);
 * - degenerate triangles: zero-area triangles (collinear or coincident
 *   corners) and triangles with a repeated index such as (a, a, b). Their
 *   distinct edges are ordinary edges; they take part in vertex-triangle and
 *   edge-edge proximities (the distance to a zero-area triangle is the distance
 *   to the segment or point it collapses to), but an edge never "crosses" a
 *   zero-area triangle (see contacts.h);
 * - duplicate triangles (the same three vertices, in any order): every copy
 *   is kept, with its index, and flagged SELFCOL_TRIANGLE_DUPLICATE after the
 *   first; queries collapse the copies into the first occurrence, which is
 *   the triangle their contacts name (contacts.h). They share their
 *   vertices, so they never collide with each other.
 *
 * What is rejected, with SELFCOL_EINVAL unless stated:
 * - a NULL pointer where data is required;
 * - no triangles at all (an empty mesh), or vertex_count == 0;
 * - a triangle index >= vertex_count;
 * - a NaN or infinite coordinate;
 * - more than 2^32 - 2 vertices or more than (2^32 - 2) / 3 = 1431655764
 *   triangles (SELFCOL_ERANGE): indices and internal offsets are uint32_t and
 *   UINT32_MAX is reserved for SELFCOL_INVALID_INDEX;
 * - coordinates outside the range the arithmetic holds in (SELFCOL_ERANGE):
 *   every coordinate must be 0 or have a magnitude from
 *   SELFCOL_MESH_MIN_COORDINATE = 2^-200 (about 6.2e-61) to
 *   SELFCOL_MESH_MAX_COORDINATE = 2^200 (about 1.6e60). Inside the range
 *   every contact set is exact; beyond it squared lengths and products
 *   overflow or underflow and answers would be silently wrong, so such
 *   positions are refused. Float positions are always inside (their
 *   smallest subnormal is 1.4e-45). A double simulation that lets a
 *   coordinate decay towards 0 should flush it to 0 below 2^-200.
 * @{
 */
#ifndef SELFCOL_MESH_H
#define SELFCOL_MESH_H

#include "common.h"

SELFCOL_BEGIN_DECLS

/** Largest coordinate magnitude accepted: 2^200 (exactly this double). */
#define SELFCOL_MESH_MAX_COORDINATE 1.6069380442589903e+60
/** Smallest nonzero coordinate magnitude accepted: 2^-200 (exactly this double). */
#define SELFCOL_MESH_MIN_COORDINATE 6.223015277861142e-61

/** Opaque triangle mesh: positions plus topology built once at creation. */
typedef struct selfcol_mesh selfcol_mesh;

/** Options for selfcol_mesh_create(). Initialise with selfcol_mesh_options_init(). */
typedef struct selfcol_mesh_options {
    unsigned int version;        /**< SELFCOL_MESH_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free */
} selfcol_mesh_options;

#define SELFCOL_MESH_OPTIONS_VERSION 1

/**
 * Writes the defaults into opts.
 * @param[out] opts the struct to initialise
 * @param[in] version SELFCOL_MESH_OPTIONS_VERSION
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION if
 *         version is 0 or newer than this library.
 */
SELFCOL_API int selfcol_mesh_options_init(selfcol_mesh_options *opts, unsigned int version);

/** What selfcol_mesh_check() found wrong, if anything. Values are pinned. */
typedef enum selfcol_mesh_problem_kind {
    SELFCOL_MESH_PROBLEM_NONE = 0,       /**< the input is accepted */
    SELFCOL_MESH_PROBLEM_ARGUMENT = 1,   /**< a NULL pointer or a zero count */
    SELFCOL_MESH_PROBLEM_COUNT = 2,      /**< more vertices or triangles than indices hold */
    SELFCOL_MESH_PROBLEM_INDEX = 3,      /**< a triangle's corner is not a vertex */
    SELFCOL_MESH_PROBLEM_NOT_FINITE = 4, /**< a NaN or infinite coordinate */
    SELFCOL_MESH_PROBLEM_TOO_LARGE = 5,  /**< beyond SELFCOL_MESH_MAX_COORDINATE */
    SELFCOL_MESH_PROBLEM_TOO_SMALL = 6   /**< nonzero, below SELFCOL_MESH_MIN_COORDINATE */
} selfcol_mesh_problem_kind;

/**
 * The first thing selfcol_mesh_create() would refuse in an input, named: the
 * culprit the status alone does not give. The caller sets version.
 */
typedef struct selfcol_mesh_problem {
    unsigned int version; /**< SELFCOL_MESH_PROBLEM_VERSION */
    int status;           /**< what selfcol_mesh_create() returns for it (0: accepted) */
    uint32_t kind;        /**< selfcol_mesh_problem_kind */
    /** The corner (INDEX) or the axis, 0 = x (coordinates); else 0. */
    uint32_t component;
    /** The triangle (INDEX) or the vertex (coordinates); else 0. */
    uint64_t element;
    /** The offending index or coordinate (NaN for NONE, ARGUMENT and COUNT). */
    double value;
    /** Why, without naming the element, for a front that names it its own
     *  way: "is not a vertex (vertex_count = 6)", "is not finite", ... */
    char reason[96];
    /** The whole sentence, in the C API's names: "triangles[53] (triangle
     *  17, corner 2) = 99 is not a vertex (vertex_count = 50)". */
    char message[256];
} selfcol_mesh_problem;

#define SELFCOL_MESH_PROBLEM_VERSION 1

/**
 * Checks an input of selfcol_mesh_create() and names its first problem (the
 * counts, then the indices in order, then the coordinates in order: the
 * first non-finite one, else the first out of range), allocating nothing.
 * @param[in,out] problem its version set by the caller; the rest written
 * @return the status selfcol_mesh_create() returns for this input, short of
 *         allocation (SELFCOL_OK, SELFCOL_EINVAL, SELFCOL_ERANGE);
 *         SELFCOL_EINVAL for a NULL problem; SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_mesh_check(size_t vertex_count, const double *positions,
                                   size_t triangle_count, const uint32_t *triangles,
                                   selfcol_mesh_problem *problem);

/**
 * As selfcol_mesh_check(), for positions alone: what
 * selfcol_mesh_set_positions() refuses in them.
 */
SELFCOL_API int selfcol_mesh_check_positions(size_t vertex_count, const double *positions,
                                             selfcol_mesh_problem *problem);

/**
 * Creates a mesh from double positions and triangle indices, and builds its
 * topology (unique edges, edge->triangles, vertex->triangles, boundary and
 * non-manifold edges, duplicate and repeated-index triangles, connected
 * components) in O(V + F) time and memory.
 * @param[out] out the new mesh; set to NULL on failure. Caller owns it and
 *             frees it with selfcol_mesh_destroy().
 * @param[in] vertex_count number of vertices
 * @param[in] positions vertex_count * 3 doubles (x, y, z per vertex). Copied.
 * @param[in] triangle_count number of triangles
 * @param[in] triangles triangle_count * 3 vertex indices. Copied.
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (see the list of rejected input above);
 *         SELFCOL_ERANGE; SELFCOL_EVERSION; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_mesh_create(selfcol_mesh **out, size_t vertex_count,
                                    const double *positions, size_t triangle_count,
                                    const uint32_t *triangles, const selfcol_mesh_options *opts);

/**
 * Same as selfcol_mesh_create(), from float positions laid out with a stride,
 * as simulators keep them (e.g. Bullet's btSoftBody::Node or an interleaved
 * vertex buffer). Positions are widened to double.
 * @param[in] positions address of the first vertex's x; y and z follow it
 * @param[in] stride_bytes distance in bytes between two vertices' x; at least
 *            3 * sizeof(float) and a multiple of sizeof(float)
 * @return as selfcol_mesh_create(); SELFCOL_EINVAL for a bad stride.
 */
SELFCOL_API int selfcol_mesh_create_float(selfcol_mesh **out, size_t vertex_count,
                                          const float *positions, size_t stride_bytes,
                                          size_t triangle_count, const uint32_t *triangles,
                                          const selfcol_mesh_options *opts);

/**
 * Destroys a mesh. Accepts NULL. The hierarchies built on it may then only
 * be destroyed (or asked their byte count): any other call on them would
 * read the freed mesh.
 * @param[in] mesh the mesh to free
 */
SELFCOL_API void selfcol_mesh_destroy(selfcol_mesh *mesh);

/**
 * Replaces all positions (a new frame). Allocates nothing. The input is
 * validated before anything is written: on error the mesh keeps its previous
 * positions. Positions equal (==) to the current ones are not a move: the
 * hierarchies stay refit, and a static scene surface stays valid.
 * @param[in,out] mesh the mesh
 * @param[in] positions vertex_count * 3 doubles. Copied.
 * @param[in] vertex_count the vertices the buffer holds: must equal the
 *            mesh's (a shorter buffer is never read past its end)
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments, a vertex_count other
 *         than the mesh's, or a NaN/infinite coordinate; SELFCOL_ERANGE for
 *         coordinates outside the contract (SELFCOL_MESH_MAX_COORDINATE).
 */
SELFCOL_API int selfcol_mesh_set_positions(selfcol_mesh *mesh, const double *positions,
                                           size_t vertex_count);

/**
 * Float variant of selfcol_mesh_set_positions(), with a stride in bytes: the
 * buffer holds (vertex_count - 1) * stride_bytes + 3 * sizeof(float) bytes.
 * @return as selfcol_mesh_set_positions(); SELFCOL_EINVAL for a bad stride.
 */
SELFCOL_API int selfcol_mesh_set_positions_float(selfcol_mesh *mesh, const float *positions,
                                                 size_t stride_bytes, size_t vertex_count);

/** Quantities reported by selfcol_mesh_count(). Values are pinned. */
typedef enum selfcol_mesh_quantity {
    SELFCOL_MESH_VERTICES = 0,                 /**< vertex_count as created */
    SELFCOL_MESH_TRIANGLES = 1,                /**< triangle_count as created */
    SELFCOL_MESH_EDGES = 2,                    /**< unique undirected edges */
    SELFCOL_MESH_BOUNDARY_EDGES = 3,           /**< edges with exactly one triangle */
    SELFCOL_MESH_NONMANIFOLD_EDGES = 4,        /**< edges with three or more triangles */
    SELFCOL_MESH_COMPONENTS = 5,               /**< components (triangles sharing a vertex) */
    SELFCOL_MESH_UNREFERENCED_VERTICES = 6,    /**< vertices used by no triangle */
    SELFCOL_MESH_REPEATED_INDEX_TRIANGLES = 7, /**< triangles such as (a, a, b) */
    SELFCOL_MESH_DUPLICATE_TRIANGLES = 8,      /**< triangles whose vertex set appeared before */
    SELFCOL_MESH_ZERO_AREA_TRIANGLES = 9,      /**< exactly collinear corners, current
                                                    positions; O(F) per call */
    /** Connected sets of boundary edges, boundary edges sharing a vertex
     *  being connected: 1 for a disk, 0 for a closed surface, 2 for an annulus;
     *  loops that touch at a vertex count once. */
    SELFCOL_MESH_BOUNDARY_LOOPS = 10,
    /** Edges with exactly two triangles that do not traverse it once in each
     *  direction. 0, with no non-manifold edge, means the mesh is consistently
     *  oriented (its triangle normals agree across every edge). */
    SELFCOL_MESH_MISORIENTED_EDGES = 11
} selfcol_mesh_quantity;

/**
 * Returns a count describing the mesh.
 * @param[in] mesh the mesh (NULL gives 0)
 * @param[in] quantity what to count; an unknown value gives 0
 * @return the count.
 */
SELFCOL_API size_t selfcol_mesh_count(const selfcol_mesh *mesh, selfcol_mesh_quantity quantity);

/**
 * Current positions, vertex_count * 3 doubles.
 * @return borrowed pointer, valid until the mesh is destroyed; NULL for NULL.
 */
SELFCOL_API const double *selfcol_mesh_positions(const selfcol_mesh *mesh);

/**
 * Triangle indices as given at creation, triangle_count * 3.
 * @return borrowed pointer, valid until the mesh is destroyed; NULL for NULL.
 */
SELFCOL_API const uint32_t *selfcol_mesh_triangles(const selfcol_mesh *mesh);

/**
 * Unique edges, two vertex indices each, the smaller first. Edges are sorted
 * by (first, second) vertex.
 * @return borrowed pointer to edge_count * 2 indices; NULL for NULL.
 */
SELFCOL_API const uint32_t *selfcol_mesh_edges(const selfcol_mesh *mesh);

/**
 * The three edges of a triangle: edge (t[0],t[1]), (t[1],t[2]), (t[2],t[0]).
 * For a repeated-index triangle the collapsed slot is SELFCOL_INVALID_INDEX.
 * @param[out] edges_out three edge indices
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL or an out-of-range triangle.
 */
SELFCOL_API int selfcol_mesh_triangle_edges(const selfcol_mesh *mesh, uint32_t triangle,
                                            uint32_t edges_out[3]);

/**
 * Triangles incident to an edge, ascending.
 * @param[out] triangles_out borrowed pointer, valid until the mesh is destroyed
 * @param[out] count_out number of triangles (1: boundary, 2: manifold, 3+: non-manifold)
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL or an out-of-range edge.
 */
SELFCOL_API int selfcol_mesh_edge_triangles(const selfcol_mesh *mesh, uint32_t edge,
                                            const uint32_t **triangles_out, size_t *count_out);

/**
 * Triangles incident to a vertex, ascending (each once, even for a
 * repeated-index triangle).
 * @param[out] triangles_out borrowed pointer, valid until the mesh is destroyed
 * @param[out] count_out number of triangles (0 for an unreferenced vertex)
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL or an out-of-range vertex.
 */
SELFCOL_API int selfcol_mesh_vertex_triangles(const selfcol_mesh *mesh, uint32_t vertex,
                                              const uint32_t **triangles_out, size_t *count_out);

/** Bits returned by selfcol_mesh_triangle_flags(). */
typedef enum selfcol_triangle_flag {
    SELFCOL_TRIANGLE_REPEATED_INDEX = 1u << 0, /**< two corners share an index */
    SELFCOL_TRIANGLE_DUPLICATE = 1u << 1,      /**< an earlier triangle has the same vertex set */
    SELFCOL_TRIANGLE_ZERO_AREA = 1u << 2       /**< corners exactly collinear (current positions) */
} selfcol_triangle_flag;

/**
 * Degeneracy flags of a triangle. ZERO_AREA is decided exactly from the current
 * positions (exact orientation predicates), the other bits from the indices.
 * @return a combination of selfcol_triangle_flag; 0 for NULL or out of range.
 */
SELFCOL_API uint32_t selfcol_mesh_triangle_flags(const selfcol_mesh *mesh, uint32_t triangle);

/**
 * Connected component of a triangle. Two triangles are connected when they
 * share a vertex. Components are numbered 0.. in order of their lowest triangle.
 * @return the component; SELFCOL_INVALID_INDEX for NULL or out of range.
 */
SELFCOL_API uint32_t selfcol_mesh_triangle_component(const selfcol_mesh *mesh, uint32_t triangle);

/**
 * Mean length of the unique edges at the current positions (the scale of the
 * standard detection distance d = 0.1 x mean edge length). O(E).
 * @return the mean; 0 for NULL.
 */
SELFCOL_API double selfcol_mesh_mean_edge_length(const selfcol_mesh *mesh);

/**
 * Bytes of memory held by the mesh.
 * @return the byte count; 0 for NULL.
 */
SELFCOL_API size_t selfcol_mesh_byte_count(const selfcol_mesh *mesh);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_MESH_H */
