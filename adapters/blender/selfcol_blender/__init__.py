# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""selfcol for Blender: where a mesh intersects itself, and where it nearly does.

The add-on checks the active mesh object, with its modifiers evaluated (a
cloth simulation, an armature, shape keys, a subdivision), on the current
frame or over a frame range, and marks its faces:

- ``selfcol`` (face attribute, integer): 0 plain, 1 near (a vertex or an
  edge closer than the detection distance to another part of the surface),
  2 intersecting (an edge of the face crosses another face, or another edge
  crosses it);
- ``selfcol_color`` (colour attribute on the face corners, set active):
  each face's grey, orange or red,
  as selfcol-cli's ``--mark``; shown in the viewport with Solid shading and
  Color: Attribute;
- the face selection: the intersecting faces (and the near ones when asked).

The checks are selfcol's exact queries (the Python module ``selfcol``,
shipped inside the add-on's zip), which release Python's lock: over a frame
range the query of a frame runs on a thread while Blender's interface stays
responsive, with a progress bar, and Esc cancels. The report gives the
counts and, for a range, the worst frame, which the marks then show.

When the modifiers change the mesh's topology (a subdivision, a remesh),
its faces are not the object's: the marks then go to a new object,
"<name> selfcol", holding the evaluated mesh.
"""

bl_info = {
    "name": "selfcol: self-intersections",
    "author": "selfcol authors",
    "version": (0, 3, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > selfcol; Object > selfcol: check intersections",
    "description": "Marks the faces where a mesh intersects itself or nearly does "
                   "(selfcol's exact queries)",
    "category": "Mesh",
}

import os
import sys
import threading
import time

import bpy
import numpy as np

# The selfcol module (and cffi, for Blender builds whose Python lacks it)
# unpacked from their wheels into _vendor/ by tools/blender_addon.sh: last on
# the path, so that a selfcol or cffi the user installed wins.
_VENDOR = os.path.join(os.path.dirname(__file__), "_vendor")
if os.path.isdir(_VENDOR) and _VENDOR not in sys.path:
    sys.path.append(_VENDOR)

PLAIN, NEAR, INTERSECTING = 0, 1, 2
# selfcol-cli --mark's colours (tools/meshio/write.c), as linear RGBA.
_COLOURS = np.array([[190, 196, 206], [245, 166, 35], [214, 39, 40]], np.float64) / 255.0


def _selfcol():
    import selfcol  # imported on first use: the add-on registers without it
    return selfcol


def evaluated_arrays(obj, depsgraph):
    """World-space vertices (n, 3), triangles (m, 3) and the face of each
    triangle (m,) of the object's evaluated mesh, and its face count."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        V = np.empty(3 * len(mesh.vertices), np.float64)
        mesh.vertices.foreach_get("co", V)
        V = V.reshape(-1, 3)
        M = np.array(evaluated.matrix_world, np.float64)
        V = V @ M[:3, :3].T + M[:3, 3]
        T = np.empty(3 * len(mesh.loop_triangles), np.int32)
        mesh.loop_triangles.foreach_get("vertices", T)
        P = np.empty(len(mesh.loop_triangles), np.int32)
        mesh.loop_triangles.foreach_get("polygon_index", P)
        return np.ascontiguousarray(V), T.reshape(-1, 3), P, len(mesh.polygons)
    finally:
        evaluated.to_mesh_clear()


def query(V, T, distance_rel, threads=1):
    """selfcol's exact query of one surface against itself: (triangle
    classes, counts). Releases Python's lock while it runs."""
    selfcol = _selfcol()
    mesh = selfcol.Mesh(V, T)
    contacts = selfcol.Hierarchy(mesh, threads=threads).self_collide(
        distance_rel=distance_rel, threads=threads)
    classes = contacts.triangle_classes()
    counts = {
        "pairs": int(len(contacts.intersecting_triangles())),
        "vf": int(len(contacts.vf)),
        "ee": int(len(contacts.ee)),
        "ef": int(len(contacts.ef)),
    }
    return np.asarray(classes), counts


def face_classes(tri_classes, tri_face, face_count):
    """A face's class: the highest of its triangles'."""
    out = np.zeros(face_count, np.int8)
    np.maximum.at(out, tri_face, tri_classes.astype(np.int8))
    return out


def _target_mesh(context, obj, depsgraph, face_count):
    """The mesh the marks go to: the object's when the modifiers keep its
    faces, else a new object's holding the evaluated mesh."""
    if len(obj.data.polygons) == face_count:
        return obj.data
    name = obj.name + " selfcol"
    copy = bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph))
    copy.transform(obj.matrix_world)
    old = bpy.data.objects.get(name)
    if old is not None:
        bpy.data.objects.remove(old)
    target = bpy.data.objects.new(name, copy)
    context.collection.objects.link(target)
    return copy


