# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Continuous queries, the store across frames, scenes and colliders."""

import numpy as np
import pytest

import selfcol
from conftest import folded, grid


def sheets():
    A = grid(10, 10, lambda u, v: (u, v, 0 * u))
    return A


def test_sweep_sheet_through_sheet():
    V, F = grid(6, 6)
    Vb = V + [0.05, 0.05, 0.2]
    m1, m2 = selfcol.Mesh(V, F), selfcol.Mesh(Vb - [0, 0, 0.4], F)
    h1, h2 = selfcol.Hierarchy(m1), selfcol.Hierarchy(m2)
    # sheet 2 moves from z = 0.2 to z = -0.2 through sheet 1 (static)
    sw = h1.sweep(V, h2, Vb)
    assert len(sw) > 0
    assert 0.45 < sw.free_fraction <= 0.5 + 1e-9
    assert sw.earliest_time == sw.free_fraction
    ex = h1.sweep(V, h2, Vb, method="exhaustive")
    assert np.array_equal(ex.hits, sw.hits)
    early = h1.sweep(V, h2, Vb, mode="earliest")
    assert len(early) <= 1 and early.free_fraction <= sw.free_fraction + 1e-6
    assert sw.vf.shape[1] == 2 and sw.ee.shape[1] == 4
    assert set(sw.stats) >= {"free_fraction", "candidates", "hits", "total_seconds"}
    # a discrete query at both ends sees nothing: the crossing passes unseen
    assert len(h1.collide(h2, 0.01)) == 0


def test_self_sweep_free_step():
    V, F = folded()
    s = selfcol.self_sweep(V, V + [0.01, 0, 0], F)  # a rigid translation
    assert s.free_fraction == 0.0 or s.free_fraction == 1.0
    V2, F2 = grid(6, 6)
    s2 = selfcol.self_sweep(V2, V2 * 1.1, F2)
    assert len(s2) == 0 and s2.free_fraction == 1.0
    h = selfcol.Hierarchy(selfcol.Mesh(V2 * 1.1, F2))
    assert np.array_equal(h.self_sweep(V2, method="exhaustive").hits, s2.hits)


def test_sweep_tolerance():
    # A coarser root-finder tolerance: the same crossing pairs found (no
    # false negative), in fewer root boxes; out of range is refused.
    V, F = grid(6, 6)
    V0 = np.concatenate([V, V + [0.05, 0.05, 0.2]])
    V1 = np.concatenate([V, V + [0.05, 0.05, -0.2]])
    F2 = np.concatenate([F, F + len(V)])
    fine = selfcol.self_sweep(V0, V1, F2)
    coarse = selfcol.self_sweep(V0, V1, F2, tolerance=1e-3)
    assert len(fine) > 0
    assert set(map(tuple, fine.hits[["kind", "first", "second"]].tolist())) <= \
        set(map(tuple, coarse.hits[["kind", "first", "second"]].tolist()))
    assert coarse.stats["narrow_boxes"] < fine.stats["narrow_boxes"]
    assert coarse.free_fraction <= fine.free_fraction
    with pytest.raises(selfcol.InvalidArgument, match="tolerance"):
        selfcol.self_sweep(V0, V1, F2, tolerance=0.5)


def test_self_sweep_exact_method():
    # EXACT adds the curvature criterion over the step: the same hits as BVH
    # on two sheets passing through each other, and its counters.
    V, F = grid(6, 6)
    V0 = np.concatenate([V, V + [0.05, 0.05, 0.2]])
    V1 = np.concatenate([V, V + [0.05, 0.05, -0.2]])
    F2 = np.concatenate([F, F + len(V)])
    bvh = selfcol.self_sweep(V0, V1, F2, method="bvh")
    exact = selfcol.self_sweep(V0, V1, F2, method="exact")
    assert len(bvh) > 0 and np.array_equal(exact.hits, bvh.hits)
    assert exact.free_fraction == bvh.free_fraction
    assert exact.stats["patches_culled"] >= 1 and bvh.stats["patches_culled"] == 0
    assert exact.stats["candidates"] < bvh.stats["candidates"]


