"""The Python module foldfill: arrays in and out, the same results as the CLI,
cancellation, and the errors of bad arguments."""

import json
import subprocess
import threading
import time

import numpy as np
import pytest

import foldfill
from conftest import make_sheets, shared_file

# Keys of a report that are measured times, which differ between runs.
TIMINGS = {"seconds", "seconds_prepare", "seconds_holes", "seconds_stitch", "seconds_crossings",
           "seconds_total"}


def without_timings(value):
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k not in TIMINGS}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def test_read_write_round_trip(tmp_path, sheet):
    V, F = sheet
    for name in ("sheet.obj", "sheet.ply", "sheet.off"):
        foldfill.write(tmp_path / name, V, F)
        V2, F2 = foldfill.read(tmp_path / name)
        assert V2.dtype == np.float64 and V2.shape == V.shape
        assert F2.dtype == np.int64 and F2.shape == F.shape
        np.testing.assert_array_equal(V2, V)
        np.testing.assert_array_equal(F2, F)


def test_holes_lists_what_the_cli_lists(tmp_path, sheet, cli):
    V, F = sheet
    loops = foldfill.holes(V, F)
    assert [loop["kind"] for loop in loops] == ["outer_edge", "hole"]
    assert [loop["outer"] for loop in loops] == [True, False]
    foldfill.write(tmp_path / "sheet.obj", V, F)
    listed = subprocess.run([cli, "holes", str(tmp_path / "sheet.obj"), "--json"], check=True,
                            capture_output=True, text=True).stdout
    assert loops == json.loads(listed)["loops"]


def test_fill_arrays_in_and_out(sheet):
    V, F = sheet
    V0, F0 = V.copy(), F.copy()
    result = foldfill.fill(V, F)
    # The originals are unchanged, and come out first, bit-identical.
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)
    n, m = len(V), len(F)
    assert result.vertices.shape[1] == 3 and result.vertices.dtype == np.float64
    assert result.faces.dtype == np.int64 and len(result.faces) > m
    np.testing.assert_array_equal(result.vertices[:n], V)
    np.testing.assert_array_equal(result.faces[:m], F)
    # New faces are marked with their hole's id, the originals with -1.
    assert result.new_faces.shape == (len(result.faces),)
    assert (result.new_faces[:m] == -1).all() and (result.new_faces[m:] == 1).all()
    assert (result.new_vertices[:n] == -1).all() and (result.new_vertices[n:] == 1).all()
    report = result.report
    assert report["filled_loops"] == [1]
    assert [loop["loop_id"] for loop in report["left_open_loops"]] == [0]
    assert report["left_open_loops"][0]["kind"] == "outer_edge"
    assert report["holes"][0]["filled"] and report["holes"][0]["loop_id"] == 1
    # The hole is closed: only the outer edge is left.
    assert [loop["kind"] for loop in foldfill.holes(result.vertices, result.faces)] == [
        "outer_edge"]


def test_fill_takes_any_array_like(sheet):
    V, F = sheet
    expected = foldfill.fill(V, F)
    result = foldfill.fill(V.astype(np.float32).astype(np.float64).tolist(), F.astype(np.int32))
    assert result.faces.shape == expected.faces.shape


def test_selection(sheet):
    V, F = sheet
    assert foldfill.fill(V, F, holes="all").report["filled_loops"] == [1]
    assert foldfill.fill(V, F, holes=[1]).report["filled_loops"] == [1]
    centroid = foldfill.holes(V, F)[1]["centroid"]
    assert foldfill.fill(V, F, near=centroid).report["filled_loops"] == [1]
    nothing = foldfill.fill(V, F, max_hole_size=3)
    assert nothing.report["filled_loops"] == [] and len(nothing.faces) == len(F)
    with pytest.raises(foldfill.UsageError, match="no loop with id 7"):
        foldfill.fill(V, F, holes=[7])
    with pytest.raises(foldfill.UsageError, match="near"):
        foldfill.fill(V, F, holes="all", near=centroid)
    with pytest.raises(foldfill.UsageError, match="keep_open"):
        foldfill.fill(V, F, holes=[1], keep_open=1)
    with pytest.raises(foldfill.UsageError, match="lambda_"):
        foldfill.fill(V, F, lambda_=float("nan"))


def test_same_result_as_the_cli_on_a_reference_case(tmp_path, cli):
    path = shared_file("data", "reference", "paper2_hole.obj")
    if path is None:
        pytest.skip("shared data not found (FOLDFILL_SHARED, FOLDFILL_SHARED_DIR): "
                    "this test needs data/reference/paper2_hole.obj")
    out, report = tmp_path / "filled.obj", tmp_path / "report.json"
    subprocess.run([cli, "fill", path, "-o", str(out), "--report", str(report), "--quiet"],
                   check=True)
    V, F = foldfill.read(path)
    result = foldfill.fill(V, F)
    V_cli, F_cli = foldfill.read(out)
    np.testing.assert_array_equal(result.vertices, V_cli)
    np.testing.assert_array_equal(result.faces, F_cli)
    cli_report = json.loads(report.read_text())
    for key in ("input", "output"):
        del cli_report[key]
    assert without_timings(result.report) == without_timings(cli_report)


