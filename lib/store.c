// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The persistent contact store (include/selfcol/store.h): section 3 of
// Volino & Magnenat Thalmann (1995). One update is linear in the contacts:
//  1. a merge of the held entries and the query's records, both sorted by
//     key (kind, first_mesh, first, second_mesh, second): kept, new,
//     remnant (geometry recomputed by the closed-form narrow phase) or
//     dropped; the side of every VF/EE entry is the exact sign of orient3d;
//  2. regions: each entry hashes the unordered pairs {u, w} of a vertex u of
//     its first element and a vertex w of its second (at most 6); entries
//     sharing a pair are neighbours. A grouping union-find over all entries
//     gives the regions; a second one, with parity, over VF/EE links whose
//     sides read clearly through the surface normals, gives the voting
//     groups (seed 3.2.1's labelling, without its recursion);
//  3. the vote per group and the region records.
// Every array is kept and grown geometrically: a steady state allocates
// nothing.
#include <selfcol/store.h>

#include "alloc.h"
#include "contacts.h"
#include "core.h"
#include "mesh.h"
#include "narrow.h"
#include "predicates.h"
#include "store.h"
#include "union_find.h"
#include "vec3.h"

#include <math.h>
#include <string.h>

struct selfcol_store {
    selfcol_allocator allocator;
    uint32_t remnance;
    int consistency;
    int orientation[2];            // per mesh slot: 0 none, +1 / -1 (store.h)
    const selfcol_mesh *meshes[2]; // meshes[0] NULL until the first update after create or clear
    selfcol_mesh_identity identity[2]; // of meshes[], from the same update

    selfcol_store_contact *entries, *spare; // held entries; the merge's destination
    size_t count, capacity;                 // capacity of both arrays

    // Per entry (capacity): the regions (at most one per entry), the grouping
    // union-find, the voting union-find with parity.
    selfcol_store_region *regions;
    size_t region_count;
    uint32_t *group_parent, *vote_parent, *label;
    int8_t *vote_parity;
    // Per voting group root: vote counts (4: +1 and -1, of new contacts and
    // of held ones), tie-break entry.
    int32_t *tally;
    uint32_t *oldest;

    // The neighbour search (link_neighbours): one key per vertex pair {u, w}
    // an entry produces, radix-sorted with its occurrence number, and per
    // occurrence the entry that produced its key first (entry << 1 | whether
    // that entry's first element held the pair's lower end). pair_capacity
    // occurrences each.
    uint64_t *pair_key[2]; // the sort's two halves
    uint32_t *pair_occ[2];
    uint64_t *pair_first;
    size_t pair_capacity;

    // Per mesh slot: the surface normal at each vertex (vertex_normal), kept
    // for one update: valid where normal_stamp equals stamp. Sized to the
    // mesh's vertices at its first update (a store's meshes are fixed until
    // selfcol_store_clear), so no update clears them.
    float *normals[2];
    uint32_t *normal_stamp[2];
    size_t normal_count[2];
    uint32_t stamp;

    selfcol_store_update_stats stats;
};

int selfcol_store_options_init(selfcol_store_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_STORE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->remnance_frames = SELFCOL_STORE_DEFAULT_REMNANCE;
    opts->consistency = 1;
    return SELFCOL_OK;
}

int selfcol_store__options(selfcol_store_options *out, const selfcol_store_options *opts) {
    SELFCOL_CHECK_VERSION(opts, SELFCOL_STORE_OPTIONS_VERSION);
    selfcol_store_options_init(out, SELFCOL_STORE_OPTIONS_VERSION);
    if (opts != NULL)
        *out = *opts; // version 1 is the only layout so far
    out->version = SELFCOL_STORE_OPTIONS_VERSION;
    SELFCOL_CHECK(selfcol_alloc__valid(&out->allocator));
    SELFCOL_CHECK(out->consistency == 0 || out->consistency == 1);
    SELFCOL_CHECK(out->first_orientation >= -1 && out->first_orientation <= 1);
    SELFCOL_CHECK(out->second_orientation >= -1 && out->second_orientation <= 1);
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
    selfcol_alloc__free_array(al, s->label, n, sizeof *s->label);
    selfcol_alloc__free_array(al, s->vote_parity, n, sizeof *s->vote_parity);
    selfcol_alloc__free_array(al, s->tally, 4 * n, sizeof *s->tally);
    selfcol_alloc__free_array(al, s->oldest, n, sizeof *s->oldest);
    selfcol_alloc__free_array(al, s->regions, n, sizeof *s->regions);
}

