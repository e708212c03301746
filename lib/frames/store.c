// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The persistent contact store (include/selfcol/store.h): section 3 of
// Volino & Magnenat Thalmann (1995). One update is linear in the contacts:
//  1. a merge of the held entries and the query's records, both sorted by
//     key (kind, first_mesh, first, second_mesh, second): kept, new,
//     remnant or dropped; the side of every VF/EE entry is the exact sign of
//     orient3d;
//  2. regions: each entry has the unordered pairs {u, w} of a vertex u of
//     its first element and a vertex w of its second (at most 6); entries
//     sharing a pair are neighbours. A grouping union-find over all entries
//     gives the regions; a second one, with parity, over VF/EE links whose
//     sides read clearly through the surface normals, gives the voting
//     groups (seed 3.2.1's labelling, without its recursion);
//  3. the vote per group and the region records.
// An entry holds its key, counters and sides only (24 bytes): its vertices
// come from the meshes' topology, and its geometry (distance, weights,
// direction) is computed when the caller copies the records
// (selfcol_store_copy_contacts), from the positions the update saw. What
// the links compare is read from each entry's direction once, into 16 bits
// (link_code), and the vote's tallies reuse the neighbour search's arrays.
// Every array is kept and grown: a steady state allocates nothing.
// With threads (selfcol_store_options.threads), step 1 runs in chunks of
// keys (each merging its ranges of held entries and records into a place
// counted beforehand by a dry run), the vertex pairs are sorted in chunks
// of entries with per-chunk bucket counts (both stable), and the grouping
// union-find runs on threads (its roots do not depend on the link order);
// the voting links, whose order decides conflicting cycles, and the vote
// stay in one thread. The store is the same for every thread count.
#include <selfcol/hierarchy.h>
#include <selfcol/store.h>

#include "base/alloc.h"
#include "base/core.h"
#include "base/parallel.h"
#include "base/predicates.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "frames/store.h"
#include "mesh/mesh.h"
#include "narrow/narrow.h"
#include "narrow/narrow_sweep.h"
#include "query/contacts.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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
    unsigned threads; // of an update (selfcol_store_options)
    uint32_t remnance;
    int consistency;
    int orientation[2];            // per mesh slot: 0 none, +1 / -1 (store.h)
    const selfcol_mesh *meshes[2]; // meshes[0] NULL until the first update after create or clear
    selfcol_mesh_identity identity[2]; // of meshes[], from the same update
    uint64_t positions_version[2];     // of meshes[] at the last update (copies check them)
    // selfcol_store_update_swept: the meshes' positions at the step's start,
    // during that update only (NULL otherwise).
    const double *step_start[2];

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

static uint32_t first_mesh(const store_entry *e) {
    return e->meshes & 1u;
}

static uint32_t second_mesh(const store_entry *e) {
    return (uint32_t)e->meshes >> 1;
}

static int side_of(const store_entry *e) {
    return (int)(e->sides & 3u) - 1;
}

static int right_side_of(const store_entry *e) {
    return (int)((e->sides >> 2) & 3u) - 1;
}

static void set_sides(store_entry *e, int side, int right_side) {
    e->sides = (uint8_t)((side + 1) | (right_side + 1) << 2);
}

