// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Coherent queries over a sequence of frames (include/selfcol/sequence.h):
// a Verlet list (the neighbour lists of molecular dynamics, kept with a
// "skin") whose validity is proven from the surface's deformation rather
// than its displacement.
//
// Proof. Let the reference be the positions at the last rebuild, R = d + s,
// and D(v) = x(v) - x_ref(v). A point p of a primitive is a convex
// combination of its vertices, so D(p) is the same combination of their D
// and lies in the box of D over any vertex set holding them. Take a primitive
// pair (P, Q) of the query's kinds that is not in the near list:
//  - VF, EE: the closed form at the reference said dist >= R, so the true
//    distance was at least R (1 - 1e-9) (contacts.h's relative band);
//  - EF: the edge e did not cross t, and its ends' VF distances to t and its
//    EE distances to t's edges were all >= R; a segment that does not meet a
//    triangle is nearest to it at one of its ends or at one of the
//    triangle's edges, so dist(e, t) >= R (1 - 1e-9) too.
// Let I be a cluster holding a triangle of P (all of P's vertices are in I's
// vertex set) and J one holding Q's. Now
//   dist_now(P, Q) >= dist_ref(P, Q) - max |D(p) - D(q)|
//                  >= max(R (1 - 1e-9), gap_ref(I, J)) - spread(I, J),
// where gap_ref is the distance between the clusters' boxes at the
// reference and spread(I, J) the largest distance between a point of I's
// displacement box and one of J's (per axis max(hi_I - lo_J, hi_J - lo_I)).
// When spread(I, J) <= max(s, gap_ref(I, J) - d) - 1e-6 R for every pair of
// clusters, dist_now(P, Q) > d (1 + 1e-9): the fresh query, whose closed
// forms err by less than that band, does not report (P, Q) either. So the
// fresh query's records are exactly those of the near list's pairs that the
// same closed forms, called here on the same positions through the same
// functions (pairs.h), report now; the list is kept in record order, so they
// come out sorted.
//
// A rebuild runs the ordinary query (the caller's exact method) at distance
// R with the closed-form narrow phase, lists its VF and EE records (those
// kinds asked) and, for EF, the edge-triangle pairs the proof needs: its EF
// records, and for each VF record (v, t) the edges at v, for each EE record
// (e, f) the pairs (e, t) with t at f and (f, t') with t' at e (no shared
// vertex for a self query, no repeated triangle).
//
// Files: this one (the handle, the queries: reference, rebuild, the
// frame's choice), sequence_clusters.c (the clusters and the check),
// sequence_list.c (the near list and its evaluation), sequence_partial.c
// (partial rebuilds); sequence_state.h the handle and the near pair they
// share.
#include "frames/sequence.h"
#include "frames/sequence_state.h"

#include "base/alloc.h"
#include "base/core.h"
#include "base/problem.h"
#include "hierarchy/hierarchy.h"
#include "mesh/mesh.h"
#include "query/contacts.h"
#include "query/context.h"
#include "query/query.h"

#include <math.h>
#include <string.h>

// At least `bytes` in b, growing geometrically; the first `keep` bytes of
// the old content are copied.
int selfcol_sequence__reserve_keep(const selfcol_allocator *a, buffer *b, size_t bytes,
                                   size_t keep) {
    if (bytes <= b->bytes)
        return SELFCOL_OK;
    size_t want = b->bytes + b->bytes / 2;
    want = want > bytes ? want : bytes;
    void *grown = selfcol_alloc__raw(a, want);
    if (grown == NULL)
        return SELFCOL_ENOMEM;
    if (keep > 0)
        memcpy(grown, b->data, keep);
    selfcol_alloc__free(a, b->data, b->bytes);
    b->data = grown;
    b->bytes = want;
    return SELFCOL_OK;
}

int selfcol_sequence__reserve(const selfcol_allocator *a, buffer *b, size_t bytes) {
    return selfcol_sequence__reserve_keep(a, b, bytes, 0);
}

void selfcol_sequence__release(const selfcol_allocator *a, buffer *b) {
    selfcol_alloc__free(a, b->data, b->bytes);
    b->data = NULL;
    b->bytes = 0;
}