static void free_pair_arrays(selfcol_store *s) {
    const selfcol_allocator *al = &s->allocator;
    const size_t n = s->pair_capacity;
    for (int k = 0; k < 2; ++k) {
        selfcol_alloc__free_array(al, s->pair_key[k], n, sizeof *s->pair_key[k]);
        selfcol_alloc__free_array(al, s->pair_occ[k], n, sizeof *s->pair_occ[k]);
        s->pair_key[k] = NULL;
        s->pair_occ[k] = NULL;
    }
    selfcol_alloc__free_array(al, s->pair_first, n, sizeof *s->pair_first);
    s->pair_first = NULL;
    s->pair_capacity = 0;
}

// Grown capacities: the need plus a half, so that a sequence whose contact
// count creeps up reallocates rarely (and a steady state never).
static size_t grown_capacity(size_t need) {
    return need + need / 2 + 64;
}

void selfcol_store_destroy(selfcol_store *store) {
    if (store == NULL)
        return;
    selfcol_allocator al = store->allocator;
    free_entry_arrays(store);
    free_pair_arrays(store);
    for (int k = 0; k < 2; ++k) {
        selfcol_alloc__free_array(&al, store->normals[k], 3 * store->normal_count[k],
                                  sizeof *store->normals[k]);
        selfcol_alloc__free_array(&al, store->normal_stamp[k], store->normal_count[k],
                                  sizeof *store->normal_stamp[k]);
    }
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
    if (n > UINT32_MAX - 1)
        return SELFCOL_ERANGE; // entries are indexed by uint32_t
    size_t cap = grown_capacity(n);
    if (cap > UINT32_MAX - 1)
        cap = UINT32_MAX - 1;
    const selfcol_allocator *al = &s->allocator;
    selfcol_store grown = *s;
    grown.capacity = cap;
    grown.entries = selfcol_alloc__array(al, cap, sizeof *grown.entries);
    grown.spare = selfcol_alloc__array(al, cap, sizeof *grown.spare);
    grown.group_parent = selfcol_alloc__array(al, cap, sizeof *grown.group_parent);
    grown.vote_parent = selfcol_alloc__array(al, cap, sizeof *grown.vote_parent);
    grown.label = selfcol_alloc__array(al, cap, sizeof *grown.label);
    grown.vote_parity = selfcol_alloc__array(al, cap, sizeof *grown.vote_parity);
    grown.tally = selfcol_alloc__array(al, 4 * cap, sizeof *grown.tally);
    grown.oldest = selfcol_alloc__array(al, cap, sizeof *grown.oldest);
    grown.regions = selfcol_alloc__array(al, cap, sizeof *grown.regions);
    if (grown.entries == NULL || grown.spare == NULL || grown.group_parent == NULL ||
        grown.vote_parent == NULL || grown.label == NULL || grown.vote_parity == NULL ||
        grown.tally == NULL || grown.oldest == NULL || grown.regions == NULL) {
        free_entry_arrays(&grown);
        return SELFCOL_ENOMEM;
    }
    if (s->count > 0)
        memcpy(grown.entries, s->entries, s->count * sizeof *s->entries);
    free_entry_arrays(s);
    *s = grown;
    return SELFCOL_OK;
}

// Vertex pairs an entry hashes: |first's vertices| x |second's|.
static size_t pairs_of_kind(uint32_t kind) {
    return kind == SELFCOL_CONTACT_VF ? 3 : kind == SELFCOL_CONTACT_EE ? 4 : 6;
}

// The neighbour search's arrays for `keys` vertex-pair occurrences.
static int reserve_pairs(selfcol_store *s, size_t keys) {
    if (keys <= s->pair_capacity)
        return SELFCOL_OK;
    const size_t cap = grown_capacity(keys);
    const selfcol_allocator *al = &s->allocator;
    selfcol_store grown = *s;
    grown.pair_capacity = cap;
    for (int k = 0; k < 2; ++k) {
        grown.pair_key[k] = selfcol_alloc__array(al, cap, sizeof *grown.pair_key[k]);
        grown.pair_occ[k] = selfcol_alloc__array(al, cap, sizeof *grown.pair_occ[k]);
    }
    grown.pair_first = selfcol_alloc__array(al, cap, sizeof *grown.pair_first);
    if (grown.pair_key[0] == NULL || grown.pair_key[1] == NULL || grown.pair_occ[0] == NULL ||
        grown.pair_occ[1] == NULL || grown.pair_first == NULL) {
        free_pair_arrays(&grown);
        return SELFCOL_ENOMEM;
    }
    free_pair_arrays(s);
    s->pair_key[0] = grown.pair_key[0];
    s->pair_key[1] = grown.pair_key[1];
    s->pair_occ[0] = grown.pair_occ[0];
    s->pair_occ[1] = grown.pair_occ[1];
    s->pair_first = grown.pair_first;
    s->pair_capacity = cap;
    return SELFCOL_OK;
}

