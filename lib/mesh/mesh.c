// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Mesh creation, validation, position updates and accessors. Input is
// validated completely before anything is allocated or written, so a rejected
// call never leaves a half-updated mesh behind.
#include "mesh/mesh.h"

#include "base/alloc.h"
#include "base/core.h"
#include "base/predicates.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int selfcol_mesh_options_init(selfcol_mesh_options *opts, unsigned int version) {
    SELFCOL_CHECK(opts != NULL);
    if (version == 0 || version > SELFCOL_MESH_OPTIONS_VERSION)
        return SELFCOL_EVERSION;
    memset(opts, 0, sizeof *opts);
    opts->version = version;
    return SELFCOL_OK;
}

// Positions come as doubles or as strided floats; one reader for both.
typedef struct position_source {
    const double *xyz;         // packed doubles, or NULL
    const unsigned char *base; // strided floats
    size_t stride;
} position_source;

static void read_position(const position_source *src, size_t v, double out[3]) {
    if (src->xyz != NULL) {
        out[0] = src->xyz[3 * v];
        out[1] = src->xyz[3 * v + 1];
        out[2] = src->xyz[3 * v + 2];
    } else {
        float f[3];
        memcpy(f, src->base + v * src->stride, sizeof f);
        out[0] = f[0];
        out[1] = f[1];
        out[2] = f[2];
    }
}

// The coordinate contract (mesh.h): finite, and every coordinate 0 or of
// magnitude in [SELFCOL_MESH_MIN_COORDINATE, SELFCOL_MESH_MAX_COORDINATE].
// Inside it, the closed forms' squared lengths and the pair filters'
// products neither overflow nor underflow, so their rounding bounds hold, and
// the exact predicates hold (predicates.h). Beyond it a crossing pair scaled
// by 10^103 or 10^-109 gave no interference and mean edge lengths inf or 0;
// and the mesh fuzzer found a mesh mixing 1e18 with subnormal coordinates
// (1e-281, 1e-316) where BVH and EXACT missed an EF crossing EXHAUSTIVE saw.
//
// One checker for creation, new positions and selfcol_mesh_check: the
// status of the first problem, and with `problem` (NULL: the status only)
// the problem named.

static int problem_none(selfcol_mesh_problem *p) {
    if (p != NULL) {
        p->status = SELFCOL_OK;
        p->kind = SELFCOL_MESH_PROBLEM_NONE;
        p->component = 0;
        p->element = 0;
        p->value = NAN;
        p->reason[0] = p->message[0] = '\0';
    }
    return SELFCOL_OK;
}

static int problem_at(selfcol_mesh_problem *p, int status, uint32_t kind, uint64_t element,
                      uint32_t component, double value, const char *reason, const char *message) {
    if (p != NULL) {
        p->status = status;
        p->kind = kind;
        p->element = element;
        p->component = component;
        p->value = value;
        snprintf(p->reason, sizeof p->reason, "%s", reason);
        snprintf(p->message, sizeof p->message, "%s", message);
    }
    return status;
}

static int coordinate_problem(selfcol_mesh_problem *p, uint32_t kind, size_t v, int k, double x,
                              const position_source *src) {
    static const char *const why[] = {
        "is not finite", "is beyond the largest coordinate magnitude 2^200 (about 1.6e60)",
        "is below the smallest nonzero coordinate magnitude 2^-200 (about 6.2e-61; flush it "
        "to 0)"};
    const char *reason = why[kind - SELFCOL_MESH_PROBLEM_NOT_FINITE];
    const int status = kind == SELFCOL_MESH_PROBLEM_NOT_FINITE ? SELFCOL_EINVAL : SELFCOL_ERANGE;
    if (p == NULL)
        return status;
    char message[sizeof p->message];
    snprintf(message, sizeof message, "positions%s[%zu] (vertex %zu, %c) = %.17g %s",
             src->xyz != NULL ? "" : " (floats)", 3 * v + (size_t)k, v, "xyz"[k], x, reason);
    return problem_at(p, status, kind, v, (uint32_t)k, x, reason, message);
}

