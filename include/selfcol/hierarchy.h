// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file hierarchy.h
 * @defgroup hierarchy Hierarchies and collision queries
 * A `selfcol_hierarchy` is the search structure over one mesh; collision
 * queries run on hierarchies and fill a `selfcol_contacts`.
 * @{
 */
#ifndef SELFCOL_HIERARCHY_H
#define SELFCOL_HIERARCHY_H

#include "common.h"
#include "contacts.h"
#include "mesh.h"

SELFCOL_BEGIN_DECLS

/** Opaque hierarchy over one mesh. It borrows the mesh, which must outlive it. */
typedef struct selfcol_hierarchy selfcol_hierarchy;

/** Options for selfcol_hierarchy_create(). Initialise with selfcol_hierarchy_options_init(). */
typedef struct selfcol_hierarchy_options {
    unsigned int version;        /**< SELFCOL_HIERARCHY_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free */
} selfcol_hierarchy_options;

/** 3 since 0.4 (threads moved to the context: selfcol_context_refit());
 *  0.3's versions 1 and 2 are refused. */
#define SELFCOL_HIERARCHY_OPTIONS_VERSION 3

/**
 * Writes the defaults into opts.
 * @param[out] opts the struct to initialise
 * @param[in] version SELFCOL_HIERARCHY_OPTIONS_VERSION
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_hierarchy_options_init(selfcol_hierarchy_options *opts,
                                               unsigned int version);

/**
 * Names what selfcol_hierarchy_create() refuses in opts, if anything
 * (selfcol_query_options_check() says how).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as
 *         selfcol_hierarchy_create() for these options.
 */
SELFCOL_API int selfcol_hierarchy_options_check(const selfcol_hierarchy_options *opts,
                                                selfcol_options_problem *problem);

/**
 * Creates a hierarchy over a mesh, from its topology (Volino & Magnenat
 * Thalmann's automatic hierarchisation): every node is an edge-connected
 * patch of triangles, built bottom-up by matching each patch with an adjacent
 * one (the one giving the most compact merged box), so children are connected
 * sub-patches of similar size. O(n) expected time and memory; the hierarchy
 * is refit to the mesh's current positions.
 * @param[out] out the new hierarchy; NULL on failure. Caller owns it and
 *             frees it with selfcol_hierarchy_destroy(). The mesh is borrowed:
 *             it must outlive every use of the hierarchy except its
 *             destruction and byte count, which never read the mesh (either
 *             handle may be destroyed first).
 * @param[in] mesh the mesh; borrowed for the hierarchy's lifetime. The
 *            hierarchy keeps the mesh's identity (its vertex, triangle and
 *            edge counts, a fingerprint of its triangles and its creation
 *            time): a refit or query on a mesh that is not that one (e.g.
 *            another mesh created at the address of the destroyed one, even
 *            with the same triangles) returns SELFCOL_EMISMATCH instead of
 *            reading out of its arrays or answering from stale boxes.
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL out or mesh, a half-set
 *         allocator); SELFCOL_EVERSION;
 *         SELFCOL_ENOMEM; SELFCOL_ERANGE (more than (2^32 - 2) / 6 = 715827882
 *         triangles: the build's adjacency offsets are 32-bit).
 */
SELFCOL_API int selfcol_hierarchy_create(selfcol_hierarchy **out, const selfcol_mesh *mesh,
                                         const selfcol_hierarchy_options *opts);

/** Destroys a hierarchy. Accepts NULL; never reads its mesh, which may
 *  already be destroyed. @param[in] hierarchy the handle */
SELFCOL_API void selfcol_hierarchy_destroy(selfcol_hierarchy *hierarchy);

/**
 * The mesh a hierarchy was built on.
 * @return borrowed pointer; NULL for NULL.
 */
SELFCOL_API const selfcol_mesh *selfcol_hierarchy_mesh(const selfcol_hierarchy *hierarchy);

/**
 * Recomputes the bounding boxes, direction masks and normal cones from the
 * mesh's current positions (after selfcol_mesh_set_positions()). O(n), no
 * allocation, on the calling thread (selfcol_context_refit() shares it
 * among a context's threads, with the same result). Queries with a hierarchy method (BVH,
 * SEED, CONE, EXACT) on a hierarchy whose mesh moved since the last refit
 * return SELFCOL_ESTALE.
 * @param[in,out] hierarchy the hierarchy
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL; SELFCOL_EMISMATCH (the mesh
 *         is not the one the hierarchy was built on: selfcol_hierarchy_create()).
 */
SELFCOL_API int selfcol_hierarchy_refit(selfcol_hierarchy *hierarchy);

/** Quantities reported by selfcol_hierarchy_count(). Values are pinned. */
typedef enum selfcol_hierarchy_quantity {
    SELFCOL_HIERARCHY_NODES = 0,  /**< all nodes */
    SELFCOL_HIERARCHY_LEAVES = 1, /**< leaf nodes (a few triangles each) */
    SELFCOL_HIERARCHY_DEPTH = 2   /**< levels from the root to the deepest leaf */
} selfcol_hierarchy_quantity;

/**
 * Returns a count describing the hierarchy.
 * @return the count; 0 for NULL or an unknown quantity.
 */
SELFCOL_API size_t selfcol_hierarchy_count(const selfcol_hierarchy *hierarchy,
                                           selfcol_hierarchy_quantity quantity);

/**
 * Bytes of memory held by the hierarchy (not counting its mesh).
 * @return the byte count; 0 for NULL.
 */
SELFCOL_API size_t selfcol_hierarchy_byte_count(const selfcol_hierarchy *hierarchy);

/** Search methods. Values are pinned; new methods are appended. */
typedef enum selfcol_method {
    /** The O(n^2) reference: every vertex against every triangle, every edge
     *  against every edge and every triangle. Defines the exact contact sets. */
    SELFCOL_METHOD_EXHAUSTIVE = 0,
    /** The hierarchy with bounding-box culling only. Exact. */
    SELFCOL_METHOD_BVH = 1,
    /** Volino & Magnenat Thalmann 1995 as written: boxes, the 14-direction
     *  curvature masks and adjacency, no contour test. Not exact: it can miss
     *  contacts inside or between smooth patches that touch themselves (a
     *  spiral ramp, a rolled sheet) and proximities closer than d inside a
     *  smooth patch. Its misses are measured, never hidden. */
    SELFCOL_METHOD_SEED = 2,
    /** SEED with exact normal cones (axis and half-angle) in place of the 14
     *  sampled directions. Not exact, for the same reasons as SEED. */
    SELFCOL_METHOD_CONE = 3,
    /** The seed's curvature criterion made exact (the default): a node -- or
     *  a pair of adjacent nodes, judged on the union of their patches -- is
     *  skipped only when its patch is a topological disk (for a pair: two
     *  disks joined along one path) whose normals lie in a cone narrower than
     *  pi/2 (rigorous bounds on rounding), whose boundary, projected along
     *  the cone's axis, is a simple polygon (exact predicates: the
     *  projection is then one-to-one, so nothing inside crosses), and whose
     *  projected altitudes and boundary clearance are at least d (so nothing
     *  inside is closer than d). Other pairs are culled by boxes. Exact. */
    SELFCOL_METHOD_EXACT = 4
} selfcol_method;

/** Narrow-phase implementations. Values are pinned. */
typedef enum selfcol_narrow {
    /** Closed-form distances and exact orientation predicates (default). */
    SELFCOL_NARROW_CLOSED_FORM = 0,
    /** libccd (proximities by its MPR intersection test on a primitive
     *  swept by a ball, bisected on the radius to 1e-7 d; interferences by
     *  its GJK intersection test). Agrees with the closed form within that
     *  tolerance, but also reports edges that only touch a triangle (within
     *  about 1.5e-8 of the mesh scale). Much slower; kept as a cross-check. */
    SELFCOL_NARROW_LIBCCD = 1
} selfcol_narrow;

/** Options of a collision query. Initialise with selfcol_query_options_init(). */
typedef struct selfcol_query_options {
    unsigned int version; /**< SELFCOL_QUERY_OPTIONS_VERSION */
    uint32_t method;      /**< selfcol_method; default SELFCOL_METHOD_EXACT */
    uint32_t narrow;      /**< selfcol_narrow; default SELFCOL_NARROW_CLOSED_FORM */
    uint32_t kinds;       /**< SELFCOL_KIND_* mask; default SELFCOL_KIND_ALL */
    /** Detection distance d >= 0 in mesh units; default 0 (interferences
     *  only). The standard setting is 0.1 x selfcol_mesh_mean_edge_length(). */
    double distance;
} selfcol_query_options;

/** 3 since 0.4: what a query computes, not where it runs (its threads are
 *  the context's: context.h, selfcol_context_self_collide()); 0.3's
 *  versions 1 and 2 are refused. */
#define SELFCOL_QUERY_OPTIONS_VERSION 3

/**
 * Writes the defaults into opts.
 * @param[out] opts the struct to initialise
 * @param[in] version SELFCOL_QUERY_OPTIONS_VERSION
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_query_options_init(selfcol_query_options *opts, unsigned int version);

/**
 * Names what a query refuses in opts, if anything: the field, its value and
 * what is accepted (common.h, selfcol_options_problem), for a front's error
 * message or a check before the call. Allocates nothing.
 * @param[in] opts query options, or NULL (the defaults: accepted)
 * @param[in,out] problem its version set by the caller; the rest written
 * @return what the queries return for opts, short of their other arguments
 *         (SELFCOL_OK, SELFCOL_EINVAL, SELFCOL_EVERSION); SELFCOL_EINVAL for
 *         a NULL problem; SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_query_options_check(const selfcol_query_options *opts,
                                            selfcol_options_problem *problem);

/**
 * Finds the self-contacts of the hierarchy's mesh at its current positions,
 * replacing the content of contacts (see contacts.h for the exact sets), on
 * the calling thread (selfcol_context_self_collide(): on a context's threads).
 * @param[in] hierarchy the hierarchy (read only: concurrent queries on one
 *            hierarchy with different contact sets are allowed)
 * @param[out] contacts receives the contacts and the statistics
 * @param[in] opts query options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL handle, unknown method, narrow or
 *         kinds bits, negative or non-finite distance or one above
 *         SELFCOL_MESH_MAX_COORDINATE); SELFCOL_EVERSION;
 *         SELFCOL_ESTALE (a hierarchy method on a hierarchy not refit since
 *         its mesh moved); SELFCOL_EMISMATCH (a mesh that is not the one the
 *         hierarchy was built on); SELFCOL_ENOMEM (contacts is then left empty).
 */
SELFCOL_API int selfcol_hierarchy_self_collide(const selfcol_hierarchy *hierarchy,
                                               selfcol_contacts *contacts,
                                               const selfcol_query_options *opts);

/**
 * Finds the contacts between two hierarchies' meshes (not the self-contacts of
 * either), replacing the content of contacts. In the records, mesh 0 is
 * first's mesh and mesh 1 is second's. Two hierarchies over the same mesh
 * (or the same hierarchy twice) are SELFCOL_EINVAL: use
 * selfcol_hierarchy_self_collide().
 * @return as selfcol_hierarchy_self_collide().
 */
SELFCOL_API int selfcol_hierarchy_collide(const selfcol_hierarchy *first,
                                          const selfcol_hierarchy *second,
                                          selfcol_contacts *contacts,
                                          const selfcol_query_options *opts);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_HIERARCHY_H */
