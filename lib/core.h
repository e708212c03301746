// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Internal helpers shared by every file of the core (cf. Box2D src/core.h).
#ifndef SELFCOL_CORE_H
#define SELFCOL_CORE_H

#include <selfcol/common.h>

#define SELFCOL_UNUSED(x) ((void)(x))

// Misuse checks. In every build they return SELFCOL_EINVAL from the public
// function (a stable API must not crash on bad input); SELFCOL_VALIDATE builds
// additionally abort, to catch the misuse in development.
#if defined(SELFCOL_VALIDATE)
#include <assert.h>
#define SELFCOL_ASSERT(cond) assert(cond)
#else
#define SELFCOL_ASSERT(cond) ((void)0)
#endif

#define SELFCOL_CHECK(cond)                                                                        \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            SELFCOL_ASSERT(cond);                                                                  \
            return SELFCOL_EINVAL;                                                                 \
        }                                                                                          \
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
