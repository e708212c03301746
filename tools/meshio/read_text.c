// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Readers for OBJ, OFF and STL (ASCII and binary). Hand-written because the
// packaged OBJ parser (tinyobjloader 2.0rc10 in Debian 12) turns "nan" and
// unparsable numbers into 0, drops faces with fewer than 3 vertices with only
// a warning, and reports out-of-range indices at the wrong line: the tool
// must reject such files with the exact line instead of checking a different
// mesh. Each parser reads a buffer that ends with a NUL sentinel.
#define _POSIX_C_SOURCE 200809L
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Accumulates positions and fan-triangulated polygons.
typedef struct builder {
    meshio_array positions; /* double */
    meshio_array triangles; /* uint32_t */
    meshio_array polygon;   /* uint32_t, the face being read */
    size_t faces;
} builder;

static void builder_init(builder *b) {
    memset(b, 0, sizeof *b);
    b->positions.item_size = sizeof(double);
    b->triangles.item_size = sizeof(uint32_t);
    b->polygon.item_size = sizeof(uint32_t);
}

static void builder_free(builder *b) {
    free(b->positions.data);
    free(b->triangles.data);
    free(b->polygon.data);
}

static int builder_vertex(builder *b, const double p[3]) {
    if (b->positions.count / 3 >= (size_t)UINT32_MAX - 1 || meshio_array_reserve(&b->positions, 3))
        return -1;
    memcpy((double *)b->positions.data + b->positions.count, p, 3 * sizeof(double));
    b->positions.count += 3;
    return 0;
}

static size_t builder_vertex_count(const builder *b) {
    return b->positions.count / 3;
}

static int builder_corner(builder *b, uint32_t v) {
    if (meshio_array_reserve(&b->polygon, 1))
        return -1;
    ((uint32_t *)b->polygon.data)[b->polygon.count++] = v;
    return 0;
}

// Fan triangulation: (p0 p1 p2), (p0 p2 p3), ... The caller checked >= 3 corners.
static int builder_polygon(builder *b) {
    size_t n = b->polygon.count;
    if (meshio_array_reserve(&b->triangles, 3 * (n - 2)))
        return -1;
    const uint32_t *p = b->polygon.data;
    uint32_t *t = (uint32_t *)b->triangles.data + b->triangles.count;
    for (size_t i = 1; i + 1 < n; ++i) {
        *t++ = p[0];
        *t++ = p[i];
        *t++ = p[i + 1];
    }
    b->triangles.count += 3 * (n - 2);
    b->polygon.count = 0;
    b->faces++;
    return 0;
}

static void builder_finish(builder *b, meshio_mesh *mesh, const char *detail) {
    mesh->vertex_count = b->positions.count / 3;
    mesh->positions = b->positions.data;
    mesh->triangle_count = b->triangles.count / 3;
    mesh->triangles = b->triangles.data;
    mesh->face_count = b->faces;
    mesh->format_detail = detail;
    free(b->polygon.data);
    memset(b, 0, sizeof *b);
}

static int is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}
static int is_end(char c) {
    return c == '\n' || c == '\0' || c == '#';
}

static const char *skip_blank(const char *p) {
    while (is_blank(*p))
        ++p;
    return p;
}

// Reads one number on the current line. Returns 1 (read), 0 (the line ended
// first), or -1 (something that is not a number, or a number glued to text).
static int parse_real(const char **pp, double *out) {
    const char *p = skip_blank(*pp);
    if (is_end(*p))
        return 0;
    char *end;
    double x = strtod(p, &end);
    if (end == p || !(is_blank(*end) || is_end(*end)))
        return -1;
    *out = x;
    *pp = end;
    return 1;
}

// Reads an integer on the current line (optional sign, decimal digits), with
// the same results as parse_real. Values are clamped to +-2^62 (then out of range).
static int parse_integer(const char **pp, long long *out, int allow_slash) {
    const char *p = skip_blank(*pp);
    if (is_end(*p))
        return 0;
    int negative = 0;
    if (*p == '-' || *p == '+')
        negative = *p++ == '-';
    if (!(*p >= '0' && *p <= '9'))
        return -1;
    long long value = 0;
    while (*p >= '0' && *p <= '9') {
        if (value < (1ll << 62) / 10)
            value = 10 * value + (*p - '0');
        else
            value = 1ll << 62;
        ++p;
    }
    if (allow_slash) // OBJ "v/vt/vn": texture and normal indices are not used
        while (*p == '/' || *p == '-' || *p == '+' || (*p >= '0' && *p <= '9'))
            ++p;
    if (!(is_blank(*p) || is_end(*p)))
        return -1;
    *out = negative ? -value : value;
    *pp = p;
    return 1;
}

