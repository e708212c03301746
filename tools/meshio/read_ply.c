// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// PLY reader: ASCII, binary little and big endian; any scalar type for the
// coordinates (x, y, z of element "vertex") and any integer type for the
// face lists ("vertex_indices" or "vertex_index" of element "face"); other
// elements and properties are skipped. Hand-written: Debian 12 packages no
// maintained C PLY reader (rply is not packaged). Every read is bounds-checked
// against the buffer, and element counts are checked against the file size
// before anything is allocated, so a hostile header cannot exhaust memory.
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum ply_type {
    PLY_NONE = 0,
    PLY_I8,
    PLY_U8,
    PLY_I16,
    PLY_U16,
    PLY_I32,
    PLY_U32,
    PLY_F32,
    PLY_F64
} ply_type;

static const struct {
    const char *name;
    ply_type type;
} ply_type_names[] = {
    {"char", PLY_I8},   {"int8", PLY_I8},     {"uchar", PLY_U8},   {"uint8", PLY_U8},
    {"short", PLY_I16}, {"int16", PLY_I16},   {"ushort", PLY_U16}, {"uint16", PLY_U16},
    {"int", PLY_I32},   {"int32", PLY_I32},   {"uint", PLY_U32},   {"uint32", PLY_U32},
    {"float", PLY_F32}, {"float32", PLY_F32}, {"double", PLY_F64}, {"float64", PLY_F64}};

