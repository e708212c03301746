# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The binding proper: errors, array conversion, the handles and the queries.

Every call into C goes through cffi, which releases the GIL for its
duration: refits, queries, sweeps and store updates of different Python
threads run side by side. The handles follow the C API's thread-safety
rules (include/selfcol/*.h): concurrent queries on one hierarchy are fine;
a handle being modified (set_positions, refit, update) must not be used by
another thread at the same time.
"""

from __future__ import annotations

import enum
import os
import sys
import struct
import threading
import time
import zlib
from typing import Any, Dict, Iterable, Iterator, List, Optional, Tuple, Union
from typing import Sequence as SequenceOf

import numpy as np

from ._selfcol_cffi import ffi, lib

__all__ = [
    "Error", "InvalidArgument", "OutOfMemory", "VersionError", "RangeError", "Mismatch",
    "StaleHierarchy", "Mesh", "Hierarchy", "Contacts", "Store", "StoreContacts", "Sweep",
    "Scene", "self_collide", "collide", "self_sweep", "mean_edge_length", "version",
]


# --------------------------------------------------------------------------
# Errors


class Error(Exception):
    """A selfcol call failed. ``status`` is the C library's selfcol_status (< 0)."""

    status: int

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


class InvalidArgument(Error, ValueError):
    """SELFCOL_EINVAL: an argument or the input data is invalid."""


class OutOfMemory(Error, MemoryError):
    """SELFCOL_ENOMEM: the allocator returned NULL (nothing was changed)."""


class VersionError(Error):
    """SELFCOL_EVERSION: an options version unknown to the linked library."""


class RangeError(Error, ValueError):
    """SELFCOL_ERANGE: a count or coordinate outside what the library represents."""


class Mismatch(Error, ValueError):
    """SELFCOL_EMISMATCH: handles that must belong together do not."""


class StaleHierarchy(Error, RuntimeError):
    """SELFCOL_ESTALE: a hierarchy was not refit after its mesh moved."""


class Cancelled(Error):
    """SELFCOL_EUSER: a progress callback asked the call to stop."""


_ERRORS = {
    int(lib.SELFCOL_EINVAL): InvalidArgument,
    int(lib.SELFCOL_ENOMEM): OutOfMemory,
    int(lib.SELFCOL_EVERSION): VersionError,
    int(lib.SELFCOL_ERANGE): RangeError,
    int(lib.SELFCOL_EMISMATCH): Mismatch,
    int(lib.SELFCOL_ESTALE): StaleHierarchy,
    int(lib.SELFCOL_EUSER): Cancelled,
}


def _status_text(status: int) -> str:
    return str(ffi.string(lib.selfcol_status_string(status)).decode())


def _check(status: int, what: str) -> None:
    if status != 0:
        cls = _ERRORS.get(status, Error)
        raise cls(status, "%s: %s (status %d)" % (what, _status_text(status), status))


def _check_options(check: Any, opts: Any, what: str) -> None:
    """Refuses options the C library would refuse, with its sentence naming
    the field, the value and what is accepted (selfcol_*_options_check)."""
    problem = ffi.new("selfcol_options_problem *")
    problem.version = lib.SELFCOL_OPTIONS_PROBLEM_VERSION
    status = check(opts, problem)
    if status != 0:
        message = ffi.string(problem.message).decode("utf-8", "replace")
        cls = _ERRORS.get(status, Error)
        raise cls(status, "%s: %s" % (what, message or _status_text(status)))


def _check_mesh(status: int, what: str, P: np.ndarray, T: Optional[np.ndarray]) -> None:
    """_check for the mesh functions: on EINVAL or ERANGE, names the first
    element the C library refuses (mesh.h's contract) instead of the status
    alone. Runs only on failure, so valid input pays nothing."""
    if status == 0:
        return
    culprit = _mesh_culprit(P, T) if status in (int(lib.SELFCOL_EINVAL),
                                                int(lib.SELFCOL_ERANGE)) else None
    if culprit is None:
        _check(status, what)
    cls = _ERRORS.get(status, Error)
    raise cls(status, "%s: %s (status %d)" % (what, culprit, status))


def _mesh_culprit(P: np.ndarray, T: Optional[np.ndarray]) -> Optional[str]:
    """The first element the C library refuses (selfcol_mesh_check, the
    checker selfcol_mesh_create runs), named in V and F's terms."""
    P64 = np.ascontiguousarray(P, dtype=np.float64)
    problem = ffi.new("selfcol_mesh_problem *")
    problem.version = lib.SELFCOL_MESH_PROBLEM_VERSION
    if T is None:
        lib.selfcol_mesh_check_positions(P64.shape[0], _ptr("double *", P64), problem)
    else:
        T32 = np.ascontiguousarray(T, dtype=np.uint32)
        lib.selfcol_mesh_check(P64.shape[0], _ptr("double *", P64), T32.shape[0],
                               _ptr("uint32_t *", T32), problem)
    if problem.status == 0:
        return None
    reason = str(ffi.string(problem.reason).decode())
    e, c = int(problem.element), int(problem.component)
    if problem.kind == lib.SELFCOL_MESH_PROBLEM_INDEX:
        return "F[%d, %d] = %d is not a row of V (%d vertices)" % (e, c, int(problem.value),
                                                                    P64.shape[0])
    if problem.kind >= lib.SELFCOL_MESH_PROBLEM_NOT_FINITE:
        return "V[%d, %d] = %r %s" % (e, c, float(P[e, c]), reason)
    return str(ffi.string(problem.message).decode())


def _invalid(message: str) -> InvalidArgument:
    return InvalidArgument(int(lib.SELFCOL_EINVAL), message)


def version() -> str:
    """Version of the linked C library, "MAJOR.MINOR.PATCH"."""
    return str(ffi.string(lib.selfcol_version_string()).decode())


# --------------------------------------------------------------------------
# Input arrays

_REAL_KINDS = "fiu"


def _as_positions(V: Any, name: str = "V") -> np.ndarray:
    """(n, 3) positions as float64 C-contiguous, or float32 rows of stride >= 12.

    No copy for C-contiguous float64 or float32 input (nor for float32 rows
    with a row stride, e.g. V[:, :3] of an (n, 4) array); anything else
    real-valued is converted once to float64."""
    a = np.asarray(V)
    if a.ndim != 2 or a.shape[1] != 3:
        raise _invalid("%s must have shape (n, 3), got %s" % (name, a.shape))
    if a.dtype.kind not in _REAL_KINDS or a.dtype == np.bool_:
        raise _invalid("%s must hold real numbers, got dtype %s" % (name, a.dtype))
    if a.shape[0] == 0:
        raise _invalid("%s is empty" % name)
    if a.dtype == np.float64 and a.flags.c_contiguous:
        return a
    if (a.dtype == np.float32 and a.strides[1] == 4 and a.strides[0] >= 12
            and a.strides[0] % 4 == 0):
        return a
    return np.ascontiguousarray(a, dtype=np.float64)


def _as_double_positions(V: Any, n: int, name: str) -> np.ndarray:
    """(n, 3) float64 C-contiguous (converted once if needed), for the C
    functions that only take doubles (sweeps' start positions)."""
    a = _as_positions(V, name)
    if a.dtype != np.float64 or not a.flags.c_contiguous:
        a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape[0] != n:
        raise _invalid("%s has %d vertices, the mesh %d" % (name, a.shape[0], n))
    return a


def _as_triangles(F: Any, name: str = "F") -> np.ndarray:
    """(m, 3) indices as uint32 C-contiguous. int32/uint32 C-contiguous input
    is passed without a copy (int32 reinterpreted after a sign check); int64
    and other integer types are converted once (the C API takes uint32)."""
    a = np.asarray(F)
    if a.ndim != 2 or a.shape[1] != 3:
        raise _invalid("%s must have shape (m, 3), got %s" % (name, a.shape))
    if a.shape[0] == 0:
        raise _invalid("%s is empty (a mesh needs at least one triangle)" % name)
    if a.dtype.kind not in "iu" or a.dtype == np.bool_:
        if a.dtype.kind == "f" and np.all(np.isfinite(a)) and np.all(a == np.floor(a)):
            a = a.astype(np.int64)
        else:
            raise _invalid("%s must hold integer indices, got dtype %s" % (name, a.dtype))
    if a.dtype.kind == "i" and a.size and int(a.min()) < 0:
        raise _invalid("%s holds a negative index" % name)
    if a.dtype == np.uint32 or a.dtype == np.int32:
        if a.flags.c_contiguous:
            return a.view(np.uint32)
        return np.ascontiguousarray(a).view(np.uint32)
    if a.size and int(a.max()) >= 0xFFFFFFFF:
        raise RangeError(int(lib.SELFCOL_ERANGE), "%s holds an index >= 2^32 - 1" % name)
    return np.ascontiguousarray(a, dtype=np.uint32)


def _ptr(ctype: str, a: np.ndarray) -> Any:
    """A pointer to a's first element; the caller keeps a alive over the call."""
    if a.flags.c_contiguous:
        return ffi.cast(ctype, ffi.from_buffer(a))
    return ffi.cast(ctype, a.__array_interface__["data"][0])  # strided float32 rows


# --------------------------------------------------------------------------
# Options

class Kind(enum.IntEnum):
    """A contact's kind, the value of ``records["kind"]`` (contacts.h)."""

    VF = 0  #: a vertex closer than the distance to a triangle
    EE = 1  #: two edges closer than the distance
    EF = 2  #: an edge crossing a triangle


class Method(enum.IntEnum):
    """A query's method (``method=`` takes these, their names or numbers)."""

    EXHAUSTIVE = 0
    BVH = 1
    SEED = 2
    CONE = 3
    EXACT = 4


class SweepFlag(enum.IntFlag):
    """Bits of a continuous query's ``flags`` (Sweep.flags)."""

    INITIAL = 1     #: within the separation already at t = 0
    UNRESOLVED = 2  #: the root finder's budget ran out (reported conservatively)


_METHODS = {"exhaustive": 0, "bvh": 1, "seed": 2, "cone": 3, "exact": 4}
_NARROW = {"closed": 0, "closed_form": 0, "libccd": 1}
_KINDS = {"vf": int(lib.SELFCOL_KIND_VF), "ee": int(lib.SELFCOL_KIND_EE),
          "ef": int(lib.SELFCOL_KIND_EF)}
_KIND_NAMES = ("vf", "ee", "ef")

KindsArg = Union[str, int, Iterable[str]]


def _kinds_mask(kinds: KindsArg) -> int:
    if isinstance(kinds, bool):
        raise _invalid("kinds must be names or a mask, got %r" % (kinds,))
    if isinstance(kinds, (int, np.integer)):
        mask = int(kinds)
        everything = int(lib.SELFCOL_KIND_ALL)
        if mask <= 0 or mask & ~everything:
            raise _invalid("kinds mask %r is not a nonzero combination of vf = %d, ee = %d and "
                           "ef = %d (all = %d)" % (kinds, _KINDS["vf"], _KINDS["ee"],
                                                  _KINDS["ef"], everything))
        return mask
    if kinds == "all":
        return int(lib.SELFCOL_KIND_ALL)
    if isinstance(kinds, str):
        if kinds.strip().lower() == "all":
            return int(lib.SELFCOL_KIND_ALL)
        names: Iterable[str] = [k for k in kinds.replace("|", ",").split(",") if k.strip()]
    else:
        names = kinds
    mask = 0
    for k in names:
        key = str(k).strip().lower()
        if key not in _KINDS:
            raise _invalid("unknown contact kind %r (vf, ee, ef or all)" % (k,))
        mask |= _KINDS[key]
    if mask == 0:
        raise _invalid("kinds selects no contact kind")
    return mask


def _lookup(table: Dict[str, int], value: Union[str, int], what: str) -> int:
    if isinstance(value, enum.Enum):
        value = int(value)
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if int(value) not in table.values():
            raise _invalid("unknown %s %r (one of %s, or their numbers %s)"
                           % (what, value, ", ".join(sorted(table)),
                              ", ".join(str(v) for v in sorted(set(table.values())))))
        return int(value)
    key = str(value).lower()
    if key not in table:
        raise _invalid("unknown %s %r (one of %s)" % (what, value, ", ".join(sorted(table))))
    return table[key]


def _context(threads: Any) -> Any:
    """The context a call with ``threads`` runs on (context.h: the library's
    one place for threads), or None for one thread (the calling thread).
    Made for the call and destroyed with it: its threads are started and
    joined within the call. A refused count is named by the library
    (selfcol_context_options_check)."""
    if not isinstance(threads, (int, np.integer)) or isinstance(threads, bool) or threads < 1:
        raise _invalid("threads must be an integer >= 1, got %r" % (threads,))
    if threads == 1:
        return None
    opts = ffi.new("selfcol_context_options *")
    _check(lib.selfcol_context_options_init(opts, lib.SELFCOL_CONTEXT_OPTIONS_VERSION),
           "selfcol_context_options_init")
    opts.threads = min(int(threads), 1 << 31)
    _check_options(lib.selfcol_context_options_check, opts, "threads")
    out = ffi.new("selfcol_context **")
    _check(lib.selfcol_context_create(out, opts), "selfcol_context_create")
    return ffi.gc(out[0], lib.selfcol_context_destroy)


def _query_options(distance: float, method: Union[str, int], kinds: KindsArg,
                   narrow: Union[str, int]) -> Any:
    opts = ffi.new("selfcol_query_options *")
    _check(lib.selfcol_query_options_init(opts, lib.SELFCOL_QUERY_OPTIONS_VERSION),
           "selfcol_query_options_init")
    opts.method = _lookup(_METHODS, method, "method")
    opts.narrow = _lookup(_NARROW, narrow, "narrow phase")
    opts.kinds = _kinds_mask(kinds)
    try:
        opts.distance = float(distance)
    except (TypeError, ValueError):
        raise _invalid("distance must be a number, got %r" % (distance,)) from None
    _check_options(lib.selfcol_query_options_check, opts, "query options")
    return opts


def _struct_dtype(ctype: str, fields: SequenceOf[Tuple[str, Any, Tuple[int, ...]]]) -> np.dtype:
    names, formats, offsets = [], [], []
    for name, fmt, shape in fields:
        names.append(name)
        formats.append((fmt, shape) if shape else fmt)
        offsets.append(ffi.offsetof(ctype, name))
    return np.dtype({"names": names, "formats": formats, "offsets": offsets,
                     "itemsize": ffi.sizeof(ctype)})


_U, _I, _D = np.uint32, np.int32, np.float64
_KEY = [("kind", _U, ()), ("first", _U, ()), ("second", _U, ()), ("first_mesh", _U, ()),
        ("second_mesh", _U, ()), ("a", _U, (2,)), ("b", _U, (3,))]
CONTACT_DTYPE = _struct_dtype("selfcol_contact", _KEY + [
    ("distance", _D, ()), ("wa", _D, (2,)), ("wb", _D, (3,)), ("direction", _D, (3,))])
STORE_CONTACT_DTYPE = _struct_dtype("selfcol_store_contact", _KEY + [
    ("region", _U, ()), ("age", _U, ()), ("missed", _U, ()), ("flags", _U, ()),
    ("side", _I, ()), ("right_side", _I, ()), ("distance", _D, ()),
    ("signed_distance", _D, ()), ("wa", _D, (2,)), ("wb", _D, (3,)), ("direction", _D, (3,))])
REGION_DTYPE = _struct_dtype("selfcol_store_region", [
    (n, _U, ()) for n in ("contacts", "interferences", "votes_majority", "votes_minority",
                          "abstained", "oriented", "flags")])
SWEEP_HIT_DTYPE = _struct_dtype("selfcol_sweep_hit", _KEY + [
    ("flags", _U, ()), ("toi", _D, ())])
COLLIDER_CONTACT_DTYPE = _struct_dtype("selfcol_collider_contact", [
    ("collider", _U, ()), ("surface", _U, ()), ("triangle", _U, ()), ("flags", _U, ()),
    ("distance", _D, ()), ("wb", _D, (3,)), ("normal", _D, (3,))])


def _copy_records(ptr: Any, count: int, dtype: np.dtype) -> np.ndarray:
    """One copy of a borrowed C array into a structured numpy array."""
    if count == 0 or ptr == ffi.NULL:
        return np.zeros(0, dtype=dtype)
    buf = ffi.buffer(ptr, count * dtype.itemsize)
    return np.frombuffer(buf, dtype=dtype, count=count).copy()


_FIELD_NAMES: Dict[str, Tuple[str, ...]] = {}


def _stats_dict(stats: Any, ctype: str) -> Dict[str, Union[int, float]]:
    names = _FIELD_NAMES.get(ctype)
    if names is None:
        names = tuple(n for n, _ in ffi.typeof(ctype).fields if n != "version")
        _FIELD_NAMES[ctype] = names
    return {n: getattr(stats, n) for n in names}


# --------------------------------------------------------------------------
# Mesh


def _mesh_like(obj: Any) -> bool:
    """A trimesh.Trimesh, or any object with ``vertices`` and ``faces``."""
    return hasattr(obj, "vertices") and hasattr(obj, "faces") and not isinstance(obj, np.ndarray)


def _vf(V: Any, F: Any) -> Tuple[Any, Any]:
    """(V, F) from arrays, or from a mesh-like object given as V with F None
    (its vertices in its own order: for a file's order, load trimesh meshes
    with process=False)."""
    if F is None:
        if not _mesh_like(V):
            raise _invalid("F is missing: give (V, F) arrays, or a mesh with .vertices and "
                           ".faces (a trimesh.Trimesh) alone")
        return np.asarray(V.vertices), np.asarray(V.faces)
    return V, F


class Mesh:
    """A triangle surface: positions and the topology built once.

    ``V``: (n, 3) positions (float64 or float32; C-contiguous float input is
    read in place, anything else converted once). ``F``: (m, 3) vertex
    indices (int32/uint32 read in place, int64 converted once). Or a
    trimesh.Trimesh (any object with ``vertices`` and ``faces``) as V alone.
    The C library copies both. Mirrors ``selfcol_mesh_create``."""

    def __init__(self, V: Any, F: Any = None) -> None:
        V, F = _vf(V, F)
        P = _as_positions(V)
        T = _as_triangles(F)
        out = ffi.new("selfcol_mesh **")
        if P.dtype == np.float64:
            st = lib.selfcol_mesh_create(out, P.shape[0], _ptr("double *", P), T.shape[0],
                                         _ptr("uint32_t *", T), ffi.NULL)
        else:
            st = lib.selfcol_mesh_create_float(out, P.shape[0], _ptr("float *", P), P.strides[0],
                                               T.shape[0], _ptr("uint32_t *", T), ffi.NULL)
        _check_mesh(st, "selfcol_mesh_create", P, T)
        self._h = ffi.gc(out[0], lib.selfcol_mesh_destroy)
        self.vertex_count = int(P.shape[0])
        self.triangle_count = int(T.shape[0])

    def __reduce__(self) -> Tuple[Any, Tuple[np.ndarray, np.ndarray]]:
        """Pickles as its current positions and triangles (a new mesh with its
        own topology is built on loading), so a Mesh crosses process
        boundaries (multiprocessing, joblib, Dask)."""
        return (Mesh, (self.positions, self.triangles))

    def set_positions(self, V: Any) -> None:
        """Replaces all positions (a new frame); hierarchies then need refit().
        On error the mesh keeps its previous positions."""
        P = _as_positions(V)
        if P.shape[0] != self.vertex_count:
            raise _invalid("set_positions: %d vertices, the mesh has %d"
                           % (P.shape[0], self.vertex_count))
        if P.dtype == np.float64:
            st = lib.selfcol_mesh_set_positions(self._h, _ptr("double *", P), P.shape[0])
        else:
            st = lib.selfcol_mesh_set_positions_float(self._h, _ptr("float *", P), P.strides[0],
                                                      P.shape[0])
        _check_mesh(st, "selfcol_mesh_set_positions", P, None)

    @property
    def positions(self) -> np.ndarray:
        """A copy of the current positions, (n, 3) float64."""
        p = lib.selfcol_mesh_positions(self._h)
        return np.frombuffer(ffi.buffer(p, self.vertex_count * 24), dtype=np.float64).reshape(
            -1, 3).copy()

    @property
    def triangles(self) -> np.ndarray:
        """A copy of the triangles, (m, 3) uint32."""
        p = lib.selfcol_mesh_triangles(self._h)
        return np.frombuffer(ffi.buffer(p, self.triangle_count * 12), dtype=np.uint32).reshape(
            -1, 3).copy()

    @property
    def edges(self) -> np.ndarray:
        """A copy of the unique edges, (e, 2) uint32, sorted, smaller vertex first."""
        n = self.count("edges")
        p = lib.selfcol_mesh_edges(self._h)
        return np.frombuffer(ffi.buffer(p, n * 8), dtype=np.uint32).reshape(-1, 2).copy()

    _QUANTITIES = {"vertices": 0, "triangles": 1, "edges": 2, "boundary_edges": 3,
                   "nonmanifold_edges": 4, "components": 5, "unreferenced_vertices": 6,
                   "repeated_index_triangles": 7, "duplicate_triangles": 8,
                   "zero_area_triangles": 9, "boundary_loops": 10, "misoriented_edges": 11}

    def count(self, quantity: str) -> int:
        """selfcol_mesh_count: 'vertices', 'triangles', 'edges', 'boundary_edges',
        'nonmanifold_edges', 'components', 'unreferenced_vertices',
        'repeated_index_triangles', 'duplicate_triangles', 'zero_area_triangles',
        'boundary_loops', 'misoriented_edges'."""
        q = _lookup(self._QUANTITIES, quantity, "mesh quantity")
        return int(lib.selfcol_mesh_count(self._h, q))

    def mean_edge_length(self) -> float:
        """Mean length of the unique edges at the current positions."""
        return float(lib.selfcol_mesh_mean_edge_length(self._h))

    @property
    def byte_count(self) -> int:
        return int(lib.selfcol_mesh_byte_count(self._h))

    def __repr__(self) -> str:
        return "selfcol.Mesh(%d vertices, %d triangles)" % (self.vertex_count,
                                                            self.triangle_count)


def mean_edge_length(*meshes: Any) -> float:
    """Mean edge length over one or more meshes (weighted by their edge counts,
    as selfcol-cli does for two meshes). Each a Mesh or a trimesh.Trimesh;
    or one surface as arrays: ``mean_edge_length(V, F)``."""
    if len(meshes) == 2 and not any(isinstance(m, Mesh) or _mesh_like(m) for m in meshes):
        meshes = (Mesh(meshes[0], meshes[1]),)
    total, edges = 0.0, 0
    for m in (x if isinstance(x, Mesh) else Mesh(x) for x in meshes):
        e = m.count("edges")
        total += e * m.mean_edge_length()
        edges += e
    return total / edges if edges else 0.0


# --------------------------------------------------------------------------
# Contacts (the result of a discrete query)


class Contacts:
    """The contacts of one discrete query, as numpy arrays (copied once from C).

    Per record (sorted by kind, first_mesh, first, second_mesh, second):
    ``kind`` (0 VF, 1 EE, 2 EF), ``first``, ``second``, ``first_mesh``,
    ``second_mesh``, ``a`` (n, 2) and ``b`` (n, 3) vertices, ``distance``,
    ``wa`` (n, 2), ``wb`` (n, 3) and ``direction`` (n, 3). Per kind:
    ``vf`` (n, 2) [vertex, triangle], ``ee`` (n, 4) [a0, a1, b0, b1],
    ``ef`` (n, 3) [a0, a1, triangle] (indices local to each record's mesh;
    ``first_mesh``/``second_mesh`` tell which). ``slice('ee')`` gives the rows
    of a kind in the per-record arrays. ``stats``: the query's counters."""

    def __init__(self, handle: Any, meshes: Tuple[Mesh, ...], distance: float) -> None:
        # The handle is never queried again: its records stay valid, and are
        # copied into numpy on first use (records, stats: lazily).
        self._h = handle
        self._meshes = meshes
        self.distance_used = distance
        self._records: Optional[np.ndarray] = None
        self._stats: Optional[Dict[str, Union[int, float]]] = None
        self._intersecting: Optional[np.ndarray] = None
        self._bounds_list: Optional[List[int]] = None

    @property
    def records(self) -> np.ndarray:
        """All records, a structured array with the fields of selfcol_contact."""
        if self._records is None:
            ptr = ffi.new("selfcol_contact **")
            cnt = ffi.new("size_t *")
            _check(lib.selfcol_contacts_data(self._h, ptr, cnt), "selfcol_contacts_data")
            self._records = _copy_records(ptr[0], int(cnt[0]), CONTACT_DTYPE)
        return self._records

    @property
    def stats(self) -> Dict[str, Union[int, float]]:
        """The query's counters and times (selfcol_query_stats)."""
        if self._stats is None:
            st = ffi.new("selfcol_query_stats *")
            st.version = lib.SELFCOL_QUERY_STATS_VERSION
            _check(lib.selfcol_contacts_stats(self._h, st), "selfcol_contacts_stats")
            self._stats = _stats_dict(st, "selfcol_query_stats")
        return self._stats

    @property
    def _bounds(self) -> List[int]:
        if self._bounds_list is None:
            self._bounds_list = [int(x) for x in np.searchsorted(self.records["kind"],
                                                                   [0, 1, 2, 3])]
        return self._bounds_list

    def __len__(self) -> int:
        if self._h is None:  # unpickled: the records are all there is
            return int(self.records.shape[0])
        return int(lib.selfcol_contacts_count(self._h))

    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]:
        """Pickles as its records, statistics, distance and meshes, and for a
        self query its intersecting triangle pairs (an unpickled Contacts
        holds no C handle; everything it answers comes from those)."""
        pairs = self.intersecting_triangles() if len(self._meshes) == 1 else None
        return (_contacts_from_state, (self.records, dict(self.stats), self.distance_used,
                                       self._meshes, pairs))

    def __iter__(self) -> Iterator[Dict[str, Any]]:
        """One dict per record, in record order (see to_dict for the keys)."""
        r = self.records
        for i in range(r.shape[0]):
            yield _record_dict(r[i])

    def to_dict(self) -> Dict[str, Any]:
        """Plain Python data (JSON-ready): the distance, the counts, the
        contacts per kind as lists of index lists (as selfcol-cli's JSON:
        vf [vertex, triangle], ee [a0, a1, b0, b1], ef [a0, a1, triangle]),
        the distance of each proximity, and the statistics."""
        out: Dict[str, Any] = {"distance": self.distance_used, "counts": self.counts}
        for kind in _KIND_NAMES:
            out[kind] = getattr(self, kind).tolist()
        out["vf_distance"] = self.records["distance"][self.slice("vf")].tolist()
        out["ee_distance"] = self.records["distance"][self.slice("ee")].tolist()
        out["stats"] = dict(self.stats)
        return out

    def slice(self, kind: str) -> slice:
        """The rows of one kind ('vf', 'ee' or 'ef') in the per-record arrays."""
        k = _KIND_NAMES.index(kind.lower())
        return slice(self._bounds[k], self._bounds[k + 1])

    def _field(self, name: str) -> np.ndarray:
        return np.ascontiguousarray(self.records[name])

    kind = property(lambda self: self._field("kind"))
    first = property(lambda self: self._field("first"))
    second = property(lambda self: self._field("second"))
    first_mesh = property(lambda self: self._field("first_mesh"))
    second_mesh = property(lambda self: self._field("second_mesh"))
    a = property(lambda self: self._field("a"))
    b = property(lambda self: self._field("b"))
    distance = property(lambda self: self._field("distance"))
    wa = property(lambda self: self._field("wa"))
    wb = property(lambda self: self._field("wb"))
    direction = property(lambda self: self._field("direction"))

    @property
    def vf(self) -> np.ndarray:
        r = self.records[self.slice("vf")]
        return np.stack([r["first"], r["second"]], axis=1).astype(np.int64).reshape(-1, 2)

    @property
    def ee(self) -> np.ndarray:
        r = self.records[self.slice("ee")]
        return np.concatenate([r["a"], r["b"][:, :2]], axis=1).astype(np.int64).reshape(-1, 4)

    @property
    def ef(self) -> np.ndarray:
        r = self.records[self.slice("ef")]
        return np.concatenate([r["a"], r["second"][:, None]], axis=1).astype(np.int64).reshape(
            -1, 3)

    @property
    def counts(self) -> Dict[str, int]:
        return {k: self._bounds[i + 1] - self._bounds[i] for i, k in enumerate(_KIND_NAMES)}

    def intersecting_triangles(self) -> np.ndarray:
        """(k, 2) sorted pairs of intersecting triangles derived from EF as
        selfcol-cli does (self queries only; each triangle on the crossing
        edge paired with the crossed one)."""
        if len(self._meshes) != 1:
            raise _invalid("intersecting_triangles: only for a self query")
        if self._intersecting is None:
            # In C (selfcol_contacts_intersecting_triangles: a radix sort of
            # the pairs the EF records give, about 1 % of the query).
            m = self._meshes[0]._h
            ptr = ffi.new("uint32_t **")
            cnt = ffi.new("size_t *")
            _check(lib.selfcol_contacts_intersecting_triangles(self._h, m, m, ptr, cnt),
                   "selfcol_contacts_intersecting_triangles")
            n = int(cnt[0])
            out = np.zeros((n, 2), dtype=np.int64)
            if n:
                out[:] = np.frombuffer(ffi.buffer(ptr[0], 8 * n), dtype=np.uint32).reshape(n, 2)
            self._intersecting = out
        return self._intersecting.copy()

    def triangle_classes(self) -> Union[np.ndarray, Tuple[np.ndarray, np.ndarray]]:
        """Per triangle, what it takes part in: 0 nothing, 1 a proximity (VF,
        EE), 2 an interference (EF): ``selfcol-cli check --mark``'s marking
        (selfcol_contacts_triangle_classes). One uint8 array for a self
        query, a pair (first mesh, second mesh) for two."""
        if self._h is None:
            raise _invalid("triangle_classes: a Contacts loaded from a pickle has no records "
                           "in C; query again")
        m0 = self._meshes[0]
        m1 = self._meshes[1] if len(self._meshes) > 1 else m0
        c0 = np.zeros(m0.triangle_count, dtype=np.uint8)
        c1 = np.zeros(m1.triangle_count, dtype=np.uint8) if m1 is not m0 else c0
        _check(lib.selfcol_contacts_triangle_classes(self._h, m0._h, m1._h,
                                                     _ptr("uint8_t *", c0),
                                                     _ptr("uint8_t *", c1)),
               "selfcol_contacts_triangle_classes")
        return c0 if m1 is m0 else (c0, c1)

    def write_marked(self, path: str) -> None:
        """Writes the mesh as ``selfcol-cli check --mark`` does (self queries):
        an ASCII PLY with intersecting faces red, faces within the distance
        orange, the rest grey, and vertex colours for Blender's importer."""
        if len(self._meshes) != 1:
            raise _invalid("write_marked: only for a self query")
        classes = self.triangle_classes()
        assert isinstance(classes, np.ndarray)
        m = self._meshes[0]
        P = np.ascontiguousarray(m.positions, dtype=np.float64)
        T = np.ascontiguousarray(m.triangles, dtype=np.uint32)
        err = ffi.new("meshio_error *")
        comment = ("selfcol %s (Python): red faces intersect, orange faces are within the "
                   "detection distance" % version()).encode()
        if lib.meshio_write_marked_ply(os.fsencode(path), _ptr("double *", P), P.shape[0],
                                       _ptr("uint32_t *", T), T.shape[0],
                                       ffi.cast("unsigned char *", classes.ctypes.data),
                                       comment, err) != 0:
            raise OSError(ffi.string(err.message).decode("utf-8", "replace"))

    def render(self, width: int = 1024, height: int = 768, azimuth: float = 35.0,
               elevation: float = 25.0) -> np.ndarray:
        """The picture of ``selfcol-cli check --png`` (its ``--size WxH`` and
        ``--view AZ,EL``), pixel for pixel: intersecting triangles red,
        triangles within the distance amber, the rest light steel, on white,
        seen orthographically from the angles in degrees (y is up). An
        ``(height, width, 3)`` uint8 RGB array, rows top first. Two meshes
        are drawn together, marked by this query (the CLI's picture of two
        files also marks each one's self-contacts)."""
        for name, value in (("width", width), ("height", height)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) \
                    or not 16 <= value <= 4096:
                raise _invalid("render: %s = %r is not a whole number of pixels in 16..4096"
                               % (name, value))
        for name, angle in (("azimuth", azimuth), ("elevation", elevation)):
            if not isinstance(angle, (int, float, np.integer, np.floating)) \
                    or isinstance(angle, bool) or not np.isfinite(angle):
                raise _invalid("render: %s = %r is not a finite angle in degrees"
                               % (name, angle))
        classes = self.triangle_classes()
        parts = classes if isinstance(classes, tuple) else (classes,)
        positions, triangles, offset = [], [], 0
        for m in self._meshes[:len(parts)]:
            positions.append(np.asarray(m.positions, dtype=np.float64))
            triangles.append(np.asarray(m.triangles, dtype=np.int64) + offset)
            offset += m.positions.shape[0]
        P = np.ascontiguousarray(np.concatenate(positions), dtype=np.float64)
        T = np.ascontiguousarray(np.concatenate(triangles), dtype=np.uint32)
        C = np.ascontiguousarray(np.concatenate(parts), dtype=np.uint8)
        view = ffi.new("meshio_view *", {"azimuth": float(azimuth), "elevation": float(elevation),
                                         "width": int(width), "height": int(height)})
        out = np.empty((int(height), int(width), 3), dtype=np.uint8)
        if lib.meshio_render_rgb(_ptr("double *", P), _ptr("uint32_t *", T), T.shape[0],
                                 ffi.cast("unsigned char *", C.ctypes.data), view,
                                 ffi.cast("unsigned char *", out.ctypes.data)) != 0:
            raise MemoryError("render: no memory for a %dx%d picture" % (width, height))
        return out

    def write_png(self, path: str, width: int = 1024, height: int = 768,
                  azimuth: float = 35.0, elevation: float = 25.0) -> None:
        """Writes render()'s picture to a PNG file: ``selfcol-cli check
        --png`` from Python (the same pixels; the file's compression may
        differ)."""
        _write_png(path, self.render(width, height, azimuth, elevation))

    def __repr__(self) -> str:
        c = self.counts
        return "selfcol.Contacts(vf=%d, ee=%d, ef=%d, distance=%g)" % (
            c["vf"], c["ee"], c["ef"], self.distance_used)


def _write_png(path: str, rgb: np.ndarray) -> None:
    """An 8-bit RGB PNG (no filter, zlib level 6): the standard library's
    zlib is all a picture needs, so the wheel carries no libpng."""
    height, width = rgb.shape[:2]

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    rows = np.zeros((height, 1 + 3 * width), dtype=np.uint8)  # filter byte 0: none
    rows[:, 1:] = rgb.reshape(height, 3 * width)
    data = (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(data)


def _record_dict(r: Any) -> Dict[str, Any]:
    kind = _KIND_NAMES[int(r["kind"])]
    return {"kind": kind, "first": int(r["first"]), "second": int(r["second"]),
            "first_mesh": int(r["first_mesh"]), "second_mesh": int(r["second_mesh"]),
            "a": [int(x) for x in r["a"]], "b": [int(x) for x in r["b"]][:2 if kind == "ee"
                                                                           else 3],
            "distance": float(r["distance"]), "wa": [float(x) for x in r["wa"]],
            "wb": [float(x) for x in r["wb"]], "direction": [float(x) for x in r["direction"]]}


def _contacts_from_state(records: np.ndarray, stats: Dict[str, Union[int, float]],
                         distance: float, meshes: Tuple[Mesh, ...],
                         intersecting: Optional[np.ndarray] = None) -> Contacts:
    c = Contacts(None, meshes, distance)
    c._records = records
    c._stats = stats
    c._intersecting = intersecting
    return c


def _new_contacts() -> Any:
    out = ffi.new("selfcol_contacts **")
    _check(lib.selfcol_contacts_create(out, ffi.NULL), "selfcol_contacts_create")
    return ffi.gc(out[0], lib.selfcol_contacts_destroy)


# --------------------------------------------------------------------------
# Hierarchy


class Hierarchy:
    """A collision hierarchy over a mesh (selfcol_hierarchy_create). Keeps its
    mesh alive. Call refit() after the mesh's positions change; a refit runs
    on up to ``threads`` threads (selfcol_context_refit; one per 4096
    triangles at most) with the same result for every count."""

    def __init__(self, mesh: Mesh, threads: int = 1) -> None:
        if not isinstance(mesh, Mesh):
            raise _invalid("Hierarchy needs a selfcol.Mesh, got %s" % type(mesh).__name__)
        _context(threads)  # refused here, not at the first refit
        out = ffi.new("selfcol_hierarchy **")
        _check(lib.selfcol_hierarchy_create(out, mesh._h, ffi.NULL), "selfcol_hierarchy_create")
        self._h = ffi.gc(out[0], lib.selfcol_hierarchy_destroy)
        self.mesh = mesh
        self._threads = int(threads)

    def refit(self) -> None:
        """Boxes, masks and cones from the mesh's current positions (GIL released)."""
        context = _context(self._threads)
        if context is None:
            _check(lib.selfcol_hierarchy_refit(self._h), "selfcol_hierarchy_refit")
        else:
            _check(lib.selfcol_context_refit(context, self._h), "selfcol_context_refit")

    def _distance(self, distance: Optional[float], distance_rel: float,
                  *meshes: Mesh) -> float:
        d = distance if distance is not None else distance_rel
        try:
            d = float(d)
        except (TypeError, ValueError):
            raise _invalid("distance must be a number, got %r" % (d,)) from None
        return d * mean_edge_length(*meshes) if distance is None else d

    def self_collide(self, distance: Optional[float] = None, distance_rel: float = 0.1,
                     method: Union[str, int] = "exact", kinds: KindsArg = "all",
                     threads: int = 1, narrow: Union[str, int] = "closed") -> Contacts:
        """Self-contacts of the mesh at its current positions
        (selfcol_hierarchy_self_collide). ``distance=None``: distance_rel x the
        mean edge length."""
        d = self._distance(distance, distance_rel, self.mesh)
        opts = _query_options(d, method, kinds, narrow)
        context = _context(threads)
        c = _new_contacts()
        if context is None:
            _check(lib.selfcol_hierarchy_self_collide(self._h, c, opts),
                   "selfcol_hierarchy_self_collide")
        else:
            _check(lib.selfcol_context_self_collide(context, self._h, c, opts),
                   "selfcol_context_self_collide")
        return Contacts(c, (self.mesh,), d)

    def collide(self, other: "Hierarchy", distance: Optional[float] = None,
                distance_rel: float = 0.1, method: Union[str, int] = "exact",
                kinds: KindsArg = "all", threads: int = 1,
                narrow: Union[str, int] = "closed") -> Contacts:
        """Contacts between this mesh (mesh 0) and other's (mesh 1), not the
        self-contacts of either (selfcol_hierarchy_collide)."""
        if not isinstance(other, Hierarchy):
            raise _invalid("collide needs another selfcol.Hierarchy")
        d = self._distance(distance, distance_rel, self.mesh, other.mesh)
        opts = _query_options(d, method, kinds, narrow)
        context = _context(threads)
        c = _new_contacts()
        if context is None:
            _check(lib.selfcol_hierarchy_collide(self._h, other._h, c, opts),
                   "selfcol_hierarchy_collide")
        else:
            _check(lib.selfcol_context_collide(context, self._h, other._h, c, opts),
                   "selfcol_context_collide")
        return Contacts(c, (self.mesh, other.mesh), d)

    def self_sweep(self, start: Any, separation: float = 0.0, method: Union[str, int] = "bvh",
                   kinds: KindsArg = "vf,ee", mode: str = "all", threads: int = 1,
                   progress: Any = None, tolerance: Optional[float] = None) -> "Sweep":
        """Continuous self-query over one step, from ``start`` (t = 0) to the
        mesh's current positions (t = 1) (selfcol_hierarchy_self_sweep).
        ``method``: "bvh" (default), "exact" (BVH and the curvature criterion
        over the step: the same true collisions, fewer candidates where
        patches move smoothly) or "exhaustive" (the reference). ``mode``:
        "all" (every pair; long on big steps) or "earliest" (the first time
        of contact only, what a simulator needs: much faster). ``progress``
        (mode "all"): True for a line on standard error, or a callable
        given the fraction done that returns True to cancel (then
        selfcol.Cancelled); Ctrl-C stops the query in every case.
        ``tolerance``: the root finder's relative tolerance (None: 1e-6,
        SELFCOL_SWEEP_DEFAULT_TOLERANCE; at most 0.1): larger is faster and
        reports pairs that come within that band of touching, never fewer."""
        S = _as_double_positions(start, self.mesh.vertex_count, "start")
        opts = _sweep_options(separation, method, kinds, mode, tolerance)
        context = _context(threads)
        sw = _new_sweep()
        if context is None:
            _run_sweep(opts, progress,
                       lambda: lib.selfcol_hierarchy_self_sweep(self._h, _ptr("double *", S), sw,
                                                                opts),
                       "selfcol_hierarchy_self_sweep")
        else:
            _run_sweep(opts, progress,
                       lambda: lib.selfcol_context_self_sweep(context, self._h,
                                                              _ptr("double *", S), sw, opts),
                       "selfcol_context_self_sweep")
        return Sweep(sw)

    def sweep(self, start: Any, other: "Hierarchy", other_start: Any, separation: float = 0.0,
              method: Union[str, int] = "bvh", kinds: KindsArg = "vf,ee", mode: str = "all",
              threads: int = 1, progress: Any = None,
              tolerance: Optional[float] = None) -> "Sweep":
        """Continuous query between this mesh (0) and other's (1) over one step
        (selfcol_hierarchy_sweep); ``progress`` and ``tolerance`` as self_sweep."""
        if not isinstance(other, Hierarchy):
            raise _invalid("sweep needs another selfcol.Hierarchy")
        S0 = _as_double_positions(start, self.mesh.vertex_count, "start")
        S1 = _as_double_positions(other_start, other.mesh.vertex_count, "other_start")
        opts = _sweep_options(separation, method, kinds, mode, tolerance)
        context = _context(threads)
        sw = _new_sweep()
        if context is None:
            _run_sweep(opts, progress,
                       lambda: lib.selfcol_hierarchy_sweep(self._h, _ptr("double *", S0), other._h,
                                                           _ptr("double *", S1), sw, opts),
                       "selfcol_hierarchy_sweep")
        else:
            _run_sweep(opts, progress,
                       lambda: lib.selfcol_context_sweep(context, self._h, _ptr("double *", S0),
                                                         other._h, _ptr("double *", S1), sw, opts),
                       "selfcol_context_sweep")
        return Sweep(sw)

    def count(self, quantity: str) -> int:
        """'nodes', 'leaves' or 'depth'."""
        q = _lookup({"nodes": 0, "leaves": 1, "depth": 2}, quantity, "hierarchy quantity")
        return int(lib.selfcol_hierarchy_count(self._h, q))

    @property
    def byte_count(self) -> int:
        return int(lib.selfcol_hierarchy_byte_count(self._h))

    def __repr__(self) -> str:
        return "selfcol.Hierarchy(%r, %d nodes)" % (self.mesh, self.count("nodes"))


# --------------------------------------------------------------------------
# Coherent queries over a sequence of frames


_SEQUENCE_ANSWERS = {0: "list", 1: "rebuilt", 2: "fresh"}
# selfcol_sequence_run_stats.last_reason (sequence.h)
_SEQUENCE_REASONS = {0: "first_frame", 1: "changed", 2: "deformation", 3: "approximate_method"}


class Sequence:
    """The same query asked frame after frame (selfcol_sequence): answered
    from a near list kept across frames while the surface deforms little,
    with exactly the contacts a fresh query returns. Keep one per query
    (one per hierarchy for self queries) and call it every frame after
    ``Mesh.set_positions``; the hierarchy need not be refit. Methods "seed"
    and "cone" (approximate) are answered by a fresh query every frame."""

    def __init__(self, skin: float = 0.0) -> None:
        opts = ffi.new("selfcol_sequence_options *")
        _check(lib.selfcol_sequence_options_init(opts, lib.SELFCOL_SEQUENCE_OPTIONS_VERSION),
               "selfcol_sequence_options_init")
        try:
            opts.skin = float(skin)
        except (TypeError, ValueError):
            raise _invalid("skin must be a number, got %r" % (skin,)) from None
        _check_options(lib.selfcol_sequence_options_check, opts, "Sequence")
        out = ffi.new("selfcol_sequence **")
        _check(lib.selfcol_sequence_create(out, opts), "selfcol_sequence_create")
        self._h = ffi.gc(out[0], lib.selfcol_sequence_destroy)
        self._distance: Optional[float] = None  # d of the last distance=None call
        self._rel_key: Any = None  # its distance_rel
        self._rel_of: Tuple[Any, ...] = ()  # and its hierarchies
        self._keep: Tuple[Any, ...] = ()

    def _fixed_distance(self, distance: Optional[float], distance_rel: float,
                        *hierarchies: "Hierarchy") -> float:
        # distance=None: distance_rel x the mean edge at the first frame of
        # these hierarchies with this distance_rel, kept while both stay the
        # same (a distance that followed the mean edge every frame would
        # restart the sequence every frame). Another distance_rel or another
        # hierarchy takes the mean edge anew: the arguments are honoured on
        # every call, never answered at an earlier call's distance.
        meshes = tuple(h.mesh for h in hierarchies)
        if distance is not None:
            return hierarchies[0]._distance(distance, distance_rel, *meshes)
        key = (float(distance_rel) if isinstance(distance_rel, (int, float, np.number))
               else distance_rel)
        same = (self._distance is not None and self._rel_key == key
                and len(self._rel_of) == len(hierarchies)
                and all(a is b for a, b in zip(self._rel_of, hierarchies)))
        if not same:
            self._distance = hierarchies[0]._distance(None, distance_rel, *meshes)
            self._rel_key = key
            self._rel_of = hierarchies
        assert self._distance is not None
        return self._distance

    def self_collide(self, hierarchy: "Hierarchy", distance: Optional[float] = None,
                     distance_rel: float = 0.1, method: Union[str, int] = "exact",
                     kinds: KindsArg = "all", threads: int = 1,
                     narrow: Union[str, int] = "closed") -> Contacts:
        """Self-contacts of the hierarchy's mesh at its current positions,
        as Hierarchy.self_collide would return them (selfcol_sequence_self_collide).
        ``method``: "exact", "bvh" or "exhaustive". ``distance=None``:
        distance_rel x the mean edge length when this hierarchy was first
        queried with this distance_rel, kept over the following frames (a
        change of distance_rel or of hierarchy measures it again); the
        distance used is Contacts.distance_used."""
        if not isinstance(hierarchy, Hierarchy):
            raise _invalid("self_collide needs a selfcol.Hierarchy")
        d = self._fixed_distance(distance, distance_rel, hierarchy)
        opts = _query_options(d, method, kinds, narrow)
        context = _context(threads)
        c = _new_contacts()
        if context is None:
            _check(lib.selfcol_sequence_self_collide(self._h, hierarchy._h, c, opts),
                   "selfcol_sequence_self_collide")
        else:
            _check(lib.selfcol_context_sequence_self_collide(context, self._h, hierarchy._h, c,
                                                             opts),
                   "selfcol_context_sequence_self_collide")
        self._keep = (hierarchy,)
        return Contacts(c, (hierarchy.mesh,), d)

    def collide(self, first: "Hierarchy", second: "Hierarchy", distance: Optional[float] = None,
                distance_rel: float = 0.1, method: Union[str, int] = "exact",
                kinds: KindsArg = "all", threads: int = 1,
                narrow: Union[str, int] = "closed") -> Contacts:
        """Contacts between two meshes, as Hierarchy.collide would return them
        (selfcol_sequence_collide)."""
        if not isinstance(first, Hierarchy) or not isinstance(second, Hierarchy):
            raise _invalid("collide needs two selfcol.Hierarchy")
        d = self._fixed_distance(distance, distance_rel, first, second)
        opts = _query_options(d, method, kinds, narrow)
        context = _context(threads)
        c = _new_contacts()
        if context is None:
            _check(lib.selfcol_sequence_collide(self._h, first._h, second._h, c, opts),
                   "selfcol_sequence_collide")
        else:
            _check(lib.selfcol_context_sequence_collide(context, self._h, first._h, second._h, c,
                                                        opts),
                   "selfcol_context_sequence_collide")
        self._keep = (first, second)
        return Contacts(c, (first.mesh, second.mesh), d)

    def reset(self) -> None:
        """Forgets the reference (the next frame is a first frame)."""
        lib.selfcol_sequence_reset(self._h)
        self._distance = None
        self._rel_of = ()

    def stats(self) -> Dict[str, Union[int, float, str]]:
        st = ffi.new("selfcol_sequence_run_stats *")
        st.version = lib.SELFCOL_SEQUENCE_RUN_STATS_VERSION
        _check(lib.selfcol_sequence_stats(self._h, st), "selfcol_sequence_stats")
        return {"frames": int(st.frames), "rebuilds": int(st.rebuilds),
                "fresh_frames": int(st.fresh_frames),
                "last_answer": _SEQUENCE_ANSWERS.get(int(st.last_answer), "?"),
                "last_reason": _SEQUENCE_REASONS.get(int(st.last_reason), "?"),
                "last_reason_code": int(st.last_reason), "near_pairs": int(st.near_pairs),
                "skin": float(st.skin), "deformation_ratio": float(st.deformation_ratio),
                "rebuild_seconds": float(st.rebuild_seconds),
                "partial_rebuilds": int(st.partial_rebuilds)}

    @property
    def byte_count(self) -> int:
        return int(lib.selfcol_sequence_byte_count(self._h))


# --------------------------------------------------------------------------
# Continuous queries


_SWEEP_METHODS = {"exhaustive": 0, "bvh": 1, "exact": 4}
_SWEEP_MODES = {"all": 0, "earliest": 1}


def _sweep_options(separation: float, method: Union[str, int], kinds: KindsArg,
                   mode: str, tolerance: Optional[float] = None) -> Any:
    opts = ffi.new("selfcol_sweep_options *")
    _check(lib.selfcol_sweep_options_init(opts, lib.SELFCOL_SWEEP_OPTIONS_VERSION),
           "selfcol_sweep_options_init")
    opts.method = _lookup(_SWEEP_METHODS, method, "sweep method")
    opts.kinds = _kinds_mask(kinds)
    opts.mode = _lookup(_SWEEP_MODES, mode, "sweep mode")
    try:
        opts.separation = float(separation)
    except (TypeError, ValueError):
        raise _invalid("separation must be a number, got %r" % (separation,)) from None
    if tolerance is not None:
        try:
            opts.tolerance = float(tolerance)
        except (TypeError, ValueError):
            raise _invalid("tolerance must be a number, got %r" % (tolerance,)) from None
    _check_options(lib.selfcol_sweep_options_check, opts, "sweep options")
    return opts


class _SweepProgress:
    """The progress of one continuous query (its ALL mode's root searches):
    a callable given by the caller (fraction done -> truthy to cancel), a
    line on standard error (True), or nothing (None); Ctrl-C cancels in
    every case, and the KeyboardInterrupt is raised once the C call has
    returned."""

    def __init__(self, progress: Any) -> None:
        self.progress = progress
        self.error: Optional[BaseException] = None
        self.start = time.perf_counter()

    def step(self, done: float) -> int:
        if callable(self.progress):
            return 1 if self.progress(done) else 0
        if self.progress:
            elapsed = time.perf_counter() - self.start
            left = elapsed * (1 - done) / done if done > 0 else 0.0
            sys.stderr.write("\rselfcol: continuous query %5.1f %%, %.0f s left   "
                             % (100 * done, left))
            if done >= 1.0:
                sys.stderr.write("\n")
            sys.stderr.flush()
        return 0


_progress_now = threading.local()  # the _SweepProgress of this thread's running query


def _progress_failed(exc_type: Any, exc_value: BaseException, tb: Any) -> int:
    # An exception in the callback (Ctrl-C arriving there included): keep it
    # for after the call, and cancel.
    state = getattr(_progress_now, "state", None)
    if state is not None and state.error is None:
        state.error = exc_value
    return 1


@ffi.def_extern(onerror=_progress_failed)  # type: ignore[untyped-decorator]
def _selfcol_sweep_progress(payload: Any, done: float) -> int:
    state: _SweepProgress = ffi.from_handle(payload)
    return state.step(done)


def _run_sweep(opts: Any, progress: Any, call: Any, what: str) -> None:
    """Runs a continuous query with the progress callback installed."""
    state = _SweepProgress(progress)
    handle = ffi.new_handle(state)
    opts.progress = lib._selfcol_sweep_progress
    opts.progress_payload = handle
    _progress_now.state = state
    try:
        status = call()
    finally:
        _progress_now.state = None
    if state.error is not None:
        raise state.error
    _check(status, what)


def _new_sweep() -> Any:
    out = ffi.new("selfcol_sweep **")
    _check(lib.selfcol_sweep_create(out, ffi.NULL), "selfcol_sweep_create")
    return ffi.gc(out[0], lib.selfcol_sweep_destroy)


class Sweep:
    """The result of a continuous query: ``hits`` (structured: kind, first,
    second, first_mesh, second_mesh, a, b, flags, toi), ``vf`` (n, 2)
    [vertex, triangle], ``ee`` (n, 4), ``toi``, ``flags``,
    ``free_fraction`` (the least toi, 1 when nothing collides), ``stats``."""

    INITIAL = SweepFlag.INITIAL
    UNRESOLVED = SweepFlag.UNRESOLVED

    def __init__(self, handle: Any) -> None:
        ptr = ffi.new("selfcol_sweep_hit **")
        cnt = ffi.new("size_t *")
        _check(lib.selfcol_sweep_hits(handle, ptr, cnt), "selfcol_sweep_hits")
        self.hits = _copy_records(ptr[0], int(cnt[0]), SWEEP_HIT_DTYPE)
        st = ffi.new("selfcol_sweep_query_stats *")
        st.version = lib.SELFCOL_SWEEP_STATS_VERSION
        _check(lib.selfcol_sweep_stats(handle, st), "selfcol_sweep_stats")
        self.stats: Dict[str, Union[int, float]] = _stats_dict(st, "selfcol_sweep_query_stats")
        self.free_fraction = float(st.free_fraction)

    def __len__(self) -> int:
        return int(self.hits.shape[0])

    @property
    def earliest_time(self) -> float:
        """The least time of impact (= free_fraction)."""
        return self.free_fraction

    @property
    def toi(self) -> np.ndarray:
        return np.ascontiguousarray(self.hits["toi"])

    @property
    def flags(self) -> np.ndarray:
        return np.ascontiguousarray(self.hits["flags"])

    @property
    def vf(self) -> np.ndarray:
        r = self.hits[self.hits["kind"] == 0]
        return np.stack([r["first"], r["second"]], axis=1).astype(np.int64).reshape(-1, 2)

    @property
    def ee(self) -> np.ndarray:
        r = self.hits[self.hits["kind"] == 1]
        return np.concatenate([r["a"], r["b"][:, :2]], axis=1).astype(np.int64).reshape(-1, 4)

    def __repr__(self) -> str:
        return "selfcol.Sweep(%d hits, free_fraction=%g)" % (len(self), self.free_fraction)


# --------------------------------------------------------------------------
# Store


class StoreContacts:
    """Contacts held by a store (structured ``records``: the fields of
    selfcol_store_contact) and its ``regions`` (selfcol_store_region)."""

    NEW, REMNANT, FLIPPED, CORRECTED, ORIENTED, SETTLED, PASSED_AROUND = (
        1, 2, 4, 8, 16, 32, 64)

    def __init__(self, records: np.ndarray, regions: np.ndarray) -> None:
        self.records = records
        self.regions = regions

    def __len__(self) -> int:
        return int(self.records.shape[0])

    def __getattr__(self, name: str) -> np.ndarray:
        recs = self.__dict__.get("records")
        if recs is not None and name in recs.dtype.names:
            return np.ascontiguousarray(recs[name])
        raise AttributeError(name)

    def __repr__(self) -> str:
        flags = self.records["flags"] if len(self) else np.zeros(0, dtype=np.uint32)
        crossed = int(np.count_nonzero(self.regions["flags"] & 1)) if self.regions.shape[0] else 0
        return ("selfcol.StoreContacts(contacts=%d, regions=%d, crossed_regions=%d, new=%d, "
                "flipped=%d)" % (len(self), int(self.regions.shape[0]), crossed,
                                 int(np.count_nonzero(flags & self.NEW)),
                                 int(np.count_nonzero(flags & self.FLIPPED))))


def _store_read(h: Any) -> StoreContacts:
    n = int(lib.selfcol_store_contact_count(h))
    recs = np.zeros(n, dtype=STORE_CONTACT_DTYPE)
    if n:
        _check(lib.selfcol_store_copy_contacts(h, 0, n, _ptr("selfcol_store_contact *", recs)),
               "selfcol_store_copy_contacts")
    ptr = ffi.new("selfcol_store_region **")
    cnt = ffi.new("size_t *")
    _check(lib.selfcol_store_regions(h, ptr, cnt), "selfcol_store_regions")
    return StoreContacts(recs, _copy_records(ptr[0], int(cnt[0]), REGION_DTYPE))


def _store_stats(h: Any) -> Dict[str, Union[int, float]]:
    st = ffi.new("selfcol_store_update_stats *")
    st.version = lib.SELFCOL_STORE_UPDATE_STATS_VERSION
    _check(lib.selfcol_store_stats(h, st), "selfcol_store_stats")
    return _stats_dict(st, "selfcol_store_update_stats")


def _orientation(value: int, what: str) -> int:
    if value not in (-1, 0, 1):
        raise _invalid("%s must be -1, 0 or +1, got %r" % (what, value))
    return int(value)


def _store_options(remnance: int, consistency: bool, first_orientation: int,
                   second_orientation: int, into: Any = None) -> Any:
    opts = into if into is not None else ffi.new("selfcol_store_options *")
    _check(lib.selfcol_store_options_init(opts, lib.SELFCOL_STORE_OPTIONS_VERSION),
           "selfcol_store_options_init")
    if not isinstance(remnance, (int, np.integer)) or not 0 <= remnance <= 0xFFFFFFFF:
        raise _invalid("remnance must be an integer in [0, 2^32), got %r" % (remnance,))
    opts.remnance_frames = int(remnance)
    opts.consistency = 1 if consistency else 0
    opts.first_orientation = _orientation(first_orientation, "first_orientation")
    opts.second_orientation = _orientation(second_orientation, "second_orientation")
    if into is None:  # a scene's: checked with the scene's options
        _check_options(lib.selfcol_store_options_check, opts, "store options")
    return opts


class Store:
    """The persistent contact store (selfcol_store): remnance, sides tracked
    through crossings, regions and their vote. Feed it each frame's query::

        store.update(hierarchy.self_collide())
    """

    def __init__(self, remnance: int = 4, consistency: bool = True, first_orientation: int = 0,
                 second_orientation: int = 0, threads: int = 1) -> None:
        opts = _store_options(remnance, consistency, first_orientation, second_orientation)
        _context(threads)  # refused here, not at the first update
        out = ffi.new("selfcol_store **")
        _check(lib.selfcol_store_create(out, opts), "selfcol_store_create")
        self._h = ffi.gc(out[0], lib.selfcol_store_destroy)
        self._meshes: Tuple[Mesh, ...] = ()
        self._threads = int(threads)

    def _meshes_of(self, detected: Contacts) -> Tuple[Any, Any]:
        if not isinstance(detected, Contacts):
            raise _invalid("update needs the Contacts returned by a query")
        m = detected._meshes
        return m[0]._h, (m[1]._h if len(m) > 1 else ffi.NULL)

    def update(self, detected: Contacts) -> Dict[str, Union[int, float]]:
        """Merges one frame's query result (selfcol_store_update); returns the
        update's counters."""
        first, second = self._meshes_of(detected)
        context = _context(self._threads)
        if context is None:
            _check(lib.selfcol_store_update(self._h, first, second, detected._h),
                   "selfcol_store_update")
        else:
            _check(lib.selfcol_context_store_update(context, self._h, first, second, detected._h),
                   "selfcol_context_store_update")
        self._meshes = detected._meshes  # the store reads them: keep them alive
        return self.stats()

    def update_swept(self, detected: Contacts, first_start: Any,
                     second_start: Any = None) -> Dict[str, Union[int, float]]:
        """As update(), with the step's start positions: a sign change is a
        crossing only if the continuous test says the elements may have met
        (selfcol_store_update_swept)."""
        first, second = self._meshes_of(detected)
        m = detected._meshes
        S0 = _as_double_positions(first_start, m[0].vertex_count, "first_start")
        S1: Any = ffi.NULL
        keep = None
        if len(m) > 1:
            if second_start is None:
                raise _invalid("update_swept: a two-mesh result needs second_start")
            keep = _as_double_positions(second_start, m[1].vertex_count, "second_start")
            S1 = _ptr("double *", keep)
        elif second_start is not None:
            raise _invalid("update_swept: second_start given for a self query")
        context = _context(self._threads)
        if context is None:
            _check(lib.selfcol_store_update_swept(self._h, first, second, detected._h,
                                                  _ptr("double *", S0), S1),
                   "selfcol_store_update_swept")
        else:
            _check(lib.selfcol_context_store_update_swept(context, self._h, first, second,
                                                          detected._h, _ptr("double *", S0), S1),
                   "selfcol_context_store_update_swept")
        self._meshes = detected._meshes
        del keep
        return self.stats()

    def contacts(self) -> StoreContacts:
        """Copy of the contacts held, with the regions."""
        return _store_read(self._h)

    def regions(self) -> np.ndarray:
        """Copy of the regions (structured: contacts, interferences,
        votes_majority, votes_minority, abstained, oriented, flags)."""
        return _store_read(self._h).regions

    def stats(self) -> Dict[str, Union[int, float]]:
        """Counters of the last update."""
        return _store_stats(self._h)

    def clear(self) -> None:
        """Forgets every contact, region and mesh."""
        lib.selfcol_store_clear(self._h)
        self._meshes = ()

    def __len__(self) -> int:
        return int(lib.selfcol_store_contact_count(self._h))

    @property
    def byte_count(self) -> int:
        return int(lib.selfcol_store_byte_count(self._h))


# --------------------------------------------------------------------------
# Scene


_SURFACE_KINDS = {"cloth": 0, "body": 1, "static": 2}
_SHAPES = {"sphere": 0, "capsule": 1, "box": 2, "convex": 3}


class SceneStore:
    """A scene's store for one pair of surfaces (borrowed; keeps the scene alive)."""

    def __init__(self, scene: "Scene", handle: Any) -> None:
        self._scene = scene
        self._h = handle

    def contacts(self) -> StoreContacts:
        return _store_read(self._h)

    def regions(self) -> np.ndarray:
        return _store_read(self._h).regions

    def stats(self) -> Dict[str, Union[int, float]]:
        return _store_stats(self._h)

    def __len__(self) -> int:
        return int(lib.selfcol_store_contact_count(self._h))


class Scene:
    """Surfaces by kind (cloth, body, static) and convex colliders, with one
    store per pair of surfaces (selfcol_scene). The scene keeps its meshes
    alive while they are surfaces of it."""

    def __init__(self, distance: float = 0.0, method: Union[str, int] = "exact",
                 kinds: KindsArg = "all", threads: int = 1, remnance: int = 4,
                 consistency: bool = True, collider_tolerance: Optional[float] = None,
                 coherent: bool = True) -> None:
        opts = ffi.new("selfcol_scene_options *")
        _check(lib.selfcol_scene_options_init(opts, lib.SELFCOL_SCENE_OPTIONS_VERSION),
               "selfcol_scene_options_init")
        # The scene reads (and copies) the structs its options point to when it
        # is created: q and store need only outlive selfcol_scene_create.
        q = _query_options(distance, method, kinds, "closed")
        store = _store_options(remnance, consistency, 0, 0, into=ffi.new("selfcol_store_options *"))
        context = _context(threads)
        opts.query = q
        opts.store = store
        if collider_tolerance is not None:
            opts.collider_tolerance = float(collider_tolerance)
        opts.coherent = 1 if coherent else 0
        _check_options(lib.selfcol_scene_options_check, opts, "Scene")
        out = ffi.new("selfcol_scene **")
        _check(lib.selfcol_scene_create(out, opts), "selfcol_scene_create")
        self._h = ffi.gc(out[0], lib.selfcol_scene_destroy)
        # threads > 1: the scene's refits, queries and stores run on a context
        # it borrows, kept as long as the scene (its destroy never reads it).
        self._context = context
        if context is not None:
            _check(lib.selfcol_scene_set_context(self._h, context), "selfcol_scene_set_context")
        self._surfaces: Dict[int, Mesh] = {}
        self._retired: List[Mesh] = []

    def add_surface(self, mesh: Mesh, kind: str = "cloth", self_collision: Optional[bool] = None,
                    orientation: Optional[int] = None) -> int:
        """Adds a surface on ``mesh``; returns its id. ``kind``: 'cloth',
        'body' or 'static'; defaults of self_collision and orientation are
        the kind's (selfcol_scene_surface_options_init)."""
        if not isinstance(mesh, Mesh):
            raise _invalid("add_surface needs a selfcol.Mesh")
        k = _lookup(_SURFACE_KINDS, kind, "surface kind")
        opts = ffi.new("selfcol_scene_surface_options *")
        _check(lib.selfcol_scene_surface_options_init(
            opts, k, lib.SELFCOL_SCENE_SURFACE_OPTIONS_VERSION),
            "selfcol_scene_surface_options_init")
        if self_collision is not None:
            opts.self_collision = 1 if self_collision else 0
        if orientation is not None:
            opts.orientation = _orientation(orientation, "orientation")
        out = ffi.new("uint32_t *")
        _check(lib.selfcol_scene_add_surface(self._h, mesh._h, opts, out),
               "selfcol_scene_add_surface")
        self._surfaces[int(out[0])] = mesh
        return int(out[0])

    def remove_surface(self, surface: int) -> None:
        _check(lib.selfcol_scene_remove_surface(self._h, _u32(surface)),
               "selfcol_scene_remove_surface")
        # the header asks the mesh to outlive the scene: keep it until then
        self._retired.append(self._surfaces.pop(int(surface)))

    def rebuild_surface(self, surface: int) -> None:
        _check(lib.selfcol_scene_rebuild_surface(self._h, _u32(surface)),
               "selfcol_scene_rebuild_surface")

    def add_collider(self, shape: str, radius: float = 0.0, half_height: float = 0.0,
                     half_extents: SequenceOf[float] = (0.0, 0.0, 0.0),
                     points: Any = None) -> int:
        """Adds a convex collider ('sphere', 'capsule', 'box' or 'convex'); returns its id."""
        s = _lookup(_SHAPES, shape, "collider shape")
        desc = ffi.new("selfcol_scene_collider_desc *")
        _check(lib.selfcol_scene_collider_desc_init(desc, s,
                                                    lib.SELFCOL_SCENE_COLLIDER_DESC_VERSION),
               "selfcol_scene_collider_desc_init")
        desc.radius = float(radius)
        desc.half_height = float(half_height)
        he = np.asarray(half_extents, dtype=np.float64).reshape(-1)
        if he.shape != (3,):
            raise _invalid("half_extents must have 3 values")
        for i in range(3):
            desc.half_extents[i] = float(he[i])
        keep = None
        if points is not None:
            keep = _as_double_positions(points, np.asarray(points).shape[0], "points")
            desc.points = _ptr("double *", keep)
            desc.point_count = keep.shape[0]
        out = ffi.new("uint32_t *")
        _check(lib.selfcol_scene_add_collider(self._h, desc, out), "selfcol_scene_add_collider")
        del keep
        return int(out[0])

    def set_collider_pose(self, collider: int, position: SequenceOf[float],
                          rotation: Any = None) -> None:
        """Places a collider: position (3,), rotation (3, 3) (identity when None)."""
        p = np.ascontiguousarray(position, dtype=np.float64).reshape(-1)
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=np.float64)
        if p.shape != (3,) or R.shape != (3, 3):
            raise _invalid("position must be (3,) and rotation (3, 3)")
        R = np.ascontiguousarray(R)
        _check(lib.selfcol_scene_set_collider_pose(self._h, _u32(collider), _ptr("double *", p),
                                                   _ptr("double *", R)),
               "selfcol_scene_set_collider_pose")

    def set_surface_start(self, surface: int, positions: Any) -> None:
        """Where a cloth or body surface was at the start of the step that
        the next update() ends ((n, 3), copied): that update then tells a
        crossing from a pass-around on the way (selfcol_scene_set_surface_start).
        Give it again before each update."""
        sid = _u32(surface)
        mesh = self._surfaces.get(int(sid))
        if mesh is None:
            raise _invalid("set_surface_start: no surface %d in this scene" % sid)
        P = _as_double_positions(positions, mesh.vertex_count, "positions")
        _check(lib.selfcol_scene_set_surface_start(self._h, sid, _ptr("double *", P)),
               "selfcol_scene_set_surface_start")

    def update(self) -> Dict[str, Union[int, float]]:
        """Refits, queries every pair and the colliders, updates the stores
        (selfcol_scene_update; GIL released); returns the counters."""
        _check(lib.selfcol_scene_update(self._h), "selfcol_scene_update")
        return self.stats()

    def store(self, first: int, second: Optional[int] = None) -> Optional[SceneStore]:
        """The store of a pair of surfaces (second=None: first with itself);
        None when the scene never tests that pair."""
        a = int(first)
        b = a if second is None else int(second)
        if a > b:
            a, b = b, a
        out = ffi.new("selfcol_store **")
        _check(lib.selfcol_scene_store(self._h, _u32(a), _u32(b), out), "selfcol_scene_store")
        if out[0] == ffi.NULL:
            return None
        return SceneStore(self, out[0])

    def collider_contacts(self) -> np.ndarray:
        """The collider contacts of the last update (structured: collider,
        surface, triangle, flags, distance, wb, normal)."""
        ptr = ffi.new("selfcol_collider_contact **")
        cnt = ffi.new("size_t *")
        _check(lib.selfcol_scene_collider_contacts(self._h, ptr, cnt),
               "selfcol_scene_collider_contacts")
        return _copy_records(ptr[0], int(cnt[0]), COLLIDER_CONTACT_DTYPE)

    def stats(self) -> Dict[str, Union[int, float]]:
        st = ffi.new("selfcol_scene_update_stats *")
        st.version = lib.SELFCOL_SCENE_UPDATE_STATS_VERSION
        _check(lib.selfcol_scene_stats(self._h, st), "selfcol_scene_stats")
        return _stats_dict(st, "selfcol_scene_update_stats")

    @property
    def byte_count(self) -> int:
        return int(lib.selfcol_scene_byte_count(self._h))


def _u32(value: Any) -> int:
    if (not isinstance(value, (int, np.integer)) or isinstance(value, bool)
            or not 0 <= int(value) <= 0xFFFFFFFF):
        raise _invalid("an id must be an integer in [0, 2^32), got %r" % (value,))
    return int(value)


# --------------------------------------------------------------------------
# One-call queries


def self_collide(V: Any, F: Any = None, distance: Optional[float] = None,
                 distance_rel: float = 0.1,
                 method: Union[str, int] = "exact", kinds: KindsArg = "all", threads: int = 1,
                 narrow: Union[str, int] = "closed") -> Contacts:
    """Self-contacts of the surface (V, F), or of a trimesh.Trimesh given as V
    alone: VF and EE proximities closer than
    ``distance`` and EF interferences (docs/contract.md). ``distance=None``:
    ``distance_rel`` x the mean edge length. Builds a Mesh and a Hierarchy;
    for frames of one topology, keep them and call set_positions/refit."""
    return Hierarchy(Mesh(V, F)).self_collide(distance, distance_rel, method, kinds, threads,
                                              narrow)


def collide(V1: Any, F1: Any, V2: Any = None, F2: Any = None, distance: Optional[float] = None,
            distance_rel: float = 0.1, method: Union[str, int] = "exact",
            kinds: KindsArg = "all", threads: int = 1,
            narrow: Union[str, int] = "closed") -> Contacts:
    """Contacts between two surfaces (mesh 0 and mesh 1 in first_mesh and
    second_mesh), not the self-contacts of either: (V1, F1, V2, F2), or two
    trimesh.Trimesh objects ``collide(a, b)``. ``distance=None``:
    ``distance_rel`` x the mean edge length of both (weighted by edges)."""
    if V2 is None and F2 is None and _mesh_like(V1) and _mesh_like(F1):
        h1, h2 = Hierarchy(Mesh(V1)), Hierarchy(Mesh(F1))
    else:
        h1, h2 = Hierarchy(Mesh(V1, F1)), Hierarchy(Mesh(V2, F2))
    return h1.collide(h2, distance, distance_rel, method, kinds, threads, narrow)


def self_sweep(V0: Any, V1: Any, F: Any, separation: float = 0.0,
               method: Union[str, int] = "bvh", kinds: KindsArg = "vf,ee",
               mode: str = "all", threads: int = 1, progress: Any = None,
               tolerance: Optional[float] = None) -> Sweep:
    """Continuous self-query of the surface F moving linearly from V0 (t = 0)
    to V1 (t = 1): every VF/EE pair coming within ``separation``, with
    conservative times of impact and the collision-free fraction.
    ``mode="earliest"`` gives the first time of contact only, much faster;
    ``progress`` and ``tolerance``: see Hierarchy.self_sweep."""
    return Hierarchy(Mesh(V1, F)).self_sweep(V0, separation, method, kinds, mode, threads,
                                             progress, tolerance)
