// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file selfcol.h
 * Umbrella header of libselfcol: collision and self-collision detection for
 * deformable triangle surfaces.
 *
 * Thread safety: libselfcol keeps no global mutable state and starts no
 * threads. Different handles may be used at the same time from different
 * threads. One handle must not be used concurrently by calls that modify it.
 * Calls that take a `const` handle (queries, `selfcol_contacts_data`) may run
 * concurrently with each other. Callbacks, including the allocator, run on the
 * calling thread and must be thread-safe if you use handles from several
 * threads.
 */
#ifndef SELFCOL_SELFCOL_H
#define SELFCOL_SELFCOL_H

#include "common.h"
#include "contacts.h"
#include "hierarchy.h"
#include "mesh.h"
#include "version.h"

#endif /* SELFCOL_SELFCOL_H */
