// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT
#include "world.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <string.h>

void world_make(world *w, const fixture *s) {
    memset(w, 0, sizeof *w);
    assert_int_equal(selfcol_mesh_create(&w->mesh, s->vertex_count, s->positions, s->triangle_count,
                                         s->triangles, NULL),
                     SELFCOL_OK);
    assert_int_equal(selfcol_hierarchy_create(&w->hierarchy, w->mesh, NULL), SELFCOL_OK);
    assert_int_equal(selfcol_contacts_create(&w->contacts, NULL), SELFCOL_OK);
}

void world_free(world *w) {
    selfcol_contacts_destroy(w->contacts);
    selfcol_hierarchy_destroy(w->hierarchy);
    selfcol_mesh_destroy(w->mesh);
}

selfcol_query_stats query_counters(const selfcol_contacts *c) {
    selfcol_query_stats st;
    memset(&st, 0, sizeof st);
    st.version = SELFCOL_QUERY_STATS_VERSION;
    assert_int_equal(selfcol_contacts_stats(c, &st), SELFCOL_OK);
    st.broad_seconds = st.narrow_seconds = st.total_seconds = 0.0;
    st.contour_seconds = st.sort_seconds = 0.0;
    return st;
}
