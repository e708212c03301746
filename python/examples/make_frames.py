# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Writes a sequence of generated frames to try python -m selfcol.batch on:
a strip folded through itself, closing a little more every frame (binary PLY).

usage: python make_frames.py OUTDIR [--frames 40] [--nx 200] [--ny 50]
"""

import argparse
import os

import numpy as np


def strip(nx, ny, t):
    u, v = np.meshgrid(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    ang = (1.6 + 0.4 * t) * np.pi * u
    r = 0.25 + 0.05 * u
    V = np.stack([r * np.cos(ang), 0.6 * v + 0.15 * np.sin(3 * ang),
                  r * np.sin(ang) * (1 - 1.2 * u)], 1)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    return V.astype("<f4"), F.astype("<i4")


def write_ply(path, V, F):
    with open(path, "wb") as fh:
        fh.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
                  "property float x\nproperty float y\nproperty float z\nelement face %d\n"
                  "property list uchar int vertex_indices\nend_header\n"
                  % (len(V), len(F))).encode())
        fh.write(V.tobytes())
        rec = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        rec["n"], rec["i"] = 3, F
        fh.write(rec.tobytes())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--frames", type=int, default=40)
    ap.add_argument("--nx", type=int, default=200)
    ap.add_argument("--ny", type=int, default=50)
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    for i in range(args.frames):
        V, F = strip(args.nx, args.ny, i / max(1, args.frames - 1))
        write_ply(os.path.join(args.outdir, "frame_%04d.ply" % i), V, F)


if __name__ == "__main__":
    main()
