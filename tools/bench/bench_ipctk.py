# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""ipc-toolkit (PyPI `ipctk`) on the meshes selfcol-bench dumps (bench-full only).

What is measured, as docs/benchmarks.md describes: its LBVH broad phase
(Candidates.build with inflation d / 2) and its narrow phase
(NormalCollisions.build with dhat = d), on one thread, on the same mesh
and d as selfcol. Its collision mesh (CollisionMesh) is built once and timed
as `build_ms`; `query_ms` is candidates plus collisions, median of the runs
after one warm-up.

ipc-toolkit regroups proximities by closest feature (vertex-vertex,
edge-vertex, edge-edge, face-vertex). Each is mapped back to the pairs of
the exact sets it stands for (docs/contract.md section 1), all of them within the
collision's distance, hence within d:
  FV(v, f)  -> VF(v, f)
  EE(e, g)  -> EE(e, g)
  EV(e, v)  -> VF(v, f) for each triangle f on e; EE(a, e) for each edge a at v
  VV(v, w)  -> VF(v, f) for f at w, VF(w, f) for f at v; EE(a, b), a at v, b at w
Pairs sharing a vertex are dropped (they are not contacts). The union is
compared with selfcol's EXACT VF and EE sets. ipc-toolkit lists no crossing
edges, so every EF contact counts as a miss, as for Bullet.

