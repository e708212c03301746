# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Mesh files for selfcol: OBJ, PLY (ASCII, binary little- and big-endian),
OFF and STL (ASCII, binary), read by selfcol-cli's own readers
(tools/meshio, built into the extension: bounds-checked, fuzzed, and with
the same messages); other formats through meshio when it is installed.
Polygons are fan-triangulated ((p0 p1 p2), (p0 p2 p3), ...) and, with
``weld_vertices=True`` (the default, as selfcol-cli does), vertices at
exactly equal coordinates are welded: the lowest file index of each group
stands for the group in F, the other copies stay in V unreferenced. So
indices in results are the file's, the same as selfcol-cli's JSON output.
"""

from __future__ import annotations

import os
from typing import Tuple

import numpy as np

from ._selfcol_cffi import ffi, lib

__all__ = ["read_mesh", "read_obj", "read_ply", "weld"]


def weld(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """F with each vertex replaced by the lowest index of the vertices at
    exactly its coordinates (-0 equals +0): selfcol-cli's weld."""
    P = np.ascontiguousarray(V, dtype=np.float64)
    rep = np.empty(P.shape[0], dtype=np.uint32)
    if P.shape[0]:
        merged = lib.meshio_weld(ffi.cast("double *", P.ctypes.data), P.shape[0],
                                 ffi.cast("uint32_t *", rep.ctypes.data))
        if merged == ffi.cast("size_t", -1):
            raise MemoryError("weld: out of memory")
    out: np.ndarray = rep[F].astype(F.dtype, copy=False)
    return out


def _read_c(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) as the file has them, through tools/meshio; ValueError with
    its message (file, line, fault) when it refuses the file."""
    mesh = ffi.new("meshio_mesh *")
    err = ffi.new("meshio_error *")
    if lib.meshio_read(os.fsencode(path), mesh, err, ffi.NULL) != 0:
        raise ValueError(ffi.string(err.message).decode("utf-8", "replace"))
    try:
        nv, nt = int(mesh.vertex_count), int(mesh.triangle_count)
        V = np.frombuffer(ffi.buffer(mesh.positions, 24 * nv), dtype=np.float64).reshape(nv, 3)
        F = np.frombuffer(ffi.buffer(mesh.triangles, 12 * nt), dtype=np.uint32).reshape(nt, 3)
        return V.copy(), F.astype(np.int64)
    finally:
        lib.meshio_mesh_free(mesh)


def read_obj(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of a Wavefront OBJ file, not welded."""
    return _read_c(path)


def read_ply(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of a PLY file (ASCII or binary, either endianness), not welded."""
    return _read_c(path)


def read_mesh(path: str, weld_vertices: bool = True) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of an OBJ, PLY, OFF or STL file (selfcol-cli's readers); other
    extensions through meshio when installed. ``weld_vertices``: see the
    module doc."""
    if not os.path.exists(path):
        raise FileNotFoundError("%s: no such file" % path)
    if os.path.isdir(path):
        raise IsADirectoryError("%s: a directory, not a mesh file" % path)
    ext = os.path.splitext(path)[1].lower()
    if ext in (".obj", ".ply", ".off", ".stl"):
        V, F = _read_c(path)
    else:
        try:
            import meshio
        except ImportError:
            raise ValueError("%s: only .obj, .ply, .off and .stl are read without meshio"
                             % path) from None
        try:
            m = meshio.read(path)
        except Exception as exc:  # meshio raises its own types; name the file
            raise ValueError("%s: meshio cannot read it: %s" % (path, exc)) from None
        V = np.asarray(m.points, dtype=np.float64)[:, :3]
        blocks = [np.asarray(c.data) for c in m.cells if c.type == "triangle"]
        F = np.concatenate(blocks) if blocks else np.zeros((0, 3), dtype=np.int64)
        bad = np.nonzero((F < 0) | (F >= V.shape[0]))
        if bad[0].size:
            t, c = int(bad[0][0]), int(bad[1][0])
            raise ValueError("%s: triangle %d names vertex %d, which is not in the file "
                             "(%d vertices)" % (path, t, int(F[t, c]), V.shape[0]))
    if F.shape[0] == 0:
        raise ValueError("%s: no triangles (%d vertices): not a mesh, or an empty one"
                         % (path, V.shape[0]))
    if weld_vertices and V.shape[0]:
        F = weld(V, F)
    return V, F
