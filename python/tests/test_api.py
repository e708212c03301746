# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Results of the binding against selfcol-cli (the C API) on the same meshes."""

import os

import numpy as np
import pytest

import selfcol
from conftest import ROOT, folded, grid, write_obj


def as_cli(c, offsets=(0, 0), toffsets=(0, 0)):
    """A Contacts in selfcol-cli's JSON shape (sets; a second mesh's indices offset)."""
    offsets, toffsets = np.asarray(offsets), np.asarray(toffsets)
    oa = offsets[c.first_mesh][:, None]
    ob = offsets[c.second_mesh][:, None]
    ot = toffsets[c.second_mesh]
    a = np.sort(c.a.astype(np.int64) + oa, axis=1)
    b = np.sort(c.b[:, :2].astype(np.int64) + ob, axis=1)
    s = c.second.astype(np.int64) + ot
    k = c.kind
    out = {"vf": set(zip(a[k == 0, 0].tolist(), s[k == 0].tolist())),
           "ef": set(zip(a[k == 2, 0].tolist(), a[k == 2, 1].tolist(), s[k == 2].tolist()))}
    e1, e2 = a[k == 1], b[k == 1]
    swap = (e1[:, 0] > e2[:, 0]) | ((e1[:, 0] == e2[:, 0]) & (e1[:, 1] > e2[:, 1]))
    lo = np.where(swap[:, None], e2, e1)
    hi = np.where(swap[:, None], e1, e2)
    out["ee"] = set(map(tuple, np.concatenate([lo, hi], axis=1).tolist()))
    return out


def cli_sets(obj):
    return {k: {tuple(x) for x in obj[k]} for k in ("vf", "ee", "ef")}


def test_version():
    assert selfcol.version() == selfcol.__version__ == "0.4.0"


def test_bundled_ribbon_matches_cli(cli):
    path = os.path.join(ROOT, "tests", "data", "folded_ribbon.obj")
    from selfcol.io import read_mesh
    V, F = read_mesh(path)
    c = selfcol.self_collide(V, F)
    want = cli(path)[0]
    assert c.counts == {"vf": 96, "ee": 280, "ef": 48}
    assert as_cli(c) == cli_sets(want)
    assert c.distance_used == pytest.approx(want["distance"], rel=1e-15)
    assert c.intersecting_triangles().tolist() == want["intersecting_triangles"]
    assert c.stats["vf_contacts"] == 96 and c.stats["ef_contacts"] == 48


@pytest.mark.parametrize("method", ["exact", "bvh", "exhaustive"])
def test_generated_matches_cli(cli, tmp_path, method):
    V, F = folded()
    path = tmp_path / "f.obj"
    write_obj(path, V, F)
    c = selfcol.self_collide(V, F, distance_rel=0.5, method=method)
    want = cli(path, "--distance-rel", 0.5, "--method", method)[0]
    assert as_cli(c) == cli_sets(want)
    assert len(c) > 0


def test_two_meshes_match_cli(cli, tmp_path):
    V1, F1 = folded(seed=1)
    V2, F2 = grid(8, 8, lambda u, v: (u - 0.5, v - 0.2, 0.02 + 0.1 * u))
    write_obj(tmp_path / "a.obj", V1, F1)
    write_obj(tmp_path / "b.obj", V2, F2)
    want = cli_sets(cli(tmp_path / "a.obj", tmp_path / "b.obj")[0])
    m1, m2 = selfcol.Mesh(V1, F1), selfcol.Mesh(V2, F2)
    d = 0.1 * selfcol.mean_edge_length(m1, m2)
    h1, h2 = selfcol.Hierarchy(m1), selfcol.Hierarchy(m2)
    got = {"vf": set(), "ee": set(), "ef": set()}
    offs, toffs = (0, len(V1)), (0, len(F1))
    for part in (as_cli(h1.self_collide(d)), as_cli(h2.self_collide(d), (len(V1),) * 2,
                                                   (len(F1),) * 2),
                 as_cli(h1.collide(h2, d), offs, toffs)):
        for k in got:
            got[k] |= part[k]
    assert got == want
    c = selfcol.collide(V1, F1, V2, F2)
    assert c.distance_used == pytest.approx(d, rel=1e-15)
    assert set(np.unique(c.first_mesh)) | set(np.unique(c.second_mesh)) <= {0, 1}


