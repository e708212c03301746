// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The coherent queries' shared state (sequence.c and its companions): the
// constants of the method, the near pair, the handle, and the functions one
// file of the sequence calls in another. Private to lib/frames.
#ifndef SELFCOL_SEQUENCE_STATE_H
#define SELFCOL_SEQUENCE_STATE_H

#include <selfcol/sequence.h>

#include "base/alloc.h"
#include "base/workspace.h"
#include "query/query.h"

#include <stddef.h>
#include <stdint.h>

// Clusters per mesh: contiguous runs of the hierarchy's triangle order (its
// depth-first leaf order keeps them compact). The check costs the clusters'
// displacement boxes (one pass over the vertices) and CLUSTERS^2 / 2 box
// pairs.
#define CLUSTERS 128 // at most 256: a cluster's index is a byte (near_pair.tag)

// Relative margin of the check (the proof above).
#define MARGIN 1e-6

// A rebuild pays when the new list is expected to last this many frames
// (run()'s policy).
#define REBUILD_LIFE 3.0

// A partial rebuild queries again the cluster pairs whose spread has used
// this share of what they allow (the pair that failed and those about to).
#define PARTIAL_SHARE 0.5

// ... unless those pairs hold more than this share of the near list: then
// the surface deforms all over, and a full rebuild costs less (no filter,
// no merge) and leaves no carries (crumpling 20k sheet, 40 frames: 43.5
// against 42.2 ms a frame with partial rebuilds only).
#define PARTIAL_MOST 0.5

// Sets of clusters as bits: words per set.
#define MASK_WORDS ((CLUSTERS + 63) / 64)

// The computed spread and gap err by a few ulps of their size: 1e-12
// relative covers it many times over.
#define ROUND (1.0 + 1e-12)

// What the sequence holds: nothing; a reference (positions and clusters)
// from a fresh frame; or a reference and its near list.
enum { STATE_NONE = 0, STATE_TRACKING = 1, STATE_LIST = 2 };

// One pair of the near list: kind and meshes in `tag` (kind << 2 |
// first_mesh << 1 | second_mesh, then the clusters of the first and second
// primitive in bits 8-15 and 16-23), the primitives as in selfcol_contact,
// and a lower bound of their distance at the reference (EF: of the edge's
// distance to the triangle, 0 when it crossed). A pair whose bound, less
// the spread of its two clusters' displacements, still exceeds d (0 for
// EF) cannot be a contact now (the proof above, for this one pair): it is
// skipped without a closed form.
typedef struct near_pair {
    uint32_t tag;
    uint32_t first, second;
    float near;
} near_pair;

#define TAG_KIND(tag) ((tag) >> 2 & 3u)
#define TAG_FIRST_MESH(tag) ((tag) >> 1 & 1u)
#define TAG_SECOND_MESH(tag) ((tag)&1u)
#define TAG_FIRST_CLUSTER(tag) ((tag) >> 8 & 0xffu)
#define TAG_SECOND_CLUSTER(tag) ((tag) >> 16 & 0xffu)

// A growable array: bytes held.
typedef struct buffer {
    void *data;
    size_t bytes;
} buffer;

typedef struct cluster_set {
    int ready; // the clusters of the current setup are built
    unsigned count;
    buffer of_triangle; // uint8_t per triangle: its cluster
    buffer offsets;     // count + 1 uint32_t into vertices
    buffer vertices;    // uint32_t, each cluster's vertex set
    buffer ref_box;     // 6 doubles per cluster: lo, hi of the reference positions
    buffer disp_box;    // 6 doubles per cluster: lo, hi of the displacements now
} cluster_set;

struct selfcol_sequence {
    selfcol_allocator allocator;
    double skin_option; // 0: automatic
    // The context of the running call (selfcol_context_sequence_*), NULL
    // between calls and for the calls without one.
    selfcol_context *context;

    // What the reference and near list were taken for (valid unless state
    // is STATE_NONE).
    int state;
    uint64_t frames_since_reference;
    int self;
    selfcol_mesh_identity identity[2];
    double distance, skin, reach;
    uint32_t kinds, narrow, method;

    buffer reference[2]; // 3 V doubles per mesh
    cluster_set clusters[2];
    buffer pairs; // near_pair, in record order
    // Per cluster pair (first mesh's x second's; both orders for a self
    // query): its spread since its reference plus its carry, rounded up; its
    // carry from the references before (partial rebuilds), rounded up; what
    // it allows, from the gap at its own reference, rounded down (0: nothing).
    buffer spread, carry, allowed;
    size_t pair_count;
    buffer masks; // uint64_t: a partial rebuild's node masks (partial_filter)
    // A partial rebuild's choice: per cluster of the first mesh, its
    // re-queried partners in the second (partial_filter).
    uint64_t partners[CLUSTERS * MASK_WORDS];
    // The last query was a partial rebuild (selfcol_sequence__check_partial).
    int partial_checkable;
    buffer stamps; // rebuild: a uint32_t per vertex (the clusters' vertex sets)

    selfcol_sequence_run_stats stats;
};

// What partial_rebuild returns when it declines (PARTIAL_MOST): nothing
// was changed, and the caller rebuilds in full.
#define PARTIAL_DECLINED 1

// Buffers (sequence.c): at least `bytes` in b, growing geometrically, the
// first `keep` bytes of the old content copied; reserve keeps nothing;
// release frees.
int selfcol_sequence__reserve_keep(const selfcol_allocator *a, buffer *b, size_t bytes,
                                   size_t keep);
int selfcol_sequence__reserve(const selfcol_allocator *a, buffer *b, size_t bytes);
void selfcol_sequence__release(const selfcol_allocator *a, buffer *b);

// Queries (sequence.c).
float selfcol_sequence__float_allowance(const selfcol_sequence *s, unsigned i, unsigned j);
void selfcol_sequence__tag_clusters(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                                    near_pair *list, size_t count);
// The context of the running call: the caller's (selfcol_context_sequence_*)
// or, without one, scratch's own (one thread). NULL without memory.
selfcol_context *selfcol_sequence__context(const selfcol_sequence *s, selfcol_contacts *scratch);
selfcol_workspace *selfcol_sequence__scratch_work(const selfcol_sequence *s,
                                                  selfcol_contacts *scratch);
int selfcol_sequence__query(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                            selfcol_contacts *out, const selfcol_query_options *o);
int selfcol_sequence__refit_stale(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                                  uint32_t method);
int selfcol_sequence__rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                              const selfcol_query_options *o, selfcol_contacts *scratch);

// Clusters and the check (sequence_clusters.c).
int selfcol_sequence__build_clusters(selfcol_sequence *s, int m, const selfcol_hierarchy *h,
                                     uint32_t *stamps);
double selfcol_sequence__allowance(const selfcol_sequence *s, unsigned i, unsigned j);
double selfcol_sequence__deformation_ratio(selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                                           double stop_above, double *since);

// The near list and its evaluation (sequence_list.c).
float selfcol_sequence__float_below(double x);
int selfcol_sequence__build_list(selfcol_sequence *s, buffer *into, size_t offset,
                                 size_t *pair_count, selfcol_hierarchy *const h[2],
                                 const selfcol_contact *rec, size_t n, selfcol_workspace *work);
int selfcol_sequence__evaluate(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                               const selfcol_query_options *o, selfcol_contacts *contacts);

// Partial rebuilds (sequence_partial.c).
int selfcol_sequence__partial_rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                                      const selfcol_query_options *o, selfcol_contacts *scratch);

#endif // SELFCOL_SEQUENCE_STATE_H
