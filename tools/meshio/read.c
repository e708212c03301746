// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// File loading, format detection, welding, and the small utilities every
// reader uses (errors, growable arrays, progress reports).
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int meshio_fail(meshio_error *err, const char *format, ...) {
    if (err != NULL) {
        va_list args;
        va_start(args, format);
        vsnprintf(err->message, sizeof err->message, format, args);
        va_end(args);
    }
    return -1;
}

void meshio_report(const meshio_progress *progress, const char *label, double done, double total) {
    if (progress != NULL && progress->update != NULL)
        progress->update(progress->context, label, done, total);
}

int meshio_array_reserve(meshio_array *array, size_t extra) {
    if (extra <= array->capacity - array->count)
        return 0;
    if (extra > SIZE_MAX / array->item_size - array->count)
        return -1;
    size_t need = array->count + extra;
    size_t capacity = array->capacity ? array->capacity : 1024;
    while (capacity < need)
        capacity = capacity > SIZE_MAX / 4 / array->item_size ? need : 2 * capacity;
    void *data = realloc(array->data, capacity * array->item_size);
    if (data == NULL)
        return -1;
    array->data = data;
    array->capacity = capacity;
    return 0;
}

void meshio_mesh_free(meshio_mesh *mesh) {
    free(mesh->positions);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}

const char *meshio_format_name(meshio_format format) {
    switch (format) {
    case MESHIO_FORMAT_OBJ: return "OBJ";
    case MESHIO_FORMAT_PLY: return "PLY";
    case MESHIO_FORMAT_OFF: return "OFF";
    case MESHIO_FORMAT_STL: return "STL";
    default: return "unknown";
    }
}

static int ends_with_ci(const char *s, const char *suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    if (m > n)
        return 0;
    for (size_t i = 0; i < m; ++i) {
        char a = s[n - m + i], b = suffix[i];
        if (a >= 'A' && a <= 'Z')
            a = (char)(a - 'A' + 'a');
        if (a != b)
            return 0;
    }
    return 1;
}

meshio_format meshio_format_from_path(const char *path) {
    if (ends_with_ci(path, ".obj"))
        return MESHIO_FORMAT_OBJ;
    if (ends_with_ci(path, ".ply"))
        return MESHIO_FORMAT_PLY;
    if (ends_with_ci(path, ".off"))
        return MESHIO_FORMAT_OFF;
    if (ends_with_ci(path, ".stl"))
        return MESHIO_FORMAT_STL;
    return MESHIO_FORMAT_UNKNOWN;
}

// The content decides where it is unambiguous ("ply" and "OFF" magic words),
// so a mislabelled file still loads; otherwise the extension, then a guess.
static meshio_format sniff(const unsigned char *data, size_t size, meshio_format hint) {
    if (size >= 4 && memcmp(data, "ply", 3) == 0 && (data[3] == '\n' || data[3] == '\r'))
        return MESHIO_FORMAT_PLY;
    if (hint != MESHIO_FORMAT_UNKNOWN)
        return hint;
    size_t i = 0;
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n'))
        ++i;
    if (size - i >= 3 && memcmp(data + i, "OFF", 3) == 0)
        return MESHIO_FORMAT_OFF;
    if (size - i >= 5 && memcmp(data + i, "solid", 5) == 0)
        return MESHIO_FORMAT_STL;
    // An OBJ file starts with comments or one of its statements.
    if (i < size && (data[i] == '#' || data[i] == 'v' || data[i] == 'o' || data[i] == 'g' ||
                     data[i] == 'm' || data[i] == 'f' || data[i] == 's'))
        return MESHIO_FORMAT_OBJ;
    if (size >= 84)
        return MESHIO_FORMAT_STL; // binary STL has no magic number
    return MESHIO_FORMAT_UNKNOWN;
}

int meshio_parse(const char *name, const unsigned char *data, size_t size, meshio_format hint,
                 meshio_mesh *mesh, meshio_error *err, const meshio_progress *progress) {
    memset(mesh, 0, sizeof *mesh);
    if (size == 0)
        return meshio_fail(err, "%s: empty file", name);
    // A UTF-8 byte-order mark (editors on Windows write one) is not part of
    // the text: left in, it hid the first OBJ line, so that faces then
    // pointed at the wrong vertices.
    if (size >= 3 && memcmp(data, "\xEF\xBB\xBF", 3) == 0) {
        data += 3;
        size -= 3;
        if (size == 0)
            return meshio_fail(err, "%s: empty file (a byte-order mark only)", name);
    }
    meshio_format format = sniff(data, size, hint);
    int status;
    switch (format) {
    case MESHIO_FORMAT_OBJ:
        status = meshio_parse_obj(name, (const char *)data, size, mesh, err, progress);
        break;
    case MESHIO_FORMAT_OFF:
        status = meshio_parse_off(name, (const char *)data, size, mesh, err, progress);
        break;
    case MESHIO_FORMAT_STL: status = meshio_parse_stl(name, data, size, mesh, err, progress); break;
    case MESHIO_FORMAT_PLY: status = meshio_parse_ply(name, data, size, mesh, err, progress); break;
    default:
        return meshio_fail(err, "%s: unknown file format (expected .obj, .ply, .off or .stl)",
                           name);
    }
    if (status == 0 && mesh->triangle_count == 0)
        status = meshio_fail(err, "%s: no faces (a surface needs at least one triangle)", name);
    if (status != 0)
        meshio_mesh_free(mesh);
    else
        mesh->format = format;
    return status;
}

