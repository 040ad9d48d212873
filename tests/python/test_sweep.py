"""Sweeps on Dask (python/msdeform/sweep.py): the grid and its ids, a real Dask cluster with a
worker killed mid-sweep, resume after an interrupt, a task that fails on bad input, bad sweep
files, and the committed sweep files against the C++ experiment runner's tables.
"""

import hashlib
import json
import os
import shutil
import signal
import subprocess

import pytest

import msdeform
from msdeform._sweep_grid import SweepError, canonical_json, load_sweep
from msdeform._sweep_report import NONDETERMINISTIC_COLUMNS
from msdeform._sweep_task import METRIC_COLUMNS, TIMING_COLUMNS, run_task

import sweep_helpers as helpers

# Debian's Dask 2022.12 on tornado 6.2: the test's own Client warns on start; not a finding.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

# The columns of the C++ tables that depend on the clock (the rest must be equal).
TABLE_TIME_COLUMNS = {"frame_ms", "solve_ms", "skin_ms", "setup_ms", "precompute_ms",
                      "rigidity_ms", "other_backend_frame_ms"}


@pytest.fixture(scope="module")
def source():
    """The repository root (MSDEFORM_SOURCE_DIR)."""
    return helpers.required_path("MSDEFORM_SOURCE_DIR")


def scenario(source, name):
    """experiments/scenarios/<name>.json of the source tree, checked."""
    path = os.path.join(source, "experiments", "scenarios", name + ".json")
    if not os.path.exists(path):
        raise RuntimeError(f"{path}: missing")
    return path


@pytest.fixture(scope="module")
def small_sweep(source, tmp_path_factory):
    """18 small tasks: cactus and hand with 5 frames, multiscale and static with two handle
    weights and two seeds, and CGAL's ARAP, measured against the converged reference
    (full_arap, one run per scenario)."""
    folder = tmp_path_factory.mktemp("small")
    return helpers.write_json(folder / "small.json", {
        "scenarios": [scenario(source, "cactus"), scenario(source, "hand_finger")],
        "methods": ["multiscale", "static", "cgal_arap"], "seeds": [1, 2], "frames": 5,
        "options": {"w_con": [100, 1000]}, "arap_reference": True})


@pytest.fixture(scope="module")
def serial_rows(small_sweep, tmp_path_factory):
    """The small sweep run serially, in this order, without Dask: the reference rows."""
    out = tmp_path_factory.mktemp("serial") / "out"
    helpers.run_sweep([small_sweep, "--out", out, "--serial"])
    return helpers.read_rows(out / "results.csv")


def deterministic(row):
    """A row without the columns that differ between runs (times, worker)."""
    return {k: v for k, v in row.items() if k not in NONDETERMINISTIC_COLUMNS}


def test_grid_order_and_stable_ids(source, tmp_path):
    """The grid is scenarios x methods x variants x options x seeds (seeds innermost), CGAL
    once per scenario, and a task's id is 12 hex digits of the SHA-256 of its canonical JSON:
    the same file gives the same ids, a known one included."""
    shutil.copy(scenario(source, "cactus"), tmp_path / "cactus.json")
    sweep_file = helpers.write_json(tmp_path / "grid.json", {
        "scenarios": ["cactus.json"], "methods": ["multiscale", "cgal_arap"], "seeds": [3, 1],
        "variants": {"default": {}, "paper_rigidity": {"rigidity": "paper"}},
        "options": {"w_con": [100, 1000]}})
    tasks = load_sweep(sweep_file).tasks
    labels = [task["label"] for task in tasks]
    assert labels == [
        "cactus / multiscale / default / w_con=100 / seed 3",
        "cactus / multiscale / default / w_con=100 / seed 1",
        "cactus / multiscale / default / w_con=1000 / seed 3",
        "cactus / multiscale / default / w_con=1000 / seed 1",
        "cactus / multiscale / paper_rigidity / w_con=100 / seed 3",
        "cactus / multiscale / paper_rigidity / w_con=100 / seed 1",
        "cactus / multiscale / paper_rigidity / w_con=1000 / seed 3",
        "cactus / multiscale / paper_rigidity / w_con=1000 / seed 1",
        "cactus / cgal_arap"]
    for task in tasks:
        digest = hashlib.sha256(canonical_json(task["params"]).encode()).hexdigest()
        assert task["id"] == digest[:12]
    assert [t["id"] for t in load_sweep(sweep_file).tasks] == [t["id"] for t in tasks]
    assert tasks[0]["params"] == {
        "scenario": "cactus.json", "method": "multiscale", "variant": "default", "seed": 3,
        "seed_field": "seed", "options": {"w_con": 100}, "frames": 0, "arap_reference": False,
        "time_other_backend": False, "cgal_iterations": None}
    # The scheme is part of the results' format: this id must never change.
    assert tasks[0]["id"] == "60fe1a6356d2"
    assert len({t["id"] for t in tasks}) == len(tasks)


