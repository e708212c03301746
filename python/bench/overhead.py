# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Per-call overhead of the Python binding against the C API, same input,
same library build (the package's Release libselfcol.a).

usage: python overhead.py --lib BUILD/python-build/selfcol-core/lib/libselfcol.a
                          [--include include] [--frame cloth_ball92.ply]
Prints a Markdown table: microseconds per call, C and Python, for a tiny
mesh, a generated 20k-triangle folded strip and (when given) a real frame.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import selfcol
from selfcol._core import _new_contacts, _query_options
from selfcol._selfcol_cffi import lib

HERE = os.path.dirname(os.path.abspath(__file__))


def grid(nx, ny, fold=True):
    u, v = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    ang = 1.9 * np.pi * u
    r = 0.25 + 0.05 * u
    V = np.stack([r * np.cos(ang), 0.6 * v + 0.15 * np.sin(3 * ang),
                  r * np.sin(ang) * (1 - 1.2 * u)], 1) if fold else np.stack(
        [u, v, 0 * u], 1)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.uint32)
    return np.ascontiguousarray(V), F


def per_call(fn, reps):
    fn()
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        for _ in range(reps):
            fn()
        best = min(best, (time.perf_counter() - t) / reps)
    return best


def c_times(exe, V, F, d, reps, tmp):
    pv, pf = os.path.join(tmp, "v.f64"), os.path.join(tmp, "f.u32")
    V.astype(np.float64).tofile(pv)
    F.astype(np.uint32).tofile(pf)
    best = {}
    for _ in range(3):
        out = subprocess.run([exe, pv, pf, str(len(V)), str(len(F)), repr(d), str(reps)],
                             check=True, stdout=subprocess.PIPE).stdout.decode()
        for line in out.splitlines():
            name, sec = line.split()[:2]
            best[name] = min(best.get(name, float("inf")), float(sec))
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lib", required=True)
    ap.add_argument("--include", default=os.path.join(HERE, "..", "..", "include"))
    ap.add_argument("--frame")
    args = ap.parse_args()
    tmp = tempfile.mkdtemp()
    exe = os.path.join(tmp, "overhead_c")
    subprocess.run(["gcc", "-O2", "-DSELFCOL_STATIC", "-I", args.include,
                    os.path.join(HERE, "overhead_c.c"), args.lib, "-lccd", "-lm", "-pthread",
                    "-o", exe], check=True)
    cases = [("tiny (2x2 grid, 8 triangles)", grid(2, 2, False), 20000),
             ("folded strip, 20,000 triangles", grid(200, 50), 20)]
    if args.frame:
        from selfcol.io import read_mesh
        cases.append(("cloth-ball frame 92, 92,230 triangles", read_mesh(args.frame), 2))
    print("| mesh | contacts | C query (reused contacts) | C query (fresh contacts) | "
          "Python cffi call | Python Hierarchy.self_collide | C one call | "
          "Python selfcol.self_collide |")
    print("|---|---|---|---|---|---|---|---|")
    for name, (V, F), reps in cases:
        m = selfcol.Mesh(V, F)
        h = selfcol.Hierarchy(m)
        d = 0.1 * m.mean_edge_length()
        ct = c_times(exe, V, F, d, reps, tmp)
        opts = _query_options(d, "exact", "all", 1, "closed")
        cc = _new_contacts()
        raw = per_call(lambda: lib.selfcol_hierarchy_self_collide(h._h, cc, opts), reps)
        wrapped = per_call(lambda: h.self_collide(d), reps)
        one = per_call(lambda: selfcol.self_collide(V, F, distance=d), max(1, reps // 10))
        n = len(h.self_collide(d))
        us = lambda s: "%.2f" % (s * 1e6) if s < 1e-3 else "%.1f ms" % (s * 1e3)  # noqa: E731
        print("| %s | %d | %s | %s | %s | %s | %s | %s |" % (
            name, n, us(ct["query_reused"]), us(ct["query_fresh"]), us(raw), us(wrapped),
            us(ct["one_call"]), us(one)))
    print("\n(microseconds per call unless marked; best of 3; %s)" % sys.version.split()[0])


if __name__ == "__main__":
    main()