// The vertices of an entry's elements, from its meshes' topology (what the
// query's record held: the update checks records against it).
static void entry_vertices(const selfcol_store *s, const store_entry *e, uint32_t a[2],
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

// ---------------------------------------------------------------------------
// Creation and memory

int selfcol_store_options_init(selfcol_store_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_STORE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    // A version 1 caller's struct ends before `threads`: write no further.
    memset(opts, 0, version >= 2 ? sizeof *opts : offsetof(selfcol_store_options, threads));
    opts->version = version;
    opts->remnance_frames = SELFCOL_STORE_DEFAULT_REMNANCE;
    opts->consistency = 1;
    if (version >= 2)
        opts->threads = 1;
    return SELFCOL_OK;
}

int selfcol_store__options(selfcol_store_options *out, const selfcol_store_options *opts) {
    SELFCOL_CHECK_VERSION(opts, SELFCOL_STORE_OPTIONS_VERSION);
    selfcol_store_options_init(out, SELFCOL_STORE_OPTIONS_VERSION);
    if (opts != NULL) {
        // Version 1 callers' structs end before `threads` (read as 1).
        memcpy(out, opts,
               opts->version >= 2 ? sizeof *out : offsetof(selfcol_store_options, threads));
    }
    out->version = SELFCOL_STORE_OPTIONS_VERSION;
    SELFCOL_CHECK(selfcol_alloc__valid(&out->allocator));
    SELFCOL_CHECK(out->consistency == 0 || out->consistency == 1);
    SELFCOL_CHECK(out->first_orientation >= -1 && out->first_orientation <= 1);
    SELFCOL_CHECK(out->second_orientation >= -1 && out->second_orientation <= 1);
    SELFCOL_CHECK(out->threads >= 1 && out->threads <= SELFCOL_MAX_THREADS);
    return SELFCOL_OK;
}

int selfcol_store_create(selfcol_store **out, const selfcol_store_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    selfcol_store_options o;
    const int checked = selfcol_store__options(&o, opts);
    if (checked != SELFCOL_OK)
        return checked;
    selfcol_store *s = selfcol_alloc__raw(&o.allocator, sizeof *s);
    if (s == NULL)
        return SELFCOL_ENOMEM;
    memset(s, 0, sizeof *s);
    s->allocator = o.allocator;
    s->remnance = o.remnance_frames;
    s->consistency = o.consistency;
    s->orientation[0] = o.first_orientation;
    s->orientation[1] = o.second_orientation;
    s->threads = o.threads;
    s->stats.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
    *out = s;
    return SELFCOL_OK;
}

static void free_entry_arrays(selfcol_store *s) {
    const selfcol_allocator *al = &s->allocator;
    const size_t n = s->capacity;
    selfcol_alloc__free_array(al, s->entries, n, sizeof *s->entries);
    selfcol_alloc__free_array(al, s->spare, n, sizeof *s->spare);
    selfcol_alloc__free_array(al, s->group_parent, n, sizeof *s->group_parent);
    selfcol_alloc__free_array(al, s->vote_parent, n, sizeof *s->vote_parent);
    selfcol_alloc__free_array(al, s->vote_parity, n, sizeof *s->vote_parity);
    selfcol_alloc__free_array(al, s->link_code, n, sizeof *s->link_code);
}

static void free_pair_arrays(selfcol_store *s) {
    const selfcol_allocator *al = &s->allocator;
    selfcol_alloc__free_array(al, s->pair_hi, s->pair_capacity, sizeof *s->pair_hi);
    selfcol_alloc__free_array(al, s->pair_entry, s->pair_capacity, sizeof *s->pair_entry);
    s->pair_hi = NULL;
    s->pair_entry = NULL;
    s->pair_capacity = 0;
}

static void free_mesh_arrays(selfcol_store *s) {
    const selfcol_allocator *al = &s->allocator;
    for (int k = 0; k < 2; ++k) {
        selfcol_alloc__free_array(al, s->normals[k], 3 * s->normal_count[k], sizeof *s->normals[k]);
        selfcol_alloc__free_array(al, s->normal_stamp[k], s->normal_count[k],
                                  sizeof *s->normal_stamp[k]);
        selfcol_alloc__free_array(al, s->hi_stamp[k], s->hi_count[k], sizeof *s->hi_stamp[k]);
        selfcol_alloc__free_array(al, s->hi_first[k], s->hi_count[k], sizeof *s->hi_first[k]);
    }
    selfcol_alloc__free_array(al, s->bucket_offset, s->threads * s->bucket_count,
                              sizeof *s->bucket_offset);
}

// Grown capacities: the need plus a quarter, so that a sequence whose
// contact count creeps up reallocates rarely (and a steady state never),
// without holding half as much again as it uses.
static size_t grown_capacity(size_t need) {
    return need + need / 4 + 64;
}

void selfcol_store_destroy(selfcol_store *store) {
    if (store == NULL)
        return;
    selfcol_allocator al = store->allocator;
    free_entry_arrays(store);
    free_pair_arrays(store);
    free_mesh_arrays(store);
    selfcol_alloc__free_array(&al, store->regions, store->region_capacity, sizeof *store->regions);
    selfcol_alloc__free(&al, store, sizeof *store);
}

void selfcol_store_clear(selfcol_store *store) {
    if (store == NULL)
        return;
    store->count = 0;
    store->region_count = 0;
    store->meshes[0] = store->meshes[1] = NULL;
    memset(&store->stats, 0, sizeof store->stats);
    store->stats.version = SELFCOL_STORE_UPDATE_STATS_VERSION;
}

// Grows every per-entry array to hold n entries (the held ones are kept).
static int reserve_entries(selfcol_store *s, size_t n) {
    if (n <= s->capacity)
        return SELFCOL_OK;
    if (n > SELFCOL_STORE_MAX_ENTRIES)
        return SELFCOL_ERANGE;
    size_t cap = grown_capacity(n);
    if (cap > SELFCOL_STORE_MAX_ENTRIES)
        cap = SELFCOL_STORE_MAX_ENTRIES;
    const selfcol_allocator *al = &s->allocator;
    selfcol_store grown = *s;
    grown.capacity = cap;
    grown.entries = selfcol_alloc__array(al, cap, sizeof *grown.entries);
    grown.spare = selfcol_alloc__array(al, cap, sizeof *grown.spare);
    grown.group_parent = selfcol_alloc__array(al, cap, sizeof *grown.group_parent);
    grown.vote_parent = selfcol_alloc__array(al, cap, sizeof *grown.vote_parent);
    grown.vote_parity = selfcol_alloc__array(al, cap, sizeof *grown.vote_parity);
    grown.link_code = selfcol_alloc__array(al, cap, sizeof *grown.link_code);
    if (grown.entries == NULL || grown.spare == NULL || grown.group_parent == NULL ||
        grown.vote_parent == NULL || grown.vote_parity == NULL || grown.link_code == NULL) {
        free_entry_arrays(&grown);
        return SELFCOL_ENOMEM;
    }
    if (s->count > 0)
        memcpy(grown.entries, s->entries, s->count * sizeof *s->entries);
    free_entry_arrays(s);
    s->entries = grown.entries;
    s->spare = grown.spare;
    s->group_parent = grown.group_parent;
    s->vote_parent = grown.vote_parent;
    s->vote_parity = grown.vote_parity;
    s->link_code = grown.link_code;
    s->capacity = cap;
    return SELFCOL_OK;
}

// The neighbour search's arrays for `keys` vertex-pair occurrences.
static int reserve_pairs(selfcol_store *s, size_t keys) {
    if (keys <= s->pair_capacity)
        return SELFCOL_OK;
    const size_t cap = grown_capacity(keys);
    const selfcol_allocator *al = &s->allocator;
    uint32_t *hi = selfcol_alloc__array(al, cap, sizeof *hi);
    uint32_t *entry = selfcol_alloc__array(al, cap, sizeof *entry);
    if (hi == NULL || entry == NULL) {
        selfcol_alloc__free_array(al, hi, cap, sizeof *hi);
        selfcol_alloc__free_array(al, entry, cap, sizeof *entry);
        return SELFCOL_ENOMEM;
    }
    free_pair_arrays(s);
    s->pair_hi = hi;
    s->pair_entry = entry;
    s->pair_capacity = cap;
    return SELFCOL_OK;
}

// Buckets of the neighbour search: one per (lo end's mesh, lo vertex, hi
// end's mesh) where lo orders before hi by (mesh, vertex): (0, v, 0), then
// (0, v, 1) and (1, v, 1) when there is a second mesh.
static size_t buckets_of(const selfcol_mesh *const meshes[2]) {
    const size_t n0 = meshes[0]->vertex_count;
    return meshes[1] != NULL ? 2 * n0 + meshes[1]->vertex_count : n0;
}

// The arrays per mesh vertex: normal caches and the neighbour search's
// buckets and stamps (grown only; every stamp 0 = nothing cached).
static int reserve_mesh_arrays(selfcol_store *s, const selfcol_mesh *const meshes[2]) {
    const selfcol_allocator *al = &s->allocator;
    for (int k = 0; k < 2; ++k) {
        const size_t n = meshes[k] != NULL ? meshes[k]->vertex_count : 0;
        if (n <= s->normal_count[k])
            continue;
        float *normals = selfcol_alloc__array(al, 3 * n, sizeof *normals);
        uint32_t *stamps = selfcol_alloc__array(al, n, sizeof *stamps);
        uint32_t *hi_stamp = selfcol_alloc__array(al, n, sizeof *hi_stamp);
        uint32_t *hi_first = selfcol_alloc__array(al, n, sizeof *hi_first);
        if (normals == NULL || stamps == NULL || hi_stamp == NULL || hi_first == NULL) {
            selfcol_alloc__free_array(al, normals, 3 * n, sizeof *normals);
            selfcol_alloc__free_array(al, stamps, n, sizeof *stamps);
            selfcol_alloc__free_array(al, hi_stamp, n, sizeof *hi_stamp);
            selfcol_alloc__free_array(al, hi_first, n, sizeof *hi_first);
            return SELFCOL_ENOMEM;
        }
        memset(stamps, 0, n * sizeof *stamps);
        memset(hi_stamp, 0, n * sizeof *hi_stamp);
        selfcol_alloc__free_array(al, s->normals[k], 3 * s->normal_count[k], sizeof *s->normals[k]);
        selfcol_alloc__free_array(al, s->normal_stamp[k], s->normal_count[k],
                                  sizeof *s->normal_stamp[k]);
        selfcol_alloc__free_array(al, s->hi_stamp[k], s->hi_count[k], sizeof *s->hi_stamp[k]);
        selfcol_alloc__free_array(al, s->hi_first[k], s->hi_count[k], sizeof *s->hi_first[k]);
        s->normals[k] = normals;
        s->normal_stamp[k] = stamps;
        s->normal_count[k] = n;
        s->hi_stamp[k] = hi_stamp;
        s->hi_first[k] = hi_first;
        s->hi_count[k] = n;
    }
    const size_t buckets = buckets_of(meshes);
    if (buckets > s->bucket_count || s->bucket_offset == NULL) {
        uint32_t *offset = selfcol_alloc__array(al, s->threads * buckets, sizeof *offset);
        if (offset == NULL)
            return SELFCOL_ENOMEM;
        selfcol_alloc__free_array(al, s->bucket_offset, s->threads * s->bucket_count,
                                  sizeof *s->bucket_offset);
        s->bucket_offset = offset;
        s->bucket_count = buckets;
    }
    return SELFCOL_OK;
}

// The region records for n regions (grown only, apart from the entries:
// regions are a few per thousand contacts).
static int reserve_regions(selfcol_store *s, size_t n) {
    if (n <= s->region_capacity)
        return SELFCOL_OK;
    const size_t cap = grown_capacity(n);
    selfcol_store_region *r = selfcol_alloc__array(&s->allocator, cap, sizeof *r);
    if (r == NULL)
        return SELFCOL_ENOMEM;
    selfcol_alloc__free_array(&s->allocator, s->regions, s->region_capacity, sizeof *s->regions);
    s->regions = r;
    s->region_capacity = cap;
    return SELFCOL_OK;
}

// ---------------------------------------------------------------------------
// Keys and validation

static int key_compare(uint32_t ka, uint32_t fma, uint32_t fa, uint32_t sma, uint32_t sa,
                       uint32_t kb, uint32_t fmb, uint32_t fb, uint32_t smb, uint32_t sb) {
    const uint32_t x[5] = {ka, fma, fa, sma, sa}, y[5] = {kb, fmb, fb, smb, sb};
    for (int i = 0; i < 5; ++i)
        if (x[i] != y[i])
            return x[i] < y[i] ? -1 : 1;
    return 0;
}

static int record_compare(const selfcol_contact *x, const selfcol_contact *y) {
    return key_compare(x->kind, x->first_mesh, x->first, x->second_mesh, x->second, y->kind,
                       y->first_mesh, y->first, y->second_mesh, y->second);
}

static int entry_record_compare(const store_entry *e, const selfcol_contact *r) {
    return key_compare(e->kind, first_mesh(e), e->first, second_mesh(e), e->second, r->kind,
                       r->first_mesh, r->first, r->second_mesh, r->second);
}

// 1 when the record's primitives exist in the meshes and its vertices are
// theirs (so that an entry's vertices can be read back from the topology),
// and a two-mesh store's record pairs the two meshes (a two-mesh query finds
// no self-contacts: a record within one mesh is another query's).
static int record_matches(const selfcol_mesh *const meshes[2], const selfcol_contact *r) {
    if (r->kind > SELFCOL_CONTACT_EF || r->first_mesh > 1 || r->second_mesh > 1)
        return 0;
    if (meshes[1] != NULL && r->first_mesh == r->second_mesh)
        return 0;
    const selfcol_mesh *ma = meshes[r->first_mesh], *mb = meshes[r->second_mesh];
    if (ma == NULL || mb == NULL)
        return 0;
    if (r->kind == SELFCOL_CONTACT_VF) {
        if (r->first >= ma->vertex_count || r->a[0] != r->first || r->a[1] != r->first)
            return 0;
    } else {
        if (r->first >= ma->edge_count || r->a[0] != ma->edges[2 * (size_t)r->first] ||
            r->a[1] != ma->edges[2 * (size_t)r->first + 1])
            return 0;
    }
    if (r->kind == SELFCOL_CONTACT_EE) {
        if (r->second >= mb->edge_count || r->b[0] != mb->edges[2 * (size_t)r->second] ||
            r->b[1] != mb->edges[2 * (size_t)r->second + 1])
            return 0;
    } else {
        if (r->second >= mb->triangle_count)
            return 0;
        for (int k = 0; k < 3; ++k)
            if (r->b[k] != mb->triangles[3 * (size_t)r->second + (size_t)k])
                return 0;
    }
    return 1;
}

// ---------------------------------------------------------------------------
// Geometry

static const double *vertex_of(const selfcol_store *s, uint32_t mesh, uint32_t v) {
    return selfcol_mesh__position(s->meshes[mesh], v);
}

// Exact side of the first element relative to the second's reference
// direction (store.h): VF orient3d(b0, b1, b2, v), EE orient3d(a0, a1, b0, b1).
static int exact_side(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                      const uint32_t b[3]) {
    const uint32_t fm = first_mesh(e), sm = second_mesh(e);
    if (e->kind == SELFCOL_CONTACT_VF)
        return selfcol_predicates__orient3d(vertex_of(s, sm, b[0]), vertex_of(s, sm, b[1]),
                                            vertex_of(s, sm, b[2]), vertex_of(s, fm, a[0]));
    return selfcol_predicates__orient3d(vertex_of(s, fm, a[0]), vertex_of(s, fm, a[1]),
                                        vertex_of(s, sm, b[0]), vertex_of(s, sm, b[1]));
}

// Distance, weights and direction of an entry at the current positions, by
// the closed-form narrow phase with the query's arguments (pairs.c): a VF or
// EE record bit for bit as a closed-form query gives it; an EF one as
// selfcol_narrow__ef gives it (all zero if it finds no crossing, which only
// a libccd query can have reported).
static void geometry(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                     const uint32_t b[3], selfcol_narrow_result *r) {
    const uint32_t fm = first_mesh(e), sm = second_mesh(e);
    if (e->kind == SELFCOL_CONTACT_VF) {
        selfcol_narrow__vf(vertex_of(s, fm, a[0]), vertex_of(s, sm, b[0]), vertex_of(s, sm, b[1]),
                           vertex_of(s, sm, b[2]), r);
    } else if (e->kind == SELFCOL_CONTACT_EE) {
        selfcol_narrow__ee(vertex_of(s, fm, a[0]), vertex_of(s, fm, a[1]), vertex_of(s, sm, b[0]),
                           vertex_of(s, sm, b[1]), r);
    } else if (!selfcol_narrow__ef(vertex_of(s, fm, a[0]), vertex_of(s, fm, a[1]),
                                   vertex_of(s, sm, b[0]), vertex_of(s, sm, b[1]),
                                   vertex_of(s, sm, b[2]), r)) {
        memset(r, 0, sizeof *r);
    }
}

// ---------------------------------------------------------------------------
// Oriented surfaces (store.h: "Oriented surfaces")

static void add_triangle_normal(const selfcol_mesh *m, uint32_t t, double n[3]) {
    const uint32_t *tri = m->triangles + 3 * (size_t)t;
    double c[3];
    vec3_triangle_normal(c, selfcol_mesh__position(m, tri[0]), selfcol_mesh__position(m, tri[1]),
                         selfcol_mesh__position(m, tri[2]));
    vec3_add(n, n, c);
}

// Adds `orientation` times the unit outward normal of an element (a vertex,
// an edge by index, or a triangle by index) of mesh m to o; a zero normal
// (degenerate triangles only) adds nothing.
static void add_element_normal(const selfcol_mesh *m, int orientation, int vertices, uint32_t index,
                               double o[3]) {
    double n[3] = {0.0, 0.0, 0.0};
    if (vertices == 1) {
        for (uint32_t k = m->vertex_tri_offsets[index]; k < m->vertex_tri_offsets[index + 1]; ++k)
            add_triangle_normal(m, m->vertex_tris[k], n);
    } else if (vertices == 2) {
        for (uint32_t k = m->edge_tri_offsets[index]; k < m->edge_tri_offsets[index + 1]; ++k)
            add_triangle_normal(m, m->edge_tris[k], n);
    } else {
        add_triangle_normal(m, index, n);
    }
    double u[3];
    if (vec3_normalize(u, n))
        for (int k = 0; k < 3; ++k)
            o[k] += orientation * u[k];
}

// The right side an oriented surface gives a VF/EE entry: +1, -1, or 0 when
// neither mesh is oriented or the sign is not clear.
static int oriented_right_side(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                               const uint32_t b[3]) {
    const uint32_t fm = first_mesh(e), sm = second_mesh(e);
    const int of = s->orientation[fm], os = s->orientation[sm];
    if (of == 0 && os == 0)
        return 0;
    const selfcol_mesh *mf = s->meshes[fm], *ms = s->meshes[sm];
    const int vf = e->kind == SELFCOL_CONTACT_VF;
    double o[3] = {0.0, 0.0, 0.0}, r[3], unit_r[3];
    if (os != 0)
        add_element_normal(ms, os, vf ? 3 : 2, e->second, o);
    if (of != 0) {
        double nf[3] = {0.0, 0.0, 0.0};
        add_element_normal(mf, of, vf ? 1 : 2, e->first, nf);
        vec3_sub(o, o, nf);
    }
    // The reference direction R (store.h; side = sign((first - second) . R)).
    if (vf) {
        vec3_triangle_normal(r, vertex_of(s, sm, b[0]), vertex_of(s, sm, b[1]),
                             vertex_of(s, sm, b[2]));
    } else {
        double u[3], w[3];
        vec3_sub(u, vertex_of(s, fm, a[1]), vertex_of(s, fm, a[0]));
        vec3_sub(w, vertex_of(s, sm, b[1]), vertex_of(s, sm, b[0]));
        vec3_cross(r, u, w);
    }
    if (!vec3_normalize(unit_r, r))
        return 0;
    const double d = vec3_dot(o, unit_r);
    return d > 1e-9 ? 1 : d < -1e-9 ? -1 : 0;
}

// Side tracking of a VF/EE entry at the current positions: a nonzero exact
// sign different from the held side is a crossing; 0 keeps the held side.
// An oriented entry's right side is then recomputed from the normals.
// selfcol_store_update_swept: whether the entry's primitives may touch at
// some time of the step, every vertex moving linearly from its step-start
// position to its current one (the continuous narrow phase, no false
// negatives: narrow_sweep.h). 0 is a proof that they never touched.
static int touched_in_step(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                           const uint32_t b[3]) {
    const uint32_t fm = first_mesh(e), sm = second_mesh(e);
    const int vf = e->kind == SELFCOL_CONTACT_VF;
    const uint32_t ids[4] = {a[0], vf ? b[0] : a[1], vf ? b[1] : b[0], vf ? b[2] : b[1]};
    const uint32_t of[4] = {fm, vf ? sm : fm, sm, sm};
    const double *start[4], *end[4];
    for (int k = 0; k < 4; ++k) {
        start[k] = s->step_start[of[k]] + 3 * (size_t)ids[k];
        end[k] = vertex_of(s, of[k], ids[k]);
    }
    double toi;
    return vf ? selfcol_narrow_sweep__vf_before(start, end, 0.0, 1.0, &toi, NULL)
              : selfcol_narrow_sweep__ee_before(start, end, 0.0, 1.0, &toi, NULL);
}

static void track_side(selfcol_store *s, store_entry *e, const uint32_t a[2], const uint32_t b[3],
                       selfcol_store_update_stats *st) {
    if (e->kind == SELFCOL_CONTACT_EF) {
        set_sides(e, 0, 0);
        return;
    }
    int side = side_of(e), right_side = right_side_of(e);
    if (s->orientation[first_mesh(e)] != 0 || s->orientation[second_mesh(e)] != 0) {
        e->flags |= SELFCOL_STORE_ORIENTED;
        const int given = oriented_right_side(s, e, a, b);
        if (given != 0)
            right_side = given;
    }
    const int now = exact_side(s, e, a, b);
    if (now != 0) {
        if (side != 0 && now != side && s->step_start[0] != NULL && !touched_in_step(s, e, a, b)) {
            // The sign changed but the elements never touched during the
            // step: they went around each other, not through. Where they
            // belong turned with the reference direction: no crossing.
            e->flags |= SELFCOL_STORE_PASSED_AROUND;
            right_side = right_side != 0 ? -right_side : 0;
            st->passed_around++;
        } else if (side != 0 && now != side) {
            e->flags |= SELFCOL_STORE_FLIPPED;
            e->flags &= (uint8_t)~SELFCOL_STORE_SETTLED; // a crossing reopens the vote
            st->flipped++;
        }
        side = now;
        if (right_side == 0)
            right_side = now; // first decided side: taken as the right one
    }
    set_sides(e, side, right_side);
}

// ---------------------------------------------------------------------------
// Union-find

static void group_unite(uint32_t *parent, uint32_t x, uint32_t y) {
    x = selfcol_union_find__root(parent, x);
    y = selfcol_union_find__root(parent, y);
    if (x != y)
        parent[x < y ? y : x] = x < y ? x : y; // the smaller index is the root
}

// group_unite for threads sharing the parents (the wait-free union-find of
// Anderson and Woll 1991, linking by index): every parent is read and
// written atomically; a root goes under the smaller root by a compare-and-
// swap that fails if it stopped being a root meanwhile (then both roots are
// found again); path halving writes a grandparent, an ancestor whichever
// thread writes it. Each group's root is its smallest entry whatever the
// order of the links, as with group_unite: the regions do not depend on the
// threads.
static uint32_t group_root_shared(uint32_t *parent, uint32_t x) {
    for (;;) {
        const uint32_t p = __atomic_load_n(&parent[x], __ATOMIC_RELAXED);
        if (p == x)
            return x;
        const uint32_t g = __atomic_load_n(&parent[p], __ATOMIC_RELAXED);
        if (g != p)
            __atomic_store_n(&parent[x], g, __ATOMIC_RELAXED);
        x = g;
    }
}

static void group_unite_shared(uint32_t *parent, uint32_t x, uint32_t y) {
    for (;;) {
        x = group_root_shared(parent, x);
        y = group_root_shared(parent, y);
        if (x == y)
            return;
        const uint32_t root = x < y ? x : y, child = x < y ? y : x;
        uint32_t expected = child;
        if (__atomic_compare_exchange_n(&parent[child], &expected, root, 0, __ATOMIC_RELAXED,
                                        __ATOMIC_RELAXED))
            return;
    }
}

// Root of x in the voting union-find, and x's parity relative to it
// (o_x = parity * o_root), compressing the path (two iterative passes).
static uint32_t vote_find(uint32_t *parent, int8_t *parity, uint32_t x, int *parity_out) {
    uint32_t root = x;
    int p = 1;
    while (parent[root] != root) {
        p *= parity[root];
        root = parent[root];
    }
    uint32_t y = x;
    int py = p;
    while (parent[y] != y) {
        const uint32_t next = parent[y];
        const int pnext = py * parity[y];
        parent[y] = root;
        parity[y] = (int8_t)py;
        y = next;
        py = pnext;
    }
    *parity_out = p;
    return root;
}

// Links x and y with o_x = relation * o_y; a link inside one group is
// ignored (consistent or not: the first links win).
static void vote_unite(uint32_t *parent, int8_t *parity, uint32_t x, uint32_t y, int relation) {
    int px, py;
    uint32_t rx = vote_find(parent, parity, x, &px), ry = vote_find(parent, parity, y, &py);
    if (rx == ry)
        return;
    // o_rx = px o_x = px relation o_y = px relation py o_ry.
    const int8_t link = (int8_t)(px * relation * py);
    if (rx < ry) {
        parent[ry] = rx;
        parity[ry] = link;
    } else {
        parent[rx] = ry;
        parity[rx] = link;
    }
}

// The unit normal of the surface at vertex v of mesh `mesh`: the
// area-weighted sum of its triangles' normals. 0 when v has none usable (no
// triangle, degenerate ones, or a one-ring whose winding cancels, as at a
// fold's hinge).
// Kept as floats (12 bytes per vertex); computed once per update, by the
// first thread that needs it. A thread that finds it missing computes it
// (the same floats whoever computes them) and publishes it if no other
// thread has claimed the vertex: a claim (stamp + 1) and the publication
// (stamp) are atomic, so a cached normal is read only once it is written.
static int vertex_normal(selfcol_store *s, uint32_t mesh, uint32_t v, double normal[3]) {
    float *cached = s->normals[mesh] + 3 * (size_t)v;
    uint32_t *stamp = &s->normal_stamp[mesh][v];
    const uint32_t ready = s->stamp, claimed = s->stamp + 1;
    uint32_t seen = SELFCOL_ATOMIC_LOAD(stamp);
    if (seen == ready) {
        for (int k = 0; k < 3; ++k)
            normal[k] = cached[k];
    } else {
        const selfcol_mesh *m = s->meshes[mesh];
        double n[3] = {0.0, 0.0, 0.0}, u[3] = {0.0, 0.0, 0.0};
        for (uint32_t k = m->vertex_tri_offsets[v]; k < m->vertex_tri_offsets[v + 1]; ++k)
            add_triangle_normal(m, m->vertex_tris[k], n);
        vec3_normalize(u, n); // (0, 0, 0) when there is none
        float f[3];
        for (int k = 0; k < 3; ++k) {
            f[k] = (float)u[k];
            normal[k] = f[k];
        }
        if (seen != claimed && SELFCOL_ATOMIC_CAS(stamp, &seen, claimed)) {
            memcpy(cached, f, sizeof f);
            SELFCOL_ATOMIC_STORE(stamp, ready);
        }
    }
    return normal[0] != 0.0 || normal[1] != 0.0 || normal[2] != 0.0;
}

// The cosine a link needs, between the surface normals at its two vertices
// and between each direction and each normal (60 degrees): measured on the
// crumpling ribbon held clean by the Bullet adapter (EF = 0), queried at
// 0.5 x mean edge, 0 of ~150k candidate links contradict the geometry with
// 0.5; with 0.3, 3-5 per frame do (all where a border edge meets the other
// layer edge-on, whose directions point every way).
#define SELFCOL_STORE_LINK_COS 0.5

// Vertex pairs an entry has: |first's vertices| x |second's|.
static int pairs_of_kind(uint32_t kind) {
    return kind == SELFCOL_CONTACT_VF ? 3 : kind == SELFCOL_CONTACT_EE ? 4 : 6;
}

// Neighbours i and j sharing a vertex pair {u, w} are compared through the
// surface normals at u and at w (store.h, "Consistency rule"). Each
// direction (the record's) points from the second element to the first, so
// it says which side of the surface at u (and at w) the entry's first
// element is on. That side is what is compared, not the directions
// themselves: two directions leaning opposite ways off the normal (closest
// points on opposite borders, frequent when the gap is small against d)
// point to the same side, although their dot product is negative (seed
// 3.2.1 propagates the surfaces' orientation; this is its local form). Same
// roles (parity +1) should point to the same side, crosswise ones (-1) to
// opposite sides: o_i = parity * relation * o_j. The link is made only
// where the geometry is clear: the two surfaces within 60 degrees of
// parallel or antiparallel, every direction within 60 degrees of both
// normals' lines, and the same relation through both normals.
//
// All of that reads from each entry alone, once per update: its link code.
// Per vertex slot (a[0], a[1], b[0], b[1], b[2]: bits 2 k and 2 k + 1) the
// side code of its direction at that vertex's normal: 1 for the normal's
// side, 2 for the other, 0 when it leans more than 60 degrees off the
// normal's line or the vertex has no normal. Per vertex pair in pair_of()'s
// order (bit 10 + k), whether the normals at its ends are within 60 degrees
// of parallel or antiparallel. Entries that do not vote (EF, oriented) have
// code 0. A link then compares two side codes per end (link_entries).
#define SIDE_CODE(code, slot) (((code) >> (2 * (slot))) & 3u)
#define PAIR_CLEAR(code, k) (((code) >> (10 + (k))) & 1u)

static uint16_t link_code(selfcol_store *s, const store_entry *e, const uint32_t a[2],
                          const uint32_t b[3], const double direction[3]) {
    const int na = e->kind == SELFCOL_CONTACT_VF ? 1 : 2,
              nb = e->kind == SELFCOL_CONTACT_EE ? 2 : 3;
    const uint32_t vertex[5] = {a[0], a[1], b[0], b[1], b[2]};
    const uint32_t mesh[5] = {first_mesh(e), first_mesh(e), second_mesh(e), second_mesh(e),
                              second_mesh(e)};
    double normal[5][3];
    int has_normal[5] = {0, 0, 0, 0, 0};
    unsigned code = 0;
    for (int slot = 0; slot < 5; ++slot) {
        if ((slot >= na && slot < 2) || slot >= 2 + nb)
            continue;
        has_normal[slot] = vertex_normal(s, mesh[slot], vertex[slot], normal[slot]);
        const double p = vec3_dot(direction, normal[slot]);
        if (has_normal[slot] && fabs(p) >= SELFCOL_STORE_LINK_COS)
            code |= (p > 0 ? 1u : 2u) << (2 * slot);
    }
    const int pairs = pairs_of_kind(e->kind);
    for (int k = 0; k < pairs; ++k) {
        const int su = k / nb, sw = 2 + k % nb;
        if (has_normal[su] && has_normal[sw] &&
            fabs(vec3_dot(normal[su], normal[sw])) >= SELFCOL_STORE_LINK_COS)
            code |= 1u << (10 + k);
    }
    return (uint16_t)code;
}

// Two entries sharing a vertex pair: link their orientations where both
// side codes read clearly through the normals at both ends and give the
// same relation (link_code). lo_i, hi_i, lo_j, hi_j: each entry's side
// code at the pair's two ends, 0 where the pair's normals are not clear.
// (They are grouped too, by the caller.)
static void link_entries(selfcol_store *s, uint32_t i, uint32_t j, int same_roles, uint32_t lo_i,
                         uint32_t hi_i, uint32_t lo_j, uint32_t hi_j) {
    if (lo_i == 0 || lo_j == 0 || hi_i == 0 || hi_j == 0)
        return;
    const int through_lo = lo_i == lo_j ? 1 : -1, through_hi = hi_i == hi_j ? 1 : -1;
    if (through_lo != through_hi)
        return;
    vote_unite(s->vote_parent, s->vote_parity, i, j, (same_roles ? 1 : -1) * through_lo);
}

// One vertex pair {u, w} of an entry: u a vertex of its first element (of
// mesh mu), w of its second (of mesh mw); first_is_lo when (mu, u) orders
// before (mw, w). An entry has pairs_of_kind() of them, taken in the order
// p over the first element's vertices, q over the second's. bucket: the
// neighbour search's bucket of the pair (lo end's mesh and vertex, hi
// end's mesh: buckets_of()); hi: its hi end.
typedef struct vertex_pair {
    int first_is_lo;
    int u_slot, w_slot; // of u and w in link_code's order
    uint32_t hi;
    size_t bucket;
} vertex_pair;

static vertex_pair pair_of(const store_entry *e, const uint32_t a[2], const uint32_t b[3], int k,
                           size_t n0) {
    const int nb = e->kind == SELFCOL_CONTACT_EE ? 2 : 3;
    const uint32_t u = a[k / nb], w = b[k % nb], mu = first_mesh(e), mw = second_mesh(e);
    vertex_pair v;
    v.u_slot = k / nb;
    v.w_slot = 2 + k % nb;
    v.first_is_lo = mu < mw || (mu == mw && u < w);
    const uint32_t lo = v.first_is_lo ? u : w, lo_mesh = v.first_is_lo ? mu : mw;
    const uint32_t hi_mesh = v.first_is_lo ? mw : mu;
    v.hi = v.first_is_lo ? w : u;
    // (0, lo, 0) at lo, (0, lo, 1) at n0 + lo, (1, lo, 1) at 2 n0 + lo.
    v.bucket = (lo_mesh + hi_mesh) * n0 + lo;
    return v;
}

// Counts an entry's vertex pairs into their buckets (count[b]: the counts
// of the entry's chunk), with the vertices the merge has just read
// (sort_pairs sorts them).
static void count_pairs(const selfcol_store *s, uint32_t *count, const store_entry *e,
                        const uint32_t a[2], const uint32_t b[3]) {
    const size_t n0 = s->meshes[0]->vertex_count;
    const int pairs = pairs_of_kind(e->kind);
    for (int k = 0; k < pairs; ++k)
        count[pair_of(e, a, b, k, n0).bucket]++;
}

// The counts of every chunk (bucket_offset) become the position where the
// chunk writes its first occurrence of each bucket: buckets in order, and
// inside a bucket the chunks in order, so the sort is stable whatever the
// number of chunks.
static void bucket_starts(selfcol_store *s, size_t chunks) {
    const size_t buckets = buckets_of(s->meshes);
    uint32_t running = 0;
    for (size_t x = 0; x < buckets; ++x) {
        for (size_t c = 0; c < chunks; ++c) {
            uint32_t *slot = &s->bucket_offset[c * s->bucket_count + x];
            const uint32_t count = *slot;
            *slot = running;
            running += count;
        }
    }
}

// Lists the vertex-pair occurrences of entries lo .. hi - 1 (chunk c) in
// their buckets (the counting sort's scatter): each with its pair's hi end,
// and its entry with the entry's side codes at the pair's ends (link_code).
// Afterwards the chunk's offsets are its ends in each bucket, and the last
// chunk's are the buckets' ends.
static void sort_pairs(selfcol_store *s, size_t c, size_t lo, size_t hi_index) {
    const size_t n0 = s->meshes[0]->vertex_count;
    uint32_t *off = s->bucket_offset + c * s->bucket_count, *hi = s->pair_hi,
             *entry = s->pair_entry;
    for (uint32_t i = (uint32_t)lo; i < hi_index; ++i) {
        const store_entry *e = &s->entries[i];
        uint32_t a[2], b[3];
        entry_vertices(s, e, a, b);
        const unsigned code = s->link_code[i];
        const int pairs = pairs_of_kind(e->kind);
        for (int k = 0; k < pairs; ++k) {
            const vertex_pair v = pair_of(e, a, b, k, n0);
            const uint32_t p = off[v.bucket]++;
            uint32_t side_u = 0, side_w = 0;
            if (PAIR_CLEAR(code, k)) {
                side_u = SIDE_CODE(code, v.u_slot);
                side_w = SIDE_CODE(code, v.w_slot);
            }
            hi[p] = v.hi;
            entry[p] = i | (v.first_is_lo ? PAIR_FIRST_IS_LO | side_u << PAIR_LO_SHIFT |
                                                side_w << PAIR_HI_SHIFT
                                          : side_w << PAIR_LO_SHIFT | side_u << PAIR_HI_SHIFT);
        }
    }
}

// Entries sharing a vertex pair are neighbours (link_entries). Each
// occurrence of a pair is linked to the pair's first occurrence. The
// occurrences are found without a sort or a hash (a hash of a few million
// pairs is a cache miss per probe): a counting sort into buckets by their
// lo end (counted during the merge, listed by sort_pairs; stable, so each
// bucket lists its occurrences in entry order), then one pass per bucket,
// in which a stamp per hi vertex marks each pair's first occurrence and
// every later one is linked to it at once. The links are made in that
// order: buckets by lo end, then entry order. A link that closes a cycle
// against the relation is ignored, so the order decides which links win;
// it is fixed by the entries and the meshes alone (not by the threads).
// (Making the links in entry order instead, by replaying the occurrences,
// cost a random read per occurrence: 20-30 % of the update on cloth-ball
// 92 -> 93.) Each occurrence carries its entry's side codes at the pair's
// ends (link_code), so a link reads nothing of either entry but its
// union-find parents. bucket_end: the buckets' ends (sort_pairs).
// The grouping union-find (regions), whose result does not depend on the
// order of its links, is done here when group_here, else by threads
// afterwards (group_chunk): each occurrence's hi end is then replaced by
// the entry it is grouped with (its own where it links nothing).
static void link_neighbours(selfcol_store *s, const uint32_t *bucket_end, int group_here) {
    const size_t n0 = s->meshes[0]->vertex_count;
    const size_t buckets = buckets_of(s->meshes);
    uint32_t *hi = s->pair_hi;
    const uint32_t *entry = s->pair_entry;
    // Per bucket, the first occurrence of each hi end: stamps unique to the
    // bucket (a running count, cleared when it would wrap).
    if (s->bucket_stamp > UINT32_MAX - buckets - 1) {
        for (int k = 0; k < 2; ++k)
            if (s->hi_count[k] > 0)
                memset(s->hi_stamp[k], 0, s->hi_count[k] * sizeof *s->hi_stamp[k]);
        s->bucket_stamp = 0;
    }
    for (size_t x = 0; x < buckets; ++x) {
        const uint32_t start = x == 0 ? 0 : bucket_end[x - 1], end = bucket_end[x];
        if (end - start < 2) { // one occurrence links nothing
            if (end > start && !group_here)
                hi[start] = entry[start] & PAIR_INDEX;
            continue;
        }
        const uint32_t stamp = ++s->bucket_stamp;
        const int hi_mesh = x >= n0 ? 1 : 0;
        uint32_t *seen = s->hi_stamp[hi_mesh], *first = s->hi_first[hi_mesh];
        for (uint32_t p = start; p < end; ++p) {
            const uint32_t y = hi[p], ei = entry[p], i = ei & PAIR_INDEX;
            if (seen[y] != stamp) {
                seen[y] = stamp;
                first[y] = p;
                if (!group_here)
                    hi[p] = i;
                continue;
            }
            const uint32_t ej = entry[first[y]], j = ej & PAIR_INDEX;
            if (!group_here)
                hi[p] = j;
            if (i == j)
                continue;
            if (group_here)
                group_unite(s->group_parent, i, j);
            link_entries(s, i, j, ((ei ^ ej) & PAIR_FIRST_IS_LO) == 0, ei >> PAIR_LO_SHIFT & 3u,
                         ei >> PAIR_HI_SHIFT & 3u, ej >> PAIR_LO_SHIFT & 3u,
                         ej >> PAIR_HI_SHIFT & 3u);
        }
    }
}

// ---------------------------------------------------------------------------
// The vote

// The vote's arrays, per group root r: the votes for o = +1 and o = -1 of
// contacts new in this update (new_votes[2 r], [2 r + 1]) and of contacts
// held from earlier updates (held_votes), the group's oldest contact, and
// the region label of r's grouping root. They live in the neighbour
// search's two arrays, free once the links are made: each holds a word per
// vertex pair, at least 3 per entry.
typedef struct tally {
    uint32_t *new_votes, *held_votes, *oldest, *label;
} tally;

static tally tally_of(const selfcol_store *s) {
    const size_t n = s->count;
    tally t = {NULL, NULL, NULL, NULL};
    if (n > 0) {
        t.new_votes = s->pair_hi;
        t.oldest = s->pair_hi + 2 * n;
        t.held_votes = s->pair_entry;
        t.label = s->pair_entry + 2 * n;
    }
    return t;
}

// Tallies each voting group's votes and numbers the regions by their first
// entry (entry regions set); returns the number of regions.
static size_t tally_and_label(selfcol_store *s, selfcol_store_update_stats *st) {
    const size_t n = s->count;
    const tally t = tally_of(s);
    for (size_t i = 0; i < n; ++i) {
        t.new_votes[2 * i] = t.new_votes[2 * i + 1] = 0;
        t.held_votes[2 * i] = t.held_votes[2 * i + 1] = 0;
        t.oldest[i] = SELFCOL_INVALID_INDEX;
    }
    // Tally: contact i's vote, in its group's frame, is sigma_i * o_i with
    // sigma_i = side * right_side (+1 on its right side). Contacts whose
    // side was never decided abstain.
    for (uint32_t i = 0; i < n; ++i) {
        const store_entry *e = &s->entries[i];
        if (e->kind == SELFCOL_CONTACT_EF || side_of(e) == 0 || (e->flags & SELFCOL_STORE_ORIENTED))
            continue;
        st->voted++;
        int o;
        const uint32_t r = vote_find(s->vote_parent, s->vote_parity, i, &o);
        const int vote = side_of(e) * right_side_of(e) * o;
        uint32_t *votes = (e->flags & SELFCOL_STORE_NEW) ? t.new_votes : t.held_votes;
        votes[2 * r + (vote > 0 ? 0 : 1)]++;
        const uint32_t old = t.oldest[r];
        if (old == SELFCOL_INVALID_INDEX || e->age > s->entries[old].age)
            t.oldest[r] = i;
    }
    // Regions, numbered by their first entry.
    for (size_t i = 0; i < n; ++i)
        t.label[i] = SELFCOL_INVALID_INDEX;
    size_t regions = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t g = selfcol_union_find__root(s->group_parent, i);
        if (t.label[g] == SELFCOL_INVALID_INDEX)
            t.label[g] = (uint32_t)regions++;
        s->entries[i].region = t.label[g];
    }
    return regions;
}

