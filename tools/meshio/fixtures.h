// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Fixtures: generated test meshes (plain arrays of positions and triangles,
// turned into meshes by their users), the shapes the tests check and the
// benchmark times, and mesh files read into the same arrays. Part of the
// static library selfcol_meshio (meshio.h), which the tests and the tools
// link; it uses no selfcol API. (Not to be confused with selfcol_scene, the
// library's surfaces and colliders.)
#ifndef SELFCOL_FIXTURES_H
#define SELFCOL_FIXTURES_H

#include <stddef.h>
#include <stdint.h>

typedef struct fixture {
    size_t vertex_count;
    size_t triangle_count;
    double *positions;   // 3 per vertex
    uint32_t *triangles; // 3 per triangle
} fixture;

void fixture_free(fixture *s);

// Reads a mesh file (OBJ, PLY, OFF or STL: meshio_read) into s. Returns 0,
// or -1 with the reader's message ("file:line: what") in err.
int fixture_read(const char *path, fixture *s, char *err, size_t err_size);

// Flat nx x ny grid in the plane z = 0 with the given spacing; every cell is
// split along its (i, j)-(i+1, j+1) diagonal. Vertex (i, j) has index
// i * (ny + 1) + j. Returns 0, or -1 on allocation failure.
int fixture_grid(fixture *s, unsigned nx, unsigned ny, double spacing);

// A strip one cell wide and n cells long (unit cells), folded back over itself:
// bottom layer at z = 0, top layer at z = gap exactly above it, joined at
// x = n by a vertical fold. Bottom vertex (i, j) is 2 i + j, top vertex (i, j)
// is 2 (n + 1) + 2 i + j, for i = 0..n, j = 0..1.
int fixture_hairpin(fixture *s, unsigned n, double gap);

// Index of the vertex above/below v in fixture_hairpin (its twin), and v's i.
uint32_t fixture_hairpin_twin(unsigned n, uint32_t v);
unsigned fixture_hairpin_column(unsigned n, uint32_t v);

// An nx x ny unit-spaced grid crumpled by a random smooth displacement strong
// enough to fold it and make it cross itself (deterministic for a seed).
int fixture_crumpled(fixture *s, unsigned nx, unsigned ny, unsigned seed, double amplitude);

// Renumbers vertices by a random permutation and shuffles the triangle order
// and each triangle's rotation; new_of_old receives the vertex map (caller
// frees). The surface is unchanged.
int fixture_shuffle(fixture *s, unsigned seed, uint32_t **new_of_old);

// Appends scene b to scene a (b's indices shifted by a's vertex count).
int fixture_append(fixture *a, const fixture *b);

// Applies x -> x + offset to every vertex.
void fixture_translate(fixture *s, const double offset[3]);

// ---------------------------------------------------------------------------
// Scenes of the hierarchy accuracy tests (tests/test_hierarchy.c). All are
// deterministic, with edges of about unit length unless stated; vertex
// (i, j) of a grid-like scene has index i * (cols + 1) + j and every cell is
// split along its (i, j)-(i+1, j+1) diagonal, as in fixture_grid. Each returns
// 0, or -1 on allocation failure (the scene is then empty).

// An nx x ny unit grid gently wrinkled: z is amplitude times a normalised sum
// of six random plane waves of wavelengths 10 to 20 cells. The slope stays
// below amplitude * 2 pi / 10, so for amplitude <= 1 the sheet never folds
// and its normals stay within 32 degrees of +z.
int fixture_wrinkled(fixture *s, unsigned nx, unsigned ny, unsigned seed, double amplitude);

// A strip of unit cells, w cells wide (along y), folded twice into a Z: three
// layers n cells long at z = 0, gap and 2 gap, joined at x = n and x = 0 by
// half-circle folds of radius gap / 2 made of fold_segments cells each (1: a
// vertical wall). The middle layer is pushed down by dip * sin(pi x / n) (0
// at the folds): dip > gap makes it cross the bottom layer. Path vertex k,
// column j has index k * (w + 1) + j; the path has 3 n + 2 fold_segments cells.
int fixture_zfold(fixture *s, unsigned n, unsigned w, double gap, unsigned fold_segments,
                  double dip);

