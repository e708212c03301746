# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Small mesh readers with no dependency beyond numpy: OBJ and PLY (ASCII,
binary little- and big-endian). Other formats go through meshio when it is
installed. Polygons are fan-triangulated ((p0 p1 p2), (p0 p2 p3), ...) and,
with ``weld=True`` (the default, as selfcol-cli does), vertices at exactly
equal coordinates are welded: the lowest file index of each group stands
for the group in F, the other copies stay in V unreferenced. So indices in
results are the file's, the same as selfcol-cli's JSON output.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Tuple

import numpy as np

__all__ = ["read_mesh", "read_obj", "read_ply", "weld"]


def weld(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """F with each vertex replaced by the lowest index of the vertices at
    exactly its coordinates (-0 equals +0)."""
    key = np.ascontiguousarray(V, dtype=np.float64) + 0.0  # -0.0 + 0.0 == +0.0
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    rep = first[inverse.reshape(-1)]
    out: np.ndarray = rep[F].astype(F.dtype, copy=False)
    return out


def _fan(polys: List[List[int]]) -> np.ndarray:
    tris: List[Tuple[int, int, int]] = []
    for p in polys:
        for i in range(1, len(p) - 1):
            tris.append((p[0], p[i], p[i + 1]))
    return np.array(tris, dtype=np.int64).reshape(-1, 3)


def read_obj(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of a Wavefront OBJ file (v and f lines; negative indices honoured)."""
    verts: List[List[float]] = []
    polys: List[List[int]] = []
    with open(path, "r", encoding="utf-8", errors="replace") as fh:
        for number, line in enumerate(fh, 1):
            parts = line.split()
            if not parts:
                continue
            where = "%s:%d" % (path, number)
            if parts[0] == "v":
                if len(parts) < 4:
                    raise ValueError("%s: a vertex line with fewer than 3 coordinates" % where)
                try:
                    verts.append([float(parts[1]), float(parts[2]), float(parts[3])])
                except ValueError:
                    raise ValueError("%s: a vertex coordinate is not a number: %r"
                                     % (where, line.strip())) from None
            elif parts[0] == "f":
                idx = []
                for tok in parts[1:]:
                    try:
                        i = int(tok.split("/")[0])
                    except ValueError:
                        raise ValueError("%s: a face index is not an integer: %r"
                                         % (where, tok)) from None
                    if i == 0:
                        raise ValueError("%s: face index 0 (OBJ indices start at 1)" % where)
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                if len(idx) < 3:
                    raise ValueError("%s: a face with fewer than 3 vertices" % where)
                polys.append(idx)
    return np.array(verts, dtype=np.float64).reshape(-1, 3), _fan(polys)


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2",
              "int16": "i2", "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4",
              "uint": "u4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
              "float64": "f8"}


class _Truncated(Exception):
    """Raised inside the PLY body readers; read_ply names the file and element."""


def read_ply(path: str) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of a PLY file: ascii, binary_little_endian or binary_big_endian;
    the vertex element's x, y, z and the face element's vertex index list.
    A malformed or truncated file raises ValueError naming the file, the
    element and what is wrong."""
    with open(path, "rb") as fh:
        data = fh.read()
    state: Dict[str, Any] = {"element": None}
    try:
        return _read_ply(path, data, state)
    except _Truncated as exc:
        raise ValueError("%s: truncated PLY: %s" % (path, exc)) from None
    except (ValueError, KeyError, IndexError, TypeError) as exc:
        el = state["element"]
        where = " (element %r)" % el if el else ""
        raise ValueError("%s: malformed PLY%s: %s" % (path, where, exc)) from None


def _take(body: bytes, off: int, size: int, what: str) -> None:
    if off + size > len(body):
        raise _Truncated("%s needs %d bytes at byte %d of the body, which has %d"
                         % (what, size, off, len(body)))


def _read_ply(path: str, data: bytes, state: Dict[str, Any]) -> Tuple[np.ndarray, np.ndarray]:
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError("%s: not a PLY file" % path)
    nl = data.find(b"\n", end)
    body = data[nl + 1:]
    fmt = ""
    elements: List[Dict[str, Any]] = []
    for line in data[:end].decode("ascii", "replace").splitlines():
        p = line.split()
        if not p:
            continue
        if p[0] == "format":
            fmt = p[1]
        elif p[0] == "element":
            if len(p) < 3 or not p[2].isdigit():
                raise ValueError("header line %r: an element needs a name and a count" % line)
            elements.append({"name": p[1], "count": int(p[2]), "props": []})
        elif p[0] == "property" and elements:
            types = p[2:4] if p[1] == "list" else p[1:2]
            for t in types:
                if t not in _PLY_TYPES:
                    raise ValueError("header line %r: unknown property type %r" % (line, t))
            if p[1] == "list":
                elements[-1]["props"].append((p[4], "list", _PLY_TYPES[p[2]], _PLY_TYPES[p[3]]))
            else:
                elements[-1]["props"].append((p[2], _PLY_TYPES[p[1]]))
    V = np.zeros((0, 3))
    F = np.zeros((0, 3), dtype=np.int64)
    if fmt == "ascii":
        tokens = body.split()
        pos = 0
        for el in elements:
            state["element"] = el["name"]
            rows = []
            for r in range(el["count"]):
                row: List[Any] = []
                for prop in el["props"]:
                    if prop[1] == "list":
                        n = int(tokens[pos]) if pos < len(tokens) else 0
                        if pos + 1 + n > len(tokens):
                            raise _Truncated("element %r ends in row %d of %d"
                                             % (el["name"], r + 1, el["count"]))
                        row.append([int(t) for t in tokens[pos + 1:pos + 1 + n]])
                        pos += 1 + n
                    else:
                        if pos >= len(tokens):
                            raise _Truncated("element %r ends in row %d of %d"
                                             % (el["name"], r + 1, el["count"]))
                        row.append(float(tokens[pos]))
                        pos += 1
                rows.append(row)
            V, F = _ply_element(el, rows, V, F)
        return V, F
    if fmt not in ("binary_little_endian", "binary_big_endian"):
        raise ValueError("%s: unknown PLY format %r" % (path, fmt))
    bo = "<" if fmt == "binary_little_endian" else ">"
    off = 0
    for el in elements:
        state["element"] = el["name"]
        props = el["props"]
        if all(p[1] != "list" for p in props):
            dt = np.dtype([(p[0], bo + p[1]) for p in props])
            _take(body, off, dt.itemsize * el["count"],
                  "element %r (%d rows of %d bytes)" % (el["name"], el["count"], dt.itemsize))
            arr = np.frombuffer(body, dtype=dt, count=el["count"], offset=off)
            off += dt.itemsize * el["count"]
            if el["name"] == "vertex":
                V = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
            continue
        # a list element: fast path for one list of triangles, else a loop
        if len(props) == 1 and el["count"]:
            _, _, ct, it = props[0]
            dt = np.dtype([("n", bo + ct), ("i", bo + it, (3,))])
            if off + dt.itemsize * el["count"] <= len(body):
                arr = np.frombuffer(body, dtype=dt, count=el["count"], offset=off)
                if np.all(arr["n"] == 3):
                    off += dt.itemsize * el["count"]
                    if el["name"] == "face":
                        F = arr["i"].astype(np.int64)
                    continue
        rows = []
        for r in range(el["count"]):
            row = []
            what = "row %d of %d of element %r" % (r + 1, el["count"], el["name"])
            for prop in props:
                if prop[1] == "list":
                    ct, it = np.dtype(bo + prop[2]), np.dtype(bo + prop[3])
                    _take(body, off, ct.itemsize, what)
                    n = int(np.frombuffer(body, dtype=ct, count=1, offset=off)[0])
                    off += ct.itemsize
                    _take(body, off, it.itemsize * n, what)
                    row.append(np.frombuffer(body, dtype=it, count=n, offset=off).tolist())
                    off += it.itemsize * n
                else:
                    t = np.dtype(bo + prop[1])
                    _take(body, off, t.itemsize, what)
                    row.append(float(np.frombuffer(body, dtype=t, count=1, offset=off)[0]))
                    off += t.itemsize
            rows.append(row)
        V, F = _ply_element(el, rows, V, F)
    return V, F


def _ply_element(el: Dict[str, Any], rows: List[List[Any]], V: np.ndarray,
                 F: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    names = [p[0] for p in el["props"]]
    if el["name"] == "vertex":
        missing = [c for c in "xyz" if c not in names]
        if missing:
            raise ValueError("the vertex element has no property %s" % ", ".join(missing))
        ix, iy, iz = names.index("x"), names.index("y"), names.index("z")
        V = np.array([[r[ix], r[iy], r[iz]] for r in rows], dtype=np.float64).reshape(-1, 3)
    elif el["name"] == "face":
        li = [i for i, p in enumerate(el["props"]) if p[1] == "list"][0]
        F = _fan([r[li] for r in rows])
    return V, F


def read_mesh(path: str, weld_vertices: bool = True) -> Tuple[np.ndarray, np.ndarray]:
    """(V, F) of an OBJ or PLY file (pure Python + numpy); other extensions
    through meshio when installed. ``weld_vertices``: see the module doc."""
    if not os.path.exists(path):
        raise FileNotFoundError("%s: no such file" % path)
    if os.path.isdir(path):
        raise IsADirectoryError("%s: a directory, not a mesh file" % path)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        V, F = read_obj(path)
    elif ext == ".ply":
        V, F = read_ply(path)
    else:
        try:
            import meshio
        except ImportError:
            raise ValueError("%s: only .obj and .ply are read without meshio" % path) from None
        try:
            m = meshio.read(path)
        except Exception as exc:  # meshio raises its own types; name the file
            raise ValueError("%s: meshio cannot read it: %s" % (path, exc)) from None
        V = np.asarray(m.points, dtype=np.float64)[:, :3]
        blocks = [np.asarray(c.data) for c in m.cells if c.type == "triangle"]
        F = np.concatenate(blocks) if blocks else np.zeros((0, 3), dtype=np.int64)
    if F.shape[0] == 0:
        raise ValueError("%s: no triangles (%d vertices): not a mesh, or an empty one"
                         % (path, V.shape[0]))
    bad = np.nonzero((F < 0) | (F >= V.shape[0]))
    if bad[0].size:
        t, c = int(bad[0][0]), int(bad[1][0])
        raise ValueError("%s: triangle %d names vertex %d, which is not in the file (%d vertices)"
                         % (path, t, int(F[t, c]), V.shape[0]))
    if weld_vertices and V.shape[0]:
        F = weld(V, F)
    return V, F