// Reads the whole file into memory with a NUL after its last byte. Only
// regular files are read: a FIFO would block the open forever when nothing
// writes to it, and a device such as /dev/zero or /dev/urandom never ends.
// The file is checked before it is opened (so a FIFO is refused without
// blocking) and again on the open descriptor (in case it was replaced).
static int read_whole_file(const char *path, unsigned char **data_out, size_t *size_out,
                           meshio_error *err) {
    struct stat st;
    if (stat(path, &st) != 0)
        return meshio_fail(err, "%s: cannot open: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return meshio_fail(err, "%s: is a directory, not a mesh file", path);
    if (!S_ISREG(st.st_mode))
        return meshio_fail(err,
                           "%s: not a regular file (a pipe, device or socket); mesh files "
                           "must be regular files",
                           path);
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return meshio_fail(err, "%s: cannot open: %s", path, strerror(errno));
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return meshio_fail(err, "%s: not a regular file", path);
    }
    // The size stat gives, plus room to notice growth (files under /proc
    // report 0 and are read in chunks).
    size_t capacity = (size_t)st.st_size + 1 < 65536 ? 65536 : (size_t)st.st_size + 1;
    unsigned char *data = malloc(capacity);
    if (data == NULL) {
        close(fd);
        return meshio_fail(err, "%s: out of memory reading %zu bytes", path, capacity);
    }
    size_t size = 0;
    for (;;) {
        if (size + 1 == capacity) {
            unsigned char *bigger = capacity < SIZE_MAX / 2 ? realloc(data, 2 * capacity) : NULL;
            if (bigger == NULL) {
                free(data);
                close(fd);
                return meshio_fail(err, "%s: out of memory", path);
            }
            data = bigger;
            capacity *= 2;
        }
        ssize_t got = read(fd, data + size, capacity - 1 - size);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            int e = errno;
            free(data);
            close(fd);
            return meshio_fail(err, "%s: read error: %s", path, strerror(e));
        }
        if (got == 0)
            break;
        size += (size_t)got;
    }
    close(fd);
    data[size] = 0;
    *data_out = data;
    *size_out = size;
    return 0;
}

int meshio_read(const char *path, meshio_mesh *mesh, meshio_error *err,
                const meshio_progress *progress) {
    memset(mesh, 0, sizeof *mesh);
    unsigned char *data = NULL;
    size_t size = 0;
    if (read_whole_file(path, &data, &size, err) != 0)
        return -1;
    int status = meshio_parse(path, data, size, meshio_format_from_path(path), mesh, err, progress);
    free(data);
    return status;
}

// Position hashing for the weld: the bit patterns of the three coordinates
// (after mapping -0 to +0, so equal values hash equally) mixed multiplicatively.
static uint64_t coordinate_bits(double x) {
    x += 0.0; // -0.0 + 0.0 == +0.0 in round-to-nearest
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    return bits;
}

static uint64_t position_hash(const double *p) {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int k = 0; k < 3; ++k) {
        h ^= coordinate_bits(p[k]);
        h *= 0xFF51AFD7ED558CCDull;
        h ^= h >> 32;
    }
    return h;
}

size_t meshio_weld(const double *positions, size_t vertex_count, uint32_t *representative_out) {
    size_t capacity = 16;
    while (capacity < 2 * vertex_count)
        capacity *= 2;
    uint32_t *table = malloc(capacity * sizeof *table);
    if (table == NULL)
        return (size_t)-1;
    memset(table, 0xFF, capacity * sizeof *table); // UINT32_MAX: empty slot
    size_t merged = 0;
    for (size_t v = 0; v < vertex_count; ++v) {
        const double *p = positions + 3 * v;
        size_t slot = (size_t)position_hash(p) & (capacity - 1);
        for (;;) {
            uint32_t other = table[slot];
            if (other == UINT32_MAX) {
                // First of its group in file order, hence the lowest index.
                table[slot] = (uint32_t)v;
                representative_out[v] = (uint32_t)v;
                break;
            }
            const double *q = positions + 3 * (size_t)other;
            if (p[0] == q[0] && p[1] == q[1] && p[2] == q[2]) {
                representative_out[v] = other;
                ++merged;
                break;
            }
            slot = (slot + 1) & (capacity - 1);
        }
    }
    free(table);
    return merged;
}
