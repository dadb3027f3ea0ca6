"""foldfill: fill holes in triangle meshes of fabric so that the folds continue.

Meshes are NumPy arrays: ``vertices`` of shape (n, 3) (float64) and ``faces``
of shape (m, 3) (integer indices into ``vertices``, counted from 0, each face
counter-clockwise seen from its front side).

    import foldfill
    V, F = foldfill.read("scan.obj")
    result = foldfill.fill(V, F)                  # the holes, as `foldfill fill` picks them
    foldfill.write("filled.ply", result.vertices, result.faces, new_faces=result.new_faces)

Errors raise subclasses of :class:`foldfill.Error` with the command line's
messages (``UsageError`` and the errors about a mesh's content, subclasses of
``InputError``, are also ``ValueError``; ``ReadError`` and ``WriteError`` are
also ``OSError``).
"""

import json as _json
import math as _math
import os as _os
import warnings as _warnings

import numpy as _np

from . import _foldfill
from ._foldfill import (
    BadFaceError,
    CancelledError,
    Error,
    FillError,
    FormatError,
    InputError,
    InternalError,
    NonFiniteCoordinateError,
    NonManifoldError,
    NotADiskError,
    ReadError,
    UsageError,
    WriteError,
)

__all__ = [
    "read", "write", "holes", "fill", "FillResult",
    "Error", "UsageError", "ReadError", "InputError", "FormatError", "NonFiniteCoordinateError",
    "BadFaceError", "NonManifoldError", "NotADiskError", "FillError", "WriteError",
    "InternalError", "CancelledError",
]
__version__ = "0.1.0"

_MESH_EXTENSIONS = (".obj", ".ply", ".off", ".stl")


def read(path):
    """Read a mesh file (OBJ, PLY, OFF or STL, by its extension).

    Returns ``(vertices, faces)``: a float64 array of shape (n, 3) and an int64
    array of shape (m, 3). Polygons are split into triangle fans. What the
    reader drops or mends (references that point nowhere, unsupported PLY
    elements) is reported with :func:`warnings.warn`, one line each.

    Raises ReadError when the file cannot be read, FormatError,
    NonFiniteCoordinateError or BadFaceError for bad content, UsageError for an
    unknown extension.
    """
    vertices, faces, warnings = _foldfill.read(_os.fspath(path))
    for warning in warnings:
        _warnings.warn(warning, stacklevel=2)
    return vertices, faces


def write(path, vertices, faces=None, *, new_faces=None, new_vertices=None, ascii=False):
    """Write a mesh file, its format by the extension of ``path``.

    ``vertices`` and ``faces`` are arrays as :func:`read` returns them; a
    :class:`FillResult` may be passed instead of both (its marks are then
    written too). ``new_faces`` / ``new_vertices`` (one int per face / vertex:
    the hole id of a new element, -1 for an original one) are written as the
    command line writes its output: PLY gets an ``int foldfill_hole`` property,
    OBJ a group ``g foldfill_hole_<id>`` per run of new faces. ``ascii``: PLY
    and STL as text instead of binary. The file is written to a temporary name
    and renamed into place, so a failure leaves no partial file.

    Raises UsageError for an unknown extension or bad arrays,
    NonFiniteCoordinateError / BadFaceError for a bad mesh, WriteError when the
    file cannot be written.
    """
    if isinstance(vertices, FillResult):
        result = vertices
        vertices, faces = result.vertices, result.faces
        if new_faces is None:
            new_faces = result.new_faces
        if new_vertices is None:
            new_vertices = result.new_vertices
    if faces is None:
        raise UsageError("write: faces are missing")
    _foldfill.write(_os.fspath(path), vertices, faces, new_vertices, new_faces, bool(ascii))


def holes(vertices, faces, *, keep_open=None):
    """List the boundary loops of a mesh and what each one is.

    Returns one dict per loop with the fields of ``foldfill holes --json``:
    ``id``, ``vertex_count``, ``length``, ``centroid``, ``bbox_diagonal``,
    ``mean_edge_length``, ``kind`` ("hole", "outer_edge", "tube_end",
    "not_a_disk"), ``kind_reason``, ``explanation``, ``outer`` (whether the
    default fill leaves it open; with ``keep_open=N``, whether that rule does),
    ``turning``, ``curvature_density``, ``predicted_area`` (None where the
    curvature around the loop is not positive), ``component_area``,
    ``hole_like``, ``disk``, ``reason``, ``split_at`` and ``vertices`` (0-based
    vertex indices in loop order).

    Raises UsageError for bad arrays, NonFiniteCoordinateError, BadFaceError or
    NonManifoldError for a bad mesh.
    """
    keep = -1 if keep_open is None else _whole("keep_open", keep_open, 0)
    return _json.loads(_foldfill.holes(vertices, faces, keep, "mesh"))


