# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""One Python package's self-intersection query on one mesh (side_by_side.sh).

Run by side_by_side.sh in each package's own venv, so that each import sees
only what its own `pip install` brought. The mesh comes as an .npz of V and F
(written once by selfcol.io, the file's vertex order), so every package
answers about the same triangles. One thread for everyone: OMP_NUM_THREADS=1
(side_by_side.sh), ipctk.set_num_threads(1) (checked), selfcol threads=1;
pymeshlab's filter and libigl's CGAL remesher run on one thread.

What each package is asked (what a user would call):
  selfcol    self_collide(V, F, distance=0): the crossing edges, hence the
             intersecting triangle pairs; the same on a kept Hierarchy; and
             the query at d on it (proximities too)
  ipctk      has_intersections (a yes or no), from the arrays and on a kept
             CollisionMesh, and Candidates LBVH + NormalCollisions at dhat = d
             on it (proximities, no crossings)
  pymeshlab  compute_selection_by_self_intersections_per_face (faces)
  libigl     copyleft.cgal.remesh_self_intersections, detect_only (pairs)
  trimesh    has no self-intersection query: loading the PLY only
usage: side_by_side.py TOOL MESH.npz PLY REPS  -> one JSON line on stdout
"""
import json
import os
import statistics
import sys
import time

import numpy as np


def timed(function, reps):
    """Median wall time (ms) of reps calls after one warm-up, and the last result."""
    result = function()
    times = []
    for _ in range(reps):
        start = time.perf_counter()
        result = function()
        times.append(1e3 * (time.perf_counter() - start))
    return statistics.median(times), result


def faces_in(pairs):
    return int(np.unique(np.asarray(pairs).ravel()).size)


def main():
    tool, npz, ply, reps = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
    data = np.load(npz)
    V, F, d = data["V"], data["F"], float(data["d"])
    row = {"tool": tool, "kept_ms": None, "proximity_ms": None}
    try:
        from importlib.metadata import version
        row["version"] = version(tool)
    except Exception:  # noqa: BLE001 (a package without metadata)
        row["version"] = "?"
    if tool == "selfcol":
        import selfcol
        ms, c = timed(lambda: selfcol.self_collide(V, F, distance=0.0, threads=1), reps)
        pairs = c.intersecting_triangles()
        row.update(query_ms=ms, what="intersecting triangle pairs (distance 0)",
                   pairs=int(pairs.shape[0]), faces=faces_in(pairs))
        hierarchy = selfcol.Hierarchy(selfcol.Mesh(V, F))
        row["kept_ms"], kept = timed(
            lambda: hierarchy.self_collide(distance=0.0, threads=1).intersecting_triangles(),
            reps)
        assert kept.shape == pairs.shape
        ms_d, c_d = timed(lambda: hierarchy.self_collide(distance=d, threads=1), reps)
        row.update(proximity_ms=ms_d, proximities=int(c_d.counts["vf"] + c_d.counts["ee"]),
                   crossing_edges=int(c_d.counts["ef"]))
    elif tool == "ipctk":
        import ipctk
        ipctk.set_num_threads(1)
        if ipctk.get_num_threads() != 1:
            sys.exit("ipctk.set_num_threads(1) did not hold")
        Vf, Ff = np.asfortranarray(V), np.asfortranarray(F.astype(np.int32))

        def from_arrays():
            m = ipctk.CollisionMesh(Vf, ipctk.edges(Ff), Ff)
            return ipctk.has_intersections(m, Vf)
        ms, hit = timed(from_arrays, reps)
        mesh = ipctk.CollisionMesh(Vf, ipctk.edges(Ff), Ff)
        row["kept_ms"], _ = timed(lambda: ipctk.has_intersections(mesh, Vf), reps)
        row.update(query_ms=ms, what="has_intersections: yes or no", intersects=bool(hit))

        def proximities():
            candidates = ipctk.Candidates()
            candidates.build(mesh, Vf, d / 2)
            collisions = ipctk.NormalCollisions()
            collisions.build(candidates, mesh, Vf, d)
            return len(collisions)
        ms_d, n = timed(proximities, reps)
        row.update(proximity_ms=ms_d, proximities=int(n))
    elif tool == "pymeshlab":
        import pymeshlab

        def query():
            ms = pymeshlab.MeshSet()
            ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)))
            ms.compute_selection_by_self_intersections_per_face()
            return int(ms.current_mesh().selected_face_number())
        ms, faces = timed(query, reps)
        row.update(query_ms=ms, what="self-intersecting faces", faces=faces)
    elif tool == "libigl":
        import igl
        import igl.copyleft.cgal as cgal
        assert igl is not None

        def query():
            # As a user calls it. (cutoff=2**30 reports the same pairs, 5x slower.)
            out = cgal.remesh_self_intersections(V, F.astype(np.int64), detect_only=True)
            return np.asarray(out[2])  # IF: the intersecting face pairs
        ms, pairs = timed(query, reps)
        pairs = np.unique(np.sort(pairs.reshape(-1, 2), axis=1), axis=0)
        row.update(query_ms=ms, what="intersecting triangle pairs (CGAL, exact)",
                   pairs=int(pairs.shape[0]), faces=faces_in(pairs))
    elif tool == "trimesh":
        import trimesh
        ms, mesh = timed(lambda: trimesh.load(ply, process=False), reps)
        row.update(query_ms=None, load_ms=ms, what="no self-intersection query (load only)",
                   vertices=int(len(mesh.vertices)), triangles=int(len(mesh.faces)))
    else:
        sys.exit("unknown tool " + tool)
    row["threads_env"] = os.environ.get("OMP_NUM_THREADS")
    print(json.dumps(row))


if __name__ == "__main__":
    main()