static const char *line_end(const char *p, const char *end) {
    const char *eol = memchr(p, '\n', (size_t)(end - p));
    return eol ? eol : end;
}

// Text formats must not contain NUL bytes: the parsers use NUL as the end.
static int check_text(const char *name, const char *text, size_t size, meshio_error *err) {
    const char *nul = memchr(text, '\0', size);
    if (nul == NULL)
        return 0;
    long line = 1;
    for (const char *p = text; p < nul; ++p)
        line += *p == '\n';
    return meshio_fail(err, "%s:%ld: NUL byte in a text file (binary data?)", name, line);
}

static int out_of_memory(const char *name, meshio_error *err) {
    return meshio_fail(err, "%s: out of memory (or more than 2^32 - 2 vertices)", name);
}

// ---------------------------------------------------------------------------
// OBJ: "v x y z [w | r g b]" and "f i[/t][/n] ..." with 1-based or negative
// (relative) indices; every other statement is ignored.

int meshio_parse_obj(const char *name, const char *text, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress) {
    if (check_text(name, text, size, err))
        return -1;
    builder b;
    builder_init(&b);
    const char *p = text, *end = text + size;
    long line = 0;
    // Positive indices may refer to vertices defined further down, so they
    // are checked at the end; the largest one and its line make the message.
    long long max_index = 0;
    long max_index_line = 0;
    size_t next_report = 1u << 20;
    int status = 0;
    while (status == 0 && p < end) {
        ++line;
        const char *eol = line_end(p, end);
        const char *q = skip_blank(p);
        // A bare 'v' or 'f' is a statement with nothing after it: an error
        // below, like 'v 1 2', rather than a line silently skipped.
        if (q[0] == 'v' && (is_blank(q[1]) || is_end(q[1]))) {
            double x[3];
            q += 1;
            for (int k = 0; k < 3 && status == 0; ++k) {
                int r = parse_real(&q, &x[k]);
                if (r <= 0)
                    status = meshio_fail(err, "%s:%ld: expected 'v x y z', %s", name, line,
                                         r == 0 ? "too few coordinates"
                                                : "a coordinate is not a number");
                else if (!isfinite(x[k]))
                    status = meshio_fail(err, "%s:%ld: NaN or infinite coordinate", name, line);
            }
            if (status == 0 && builder_vertex(&b, x))
                status = out_of_memory(name, err);
        } else if (q[0] == 'f' && (is_blank(q[1]) || is_end(q[1]))) {
            q += 1;
            long long index;
            int r;
            while (status == 0 && (r = parse_integer(&q, &index, 1)) == 1) {
                long long count = (long long)builder_vertex_count(&b);
                long long v;
                if (index == 0) {
                    status = meshio_fail(err, "%s:%ld: face index 0 (OBJ indices start at 1)", name,
                                         line);
                    break;
                }
                if (index < 0) {
                    v = count + index;
                    if (v < 0) {
                        status = meshio_fail(
                            err, "%s:%ld: face index %lld out of range (%lld vertices so far)",
                            name, line, index, count);
                        break;
                    }
                } else {
                    v = index - 1;
                    if (index > max_index) {
                        max_index = index;
                        max_index_line = line;
                    }
                }
                if (v >= (long long)UINT32_MAX - 1) {
                    status =
                        meshio_fail(err, "%s:%ld: face index %lld out of range", name, line, index);
                    break;
                }
                if (builder_corner(&b, (uint32_t)v))
                    status = out_of_memory(name, err);
            }
            if (status == 0 && r < 0)
                status = meshio_fail(err, "%s:%ld: expected vertex indices after 'f'", name, line);
            else if (status == 0 && b.polygon.count < 3)
                status = meshio_fail(err, "%s:%ld: face with %zu vertices (at least 3 needed)",
                                     name, line, b.polygon.count);
            else if (status == 0 && builder_polygon(&b))
                status = out_of_memory(name, err);
        }
        p = eol + (eol < end);
        if ((size_t)(p - text) >= next_report) {
            meshio_report(progress, name, (double)(p - text), (double)size);
            next_report += 1u << 20;
        }
    }
    if (status == 0 && max_index > (long long)builder_vertex_count(&b))
        status =
            meshio_fail(err, "%s:%ld: face index %lld out of range (the file has %zu vertices)",
                        name, max_index_line, max_index, builder_vertex_count(&b));
    if (status != 0) {
        builder_free(&b);
        return -1;
    }
    builder_finish(&b, mesh, "text");
    return 0;
}

