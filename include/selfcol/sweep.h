// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file sweep.h
 * @defgroup sweep Continuous queries
 * Continuous collision detection over one step: nothing passes through
 * between two frames unseen.
 *
 * A discrete query (hierarchy.h) answers for one set of positions: a vertex
 * that goes through a triangle within one step is close to it at neither end
 * and is never reported. A continuous query ("sweep") takes each vertex on the
 * straight line from its position at the start of the step (t = 0, given as
 * an array) to its current position in the mesh (t = 1), and finds every
 * vertex-triangle (VF) and edge-edge (EE) pair that comes within the
 * separation delta >= 0 at some t in [0, 1] (delta = 0: they touch). For each
 * such pair it reports a conservative time of impact (toi <= the earliest
 * such t), and for the whole step the collision-free fraction: the least toi
 * over all pairs (1 when there is none), the number a simulator's line search
 * or step-size control needs.
 *
 * **The contact set.** The same pairs as a discrete query's VF and EE kinds
 * (contacts.h): for one surface, a vertex against a triangle it is not a
 * corner of, an edge against an edge sharing no vertex; for two surfaces,
 * every vertex of one against every triangle of the other (both ways) and
 * every edge of one against every edge of the other; vertices of no triangle
 * and repeated triangles (SELFCOL_TRIANGLE_DUPLICATE) as there. A pair is
 * reported when the continuous narrow phase answers 1 for it:
 *
 * - **No false negatives**: a pair that comes within delta in exact
 *   arithmetic, at any t in [0, 1], is reported, and its toi is at most the
 *   earliest such t. Rounding is covered by a derived bound (lib/
 *   narrow_sweep.c, an inclusion-based root finder after Tight-Inclusion,
 *   Wang et al. 2021). Checked against the exact truth of the continuous-
 *   collision benchmark (7,279 queries, 0 misses) and of real simulation
 *   steps (`mma_bool`).
 * - **Bounded false positives**: a reported pair came, at t = toi, within
 *   about sqrt(3) (delta + 1e-6 L) of touching, L being the extent of the
 *   pair's eight positions' bounding box (1e-6: the option `tolerance`,
 *   which the caller may raise); except pairs flagged
 *   SELFCOL_SWEEP_UNRESOLVED, for which the root finder's work budget (1e5
 *   boxes) ran out before it could decide: reported, conservatively, with
 *   the earliest time still undecided. At delta = 0 a pair whose four
 *   points are provably coplanar at no time of the step (a cubic's
 *   Bernstein coefficients of one sign, lib/narrow/narrow_sweep.c) is not
 *   reported: it cannot touch.
 * - **Pairs already within delta at t = 0 are reported** with toi 0 (and
 *   SELFCOL_SWEEP_INITIAL when the closed-form distance at t = 0 is at most
 *   delta), so the collision-free fraction is then 0. That is the honest
 *   answer for a step that starts in contact; a simulator that keeps contacts
 *   within delta should query with a smaller separation than its contact
 *   distance (as IPC does with its minimum distance).
 *
 * SELFCOL_METHOD_EXHAUSTIVE and SELFCOL_METHOD_BVH return the same pairs with
 * the same toi: both run the same narrow phase on the same pairs, after
 * filters that only remove pairs whose swept boxes are farther apart than
 * delta on some axis (the box of a primitive's start and end positions holds
 * it at every t, since each point moves on a segment). EXHAUSTIVE tests every
 * pair; BVH descends the hierarchy's tree with the swept boxes of its nodes,
 * computed by the query (the hierarchy's own boxes are not used, so it need
 * not be refit).
 *
 * SELFCOL_METHOD_EXACT (self queries; on two surfaces it is BVH) adds the
 * curvature criterion over the step (lib/continuous/sweep_cull.c): a patch whose
 * normals stay in one open half-space at every t (cones around the Bernstein
 * coefficients of each triangle's normal) and whose projected boundary stays
 * a simple polygon with clearance delta (checked at t = 0 with the clearance
 * raised by twice the boundary's deformation over the step) holds no pair of
 * the contact set, and is skipped. Its hits are BVH's except pairs that
 * provably never come within delta, i.e. narrow-phase false positives; the
 * true collisions and the free fraction's guarantee are the same. It pays
 * where patches move smoothly (a sheet translated and deepening its
 * wrinkles: no candidate left); on the benchmark's real steps, where
 * vertices move about 1.4 mean edges per step, it removes 3 to 31 % of the
 * candidates and costs more than it saves (docs/benchmarks.md), so BVH stays
 * the default.
 * @{
 */
#ifndef SELFCOL_SWEEP_H
#define SELFCOL_SWEEP_H

#include "common.h"
#include "hierarchy.h"

SELFCOL_BEGIN_DECLS

/** Opaque result of continuous queries, with the memory they reuse. */
typedef struct selfcol_sweep selfcol_sweep;

/** What a continuous query reports. */
typedef enum selfcol_sweep_mode {
    /** Every colliding pair with its toi, and the collision-free fraction. */
    SELFCOL_SWEEP_ALL = 0,
    /** The collision-free fraction only, and the one pair that gives it: each
     *  pair's root search stops at the earliest time found so far, and once
     *  that time is well below the span the broad phase swept its boxes
     *  over, the broad phase starts again over [0, that time] alone; much
     *  faster when many pairs collide. The fraction is conservative
     *  (no later than the earliest contact) like every toi, but need not
     *  equal the least toi of SELFCOL_SWEEP_ALL to the last bit: the root
     *  finder subdivides differently when told to stop early. */
    SELFCOL_SWEEP_EARLIEST = 1
} selfcol_sweep_mode;

/** Options of a continuous query. Initialise with selfcol_sweep_options_init(). */
typedef struct selfcol_sweep_options {
    unsigned int version; /**< SELFCOL_SWEEP_OPTIONS_VERSION */
    /** SELFCOL_METHOD_BVH (default), SELFCOL_METHOD_EXACT (BVH and the
     *  curvature criterion over the step) or SELFCOL_METHOD_EXHAUSTIVE (the
     *  reference); other methods are SELFCOL_EINVAL. */
    uint32_t method;
    /** SELFCOL_KIND_VF and/or SELFCOL_KIND_EE (default both). */
    uint32_t kinds;
    /** selfcol_sweep_mode; default SELFCOL_SWEEP_ALL. */
    uint32_t mode;
    /** Separation delta >= 0 in mesh units; default 0. */
    double separation;
    /** Progress and cancel (libgit2's model): called on the calling thread between rounds of
     * SELFCOL_SWEEP_ALL's root searches (about 64 times, every 1024 candidates at least, the last
     * time with 1) with the fraction of the candidates done, in [0, 1]; a non-zero return cancels
     * the query, which then returns SELFCOL_EUSER with the result empty. NULL (the default): none.
     * SELFCOL_SWEEP_EARLIEST does not call it (its passes take about a query each). */
    int (*progress)(void *payload, double done);
    void *progress_payload; /**< passed to progress */
    /** Pairs restricted to active vertices: per mesh (first, second; a self query reads [0]
     *  only), NULL or one byte per vertex of that mesh, non-zero for an active vertex. When
     *  an array the query reads is set, only the pairs of the contact set with at least one
     *  active vertex are tested (a NULL array then has no active vertex): the hits are exactly
     *  the unrestricted query's hits that have one, with the same toi and flags (each pair's
     *  answer depends on its own vertices' motion alone), and SELFCOL_SWEEP_EARLIEST's
     *  fraction is theirs. Both NULL (the default): every pair. The use: a response that
     *  changes some vertices' motion and queries the step again (held-back passes, impact
     *  zones) marks those vertices, since no other pair's answer can have changed; the
     *  traversal then skips node pairs with no active vertex below them. */
    const uint8_t *active_vertices[2];
    /** The root finder's relative tolerance, in 1e-12 .. 0.1 (default
     *  SELFCOL_SWEEP_DEFAULT_TOLERANCE): a pair is reported when, at its toi, two of its points
     *  are within sqrt(3) (separation + tolerance L + a rounding term of 2^-45 times the
     *  coordinates' magnitude) of each other, L the largest extent of the box of its four
     *  points' start and end positions. Never a false negative, whatever the tolerance. A
     *  larger one stops each pair's search sooner, and reports the pairs that come within
     *  that band: rod-twist 3036 -> 3037 with SELFCOL_SWEEP_ALL (BVH, one thread) takes 1.8 s
     *  at 1e-3 against 6.5 s at 1e-6, with 6,484 pairs against 4,950 (docs/benchmarks.md).
     *  A toi is then only as early as the band allows: a pair that starts within it gets toi
     *  0, so SELFCOL_SWEEP_EARLIEST's fraction drops to 0 there (rod-twist: 5.34e-5 at 1e-6,
     *  0 at 1e-4 and 1e-3). */
    double tolerance;
} selfcol_sweep_options;

/** Default of selfcol_sweep_options.tolerance: Tight-Inclusion's (Wang et al. 2021) 1e-6,
 *  relative here (times the pair's extent L). */
#define SELFCOL_SWEEP_DEFAULT_TOLERANCE 1e-6

/** 3 since 0.4 (threads moved to the context: selfcol_context_self_sweep());
 *  0.3's versions 1 and 2 are refused. */
#define SELFCOL_SWEEP_OPTIONS_VERSION 3

/** Bits of selfcol_sweep_hit.flags. */
typedef enum selfcol_sweep_hit_flag {
    /** Within the separation already at t = 0 (closed-form distance). */
    SELFCOL_SWEEP_INITIAL = 1u << 0,
    /** The root finder's budget ran out: reported conservatively, no
     *  distance bound. */
    SELFCOL_SWEEP_UNRESOLVED = 1u << 1
} selfcol_sweep_hit_flag;

/** One colliding pair of a continuous query. Plain data; the layout is part of the ABI. */
typedef struct selfcol_sweep_hit {
    uint32_t kind;        /**< SELFCOL_CONTACT_VF or SELFCOL_CONTACT_EE */
    uint32_t first;       /**< vertex (VF) or edge (EE), as in selfcol_contact */
    uint32_t second;      /**< triangle (VF) or edge (EE) */
    uint32_t first_mesh;  /**< 0 or 1 */
    uint32_t second_mesh; /**< 0 or 1 */
    uint32_t a[2];        /**< vertices of the first primitive (a[1] = a[0] for VF) */
    uint32_t b[3];        /**< vertices of the second (b[2] = SELFCOL_INVALID_INDEX for EE) */
    uint32_t flags;       /**< selfcol_sweep_hit_flag bits */
    /** Conservative time of impact in [0, 1]: at most the earliest t at which
     *  the pair is within the separation. */
    double toi;
} selfcol_sweep_hit;

/**
 * Counters of the last continuous query. The caller sets version to
 * SELFCOL_SWEEP_STATS_VERSION; the library writes the fields of that version.
 */
typedef struct selfcol_sweep_query_stats {
    unsigned int version; /**< SELFCOL_SWEEP_STATS_VERSION */
    /** The collision-free fraction: the least toi over all pairs, 1 when no
     *  pair collides. A SELFCOL_SWEEP_UNRESOLVED hit's toi is only the
     *  earliest time its root finder left undecided (often 0); such a pair
     *  is searched again over [0, fraction of the others) alone and lowers
     *  the fraction only if it may collide there. */
    double free_fraction;
    /** broad-phase passes: 1 for ALL; EARLIEST starts again with boxes
     *  swept over [0, t] once it has found a time t well below their span */
    uint64_t passes;
    uint64_t node_pairs;    /**< node pairs whose swept boxes were compared (BVH) */
    uint64_t candidates;    /**< primitive pairs whose swept boxes are within delta */
    uint64_t vf_candidates; /**< of which VF */
    uint64_t ee_candidates; /**< of which EE */
    /** candidates shown apart by a fixed direction separating them at both
     *  ends of the step (an axis, the pair's normal, or one of its in-plane
     *  normals), before any root finding */
    uint64_t separated;
    uint64_t narrow_boxes; /**< root finder boxes evaluated, over all candidates */
    uint64_t hits;         /**< colliding pairs (SELFCOL_SWEEP_ALL) */
    uint64_t initial;      /**< of which within the separation at t = 0 */
    uint64_t unresolved;   /**< of which unresolved (budget) */
    double broad_seconds;  /**< swept boxes and the candidate search */
    double narrow_seconds; /**< root finding over the candidates */
    double total_seconds;  /**< the whole query */
    /* Version 2. */
    /** patches (Self of a node, or Pair of two adjacent nodes) that
     *  SELFCOL_METHOD_EXACT proved free of contacts over the whole step and
     *  skipped */
    uint64_t patches_culled;
    uint64_t cull_tests; /**< contour tests run by that proof (passed or not) */
    double cull_seconds; /**< the cones over the step and the contour tests (part of broad) */
} selfcol_sweep_query_stats;

#define SELFCOL_SWEEP_STATS_VERSION 2

/**
 * Writes the defaults into opts (BVH, VF and EE, SELFCOL_SWEEP_ALL,
 * separation 0, one thread).
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_sweep_options_init(selfcol_sweep_options *opts, unsigned int version);

/**
 * Names what the continuous queries refuse in opts, if anything: the field,
 * its value and what is accepted (common.h, selfcol_options_problem).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as the queries for
 *         these options (short of their other arguments); SELFCOL_EINVAL
 *         for a NULL problem, SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_sweep_options_check(const selfcol_sweep_options *opts,
                                            selfcol_options_problem *problem);

/**
 * Creates an empty result.
 * @param[out] out the new handle; NULL on failure. Free it with selfcol_sweep_destroy().
 * @param[in] allocator its allocator hooks (copied), or NULL for malloc/free
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL out, half-set allocator); SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_sweep_create(selfcol_sweep **out, const selfcol_allocator *allocator);

/** Destroys a result. Accepts NULL. */
SELFCOL_API void selfcol_sweep_destroy(selfcol_sweep *sweep);

/**
 * Continuous self-query of the hierarchy's mesh over one step: from
 * start_positions (t = 0) to the mesh's current positions (t = 1). Replaces
 * the content of result. The hierarchy's tree is used, not its boxes: it need
 * not be refit.
 * @param[in] hierarchy a hierarchy of the mesh
 * @param[in] start_positions 3 x vertex_count doubles (x, y, z per vertex),
 *            each 0 or of magnitude in [SELFCOL_MESH_MIN_COORDINATE,
 *            SELFCOL_MESH_MAX_COORDINATE] (mesh.h's contract)
 * @param[out] result receives the pairs and the statistics
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL argument, bad option, a
 *         start coordinate outside mesh.h's contract); SELFCOL_EVERSION;
 *         SELFCOL_EMISMATCH (the hierarchy's mesh is not the one it was
 *         built on); SELFCOL_ENOMEM (result then empty).
 */
SELFCOL_API int selfcol_hierarchy_self_sweep(const selfcol_hierarchy *hierarchy,
                                             const double *start_positions, selfcol_sweep *result,
                                             const selfcol_sweep_options *opts);

/**
 * Continuous query between two hierarchies' meshes over one step (not the
 * self-collisions of either); in the hits, mesh 0 is first's and mesh 1 is
 * second's. Two hierarchies over the same mesh are SELFCOL_EINVAL.
 * @return as selfcol_hierarchy_self_sweep().
 */
SELFCOL_API int selfcol_hierarchy_sweep(const selfcol_hierarchy *first, const double *first_start,
                                        const selfcol_hierarchy *second, const double *second_start,
                                        selfcol_sweep *result, const selfcol_sweep_options *opts);

/**
 * The colliding pairs of the last query, sorted by (kind, first_mesh, first,
 * second_mesh, second). SELFCOL_SWEEP_EARLIEST: at most one, the pair that
 * gives the collision-free fraction.
 * @param[out] data_out borrowed, valid until the next query or destroy; NULL when empty
 * @param[out] count_out number of hits
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL arguments.
 */
SELFCOL_API int selfcol_sweep_hits(const selfcol_sweep *sweep, const selfcol_sweep_hit **data_out,
                                   size_t *count_out);

/**
 * Counters of the last query (free_fraction 1 and zeros before any).
 * @param[in,out] stats its version field set by the caller
 * @return SELFCOL_OK; SELFCOL_EINVAL for NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_sweep_stats(const selfcol_sweep *sweep, selfcol_sweep_query_stats *stats);

/** Bytes of memory held by the result. @return the count; 0 for NULL. */
SELFCOL_API size_t selfcol_sweep_byte_count(const selfcol_sweep *sweep);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_SWEEP_H */
