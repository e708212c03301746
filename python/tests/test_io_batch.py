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
    assert rec["status"] == "error"
    # The reader refuses it first, naming the line (selfcol-cli's message).
    assert rec["error"] == "%s:2: NaN or infinite coordinate" % bad


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


def test_batch_out_dash_writes_standard_output(tmp_path):
    """--out - puts the JSON Lines on standard output, the final line on
    standard error; they equal a file's records."""
    make_frames(str(tmp_path / "frames"), 3)
    pattern = str(tmp_path / "frames" / "frame_*")
    proc = subprocess.run([sys.executable, "-m", "selfcol.batch", pattern, "--no-dask",
                           "--out", "-"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          timeout=300, cwd=str(tmp_path))
    assert proc.returncode in (0, 1), proc.stderr.decode()
    recs = [json.loads(x) for x in proc.stdout.decode().splitlines() if x.strip()]
    assert [r["index"] for r in recs[:-1]] == [0, 1, 2] and recs[-1]["frames"] == 3
    assert "3 frames" in proc.stderr.decode() and "standard output" in proc.stderr.decode()
    batch.main([pattern, "--no-dask", "--quiet", "--out", str(tmp_path / "f.jsonl")])
    strip = lambda r: {k: v for k, v in r.items() if k != "seconds"}  # noqa: E731
    assert [strip(r) for r in lines(tmp_path / "f.jsonl")[:-1]] == [strip(r) for r in recs[:-1]]


def test_batch_progress_line(tmp_path, capsys):
    """The progress line: frames done of all, throughput, time left; not in a
    pipe or a log unless asked (progress=True), never with --quiet."""
    make_frames(str(tmp_path / "frames"), 4)
    pattern = str(tmp_path / "frames" / "frame_*")
    batch.run([pattern], str(tmp_path / "a.jsonl"), use_dask=False, progress=True)
    err = capsys.readouterr().err
    assert "4/4 frames" in err and "frames/s" in err and "left" in err
    batch.run([pattern], str(tmp_path / "b.jsonl"), use_dask=False)  # not a terminal here
    assert "frames/s" not in capsys.readouterr().err
    assert batch.main([pattern, "--no-dask", "--quiet", "--out", str(tmp_path / "c.jsonl")]) in (0, 1)
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


# ---------------------------------------------------------------------------
# Hardening 0.4: outputs never overwrite inputs; usage errors up front;
# errors name the file and what is wrong with it.

def _batch(tmp_path, *args):
    proc = subprocess.run([sys.executable, "-m", "selfcol.batch", *map(str, args)],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300,
                          cwd=str(tmp_path))
    return proc.returncode, proc.stderr.decode()


def _snapshot(paths):
    return {str(p): (os.path.islink(p), open(p, "rb").read()) for p in paths}


def test_batch_never_writes_over_an_input(tmp_path):
    """--out F F and --summary F F overwrote the frame F with JSON (exit 0)."""
    frame = make_frames(str(tmp_path / "f"), 1)[0]
    link = tmp_path / "link.obj"
    os.symlink(frame, link)
    hard = tmp_path / "hard.obj"
    os.link(frame, hard)
    before = _snapshot([frame])
    cases = [
        ["--out", frame, frame],
        ["--out", tmp_path / "r.jsonl", "--summary", frame, frame],
        ["--out", link, frame],  # through a symbolic link
        ["--out", frame, link],
        ["--out", hard, frame],  # a hard link to the input
        ["--out", tmp_path / "r.jsonl", "--summary", hard, str(tmp_path / "f")],
        ["--out", tmp_path / "same.json", "--summary", tmp_path / "same.json", frame],
    ]
    for args in cases:
        rc, err = _batch(tmp_path, "--no-dask", *args)
        assert rc == 2, (args, err)
        assert "refusing to overwrite an input" in err or "name the same file" in err, err
        assert _snapshot([frame]) == before, args
        assert not (tmp_path / "r.jsonl").exists() and not (tmp_path / "same.json").exists()
    # merge: a part named as the output
    part = tmp_path / "part.jsonl"
    assert batch.main([frame, "--no-dask", "--out", str(part)]) in (0, 1)
    text = part.read_text()
    assert batch.main(["--merge", str(part), "--out", str(part)]) == 2
    assert part.read_text() == text


@pytest.mark.parametrize("args, says", [
    (["nothing_*.obj"], "no file matches this pattern"),
    (["empty_dir"], "a directory with no .obj or .ply file"),
    (["missing.xyz"], "missing.xyz: no such file or directory"),
    (["FRAME", "--threads", "0"], "--threads must be 1 to 64"),
    (["FRAME", "--threads", "65"], "--threads must be 1 to 64"),
    (["FRAME", "--distance", "-1"], "--distance must be a finite number >= 0"),
    (["FRAME", "--distance", "nan"], "--distance must be a finite number >= 0"),
    (["FRAME", "--distance-rel", "inf"], "--distance-rel must be a finite number >= 0"),
    (["FRAME", "--method", "nope"], "--method 'nope' is not one of"),
    (["FRAME", "--workers", "0"], "--workers must be >= 1"),
    (["FRAME", "--shard", "2/2"], "--shard I/N needs 0 <= I < N"),
])
def test_batch_usage_errors_before_any_frame(tmp_path, args, says):
    frame = make_frames(str(tmp_path / "f"), 1)[0]
    os.makedirs(tmp_path / "empty_dir")
    out = tmp_path / "r.jsonl"
    args = [frame if a == "FRAME" else a for a in args]
    rc, err = _batch(tmp_path, "--no-dask", "--out", out, *args)
    assert rc == 2 and says in err, err
    assert not out.exists()  # nothing created


def _truncated(tmp_path, fmt):
    V, F = folded(8, 4)
    p = tmp_path / ("t_%s.ply" % fmt)
    write_ply(p, V, F, fmt)
    data = p.read_bytes()
    p.write_bytes(data[:len(data) - 40])
    return p


@pytest.mark.parametrize("make, says", [
    # The readers are selfcol-cli's (tools/meshio): the same messages.
    (lambda t: t / "empty.obj", "empty file"),
    (lambda t: t / "text.ply", ":1: not a PLY file"),
    (lambda t: _truncated(t, "binary_little_endian"), "file truncated (binary data ends inside"),
    (lambda t: _truncated(t, "ascii"), "file ends inside this record"),
    (lambda t: t / "badidx.obj", ":4: face index 10 out of range (the file has 3 vertices)"),
    (lambda t: t / "word.obj", ":2: expected 'v x y z', a coordinate is not a number"),
    (lambda t: t / "far.obj", "V[1, 1] = 1e+300 is beyond the largest coordinate"),
])
def test_batch_errors_name_the_file_and_the_fault(tmp_path, make, says):
    (tmp_path / "empty.obj").write_text("")
    (tmp_path / "text.ply").write_text("this is no mesh\n")
    (tmp_path / "badidx.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 10\n")
    (tmp_path / "word.obj").write_text("v 0 0 0\nv one 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "far.obj").write_text("v 0 0 0\nv 1 1e300 0\nv 0 1 0\nf 1 2 3\n")
    path = str(make(tmp_path))
    rec = batch.check_frame(path)
    assert rec["status"] == "error"
    assert rec["error"].startswith(path) and says in rec["error"], rec["error"]
    for internal in ("IndexError", "buffer is smaller", "list index", "V is empty"):
        assert internal not in rec["error"]
