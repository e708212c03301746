// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Loading meshes into the library.
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <stdlib.h>
#include <string.h>

// The message of a failed selfcol_mesh_create or _set_positions: on
// SELFCOL_EINVAL or SELFCOL_ERANGE the element the library refuses, found by
// its own checker (selfcol_mesh_check) and named in the file's terms, else
// the status.
int cli_fail_mesh(cli_error *err, const char *path, int rc, const double *positions,
                  size_t vertex_count, const uint32_t *triangles, size_t triangle_count) {
    if (rc == SELFCOL_EINVAL || rc == SELFCOL_ERANGE) {
        selfcol_mesh_problem p;
        p.version = SELFCOL_MESH_PROBLEM_VERSION;
        if (triangles != NULL)
            selfcol_mesh_check(vertex_count, positions, triangle_count, triangles, &p);
        else
            selfcol_mesh_check_positions(vertex_count, positions, &p);
        if (p.kind == SELFCOL_MESH_PROBLEM_INDEX)
            return cli_fail(
                err, "%s: triangle %llu names vertex %lu, not in the file (%zu vertices)", path,
                (unsigned long long)p.element, (unsigned long)p.value, vertex_count);
        if (p.kind >= SELFCOL_MESH_PROBLEM_NOT_FINITE)
            return cli_fail(err, "%s: vertex %llu, coordinate %c = %g %s", path,
                            (unsigned long long)p.element, "xyz"[p.component % 3], p.value,
                            p.reason);
        if (p.kind != SELFCOL_MESH_PROBLEM_NONE)
            return cli_fail(err, "%s: %s", path, p.message);
    }
    return cli_fail(err, "%s: %s", path, selfcol_status_string(rc));
}

void cli_part_free(cli_part *part) {
    selfcol_sequence_destroy(part->sequence);
    selfcol_hierarchy_destroy(part->hierarchy);
    selfcol_mesh_destroy(part->mesh);
    free(part->welded_triangles);
    meshio_mesh_free(&part->file);
    memset(part, 0, sizeof *part);
}

// Welds (unless no_weld) and creates the library mesh: its vertices are the
// file's vertices (duplicates stay, unreferenced), so library indices are
// file indices and each welded group is named by its lowest file index.
int cli_part_create(cli_part *part, int no_weld, int build_hierarchy, selfcol_context *context,
                    double *seconds_topology, double *seconds_hierarchy, cli_error *err) {
    size_t nv = part->file.vertex_count, nt = part->file.triangle_count;
    part->welded_triangles = malloc(3 * nt * sizeof(uint32_t) + 1);
    uint32_t *representative = malloc(nv * sizeof(uint32_t) + 1);
    if (part->welded_triangles == NULL || representative == NULL) {
        free(representative);
        return cli_fail(err, "%s: out of memory", part->path);
    }
    double start = cli_now();
    if (no_weld) {
        for (size_t v = 0; v < nv; ++v)
            representative[v] = (uint32_t)v;
        part->merged_vertices = 0;
    } else {
        part->merged_vertices = meshio_weld(part->file.positions, nv, representative);
        if (part->merged_vertices == (size_t)-1) {
            free(representative);
            return cli_fail(err, "%s: out of memory", part->path);
        }
    }
    for (size_t i = 0; i < 3 * nt; ++i)
        part->welded_triangles[i] = representative[part->file.triangles[i]];
    free(representative);
    int rc = selfcol_mesh_create(&part->mesh, nv, part->file.positions, nt, part->welded_triangles,
                                 NULL);
    double mid = cli_now();
    *seconds_topology += mid - start;
    part->context = context;
    if (rc == SELFCOL_OK && build_hierarchy)
        rc = selfcol_hierarchy_create(&part->hierarchy, part->mesh, NULL);
    *seconds_hierarchy += cli_now() - mid;
    if (rc != SELFCOL_OK && part->mesh == NULL)
        return cli_fail_mesh(err, part->path, rc, part->file.positions, nv, part->file.triangles,
                             nt);
    if (rc != SELFCOL_OK)
        return cli_fail(err, "%s: %s", part->path, selfcol_status_string(rc));
    return 0;
}

int cli_part_self_collide(cli_part *part, int coherent, selfcol_contacts *contacts,
                          const selfcol_query_options *query) {
    selfcol_context *c = part->context;
    if (!coherent)
        return c != NULL ? selfcol_context_self_collide(c, part->hierarchy, contacts, query)
                         : selfcol_hierarchy_self_collide(part->hierarchy, contacts, query);
    if (part->sequence == NULL) {
        int rc = selfcol_sequence_create(&part->sequence, NULL);
        if (rc != SELFCOL_OK)
            return rc;
    }
    return c != NULL
               ? selfcol_context_sequence_self_collide(c, part->sequence, part->hierarchy, contacts,
                                                       query)
               : selfcol_sequence_self_collide(part->sequence, part->hierarchy, contacts, query);
}

int cli_part_refit(cli_part *part) {
    return part->context != NULL ? selfcol_context_refit(part->context, part->hierarchy)
                                 : selfcol_hierarchy_refit(part->hierarchy);
}

int cli_context_create(unsigned threads, selfcol_context **out, cli_error *err) {
    *out = NULL;
    if (threads <= 1)
        return 0;
    selfcol_context_options co;
    selfcol_context_options_init(&co, SELFCOL_CONTEXT_OPTIONS_VERSION);
    co.threads = threads; // 2..SELFCOL_MAX_THREADS: parse_threads checked it
    const int rc = selfcol_context_create(out, &co);
    return rc == SELFCOL_OK ? 0 : cli_fail(err, "%s", selfcol_status_string(rc));
}
