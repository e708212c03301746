// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Collision queries: option checking, dispatch to a search method, and the
// primitive tests every method shares (narrow-phase choice, record filling,
// statistics).
#include "query.h"

#include "core.h"
#include "hierarchy.h"
#include "narrow.h"

#include <math.h>
#include <string.h>

int selfcol_query_options_init(selfcol_query_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_QUERY_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    opts->method = SELFCOL_METHOD_EXACT;
    opts->narrow = SELFCOL_NARROW_CLOSED_FORM;
    opts->kinds = SELFCOL_KIND_ALL;
    opts->distance = 0.0;
    return SELFCOL_OK;
}

static void fill_record(const selfcol_query *q, selfcol_contact *c, selfcol_contact_kind kind,
                        int m_first, uint32_t first, int m_second, uint32_t second,
                        const selfcol_narrow_result *r) {
    c->kind = (uint32_t)kind;
    c->first = first;
    c->second = second;
    // A self query reads both sides from mesh[0] == mesh[1]: both are mesh 0.
    c->first_mesh = q->self ? 0u : (uint32_t)m_first;
    c->second_mesh = q->self ? 0u : (uint32_t)m_second;
    c->distance = r->distance;
    memcpy(c->wa, r->wa, sizeof c->wa);
    memcpy(c->wb, r->wb, sizeof c->wb);
    memcpy(c->direction, r->direction, sizeof c->direction);
}

int selfcol_query__test_vf(selfcol_query *q, int mv, uint32_t v, int mt, uint32_t t) {
    const selfcol_mesh *meshv = q->mesh[mv], *mesht = q->mesh[mt];
    const uint32_t *tri = mesht->triangles + 3 * (size_t)t;
    const double *p = selfcol_mesh__position(meshv, v);
    const double *a = selfcol_mesh__position(mesht, tri[0]);
    const double *b = selfcol_mesh__position(mesht, tri[1]);
    const double *c = selfcol_mesh__position(mesht, tri[2]);
    selfcol_narrow_result r;
    double dist = q->narrow == SELFCOL_NARROW_LIBCCD
                      ? selfcol_narrow_ccd__vf(p, a, b, c, q->distance, q->ccd_tolerance, &r)
                      : selfcol_narrow__vf(p, a, b, c, &r);
    q->out->stats.vf_tests++;
    if (!(dist < q->distance))
        return SELFCOL_OK;
    selfcol_contact rec;
    fill_record(q, &rec, SELFCOL_CONTACT_VF, mv, v, mt, t, &r);
    rec.a[0] = rec.a[1] = v;
    memcpy(rec.b, tri, sizeof rec.b);
    q->out->stats.vf_contacts++;
    return selfcol_contacts__push(q->out, &rec);
}

int selfcol_query__test_ee(selfcol_query *q, int me, uint32_t e, int mf, uint32_t f) {
    const uint32_t *ev = q->mesh[me]->edges + 2 * (size_t)e;
    const uint32_t *fv = q->mesh[mf]->edges + 2 * (size_t)f;
    const double *p0 = selfcol_mesh__position(q->mesh[me], ev[0]);
    const double *p1 = selfcol_mesh__position(q->mesh[me], ev[1]);
    const double *q0 = selfcol_mesh__position(q->mesh[mf], fv[0]);
    const double *q1 = selfcol_mesh__position(q->mesh[mf], fv[1]);
    selfcol_narrow_result r;
    double dist = q->narrow == SELFCOL_NARROW_LIBCCD
                      ? selfcol_narrow_ccd__ee(p0, p1, q0, q1, q->distance, q->ccd_tolerance, &r)
                      : selfcol_narrow__ee(p0, p1, q0, q1, &r);
    q->out->stats.ee_tests++;
    if (!(dist < q->distance))
        return SELFCOL_OK;
    selfcol_contact rec;
    fill_record(q, &rec, SELFCOL_CONTACT_EE, me, e, mf, f, &r);
    rec.a[0] = ev[0];
    rec.a[1] = ev[1];
    rec.b[0] = fv[0];
    rec.b[1] = fv[1];
    rec.b[2] = SELFCOL_INVALID_INDEX;
    q->out->stats.ee_contacts++;
    return selfcol_contacts__push(q->out, &rec);
}

