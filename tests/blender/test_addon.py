"""The Blender add-on in headless Blender:

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_addon.py

installs the add-on's zip (FOLDFILL_ADDON_ZIP, set by CTest; the zip carries
the foldfill module) into BLENDER_USER_SCRIPTS, builds a folded sheet with a
hole, runs Mesh > Clean Up > Fill Fabric Holes in Edit Mode and checks that
the hole is closed, the original vertices and faces are unchanged and the new
faces are selected, alone; then that a mesh foldfill refuses gives the
library's message as an error report. Any failure raises, and Blender exits
with 1.
"""

import os
import pathlib
import sys
import time

import bmesh
import bpy

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tools"))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import make_sheets  # noqa: E402

from blender_support import OUTER_EDGES, boundary_edges, check, install_addon, new_object  # noqa: E402


def test_fills_the_hole():
    vertices, faces = make_sheets.folded_sheet(0)
    obj = new_object("sheet", vertices, faces)
    bm = bmesh.from_edit_mesh(obj.data)
    check(boundary_edges(bm) > OUTER_EDGES, "the sheet has no hole")
    coordinates = [v.co[:] for v in bm.verts]  # float32 values, compared exactly
    original_faces = [tuple(v.index for v in f.verts) for f in bm.faces]

    start = time.perf_counter()
    result = bpy.ops.mesh.foldfill_fill_holes()
    print("foldfill_fill_holes: {:.2f} s".format(time.perf_counter() - start))
    check(result == {'FINISHED'}, "the operator returned {}".format(result))

    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.faces.ensure_lookup_table()
    check(boundary_edges(bm) == OUTER_EDGES, "{} boundary edges after the fill, not the outer "
          "edge's {}".format(boundary_edges(bm), OUTER_EDGES))
    check(len(bm.verts) > len(coordinates), "no vertex was added")
    for i, co in enumerate(coordinates):
        check(bm.verts[i].co[:] == co, "vertex {} moved: {} -> {}".format(i, co, bm.verts[i].co))
    for i, face in enumerate(original_faces):
        check(tuple(v.index for v in bm.faces[i].verts) == face, "face {} changed".format(i))
    new_faces = bm.faces[len(original_faces):]
    check(new_faces, "no face was added")
    check(all(f.select for f in new_faces), "a new face is not selected")
    check(not any(f.select for f in bm.faces[:len(original_faces)]),
          "an original face is selected")
    print("filled: {} new vertices, {} new faces".format(
        len(bm.verts) - len(coordinates), len(new_faces)))


def test_selection_names_the_hole():
    # Quads (the add-on triangulates a copy); a vertex of the hole's rim selected.
    vertices, triangles = make_sheets.folded_sheet(0)
    pairs = {}
    for a, b, c in triangles:
        pairs.setdefault(a, []).append((a, b, c))
    quads, faces = 0, []
    for a, group in pairs.items():
        if len(group) == 2 and group[0][2] == group[1][1]:  # [a, b, d] and [a, d, c]
            (_, b, d), (_, _, c) = group
            faces.append([a, b, d, c])
            quads += 1
        else:
            faces.extend(list(t) for t in group)
    check(quads > 100, "the sheet has no quads")
    obj = new_object("quads", vertices, faces)
    bm = bmesh.from_edit_mesh(obj.data)
    hole_rim = [v for v in bm.verts if v.is_boundary and 0.05 < v.co.x < 1.55
                and 0.05 < v.co.y < 1.35]
    check(hole_rim, "no vertex on the hole's rim")
    hole_rim[0].select = True
    original_faces = [tuple(v.index for v in f.verts) for f in bm.faces]
    face_count = len(original_faces)
    check(bpy.ops.mesh.foldfill_fill_holes(density=1.5) == {'FINISHED'}, "the operator failed")
    bm = bmesh.from_edit_mesh(obj.data)
    check(boundary_edges(bm) == OUTER_EDGES, "the hole is still open")
    bm.faces.ensure_lookup_table()
    check([tuple(v.index for v in bm.faces[i].verts) for i in range(face_count)] == original_faces,
          "an original face changed")
    check(sorted(f.index for f in bm.faces if f.select) == list(range(face_count, len(bm.faces))),
          "the selection is not the new faces")


def test_error_is_reported():
    # Three faces on one edge: foldfill refuses the mesh (NonManifoldError); the
    # operator reports the message as an error, which bpy.ops raises.
    vertices = [(0, 0, 0), (1, 0, 0), (0.5, 1, 0), (0.5, -1, 0), (0.5, 0, 1)]
    obj = new_object("bad", vertices, [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
    try:
        bpy.ops.mesh.foldfill_fill_holes()
    except RuntimeError as e:
        check("edge" in str(e), "the error does not say what is wrong: {}".format(e))
        print("error reported: {}".format(str(e).strip()))
    else:
        raise AssertionError("a non-manifold mesh was not refused")
    check(len(bmesh.from_edit_mesh(obj.data).faces) == 3, "the refused mesh changed")


start = time.perf_counter()
install_addon()
test_fills_the_hole()
test_selection_names_the_hole()
test_error_is_reported()
print("test_addon: all checks passed in {:.1f} s".format(time.perf_counter() - start))
