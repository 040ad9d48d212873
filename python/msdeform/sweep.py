"""Sweeps on Dask: a grid of scenario runs, one row of metrics per task, merged into a table.

    python3 -m msdeform.sweep SWEEP.json --out DIR                  # local Dask cluster
    python3 -m msdeform.sweep SWEEP.json --out DIR --scheduler tls://HOST:8786 \
        --tls-ca-file ca.pem --tls-cert client.pem --tls-key client.key
    python3 -m msdeform.sweep SWEEP.json --out DIR --resume         # run only what is missing
    python3 -m msdeform.sweep SWEEP.json --out DIR --serial         # in this process, in order
    python3 -m msdeform.sweep SWEEP.json --list                     # the task grid, nothing run

The sweep file's format is in msdeform._sweep_grid; README.md, "Sweeps", shows how to run one
on a cluster. DIR gets tasks/<id>.json (one row per finished task, written as it arrives),
tasks.json (the grid), results.csv (every task's row, in task order), summary.md (per variant,
mean and spread over the seeds), chart.png and the sweep's table projections (e.g. table2.csv).

Exit status: 0 when every task has a row (tasks that failed included: their rows say why),
1 on bad input (nothing written), 2 when Dask gave up on a task (status "lost": rerun with
--resume), 130 when interrupted (Ctrl-C) and 143 on SIGTERM (--resume continues).
"""

import argparse
import datetime
import json
import os
import shutil
import signal
import sys
import tempfile
import threading
import time

import msdeform
from msdeform import _sweep_report as report
from msdeform._sweep_cluster import (add_security_arguments, check_security_arguments,
                                     start_client)
from msdeform._sweep_grid import SweepError, describe_task, load_sweep, task_id
from msdeform._sweep_task import FAILED, LOST, OK, run_reference, run_task

EXIT_OK, EXIT_BAD_INPUT, EXIT_LOST, EXIT_INTERRUPTED, EXIT_TERMINATED = 0, 1, 2, 130, 143


