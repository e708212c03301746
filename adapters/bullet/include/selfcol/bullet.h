// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file bullet.h
 * @defgroup bullet Bullet soft-body adapter (libselfcol_bullet)
 * selfcol as the cloth self-collision (and soft-soft collision) of Bullet
 * 3.24's deformable world, `btDeformableMultiBodyDynamicsWorld`.
 *
 * An adapter belongs to one world. Soft bodies attached to it get their
 * self-collision and their collisions with each other from selfcol:
 * Bullet's own self-collision is switched off on them, and Bullet's
 * soft-soft handling skips every pair of two attached bodies (attach marks
 * the body with the CL_SELF bit of btSoftBody::fCollision, which Bullet
 * 3.24 reads only for cluster self-collision; btSoftBody::
 * defaultCollisionHandler() handles a pair only when the two bodies' common
 * soft-soft bits are exactly VF_DD, so two marked bodies never match).
 * Pairs of an attached body with an unattached one keep Bullet's own
 * vertex-face handling (VF_DD, when both bodies have it), as do rigid
 * bodies, multibodies and Bullet's soft-rigid collision. Detaching (or
 * destroying the adapter) restores the body's settings.
 *
 * Lifetimes and identity. The world must outlive the adapter: destroy the
 * adapter before deleting the world. A program whose teardown deletes the
 * world first (the order of many Bullet programs, and of C++ members
 * declared in the wrong order) calls selfcol_bullet_destroy_after_world()
 * instead, which reads neither the world nor the bodies; calling
 * selfcol_bullet_destroy() after the world is gone reads freed memory (it
 * removes the adapter's action from the world). A body is
 * known by its address: attach only bodies that are in the adapter's world
 * (btDeformableMultiBodyDynamicsWorld::getSoftBodyArray()), and detach a
 * body (selfcol_bullet_detach()) or destroy the adapter before deleting it.
 * A body removed from the world while attached is dropped, with the stores
 * of its pairs, at the adapter's next step, without reading or writing it
 * (it may have been deleted: its settings are not restored); every step
 * and selfcol_bullet_destroy() check the world's soft body array by
 * pointer before they touch an attached body. What no check can see: a body
 * deleted and another one created at the same address and added to the
 * world before the next step would be taken for the first (its node and
 * face counts are checked, SELFCOL_ESTALE when they differ); so remove and
 * delete an attached body only after detaching it, or step in between. A
 * body can be attached to one adapter at a time (the CL_SELF mark): a body
 * already attached elsewhere, or using Bullet's cluster self-collision
 * (CL_SELF set by its owner), is refused.
 *
 * Each internal step of the world (the adapter registers a btActionInterface,
 * which the deformable world runs right after it has moved the nodes,
 * x_{n+1} = x_n + dt v_{n+1}), the adapter:
 * 1. reads the node positions (selfcol_mesh_set_positions_float() with the
 *    stride of btSoftBody::Node, no copy on Bullet's side);
 * 2. refits, queries (VF, EE and EF, exact) and updates the contact stores
 *    of a selfcol_scene: remnance, sides tracked through crossings and the
 *    region vote (Volino & Magnenat Thalmann 1995, section 3);
 * 3. applies one response per stored contact along its consistent side:
 *    an inelastic velocity impulse that stops the two elements approaching
 *    and a repulsion that moves them apart toward the thickness (the
 *    detection distance d), mass-weighted over the four nodes with the
 *    contact's barycentric weights, in the spirit of Bridson, Fedkiw and
 *    Anderson 2002 (section 7). A contact whose elements have crossed
 *    (negative signed distance) is pushed back through to its right side,
 *    which is what lets cloth that starts interpenetrating come apart.
 *
 * Bullet's soft-rigid world (btSoftRigidDynamicsWorld) is not supported: it
 * solves its soft bodies after every hook a world offers (actions and tick
 * callbacks run before solveSoftBodiesConstraints()), so a response there
 * would be overwritten by its position solver. Bullet built with double
 * precision is refused when the adapter is built (CMake message, and an
 * #error in this header when BT_USE_DOUBLE_PRECISION is defined).
 *
 * Every function is `extern "C"` and catches every exception: none crosses
 * this boundary (std::bad_alloc becomes SELFCOL_ENOMEM). Not thread-safe:
 * one thread drives a world and its adapter.
 * @{
 */
#ifndef SELFCOL_BULLET_H
#define SELFCOL_BULLET_H

#include <selfcol/selfcol.h>

#if defined(BT_USE_DOUBLE_PRECISION)
#error "libselfcol_bullet supports single-precision Bullet only (btScalar = float)"
#endif

/* Exported from the shared library only: a static libselfcol_bullet is built
   with SELFCOL_BULLET_STATIC, so its symbols stay hidden in what links it. */
#if defined(SELFCOL_BULLET_BUILDING) && !defined(SELFCOL_BULLET_STATIC)
#define SELFCOL_BULLET_API __attribute__((visibility("default")))
#else
#define SELFCOL_BULLET_API
#endif

/* Bullet's classes, opaque here: C code passes the pointers through. */
#ifdef __cplusplus
class btSoftBody;
class btDeformableMultiBodyDynamicsWorld;
#else
typedef struct btSoftBody btSoftBody;
typedef struct btDeformableMultiBodyDynamicsWorld btDeformableMultiBodyDynamicsWorld;
#endif

SELFCOL_BEGIN_DECLS

/** Opaque adapter: one per world. */
typedef struct selfcol_bullet selfcol_bullet;

/** Default thickness: this fraction of the attached bodies' mean edge length. */
#define SELFCOL_BULLET_DEFAULT_DISTANCE_FACTOR 0.25
/** Default fraction of the gap to the thickness that the repulsion closes per step. */
#define SELFCOL_BULLET_DEFAULT_REPULSION 0.5
/** Default Gauss-Seidel passes over the contacts per step. */
#define SELFCOL_BULLET_DEFAULT_ITERATIONS 4u

/**
 * Options for selfcol_bullet_create(). Initialise with selfcol_bullet_options_init().
 * The queries and the contact stores are configured by the core's own
 * option structs, passed by pointer (docs/architecture.md, "Threads and
 * options": a field added to either changes neither this layout nor its
 * version), read as their own versions say and checked at creation by the
 * core's rules. selfcol_bullet_create() keeps copies: the pointed-to
 * structs need not outlive the call.
 */
typedef struct selfcol_bullet_options {
    unsigned int version; /**< SELFCOL_BULLET_OPTIONS_VERSION */
    selfcol_allocator
        allocator; /**< of the adapter and its selfcol handles; all-zero: malloc/free */
    /**
     * The queries; NULL for selfcol_query_options_init()'s defaults (kinds
     * VF|EE|EF, method EXACT, closed-form narrow phase, distance 0).
     * `distance` is the
     * detection distance and cloth thickness d, in world units, at most
     * SELFCOL_MESH_MAX_COORDINATE; 0 (the default here): distance_factor x
     * the mean edge length of the bodies attached at the first step, so that
     * any scale works (a 1 m cloth with 1 cm edges collides at 2.5 mm). The
     * thickness is fixed when the scene is made, at the first step with a
     * body attached: bodies attached later collide at that thickness (set
     * it explicitly when bodies of very different edge lengths come and go).
     * Responses need VF and EE contacts, the untangling EF interferences:
     * leaving a kind out leaves out what it drives.
     */
    const selfcol_query_options *query;
    /**
     * The contact stores: remnance_frames (default
     * SELFCOL_STORE_DEFAULT_REMNANCE) and consistency (the region vote,
     * default 1); NULL for those defaults. Its
     * allocator and orientations must stay zero: the adapter's allocator
     * serves the stores, and cloth has no orientation.
     */
    const selfcol_store_options *store;
    double distance_factor; /**< default SELFCOL_BULLET_DEFAULT_DISTANCE_FACTOR; used when
                               the query's distance is 0 (or query is NULL) */
    /**
     * Repulsion strength, in (0, 1]: the fraction of the gap between a
     * contact's signed distance and d that one step closes (at most d per
     * step). Dimensionless, so it holds at any scale and mass: impulses are
     * weighted by the nodes' inverse masses. Default SELFCOL_BULLET_DEFAULT_REPULSION.
     */
    double repulsion;
    unsigned int iterations; /**< Gauss-Seidel passes per step (default 4, at most 64) */
    /**
     * 1 (default): the adapter registers an action in the world and runs at
     * every internal step. 0: nothing is registered; the caller runs
     * selfcol_bullet_step() itself after each internal step.
     */
    int automatic;
    /**
     * 1 (default): where surfaces cross, shorten their intersection contours
     * each step (Volino and Magnenat-Thalmann 2006, intersection contour
     * minimisation, local form): every EF interference moves its edge's and
     * triangle's nodes apart along the direction that shortens the contour,
     * by SELFCOL_BULLET_UNTANGLE_STEP x d of relative displacement (no node
     * moves further than that in one step, however many crossings share
     * it). This undoes crossings that no proximity reaches (a vertex pushed
     * through the other layer, whose contacts took the crossed side as
     * right), with no side to decide. 0: off.
     */
    int untangle;
    /**
     * 1: keep each step free of new pass-throughs (default 0: off). After the
     * response, a continuous query (selfcol/sweep.h, separation 0) follows
     * every attached node on the straight line from where the last step
     * left it to where this step puts it; each node of a pair that would
     * touch during the step is held back to SELFCOL_BULLET_CONTINUOUS_HOLD
     * of the pair's time of impact (its velocity scaled alike), and the
     * query runs again on the held motion, up to
     * SELFCOL_BULLET_CONTINUOUS_PASSES times. The pairs still touching then
     * go to rigid impact zones (Provot 1997; Bridson, Fedkiw and Anderson
     * 2002): their nodes join zones, each zone moves as one body from where
     * the step started (keeping its linear and angular momentum, or
     * following its kinematic nodes), and the query runs again, merging
     * zones, up to SELFCOL_BULLET_CONTINUOUS_ZONE_PASSES times (after 8,
     * zones without kinematic nodes stay where the step started, and a
     * pass that merges no zone pins the free nodes of its pairs where the
     * step started; when it pins no new node, the free nodes of its pairs
     * that a kinematic or following node first touches after the step's
     * start follow their zone again; the passes end at the first that
     * merges no zone, pins no new node and sets none following, which
     * every later one would repeat): a step
     * that starts with no crossing ends with none unless pairs are left
     * after the last pass (stats: continuous_remaining: zones that did not
     * settle within the passes, or kinematic nodes that do not move as one
     * body). A crossing already there when the step starts (an edge through
     * a triangle: an exact EF query at the end of each step finds them) is
     * not held in place: the pairs it is made of (a vertex of the edge
     * against the triangle, the edge against the triangle's edges) are let
     * through (stats: continuous_exempt), so the response and the
     * untangling can undo it. Kinematic nodes (zero inverse mass) are never held or moved: a
     * pair of kinematic nodes only is left alone. The first step after an
     * attach or detach has no last positions and is not checked. Costs a
     * continuous query per pass (stats): the step's first over every pair,
     * the later ones over the pairs of the nodes the last pass moved
     * (selfcol_sweep_options.active_vertices), on the adapter's threads (or
     * Bullet's scheduler: selfcol_bullet_use_task_scheduler); the held
     * positions do not depend on the threads.
     * The option also gives the scene where each step starts (where the
     * last step left the nodes: selfcol_scene_set_surface_start), so a
     * contact whose side changes sign counts as crossed only if its
     * elements may have touched on the way; a pair that went around each
     * other keeps its side (stats: passed_around) instead of being pushed
     * back through. 48 bytes per node more in the scene.
     */
    int continuous;
    /**
     * 1 (default): each surface pair's query is answered from a
     * selfcol_sequence (selfcol/sequence.h) while the cloth's deformation
     * since its last rebuild allows: the same contacts as a fresh query
     * every step, at a fraction of its cost when nodes move a little per
     * step. 0: a fresh query every step (the scene option `coherent`).
     */
    int coherent;
    /**
     * Threads of the adapter's refits, queries, store updates and continuous
     * passes, 1 (default: Bullet's calling thread) to SELFCOL_MAX_THREADS.
     * With more, the adapter keeps a context of that many POSIX threads
     * (selfcol/context.h), asleep between steps and joined by
     * selfcol_bullet_destroy(); selfcol_bullet_use_task_scheduler() runs the
     * same stages on Bullet's scheduler instead. The contacts and the held
     * positions do not depend on the threads.
     */
    unsigned int threads;
} selfcol_bullet_options;

/** 4 since 0.4 (the query and store options by pointer); 0.2's versions 1
 *  and 2 and 0.3's version 3 (those options embedded) are refused. */
#define SELFCOL_BULLET_OPTIONS_VERSION 4
/** Relative displacement per step of each EF interference's nodes when untangling, in units of d.
 */
#define SELFCOL_BULLET_UNTANGLE_STEP 0.25
/** Continuous option: the fraction of a pair's time of impact its nodes keep of their motion. */
#define SELFCOL_BULLET_CONTINUOUS_HOLD 0.8
/** Continuous option: held-back passes per step at most, before the impact zones. */
#define SELFCOL_BULLET_CONTINUOUS_PASSES 4
/** Continuous option: impact-zone passes per step at most (the last one's hits are counted);
 *  after the first 8, zones without kinematic nodes stay where the step started, a pass that
 *  merges no zone pins its pairs' free nodes where the step started (or, pinning none, lets
 *  those that a driven node sweeps into follow their zone), and one that merges no zone and
 *  changes no node's state is the last. */
#define SELFCOL_BULLET_CONTINUOUS_ZONE_PASSES 32

/** Counters of the last step. The caller sets version. */
typedef struct selfcol_bullet_step_stats {
    unsigned int version; /**< SELFCOL_BULLET_STEP_STATS_VERSION */
    int status;           /**< the last step's status (0, or the selfcol_status that stopped it) */
    uint64_t steps;       /**< steps run since creation */
    double distance;      /**< the thickness in use (0 before the first step) */
    uint64_t contacts;    /**< VF and EE contacts held (self and soft-soft) */
    /** EF interferences (edges crossing triangles) held, as the step's
     *  detection found them (before its response and continuous passes) */
    uint64_t interferences;
    uint64_t crossed; /**< of the contacts, those on their wrong side (negative signed distance) */
    uint64_t flipped; /**< contacts that crossed during the step (store counter) */
    uint64_t corrected;    /**< contacts whose right side the region vote changed */
    uint64_t responses;    /**< contacts that received an impulse */
    double max_push;       /**< largest position correction of a contact, world units */
    double seconds_detect; /**< positions in, refit, query and stores */
    double seconds_response;
    /* Version 2. */
    uint64_t untangled; /**< EF interferences whose nodes the untangling moved */
    /* Version 3 (continuous option; 0 when it is off). */
    uint64_t continuous_hits;      /**< pairs touching during the step, first pass */
    uint64_t continuous_held;      /**< nodes held back, over all passes */
    uint64_t continuous_passes;    /**< continuous queries run */
    uint64_t continuous_remaining; /**< pairs still touching after the last pass */
    double seconds_continuous;     /**< time of the continuous passes */
    /* Version 4 (continuous option; 0 when it is off). */
    /** sign changes of contacts that the step's path proved were no crossing
     *  (selfcol_scene_update_stats.passed_around) */
    uint64_t passed_around;
    /** nodes the impact zones moved in their last pass (continuous option) */
    uint64_t zone_nodes;
    /** pairs of the step's first continuous pass let through because they
     *  are part of a crossing where the step started (continuous option) */
    uint64_t continuous_exempt;
    /** EF interferences (edges crossing triangles) where the step left the
     *  nodes, after its response and continuous passes: the crossings the
     *  next step starts with (continuous option: its exact EF query at the
     *  step's end; 0 when it is off, where `interferences` is the count) */
    uint64_t crossings_after;
} selfcol_bullet_step_stats;

#define SELFCOL_BULLET_STEP_STATS_VERSION 4

/**
 * Writes the defaults into opts (query and store NULL: the core's defaults).
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL); SELFCOL_EVERSION (any version
 *         but SELFCOL_BULLET_OPTIONS_VERSION: 0.2's and 0.3's layouts are
 *         refused).
 */
SELFCOL_BULLET_API int selfcol_bullet_options_init(selfcol_bullet_options *opts,
                                                   unsigned int version);

/**
 * Names what selfcol_bullet_create() refuses in opts, if anything: the
 * field ("repulsion", "threads", "query->kinds", "store->consistency", ...), its value
 * and what is accepted (selfcol/common.h, selfcol_options_problem).
 * @return what selfcol_bullet_create() returns for these options, short of
 *         its world and of memory (SELFCOL_OK, SELFCOL_EINVAL,
 *         SELFCOL_EVERSION); SELFCOL_EINVAL for a NULL problem,
 *         SELFCOL_EVERSION for its version.
 */
SELFCOL_BULLET_API int selfcol_bullet_options_check(const selfcol_bullet_options *opts,
                                                    selfcol_options_problem *problem);

/**
 * Creates an adapter for a deformable world (and, with automatic on, adds its
 * action to the world).
 * @param[out] out the adapter; NULL on failure
 * @param[in] world the world; it must outlive the adapter
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, query->distance < 0, not finite
 *         or above SELFCOL_MESH_MAX_COORDINATE, distance_factor not positive
 *         and finite when the distance is 0, any query or store option
 *         that selfcol_scene_create() refuses (kinds, method, narrow phase,
 *         consistency, a store allocator or orientation), threads outside
 *         1..SELFCOL_MAX_THREADS, repulsion outside (0, 1], iterations
 *         0 or > 64, automatic or untangle not 0 or 1, half-set allocator);
 *         SELFCOL_EVERSION (the options', the query's or the store's
 *         version); SELFCOL_ENOMEM.
 */
SELFCOL_BULLET_API int selfcol_bullet_create(selfcol_bullet **out,
                                             btDeformableMultiBodyDynamicsWorld *world,
                                             const selfcol_bullet_options *opts);

/**
 * Removes the action, detaches every attached body that is still in the
 * world (a body no longer in it is forgotten untouched: see the lifetime
 * rules above), and frees everything. Accepts NULL.
 */
SELFCOL_BULLET_API void selfcol_bullet_destroy(selfcol_bullet *adapter);

/**
 * Frees an adapter whose world has already been deleted (see the lifetime
 * rules above), reading neither the world nor any attached body: the action
 * is not removed (the world that held it is gone) and the bodies' settings
 * are not restored (they may be gone too). Only for that order: while the
 * world lives, its action would be left pointing at freed memory, so use
 * selfcol_bullet_destroy(). Accepts NULL.
 */
SELFCOL_BULLET_API void selfcol_bullet_destroy_after_world(selfcol_bullet *adapter);

/**
 * Attaches a soft body of the adapter's world, with its faces. The mesh is
 * its nodes and faces as they are now; the body's topology must not change
 * while attached (a changed node or face count makes the next step return
 * SELFCOL_ESTALE). Switches off the body's own self-collision
 * (setSelfCollision(false)) and marks it (CL_SELF) so that Bullet's
 * soft-soft handling skips its pairs with other attached bodies; its pairs
 * with unattached bodies stay Bullet's. Nodes of zero mass (pinned or
 * kinematic) take no impulse.
 *
 * Attaching to a live scene (after the first step) adds the body's surface
 * to it: every other pair keeps its store, with its contacts' memory. The
 * body collides at the scene's thickness (selfcol_bullet_options.query).
 * @param[out] id_out the body's surface id in selfcol_bullet_scene(), or
 *            NULL. Ids follow attach order and are never reused.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, a body not in the adapter's
 *         world, no faces, attached to this or another adapter or carrying
 *         CL_SELF, non-finite positions or velocities); SELFCOL_ERANGE
 *         (2^31 nodes or 2^16 attaches in all); SELFCOL_ENOMEM. On error
 *         nothing changes.
 */
SELFCOL_BULLET_API int selfcol_bullet_attach(selfcol_bullet *adapter, btSoftBody *body,
                                             uint32_t *id_out);

/**
 * Detaches a body: restores its self-collision setting, removes the mark,
 * and removes its surface and the stores of its pairs from the scene. Every
 * other pair keeps its store. Call it before deleting an attached body.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL, a body not attached, or one a
 *         step already dropped because it had left the world).
 */
SELFCOL_BULLET_API int selfcol_bullet_detach(selfcol_bullet *adapter, btSoftBody *body);

/**
 * One step: detection, stores, response (what the action runs). Call it
 * yourself only with automatic off, once after each internal step. First
 * it drops the attached bodies that are no longer in the world (lifetime
 * rules above).
 * @param[in] dt the internal step's length, > 0
 * @return SELFCOL_OK; SELFCOL_EINVAL (dt, a non-finite node position or
 *         velocity); SELFCOL_ESTALE (a body's topology changed); SELFCOL_ENOMEM;
 *         an error of the scene (selfcol_status). On error no node is
 *         changed. The action records the status in the stats.
 */
SELFCOL_BULLET_API int selfcol_bullet_step(selfcol_bullet *adapter, double dt);

/** Counters of the last step. @return SELFCOL_OK; SELFCOL_EINVAL; SELFCOL_EVERSION. */
SELFCOL_BULLET_API int selfcol_bullet_stats(const selfcol_bullet *adapter,
                                            selfcol_bullet_step_stats *stats);

/**
 * on = 1: the adapter's refits, queries, coherent sequences, store updates
 * and continuous queries (the continuous option) run their parallel stages
 * on Bullet's task scheduler
 * (btGetTaskScheduler(), through btParallelFor), as many work items as it has threads now
 * (getNumThreads(), at most SELFCOL_MAX_THREADS; 1 when no scheduler is
 * installed): the engine's own threads,
 * none started by selfcol. on = 0 (the default): the adapter's own threads
 * (selfcol_bullet_options.threads). The contacts are the same either way. Call it again
 * after changing Bullet's scheduler or its thread count.
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL adapter, on not 0 or 1);
 *         SELFCOL_ENOMEM (nothing changed).
 */
SELFCOL_BULLET_API int selfcol_bullet_use_task_scheduler(selfcol_bullet *adapter, int on);

/**
 * The scene the adapter runs (NULL before the first step with a body
 * attached): its stores hold the contacts with their sides
 * (selfcol_scene_store()), surface ids as returned by
 * selfcol_bullet_attach(). Borrowed; valid until the adapter is destroyed
 * (attach and detach add and remove surfaces; a removed surface's stores
 * are gone).
 */
SELFCOL_BULLET_API const selfcol_scene *selfcol_bullet_scene(const selfcol_bullet *adapter);

/**
 * The attached body's mesh (positions of the last step). Borrowed, valid
 * while the body is attached. NULL for an id not attached (never given,
 * detached, or dropped).
 */
SELFCOL_BULLET_API const selfcol_mesh *selfcol_bullet_mesh(const selfcol_bullet *adapter,
                                                           uint32_t id);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_BULLET_H */