static int positions_check(const position_source *src, size_t vertex_count,
                           selfcol_mesh_problem *problem) {
    // The first non-finite coordinate wins over an earlier one out of range
    // (EINVAL before ERANGE, as the status always was).
    size_t range_v = 0;
    int range_k = -1;
    uint32_t range_kind = 0;
    double range_x = 0.0;
    for (size_t v = 0; v < vertex_count; ++v) {
        double p[3];
        read_position(src, v, p);
        for (int k = 0; k < 3; ++k) {
            if (!isfinite(p[k]))
                return coordinate_problem(problem, SELFCOL_MESH_PROBLEM_NOT_FINITE, v, k, p[k],
                                          src);
            const double a = fabs(p[k]);
            if (range_k < 0 && (a > SELFCOL_MESH_MAX_COORDINATE ||
                                (a != 0.0 && a < SELFCOL_MESH_MIN_COORDINATE))) {
                range_v = v;
                range_k = k;
                range_x = p[k];
                range_kind = a > SELFCOL_MESH_MAX_COORDINATE ? SELFCOL_MESH_PROBLEM_TOO_LARGE
                                                             : SELFCOL_MESH_PROBLEM_TOO_SMALL;
            }
        }
    }
    if (range_k >= 0)
        return coordinate_problem(problem, range_kind, range_v, range_k, range_x, src);
    return problem_none(problem);
}

// What create_mesh refuses, in its order: arguments, counts, indices,
// coordinates.
static int input_check(size_t vertex_count, const position_source *src, size_t triangle_count,
                       const uint32_t *triangles, selfcol_mesh_problem *problem) {
    const char *null_name = (src->xyz == NULL && src->base == NULL) ? "positions"
                            : triangles == NULL                     ? "triangles"
                                                                    : NULL;
    if (null_name != NULL) {
        char message[64];
        snprintf(message, sizeof message, "%s is NULL", null_name);
        return problem_at(problem, SELFCOL_EINVAL, SELFCOL_MESH_PROBLEM_ARGUMENT, 0, 0, NAN,
                          "is NULL", message);
    }
    if (vertex_count == 0 || triangle_count == 0)
        return problem_at(problem, SELFCOL_EINVAL, SELFCOL_MESH_PROBLEM_ARGUMENT, 0, 0, NAN,
                          "is 0 (an empty mesh)",
                          vertex_count == 0 ? "vertex_count is 0 (an empty mesh)"
                                            : "triangle_count is 0 (an empty mesh)");
    if (vertex_count > SELFCOL_MESH_MAX_VERTICES || triangle_count > SELFCOL_MESH_MAX_TRIANGLES) {
        char message[sizeof problem->message];
        const int vertices = vertex_count > SELFCOL_MESH_MAX_VERTICES;
        snprintf(message, sizeof message, "%s = %zu is more than %s indices hold (%zu)",
                 vertices ? "vertex_count" : "triangle_count",
                 vertices ? vertex_count : triangle_count, vertices ? "vertex" : "triangle",
                 vertices ? (size_t)SELFCOL_MESH_MAX_VERTICES : (size_t)SELFCOL_MESH_MAX_TRIANGLES);
        return problem_at(problem, SELFCOL_ERANGE, SELFCOL_MESH_PROBLEM_COUNT, 0, 0, NAN,
                          "is more than 32-bit indices hold", message);
    }
    for (size_t i = 0; i < 3 * triangle_count; ++i)
        if (triangles[i] >= vertex_count) {
            if (problem == NULL)
                return SELFCOL_EINVAL;
            char reason[sizeof problem->reason], message[sizeof problem->message];
            snprintf(reason, sizeof reason, "is not a vertex (vertex_count = %zu)", vertex_count);
            snprintf(message, sizeof message, "triangles[%zu] (triangle %zu, corner %zu) = %lu %s",
                     i, i / 3, i % 3, (unsigned long)triangles[i], reason);
            return problem_at(problem, SELFCOL_EINVAL, SELFCOL_MESH_PROBLEM_INDEX, i / 3,
                              (uint32_t)(i % 3), (double)triangles[i], reason, message);
        }
    return positions_check(src, vertex_count, problem);
}

static int problem_ready(selfcol_mesh_problem *problem) {
    SELFCOL_CHECK(problem != NULL);
    if (problem->version == 0 || problem->version > SELFCOL_MESH_PROBLEM_VERSION)
        return SELFCOL_EVERSION;
    return SELFCOL_OK;
}

int selfcol_mesh_check(size_t vertex_count, const double *positions, size_t triangle_count,
                       const uint32_t *triangles, selfcol_mesh_problem *problem) {
    const int ready = problem_ready(problem);
    if (ready != SELFCOL_OK)
        return ready;
    const position_source src = {positions, NULL, 0};
    return input_check(vertex_count, &src, triangle_count, triangles, problem);
}

