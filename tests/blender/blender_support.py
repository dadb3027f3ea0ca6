"""What the Blender tests share: checks, installing the add-on, a mesh object in Edit Mode."""

import os

import bpy

NX, NY = 17, 15  # make_sheets.folded_sheet's grid
OUTER_EDGES = 2 * (NX - 1) + 2 * (NY - 1)


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def install_addon():
    zip_path = os.environ.get("FOLDFILL_ADDON_ZIP")
    check(zip_path and os.path.exists(zip_path),
          "FOLDFILL_ADDON_ZIP is not set to the add-on's zip (build/foldfill_blender_addon.zip)")
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bpy.ops.preferences.addon_enable(module="foldfill_addon")
    check(hasattr(bpy.types, "MESH_OT_foldfill_fill_holes"), "the operator is not registered")


def new_object(name, vertices, faces):
    """A new mesh object, active, alone in the scene, in Edit Mode with nothing selected."""
    if bpy.context.object and bpy.context.object.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='DESELECT')
    return obj


def boundary_edges(bm):
    return sum(1 for e in bm.edges if e.is_boundary)