def test_progress_and_cancellation(sheet):
    V, F = sheet
    calls = []

    def record(hole, iteration, energy):
        calls.append((hole, iteration, energy))

    foldfill.fill(V, F, progress=record)
    assert calls and all(h == 1 and isinstance(i, int) and isinstance(e, float)
                         for h, i, e in calls)

    def stop(hole, iteration, energy):
        return iteration < 3

    with pytest.raises(foldfill.CancelledError, match="cancelled"):
        foldfill.fill(V, F, progress=stop)

    def fails(hole, iteration, energy):
        raise KeyError("from the callback")

    with pytest.raises(KeyError, match="from the callback"):
        foldfill.fill(V, F, progress=fails)


def test_gil_is_released_while_filling():
    # A finer sheet than the fixture's, whose fill takes long enough to tell.
    vertices, faces = (np.array(a) for a in make_sheets.folded_sheet(0, nx=65, ny=57))
    done = threading.Event()
    ticks = [0]

    def count():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    ticks_before = ticks[0]
    foldfill.fill(vertices, faces, density=2)
    seconds = time.perf_counter() - start
    done.set()
    counter.join()
    if seconds < 0.05:
        pytest.skip("the fills took {:.3f} s: too short to tell".format(seconds))
    # Holding the GIL for the whole fill would have stopped the counter (it
    # ticks about once a millisecond when it can run).
    assert ticks[0] - ticks_before > 0.05 * seconds / 0.001


@pytest.mark.parametrize("vertices, faces, error, message", [
    (np.zeros((4, 2)), [[0, 1, 2]], foldfill.UsageError, r"vertices: expected an array of shape \(n, 3\), got shape \(4, 2\)"),
    (np.zeros(12), [[0, 1, 2]], foldfill.UsageError, r"got shape \(12,\)"),
    (np.eye(3), [[0, 1]], foldfill.UsageError, r"faces: expected an array of shape \(n, 3\)"),
    (np.eye(3), [[0.0, 1.0, 2.0]], foldfill.UsageError, "faces: expected integer vertex indices"),
    (np.eye(3), [["a", "b", "c"]], foldfill.UsageError, "faces: expected integer"),
    ([[0, 0, 0], [1, 0, float("nan")], [0, 1, 0]], [[0, 1, 2]],
     foldfill.NonFiniteCoordinateError, "mesh: vertex 1 has a non-finite coordinate"),
    (np.eye(3), [[0, 1, 3]], foldfill.BadFaceError,
     r"mesh: face 0: face vertex 3 out of range \(mesh has 3 vertices\)"),
    (np.eye(3), [[0, 1, -1]], foldfill.BadFaceError, "face vertex -1 out of range"),
    (np.eye(3), [[0, 1, 2**40]], foldfill.BadFaceError, "out of range"),
    (np.eye(3), [[0, 1, 1]], foldfill.BadFaceError, "repeats vertex 1"),
])
def test_bad_arrays_raise_clear_errors(vertices, faces, error, message):
    for call in (foldfill.fill, foldfill.holes):
        with pytest.raises(error, match=message) as caught:
            call(vertices, faces)
        assert isinstance(caught.value, foldfill.Error)
        assert isinstance(caught.value, ValueError)
        # The mesh's content is an InputError, as in C++; bad arguments are not.
        assert isinstance(caught.value, foldfill.InputError) == (error is not foldfill.UsageError)


def test_file_errors(tmp_path, sheet):
    with pytest.raises(foldfill.ReadError, match="cannot open") as caught:
        foldfill.read(tmp_path / "missing.obj")
    assert isinstance(caught.value, OSError) and caught.value.kind == "cannot_read"
    (tmp_path / "garbage.off").write_text("not a mesh\n")
    with pytest.raises(foldfill.FormatError) as caught:
        foldfill.read(tmp_path / "garbage.off")
    assert isinstance(caught.value, foldfill.InputError) and caught.value.kind == "bad_format"
    with pytest.raises(foldfill.UsageError, match="unknown mesh format"):
        foldfill.write(tmp_path / "sheet.xyz", *sheet)
    with pytest.raises(foldfill.WriteError):
        foldfill.write(tmp_path / "no" / "such" / "folder.obj", *sheet)


def test_write_marks_new_faces(tmp_path, sheet):
    V, F = sheet
    result = foldfill.fill(V, F)
    foldfill.write(tmp_path / "filled.obj", result)
    text = (tmp_path / "filled.obj").read_text()
    assert "g foldfill_hole_1" in text
    V2, F2 = foldfill.read(tmp_path / "filled.obj")
    np.testing.assert_array_equal(V2, result.vertices)


def test_obstacles(sheet):
    V, F = sheet
    below = {"type": "plane", "point": [0, 0, -0.5], "normal": [0, 0, 1]}
    result = foldfill.fill(V, F, obstacles=[below])
    assert result.report["holes"][0]["filled"]
    with pytest.raises(foldfill.UsageError):
        foldfill.fill(V, F, obstacles=[{"type": "cube"}])


def test_docstrings():
    for name in foldfill.__all__:
        assert getattr(foldfill, name).__doc__, name
