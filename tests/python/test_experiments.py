"""The experiments' runner and metrics on arrays: the C++ tables' numbers, and known answers."""

import csv
import subprocess

import numpy as np
import pytest

import msdeform

# Columns of table2.csv and ablations.csv that do not depend on the clock.
METRIC_COLUMNS = ["vertices", "nodes_optimized", "variables", "iterations", "unconverged_frames",
                  "handle_rms_rel", "fixed_max_rel", "arap_energy", "arap_energy_joint", "strain",
                  "leakage_rel", "leakage_max_rel", "orthogonality", "arap_energy_ratio",
                  "ref_distance_rel", "ref_distance_max_rel",
                  "selected_scale"]


def read_table(path):
    """Rows of a table CSV (after its '#' provenance lines) keyed by (scenario, method/variant)."""
    with open(path) as file:
        rows = csv.DictReader(line for line in file if not line.startswith("#"))
        return {(row["scenario"], row.get("method") or row["variant"]): row for row in rows}


def as_table_text(value):
    """A number as the tables print it (experiments/tables.h, FormatNumber: %.4g, NaN empty)."""
    if isinstance(value, float) and np.isnan(value):
        return ""
    if isinstance(value, (int, np.integer)):
        return str(value)
    return "%.4g" % value


@pytest.fixture(scope="module")
def cpp_tables(experiments_cli, tmp_path_factory):
    """The experiment runner's quick cactus tables (5 frames, energy ed), run here."""
    out = tmp_path_factory.mktemp("tables")
    subprocess.run([str(experiments_cli), "--quick", "--only=cactus", f"--out_dir={out}",
                    "--methods=multiscale,static,cgal_arap,full_arap",
                    "--time_other_backend=false",
                    "--energies=ed"],
                   check=True, capture_output=True)
    return read_table(out / "table2.csv"), read_table(out / "ablations.csv")


@pytest.fixture(scope="module")
def cactus(scenarios):
    return msdeform.load_scenario(scenarios / "cactus.json", frames=5)


def check_row(row, table_row):
    for column in METRIC_COLUMNS:
        if column in table_row:
            assert as_table_text(row[column]) == table_row[column], column


def test_run_deformer_gives_the_tables_numbers(cpp_tables, cactus):
    table2, ablations = cpp_tables
    # The runner's reference (full_arap) measured against itself, as its table row.
    reference_row, arap_V2 = msdeform.run_method(cactus, "full_arap", reference=None)
    again, _ = msdeform.run_method(cactus, "full_arap", reference=arap_V2)
    check_row(again, table2[("cactus", "full_arap")])
    assert table2[("cactus", "full_arap")]["arap_energy_ratio"] == "1"
    assert as_table_text(reference_row["arap_energy"]) == \
        table2[("cactus", "full_arap")]["arap_energy"]
    cgal_row, _ = msdeform.run_method(cactus, "cgal_arap", reference=arap_V2)
    check_row(cgal_row, table2[("cactus", "cgal_arap")])
    for method in ("multiscale", "static"):
        row = msdeform.run_deformer(cactus, method=method, num_threads=1, arap_result=arap_V2)
        assert row["method"] == method
        assert row["energy"] == "ed"
        check_row(row, table2[("cactus", method)])
    paper = msdeform.run_deformer(cactus, msdeform.paper_procedure(), label="paper",
                                  num_threads=1, arap_result=arap_V2)
    check_row(paper, ablations[("cactus", "paper")])
    stiff = msdeform.run_deformer(cactus, label="w_con_1e3", w_con=1e3, num_threads=1,
                                  arap_result=arap_V2)
    check_row(stiff, ablations[("cactus", "w_con_1e3")])