def mark(mesh, classes, select_near=False):
    """Writes the face attributes and the selection (see the module's
    docstring)."""
    attribute = mesh.attributes.get("selfcol")
    if attribute is not None and (attribute.domain != "FACE" or attribute.data_type != "INT"):
        mesh.attributes.remove(attribute)
        attribute = None
    if attribute is None:
        attribute = mesh.attributes.new("selfcol", "INT", "FACE")
    attribute.data.foreach_set("value", classes.astype(np.int32))
    # Colour attributes live on points or face corners: each corner takes
    # its face's colour.
    colour = mesh.color_attributes.get("selfcol_color")
    if colour is not None and colour.domain != "CORNER":
        mesh.color_attributes.remove(colour)
        colour = None
    if colour is None:
        colour = mesh.color_attributes.new("selfcol_color", "BYTE_COLOR", "CORNER")
    corners = np.empty(len(mesh.polygons), np.int32)
    mesh.polygons.foreach_get("loop_total", corners)
    rgba = np.ones((len(classes), 4), np.float32)
    rgba[:, :3] = _COLOURS[classes]
    colour.data.foreach_set("color", np.repeat(rgba, corners, axis=0).ravel())
    mesh.color_attributes.active_color = colour
    selected = classes >= (NEAR if select_near else INTERSECTING)
    mesh.polygons.foreach_set("select", selected)
    mesh.update()


def _report_line(counts, faces, frame=None):
    head = "frame %d: " % frame if frame is not None else ""
    return ("%s%d intersecting faces (%d intersecting triangle pairs), %d near faces; "
            "VF %d, EE %d, EF %d" % (head, int(np.sum(faces == INTERSECTING)), counts["pairs"],
                                     int(np.sum(faces == NEAR)), counts["vf"], counts["ee"],
                                     counts["ef"]))


