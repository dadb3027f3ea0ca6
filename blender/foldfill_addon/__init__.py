"""Blender add-on: fill holes in fabric meshes with foldfill.

Edit Mode > Mesh > Clean Up > Fill Fabric Holes (``mesh.foldfill_fill_holes``)
fills the boundary loops that have a selected vertex, or the loops foldfill
takes for holes (its default selection: outer edges and sleeve ends stay open)
when nothing, or everything, is selected. The original vertices and faces stay
as they are; the new ones are appended and the new faces are selected, alone.

The add-on needs the Python module ``foldfill``, built for the Python Blender
runs on (Debian's Blender 3.4: the system Python 3.11). It is looked for, in
this order: a copy bundled in the add-on's folder (the zip that
scripts/package_blender_addon.sh writes carries one when the module was
built), the folder set in the add-on's preferences, and Python's own path
(PYTHONPATH, or the module installed into site-packages).
"""

bl_info = {
    "name": "foldfill: Fill Fabric Holes",
    "author": "foldfill authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Edit Mode > Mesh > Clean Up > Fill Fabric Holes",
    "description": "Fill holes in cloth meshes so that the folds continue through them",
    "category": "Mesh",
}

import importlib
import inspect
import os
import sys
import threading
import time

import bmesh
import bpy
import numpy as np
from bpy.props import FloatProperty, StringProperty

# The library's defaults (foldfill.DEFAULT_*), repeated here so that the redo
# panel can be built before the module is found.
DEFAULT_LAMBDA = 0.0002
DEFAULT_SHRINK = 0.5
DEFAULT_DENSITY = 1.0
DEFAULT_REPULSION = 1.0

# Steps of the status bar's progress: each hole gets an equal share.
PROGRESS_STEPS = 1000

# The values the last fill showed in the status bar's progress, in order
# (the last one is PROGRESS_STEPS when the fill finished): for scripts and
# tests that want to see what a user saw.
last_progress = []


def _load_foldfill(context):
    """The foldfill module, or raise ImportError saying where it was looked for."""
    bundled = os.path.join(os.path.dirname(__file__), "foldfill", "__init__.py")
    if os.path.exists(bundled):
        return importlib.import_module(__name__ + ".foldfill")
    addon = context.preferences.addons.get(__name__)
    folder = bpy.path.abspath(addon.preferences.module_dir) if addon else ""
    if folder and folder not in sys.path:
        sys.path.insert(0, folder)
    try:
        return importlib.import_module("foldfill")
    except ImportError as e:
        raise ImportError(
            "the Python module foldfill is not found ({}); build it (build/python/foldfill) and "
            "set its folder (build/python) in the add-on's preferences, or install the zip of "
            "scripts/package_blender_addon.sh, which carries it".format(e)) from None


class FoldfillPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__

    module_dir: StringProperty(
        name="Module folder",
        description="Folder that holds the foldfill Python package (build/python of a "
                    "foldfill build); not needed when the add-on carries the module or "
                    "Python finds it",
        subtype='DIR_PATH',
    )

    def draw(self, context):
        self.layout.prop(self, "module_dir")


def _triangles(bm):
    """The faces of `bm` as vertex index triples; polygons split on a copy."""
    if all(len(f.verts) == 3 for f in bm.faces):
        return [[v.index for v in f.verts] for f in bm.faces]
    # bmesh.ops.triangulate adds no vertex, so the copy's indices are the mesh's.
    copy = bm.copy()
    try:
        bmesh.ops.triangulate(copy, faces=copy.faces[:])
        copy.verts.index_update()
        return [[v.index for v in f.verts] for f in copy.faces]
    finally:
        copy.free()