class Progress:
    """The progress line on stderr: tasks done, failed, running, waiting, rate and time left.

    On a terminal the line is redrawn every second; otherwise printed every 10 s. A failed or
    lost task gets a line of its own when it arrives.
    """

    def __init__(self, total, already, stream=sys.stderr, running=None):
        """total: tasks to run now; already: tasks with rows before (--resume); running: a
        function giving (tasks running, references running)."""
        self.total, self.already, self.stream, self.running = total, already, stream, running
        self.done = self.failed = 0
        self.start = time.monotonic()
        self.end = None
        self.tty = stream.isatty()
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = None
        self._last = 0.0

    def elapsed(self):
        """Seconds from the first task's start to the last one's row (or to now)."""
        return (self.end if self.end is not None else time.monotonic()) - self.start

    def line(self):
        """The current progress line."""
        done, failed, elapsed = self.done, self.failed, self.elapsed()  # the ticker's snapshot
        rate = done / elapsed if elapsed > 0 else 0.0
        left = self.total - done
        running = references = None
        if self.running is not None:
            try:
                running, references = self.running()
                running = min(running, left)
            except Exception:  # noqa: BLE001 -- a progress line never stops a sweep
                running = None
        parts = [f"{self.already + done}/{self.already + self.total} done"]
        if failed:
            parts.append(f"{failed} failed")
        if running is not None:
            parts.append(f"{running} running, {left - running} waiting")
            if references:
                parts.append(f"{references} reference(s) running")
        parts.append(f"{rate:.2f} tasks/s")
        if done and left and rate > 0:
            parts.append(f"~{_duration(left / rate)} left")
        parts.append(f"{_duration(elapsed)} elapsed")
        return "sweep: " + ", ".join(parts)

    def _print(self, force=False):
        """Prints the line (redrawn in place on a terminal)."""
        now = time.monotonic()
        if not force and now - self._last < (1.0 if self.tty else 10.0):
            return
        self._last = now
        text = self.line()
        with self._lock:
            if self.tty:
                self.stream.write("\r" + text.ljust(100) + "\r")
            else:
                self.stream.write(text + "\n")
            self.stream.flush()

    def note(self, text):
        """A line of its own (a failed task, a message) above the progress line."""
        with self._lock:
            self.stream.write(("\r" + " " * 100 + "\r" if self.tty else "") + text + "\n")
            self.stream.flush()

    def task_done(self, task, row):
        """Counts a finished task; a failed or lost one is named with its message."""
        self.done += 1
        if row["status"] != OK:
            self.failed += 1
            self.note(f"sweep: task {task['index']} {task['id']} ({describe_task(task)}) "
                      f"{row['status']}: {row['error_type']}: {row['error']}")
        self._print(force=self.tty)

    def __enter__(self):
        """Starts the ticker that redraws the line between tasks."""
        def tick():
            """Redraws the line every second until __exit__."""
            while not self._stop.wait(1.0):
                self._print()
        self._thread = threading.Thread(target=tick, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        """Stops the ticker and prints the last line."""
        self.end = time.monotonic()
        self._stop.set()
        self._thread.join()
        self._print(force=True)
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()
        return False


def _duration(seconds):
    """Seconds as '42 s', '3.5 min' or '2.1 h'."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def needed_reference(sweep, task):
    """The parameters of the converged ARAP run a task depends on (its scenario's reference of
    arap_energy_ratio, ref_distance_rel and ref_distance_max_rel; a full_arap task without
    options of its own takes that run as its row), or None when the sweep has no
    arap_reference."""
    if not sweep.settings["arap_reference"]:
        return None
    params = task["params"]
    return {"scenario": params["scenario"], "frames": params["frames"]}


def lost_row(task, error, columns):
    """The row of a task Dask gave up on: parameters, status lost, the error."""
    row = {column: None for column in columns}
    row.update({"index": task["index"], "task_id": task["id"], "status": LOST,
                "error_type": type(error).__name__, "error": str(error) or repr(error),
                "commit": msdeform.COMMIT})
    row["scenario"] = os.path.splitext(os.path.basename(task["params"]["scenario"]))[0]
    row.update(task["columns"])
    return row


def run_serial(sweep, todo, record):
    """Runs the tasks in this process, in task order (the reference of 'identical to a serial
    run'), computing each reference once."""
    references = {}
    for task in todo:
        params = needed_reference(sweep, task)
        reference = None
        if params is not None:
            key = task_id(params)
            if key not in references:
                references[key] = run_reference(task["scenario_path"], params)
            reference = references[key]
        record(task, run_task(task, reference))


def run_dask(sweep, todo, record, client, columns, retries):
    """Submits every task (and each reference once) to Dask and records the rows as they
    arrive. A task whose worker dies is rescheduled by Dask's scheduler on another worker (up
    to its allowed-failures deaths); one that raises on a worker outside run_task's own
    handling (a worker that cannot unpickle it) is rerun `retries` times; one Dask gives up on
    is recorded as lost."""
    from distributed import as_completed

    references, futures = {}, {}
    for task in todo:
        params = needed_reference(sweep, task)
        reference = None
        if params is not None:
            key = "msdeform-reference-" + task_id(params)
            if key not in references:
                references[key] = client.submit(run_reference, task["scenario_path"], params,
                                                key=key, pure=False, retries=retries, priority=1)
            reference = references[key]
        future = client.submit(run_task, task, reference, key="msdeform-task-" + task["id"],
                               pure=False, retries=retries)
        futures[future] = task
    try:
        for future in as_completed(futures):
            task = futures[future]
            try:
                row = future.result()
            except Exception as error:  # noqa: BLE001 -- Dask's failure is the task's row
                row = lost_row(task, error, columns)
            record(task, row)
            future.release()
    except BaseException:
        client.cancel(list(futures) + list(references.values()))
        raise


def _running_on(client):
    """A function counting this sweep's tasks and references processing on the workers."""
    threads = {}

    def running():
        """(tasks, references) of this sweep executing now: per worker, at most its thread
        count, references first (they are submitted first, at a higher priority)."""
        tasks = references = 0
        for worker, keys in client.processing().items():
            if worker not in threads:
                threads.update({address: info["nthreads"] for address, info
                                in client.scheduler_info()["workers"].items()})
            keys = [str(key) for key in keys]
            slots = threads.get(worker, len(keys))
            ours = min(sum(k.startswith("msdeform-reference-") for k in keys), slots)
            references += ours
            tasks += min(sum(k.startswith("msdeform-task-") for k in keys), slots - ours)
        return tasks, references
    return running


def prepare_out(out, resume, sweep):
    """Checks DIR and returns {task id: row} of the tasks that already have rows (--resume).

    Without --resume DIR must not exist or be empty; rows made by another msdeform commit are
    refused (a table mixes one build's numbers only).
    """
    if os.path.exists(out) and not os.path.isdir(out):
        raise SweepError(f"{out}: not a folder")
    if os.path.isdir(out) and os.listdir(out) and not resume:
        raise SweepError(f"{out}: exists and is not empty; --resume continues the sweep in it, "
                         f"or choose another --out")
    done = {}
    if resume and os.path.isdir(os.path.join(out, "tasks")):
        for task in sweep.tasks:
            try:
                row = report.read_task_row(out, task)
            except ValueError as error:
                raise SweepError(str(error)) from None
            if row is None:
                continue
            if row.get("commit") != msdeform.COMMIT:
                raise SweepError(f"{report.task_file(out, task['id'])}: made by msdeform "
                                 f"{row.get('commit')}, this is {msdeform.COMMIT}; run the sweep "
                                 f"into a new --out")
            done[task["id"]] = row
    return done


def start_out(out, sweep, say):
    """Makes DIR/tasks/ and writes DIR/tasks.json (the grid), once the engine is up; names row
    files of tasks that are not in the grid (a sweep file changed since)."""
    os.makedirs(os.path.join(out, "tasks"), exist_ok=True)
    grid = [{"index": t["index"], "id": t["id"], "params": t["params"]} for t in sweep.tasks]
    text = json.dumps(grid, indent=1) + "\n"
    report.write_atomically(os.path.join(out, "tasks.json"), lambda file: file.write(text))
    ids = {task["id"] for task in sweep.tasks}
    others = [name for name in os.listdir(os.path.join(out, "tasks"))
              if name.endswith(".json") and name[:-5] not in ids]
    if others:
        say(f"sweep: {len(others)} row file(s) in {os.path.join(out, 'tasks')} are of tasks not "
            f"in this sweep; left as they are, not in the tables")


def write_outputs(out, sweep, rows, header, chart_x, chart_y):
    """results.csv, summary.md, chart.png and the table projections; returns their paths."""
    columns = report.columns_of(sweep)
    report.write_results(out, columns, rows)
    paths = [os.path.join(out, "results.csv"), report.write_summary(out, sweep, rows, header)]
    paths.append(report.write_chart(out, sweep, rows, chart_x, chart_y))
    paths += report.write_tables(out, sweep, rows, header)
    return paths


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error and exit status 1 (2 means lost tasks here)."""

    def error(self, message):
        """Prints 'msdeform.sweep: message' and exits 1."""
        self.exit(EXIT_BAD_INPUT, f"msdeform.sweep: {message} (--help lists the options)\n")


def parse_args(argv):
    """The command line."""
    parser = _Parser(
        prog="python3 -m msdeform.sweep",
        description="Runs a sweep (a grid of msdeform scenario runs) on Dask and merges one row "
                    "per task into DIR/results.csv (README.md, 'Sweeps').")
    parser.add_argument("sweep", help="the sweep file (JSON; scenario paths relative to it)")
    parser.add_argument("--out",
                        help="output folder (created; must be new or empty unless --resume)")
    parser.add_argument("--resume", action="store_true",
                        help="continue a sweep in --out: run only the tasks without a row")
    engine = parser.add_mutually_exclusive_group()
    engine.add_argument("--scheduler", metavar="tls://HOST:PORT",
                        help="a running Dask scheduler, tls:// with the --tls-* flags or tcp:// "
                             "(no authentication: README.md, 'Sweeps'); default: a local "
                             "cluster on 127.0.0.1")
    engine.add_argument("--workers", type=int, metavar="N",
                        help="worker processes of the local cluster (default: one per core)")
    engine.add_argument("--serial", action="store_true",
                        help="run the tasks in this process, in order, without Dask")
    add_security_arguments(parser)
    parser.add_argument("--retries", type=int, default=3, metavar="N",
                        help="worker deaths a task may see before Dask gives up on it (the "
                             "local cluster's allowed-failures; a running scheduler has its "
                             "own), and Dask's retries of a task that raised on a worker "
                             "(default 3)")
    parser.add_argument("--worker-timeout", type=float, default=60.0, metavar="S",
                        help="seconds to wait for the scheduler and a first worker (default 60)")
    parser.add_argument("--chart-x", metavar="PARAM",
                        help="the chart's parameter (an option, seed or frames)")
    parser.add_argument("--chart-y", metavar="METRIC",
                        help="the chart's metric (default arap_energy)")
    parser.add_argument("--list", action="store_true", help="print the task grid and exit")
    args = parser.parse_args(argv)
    if not args.list and not args.out:
        parser.error("--out is required (unless --list)")
    if args.workers is not None and args.workers < 1:
        parser.error("--workers: expected an integer >= 1")
    if args.retries < 0:
        parser.error("--retries: expected an integer >= 0")
    security = check_security_arguments(args)
    if security:
        parser.error(security)
    if args.workers is None:
        args.workers = len(os.sched_getaffinity(0))
    return args


class Interrupted(KeyboardInterrupt):
    """SIGTERM (a batch system's stop), handled as Ctrl-C: rows so far are kept."""


def _raise_interrupted(signum, frame):
    """The SIGTERM handler: stops the sweep as Ctrl-C does."""
    raise Interrupted()


def main(argv=None):
    """Runs the command line; returns the exit status."""
    args = parse_args(argv)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _raise_interrupted)
    say = lambda text: print(text, file=sys.stderr, flush=True)  # noqa: E731
    try:
        sweep = load_sweep(args.sweep)
        if args.list:
            for task in sweep.tasks:
                print(f"{task['index']}\t{task['id']}\t{describe_task(task)}")
            return EXIT_OK
        report.check_outputs(sweep, args.chart_x, args.chart_y)
        out = args.out
        done = prepare_out(out, args.resume, sweep)
    except (SweepError, ValueError) as error:
        say(f"msdeform.sweep: {error}")
        return EXIT_BAD_INPUT

    todo = [task for task in sweep.tasks if task["id"] not in done]
    say(f"sweep: {args.sweep}: {len(sweep.tasks)} tasks" +
        (f", {len(done)} with rows in {out}, {len(todo)} to run" if args.resume else ""))
    rows = dict(done)
    columns = report.columns_of(sweep)

    def record(task, row):
        """Keeps a finished task's row; writes it at once unless Dask lost the task."""
        assert row["task_id"] == task["id"], (row["task_id"], task["id"])
        if row["status"] != LOST:
            report.write_task_row(out, task, row)
        rows[task["id"]] = row
        progress.task_done(task, row)

    started = time.monotonic()
    client = cluster = scratch = None
    status = EXIT_OK
    try:
        if args.serial or not todo:
            engine = "serial (this process)"
            start_out(out, sweep, say)
            progress = Progress(len(todo), len(done), running=lambda: (1, 0))
            with progress:
                run_serial(sweep, todo, record)
        else:
            # The local workers' own scratch folder: Dask's shared default in /tmp keeps the
            # lock files of workers killed elsewhere, and logs about them.
            if not args.scheduler:
                scratch = tempfile.mkdtemp(prefix="msdeform-sweep-dask-")
            client, cluster, engine = start_client(args, say, scratch)
            engine += f", up in {time.monotonic() - started:.1f} s"
            start_out(out, sweep, say)
            progress = Progress(len(todo), len(done), running=_running_on(client))
            with progress:
                run_dask(sweep, todo, record, client, columns, args.retries)
    except KeyboardInterrupt as interrupt:
        say(f"\nsweep: interrupted; {len(rows)} of {len(sweep.tasks)} tasks have rows in "
            f"{os.path.join(out, 'tasks')}; continue with --resume")
        status = EXIT_TERMINATED if isinstance(interrupt, Interrupted) else EXIT_INTERRUPTED
    except SweepError as error:
        say(f"msdeform.sweep: {error}")
        status = EXIT_BAD_INPUT
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)
    if status != EXIT_OK:
        return status

    ordered = [rows[task["id"]] for task in sweep.tasks]
    counts = {s: sum(1 for row in ordered if row["status"] == s) for s in (OK, FAILED, LOST)}
    now = datetime.datetime.now(datetime.timezone.utc)
    header = [f"sweep: {args.sweep} ({len(ordered)} tasks: {counts[OK]} ok, {counts[FAILED]} "
              f"failed, {counts[LOST]} lost)",
              f"commit: {msdeform.COMMIT} (msdeform {msdeform.__version__})",
              f"date: {now.strftime('%Y-%m-%dT%H:%M:%SZ')}",
              f"engine: {engine}; {len(todo)} task(s) run in {progress.elapsed():.1f} s "
              f"({len(todo) / max(progress.elapsed(), 1e-9):.2f} tasks/s)"]
    try:
        paths = write_outputs(out, sweep, ordered, header, args.chart_x, args.chart_y)
    except ValueError as error:
        say(f"msdeform.sweep: {error}")
        return EXIT_BAD_INPUT
    say(f"sweep: {header[-1]}")
    say(f"sweep: {counts[OK]} ok, {counts[FAILED]} failed, {counts[LOST]} lost; wrote " +
        ", ".join(paths))
    if counts[LOST]:
        say("sweep: Dask gave up on the lost tasks; rerun with --resume to run them again")
        return EXIT_LOST
    return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
