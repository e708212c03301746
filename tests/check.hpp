// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// The adapters' C++ tests (adapters/*/tests) check without a framework: a
// failed CHECK prints where and what, counts, and the test goes on, so one
// run lists every failure; main() returns nonzero when `failures` is.
// One test program per translation unit: each has its own counter.
#ifndef SELFCOL_TESTS_CHECK_HPP
#define SELFCOL_TESTS_CHECK_HPP

#include <cstdio>

static int failures = 0;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);          \
            ++failures;                                                                            \
        }                                                                                          \
    } while (0)

#endif // SELFCOL_TESTS_CHECK_HPP
