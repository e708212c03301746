# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The add-on page's picture (adapters/blender/README.md), rendered headless
with Cycles on the CPU after the add-on marked a folded cloth:

    blender -b --factory-startup --python screenshot.py -- ZIP OUT.png

Run by `sh tools/blender_addon.sh BUILD --screenshot`; the committed picture
is docs/images/blender-addon.png."""

import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from folded_cloth import folded_cloth  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
ZIP, PNG = argv[0], argv[1]
bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
bpy.ops.preferences.addon_enable(module="selfcol_blender")

for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
# The test's cloth (folded_cloth.py), finer, nearly untwisted.
cloth, mesh, twist, verts = folded_cloth(96, 32, 1.0)
bpy.context.view_layer.objects.active = cloth
assert bpy.ops.selfcol.check() == {"FINISHED"}

# The marks as the material's colour (the colour attribute).
material = bpy.data.materials.new("selfcol marks")
material.use_nodes = True
nodes = material.node_tree.nodes
attribute = nodes.new("ShaderNodeAttribute")
attribute.attribute_name = "selfcol_color"
bsdf = nodes["Principled BSDF"]
material.node_tree.links.new(attribute.outputs["Color"], bsdf.inputs["Base Color"])
mesh.materials.append(material)

scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 32
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = 960, 540
scene.render.film_transparent = False
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
bpy.context.collection.objects.link(camera)
camera.location = (1.9, -1.9, 0.55)
direction = (0.5 - camera.location[0], 0.5 - camera.location[1], 0.0 - camera.location[2])
camera.rotation_euler = (math.atan2(math.hypot(direction[0], direction[1]), -direction[2]), 0.0,
                         math.atan2(direction[1], direction[0]) - math.pi / 2)
scene.camera = camera
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
bpy.context.collection.objects.link(sun)
world = bpy.data.worlds.new("world")
world.color = (0.6, 0.6, 0.62)
scene.world = world
scene.render.filepath = PNG
bpy.ops.render.render(write_still=True)
print("screenshot:", PNG, bpy.context.window_manager.get("selfcol_last_report"))
