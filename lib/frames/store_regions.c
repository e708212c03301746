// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact store: neighbours (entries sharing a vertex pair), the
// regions and the voting groups (union-finds), and the vote (store.c's
// steps 2 and 3; the method: store.c's opening comment).
#include "base/alloc.h"
#include "base/core.h"
#include "base/parallel.h"
#include "base/predicates.h"
#include "base/union_find.h"
#include "base/vec3.h"
#include "frames/store.h"
#include "frames/store_entry.h"
#include "mesh/mesh.h"
#include "narrow/narrow.h"
#include "narrow/narrow_sweep.h"
#include "query/contacts.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

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

void selfcol_store__group_unite_shared(uint32_t *parent, uint32_t x, uint32_t y) {
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
            selfcol_store__add_triangle_normal(m, m->vertex_tris[k], n);
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
int selfcol_store__pairs_of_kind(uint32_t kind) {
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

uint16_t selfcol_store__link_code(selfcol_store *s, const store_entry *e, const uint32_t a[2],
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
    const int pairs = selfcol_store__pairs_of_kind(e->kind);
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
// before (mw, w). An entry has selfcol_store__pairs_of_kind() of them, taken in the order
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
void selfcol_store__count_pairs(const selfcol_store *s, uint32_t *count, const store_entry *e,
                                const uint32_t a[2], const uint32_t b[3]) {
    const size_t n0 = s->meshes[0]->vertex_count;
    const int pairs = selfcol_store__pairs_of_kind(e->kind);
    for (int k = 0; k < pairs; ++k)
        count[pair_of(e, a, b, k, n0).bucket]++;
}

// The counts of every chunk (bucket_offset) become the position where the
// chunk writes its first occurrence of each bucket: buckets in order, and
// inside a bucket the chunks in order, so the sort is stable whatever the
// number of chunks.
void selfcol_store__bucket_starts(selfcol_store *s, size_t chunks) {
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
void selfcol_store__sort_pairs(selfcol_store *s, size_t c, size_t lo, size_t hi_index) {
    const size_t n0 = s->meshes[0]->vertex_count;
    uint32_t *off = s->bucket_offset + c * s->bucket_count, *hi = s->pair_hi,
             *entry = s->pair_entry;
    for (uint32_t i = (uint32_t)lo; i < hi_index; ++i) {
        const store_entry *e = &s->entries[i];
        uint32_t a[2], b[3];
        entry_vertices(s, e, a, b);
        const unsigned code = s->link_code[i];
        const int pairs = selfcol_store__pairs_of_kind(e->kind);
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
void selfcol_store__link_neighbours(selfcol_store *s, const uint32_t *bucket_end, int group_here) {
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
size_t selfcol_store__tally_and_label(selfcol_store *s, selfcol_store_update_stats *st) {
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
void selfcol_store__impose(selfcol_store *s, size_t regions, selfcol_store_update_stats *st) {
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