def test_row_columns_are_run_deformers(source):
    """The sweep's metric and timing columns are exactly run_deformer's numbers (scenario,
    method and energy are parameter columns) plus the task's own load_ms, task_ms and
    task_cpu_ms."""
    scenario_object = msdeform.load_scenario(scenario(source, "cactus"), frames=1)
    keys = set(msdeform.run_deformer(scenario_object, num_threads=1))
    own = {"load_ms", "task_ms", "task_cpu_ms"}
    assert keys - {"scenario", "method", "energy"} == set(METRIC_COLUMNS + TIMING_COLUMNS) - own


def test_dask_cluster_worker_killed_mid_sweep(small_sweep, serial_rows, tmp_path):
    """A real dask-scheduler and two dask-workers; one worker is killed while it runs a task:
    every task ends with exactly one row, the killed worker's tasks ran on the other worker,
    and the table equals the serial run's in every column but the times."""
    out = tmp_path / "out"
    ids = helpers.listed_ids(small_sweep)
    assert len(ids) == 18
    with helpers.DaskCluster(tmp_path, workers=2) as cluster:
        survivor = cluster.worker_addresses()[1]
        held, driver, stdout, stderr = helpers.sweep_killing_worker_0(cluster, small_sweep, out)
        assert driver.returncode == 0, stderr
        assert list(cluster.worker_addresses().values()) == [survivor]
    assert f"Dask at {cluster.address}, 2 worker(s)" in stderr
    rows = helpers.read_rows(out / "results.csv")
    assert [row["task_id"] for row in rows] == ids
    assert sorted(helpers.task_files(out)) == sorted(ids)
    assert all(row["status"] == "ok" for row in rows)
    assert [deterministic(r) for r in rows] == [deterministic(r) for r in serial_rows]
    by_id = {row["task_id"]: row for row in rows}
    for key in held:
        assert by_id[key[len("msdeform-task-"):]]["worker"] == survivor, held


def test_resume_reruns_only_missing_tasks(small_sweep, serial_rows, tmp_path):
    """A sweep interrupted (SIGINT) after a few rows exits 130 with no results.csv; --resume
    runs only the tasks without a row, leaves the others' files untouched, and the table
    equals the serial run's."""
    out = tmp_path / "out"
    driver = helpers.start_sweep([small_sweep, "--out", out, "--serial"])
    try:
        helpers.wait_until(lambda: os.path.isdir(out / "tasks")
                           and len(helpers.task_files(out)) >= 4, 120, "four rows")
        driver.send_signal(signal.SIGINT)
        _, stderr = driver.communicate(timeout=60)
    finally:
        helpers.stop(driver)
    assert driver.returncode == 130, stderr
    assert "continue with --resume" in stderr
    assert not (out / "results.csv").exists()
    first = {task_id: (os.stat(path).st_mtime_ns, open(path).read())
             for task_id, path in helpers.task_files(out).items()}
    assert 4 <= len(first) < 18

    again = helpers.run_sweep([small_sweep, "--out", out, "--resume", "--workers", "1"])
    assert f"18 tasks, {len(first)} with rows in {out}, {18 - len(first)} to run" in again.stderr
    for task_id, path in helpers.task_files(out).items():
        if task_id in first:
            assert (os.stat(path).st_mtime_ns, open(path).read()) == first[task_id]
    rows = helpers.read_rows(out / "results.csv")
    assert [deterministic(r) for r in rows] == [deterministic(r) for r in serial_rows]
    for row in rows:
        if row["task_id"] in first:
            kept = json.loads(first[row["task_id"]][1])["row"]
            assert row["task_ms"] == repr(kept["task_ms"])

    # Without --resume the folder is refused; with it and nothing missing, nothing runs.
    refused = helpers.run_sweep([small_sweep, "--out", out, "--serial"], check=False)
    assert refused.returncode == 1
    assert refused.stderr.strip() == (f"msdeform.sweep: {out}: exists and is not empty; --resume "
                                      f"continues the sweep in it, or choose another --out")
    done = helpers.run_sweep([small_sweep, "--out", out, "--resume"])
    assert "18 with rows in" in done.stderr and "0 to run" in done.stderr
    assert helpers.read_rows(out / "results.csv") == rows