// Each voting group's majority right side, imposed; then the region
// records (s->regions holds `regions`).
static void impose(selfcol_store *s, size_t regions, selfcol_store_update_stats *st) {
    const size_t n = s->count;
    const tally t = tally_of(s);
    if (regions > 0)
        memset(s->regions, 0, regions * sizeof *s->regions);
    for (uint32_t i = 0; i < n; ++i) {
        store_entry *e = &s->entries[i];
        selfcol_store_region *reg = &s->regions[e->region];
        if (e->kind == SELFCOL_CONTACT_EF) {
            reg->interferences++;
            reg->flags |= SELFCOL_REGION_CROSSED;
            continue;
        }
        reg->contacts++;
        if (e->flags & SELFCOL_STORE_ORIENTED) {
            reg->oriented++;
            st->oriented++;
            continue;
        }
        int o;
        const uint32_t r = vote_find(s->vote_parent, s->vote_parity, i, &o);
        // A group with held contacts follows their votes only: a held
        // contact's right side carries memory (of its side before a
        // crossing, or of an earlier vote), a new contact's is a guess (its
        // current side). New contacts decide only groups of new contacts.
        const uint32_t *h = t.held_votes + 2 * r;
        const uint32_t *v = h[0] + h[1] > 0 ? h : t.new_votes + 2 * r;
        const uint32_t plus = v[0], minus = v[1];
        const int side = side_of(e);
        if (side == 0) {
            reg->abstained++;
            continue;
        }
        int majority; // the group's winning sigma * o
        if (plus != minus) {
            majority = plus > minus ? 1 : -1;
        } else if (plus == 0) {
            majority = 0; // nobody voted: nothing to impose
        } else {
            // Tie: the oldest contact keeps its right side.
            const store_entry *oldest = &s->entries[t.oldest[r]];
            int ot;
            vote_find(s->vote_parent, s->vote_parity, t.oldest[r], &ot);
            majority = side_of(oldest) * right_side_of(oldest) * ot;
            reg->flags |= SELFCOL_REGION_TIE;
        }
        // A decided side always has a right side (track_side).
        const int right_side = right_side_of(e);
        if (side * right_side * o == majority || majority == 0) {
            reg->votes_majority++;
        } else {
            reg->votes_minority++;
            if (s->consistency && !(e->flags & SELFCOL_STORE_SETTLED)) {
                set_sides(e, side, -right_side);
                e->flags |= SELFCOL_STORE_CORRECTED;
                st->corrected++;
                reg->flags |= SELFCOL_REGION_CORRECTED;
            }
        }
        if (s->consistency && majority != 0)
            e->flags |= SELFCOL_STORE_SETTLED; // through a vote: settled until it crosses
    }
    for (size_t r = 0; r < regions; ++r) {
        st->crossed_regions += (s->regions[r].flags & SELFCOL_REGION_CROSSED) != 0;
        st->corrected_regions += (s->regions[r].flags & SELFCOL_REGION_CORRECTED) != 0;
    }
    st->regions = regions;
}

