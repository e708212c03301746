// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file store.h
 * @defgroup store Contact store
 * The persistent contact store: section 3 of Volino & Magnenat Thalmann
 * (1995) -- remnance, orientation tracked through crossings, and consistency
 * by region -- for surfaces that have no inside or outside of their own.
 *
 * A query (selfcol_hierarchy_self_collide(), selfcol_hierarchy_collide())
 * fills a `selfcol_contacts` with one frame's contacts and forgets them. A
 * `selfcol_store` is given each frame's query result with
 * selfcol_store_update() and keeps, per contact (keyed by its kind and
 * primitives, as in selfcol_contact):
 *
 * - **side** (+1, -1; 0 while never decided): the sign of the oriented
 *   distance of the first element from the second along the contact's
 *   reference direction, which moves with the elements: VF, the triangle's
 *   normal (b[0], b[1], b[2] counter-clockwise); EE, (a[1] - a[0]) x
 *   (b[1] - b[0]). Decided exactly (orient3d). When it changes sign between
 *   two updates the elements have crossed: the contact is FLIPPED. A sign of
 *   exactly 0 (coplanar) keeps the previous side: touching is not crossing.
 *   Two frames' positions cannot tell a vertex that went through a triangle
 *   from one that went around its border: both count as a crossing (the
 *   region vote below is what corrects a lone wrong flip).
 * - **right side** (+1, -1; 0 unknown): the side the elements belong on. A
 *   new contact is taken to be on its right side (the seed's assumption: a
 *   detected proximity has a positive distance); a crossing leaves it
 *   unchanged, so the contact then has a negative signed distance.
 * - **signed distance**: +distance on the right side, -distance otherwise.
 * - **age** (updates since it appeared) and **missed** (updates since it was
 *   last detected). Remnance: a VF or EE contact that is no longer detected
 *   stays, recomputed from the current positions and still tracking its
 *   side, for `remnance_frames` updates, then goes. EF interferences are
 *   states, not contacts: they stay only while detected.
 * - **region**: contacts are neighbours when their elements are neighbours
 *   on the mesh (first shares a vertex with first and second with second,
 *   or crosswise); regions are the connected groups (union-find, no
 *   recursion). With consistency on, each region's majority side is imposed
 *   on all its contacts (see selfcol_store_update() for the exact rule);
 *   interferences in a region mark it CROSSED.
 *
 * The store holds a compact entry per contact (its key, age, missed, flags,
 * sides and region: 24 bytes) and computes the public record,
 * selfcol_store_contact, when it is copied (selfcol_store_copy_contacts(),
 * from the meshes' positions of the last update). Memory is linear in the
 * contacts held and in the meshes' vertices (selfcol_store_byte_count());
 * once the store's arrays have grown, an update allocates nothing.
 * @{
 */
#ifndef SELFCOL_STORE_H
#define SELFCOL_STORE_H

#include "common.h"
#include "contacts.h"
#include "mesh.h"

SELFCOL_BEGIN_DECLS

/** Opaque persistent contact store. */
typedef struct selfcol_store selfcol_store;

/** Default remnance: a contact stays 4 updates after it was last detected.
 *  A contact scattered by one bad step (the seed's case) and the solver's
 *  next 2-3 steps of recovery keep their side; at a detection distance of
 *  0.1 x edge and contact speeds of at most d per step, elements apart for 4
 *  steps are over 4 d away, where a remembered side would be stale rather
 *  than useful (the "flip over and touch again" limit, README). */
#define SELFCOL_STORE_DEFAULT_REMNANCE 4u

/** Options for selfcol_store_create(). Initialise with selfcol_store_options_init(). */
typedef struct selfcol_store_options {
    unsigned int version;        /**< SELFCOL_STORE_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free */
    /** Updates a VF/EE contact stays after it was last detected (0: none). */
    uint32_t remnance_frames;
    /** 1 (default): impose each region's majority side; 0: track sides only. */
    int consistency;
    /**
     * Orientation of the first (or only) mesh's surface: 0 (default) none,
     * the right sides of its contacts are voted; +1 its counter-clockwise
     * triangle normals point to the side where other surfaces belong (a
     * closed body wound counter-clockwise seen from outside, or an oriented
     * floor); -1 they point away from it. See "Oriented surfaces" in
     * selfcol_store_update().
     */
    int first_orientation;
    /** Orientation of the second mesh of a two-mesh query, as first_orientation. */
    int second_orientation;
} selfcol_store_options;

/** 3 since 0.4 (threads moved to the context: selfcol_context_store_update());
 *  0.3's versions 1 and 2 are refused. */
#define SELFCOL_STORE_OPTIONS_VERSION 3

/** Bits of selfcol_store_contact.flags, about the last update (VOTED excepted). */
typedef enum selfcol_store_contact_flag {
    SELFCOL_STORE_NEW = 1u << 0,       /**< first detected by this update */
    SELFCOL_STORE_REMNANT = 1u << 1,   /**< not detected by this update, kept by remnance */
    SELFCOL_STORE_FLIPPED = 1u << 2,   /**< its side changed sign: the elements crossed */
    SELFCOL_STORE_CORRECTED = 1u << 3, /**< its right side was changed by its region's vote */
    /** its right side comes from the meshes' orientation (never voted) */
    SELFCOL_STORE_ORIENTED = 1u << 4,
    /** Persistent (not about the last update alone): its right side has
     *  been through a vote (kept or corrected) and it has not crossed
     *  since, so no later vote changes it until it crosses (FLIPPED clears
     *  the bit). This keeps the vote from flickering where a region's links
     *  contradict each other. */
    SELFCOL_STORE_SETTLED = 1u << 5,
    /** selfcol_store_update_swept() only: its side changed sign, but the
     *  continuous test proves that the elements never touched during the
     *  step: they went around each other, not through. Not a crossing: its
     *  right side turned with its side (the signed distance keeps its
     *  sign), and it is not FLIPPED. */
    SELFCOL_STORE_PASSED_AROUND = 1u << 6
} selfcol_store_contact_flag;

/** One contact held by the store, as selfcol_store_copy_contacts() writes it.
 *  Plain data; the layout is part of the ABI. */
typedef struct selfcol_store_contact {
    uint32_t kind;        /**< selfcol_contact_kind */
    uint32_t first;       /**< vertex (VF) or edge (EE, EF), as in selfcol_contact */
    uint32_t second;      /**< triangle (VF, EF) or edge (EE) */
    uint32_t first_mesh;  /**< 0 or 1 */
    uint32_t second_mesh; /**< 0 or 1 */
    uint32_t a[2];        /**< vertices of the first primitive */
    uint32_t b[3];        /**< vertices of the second (b[2] = SELFCOL_INVALID_INDEX for EE) */
    uint32_t region;      /**< index into selfcol_store_regions() */
    uint32_t age;         /**< updates since it was first detected (0: this one) */
    uint32_t missed;      /**< updates since it was last detected (0: this one) */
    uint32_t flags;       /**< selfcol_store_contact_flag bits */
    int32_t side;         /**< +1, -1; 0 never decided (always 0 for EF) */
    int32_t right_side;   /**< +1, -1; 0 unknown (always 0 for EF) */
    double distance;      /**< current distance, >= 0 (0 for EF) */
    /** +distance when side == right_side (or either is 0), -distance otherwise. */
    double signed_distance;
    double wa[2];        /**< closest point weights, as in selfcol_contact */
    double wb[3];        /**< closest point weights, as in selfcol_contact */
    double direction[3]; /**< unit vector from the second closest point toward the first */
} selfcol_store_contact;

/** Bits of selfcol_store_region.flags. */
typedef enum selfcol_store_region_flag {
    SELFCOL_REGION_CROSSED = 1u << 0,   /**< holds EF interferences: the surfaces cross here */
    SELFCOL_REGION_CORRECTED = 1u << 1, /**< the vote changed the right side of some contact */
    SELFCOL_REGION_TIE = 1u << 2        /**< some vote was tied and decided by the tie rule */
} selfcol_store_region_flag;

/** One region: a connected group of neighbouring contacts. */
typedef struct selfcol_store_region {
    uint32_t contacts;      /**< VF and EE contacts */
    uint32_t interferences; /**< EF interferences */
    /** Contacts already on the majority side (the vote's winners). */
    uint32_t votes_majority;
    /** Contacts on the minority side (corrected when consistency is on). */
    uint32_t votes_minority;
    uint32_t abstained; /**< contacts without a decided side (no vote) */
    /** Contacts whose right side an oriented surface gives (not voted). */
    uint32_t oriented;
    uint32_t flags; /**< selfcol_store_region_flag bits */
} selfcol_store_region;

/**
 * Counters of the last update. The caller sets version to
 * SELFCOL_STORE_UPDATE_STATS_VERSION; the library writes the fields of that version.
 */
typedef struct selfcol_store_update_stats {
    unsigned int version;       /**< SELFCOL_STORE_UPDATE_STATS_VERSION */
    uint64_t contacts;          /**< VF and EE contacts held after the update */
    uint64_t interferences;     /**< EF interferences held (those detected) */
    uint64_t new_contacts;      /**< VF/EE first detected by this update */
    uint64_t kept;              /**< VF/EE held before and detected again */
    uint64_t remnant;           /**< VF/EE held but not detected (kept by remnance) */
    uint64_t dropped;           /**< VF/EE/EF removed (remnance over, or EF gone) */
    uint64_t flipped;           /**< contacts whose side changed sign (crossings) */
    uint64_t corrected;         /**< contacts whose right side the vote changed */
    uint64_t voted;             /**< contacts that took part in a vote */
    uint64_t oriented;          /**< contacts whose right side an oriented surface gave */
    uint64_t regions;           /**< regions */
    uint64_t crossed_regions;   /**< regions holding interferences */
    uint64_t corrected_regions; /**< regions where the vote corrected a contact */
    double seconds;             /**< wall time of the update */
    /* Version 2 */
    /** sign changes that selfcol_store_update_swept() proved were no
     *  crossing (SELFCOL_STORE_PASSED_AROUND) */
    uint64_t passed_around;
} selfcol_store_update_stats;

#define SELFCOL_STORE_UPDATE_STATS_VERSION 2

/**
 * Writes the defaults into opts (remnance SELFCOL_STORE_DEFAULT_REMNANCE,
 * consistency on, 1 thread; a version 1 struct is written up to its end).
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_store_options_init(selfcol_store_options *opts, unsigned int version);

/**
 * Names what selfcol_store_create() refuses in opts, if anything: the field,
 * its value and what is accepted (common.h, selfcol_options_problem).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as
 *         selfcol_store_create() for these options; SELFCOL_EINVAL for a
 *         NULL problem, SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_store_options_check(const selfcol_store_options *opts,
                                            selfcol_options_problem *problem);

/**
 * Creates an empty store.
 * @param[out] out the new handle; NULL on failure. Free it with selfcol_store_destroy().
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL out, half-set allocator,
 *         consistency not 0 or 1, an orientation not -1, 0 or +1);
 *         SELFCOL_EVERSION; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_store_create(selfcol_store **out, const selfcol_store_options *opts);

/** Destroys a store. Accepts NULL. Never reads the meshes. */
SELFCOL_API void selfcol_store_destroy(selfcol_store *store);

/** Forgets every contact and region, and the meshes; keeps the memory. Accepts NULL. */
SELFCOL_API void selfcol_store_clear(selfcol_store *store);

/**
 * Merges one frame's query result into the store, then regroups and votes.
 * `detected` must come from a query on the same meshes at their current
 * positions: selfcol_hierarchy_self_collide() on a hierarchy of `first`
 * (second NULL), or selfcol_hierarchy_collide() of hierarchies of `first`
 * and `second`. A store follows one such query from frame to frame; it
 * remembers its meshes (not their positions) from the first update until
 * selfcol_store_clear(), by address and by identity (vertex, triangle and
 * edge counts, a fingerprint of the triangles and the creation time): a
 * mesh destroyed and another created at its address is another mesh
 * (SELFCOL_EMISMATCH), whatever the allocator does. Any contact kinds and
 * distance may be queried; a contact is detected when the query reports it.
 *
 * Consistency rule. Within a region, each contact says which side of the
 * other surface its first element belongs on; neighbours (contacts sharing
 * a vertex pair {u, w}) are compared through the surface normals at u and
 * at w (each vertex's sum of its triangles' area-weighted normals): the
 * side each one's direction points to, times +1 on its right side and -1 on
 * the wrong one, should agree for neighbours with the same roles (first
 * near first) and be opposite for crosswise ones. A link carries this
 * relation only where the geometry is clear: the normals at u and w within
 * 60 degrees of parallel or antiparallel, both directions within 60 degrees
 * of both normals' lines, and the same relation through either normal
 * (elsewhere, e.g. at a fold's hinge or where a border edge meets a surface
 * edge-on, the contacts stay in one region but do not vote together).
 * Linked contacts form voting groups (union-find with parity; a link
 * closing a cycle against the relation is ignored). Every contact with a
 * decided side and right side votes for its right side as seen from the
 * group's frame. In a group holding contacts from earlier updates only
 * their votes count (their right sides carry memory; a new contact's is its
 * current side, a guess); a group of new contacts decides by all its votes.
 * The majority is imposed (right sides changed: CORRECTED). A tied vote
 * keeps the right side of the group's oldest contact (greatest age; among
 * equals, the first in key order) and sets SELFCOL_REGION_TIE. Only
 * contacts that have not been through a vote since they appeared or last
 * crossed can be corrected; the others vote but keep their right side
 * (SELFCOL_STORE_SETTLED): where a region's links contradict each other
 * (surfaces that already cross) the groups a frame's links form change from
 * frame to frame with no crossing, and re-deciding settled contacts would
 * flip them back and forth (measured on a crumpled, self-intersecting
 * 45k-triangle cloth: 44 to 214 corrections per update with no crossing at
 * all, 0 with this rule).
 * Contacts whose side was never decided (exactly
 * coplanar since they appeared) abstain; a contact takes its first decided
 * side as its right side, then votes like the others.
 *
 * Oriented surfaces (first_orientation, second_orientation). A contact with
 * an element of an oriented mesh takes no part in the vote: its right side
 * is recomputed at every update from the surface normals (SELFCOL_STORE_
 * ORIENTED). With n_s and n_f the unit outward normals of the second and
 * first elements (a triangle's own normal, an edge's or a vertex's sum of its
 * triangles' area-weighted normals, times the mesh's orientation; 0 for an
 * element of a mesh without orientation), the right side is the sign of
 * (n_s - n_f) . R, where R is the contact's reference direction: the first
 * element belongs outside the second's surface and the second outside the
 * first's. When that sign is not clear (|(n_s - n_f) . R| < 1e-9 |R|, e.g.
 * an edge grazing along a body's edge) the right side stays what it was (or
 * the first decided side, as for unoriented contacts). A closed body whose
 * outward normals give the side never needs a vote: its contacts are right
 * or wrong on their own.
 *
 * On any error the store is unchanged.
 * @param[in,out] store the store
 * @param[in] first the query's first (or only) mesh
 * @param[in] second the second mesh of a two-mesh query, or NULL
 * @param[in] detected the query's result
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments or records that are
 *         not sorted as a query sorts them; SELFCOL_EMISMATCH when the meshes
 *         are not those of the store's earlier updates, or a record does not
 *         match them (an index out of range, vertices that are not its
 *         elements', or, with a second mesh, a record within one mesh: a
 *         two-mesh store holds a two-mesh query's contacts only); SELFCOL_ERANGE when the contacts
 * the update would hold (detected ones and remnants) exceed 2^27 - 1, or their vertex pairs 2^32 -
 * 1; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_store_update(selfcol_store *store, const selfcol_mesh *first,
                                     const selfcol_mesh *second, const selfcol_contacts *detected);

/**
 * selfcol_store_update() for a step whose start the caller knows: first_start
 * (and second_start for a two-mesh store, else NULL) hold the meshes'
 * positions at the start of the step, i.e. at the store's previous update
 * (3 doubles per vertex). A contact whose side changes sign is then a
 * crossing only if the continuous test (include/selfcol/sweep.h's narrow
 * phase, no false negatives) finds that its elements may have touched
 * during the step, every vertex moving on the straight line from its start
 * to its current position. Otherwise they went around each other (a vertex
 * around a triangle's border): SELFCOL_STORE_PASSED_AROUND, the right side
 * turns with the side, no FLIPPED. This removes the pass-around limit of
 * two frames (README). The first update of a store has nothing to confirm.
 * @return as selfcol_store_update(); SELFCOL_EINVAL also for a NULL
 *         first_start, second_start given without a second mesh or missing
 *         with one, or a start coordinate outside mesh.h's contract (not
 *         finite, or nonzero of magnitude outside [SELFCOL_MESH_MIN_COORDINATE,
 *         SELFCOL_MESH_MAX_COORDINATE]: the mesh's own check).
 */
SELFCOL_API int selfcol_store_update_swept(selfcol_store *store, const selfcol_mesh *first,
                                           const selfcol_mesh *second,
                                           const selfcol_contacts *detected,
                                           const double *first_start, const double *second_start);

/**
 * Number of contacts held (VF, EE and EF): the records
 * selfcol_store_copy_contacts() can copy.
 * @return the count; 0 for NULL.
 */
SELFCOL_API size_t selfcol_store_contact_count(const selfcol_store *store);

/**
 * Copies the records first_index .. first_index + count - 1 of the contacts
 * held (VF, EE and EF), sorted by (kind, first_mesh, first, second_mesh,
 * second), into the caller's array. The store keeps no record: it keeps
 * each contact's key, counters and sides, and computes the rest now. The
 * vertices (a, b) come from the meshes' topology; distance, weights and
 * direction from the meshes' current positions by the closed-form narrow
 * phase, which are the positions of the last update: a VF or EE record is
 * then bit for bit the record a closed-form query (SELFCOL_NARROW_CLOSED_FORM)
 * gave for it, or, for a remnant, the closed-form distance at those
 * positions; an EF record carries the crossing point and the triangle's
 * normal as the query gives them (all zero, with libccd's narrow phase, for
 * an interference the exact test does not call crossing). A libccd query's
 * VF/EE records differ from these in their geometry only.
 *
 * The store's meshes must therefore still be alive and unmoved since the
 * last update: copy the contacts after selfcol_store_update() and before the
 * next selfcol_mesh_set_positions(). A range may be copied in several calls
 * (e.g. in blocks, into a buffer kept from frame to frame: nothing is
 * allocated); reading one record costs a narrow-phase evaluation.
 * @param[in] store the store
 * @param[in] first_index index of the first record to copy
 * @param[in] count records to copy; 0 copies nothing (and checks no mesh)
 * @param[out] out caller owns: at least count records; may be NULL when count is 0
 * @return SELFCOL_OK; SELFCOL_EINVAL for a NULL store, a NULL out with count
 *         > 0, or a range past the end (first_index + count >
 *         selfcol_store_contact_count(): nothing is clamped, nothing copied);
 *         SELFCOL_ESTALE when a mesh's positions changed since the last
 *         update (selfcol_mesh_set_positions() with other positions);
 *         SELFCOL_EMISMATCH when a mesh is no longer the one the store was
 *         given (another mesh at its address). Nothing is written on error.
 */
SELFCOL_API int selfcol_store_copy_contacts(const selfcol_store *store, size_t first_index,
                                            size_t count, selfcol_store_contact *out);

/**
 * The regions of the last update, numbered in order of their first contact.
 * @param[out] data_out borrowed, valid until the next update, clear or destroy; NULL when empty
 * @param[out] count_out number of regions
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments.
 */
SELFCOL_API int selfcol_store_regions(const selfcol_store *store,
                                      const selfcol_store_region **data_out, size_t *count_out);

/**
 * Counters of the last update.
 * @param[in,out] stats its version field set by the caller
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_store_stats(const selfcol_store *store, selfcol_store_update_stats *stats);

/** Bytes of memory held by the store. @return the count; 0 for NULL. */
SELFCOL_API size_t selfcol_store_byte_count(const selfcol_store *store);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_STORE_H */