class MESH_OT_foldfill_fill_holes(bpy.types.Operator):
    """Fill the holes touched by the selection (every hole when nothing is selected) \
so that the folds of the cloth continue through them"""

    bl_idname = "mesh.foldfill_fill_holes"
    bl_label = "Fill Fabric Holes"
    bl_options = {'REGISTER', 'UNDO'}

    lambda_: FloatProperty(
        name="Lambda", description="Bending stiffness relative to the edge-length term",
        default=DEFAULT_LAMBDA, min=0.0, soft_max=0.01, precision=5, step=0.01)
    shrink: FloatProperty(
        name="Shrink", description="ARAP shrink factor c of the rest shape",
        default=DEFAULT_SHRINK, min=0.01, max=1.0)
    density: FloatProperty(
        name="Density", description="Interior vertex density relative to the boundary's",
        default=DEFAULT_DENSITY, min=0.1, max=10.0)
    repulsion: FloatProperty(
        name="Repulsion", description="Self-repulsion weight of the fabric energy",
        default=DEFAULT_REPULSION, min=0.0, soft_max=10.0)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == 'MESH' and context.mode == 'EDIT_MESH'

    def execute(self, context):
        try:
            foldfill = _load_foldfill(context)
        except ImportError as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        mesh = context.active_object.data
        bm = bmesh.from_edit_mesh(mesh)
        bm.verts.ensure_lookup_table()
        bm.verts.index_update()
        vertices = np.array([v.co[:] for v in bm.verts], dtype=np.float64).reshape(-1, 3)
        faces = np.array(_triangles(bm), dtype=np.int64).reshape(-1, 3)
        if not len(faces):
            self.report({'ERROR'}, "the mesh has no faces")
            return {'CANCELLED'}

        try:
            holes, targets = self._choose(foldfill, bm, vertices, faces)
        except foldfill.Error as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        if holes is None:
            self.report({'WARNING'}, "the selection touches no boundary loop: nothing to fill")
            return {'CANCELLED'}
        if not targets:
            self.report({'INFO'}, "the mesh has no hole to fill (outer edges stay open)")
            return {'CANCELLED'}

        start = time.perf_counter()
        try:
            result = self._fill(context, foldfill, vertices, faces, holes, targets)
        except foldfill.Error as e:
            self.report({'ERROR'}, str(e))
            return {'CANCELLED'}
        seconds = time.perf_counter() - start

        added_vertices, added_faces = self._write(context, mesh, bm, result, len(vertices))
        self._summarise(result, added_vertices, added_faces, seconds)
        return {'FINISHED'}

    def _choose(self, foldfill, bm, vertices, faces):
        """(holes argument of foldfill.fill, loop ids expected to be filled).

        holes is None when vertices are selected but no boundary loop has one.
        """
        selected = {v.index for v in bm.verts if v.select}
        loops = foldfill.holes(vertices, faces)
        if not selected or len(selected) == len(bm.verts):
            return "default", [loop["id"] for loop in loops if not loop["outer"]]
        touched = [loop["id"] for loop in loops if selected.intersection(loop["vertices"])]
        return (touched or None), touched

    def _fill(self, context, foldfill, vertices, faces, holes, targets):
        """foldfill.fill in a worker thread, the progress shown from this one.

        Blender's API is called from the main thread only: the progress
        callback (called from foldfill's threads) just records where the fill
        is, and this thread turns it into the status bar's progress.
        """
        share = {hole: k for k, hole in enumerate(targets)}
        iterations = inspect.signature(foldfill.fill).parameters["max_iterations"].default
        state = {"value": 0.0, "result": None, "error": None}

        def progress(hole, iteration, energy):
            if hole in share:
                done = share[hole] + min(iteration / iterations, 1.0)
                state["value"] = max(state["value"], PROGRESS_STEPS * done / len(targets))
            return True

        def work():
            try:
                state["result"] = foldfill.fill(
                    vertices, faces, holes=holes, lambda_=self.lambda_, shrink=self.shrink,
                    density=self.density, repulsion=self.repulsion, progress=progress)
            except BaseException as e:  # raised again in the main thread
                state["error"] = e

        wm = context.window_manager
        shown = []
        last_progress[:] = []

        def show(value):
            wm.progress_update(value)
            shown.append(value)

        wm.progress_begin(0, PROGRESS_STEPS)
        try:
            worker = threading.Thread(target=work, name="foldfill")
            worker.start()
            while worker.is_alive():
                worker.join(0.1)
                show(int(state["value"]))
            if state["error"] is None:
                show(PROGRESS_STEPS)
        finally:
            wm.progress_end()
            last_progress[:] = shown
        if state["error"] is not None:
            raise state["error"]
        return state["result"]

    @staticmethod
    def _write(context, mesh, bm, result, original_count):
        """Append the result's new vertices and faces to `bm`; select the new faces alone."""
        new_verts = [bm.verts.new(co) for co in result.vertices[original_count:].tolist()]
        bm.verts.ensure_lookup_table()
        for element in (*bm.verts, *bm.edges, *bm.faces):
            element.select = False
        added = 0
        for face, hole in zip(result.faces.tolist(), result.new_faces.tolist()):
            if hole < 0:
                continue
            new_face = bm.faces.new([bm.verts[i] for i in face])
            new_face.select_set(True)
            added += 1
        # Face select mode, so that the selection stays the new faces only (in
        # vertex mode an original face with its three vertices on the hole's
        # rim would become selected as well).
        bm.select_mode = {'FACE'}
        context.tool_settings.mesh_select_mode = (False, False, True)
        bm.select_flush_mode()
        bm.verts.index_update()
        bm.faces.index_update()
        bmesh.update_edit_mesh(mesh, loop_triangles=True, destructive=True)
        return len(new_verts), added

    def _summarise(self, result, added_vertices, added_faces, seconds):
        report = result.report
        filled = report.get("filled_loops") or []
        message = "Filled {} hole{} (loop{} {}): {} new vertices, {} new faces, {:.1f} s".format(
            len(filled), "" if len(filled) == 1 else "s", "" if len(filled) == 1 else "s",
            ", ".join(str(i) for i in filled) or "none", added_vertices, added_faces, seconds)
        open_holes = [hole for hole in report.get("holes", []) if not hole.get("filled")]
        if open_holes:
            reasons = "; ".join("loop {}: {}".format(h.get("loop_id"), h.get("reason"))
                                for h in open_holes)
            self.report({'WARNING'}, message + "; left open: " + reasons)
        else:
            self.report({'INFO'}, message)


def _menu(self, context):
    self.layout.operator(MESH_OT_foldfill_fill_holes.bl_idname)


_classes = (FoldfillPreferences, MESH_OT_foldfill_fill_holes)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_edit_mesh_clean.append(_menu)


def unregister():
    bpy.types.VIEW3D_MT_edit_mesh_clean.remove(_menu)
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