def test_metrics_on_arrays_give_the_runners_numbers(cactus):
    row = msdeform.run_deformer(cactus, num_threads=1)
    d = msdeform.Method(cactus.V, cactus.F, num_threads=1)
    d.set_handles(cactus.status)
    V, F, V2 = cactus.V, cactus.F, d.drag_along(cactus.path).copy()
    diagonal = msdeform.bounding_box_diagonal(V)
    assert msdeform.handle_rms_error(V, V2, cactus.handle, cactus.path[-1]) / diagonal == \
        row["handle_rms_rel"]
    assert msdeform.vertex_displacement(V, V2, cactus.fixed)[1] / diagonal == row["fixed_max_rel"]
    energy, normaliser = msdeform.arap_energy_per_vertex(V, F, V2)
    assert msdeform.normalised_arap_energy(energy, normaliser) == row["arap_energy"]
    joint = msdeform.vertices_near(V, F, cactus.fixed, 0.05 * diagonal)
    assert msdeform.normalised_arap_energy(energy, normaliser, joint) == row["arap_energy_joint"]
    assert msdeform.mean_edge_strain(V, F, V2) == row["strain"]
    rotations = d.node_rotations
    optimised = np.flatnonzero(d.node_classes != 0)
    assert msdeform.orthogonality_error(rotations, optimised) == row["orthogonality"]


def test_leakage_is_the_watch_regions_mean_and_max_displacement(scenarios):
    ear = msdeform.load_scenario(scenarios / "armadillo_ear.json", frames=2)
    row = msdeform.run_deformer(ear, num_threads=1)
    d = msdeform.Method(ear.V, ear.F, num_threads=1)
    d.set_handles(ear.status)
    V2 = d.drag_along(ear.path)
    leak = msdeform.leakage(ear.V, V2, ear.watch)
    assert leak == {"leakage_rel": row["leakage_rel"], "leakage_max_rel": row["leakage_max_rel"]}
    moved = np.linalg.norm(V2[ear.watch] - ear.V[ear.watch], axis=1)
    diagonal = msdeform.bounding_box_diagonal(ear.V)
    assert leak["leakage_rel"] == pytest.approx(moved.mean() / diagonal, rel=1e-12)
    assert leak["leakage_max_rel"] == pytest.approx(moved.max() / diagonal, rel=1e-12)


def tetrahedron():
    V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    return V, F


def test_metrics_known_answers():
    V, F = tetrahedron()
    # A rigid motion has no ARAP energy and no strain; a uniform scale by 1.1 strains every edge 0.1.
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    moved = V @ turn.T + [1.0, 2.0, 3.0]
    energy, normaliser = msdeform.arap_energy_per_vertex(V, F, moved)
    assert msdeform.normalised_arap_energy(energy, normaliser) == pytest.approx(0.0, abs=1e-15)
    assert msdeform.mean_edge_strain(V, F, moved) == pytest.approx(0.0, abs=1e-15)
    assert msdeform.mean_edge_strain(V, F, 1.1 * V) == pytest.approx(0.1, rel=1e-12)
    # Handle error: the handle vertices 0.1 away from where M puts them.
    M = np.eye(4)
    shifted = V + [0.0, 0.1, 0.0]
    assert msdeform.handle_rms_error(V, shifted, [1, 2], M) == pytest.approx(0.1, rel=1e-12)
    assert msdeform.vertex_displacement(V, shifted, [0, 3]) == pytest.approx((0.1, 0.1), rel=1e-12)
    # Orthogonality: 0 for rotations, ||diag(1.21 - 1)||_F for a scale by 1.1.
    R = np.stack([np.eye(3), turn, 1.1 * np.eye(3)])
    assert msdeform.orthogonality_error(R, [0, 1]) == 0.0
    assert msdeform.orthogonality_error(R, [2]) == pytest.approx(np.sqrt(3) * 0.21, rel=1e-12)
    # Vertices along edges within a radius: 1 and 3 are 1 away from 0, 2 too; sqrt(2) between them.
    assert sorted(msdeform.vertices_near(V, F, [0], 0.5).tolist()) == []
    assert sorted(msdeform.vertices_near(V, F, [0], 1.0).tolist()) == [1, 2, 3]


def test_run_deformer_on_arrays_equals_the_scenario_files_run(cactus):
    from_arrays = msdeform.Scenario(np.array(cactus.V), np.array(cactus.F), cactus.status,
                                    cactus.path, name="cactus")
    assert from_arrays.frames == cactus.frames and np.array_equal(from_arrays.handle, cactus.handle)
    row = msdeform.run_deformer(from_arrays, num_threads=1)
    expected = msdeform.run_deformer(cactus, num_threads=1)
    for column in METRIC_COLUMNS:
        assert as_table_text(row[column]) == as_table_text(expected[column]), column
    with pytest.raises(ValueError, match="status: "):
        msdeform.Scenario(cactus.V, cactus.F, np.zeros(len(cactus.V), dtype=int), np.eye(4))