int selfcol_sequence_options_init(selfcol_sequence_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_SEQUENCE_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

int selfcol_sequence__options(selfcol_sequence_options *out, const selfcol_sequence_options *opts,
                              const selfcol_problem_at *at) {
    selfcol_sequence_options_init(out, SELFCOL_SEQUENCE_OPTIONS_VERSION);
    if (opts != NULL) {
        const int version =
            selfcol_problem__version(at, opts->version, SELFCOL_SEQUENCE_OPTIONS_VERSION);
        if (version != SELFCOL_OK)
            return version;
        out->allocator = opts->allocator;
        out->skin = opts->skin;
    }
    SELFCOL_CHECK_ALLOCATOR(at, out->allocator);
    SELFCOL_CHECK_FIELD(
        at, isfinite(out->skin) && out->skin >= 0.0 && out->skin <= SELFCOL_MESH_MAX_COORDINATE,
        "skin", "= %g is not a distance in 0 .. %g (0: automatic)", out->skin,
        SELFCOL_MESH_MAX_COORDINATE);
    return SELFCOL_OK;
}

int selfcol_sequence_options_check(const selfcol_sequence_options *opts,
                                   selfcol_options_problem *problem) {
    const int begun = selfcol_problem__begin(problem);
    if (begun != SELFCOL_OK)
        return begun;
    const selfcol_problem_at at = {problem, "selfcol_sequence_options", ""};
    selfcol_sequence_options checked;
    return selfcol_sequence__options(&checked, opts, &at);
}

int selfcol_sequence_create(selfcol_sequence **out, const selfcol_sequence_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    selfcol_sequence_options o;
    const int checked = selfcol_sequence__options(&o, opts, NULL);
    if (checked != SELFCOL_OK)
        return checked;
    selfcol_sequence *s = selfcol_alloc__raw(&o.allocator, sizeof *s);
    if (s == NULL)
        return SELFCOL_ENOMEM;
    memset(s, 0, sizeof *s);
    s->allocator = o.allocator;
    s->skin_option = o.skin;
    s->stats.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
    *out = s;
    return SELFCOL_OK;
}

void selfcol_sequence_destroy(selfcol_sequence *s) {
    if (s == NULL)
        return;
    const selfcol_allocator a = s->allocator;
    for (int m = 0; m < 2; ++m) {
        selfcol_sequence__release(&a, &s->reference[m]);
        selfcol_sequence__release(&a, &s->clusters[m].offsets);
        selfcol_sequence__release(&a, &s->clusters[m].vertices);
        selfcol_sequence__release(&a, &s->clusters[m].ref_box);
        selfcol_sequence__release(&a, &s->clusters[m].disp_box);
        selfcol_sequence__release(&a, &s->clusters[m].of_triangle);
    }
    selfcol_sequence__release(&a, &s->pairs);
    selfcol_sequence__release(&a, &s->spread);
    selfcol_sequence__release(&a, &s->carry);
    selfcol_sequence__release(&a, &s->allowed);
    selfcol_sequence__release(&a, &s->masks);
    selfcol_sequence__release(&a, &s->stamps);
    selfcol_alloc__free(&a, s, sizeof *s);
}

void selfcol_sequence_reset(selfcol_sequence *s) {
    if (s == NULL)
        return;
    s->state = STATE_NONE;
    memset(&s->stats, 0, sizeof s->stats);
    s->stats.version = SELFCOL_SEQUENCE_RUN_STATS_VERSION;
}

int selfcol_sequence_stats(const selfcol_sequence *s, selfcol_sequence_run_stats *stats) {
    SELFCOL_CHECK(s != NULL && stats != NULL);
    if (stats->version == 0 || stats->version > SELFCOL_SEQUENCE_RUN_STATS_VERSION)
        return SELFCOL_EVERSION;
    *stats = s->stats;
    return SELFCOL_OK;
}

size_t selfcol_sequence_byte_count(const selfcol_sequence *s) {
    if (s == NULL)
        return 0;
    size_t bytes = sizeof *s + s->pairs.bytes + s->stamps.bytes + s->spread.bytes + s->carry.bytes +
                   s->allowed.bytes + s->masks.bytes;
    for (int m = 0; m < 2; ++m) {
        const cluster_set *c = &s->clusters[m];
        bytes += s->reference[m].bytes + c->offsets.bytes + c->vertices.bytes + c->ref_box.bytes +
                 c->disp_box.bytes + c->of_triangle.bytes;
    }
    return bytes;
}

// ---------------------------------------------------------------------------
// Queries

static double automatic_skin(double distance, const selfcol_mesh *const mesh[2], int self) {
    if (distance > 0.0)
        return distance;
    double sum = selfcol_mesh_mean_edge_length(mesh[0]);
    if (!self)
        sum = 0.5 * (sum + selfcol_mesh_mean_edge_length(mesh[1]));
    return 0.1 * sum;
}

// Takes the query's setup (meshes, options); forgets any reference.
static void setup(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                  const selfcol_query_options *o) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    s->skin = s->reach = 0.0;
    s->state = STATE_NONE;
    s->clusters[0].ready = s->clusters[1].ready = 0;
    s->self = h[0] == h[1];
    for (int m = 0; m < 2; ++m)
        s->identity[m] = mesh[m]->identity;
    s->distance = o->distance;
    s->kinds = o->kinds;
    s->narrow = o->narrow;
    s->method = o->method;
}