// ---------------------------------------------------------------------------
// OFF (Geomview): a header word [ST][C][N]OFF, counts "V F [E]", V vertex
// lines "x y z [extra]", F face lines "n i0 .. i(n-1) [colour]", 0-based
// indices; '#' starts a comment. One record per line, as writers produce.

// Next line with data on it (comments and blank lines skipped), or NULL at the end.
static const char *next_data_line(const char **pp, const char *end, long *line) {
    while (*pp < end) {
        const char *start = *pp;
        const char *eol = line_end(start, end);
        *pp = eol + (eol < end);
        ++*line;
        const char *q = skip_blank(start);
        if (!is_end(*q))
            return q;
    }
    return NULL;
}

int meshio_parse_off(const char *name, const char *text, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress) {
    if (check_text(name, text, size, err))
        return -1;
    const char *p = text, *end = text + size;
    long line = 0;
    const char *q = next_data_line(&p, end, &line);
    if (q == NULL)
        return meshio_fail(err, "%s: no OFF header", name);
    // The header word: optional ST, C, N prefixes; 4 and n (other dimensions)
    // and binary OFF are not supported.
    while (*q == 'S' || *q == 'T' || *q == 'C' || *q == 'N')
        ++q;
    if (strncmp(q, "OFF", 3) != 0 || !(is_blank(q[3]) || is_end(q[3])))
        return meshio_fail(err, "%s:%ld: expected an OFF header (OFF, COFF, NOFF, STOFF...)", name,
                           line);
    q += 3;
    long long counts[3] = {0, 0, 0};
    int got = 0;
    const char *header_rest = skip_blank(q);
    if (strncmp(header_rest, "BINARY", 6) == 0)
        return meshio_fail(err, "%s:%ld: binary OFF is not supported", name, line);
    if (is_end(*header_rest)) {
        q = next_data_line(&p, end, &line);
        if (q == NULL)
            return meshio_fail(err, "%s: missing vertex and face counts after the header", name);
    }
    for (got = 0; got < 3; ++got) {
        int r = parse_integer(&q, &counts[got], 0);
        if (r < 0)
            return meshio_fail(err, "%s:%ld: expected 'vertices faces edges' counts", name, line);
        if (r == 0)
            break;
    }
    if (got < 2 || counts[0] < 0 || counts[1] < 0)
        return meshio_fail(err, "%s:%ld: expected 'vertices faces edges' counts", name, line);
    if (counts[0] >= (long long)UINT32_MAX - 1)
        return meshio_fail(err, "%s:%ld: too many vertices (%lld)", name, line, counts[0]);
    builder b;
    builder_init(&b);
    // Each vertex line takes at least 6 bytes: do not trust the header further.
    size_t expect = (size_t)counts[0] < size / 6 ? (size_t)counts[0] : size / 6;
    if (meshio_array_reserve(&b.positions, 3 * expect)) {
        builder_free(&b);
        return out_of_memory(name, err);
    }
    int status = 0;
    for (long long v = 0; status == 0 && v < counts[0]; ++v) {
        q = next_data_line(&p, end, &line);
        if (q == NULL) {
            status = meshio_fail(err, "%s: file ends at vertex %lld of %lld", name, v, counts[0]);
            break;
        }
        double x[3];
        for (int k = 0; k < 3 && status == 0; ++k) {
            int r = parse_real(&q, &x[k]);
            if (r <= 0)
                status =
                    meshio_fail(err, "%s:%ld: expected 'x y z' for vertex %lld", name, line, v);
            else if (!isfinite(x[k]))
                status = meshio_fail(err, "%s:%ld: NaN or infinite coordinate", name, line);
        }
        if (status == 0 && builder_vertex(&b, x))
            status = out_of_memory(name, err);
        if ((v & 0xFFFF) == 0)
            meshio_report(progress, name, (double)(p - text), (double)size);
    }
    for (long long f = 0; status == 0 && f < counts[1]; ++f) {
        q = next_data_line(&p, end, &line);
        if (q == NULL) {
            status = meshio_fail(err, "%s: file ends at face %lld of %lld", name, f, counts[1]);
            break;
        }
        long long n, index;
        if (parse_integer(&q, &n, 0) != 1 || n < 0) {
            status =
                meshio_fail(err, "%s:%ld: expected a vertex count for face %lld", name, line, f);
            break;
        }
        if (n < 3) {
            status = meshio_fail(err, "%s:%ld: face with %lld vertices (at least 3 needed)", name,
                                 line, n);
            break;
        }
        for (long long k = 0; status == 0 && k < n; ++k) {
            if (parse_integer(&q, &index, 0) != 1)
                status = meshio_fail(err, "%s:%ld: face %lld: expected %lld vertex indices", name,
                                     line, f, n);
            else if (index < 0 || index >= counts[0])
                status = meshio_fail(err, "%s:%ld: face index %lld out of range (%lld vertices)",
                                     name, line, index, counts[0]);
            else if (builder_corner(&b, (uint32_t)index))
                status = out_of_memory(name, err);
        }
        if (status == 0 && builder_polygon(&b))
            status = out_of_memory(name, err);
        if ((f & 0xFFFF) == 0)
            meshio_report(progress, name, (double)(p - text), (double)size);
    }
    if (status != 0) {
        builder_free(&b);
        return -1;
    }
    builder_finish(&b, mesh, "text");
    return 0;
}

