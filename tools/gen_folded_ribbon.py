#!/usr/bin/env python3
# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Writes tests/data/folded_ribbon.obj, the bundled demo mesh: a ribbon folded
back over itself whose upper layer sags through the lower one, so it has both
proximities (the near-parallel layers) and interferences (where the sag
crosses)."""
import math
import sys

L, W, NU, NV, R, NF = 1.2, 0.3, 40, 4, 0.03, 8


def main(out):
    path = [(L * i / NU, 0.0) for i in range(NU + 1)]
    for i in range(1, NF):
        a = -math.pi / 2 + math.pi * i / NF
        path.append((L + R * math.cos(a), R + R * math.sin(a)))
    for i in range(NU + 1):
        x = L - L * i / NU
        path.append((x, 2 * R - 0.08 * math.exp(-((x - 0.6) / 0.15) ** 2)))
    pts = [(x, W * j / NV - W / 2, z) for (x, z) in path for j in range(NV + 1)]
    faces = []
    for i in range(len(path) - 1):
        for j in range(NV):
            a, b = i * (NV + 1) + j, (i + 1) * (NV + 1) + j
            faces += [(a, b, b + 1), (a, b + 1, a + 1)]
    with open(out, "w") as f:
        f.write("# selfcol demo mesh: a ribbon folded back over itself whose upper layer\n")
        f.write("# sags through the lower one (generated; %d vertices, %d triangles)\n"
                % (len(pts), len(faces)))
        for p in pts:
            f.write("v %.6f %.6f %.6f\n" % p)
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "tests/data/folded_ribbon.obj")
