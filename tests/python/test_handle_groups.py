"""Several handles that move independently (handle groups) and per-vertex targets from Python:
the command line's results on a two-handle scenario, known answers, and one-line errors."""

import json
import re
import subprocess

import numpy as np

import pytest

import msdeform
from conftest import read_off_exact


def _two_handle_scenario(meshes, tmp_path):
    """The cactus with its middle fixed, its left tenth lifted and its right tenth turned."""
    scenario = {
        "mesh": str(meshes / "cactus.off"),
        "fixed": [{"slab": {"axis": "x", "from": 0.45, "to": 0.55}}],
        "handles": [
            {"region": {"slab": {"axis": "x", "from": 0.0, "to": 0.1}},
             "transform": {"translation_rel": [0.0, 0.0, 0.05]}},
            {"region": {"slab": {"axis": "x", "from": 0.9, "to": 1.0}},
             "transform": {"rotation": {"axis": [0, 1, 0], "angle_deg": 20}}},
        ],
        "frames": 3,
    }
    path = tmp_path / "two_handles.json"
    path.write_text(json.dumps(scenario))
    return path


@pytest.mark.parametrize("method", ["full_arap", "fastlsm", "multiscale"])
def test_two_handles_equal_the_command_line(cli, meshes, tmp_path, method):
    scenario_file = _two_handle_scenario(meshes, tmp_path)
    out = tmp_path / "cli.off"
    subprocess.run([str(cli), f"--scenario={scenario_file}", f"--method={method}",
                    f"--out={out}", "--quiet"], check=True)
    V_cli, _ = read_off_exact(out)
    scenario = msdeform.load_scenario(scenario_file)
    assert sorted(set(scenario.status.tolist())) == [0, 1, 2, 3]
    assert scenario.path.shape == (3, 2, 4, 4)
    e = msdeform.Method(scenario.V, scenario.F, method)
    e.set_handles(scenario.status)
    assert np.array_equal(e.status, scenario.status)
    V2 = e.drag(scenario.path)  # a path: (frames, groups, 4, 4)
    assert np.array_equal(V2, V_cli)
    if method != "multiscale":  # the default energy's handle is soft
        for g in (0, 1):
            ids = np.flatnonzero(scenario.status == 2 + g)
            M = scenario.path[-1, g]
            assert np.abs(V2[ids] - (scenario.V[ids] @ M[:3, :3].T + M[:3, 3])).max() <= 1e-12


def test_targets_of_a_rigid_motion_equal_the_transform(meshes, tmp_path):
    scenario = msdeform.load_scenario(_two_handle_scenario(meshes, tmp_path))
    handle = np.flatnonzero(scenario.status >= 2)
    group = scenario.status[handle] - 2
    M = scenario.path[-1]
    targets = np.empty((len(handle), 3))
    for g in (0, 1):
        rows = group == g
        targets[rows] = scenario.V[handle[rows]] @ M[g, :3, :3].T + M[g, :3, 3]
    by_matrix = msdeform.Method(scenario.V, scenario.F, "full_arap")
    by_matrix.set_handles(scenario.status)
    V_matrix = by_matrix.drag(M)
    by_targets = msdeform.Method(scenario.V, scenario.F, "full_arap")
    by_targets.set_handles(scenario.status)
    V_targets = by_targets.drag(targets=targets)
    diagonal = msdeform.bounding_box_diagonal(scenario.V)
    assert np.abs(V_targets[handle] - targets).max() <= 1e-9 * diagonal
    assert np.abs(V_targets - V_matrix).max() <= 1e-9 * diagonal


def test_targets_that_bend_a_group_are_reached_by_the_arap_methods(meshes, tmp_path):
    # full_arap and CGAL place the handle vertices one by one: any targets, exactly; the
    # polish keeps them.
    scenario = msdeform.load_scenario(_two_handle_scenario(meshes, tmp_path))
    handle = np.flatnonzero(scenario.status >= 2)
    diagonal = msdeform.bounding_box_diagonal(scenario.V)
    targets = scenario.V[handle].copy()
    targets[:, 2] += 0.05 * diagonal * np.cos(np.arange(len(handle)))  # no transform does this
    for method in ("full_arap", "cgal_arap"):
        e = msdeform.Method(scenario.V, scenario.F, method)
        e.set_handles(scenario.status)
        V2 = e.drag(targets=targets)
        assert np.abs(V2[handle] - targets).max() <= 1e-12 * diagonal
    report = e.polish()
    assert np.abs(e.deformed_vertices[handle] - targets).max() <= 1e-12 * diagonal
    assert report["energy_after"] <= report["energy_before"]


def test_bad_groups_and_targets_are_one_line_errors(meshes, tmp_path):
    scenario = msdeform.load_scenario(_two_handle_scenario(meshes, tmp_path))
    e = msdeform.Method(scenario.V, scenario.F, "fastlsm")
    status = scenario.status.copy()
    status[status == 3] = 4  # groups 0 and 2, none 1
    with pytest.raises(ValueError, match=re.escape(
            "status: no vertex has status 3 (handle group 1), but 4 is used")):
        e.set_handles(status)
    e.set_handles(scenario.status)
    handle = np.flatnonzero(scenario.status >= 2)
    bent = scenario.V[handle].copy()
    bent[0] += [0.0, 0.0, 0.1 * msdeform.bounding_box_diagonal(scenario.V)]
    with pytest.raises(ValueError, match="^targets: the targets of handle group [01] are no "
                                         "affine map of its rest positions.*fastlsm moves each "
                                         "group by one transform; full_arap, cgal_arap and "
                                         "cgal_sr_arap take any targets"):
        e.drag(targets=bent)
    with pytest.raises(TypeError, match="give M .* or targets .*, one of the two"):
        e.drag(np.eye(4), targets=scenario.V[handle])
    with pytest.raises(ValueError, match=re.escape(
            "M: 3 transforms for a layout of 2 handle groups")):
        e.drag(np.stack([np.eye(4)] * 3))
