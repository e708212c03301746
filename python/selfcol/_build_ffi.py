# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""cffi (API mode) description of the C ABI used by the selfcol package.

Run at build time by python/CMakeLists.txt: ``python _build_ffi.py OUT.c``
writes the extension's C source, which CMake compiles against
include/selfcol/ (so every declaration below is checked by the compiler)
and links with the static libselfcol. cffi releases the GIL around every
call into C.
"""

import sys
from typing import Any

import cffi

CDEF = r"""
typedef struct selfcol_allocator {
    void *(*alloc)(void *user, size_t size, size_t alignment);
    void (*free)(void *user, void *ptr, size_t size);
    void *user;
} selfcol_allocator;

const char *selfcol_status_string(int status);
unsigned selfcol_version_number(void);
const char *selfcol_version_string(void);

#define SELFCOL_OK ...
#define SELFCOL_ERROR ...
#define SELFCOL_ENOMEM ...
#define SELFCOL_EINVAL ...
#define SELFCOL_EVERSION ...
#define SELFCOL_EBUFS ...
#define SELFCOL_EUSER ...
#define SELFCOL_ERANGE ...
#define SELFCOL_EMISMATCH ...
#define SELFCOL_ESTALE ...
#define SELFCOL_INVALID_INDEX ...
#define SELFCOL_MAX_THREADS ...
#define SELFCOL_KIND_VF ...
#define SELFCOL_KIND_EE ...
#define SELFCOL_KIND_EF ...
#define SELFCOL_KIND_ALL ...
#define SELFCOL_QUERY_OPTIONS_VERSION ...
#define SELFCOL_CONTEXT_OPTIONS_VERSION ...
#define SELFCOL_HIERARCHY_OPTIONS_VERSION ...
#define SELFCOL_QUERY_STATS_VERSION ...
#define SELFCOL_STORE_OPTIONS_VERSION ...
#define SELFCOL_STORE_UPDATE_STATS_VERSION ...
#define SELFCOL_SWEEP_OPTIONS_VERSION ...
#define SELFCOL_SWEEP_STATS_VERSION ...
#define SELFCOL_SCENE_OPTIONS_VERSION ...
#define SELFCOL_SCENE_SURFACE_OPTIONS_VERSION ...
#define SELFCOL_SCENE_COLLIDER_DESC_VERSION ...
#define SELFCOL_SCENE_UPDATE_STATS_VERSION ...
#define SELFCOL_COLLIDER_MAX_POINTS ...
#define SELFCOL_STORE_DEFAULT_REMNANCE ...

/* mesh.h */
typedef struct selfcol_mesh selfcol_mesh;
int selfcol_mesh_create(selfcol_mesh **out, size_t vertex_count, const double *positions,
                        size_t triangle_count, const uint32_t *triangles, const void *opts);
int selfcol_mesh_create_float(selfcol_mesh **out, size_t vertex_count, const float *positions,
                              size_t stride_bytes, size_t triangle_count,
                              const uint32_t *triangles, const void *opts);
void selfcol_mesh_destroy(selfcol_mesh *mesh);
typedef struct selfcol_mesh_problem {
    unsigned int version;
    int status;
    uint32_t kind;
    uint32_t component;
    uint64_t element;
    double value;
    char reason[96];
    char message[256];
} selfcol_mesh_problem;
#define SELFCOL_MESH_PROBLEM_VERSION ...
#define SELFCOL_MESH_PROBLEM_INDEX ...
#define SELFCOL_MESH_PROBLEM_NOT_FINITE ...
int selfcol_mesh_check(size_t vertex_count, const double *positions, size_t triangle_count,
                       const uint32_t *triangles, selfcol_mesh_problem *problem);
int selfcol_mesh_check_positions(size_t vertex_count, const double *positions,
                                 selfcol_mesh_problem *problem);
