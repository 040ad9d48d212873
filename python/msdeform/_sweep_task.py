"""One task of a sweep: a scenario through the Python module, returned as one row.

These functions run on Dask workers (or in the driver for a serial run); they take and return
plain dicts, lists and NumPy arrays, so that Dask can ship them. A task that raises is a row
with status "failed" and the exception's message, never an exception: one bad input does not
stop a sweep, and Dask retries only what a dead worker left undone.
"""

import math
import os
import socket
import sys
import time

import msdeform
from msdeform._sweep_grid import DEFORMER_METHODS, build_options, method_keywords

# The row of a task, in column order: the parameters come first (the sweep's columns: index,
# task_id, scenario, scenario_file, model, method, energy, variant, seed, frames,
# opt_<option>...); energy is what the method minimised, as run_deformer says.
STATUS_COLUMNS = ("status", "error_type", "error")
# run_deformer's numbers that do not depend on the clock: the same task gives the same values.
# Read from RunResult's one column table (msdeform.RESULT_COLUMNS, experiments/runner.h), less
# the parameters a task already has (scenario, method, energy).
_PARAMETER_COLUMNS = ("scenario", "method", "energy")
METRIC_COLUMNS = tuple(name for name, timing in msdeform.RESULT_COLUMNS
                       if not timing and name not in _PARAMETER_COLUMNS)
# Times (ms): run_deformer's, then the task's own (load_ms: reading the scenario; task_ms: the
# whole task on its worker; task_cpu_ms: the CPU time of the thread that ran it, which other
# load on the machine does not inflate). They differ between runs of the same task.
TIMING_COLUMNS = tuple(name for name, timing in msdeform.RESULT_COLUMNS if timing) + (
    "load_ms", "task_ms", "task_cpu_ms")
# Where and by what the row was made: the worker (differs between runs) and msdeform's commit.
PROVENANCE_COLUMNS = ("worker", "commit")

# Status values: "ok"; "failed": the task raised (its message in error); "lost": Dask gave up
# on it (its worker died too often, error says why); only "lost" tasks are rerun by --resume.
OK, FAILED, LOST = "ok", "failed", "lost"


def worker_name():
    """The Dask worker's address, or host:pid outside a worker (a serial run)."""
    if "distributed" in sys.modules:  # a serial run does not import Dask for this
        try:
            return sys.modules["distributed"].get_worker().address
        except ValueError:
            pass
    return f"{socket.gethostname()}:{os.getpid()}"


def _finite_or_none(value):
    """NaN (the tables' "does not apply") as None, so rows are plain JSON; others unchanged."""
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def _load(task):
    """(scenario, load ms) of a task's scenario file with the sweep's frames."""
    start = time.perf_counter()
    scenario = msdeform.load_scenario(task["scenario_path"], frames=task["params"]["frames"])
    return scenario, (time.perf_counter() - start) * 1e3


# The method whose final mesh is every task's reference when the sweep has arap_reference: the
# converged ARAP energy, as the experiment runner's (RunnerOptions::reference_method).
REFERENCE_METHOD = "full_arap"
# Below this ARAP energy the reference is a rigid motion to rounding and has no ratio (the
# runner's kRigidEnergy, experiments/runner.cc).
RIGID_ENERGY = 1e-12


def _base_row(task):
    """The parameter columns of a task's row, before it runs."""
    params = task["params"]
    row = {"index": task["index"], "task_id": task["id"],
           "scenario": os.path.splitext(os.path.basename(params["scenario"]))[0], "model": None}
    row.update(task["columns"])
    row["energy"] = None
    for column in STATUS_COLUMNS + METRIC_COLUMNS + TIMING_COLUMNS:
        row[column] = None
    row["status"] = OK
    row["worker"] = worker_name()
    row["commit"] = msdeform.COMMIT
    return row


def _fill(row, result, scenario):
    """Copies run_deformer's (or run_method's) numbers into the row."""
    row["scenario"] = scenario.name
    row["model"] = os.path.splitext(os.path.basename(scenario.mesh_path))[0]
    row["energy"] = result.get("energy")
    for column in METRIC_COLUMNS + TIMING_COLUMNS:
        if column in result:
            row[column] = _finite_or_none(result[column])


def _failed(row, error):
    """Marks the row failed with the exception's type and message (the C++ message)."""
    row["status"] = FAILED
    row["error_type"] = type(error).__name__
    row["error"] = str(error)
    return row