// The skin for a new reference (the automatic one follows the mean edge).
static void choose_skin(selfcol_sequence *s, selfcol_hierarchy *const h[2]) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    const double skin =
        s->skin_option > 0.0 ? s->skin_option : automatic_skin(s->distance, mesh, s->self);
    double reach = s->distance + skin;
    if (!(reach <= SELFCOL_MESH_MAX_COORDINATE))
        reach = SELFCOL_MESH_MAX_COORDINATE;
    s->skin = reach - s->distance;
    s->reach = reach;
}

static int same_setup(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                      const selfcol_query_options *o) {
    return s->state != STATE_NONE && s->self == (h[0] == h[1]) &&
           selfcol_mesh__is(h[0]->mesh, &s->identity[0]) &&
           selfcol_mesh__is(h[1]->mesh, &s->identity[1]) && s->distance == o->distance &&
           s->kinds == o->kinds && s->narrow == o->narrow && s->method == o->method;
}

// What cluster pair (i, j) allows at the current reference as a float
// rounded down; 0 when it allows nothing.
float selfcol_sequence__float_allowance(const selfcol_sequence *s, unsigned i, unsigned j) {
    const double allowed = selfcol_sequence__allowance(s, i, j);
    return allowed > 0.0 ? selfcol_sequence__float_below(allowed) : 0.0f;
}

// The current positions become the reference: copied, with the clusters
// and their boxes (the caller has chosen the skin for them).
static int take_reference(selfcol_sequence *s, selfcol_hierarchy *const h[2]) {
    const int meshes = s->self ? 1 : 2;
    size_t stamp_bytes = 0;
    int status = SELFCOL_OK;
    for (int m = 0; m < meshes && status == SELFCOL_OK; ++m) {
        const selfcol_mesh *mesh = h[m]->mesh;
        const size_t V = mesh->vertex_count;
        stamp_bytes = V * sizeof(uint32_t) > stamp_bytes ? V * sizeof(uint32_t) : stamp_bytes;
        status = selfcol_sequence__reserve(&s->allocator, &s->reference[m], 3 * V * sizeof(double));
        if (status == SELFCOL_OK)
            memcpy(s->reference[m].data, mesh->positions, 3 * V * sizeof(double));
    }
    if (status == SELFCOL_OK)
        status = selfcol_sequence__reserve(&s->allocator, &s->stamps, stamp_bytes);
    for (int m = 0; m < meshes && status == SELFCOL_OK; ++m)
        status = selfcol_sequence__build_clusters(s, m, h[m], s->stamps.data);
    // No displacement yet: every cluster pair's spread and carry are 0, and
    // each allows what the new reference gives it.
    const size_t K0 = s->clusters[0].count, K1 = s->clusters[s->self ? 0 : 1].count;
    const size_t bytes = (K0 * K1 + 1) * sizeof(float);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__reserve(&s->allocator, &s->spread, bytes);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__reserve(&s->allocator, &s->carry, bytes);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__reserve(&s->allocator, &s->allowed, bytes);
    if (status != SELFCOL_OK)
        return status;
    memset(s->spread.data, 0, bytes);
    memset(s->carry.data, 0, bytes);
    float *allowed = s->allowed.data;
    for (unsigned i = 0; i < K0; ++i)
        for (unsigned j = 0; j < K1; ++j)
            allowed[i * K1 + j] = selfcol_sequence__float_allowance(s, i, j);
    return SELFCOL_OK;
}

