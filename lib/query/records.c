// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "query/records.h"

#include "base/alloc.h"
#include "base/core.h"

#include <stddef.h>
#include <string.h>

void selfcol_records__init(selfcol_records *r, const selfcol_allocator *allocator) {
    memset(r, 0, sizeof *r);
    r->allocator = *allocator;
    r->stats.version = SELFCOL_QUERY_STATS_VERSION;
}

void selfcol_records__free(selfcol_records *r) {
    selfcol_alloc__free_array(&r->allocator, r->items, r->capacity, sizeof(selfcol_contact));
    selfcol_alloc__free_array(&r->allocator, r->spare, r->spare_capacity, sizeof(selfcol_contact));
    selfcol_allocator allocator = r->allocator;
    selfcol_records__init(r, &allocator);
}

void selfcol_records__clear(selfcol_records *r) {
    r->count = 0;
    r->generation++;
    memset(&r->stats, 0, sizeof r->stats);
    r->stats.version = SELFCOL_QUERY_STATS_VERSION;
}

size_t selfcol_records__byte_count(const selfcol_records *r) {
    return (r->capacity + r->spare_capacity) * sizeof(selfcol_contact);
}

// absorb adds every field up to sort_seconds: a field appended to the
// statistics must be added there too (this fails to compile until it is).
typedef char
    stats_fields_all_absorbed[offsetof(selfcol_query_stats, sort_seconds) + sizeof(double) ==
                                      sizeof(selfcol_query_stats)
                                  ? 1
                                  : -1];

// Room for `extra` more records, growing geometrically (at least 64).
static int reserve_records(selfcol_records *c, size_t extra) {
    if (extra <= c->capacity - c->count)
        return SELFCOL_OK;
    if (extra > SIZE_MAX / sizeof(selfcol_contact) - c->count)
        return SELFCOL_ENOMEM;
    size_t need = c->count + extra;
    size_t capacity = c->capacity < 64 ? 64 : 2 * c->capacity;
    capacity = capacity > need ? capacity : need;
    // Grown in place where the allocator can (a query's records double
    // about a dozen times: copying them was a third of a cold query's page
    // faults, perf on cloth-ball 92).
    selfcol_contact *items = selfcol_alloc__grow_array(
        &c->allocator, c->items, c->count, c->capacity, capacity, sizeof(selfcol_contact));
    if (items == NULL)
        return SELFCOL_ENOMEM;
    c->items = items;
    c->capacity = capacity;
    return SELFCOL_OK;
}

void selfcol_records__absorb_stats(selfcol_records *c, const selfcol_records *worker) {
    selfcol_query_stats *to = &c->stats;
    const selfcol_query_stats *from = &worker->stats;
    to->candidate_pairs += from->candidate_pairs;
    to->vf_tests += from->vf_tests;
    to->ee_tests += from->ee_tests;
    to->ef_tests += from->ef_tests;
    to->vf_contacts += from->vf_contacts;
    to->ee_contacts += from->ee_contacts;
    to->ef_contacts += from->ef_contacts;
    to->nodes_visited += from->nodes_visited;
    to->culled_box += from->culled_box;
    to->culled_curvature += from->culled_curvature;
    to->culled_adjacency += from->culled_adjacency;
    to->triangle_pairs += from->triangle_pairs;
    to->contour_tests += from->contour_tests;
    to->contour_refused += from->contour_refused;
    to->contour_seconds += from->contour_seconds;
    to->pairs_separated += from->pairs_separated;
    to->primitives_filtered += from->primitives_filtered;
}

int selfcol_records__push(selfcol_records *c, const selfcol_contact *contact) {
    if (c->count == c->capacity && reserve_records(c, 1) != SELFCOL_OK)
        return SELFCOL_ENOMEM;
    c->items[c->count++] = *contact;
    return SELFCOL_OK;
}

static int contact_less(const selfcol_contact *a, const selfcol_contact *b) {
    const uint32_t ka[5] = {a->kind, a->first_mesh, a->first, a->second_mesh, a->second};
    const uint32_t kb[5] = {b->kind, b->first_mesh, b->first, b->second_mesh, b->second};
    for (int i = 0; i < 5; ++i)
        if (ka[i] != kb[i])
            return ka[i] < kb[i];
    return 0;
}

// Sort keys: (kind, first_mesh, first) in hi (35 bits) and (second_mesh,
// second) in lo (33 bits); an LSD radix sort on lo, then on hi, orders the
// records lexicographically. Digits of 11 bits: 3 passes cover lo, 4 cover
// hi, and a pass whose digit is the same for every key is skipped (indices
// of a 100k-triangle mesh need 2 of the 3, a self query none of the mesh
// bits), so a typical sort makes 5 passes over 24-byte items.
typedef struct sort_item {
    uint64_t hi, lo;
    uint64_t index; // the record: its source << SOURCE_SHIFT | its index there
} sort_item;