def test_failed_task_is_recorded_and_the_sweep_goes_on(source, tmp_path):
    """A scenario whose mesh is missing: its task's row is failed with the message the msdeform
    program prints for the same file; the other task runs, on a local Dask cluster."""
    bad = helpers.write_json(tmp_path / "missing_mesh.json", {
        "name": "missing_mesh", "mesh": str(tmp_path / "nowhere.off"),
        "sel": os.path.join(source, "data", "meshes", "cactus.sel"),
        "def": os.path.join(source, "data", "meshes", "cactus.def"), "frames": 5})
    cli = subprocess.run([helpers.required_path("MSDEFORM_CLI"), f"--scenario={bad}",
                          f"--out={tmp_path / 'never.off'}"], capture_output=True, text=True)
    assert cli.returncode == 1
    expected = cli.stderr.strip()
    assert expected.startswith("msdeform: ")
    expected = expected[len("msdeform: "):]

    sweep_file = helpers.write_json(tmp_path / "with_bad.json", {
        "scenarios": [scenario(source, "cactus"), "missing_mesh.json"], "frames": 5})
    out = tmp_path / "out"
    done = helpers.run_sweep([sweep_file, "--out", out, "--workers", "1"])
    rows = helpers.read_rows(out / "results.csv")
    assert [row["status"] for row in rows] == ["ok", "failed"]
    assert rows[1]["error_type"] == "OSError"
    assert rows[1]["error"] == expected
    assert rows[1]["scenario_file"] == "missing_mesh.json"
    assert all(rows[1][column] == "" for column in METRIC_COLUMNS)
    assert float(rows[0]["arap_energy"]) > 0
    assert f"failed: OSError: {expected}" in done.stderr
    assert "1 ok, 1 failed, 0 lost" in done.stderr
    summary = (out / "summary.md").read_text()
    assert "## Failed tasks" in summary and expected in summary
    assert (out / "chart.png").stat().st_size > 0


@pytest.mark.parametrize("change, field, message", [
    ({"options": {"w_cn": [1]}}, "options.w_cn",
     "unknown flag --w_cn (did you mean --w_con?); --help lists the flags"),
    ({"options": {"solver": ["ceres", "newton"]}}, "options.solver[1]",
     "--solver=newton: expected gauss_newton or ceres"),
    ({"options": {"w_con": 100}}, "options.w_con", "expected a non-empty list of values, got 100"),
    ({"options": {"method": ["static"]}}, "options.method",
     "the method is the 'methods' axis, not an option"),
    ({"variants": {"v": {"selection.member_extnt": "mean"}}}, "variants.v.selection.member_extnt",
     "member_extnt is not a field of DeformerOptions.selection (fields: threshold_floor, "
     "fixed_extent_cutoff, member_extent, local_detail_distance, omega_max, alpha_all_one, "
     "half_free, border, pin_fixed_region)"),
    ({"methods": ["multiscale", "arap"]}, "methods[1]",
     "'arap': expected one of " + ", ".join(msdeform.METHODS)),
    ({"scenarios": ["nowhere.json"]}, "scenarios[0]", "nowhere.json: no such file"),
    ({"seeds": [1, -2]}, "seeds[1]", "expected an integer in 0..2^64-1, got -2"),
    ({"frame": 5}, "frame", "unknown key"),
    # 10^8 frames ran out of memory in the task instead of failing here.
    ({"frames": 100000001}, "frames", "expected an integer in 0..100000, got 100000001"),
])
def test_bad_sweep_file(source, tmp_path, change, field, message):
    """Bad input in a sweep file: one line naming the file and the field, exit 1, no output."""
    raw = {"scenarios": [scenario(source, "cactus")], "frames": 5}
    raw.update(change)
    sweep_file = helpers.write_json(tmp_path / "bad.json", raw)
    out = tmp_path / "out"
    done = helpers.run_sweep([sweep_file, "--out", out, "--serial"], check=False)
    assert done.returncode == 1
    assert len(done.stderr.splitlines()) == 1
    assert done.stderr.startswith(f"msdeform.sweep: {sweep_file}: {field}: {message}")
    assert not out.exists()
    with pytest.raises(SweepError):
        load_sweep(sweep_file)