def test_real_frames_match_cli(cli, shared_data):
    frame = os.path.join(shared_data, "sample-scalable-ccd-data", "cloth-ball", "frames",
                         "cloth_ball92.ply")
    if not os.path.exists(frame):
        pytest.skip("no cloth-ball frame")
    from selfcol.io import read_mesh
    V, F = read_mesh(frame)
    c = selfcol.self_collide(V, F)
    want = cli(frame)[0]
    assert as_cli(c) == cli_sets(want)
    assert c.counts["ef"] > 0
    assert c.intersecting_triangles().tolist() == want["intersecting_triangles"]
    # float32 positions (the file's precision) give the same sets
    c32 = selfcol.self_collide(V.astype(np.float32), F)
    assert as_cli(c32) == cli_sets(want)


def test_record_fields_consistent():
    V, F = folded()
    c = selfcol.self_collide(V, F, distance_rel=0.5)
    n = len(c)
    assert c.kind.shape == (n,) and c.a.shape == (n, 2) and c.b.shape == (n, 3)
    assert c.wa.shape == (n, 2) and c.wb.shape == (n, 3) and c.direction.shape == (n, 3)
    vf = c.slice("vf")
    # closest points: the weights reproduce the distance along the direction
    pa = (c.wa[vf, :, None] * V[c.a[vf]]).sum(1)
    pb = (c.wb[vf, :, None] * V[c.b[vf]]).sum(1)
    np.testing.assert_allclose(np.linalg.norm(pa - pb, axis=1), c.distance[vf], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(c.direction, axis=1), 1.0, atol=1e-12)
    assert (c.distance[c.slice("ef")] == 0).all()
    assert c.vf.shape[1] == 2 and c.ee.shape[1] == 4 and c.ef.shape[1] == 3
    assert c.vf.shape[0] + c.ee.shape[0] + c.ef.shape[0] == n
    assert set(c.stats) >= {"candidate_pairs", "total_seconds", "vf_contacts", "sort_seconds"}


def test_input_layouts_give_identical_results():
    V, F = folded()
    ref = selfcol.self_collide(V, F, distance_rel=0.3)
    V32 = V.astype(np.float32)
    variants = [
        (V, F.astype(np.int64)), (V, F.astype(np.uint32)), (V, F.astype(np.int16)),
        (np.asfortranarray(V), F), (V.tolist(), F.tolist()),
    ]
    for Vx, Fx in variants:
        c = selfcol.self_collide(Vx, Fx, distance_rel=0.3)
        assert np.array_equal(c.records, ref.records)
    # float32 in place, also as the first 3 columns of an (n, 4) array (strided rows)
    V4 = np.zeros((len(V), 4), dtype=np.float32)
    V4[:, :3] = V32
    a = selfcol.self_collide(V32, F, distance_rel=0.3)
    b = selfcol.self_collide(V4[:, :3], F, distance_rel=0.3)
    assert np.array_equal(a.records, b.records)


def test_kinds_and_threads():
    V, F = folded()
    full = selfcol.self_collide(V, F, distance_rel=0.5)
    for kinds, keep in (("vf", 0), (["ee"], 1), ("ef", 2), (selfcol._core._KINDS["ee"], 1)):
        c = selfcol.self_collide(V, F, distance_rel=0.5, kinds=kinds)
        assert np.array_equal(c.records, full.records[full.records["kind"] == keep])
    t = selfcol.self_collide(V, F, distance_rel=0.5, threads=2)
    assert np.array_equal(t.records, full.records)


def test_hierarchy_refit_threads_find_the_same_contacts():
    # Two wavy 70 x 70 sheets 0.001 apart in one mesh (19,600 triangles:
    # up to four refit workers, one per 4096 triangles).
    def layers(k):
        V, F = grid(70, 70, lambda u, v: (u, v, 0.05 * np.sin(9 * u + k) * np.cos(7 * v)))
        return np.concatenate([V, V + [0, 0, 0.001]]), np.concatenate([F, F + len(V)])
    mesh = selfcol.Mesh(*layers(0))
    one, two = selfcol.Hierarchy(mesh), selfcol.Hierarchy(mesh, threads=2)
    folded_sheet = selfcol.Mesh(*folded())
    for k in range(3):
        mesh.set_positions(layers(0.5 * k)[0])
        one.refit()
        two.refit()
        a, b = one.self_collide(), two.self_collide()
        assert len(a) > 0
        assert np.array_equal(a.records, b.records)
    for bad in (0, -1, 1.5, True):
        try:
            selfcol.Hierarchy(folded_sheet, threads=bad)
        except selfcol.InvalidArgument:
            pass
        else:
            raise AssertionError("threads=%r accepted" % (bad,))