// The normal caches for the meshes' vertices (grown only; every stamp 0 =
// nothing cached).
static int reserve_normals(selfcol_store *s, const selfcol_mesh *const meshes[2]) {
    for (int k = 0; k < 2; ++k) {
        const size_t n = meshes[k] != NULL ? meshes[k]->vertex_count : 0;
        if (n <= s->normal_count[k])
            continue;
        float *normals = selfcol_alloc__array(&s->allocator, 3 * n, sizeof *normals);
        uint32_t *stamps = selfcol_alloc__array(&s->allocator, n, sizeof *stamps);
        if (normals == NULL || stamps == NULL) {
            selfcol_alloc__free_array(&s->allocator, normals, 3 * n, sizeof *normals);
            selfcol_alloc__free_array(&s->allocator, stamps, n, sizeof *stamps);
            return SELFCOL_ENOMEM;
        }
        memset(stamps, 0, n * sizeof *stamps);
        selfcol_alloc__free_array(&s->allocator, s->normals[k], 3 * s->normal_count[k],
                                  sizeof *s->normals[k]);
        selfcol_alloc__free_array(&s->allocator, s->normal_stamp[k], s->normal_count[k],
                                  sizeof *s->normal_stamp[k]);
        s->normals[k] = normals;
        s->normal_stamp[k] = stamps;
        s->normal_count[k] = n;
    }
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

static int entry_record_compare(const selfcol_store_contact *e, const selfcol_contact *r) {
    return key_compare(e->kind, e->first_mesh, e->first, e->second_mesh, e->second, r->kind,
                       r->first_mesh, r->first, r->second_mesh, r->second);
}

// 1 when the record's primitives exist in the meshes and its vertices are
// theirs.
static int record_matches(const selfcol_mesh *const meshes[2], const selfcol_contact *r) {
    if (r->kind > SELFCOL_CONTACT_EF || r->first_mesh > 1 || r->second_mesh > 1)
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
static int exact_side(const selfcol_store *s, const selfcol_store_contact *e) {
    const uint32_t fm = e->first_mesh, sm = e->second_mesh;
    if (e->kind == SELFCOL_CONTACT_VF)
        return selfcol_predicates__orient3d(vertex_of(s, sm, e->b[0]), vertex_of(s, sm, e->b[1]),
                                            vertex_of(s, sm, e->b[2]), vertex_of(s, fm, e->a[0]));
    return selfcol_predicates__orient3d(vertex_of(s, fm, e->a[0]), vertex_of(s, fm, e->a[1]),
                                        vertex_of(s, sm, e->b[0]), vertex_of(s, sm, e->b[1]));
}

// Distance, weights and direction of a remnant VF/EE entry at the current
// positions (the closed form of the narrow phase).
static void recompute(const selfcol_store *s, selfcol_store_contact *e) {
    const uint32_t fm = e->first_mesh, sm = e->second_mesh;
    selfcol_narrow_result r;
    if (e->kind == SELFCOL_CONTACT_VF)
        selfcol_narrow__vf(vertex_of(s, fm, e->a[0]), vertex_of(s, sm, e->b[0]),
                           vertex_of(s, sm, e->b[1]), vertex_of(s, sm, e->b[2]), &r);
    else
        selfcol_narrow__ee(vertex_of(s, fm, e->a[0]), vertex_of(s, fm, e->a[1]),
                           vertex_of(s, sm, e->b[0]), vertex_of(s, sm, e->b[1]), &r);
    e->distance = r.distance;
    memcpy(e->wa, r.wa, sizeof e->wa);
    memcpy(e->wb, r.wb, sizeof e->wb);
    memcpy(e->direction, r.direction, sizeof e->direction);
}

static void take_record(selfcol_store_contact *e, const selfcol_contact *r) {
    e->kind = r->kind;
    e->first = r->first;
    e->second = r->second;
    e->first_mesh = r->first_mesh;
    e->second_mesh = r->second_mesh;
    memcpy(e->a, r->a, sizeof e->a);
    memcpy(e->b, r->b, sizeof e->b);
    e->distance = r->distance;
    memcpy(e->wa, r->wa, sizeof e->wa);
    memcpy(e->wb, r->wb, sizeof e->wb);
    memcpy(e->direction, r->direction, sizeof e->direction);
}

static void set_signed_distance(selfcol_store_contact *e) {
    const int wrong = e->side != 0 && e->right_side != 0 && e->side != e->right_side;
    e->signed_distance = wrong ? -e->distance : e->distance;
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
static int oriented_right_side(const selfcol_store *s, const selfcol_store_contact *e) {
    const int of = s->orientation[e->first_mesh], os = s->orientation[e->second_mesh];
    if (of == 0 && os == 0)
        return 0;
    const selfcol_mesh *mf = s->meshes[e->first_mesh], *ms = s->meshes[e->second_mesh];
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
        vec3_triangle_normal(r, vertex_of(s, e->second_mesh, e->b[0]),
                             vertex_of(s, e->second_mesh, e->b[1]),
                             vertex_of(s, e->second_mesh, e->b[2]));
    } else {
        double u[3], w[3];
        vec3_sub(u, vertex_of(s, e->first_mesh, e->a[1]), vertex_of(s, e->first_mesh, e->a[0]));
        vec3_sub(w, vertex_of(s, e->second_mesh, e->b[1]), vertex_of(s, e->second_mesh, e->b[0]));
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
static void track_side(selfcol_store *s, selfcol_store_contact *e) {
    if (e->kind == SELFCOL_CONTACT_EF) {
        e->side = e->right_side = 0;
        return;
    }
    if (s->orientation[e->first_mesh] != 0 || s->orientation[e->second_mesh] != 0) {
        e->flags |= SELFCOL_STORE_ORIENTED;
        const int given = oriented_right_side(s, e);
        if (given != 0)
            e->right_side = given;
    }
    const int now = exact_side(s, e);
    if (now != 0) {
        if (e->side != 0 && now != e->side) {
            e->flags |= SELFCOL_STORE_FLIPPED;
            e->flags &= ~(uint32_t)SELFCOL_STORE_SETTLED; // a crossing reopens the vote
            s->stats.flipped++;
        }
        e->side = now;
        if (e->right_side == 0)
            e->right_side = now; // first decided side: taken as the right one
    }
}

// ---------------------------------------------------------------------------
// Union-find

static void group_unite(uint32_t *parent, uint32_t x, uint32_t y) {
    x = selfcol_union_find__root(parent, x);
    y = selfcol_union_find__root(parent, y);
    if (x != y)
        parent[x < y ? y : x] = x < y ? x : y; // the smaller index is the root
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
static int vertex_normal(selfcol_store *s, uint32_t mesh, uint32_t v, double normal[3]) {
    float *cached = s->normals[mesh] + 3 * (size_t)v;
    if (s->normal_stamp[mesh][v] != s->stamp) {
        const selfcol_mesh *m = s->meshes[mesh];
        double n[3] = {0.0, 0.0, 0.0}, u[3] = {0.0, 0.0, 0.0};
        for (uint32_t k = m->vertex_tri_offsets[v]; k < m->vertex_tri_offsets[v + 1]; ++k)
            add_triangle_normal(m, m->vertex_tris[k], n);
        vec3_normalize(u, n); // (0, 0, 0) when there is none
        for (int k = 0; k < 3; ++k)
            cached[k] = (float)u[k];
        s->normal_stamp[mesh][v] = s->stamp;
    }
    for (int k = 0; k < 3; ++k)
        normal[k] = cached[k];
    return normal[0] != 0.0 || normal[1] != 0.0 || normal[2] != 0.0;
}

// The cosine a link needs, between the surface normals at its two vertices
// and between each direction and each normal (60 degrees): measured on the
// crumpling ribbon held clean by the Bullet adapter (EF = 0), queried at
// 0.5 x mean edge, 0 of ~150k candidate links contradict the geometry with
// 0.5; with 0.3, 3-5 per frame do (all where a border edge meets the other
// layer edge-on, whose directions point every way).
#define SELFCOL_STORE_LINK_COS 0.5

// The orientation relation of two entries through the surface normal n:
// +1 or -1 as both directions point to the same side of n or to opposite
// sides; 0 when one of them leans too far from n to tell.
static int side_relation(const double n[3], const double dx[3], const double dy[3]) {
    const double px = vec3_dot(dx, n), py = vec3_dot(dy, n);
    if (!(fabs(px) >= SELFCOL_STORE_LINK_COS && fabs(py) >= SELFCOL_STORE_LINK_COS))
        return 0;
    return (px > 0) == (py > 0) ? 1 : -1;
}

// Two entries linked through a shared vertex pair {u, w} (u of mesh
// u_mesh, w of w_mesh): group them; if both vote (VF/EE), link their
// orientations. Each direction points from the second element to the
// first, so it says which side of the surface at u (and at w) the entry's
// first element is on. That side is what is compared, not the directions
// themselves: two directions leaning opposite ways off the normal (closest
// points on opposite borders, frequent when the gap is small against d)
// point to the same side, although their dot product is negative (seed
// 3.2.1 propagates the surfaces' orientation; this is its local form).
// Same roles (parity +1) should point to the same side, crosswise ones
// (-1) to opposite sides: o_i = parity * relation * o_j. The link is made
// only where the geometry is clear: the two surfaces within 60 degrees of
// parallel or antiparallel, every direction within 60 degrees of both
// normals' lines, and the same relation through both normals.
static void link_entries(selfcol_store *s, uint32_t i, uint32_t j, int same_roles, uint32_t u,
                         uint32_t u_mesh, uint32_t w, uint32_t w_mesh) {
    group_unite(s->group_parent, i, j);
    const selfcol_store_contact *x = &s->entries[i], *y = &s->entries[j];
    if (x->kind == SELFCOL_CONTACT_EF || y->kind == SELFCOL_CONTACT_EF ||
        ((x->flags | y->flags) & SELFCOL_STORE_ORIENTED))
        return; // only voting contacts are linked for the vote
    int parity_unused;
    if (vote_find(s->vote_parent, s->vote_parity, i, &parity_unused) ==
        vote_find(s->vote_parent, s->vote_parity, j, &parity_unused))
        return; // already in one group: the link would be ignored (vote_unite)
    double nu[3], nw[3];
    if (!vertex_normal(s, u_mesh, u, nu) || !vertex_normal(s, w_mesh, w, nw) ||
        !(fabs(vec3_dot(nu, nw)) >= SELFCOL_STORE_LINK_COS))
        return;
    const int through_u = side_relation(nu, x->direction, y->direction);
    if (through_u == 0 || side_relation(nw, x->direction, y->direction) != through_u)
        return;
    vote_unite(s->vote_parent, s->vote_parity, i, j, (same_roles ? 1 : -1) * through_u);
}

// One vertex pair {u, w} of an entry: u a vertex of its first element (of
// mesh mu), w of its second (of mesh mw); first_is_lo when (mu, u) orders
// before (mw, w). An entry has pairs_of_kind() of them, taken in the order
// p over the first element's vertices, q over the second's.
typedef struct vertex_pair {
    uint32_t u, w, mu, mw;
    int first_is_lo;
} vertex_pair;

static vertex_pair pair_of(const selfcol_store_contact *e, int k) {
    const int nb = e->kind == SELFCOL_CONTACT_EE ? 2 : 3;
    vertex_pair v = {e->a[k / nb], e->b[k % nb], e->first_mesh, e->second_mesh, 0};
    v.first_is_lo = v.mu < v.mw || (v.mu == v.mw && v.u < v.w);
    return v;
}

// Entries sharing a vertex pair are neighbours (link_entries). Each
// occurrence of a pair is linked to the pair's first occurrence (in entry
// order), and the links are made in entry order: a link that closes a
// cycle against the relation is ignored, so the order decides which links
// win. The pairs are found by an LSD radix sort of their keys (stable, so
// a run's first element is its first occurrence), not by hashing: a hash
// of a few million pairs is a cache miss per probe (46 % of the update on
// cloth-ball 92 -> 93); the sort reads and writes sequentially. Keys hold
// (meshes, lo, hi): only the bits that vary are sorted, 11 at a time.
static void link_neighbours(selfcol_store *s) {
    size_t max_vertex = 1;
    for (int k = 0; k < 2; ++k)
        if (s->meshes[k] != NULL && s->meshes[k]->vertex_count > max_vertex)
            max_vertex = s->meshes[k]->vertex_count;
    unsigned vbits = 1;
    while (vbits < 32 && ((size_t)1 << vbits) < max_vertex)
        ++vbits;
    // key = lo << vbits | hi, with the ends' meshes above (two bits) when
    // they fit in 64 bits; otherwise (vbits 32) the meshes go in a last pass.
    const int two_meshes = s->meshes[1] != NULL;
    const unsigned key_bits = 2 * vbits + (two_meshes ? 2 : 0);
    uint64_t *key = s->pair_key[0];
    uint32_t *occ_of = s->pair_occ[0];
    size_t n = 0; // occurrences
    for (uint32_t i = 0; i < s->count; ++i)
        for (int k = 0; k < (int)pairs_of_kind(s->entries[i].kind); ++k, ++n) {
            const vertex_pair v = pair_of(&s->entries[i], k);
            const uint64_t lo = v.first_is_lo ? v.u : v.w, hi = v.first_is_lo ? v.w : v.u;
            const uint64_t meshes = v.first_is_lo ? (v.mu | v.mw << 1) : (v.mw | v.mu << 1);
            key[n] = (lo << vbits | hi) | (key_bits <= 64 ? meshes << (2 * vbits) : 0);
            occ_of[n] = (uint32_t)n;
            s->pair_first[n] = (uint64_t)i << 1 | (uint64_t)v.first_is_lo;
        }

    enum { DIGIT = 11, BUCKETS = 1 << DIGIT };
    size_t count[BUCKETS];
    const unsigned sorted_bits = key_bits <= 64 ? key_bits : 64;
    int from = 0;
    for (unsigned shift = 0; shift < sorted_bits; shift += DIGIT) {
        const uint64_t *k0 = s->pair_key[from];
        const uint32_t *o0 = s->pair_occ[from];
        uint64_t *k1 = s->pair_key[1 - from];
        uint32_t *o1 = s->pair_occ[1 - from];
        memset(count, 0, sizeof count);
        for (size_t x = 0; x < n; ++x)
            count[(k0[x] >> shift) & (BUCKETS - 1)]++;
        size_t sum = 0;
        for (size_t b = 0; b < BUCKETS; ++b) {
            const size_t c = count[b];
            count[b] = sum;
            sum += c;
        }
        for (size_t x = 0; x < n; ++x) {
            const size_t at = count[(k0[x] >> shift) & (BUCKETS - 1)]++;
            k1[at] = k0[x];
            o1[at] = o0[x];
        }
        from = 1 - from;
    }
    // Runs of one key: every member takes its first occurrence's entry.
    // Vertex indices of 32 bits leave no room for the meshes in the key:
    // then a run is split by the meshes read back from the entries.
    const uint64_t *k = s->pair_key[from];
    const uint32_t *o = s->pair_occ[from];
    for (size_t x = 0; x < n;) {
        size_t end = x + 1;
        while (end < n && k[end] == k[x])
            ++end;
        if (key_bits <= 64) {
            const uint64_t first = s->pair_first[o[x]];
            for (size_t y = x + 1; y < end; ++y)
                s->pair_first[o[y]] = first;
        } else {
            // Few such runs (meshes beyond 2^31 vertices): quadratic in the
            // run only, each member to the earliest one with its meshes.
            for (size_t y = x + 1; y < end; ++y)
                for (size_t z = x; z < y; ++z) {
                    const uint64_t fz = s->pair_first[o[z]], fy = s->pair_first[o[y]];
                    const selfcol_store_contact *ez = &s->entries[fz >> 1],
                                                *ey = &s->entries[fy >> 1];
                    const uint32_t mz = (fz & 1) ? (ez->first_mesh | ez->second_mesh << 1)
                                                 : (ez->second_mesh | ez->first_mesh << 1);
                    const uint32_t my = (fy & 1) ? (ey->first_mesh | ey->second_mesh << 1)
                                                 : (ey->second_mesh | ey->first_mesh << 1);
                    if (mz == my && o[z] < o[y]) {
                        s->pair_first[o[y]] = s->pair_first[o[z]];
                        break;
                    }
                }
        }
        x = end;
    }
    size_t occ = 0;
    for (uint32_t i = 0; i < s->count; ++i)
        for (int k = 0; k < (int)pairs_of_kind(s->entries[i].kind); ++k, ++occ) {
            const uint64_t first = s->pair_first[occ];
            const uint32_t j = (uint32_t)(first >> 1);
            if (j == i)
                continue; // the pair's first occurrence
            const vertex_pair v = pair_of(&s->entries[i], k);
            link_entries(s, i, j, (int)(first & 1) == v.first_is_lo, v.u, v.mu, v.w, v.mw);
        }
}

// ---------------------------------------------------------------------------
// The vote

// Each voting group's majority right side, imposed; then the region records.
static void vote_and_label(selfcol_store *s) {
    const size_t n = s->count;
    // Per group root r: [4 r] and [4 r + 1] count the votes for o = +1 and
    // o = -1 of contacts new in this update, [4 r + 2] and [4 r + 3] those of
    // contacts held from earlier updates.
    int32_t *votes = s->tally;
    for (size_t i = 0; i < n; ++i) {
        votes[4 * i] = votes[4 * i + 1] = votes[4 * i + 2] = votes[4 * i + 3] = 0;
        s->oldest[i] = SELFCOL_INVALID_INDEX;
    }
    // Tally: contact i's vote, in its group's frame, is sigma_i * o_i with
    // sigma_i = side * right_side (+1 on its right side). Contacts whose
    // side was never decided abstain.
    for (uint32_t i = 0; i < n; ++i) {
        const selfcol_store_contact *e = &s->entries[i];
        if (e->kind == SELFCOL_CONTACT_EF || e->side == 0 || (e->flags & SELFCOL_STORE_ORIENTED))
            continue;
        s->stats.voted++;
        int o;
        const uint32_t r = vote_find(s->vote_parent, s->vote_parity, i, &o);
        const int vote = e->side * e->right_side * o;
        const int held = (e->flags & SELFCOL_STORE_NEW) == 0;
        votes[4 * r + 2 * held + (vote > 0 ? 0 : 1)]++;
        const uint32_t old = s->oldest[r];
        if (old == SELFCOL_INVALID_INDEX || e->age > s->entries[old].age)
            s->oldest[r] = i;
    }
    // Regions, numbered by their first entry.
    for (size_t i = 0; i < n; ++i)
        s->label[i] = SELFCOL_INVALID_INDEX;
    size_t regions = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t g = selfcol_union_find__root(s->group_parent, i);
        if (s->label[g] == SELFCOL_INVALID_INDEX)
            s->label[g] = (uint32_t)regions++;
        s->entries[i].region = s->label[g];
    }
    // One region per entry at most: the per-entry array suffices.
    s->region_count = regions;
    if (regions > 0) // (never grown when no contact was ever held: no array)
        memset(s->regions, 0, regions * sizeof *s->regions);
    // Impose and count.
    for (uint32_t i = 0; i < n; ++i) {
        selfcol_store_contact *e = &s->entries[i];
        selfcol_store_region *reg = &s->regions[e->region];
        if (e->kind == SELFCOL_CONTACT_EF) {
            reg->interferences++;
            reg->flags |= SELFCOL_REGION_CROSSED;
            continue;
        }
        reg->contacts++;
        if (e->flags & SELFCOL_STORE_ORIENTED) {
            reg->oriented++;
            s->stats.oriented++;
            set_signed_distance(e);
            continue;
        }
        int o;
        const uint32_t r = vote_find(s->vote_parent, s->vote_parity, i, &o);
        // A group with held contacts follows their votes only: a held
        // contact's right side carries memory (of its side before a
        // crossing, or of an earlier vote), a new contact's is a guess (its
        // current side). New contacts decide only groups of new contacts.
        const int32_t *v = votes + 4 * r + (votes[4 * r + 2] + votes[4 * r + 3] > 0 ? 2 : 0);
        const int32_t plus = v[0], minus = v[1];
        if (e->side == 0) {
            reg->abstained++;
            set_signed_distance(e);
            continue;
        }
        int majority; // the group's winning sigma * o
        if (plus != minus) {
            majority = plus > minus ? 1 : -1;
        } else if (plus == 0) {
            majority = 0; // nobody voted: nothing to impose
        } else {
            // Tie: the oldest contact keeps its right side.
            const selfcol_store_contact *t = &s->entries[s->oldest[r]];
            int ot;
            vote_find(s->vote_parent, s->vote_parity, s->oldest[r], &ot);
            majority = t->side * t->right_side * ot;
            reg->flags |= SELFCOL_REGION_TIE;
        }
        // A decided side always has a right side (track_side).
        if (e->side * e->right_side * o == majority || majority == 0) {
            reg->votes_majority++;
        } else {
            reg->votes_minority++;
            if (s->consistency && !(e->flags & SELFCOL_STORE_SETTLED)) {
                e->right_side = -e->right_side;
                e->flags |= SELFCOL_STORE_CORRECTED;
                s->stats.corrected++;
                reg->flags |= SELFCOL_REGION_CORRECTED;
            }
        }
        if (s->consistency && majority != 0)
            e->flags |= SELFCOL_STORE_SETTLED; // through a vote: settled until it crosses
        set_signed_distance(e);
    }
    for (size_t r = 0; r < regions; ++r) {
        s->stats.crossed_regions += (s->regions[r].flags & SELFCOL_REGION_CROSSED) != 0;
        s->stats.corrected_regions += (s->regions[r].flags & SELFCOL_REGION_CORRECTED) != 0;
    }
    s->stats.regions = regions;
}

// ---------------------------------------------------------------------------
// The update

// The entries step 1 keeps (held and detected again, new, or remnant) and
// the vertex pairs they produce, without changing anything.
static void merge_size(const selfcol_store *s, const selfcol_contact *rec, size_t m,
                       size_t *entries_out, size_t *keys_out) {
    size_t i = 0, j = 0, n = 0, keys = 0;
    const selfcol_store_contact *held = s->entries;
    while (i < s->count || j < m) {
        const int c = i == s->count ? 1 : j == m ? -1 : entry_record_compare(&held[i], &rec[j]);
        uint32_t kind;
        if (c >= 0) {
            kind = rec[j++].kind;
            i += c == 0;
        } else {
            const selfcol_store_contact *h = &held[i++];
            if (h->kind == SELFCOL_CONTACT_EF || h->missed >= s->remnance)
                continue; // dropped
            kind = h->kind;
        }
        ++n;
        keys += pairs_of_kind(kind);
    }
    *entries_out = n;
    *keys_out = keys;
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
    const selfcol_contact *rec = detected->items;
    const size_t m = detected->count;
    // Validate and reserve everything before changing anything.
    int status = SELFCOL_OK;
    for (size_t j = 0; j < m && status == SELFCOL_OK; ++j) {
        if (!record_matches(meshes, &rec[j]))
            status = SELFCOL_EMISMATCH;
        else if (j > 0 && record_compare(&rec[j - 1], &rec[j]) >= 0)
            status = SELFCOL_EINVAL;
    }
    // The merge's outcome, counted first (a dry run of step 1), so that
    // every array is sized to the entries the update keeps, not to held +
    // detected (which was twice as much on cloth-ball 92 -> 93).
    size_t kept_entries = 0, keys = 0;
    if (status == SELFCOL_OK)
        merge_size(store, rec, m, &kept_entries, &keys);
    if (status == SELFCOL_OK)
        status = reserve_entries(store, kept_entries > store->count ? kept_entries : store->count);
    if (status == SELFCOL_OK)
        status = reserve_normals(store, meshes);
    if (status == SELFCOL_OK)
        status = keys > UINT32_MAX ? SELFCOL_ERANGE : reserve_pairs(store, keys);
    if (status != SELFCOL_OK)
        return status;
    store->meshes[0] = first;
    store->meshes[1] = second;
    store->identity[0] = first->identity;
    if (second != NULL)
        store->identity[1] = second->identity;
    if (++store->stamp == 0) { // wrapped: forget every cached normal
        for (int k = 0; k < 2; ++k)
            if (store->normal_count[k] > 0)
                memset(store->normal_stamp[k], 0,
                       store->normal_count[k] * sizeof *store->normal_stamp[k]);
        store->stamp = 1;
    }
    memset(&store->stats, 0, sizeof store->stats);
    store->stats.version = SELFCOL_STORE_UPDATE_STATS_VERSION;

    // 1. Merge the held entries (sorted) with the records (sorted).
    selfcol_store_contact *out = store->spare;
    size_t i = 0, j = 0, n = 0;
    const selfcol_store_contact *held = store->entries;
    while (i < store->count || j < m) {
        int c = i == store->count ? 1 : j == m ? -1 : entry_record_compare(&held[i], &rec[j]);
        selfcol_store_contact *e = &out[n];
        if (c == 0) { // held and detected again
            *e = held[i++];
            take_record(e, &rec[j++]);
            e->age += e->age < UINT32_MAX;
            e->missed = 0;
            e->flags &= SELFCOL_STORE_SETTLED; // the only flag that persists
            store->stats.kept += e->kind != SELFCOL_CONTACT_EF;
        } else if (c > 0) { // new
            memset(e, 0, sizeof *e);
            take_record(e, &rec[j++]);
            e->flags = SELFCOL_STORE_NEW;
            store->stats.new_contacts += e->kind != SELFCOL_CONTACT_EF;
        } else { // held, not detected
            const selfcol_store_contact *h = &held[i++];
            if (h->kind == SELFCOL_CONTACT_EF || h->missed >= store->remnance) {
                store->stats.dropped++;
                continue;
            }
            *e = *h;
            e->age += e->age < UINT32_MAX;
            e->missed++;
            e->flags = (e->flags & SELFCOL_STORE_SETTLED) | SELFCOL_STORE_REMNANT;
            recompute(store, e);
            store->stats.remnant++;
        }
        track_side(store, e);
        set_signed_distance(e);
        if (e->kind == SELFCOL_CONTACT_EF)
            store->stats.interferences++;
        else
            store->stats.contacts++;
        ++n;
    }
    store->spare = store->entries;
    store->entries = out;
    store->count = n;

    // 2. Regions and voting groups.
    for (uint32_t k = 0; k < n; ++k) {
        store->group_parent[k] = store->vote_parent[k] = k;
        store->vote_parity[k] = 1;
    }
    link_neighbours(store);
    // 3. The vote.
    vote_and_label(store);
    store->stats.seconds = selfcol_core__seconds() - start;
    return SELFCOL_OK;
}

int selfcol_store_contacts(const selfcol_store *store, const selfcol_store_contact **data_out,
                           size_t *count_out) {
    SELFCOL_CHECK(store != NULL && data_out != NULL && count_out != NULL);
    *data_out = store->count > 0 ? store->entries : NULL;
    *count_out = store->count;
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
    *stats = store->stats; // one version so far: the whole struct
    stats->version = version;
    return SELFCOL_OK;
}

size_t selfcol_store_byte_count(const selfcol_store *store) {
    if (store == NULL)
        return 0;
    const size_t per_entry = 2 * sizeof(selfcol_store_contact) + 3 * sizeof(uint32_t) +
                             sizeof(int8_t) + 4 * sizeof(int32_t) + sizeof(uint32_t) +
                             sizeof(selfcol_store_region);
    const size_t per_pair = 3 * sizeof(uint64_t) + 2 * sizeof(uint32_t);
    const size_t per_vertex = 3 * sizeof(float) + sizeof(uint32_t);
    return sizeof *store + store->capacity * per_entry + store->pair_capacity * per_pair +
           (store->normal_count[0] + store->normal_count[1]) * per_vertex;
}
