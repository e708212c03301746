// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

/**
 * @file common.h
 * @defgroup common Common definitions
 * Export macros, status codes, allocator hooks and plain value types shared by
 * every selfcol header.
 * @{
 */
#ifndef SELFCOL_COMMON_H
#define SELFCOL_COMMON_H

#include <stddef.h>
#include <stdint.h>

#if defined(SELFCOL_STATIC)
#define SELFCOL_API
#elif defined(_WIN32) && defined(SELFCOL_BUILDING)
#define SELFCOL_API __declspec(dllexport)
#elif defined(_WIN32)
#define SELFCOL_API __declspec(dllimport)
#elif defined(__GNUC__) && __GNUC__ >= 4
#define SELFCOL_API __attribute__((visibility("default")))
#else
#define SELFCOL_API
#endif

#ifdef __cplusplus
#define SELFCOL_BEGIN_DECLS extern "C" {
#define SELFCOL_END_DECLS }
#else
#define SELFCOL_BEGIN_DECLS
#define SELFCOL_END_DECLS
#endif

#if defined(__GNUC__) || defined(__clang__)
#define SELFCOL_DEPRECATED(msg) __attribute__((deprecated(msg)))
#else
#define SELFCOL_DEPRECATED(msg)
#endif

/** Largest thread count of a context (selfcol_context_options.threads, the
 *  Bullet adapter's threads): defined here, so that each header that names
 *  it compiles alone. */
#define SELFCOL_MAX_THREADS 64

SELFCOL_BEGIN_DECLS

/** Opaque query context (context.h): the one place where threads are said.
 *  Declared here so that the headers of the handles it serves can name it. */
typedef struct selfcol_context selfcol_context;

/**
 * Status codes returned by every fallible function: 0 on success, negative on
 * failure. The values are pinned forever; new codes are only appended.
 */
typedef enum selfcol_status {
    SELFCOL_OK = 0, /**< success */
    /** An unspecified internal error: returned only by the Bullet adapter's
     *  step, for an exception other than std::bad_alloc thrown inside it. */
    SELFCOL_ERROR = -1,
    SELFCOL_ENOMEM = -2,   /**< the allocator returned NULL */
    SELFCOL_EINVAL = -3,   /**< an argument or the input data is invalid */
    SELFCOL_EVERSION = -4, /**< options.version is 0 or unknown to this library */
    /** Reserved, never returned (0.1 to 0.3): a caller-provided buffer is too small. */
    SELFCOL_EBUFS = -5,
    /** A callback asked to stop (selfcol_sweep_options.progress returned non-zero). */
    SELFCOL_EUSER = -6,
    /** A count, index or coordinate is outside what the library represents
     *  exactly (mesh sizes, the coordinate range of mesh.h). */
    SELFCOL_ERANGE = -7,
    /** Handles or data that must belong together do not (selfcol_store_update()
     *  with other meshes than the store follows, or records of another mesh;
     *  a hierarchy refit or queried on a mesh other than its own). */
    SELFCOL_EMISMATCH = -8,
    SELFCOL_ESTALE = -9 /**< a hierarchy was not refit after its mesh moved */
} selfcol_status;

/**
 * Human-readable text for a status code.
 * @param[in] status a value returned by a selfcol function (any int is accepted)
 * @return a static, NUL-terminated string; never NULL. Borrowed: do not free.
 */
SELFCOL_API const char *selfcol_status_string(int status);

/**
 * Allocator hooks, given per handle in its options. All-zero (both function
 * pointers NULL) selects the C library's allocator. Either both functions are
 * set or neither; a half-set allocator is rejected with SELFCOL_EINVAL.
 */
typedef struct selfcol_allocator {
    /** Returns size bytes aligned to alignment (a power of two), or NULL. */
    void *(*alloc)(void *user, size_t size, size_t alignment);
    /** Frees ptr, which alloc returned for exactly size bytes. ptr is never NULL. */
    void (*free)(void *user, void *ptr, size_t size);
    /** Passed unchanged to alloc and free. */
    void *user;
} selfcol_allocator;

/** Sentinel index: "no such vertex, edge or triangle". */
#define SELFCOL_INVALID_INDEX UINT32_MAX

/**
 * What an options struct's check (selfcol_query_options_check() and its
 * siblings, one per options struct) found wrong: the field, by its C name,
 * and a sentence a front can print as it is. A status code says that an
 * option was refused; this says which and why, with no global state: the
 * caller asks, after a call failed or before making it.
 */
typedef struct selfcol_options_problem {
    unsigned int version; /**< SELFCOL_OPTIONS_PROBLEM_VERSION, set by the caller */
    /** What the options' consumer (the create or query call) returns for
     *  them: SELFCOL_OK when they are accepted, else SELFCOL_EINVAL or
     *  SELFCOL_EVERSION. */
    int status;
    /** The refused field as the C code names it ("distance", "threads",
     *  "query.kinds" in a struct nested by value); "" when accepted. */
    char field[64];
    /** The whole sentence, naming the struct, the field, the value and what
     *  is accepted: "selfcol_query_options.distance = nan is not a distance
     *  in 0 .. 1.60694e+60"; "" when accepted. */
    char message[256];
} selfcol_options_problem;

#define SELFCOL_OPTIONS_PROBLEM_VERSION 1

/** @} */
SELFCOL_END_DECLS

#endif /* SELFCOL_COMMON_H */