def test_frames_with_handles():
    V, F = folded()
    mesh = selfcol.Mesh(V, F)
    h = selfcol.Hierarchy(mesh)
    d = 0.3 * mesh.mean_edge_length()
    for s in (1.0, 1.05, 0.97):
        mesh.set_positions(V * s)
        h.refit()
        c = h.self_collide(d, method="bvh")
        want = selfcol.self_collide(V * s, F, distance=d, method="exhaustive")
        assert np.array_equal(c.records, want.records)
    mesh.set_positions((V * 1.01).astype(np.float32))
    assert np.allclose(mesh.positions, (V * 1.01).astype(np.float32))
    assert mesh.count("triangles") == len(F) and mesh.count("vertices") == len(V)
    assert mesh.edges.shape == (mesh.count("edges"), 2)
    assert np.array_equal(mesh.triangles, F)
    assert h.count("nodes") > h.count("leaves") > 0 and h.byte_count > 0


def test_read_only_and_reversed_inputs():
    V, F = folded()
    ref = selfcol.self_collide(V, F, distance_rel=0.3)
    Vr, Fr = V.copy(), F.copy()
    Vr.setflags(write=False)
    Fr.setflags(write=False)
    assert np.array_equal(selfcol.self_collide(Vr, Fr, distance_rel=0.3).records, ref.records)
    # negative strides are converted (once), not misread
    W = V[::-1].copy()[::-1]
    assert np.array_equal(selfcol.self_collide(W, F, distance_rel=0.3).records, ref.records)
    W32 = V.astype(np.float32)[::-1][::-1]
    c32 = selfcol.self_collide(W32, F, distance_rel=0.3)
    assert np.array_equal(c32.records, selfcol.self_collide(V.astype(np.float32), F,
                                                            distance_rel=0.3).records)


def _intersecting_triangles_by_edges(c, mesh):
    """The per-edge definition, through selfcol_mesh_edge_triangles (the
    C topology, as selfcol-cli derives its pairs): each triangle on a crossing
    edge paired with each triangle that edge crosses, sorted and unique."""
    from selfcol._core import ffi, lib
    r = c.records[c.slice("ef")]
    ptr, cnt = ffi.new("uint32_t **"), ffi.new("size_t *")
    pairs = set()
    for e, t in zip(r["first"].tolist(), r["second"].tolist()):
        assert lib.selfcol_mesh_edge_triangles(mesh._h, e, ptr, cnt) == 0
        for u in ffi.unpack(ptr[0], int(cnt[0])):
            if u != t:
                pairs.add((min(u, t), max(u, t)))
    return sorted(pairs)


def test_intersecting_triangles_vectorised_equals_per_edge():
    # A folded strip through itself, plus a non-manifold fin (three triangles
    # on one edge), a triangle with a repeated corner and a duplicate
    # triangle, all crossing the strip.
    V, F = folded()
    n = len(V)
    extra_v = np.array([[0.0, 0.3, -0.5], [0.0, 0.3, 0.5], [0.4, 0.3, 0.0],
                        [-0.4, 0.3, 0.0], [0.0, 0.6, 0.0]])
    extra_f = np.array([[n, n + 1, n + 2], [n, n + 1, n + 3], [n, n + 1, n + 4],
                        [n, n, n + 2], [n, n + 1, n + 2]])
    V2 = np.vstack([V, extra_v])
    F2 = np.vstack([F, extra_f]).astype(np.int64)
    for VV, FF in ((V, F), (V2, F2)):
        mesh = selfcol.Mesh(VV, FF)
        c = selfcol.Hierarchy(mesh).self_collide()
        got = c.intersecting_triangles()
        assert c.counts["ef"] > 0
        assert got.tolist() == [list(p) for p in _intersecting_triangles_by_edges(c, mesh)]
        assert np.array_equal(c.intersecting_triangles(), got)  # the cached table