def test_store_across_frames():
    V, F = folded()
    m = selfcol.Mesh(V, F)
    h = selfcol.Hierarchy(m)
    d = 0.3 * m.mean_edge_length()
    s = selfcol.Store(remnance=2)
    st = s.update(h.self_collide(d))
    assert st["new_contacts"] == st["contacts"] > 0
    prev = V
    for k in range(1, 4):
        W = V * (1 + 0.01 * k)
        m.set_positions(W)
        h.refit()
        st = s.update_swept(h.self_collide(d), prev)
        prev = W
    sc = s.contacts()
    assert len(sc) == len(s) == st["contacts"] + st["interferences"]
    assert sc.records["region"].max() < len(sc.regions)
    assert set(np.unique(sc.side)) <= {-1, 0, 1}
    assert sc.signed_distance.shape == (len(sc),)
    assert len(s.regions()) == st["regions"]
    assert s.byte_count > 0
    s.clear()
    assert len(s) == 0


def test_store_threads_hold_the_same_records():
    # Two sheets closer than d: tens of thousands of contacts, enough for
    # the update to split them among threads (store.c: 4096 per chunk).
    V, F = grid(60, 60)
    h1 = selfcol.Hierarchy(selfcol.Mesh(V, F))
    m2 = selfcol.Mesh(V + [0, 0, 0.008], F)
    h2 = selfcol.Hierarchy(m2)
    stores = [selfcol.Store(), selfcol.Store(threads=2), selfcol.Store(threads=3)]
    for k in range(3):
        m2.set_positions(V + [0, 0, 0.008 * (1 + 0.1 * k)])
        h2.refit()
        c = h1.collide(h2, 0.01)
        stats = [s.update(c) for s in stores]
        assert stats[0]["contacts"] > 3 * 4096
        held = [s.contacts() for s in stores]
        for other, st in zip(held[1:], stats[1:]):
            assert np.array_equal(other.records, held[0].records)
            assert np.array_equal(other.regions, held[0].regions)
            assert {k: v for k, v in st.items() if k != "seconds"} == \
                {k: v for k, v in stats[0].items() if k != "seconds"}


def test_store_two_meshes_swept_needs_both_starts():
    V, F = grid(6, 6)
    c = selfcol.collide(V, F, V + [0, 0, 0.01], F, distance=0.05)
    s = selfcol.Store()
    try:
        s.update_swept(c, V)
    except selfcol.InvalidArgument:
        pass
    else:
        raise AssertionError("missing second_start accepted")
    s.update_swept(c, V, V + [0, 0, 0.01])
    assert len(s) > 0


def test_scene_surfaces_and_colliders():
    V, F = grid(12, 12, lambda u, v: (u - 0.5, v - 0.5, 0 * u))
    cloth = selfcol.Mesh(V + [0, 0, 0.3], F)
    floor = selfcol.Mesh(V * 3, F)
    scene = selfcol.Scene(distance=0.02)
    c = scene.add_surface(cloth, "cloth")
    f = scene.add_surface(floor, "static", orientation=1)
    ball = scene.add_collider("sphere", radius=0.25)
    scene.set_collider_pose(ball, (0, 0, 0.05))
    st = scene.update()
    assert st["surfaces"] == 2 and st["colliders"] == 1
    assert st["collider_contacts"] > 0
    cc = scene.collider_contacts()
    assert (cc["collider"] == ball).all() and (cc["surface"] == c).all()
    assert scene.store(c) is not None
    assert scene.store(f) is None  # a static surface is not tested against itself
    # drop the cloth to the floor: contacts between them
    cloth.set_positions(V + [0, 0, 0.01])
    scene.set_collider_pose(ball, (5, 5, 5), np.eye(3))
    scene.update()
    pair = scene.store(f, c)
    assert pair is not None and len(pair) > 0
    assert pair.stats()["contacts"] > 0
    box = scene.add_collider("box", half_extents=(0.1, 0.1, 0.1))
    hull = scene.add_collider("convex", points=np.random.default_rng(0).normal(size=(10, 3)))
    cap = scene.add_collider("capsule", radius=0.1, half_height=0.2)
    assert len({box, hull, cap}) == 3
    scene.remove_surface(c)
    assert scene.update()["surfaces"] == 1


