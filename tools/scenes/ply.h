// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A small PLY reader into a scene (ASCII, binary little and big endian; any
// scalar types; polygons fan-triangulated), for the tests' fixtures and the
// benchmark's real frames. selfcol-cli has its own, fuller reader
// (tools/cli/read_ply.c).
#ifndef SELFCOL_SCENES_PLY_H
#define SELFCOL_SCENES_PLY_H

#include "scenes.h"

// Returns 0 and fills s, or -1 with a message in err.
int ply_read(const char *path, scene *s, char *err, size_t err_size);

#endif
