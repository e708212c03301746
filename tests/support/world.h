// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A scene loaded into the library: its mesh, a hierarchy over it and a
// contact set, as most public-API tests need them (creation failures fail
// the running cmocka test).
#ifndef SELFCOL_TEST_WORLD_H
#define SELFCOL_TEST_WORLD_H

#include <selfcol/selfcol.h>

#include "fixtures.h"

typedef struct world {
    selfcol_mesh *mesh;
    selfcol_hierarchy *hierarchy;
    selfcol_contacts *contacts;
} world;

void world_make(world *w, const fixture *s);
void world_free(world *w);

// A contact set's query statistics with the times (which differ from run
// to run) zeroed: what two runs of one query must share, field for field.
selfcol_query_stats query_counters(const selfcol_contacts *c);

#endif // SELFCOL_TEST_WORLD_H
