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
 * with the destruction of a handle it uses. The library runs on threads only
 * through a context (context.h: the calls named selfcol_context_*, and a
 * scene or Bullet adapter given one): the context keeps its threads asleep
 * between calls and selfcol_context_destroy() joins them, or, with a
 * scheduler, runs on the scheduler's threads instead. Every other call runs
 * on the calling thread.
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