// A helicoidal ramp of two turns around a central hole: radii r_in .. r_in +
// nr (unit radial cells), na angular cells per turn. The first turn rises by
// pitch; the second lies gap(phi, r) above the first, where gap goes from
// pitch (at the junction, phi = 0 and 2 pi) down to about gmin (phi = pi) and
// back, gmin tilted by +-25 % across the radius so the crossing curve is not
// radial. With gmin < 0 the second turn dips through the first, and on both
// sides of that crossing it lies within any d of it. With pitch and |gmin|
// well below r_in every normal is near +z (a smooth patch touching itself).
// Vertex (k, i), k = 0..2 na angular, i = 0..nr radial, is k * (nr + 1) + i.
int fixture_ramp(fixture *s, unsigned nr, unsigned na, double r_in, double pitch, double gmin);

// A sheet w unit cells wide (along y) rolled around the y axis into an
// Archimedean spiral of `turns` turns, inner radius r0, about unit cells along
// the spiral. The radial gap between successive layers varies linearly across
// the width, from gap0 at y = 0 to gap1 at y = w: a small gap0 puts the layers
// within d of each other along one side, a negative gap0 makes them cross.
int fixture_rolled(fixture *s, unsigned w, double turns, double r0, double gap0, double gap1);

// An icosphere: the icosahedron with each triangle split into 4, subdivisions
// times, projected on the sphere of the given radius. Closed and consistently
// oriented (outward); 20 * 4^subdivisions triangles.
int fixture_icosphere(fixture *s, unsigned subdivisions, double radius);

// A UV sphere: two poles with triangle fans and rings - 1 rings of segments
// vertices; closed, outward. Near the poles, non-adjacent primitives of the
// fans are much closer than the mean edge length.
int fixture_uv_sphere(fixture *s, unsigned rings, unsigned segments, double radius);

// Two gently wrinkled n x n unit grids (fixture_wrinkled, amplitude 0.3, seeds
// seed and seed + 1): a in the plane z ~ 0; b turned by angle (radians) about
// the x axis through its middle row and moved so that its middle row lies at
// (x from n / 3 + 0.37, y = n / 2 + 0.21, z = offset). angle = 0 stacks b over
// a, offset apart; a steep angle makes b cross a. fixture_append(a, b) gives the
// two-component surface.
int fixture_sheet_pair(fixture *a, fixture *b, unsigned n, unsigned seed, double angle,
                       double offset);

// An nx x ny unit grid with a round hole: the triangles whose centroid lies
// within hole_radius of the centre are removed (their vertices are kept,
// unreferenced), then the sheet is displaced like fixture_crumpled with the
// given amplitude (0: flat).
int fixture_holed(fixture *s, unsigned nx, unsigned ny, double hole_radius, unsigned seed,
                  double amplitude);

// A Moebius band: nu cells around a circle of the given radius, nv cells
// across a width of 2 half_width, half_twists half-turns (odd: one-sided, the
// seam joins column j to column nv - j), then y scaled by squash: squash 1 is
// the round band, a small squash presses the two halves of the loop together
// until they touch and cross. Vertex (i, j), i = 0..nu - 1, is i (nv + 1) + j.
int fixture_moebius(fixture *s, unsigned nu, unsigned nv, double radius, double half_width,
                    unsigned half_twists, double squash);

// A cloth over a sphere centred at the origin: an n x n grid over [-half,
// half]^2 draped at height gap over the sphere's cap (and along its tangent
// cone beyond 0.8 of the radius), plus a ripple of the given amplitude:
// ripple > gap makes the cloth cross the sphere in places.
int fixture_draped_cloth(fixture *s, unsigned n, double half, double radius, double gap,
                         double ripple);

#endif