int selfcol_mesh_set_positions(selfcol_mesh *mesh, const double *positions, size_t vertex_count);
int selfcol_mesh_set_positions_float(selfcol_mesh *mesh, const float *positions,
                                     size_t stride_bytes, size_t vertex_count);
size_t selfcol_mesh_count(const selfcol_mesh *mesh, int quantity);
const double *selfcol_mesh_positions(const selfcol_mesh *mesh);
const uint32_t *selfcol_mesh_triangles(const selfcol_mesh *mesh);
const uint32_t *selfcol_mesh_edges(const selfcol_mesh *mesh);
int selfcol_mesh_edge_triangles(const selfcol_mesh *mesh, uint32_t edge,
                                const uint32_t **triangles_out, size_t *count_out);
uint32_t selfcol_mesh_triangle_flags(const selfcol_mesh *mesh, uint32_t triangle);
uint32_t selfcol_mesh_triangle_component(const selfcol_mesh *mesh, uint32_t triangle);
double selfcol_mesh_mean_edge_length(const selfcol_mesh *mesh);
size_t selfcol_mesh_byte_count(const selfcol_mesh *mesh);

/* contacts.h */
typedef struct selfcol_contact {
    uint32_t kind; uint32_t first; uint32_t second; uint32_t first_mesh; uint32_t second_mesh;
    uint32_t a[2]; uint32_t b[3];
    double distance; double wa[2]; double wb[3]; double direction[3];
} selfcol_contact;
typedef struct selfcol_query_stats {
    unsigned int version;
    uint64_t candidate_pairs; uint64_t vf_tests; uint64_t ee_tests; uint64_t ef_tests;
    uint64_t vf_contacts; uint64_t ee_contacts; uint64_t ef_contacts;
    double broad_seconds; double narrow_seconds; double total_seconds;
    uint64_t nodes_visited; uint64_t culled_box; uint64_t culled_curvature;
    uint64_t culled_adjacency; uint64_t triangle_pairs;
    uint64_t contour_tests; uint64_t contour_refused; double contour_seconds;
    uint64_t pairs_separated; uint64_t primitives_filtered; double sort_seconds;
} selfcol_query_stats;
typedef struct selfcol_contacts selfcol_contacts;
int selfcol_contacts_create(selfcol_contacts **out, const void *opts);
void selfcol_contacts_destroy(selfcol_contacts *contacts);
size_t selfcol_contacts_count(const selfcol_contacts *contacts);
int selfcol_contacts_data(const selfcol_contacts *contacts, const selfcol_contact **data_out,
                          size_t *count_out);
int selfcol_contacts_stats(const selfcol_contacts *contacts, selfcol_query_stats *stats);
int selfcol_contacts_triangle_classes(const selfcol_contacts *contacts, const selfcol_mesh *first,
                                      const selfcol_mesh *second, uint8_t *first_classes,
                                      uint8_t *second_classes);
int selfcol_contacts_intersecting_triangles(selfcol_contacts *contacts, const selfcol_mesh *first,
                                            const selfcol_mesh *second, const uint32_t **pairs_out,
                                            size_t *count_out);

/* hierarchy.h */
typedef struct selfcol_hierarchy selfcol_hierarchy;
typedef struct selfcol_query_options {
    unsigned int version; uint32_t method; uint32_t narrow; uint32_t kinds;
    double distance;
} selfcol_query_options;
int selfcol_query_options_init(selfcol_query_options *opts, unsigned int version);
typedef struct selfcol_hierarchy_options {
    unsigned int version; selfcol_allocator allocator;
} selfcol_hierarchy_options;
int selfcol_hierarchy_options_init(selfcol_hierarchy_options *opts, unsigned int version);
int selfcol_hierarchy_create(selfcol_hierarchy **out, const selfcol_mesh *mesh,
                             const selfcol_hierarchy_options *opts);
