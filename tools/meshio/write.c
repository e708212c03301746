// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Writers: the coloured ASCII PLY (selfcol-cli's --mark output).
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <errno.h>
#include <stdio.h>
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