// The records to sort can come from several sets (the caller's and the
// pending worker sets of a threaded query): source k's records are global items
// begin[k] to begin[k + 1] - 1, and an item's index names its source and
// its place there, so the permutation reads each record where it lies.
#define SOURCE_SHIFT 48
#define MAX_SOURCES (SELFCOL_MAX_THREADS + 1)

#define RADIX_BITS 11
#define RADIX_SIZE (1u << RADIX_BITS)
#define RADIX_PASSES 7 // 3 over lo, then 4 over hi

static uint32_t digit_of(const sort_item *it, int pass) {
    uint64_t key = pass < 3 ? it->lo : it->hi;
    int shift = RADIX_BITS * (pass < 3 ? pass : pass - 3);
    return (uint32_t)(key >> shift) & (RADIX_SIZE - 1u);
}

// On threads (the query's count), the keys are built, counted and
// scattered in chunks of the array: each chunk keeps its own bucket counts,
// and a bucket's slots are laid out chunk by chunk, so every item lands
// where the one-chunk sort puts it (an LSD radix sort is stable), whatever
// the number of chunks. A pass's histogram over the whole array does not
// depend on the order, so the build's counts decide which passes to skip;
// a chunk's counts do, so each chunk counts again before every pass but the
// first it makes. Chunks are tasks handed out by a counter (a worker that
// could not be started leaves its chunks to the others).

// Items per chunk at least: below that, starting threads (twice per pass)
// costs about what the chunk's share of the sort does. Waking a pool's
// threads or a scheduler's costs far less (pool.h): a quarter of it then.
#define SORT_MIN_CHUNK 65536u
#define SORT_MIN_CHUNK_KEPT_THREADS 16384u

enum { SORT_BUILD, SORT_COUNT, SORT_SCATTER, SORT_PERMUTE };

typedef struct sort_job {
    selfcol_records *c;
    const selfcol_contact *source[MAX_SOURCES];
    size_t begin[MAX_SOURCES + 1]; // global index of each source's first record
    unsigned sources;
    sort_item *items, *other;
    size_t *count; // count[(chunk * RADIX_PASSES + pass) * RADIX_SIZE + digit]
    size_t n;
    unsigned chunks;
    const selfcol_executor *executor;
    int stage, pass;
    uint32_t next_chunk; // atomic task counter
} sort_job;

static size_t *chunk_counts(const sort_job *job, unsigned chunk, int pass) {
    return job->count + ((size_t)chunk * RADIX_PASSES + (size_t)pass) * RADIX_SIZE;
}

static void sort_chunk(sort_job *job, unsigned chunk) {
    // Chunk k: n / chunks items, one more for the first n % chunks chunks.
    const size_t share = job->n / job->chunks, extra = job->n % job->chunks;
    const size_t begin = share * chunk + (chunk < extra ? chunk : extra);
    const size_t end = begin + share + (chunk < extra);
    sort_item *items = job->items;
    switch (job->stage) {
    case SORT_BUILD: {
        size_t *count = chunk_counts(job, chunk, 0);
        memset(count, 0, RADIX_PASSES * RADIX_SIZE * sizeof *count);
        unsigned k = 0;
        while (job->begin[k + 1] <= begin && k + 1 < job->sources)
            ++k;
        for (size_t i = begin; i < end; ++i) {
            while (i >= job->begin[k + 1])
                ++k;
            const size_t local = i - job->begin[k];
            const selfcol_contact *r = &job->source[k][local];
            sort_item *it = &items[i];
            it->hi = ((uint64_t)(r->kind * 2u + r->first_mesh) << 32) | r->first;
            it->lo = ((uint64_t)r->second_mesh << 32) | r->second;
            it->index = (uint64_t)k << SOURCE_SHIFT | local;
            for (int pass = 0; pass < RADIX_PASSES; ++pass)
                count[pass * RADIX_SIZE + digit_of(it, pass)]++;
        }
        break;
    }
    case SORT_COUNT: {
        size_t *count = chunk_counts(job, chunk, job->pass);
        memset(count, 0, RADIX_SIZE * sizeof *count);
        for (size_t i = begin; i < end; ++i)
            count[digit_of(&items[i], job->pass)]++;
        break;
    }
    case SORT_SCATTER: {
        size_t *slot = chunk_counts(job, chunk, job->pass); // offsets by now
        for (size_t i = begin; i < end; ++i)
            job->other[slot[digit_of(&items[i], job->pass)]++] = items[i];
        break;
    }
    default: { // SORT_PERMUTE
        const uint64_t local_mask = ((uint64_t)1 << SOURCE_SHIFT) - 1u;
        for (size_t i = begin; i < end; ++i) {
            const uint64_t at = items[i].index;
            job->c->spare[i] = job->source[at >> SOURCE_SHIFT][at & local_mask];
        }
        break;
    }
    }
}

static int sort_worker(void *context, unsigned worker) {
    (void)worker;
    sort_job *job = context;
    for (;;) {
        uint32_t chunk = SELFCOL_ATOMIC_FETCH_ADD(&job->next_chunk, 1u);
        if (chunk >= job->chunks)
            return SELFCOL_OK;
        sort_chunk(job, chunk);
    }
}

