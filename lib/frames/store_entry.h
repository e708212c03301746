// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact store's insides, shared by its three files: store.c (the
// handle, the update's stages and the reads), store_sides.c (each
// contact's side and geometry) and store_regions.c (the neighbours, the
// regions and the vote). The method: store.c's opening comment.
#ifndef SELFCOL_STORE_ENTRY_H
#define SELFCOL_STORE_ENTRY_H

#include <selfcol/store.h>

#include "base/parallel.h"
#include "mesh/mesh.h"
#include "narrow/narrow.h"

// Entries are indexed by uint32_t, and the neighbour search keeps five bits
// in the top of an entry's index (link_neighbours): PAIR_FIRST_IS_LO and
// the entry's side codes at the pair's lo and hi ends (link_code).
#define SELFCOL_STORE_MAX_ENTRIES ((1u << 27) - 1u)
#define PAIR_FIRST_IS_LO (1u << 31)
#define PAIR_LO_SHIFT 29
#define PAIR_HI_SHIFT 27
#define PAIR_INDEX ((1u << 27) - 1u)

// One held contact. Its vertices are its elements' (mesh topology), its
// geometry is recomputed on demand: nothing here is a double.
typedef struct store_entry {
    uint32_t first, second; // as in selfcol_contact
    uint32_t age, missed;   // as in selfcol_store_contact
    uint32_t region;        // of the last update
    uint8_t kind;           // selfcol_contact_kind
    uint8_t meshes;         // first_mesh | second_mesh << 1
    uint8_t flags;          // selfcol_store_contact_flag bits (all below 1 << 8)
    uint8_t sides;          // (side + 1) | (right_side + 1) << 2
} store_entry;

struct selfcol_store {
    selfcol_allocator allocator;
    // The running update's threads and who runs them: its context's
    // (selfcol_context_store_update), or 1 and NULL without one.
    unsigned threads;
    const selfcol_executor *executor;
    unsigned bucket_threads; // the thread count bucket_offset is sized for
    uint32_t remnance;
    int consistency;
    int orientation[2];            // per mesh slot: 0 none, +1 / -1 (store.h)
    const selfcol_mesh *meshes[2]; // meshes[0] NULL until the first update after create or clear
    selfcol_mesh_identity identity[2]; // of meshes[], from the same update
    uint64_t positions_version[2];     // of meshes[] at the last update (copies check them)
    // selfcol_store_update_swept: the meshes' positions at the step's start,
    // during that update only (NULL otherwise); selfcol_store__update_path
    // adds the positions at the previous update (the path then runs from
    // these through step_start to the current positions; NULL: one segment).
    const double *step_start[2];
    const double *step_before[2];

    store_entry *entries, *spare; // held entries; the merge's destination
    size_t count, capacity;       // capacity of every per-entry array

    // Per entry, for one update: the grouping union-find, the voting
    // union-find with parity, and the entry's link code (link_code).
    uint32_t *group_parent, *vote_parent;
    int8_t *vote_parity;
    uint16_t *link_code;

    selfcol_store_region *regions; // the last update's, grown apart from the entries
    size_t region_count, region_capacity;

    // The neighbour search (link_neighbours): per vertex-pair occurrence its
    // pair's hi end and its entry (with the PAIR_ bits); pair_capacity
    // occurrences. Per chunk of the entries (at most `threads`: chunk c's
    // array at bucket_offset + c * bucket_count) and per bucket (lo end's
    // mesh and vertex, hi end's mesh): the count of the chunk's occurrences
    // in the bucket, taken during the merge, then where the chunk writes
    // its next one (sort_pairs). Per mesh slot and vertex, the stamp and
    // first position of the bucket pass.
    uint32_t *pair_hi, *pair_entry;
    size_t pair_capacity;
    uint32_t *bucket_offset;
    size_t bucket_count; // per chunk; threads * bucket_count offsets
    uint32_t *hi_stamp[2], *hi_first[2];
    size_t hi_count[2];
    uint32_t bucket_stamp;

    // Per mesh slot: the surface normal at each vertex (vertex_normal), kept
    // for one update: valid where normal_stamp equals stamp (even), being
    // written by one thread where it is stamp + 1. Sized to the mesh's
    // vertices at its first update (a store's meshes are fixed until
    // selfcol_store_clear), so no update clears them.
    float *normals[2];
    uint32_t *normal_stamp[2];
    size_t normal_count[2];
    uint32_t stamp;

