# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The Blender add-on, headless in a real Blender (tools/blender_addon.sh --test):

    blender -b --factory-startup --python-exit-code 1 --python test_addon.py -- ZIP CLI OUTDIR

1. The add-on is installed from its zip and enabled, as an artist would.
2. A cloth folded through itself (a sheet whose folded half dips through
   the other), with a modifier that moves its vertices (SimpleDeform twist,
   keeping its faces): the operator's face marks must equal selfcol-cli's
   --mark of the evaluated mesh, exported here (world coordinates, the
   triangles of Blender's own triangulation), per face the highest class of
   its triangles; there must be intersecting and near faces.
3. A frame range over a keyframed twist: the report names the worst frame.
4. A modifier that changes the faces (Subdivision): the marks go to a new
   object holding the evaluated mesh.
Any failed check raises, and Blender exits with status 1.
"""

import math
import os
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folded_cloth import folded_cloth  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
ZIP, CLI, OUT = argv[0], argv[1], argv[2]


def check(condition, what):
    if not condition:
        raise AssertionError(what)
    print("ok:", what)


# 1. Install and enable from the zip.
bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
bpy.ops.preferences.addon_enable(module="selfcol_blender")
import selfcol_blender  # noqa: E402

check(hasattr(bpy.ops.selfcol, "check"), "the add-on's operator is registered")

# 2. The folded cloth (folded_cloth.py), moved and scaled, with an 8 degree
# twist.
cloth, mesh, twist, verts = folded_cloth(48, 16, 8.0)
cloth.location = (0.3, -0.2, 1.0)
cloth.scale = (1.5, 1.5, 1.5)
bpy.context.view_layer.objects.active = cloth
cloth.select_set(True)

result = bpy.ops.selfcol.check(distance_rel=0.1)
check(result == {"FINISHED"}, "the operator finished: %s" % result)
attribute = mesh.attributes.get("selfcol")
check(attribute is not None and attribute.domain == "FACE", "the face attribute 'selfcol'")
marks = np.empty(len(mesh.polygons), np.int32)
attribute.data.foreach_get("value", marks)
check(mesh.color_attributes.get("selfcol_color") is not None, "the colour attribute")
selected = np.empty(len(mesh.polygons), bool)
mesh.polygons.foreach_get("select", selected)
check(np.array_equal(selected, marks == 2), "the intersecting faces are the selection")

# The evaluated mesh, exported by this test through Blender's API.
depsgraph = bpy.context.evaluated_depsgraph_get()
evaluated = cloth.evaluated_get(depsgraph)
em = evaluated.to_mesh()
em.calc_loop_triangles()
V = np.empty(3 * len(em.vertices))
em.vertices.foreach_get("co", V)
M = np.array(evaluated.matrix_world)
V = V.reshape(-1, 3) @ M[:3, :3].T + M[:3, 3]
T = np.empty(3 * len(em.loop_triangles), np.int32)
em.loop_triangles.foreach_get("vertices", T)
T = T.reshape(-1, 3)
P = np.empty(len(em.loop_triangles), np.int32)
em.loop_triangles.foreach_get("polygon_index", P)
check(not np.allclose(V[:, 1], np.array(verts)[:, 1] * 1.5 - 0.2), "the modifier moved vertices")
evaluated.to_mesh_clear()
ply = os.path.join(OUT, "cloth.ply")
with open(ply, "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
            "property double z\nelement face %d\nproperty list uchar int vertex_indices\n"
            "end_header\n" % (len(V), len(T)))
    for p in V:
        f.write("%.17g %.17g %.17g\n" % tuple(p))
    for t in T:
        f.write("3 %d %d %d\n" % tuple(t))
marked = os.path.join(OUT, "cloth_marked.ply")
run = subprocess.run([CLI, "check", "--no-weld", "--distance-rel", "0.1", "--quiet", "--mark",
                      marked, ply], capture_output=True, text=True)
check(run.returncode in (0, 1), "selfcol-cli ran: %s" % run.stderr.strip())
lines = open(marked).read().splitlines()
end = lines.index("end_header")
nv = len(V)
colours = {(190, 196, 206): 0, (245, 166, 35): 1, (214, 39, 40): 2}
tri_class = np.array([colours[tuple(int(x) for x in line.split()[4:7])]
                      for line in lines[end + 1 + nv:end + 1 + nv + len(T)]])
expected = np.zeros(len(mesh.polygons), np.int32)
np.maximum.at(expected, P, tri_class)
print("faces: %d intersecting, %d near, %d plain (selfcol-cli: %d, %d)"
      % (np.sum(marks == 2), np.sum(marks == 1), np.sum(marks == 0), np.sum(expected == 2),
         np.sum(expected == 1)))
check(np.sum(expected == 2) > 0 and np.sum(expected == 1) > 0,
      "the cloth has intersecting and near faces")
check(np.array_equal(marks, expected), "the add-on's marks equal selfcol-cli's --mark")

# 3. A frame range over a keyframed twist: 0 degrees at frame 1 (the fold
# alone), 40 at frame 3; the report names the worst frame.
twist.angle = 0.0
twist.keyframe_insert("angle", frame=1)
twist.angle = math.radians(40.0)
twist.keyframe_insert("angle", frame=3)
result = bpy.ops.selfcol.check(use_range=True, frame_start=1, frame_end=3)
report = bpy.context.window_manager.get("selfcol_last_report", "")
print("report:", report)
check(result == {"FINISHED"} and report.startswith("worst frame "), "a range names its worst frame")
check(bpy.context.scene.frame_current == int(report.split()[2].rstrip(":")),
      "the marks show the worst frame")

# 4. A modifier that changes the faces: a new object holds the marks.
cloth.modifiers.new("subdivision", "SUBSURF").levels = 1
result = bpy.ops.selfcol.check()
out = bpy.data.objects.get("cloth selfcol")
check(result == {"FINISHED"} and out is not None, "a new object for a changed topology")
check(len(out.data.polygons) == 4 * len(mesh.polygons) and
      out.data.attributes.get("selfcol") is not None, "its faces are the subdivided ones, marked")
print("blender add-on: all checks passed")