def test_results_are_plain_python_objects():
    """Mesh and Contacts pickle (multiprocessing, joblib, Dask), Contacts
    iterates over dicts and has to_dict (JSON-ready), StoreContacts prints
    what it holds."""
    import json
    import pickle
    V, F = folded()
    mesh = selfcol.Mesh(V, F)
    c = selfcol.Hierarchy(mesh).self_collide()
    assert c.counts["ef"] > 0 and c.counts["ee"] > 0
    m2 = pickle.loads(pickle.dumps(mesh))
    assert np.array_equal(m2.positions, mesh.positions)
    assert np.array_equal(m2.triangles, mesh.triangles)
    c2 = pickle.loads(pickle.dumps(c))
    assert len(c2) == len(c) and c2.counts == c.counts
    assert np.array_equal(c2.records, c.records)
    assert c2.stats == c.stats and c2.distance_used == c.distance_used
    assert np.array_equal(c2.intersecting_triangles(), c.intersecting_triangles())
    assert np.array_equal(c2.ee, c.ee) and repr(c2) == repr(c)
    rows = list(c)
    assert len(rows) == len(c)
    assert [r["kind"] for r in rows].count("ef") == c.counts["ef"]
    first_ee = rows[c.slice("ee").start]
    assert first_ee["a"] + first_ee["b"] == c.ee[0].tolist()
    d = c.to_dict()
    assert json.loads(json.dumps(d))["counts"] == c.counts
    assert d["ef"] == c.ef.tolist() and len(d["vf_distance"]) == c.counts["vf"]
    store = selfcol.Store()
    store.update(c)
    text = repr(store.contacts())
    assert text.startswith("selfcol.StoreContacts(contacts=%d, regions=" % len(store))
    assert "object at" not in text


def test_mesh_like_objects():
    """A trimesh.Trimesh (any object with .vertices and .faces) alone in
    place of (V, F): the same contacts; mean_edge_length takes arrays too."""
    import types
    V, F = folded(12, 5)
    like = types.SimpleNamespace(vertices=V, faces=F)
    ref = selfcol.self_collide(V, F)
    got = selfcol.self_collide(like)
    assert np.array_equal(got.records, ref.records) and ref.counts["ef"] + ref.counts["vf"] > 0
    assert selfcol.mean_edge_length(V, F) == selfcol.mean_edge_length(like)
    assert selfcol.mean_edge_length(V, F) == selfcol.mean_edge_length(selfcol.Mesh(V, F))
    W = V + np.array([0.0, 0.0, 0.01])
    other = types.SimpleNamespace(vertices=W, faces=F)
    assert np.array_equal(selfcol.collide(like, other).records,
                          selfcol.collide(V, F, W, F).records)
    with pytest.raises(selfcol.InvalidArgument, match="F is missing"):
        selfcol.Mesh(V)
    try:
        import trimesh
    except ImportError:
        return
    t = trimesh.Trimesh(vertices=V, faces=F, process=False)
    assert np.array_equal(selfcol.self_collide(t).records, ref.records)


def test_sweep_progress_and_cancel():
    """A continuous query's progress callback sees fractions rising to 1 and
    the same hits as without; returning True cancels (selfcol.Cancelled);
    an exception in the callback (Ctrl-C's KeyboardInterrupt included) stops
    the query and is raised after it."""
    V, F = folded(60, 12)
    W = V + np.array([0.0, 0.0, 0.3]) * np.sin(np.arange(V.shape[0]))[:, None]
    ref = selfcol.self_sweep(V, W, F, separation=0.01)
    seen = []
    got = selfcol.self_sweep(V, W, F, separation=0.01, progress=lambda f: seen.append(f))
    assert np.array_equal(got.hits, ref.hits) and ref.hits.shape[0] > 0
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(selfcol.Cancelled):
        selfcol.self_sweep(V, W, F, separation=0.01, progress=lambda f: True)

    def interrupt(fraction):
        raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        selfcol.self_sweep(V, W, F, separation=0.01, progress=interrupt)
    # The hierarchy still answers afterwards.
    assert np.array_equal(selfcol.self_sweep(V, W, F, separation=0.01).hits, ref.hits)


def test_enums():
    """Kind, Method and SweepFlag name the C library's numbers."""
    V, F = folded()
    c = selfcol.self_collide(V, F, method=selfcol.Method.EXACT)
    assert np.array_equal(c.records, selfcol.self_collide(V, F, method="exact").records)
    kinds = c.records["kind"]
    assert (kinds == selfcol.Kind.EF).sum() == c.counts["ef"] > 0
    assert [int(k) for k in selfcol.Kind] == [0, 1, 2]
    assert selfcol.Sweep.INITIAL == selfcol.SweepFlag.INITIAL == 1
    with pytest.raises(selfcol.InvalidArgument):
        selfcol.self_collide(V, F, method=7)


