"""The deformation-graph methods through msdeform.Method: the command line's result, known
answers, views, the intermediate results of the paper's method, the GIL."""

import subprocess
import threading
import time

import numpy as np
import pytest

import msdeform
from conftest import read_off_exact


def run_cli(cli, tmp_path, *arguments):
    """Runs msdeform with `arguments`, returns the deformed vertices it wrote (exact doubles)."""
    out = tmp_path / "cli.off"
    subprocess.run([str(cli), *arguments, f"--out={out}", "--quiet"], check=True)
    V, _ = read_off_exact(out)
    return V


def test_drag_equals_the_command_lines_for_a_sel_def_pair(cli, meshes, tmp_path):
    V_cli = run_cli(cli, tmp_path, f"--mesh={meshes / 'cactus.off'}",
                    f"--sel={meshes / 'cactus.sel'}", f"--def={meshes / 'cactus.def'}",
                    "--frames=5")
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    d = msdeform.Method(V, F, "multiscale")
    d.set_handles(meshes / "cactus.sel")
    V2 = d.drag_along(msdeform.read_def(meshes / "cactus.def"), frames=5)
    assert np.abs(V2 - V_cli).max() <= 1e-12 * d.diagonal
    assert np.abs(V2 - V).max() > 0.1 * d.diagonal  # the trunk did bend


def test_drag_equals_the_command_lines_for_a_scenario(cli, scenarios, tmp_path):
    scenario_file = scenarios / "hand_finger.json"
    V_cli = run_cli(cli, tmp_path, f"--scenario={scenario_file}", "--frames=4",
                    "--method=static", "--w_con=1000")
    scenario = msdeform.load_scenario(scenario_file, frames=4)
    options = msdeform.options_from_flags({"method": "static", "w_con": 1000})
    # No name: the one the options give (static).
    d = msdeform.Method(scenario.V, scenario.F, options=options)
    assert d.name == "static"
    d.set_handles(scenario.status)
    V2 = d.drag_along(scenario.path)
    assert np.abs(V2 - V_cli).max() <= 1e-12 * d.diagonal