class SELFCOL_OT_check(bpy.types.Operator):
    """Find where the active mesh intersects itself or nearly does, and mark those faces"""

    bl_idname = "selfcol.check"
    bl_label = "selfcol: check intersections"
    bl_options = {"REGISTER", "UNDO"}

    distance_rel: bpy.props.FloatProperty(
        name="Distance", description="Detection distance, times the mean edge length",
        default=0.1, min=0.0, soft_max=1.0)
    select_near: bpy.props.BoolProperty(
        name="Select near faces", description="Select the near faces too", default=False)
    use_range: bpy.props.BoolProperty(
        name="Frame range", description="Check every frame of the range", default=False)
    frame_start: bpy.props.IntProperty(name="Start", default=1)
    frame_end: bpy.props.IntProperty(name="End", default=250)
    threads: bpy.props.IntProperty(name="Threads", default=1, min=1, max=64)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    # -- the work of one frame (main thread: Blender's data) -----------------

    def _prepare(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        return depsgraph, evaluated_arrays(context.active_object, depsgraph)

    def _finish(self, context, depsgraph, arrays, tri_classes):
        V, T, P, face_count = arrays
        faces = face_classes(tri_classes, P, face_count)
        target = _target_mesh(context, context.active_object, depsgraph, face_count)
        mark(target, faces, self.select_near)
        return faces

    # -- one frame, or a range without the interface (scripts, tests) --------

    def execute(self, context):
        scene = context.scene
        frames = (range(self.frame_start, self.frame_end + 1) if self.use_range
                  else [scene.frame_current])
        keep = scene.frame_current
        worst = None
        try:
            for frame in frames:
                if self.use_range:
                    scene.frame_set(frame)
                depsgraph, arrays = self._prepare(context)
                classes, counts = query(arrays[0], arrays[1], self.distance_rel, self.threads)
                if worst is None or counts["pairs"] > worst[1]["pairs"]:
                    worst = (frame, counts, classes, depsgraph, arrays)
        except Exception as e:  # selfcol's errors name the culprit
            self.report({"ERROR"}, "selfcol: %s" % e)
            return {"CANCELLED"}
        frame, counts, classes, depsgraph, arrays = worst
        if self.use_range and frame != scene.frame_current:
            scene.frame_set(frame)
            depsgraph, arrays = self._prepare(context)
        faces = self._finish(context, depsgraph, arrays, classes)
        line = _report_line(counts, faces, frame if self.use_range else None)
        if self.use_range:
            line = "worst " + line + " (of %d frames)" % len(frames)
        self.report({"INFO"}, line)
        context.window_manager["selfcol_last_report"] = line
        if not self.use_range:
            scene.frame_set(keep)
        return {"FINISHED"}

    # -- a range in the interface: a thread per frame, a progress bar --------

    def invoke(self, context, event):
        if not self.use_range:
            return self.execute(context)
        self._frames = list(range(self.frame_start, self.frame_end + 1))
        if not self._frames:
            self.report({"WARNING"}, "selfcol: the frame range is empty")
            return {"CANCELLED"}
        self._at = 0
        self._worker = None
        self._worst = None
        wm = context.window_manager
        wm.progress_begin(0, len(self._frames))
        self._timer = wm.event_timer_add(0.05, window=context.window)
        wm.modal_handler_add(self)
        self._started = time.monotonic()
        return {"RUNNING_MODAL"}

    def _start_frame(self, context):
        frame = self._frames[self._at]
        context.scene.frame_set(frame)
        depsgraph, arrays = self._prepare(context)
        box = {}

        def work():  # selfcol releases the lock: the interface keeps running
            try:
                box["result"] = query(arrays[0], arrays[1], self.distance_rel, self.threads)
            except Exception as e:
                box["error"] = e

        self._worker = (threading.Thread(target=work, daemon=True), box, frame)
        self._worker[0].start()

    def _end(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()

    def modal(self, context, event):
        if event.type == "ESC":
            if self._worker is not None:
                self._worker[0].join()
            self._end(context)
            self.report({"WARNING"}, "selfcol: cancelled after %d frames" % self._at)
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        if self._worker is None:
            self._start_frame(context)
            return {"RUNNING_MODAL"}
        thread, box, frame = self._worker
        if thread.is_alive():
            return {"RUNNING_MODAL"}
        self._worker = None
        if "error" in box:
            self._end(context)
            self.report({"ERROR"}, "selfcol: frame %d: %s" % (frame, box["error"]))
            return {"CANCELLED"}
        classes, counts = box["result"]
        if self._worst is None or counts["pairs"] > self._worst[1]["pairs"]:
            self._worst = (frame, counts, classes)
        self._at += 1
        context.window_manager.progress_update(self._at)
        if self._at < len(self._frames):
            return {"RUNNING_MODAL"}
        self._end(context)
        frame, counts, classes = self._worst
        context.scene.frame_set(frame)
        depsgraph, arrays = self._prepare(context)
        faces = self._finish(context, depsgraph, arrays, classes)
        line = "worst " + _report_line(counts, faces, frame) + " (of %d frames, %.1f s)" % (
            len(self._frames), time.monotonic() - self._started)
        self.report({"INFO"}, line)
        context.window_manager["selfcol_last_report"] = line
        return {"FINISHED"}


class SELFCOL_PT_panel(bpy.types.Panel):
    bl_label = "selfcol"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "selfcol"

    def draw(self, context):
        layout = self.layout
        scene = context.scene
        layout.prop(scene, "selfcol_distance_rel")
        layout.prop(scene, "selfcol_select_near")
        row = layout.row()
        row.prop(scene, "selfcol_use_range")
        sub = row.row(align=True)
        sub.enabled = scene.selfcol_use_range
        sub.prop(scene, "frame_start", text="")
        sub.prop(scene, "frame_end", text="")
        op = layout.operator(SELFCOL_OT_check.bl_idname, text="Check intersections")
        op.distance_rel = scene.selfcol_distance_rel
        op.select_near = scene.selfcol_select_near
        op.use_range = scene.selfcol_use_range
        op.frame_start = scene.frame_start
        op.frame_end = scene.frame_end
        last = context.window_manager.get("selfcol_last_report")
        if last:
            layout.label(text=last)
        layout.label(text="Show: Solid shading, Color: Attribute")


def _menu(self, context):
    self.layout.operator(SELFCOL_OT_check.bl_idname)


def register():
    bpy.utils.register_class(SELFCOL_OT_check)
    bpy.utils.register_class(SELFCOL_PT_panel)
    bpy.types.Scene.selfcol_distance_rel = bpy.props.FloatProperty(
        name="Distance (x mean edge)", default=0.1, min=0.0, soft_max=1.0)
    bpy.types.Scene.selfcol_select_near = bpy.props.BoolProperty(
        name="Select near faces", default=False)
    bpy.types.Scene.selfcol_use_range = bpy.props.BoolProperty(name="Frame range", default=False)
    bpy.types.VIEW3D_MT_object.append(_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_menu)
    del bpy.types.Scene.selfcol_use_range
    del bpy.types.Scene.selfcol_select_near
    del bpy.types.Scene.selfcol_distance_rel
    bpy.utils.unregister_class(SELFCOL_PT_panel)
    bpy.utils.unregister_class(SELFCOL_OT_check)
