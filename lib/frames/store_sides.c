// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact store: each contact's side (the exact sign of orient3d), its
// right side through crossings, and its geometry at the current positions
// (store.c's step 1; the method: store.c's opening comment).
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
void selfcol_store__geometry(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
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

void selfcol_store__add_triangle_normal(const selfcol_mesh *m, uint32_t t, double n[3]) {
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
            selfcol_store__add_triangle_normal(m, m->vertex_tris[k], n);
    } else if (vertices == 2) {
        for (uint32_t k = m->edge_tri_offsets[index]; k < m->edge_tri_offsets[index + 1]; ++k)
            selfcol_store__add_triangle_normal(m, m->edge_tris[k], n);
    } else {
        selfcol_store__add_triangle_normal(m, index, n);
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
// With the positions at the previous update (selfcol_store__update_path),
// the path has two straight segments, before -> start -> current, and the
// elements may have touched on either.
static int touched_in_step(const selfcol_store *s, const store_entry *e, const uint32_t a[2],
                           const uint32_t b[3]) {
    const uint32_t fm = first_mesh(e), sm = second_mesh(e);
    const int vf = e->kind == SELFCOL_CONTACT_VF;
    const uint32_t ids[4] = {a[0], vf ? b[0] : a[1], vf ? b[1] : b[0], vf ? b[2] : b[1]};
    const uint32_t of[4] = {fm, vf ? sm : fm, sm, sm};
    const double *before[4], *start[4], *end[4];
    for (int k = 0; k < 4; ++k) {
        const double *path_before = s->step_before[of[k]];
        start[k] = s->step_start[of[k]] + 3 * (size_t)ids[k];
        before[k] = path_before != NULL ? path_before + 3 * (size_t)ids[k] : start[k];
        end[k] = vertex_of(s, of[k], ids[k]);
    }
    if ((s->step_before[0] != NULL || s->step_before[1] != NULL) &&
        selfcol_narrow_sweep__may_touch(before, start, !vf, NULL))
        return 1;
    return selfcol_narrow_sweep__may_touch(start, end, !vf, NULL);
}

void selfcol_store__track_side(selfcol_store *s, store_entry *e, const uint32_t a[2],
                               const uint32_t b[3], selfcol_store_update_stats *st) {
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