def test_identity_drag_leaves_the_mesh_at_rest(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    d = msdeform.Method(V, F)
    d.set_handles(meshes / "cactus.sel")
    V2 = d.drag(np.eye(4))
    assert np.abs(V2 - V).max() <= 1e-9 * d.diagonal


def test_drag_returns_an_array_later_drags_leave_alone(meshes):
    # As libigl: V2 = d.drag(M) is a new array; d.deformed_vertices is the view that follows.
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    d = msdeform.Method(V, F)
    d.set_handles(meshes / "cactus.sel")
    M = msdeform.read_def(meshes / "cactus.def")
    first = d.drag(M)
    kept = first.copy()
    assert first.flags.writeable and first.dtype == np.float64 and first.shape == V.shape
    assert not np.shares_memory(first, d.deformed_vertices)
    along = d.drag_along(M, frames=3)
    assert np.array_equal(first, kept)  # the next calls did not change it
    assert not np.shares_memory(along, d.deformed_vertices)
    assert np.array_equal(along, d.deformed_vertices)
    second = d.drag(np.eye(4))
    assert np.array_equal(first, kept) and not np.array_equal(second, kept)
    assert not np.array_equal(along, second)
    view = d.deformed_vertices
    assert not view.flags.writeable
    with pytest.raises(ValueError):
        view[0, 0] = 1.0
    before = view.copy()
    d.drag(M)
    assert not np.array_equal(view, before)  # the view follows the frame
    assert "new float64 (#V, 3) array" in msdeform.Method.drag.__doc__


def test_per_particle_and_per_node_members_say_so():
    # relative_extent: one per lattice particle; node_classes: one per node (help() shows it).
    doc = msdeform.Method.relative_extent.__doc__
    assert doc.startswith("One entry per lattice particle, not per node")
    assert msdeform.Method.node_classes.__doc__.startswith(
        "One entry per node of the selected scale")


def test_method_intermediates_follow_the_paper(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    d = msdeform.Method(V, F)
    d.set_handles(meshes / "cactus.sel")
    classes = d.node_classes
    assert set(np.unique(classes)) <= {0, 1, 2}
    assert msdeform.NODE_CLASSES == ("fixed", "half_free", "totally_free")
    # Node classes decide the variables: 12 per Totally Free node, 9 per Half Free one.
    assert d.num_variables == 12 * np.count_nonzero(classes == 2) + 9 * np.count_nonzero(classes == 1)
    assert 1 <= d.selected_scale <= d.num_scales
    assert d.selection["scale"] == d.selected_scale
    assert np.array_equal(d.node_positions, d.graph_node_positions(d.selected_scale))
    assert len(d.node_classes) == len(d.node_positions) == len(d.node_extent)
    # e' is per lattice particle; normalised by the handle's extent (Eq. 5).
    assert d.relative_extent.shape == (len(d.particle_positions),)
    assert np.allclose(d.relative_extent, d.extent / d.handle_extent, rtol=1e-14, atol=0)
    d.drag_along(msdeform.read_def(meshes / "cactus.def"), frames=3)
    stats = d.frame_stats
    assert len(stats) == 3 and d.last_stats["frame_ms"] == stats[-1]["frame_ms"]
    assert all(s["final_cost"] <= s["initial_cost"] for s in stats)
    assert stats[-1]["trace"].shape[1] == 2


def test_static_baseline_has_one_scale_and_no_rigidity(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    d = msdeform.Method(V, F, method="static", static_nodes=150)
    d.set_handles(meshes / "cactus.sel")
    assert d.num_scales == 1
    assert d.relative_extent.size == 0
    assert d.options.static_nodes == 150


def test_keywords_are_the_options_fields_with_the_cpp_defaults():
    defaults = dict(msdeform.describe_options())
    options = msdeform.DeformerOptions()
    assert defaults["w_con"] == "100" and options.w_con == 100.0
    assert defaults["stopping.max_iterations"] == str(options.stopping.max_iterations)
    changed = msdeform.DeformerOptions(w_con=1e3, stopping={"max_iterations": 5})
    described = dict(msdeform.describe_options(changed))
    assert described["w_con"] == "1000" and described["stopping.max_iterations"] == "5"
    assert msdeform.options_from_flags({"w_con": 1000, "max_iterations": 5}) == changed


def test_the_one_thread_count_bounds_the_graph_building_too(meshes):
    assert msdeform.options_from_flags({"threads": 1}).graph.num_threads == 1
    assert dict(msdeform.describe_options({"num_threads": 3}))["graph.num_threads"] == "3"
    d = msdeform.Method(*msdeform.read_mesh(meshes / "cactus.off"), num_threads=1)
    assert d.options.num_threads == 1 and d.options.graph.num_threads == 1
    # A graph of its own keeps its count; no keyword keeps the default (0: OpenMP's).
    own = {"num_threads": 1, "graph": {"num_threads": 2}}
    assert dict(msdeform.describe_options(own))["graph.num_threads"] == "2"
    assert msdeform.DeformerOptions(num_threads=1).graph.num_threads == 0


def test_the_gil_is_released_while_dragging(meshes):
    """A Python thread keeps running while another thread drags.

    If the solve held the GIL, the main thread's loop would stall for the whole drag_along
    call (a pause of about the call's length); with it released, the longest pause is a
    small part of the call (half leaves room for a loaded machine's scheduling). 200
    frames make the call about half a second, long against the time slices a scheduler
    shares two cores in when ctest runs another test beside this one (40 frames were
    about 80 ms: one scheduling delay away from the bound).
    """
    V, F = msdeform.read_mesh(meshes / "armadillo.off")
    d = msdeform.Method(V, F, num_threads=1)
    status = np.ones(len(V), dtype=np.int32)
    status[V[:, 1] < np.quantile(V[:, 1], 0.2)] = 0
    status[V[:, 1] > np.quantile(V[:, 1], 0.9)] = 2
    d.set_handles(status)
    M = np.eye(4)
    M[:3, 3] = [0.0, 0.0, 0.1 * d.diagonal]
    worker = threading.Thread(target=d.drag_along, args=(M,), kwargs={"frames": 200})
    started = time.perf_counter()
    worker.start()
    longest_pause, last = 0.0, time.perf_counter()
    while worker.is_alive():
        now = time.perf_counter()
        longest_pause, last = max(longest_pause, now - last), now
    duration = time.perf_counter() - started
    worker.join()
    assert len(d.frame_stats) == 200
    assert longest_pause < 0.5 * duration, (longest_pause, duration)