    selfcol_store_update_stats stats;
};
// ---------------------------------------------------------------------------
// Entry fields

static inline uint32_t first_mesh(const store_entry *e) {
    return e->meshes & 1u;
}

static inline uint32_t second_mesh(const store_entry *e) {
    return (uint32_t)e->meshes >> 1;
}

static inline int side_of(const store_entry *e) {
    return (int)(e->sides & 3u) - 1;
}

static inline int right_side_of(const store_entry *e) {
    return (int)((e->sides >> 2) & 3u) - 1;
}

static inline void set_sides(store_entry *e, int side, int right_side) {
    e->sides = (uint8_t)((side + 1) | (right_side + 1) << 2);
}

// The vertices of an entry's elements, from its meshes' topology (what the
// query's record held: the update checks records against it).
static inline void entry_vertices(const selfcol_store *s, const store_entry *e, uint32_t a[2],
                                  uint32_t b[3]) {
    const selfcol_mesh *mf = s->meshes[first_mesh(e)], *ms = s->meshes[second_mesh(e)];
    if (e->kind == SELFCOL_CONTACT_VF) {
        a[0] = a[1] = e->first;
    } else {
        a[0] = mf->edges[2 * (size_t)e->first];
        a[1] = mf->edges[2 * (size_t)e->first + 1];
    }
    if (e->kind == SELFCOL_CONTACT_EE) {
        b[0] = ms->edges[2 * (size_t)e->second];
        b[1] = ms->edges[2 * (size_t)e->second + 1];
        b[2] = SELFCOL_INVALID_INDEX;
    } else {
        const uint32_t *t = ms->triangles + 3 * (size_t)e->second;
        b[0] = t[0];
        b[1] = t[1];
        b[2] = t[2];
    }
}

static inline size_t buckets_of(const selfcol_mesh *const meshes[2]) {
    const size_t n0 = meshes[0]->vertex_count;
    return meshes[1] != NULL ? 2 * n0 + meshes[1]->vertex_count : n0;
}

// ---------------------------------------------------------------------------
// store_sides.c

// Distance, weights and direction of an entry at the current positions (a
// VF or EE record bit for bit as a closed-form query gives it).
void selfcol_store__geometry(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                             const uint32_t b[3], selfcol_narrow_result *r);

// Adds triangle t's (unnormalised) normal to n.
void selfcol_store__add_triangle_normal(const selfcol_mesh *m, uint32_t t, double n[3]);

// An entry's side at the current positions and its right side: kept,
// flipped or set for the first time (the update's step 1, per entry).
void selfcol_store__track_side(selfcol_store *s, store_entry *e, const uint32_t a[2],
                               const uint32_t b[3], selfcol_store_update_stats *st);

// ---------------------------------------------------------------------------
// store_regions.c

// The grouping union-find's union, safe with other threads uniting at once.
void selfcol_store__group_unite_shared(uint32_t *parent, uint32_t x, uint32_t y);

// Vertex pairs an entry has: |first's vertices| x |second's|.
int selfcol_store__pairs_of_kind(uint32_t kind);

// What an entry's links compare, read once from its direction (16 bits).
uint16_t selfcol_store__link_code(selfcol_store *s, const store_entry *e, const uint32_t a[2],
                                  const uint32_t b[3], const double direction[3]);

// Counts an entry's vertex pairs into their buckets (the counts of its chunk).
void selfcol_store__count_pairs(const selfcol_store *s, uint32_t *count, const store_entry *e,
                                const uint32_t a[2], const uint32_t b[3]);

// The chunks' counts become each chunk's first position in each bucket.
void selfcol_store__bucket_starts(selfcol_store *s, size_t chunks);

// The counting sort's scatter of entries lo .. hi - 1's pairs (chunk c).
void selfcol_store__sort_pairs(selfcol_store *s, size_t c, size_t lo, size_t hi_index);

// Links the entries sharing a vertex pair (regions; voting groups).
void selfcol_store__link_neighbours(selfcol_store *s, const uint32_t *bucket_end, int group_here);

// Tallies the voting groups and numbers the regions; returns their count.
size_t selfcol_store__tally_and_label(selfcol_store *s, selfcol_store_update_stats *st);

// Each voting group's majority right side, imposed; the region records.
void selfcol_store__impose(selfcol_store *s, size_t regions, selfcol_store_update_stats *st);

#endif // SELFCOL_STORE_ENTRY_H
