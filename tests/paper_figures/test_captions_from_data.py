"""The figure index's captions (paper_figures/write_index.py) print the numbers of the figure
data they are written from, with significant digits: made-up data with known answers in a
temporary folder, and the committed index checked for displacements rounded to zero. Needs
numpy and VTK's Python module (figlib imports it; no display)."""

import json
import pathlib
import re
import sys

import numpy as np
import pytest

pytest.importorskip("vtk")
ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "paper_figures"))
import write_index  # noqa: E402


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
        f.writelines("%.17g %.17g %.17g\n" % tuple(v) for v in V)
        f.writelines("3 %d %d %d\n" % tuple(t) for t in F)


def camel_leg_edit(data, name, V, F, moved):
    """An edit of a made-up 'camel' whose other front leg (x < 0, y < 0, z > -0.1) has one
    vertex moved by `moved` diagonals; the body (y > 0) is fixed."""
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    Vd = V.copy()
    leg = np.nonzero((V[:, 0] < 0) & (V[:, 2] > -0.1) & (V[:, 1] < 0))[0]
    Vd[leg[0]] += (moved * diag, 0.0, 0.0)
    write_off(data / (name + ".off"), Vd, F)
    d = {"mesh": "data/meshes/camel.off", "deformed_mesh": name + ".off", "diag": diag,
         "fixed": np.nonzero(V[:, 1] > 0)[0].tolist(), "moveable": [int(leg[-1])],
         "displacement": np.linalg.norm(Vd - V, axis=1).tolist()}
    with open(data / (name + ".json"), "w") as f:
        json.dump(d, f)
    return float(np.linalg.norm(Vd - V, axis=1)[leg].max()) / diag


@pytest.fixture
def made_up(tmp_path, monkeypatch):
    root, data = tmp_path / "root", tmp_path / "data"
    (root / "data" / "meshes").mkdir(parents=True)
    data.mkdir()
    rng = np.random.default_rng(1)
    V = rng.uniform(-1, 1, size=(40, 3))
    F = np.array([[i, i + 1, i + 2] for i in range(38)])
    write_off(root / "data" / "meshes" / "camel.off", V, F)
    monkeypatch.setattr(write_index, "ROOT", str(root))
    monkeypatch.setattr(write_index, "DATA", str(data))
    write_index._meshes.clear()
    return data, V, F


def test_fig6_camel_leg_prints_the_datas_displacement(made_up):
    # The "moves by up to 0.000 of the diagonal": the other leg moved by 0.000157.
    data, V, F = made_up
    default = camel_leg_edit(data, "edit_camel_leg_bend_multiscale", V, F, 0.000157)
    paper = camel_leg_edit(data, "edit_camel_leg_bend_paper", V, F, 0.0095)
    text = write_index.fig6_caption()
    printed = [float(x) for x in re.findall(r"moves by up to ([0-9.e+-]+) of the diagonal", text)]
    assert printed == [float("%.2g" % default), float("%.2g" % paper)] == [0.00016, 0.0095]
    assert "0.000 " not in text


def test_fig6_camel_leg_still_below_the_bound(made_up):
    data, V, F = made_up
    camel_leg_edit(data, "edit_camel_leg_bend_multiscale", V, F, 2e-6)
    camel_leg_edit(data, "edit_camel_leg_bend_paper", V, F, 0.0095)
    text = write_index.fig6_caption()
    assert "stays still (below 1e-4 of the diagonal) under the default" in text
    assert "in paper mode it moves by up to 0.0095 of the diagonal" in text


def test_committed_index_has_no_length_rounded_to_zero():
    # A nonzero length printed with fixed decimals ("0.000", "0.00") reads as none at all.
    text = (ROOT / "paper_figures" / "out" / "index.md").read_text()
    zeros = re.findall(r"(?<![0-9.])0\.0+(?![0-9])", text)
    assert zeros == []
