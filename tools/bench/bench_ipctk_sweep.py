# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""ipc-toolkit (PyPI `ipctk`) continuous checks on the steps selfcol-bench-sweep dumps.

What is measured, on one thread unless --threads says otherwise (set
explicitly: ipctk's default is every core, 2 on the 2-core benchmark
machine, which results/sweep.md and the first results/sweep-earliest.md
used while calling it one thread), on the same start and end
positions as selfcol's continuous query, minimum distance 0, its default
broad phase and its default narrow phase (Tight-Inclusion):
  - compute_collision_free_stepsize: the collision-free fraction, the number
    selfcol's SELFCOL_SWEEP_EARLIEST returns;
  - is_step_collision_free: stops at the first colliding pair.
Its collision mesh (CollisionMesh with its edges) is built once and timed as
build_ms. Medians over --reps runs, after none (a 6 s call needs no warm-up).

usage: bench_ipctk_sweep.py --dump DIR --case NAME [--case NAME...] --reps N [--threads T]
prints markdown rows on stdout.
"""
import argparse
import os
import statistics
import time

import numpy as np

import ipctk


def read_step(path):
    with open(path, "rb") as f:
        nv, nf = (int(x) for x in f.readline().split())
        start = np.fromfile(f, dtype=np.float64, count=3 * nv).reshape(nv, 3)
        end = np.fromfile(f, dtype=np.float64, count=3 * nv).reshape(nv, 3)
        faces = np.fromfile(f, dtype=np.int32, count=3 * nf).reshape(nf, 3)
    return np.asfortranarray(start), np.asfortranarray(end), np.asfortranarray(faces)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--dump", required=True)
    parser.add_argument("--case", action="append", required=True)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    ipctk.set_num_threads(args.threads)
    if ipctk.get_num_threads() != args.threads:
        raise SystemExit("bench_ipctk_sweep: ipctk runs %d threads, not %d"
                         % (ipctk.get_num_threads(), args.threads))
    for case in args.case:
        path = os.path.join(args.dump, case + ".step")
        if not os.path.exists(path):
            continue
        start, end, faces = read_step(path)
        t0 = time.perf_counter()
        edges = ipctk.edges(faces)
        mesh = ipctk.CollisionMesh(start, edges, faces)
        build_ms = 1e3 * (time.perf_counter() - t0)
        step_ms, free_ms = [], []
        fraction, collision_free = None, None
        for _ in range(args.reps):
            t0 = time.perf_counter()
            fraction = ipctk.compute_collision_free_stepsize(mesh, start, end)
            step_ms.append(1e3 * (time.perf_counter() - t0))
            t0 = time.perf_counter()
            collision_free = ipctk.is_step_collision_free(mesh, start, end)
            free_ms.append(1e3 * (time.perf_counter() - t0))
        print("| %s | %d | %.1f (%.1f-%.1f) | %.3g | %.1f | %s | %.1f |" % (
            case, faces.shape[0], statistics.median(step_ms), min(step_ms), max(step_ms),
            fraction, statistics.median(free_ms), collision_free, build_ms), flush=True)


if __name__ == "__main__":
    main()