// ---------------------------------------------------------------------------
// The update

// The merge (step 1) of held entries i0 .. i1 - 1 with records j0 .. j1 - 1,
// both sorted by key: per step, the held entry (c < 0), the record (c > 0),
// or both (c == 0, the same key).
static int merge_step(const selfcol_store *s, const selfcol_contact *rec, size_t i, size_t i1,
                      size_t j, size_t j1) {
    return i == i1 ? 1 : j == j1 ? -1 : entry_record_compare(&s->entries[i], &rec[j]);
}

// A held entry that is not detected again and goes (EF, or remnance over).
static int dropped(const selfcol_store *s, const store_entry *e) {
    return e->kind == SELFCOL_CONTACT_EF || e->missed >= s->remnance;
}

// ---------------------------------------------------------------------------
// The update's work in parallel

// The least entries (or records) per chunk worth a thread: a chunk's work
// (about 0.3 us per entry) then outweighs a thread's start (tens of us).
#define SELFCOL_STORE_MIN_CHUNK 4096u

// Chunks for `total` items: at most `threads`, each of at least
// SELFCOL_STORE_MIN_CHUNK items (1 chunk below that).
static size_t chunks_for(size_t total, unsigned threads) {
    const size_t most = total / SELFCOL_STORE_MIN_CHUNK;
    return most < 1 ? 1 : most < threads ? most : threads;
}