def run_reference(scenario_path, params):
    """The converged ARAP energy (REFERENCE_METHOD, its default options) on a scenario: the
    reference of arap_energy_ratio, ref_distance_rel and ref_distance_max_rel for every task of
    that scenario, and the row of its full_arap task, measured against itself as the runner's
    (ratio 1, or None where its energy is below RIGID_ENERGY; distances 0). Returns {"result", "V2", "model",
    "name", "load_ms"} or {"error_type", "error"}."""
    try:
        start = time.perf_counter()
        scenario = msdeform.load_scenario(scenario_path, frames=params["frames"])
        load_ms = (time.perf_counter() - start) * 1e3
        result, deformed = msdeform.run_method(scenario, REFERENCE_METHOD)
    except Exception as error:  # noqa: BLE001 -- recorded in the rows that need it
        return {"error_type": type(error).__name__, "error": str(error)}
    result["arap_energy_ratio"] = 1.0 if result["arap_energy"] >= RIGID_ENERGY else math.nan
    result["ref_distance_rel"] = result["ref_distance_max_rel"] = 0.0
    return {"result": result, "V2": deformed, "name": scenario.name,
            "model": os.path.splitext(os.path.basename(scenario.mesh_path))[0], "load_ms": load_ms}


def _failed_reference(row, reference):
    """Marks the row failed with the error of the reference it needed."""
    row["status"] = FAILED
    row["error_type"], row["error"] = reference["error_type"], reference["error"]
    return row


def _reference_row(row, reference):
    """A REFERENCE_METHOD task without options of its own: the reference's row."""
    if "error" in reference:
        return _failed_reference(row, reference)
    row["scenario"], row["model"] = reference["name"], reference["model"]
    row["energy"] = reference["result"].get("energy")
    for column in METRIC_COLUMNS + TIMING_COLUMNS:
        if column in reference["result"]:
            row[column] = _finite_or_none(reference["result"][column])
    row["load_ms"] = reference["load_ms"]
    row["other_backend_frame_ms"] = None
    return row


def _run_deformer_task(task, row, reference):
    """A Deformer task: run_deformer with the task's options (and the other backend's frame
    time when the sweep asks, as the experiment runner's table 2: energy ed only, as Ceres does
    not run energy arap)."""
    params = task["params"]
    if reference is not None and "error" in reference:
        return _failed_reference(row, reference)
    options = build_options(params["method"], params["options"], params["seed"],
                            params["seed_field"])
    scenario, row["load_ms"] = _load(task)
    arap_result = reference["V2"] if reference is not None else None
    result = msdeform.run_deformer(scenario, options, label=params["method"],
                                   arap_result=arap_result)
    _fill(row, result, scenario)
    row["other_backend_frame_ms"] = None
    if (params["time_other_backend"] and params["method"] != "static_dense"
            and options.energy == "ed"):
        options.backend = "ceres" if options.backend == "gauss_newton" else "gauss_newton"
        other = msdeform.run_deformer(scenario, options, label=params["method"])
        row["other_backend_frame_ms"] = other["frame_ms"]
    return row


def _run_method_task(task, row, reference):
    """A task of a method without Deformer options (cgal_arap, fastlsm, ...): run_method with
    the sweep's CGAL iterations and the task's own options, against the scenario's reference
    when there is one."""
    params = task["params"]
    if reference is not None and "error" in reference:
        return _failed_reference(row, reference)
    scenario, row["load_ms"] = _load(task)
    keywords = {}
    if params.get("cgal_iterations") is not None:
        keywords["cgal_iterations"] = params["cgal_iterations"]
    # Its own options (fastlsm.steps_per_frame), as Method keywords; they win over the sweep's
    # cgal_iterations.
    keywords.update(method_keywords(params.get("options", {})))
    result, _ = msdeform.run_method(scenario, params["method"],
                                    reference=reference["V2"] if reference is not None else None,
                                    **keywords)
    _fill(row, result, scenario)
    row["other_backend_frame_ms"] = None
    return row


def run_task(task, reference=None):
    """Runs one task and returns its row (a dict of the result columns).

    `reference` is run_reference's result for the task's scenario when the sweep measures
    against the converged reference (arap_reference), else None. Never raises for the task's own errors: they give a row with
    status "failed", error_type and error (the exception's message, the C++ message for the
    module's errors).
    """
    start, start_cpu = time.perf_counter(), time.thread_time()
    row = _base_row(task)
    try:
        if (task["method"] == REFERENCE_METHOD and reference is not None
                and not task["params"].get("options")):
            _reference_row(row, reference)
        elif task["method"] in DEFORMER_METHODS:
            _run_deformer_task(task, row, reference)
        else:
            _run_method_task(task, row, reference)
    except Exception as error:  # noqa: BLE001 -- a task's failure is a row, not a stop
        _failed(row, error)
    if row["status"] != OK:
        for column in METRIC_COLUMNS + TIMING_COLUMNS:
            row[column] = None
    row["task_ms"] = (time.perf_counter() - start) * 1e3
    row["task_cpu_ms"] = (time.thread_time() - start_cpu) * 1e3
    return row


def probe():
    """What a worker runs before a sweep: its msdeform commit and package folder."""
    return {"commit": msdeform.COMMIT, "package": os.path.dirname(msdeform.__file__)}
