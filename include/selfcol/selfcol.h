// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file selfcol.h
 * Umbrella header of libselfcol: collision and self-collision detection for
 * deformable triangle surfaces.
 *
 * Thread safety: libselfcol keeps no global mutable state. Queries on one
 * hierarchy (or on hierarchies over one mesh) may run at the same time from
 * several threads, each with its own selfcol_contacts, while nothing modifies
 * that mesh or those hierarchies; read-only calls may run with each other and
 * with queries filling other contact sets; unrelated handles are independent.
 * Never at the same time: selfcol_mesh_set_positions* with any call reading
 * that mesh (refits and queries of its hierarchies included), a refit with a
 * query on that hierarchy, two queries into one selfcol_contacts or through
 * one selfcol_context, or any call
 * with the destruction of a handle it uses. The library starts threads only
 * inside a query with selfcol_query_options.threads > 1 (or a continuous
 * one, selfcol_sweep_options.threads), inside a store update with
 * selfcol_store_options.threads > 1, and inside a refit (and the refit
 * ending creation) of a hierarchy with selfcol_hierarchy_options.threads
 * > 1, and joins them before the call returns, except a query through a
 * context: a context keeps its threads asleep between its queries and
 * selfcol_context_destroy() joins them, or, with a scheduler, runs on the
 * scheduler's threads instead (context.h).
 * The contacts' and the context's allocators may be called from a query's
 * threads at once (a store allocates before its threads start). Every
 * other callback runs on the calling thread.
 */
#ifndef SELFCOL_SELFCOL_H
#define SELFCOL_SELFCOL_H

#include "common.h"
#include "contacts.h"
#include "context.h"
#include "hierarchy.h"
#include "mesh.h"
#include "scene.h"
#include "sequence.h"
#include "store.h"
#include "sweep.h"
#include "version.h"

#endif /* SELFCOL_SELFCOL_H */
