# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""A frame sequence read with meshio (pip install meshio): one Mesh and one
Hierarchy for the whole sequence, a refit per frame, and the contact store
tracking crossings across frames.

usage: python meshio_example.py FRAME0 FRAME1 ...   (one topology: e.g. cloth_*.ply)
"""

import sys

import meshio  # type: ignore[import-not-found]
import numpy as np

import selfcol


def triangles(m: "meshio.Mesh") -> np.ndarray:
    return np.concatenate([c.data for c in m.cells if c.type == "triangle"])


def main(paths: list) -> None:
    first = meshio.read(paths[0])
    F = triangles(first)  # meshio gives int64 (or int32) indices: converted once
    mesh = selfcol.Mesh(first.points[:, :3], F)
    hier = selfcol.Hierarchy(mesh)
    d = 0.1 * mesh.mean_edge_length()
    store = selfcol.Store()
    prev = mesh.positions
    for i, path in enumerate(paths):
        if i:
            mesh.set_positions(meshio.read(path).points[:, :3])
            hier.refit()
        contacts = hier.self_collide(d)
        stats = store.update_swept(contacts, prev) if i else store.update(contacts)
        prev = mesh.positions
        print("%s: vf %d ee %d ef %d | regions %d, flipped %d, crossed regions %d" % (
            path, *contacts.counts.values(), stats["regions"], stats["flipped"],
            stats["crossed_regions"]))


if __name__ == "__main__":
    main(sys.argv[1:])