// Writes the clusters of each near pair's primitives into its tag (after
// take_reference: a vertex or an edge goes to the cluster of its first
// triangle, whose vertex set holds it).
void selfcol_sequence__tag_clusters(const selfcol_sequence *s, const selfcol_mesh *const mesh[2],
                                    near_pair *list, size_t count) {
    for (size_t i = 0; i < count; ++i) {
        near_pair *p = &list[i];
        const uint32_t kind = TAG_KIND(p->tag);
        const uint32_t m1 = TAG_FIRST_MESH(p->tag), m2 = TAG_SECOND_MESH(p->tag);
        const selfcol_mesh *M1 = mesh[m1], *M2 = mesh[m2];
        const uint8_t *of1 = s->clusters[s->self ? 0 : m1].of_triangle.data;
        const uint8_t *of2 = s->clusters[s->self ? 0 : m2].of_triangle.data;
        const uint32_t t1 = kind == SELFCOL_CONTACT_VF
                                ? M1->vertex_tris[M1->vertex_tri_offsets[p->first]]
                                : M1->edge_tris[M1->edge_tri_offsets[p->first]];
        const uint32_t t2 =
            kind == SELFCOL_CONTACT_EE ? M2->edge_tris[M2->edge_tri_offsets[p->second]] : p->second;
        p->tag = (p->tag & 0xffu) | (uint32_t)of1[t1] << 8 | (uint32_t)of2[t2] << 16;
    }
}

selfcol_context *selfcol_sequence__context(const selfcol_sequence *s, selfcol_contacts *scratch) {
    return s->context != NULL ? s->context : selfcol_query__implicit_context(scratch);
}

// The working memory of the context that filled `scratch` (the run's, or
// the set's own, made by its first query: query.h): its sort slot serves
// the list's builds.
selfcol_workspace *selfcol_sequence__scratch_work(const selfcol_sequence *s,
                                                  selfcol_contacts *scratch) {
    return s->context != NULL ? &s->context->work : &scratch->implicit_context->work;
}

// The ordinary query of the hierarchies (a self query when they are one),
// on the run's context if it has one.
int selfcol_sequence__query(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                            selfcol_contacts *out, const selfcol_query_options *o) {
    if (s->context != NULL)
        return h[0] == h[1] ? selfcol_context_self_collide(s->context, h[0], out, o)
                            : selfcol_context_collide(s->context, h[0], h[1], out, o);
    return h[0] == h[1] ? selfcol_hierarchy_self_collide(h[0], out, o)
                        : selfcol_hierarchy_collide(h[0], h[1], out, o);
}

// Refits the hierarchies that are stale (none for EXHAUSTIVE), on the run's
// context if it has one.
int selfcol_sequence__refit_stale(const selfcol_sequence *s, selfcol_hierarchy *const h[2],
                                  uint32_t method) {
    const int meshes = h[0] == h[1] ? 1 : 2;
    for (int m = 0; m < meshes; ++m) {
        if (method != SELFCOL_METHOD_EXHAUSTIVE &&
            h[m]->refit_version != h[m]->mesh->positions_version) {
            int status = s->context != NULL ? selfcol_context_refit(s->context, h[m])
                                            : selfcol_hierarchy_refit(h[m]);
            if (status != SELFCOL_OK)
                return status;
        }
    }
    return SELFCOL_OK;
}

// Rebuilds the near list at the current positions; the reach set's records
// pass through `scratch` (the caller's contact set, cleared afterwards: its
// records and context are reused instead of a second set's).
int selfcol_sequence__rebuild(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                              const selfcol_query_options *o, selfcol_contacts *scratch) {
    const selfcol_mesh *const mesh[2] = {h[0]->mesh, h[1]->mesh};
    // The reach set: the caller's exact method at distance R, closed forms
    // (libccd's distances are approximate), every kind the list needs.
    int status = selfcol_sequence__refit_stale(s, h, o->method);
    choose_skin(s, h);
    selfcol_query_options r = *o;
    r.distance = s->reach;
    r.narrow = SELFCOL_NARROW_CLOSED_FORM;
    if (o->kinds & SELFCOL_KIND_EF)
        r.kinds = SELFCOL_KIND_ALL;
    if (status == SELFCOL_OK)
        status = selfcol_sequence__query(s, h, scratch, &r);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__build_list(s, &s->pairs, 0, &s->pair_count, h,
                                              scratch->records.items, scratch->records.count,
                                              selfcol_sequence__scratch_work(s, scratch));
    selfcol_contacts_clear(scratch);
    if (status == SELFCOL_OK)
        status = take_reference(s, h);
    if (status == SELFCOL_OK)
        selfcol_sequence__tag_clusters(s, mesh, s->pairs.data, s->pair_count);
    return status;
}

