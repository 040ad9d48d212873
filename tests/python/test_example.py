"""examples/drag_cactus.py runs as its docstring says and writes what it prints."""

import os
import subprocess
import sys

import numpy as np

import msdeform


def test_example_runs_and_writes_the_two_meshes(source_dir, meshes, tmp_path):
    result = subprocess.run([sys.executable, str(source_dir / "examples" / "drag_cactus.py"),
                             str(tmp_path)], check=True, capture_output=True, text=True,
                            env=dict(os.environ))
    lines = result.stdout.splitlines()
    assert lines[0] == "cactus: 620 vertices, 68 fixed, 87 handle"
    assert any(line.strip().startswith("multiscale: scale") for line in lines)
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    for method in ("multiscale", "static"):
        V2, F2 = msdeform.read_mesh(tmp_path / f"cactus_{method}.off")
        assert np.array_equal(F2, F)
        assert np.abs(V2 - V).max() > 0.1 * msdeform.bounding_box_diagonal(V)
