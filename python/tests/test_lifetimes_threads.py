# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Lifetimes (a hierarchy keeps its mesh alive; any deletion order is safe)
and threads (two Python threads querying at once; the GIL is released)."""

import gc
import itertools
import threading
import time
import weakref

import numpy as np
import pytest

import selfcol
from conftest import folded, grid


def test_hierarchy_keeps_mesh_alive():
    V, F = folded()
    m = selfcol.Mesh(V, F)
    ref = weakref.ref(m)
    h = selfcol.Hierarchy(m)
    del m
    gc.collect()
    assert ref() is not None
    c = h.self_collide(distance_rel=0.5)
    assert len(c) > 0
    del h
    gc.collect()
    # collected, or held by c (whose answers then still read it)
    assert ref() is None or len(c.vf) + len(c.ee) + len(c.ef) == len(c)
    del c
    gc.collect()
    assert ref() is None


@pytest.mark.parametrize("order", list(itertools.permutations(range(5)))[::11])
def test_any_deletion_order(order):
    V, F = folded(12, 4)
    objs = {}
    objs[0] = selfcol.Mesh(V, F)
    objs[1] = selfcol.Hierarchy(objs[0])
    objs[2] = objs[1].self_collide(distance_rel=0.5)
    objs[3] = selfcol.Store()
    objs[3].update(objs[2])
    held = len(objs[3])
    assert held > 0
    objs[4] = selfcol.Scene(distance=0.01)
    objs[4].add_surface(objs[0])
    objs[4].update()
    store = objs[4].store(0)
    in_scene = len(store.contacts())
    assert in_scene > 0
    for k in order:
        del objs[k]
        gc.collect()
        # what is left still works
        if 1 in objs:
            objs[1].refit()
            objs[1].self_collide(distance_rel=0.5)
        if 3 in objs:  # the store reads its meshes, which it keeps alive
            assert len(objs[3].contacts()) == held
        if 4 in objs:
            objs[4].update()  # the same positions: the same contacts
    assert len(store.contacts()) == in_scene  # a scene store keeps its scene


def test_results_outlive_their_handles():
    V, F = folded()
    c = selfcol.self_collide(V, F, distance_rel=0.5)
    gc.collect()
    assert len(c.vf) + len(c.ee) + len(c.ef) == len(c)
    s = selfcol.Store()
    s.update(c)  # the result keeps its mesh alive for the store
    del c
    gc.collect()
    assert len(s.contacts()) > 0


def test_two_threads_query_at_once():
    V, F = folded(40, 10)
    m = selfcol.Mesh(V, F)
    h = selfcol.Hierarchy(m)
    ref = {meth: h.self_collide(distance_rel=0.5, method=meth).records
           for meth in ("exact", "bvh")}
    errors = []
    barrier = threading.Barrier(2)

    def work(meth):
        try:
            barrier.wait()
            for _ in range(20):
                c = h.self_collide(distance_rel=0.5, method=meth)
                assert np.array_equal(c.records, ref[meth])
        except Exception as exc:  # reported below
            errors.append(exc)

    ts = [threading.Thread(target=work, args=(m_,)) for m_ in ("exact", "bvh")]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert not errors


def test_gil_released_during_a_query():
    # An exhaustive query of a few thousand triangles takes a while in C; a
    # Python loop in the main thread must keep running meanwhile.
    V, F = grid(40, 40, lambda u, v: (u, v, 0.05 * np.sin(6 * u)))
    h = selfcol.Hierarchy(selfcol.Mesh(V, F))
    t0 = time.perf_counter()
    h.self_collide(distance_rel=0.5, method="exhaustive")
    single = time.perf_counter() - t0
    done = threading.Event()
    inside = []

    def query():
        h.self_collide(distance_rel=0.5, method="exhaustive")
        done.set()

    t = threading.Thread(target=query)
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        if ticks == 1:
            inside.append(time.perf_counter())
    t.join()
    # with the GIL held by the query, the loop would stall for the whole call
    assert ticks > 1000, (ticks, single)


def test_store_keeps_the_meshes_it_follows():
    V, F = folded(12, 4)
    a = selfcol.Hierarchy(selfcol.Mesh(V, F))
    s = selfcol.Store()
    s.update(a.self_collide(distance_rel=0.5))
    ref = weakref.ref(a.mesh)
    b = selfcol.Hierarchy(selfcol.Mesh(V + 3, F))
    with pytest.raises(selfcol.Mismatch):
        s.update(b.self_collide(distance_rel=0.5))  # refused: the store keeps following a
    del a, b
    gc.collect()
    assert ref() is not None  # still held by the store, which reads it
    assert len(s.contacts()) > 0
    s.clear()
    gc.collect()
    assert ref() is None


def test_scene_keeps_removed_meshes_until_it_goes():
    V, F = grid(4, 4)
    scene = selfcol.Scene(distance=0.01)
    m = selfcol.Mesh(V, F)
    ref = weakref.ref(m)
    sid = scene.add_surface(m)
    scene.update()
    scene.remove_surface(sid)
    del m
    gc.collect()
    assert ref() is not None
    scene.update()
    del scene
    gc.collect()
    assert ref() is None