// What the query does this frame (run()).
enum { ANSWER_LIST = 0, ANSWER_REBUILT = 1, ANSWER_FRESH = 2 };

// SEED and CONE skip contacts by an approximate criterion, which no near
// list can reproduce: every frame is their own fresh query, and leaves no
// reference (the next frame with an exact method is a first frame).
static int approximate(selfcol_sequence *s, selfcol_hierarchy *const h[2],
                       selfcol_contacts *contacts, const selfcol_query_options *o) {
    s->state = STATE_NONE;
    selfcol_contacts_clear(contacts);
    int status = selfcol_sequence__refit_stale(s, h, o->method);
    if (status == SELFCOL_OK)
        status = selfcol_sequence__query(s, h, contacts, o);
    if (status != SELFCOL_OK)
        return status;
    s->stats.frames++;
    s->stats.fresh_frames++;
    s->stats.last_answer = ANSWER_FRESH;
    s->stats.last_reason = 3;
    s->stats.near_pairs = 0;
    s->stats.deformation_ratio = 0.0;
    return SELFCOL_OK;
}

static int run(selfcol_sequence *s, selfcol_hierarchy *first, selfcol_hierarchy *second,
               selfcol_contacts *contacts, const selfcol_query_options *given) {
    SELFCOL_CHECK(s != NULL && first != NULL && second != NULL && contacts != NULL);
    selfcol_query_options o;
    int status = selfcol_query__options(&o, given, NULL);
    if (status != SELFCOL_OK)
        return status;
    if (!selfcol_mesh__is(first->mesh, &first->mesh_identity) ||
        !selfcol_mesh__is(second->mesh, &second->mesh_identity))
        return SELFCOL_EMISMATCH;
    selfcol_hierarchy *const h[2] = {first, second};
    const selfcol_mesh *const mesh[2] = {first->mesh, second->mesh};
    if (o.method != SELFCOL_METHOD_EXACT && o.method != SELFCOL_METHOD_BVH &&
        o.method != SELFCOL_METHOD_EXHAUSTIVE)
        return approximate(s, h, contacts, &o);

    const double start = selfcol_core__seconds();
    selfcol_contacts_clear(contacts);
    // The policy. A list answers while the check holds. When it fails, the
    // check's ratio over the frames since the reference is the surface's
    // deformation per frame, in units of what a list allows: a new list
    // would last about 1 / rate frames. A rebuild costs a query at d + s
    // (about two fresh queries on folded cloth), so below REBUILD_LIFE
    // frames a fresh query at d is cheaper: it answers the frame and its
    // positions become the reference against which the next frame's rate
    // is measured. The first frame has no rate: it is fresh. A list that
    // fails is rebuilt in part (partial_rebuild): only its cluster pairs
    // near or past their bound are queried again.
    uint32_t reason = 0;
    double ratio = 0.0, rate = INFINITY;
    if (!same_setup(s, h, &o)) {
        reason = s->state != STATE_NONE ? 1u : 0u;
        setup(s, h, &o);
    } else {
        // Above this, a new list would not pay; a list needs every pair's
        // spread (for its skips, and for a partial rebuild).
        const double n = (double)(s->frames_since_reference + 1);
        const double stop = s->state == STATE_LIST ? INFINITY : n / REBUILD_LIFE;
        double since;
        ratio = selfcol_sequence__deformation_ratio(s, mesh, stop, &since);
        s->frames_since_reference++;
        rate = since / n;
        reason = 2;
    }
    int answer;
    if (s->state == STATE_LIST && ratio < 1.0)
        answer = ANSWER_LIST;
    else
        answer = rate * REBUILD_LIFE <= 1.0 ? ANSWER_REBUILT : ANSWER_FRESH;

    double rebuild_seconds = 0.0;
    int partial = answer == ANSWER_REBUILT && s->state == STATE_LIST;
    s->partial_checkable = 0;
    if (answer == ANSWER_REBUILT) {
        s->state = STATE_NONE;
        if (partial)
            status = selfcol_sequence__partial_rebuild(s, h, &o, contacts);
        if (!partial || status == PARTIAL_DECLINED) {
            partial = 0;
            status = selfcol_sequence__rebuild(s, h, &o, contacts);
        }
        if (status == SELFCOL_OK) {
            s->state = STATE_LIST;
            s->frames_since_reference = 0;
        }
        rebuild_seconds = selfcol_core__seconds() - start;
    }
    const double narrow_start = selfcol_core__seconds();
    if (status == SELFCOL_OK && answer != ANSWER_FRESH)
        status = selfcol_sequence__evaluate(s, mesh, &o, contacts);
    if (status == SELFCOL_OK && answer == ANSWER_FRESH) {
        s->state = STATE_NONE;
        status = selfcol_sequence__refit_stale(s, h, o.method);
        if (status == SELFCOL_OK)
            status = selfcol_sequence__query(s, h, contacts, &o);
        // The contacts' statistics are the fresh query's own.
        const selfcol_query_stats kept = contacts->records.stats;
        choose_skin(s, h);
        if (status == SELFCOL_OK)
            status = take_reference(s, h);
        contacts->records.stats = kept;
        if (status == SELFCOL_OK) {
            s->state = STATE_TRACKING;
            s->frames_since_reference = 0;
        }
    }
    const double end = selfcol_core__seconds();
    if (status != SELFCOL_OK) {
        s->state = STATE_NONE;
        selfcol_contacts_clear(contacts);
        return status;
    }
    if (answer != ANSWER_FRESH) {
        contacts->records.stats.broad_seconds = narrow_start - start;
        contacts->records.stats.narrow_seconds = end - narrow_start;
    }
    contacts->records.stats.total_seconds = end - start;
    s->stats.frames++;
    s->stats.last_answer = (uint32_t)answer;
    if (answer != ANSWER_LIST)
        s->stats.last_reason = reason;
    if (answer == ANSWER_REBUILT) {
        s->stats.rebuilds++;
        s->stats.partial_rebuilds += (uint64_t)partial;
        s->stats.rebuild_seconds = rebuild_seconds;
    }
    s->stats.fresh_frames += answer == ANSWER_FRESH;
    s->stats.near_pairs = s->state == STATE_LIST ? s->pair_count : 0;
    s->stats.skin = s->skin;
    s->stats.deformation_ratio = ratio;
    return SELFCOL_OK;
}

