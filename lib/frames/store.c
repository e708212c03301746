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
// On a context's threads (selfcol_context_store_update), step 1 runs in chunks of
// keys (each merging its ranges of held entries and records into a place
// counted beforehand by a dry run), the vertex pairs are sorted in chunks
// of entries with per-chunk bucket counts (both stable), and the grouping
// union-find runs on threads (its roots do not depend on the link order);
// the voting links, whose order decides conflicting cycles, and the vote
// stay in one thread. The store is the same for every thread count.
// Files: this one (the handle, the update's stages, the reads),
// store_sides.c (sides and geometry), store_regions.c (neighbours, regions,
// the vote); store_entry.h the entry and the handle they share.
#include <selfcol/hierarchy.h>
#include <selfcol/store.h>

#include "base/alloc.h"
#include "base/core.h"
#include "base/parallel.h"
#include "base/predicates.h"
#include "base/problem.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "frames/store.h"
#include "frames/store_entry.h"
#include "mesh/mesh.h"
#include "narrow/narrow.h"
#include "narrow/narrow_sweep.h"
#include "query/contacts.h"
#include "query/context.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

// ---------------------------------------------------------------------------
// Creation and memory

int selfcol_store_options_init(selfcol_store_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    // Versions 1 and 2 were 0.3's layouts (2 with threads).
    if (version < SELFCOL_STORE_OPTIONS_VERSION || version > SELFCOL_STORE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->remnance_frames = SELFCOL_STORE_DEFAULT_REMNANCE;
    opts->consistency = 1;
    return SELFCOL_OK;
}

int selfcol_store__options(selfcol_store_options *out, const selfcol_store_options *opts,
                           const selfcol_problem_at *at) {
    if (opts != NULL) {
        const int version = selfcol_problem__version_since(
            at, opts->version, SELFCOL_STORE_OPTIONS_VERSION, SELFCOL_STORE_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
    }
    selfcol_store_options_init(out, SELFCOL_STORE_OPTIONS_VERSION);
    if (opts != NULL)
        *out = *opts;
    out->version = SELFCOL_STORE_OPTIONS_VERSION;
    SELFCOL_CHECK_ALLOCATOR(at, out->allocator);
    SELFCOL_CHECK_FIELD(at, out->consistency == 0 || out->consistency == 1, "consistency",
                        "= %d is not 0 or 1", out->consistency);
    SELFCOL_CHECK_FIELD(at, out->first_orientation >= -1 && out->first_orientation <= 1,
                        "first_orientation", "= %d is not -1, 0 or +1", out->first_orientation);
    SELFCOL_CHECK_FIELD(at, out->second_orientation >= -1 && out->second_orientation <= 1,
                        "second_orientation", "= %d is not -1, 0 or +1", out->second_orientation);
    return SELFCOL_OK;
}

int selfcol_store_options_check(const selfcol_store_options *opts,
                                selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_store_options", ""};
    selfcol_store_options checked;
    return selfcol_store__options(&checked, opts, &at);
}

int selfcol_store_create(selfcol_store **out, const selfcol_store_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    selfcol_store_options o;
    const int checked = selfcol_store__options(&o, opts, NULL);
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
    s->threads = 1;
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
    selfcol_alloc__free_array(al, s->bucket_offset, s->bucket_threads * s->bucket_count,
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
    // Per chunk (at most the update's threads) and bucket: grown only, in
    // both directions, so that a steady state allocates nothing.
    const size_t need = buckets_of(meshes);
    const size_t buckets = need > s->bucket_count ? need : s->bucket_count;
    const unsigned threads = s->threads > s->bucket_threads ? s->threads : s->bucket_threads;
    if (s->bucket_offset == NULL || buckets > s->bucket_count || threads > s->bucket_threads) {
        uint32_t *offset = selfcol_alloc__array(al, (size_t)threads * buckets, sizeof *offset);
        if (offset == NULL)
            return SELFCOL_ENOMEM;
        selfcol_alloc__free_array(al, s->bucket_offset, s->bucket_threads * s->bucket_count,
                                  sizeof *s->bucket_offset);
        s->bucket_offset = offset;
        s->bucket_count = buckets;
        s->bucket_threads = threads;
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
        keys += (size_t)selfcol_store__pairs_of_kind(kind);
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
        selfcol_store__count_pairs(s, count, e, a, b);
        selfcol_store__track_side(s, e, a, b, st);
        s->link_code[n] = 0;
        if (e->kind != SELFCOL_CONTACT_EF && !(e->flags & SELFCOL_STORE_ORIENTED)) {
            selfcol_narrow_result r;
            if (direction == NULL) { // a remnant's, at the current positions
                selfcol_store__geometry(s, e, a, b, &r);
                direction = r.direction;
            }
            s->link_code[n] = selfcol_store__link_code(s, e, a, b, direction);
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
    selfcol_store__sort_pairs(s, c, lo, hi);
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
            selfcol_store__group_unite_shared(s->group_parent, i, j);
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
// of the update's executor (the calling thread alone for one chunk).
static void run_stage(update_job *job, enum update_stage stage) {
    job->stage = stage;
    job->next_chunk = 0;
    const unsigned workers =
        job->chunks < job->s->threads ? (unsigned)job->chunks : job->s->threads;
    if (workers <= 1)
        update_worker(job, 0);
    else
        selfcol_parallel__run(job->s->executor, workers, update_worker, job);
}

static int update(selfcol_store *store, const selfcol_mesh *first, const selfcol_mesh *second,
                  const selfcol_contacts *detected);

// selfcol_store_update_swept's checks, then the update with the step's start.
static int update_swept(selfcol_store *store, const selfcol_mesh *first, const selfcol_mesh *second,
                        const selfcol_contacts *detected, const double *first_start,
                        const double *second_start) {
    SELFCOL_CHECK(store != NULL && first != NULL && detected != NULL && first_start != NULL);
    SELFCOL_CHECK((second == NULL) == (second_start == NULL));
    SELFCOL_CHECK(selfcol_mesh__positions_in_contract(first_start, first->vertex_count));
    SELFCOL_CHECK(second == NULL ||
                  selfcol_mesh__positions_in_contract(second_start, second->vertex_count));
    store->step_start[0] = first_start;
    store->step_start[1] = second_start;
    const int status = update(store, first, second, detected);
    store->step_start[0] = store->step_start[1] = NULL;
    return status;
}

// An update (swept when first_start is given) on `context`'s threads, or on
// the calling thread for NULL: the store holds them for the call only.
static int update_on(selfcol_context *context, selfcol_store *store, const selfcol_mesh *first,
                     const selfcol_mesh *second, const selfcol_contacts *detected, int swept,
                     const double *first_start, const double *second_start) {
    SELFCOL_CHECK(store != NULL);
    store->threads = context != NULL ? context->threads : 1;
    store->executor = context != NULL ? &context->executor : NULL;
    const int status = swept
                           ? update_swept(store, first, second, detected, first_start, second_start)
                           : update(store, first, second, detected);
    store->threads = 1;
    store->executor = NULL;
    return status;
}

int selfcol_store_update(selfcol_store *store, const selfcol_mesh *first,
                         const selfcol_mesh *second, const selfcol_contacts *detected) {
    return update_on(NULL, store, first, second, detected, 0, NULL, NULL);
}

int selfcol_store_update_swept(selfcol_store *store, const selfcol_mesh *first,
                               const selfcol_mesh *second, const selfcol_contacts *detected,
                               const double *first_start, const double *second_start) {
    return update_on(NULL, store, first, second, detected, 1, first_start, second_start);
}

int selfcol_context_store_update(selfcol_context *context, selfcol_store *store,
                                 const selfcol_mesh *first, const selfcol_mesh *second,
                                 const selfcol_contacts *detected) {
    SELFCOL_CHECK(context != NULL);
    return update_on(context, store, first, second, detected, 0, NULL, NULL);
}

int selfcol_context_store_update_swept(selfcol_context *context, selfcol_store *store,
                                       const selfcol_mesh *first, const selfcol_mesh *second,
                                       const selfcol_contacts *detected, const double *first_start,
                                       const double *second_start) {
    SELFCOL_CHECK(context != NULL);
    return update_on(context, store, first, second, detected, 1, first_start, second_start);
}

int selfcol_store__update_path(selfcol_context *context, selfcol_store *store,
                               const selfcol_mesh *first, const selfcol_mesh *second,
                               const selfcol_contacts *detected, const double *const first_path[2],
                               const double *const second_path[2]) {
    SELFCOL_CHECK(store != NULL && first_path != NULL && first_path[0] != NULL);
    SELFCOL_CHECK((second == NULL) == (second_path == NULL));
    SELFCOL_CHECK(second_path == NULL || second_path[0] != NULL);
    store->step_before[0] = first_path[0];
    store->step_before[1] = second_path != NULL ? second_path[0] : NULL;
    const int status = update_on(context, store, first, second, detected, 1, first_path[1],
                                 second_path != NULL ? second_path[1] : NULL);
    store->step_before[0] = store->step_before[1] = NULL;
    return status;
}

static int update(selfcol_store *store, const selfcol_mesh *first, const selfcol_mesh *second,
                  const selfcol_contacts *detected) {
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
    selfcol_store__bucket_starts(store, job.chunks);
    run_stage(&job, STAGE_SORT);
    const uint32_t *bucket_end = store->bucket_offset + (job.chunks - 1) * store->bucket_count;
    job.pairs = keys;
    const size_t group_chunks = chunks_for(keys, store->threads);
    selfcol_store__link_neighbours(store, bucket_end, group_chunks == 1);
    if (group_chunks > 1) {
        job.chunks = group_chunks;
        run_stage(&job, STAGE_GROUP);
    }
    // 3. The vote.
    const size_t regions = selfcol_store__tally_and_label(store, &st);
    status = reserve_regions(store, regions);
    if (status != SELFCOL_OK) { // the store as it was
        store->entries = store->spare;
        store->spare = job.out;
        store->count = old_count;
        store->meshes[0] = old_meshes[0];
        store->meshes[1] = old_meshes[1];
        return status;
    }
    selfcol_store__impose(store, regions, &st);
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
        selfcol_store__geometry(store, e, a, b, &r);
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
        bytes += store->bucket_threads * store->bucket_count * sizeof(uint32_t);
    for (int k = 0; k < 2; ++k)
        bytes += store->normal_count[k] * (3 * sizeof(float) + sizeof(uint32_t)) +
                 store->hi_count[k] * 2 * sizeof(uint32_t);
    return bytes;
}