int selfcol_query__test_ef(selfcol_query *q, int me, uint32_t e, int mt, uint32_t t) {
    const uint32_t *ev = q->mesh[me]->edges + 2 * (size_t)e;
    const uint32_t *tri = q->mesh[mt]->triangles + 3 * (size_t)t;
    const double *p0 = selfcol_mesh__position(q->mesh[me], ev[0]);
    const double *p1 = selfcol_mesh__position(q->mesh[me], ev[1]);
    const double *a = selfcol_mesh__position(q->mesh[mt], tri[0]);
    const double *b = selfcol_mesh__position(q->mesh[mt], tri[1]);
    const double *c = selfcol_mesh__position(q->mesh[mt], tri[2]);
    selfcol_narrow_result r;
    int hit = q->narrow == SELFCOL_NARROW_LIBCCD
                  ? selfcol_narrow_ccd__ef(p0, p1, a, b, c, q->ccd_tolerance, &r)
                  : selfcol_narrow__ef(p0, p1, a, b, c, &r);
    q->out->stats.ef_tests++;
    if (!hit)
        return SELFCOL_OK;
    selfcol_contact rec;
    fill_record(q, &rec, SELFCOL_CONTACT_EF, me, e, mt, t, &r);
    rec.a[0] = ev[0];
    rec.a[1] = ev[1];
    memcpy(rec.b, tri, sizeof rec.b);
    q->out->stats.ef_contacts++;
    return selfcol_contacts__push(q->out, &rec);
}

static int run_query(const selfcol_hierarchy *first, const selfcol_hierarchy *second,
                     selfcol_contacts *contacts, const selfcol_query_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && contacts != NULL);
    SELFCOL_CHECK_VERSION(opts, SELFCOL_QUERY_OPTIONS_VERSION);
    selfcol_query_options defaults;
    if (opts == NULL) {
        selfcol_query_options_init(&defaults, SELFCOL_QUERY_OPTIONS_VERSION);
        opts = &defaults;
    }
    SELFCOL_CHECK(opts->method <= SELFCOL_METHOD_EXACT);
    SELFCOL_CHECK(opts->narrow == SELFCOL_NARROW_CLOSED_FORM ||
                  opts->narrow == SELFCOL_NARROW_LIBCCD);
    SELFCOL_CHECK((opts->kinds & ~(uint32_t)SELFCOL_KIND_ALL) == 0);
    SELFCOL_CHECK(isfinite(opts->distance) && opts->distance >= 0.0);

    if (opts->method != SELFCOL_METHOD_EXHAUSTIVE &&
        (first->refit_version != first->mesh->positions_version ||
         second->refit_version != second->mesh->positions_version))
        return SELFCOL_ESTALE;

    double start = selfcol_core__seconds();
    selfcol_contacts_clear(contacts);
    selfcol_query q;
    q.mesh[0] = first->mesh;
    q.mesh[1] = second->mesh;
    q.self = (first == second);
    q.distance = opts->distance;
    q.kinds = opts->kinds;
    q.narrow = opts->narrow;
    // libccd's tolerances are absolute: its distances (a bisection on the
    // inflation radius) are asked to 1e-7 of the detection distance.
    q.ccd_tolerance = 1e-7 * q.distance;
    q.out = contacts;

    int status = opts->method == SELFCOL_METHOD_EXHAUSTIVE
                     ? selfcol_exhaustive__run(&q)
                     : selfcol_traverse__run(&q, first, second, opts->method);
    if (status != SELFCOL_OK) {
        selfcol_contacts_clear(contacts);
        return status;
    }
    selfcol_contacts__sort(contacts);
    contacts->stats.total_seconds = selfcol_core__seconds() - start;
    return SELFCOL_OK;
}

int selfcol_hierarchy_self_collide(const selfcol_hierarchy *hierarchy, selfcol_contacts *contacts,
                                   const selfcol_query_options *opts) {
    return run_query(hierarchy, hierarchy, contacts, opts);
}

int selfcol_hierarchy_collide(const selfcol_hierarchy *first, const selfcol_hierarchy *second,
                              selfcol_contacts *contacts, const selfcol_query_options *opts) {
    SELFCOL_CHECK(first != NULL && second != NULL && first->mesh != second->mesh);
    return run_query(first, second, contacts, opts);
}