usage: bench_ipctk.py --dump DIR --case NAME [--case NAME...] --subset S --reps N
prints CSV rows in selfcol-bench's format on stdout.
"""
import argparse
import os
import resource
import sys
import time

import numpy as np

import ipctk

def read_mesh(path):
    with open(path) as f:
        nv, nf, scale, mean_edge, scene = f.readline().split()
        nv, nf = int(nv), int(nf)
        data = np.loadtxt(f, max_rows=nv + nf)
    V = np.asfortranarray(data[:nv], dtype=np.float64)
    F = np.asfortranarray(data[nv:nv + nf], dtype=np.int32)
    return V, F, float(scale), float(mean_edge), scene


def read_keys(path):
    with open(path) as f:
        d = float(f.readline())
        keys = np.loadtxt(f, dtype=np.int64, ndmin=2)
    return d, keys


def unique_edges(F):
    # selfcol numbers edges sorted by (smaller vertex, larger vertex); so do we,
    # so that EE keys compare directly.
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e.sort(axis=1)
    e = e[e[:, 0] != e[:, 1]]
    return np.unique(e, axis=0)


def expand(collisions, F, E):
    """The exact-set pairs (kind, first, second) that ipc-toolkit's collisions stand for."""
    nv = int(max(F.max(), E.max())) + 1
    tri_at = [[] for _ in range(nv)]
    for t, (a, b, c) in enumerate(F):
        for v in {int(a), int(b), int(c)}:
            tri_at[v].append(t)
    edge_at = [[] for _ in range(nv)]
    for i, (a, b) in enumerate(E):
        edge_at[int(a)].append(i)
        edge_at[int(b)].append(i)
    edge_tris = {}
    for t, (a, b, c) in enumerate(F):
        for u, w in ((a, b), (b, c), (c, a)):
            edge_tris.setdefault((min(int(u), int(w)), max(int(u), int(w))), []).append(t)
    tri_set = [set(map(int, f)) for f in F]

    out = set()

    def vf(v, t):
        if v not in tri_set[t]:
            out.add((0, v, t))

    def ee(a, b):
        if a == b:
            return
        ea, eb = E[a], E[b]
        if ea[0] in (eb[0], eb[1]) or ea[1] in (eb[0], eb[1]):
            return
        out.add((1, min(a, b), max(a, b)))

    for c in collisions.fv_collisions:
        vf(int(c.vertex_id), int(c.face_id))
    for c in collisions.ee_collisions:
        ee(int(c.edge0_id), int(c.edge1_id))
    for c in collisions.ev_collisions:
        e, v = int(c.edge_id), int(c.vertex_id)
        a, b = int(E[e][0]), int(E[e][1])
        for t in edge_tris.get((a, b), ()):
            vf(v, t)
        for g in edge_at[v]:
            ee(g, e)
    for c in collisions.vv_collisions:
        v, w = int(c.vertex0_id), int(c.vertex1_id)
        for t in tri_at[w]:
            vf(v, t)
        for t in tri_at[v]:
            vf(w, t)
        for a in edge_at[v]:
            for b in edge_at[w]:
                ee(a, b)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dump", required=True)
    ap.add_argument("--case", action="append", required=True)
    ap.add_argument("--subset", default="full")
    ap.add_argument("--reps", type=int, default=5)
    a = ap.parse_args()
    ap_threads = [1, 2] if a.subset == "full" else [1]
    for case, threads in [(c, t) for c in a.case for t in ap_threads]:
        # One thread is the reference setting (as selfcol's); bench-full adds two.
        ipctk.set_num_threads(threads)
        mpath = os.path.join(a.dump, case + ".mesh")
        if not os.path.exists(mpath):
            print("bench_ipctk: %s: no dump, skipped" % case, file=sys.stderr)
            continue
        V, F, scale, mean_edge, scene = read_mesh(mpath)
        E = unique_edges(F)
        t0 = time.perf_counter()
        mesh = ipctk.CollisionMesh(V, np.asfortranarray(E, dtype=np.int32), F)
        build_ms = 1e3 * (time.perf_counter() - t0)
        for factor in ("0.1", "0.5"):
            d, keys = read_keys(os.path.join(a.dump, "%s-d%s.keys" % (case, factor)))
            ref = set(map(tuple, keys.tolist()))
            ref_k = [sum(1 for k in ref if k[0] == i) for i in range(3)]
            times = []
            for rep in range(a.reps + 1):
                t0 = time.perf_counter()
                cands = ipctk.Candidates()
                cands.build(mesh, V, d / 2, ipctk.LBVH())
                cols = ipctk.NormalCollisions()
                cols.build(cands, mesh, V, d)
                if rep > 0:  # the first run is the warm-up
                    times.append(1e3 * (time.perf_counter() - t0))
            times.sort()
            med = times[len(times) // 2] if len(times) % 2 else 0.5 * (times[len(times) // 2 - 1] + times[len(times) // 2])
            got = expand(cols, F, E)
            found = [sum(1 for k in got if k[0] == i) for i in range(3)]
            miss = [sum(1 for k in ref if k[0] == i and k not in got) for i in range(3)]
            extra = [sum(1 for k in got if k[0] == i and k not in ref) for i in range(3)]
            raw = (len(cols.vv_collisions) + len(cols.ev_collisions) + len(cols.ee_collisions)
                   + len(cols.fv_collisions))
            rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
            note = ("ipctk %s, %d thread(s), LBVH; VV/EV/EE/FV %d/%d/%d/%d mapped to VF/EE; no EF"
                    % (getattr(ipctk, "__version__", "?"), threads, len(cols.vv_collisions),
                       len(cols.ev_collisions), len(cols.ee_collisions), len(cols.fv_collisions)))
            row = [a.subset, case, scene,
                   len(F), len(V), len(E), "%g" % scale, factor, "%.9g" % d, "IPCTK", "ipctk", "EXACT",
                   len(times), "%.4f" % build_ms, "0", "0", "0", "%.4f" % med, "%.4f" % times[0],
                   "%.4f" % times[-1], "%.4f" % med, 0, len(cands), 0, 0, 0, 0, 0, 0, 0,
                   0, 0, "0", "0", "0", "0", 0, 0,  # contour and stage columns: selfcol's only
                   found[0], found[1], found[2], sum(found), raw, ref_k[0], ref_k[1], ref_k[2],
                   miss[0], miss[1], miss[2], sum(miss), extra[0], extra[1], extra[2], sum(extra),
                   0, "0.00", rss, threads]
            row += [0] * 13  # the store_* columns: contact-store rows only
            row.append('"%s"' % note)
            print(",".join(str(x) for x in row))
            sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
