# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Every error path: clear exceptions, never a crash."""

import numpy as np
import pytest

import selfcol
from selfcol._core import _check
from selfcol._selfcol_cffi import lib
from conftest import folded, grid


def test_hierarchy_of_exceptions():
    assert issubclass(selfcol.InvalidArgument, ValueError)
    assert issubclass(selfcol.InvalidArgument, selfcol.Error)
    assert issubclass(selfcol.OutOfMemory, MemoryError)
    assert issubclass(selfcol.RangeError, ValueError)
    for status, cls in ((lib.SELFCOL_EINVAL, selfcol.InvalidArgument),
                        (lib.SELFCOL_ENOMEM, selfcol.OutOfMemory),
                        (lib.SELFCOL_EVERSION, selfcol.VersionError),
                        (lib.SELFCOL_ERANGE, selfcol.RangeError),
                        (lib.SELFCOL_EMISMATCH, selfcol.Mismatch),
                        (lib.SELFCOL_ESTALE, selfcol.StaleHierarchy),
                        (lib.SELFCOL_ERROR, selfcol.Error),
                        (-1234, selfcol.Error)):
        with pytest.raises(cls) as info:
            _check(status, "call")
        assert info.value.status == status
        assert "call" in str(info.value)


V, F = grid(3, 3)


@pytest.mark.parametrize("Vbad", [
    np.zeros((4, 2)), np.zeros(12), np.zeros((0, 3)), np.array([["a", "b", "c"]] * 16),
    np.zeros((16, 3), dtype=complex), np.zeros((16, 3), dtype=bool), [[1, 2]],
])
def test_bad_positions(Vbad):
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.self_collide(Vbad, F)


@pytest.mark.parametrize("Fbad", [
    np.zeros((2, 4), dtype=int), np.zeros((0, 3), dtype=int), F.astype(float) + 0.5,
    -F - 1, F + 100, np.array([["x", "y", "z"]]),
])
def test_bad_triangles(Fbad):
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.self_collide(V, Fbad)


def test_index_too_large():
    with pytest.raises(selfcol.RangeError):
        selfcol.Mesh(V, np.array([[0, 1, 2**33]]))


def test_non_finite_and_range():
    for bad in (np.nan, np.inf, -np.inf):
        W = V.copy()
        W[3, 1] = bad
        with pytest.raises(selfcol.InvalidArgument) as info:
            selfcol.Mesh(W, F)
        assert info.value.status == lib.SELFCOL_EINVAL
    W = V.copy()
    W[0, 0] = 1e300
    with pytest.raises(selfcol.RangeError):
        selfcol.Mesh(W, F)


def test_set_positions_errors_keep_the_mesh():
    m = selfcol.Mesh(V, F)
    with pytest.raises(selfcol.InvalidArgument):
        m.set_positions(V[:-1])
    W = V.copy()
    W[0, 0] = np.nan
    with pytest.raises(selfcol.InvalidArgument):
        m.set_positions(W)
    assert np.array_equal(m.positions, V)


@pytest.mark.parametrize("kw", [
    {"method": "fast"}, {"method": 99}, {"kinds": "vf,xx"}, {"kinds": ""}, {"kinds": 1 << 7},
    {"distance": -1.0}, {"distance": float("nan")}, {"distance": "far"}, {"threads": 0},
    {"threads": 65}, {"threads": 1.5}, {"narrow": "gjk"},
    # silently masked to VF, or an OverflowError, before 0.4
    {"kinds": 2**32 + 1}, {"kinds": 0}, {"kinds": -1}, {"method": -1}, {"method": 2**40},
    {"method": 5}, {"narrow": 2**33},
])
def test_bad_query_options(kw):
    h = selfcol.Hierarchy(selfcol.Mesh(V, F))
    with pytest.raises(selfcol.InvalidArgument):
        h.self_collide(**kw)


def test_stale_hierarchy():
    m = selfcol.Mesh(V, F)
    h = selfcol.Hierarchy(m)
    m.set_positions(V * 2)
    with pytest.raises(selfcol.StaleHierarchy) as info:
        h.self_collide(0.1, method="bvh")
    assert info.value.status == lib.SELFCOL_ESTALE
    h.refit()
    h.self_collide(0.1, method="bvh")


def test_collide_same_mesh_and_bad_handles():
    m = selfcol.Mesh(V, F)
    h1, h2 = selfcol.Hierarchy(m), selfcol.Hierarchy(m)
    with pytest.raises(selfcol.InvalidArgument):
        h1.collide(h2)
    with pytest.raises(selfcol.InvalidArgument):
        h1.collide("not a hierarchy")
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.Hierarchy(V)


def test_store_mismatch():
    a, b = selfcol.Hierarchy(selfcol.Mesh(V, F)), selfcol.Hierarchy(selfcol.Mesh(V + 5, F))
    s = selfcol.Store()
    s.update(a.self_collide(0.1))
    with pytest.raises(selfcol.Mismatch):
        s.update(b.self_collide(0.1))
    with pytest.raises(selfcol.InvalidArgument):
        s.update("contacts")
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.Store(first_orientation=2)
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.Store(remnance=-1)
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.Store(threads=0)


