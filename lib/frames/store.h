// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact store's internal entry points (the store itself: store.c).
#ifndef SELFCOL_STORE_INTERNAL_H
#define SELFCOL_STORE_INTERNAL_H

#include <selfcol/store.h>

#include "base/problem.h"

// Reads a caller's store options (NULL: the defaults) as their version says
// into a copy of the current version, and checks every field: SELFCOL_OK,
// SELFCOL_EVERSION or SELFCOL_EINVAL. Stores and scenes go through it.
int selfcol_store__options(selfcol_store_options *out, const selfcol_store_options *opts,
                           const selfcol_problem_at *at);

// selfcol_store_update_swept() on a path of two straight segments per mesh:
// path[0] the positions at the store's previous update, path[1] those at the
// step's start (after the caller moved the meshes, e.g. a collision
// response), then the current ones. A sign change is a crossing when the
// elements may have touched on either segment. second_path NULL for a self
// store. On `context`'s threads (NULL: the calling thread). The scene's
// swept updates (selfcol_scene_set_surface_start()).
int selfcol_store__update_path(selfcol_context *context, selfcol_store *store,
                               const selfcol_mesh *first, const selfcol_mesh *second,
                               const selfcol_contacts *detected, const double *const first_path[2],
                               const double *const second_path[2]);

#endif // SELFCOL_STORE_INTERNAL_H
