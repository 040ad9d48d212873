"""Every registered method by name from Python (msdeform.Method, msdeform.run_method): the
command line's results, known answers, and one-line errors."""

import re
import subprocess

import numpy as np

import pytest

import msdeform
from conftest import read_off_exact


def test_methods_lists_the_registry():
    # The project's methods in registration order; a method registered later
    # comes after them and needs no change here.
    assert msdeform.METHODS[:8] == ("multiscale", "static", "static_dense", "cgal_arap",
                                    "cgal_sr_arap", "fastlsm", "rigid_cells", "full_arap")
    assert len(set(msdeform.METHODS)) == len(msdeform.METHODS)


@pytest.mark.parametrize("method", ["multiscale", "static", "cgal_arap", "cgal_sr_arap",
                                    "fastlsm"])
def test_method_equals_the_command_line(cli, scenarios, tmp_path, method):
    scenario_file = scenarios / "cactus.json"
    out = tmp_path / "cli.off"
    subprocess.run([str(cli), f"--scenario={scenario_file}", "--frames=3", f"--method={method}",
                    f"--out={out}", "--quiet"], check=True)
    V_cli, _ = read_off_exact(out)
    scenario = msdeform.load_scenario(scenario_file, frames=3)
    e = msdeform.Method(scenario.V, scenario.F, method)
    assert e.name == method
    e.set_handles(scenario.status)
    V2 = e.drag(np.stack(scenario.path))
    assert np.array_equal(V2, V_cli)
    assert len(e.frame_stats) == 3
    assert e.num_variables > 0


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_a_whole_mesh_handle_moves_rigidly(meshes, method):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    e = msdeform.Method(V, F, method)
    e.set_handles(np.full(len(V), 2, dtype=np.int32))
    M = np.eye(4)
    M[:3, :3] = [[np.cos(0.7), -np.sin(0.7), 0.0], [np.sin(0.7), np.cos(0.7), 0.0],
                 [0.0, 0.0, 1.0]]
    M[:3, 3] = [0.3, -0.2, 0.5]
    V2 = e.drag(M)
    diagonal = msdeform.bounding_box_diagonal(V)
    assert np.abs(V2 - (V @ M[:3, :3].T + M[:3, 3])).max() <= 1e-6 * diagonal


