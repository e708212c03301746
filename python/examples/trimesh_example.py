# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Self-contacts of a mesh loaded with trimesh (pip install trimesh).

usage: python trimesh_example.py MESH [--distance-rel 0.1]

trimesh keeps vertices as a C-contiguous float64 (n, 3) array and faces as
int64 (m, 3): selfcol reads the vertices in place and converts the faces once
(the C API takes uint32). trimesh merges vertices on load (process=True), so
the indices are trimesh's, not the file's.
"""

import argparse

import selfcol
import trimesh  # type: ignore[import-not-found]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("--distance-rel", type=float, default=0.1)
    args = ap.parse_args()
    tm = trimesh.load(args.mesh, force="mesh")
    c = selfcol.self_collide(tm.vertices, tm.faces, distance_rel=args.distance_rel)
    print(c)  # selfcol.Contacts(vf=..., ee=..., ef=..., distance=...)
    crossing = c.intersecting_triangles()
    print("%d intersecting triangle pairs" % len(crossing))
    if len(crossing):
        # colour the intersecting faces red and save a copy to look at
        tm.visual.face_colors = [200, 200, 200, 255]
        tm.visual.face_colors[crossing.ravel()] = [255, 0, 0, 255]
        tm.export("selfcol_marked.ply")
        print("wrote selfcol_marked.ply")


if __name__ == "__main__":
    main()
