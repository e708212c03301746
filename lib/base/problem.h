// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Naming a refused option (selfcol_options_problem, common.h). An options
// validator takes where to report (a selfcol_problem_at, or NULL when its
// caller, a create or query call, needs the status only) and refuses each
// field through SELFCOL_CHECK_FIELD, which names it.
#ifndef SELFCOL_PROBLEM_H
#define SELFCOL_PROBLEM_H

#include <selfcol/common.h>

#include "base/alloc.h" // SELFCOL_CHECK_ALLOCATOR

// Where a validator reports: the problem (NULL: nowhere), the struct's C
// name, and the prefix of its fields when another struct points to it
// ("query->" in selfcol_scene_options), else "".
typedef struct selfcol_problem_at {
    selfcol_options_problem *problem;
    const char *type;
    const char *prefix;
} selfcol_problem_at;

// The start of a public *_options_check(): the problem's own arguments.
// SELFCOL_OK (the problem cleared: accepted until a check says otherwise),
// SELFCOL_EINVAL for a NULL problem, SELFCOL_EVERSION for its version.
int selfcol_problem__begin(selfcol_options_problem *problem);

// Records status for the field (at may be NULL, and at->problem: nothing is
// written): the field "prefix+field" and the sentence "type.prefix+field
// <printf text>". Returns status. The first refusal wins: a validator
// returns at once.
int selfcol_problem__field(const selfcol_problem_at *at, int status, const char *field,
                           const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

// The version field of an options struct: 0 is "never initialised", above
// latest "newer than this library" (SELFCOL_EVERSION, named).
int selfcol_problem__version(const selfcol_problem_at *at, unsigned int version,
                             unsigned int latest);

// As selfcol_problem__version, also refusing versions below `first`: the
// layouts an ABI break left behind (0.4 moved every `threads` field to the
// context), named as such.
int selfcol_problem__version_since(const selfcol_problem_at *at, unsigned int version,
                                   unsigned int first, unsigned int latest);

// A pointed-to struct's place: the same problem and type, prefix extended
// by `field->` (into holds the text; 64 bytes are plenty for our names).
selfcol_problem_at selfcol_problem__nested(const selfcol_problem_at *at, const char *field,
                                           char into[64]);

// Refuses field when cond is false: SELFCOL_EINVAL, named.
#define SELFCOL_CHECK_FIELD(at, cond, field, ...)                                                  \
    do {                                                                                           \
        if (!(cond))                                                                               \
            return selfcol_problem__field(at, SELFCOL_EINVAL, field, __VA_ARGS__);                 \
    } while (0)

// The allocator rule of every options struct: both functions or neither.
#define SELFCOL_CHECK_ALLOCATOR(at, allocator)                                                     \
    SELFCOL_CHECK_FIELD(at, selfcol_alloc__valid(&(allocator)), "allocator",                       \
                        "is half set: give both alloc and free, or neither")

#endif // SELFCOL_PROBLEM_H