class FillResult:
    """The result of :func:`fill`.

    Attributes:
        vertices: float64 array (n', 3): the input's vertices, bit-identical and
            in the same order, then the new ones.
        faces: int64 array (m', 3): the input's faces, then the new ones.
        new_faces: int64 array (m',): the hole (loop id) each face fills, -1
            for the input's faces.
        new_vertices: int64 array (n',): the same for vertices.
        report: dict, the content of the command line's JSON report (``--report``)
            without the file names: per hole ``holes[k]`` (loop id, filled,
            reason, method, counts, energies, timings, ...), ``filled_loops``,
            ``left_open_loops``, ``warnings``, timings.
    """

    __slots__ = ("vertices", "faces", "new_faces", "new_vertices", "report")

    def __init__(self, vertices, faces, new_faces, new_vertices, report):
        self.vertices = vertices
        self.faces = faces
        self.new_faces = new_faces
        self.new_vertices = new_vertices
        self.report = report

    def __repr__(self):
        return "FillResult({} vertices, {} faces, filled loops {})".format(
            len(self.vertices), len(self.faces), self.report.get("filled_loops"))


def _finite(name, value, low=-_math.inf, high=_math.inf, above=False):
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise UsageError("{}: {!r} is not a number".format(name, value)) from None
    if isinstance(value, bool) or not _math.isfinite(number):
        raise UsageError("{}: {!r} is not a finite number".format(name, value))
    if (above and number <= low) or number < low or number > high:
        where = "above {}".format(low) if above else "in [{}, {}]".format(low, high)
        raise UsageError("{}: {!r} is not {}".format(name, value, where))
    return number


def _whole(name, value, low, high=2**31 - 1):
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise UsageError("{}: {!r} is not a whole number".format(name, value))
    if value < low or value > high:
        raise UsageError("{}: {!r} is not in [{}, {}]".format(name, value, low, high))
    return int(value)


def _choice(name, value, allowed):
    if value not in allowed:
        raise UsageError("{}: {!r} is not one of {}".format(name, value, ", ".join(allowed)))
    return value


def _point(value):
    try:
        point = [float(c) for c in value]
    except (TypeError, ValueError):
        point = []
    if len(point) != 3 or not all(_math.isfinite(c) for c in point):
        raise UsageError("near: {!r} is not a point (three finite numbers x, y, z)".format(value))
    return point


