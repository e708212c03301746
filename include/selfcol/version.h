// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file version.h
 * @defgroup version Version
 * Compile-time and run-time version of the library. This header is the single
 * source of truth for the version: CMake and the Makefile read it.
 * @{
 */
#ifndef SELFCOL_VERSION_H
#define SELFCOL_VERSION_H

#include "common.h"

#define SELFCOL_VERSION_MAJOR 0
#define SELFCOL_VERSION_MINOR 4
#define SELFCOL_VERSION_PATCH 0

#define SELFCOL_VERSION_NUMBER                                                                     \
    (SELFCOL_VERSION_MAJOR * 10000 + SELFCOL_VERSION_MINOR * 100 + SELFCOL_VERSION_PATCH)

#define SELFCOL_VERSION_STRINGIFY_(x) #x
#define SELFCOL_VERSION_STRINGIFY(x) SELFCOL_VERSION_STRINGIFY_(x)
#define SELFCOL_VERSION_STRING                                                                     \
    SELFCOL_VERSION_STRINGIFY(SELFCOL_VERSION_MAJOR)                                               \
    "." SELFCOL_VERSION_STRINGIFY(SELFCOL_VERSION_MINOR) "." SELFCOL_VERSION_STRINGIFY(            \
        SELFCOL_VERSION_PATCH)

/** True when the headers are at least version M.m.p. */
#define SELFCOL_VERSION_CHECK(M, m, p) (SELFCOL_VERSION_NUMBER >= ((M)*10000 + (m)*100 + (p)))

SELFCOL_BEGIN_DECLS

/**
 * Version of the library actually linked, as MAJOR*10000 + MINOR*100 + PATCH.
 * @return the version number; cannot fail.
 */
SELFCOL_API unsigned selfcol_version_number(void);

/**
 * Version of the library actually linked, as "MAJOR.MINOR.PATCH".
 * @return a static string; never NULL. Borrowed: do not free.
 */
SELFCOL_API const char *selfcol_version_string(void);

SELFCOL_END_DECLS
/** @} */

#endif /* SELFCOL_VERSION_H */
