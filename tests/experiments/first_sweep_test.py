"""experiments/sweeps/first.json, the small sweep README.md's "Sweeps" starts a new user with:
at most 4 tasks, and its committed output (experiments/results/sweep_first/results.csv) is
what the current build computes, in every column but the times, the worker and the commit.
Runs the sweep with --serial (about 5 s). Needs the build's Python package on PYTHONPATH."""

import csv
import os
import pathlib
import subprocess
import sys

from msdeform._sweep_report import NONDETERMINISTIC_COLUMNS

ROOT = pathlib.Path(__file__).resolve().parents[2]
SWEEP = ROOT / "experiments" / "sweeps" / "first.json"
COMMITTED = ROOT / "experiments" / "results" / "sweep_first" / "results.csv"


def rows(path):
    with open(path, newline="") as f:
        return [{k: v for k, v in r.items() if k not in NONDETERMINISTIC_COLUMNS + ("commit",)}
                for r in csv.DictReader(f)]


def test_first_sweep_is_small():
    listing = subprocess.run([sys.executable, "-m", "msdeform.sweep", str(SWEEP), "--list"],
                             check=True, capture_output=True, text=True).stdout
    tasks = [line for line in listing.splitlines() if line.strip()]
    assert 1 <= len(tasks) <= 4, listing


def test_committed_results_are_the_current_builds(tmp_path):
    out = tmp_path / "out"
    subprocess.run([sys.executable, "-m", "msdeform.sweep", str(SWEEP), "--out", str(out),
                    "--serial"], check=True, capture_output=True, text=True,
                   env=dict(os.environ))
    fresh, committed = rows(out / "results.csv"), rows(COMMITTED)
    assert [r["status"] for r in committed] == ["ok"] * len(committed)
    assert fresh == committed