void selfcol_hierarchy_destroy(selfcol_hierarchy *hierarchy);
int selfcol_hierarchy_refit(selfcol_hierarchy *hierarchy);
size_t selfcol_hierarchy_count(const selfcol_hierarchy *hierarchy, int quantity);
size_t selfcol_hierarchy_byte_count(const selfcol_hierarchy *hierarchy);
int selfcol_hierarchy_self_collide(const selfcol_hierarchy *hierarchy, selfcol_contacts *contacts,
                                   const selfcol_query_options *opts);
int selfcol_hierarchy_collide(const selfcol_hierarchy *first, const selfcol_hierarchy *second,
                              selfcol_contacts *contacts, const selfcol_query_options *opts);

/* store.h */
typedef struct selfcol_store selfcol_store;
typedef struct selfcol_store_options {
    unsigned int version; selfcol_allocator allocator; uint32_t remnance_frames;
    int consistency; int first_orientation; int second_orientation;
} selfcol_store_options;
typedef struct selfcol_store_contact {
    uint32_t kind; uint32_t first; uint32_t second; uint32_t first_mesh; uint32_t second_mesh;
    uint32_t a[2]; uint32_t b[3];
    uint32_t region; uint32_t age; uint32_t missed; uint32_t flags;
    int32_t side; int32_t right_side;
    double distance; double signed_distance; double wa[2]; double wb[3]; double direction[3];
} selfcol_store_contact;
typedef struct selfcol_store_region {
    uint32_t contacts; uint32_t interferences; uint32_t votes_majority; uint32_t votes_minority;
    uint32_t abstained; uint32_t oriented; uint32_t flags;
} selfcol_store_region;
typedef struct selfcol_store_update_stats {
    unsigned int version;
    uint64_t contacts; uint64_t interferences; uint64_t new_contacts; uint64_t kept;
    uint64_t remnant; uint64_t dropped; uint64_t flipped; uint64_t corrected; uint64_t voted;
    uint64_t oriented; uint64_t regions; uint64_t crossed_regions; uint64_t corrected_regions;
    double seconds; uint64_t passed_around;
} selfcol_store_update_stats;
int selfcol_store_options_init(selfcol_store_options *opts, unsigned int version);
int selfcol_store_create(selfcol_store **out, const selfcol_store_options *opts);
void selfcol_store_destroy(selfcol_store *store);
void selfcol_store_clear(selfcol_store *store);
int selfcol_store_update(selfcol_store *store, const selfcol_mesh *first,
                         const selfcol_mesh *second, const selfcol_contacts *detected);
int selfcol_store_update_swept(selfcol_store *store, const selfcol_mesh *first,
                               const selfcol_mesh *second, const selfcol_contacts *detected,
                               const double *first_start, const double *second_start);
size_t selfcol_store_contact_count(const selfcol_store *store);
int selfcol_store_copy_contacts(const selfcol_store *store, size_t first_index, size_t count,
                                selfcol_store_contact *out);
int selfcol_store_regions(const selfcol_store *store, const selfcol_store_region **data_out,
                          size_t *count_out);
int selfcol_store_stats(const selfcol_store *store, selfcol_store_update_stats *stats);
size_t selfcol_store_byte_count(const selfcol_store *store);