int selfcol_mesh_check_positions(size_t vertex_count, const double *positions,
                                 selfcol_mesh_problem *problem) {
    const int ready = problem_ready(problem);
    if (ready != SELFCOL_OK)
        return ready;
    if (positions == NULL)
        return problem_at(problem, SELFCOL_EINVAL, SELFCOL_MESH_PROBLEM_ARGUMENT, 0, 0, NAN,
                          "is NULL", "positions is NULL");
    const position_source src = {positions, NULL, 0};
    return positions_check(&src, vertex_count, problem);
}

int selfcol_mesh__positions_in_contract(const double *xyz, size_t vertex_count) {
    for (size_t i = 0; i < 3 * vertex_count; ++i)
        if (!selfcol_mesh__coordinate_in_contract(xyz[i]))
            return 0;
    return 1;
}

static void copy_positions(double *dst, const position_source *src, size_t vertex_count) {
    if (src->xyz != NULL) {
        memcpy(dst, src->xyz, vertex_count * 3 * sizeof(double));
        return;
    }
    for (size_t v = 0; v < vertex_count; ++v)
        read_position(src, v, dst + 3 * v);
}

static int valid_stride(size_t stride_bytes) {
    return stride_bytes >= 3 * sizeof(float) && stride_bytes % sizeof(float) == 0;
}

// A 64-bit fingerprint of the topology as given (splitmix64's finaliser
// folded over the counts and the indices): O(F), once per mesh.
static uint64_t mix64(uint64_t h, uint64_t x) {
    h ^= x + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= h >> 30;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 27;
    h *= 0x94D049BB133111EBull;
    return h ^ (h >> 31);
}

// The identity also holds the creation time, in nanoseconds of the
// monotonic clock: a mesh destroyed and another created at its address with
// the same topology is still another mesh (its positions are not the ones
// a hierarchy's boxes were computed from).
static void set_identity(selfcol_mesh *m) {
    uint64_t h = mix64(mix64(0, m->vertex_count), m->triangle_count);
    for (size_t i = 0; i < 3 * m->triangle_count; ++i)
        h = mix64(h, m->triangles[i]);
    const uint64_t created = (uint64_t)(selfcol_core__seconds() * 1e9);
    m->identity =
        (selfcol_mesh_identity){m->vertex_count, m->triangle_count, m->edge_count, h, created};
}

static int create_mesh(selfcol_mesh **out, size_t vertex_count, const position_source *src,
                       size_t triangle_count, const uint32_t *triangles,
                       const selfcol_mesh_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK_VERSION(opts, SELFCOL_MESH_OPTIONS_VERSION);
    selfcol_allocator allocator = {NULL, NULL, NULL};
    if (opts != NULL)
        allocator = opts->allocator;
    SELFCOL_CHECK(selfcol_alloc__valid(&allocator));
    const int checked = input_check(vertex_count, src, triangle_count, triangles, NULL);
    if (checked != SELFCOL_OK)
        return checked;

    selfcol_mesh *m = selfcol_alloc__raw(&allocator, sizeof *m);
    if (m == NULL)
        return SELFCOL_ENOMEM;
    memset(m, 0, sizeof *m);
    m->allocator = allocator;
    m->vertex_count = vertex_count;
    m->triangle_count = triangle_count;
    m->positions = selfcol_alloc__array(&allocator, 3 * vertex_count, sizeof(double));
    m->triangles = selfcol_alloc__array(&allocator, 3 * triangle_count, sizeof(uint32_t));
    int status = SELFCOL_ENOMEM;
    if (m->positions != NULL && m->triangles != NULL) {
        copy_positions(m->positions, src, vertex_count);
        memcpy(m->triangles, triangles, 3 * triangle_count * sizeof(uint32_t));
        status = selfcol_mesh__build_topology(m);
    }
    if (status == SELFCOL_OK)
        set_identity(m);
    if (status != SELFCOL_OK) {
        selfcol_mesh_destroy(m);
        return status;
    }
    *out = m;
    return SELFCOL_OK;
}

int selfcol_mesh_create(selfcol_mesh **out, size_t vertex_count, const double *positions,
                        size_t triangle_count, const uint32_t *triangles,
                        const selfcol_mesh_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK(positions != NULL);
    position_source src = {positions, NULL, 0};
    return create_mesh(out, vertex_count, &src, triangle_count, triangles, opts);
}