def test_sweep_matches_cli_continuous(tmp_path):
    import os
    import subprocess
    from conftest import ROOT, write_obj
    exe = os.environ.get("SELFCOL_CLI") or os.path.join(ROOT, "build", "tools", "cli",
                                                         "selfcol-cli")
    if not os.access(exe, os.X_OK):
        import pytest
        pytest.skip("selfcol-cli not built")
    V, F = grid(6, 6)
    V0 = np.concatenate([V, V + [0.05, 0.05, 0.2]])
    V1 = np.concatenate([V, V + [0.05, 0.05, -0.2]])
    F2 = np.concatenate([F, F + len(V)])
    write_obj(tmp_path / "s0.obj", V0, F2)
    write_obj(tmp_path / "s1.obj", V1, F2)
    for method in ("bvh", "exhaustive"):
        proc = subprocess.run([exe, "check", "--continuous", "--method", method, "--quiet",
                               "--frames", str(tmp_path / "s0.obj"), str(tmp_path / "s1.obj"),
                               "--csv", "-"], stdout=subprocess.PIPE, timeout=300)
        assert proc.returncode == 1
        # step_from,step_to,kind,i0,i1,i2,i3,toi,flags: VF rows give v, t;
        # EE rows the two edges' vertices (docs/cli.md).
        rows = [r.split(",") for r in proc.stdout.decode().splitlines()[1:]]
        want = {(r[2],) + tuple(int(x) for x in r[3:7] if x != "") + (float(r[7]), int(r[8]))
                for r in rows}
        s = selfcol.self_sweep(V0, V1, F2, method=method)
        got = set()
        for h in s.hits:
            if int(h["kind"]) == 0:
                ids = (int(h["first"]), int(h["second"]))
            else:
                ids = (int(h["a"][0]), int(h["a"][1]), int(h["b"][0]), int(h["b"][1]))
            got.add((("VF", "EE")[int(h["kind"])],) + ids + (float(h["toi"]), int(h["flags"])))
        assert got == want and len(got) == len(s) > 0


def test_store_matches_cli_track(tmp_path):
    import json
    import os
    import subprocess
    import pytest
    from conftest import ROOT, write_obj
    exe = os.environ.get("SELFCOL_CLI") or os.path.join(ROOT, "build", "tools", "cli",
                                                         "selfcol-cli")
    if not os.access(exe, os.X_OK):
        pytest.skip("selfcol-cli not built")
    # two sheets in one mesh; the second sinks through the first in steps
    # smaller than d, so contacts are seen on both sides (flips)
    A, FA = grid(10, 10)
    F = np.concatenate([FA, FA + len(A)])
    frames = []
    for i in range(8):
        z = 0.009 - 0.003 * i
        W = np.concatenate([A, A + [0.031, 0.043, z]])
        W[len(A):, 2] += 0.002 * np.sin(7 * W[len(A):, 0])
        write_obj(tmp_path / ("f%d.obj" % i), W, F)
        frames.append(W)
    proc = subprocess.run([exe, "track", "--quiet", "--jsonl", "-", "--frames"]
                          + [str(tmp_path / ("f%d.obj" % i)) for i in range(8)],
                          stdout=subprocess.PIPE, timeout=300)
    want = [json.loads(line) for line in proc.stdout.decode().splitlines() if line.strip()]
    mesh = selfcol.Mesh(frames[0], F)
    h = selfcol.Hierarchy(mesh)
    d = 0.1 * mesh.mean_edge_length()
    store = selfcol.Store()
    keys = ("contacts", "regions", "new", "kept", "remnant", "dropped", "flipped", "corrected",
            "corrected_regions", "interferences", "crossed_regions")
    rename = {"new": "new_contacts"}
    seen_flip = False
    for i, W in enumerate(frames):
        mesh.set_positions(W)
        h.refit()
        c = h.self_collide(d)
        st = store.update(c)
        assert want[i]["distance"] == d
        assert {k: st[rename.get(k, k)] for k in keys} == {k: want[i][k] for k in keys}
        assert c.counts == want[i]["detected"]
        seen_flip |= st["flipped"] > 0
    assert len(want) == 8 and seen_flip


