// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "ply.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_PROPS = 32, MAX_ELEMENTS = 8 };

typedef struct property {
    char name[64];
    int type; // byte size of the scalar, negative for float/double marker below
    int is_float;
    int is_signed;
    int is_list;
    int count_size; // list count scalar size
} property;

typedef struct element {
    char name[64];
    long count;
    int nprops;
    property props[MAX_PROPS];
} element;

static int type_of(const char *t, int *size, int *is_float, int *is_signed) {
    static const struct {
        const char *name;
        int size, is_float, is_signed;
    } types[] = {
        {"char", 1, 0, 1},  {"int8", 1, 0, 1},    {"uchar", 1, 0, 0},  {"uint8", 1, 0, 0},
        {"short", 2, 0, 1}, {"int16", 2, 0, 1},   {"ushort", 2, 0, 0}, {"uint16", 2, 0, 0},
        {"int", 4, 0, 1},   {"int32", 4, 0, 1},   {"uint", 4, 0, 0},   {"uint32", 4, 0, 0},
        {"float", 4, 1, 1}, {"float32", 4, 1, 1}, {"double", 8, 1, 1}, {"float64", 8, 1, 1}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i)
        if (strcmp(t, types[i].name) == 0) {
            *size = types[i].size;
            *is_float = types[i].is_float;
            *is_signed = types[i].is_signed;
            return 0;
        }
    return -1;
}

static int host_little(void) {
    const uint16_t one = 1;
    return *(const unsigned char *)&one == 1;
}

// Reads one binary scalar as double.
static int read_binary(FILE *f, int size, int is_float, int is_signed, int swap, double *out) {
    unsigned char b[8];
    if (fread(b, 1, (size_t)size, f) != (size_t)size)
        return -1;
    if (swap)
        for (int i = 0; i < size / 2; ++i) {
            unsigned char t = b[i];
            b[i] = b[size - 1 - i];
            b[size - 1 - i] = t;
        }
    if (is_float && size == 4) {
        float v;
        memcpy(&v, b, 4);
        *out = v;
    } else if (is_float) {
        double v;
        memcpy(&v, b, 8);
        *out = v;
    } else if (size == 1)
        *out = is_signed ? (double)(int8_t)b[0] : (double)b[0];
    else if (size == 2) {
        uint16_t v;
        memcpy(&v, b, 2);
        *out = is_signed ? (double)(int16_t)v : v;
    } else {
        uint32_t v;
        memcpy(&v, b, 4);
        *out = is_signed ? (double)(int32_t)v : v;
    }
    return 0;
}

static int read_scalar(FILE *f, int format, int size, int is_float, int is_signed, double *out) {
    if (format == 0)
        return fscanf(f, "%lf", out) == 1 ? 0 : -1;
    return read_binary(f, size, is_float, is_signed, (format == 1) != host_little(), out);
}

int ply_read(const char *path, scene *s, char *err, size_t err_size) {
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        snprintf(err, err_size, "%s: cannot open", path);
        return -1;
    }
    char line[512];
    element el[MAX_ELEMENTS];
    int nel = 0, format = -1; // 0 ascii, 1 little, 2 big
    if (fgets(line, sizeof line, f) == NULL || strncmp(line, "ply", 3) != 0)
        goto bad;
    while (fgets(line, sizeof line, f) != NULL) {
        char a[64], b[64], c[64], d[64], e[64];
        int n = sscanf(line, "%63s %63s %63s %63s %63s", a, b, c, d, e);
        if (n <= 0 || strcmp(a, "comment") == 0 || strcmp(a, "obj_info") == 0)
            continue;
        if (strcmp(a, "end_header") == 0)
            break;
        if (strcmp(a, "format") == 0 && n >= 2)
            format = strcmp(b, "ascii") == 0                  ? 0
                     : strcmp(b, "binary_little_endian") == 0 ? 1
                     : strcmp(b, "binary_big_endian") == 0    ? 2
                                                              : -1;
        else if (strcmp(a, "element") == 0 && n == 3 && nel < MAX_ELEMENTS) {
            snprintf(el[nel].name, sizeof el[nel].name, "%s", b);
            el[nel].count = strtol(c, NULL, 10);
            el[nel].nprops = 0;
            nel++;
        } else if (strcmp(a, "property") == 0 && nel > 0 && el[nel - 1].nprops < MAX_PROPS) {
            property *p = &el[nel - 1].props[el[nel - 1].nprops++];
            memset(p, 0, sizeof *p);
            if (strcmp(b, "list") == 0 && n == 5) {
                int fl, sg;
                p->is_list = 1;
                if (type_of(c, &p->count_size, &fl, &sg) != 0 ||
                    type_of(d, &p->type, &p->is_float, &p->is_signed) != 0)
                    goto bad;
                snprintf(p->name, sizeof p->name, "%s", e);
            } else if (n == 3) {
                if (type_of(b, &p->type, &p->is_float, &p->is_signed) != 0)
                    goto bad;
                snprintf(p->name, sizeof p->name, "%s", c);
            } else
                goto bad;
        }
    }
    if (format < 0)
        goto bad;
    size_t tri_cap = 0;
    for (int i = 0; i < nel; ++i) {
        element *E = &el[i];
        int is_vertex = strcmp(E->name, "vertex") == 0, is_face = strcmp(E->name, "face") == 0;
        if (is_vertex) {
            s->vertex_count = (size_t)E->count;
            s->positions = calloc(3 * s->vertex_count + 1, sizeof(double));
            if (s->positions == NULL)
                goto bad;
        }
        for (long r = 0; r < E->count; ++r) {
            for (int k = 0; k < E->nprops; ++k) {
                property *p = &E->props[k];
                double v;
                if (!p->is_list) {
                    if (read_scalar(f, format, p->type, p->is_float, p->is_signed, &v) != 0)
                        goto bad;
                    if (is_vertex && p->name[1] == 0 && p->name[0] >= 'x' && p->name[0] <= 'z')
                        s->positions[3 * (size_t)r + (size_t)(p->name[0] - 'x')] = v;
                    continue;
                }
                double cnt;
                if (read_scalar(f, format, p->count_size, 0, 0, &cnt) != 0 || cnt < 0 || cnt > 64)
                    goto bad;
                uint32_t poly[64];
                for (int j = 0; j < (int)cnt; ++j) {
                    if (read_scalar(f, format, p->type, p->is_float, p->is_signed, &v) != 0)
                        goto bad;
                    poly[j] = (uint32_t)v;
                }
                if (!is_face || (strcmp(p->name, "vertex_indices") != 0 &&
                                 strcmp(p->name, "vertex_index") != 0))
                    continue;
                for (int j = 1; j + 1 < (int)cnt; ++j) {
                    if (s->triangle_count == tri_cap) {
                        tri_cap = tri_cap ? 2 * tri_cap : 1024;
                        uint32_t *t = realloc(s->triangles, 3 * tri_cap * sizeof(uint32_t));
                        if (t == NULL)
                            goto bad;
                        s->triangles = t;
                    }
                    uint32_t *t = s->triangles + 3 * s->triangle_count++;
                    t[0] = poly[0];
                    t[1] = poly[j];
                    t[2] = poly[j + 1];
                }
            }
        }
    }
    fclose(f);
    if (s->positions == NULL || s->triangles == NULL) {
        snprintf(err, err_size, "%s: no vertices or no faces", path);
        scene_free(s);
        return -1;
    }
    return 0;
bad:
    fclose(f);
    scene_free(s);
    snprintf(err, err_size, "%s: malformed or unsupported PLY", path);
    return -1;
}
