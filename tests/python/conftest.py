"""Shared fixtures of the Python module's tests.

ctest (tests/CMakeLists.txt, python/pytest) sets the environment: PYTHONPATH to the build
tree's package, MSDEFORM_SOURCE_DIR, MSDEFORM_BUILD_DIR, and the command-line programs
MSDEFORM_CLI and MSDEFORM_EXPERIMENTS. A missing variable is an error, not a skip.
"""

import os
import pathlib

import numpy as np
import pytest


def _required_path(variable):
    value = os.environ.get(variable)
    if not value:
        raise RuntimeError(f"{variable} is not set: run these tests through ctest (python/pytest)")
    path = pathlib.Path(value)
    if not path.exists():
        raise RuntimeError(f"{variable}={value}: no such file or folder")
    return path


@pytest.fixture(scope="session")
def source_dir():
    """The repository root."""
    return _required_path("MSDEFORM_SOURCE_DIR")


@pytest.fixture(scope="session")
def cli():
    """The msdeform command-line program."""
    return _required_path("MSDEFORM_CLI")


@pytest.fixture(scope="session")
def experiments_cli():
    """The msdeform_experiments program (the experiment runner)."""
    return _required_path("MSDEFORM_EXPERIMENTS")


@pytest.fixture(scope="session")
def meshes(source_dir):
    """data/meshes/, with the real meshes scripts/build.sh brings."""
    folder = source_dir / "data" / "meshes"
    if not (folder / "cactus.off").exists():
        raise RuntimeError(f"{folder}: no cactus.off; run scripts/build.sh first")
    return folder


@pytest.fixture(scope="session")
def scenarios(source_dir):
    """experiments/scenarios/."""
    return source_dir / "experiments" / "scenarios"


def read_off_exact(path):
    """(V, F) of a triangle OFF (or COFF) file in the one-item-per-line layout msdeform
    writes, coordinates parsed as doubles and colours ignored.

    Parsed without msdeform, to check msdeform.read_mesh and write_mesh against the file's
    own numbers (e.g. the exact doubles msdeform's writer printed).
    """
    with open(path) as file:
        assert file.readline().strip() in ("OFF", "COFF")
        num_vertices, num_faces, _ = (int(x) for x in file.readline().split())
        V = np.loadtxt(file, max_rows=num_vertices, dtype=np.float64, ndmin=2)[:, :3]
        F = np.loadtxt(file, max_rows=num_faces, dtype=np.int64, ndmin=2)[:, 1:4]
    return V, F
