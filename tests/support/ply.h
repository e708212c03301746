// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// A small PLY reader for test fixtures (ASCII, binary little and big endian;
// any scalar types; polygons fan-triangulated). The CLI issue brings the
// production reader; this one only feeds tests.
#ifndef SELFCOL_TEST_PLY_H
#define SELFCOL_TEST_PLY_H

#include "scenes.h"

// Returns 0 and fills s, or -1 with a message in err.
int ply_read(const char *path, scene *s, char *err, size_t err_size);

#endif
