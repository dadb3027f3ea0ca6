"""The Blender add-on in Blender with its window (under a virtual X display):

    xvfb-run -a blender --factory-startup --python tests/blender/test_addon_ui.py

What headless Blender cannot show: undo and the status bar's progress. With
a window, Blender keeps an undo stack and a window manager that shows
progress. The test installs the add-on, builds a folded sheet with a hole in
Edit Mode and runs Fill Fabric Holes from the window's event loop (a timer).
It then checks that the status bar's progress rose to its end, that Edit > Undo
gives back the sheet with its hole, bit for bit, and that Redo fills it again.
Blender exits with 0 when every check passes, else with 1.
"""

import os
import pathlib
import sys
import traceback

import bmesh
import bpy

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tools"))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import make_sheets  # noqa: E402

from blender_support import OUTER_EDGES, boundary_edges, check, install_addon, new_object  # noqa: E402


def mesh_state(obj):
    """The edit mesh's coordinates and faces, for exact comparison."""
    bm = bmesh.from_edit_mesh(obj.data)
    return ([v.co[:] for v in bm.verts], [tuple(v.index for v in f.verts) for f in bm.faces],
            boundary_edges(bm))


def test_undo_and_progress():
    import foldfill_addon

    vertices, faces = make_sheets.folded_sheet(0)
    obj = new_object("sheet", vertices, faces)
    bpy.ops.ed.undo_push(message="sheet with a hole")
    before = mesh_state(obj)
    check(before[2] > OUTER_EDGES, "the sheet has no hole")

    # As from the menu: the call pushes its undo step (the second argument).
    check(bpy.ops.mesh.foldfill_fill_holes('EXEC_DEFAULT', True) == {'FINISHED'},
          "the operator failed")
    filled = mesh_state(obj)
    check(filled[2] == OUTER_EDGES, "the hole is still open after the fill")
    check(len(filled[1]) > len(before[1]), "no face was added")

    shown = list(foldfill_addon.last_progress)
    check(shown, "no progress was shown")
    check(all(a <= b for a, b in zip(shown, shown[1:])), "the progress went back: {}".format(shown))
    check(shown[-1] == foldfill_addon.PROGRESS_STEPS,
          "the progress ended at {} of {}".format(shown[-1], foldfill_addon.PROGRESS_STEPS))

    bpy.ops.ed.undo()
    obj = bpy.context.view_layer.objects.active
    check(obj is not None and obj.mode == 'EDIT', "undo left no mesh in Edit Mode")
    check(mesh_state(obj) == before, "undo did not give back the sheet as it was")

    bpy.ops.ed.redo()
    obj = bpy.context.view_layer.objects.active
    check(mesh_state(obj) == filled, "redo did not give back the filled sheet")
    print("undo and redo: {} faces -> {} -> {} -> {}; progress shown {} times".format(
        len(before[1]), len(filled[1]), len(before[1]), len(filled[1]), len(shown)))


def run():
    code = 0
    try:
        check(bpy.context.window is not None, "Blender has no window (run it without -b)")
        install_addon()
        test_undo_and_progress()
        print("test_addon_ui: all checks passed")
    except Exception:
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)  # from a timer, sys.exit would only end the timer


# The checks run once the window's event loop has started.
bpy.app.timers.register(run, first_interval=0.5)