/* sweep.h */
typedef struct selfcol_sweep selfcol_sweep;
typedef struct selfcol_sweep_options {
    unsigned int version; uint32_t method; uint32_t kinds; uint32_t mode;
    double separation;
    int (*progress)(void *payload, double done); void *progress_payload;
    const uint8_t *active_vertices[2];
    double tolerance;
} selfcol_sweep_options;
extern "Python" int _selfcol_sweep_progress(void *payload, double done);
typedef struct selfcol_sweep_hit {
    uint32_t kind; uint32_t first; uint32_t second; uint32_t first_mesh; uint32_t second_mesh;
    uint32_t a[2]; uint32_t b[3]; uint32_t flags; double toi;
} selfcol_sweep_hit;
typedef struct selfcol_sweep_query_stats {
    unsigned int version;
    double free_fraction;
    uint64_t passes; uint64_t node_pairs; uint64_t candidates; uint64_t vf_candidates;
    uint64_t ee_candidates; uint64_t separated; uint64_t narrow_boxes; uint64_t hits;
    uint64_t initial; uint64_t unresolved;
    double broad_seconds; double narrow_seconds; double total_seconds;
    uint64_t patches_culled; uint64_t cull_tests; double cull_seconds;
} selfcol_sweep_query_stats;
int selfcol_sweep_options_init(selfcol_sweep_options *opts, unsigned int version);
int selfcol_sweep_create(selfcol_sweep **out, const selfcol_allocator *allocator);
void selfcol_sweep_destroy(selfcol_sweep *sweep);
int selfcol_hierarchy_self_sweep(const selfcol_hierarchy *hierarchy, const double *start_positions,
                                 selfcol_sweep *result, const selfcol_sweep_options *opts);
int selfcol_hierarchy_sweep(const selfcol_hierarchy *first, const double *first_start,
                            const selfcol_hierarchy *second, const double *second_start,
                            selfcol_sweep *result, const selfcol_sweep_options *opts);
int selfcol_sweep_hits(const selfcol_sweep *sweep, const selfcol_sweep_hit **data_out,
                       size_t *count_out);
int selfcol_sweep_stats(const selfcol_sweep *sweep, selfcol_sweep_query_stats *stats);

/* sequence.h */
typedef struct selfcol_sequence selfcol_sequence;
typedef struct selfcol_sequence_options {
    unsigned int version; selfcol_allocator allocator; double skin;
} selfcol_sequence_options;
#define SELFCOL_SEQUENCE_OPTIONS_VERSION ...
typedef struct selfcol_sequence_run_stats {
    unsigned int version; uint64_t frames; uint64_t rebuilds; uint64_t fresh_frames;
    uint32_t last_answer; uint32_t last_reason; uint64_t near_pairs; double skin;
    double deformation_ratio; double rebuild_seconds; uint64_t partial_rebuilds;
} selfcol_sequence_run_stats;
#define SELFCOL_SEQUENCE_RUN_STATS_VERSION ...
int selfcol_sequence_options_init(selfcol_sequence_options *opts, unsigned int version);
int selfcol_sequence_create(selfcol_sequence **out, const selfcol_sequence_options *opts);
void selfcol_sequence_destroy(selfcol_sequence *sequence);
void selfcol_sequence_reset(selfcol_sequence *sequence);
int selfcol_sequence_self_collide(selfcol_sequence *sequence, selfcol_hierarchy *hierarchy,
                                  selfcol_contacts *contacts, const selfcol_query_options *opts);
int selfcol_sequence_collide(selfcol_sequence *sequence, selfcol_hierarchy *first,
                             selfcol_hierarchy *second, selfcol_contacts *contacts,
                             const selfcol_query_options *opts);
int selfcol_sequence_stats(const selfcol_sequence *sequence, selfcol_sequence_run_stats *stats);
size_t selfcol_sequence_byte_count(const selfcol_sequence *sequence);

/* scene.h */
typedef struct selfcol_scene selfcol_scene;
typedef struct selfcol_scene_surface_options {
    unsigned int version; uint32_t kind; int self_collision; int orientation;
} selfcol_scene_surface_options;
typedef struct selfcol_scene_collider_desc {
    unsigned int version; uint32_t shape; double radius; double half_height;
    double half_extents[3]; const double *points; size_t point_count;
} selfcol_scene_collider_desc;
typedef struct selfcol_scene_options {
    unsigned int version; selfcol_allocator allocator; const selfcol_query_options *query;
    const selfcol_store_options *store; double collider_tolerance; int coherent;
    const selfcol_sequence_options *sequence;
} selfcol_scene_options;
typedef struct selfcol_collider_contact {
    uint32_t collider; uint32_t surface; uint32_t triangle; uint32_t flags;
    double distance; double wb[3]; double normal[3];
} selfcol_collider_contact;
typedef struct selfcol_scene_update_stats {
    unsigned int version;
    uint64_t surfaces; uint64_t colliders; uint64_t refits; uint64_t builds;
    uint64_t pairs_queried; uint64_t pairs_apart; uint64_t contacts; uint64_t interferences;
    uint64_t flipped; uint64_t corrected; uint64_t voted; uint64_t oriented;
    uint64_t collider_candidates; uint64_t collider_contacts; uint64_t collider_penetrating;
    double seconds; uint64_t passed_around;
} selfcol_scene_update_stats;
int selfcol_scene_options_init(selfcol_scene_options *opts, unsigned int version);
int selfcol_scene_surface_options_init(selfcol_scene_surface_options *opts, uint32_t kind,
                                       unsigned int version);
