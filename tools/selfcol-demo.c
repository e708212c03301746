// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol-demo: the smallest complete use of the public API. Reads an OBJ
// file (positions and faces; polygons are fan-triangulated), finds its
// self-contacts with the hierarchy (method EXACT, the default) at d = K x mean edge
// length (K = 0.1 by default, the standard cloth thickness), checks them
// against the exhaustive reference, and prints what it found.
// selfcol-cli (tools/cli) is the tool for users; this file is the example
// for programmers embedding the C API.
//
// usage: selfcol-demo MESH.obj [K]
#include <selfcol/selfcol.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct growable {
    void *data;
    size_t count, capacity, item;
} growable;

static int push(growable *g, const void *item) {
    if (g->count == g->capacity) {
        size_t capacity = g->capacity ? 2 * g->capacity : 256;
        void *data = realloc(g->data, capacity * g->item);
        if (data == NULL)
            return -1;
        g->data = data;
        g->capacity = capacity;
    }
    memcpy((char *)g->data + g->count * g->item, item, g->item);
    g->count++;
    return 0;
}

// Minimal OBJ reader: 'v x y z' and 'f a b c ...' (a may be a/b/c, negative
// indices count from the end). Returns 0, or prints "file:line: message".
static int read_obj(const char *path, growable *positions, growable *triangles) {
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "%s: %s\n", path, strerror(errno));
        return -1;
    }
    char line[4096];
    long lineno = 0;
    int status = 0;
    while (status == 0 && fgets(line, sizeof line, f) != NULL) {
        lineno++;
        if (line[0] == 'v' && line[1] == ' ') {
            double p[3];
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) {
                fprintf(stderr, "%s:%ld: expected 'v x y z'\n", path, lineno);
                status = -1;
            }
            for (int k = 0; k < 3 && status == 0; ++k)
                status = push(positions, &p[k]);
        } else if (line[0] == 'f' && line[1] == ' ') {
            uint32_t poly[64];
            int n = 0;
            char *tok = strtok(line + 2, " \t\r\n");
            for (; tok != NULL && status == 0; tok = strtok(NULL, " \t\r\n")) {
                long idx = strtol(tok, NULL, 10);
                long count = (long)(positions->count / 3);
                if (idx < 0)
                    idx += count + 1;
                if (idx < 1 || idx > count || n == 64) {
                    fprintf(stderr, "%s:%ld: bad face index '%s'\n", path, lineno, tok);
                    status = -1;
                    break;
                }
                poly[n++] = (uint32_t)(idx - 1);
            }
            if (status == 0 && n < 3) {
                fprintf(stderr, "%s:%ld: face with fewer than 3 vertices\n", path, lineno);
                status = -1;
            }
            for (int i = 1; status == 0 && i + 1 < n; ++i) {
                uint32_t t[3] = {poly[0], poly[i], poly[i + 1]};
                for (int k = 0; k < 3 && status == 0; ++k)
                    status = push(triangles, &t[k]);
            }
        }
    }
    fclose(f);
    return status;
}

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
    growable positions = {NULL, 0, 0, sizeof(double)};
    growable triangles = {NULL, 0, 0, sizeof(uint32_t)};
    int exit_code = 2;
    selfcol_mesh *mesh = NULL;
    selfcol_hierarchy *hierarchy = NULL;
    selfcol_contacts *contacts = NULL;
    if (read_obj(argv[1], &positions, &triangles) != 0)
        goto done;

    int status = selfcol_mesh_create(&mesh, positions.count / 3, positions.data,
                                     triangles.count / 3, triangles.data, NULL);
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
    free(positions.data);
    free(triangles.data);
    return exit_code;
}
