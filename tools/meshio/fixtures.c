// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

#include "fixtures.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "meshio.h"

void fixture_free(fixture *s) {
    free(s->positions);
    free(s->triangles);
    memset(s, 0, sizeof *s);
}

int fixture_read(const char *path, fixture *s, char *err, size_t err_size) {
    memset(s, 0, sizeof *s);
    meshio_mesh mesh;
    meshio_error error;
    if (meshio_read(path, &mesh, &error, NULL) != 0) {
        snprintf(err, err_size, "%s", error.message);
        return -1;
    }
    s->vertex_count = mesh.vertex_count;
    s->triangle_count = mesh.triangle_count;
    s->positions = mesh.positions;
    s->triangles = mesh.triangles;
    return 0;
}

static int fixture_alloc(fixture *s, size_t vertices, size_t triangles) {
    s->vertex_count = vertices;
    s->triangle_count = triangles;
    s->positions = calloc(3 * vertices, sizeof(double));
    s->triangles = calloc(3 * triangles, sizeof(uint32_t));
    if (s->positions == NULL || s->triangles == NULL) {
        fixture_free(s);
        return -1;
    }
    return 0;
}

static void set_tri(uint32_t *t, uint32_t a, uint32_t b, uint32_t c) {
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

int fixture_grid(fixture *s, unsigned nx, unsigned ny, double spacing) {
    if (fixture_alloc(s, (size_t)(nx + 1) * (ny + 1), (size_t)2 * nx * ny) != 0)
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

int fixture_hairpin(fixture *s, unsigned n, double gap) {
    if (fixture_alloc(s, (size_t)4 * (n + 1), (size_t)4 * n + 2) != 0)
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

uint32_t fixture_hairpin_twin(unsigned n, uint32_t v) {
    uint32_t top = 2 * (n + 1);
    return v < top ? v + top : v - top;
}

unsigned fixture_hairpin_column(unsigned n, uint32_t v) {
    uint32_t top = 2 * (n + 1);
    return (v < top ? v : v - top) / 2;
}

int fixture_append(fixture *a, const fixture *b) {
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

void fixture_translate(fixture *s, const double offset[3]) {
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

int fixture_crumpled(fixture *s, unsigned nx, unsigned ny, unsigned seed, double amplitude) {
    if (fixture_grid(s, nx, ny, 1.0) != 0)
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

int fixture_shuffle(fixture *s, unsigned seed, uint32_t **new_of_old) {
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

// ---------------------------------------------------------------------------
// Scenes of the hierarchy accuracy tests.

#define SCENE_PI 3.14159265358979323846

// Allocates an (nu + 1) x (nv + 1) vertex grid's arrays and fills its
// triangles (the pattern of fixture_grid); positions are left to the caller.
static int grid_alloc(fixture *s, unsigned nu, unsigned nv) {
    if (fixture_alloc(s, (size_t)(nu + 1) * (nv + 1), (size_t)2 * nu * nv) != 0)
        return -1;
    uint32_t *t = s->triangles;
    for (unsigned i = 0; i < nu; ++i)
        for (unsigned j = 0; j < nv; ++j) {
            uint32_t v00 = i * (nv + 1) + j, v10 = (i + 1) * (nv + 1) + j;
            set_tri(t, v00, v10, v10 + 1);
            set_tri(t + 3, v00, v10 + 1, v00 + 1);
            t += 6;
        }
    return 0;
}

static void set_point(fixture *s, size_t v, double x, double y, double z) {
    double *p = s->positions + 3 * v;
    p[0] = x;
    p[1] = y;
    p[2] = z;
}

// Six random plane waves per coordinate, wavelengths wl_min .. wl_min + wl_span.
enum { SCENE_WAVES = 6 };
typedef struct waves {
    double k[3][SCENE_WAVES][2];
    double phase[3][SCENE_WAVES];
} waves;

static void waves_init(waves *w, unsigned seed, double wl_min, double wl_span) {
    unsigned st = seed * 2246822519u + 7u;
    memset(w, 0, sizeof *w);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < SCENE_WAVES; ++i) {
            double wavelength = wl_min + wl_span * unit_random(&st);
            double angle = 2.0 * SCENE_PI * unit_random(&st);
            w->k[c][i][0] = 2.0 * SCENE_PI / wavelength * cos(angle);
            w->k[c][i][1] = 2.0 * SCENE_PI / wavelength * sin(angle);
            w->phase[c][i] = 2.0 * SCENE_PI * unit_random(&st);
        }
}

// Mean of coordinate c's waves at (x, y): in [-1, 1], gradient below max |k|.
static double waves_eval(const waves *w, int c, double x, double y) {
    double sum = 0.0;
    for (int i = 0; i < SCENE_WAVES; ++i)
        sum += sin(w->k[c][i][0] * x + w->k[c][i][1] * y + w->phase[c][i]);
    return sum / SCENE_WAVES;
}

int fixture_wrinkled(fixture *s, unsigned nx, unsigned ny, unsigned seed, double amplitude) {
    if (fixture_grid(s, nx, ny, 1.0) != 0)
        return -1;
    waves w;
    waves_init(&w, seed, 10.0, 10.0);
    for (size_t v = 0; v < s->vertex_count; ++v) {
        double *p = s->positions + 3 * v;
        p[2] = amplitude * waves_eval(&w, 2, p[0], p[1]);
    }
    return 0;
}

int fixture_zfold(fixture *s, unsigned n, unsigned w, double gap, unsigned fold_segments,
                  double dip) {
    const unsigned fs = fold_segments > 0 ? fold_segments : 1;
    const unsigned cells = 3 * n + 2 * fs;
    if (grid_alloc(s, cells, w) != 0)
        return -1;
    const double r = 0.5 * gap;
    for (unsigned k = 0; k <= cells; ++k) {
        double x, z;
        if (k <= n) { // bottom layer, x = 0 .. n
            x = k;
            z = 0.0;
        } else if (k < n + fs) { // first fold, around (n, gap / 2), bulging to +x
            double a = -0.5 * SCENE_PI + SCENE_PI * (k - n) / fs;
            x = n + r * cos(a);
            z = r + r * sin(a);
        } else if (k <= 2 * n + fs) { // middle layer, x = n .. 0
            x = (double)n - (double)(k - n - fs);
            z = gap - dip * sin(SCENE_PI * x / n);
        } else if (k < 2 * n + 2 * fs) { // second fold, around (0, 3 gap / 2), bulging to -x
            double a = -0.5 * SCENE_PI - SCENE_PI * (k - 2 * n - fs) / fs;
            x = r * cos(a);
            z = 3.0 * r + r * sin(a);
        } else { // top layer, x = 0 .. n
            x = (double)(k - 2 * n - 2 * fs);
            z = 2.0 * gap;
        }
        for (unsigned j = 0; j <= w; ++j)
            set_point(s, (size_t)k * (w + 1) + j, x, j, z);
    }
    return 0;
}

int fixture_ramp(fixture *s, unsigned nr, unsigned na, double r_in, double pitch, double gmin) {
    if (grid_alloc(s, 2 * na, nr) != 0)
        return -1;
    for (unsigned k = 0; k <= 2 * na; ++k) {
        double theta = 2.0 * SCENE_PI * k / na;
        for (unsigned i = 0; i <= nr; ++i) {
            double r = r_in + i, z;
            if (k <= na) {
                z = pitch * k / na;
            } else {
                double phi = theta - 2.0 * SCENE_PI;
                double gm = gmin * (1.0 + 0.5 * ((double)i - 0.5 * nr) / nr);
                z = pitch * (double)(k - na) / na + gm + (pitch - gm) * 0.5 * (1.0 + cos(phi));
            }
            set_point(s, (size_t)k * (nr + 1) + i, r * cos(theta), r * sin(theta), z);
        }
    }
    return 0;
}

int fixture_rolled(fixture *s, unsigned w, double turns, double r0, double gap0, double gap1) {
    const double span = 2.0 * SCENE_PI * turns;
    const double r_mean = r0 + 0.25 * (gap0 + gap1) * turns;
    unsigned k_max = (unsigned)ceil(span * r_mean);
    k_max = k_max < 3 ? 3 : k_max;
    const unsigned width = w > 0 ? w : 1;
    if (grid_alloc(s, k_max, width) != 0)
        return -1;
    for (unsigned k = 0; k <= k_max; ++k) {
        double theta = span * k / k_max;
        for (unsigned j = 0; j <= width; ++j) {
            double gap = gap0 + (gap1 - gap0) * j / width;
            double r = r0 + gap * theta / (2.0 * SCENE_PI);
            set_point(s, (size_t)k * (width + 1) + j, r * cos(theta), j, r * sin(theta));
        }
    }
    return 0;
}

// Midpoint cache of the icosphere: open addressing on the (min, max) pair.
typedef struct midpoint_table {
    uint64_t *keys; // 0: empty slot (keys are stored + 1)
    uint32_t *values;
    size_t mask;
} midpoint_table;

static uint32_t midpoint(fixture *s, midpoint_table *tab, uint32_t a, uint32_t b, double radius) {
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t key = (((uint64_t)lo << 32) | hi) + 1u;
    size_t slot = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & tab->mask;
    while (tab->keys[slot] != 0 && tab->keys[slot] != key)
        slot = (slot + 1) & tab->mask;
    if (tab->keys[slot] == key)
        return tab->values[slot];
    uint32_t v = (uint32_t)s->vertex_count++;
    double m[3], len = 0.0;
    for (int k = 0; k < 3; ++k) {
        m[k] = 0.5 * (s->positions[3 * (size_t)a + k] + s->positions[3 * (size_t)b + k]);
        len += m[k] * m[k];
    }
    len = sqrt(len);
    set_point(s, v, radius * m[0] / len, radius * m[1] / len, radius * m[2] / len);
    tab->keys[slot] = key;
    tab->values[slot] = v;
    return v;
}

int fixture_icosphere(fixture *s, unsigned subdivisions, double radius) {
    static const uint32_t faces[20][3] = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    const double t = 0.5 * (1.0 + sqrt(5.0));
    const double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    size_t F = 20, V = 12;
    for (unsigned i = 0; i < subdivisions; ++i) {
        V += F * 3 / 2; // one new vertex per edge
        F *= 4;
    }
    if (fixture_alloc(s, V, F) != 0)
        return -1;
    uint32_t *next = malloc(3 * F * sizeof(uint32_t));
    size_t slots = 1;
    while (slots < 4 * V)
        slots *= 2;
    midpoint_table tab = {calloc(slots, sizeof(uint64_t)), malloc(slots * sizeof(uint32_t)),
                          slots - 1};
    if (next == NULL || tab.keys == NULL || tab.values == NULL) {
        free(next);
        free(tab.keys);
        free(tab.values);
        fixture_free(s);
        return -1;
    }
    for (uint32_t v = 0; v < 12; ++v) {
        const double *b = base[v];
        double len = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        set_point(s, v, radius * b[0] / len, radius * b[1] / len, radius * b[2] / len);
    }
    memcpy(s->triangles, faces, sizeof faces);
    s->vertex_count = 12;
    size_t count = 20;
    for (unsigned i = 0; i < subdivisions; ++i) {
        for (size_t f = 0; f < count; ++f) {
            const uint32_t *tri = s->triangles + 3 * f;
            uint32_t ab = midpoint(s, &tab, tri[0], tri[1], radius);
            uint32_t bc = midpoint(s, &tab, tri[1], tri[2], radius);
            uint32_t ca = midpoint(s, &tab, tri[2], tri[0], radius);
            set_tri(next + 12 * f, tri[0], ab, ca);
            set_tri(next + 12 * f + 3, ab, tri[1], bc);
            set_tri(next + 12 * f + 6, ca, bc, tri[2]);
            set_tri(next + 12 * f + 9, ab, bc, ca);
        }
        count *= 4;
        memcpy(s->triangles, next, 3 * count * sizeof(uint32_t));
    }
    free(next);
    free(tab.keys);
    free(tab.values);
    return 0;
}

int fixture_uv_sphere(fixture *s, unsigned rings, unsigned segments, double radius) {
    rings = rings < 2 ? 2 : rings;
    segments = segments < 3 ? 3 : segments;
    const size_t ring_vertices = (size_t)(rings - 1) * segments;
    if (fixture_alloc(s, ring_vertices + 2, (size_t)2 * segments * (rings - 1)) != 0)
        return -1;
    const uint32_t north = 0, south = (uint32_t)ring_vertices + 1;
    set_point(s, north, 0.0, 0.0, radius);
    set_point(s, south, 0.0, 0.0, -radius);
    for (unsigned r = 1; r < rings; ++r) {
        double polar = SCENE_PI * r / rings;
        for (unsigned k = 0; k < segments; ++k) {
            double azimuth = 2.0 * SCENE_PI * k / segments;
            set_point(s, 1 + (size_t)(r - 1) * segments + k, radius * sin(polar) * cos(azimuth),
                      radius * sin(polar) * sin(azimuth), radius * cos(polar));
        }
    }
    uint32_t *t = s->triangles;
    for (unsigned k = 0; k < segments; ++k) {
        uint32_t k1 = (k + 1) % segments;
        set_tri(t, north, 1 + k, 1 + k1);
        t += 3;
        for (unsigned r = 1; r + 1 < rings; ++r) {
            uint32_t a = 1 + (r - 1) * segments + k, b = 1 + (r - 1) * segments + k1;
            uint32_t d = a + segments, c = b + segments;
            set_tri(t, a, d, c);
            set_tri(t + 3, a, c, b);
            t += 6;
        }
        uint32_t last = 1 + (rings - 2) * segments;
        set_tri(t, south, last + k1, last + k);
        t += 3;
    }
    return 0;
}

int fixture_sheet_pair(fixture *a, fixture *b, unsigned n, unsigned seed, double angle,
                       double offset) {
    if (fixture_wrinkled(a, n, n, seed, 0.3) != 0)
        return -1;
    if (fixture_wrinkled(b, n, n, seed + 1, 0.3) != 0) {
        fixture_free(a);
        return -1;
    }
    const double c = cos(angle), sn = sin(angle), half = 0.5 * n;
    for (size_t v = 0; v < b->vertex_count; ++v) {
        double *p = b->positions + 3 * v;
        double y0 = p[1] - half, w = p[2];
        set_point(b, v, p[0] + n / 3.0 + 0.37, half + 0.21 + y0 * c - w * sn,
                  offset + y0 * sn + w * c);
    }
    return 0;
}

int fixture_holed(fixture *s, unsigned nx, unsigned ny, double hole_radius, unsigned seed,
                  double amplitude) {
    if (fixture_grid(s, nx, ny, 1.0) != 0)
        return -1;
    const double cx = 0.5 * nx, cy = 0.5 * ny;
    size_t kept = 0;
    for (size_t f = 0; f < s->triangle_count; ++f) {
        const uint32_t *tri = s->triangles + 3 * f;
        double x = 0.0, y = 0.0;
        for (int i = 0; i < 3; ++i) {
            x += s->positions[3 * (size_t)tri[i]] / 3.0;
            y += s->positions[3 * (size_t)tri[i] + 1] / 3.0;
        }
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < hole_radius * hole_radius)
            continue;
        memmove(s->triangles + 3 * kept, tri, 3 * sizeof(uint32_t));
        kept++;
    }
    s->triangle_count = kept;
    waves w;
    waves_init(&w, seed + 1000u, 4.0, 12.0);
    for (size_t v = 0; v < s->vertex_count; ++v) {
        double *p = s->positions + 3 * v;
        double x = p[0], y = p[1];
        for (int c = 0; c < 3; ++c)
            p[c] += amplitude * waves_eval(&w, c, x, y) * (c == 2 ? 2.0 : 1.0);
    }
    return 0;
}

int fixture_moebius(fixture *s, unsigned nu, unsigned nv, double radius, double half_width,
                    unsigned half_twists, double squash) {
    nu = nu < 3 ? 3 : nu;
    nv = nv < 1 ? 1 : nv;
    if (fixture_alloc(s, (size_t)nu * (nv + 1), (size_t)2 * nu * nv) != 0)
        return -1;
    for (unsigned i = 0; i < nu; ++i) {
        double u = 2.0 * SCENE_PI * i / nu;
        double c = cos(0.5 * half_twists * u), sn = sin(0.5 * half_twists * u);
        for (unsigned j = 0; j <= nv; ++j) {
            double v = -half_width + 2.0 * half_width * j / nv;
            set_point(s, (size_t)i * (nv + 1) + j, (radius + v * c) * cos(u),
                      squash * (radius + v * c) * sin(u), v * sn);
        }
    }
    const int flip = half_twists % 2 == 1;
    uint32_t *t = s->triangles;
    for (unsigned i = 0; i < nu; ++i) {
        unsigned i1 = (i + 1) % nu;
        for (unsigned j = 0; j < nv; ++j) {
            uint32_t v00 = i * (nv + 1) + j, v01 = v00 + 1, v10, v11;
            if (i1 == 0 && flip) {
                v10 = nv - j;
                v11 = nv - j - 1;
            } else {
                v10 = i1 * (nv + 1) + j;
                v11 = v10 + 1;
            }
            set_tri(t, v00, v10, v11);
            set_tri(t + 3, v00, v11, v01);
            t += 6;
        }
    }
    return 0;
}

int fixture_draped_cloth(fixture *s, unsigned n, double half, double radius, double gap,
                         double ripple) {
    if (grid_alloc(s, n, n) != 0)
        return -1;
    const double rc = radius + gap, r1 = 0.8 * rc, h1 = sqrt(rc * rc - r1 * r1);
    for (unsigned i = 0; i <= n; ++i)
        for (unsigned j = 0; j <= n; ++j) {
            double x = -half + 2.0 * half * i / n, y = -half + 2.0 * half * j / n;
            double r = sqrt(x * x + y * y);
            double z = r < r1 ? sqrt(rc * rc - r * r) : h1 - (r - r1) * r1 / h1;
            z += ripple * sin(2.3 * x + 0.4) * sin(1.9 * y + 1.1);
            set_point(s, (size_t)i * (n + 1) + j, x, y, z);
        }
    return 0;
}