int selfcol_scene_collider_desc_init(selfcol_scene_collider_desc *desc, uint32_t shape,
                                     unsigned int version);
int selfcol_scene_create(selfcol_scene **out, const selfcol_scene_options *opts);
int selfcol_scene_set_surface_start(selfcol_scene *scene, uint32_t surface,
                                    const double *positions);
void selfcol_scene_destroy(selfcol_scene *scene);
int selfcol_scene_add_surface(selfcol_scene *scene, const selfcol_mesh *mesh,
                              const selfcol_scene_surface_options *opts, uint32_t *id_out);
int selfcol_scene_remove_surface(selfcol_scene *scene, uint32_t id);
int selfcol_scene_rebuild_surface(selfcol_scene *scene, uint32_t id);
int selfcol_scene_add_collider(selfcol_scene *scene, const selfcol_scene_collider_desc *desc,
                               uint32_t *id_out);
int selfcol_scene_set_collider_pose(selfcol_scene *scene, uint32_t collider,
                                    const double position[3], const double rotation[9]);
int selfcol_scene_update(selfcol_scene *scene);
int selfcol_scene_store(const selfcol_scene *scene, uint32_t first, uint32_t second,
                        const selfcol_store **store_out);
int selfcol_scene_collider_contacts(const selfcol_scene *scene,
                                    const selfcol_collider_contact **data_out, size_t *count_out);
int selfcol_scene_stats(const selfcol_scene *scene, selfcol_scene_update_stats *stats);
size_t selfcol_scene_byte_count(const selfcol_scene *scene);

/* context.h: the one place where threads are said (the threads= arguments). */
typedef struct selfcol_context selfcol_context;
typedef void selfcol_task_fn(uint32_t begin, uint32_t end, uint32_t worker, void *task_context);
typedef void *selfcol_enqueue_task_fn(selfcol_task_fn *task, uint32_t item_count,
                                      uint32_t min_range, void *task_context, void *user_context);
typedef void selfcol_finish_task_fn(void *user_task, void *user_context);
typedef struct selfcol_context_options {
    unsigned int version; selfcol_allocator allocator; unsigned int threads;
    selfcol_enqueue_task_fn *enqueue_task; selfcol_finish_task_fn *finish_task;
    void *user_context;
} selfcol_context_options;
int selfcol_context_options_init(selfcol_context_options *opts, unsigned int version);
int selfcol_context_create(selfcol_context **out, const selfcol_context_options *opts);
void selfcol_context_destroy(selfcol_context *context);
int selfcol_context_self_collide(selfcol_context *context, const selfcol_hierarchy *hierarchy,
                                 selfcol_contacts *contacts, const selfcol_query_options *opts);
int selfcol_context_collide(selfcol_context *context, const selfcol_hierarchy *first,
                            const selfcol_hierarchy *second, selfcol_contacts *contacts,
                            const selfcol_query_options *opts);
int selfcol_context_self_sweep(selfcol_context *context, const selfcol_hierarchy *hierarchy,
                               const double *start_positions, selfcol_sweep *result,
                               const selfcol_sweep_options *opts);