// ---------------------------------------------------------------------------
// STL. Binary: 80-byte header, uint32 facet count, 50 bytes per facet
// (normal, three corners as little-endian float32, uint16 attribute). ASCII:
// solid / facet normal / outer loop / vertex x y z (x3) / endloop / endfacet.
// Facets share no vertices in STL: each corner is a file vertex (3 per facet).

static uint32_t load_u32le(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float load_f32le(const unsigned char *p) {
    uint32_t bits = load_u32le(p);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static int parse_stl_binary(const char *name, const unsigned char *data, size_t size,
                            meshio_mesh *mesh, meshio_error *err, const meshio_progress *progress) {
    if (size < 84)
        return meshio_fail(
            err, "%s: too short for a binary STL (%zu bytes, the header alone is 84)", name, size);
    uint64_t n = load_u32le(data + 80);
    uint64_t expected = 84 + 50 * n;
    if ((uint64_t)size != expected)
        return meshio_fail(err,
                           "%s: binary STL declares %llu triangles (%llu bytes) but the file has "
                           "%zu bytes (truncated or not an STL file)",
                           name, (unsigned long long)n, (unsigned long long)expected, size);
    if (3 * n >= (uint64_t)UINT32_MAX - 1)
        return meshio_fail(err, "%s: too many triangles (%llu)", name, (unsigned long long)n);
    double *positions = malloc((size_t)(9 * n) * sizeof *positions + 1);
    uint32_t *triangles = malloc((size_t)(3 * n) * sizeof *triangles + 1);
    if (positions == NULL || triangles == NULL) {
        free(positions);
        free(triangles);
        return out_of_memory(name, err);
    }
    for (uint64_t f = 0; f < n; ++f) {
        const unsigned char *rec = data + 84 + 50 * f + 12; // skip the normal
        for (int k = 0; k < 9; ++k) {
            double x = load_f32le(rec + 4 * k);
            if (!isfinite(x)) {
                free(positions);
                free(triangles);
                return meshio_fail(err, "%s: triangle %llu has a NaN or infinite coordinate", name,
                                   (unsigned long long)f);
            }
            positions[9 * f + (uint64_t)k] = x;
        }
        for (int k = 0; k < 3; ++k)
            triangles[3 * f + (uint64_t)k] = (uint32_t)(3 * f + (uint64_t)k);
        if ((f & 0xFFFF) == 0)
            meshio_report(progress, name, (double)f, (double)n);
    }
    mesh->vertex_count = (size_t)(3 * n);
    mesh->positions = positions;
    mesh->triangle_count = (size_t)n;
    mesh->triangles = triangles;
    mesh->face_count = (size_t)n;
    mesh->format_detail = "binary";
    return 0;
}

// Next whitespace-separated token, counting lines; returns its length (0 at the end).
static size_t next_token(const char **pp, long *line) {
    const char *p = *pp;
    for (;;) {
        while (is_blank(*p))
            ++p;
        if (*p != '\n')
            break;
        ++*line;
        ++p;
    }
    *pp = p;
    size_t n = 0;
    while (p[n] != '\0' && p[n] != '\n' && !is_blank(p[n]))
        ++n;
    return n;
}

static int token_is(const char *token, size_t n, const char *word) {
    return n == strlen(word) && memcmp(token, word, n) == 0;
}

static const char *rest_of_line(const char *p) {
    while (*p != '\n' && *p != '\0')
        ++p;
    return p;
}

static int parse_stl_ascii(const char *name, const char *text, size_t size, meshio_mesh *mesh,
                           meshio_error *err, const meshio_progress *progress) {
    if (check_text(name, text, size, err))
        return -1;
    builder b;
    builder_init(&b);
    const char *p = text;
    long line = 1;
    int status = 0, in_facet = 0;
    size_t next_report = 1u << 20;
    for (;;) {
        size_t n = next_token(&p, &line);
        if (n == 0)
            break;
        const char *token = p;
        p += n;
        if (token_is(token, n, "solid") || token_is(token, n, "endsolid")) {
            p = rest_of_line(p); // the solid's name
        } else if (token_is(token, n, "facet")) {
            if (in_facet) {
                status = meshio_fail(err, "%s:%ld: 'facet' inside a facet", name, line);
                break;
            }
            in_facet = 1;
            b.polygon.count = 0;
            p = rest_of_line(p); // "normal nx ny nz": recomputed from the corners
        } else if (token_is(token, n, "outer")) {
            size_t m = next_token(&p, &line);
            if (!token_is(p, m, "loop")) {
                status = meshio_fail(err, "%s:%ld: expected 'outer loop'", name, line);
                break;
            }
            p += m;
        } else if (token_is(token, n, "vertex")) {
            double x[3];
            for (int k = 0; k < 3 && status == 0; ++k) {
                int r = parse_real(&p, &x[k]);
                if (r <= 0)
                    status = meshio_fail(err, "%s:%ld: expected 'vertex x y z'", name, line);
                else if (!isfinite(x[k]))
                    status = meshio_fail(err, "%s:%ld: NaN or infinite coordinate", name, line);
            }
            if (status == 0 && !in_facet)
                status = meshio_fail(err, "%s:%ld: 'vertex' outside a facet", name, line);
            if (status == 0 && (builder_vertex(&b, x) ||
                                builder_corner(&b, (uint32_t)(builder_vertex_count(&b) - 1))))
                status = out_of_memory(name, err);
            if (status)
                break;
        } else if (token_is(token, n, "endloop")) {
        } else if (token_is(token, n, "endfacet")) {
            if (!in_facet) {
                status = meshio_fail(err, "%s:%ld: 'endfacet' without 'facet'", name, line);
                break;
            }
            if (b.polygon.count < 3) {
                status = meshio_fail(err, "%s:%ld: facet with %zu vertices (at least 3 needed)",
                                     name, line, b.polygon.count);
                break;
            }
            if (builder_polygon(&b)) {
                status = out_of_memory(name, err);
                break;
            }
            in_facet = 0;
        } else {
            status = meshio_fail(err, "%s:%ld: unexpected '%.*s' in an ASCII STL file", name, line,
                                 (int)(n < 40 ? n : 40), token);
            break;
        }
        if ((size_t)(p - text) >= next_report) {
            meshio_report(progress, name, (double)(p - text), (double)size);
            next_report += 1u << 20;
        }
    }
    if (status == 0 && in_facet)
        status = meshio_fail(err, "%s:%ld: file ends inside a facet", name, line);
    if (status != 0) {
        builder_free(&b);
        return -1;
    }
    builder_finish(&b, mesh, "ascii");
    return 0;
}

int meshio_parse_stl(const char *name, const unsigned char *data, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress) {
    // Binary files may also begin with "solid" (some exporters write it into
    // the header), so an exact binary size wins over the magic word.
    if (size >= 84 && (uint64_t)size == 84 + 50 * (uint64_t)load_u32le(data + 80))
        return parse_stl_binary(name, data, size, mesh, err, progress);
    size_t i = 0;
    while (i < size && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n'))
        ++i;
    if (size - i >= 5 && memcmp(data + i, "solid", 5) == 0)
        return parse_stl_ascii(name, (const char *)data, size, mesh, err, progress);
    return parse_stl_binary(name, data, size, mesh, err, progress);
}