static void sort_stage(sort_job *job, int stage, int pass) {
    job->stage = stage;
    job->pass = pass;
    job->next_chunk = 0;
    if (job->chunks == 1)
        sort_chunk(job, 0);
    else
        (void)selfcol_parallel__run(job->executor, job->chunks, sort_worker, job);
}

int selfcol_records__sort(selfcol_records *c, selfcol_records *const *pending_sets,
                          unsigned pending, selfcol_workspace *work,
                          const selfcol_executor *executor, unsigned threads) {
    // The caller's records, then those of the pending worker sets.
    sort_job job;
    memset(&job, 0, sizeof job);
    job.source[0] = c->items;
    job.begin[1] = c->count;
    job.sources = 1;
    for (unsigned w = 0; w < pending; ++w) {
        const selfcol_records *worker = pending_sets[w];
        job.source[job.sources] = worker->items;
        job.begin[job.sources + 1] = job.begin[job.sources] + worker->count;
        job.sources++;
    }
    size_t n = job.begin[job.sources];
    if (pending > 0 && n < 2) { // nothing to order: the record, if any, joins c's
        for (unsigned w = 0; w < pending; ++w) {
            selfcol_records *worker = pending_sets[w];
            if (worker->count > 0) {
                if (reserve_records(c, worker->count) != SELFCOL_OK)
                    return SELFCOL_ENOMEM;
                memcpy(c->items + c->count, worker->items, worker->count * sizeof *c->items);
                c->count += worker->count;
                worker->count = 0;
            }
        }
        return SELFCOL_OK;
    }
    if (pending == 0) {
        size_t i = 1;
        while (i < n && !contact_less(&c->items[i], &c->items[i - 1]))
            ++i;
        if (i >= n)
            return SELFCOL_OK; // already sorted (the exhaustive search emits in order)
    }
    const int kept = executor != NULL && (executor->pool != NULL || executor->enqueue_task != NULL);
    const size_t most = n / (kept ? SORT_MIN_CHUNK_KEPT_THREADS : SORT_MIN_CHUNK);
    const unsigned chunks = most < 2 ? 1u : threads < most ? threads : (unsigned)most;
    const size_t count_bytes = (size_t)chunks * RADIX_PASSES * RADIX_SIZE * sizeof(size_t);
    if (n > (SIZE_MAX - count_bytes) / (2 * sizeof(sort_item)))
        return SELFCOL_ENOMEM;
    size_t bytes = 2 * n * sizeof(sort_item) + count_bytes;
    sort_item *items = selfcol_workspace__buffer(work, SELFCOL_SCRATCH_SORT, bytes, 0);
    if (items == NULL)
        return SELFCOL_ENOMEM;
    const size_t want = n > c->capacity ? n : c->capacity;
    if (c->spare_capacity < want) {
        selfcol_contact *spare = selfcol_alloc__array(&c->allocator, want, sizeof *spare);
        if (spare == NULL)
            return SELFCOL_ENOMEM;
        selfcol_alloc__free_array(&c->allocator, c->spare, c->spare_capacity, sizeof *spare);
        c->spare = spare;
        c->spare_capacity = want;
    }
    job.c = c;
    job.executor = executor;
    job.items = items;
    job.other = items + n;
    job.count = (size_t *)(items + 2 * n);
    job.n = n;
    job.chunks = chunks;
    sort_stage(&job, SORT_BUILD, 0);
    int scattered = 0;
    for (int pass = 0; pass < RADIX_PASSES; ++pass) {
        // A pass's counts are the build's until the pass itself: their sum
        // over the chunks is the histogram of any order.
        const uint32_t first_digit = digit_of(&job.items[0], pass);
        size_t same = 0;
        for (unsigned k = 0; k < chunks; ++k)
            same += chunk_counts(&job, k, pass)[first_digit];
        if (same == n)
            continue; // every key has this digit
        if (scattered && chunks > 1)
            sort_stage(&job, SORT_COUNT, pass); // each chunk's, in the current order
        // Offsets: bucket by bucket, chunk by chunk inside a bucket.
        size_t sum = 0;
        for (uint32_t b = 0; b < RADIX_SIZE; ++b)
            for (unsigned k = 0; k < chunks; ++k) {
                size_t *slot = &chunk_counts(&job, k, pass)[b];
                size_t here = *slot;
                *slot = sum;
                sum += here;
            }
        sort_stage(&job, SORT_SCATTER, pass);
        sort_item *swap = job.items;
        job.items = job.other;
        job.other = swap;
        scattered = 1;
    }
    sort_stage(&job, SORT_PERMUTE, 0);
    selfcol_contact *swap = c->items;
    c->items = c->spare;
    c->spare = swap;
    size_t capacity = c->capacity;
    c->capacity = c->spare_capacity;
    c->spare_capacity = capacity;
    c->count = n;
    for (unsigned w = 0; w < pending; ++w)
        pending_sets[w]->count = 0; // taken in
    return SELFCOL_OK;
}
