// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file scene.h
 * @defgroup scene Scenes of several surfaces and colliders
 * A `selfcol_scene` holds several surfaces, each declared by kind and
 * modelled no more than its kind needs, and convex colliders. One
 * selfcol_scene_update() per frame refits what moves, queries the pairs
 * that can matter, and keeps one contact store (store.h) per surface pair.
 *
 * | kind                    | refit       | self-collision | right side of its contacts        |
 * |-------------------------|-------------|----------------|-----------------------------------|
 * | SELFCOL_SURFACE_CLOTH   | every update| on (optional)  | voted by region (store.h)          |
 * | SELFCOL_SURFACE_BODY    | every update| off (optional) | its outward normals, never voted   |
 * | SELFCOL_SURFACE_STATIC  | never       | never          | voted, or a declared orientation   |
 * | collider (sphere, capsule, box, convex points) | a pose per update | never | outside the
 * collider |
 *
 * Pairs tested by an update: every surface with itself when its
 * self-collision is on; every two surfaces except two static ones; every
 * collider with every cloth and body surface (never with a static surface
 * nor with another collider: rigid against rigid is the rigid solver's
 * job). Two surfaces whose hierarchies' root boxes are farther apart than
 * the distance are skipped without a query (their store then ages as after
 * an update that detects nothing).
 *
 * Surfaces reference caller-owned meshes: the caller moves a cloth or body
 * by selfcol_mesh_set_positions() between updates. A static surface's mesh
 * must not move after it was added (selfcol_scene_update() returns
 * SELFCOL_ESTALE if it did; setting the positions it already has is not a
 * move); to move it on purpose, set its positions and call
 * selfcol_scene_rebuild_surface(). A mesh must outlive its surface: remove
 * the surface (selfcol_scene_remove_surface()) or destroy the scene before
 * destroying the mesh. The scene checks each mesh's identity (counts, a
 * fingerprint of its triangles and its creation time) at every update, so a
 * destroyed mesh replaced by another at the same address gives
 * SELFCOL_EMISMATCH rather than out-of-range reads or stale answers.
 *
 * Colliders are convex: a point (sphere), a segment (capsule), a box or the
 * convex hull of points, swept by a ball of `radius`, placed by their pose
 * (the rotation taken as orthonormal). A contact's distance is within
 * `collider_tolerance` of the exact distance of the triangle (as its double
 * coordinates say) to the collider (as its description and pose say),
 * whatever their sizes and positions, within these limits:
 * - every shape: radius + distance <= 2^95 x collider_tolerance (2e21 at
 *   the default tolerance for d = 0.05; a box's half-extents are not
 *   limited), distance <= 2^45 x collider_tolerance, and triangles whose
 *   longest edge is <= 2^47 x collider_tolerance (7e6 at that tolerance);
 * - convex point sets (libccd, whose answers are good to about 2^-26 of the
 *   coordinates it sees): the hull, the triangle and the gap between them
 *   within 2^25 x collider_tolerance of the triangle's first corner (1.7 at
 *   the default tolerance for d = 0.05: raise `collider_tolerance` for
 *   larger hulls).
 * Beyond a limit selfcol_scene_update() returns SELFCOL_ERANGE (its
 * collider contacts empty) rather than a wrong distance. Spheres, capsules
 * and boxes are solved in closed form in the collider's frame with
 * error-free arithmetic, and their normal (from the collider toward the
 * triangle's closest point) and closest point on the triangle are exact to
 * rounding; when the triangle meets the core (the point, segment or box),
 * the normal is the triangle's, turned away from the collider's centre.
 * Convex point sets use libccd's MPR test by inflation and bisection
 * (narrow_ccd.c); their normal and point come from MPR's penetration just
 * past the contact (SELFCOL_COLLIDER_APPROXIMATE).
 *
 * Memory is linear in the triangles plus the contacts held; once every
 * array has grown, an update allocates nothing.
 * @{
 */
#ifndef SELFCOL_SCENE_H
#define SELFCOL_SCENE_H

#include "common.h"
#include "context.h"
#include "hierarchy.h"
#include "mesh.h"
#include "sequence.h"
#include "store.h"

SELFCOL_BEGIN_DECLS

/** Opaque scene. */
typedef struct selfcol_scene selfcol_scene;

/** What a surface is (the table above). */
typedef enum selfcol_surface_kind {
    SELFCOL_SURFACE_CLOTH = 0,  /**< a deformable open surface */
    SELFCOL_SURFACE_BODY = 1,   /**< a deformable closed oriented surface */
    SELFCOL_SURFACE_STATIC = 2, /**< a surface that never moves */
} selfcol_surface_kind;

/** Options for selfcol_scene_add_surface(). Initialise with selfcol_scene_surface_options_init().
 */
typedef struct selfcol_scene_surface_options {
    unsigned int version; /**< SELFCOL_SCENE_SURFACE_OPTIONS_VERSION */
    uint32_t kind;        /**< selfcol_surface_kind */
    /** 1: query the surface against itself (cloth default 1, body 0; static must be 0). */
    int self_collision;
    /**
     * Static surfaces only (0 for the others): 0 (default) its contacts'
     * sides are voted; +1 or -1 as selfcol_store_options.first_orientation
     * (e.g. +1 for a floor whose normals point up). A body's orientation is
     * always taken from its signed volume.
     */
    int orientation;
} selfcol_scene_surface_options;

#define SELFCOL_SCENE_SURFACE_OPTIONS_VERSION 1

/** Shapes of convex colliders. */
typedef enum selfcol_collider_shape {
    SELFCOL_COLLIDER_SPHERE = 0, /**< a point swept by radius */
    SELFCOL_COLLIDER_CAPSULE =
        1, /**< the segment (0, 0, -half_height)..(0, 0, +half_height) swept by radius */
    SELFCOL_COLLIDER_BOX = 2,   /**< the box of half_extents, rounded by radius (0: sharp) */
    SELFCOL_COLLIDER_CONVEX = 3 /**< the convex hull of points, rounded by radius */
} selfcol_collider_shape;

/** A convex collider, in its local frame. Initialise with selfcol_scene_collider_desc_init(). */
typedef struct selfcol_scene_collider_desc {
    unsigned int version;   /**< SELFCOL_SCENE_COLLIDER_DESC_VERSION */
    uint32_t shape;         /**< selfcol_collider_shape */
    double radius;          /**< sphere and capsule: > 0; box and convex: >= 0 (rounding) */
    double half_height;     /**< capsule: >= 0 */
    double half_extents[3]; /**< box: each >= 0 */
    const double *points;   /**< convex: point_count x 3 coordinates, copied */
    size_t point_count;     /**< convex: 1 .. SELFCOL_COLLIDER_MAX_POINTS */
} selfcol_scene_collider_desc;

#define SELFCOL_SCENE_COLLIDER_DESC_VERSION 1
/** The most points of a convex collider (libccd's support search is linear in them). */
#define SELFCOL_COLLIDER_MAX_POINTS 4096u

/**
 * Options for selfcol_scene_create(). Initialise with selfcol_scene_options_init().
 * The scene's queries, stores and sequences take their settings from the
 * core's own option structs, passed by pointer (docs/architecture.md,
 * "Threads and options"): a field added to one of them changes neither
 * this struct's layout nor its version. selfcol_scene_create() reads the
 * pointed-to structs, each as its own version says, and keeps copies: they
 * need not outlive the call.
 */
typedef struct selfcol_scene_options {
    unsigned int version; /**< SELFCOL_SCENE_OPTIONS_VERSION */
    selfcol_allocator
        allocator; /**< of the scene, its hierarchies and stores; all-zero: malloc/free */
    /**
     * The surface queries (required: a scene has no default distance):
     * distance (> 0: the thickness, in mesh units), kinds (non-zero), method
     * and narrow phase. The scene's threads are those of the context set on
     * it (selfcol_scene_set_context()); without one it runs on the calling
     * thread.
     */
    const selfcol_query_options *query;
    /**
     * Every store's remnance_frames and consistency; NULL for
     * selfcol_store_options_init()'s defaults. Its allocator must be all-zero and its
     * orientations 0: the scene's allocator serves every store, and a
     * surface's orientation comes from its kind (selfcol_scene_surface_options).
     */
    const selfcol_store_options *store;
    /** Absolute accuracy of collider distances (default 0: 1e-6 x distance). */
    double collider_tolerance;
    /**
     * 1 (default): each surface pair keeps a selfcol_sequence (sequence.h)
     * and is answered from its near list while the surfaces' deformation
     * allows: the same contacts as a fresh query, at a fraction of its cost
     * when the surfaces move a little per update. 0: a fresh query every
     * update. Methods SEED and CONE always query afresh.
     */
    int coherent;
    /**
     * The sequences' options (skin); NULL for
     * selfcol_sequence_options_init()'s defaults. Its allocator must be
     * all-zero: the scene's serves them.
     */
    const selfcol_sequence_options *sequence;
} selfcol_scene_options;

/** 3 since 0.4 (the query, store and sequence options by pointer); 0.2's
 *  version 1 and 0.3's version 2 (those options embedded) are refused. */
#define SELFCOL_SCENE_OPTIONS_VERSION 3

/** Bits of selfcol_collider_contact.flags. */
typedef enum selfcol_collider_contact_flag {
    /** The triangle meets the collider (distance 0). */
    SELFCOL_COLLIDER_PENETRATING = 1u << 0,
    /** normal and wb come from libccd's MPR penetration (approximate), not a closed form. */
    SELFCOL_COLLIDER_APPROXIMATE = 1u << 1
} selfcol_collider_contact_flag;

/** One collider contact: a triangle within the distance of a collider. */
typedef struct selfcol_collider_contact {
    uint32_t collider; /**< collider id */
    uint32_t surface;  /**< surface id */
    uint32_t triangle; /**< triangle of the surface's mesh */
    uint32_t flags;    /**< selfcol_collider_contact_flag bits */
    double distance;   /**< >= 0, within collider_tolerance; 0 when penetrating */
    double wb[3];      /**< weights of the closest point on the triangle */
    /** Unit vector from the collider toward the triangle (the way to push the triangle). */
    double normal[3];
} selfcol_collider_contact;

/** Counters of the last update. The caller sets version. */
typedef struct selfcol_scene_update_stats {
    unsigned int version;          /**< SELFCOL_SCENE_UPDATE_STATS_VERSION */
    uint64_t surfaces;             /**< surfaces in the scene */
    uint64_t colliders;            /**< colliders in the scene */
    uint64_t refits;               /**< hierarchies refit by the last update */
    uint64_t builds;               /**< hierarchies built since the scene was created */
    uint64_t pairs_queried;        /**< surface pairs queried by the last update */
    uint64_t pairs_apart;          /**< surface pairs skipped: root boxes apart */
    uint64_t contacts;             /**< VF/EE contacts held by all stores */
    uint64_t interferences;        /**< EF interferences held by all stores */
    uint64_t flipped;              /**< summed over the stores (selfcol_store_update_stats) */
    uint64_t corrected;            /**< summed over the stores */
    uint64_t voted;                /**< summed over the stores */
    uint64_t oriented;             /**< summed over the stores */
    uint64_t collider_candidates;  /**< triangles given to the collider narrow phase */
    uint64_t collider_contacts;    /**< collider contacts found */
    uint64_t collider_penetrating; /**< of which penetrating */
    double seconds;                /**< wall time of the update */
    /* Version 2 */
    /** summed over the stores: sign changes that the step's start proved
     *  were no crossing (selfcol_scene_set_surface_start()) */
    uint64_t passed_around;
} selfcol_scene_update_stats;

/** The library writes the fields of the caller's version (1: up to `seconds`). */
#define SELFCOL_SCENE_UPDATE_STATS_VERSION 2

/**
 * Writes the defaults into opts: no query options (they must be given, with
 * a distance), NULL store and sequence options (their defaults), coherent 1.
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_scene_options_init(selfcol_scene_options *opts, unsigned int version);

/**
 * Names what selfcol_scene_create() refuses in opts, if anything: the field
 * (nested ones as "query->distance", "store->consistency", "sequence->skin"), its
 * value and what is accepted (common.h, selfcol_options_problem).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as
 *         selfcol_scene_create() for these options (NULL opts: SELFCOL_EINVAL);
 *         SELFCOL_EINVAL for a NULL problem, SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_scene_options_check(const selfcol_scene_options *opts,
                                            selfcol_options_problem *problem);

/**
 * Writes the defaults of a kind into opts (self-collision on for a cloth
 * only; orientation 0).
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, unknown kind); SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_scene_surface_options_init(selfcol_scene_surface_options *opts,
                                                   uint32_t kind, unsigned int version);

/**
 * Writes the defaults of a shape into desc (radius 0, half-height 0, half
 * extents 0, no points: the caller sets the shape's sizes).
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, unknown shape); SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_scene_collider_desc_init(selfcol_scene_collider_desc *desc, uint32_t shape,
                                                 unsigned int version);

/**
 * Creates an empty scene.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL out, NULL query, query->distance not in
 *         (0, 2^200], no kinds or unknown kinds, method or narrow phase
 *         as selfcol_hierarchy_self_collide() refuses them,
 *         consistency not 0 or 1, a store allocator or orientation set,
 *         negative or non-finite tolerance, half-set allocator);
 *         SELFCOL_EVERSION (the scene's, the query's, the store's or the
 *         sequence's version 0 or unknown, or scene version 1 or 2); SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_scene_create(selfcol_scene **out, const selfcol_scene_options *opts);

/** Destroys a scene, its hierarchies and stores (never the meshes). Accepts NULL. */
SELFCOL_API void selfcol_scene_destroy(selfcol_scene *scene);

/**
 * Adds a surface on a caller-owned mesh, which must outlive the scene, and
 * builds its hierarchy. Surfaces are numbered from 0 in the order added.
 * A body must be closed (no boundary edge), manifold and consistently
 * oriented (SELFCOL_MESH_MISORIENTED_EDGES 0), with a nonzero signed volume;
 * its orientation (+1 counter-clockwise outward, -1 inward) is taken from
 * the sign of that volume at the positions it has when added.
 * @param[out] id_out the surface id (may be NULL)
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL scene or mesh, a mesh added
 *         twice, unknown kind, self-collision on a static surface, an
 *         orientation on a non-static surface, a body that is not closed
 *         and oriented); SELFCOL_EVERSION; SELFCOL_ERANGE (more than 2^16
 *         surfaces, or the hierarchy's limits); SELFCOL_ENOMEM. On error the
 *         scene is unchanged.
 */
SELFCOL_API int selfcol_scene_add_surface(selfcol_scene *scene, const selfcol_mesh *mesh,
                                          const selfcol_scene_surface_options *opts,
                                          uint32_t *id_out);

/**
 * Removes a surface: destroys its hierarchy and the stores of the pairs it
 * belongs to. Every other pair keeps its store, with its contacts' memory
 * (remnance, sides through crossings). The id is never reused: the other
 * surfaces keep theirs, and a later selfcol_scene_add_surface() gets a new
 * one. After this the scene no longer reads the mesh, which the caller may
 * destroy.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL scene, unknown or removed id).
 */
SELFCOL_API int selfcol_scene_remove_surface(selfcol_scene *scene, uint32_t id);

/**
 * Rebuilds a surface's hierarchy from its mesh's current positions, keeping
 * its stores. This is how a static surface is moved on purpose: set its
 * mesh's positions, then rebuild it (updates would otherwise return
 * SELFCOL_ESTALE). For a cloth or body it is optional: a refit follows any
 * motion, and a rebuild only regroups the tree after large deformation.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL scene, unknown or removed id);
 *         SELFCOL_EMISMATCH (the mesh is not the one added: counts or
 *         topology changed); SELFCOL_ENOMEM (the surface keeps its old
 *         hierarchy).
 */
SELFCOL_API int selfcol_scene_rebuild_surface(selfcol_scene *scene, uint32_t id);

/**
 * Adds a convex collider, placed at the origin with no rotation until
 * selfcol_scene_set_collider_pose(). Colliders are numbered from 0.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, unknown shape, sizes negative or
 *         non-finite or beyond 2^200, a sphere or capsule without radius, a
 *         convex collider without points or with more than
 *         SELFCOL_COLLIDER_MAX_POINTS); SELFCOL_EVERSION; SELFCOL_ERANGE
 *         (more than 2^16 colliders); SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_scene_add_collider(selfcol_scene *scene,
                                           const selfcol_scene_collider_desc *desc,
                                           uint32_t *id_out);

/**
 * Places a collider: world = rotation * local + position.
 * @param[in] position 3 coordinates
 * @param[in] rotation 3 x 3, row-major, orthonormal with determinant +1
 *            (within 1e-6), or NULL for the identity
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL scene or position, unknown id,
 *         non-finite values, not a rotation); SELFCOL_ERANGE (a coordinate
 *         beyond 2^200). On error the pose is unchanged.
 */
SELFCOL_API int selfcol_scene_set_collider_pose(selfcol_scene *scene, uint32_t collider,
                                                const double position[3], const double rotation[9]);

/**
 * Runs the scene's refits, surface queries, coherent sequences and store
 * updates on `context` (context.h: its threads, its scheduler, its working
 * memory) from the next update on; without one (the default) they run on
 * the calling thread. The context is borrowed: it must outlive the scene or
 * be replaced first, and must not serve another call while the scene
 * updates. The stores are the same either way.
 * @param[in] context the context, or NULL to go back to the calling thread
 * @return SELFCOL_OK; SELFCOL_EINVAL for a NULL scene.
 */
SELFCOL_API int selfcol_scene_set_context(selfcol_scene *scene, selfcol_context *context);

/**
 * The positions of a cloth or body surface at the start of the step that the
 * next selfcol_scene_update() ends (3 doubles per vertex, copied), e.g. where
 * the caller's collision response left it after the last update. That update
 * then judges each sign change of the surface's pairs on the surface's path:
 * straight from its positions at the last update to these, then straight to
 * its current ones. A sign change is a crossing only if the elements may
 * have touched on the way (the continuous test of sweep.h's narrow phase);
 * otherwise they went around each other (SELFCOL_STORE_PASSED_AROUND, as
 * selfcol_store_update_swept()), which removes the two-frame pass-around
 * limit of the README. A pair uses it when each of its surfaces has a path
 * for this update (a start given, and an update since its first start) or
 * is static and not rebuilt since the last update; other pairs are updated
 * as before. Every update consumes the starts: give them before each update.
 * The scene keeps two arrays per such surface (48 bytes per vertex), made at
 * its first call.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL arguments, an unknown or removed
 *         surface, a static one, or a coordinate outside mesh.h's contract);
 *         SELFCOL_ENOMEM (the arrays, first call only: nothing changed).
 */
SELFCOL_API int selfcol_scene_set_surface_start(selfcol_scene *scene, uint32_t surface,
                                                const double *positions);

/**
 * One frame: refits the cloth and body hierarchies (never a static one),
 * queries every pair that can matter and updates its store, then finds the
 * collider contacts.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL); SELFCOL_ESTALE (a static
 *         surface's mesh moved); SELFCOL_EMISMATCH (a surface's mesh is not
 *         the one added: see above); the first error of a query or a store
 *         update (SELFCOL_ENOMEM, SELFCOL_ERANGE), after which the stores
 *         not yet updated keep the previous frame and the collider contacts
 *         are empty.
 */
SELFCOL_API int selfcol_scene_update(selfcol_scene *scene);

/**
 * The store of a surface pair (first <= second; first == second for
 * self-collision). Copy its contacts (selfcol_store_copy_contacts()) after
 * selfcol_scene_update() and before the surfaces' positions are set again:
 * their geometry is computed from the positions of that update.
 * @param[out] store_out borrowed, valid until the scene is destroyed; NULL
 *             when the scene never tests that pair (two static surfaces, a
 *             self pair without self-collision)
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL arguments, unknown ids, first > second).
 */
SELFCOL_API int selfcol_scene_store(const selfcol_scene *scene, uint32_t first, uint32_t second,
                                    const selfcol_store **store_out);

/**
 * The collider contacts of the last update, sorted by (collider, surface,
 * triangle).
 * @param[out] data_out borrowed, valid until the next update or destroy; NULL when empty
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments.
 */
SELFCOL_API int selfcol_scene_collider_contacts(const selfcol_scene *scene,
                                                const selfcol_collider_contact **data_out,
                                                size_t *count_out);

/**
 * Counters of the last update.
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_scene_stats(const selfcol_scene *scene, selfcol_scene_update_stats *stats);

/** Bytes held by the scene, its hierarchies and stores (not the meshes). 0 for NULL. */
SELFCOL_API size_t selfcol_scene_byte_count(const selfcol_scene *scene);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_SCENE_H */