static size_t type_size(ply_type t) {
    static const size_t sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

static int type_is_integer(ply_type t) {
    return t >= PLY_I8 && t <= PLY_U32;
}

enum { MAX_ELEMENTS = 32, MAX_PROPERTIES = 128, MAX_NAME = 64 };

// What a property is used for.
enum { ROLE_SKIP = 0, ROLE_X, ROLE_Y, ROLE_Z, ROLE_INDICES };

typedef struct ply_property {
    ply_type type;       /* scalar type, or item type of a list */
    ply_type count_type; /* PLY_NONE for a scalar */
    int role;
} ply_property;

typedef struct ply_element {
    char name[MAX_NAME];
    uint64_t count;
    int property_count;
    ply_property properties[MAX_PROPERTIES];
} ply_element;

typedef enum ply_encoding { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE } ply_encoding;

typedef struct ply_reader {
    const char *name;
    const unsigned char *p, *end; /* body cursor */
    long line;                    /* ASCII body: current line */
    ply_encoding encoding;
    meshio_error *err;
} ply_reader;

// Header: one keyword line at a time. Splits the line into at most 6 words.
static int split_words(const char *line, size_t length, char words[6][MAX_NAME]) {
    int n = 0;
    size_t i = 0;
    while (i < length && n < 6) {
        while (i < length && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r'))
            ++i;
        if (i == length)
            break;
        size_t start = i;
        while (i < length && line[i] != ' ' && line[i] != '\t' && line[i] != '\r')
            ++i;
        size_t w = i - start < MAX_NAME - 1 ? i - start : MAX_NAME - 1;
        memcpy(words[n], line + start, w);
        words[n][w] = '\0';
        ++n;
    }
    return n;
}

static ply_type parse_type(const char *word) {
    for (size_t i = 0; i < sizeof ply_type_names / sizeof ply_type_names[0]; ++i)
        if (strcmp(word, ply_type_names[i].name) == 0)
            return ply_type_names[i].type;
    return PLY_NONE;
}

// Parses the header; on success *body is the first byte after "end_header\n".
static int parse_header(const char *name, const unsigned char *data, size_t size,
                        ply_element *elements, int *element_count, ply_encoding *encoding,
                        size_t *body, long *body_line, meshio_error *err) {
    size_t pos = 0;
    long line = 0;
    int have_format = 0;
    *element_count = 0;
    for (;;) {
        if (pos >= size)
            return meshio_fail(err, "%s: PLY header has no 'end_header'", name);
        const unsigned char *nl = memchr(data + pos, '\n', size - pos);
        if (nl == NULL)
            return meshio_fail(err, "%s: PLY header has no 'end_header'", name);
        const char *text = (const char *)data + pos;
        size_t length = (size_t)(nl - (data + pos));
        pos += length + 1;
        ++line;
        char words[6][MAX_NAME];
        int n = split_words(text, length, words);
        if (line == 1) {
            if (n != 1 || strcmp(words[0], "ply") != 0)
                return meshio_fail(err, "%s:1: not a PLY file (expected 'ply')", name);
            continue;
        }
        if (n == 0 || strcmp(words[0], "comment") == 0 || strcmp(words[0], "obj_info") == 0)
            continue;
        if (strcmp(words[0], "format") == 0) {
            if (n < 3 || strcmp(words[2], "1.0") != 0)
                return meshio_fail(err, "%s:%ld: expected 'format <encoding> 1.0'", name, line);
            if (strcmp(words[1], "ascii") == 0)
                *encoding = PLY_ASCII;
            else if (strcmp(words[1], "binary_little_endian") == 0)
                *encoding = PLY_BINARY_LE;
            else if (strcmp(words[1], "binary_big_endian") == 0)
                *encoding = PLY_BINARY_BE;
            else
                return meshio_fail(err, "%s:%ld: unknown PLY format '%s'", name, line, words[1]);
            have_format = 1;
        } else if (strcmp(words[0], "element") == 0) {
            if (n != 3)
                return meshio_fail(err, "%s:%ld: expected 'element <name> <count>'", name, line);
            if (*element_count == MAX_ELEMENTS)
                return meshio_fail(err, "%s:%ld: more than %d elements", name, line, MAX_ELEMENTS);
            char *tail;
            unsigned long long count = strtoull(words[2], &tail, 10);
            if (*tail != '\0' || words[2][0] == '-' || tail == words[2])
                return meshio_fail(err, "%s:%ld: bad element count '%s'", name, line, words[2]);
            ply_element *e = &elements[(*element_count)++];
            memset(e, 0, sizeof *e);
            memcpy(e->name, words[1], sizeof e->name);
            e->count = count;
        } else if (strcmp(words[0], "property") == 0) {
            if (*element_count == 0)
                return meshio_fail(err, "%s:%ld: 'property' before any 'element'", name, line);
            ply_element *e = &elements[*element_count - 1];
            if (e->property_count == MAX_PROPERTIES)
                return meshio_fail(err, "%s:%ld: more than %d properties", name, line,
                                   MAX_PROPERTIES);
            ply_property *prop = &e->properties[e->property_count++];
            const char *prop_name;
            if (n == 5 && strcmp(words[1], "list") == 0) {
                prop->count_type = parse_type(words[2]);
                prop->type = parse_type(words[3]);
                prop_name = words[4];
                if (prop->count_type == PLY_NONE || prop->type == PLY_NONE ||
                    !type_is_integer(prop->count_type))
                    return meshio_fail(err, "%s:%ld: bad list property types", name, line);
            } else if (n == 3) {
                prop->type = parse_type(words[1]);
                prop_name = words[2];
                if (prop->type == PLY_NONE)
                    return meshio_fail(err, "%s:%ld: unknown property type '%s'", name, line,
                                       words[1]);
            } else {
                return meshio_fail(err, "%s:%ld: expected 'property <type> <name>'", name, line);
            }
            int is_list = prop->count_type != PLY_NONE;
            if (strcmp(e->name, "vertex") == 0 && !is_list) {
                if (strcmp(prop_name, "x") == 0)
                    prop->role = ROLE_X;
                else if (strcmp(prop_name, "y") == 0)
                    prop->role = ROLE_Y;
                else if (strcmp(prop_name, "z") == 0)
                    prop->role = ROLE_Z;
            } else if (strcmp(e->name, "face") == 0 && is_list &&
                       (strcmp(prop_name, "vertex_indices") == 0 ||
                        strcmp(prop_name, "vertex_index") == 0)) {
                if (!type_is_integer(prop->type))
                    return meshio_fail(err, "%s:%ld: face indices must have an integer type", name,
                                       line);
                prop->role = ROLE_INDICES;
            }
        } else if (strcmp(words[0], "end_header") == 0) {
            break;
        } else {
            return meshio_fail(err, "%s:%ld: unknown PLY header line '%s'", name, line, words[0]);
        }
    }
    if (!have_format)
        return meshio_fail(err, "%s: PLY header has no 'format' line", name);
    *body = pos;
    *body_line = line + 1;
    return 0;
}

static uint64_t load_bits(const unsigned char *p, size_t n, int big_endian) {
    uint64_t bits = 0;
    for (size_t i = 0; i < n; ++i)
        bits |= (uint64_t)p[big_endian ? n - 1 - i : i] << (8 * i);
    return bits;
}

// Decodes one binary scalar; every integer type up to 32 bits is exact in double.
static double decode(ply_type t, const unsigned char *p, int big_endian) {
    uint64_t bits = load_bits(p, type_size(t), big_endian);
    switch (t) {
    case PLY_I8: return (double)(int8_t)(uint8_t)bits;
    case PLY_U8: return (double)(uint8_t)bits;
    case PLY_I16: return (double)(int16_t)(uint16_t)bits;
    case PLY_U16: return (double)(uint16_t)bits;
    case PLY_I32: return (double)(int32_t)(uint32_t)bits;
    case PLY_U32: return (double)(uint32_t)bits;
    case PLY_F32: {
        uint32_t b32 = (uint32_t)bits;
        float f;
        memcpy(&f, &b32, sizeof f);
        return f;
    }
    case PLY_F64: {
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    default: return 0.0;
    }
}

// Where the reader is, for messages: a line (ASCII) or a record (binary).
static void location(const ply_reader *r, const ply_element *e, uint64_t record, char *out,
                     size_t out_size) {
    if (r->encoding == PLY_ASCII)
        snprintf(out, out_size, "%s:%ld: %s %llu", r->name, r->line, e->name,
                 (unsigned long long)record);
    else
        snprintf(out, out_size, "%s: %s %llu", r->name, e->name, (unsigned long long)record);
}

// Reads the next value of type t. Returns 0, or -1 with the error set.
static int read_value(ply_reader *r, const ply_element *e, uint64_t record, ply_type t,
                      double *out) {
    char where[256];
    if (r->encoding != PLY_ASCII) {
        size_t n = type_size(t);
        if ((size_t)(r->end - r->p) < n) {
            location(r, e, record, where, sizeof where);
            return meshio_fail(r->err, "%s: file truncated (binary data ends inside this record)",
                               where);
        }
        *out = decode(t, r->p, r->encoding == PLY_BINARY_BE);
        r->p += n;
        return 0;
    }
    const unsigned char *p = r->p;
    for (;;) {
        while (p < r->end && (*p == ' ' || *p == '\t' || *p == '\r'))
            ++p;
        if (p < r->end && *p == '\n') {
            ++r->line;
            ++p;
            continue;
        }
        break;
    }
    r->p = p;
    if (p >= r->end) {
        location(r, e, record, where, sizeof where);
        return meshio_fail(r->err, "%s: file ends inside this record", where);
    }
    char *tail;
    double x;
    if (type_is_integer(t)) {
        long long v = strtoll((const char *)p, &tail, 10);
        x = (double)v;
        if (v > (1ll << 40) || v < -(1ll << 40))
            x = -1.0; // far beyond any 32-bit type: reported as out of range by the caller
    } else {
        x = strtod((const char *)p, &tail);
    }
    if ((const unsigned char *)tail == p ||
        !(*tail == ' ' || *tail == '\t' || *tail == '\r' || *tail == '\n' || *tail == '\0')) {
        location(r, e, record, where, sizeof where);
        return meshio_fail(r->err, "%s: expected a%s number", where,
                           type_is_integer(t) ? "n integer" : "");
    }
    r->p = (const unsigned char *)tail;
    *out = x;
    return 0;
}

// Smallest number of bytes one record of e can take (binary), or one value per byte (ASCII).
static uint64_t min_record_size(const ply_element *e, ply_encoding encoding) {
    uint64_t bytes = 0;
    for (int i = 0; i < e->property_count; ++i) {
        const ply_property *p = &e->properties[i];
        if (encoding == PLY_ASCII)
            bytes += 1;
        else
            bytes += type_size(p->count_type != PLY_NONE ? p->count_type : p->type);
    }
    return bytes;
}

// What the header says the body holds: the counts of the vertex and face
// elements and the coordinates' type.
typedef struct ply_layout {
    uint64_t vertex_count, face_count;
    ply_type coordinate_type;
} ply_layout;

// Checks the declared elements against what a mesh needs and what the body
// (body_size bytes) can hold. Returns 0, or -1 with the error set.
static int check_elements(const char *name, const ply_element *elements, int element_count,
                          ply_encoding encoding, size_t body_size, ply_layout *layout,
                          meshio_error *err) {
    int have_vertex = 0, have_faces = 0;
    memset(layout, 0, sizeof *layout);
    layout->coordinate_type = PLY_NONE;
    for (int i = 0; i < element_count; ++i) {
        const ply_element *e = &elements[i];
        if ((have_vertex && strcmp(e->name, "vertex") == 0) ||
            (have_faces && strcmp(e->name, "face") == 0))
            return meshio_fail(err, "%s: element '%s' declared twice", name, e->name);
        uint64_t min_size = min_record_size(e, encoding);
        if (min_size > 0 && e->count > (uint64_t)body_size / min_size)
            return meshio_fail(err,
                               "%s: element '%s' declares %llu records, more than the file can "
                               "hold (truncated file?)",
                               name, e->name, (unsigned long long)e->count);
        if (strcmp(e->name, "vertex") == 0) {
            int roles = 0;
            for (int k = 0; k < e->property_count; ++k) {
                roles |= 1 << e->properties[k].role;
                if (e->properties[k].role == ROLE_X)
                    layout->coordinate_type = e->properties[k].type;
            }
            if ((roles & (1 << ROLE_X | 1 << ROLE_Y | 1 << ROLE_Z)) !=
                (1 << ROLE_X | 1 << ROLE_Y | 1 << ROLE_Z))
                return meshio_fail(err, "%s: element 'vertex' lacks an x, y or z property", name);
            have_vertex = 1;
            layout->vertex_count = e->count;
        }
        if (strcmp(e->name, "face") == 0) {
            int found = 0;
            for (int k = 0; k < e->property_count; ++k)
                found |= e->properties[k].role == ROLE_INDICES;
            if (!found)
                return meshio_fail(err, "%s: element 'face' has no 'vertex_indices' list", name);
            have_faces = 1;
            layout->face_count = e->count;
        }
    }
    if (!have_vertex)
        return meshio_fail(err, "%s: no 'vertex' element", name);
    if (!have_faces)
        return meshio_fail(err, "%s: no 'face' element", name);
    if (layout->vertex_count >= (uint64_t)UINT32_MAX - 1)
        return meshio_fail(err, "%s: too many vertices (%llu)", name,
                           (unsigned long long)layout->vertex_count);
    return 0;
}

// The mesh being read from the body.
typedef struct ply_target {
    double *positions;
    uint64_t vertex_count;
    meshio_array triangles; /* uint32_t */
    meshio_array polygon;   /* uint32_t, the face being read */
} ply_target;

// Reads one list property of record `rec` of e; the vertex indices of a face
// are checked and fan-triangulated into t. Returns 0, or -1 with the error set.
static int read_list(ply_reader *r, const ply_element *e, uint64_t rec, const ply_property *prop,
                     ply_target *t) {
    double count, x;
    char where[256];
    if (read_value(r, e, rec, prop->count_type, &count) != 0)
        return -1;
    if (count < 0) {
        location(r, e, rec, where, sizeof where);
        return meshio_fail(r->err, "%s: negative list length", where);
    }
    if (prop->role == ROLE_INDICES && count < 3) {
        location(r, e, rec, where, sizeof where);
        return meshio_fail(r->err, "%s: face with %.0f vertices (at least 3 needed)", where, count);
    }
    t->polygon.count = 0;
    for (uint64_t j = 0; j < (uint64_t)count; ++j) {
        if (read_value(r, e, rec, prop->type, &x) != 0)
            return -1;
        if (prop->role != ROLE_INDICES)
            continue;
        if (!(x >= 0 && x < (double)t->vertex_count)) {
            location(r, e, rec, where, sizeof where);
            return meshio_fail(r->err, "%s: vertex index %.0f out of range (%llu vertices)", where,
                               x, (unsigned long long)t->vertex_count);
        }
        if (meshio_array_reserve(&t->polygon, 1))
            return meshio_fail(r->err, "%s: out of memory", r->name);
        ((uint32_t *)t->polygon.data)[t->polygon.count++] = (uint32_t)x;
    }
    if (prop->role != ROLE_INDICES)
        return 0;
    size_t n = t->polygon.count;
    if (meshio_array_reserve(&t->triangles, 3 * (n - 2)))
        return meshio_fail(r->err, "%s: out of memory", r->name);
    const uint32_t *pv = t->polygon.data;
    uint32_t *out = (uint32_t *)t->triangles.data + t->triangles.count;
    for (size_t j = 1; j + 1 < n; ++j) { // fan triangulation
        *out++ = pv[0];
        *out++ = pv[j];
        *out++ = pv[j + 1];
    }
    t->triangles.count += 3 * (n - 2);
    return 0;
}

// Reads record `rec` of e: its coordinates (vertex) into t->positions, its
// face lists into t->triangles; other values are read and dropped.
static int read_record(ply_reader *r, const ply_element *e, uint64_t rec, int is_vertex,
                       ply_target *t) {
    for (int k = 0; k < e->property_count; ++k) {
        const ply_property *prop = &e->properties[k];
        if (prop->count_type != PLY_NONE) {
            if (read_list(r, e, rec, prop, t) != 0)
                return -1;
            continue;
        }
        double x;
        if (read_value(r, e, rec, prop->type, &x) != 0)
            return -1;
        if (is_vertex && prop->role != ROLE_SKIP) {
            if (!isfinite(x)) {
                char where[256];
                location(r, e, rec, where, sizeof where);
                return meshio_fail(r->err, "%s: NaN or infinite coordinate", where);
            }
            t->positions[3 * rec + (uint64_t)(prop->role - ROLE_X)] = x;
        }
    }
    return 0;
}

// Reads every record of every element, reporting progress every 65536
// records (the record that fails included).
static int read_body(ply_reader *r, const ply_element *elements, int element_count, ply_target *t,
                     const meshio_progress *progress) {
    uint64_t total_records = 0, done_records = 0;
    for (int i = 0; i < element_count; ++i)
        total_records += elements[i].count;
    for (int i = 0; i < element_count; ++i) {
        const ply_element *e = &elements[i];
        if (e->property_count == 0)
            continue; // no data at all, whatever its count says
        int is_vertex = strcmp(e->name, "vertex") == 0;
        for (uint64_t rec = 0; rec < e->count; ++rec) {
            int status = read_record(r, e, rec, is_vertex, t);
            if ((++done_records & 0xFFFF) == 0)
                meshio_report(progress, r->name, (double)done_records, (double)total_records);
            if (status != 0)
                return -1;
        }
    }
    return 0;
}

int meshio_parse_ply(const char *name, const unsigned char *data, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress) {
    ply_element *elements = calloc(MAX_ELEMENTS, sizeof *elements);
    if (elements == NULL)
        return meshio_fail(err, "%s: out of memory", name);
    int element_count = 0;
    ply_reader r;
    memset(&r, 0, sizeof r);
    r.name = name;
    r.err = err;
    size_t body = 0;
    ply_layout layout;
    ply_target t = {NULL, 0, {NULL, 0, 0, sizeof(uint32_t)}, {NULL, 0, 0, sizeof(uint32_t)}};
    int status =
        parse_header(name, data, size, elements, &element_count, &r.encoding, &body, &r.line, err);
    if (status == 0)
        status =
            check_elements(name, elements, element_count, r.encoding, size - body, &layout, err);
    if (status == 0) {
        t.vertex_count = layout.vertex_count;
        t.positions = malloc((size_t)layout.vertex_count * 3 * sizeof *t.positions + 1);
        if (t.positions == NULL ||
            meshio_array_reserve(&t.triangles, 3 * (size_t)layout.face_count))
            status = meshio_fail(err, "%s: out of memory", name);
    }
    r.p = data + body;
    r.end = data + size;
    if (status == 0)
        status = read_body(&r, elements, element_count, &t, progress);
    free(elements);
    free(t.polygon.data);
    if (status != 0) {
        free(t.positions);
        free(t.triangles.data);
        return -1;
    }
    static const char *details[3][2] = {
        {"ascii", "ascii"},
        {"binary little endian, float32", "binary little endian, float64"},
        {"binary big endian, float32", "binary big endian, float64"}};
    mesh->vertex_count = (size_t)layout.vertex_count;
    mesh->positions = t.positions;
    mesh->triangle_count = t.triangles.count / 3;
    mesh->triangles = t.triangles.data;
    mesh->face_count = (size_t)layout.face_count;
    mesh->format_detail = details[r.encoding][layout.coordinate_type == PLY_F64];
    return 0;
}