def test_sequence_equals_fresh_queries():
    # A folded strip closing slowly, frame after frame: the coherent query's
    # records equal a fresh query's on every frame, and most frames come
    # from its near list.
    V, F = folded()
    m = selfcol.Mesh(V, F)
    fresh, coherent = selfcol.Hierarchy(m), selfcol.Hierarchy(m)
    seq = selfcol.Sequence()
    d = 0.1 * selfcol.mean_edge_length(m)
    for k in range(30):
        m.set_positions(V * (1.0 - 0.0005 * k))
        fresh.refit()
        want = fresh.self_collide(d)
        got = seq.self_collide(coherent, d)
        assert len(want) > 0
        assert np.array_equal(got.records, want.records)
    st = seq.stats()
    assert st["frames"] == 30
    assert st["rebuilds"] + st["fresh_frames"] < 10
    assert 0 <= st["partial_rebuilds"] <= st["rebuilds"]
    assert st["last_answer"] in ("list", "rebuilt", "fresh")
    assert seq.byte_count > 0
    seq.reset()
    assert seq.stats()["frames"] == 0
    # SEED's approximate skips no near list reproduces: answered afresh.
    got = seq.self_collide(coherent, d, method="seed")
    fresh.refit()
    assert np.array_equal(got.records, fresh.self_collide(d, method="seed").records)
    st = seq.stats()
    assert st["last_answer"] == "fresh" and st["last_reason"] == "approximate_method"
    assert st["last_reason_code"] == 3


def test_sequence_honours_distance_rel_and_hierarchy():
    """distance=None kept the first call's d for ever: a later distance_rel
    and a second hierarchy on a 10x larger mesh were answered at it."""
    V, F = folded()
    m = selfcol.Mesh(V, F)
    h = selfcol.Hierarchy(m)
    seq = selfcol.Sequence()
    for rel in (0.1, 0.5, 0.1):
        got = seq.self_collide(h, distance_rel=rel)
        want = h.self_collide(distance_rel=rel)
        assert got.distance_used == want.distance_used
        assert np.array_equal(got.records, want.records), rel
    assert len(seq.self_collide(h, distance_rel=0.5)) > len(seq.self_collide(h))
    big = selfcol.Mesh(10 * V, F)
    hb = selfcol.Hierarchy(big)
    got = seq.self_collide(hb)
    want = hb.self_collide()
    assert got.distance_used == want.distance_used and len(want) > 0
    assert np.array_equal(got.records, want.records)
    # While the hierarchy and distance_rel stay, d stays the first frame's
    # (a d that followed the mean edge would restart the sequence).
    d0 = seq.self_collide(h).distance_used
    m.set_positions(V * 1.01)
    assert seq.self_collide(h).distance_used == d0


def test_scene_coherent_option():
    V, F = folded()
    for coherent in (True, False):
        sc = selfcol.Scene(distance=0.01, coherent=coherent)
        m = selfcol.Mesh(V, F)
        sc.add_surface(m)
        sc.update()
        m.set_positions(V * 0.999)
        sc.update()
        assert len(sc.store(0, 0)) > 0


def test_scene_surface_start_tells_a_pass_around():
    # A small triangle passes the plane of a big one beside it: a sign change
    # without contact. Told the step's start, the scene calls it passed
    # around; not told, a crossing (selfcol_scene_set_surface_start).
    A = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    F = np.array([[0, 1, 2]], np.uint32)

    def small(z):
        return np.array([[1.2, 0.2, z], [1.25, 0.2, z], [1.2, 0.25, z]])

    out = {}
    for told in (True, False):
        sc = selfcol.Scene(distance=0.5)
        ma, mb = selfcol.Mesh(A, F), selfcol.Mesh(small(0.1), F)
        ia = sc.add_surface(ma, self_collision=False)
        ib = sc.add_surface(mb, self_collision=False)
        if told:
            sc.set_surface_start(ia, A)
            sc.set_surface_start(ib, small(0.1))
        sc.update()
        mb.set_positions(small(-0.1))
        if told:
            sc.set_surface_start(ia, A)
            sc.set_surface_start(ib, small(0.1))
        out[told] = sc.update()
    assert out[False]["flipped"] > 0 and out[False]["passed_around"] == 0
    assert out[True]["flipped"] == 0
    assert out[True]["passed_around"] == out[False]["flipped"]
    with np.testing.assert_raises(selfcol.InvalidArgument):
        sc.set_surface_start(ib, np.zeros((4, 3)))
