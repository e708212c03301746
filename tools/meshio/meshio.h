// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol_meshio: mesh files in and out (readers for OBJ, PLY ASCII and
// binary of either endianness, OFF, STL ASCII and binary; a coloured PLY
// writer), the vertex weld, and a growable array. Shared by selfcol-cli, the
// benchmark runner, the demo and the tests; generated test meshes are in
// fixtures.h. Plain C99, no selfcol dependency; not installed. Errors are
// reported into a meshio_error, never printed; progress goes to an optional
// callback.
#ifndef SELFCOL_MESHIO_H
#define SELFCOL_MESHIO_H

#include <stddef.h>
#include <stdint.h>

/** One error message, "file:line: what" (the line only for text formats). */
typedef struct meshio_error {
    char message[640];
} meshio_error;

/**
 * Progress of a long read: update(context, label, done, total) is called
 * now and then while a file is parsed (label: the file's name). NULL, or a
 * NULL update, reports nothing.
 */
typedef struct meshio_progress {
    void (*update)(void *context, const char *label, double done, double total);
    void *context;
} meshio_progress;

/** File formats the readers understand. */
typedef enum meshio_format {
    MESHIO_FORMAT_UNKNOWN = 0,
    MESHIO_FORMAT_OBJ,
    MESHIO_FORMAT_PLY,
    MESHIO_FORMAT_OFF,
    MESHIO_FORMAT_STL
} meshio_format;

/** "OBJ", "PLY", "OFF", "STL" or "unknown". */
const char *meshio_format_name(meshio_format format);

/** Formats an error message into err (printf-style). Returns -1 for `return meshio_fail(...)`. */
int meshio_fail(meshio_error *err, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/** Format named by a path's extension (case-insensitive), or UNKNOWN. */
meshio_format meshio_format_from_path(const char *path);

/**
 * A triangle mesh as the file has it: vertices in file order, triangles in
 * file order after fan-triangulating each polygon (p0 p1 p2, p0 p2 p3, ...),
 * with file vertex indices (0-based). STL has no shared vertices: its file
 * vertices are the facet corners, 3 per facet in order.
 */
typedef struct meshio_mesh {
    size_t vertex_count;
    double *positions; /* 3 * vertex_count */
    size_t triangle_count;
    uint32_t *triangles; /* 3 * triangle_count */
    size_t face_count;   /* polygons in the file, before triangulation */
    meshio_format format;
    const char *format_detail; /* "ascii", "binary little endian", ... (static) */
} meshio_mesh;

void meshio_mesh_free(meshio_mesh *mesh);

/**
 * Parses a whole file held in memory. data must be followed by one readable
 * NUL byte (data[size] == 0): text parsers rely on it as a sentinel. name is
 * used in messages only. hint: from the file name, or UNKNOWN to sniff.
 * Returns 0, or -1 with err set; on failure mesh holds nothing.
 */
int meshio_parse(const char *name, const unsigned char *data, size_t size, meshio_format hint,
                 meshio_mesh *mesh, meshio_error *err, const meshio_progress *progress);

/**
 * Reads and parses a file (format from its extension, else from its
 * content). Only regular files are read (a FIFO or a device is refused).
 */
int meshio_read(const char *path, meshio_mesh *mesh, meshio_error *err,
                const meshio_progress *progress);

/**
 * Welds vertices with exactly equal positions (-0 equals +0): writes into
 * representative_out[v] the lowest file index of v's group. O(n) expected.
 * Returns the number of vertices that were merged into a lower one, or
 * (size_t)-1 when out of memory.
 */
size_t meshio_weld(const double *positions, size_t vertex_count, uint32_t *representative_out);

/**
 * Writes an ASCII PLY with a colour per vertex and per face (MeshLab and
 * Blender read them): double x, y, z and uchar red, green, blue per vertex;
 * "list uchar uint vertex_indices" and red, green, blue per face. comment
 * (one line, may be NULL) goes into the header. Returns 0, or -1 with err set.
 */
int meshio_write_coloured_ply(const char *path, const double *positions, size_t vertex_count,
                              const unsigned char *vertex_rgb, const uint32_t *triangles,
                              size_t triangle_count, const unsigned char *triangle_rgb,
                              const char *comment, meshio_error *err);

/**
 * The coloured PLY of `selfcol-cli check --mark`: per triangle its class
 * (0 plain: grey, 1 within the detection distance: orange, 2 intersecting:
 * red; selfcol_triangle_class), per vertex the most severe class of its
 * triangles (Blender's importer reads vertex colours only). Returns 0, or
 * -1 with err set.
 */
int meshio_write_marked_ply(const char *path, const double *positions, size_t vertex_count,
                            const uint32_t *triangles, size_t triangle_count,
                            const unsigned char *classes, const char *comment, meshio_error *err);

/** View of a picture: angles in degrees (y is up), size in pixels. */
typedef struct meshio_view {
    double azimuth, elevation;
    int width, height;
} meshio_view;

/**
 * The picture of `selfcol-cli check --png`: the triangles flat-shaded and
 * z-buffered, coloured by class (0 plain: light steel, 1 within the
 * detection distance: amber, 2 intersecting: red), seen orthographically
 * from the view's angles and fitted to the picture, on white. Writes
 * width * height * 3 bytes of RGB, rows top first, into out. Returns 0, or
 * -1 when its work memory (16 to 64 bytes per pixel) cannot be allocated.
 */
int meshio_render_rgb(const double *positions, const uint32_t *triangles, size_t triangle_count,
                      const unsigned char *classes, const meshio_view *view, unsigned char *out);

/** A growable array of fixed-size items (realloc doubling). */
typedef struct meshio_array {
    void *data;
    size_t count, capacity, item_size;
} meshio_array;

/** Makes room for extra more items; returns 0 or -1 (out of memory or overflow). */
int meshio_array_reserve(meshio_array *array, size_t extra);

#endif /* SELFCOL_MESHIO_H */
