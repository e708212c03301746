// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "scenes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void scene_free(scene *s) {
    free(s->positions);
    free(s->triangles);
    memset(s, 0, sizeof *s);
}

static int scene_alloc(scene *s, size_t vertices, size_t triangles) {
    s->vertex_count = vertices;
    s->triangle_count = triangles;
    s->positions = calloc(3 * vertices, sizeof(double));
    s->triangles = calloc(3 * triangles, sizeof(uint32_t));
    if (s->positions == NULL || s->triangles == NULL) {
        scene_free(s);
        return -1;
    }
    return 0;
}

static void set_tri(uint32_t *t, uint32_t a, uint32_t b, uint32_t c) {
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

int scene_grid(scene *s, unsigned nx, unsigned ny, double spacing) {
    if (scene_alloc(s, (size_t)(nx + 1) * (ny + 1), (size_t)2 * nx * ny) != 0)
        return -1;
    for (unsigned i = 0; i <= nx; ++i)
        for (unsigned j = 0; j <= ny; ++j) {
            double *p = s->positions + 3 * ((size_t)i * (ny + 1) + j);
            p[0] = i * spacing;
            p[1] = j * spacing;
            p[2] = 0.0;
        }
    uint32_t *t = s->triangles;
    for (unsigned i = 0; i < nx; ++i)
        for (unsigned j = 0; j < ny; ++j) {
            uint32_t v00 = i * (ny + 1) + j, v10 = (i + 1) * (ny + 1) + j;
            uint32_t v01 = v00 + 1, v11 = v10 + 1;
            set_tri(t, v00, v10, v11);
            set_tri(t + 3, v00, v11, v01);
            t += 6;
        }
    return 0;
}

int scene_hairpin(scene *s, unsigned n, double gap) {
    if (scene_alloc(s, (size_t)4 * (n + 1), (size_t)4 * n + 2) != 0)
        return -1;
    uint32_t top = 2 * (n + 1);
    for (unsigned i = 0; i <= n; ++i)
        for (unsigned j = 0; j <= 1; ++j) {
            double *b = s->positions + 3 * (2 * i + j);
            double *u = s->positions + 3 * (top + 2 * i + j);
            b[0] = u[0] = i;
            b[1] = u[1] = j;
            b[2] = 0.0;
            u[2] = gap;
        }
    uint32_t *t = s->triangles;
    for (unsigned layer = 0; layer < 2; ++layer) {
        uint32_t base = layer ? top : 0;
        for (unsigned i = 0; i < n; ++i) {
            uint32_t v00 = base + 2 * i, v10 = base + 2 * (i + 1);
            set_tri(t, v00, v10, v10 + 1);
            set_tri(t + 3, v00, v10 + 1, v00 + 1);
            t += 6;
        }
    }
    // The fold: a vertical quad at x = n joining the two layers.
    uint32_t b0 = 2 * n, b1 = 2 * n + 1, u0 = top + 2 * n, u1 = top + 2 * n + 1;
    set_tri(t, b0, u0, u1);
    set_tri(t + 3, b0, u1, b1);
    return 0;
}

uint32_t hairpin_twin(unsigned n, uint32_t v) {
    uint32_t top = 2 * (n + 1);
    return v < top ? v + top : v - top;
}

unsigned hairpin_column(unsigned n, uint32_t v) {
    uint32_t top = 2 * (n + 1);
    return (v < top ? v : v - top) / 2;
}

int scene_append(scene *a, const scene *b) {
    size_t V = a->vertex_count + b->vertex_count, F = a->triangle_count + b->triangle_count;
    double *p = realloc(a->positions, 3 * V * sizeof(double));
    if (p == NULL)
        return -1;
    a->positions = p;
    uint32_t *t = realloc(a->triangles, 3 * F * sizeof(uint32_t));
    if (t == NULL)
        return -1;
    a->triangles = t;
    memcpy(a->positions + 3 * a->vertex_count, b->positions, 3 * b->vertex_count * sizeof(double));
    for (size_t i = 0; i < 3 * b->triangle_count; ++i)
        a->triangles[3 * a->triangle_count + i] = b->triangles[i] + (uint32_t)a->vertex_count;
    a->vertex_count = V;
    a->triangle_count = F;
    return 0;
}

void scene_translate(scene *s, const double offset[3]) {
    for (size_t v = 0; v < s->vertex_count; ++v)
        for (int k = 0; k < 3; ++k)
            s->positions[3 * v + (size_t)k] += offset[k];
}

static unsigned next_random(unsigned *state) {
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static double unit_random(unsigned *state) {
    return (double)next_random(state) / (double)(1u << 24);
}

int scene_crumpled(scene *s, unsigned nx, unsigned ny, unsigned seed, double amplitude) {
    if (scene_grid(s, nx, ny, 1.0) != 0)
        return -1;
    // Sum of a few random plane waves per coordinate, wavelengths of a few
    // cells: smooth, but with amplitude several cells it folds and crosses.
    enum { WAVES = 6 };
    double k[3][WAVES][2], phase[3][WAVES];
    unsigned st = seed * 2654435761u + 1u;
    for (int c = 0; c < 3; ++c)
        for (int w = 0; w < WAVES; ++w) {
            double wavelength = 4.0 + 12.0 * unit_random(&st);
            double angle = 6.283185307179586 * unit_random(&st);
            k[c][w][0] = 6.283185307179586 / wavelength * cos(angle);
            k[c][w][1] = 6.283185307179586 / wavelength * sin(angle);
            phase[c][w] = 6.283185307179586 * unit_random(&st);
        }
    for (size_t v = 0; v < s->vertex_count; ++v) {
        double *p = s->positions + 3 * v;
        double x = p[0], y = p[1];
        for (int c = 0; c < 3; ++c) {
            double sum = 0.0;
            for (int w = 0; w < WAVES; ++w)
                sum += sin(k[c][w][0] * x + k[c][w][1] * y + phase[c][w]);
            p[c] += amplitude * sum / WAVES * (c == 2 ? 2.0 : 1.0);
        }
    }
    return 0;
}

int scene_shuffle(scene *s, unsigned seed, uint32_t **new_of_old) {
    unsigned st = seed + 17u;
    uint32_t *perm = malloc(s->vertex_count * sizeof(uint32_t));
    double *pos = malloc(3 * s->vertex_count * sizeof(double));
    if (perm == NULL || pos == NULL) {
        free(perm);
        free(pos);
        return -1;
    }
    for (size_t i = 0; i < s->vertex_count; ++i)
        perm[i] = (uint32_t)i;
    for (size_t i = s->vertex_count; i > 1; --i) {
        size_t j = next_random(&st) % i;
        uint32_t t = perm[i - 1];
        perm[i - 1] = perm[j];
        perm[j] = t;
    }
    for (size_t v = 0; v < s->vertex_count; ++v)
        memcpy(pos + 3 * (size_t)perm[v], s->positions + 3 * v, 3 * sizeof(double));
    free(s->positions);
    s->positions = pos;
    for (size_t i = 0; i < 3 * s->triangle_count; ++i)
        s->triangles[i] = perm[s->triangles[i]];
    for (size_t t = s->triangle_count; t > 1; --t) {
        size_t j = next_random(&st) % t;
        uint32_t tmp[3];
        memcpy(tmp, s->triangles + 3 * (t - 1), sizeof tmp);
        memcpy(s->triangles + 3 * (t - 1), s->triangles + 3 * j, sizeof tmp);
        memcpy(s->triangles + 3 * j, tmp, sizeof tmp);
    }
    for (size_t t = 0; t < s->triangle_count; ++t) {
        unsigned r = next_random(&st) % 3;
        uint32_t *tri = s->triangles + 3 * t;
        for (unsigned i = 0; i < r; ++i) {
            uint32_t x = tri[0];
            tri[0] = tri[1];
            tri[1] = tri[2];
            tri[2] = x;
        }
    }
    *new_of_old = perm;
    return 0;
}
