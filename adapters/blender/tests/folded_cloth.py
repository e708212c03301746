# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The cloth of the add-on's test and picture: a sheet folded through itself.

u in [0, 2] along the sheet, v in [0, 1] across. The first half lies flat;
the second folds back over it, its height 0.25 sin(3 pi (u - 1)) + 0.004
dipping below the first half around u in (4/3, 5/3) (the offset keeps the
crossings off the grid's lines) and starting just above it at the hinge
(near faces there). A SimpleDeform twist about X moves its vertices
without changing its faces."""

import math

import bpy


def folded_cloth(nu, nv, twist_degrees, name="cloth"):
    """The object (linked to the current collection), its mesh, its twist
    modifier and the vertices as built (before the object's transform)."""
    verts, faces = [], []
    for i in range(nu + 1):
        u = 2.0 * i / nu
        for j in range(nv + 1):
            v = j / nv
            verts.append((u, v, 0.0) if u <= 1.0 else
                         (2.0 - u, v, 0.25 * math.sin(3.0 * math.pi * (u - 1.0)) + 0.004))
    for i in range(nu):
        for j in range(nv):
            a = i * (nv + 1) + j
            faces.append((a, a + nv + 1, a + nv + 2, a + 1))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.collection.objects.link(obj)
    twist = obj.modifiers.new("twist", "SIMPLE_DEFORM")
    twist.deform_method = "TWIST"
    twist.deform_axis = "X"
    twist.angle = math.radians(twist_degrees)
    return obj, mesh, twist, verts
