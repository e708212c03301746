// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// Bullet 3.24's own soft-body self-collision, driven the way its deformable
// world drives it, behind a C interface so that the (C99) runner can time it
// next to selfcol on the same mesh in the same process. Implemented in
// bench_bullet.cpp; without Bullet (SELFCOL_BENCH_BULLET undefined) the
// runner simply emits no Bullet rows.
#ifndef SELFCOL_BENCH_BULLET_H
#define SELFCOL_BENCH_BULLET_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bench_bullet bench_bullet;

// Builds a btSoftBody from the nodes (appendLink per unique edge, appendFace
// per triangle) and its face tree (initializeFaceTree, O(F^2) in 3.24).
// build_seconds receives the face-tree build time alone; tree_bytes the heap
// the build kept (malloc accounting). Returns NULL on failure.
bench_bullet *bench_bullet_create(size_t vertex_count, const double *xyz, size_t triangle_count,
                                  const uint32_t *triangles, size_t edge_count,
                                  const uint32_t *edges, double *build_seconds, size_t *tree_bytes);

// Detection distance: Bullet's self-collision reports node-face pairs within
// 2 x the collision margin, so the margin is set to d / 2.
void bench_bullet_set_distance(bench_bullet *b, double d);

// Per-frame refit as its deformable solver does it: face normals, then the
// face trees padded by the margin. Returns seconds.
double bench_bullet_refit(bench_bullet *b);

// One self-collision call (defaultCollisionHandler(self) with VF_DD and
// self-collision on). Returns seconds; the contacts stay until the next call.
double bench_bullet_self_collide(bench_bullet *b);

// Contacts of the last call: raw count (Bullet reports a node-face pair once
// per face pair that sees it), and the unique pairs as (node << 32 | triangle)
// sorted ascending, triangle indices those of the input. *pairs is malloc'd
// (caller frees); returns the number of unique pairs, or (size_t)-1.
size_t bench_bullet_contacts(bench_bullet *b, size_t *raw_count, uint64_t **pairs);

void bench_bullet_destroy(bench_bullet *b);

// "3.24" style version string of the headers compiled against.
const char *bench_bullet_version(void);

#ifdef __cplusplus
}
#endif

#endif