// run() on `context` (NULL: the calling thread), which the sequence holds
// for the call only.
static int run_on(selfcol_context *context, selfcol_sequence *s, selfcol_hierarchy *first,
                  selfcol_hierarchy *second, selfcol_contacts *contacts,
                  const selfcol_query_options *opts) {
    SELFCOL_CHECK(s != NULL);
    s->context = context;
    const int status = run(s, first, second, contacts, opts);
    s->context = NULL;
    return status;
}

int selfcol_sequence_self_collide(selfcol_sequence *sequence, selfcol_hierarchy *hierarchy,
                                  selfcol_contacts *contacts, const selfcol_query_options *opts) {
    return run_on(NULL, sequence, hierarchy, hierarchy, contacts, opts);
}

int selfcol_sequence_collide(selfcol_sequence *sequence, selfcol_hierarchy *first,
                             selfcol_hierarchy *second, selfcol_contacts *contacts,
                             const selfcol_query_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run_on(NULL, sequence, first, second, contacts, opts);
}

int selfcol_context_sequence_self_collide(selfcol_context *context, selfcol_sequence *sequence,
                                          selfcol_hierarchy *hierarchy, selfcol_contacts *contacts,
                                          const selfcol_query_options *opts) {
    SELFCOL_CHECK(context != NULL);
    return run_on(context, sequence, hierarchy, hierarchy, contacts, opts);
}

int selfcol_context_sequence_collide(selfcol_context *context, selfcol_sequence *sequence,
                                     selfcol_hierarchy *first, selfcol_hierarchy *second,
                                     selfcol_contacts *contacts,
                                     const selfcol_query_options *opts) {
    SELFCOL_CHECK(context != NULL);
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run_on(context, sequence, first, second, contacts, opts);
}
