// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Generated test scenes (plain arrays; the tests turn them into meshes).
#ifndef SELFCOL_TEST_SCENES_H
#define SELFCOL_TEST_SCENES_H

#include <stddef.h>
#include <stdint.h>

typedef struct scene {
    size_t vertex_count;
    size_t triangle_count;
    double *positions;   // 3 per vertex
    uint32_t *triangles; // 3 per triangle
} scene;

void scene_free(scene *s);

// Flat nx x ny grid in the plane z = 0 with the given spacing; every cell is
// split along its (i, j)-(i+1, j+1) diagonal. Vertex (i, j) has index
// i * (ny + 1) + j. Returns 0, or -1 on allocation failure.
int scene_grid(scene *s, unsigned nx, unsigned ny, double spacing);

// A strip one cell wide and n cells long (unit cells), folded back over itself:
// bottom layer at z = 0, top layer at z = gap exactly above it, joined at
// x = n by a vertical fold. Bottom vertex (i, j) is 2 i + j, top vertex (i, j)
// is 2 (n + 1) + 2 i + j, for i = 0..n, j = 0..1.
int scene_hairpin(scene *s, unsigned n, double gap);

// Index of the vertex above/below v in scene_hairpin (its twin), and v's i.
uint32_t hairpin_twin(unsigned n, uint32_t v);
unsigned hairpin_column(unsigned n, uint32_t v);

// An nx x ny unit-spaced grid crumpled by a random smooth displacement strong
// enough to fold it and make it cross itself (deterministic for a seed).
int scene_crumpled(scene *s, unsigned nx, unsigned ny, unsigned seed, double amplitude);

// Renumbers vertices by a random permutation and shuffles the triangle order
// and each triangle's rotation; new_of_old receives the vertex map (caller
// frees). The surface is unchanged.
int scene_shuffle(scene *s, unsigned seed, uint32_t **new_of_old);

// Appends scene b to scene a (b's indices shifted by a's vertex count).
int scene_append(scene *a, const scene *b);

// Applies x -> x + offset to every vertex.
void scene_translate(scene *s, const double offset[3]);

#endif
