"""Fixtures of the Python module's tests: a folded sheet with a hole, the CLI
and the shared reference data (FOLDFILL_CLI, FOLDFILL_SHARED or
FOLDFILL_SHARED_DIR, set by CTest)."""

import os
import pathlib
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tools"))
import make_sheets  # noqa: E402


@pytest.fixture
def sheet():
    """(vertices, faces) of a folded sheet with one hole (loop 1) inside it."""
    vertices, faces = make_sheets.folded_sheet(0)
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


@pytest.fixture
def cli():
    path = os.environ.get("FOLDFILL_CLI")
    if not path or not os.path.exists(path):
        pytest.skip("FOLDFILL_CLI is not set to the foldfill program")
    return path


def shared_file(*parts):
    """A file of the shared data, or None when it is absent."""
    for variable in ("FOLDFILL_SHARED", "FOLDFILL_SHARED_DIR"):
        root = os.environ.get(variable)
        if root and os.path.exists(os.path.join(root, *parts)):
            return os.path.join(root, *parts)
    return None
