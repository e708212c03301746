// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file contacts.h
 * @defgroup contacts Contacts
 * Contact records and the `selfcol_contacts` handle that queries fill.
 *
 * The contact sets (docs/contract.md section 1), for detection distance d:
 * - VF proximity: vertex v and triangle t, v not a corner of t, dist(v, t) < d;
 * - EE proximity: edges e and f with no common vertex, dist(e, f) < d;
 * - EF interference: edge e crosses triangle t, no common vertex.
 * Between two different meshes the "no common vertex" condition is dropped.
 * Only vertices used by at least one triangle take part. A duplicate triangle
 * (the same three vertices as an earlier one, in any order:
 * SELFCOL_TRIANGLE_DUPLICATE) is collapsed into its first occurrence, which
 * stands for every copy: t above ranges over the triangles that are not
 * duplicates, and records name the first occurrence's index (the caller's
 * own index; nothing is renumbered). The copies' edges and vertices are the
 * first occurrence's, so no contact is lost; k copies of one triangle cost
 * the query O(k), not the O(k^2) of testing every copy against the others
 * (they share all their vertices, so they never collide with each other).
 *
 * "Crosses" is decided with exact orientation predicates: the two endpoints
 * of e lie strictly on opposite sides of the plane of t, and the line of e
 * meets the closed triangle t (its edges and corners included). So:
 * - an edge that only touches the plane of t (an endpoint exactly on it) does
 *   not cross t; it shows up as a VF proximity at distance 0;
 * - an edge lying in the plane of t (coplanar) does not cross t; it shows up
 *   as EE/VF proximities at distance 0;
 * - an edge passing exactly through an edge or corner of t crosses t (and
 *   every triangle sharing that edge or corner: the surface is crossed there);
 * - a zero-area triangle has no plane, so nothing crosses it.
 * Distances are computed in double precision; pairs within a relative 1e-9 of d
 * may fall either way.
 * @{
 */
#ifndef SELFCOL_CONTACTS_H
#define SELFCOL_CONTACTS_H

#include "common.h"
#include "mesh.h"

SELFCOL_BEGIN_DECLS

/** Kind of a contact. Values are pinned. */
typedef enum selfcol_contact_kind {
    SELFCOL_CONTACT_VF = 0, /**< vertex-triangle proximity */
    SELFCOL_CONTACT_EE = 1, /**< edge-edge proximity */
    SELFCOL_CONTACT_EF = 2  /**< edge-triangle interference (the edge crosses the triangle) */
} selfcol_contact_kind;

/** Bit masks selecting contact kinds in selfcol_query_options.kinds. */
#define SELFCOL_KIND_VF (1u << SELFCOL_CONTACT_VF)
#define SELFCOL_KIND_EE (1u << SELFCOL_CONTACT_EE)
#define SELFCOL_KIND_EF (1u << SELFCOL_CONTACT_EF)
#define SELFCOL_KIND_ALL (SELFCOL_KIND_VF | SELFCOL_KIND_EE | SELFCOL_KIND_EF)

/**
 * One contact between a first primitive (a vertex or an edge) and a second
 * primitive (a triangle or an edge). Plain data; the layout is part of the ABI.
 *
 * | kind | first       | a            | second      | b                 |
 * |------|-------------|--------------|-------------|-------------------|
 * | VF   | vertex      | {v, v}       | triangle    | its 3 corners     |
 * | EE   | edge        | its vertices | edge        | its vertices, b[2] = SELFCOL_INVALID_INDEX |
 * | EF   | edge        | its vertices | triangle    | its 3 corners     |
 *
 * Edge indices refer to selfcol_mesh_edges(); edge vertices are listed smaller
 * first. For a self query, EE contacts have first < second. first_mesh and
 * second_mesh say which mesh each primitive belongs to (0: the first mesh of
 * the query, 1: the second; both 0 for a self query).
 */
typedef struct selfcol_contact {
    uint32_t kind;        /**< selfcol_contact_kind */
    uint32_t first;       /**< vertex (VF) or edge (EE, EF) index */
    uint32_t second;      /**< triangle (VF, EF) or edge (EE) index */
    uint32_t first_mesh;  /**< 0 or 1 */
    uint32_t second_mesh; /**< 0 or 1 */
    uint32_t a[2];        /**< vertices of the first primitive */
    uint32_t b[3];        /**< vertices of the second primitive */
    /** Distance between the primitives, >= 0 (0 for EF). */
    double distance;
    /** Closest point on the first primitive = wa[0] x(a[0]) + wa[1] x(a[1]).
     *  EF: the point where the edge crosses the triangle's plane. */
    double wa[2];
    /** Closest point on the second primitive = sum of wb[i] x(b[i]) (wb[2] = 0 for EE).
     *  EF: the same crossing point, in barycentric coordinates of the triangle. */
    double wb[3];
    /** Unit vector from the second closest point toward the first. When the
     *  distance is 0: the triangle's unit normal (VF, EF), the unit common
     *  normal of the two edges (EE), or any unit vector when neither exists. */
    double direction[3];
} selfcol_contact;

/**
 * Counters and timings of the last query. The caller sets version to
 * SELFCOL_QUERY_STATS_VERSION; the library writes only the fields that exist in
 * that version.
 */
typedef struct selfcol_query_stats {
    unsigned int version; /**< SELFCOL_QUERY_STATS_VERSION */
    /** Primitive pairs examined: EXHAUSTIVE's enumerated pairs, or the near
     *  list's pairs on a frame a selfcol_sequence answered from it. 0 for
     *  the hierarchy methods, whose candidates are triangle_pairs. */
    uint64_t candidate_pairs;
    uint64_t vf_tests;    /**< vertex-triangle distance evaluations (closed form or libccd) */
    uint64_t ee_tests;    /**< edge-edge distance evaluations */
    uint64_t ef_tests;    /**< edge-triangle crossing evaluations */
    uint64_t vf_contacts; /**< VF contacts found */
    uint64_t ee_contacts; /**< EE contacts found */
    uint64_t ef_contacts; /**< EF contacts found */
    /** Time spent selecting candidates; 0 for EXHAUSTIVE, whose enumeration
     *  and primitive tests are interleaved (its whole time is in total_seconds). */
    double broad_seconds;
    double narrow_seconds; /**< time spent in primitive tests; 0 for EXHAUSTIVE */
    double total_seconds;  /**< wall time of the whole query */
    /* Version 2: the hierarchy traversal (all 0 for EXHAUSTIVE). */
    uint64_t nodes_visited; /**< nodes and node pairs examined */
    uint64_t culled_box;    /**< node pairs skipped because their boxes are apart */
    /** Nodes skipped by the curvature criterion (self; for EXACT, curvature
     *  and contour). */
    uint64_t culled_curvature;
    /** Adjacent node pairs skipped by the joint criterion (for EXACT, joint
     *  curvature and contour). */
    uint64_t culled_adjacency;
    /** Candidate triangle pairs: those whose boxes are within d (including
     *  the pairs_separated of version 4, which get no primitive test). */
    uint64_t triangle_pairs;
    /* Version 3: the contour criterion of SELFCOL_METHOD_EXACT (0 otherwise). */
    /** Nodes and adjacent node pairs whose normals passed the curvature test
     *  and whose projected contour was then examined. */
    uint64_t contour_tests;
    /** Of those, the ones the contour test could not prove free (the price
     *  of exactness: SEED would have skipped them). */
    uint64_t contour_refused;
    double contour_seconds; /**< time in the contour test (part of broad_seconds) */
    /* Version 4: the narrow phase's filters and the sort. */
    /** Candidate triangle pairs rejected whole because one triangle lies
     *  beyond d of the other's plane (no primitive test was made for them). */
    uint64_t pairs_separated;
    /** Primitive pairs rejected by a conservative filter (plane distance or
     *  box) before their closed form; not counted in vf/ee/ef_tests. */
    uint64_t primitives_filtered;
    double sort_seconds; /**< time spent sorting the records (part of total_seconds) */
} selfcol_query_stats;

#define SELFCOL_QUERY_STATS_VERSION 4

/** Opaque set of contacts, filled by the queries of hierarchy.h. */
typedef struct selfcol_contacts selfcol_contacts;

/** Options for selfcol_contacts_create(). Initialise with selfcol_contacts_options_init(). */
typedef struct selfcol_contacts_options {
    unsigned int version;        /**< SELFCOL_CONTACTS_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free */
} selfcol_contacts_options;

#define SELFCOL_CONTACTS_OPTIONS_VERSION 1

/**
 * Writes the defaults into opts.
 * @param[out] opts the struct to initialise
 * @param[in] version SELFCOL_CONTACTS_OPTIONS_VERSION
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_contacts_options_init(selfcol_contacts_options *opts, unsigned int version);

/**
 * Creates an empty contact set.
 * @param[out] out the new handle; NULL on failure. Caller owns it; free it with
 *             selfcol_contacts_destroy().
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL; SELFCOL_EVERSION; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_contacts_create(selfcol_contacts **out,
                                        const selfcol_contacts_options *opts);

/** Destroys a contact set. Accepts NULL. @param[in] contacts the handle */
SELFCOL_API void selfcol_contacts_destroy(selfcol_contacts *contacts);

/** Removes all contacts and zeroes the statistics; keeps the memory. @param[in,out] contacts the
 * handle */
SELFCOL_API void selfcol_contacts_clear(selfcol_contacts *contacts);

/**
 * Number of contacts held.
 * @return the count; 0 for NULL.
 */
SELFCOL_API size_t selfcol_contacts_count(const selfcol_contacts *contacts);

/**
 * The contacts, sorted by (kind, first_mesh, first, second_mesh, second).
 * @param[out] data_out borrowed array, valid until the next call that modifies
 *             the handle (a query, clear, destroy); NULL when empty
 * @param[out] count_out number of records
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments.
 */
SELFCOL_API int selfcol_contacts_data(const selfcol_contacts *contacts,
                                      const selfcol_contact **data_out, size_t *count_out);

/**
 * Statistics of the last query that filled the handle.
 * @param[in,out] stats its version field set by the caller; the rest is written
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL; SELFCOL_EVERSION for version 0
 *         or a version newer than the library.
 */
SELFCOL_API int selfcol_contacts_stats(const selfcol_contacts *contacts,
                                       selfcol_query_stats *stats);

/**
 * The intersecting triangle pairs of the last query, derived from its EF
 * interferences: an edge crossing triangle t puts every triangle having
 * that edge in a pair with t (their intersection holds the crossing point;
 * two triangles that intersect away from their common vertices always have
 * such an edge, since the intersection segment ends on an edge of one
 * crossing the other). Self query: pairs (a, b), a < b, of the mesh's
 * triangles; two meshes: (a, b), a a triangle of the first mesh, b of the
 * second. Sorted, each pair once. Computed at the first call after a query
 * (O(n) in the EF records, radix-sorted) and kept with the contacts.
 * @param[in] first, second the query's meshes (the same mesh twice for a
 *            self query), unchanged since the query
 * @param[out] pairs_out borrowed: 2 * count triangle indices, valid until
 *             the next call that modifies the contact set; NULL when none
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL arguments, records naming an
 *         element the meshes do not have); SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_contacts_intersecting_triangles(selfcol_contacts *contacts,
                                                        const selfcol_mesh *first,
                                                        const selfcol_mesh *second,
                                                        const uint32_t **pairs_out,
                                                        size_t *count_out);

/** Classes of selfcol_contacts_triangle_classes(): what a triangle takes part in. */
typedef enum selfcol_triangle_class {
    SELFCOL_TRIANGLE_PLAIN = 0, /**< no contact */
    SELFCOL_TRIANGLE_NEAR = 1,  /**< a VF or EE proximity (its corner, edge or face) */
    SELFCOL_TRIANGLE_INTERSECTING =
        2 /**< an EF interference (the crossed face, or the crossing edge's) */
} selfcol_triangle_class;

/**
 * Raises each triangle's class to what it takes part in in the last query's
 * records (the marking of `selfcol-cli check --mark`): a VF proximity's
 * face, and every face around its vertex, are NEAR; an EE proximity's
 * edges' faces are NEAR; an EF interference's crossed face and the
 * crossing edge's faces are INTERSECTING. A class only goes up (max), so
 * one array can gather several queries.
 * @param[in] first, second the query's meshes (the same mesh twice for a self query)
 * @param[in,out] first_classes one byte per triangle of first (selfcol_triangle_class)
 * @param[in,out] second_classes one per triangle of second; ignored (may be
 *                NULL) for a self query, which writes first_classes only
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL arguments, records naming an
 *         element the meshes do not have).
 */
SELFCOL_API int selfcol_contacts_triangle_classes(const selfcol_contacts *contacts,
                                                  const selfcol_mesh *first,
                                                  const selfcol_mesh *second,
                                                  uint8_t *first_classes, uint8_t *second_classes);

/**
 * Bytes of memory held by the contact set.
 * @return the byte count; 0 for NULL.
 */
SELFCOL_API size_t selfcol_contacts_byte_count(const selfcol_contacts *contacts);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_CONTACTS_H */