def fill(vertices, faces, holes="default", *, near=None, keep_open=None, max_hole_size=None,
         max_hole_diameter=None, lambda_=_foldfill.DEFAULT_LAMBDA,
         shrink=_foldfill.DEFAULT_SHRINK, density=_foldfill.DEFAULT_DENSITY,
         repulsion=_foldfill.DEFAULT_REPULSION, thickness=_foldfill.DEFAULT_THICKNESS,
         bending="quadratic", solver="fast", max_iterations=_foldfill.DEFAULT_MAX_ITERATIONS,
         coarse_start=_foldfill.DEFAULT_COARSE_START, time_limit=0, method="foldfill",
         obstacles=(), progress=None):
    """Fill holes in a mesh, as ``foldfill fill`` does (Gisbert, Chaine and
    Coeurjolly, *Inpainting holes in folded fabric meshes*, 2023): per hole,
    flatten the strip around it (LSCM), triangulate the flat outline, embed the
    patch with ARAP and a fabric energy that never lets it cross anything, and
    stitch it in.

    Selection (the command line's rules; see ``foldfill holes``):
        holes: "default" or "auto" (the loops that are holes; outer edges and
            tube ends stay open), "all" (the same, said explicitly), or a list
            of loop ids (as :func:`holes` lists them), filled whatever they are.
        near: a point (x, y, z) or a list of points; each fills its nearest
            loop (refused when farther from every loop than that loop's size).
            With a list of ids in ``holes``: every loop named.
        keep_open: instead, fill all but the N longest loops.
        max_hole_size: on top: only loops of at most N boundary edges.
        max_hole_diameter: on top: only loops whose bounding-box diagonal is at
            most D mean edge lengths of the mesh.

    Parameters (the command line's options of the same names):
        lambda_ (bending stiffness, >= 0), shrink (ARAP shrink factor c, in
        [0.01, 1]), density (interior vertex density, in [0.1, 10]),
        repulsion (>= 0), thickness (in [1e-4, 1]), bending ("quadratic" or
        "two-ring"), solver ("fast" or "gd"), max_iterations (per hole),
        coarse_start (0: never), time_limit (seconds per hole, 0: none),
        method ("foldfill", or "liepa": CGAL's smooth fill).
        obstacles: a list of things the patch stays outside of: dicts as in an
            obstacles file ({"type": "sphere", "center": [x, y, z],
            "radius": r}, "cylinder", "plane"), paths of obstacles files (JSON
            or the prototype's text), paths of mesh files (.obj, .ply, .off,
            .stl), or (vertices, faces) pairs of meshes.
        progress: None, or a callable progress(hole, iteration, energy) called
            while each hole is minimised (from the filling threads, holding the
            GIL); returning False cancels the fill. An exception it raises
            cancels the fill and is raised by fill.

    The input arrays are not modified. The GIL is released while filling.

    Returns a :class:`FillResult`. A hole that cannot be filled is left open,
    with its reason in ``report["holes"][k]["reason"]``.

    Raises UsageError for bad arguments or arrays (wrong shape or type, an
    unknown loop id, contradicting options), NonFiniteCoordinateError,
    BadFaceError, NonManifoldError for a bad mesh, NotADiskError for a named
    loop that is not a disk's boundary, CancelledError when ``progress``
    returned False.
    """
    args = _foldfill.FillArguments()
    ids = []
    if isinstance(holes, str):
        mode = _choice("holes", holes, ("default", "auto", "all"))
        mode = "default" if mode == "auto" else mode
    else:
        try:
            ids = [_whole("holes", i, 0) for i in holes]
        except TypeError:
            raise UsageError("holes: {!r} is not 'default', 'auto', 'all' or a list of loop "
                             "ids".format(holes)) from None
        if not ids:
            raise UsageError("holes: an empty list of loop ids")
        mode = "ids"
    points = []
    if near is not None:
        near_list = list(near)
        single = len(near_list) == 3 and all(
            isinstance(c, (int, float, _np.number)) for c in near_list)
        points = [_point(near_list)] if single else [_point(p) for p in near_list]
        if not points:
            raise UsageError("near: no point")
        if mode == "all":
            raise UsageError("near: not with holes='all' (near names loops; so does a list "
                             "of loop ids)")
        mode = "near"
    if keep_open is not None:
        if mode != "default" or holes != "default":
            raise UsageError("keep_open: not with holes or near (it is a choice of its own: "
                             "all but the N longest loops)")
        args.keep_open = _whole("keep_open", keep_open, 0)
        mode = "keep_open"
    args.mode, args.ids, args.near = mode, ids, points
    if max_hole_size is not None:
        args.max_hole_size = _whole("max_hole_size", max_hole_size, 1)
    if max_hole_diameter is not None:
        args.max_hole_diameter = _finite("max_hole_diameter", max_hole_diameter, 0, above=True)
    args.lambda_ = _finite("lambda_", lambda_, 0)
    args.shrink = _finite("shrink", shrink, 0.01, 1.0)
    args.density = _finite("density", density, 0.1, 10.0)
    args.repulsion = _finite("repulsion", repulsion, 0)
    args.thickness = _finite("thickness", thickness, 1e-4, 1.0)
    args.bending = _choice("bending", bending, ("quadratic", "two-ring"))
    args.solver = _choice("solver", solver, ("fast", "gd"))
    args.method = _choice("method", method, ("foldfill", "liepa"))
    args.max_iterations = _whole("max_iterations", max_iterations, 1)
    args.coarse_start = _whole("coarse_start", coarse_start, 0)
    args.time_limit = _finite("time_limit", time_limit, 0)
    _set_obstacles(args, obstacles)
    if progress is not None and not callable(progress):
        raise UsageError("progress: {!r} is not callable".format(progress))
    V, F, new_vertices, new_faces, report = _foldfill.fill(vertices, faces, args, progress)
    return FillResult(V, F, new_faces, new_vertices, _json.loads(report))


def _set_obstacles(args, obstacles):
    shapes, files, mesh_files, meshes = [], [], [], []
    for k, obstacle in enumerate(obstacles or ()):
        if isinstance(obstacle, dict):
            shapes.append(obstacle)
        elif isinstance(obstacle, (str, bytes, _os.PathLike)):
            path = _os.fsdecode(obstacle)
            (mesh_files if path.lower().endswith(_MESH_EXTENSIONS) else files).append(path)
        elif isinstance(obstacle, (tuple, list)) and len(obstacle) == 2:
            meshes.append((obstacle[0], obstacle[1]))
        else:
            raise UsageError("obstacles[{}]: {!r} is not a dict, a file or a (vertices, faces) "
                             "pair".format(k, obstacle))
    if shapes:
        try:
            args.obstacles_json = _json.dumps({"obstacles": shapes})
        except (TypeError, ValueError) as e:
            raise UsageError("obstacles: {}".format(e)) from None
    args.obstacle_files, args.obstacle_mesh_files, args.obstacle_meshes = files, mesh_files, meshes