def test_sweep_errors():
    h = selfcol.Hierarchy(selfcol.Mesh(V, F))
    with pytest.raises(selfcol.InvalidArgument):
        h.self_sweep(V[:-1])
    with pytest.raises(selfcol.InvalidArgument):
        h.self_sweep(V, method="seed")
    with pytest.raises(selfcol.InvalidArgument):
        h.self_sweep(V, mode="soon")
    with pytest.raises(selfcol.InvalidArgument):
        h.self_sweep(V, separation=-1)
    W = V.copy()
    W[0, 0] = np.inf
    with pytest.raises(selfcol.InvalidArgument):
        h.self_sweep(W)


def test_scene_errors():
    s = selfcol.Scene(distance=0.01)
    m = selfcol.Mesh(V, F)
    with pytest.raises(selfcol.InvalidArgument):
        s.add_surface(m, kind="liquid")
    with pytest.raises(selfcol.InvalidArgument):
        s.add_surface(m, kind="static", self_collision=True)
    with pytest.raises(selfcol.InvalidArgument):
        s.remove_surface(7)
    with pytest.raises(selfcol.InvalidArgument):
        s.remove_surface(-1)
    with pytest.raises(selfcol.InvalidArgument):
        s.add_collider("sphere", radius=-1)
    with pytest.raises(selfcol.InvalidArgument):
        s.add_collider("cone")
    with pytest.raises(selfcol.InvalidArgument):
        s.set_collider_pose(3, (0, 0, 0))
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.Scene(distance=-1)
    with pytest.raises(selfcol.InvalidArgument):
        s.store(0, 9)


def test_intersecting_triangles_needs_self_query():
    V1, F1 = folded()
    c = selfcol.collide(V1, F1, V1 + 0.01, F1)
    with pytest.raises(selfcol.InvalidArgument):
        c.intersecting_triangles()


def test_mesh_errors_name_the_element():
    """A coordinate of 1e300 was "count or index out of the supported range";
    a bad index "invalid argument or input data": both name the culprit."""
    W = V.astype(np.float64).copy()
    W[4, 2] = 1e300
    with pytest.raises(selfcol.RangeError, match=r"V\[4, 2\] = 1e\+300 is beyond the largest "
                       r"coordinate magnitude 2\^200"):
        selfcol.Mesh(W, F)
    W[4, 2] = 1e-310
    with pytest.raises(selfcol.RangeError, match=r"V\[4, 2\] = 1e-310 is below the smallest"):
        selfcol.Mesh(W, F)
    W[4, 2] = np.nan
    with pytest.raises(selfcol.InvalidArgument, match=r"V\[4, 2\] = nan is not finite"):
        selfcol.Mesh(W, F)
    G = F.astype(np.int64).copy()
    G[3, 1] = len(V) + 5
    with pytest.raises(selfcol.InvalidArgument,
                       match=r"F\[3, 1\] = %d is not a row of V \(%d vertices\)"
                       % (len(V) + 5, len(V))):
        selfcol.Mesh(V, G)
    m = selfcol.Mesh(V, F)
    W = V.astype(np.float32).copy()
    W[2, 0] = np.inf
    with pytest.raises(selfcol.InvalidArgument, match=r"V\[2, 0\] = inf is not finite"):
        m.set_positions(W)


@pytest.mark.parametrize("call, names", [
    (lambda: selfcol.self_collide(V, F, distance=float("nan")),
     "selfcol_query_options.distance = nan"),
    (lambda: selfcol.self_collide(V, F, distance=1e200), "selfcol_query_options.distance = 1e+200"),
    (lambda: selfcol.self_collide(V, F, threads=100), "selfcol_context_options.threads = 100"),
    (lambda: selfcol.Hierarchy(selfcol.Mesh(V, F), threads=65),
     "selfcol_context_options.threads = 65"),
    (lambda: selfcol.Hierarchy(selfcol.Mesh(V, F)).self_sweep(V, separation=-1),
     "selfcol_sweep_options.separation = -1"),
    (lambda: selfcol.Hierarchy(selfcol.Mesh(V, F)).self_sweep(V, threads=99),
     "selfcol_context_options.threads = 99"),
    (lambda: selfcol.Sequence(skin=float("inf")), "selfcol_sequence_options.skin = inf"),
    (lambda: selfcol.Store(threads=70), "selfcol_context_options.threads = 70"),
    (lambda: selfcol.Scene(distance=0.1, threads=80), "selfcol_context_options.threads = 80"),
    (lambda: selfcol.Scene(distance=0.0), "selfcol_scene_options.query->distance = 0"),
    (lambda: selfcol.Scene(distance=0.1, collider_tolerance=-1.0),
     "selfcol_scene_options.collider_tolerance = -1"),
])
def test_refused_options_are_named(call, names):
    """Options the C library refuses are named by its own check
    (selfcol_*_options_check): the struct, the field and the value."""
    with pytest.raises(selfcol.InvalidArgument) as info:
        call()
    assert names in str(info.value)
    assert "invalid argument or input data" not in str(info.value)
