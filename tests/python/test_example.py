"""examples/drag_cactus.py runs as its docstring says, writes what it prints, and prints the
handle error and ARAP energy of the meshes it wrote, recomputed here independently (NumPy from
the files and the .def, with an ARAP energy checked on deformations of known energy)."""

import os
import re
import subprocess
import sys

import numpy as np

import msdeform
from conftest import read_off_exact


def arap_energy(V, F, V2):
    """Sorkine & Alexa's cotangent ARAP energy over its normaliser, sum_i E_i / sum_i N_i, in
    NumPy: E_i = sum_j w_ij |e'_ij - R_i e_ij|^2 with R_i the best rotation, N_i = sum_j
    w_ij |e_ij|^2, w_ij = (cot a_ij + cot b_ij) / 2 clamped at 0 (experiments/metrics.h)."""
    weights = {}
    for face in F:
        for c in range(3):
            i, j, k = face[c], face[(c + 1) % 3], face[(c + 2) % 3]
            a, b = V[j] - V[i], V[k] - V[i]
            cross = np.linalg.norm(np.cross(a, b))
            key = (min(j, k), max(j, k))
            weights[key] = weights.get(key, 0.0) + (0.5 * a @ b / cross if cross > 0 else 0.0)
    edges = np.array(list(weights), dtype=np.int64)
    w = np.maximum(np.array(list(weights.values())), 0.0)
    e0 = V[edges[:, 0]] - V[edges[:, 1]]
    e1 = V2[edges[:, 0]] - V2[edges[:, 1]]
    covariance = np.zeros((len(V), 3, 3))
    outer = w[:, None, None] * e1[:, :, None] * e0[:, None, :]
    for end in (0, 1):
        np.add.at(covariance, edges[:, end], outer)
    U, _, Wt = np.linalg.svd(covariance)
    D = np.ones((len(V), 3))
    D[:, 2] = np.sign(np.linalg.det(U @ Wt))
    R = U @ (D[:, :, None] * Wt)
    energy = normaliser = 0.0
    for end in (0, 1):
        residual = e1 - np.einsum("nij,nj->ni", R[edges[:, end]], e0)
        energy += (w * (residual ** 2).sum(1)).sum()
        normaliser += (w * (e0 ** 2).sum(1)).sum()
    return energy / normaliser


def test_the_reference_arap_energy_has_known_answers(meshes):
    """A rigid motion has energy 0, a uniform scale by s has (s - 1)^2."""
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    c, s = np.cos(0.7), np.sin(0.7)
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    assert abs(arap_energy(V, F, V @ R.T + [0.3, -0.2, 0.1])) < 1e-12
    assert np.isclose(arap_energy(V, F, 1.1 * V), 0.01, rtol=1e-12)


def test_example_prints_what_its_meshes_show(source_dir, meshes, tmp_path):
    """Each method's printed handle error (RMS distance of the handle vertices to the .def
    transform of their rest positions, over the bounding-box diagonal) and ARAP energy are
    those of the mesh it wrote (same faces, coordinates read as the doubles written), to the
    digits printed."""
    result = subprocess.run([sys.executable, str(source_dir / "examples" / "drag_cactus.py"),
                             str(tmp_path)], check=True, capture_output=True, text=True,
                            env=dict(os.environ))
    lines = result.stdout.splitlines()
    assert lines[0] == "cactus: 620 vertices, 68 fixed, 87 handle"
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    status = msdeform.read_sel(meshes / "cactus.sel", len(V))
    M = msdeform.read_def(meshes / "cactus.def")
    handle = status == 2
    target = V[handle] @ M[:3, :3].T + M[:3, 3]
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    printed = re.compile(r"^\s*(\w+): .* handle error (\S+) of the diagonal, ARAP energy (\S+)$")
    found = [printed.match(line).groups() for line in lines if printed.match(line)]
    assert [method for method, _, _ in found] == ["multiscale", "static"]
    for method, handle_error, energy in found:
        V2, F2 = read_off_exact(tmp_path / f"cactus_{method}.off")
        assert np.array_equal(F2, F)
        rms = np.sqrt(((V2[handle] - target) ** 2).sum(axis=1).mean()) / diagonal
        assert handle_error == f"{rms:.2e}", method
        assert energy == f"{arap_energy(V, F, V2):.4f}", method
        # The handle went to its target: the error is a small part of the drag.
        drag = np.sqrt(((target - V[handle]) ** 2).sum(axis=1).mean()) / diagonal
        assert rms < 0.1 * drag, (method, rms, drag)
