// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The contact store's internal entry points (the store itself: store.c).
#ifndef SELFCOL_STORE_INTERNAL_H
#define SELFCOL_STORE_INTERNAL_H

#include <selfcol/store.h>

// Reads a caller's store options (NULL: the defaults) as their version says
// into a copy of the current version, and checks every field: SELFCOL_OK,
// SELFCOL_EVERSION or SELFCOL_EINVAL. Stores and scenes go through it.
int selfcol_store__options(selfcol_store_options *out, const selfcol_store_options *opts);

#endif // SELFCOL_STORE_INTERNAL_H
