// SPDX-FileCopyrightText: 2026 selfcol authors
// SPDX-License-Identifier: MIT

// selfcol_meshio's own pieces: the error formatter, progress reporting and
// the individual parsers (read_text.c, read_ply.c), which read.c dispatches
// to. Not for the library's users (they call meshio_parse or meshio_read).
#ifndef SELFCOL_MESHIO_INTERNAL_H
#define SELFCOL_MESHIO_INTERNAL_H

#include "meshio.h"

/** Calls progress->update when there is one. */
void meshio_report(const meshio_progress *progress, const char *label, double done, double total);

/* The individual parsers; same contract as meshio_parse. */
int meshio_parse_obj(const char *name, const char *text, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress);
int meshio_parse_off(const char *name, const char *text, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress);
int meshio_parse_stl(const char *name, const unsigned char *data, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress);
int meshio_parse_ply(const char *name, const unsigned char *data, size_t size, meshio_mesh *mesh,
                     meshio_error *err, const meshio_progress *progress);

#endif /* SELFCOL_MESHIO_INTERNAL_H */
