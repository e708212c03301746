// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Writers: the coloured ASCII PLY (selfcol-cli's --mark output).
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int meshio_write_coloured_ply(const char *path, const double *positions, size_t vertex_count,
                              const unsigned char *vertex_rgb, const uint32_t *triangles,
                              size_t triangle_count, const unsigned char *triangle_rgb,
                              const char *comment, meshio_error *err) {
    FILE *f = fopen(path, "w");
    if (f == NULL)
        return meshio_fail(err, "%s: cannot write: %s", path, strerror(errno));
    fprintf(f, "ply\nformat ascii 1.0\n");
    if (comment != NULL)
        fprintf(f, "comment %s\n", comment);
    fprintf(f,
            "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face %zu\n"
            "property list uchar uint vertex_indices\nproperty uchar red\nproperty uchar green\n"
            "property uchar blue\nend_header\n",
            vertex_count, triangle_count);
    for (size_t v = 0; v < vertex_count; ++v) {
        const unsigned char *c = vertex_rgb + 3 * v;
        fprintf(f, "%.17g %.17g %.17g %u %u %u\n", positions[3 * v], positions[3 * v + 1],
                positions[3 * v + 2], c[0], c[1], c[2]);
    }
    for (size_t t = 0; t < triangle_count; ++t) {
        const unsigned char *c = triangle_rgb + 3 * t;
        fprintf(f, "3 %u %u %u %u %u %u\n", (unsigned)triangles[3 * t],
                (unsigned)triangles[3 * t + 1], (unsigned)triangles[3 * t + 2], c[0], c[1], c[2]);
    }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad)
        return meshio_fail(err, "%s: write error", path);
    return 0;
}

// Colours of meshio_write_marked_ply's classes.
static const unsigned char class_colours[3][3] = {
    {190, 196, 206}, /* plain */
    {245, 166, 35},  /* proximity */
    {214, 39, 40}    /* intersecting */
};

int meshio_write_marked_ply(const char *path, const double *positions, size_t vertex_count,
                            const uint32_t *triangles, size_t triangle_count,
                            const unsigned char *classes, const char *comment, meshio_error *err) {
    // Vertex colours too: Blender's importer reads only those; a vertex takes
    // the most severe class of its triangles.
    unsigned char *vertex_class = calloc(vertex_count + 1, 1);
    unsigned char *vertex_rgb = malloc(3 * vertex_count + 1);
    unsigned char *triangle_rgb = malloc(3 * triangle_count + 1);
    if (vertex_class == NULL || vertex_rgb == NULL || triangle_rgb == NULL) {
        free(vertex_class);
        free(vertex_rgb);
        free(triangle_rgb);
        return meshio_fail(err, "%s: out of memory", path);
    }
    for (size_t t = 0; t < triangle_count; ++t) {
        const unsigned char c = classes[t] < 3 ? classes[t] : 2;
        for (int k = 0; k < 3; ++k)
            if (vertex_class[triangles[3 * t + k]] < c)
                vertex_class[triangles[3 * t + k]] = c;
        memcpy(triangle_rgb + 3 * t, class_colours[c], 3);
    }
    for (size_t v = 0; v < vertex_count; ++v)
        memcpy(vertex_rgb + 3 * v, class_colours[vertex_class[v]], 3);
    int status = meshio_write_coloured_ply(path, positions, vertex_count, vertex_rgb, triangles,
                                           triangle_count, triangle_rgb, comment, err);
    free(vertex_class);
    free(vertex_rgb);
    free(triangle_rgb);
    return status;
}