// First item of chunk c of `chunks` over `total` items.
static size_t chunk_start(size_t total, size_t chunks, size_t c) {
    return (size_t)((uint64_t)total * c / chunks);
}

enum update_stage { STAGE_VALIDATE, STAGE_SIZE, STAGE_MERGE, STAGE_SORT, STAGE_GROUP };

// The parallel stages of an update. Chunk c of a stage covers the records
// record_at[c] .. record_at[c + 1] - 1 and the held entries held_at[c] ..
// held_at[c + 1] - 1 (a range of keys: the merge's chunks), and makes the
// entries entry_at[c] .. entry_at[c + 1] - 1. The workers take chunks from
// a shared counter; a chunk writes only its own items and results, so the
// store does not depend on which worker ran which chunk, nor on how many
// chunks there were.
typedef struct update_job {
    selfcol_store *s;
    const selfcol_mesh *const *meshes;
    const selfcol_contact *rec;
    store_entry *out; // the merge's destination
    size_t chunks;
    enum update_stage stage;
    size_t next_chunk; // atomic
    size_t pairs;      // STAGE_GROUP: vertex-pair occurrences, in equal chunks
    size_t record_at[SELFCOL_MAX_THREADS + 1], held_at[SELFCOL_MAX_THREADS + 1],
        entry_at[SELFCOL_MAX_THREADS + 1];
    // STAGE_VALIDATE: its first bad record (SIZE_MAX: none) and why.
    // STAGE_SIZE: the entries the chunk keeps and their vertex pairs.
    size_t bad[SELFCOL_MAX_THREADS], kept[SELFCOL_MAX_THREADS], keys[SELFCOL_MAX_THREADS];
    int bad_status[SELFCOL_MAX_THREADS];
    // STAGE_MERGE: the chunk's counters.
    selfcol_store_update_stats stats[SELFCOL_MAX_THREADS];
} update_job;