def _read_png_rgb(path):
    """Decodes an 8-bit RGB, non-interlaced PNG (every filter type: libpng
    picks them row by row) into an (height, width, 3) uint8 array."""
    import struct
    import zlib
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert (depth, colour, interlace) == (8, 2, 0)
    raw = zlib.decompress(idat)
    stride = 3 * width
    out = np.zeros((height, stride), dtype=np.int64)
    previous = np.zeros(stride, dtype=np.int64)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        row = np.frombuffer(raw, dtype=np.uint8, count=stride,
                            offset=y * (stride + 1) + 1).astype(np.int64)
        if kind in (0, 2):
            row = (row + (previous if kind == 2 else 0)) % 256
        else:  # sub, average and Paeth read the pixel to the left: one byte at a time
            for x in range(stride):
                a = row[x - 3] if x >= 3 else 0
                b, c = previous[x], previous[x - 3] if x >= 3 else 0
                if kind == 1:
                    pred = a
                elif kind == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                row[x] = (row[x] + pred) % 256
        out[y] = previous = row
    return out.astype(np.uint8).reshape(height, width, 3)


def test_picture_matches_the_cli(cli, tmp_path):
    """render() draws selfcol-cli check --png's picture pixel for pixel (its
    --size and --view); write_png's file holds those pixels."""
    from selfcol.io import read_mesh
    path = os.path.join(ROOT, "tests", "data", "folded_ribbon.obj")
    V, F = read_mesh(path)
    c = selfcol.self_collide(V, F)
    picture = c.render(160, 120, azimuth=20.0, elevation=40.0)
    assert picture.shape == (120, 160, 3) and picture.dtype == np.uint8
    theirs = tmp_path / "cli.png"
    cli("--png", theirs, "--size", "160x120", "--view", "20,40", path)
    assert (picture == _read_png_rgb(theirs)).all()
    # Red (intersecting) and amber (near) pixels are both there, on white.
    flat = picture.reshape(-1, 3).astype(int)
    red, green, blue = flat[:, 0], flat[:, 1], flat[:, 2]
    assert ((red > 100) & (green < 50) & (blue < 50)).any()
    assert ((red > 100) & (green > 70) & (blue < 40)).any()
    assert (flat == 255).all(axis=1).any()
    ours = tmp_path / "ours.png"
    c.write_png(str(ours), 160, 120, 20.0, 40.0)
    assert (_read_png_rgb(ours) == picture).all()
    # Two meshes, drawn together: the marks are this query's, so a copy
    # lifted half through the ribbon shows red, one far away none (the CLI
    # marks each mesh's self-contacts too, so its picture is not the same).
    def marked(rgb):
        r, g, b = (rgb.reshape(-1, 3).astype(int)[:, k] for k in range(3))
        return ((r > 100) & (b < 50) & ((g < 50) | (g > 70))).sum()
    lifted = selfcol.collide(V, F, V + np.array([0.0, 0.05, 0.0]), F)
    assert lifted.counts["ef"] > 0 and marked(lifted.render(160, 120)) > 0
    apart = selfcol.collide(V, F, V + np.array([0.0, 50.0, 0.0]), F)
    assert sum(apart.counts.values()) == 0
    far = apart.render(160, 120)
    assert marked(far) == 0 and (far.reshape(-1, 3) != 255).any(axis=1).any()
    for bad in ({"width": 15}, {"height": 4097}, {"width": 100.0}, {"azimuth": float("nan")}):
        with pytest.raises(selfcol.InvalidArgument):
            c.render(**bad)


def test_marked_mesh_matches_the_cli(cli, tmp_path):
    """write_marked writes the PLY of selfcol-cli check --mark, byte for byte
    but its comment line; triangle_classes is its marking."""
    from selfcol.io import read_mesh
    path = os.path.join(ROOT, "tests", "data", "folded_ribbon.obj")
    V, F = read_mesh(path)
    c = selfcol.self_collide(V, F)
    classes = c.triangle_classes()
    assert classes.shape == (F.shape[0],) and set(np.unique(classes)) <= {0, 1, 2}
    assert (classes == 2).sum() > 0 and (classes == 1).sum() > 0
    # Every intersecting pair's triangles are marked 2.
    assert (classes[c.intersecting_triangles().ravel()] == 2).all()
    ours = tmp_path / "ours.ply"
    c.write_marked(str(ours))
    theirs = tmp_path / "cli.ply"
    cli("--mark", theirs, path)  # selfcol-cli check --json - --mark cli.ply ribbon
    strip = lambda p: [x for x in p.read_bytes().split(b"\n")  # noqa: E731
                       if not x.startswith(b"comment")]
    assert strip(ours) == strip(theirs)
    W = V + np.array([0.0, 0.0, 1e3])
    a, b = selfcol.collide(V, F, W, F).triangle_classes()
    assert a.shape == b.shape == (F.shape[0],) and a.max() == 0 and b.max() == 0