int selfcol_mesh_create_float(selfcol_mesh **out, size_t vertex_count, const float *positions,
                              size_t stride_bytes, size_t triangle_count, const uint32_t *triangles,
                              const selfcol_mesh_options *opts) {
    SELFCOL_CHECK(out != NULL);
    *out = NULL;
    SELFCOL_CHECK(positions != NULL && valid_stride(stride_bytes));
    position_source src = {NULL, (const unsigned char *)positions, stride_bytes};
    return create_mesh(out, vertex_count, &src, triangle_count, triangles, opts);
}

void selfcol_mesh_destroy(selfcol_mesh *mesh) {
    if (mesh == NULL)
        return;
    selfcol_allocator allocator = mesh->allocator;
    selfcol_mesh__free_topology(mesh);
    selfcol_alloc__free_array(&allocator, mesh->positions, 3 * mesh->vertex_count, sizeof(double));
    selfcol_alloc__free_array(&allocator, mesh->triangles, 3 * mesh->triangle_count,
                              sizeof(uint32_t));
    selfcol_alloc__free(&allocator, mesh, sizeof *mesh);
}

static int set_positions(selfcol_mesh *mesh, const position_source *src) {
    int checked = positions_check(src, mesh->vertex_count, NULL);
    if (checked != SELFCOL_OK)
        return checked;
    // Positions equal to the current ones are not a move: the version (which
    // hierarchies, queries and static scene surfaces compare) stays, so
    // setting a static surface's own positions again is harmless.
    int moved = 0;
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        double p[3];
        read_position(src, v, p);
        double *q = mesh->positions + 3 * v;
        moved |= p[0] != q[0] || p[1] != q[1] || p[2] != q[2];
        q[0] = p[0];
        q[1] = p[1];
        q[2] = p[2];
    }
    mesh->positions_version += moved;
    return SELFCOL_OK;
}

int selfcol_mesh_set_positions(selfcol_mesh *mesh, const double *positions, size_t vertex_count) {
    SELFCOL_CHECK(mesh != NULL && positions != NULL);
    SELFCOL_CHECK(vertex_count == mesh->vertex_count);
    position_source src = {positions, NULL, 0};
    return set_positions(mesh, &src);
}

int selfcol_mesh_set_positions_float(selfcol_mesh *mesh, const float *positions,
                                     size_t stride_bytes, size_t vertex_count) {
    SELFCOL_CHECK(mesh != NULL && positions != NULL && valid_stride(stride_bytes));
    SELFCOL_CHECK(vertex_count == mesh->vertex_count);
    position_source src = {NULL, (const unsigned char *)positions, stride_bytes};
    return set_positions(mesh, &src);
}

static int zero_area(const selfcol_mesh *mesh, size_t t) {
    const uint32_t *tri = mesh->triangles + 3 * t;
    return selfcol_predicates__collinear3d(selfcol_mesh__position(mesh, tri[0]),
                                           selfcol_mesh__position(mesh, tri[1]),
                                           selfcol_mesh__position(mesh, tri[2]));
}

size_t selfcol_mesh_count(const selfcol_mesh *mesh, selfcol_mesh_quantity quantity) {
    if (mesh == NULL)
        return 0;
    switch (quantity) {
    case SELFCOL_MESH_VERTICES: return mesh->vertex_count;
    case SELFCOL_MESH_TRIANGLES: return mesh->triangle_count;
    case SELFCOL_MESH_EDGES: return mesh->edge_count;
    case SELFCOL_MESH_BOUNDARY_EDGES: return mesh->boundary_edges;
    case SELFCOL_MESH_NONMANIFOLD_EDGES: return mesh->nonmanifold_edges;
    case SELFCOL_MESH_COMPONENTS: return mesh->components;
    case SELFCOL_MESH_UNREFERENCED_VERTICES: return mesh->unreferenced_vertices;
    case SELFCOL_MESH_REPEATED_INDEX_TRIANGLES: return mesh->repeated_index_triangles;
    case SELFCOL_MESH_DUPLICATE_TRIANGLES: return mesh->duplicate_triangles;
    case SELFCOL_MESH_BOUNDARY_LOOPS: return mesh->boundary_loops;
    case SELFCOL_MESH_MISORIENTED_EDGES: return mesh->misoriented_edges;
    case SELFCOL_MESH_ZERO_AREA_TRIANGLES: {
        size_t count = 0;
        for (size_t t = 0; t < mesh->triangle_count; ++t)
            count += (size_t)zero_area(mesh, t);
        return count;
    }
    }
    return 0;
}