// Records of chunk c: each must match the meshes and follow the one before
// it in key order (the query's sort).
static void validate_records(update_job *job, size_t c) {
    job->bad[c] = SIZE_MAX;
    for (size_t j = job->record_at[c]; j < job->record_at[c + 1]; ++j) {
        int status = SELFCOL_OK;
        if (!record_matches(job->meshes, &job->rec[j]))
            status = SELFCOL_EMISMATCH;
        else if (j > 0 && record_compare(&job->rec[j - 1], &job->rec[j]) >= 0)
            status = SELFCOL_EINVAL;
        if (status != SELFCOL_OK) {
            job->bad[c] = j;
            job->bad_status[c] = status;
            return;
        }
    }
}

// An EF entry's share of the merge's work against a VF or EE entry's: it
// has no side, geometry or link code (measured: about a quarter).
#define EF_WORK 0.25

// Where chunk c of `chunks` starts in `total` items sorted by kind whose EF
// ones start at ef_start, in equal shares of work (EF_WORK): on cloth-ball
// 93 a fifth of the entries are EF, and an equal split by count gave one
// chunk 2.7 times the contacts of the other.
static size_t work_split(size_t total, size_t ef_start, size_t chunks, size_t c) {
    const double work = (double)ef_start + EF_WORK * (double)(total - ef_start);
    const double share = work * (double)c / (double)chunks;
    const double at =
        share <= (double)ef_start ? share : (double)ef_start + (share - (double)ef_start) / EF_WORK;
    return at < (double)total ? (size_t)at : total;
}

// The first EF record or held entry: a binary search over either array
// (both sorted by kind), through its kind reader.
static uint32_t record_kind_at(const void *items, size_t i) {
    return ((const selfcol_contact *)items)[i].kind;
}

static uint32_t entry_kind_at(const void *items, size_t i) {
    return ((const store_entry *)items)[i].kind;
}

static size_t first_ef(const void *items, size_t n, uint32_t (*kind_at)(const void *, size_t)) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (kind_at(items, mid) < SELFCOL_CONTACT_EF)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

