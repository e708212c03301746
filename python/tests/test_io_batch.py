# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The readers and python -m selfcol.batch (on a 2-worker LocalCluster)."""

import json
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

import selfcol
from selfcol import batch
from selfcol.io import read_mesh
from conftest import folded, grid, write_obj


def write_ply(path, V, F, fmt="ascii"):
    head = ("ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
            "end_header\n" % (fmt, len(V), len(F)))
    with open(path, "wb") as fh:
        fh.write(head.encode())
        if fmt == "ascii":
            for p in V:
                fh.write(("%.17g %.17g %.17g\n" % tuple(p)).encode())
            for t in F:
                fh.write(("3 %d %d %d\n" % tuple(t)).encode())
        else:
            bo = "<" if fmt == "binary_little_endian" else ">"
            for p in V:
                fh.write(struct.pack(bo + "3f", *p))
            for t in F:
                fh.write(struct.pack(bo + "B3i", 3, *t))


@pytest.mark.parametrize("fmt", ["ascii", "binary_little_endian", "binary_big_endian"])
def test_ply_reader(tmp_path, fmt):
    V, F = folded()
    V = V.astype(np.float32).astype(np.float64)
    write_ply(tmp_path / "m.ply", V, F, fmt)
    V2, F2 = read_mesh(str(tmp_path / "m.ply"))
    assert np.array_equal(V2, V) and np.array_equal(F2, F)


def test_obj_reader_polygons_and_weld(tmp_path):
    p = tmp_path / "q.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 0\nf 1 2 3 4\nf -1 2/5/6 3//1\n")
    V, F = read_mesh(str(p))
    assert F.tolist() == [[0, 1, 2], [0, 2, 3], [0, 1, 2]]  # vertex 5 welded to vertex 1
    V, F = read_mesh(str(p), weld_vertices=False)
    assert F.tolist()[2] == [4, 1, 2]


def make_frames(folder, n=6):
    os.makedirs(folder, exist_ok=True)
    V, F = folded(30, 8)
    paths = []
    for i in range(n):
        s = 0.9 + 0.05 * i  # some frames fold through themselves, others not
        W = V.copy()
        W[:, 2] *= s
        if i % 2:
            p = os.path.join(folder, "frame_%03d.obj" % i)
            write_obj(p, W, F)
        else:
            p = os.path.join(folder, "frame_%03d.ply" % i)
            write_ply(p, W, F, "binary_little_endian")
        paths.append(p)
    return paths


def lines(path):
    with open(path) as fh:
        return [json.loads(line) for line in fh if line.strip()]


def test_check_frame_matches_the_api(tmp_path):
    paths = make_frames(str(tmp_path / "f"), 2)
    rec = batch.check_frame(paths[1], 1)
    V, F = read_mesh(paths[1])
    c = selfcol.self_collide(V, F)
    assert rec["status"] in ("clean", "intersects")
    assert rec["counts"]["vf"] == c.counts["vf"] and rec["counts"]["ef"] == c.counts["ef"]
    assert rec["counts"]["intersecting_triangles"] == len(c.intersecting_triangles())
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    rec = batch.check_frame(str(bad))
    assert rec["status"] == "error" and "InvalidArgument" in rec["error"]


def test_batch_on_a_two_worker_local_cluster(tmp_path):
    pytest.importorskip("dask.distributed")
    paths = make_frames(str(tmp_path / "frames"), 6)
    out, summ = tmp_path / "r.jsonl", tmp_path / "s.json"
    proc = subprocess.run([sys.executable, "-m", "selfcol.batch", str(tmp_path / "frames"),
                           "--workers", "2", "--out", str(out), "--summary", str(summ)],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300,
                          cwd=str(tmp_path))
    recs = lines(out)
    assert proc.returncode in (0, 1), proc.stderr.decode()[-3000:]
    assert len(recs) == 7 and recs[-1]["summary"] and recs[-1]["workers"] == 2
    by_file = {r["file"]: r for r in recs[:-1]}
    assert set(by_file) == set(paths)
    for p in paths:
        V, F = read_mesh(p)
        c = selfcol.self_collide(V, F)
        assert by_file[p]["counts"]["ee"] == c.counts["ee"]
        assert by_file[p]["counts"]["ef"] == c.counts["ef"]
    s = json.loads(summ.read_text())
    assert s["frames"] == 6 and s["errors"] == 0
    assert s["intersecting"] == sum(r["status"] == "intersects" for r in recs[:-1])
    assert proc.returncode == (1 if s["intersecting"] else 0)
    worst = [r for r in recs[:-1] if r["status"] == "intersects"]
    if worst:
        assert worst[0]["worst_regions"][0]["crossed"]


def test_batch_shards_and_merge(tmp_path):
    make_frames(str(tmp_path / "frames"), 5)
    pattern = str(tmp_path / "frames" / "frame_*")
    for i in range(2):
        rc = batch.main([pattern, "--no-dask", "--shard", "%d/2" % i,
                         "--out", str(tmp_path / ("part-%d.jsonl" % i))])
        assert rc in (0, 1)
    rc = batch.main(["--merge", str(tmp_path / "part-*.jsonl"), "--out",
                     str(tmp_path / "all.jsonl")])
    recs = lines(tmp_path / "all.jsonl")
    assert [r["index"] for r in recs[:-1]] == list(range(5))
    assert recs[-1]["frames"] == 5
    whole = batch.main([pattern, "--no-dask", "--out", str(tmp_path / "one.jsonl")])
    one = lines(tmp_path / "one.jsonl")
    strip = lambda r: {k: v for k, v in r.items() if k != "seconds"}  # noqa: E731
    assert [strip(r) for r in one[:-1]] == [strip(r) for r in recs[:-1]]
    assert whole == rc
    assert batch.main([str(tmp_path / "missing.obj"), "--no-dask",
                       "--out", str(tmp_path / "e.jsonl")]) == 2