const double *selfcol_mesh_positions(const selfcol_mesh *mesh) {
    return mesh != NULL ? mesh->positions : NULL;
}

const uint32_t *selfcol_mesh_triangles(const selfcol_mesh *mesh) {
    return mesh != NULL ? mesh->triangles : NULL;
}

const uint32_t *selfcol_mesh_edges(const selfcol_mesh *mesh) {
    return mesh != NULL ? mesh->edges : NULL;
}

int selfcol_mesh_triangle_edges(const selfcol_mesh *mesh, uint32_t triangle,
                                uint32_t edges_out[3]) {
    SELFCOL_CHECK(mesh != NULL && edges_out != NULL && triangle < mesh->triangle_count);
    memcpy(edges_out, mesh->triangle_edges + 3 * (size_t)triangle, 3 * sizeof(uint32_t));
    return SELFCOL_OK;
}

int selfcol_mesh_edge_triangles(const selfcol_mesh *mesh, uint32_t edge,
                                const uint32_t **triangles_out, size_t *count_out) {
    SELFCOL_CHECK(mesh != NULL && triangles_out != NULL && count_out != NULL);
    SELFCOL_CHECK(edge < mesh->edge_count);
    *triangles_out = mesh->edge_tris + mesh->edge_tri_offsets[edge];
    *count_out = mesh->edge_tri_offsets[edge + 1] - mesh->edge_tri_offsets[edge];
    return SELFCOL_OK;
}

int selfcol_mesh_vertex_triangles(const selfcol_mesh *mesh, uint32_t vertex,
                                  const uint32_t **triangles_out, size_t *count_out) {
    SELFCOL_CHECK(mesh != NULL && triangles_out != NULL && count_out != NULL);
    SELFCOL_CHECK(vertex < mesh->vertex_count);
    *triangles_out = mesh->vertex_tris + mesh->vertex_tri_offsets[vertex];
    *count_out = mesh->vertex_tri_offsets[vertex + 1] - mesh->vertex_tri_offsets[vertex];
    return SELFCOL_OK;
}

uint32_t selfcol_mesh_triangle_flags(const selfcol_mesh *mesh, uint32_t triangle) {
    if (mesh == NULL || triangle >= mesh->triangle_count)
        return 0;
    uint32_t flags = mesh->triangle_flags[triangle];
    if (zero_area(mesh, triangle))
        flags |= SELFCOL_TRIANGLE_ZERO_AREA;
    return flags;
}

uint32_t selfcol_mesh_triangle_component(const selfcol_mesh *mesh, uint32_t triangle) {
    if (mesh == NULL || triangle >= mesh->triangle_count)
        return SELFCOL_INVALID_INDEX;
    return mesh->triangle_component[triangle];
}

double selfcol_mesh_mean_edge_length(const selfcol_mesh *mesh) {
    if (mesh == NULL || mesh->edge_count == 0)
        return 0.0;
    double sum = 0.0;
    for (size_t e = 0; e < mesh->edge_count; ++e) {
        const double *a = selfcol_mesh__position(mesh, mesh->edges[2 * e]);
        const double *b = selfcol_mesh__position(mesh, mesh->edges[2 * e + 1]);
        double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
        sum += sqrt(dx * dx + dy * dy + dz * dz);
    }
    return sum / (double)mesh->edge_count;
}

size_t selfcol_mesh_byte_count(const selfcol_mesh *mesh) {
    if (mesh == NULL)
        return 0;
    return sizeof *mesh + mesh->vertex_count * 3 * sizeof(double) +
           mesh->triangle_count *
               (3 * sizeof(uint32_t) + 3 * sizeof(uint32_t) + sizeof(uint32_t) + sizeof(uint8_t)) +
           mesh->edge_count * 2 * sizeof(uint32_t) + (mesh->edge_count + 1) * sizeof(uint32_t) +
           mesh->edge_tri_total * sizeof(uint32_t) + (mesh->vertex_count + 1) * sizeof(uint32_t) +
           mesh->vertex_tri_total * sizeof(uint32_t);
}