// The merge's chunks: ranges of keys, split at every chunk's share of the
// work (work_split) in the longer of the held entries and the records (the
// other split where its keys reach the split key). Needs the records
// validated (sorted).
static void split_by_keys(update_job *job, size_t records, size_t chunks) {
    const selfcol_store *s = job->s;
    const size_t held = s->count, m = records;
    const size_t ef_split = m >= held ? first_ef(job->rec, m, record_kind_at)
                                      : first_ef(s->entries, held, entry_kind_at);
    job->chunks = chunks;
    for (size_t c = 0; c <= chunks; ++c) {
        size_t i, j;
        if (c == 0) {
            i = j = 0;
        } else if (c == chunks) {
            i = held;
            j = m;
        } else if (m >= held) { // held entries before the split record's key
            j = work_split(m, ef_split, chunks, c);
            size_t lo = 0, hi = held;
            while (lo < hi) {
                const size_t mid = lo + (hi - lo) / 2;
                if (j < m && entry_record_compare(&s->entries[mid], &job->rec[j]) < 0)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            i = j < m ? lo : held;
        } else { // records before the split entry's key
            i = work_split(held, ef_split, chunks, c);
            size_t lo = 0, hi = i < held ? m : 0;
            while (lo < hi) {
                const size_t mid = lo + (hi - lo) / 2;
                if (entry_record_compare(&s->entries[i], &job->rec[mid]) > 0)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            j = i < held ? lo : m;
        }
        job->held_at[c] = i;
        job->record_at[c] = j;
    }
}

// A dry run of the merge of chunk c: the entries it keeps (held and
// detected again, new, or remnant) and their vertex pairs.
static void size_chunk(update_job *job, size_t c) {
    const selfcol_store *s = job->s;
    size_t i = job->held_at[c], j = job->record_at[c], n = 0, keys = 0;
    const size_t i1 = job->held_at[c + 1], j1 = job->record_at[c + 1];
    while (i < i1 || j < j1) {
        const int step = merge_step(s, job->rec, i, i1, j, j1);
        uint32_t kind;
        if (step >= 0) {
            kind = job->rec[j++].kind;
            i += step == 0;
        } else {
            const store_entry *h = &s->entries[i++];
            if (dropped(s, h))
                continue;
            kind = h->kind;
        }
        ++n;
        keys += (size_t)pairs_of_kind(kind);
    }
    job->kept[c] = n;
    job->keys[c] = keys;
}

// The merge of chunk c into entries entry_at[c] ..: each entry kept, new or
// remnant, its side tracked (track_side), what its links compare
// (link_code, from its record's direction or, for a remnant, its direction
// at the current positions), and its vertex pairs counted into the chunk's
// buckets.
static void merge_chunk(update_job *job, size_t c) {
    selfcol_store *s = job->s;
    const selfcol_contact *rec = job->rec;
    // Counted here, written once (the chunks' records share cache lines).
    selfcol_store_update_stats counters;
    memset(&counters, 0, sizeof counters);
    selfcol_store_update_stats *st = &counters;
    uint32_t *count = s->bucket_offset + c * s->bucket_count;
    size_t i = job->held_at[c], j = job->record_at[c], n = job->entry_at[c];
    const size_t i1 = job->held_at[c + 1], j1 = job->record_at[c + 1];
    const store_entry *held = s->entries;
    while (i < i1 || j < j1) {
        const int step = merge_step(s, rec, i, i1, j, j1);
        store_entry *e = &job->out[n];
        if (step < 0 && dropped(s, &held[i])) {
            ++i;
            st->dropped++;
            continue;
        }
        if (step == 0) { // held and detected again
            *e = held[i++];
            e->age += e->age < UINT32_MAX;
            e->missed = 0;
            e->flags &= SELFCOL_STORE_SETTLED; // the only flag that persists
            st->kept += e->kind != SELFCOL_CONTACT_EF;
        } else if (step > 0) { // new
            memset(e, 0, sizeof *e);
            e->kind = (uint8_t)rec[j].kind;
            e->meshes = (uint8_t)(rec[j].first_mesh | rec[j].second_mesh << 1);
            e->first = rec[j].first;
            e->second = rec[j].second;
            set_sides(e, 0, 0);
            e->flags = SELFCOL_STORE_NEW;
            st->new_contacts += e->kind != SELFCOL_CONTACT_EF;
        } else { // held, not detected, remnant
            *e = held[i++];
            e->age += e->age < UINT32_MAX;
            e->missed++;
            e->flags = (uint8_t)((e->flags & SELFCOL_STORE_SETTLED) | SELFCOL_STORE_REMNANT);
            st->remnant++;
        }
        uint32_t a[2], b[3];
        const double *direction = NULL;
        if (step >= 0) { // the record's vertices (record_matches: the topology's)
            memcpy(a, rec[j].a, sizeof a);
            memcpy(b, rec[j].b, sizeof b);
            if (e->kind == SELFCOL_CONTACT_EE)
                b[2] = SELFCOL_INVALID_INDEX;
            direction = rec[j++].direction;
        } else {
            entry_vertices(s, e, a, b);
        }
        count_pairs(s, count, e, a, b);
        track_side(s, e, a, b, st);
        s->link_code[n] = 0;
        if (e->kind != SELFCOL_CONTACT_EF && !(e->flags & SELFCOL_STORE_ORIENTED)) {
            selfcol_narrow_result r;
            if (direction == NULL) { // a remnant's, at the current positions
                geometry(s, e, a, b, &r);
                direction = r.direction;
            }
            s->link_code[n] = link_code(s, e, a, b, direction);
        }
        if (e->kind == SELFCOL_CONTACT_EF)
            st->interferences++;
        else
            st->contacts++;
        ++n;
    }
    job->stats[c] = counters;
}

// Entries of chunk c: their vertex pairs listed in their buckets
// (sort_pairs), and their union-find nodes started.
static void sort_chunk(update_job *job, size_t c) {
    selfcol_store *s = job->s;
    const size_t lo = job->entry_at[c], hi = job->entry_at[c + 1];
    sort_pairs(s, c, lo, hi);
    for (size_t k = lo; k < hi; ++k) {
        s->group_parent[k] = s->vote_parent[k] = (uint32_t)k;
        s->vote_parity[k] = 1;
    }
}

// Occurrences of chunk c of the vertex pairs: each entry grouped with the
// entry link_neighbours put in its place.
static void group_chunk(update_job *job, size_t c) {
    selfcol_store *s = job->s;
    const size_t lo = chunk_start(job->pairs, job->chunks, c),
                 hi = chunk_start(job->pairs, job->chunks, c + 1);
    const uint32_t *partner = s->pair_hi, *entry = s->pair_entry;
    for (size_t p = lo; p < hi; ++p) {
        const uint32_t i = entry[p] & PAIR_INDEX, j = partner[p];
        if (i != j)
            group_unite_shared(s->group_parent, i, j);
    }
}

static int update_worker(void *context, unsigned worker) {
    (void)worker;
    update_job *job = context;
    for (;;) {
        const size_t c = SELFCOL_ATOMIC_FETCH_ADD(&job->next_chunk, (size_t)1);
        if (c >= job->chunks)
            return SELFCOL_OK;
        if (job->stage == STAGE_VALIDATE)
            validate_records(job, c);
        else if (job->stage == STAGE_SIZE)
            size_chunk(job, c);
        else if (job->stage == STAGE_MERGE)
            merge_chunk(job, c);
        else if (job->stage == STAGE_SORT)
            sort_chunk(job, c);
        else
            group_chunk(job, c);
    }
}

// Runs one stage over the job's chunks, on at most store->threads workers
// (the calling thread alone for one chunk).
static void run_stage(update_job *job, enum update_stage stage) {
    job->stage = stage;
    job->next_chunk = 0;
    const unsigned workers =
        job->chunks < job->s->threads ? (unsigned)job->chunks : job->s->threads;
    if (workers <= 1)
        update_worker(job, 0);
    else
        selfcol_parallel__run(NULL, workers, update_worker, job);
}

int selfcol_store_update_swept(selfcol_store *store, const selfcol_mesh *first,
                               const selfcol_mesh *second, const selfcol_contacts *detected,
                               const double *first_start, const double *second_start) {
    SELFCOL_CHECK(store != NULL && first != NULL && detected != NULL && first_start != NULL);
    SELFCOL_CHECK((second == NULL) == (second_start == NULL));
    SELFCOL_CHECK(selfcol_mesh__positions_in_contract(first_start, first->vertex_count));
    SELFCOL_CHECK(second == NULL ||
                  selfcol_mesh__positions_in_contract(second_start, second->vertex_count));
    store->step_start[0] = first_start;
    store->step_start[1] = second_start;
    const int status = selfcol_store_update(store, first, second, detected);
    store->step_start[0] = store->step_start[1] = NULL;
    return status;
}

int selfcol_store_update(selfcol_store *store, const selfcol_mesh *first,
                         const selfcol_mesh *second, const selfcol_contacts *detected) {
    SELFCOL_CHECK(store != NULL && first != NULL && detected != NULL);
    const double start = selfcol_core__seconds();
    // Its meshes by address and identity: an address alone is reused by the
    // allocator once a mesh is destroyed, and the held contacts' indices
    // would then be read against another mesh's arrays.
    if (store->meshes[0] != NULL &&
        (store->meshes[0] != first || store->meshes[1] != second ||
         !selfcol_mesh__is(first, &store->identity[0]) ||
         (second != NULL && !selfcol_mesh__is(second, &store->identity[1]))))
        return SELFCOL_EMISMATCH;
    const selfcol_mesh *const meshes[2] = {first, second};
    const selfcol_contact *rec = detected->records.items;
    const size_t m = detected->records.count;
    update_job job;
    job.s = store;
    job.meshes = meshes;
    job.rec = rec;
    // Validate and reserve everything before changing anything. The first
    // bad record decides the status, whatever the threads.
    int status = SELFCOL_OK;
    job.chunks = chunks_for(m, store->threads);
    for (size_t c = 0; c <= job.chunks; ++c)
        job.record_at[c] = chunk_start(m, job.chunks, c);
    run_stage(&job, STAGE_VALIDATE);
    for (size_t c = 0; c < job.chunks && status == SELFCOL_OK; ++c)
        if (job.bad[c] != SIZE_MAX)
            status = job.bad_status[c];
    if (status != SELFCOL_OK)
        return status;
    // The merge's outcome, counted first (a dry run of step 1), so that
    // every array is sized to the entries the update keeps, not to held +
    // detected (which was twice as much on cloth-ball 92 -> 93), and each
    // chunk knows where its entries go.
    split_by_keys(&job, m, chunks_for(store->count > m ? store->count : m, store->threads));
    run_stage(&job, STAGE_SIZE);
    size_t keys = 0;
    job.entry_at[0] = 0;
    for (size_t c = 0; c < job.chunks; ++c) {
        job.entry_at[c + 1] = job.entry_at[c] + job.kept[c];
        keys += job.keys[c];
    }
    const size_t kept_entries = job.entry_at[job.chunks];
    status = reserve_entries(store, kept_entries > store->count ? kept_entries : store->count);
    if (status == SELFCOL_OK)
        status = reserve_mesh_arrays(store, meshes);
    if (status == SELFCOL_OK)
        status = keys > UINT32_MAX ? SELFCOL_ERANGE : reserve_pairs(store, keys);
    if (status != SELFCOL_OK)
        return status;
    // From here on only the region records can fail (their count is known
    // after the links): until then the held entries, the meshes and the
    // stats are kept aside, and restored on that failure.
    const selfcol_mesh *const old_meshes[2] = {store->meshes[0], store->meshes[1]};
    store->meshes[0] = first;
    store->meshes[1] = second;
    store->stamp += 2; // even: stamp + 1 marks a normal being written (vertex_normal)
    if (store->stamp > UINT32_MAX - 2) { // wrapping: forget every cached normal
        for (int k = 0; k < 2; ++k)
            if (store->normal_count[k] > 0)
                memset(store->normal_stamp[k], 0,
                       store->normal_count[k] * sizeof *store->normal_stamp[k]);
        store->stamp = 2;
    }
    selfcol_store_update_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_STORE_UPDATE_STATS_VERSION;

    // 1. Merge the held entries (sorted) with the records (sorted), chunk
    // by chunk of keys: kept, new, remnant or dropped; sides and link codes;
    // each chunk's vertex pairs counted into its buckets.
    job.out = store->spare;
    memset(store->bucket_offset, 0,
           job.chunks * store->bucket_count * sizeof *store->bucket_offset);
    run_stage(&job, STAGE_MERGE);
    for (size_t c = 0; c < job.chunks; ++c) {
        const selfcol_store_update_stats *cs = &job.stats[c];
        st.contacts += cs->contacts;
        st.interferences += cs->interferences;
        st.new_contacts += cs->new_contacts;
        st.kept += cs->kept;
        st.remnant += cs->remnant;
        st.dropped += cs->dropped;
        st.flipped += cs->flipped;
        st.passed_around += cs->passed_around;
    }
    const size_t old_count = store->count;
    store->spare = store->entries;
    store->entries = job.out;
    store->count = kept_entries;

    // 2. Regions and voting groups: the vertex pairs sorted by bucket,
    // chunk by chunk of the entries (stable), then linked in one thread.
    bucket_starts(store, job.chunks);
    run_stage(&job, STAGE_SORT);
    const uint32_t *bucket_end = store->bucket_offset + (job.chunks - 1) * store->bucket_count;
    job.pairs = keys;
    const size_t group_chunks = chunks_for(keys, store->threads);
    link_neighbours(store, bucket_end, group_chunks == 1);
    if (group_chunks > 1) {
        job.chunks = group_chunks;
        run_stage(&job, STAGE_GROUP);
    }
    // 3. The vote.
    const size_t regions = tally_and_label(store, &st);
    status = reserve_regions(store, regions);
    if (status != SELFCOL_OK) { // the store as it was
        store->entries = store->spare;
        store->spare = job.out;
        store->count = old_count;
        store->meshes[0] = old_meshes[0];
        store->meshes[1] = old_meshes[1];
        return status;
    }
    impose(store, regions, &st);
    store->region_count = regions;
    store->identity[0] = first->identity;
    store->positions_version[0] = first->positions_version;
    if (second != NULL) {
        store->identity[1] = second->identity;
        store->positions_version[1] = second->positions_version;
    }
    st.seconds = selfcol_core__seconds() - start;
    store->stats = st;
    return SELFCOL_OK;
}

size_t selfcol_store_contact_count(const selfcol_store *store) {
    return store != NULL ? store->count : 0;
}

int selfcol_store_copy_contacts(const selfcol_store *store, size_t first_index, size_t count,
                                selfcol_store_contact *out) {
    SELFCOL_CHECK(store != NULL && (out != NULL || count == 0));
    SELFCOL_CHECK(first_index <= store->count && count <= store->count - first_index);
    if (count == 0)
        return SELFCOL_OK;
    // The geometry is computed now, from the positions the last update saw:
    // the meshes must not have moved since (or been replaced).
    for (int k = 0; k < 2; ++k) {
        const selfcol_mesh *m = store->meshes[k];
        if (m == NULL)
            continue;
        if (!selfcol_mesh__is(m, &store->identity[k]))
            return SELFCOL_EMISMATCH;
        if (m->positions_version != store->positions_version[k])
            return SELFCOL_ESTALE;
    }
    for (size_t x = 0; x < count; ++x) {
        const store_entry *e = &store->entries[first_index + x];
        selfcol_store_contact *c = &out[x];
        memset(c, 0, sizeof *c); // the padding too: records compare bytewise
        uint32_t a[2], b[3];
        entry_vertices(store, e, a, b);
        selfcol_narrow_result r;
        geometry(store, e, a, b, &r);
        c->kind = e->kind;
        c->first = e->first;
        c->second = e->second;
        c->first_mesh = first_mesh(e);
        c->second_mesh = second_mesh(e);
        memcpy(c->a, a, sizeof c->a);
        memcpy(c->b, b, sizeof c->b);
        c->region = e->region;
        c->age = e->age;
        c->missed = e->missed;
        c->flags = e->flags;
        c->side = side_of(e);
        c->right_side = right_side_of(e);
        c->distance = r.distance;
        const int wrong = c->side != 0 && c->right_side != 0 && c->side != c->right_side;
        c->signed_distance = wrong ? -r.distance : r.distance;
        memcpy(c->wa, r.wa, sizeof c->wa);
        memcpy(c->wb, r.wb, sizeof c->wb);
        memcpy(c->direction, r.direction, sizeof c->direction);
    }
    return SELFCOL_OK;
}

int selfcol_store_regions(const selfcol_store *store, const selfcol_store_region **data_out,
                          size_t *count_out) {
    SELFCOL_CHECK(store != NULL && data_out != NULL && count_out != NULL);
    *data_out = store->region_count > 0 ? store->regions : NULL;
    *count_out = store->region_count;
    return SELFCOL_OK;
}

int selfcol_store_stats(const selfcol_store *store, selfcol_store_update_stats *stats) {
    SELFCOL_CHECK(store != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_STORE_UPDATE_STATS_VERSION)
        return SELFCOL_EVERSION;
    const unsigned version = stats->version;
    // A version 1 caller's struct ends before passed_around.
    memcpy(stats, &store->stats,
           version >= 2 ? sizeof *stats : offsetof(selfcol_store_update_stats, passed_around));
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_store_byte_count(const selfcol_store *store) {
    if (store == NULL)
        return 0;
    const size_t per_entry =
        2 * sizeof(store_entry) + 2 * sizeof(uint32_t) + sizeof(int8_t) + sizeof(uint16_t);
    size_t bytes = sizeof *store + store->capacity * per_entry +
                   store->pair_capacity * 2 * sizeof(uint32_t) +
                   store->region_capacity * sizeof(selfcol_store_region);
    if (store->bucket_offset != NULL)
        bytes += store->threads * store->bucket_count * sizeof(uint32_t);
    for (int k = 0; k < 2; ++k)
        bytes += store->normal_count[k] * (3 * sizeof(float) + sizeof(uint32_t)) +
                 store->hi_count[k] * 2 * sizeof(uint32_t);
    return bytes;
}
