// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-demo: the smallest complete use of the public API. Reads a mesh
// file (OBJ, or PLY, OFF, STL: the readers of tools/meshio; polygons are
// fan-triangulated), finds its self-contacts with the hierarchy (method
// EXACT, the default) at d = K x mean edge length (K = 0.1 by default, the
// standard cloth thickness), checks them against the exhaustive reference,
// and prints what it found.
// selfcol-cli (tools/cli) is the tool for users; this file is the example
// for programmers embedding the C API.
//
// usage: selfcol-demo MESH.obj [K]
#include <selfcol/selfcol.h>

#include <stdio.h>
#include <stdlib.h>

#include "meshio.h" // the mesh file readers of tools/meshio

static const char *kind_name(uint32_t kind) {
    return kind == SELFCOL_CONTACT_VF ? "VF" : kind == SELFCOL_CONTACT_EE ? "EE" : "EF";
}

int main(int argc, char **argv) {
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: %s MESH.obj [K]  (detection distance d = K x mean edge)\n",
                argv[0]);
        return 2;
    }
    double k = argc == 3 ? strtod(argv[2], NULL) : 0.1;
    meshio_mesh file = {0};
    meshio_error error;
    int exit_code = 2;
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *hierarchy = NULL;
    selfcol_contacts *contacts = NULL;
    if (meshio_read(argv[1], &file, &error, NULL) != 0) {
        fprintf(stderr, "%s\n", error.message);
        goto done;
    }

    int status = selfcol_mesh_create(&mesh, file.vertex_count, file.positions, file.triangle_count,
                                     file.triangles, NULL);
    if (status == SELFCOL_OK)
        status = selfcol_hierarchy_create(&hierarchy, mesh, NULL);
    if (status == SELFCOL_OK)
        status = selfcol_contacts_create(&contacts, NULL);
    selfcol_query_options opts;
    selfcol_query_options_init(&opts, SELFCOL_QUERY_OPTIONS_VERSION);
    opts.method = SELFCOL_METHOD_EXHAUSTIVE;
    opts.distance = k * selfcol_mesh_mean_edge_length(mesh);
    size_t reference_count = 0;
    double reference_ms = 0.0;
    if (status == SELFCOL_OK)
        status = selfcol_hierarchy_self_collide(hierarchy, contacts, &opts);
    if (status == SELFCOL_OK) {
        selfcol_query_stats reference;
        reference.version = SELFCOL_QUERY_STATS_VERSION;
        selfcol_contacts_stats(contacts, &reference);
        reference_count = selfcol_contacts_count(contacts);
        reference_ms = 1e3 * reference.total_seconds;
        opts.method = SELFCOL_METHOD_EXACT;
        status = selfcol_hierarchy_self_collide(hierarchy, contacts, &opts);
    }
    if (status != SELFCOL_OK) {
        fprintf(stderr, "%s: %s\n", argv[1], selfcol_status_string(status));
        goto done;
    }

    selfcol_query_stats stats;
    stats.version = SELFCOL_QUERY_STATS_VERSION;
    selfcol_contacts_stats(contacts, &stats);
    printf("selfcol %s  %s\n", selfcol_version_string(), argv[1]);
    printf("  %zu vertices, %zu triangles, %zu edges (%zu boundary, %zu non-manifold), "
           "%zu component(s)\n",
           selfcol_mesh_count(mesh, SELFCOL_MESH_VERTICES),
           selfcol_mesh_count(mesh, SELFCOL_MESH_TRIANGLES),
           selfcol_mesh_count(mesh, SELFCOL_MESH_EDGES),
           selfcol_mesh_count(mesh, SELFCOL_MESH_BOUNDARY_EDGES),
           selfcol_mesh_count(mesh, SELFCOL_MESH_NONMANIFOLD_EDGES),
           selfcol_mesh_count(mesh, SELFCOL_MESH_COMPONENTS));
    printf("  hierarchy: %zu nodes, depth %zu, %zu bytes\n",
           selfcol_hierarchy_count(hierarchy, SELFCOL_HIERARCHY_NODES),
           selfcol_hierarchy_count(hierarchy, SELFCOL_HIERARCHY_DEPTH),
           selfcol_hierarchy_byte_count(hierarchy));
    printf("  detection distance d = %g (%g x mean edge), method EXACT\n", opts.distance, k);
    printf("  VF proximities %llu, EE proximities %llu, EF interferences %llu\n",
           (unsigned long long)stats.vf_contacts, (unsigned long long)stats.ee_contacts,
           (unsigned long long)stats.ef_contacts);
    printf("  %llu triangle pairs, %llu primitive tests, %.3f ms (broad %.3f, narrow %.3f)\n",
           (unsigned long long)stats.triangle_pairs,
           (unsigned long long)(stats.vf_tests + stats.ee_tests + stats.ef_tests),
           1e3 * stats.total_seconds, 1e3 * stats.broad_seconds, 1e3 * stats.narrow_seconds);
    printf("  exhaustive reference: %zu contacts in %.3f ms (%s)\n", reference_count, reference_ms,
           reference_count == selfcol_contacts_count(contacts) ? "same count" : "DIFFERENT");

    const selfcol_contact *c;
    size_t n;
    selfcol_contacts_data(contacts, &c, &n);
    uint32_t shown_kind = 99;
    int shown = 0;
    for (size_t i = 0; i < n; ++i) {
        if (c[i].kind != shown_kind) {
            shown_kind = c[i].kind;
            shown = 0;
        }
        if (shown++ >= 3)
            continue;
        if (c[i].kind == SELFCOL_CONTACT_VF)
            printf("  %s vertex %u - triangle %u (%u %u %u)  distance %.4g\n", kind_name(c[i].kind),
                   c[i].first, c[i].second, c[i].b[0], c[i].b[1], c[i].b[2], c[i].distance);
        else if (c[i].kind == SELFCOL_CONTACT_EE)
            printf("  %s edge (%u %u) - edge (%u %u)  distance %.4g\n", kind_name(c[i].kind),
                   c[i].a[0], c[i].a[1], c[i].b[0], c[i].b[1], c[i].distance);
        else
            printf("  %s edge (%u %u) crosses triangle %u (%u %u %u)\n", kind_name(c[i].kind),
                   c[i].a[0], c[i].a[1], c[i].second, c[i].b[0], c[i].b[1], c[i].b[2]);
    }
    exit_code = 0;
done:
    selfcol_contacts_destroy(contacts);
    selfcol_hierarchy_destroy(hierarchy);
    selfcol_mesh_destroy(mesh);
    meshio_mesh_free(&file);
    return exit_code;
}