def cpp_runner_tables(out):
    """The C++ experiment runner's quick tables of the cactus (5 frames, every method, the
    graph methods with energies ed and arap, the other backend timed, its ablations), run
    here."""
    subprocess.run([helpers.required_path("MSDEFORM_EXPERIMENTS"), "--quick",
                    "--only=cactus", f"--out_dir={out}"], check=True, capture_output=True)
    return {name: helpers.read_table(os.path.join(out, name + ".csv"))
            for name in ("table1", "table2", "ablations")}


def test_committed_sweeps_reproduce_the_runners_tables(source, tmp_path):
    """experiments/sweeps/table2.json and ablations.json, narrowed to the cactus with 5 frames,
    give table1, table2 and the ablations equal to msdeform_experiments' in every cell but the
    times (same columns, rows, order and printed digits)."""
    expected = cpp_runner_tables(tmp_path / "cpp")
    for name, tables in (("table2", ("table1", "table2")), ("ablations", ("ablations",))):
        with open(os.path.join(source, "experiments", "sweeps", name + ".json")) as file:
            raw = json.load(file)
        raw["scenarios"] = [scenario(source, "cactus")]
        raw["frames"] = 5
        sweep_file = helpers.write_json(tmp_path / (name + ".json"), raw)
        helpers.run_sweep([sweep_file, "--out", tmp_path / name, "--serial"])
        for table in tables:
            columns, rows = helpers.read_table(tmp_path / name / (table + ".csv"))
            cpp_columns, cpp_rows = expected[table]
            assert columns == cpp_columns
            assert len(rows) == len(cpp_rows) > 0
            keep = [i for i, c in enumerate(columns) if c not in TABLE_TIME_COLUMNS]
            assert [[r[i] for i in keep] for r in rows] == [[r[i] for i in keep] for r in cpp_rows]