def test_unknown_method_and_drag_before_handles_are_errors(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    with pytest.raises(ValueError, match="^" + re.escape(
            "method: unknown method 'arap' (expected " + ", ".join(msdeform.METHODS) + ")") + "$"):
        msdeform.Method(V, F, "arap")
    e = msdeform.Method(V, F, "fastlsm")
    with pytest.raises(RuntimeError, match="^fastlsm: no handle layout: call set_handles"):
        e.drag(np.eye(4))


def test_run_method_gives_the_runner_rows(scenarios):
    cactus = msdeform.load_scenario(scenarios / "cactus.json", frames=3)
    reference_row, reference = msdeform.run_method(cactus, "full_arap")
    assert np.isnan(reference_row["arap_energy_ratio"])  # no reference given
    cgal_method_row, _ = msdeform.run_method(cactus, "cgal_arap", reference=reference)
    cgal_row, _ = msdeform.run_cgal_arap(cactus)
    for column in ("handle_rms_rel", "arap_energy", "nodes_optimized", "variables"):
        assert cgal_method_row[column] == cgal_row[column]
    # run_cgal_arap measures against its own result; the converged energy is below CGAL's.
    assert cgal_row["arap_energy_ratio"] == 1.0 and cgal_row["ref_distance_max_rel"] == 0.0
    assert cgal_method_row["arap_energy_ratio"] == pytest.approx(
        cgal_row["arap_energy"] / reference_row["arap_energy"], rel=1e-15)
    assert cgal_method_row["arap_energy_ratio"] > 1.0
    again, _ = msdeform.run_method(cactus, "full_arap", reference=reference)
    assert again["arap_energy_ratio"] == 1.0
    assert again["ref_distance_rel"] == 0.0 and again["ref_distance_max_rel"] == 0.0
    row, _ = msdeform.run_method(cactus, "fastlsm", reference=reference)
    assert row["method"] == "fastlsm"
    assert row["handle_rms_rel"] == 0.0 and row["fixed_max_rel"] == 0.0
    assert 0.0 < row["ref_distance_rel"] < row["ref_distance_max_rel"]
    deformer_row = msdeform.run_deformer(cactus, method="static", arap_result=reference)
    method_row, _ = msdeform.run_method(cactus, "static", reference=reference)
    for column in ("handle_rms_rel", "arap_energy", "arap_energy_ratio", "ref_distance_rel",
                   "ref_distance_max_rel", "orthogonality"):
        assert method_row[column] == deformer_row[column]


# The methods' own options: rows of the one table (msdeform.option_rows()), keywords of Method
# and run_method under the row's name ('fastlsm_steps_per_frame') or the flag's
# ('fastlsm_steps').
METHOD_ROWS = {"cgal.iterations": "3", "cgal.tolerance": "0.5", "cgal.sre_alpha": "0.125",
               "fastlsm.steps_per_frame": "3", "fastlsm.region_half_width": "1",
               "fastlsm.damping": "0.25", "full_arap.relative_tolerance": "1e-06",
               "full_arap.max_iterations": "50", "full_arap.anderson_window": "3",
               "full_arap.factorization": "cholmod"}


def test_option_rows_list_the_method_rows():
    rows = {row["name"]: row for row in msdeform._msdeform.option_rows() if row["keywords"]}
    assert set(rows) == set(METHOD_ROWS)
    assert rows["fastlsm.steps_per_frame"]["keywords"] == ["fastlsm_steps_per_frame",
                                                          "fastlsm_steps"]
    assert rows["fastlsm.steps_per_frame"]["aliases"] == ["fastlsm_steps"]
    assert rows["fastlsm.steps_per_frame"]["flag_topic"] == "method"
    assert rows["cgal.iterations"]["default"] == "20"
    assert rows["fastlsm.damping"]["range"] == "a number in [0, 1)"


@pytest.mark.parametrize("method,prefix", [("fastlsm", "fastlsm."), ("cgal_sr_arap", "cgal.")])
def test_method_keywords_equal_the_flags(cli, scenarios, tmp_path, method, prefix):
    scenario_file = scenarios / "cactus.json"
    rows = {row["name"]: row for row in msdeform._msdeform.option_rows() if row["keywords"]}
    flags = [f"--{rows[name]['aliases'][0]}={value}" for name, value in METHOD_ROWS.items()
             if name.startswith(prefix)]
    out = tmp_path / "cli.off"
    subprocess.run([str(cli), f"--scenario={scenario_file}", "--frames=3", f"--method={method}",
                    f"--out={out}", "--quiet", *flags], check=True)
    V_cli, _ = read_off_exact(out)
    scenario = msdeform.load_scenario(scenario_file, frames=3)
    path = np.stack(scenario.path)
    for keyword_of in (lambda name: rows[name]["keywords"][0],   # fastlsm_steps_per_frame
                       lambda name: rows[name]["keywords"][-1]):  # fastlsm_steps
        keywords = {keyword_of(name): float(value) if "." in value else int(value)
                    for name, value in METHOD_ROWS.items() if name.startswith(prefix)}
        e = msdeform.Method(scenario.V, scenario.F, method, **keywords)
        e.set_handles(scenario.status)
        assert np.array_equal(e.drag(path), V_cli)
        _, V_run = msdeform.run_method(scenario, method, **keywords)
        assert np.array_equal(V_run, V_cli)
    default = msdeform.Method(scenario.V, scenario.F, method)
    default.set_handles(scenario.status)
    assert not np.array_equal(default.drag(path), V_cli)


def test_method_keywords_out_of_range_name_the_keyword(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    with pytest.raises(ValueError, match=r"^fastlsm_steps=0: expected an integer in 1..100000$"):
        msdeform.Method(V, F, "fastlsm", fastlsm_steps=0)
    with pytest.raises(ValueError, match=r"^fastlsm_damping=1: expected a number in \[0, 1\)$"):
        msdeform.Method(V, F, "fastlsm", fastlsm_damping=1.0)
    with pytest.raises(ValueError, match=r"^cgal_iterations=0: expected an integer >= 1$"):
        msdeform.Method(V, F, "cgal_arap", cgal_iterations=0)
    with pytest.raises(ValueError, match=r"^fastlsm_steps: one option "
                                         r"\(fastlsm.steps_per_frame\), given twice$"):
        msdeform.Method(V, F, "fastlsm", fastlsm_steps=3, fastlsm_steps_per_frame=4)


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_drag_along_is_drag_through_its_path(scenarios, method):
    """Every registered method through the one class: drag_along(M, frames) drags through
    drag_path(M, frames), frame by frame, to the same vertices."""
    scenario = msdeform.load_scenario(scenarios / "cactus.json", frames=3)
    along = msdeform.Method(scenario.V, scenario.F, method)
    along.set_handles(scenario.status)
    V_along = along.drag_along(scenario.path[-1], frames=3).copy()
    assert len(along.frame_stats) == 3
    assert along.last_stats["frame_ms"] == along.frame_stats[-1]["frame_ms"]
    assert along.failed_frames == []
    stepped = msdeform.Method(scenario.V, scenario.F, method)
    stepped.set_handles(scenario.status)
    path = stepped.drag_path(scenario.path[-1], frames=3)
    assert path.shape == (3, 4, 4)
    assert np.array_equal(stepped.drag(path), V_along)


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_method_says_what_it_minimises(meshes, method):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    e = msdeform.Method(V, F, method)
    known = {"cgal_arap": "arap", "cgal_sr_arap": "sr_arap", "fastlsm": "shape_matching"}
    if method in known:
        assert not e.graph and e.energy == known[method]
    if e.graph:
        assert e.energy == "ed"
        assert msdeform.Method(V, F, method, energy="arap").energy == "arap"
