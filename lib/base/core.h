// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Internal helpers shared by every file of the core (cf. Box2D src/core.h).
#ifndef SELFCOL_CORE_H
#define SELFCOL_CORE_H

#include <selfcol/common.h>

// Internal invariants: checked (aborting) in SELFCOL_VALIDATE builds, where
// the heavy checks run too (the hierarchy validator after every build and
// refit); nothing in other builds. Not assert(): it must not depend on NDEBUG.
#if defined(SELFCOL_VALIDATE)
#include <stdio.h>
#include <stdlib.h>
#define SELFCOL_ASSERT(cond)                                                                       \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: selfcol invariant failed: %s\n", __FILE__, __LINE__, #cond);   \
            abort();                                                                               \
        }                                                                                          \
    } while (0)
#else
#define SELFCOL_ASSERT(cond) ((void)0)
#endif

// Misuse checks: SELFCOL_EINVAL from the public function, in every build (a
// stable API must not crash on bad input, and the tests pass bad input on
// purpose, also in SELFCOL_VALIDATE builds).
#define SELFCOL_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond))                                                                               \
            return SELFCOL_EINVAL;                                                                 \
    } while (0)

// Checks the version field of an options struct: 0 means "never initialised",
// a value above `latest` comes from newer headers than this library.
#define SELFCOL_CHECK_VERSION(opts, latest)                                                        \
    do {                                                                                           \
        if ((opts) != NULL && ((opts)->version == 0 || (opts)->version > (latest)))                \
            return SELFCOL_EVERSION;                                                               \
    } while (0)

// Monotonic wall clock in seconds, for the per-stage timings of the statistics.
double selfcol_core__seconds(void);

#endif // SELFCOL_CORE_H