def test_task_dask_gives_up_on_is_lost_then_resumed(source, tmp_path):
    """With no second chance (the scheduler started with allowed-failures 0) the tasks a
    killed worker held are recorded as lost: exit 2, no task file for them, their rows in
    results.csv with Dask's KilledWorker message; --resume runs exactly those, and the table
    then equals a serial run's."""
    sweep_file = helpers.write_json(tmp_path / "lost.json", {
        "scenarios": [scenario(source, "cactus")], "methods": ["multiscale", "static"],
        "seeds": [1, 2, 3], "frames": 5, "options": {"w_con": [100, 1000]}})
    helpers.run_sweep([sweep_file, "--out", tmp_path / "serial", "--serial"])
    serial = helpers.read_rows(tmp_path / "serial" / "results.csv")
    out = tmp_path / "out"
    config = {"DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "0"}
    with helpers.DaskCluster(tmp_path, workers=2, config=config) as cluster:
        held, driver, _, stderr = helpers.sweep_killing_worker_0(cluster, sweep_file, out)
        assert driver.returncode == 2, stderr
        lost_ids = sorted(key[len("msdeform-task-"):] for key in held)
        rows = helpers.read_rows(out / "results.csv")
        assert sorted(r["task_id"] for r in rows if r["status"] == "lost") == lost_ids
        for row in rows:
            if row["status"] == "lost":
                assert row["error_type"] == "KilledWorker"
                assert row["task_id"] in row["error"]
                assert row["task_id"] not in helpers.task_files(out)
        assert len(helpers.task_files(out)) == len(rows) - len(lost_ids)

        again = helpers.run_sweep([sweep_file, "--out", out, "--resume", "--scheduler",
                                   cluster.address])
    assert f"{len(rows) - len(lost_ids)} with rows in {out}, {len(lost_ids)} to run" in again.stderr
    rows = helpers.read_rows(out / "results.csv")
    assert [deterministic(r) for r in rows] == [deterministic(r) for r in serial]


def test_bad_command_line(source, tmp_path):
    """No --out, or a scheduler that does not answer: one line, exit 1, nothing written."""
    sweep_file = helpers.write_json(tmp_path / "ok.json", {
        "scenarios": [scenario(source, "cactus")], "frames": 5})
    done = helpers.run_sweep([sweep_file], check=False)
    assert (done.returncode, done.stderr) == (
        1, "msdeform.sweep: --out is required (unless --list) (--help lists the options)\n")
    out = tmp_path / "out"
    done = helpers.run_sweep([sweep_file, "--out", out, "--scheduler", "tcp://127.0.0.1:1",
                              "--worker-timeout", "2"], check=False)
    assert done.returncode == 1
    assert done.stderr.splitlines()[-1].startswith(
        "msdeform.sweep: --scheduler tcp://127.0.0.1:1: cannot connect within 2 s")
    assert not out.exists()


def test_method_options_by_table_name(source, tmp_path):
    """A method's own option, named as the options table names it (fastlsm.steps_per_frame),
    is an axis of the methods that read it only: the graph method's tasks are not repeated
    along it, the fastlsm tasks run with it (run_method's rows with the same keyword), and a
    bad value names the field and the row."""
    sweep_file = helpers.write_json(tmp_path / "own.json", {
        "scenarios": [scenario(source, "cactus")], "methods": ["static", "fastlsm"], "frames": 2,
        "options": {"w_con": [100, 1000], "fastlsm.steps_per_frame": [3, 7]}})
    tasks = load_sweep(sweep_file).tasks
    seed = tasks[0]["params"]["seed"]
    assert [task["label"] for task in tasks] == [
        f"cactus / static / default / w_con=100 / seed {seed}",
        f"cactus / static / default / w_con=1000 / seed {seed}",
        "cactus / fastlsm / fastlsm.steps_per_frame=3",
        "cactus / fastlsm / fastlsm.steps_per_frame=7"]
    assert tasks[0]["params"]["options"] == {"w_con": 100}
    assert tasks[0]["columns"]["opt_fastlsm.steps_per_frame"] is None
    assert tasks[2]["params"]["options"] == {"fastlsm.steps_per_frame": 3}
    assert tasks[2]["columns"]["opt_fastlsm.steps_per_frame"] == 3
    assert tasks[2]["columns"]["opt_w_con"] is None
    cactus = msdeform.load_scenario(scenario(source, "cactus"), frames=2)
    for task, steps in ((tasks[2], 3), (tasks[3], 7)):
        row = run_task(task)
        assert row["status"] == "ok", row
        expected, _ = msdeform.run_method(cactus, "fastlsm", fastlsm_steps=steps)
        for column in ("handle_rms_rel", "arap_energy", "variables"):
            assert row[column] == expected[column], (column, steps)
    assert run_task(tasks[2])["arap_energy"] != run_task(tasks[3])["arap_energy"]
    bad = helpers.write_json(tmp_path / "bad.json", {
        "scenarios": [scenario(source, "cactus")], "methods": ["fastlsm"],
        "options": {"fastlsm.steps_per_frame": [0]}})
    with pytest.raises(SweepError, match=r"options\.fastlsm\.steps_per_frame\[0\]: "
                                         r"fastlsm_steps_per_frame=0: expected an integer in "
                                         r"1\.\.100000$"):
        load_sweep(bad)
