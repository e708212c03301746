// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file sequence.h
 * @defgroup sequence Coherent queries over a sequence of frames
 * The same query asked frame after frame, answered from what the previous
 * frames proved.
 *
 * A simulation asks the same query every step, and between steps every
 * vertex moves a fraction of an edge. A `selfcol_sequence` kept by the caller
 * across frames remembers, from the last frame where it rebuilt:
 * - the positions of that frame (the reference);
 * - the *near list*: every primitive pair of the query's kinds within
 *   d + s of each other at the reference (d the detection distance, s the
 *   skin), found by an ordinary query at distance d + s, and for EF every
 *   edge-triangle pair within d + s (derived from the VF and EE pairs: an
 *   edge that does not cross a triangle is nearest to it at one of its ends
 *   or at one of the triangle's edges).
 *
 * On a later frame it bounds how much the surface has *deformed* since the
 * reference, not how far it moved: with D(x) the displacement of point x, a
 * pair of points p, q changes distance by at most |D(p) - D(q)|, which is
 * zero for any rigid translation. The triangles are split into clusters
 * (contiguous runs of the hierarchy's triangle order: compact patches), and
 * for every pair of clusters I, J the query checks that the displacements'
 * boxes allow |D(p) - D(q)| < max(s, gap(I, J) - d), gap being the distance
 * between the clusters' boxes at the reference. When that holds, no pair
 * outside the near list can have come within d: the near list is tested with
 * the ordinary narrow phase (the same functions on the same positions, so
 * the same records bit for bit). When it fails anywhere (a large step, a
 * teleport with rotation, a reset), the list is rebuilt or dropped.
 *
 * **Partial rebuilds.** Where only part of the surface deforms (a sleeve
 * moving, a garment at rest elsewhere), a list usually fails in a few
 * cluster pairs. The sequence then queries again only the cluster pairs
 * whose bound has used half of what they allow, restricted to the
 * hierarchy nodes that can hold their pairs, and keeps the other pairs'
 * near lists: every cluster takes the current positions as its new
 * reference, and a kept pair carries its deformation so far into its next
 * checks (the triangle inequality), so its old proof still holds. When the
 * failing pairs hold more than half of the list (the whole surface
 * deforms), it rebuilds in full. Either way the records are the fresh
 * query's; selfcol_sequence_run_stats.partial_rebuilds counts them.
 *
 * **When to rebuild.** A rebuild costs one ordinary query at distance
 * d + s, about twice a fresh query on folded cloth, so it pays only if the
 * new list lasts a few frames. The check's ratio divided by the frames
 * since the reference measures the deformation per frame: when a new list
 * would last fewer than 3 frames, the sequence answers with a fresh query
 * at d instead (its positions become the next reference), and it rebuilds
 * as soon as the deformation per frame has slowed down. The first frame is
 * fresh. So a sequence costs about a fresh query plus a pass over the
 * vertices while the surface deforms fast (the Bullet ribbon driven at 0.27
 * edges per step deforms 1.5 to 2 skins per step), and a fraction of one
 * while it deforms slowly.
 *
 * **The result is exactly the fresh query's**: the same sorted records
 * (contacts.h) as selfcol_hierarchy_self_collide / _collide with the same
 * options on the same positions, every frame, whatever was reused; the
 * tests hold them equal frame by frame on several sequences, jumps and
 * resets included. The statistics (selfcol_query_stats) count the work done:
 * on a frame answered from the near list, candidate_pairs is the list's
 * length and the traversal counters are 0; on a rebuild, the list's
 * evaluation (the query at d + s is in broad_seconds); on a fresh frame,
 * the fresh query's own. The contact counts are always the fresh query's. Rounding: the check keeps
 * a margin of 1e-6 (d + s), far above the closed forms' documented 1e-9 relative band.
 *
 * Only the exact methods can be answered so: SELFCOL_METHOD_EXACT, _BVH and
 * _EXHAUSTIVE (all three return the same set). SEED and CONE skip contacts by
 * an approximate criterion that no near list can reproduce: a sequence
 * answers them with their own fresh query every frame (last_answer
 * SELFCOL_SEQUENCE_FRESH, last_reason 3) and keeps no reference, so a caller
 * may hand any method to a sequence.
 *
 * The hierarchies need not be refit: the sequence refits them on the frames
 * where it rebuilds or queries afresh and does not read them on the others
 * (so a frame answered from the near list also saves the refit). Changing
 * the meshes, the distance, the kinds, the narrow phase or the method
 * starts afresh (a first frame).
 * @{
 */
#ifndef SELFCOL_SEQUENCE_H
#define SELFCOL_SEQUENCE_H

#include "common.h"
#include "contacts.h"
#include "hierarchy.h"

SELFCOL_BEGIN_DECLS

/** A query kept across frames. Opaque. */
typedef struct selfcol_sequence selfcol_sequence;

/** Options for selfcol_sequence_create(). Initialise with selfcol_sequence_options_init(). */
typedef struct selfcol_sequence_options {
    unsigned int version;        /**< SELFCOL_SEQUENCE_OPTIONS_VERSION */
    selfcol_allocator allocator; /**< all-zero: malloc/free */
    /** The skin s, 0 <= s <= SELFCOL_MESH_MAX_COORDINATE (2^200), in mesh
     *  units: how much farther than d the near list looks. A larger skin
     *  lasts more frames but tests more pairs per frame. 0 (the default): d,
     *  or 0.1 x the mean edge length when d is 0. */
    double skin;
} selfcol_sequence_options;

#define SELFCOL_SEQUENCE_OPTIONS_VERSION 1

/** How a sequence answered a query (selfcol_sequence_run_stats.last_answer). */
typedef enum selfcol_sequence_answer {
    SELFCOL_SEQUENCE_FROM_LIST = 0, /**< from the near list (the check held) */
    SELFCOL_SEQUENCE_REBUILT = 1,   /**< a rebuild (a query at d + s), then the new list */
    SELFCOL_SEQUENCE_FRESH = 2      /**< a fresh query at d: deforming too fast for a list */
} selfcol_sequence_answer;

/** Counters of a sequence since its creation (or last reset). */
typedef struct selfcol_sequence_run_stats {
    unsigned int version;  /**< SELFCOL_SEQUENCE_RUN_STATS_VERSION */
    uint64_t frames;       /**< queries answered */
    uint64_t rebuilds;     /**< of which with a rebuild */
    uint64_t fresh_frames; /**< of which by a fresh query */
    uint32_t last_answer;  /**< selfcol_sequence_answer of the last query */
    /** Why the last query that did not answer from the list did so: 0 first
     *  frame (or after a reset, or after a frame with SEED or CONE), 1
     *  other meshes or options, 2 the deformation since the reference, 3 an
     *  approximate method (SEED, CONE): always fresh. */
    uint32_t last_reason;
    uint64_t near_pairs; /**< primitive pairs in the near list (0 when there is none) */
    double skin;         /**< the skin in use */
    /** The check's ratio at the last query: the largest, over the cluster
     *  pairs, of the deformation bound since the reference to what the pair
     *  allows (a list holds while it is below 1; 0 on a first frame). */
    double deformation_ratio;
    double rebuild_seconds; /**< time of the last rebuild (its query included) */
    /** Of the rebuilds, those that queried again only the cluster pairs whose
     *  bound failed or nearly did, keeping the others' near pairs. */
    uint64_t partial_rebuilds;
} selfcol_sequence_run_stats;

#define SELFCOL_SEQUENCE_RUN_STATS_VERSION 1

/**
 * Writes the defaults into opts.
 * @return SELFCOL_OK; SELFCOL_EINVAL if opts is NULL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_sequence_options_init(selfcol_sequence_options *opts, unsigned int version);

/**
 * Names what selfcol_sequence_create() refuses in opts, if anything: the field, its
 * value and what is accepted (common.h, selfcol_options_problem).
 * @return SELFCOL_OK, SELFCOL_EINVAL or SELFCOL_EVERSION, as selfcol_sequence_create()
 *         for these options; SELFCOL_EINVAL for a NULL problem,
 *         SELFCOL_EVERSION for its version.
 */
SELFCOL_API int selfcol_sequence_options_check(const selfcol_sequence_options *opts,
                                               selfcol_options_problem *problem);

/**
 * Creates an empty sequence (its first query is fresh).
 * @param[out] out the new handle; NULL on failure. Free it with selfcol_sequence_destroy().
 * @param[in] opts options, or NULL for defaults
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL out, skin negative, not finite or
 *         above SELFCOL_MESH_MAX_COORDINATE, half an allocator);
 *         SELFCOL_EVERSION; SELFCOL_ENOMEM.
 */
SELFCOL_API int selfcol_sequence_create(selfcol_sequence **out,
                                        const selfcol_sequence_options *opts);

/** Destroys a sequence. Accepts NULL. */
SELFCOL_API void selfcol_sequence_destroy(selfcol_sequence *sequence);

/** Forgets the reference: the next query is a first frame. Keeps the memory. */
SELFCOL_API void selfcol_sequence_reset(selfcol_sequence *sequence);

/**
 * Self-collision query of the hierarchy's mesh at its current positions,
 * answered as selfcol_hierarchy_self_collide() would (same records, sorted).
 * @param[in,out] sequence the handle kept across frames
 * @param[in,out] hierarchy the mesh's hierarchy; refit here when the
 *                sequence rebuilds or queries afresh (it need not be
 *                refit by the caller)
 * @param[out] contacts receives the records and the statistics
 * @param[in] opts query options (NULL: defaults); any method (SEED and CONE
 *                are answered by a fresh query every frame)
 * @return SELFCOL_OK; SELFCOL_EINVAL (NULL arguments, bad options);
 *         SELFCOL_EVERSION; SELFCOL_EMISMATCH (the
 *         hierarchy's mesh is not the one it was built on); SELFCOL_ENOMEM
 *         (contacts then empty; the next query is a first frame).
 */
SELFCOL_API int selfcol_sequence_self_collide(selfcol_sequence *sequence,
                                              selfcol_hierarchy *hierarchy,
                                              selfcol_contacts *contacts,
                                              const selfcol_query_options *opts);

/**
 * Collision query between two meshes, answered as selfcol_hierarchy_collide()
 * would. As selfcol_sequence_self_collide(), for two hierarchies of
 * different meshes.
 */
SELFCOL_API int selfcol_sequence_collide(selfcol_sequence *sequence, selfcol_hierarchy *first,
                                         selfcol_hierarchy *second, selfcol_contacts *contacts,
                                         const selfcol_query_options *opts);

/**
 * Counters of the sequence.
 * @param[in,out] stats its version field set by the caller
 * @return SELFCOL_OK; SELFCOL_EINVAL; SELFCOL_EVERSION.
 */
SELFCOL_API int selfcol_sequence_stats(const selfcol_sequence *sequence,
                                       selfcol_sequence_run_stats *stats);

/** Bytes held by the sequence: reference positions, clusters and the near
 *  list (a rebuild's query at distance d + s runs in the caller's contact
 *  set, whose records it then replaces, so that set grows to the reach
 *  set's size; a partial rebuild also passes its new pairs through that
 *  set's sort scratch). 0 for NULL. */
SELFCOL_API size_t selfcol_sequence_byte_count(const selfcol_sequence *sequence);

SELFCOL_END_DECLS

/** @} */

#endif // SELFCOL_SEQUENCE_H