int selfcol_context_sweep(selfcol_context *context, const selfcol_hierarchy *first,
                          const double *first_start, const selfcol_hierarchy *second,
                          const double *second_start, selfcol_sweep *result,
                          const selfcol_sweep_options *opts);
int selfcol_context_refit(selfcol_context *context, selfcol_hierarchy *hierarchy);
int selfcol_context_store_update(selfcol_context *context, selfcol_store *store,
                                 const selfcol_mesh *first, const selfcol_mesh *second,
                                 const selfcol_contacts *detected);
int selfcol_context_store_update_swept(selfcol_context *context, selfcol_store *store,
                                       const selfcol_mesh *first, const selfcol_mesh *second,
                                       const selfcol_contacts *detected,
                                       const double *first_start, const double *second_start);
int selfcol_context_sequence_self_collide(selfcol_context *context, selfcol_sequence *sequence,
                                          selfcol_hierarchy *hierarchy,
                                          selfcol_contacts *contacts,
                                          const selfcol_query_options *opts);
int selfcol_context_sequence_collide(selfcol_context *context, selfcol_sequence *sequence,
                                     selfcol_hierarchy *first, selfcol_hierarchy *second,
                                     selfcol_contacts *contacts,
                                     const selfcol_query_options *opts);
int selfcol_scene_set_context(selfcol_scene *scene, selfcol_context *context);

/* Options that name what they refuse (common.h). */
typedef struct selfcol_options_problem {
    unsigned int version;
    int status;
    char field[64];
    char message[256];
} selfcol_options_problem;
#define SELFCOL_OPTIONS_PROBLEM_VERSION ...
int selfcol_query_options_check(const selfcol_query_options *opts,
                                selfcol_options_problem *problem);
int selfcol_hierarchy_options_check(const selfcol_hierarchy_options *opts,
                                    selfcol_options_problem *problem);
int selfcol_store_options_check(const selfcol_store_options *opts,
                                selfcol_options_problem *problem);
int selfcol_sequence_options_check(const selfcol_sequence_options *opts,
                                   selfcol_options_problem *problem);
int selfcol_context_options_check(const selfcol_context_options *opts,
                                  selfcol_options_problem *problem);
int selfcol_sweep_options_check(const selfcol_sweep_options *opts,
                                selfcol_options_problem *problem);
int selfcol_scene_options_check(const selfcol_scene_options *opts,
                                selfcol_options_problem *problem);

/* tools/meshio: the mesh file readers of selfcol-cli (selfcol.io). */
typedef struct meshio_error {
    char message[640];
} meshio_error;
typedef struct meshio_progress meshio_progress;
typedef struct meshio_mesh {
    size_t vertex_count;
    double *positions;
    size_t triangle_count;
    uint32_t *triangles;
    ...;
} meshio_mesh;
int meshio_read(const char *path, meshio_mesh *mesh, meshio_error *err,
                const meshio_progress *progress);
void meshio_mesh_free(meshio_mesh *mesh);
size_t meshio_weld(const double *positions, size_t vertex_count, uint32_t *representative_out);
int meshio_write_marked_ply(const char *path, const double *positions, size_t vertex_count,
                            const uint32_t *triangles, size_t triangle_count,
                            const unsigned char *classes, const char *comment, meshio_error *err);
typedef struct meshio_view {
    double azimuth, elevation;
    int width, height;
} meshio_view;
int meshio_render_rgb(const double *positions, const uint32_t *triangles, size_t triangle_count,
                      const unsigned char *classes, const meshio_view *view, unsigned char *out);
"""


def build_ffi() -> Any:
    ffi = cffi.FFI()
    ffi.cdef(CDEF)
    ffi.set_source("selfcol._selfcol_cffi", "#include <selfcol/selfcol.h>\n#include \"meshio.h\"\n")
    return ffi


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: _build_ffi.py OUT.c")
    build_ffi().emit_c_code(sys.argv[1])
