// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// libFuzzer harness for the mesh readers of selfcol_meshio (tools/meshio:
// OBJ, PLY, OFF, STL).
// The first input byte picks the format hint (as a file extension would);
// the rest is the file. A successful parse must give a mesh the library
// would accept: indices in range, finite coordinates, at least one triangle.
// Built and run by tests/fuzz/run.sh (make fuzz; needs clang), seeded from
// tests/fuzz/corpus/readers.
#include "meshio.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1)
        return 0;
    static const meshio_format hints[5] = {MESHIO_FORMAT_UNKNOWN, MESHIO_FORMAT_OBJ,
                                           MESHIO_FORMAT_PLY, MESHIO_FORMAT_OFF, MESHIO_FORMAT_STL};
    meshio_format hint = hints[data[0] % 5];
    // A copy of exactly the file's bytes plus the NUL sentinel the parsers
    // rely on, so that ASan sees any read past it.
    unsigned char *copy = malloc(size);
    if (copy == NULL)
        return 0;
    memcpy(copy, data + 1, size - 1);
    copy[size - 1] = 0;
    meshio_mesh mesh;
    meshio_error err;
    if (meshio_parse("fuzz", copy, size - 1, hint, &mesh, &err, NULL) == 0) {
        if (mesh.triangle_count == 0)
            abort();
        for (size_t i = 0; i < 3 * mesh.triangle_count; ++i)
            if (mesh.triangles[i] >= mesh.vertex_count)
                abort();
        for (size_t i = 0; i < 3 * mesh.vertex_count; ++i)
            if (!isfinite(mesh.positions[i]))
                abort();
        uint32_t *representative = malloc(mesh.vertex_count * sizeof *representative + 1);
        if (representative != NULL &&
            meshio_weld(mesh.positions, mesh.vertex_count, representative) != (size_t)-1)
            for (size_t v = 0; v < mesh.vertex_count; ++v)
                if (representative[v] > v)
                    abort();
        free(representative);
        meshio_mesh_free(&mesh);
    } else if (err.message[0] == '\0' || strncmp(err.message, "fuzz", 4) != 0) {
        abort(); // every error names the file
    }
    free(copy);
    return 0;
}
