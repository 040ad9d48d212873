"""Helpers of test_sweep.py and test_sweep_cluster.py: the environment, sweep files, the sweep
driver as a subprocess, a real Dask cluster (dask-scheduler and dask-worker processes on
127.0.0.1, optionally with TLS), certificates made with openssl, and result tables.
"""

import contextlib
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time

# Debian's interpreter: the one with NumPy, Dask and matplotlib (tests/CMakeLists.txt runs
# pytest with it).
PYTHON = sys.executable


def required_path(variable):
    """A path from the environment ctest sets (MSDEFORM_SOURCE_DIR, MSDEFORM_BUILD_DIR,
    MSDEFORM_CLI, MSDEFORM_EXPERIMENTS); an error (never a skip) when unset or missing."""
    value = os.environ.get(variable)
    if not value:
        raise RuntimeError(f"{variable} is not set: run these tests through ctest (python/pytest)")
    if not os.path.exists(value):
        raise RuntimeError(f"{variable}={value}: no such file or folder")
    return value


def environment():
    """The environment of the driver and the Dask processes: this test's, with PYTHONPATH
    holding the build tree's package (ctest sets it; checked here)."""
    build = required_path("MSDEFORM_BUILD_DIR")
    package = os.path.join(build, "python")
    if not os.path.exists(os.path.join(package, "msdeform", "sweep.py")):
        raise RuntimeError(f"{package}/msdeform/sweep.py: missing; build the _msdeform target")
    env = dict(os.environ)
    paths = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    env["PYTHONPATH"] = os.pathsep.join([package] + [p for p in paths if p != package])
    return env


def dask_command(name):
    """The path of a Dask command (dask-scheduler, dask-worker); an error when missing."""
    path = shutil.which(name)
    if path is None:
        raise RuntimeError(f"{name}: not on PATH (Debian's python3-distributed has it)")
    return path


def write_json(path, value):
    """Writes value as JSON to path; returns the path as a str."""
    with open(path, "w", encoding="utf-8") as file:
        json.dump(value, file, indent=1)
    return str(path)


def run_sweep(args, timeout=300, check=True):
    """Runs `python3 -m msdeform.sweep ARGS`; returns the CompletedProcess (text output)."""
    done = subprocess.run([PYTHON, "-m", "msdeform.sweep"] + [str(a) for a in args],
                          env=environment(), capture_output=True, text=True, timeout=timeout)
    if check and done.returncode != 0:
        raise AssertionError(f"sweep exited {done.returncode}:\n{done.stderr}")
    return done


def start_sweep(args):
    """Starts `python3 -m msdeform.sweep ARGS` in the background (its own process group)."""
    return subprocess.Popen([PYTHON, "-m", "msdeform.sweep"] + [str(a) for a in args],
                            env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)


def listed_ids(sweep_file):
    """The task ids of a sweep in task order, from `--list`."""
    done = run_sweep([sweep_file, "--list"])
    return [line.split("\t")[1] for line in done.stdout.splitlines()]


def read_rows(path):
    """The rows of a results.csv as dicts of text."""
    with open(path, newline="", encoding="utf-8") as file:
        return list(csv.DictReader(file))


def read_table(path):
    """(columns, rows as lists of text) of a C++-style table CSV, after its '#' lines."""
    with open(path, encoding="utf-8") as file:
        lines = [line.rstrip("\n") for line in file if not line.startswith("#")]
    return lines[0].split(","), [line.split(",") for line in lines[1:]]


def task_files(out):
    """{task id: path} of DIR/tasks/*.json."""
    folder = os.path.join(out, "tasks")
    return {name[:-5]: os.path.join(folder, name) for name in sorted(os.listdir(folder))
            if name.endswith(".json")}


def wait_until(condition, timeout, what, interval=0.02):
    """Polls condition() until it is truthy (returns its value) or raises after timeout s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(interval)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def stop(process, timeout=10):
    """Ends a process this test started: SIGTERM, then SIGKILL after timeout s."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def make_certificates(folder):
    """Makes, with openssl, a cluster CA, a certificate it signs (one for the scheduler, the
    workers and the driver, as README.md's "On a cluster" does) and a stranger's self-signed
    certificate. Returns {"ca", "cert", "key", "other_cert", "other_key"}: PEM file paths."""
    openssl = shutil.which("openssl")
    if openssl is None:
        raise RuntimeError("openssl: not on PATH (scripts/install_deps.sh installs it)")
    folder = str(folder)
    paths = {name: os.path.join(folder, name + ".pem")
             for name in ("ca", "ca_key", "cert", "key", "request", "other_cert", "other_key")}

    def run(*args):
        """Runs openssl ARGS; raises with its message when it fails."""
        done = subprocess.run([openssl] + list(args), capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"openssl {' '.join(args)}: {done.stderr.strip()}")

    new_key = ["-newkey", "rsa:2048", "-nodes", "-days", "2"]
    run("req", "-x509", *new_key, "-keyout", paths["ca_key"], "-out", paths["ca"],
        "-subj", "/CN=msdeform test cluster CA")
    run("req", *new_key[:3], "-keyout", paths["key"], "-out", paths["request"],
        "-subj", "/CN=msdeform test node")
    run("x509", "-req", "-in", paths["request"], "-CA", paths["ca"], "-CAkey", paths["ca_key"],
        "-CAcreateserial", "-days", "2", "-out", paths["cert"])
    run("req", "-x509", *new_key, "-keyout", paths["other_key"], "-out", paths["other_cert"],
        "-subj", "/CN=a stranger")
    return {name: paths[name] for name in ("ca", "cert", "key", "other_cert", "other_key")}


def tls_flags(ca, cert, key):
    """The TLS flags shared by dask-scheduler, dask-worker and msdeform.sweep."""
    return ["--tls-ca-file", ca, "--tls-cert", cert, "--tls-key", key]


def read_scheduler_address(path):
    """The address in a Dask scheduler file, or None while the file is missing or half
    written (dask-scheduler opens it before it writes the JSON)."""
    try:
        with open(path) as file:
            return json.load(file).get("address")
    except (FileNotFoundError, json.JSONDecodeError):
        return None


class DaskCluster:
    """A real Dask cluster on 127.0.0.1: `dask-scheduler` and `workers` `dask-worker`
    processes (one process, one thread each, no nanny: killing one kills that worker), all
    ended on exit, also when the test fails. Use as a context manager."""

    def __init__(self, folder, workers=2, config=None, tls=None):
        """folder: where the scheduler file and the logs go; config: Dask settings as
        environment variables (DASK_DISTRIBUTED__...) of the scheduler and the workers; tls:
        make_certificates' paths for a TLS cluster (every process uses "cert" and "key")."""
        self.folder, self.count, self.config = str(folder), workers, dict(config or {})
        self.tls = tls
        self.scheduler = None
        self.workers = []
        self.address = None
        self.client = None
        self._stack = contextlib.ExitStack()

    def _log(self, name):
        """An open log file for a process."""
        return self._stack.enter_context(open(os.path.join(self.folder, name + ".log"), "w"))

    def __enter__(self):
        """Starts the scheduler, then the workers, and waits until all have joined."""
        self._stack.__enter__()
        self._stack.callback(self._stop_all)
        try:
            scheduler_file = os.path.join(self.folder, "scheduler.json")
            env = environment()
            env.update(self.config)
            security = []
            if self.tls:
                security = tls_flags(self.tls["ca"], self.tls["cert"], self.tls["key"])
            self.scheduler = subprocess.Popen(
                [dask_command("dask-scheduler"), "--host", "127.0.0.1", "--port", "0",
                 "--no-dashboard", "--scheduler-file", scheduler_file] +
                (["--protocol", "tls"] + security if self.tls else []),
                env=env, stdout=subprocess.DEVNULL, stderr=self._log("scheduler"),
                start_new_session=True)
            # The scheduler creates its file, then writes it: wait for a whole JSON document.
            wait_until(lambda: read_scheduler_address(scheduler_file) or
                       self.scheduler.poll() is not None, 60, "the scheduler file")
            if self.scheduler.poll() is not None:
                raise RuntimeError(f"dask-scheduler exited {self.scheduler.returncode}; see "
                                   f"{self.folder}/scheduler.log")
            self.address = read_scheduler_address(scheduler_file)
            for i in range(self.count):
                self.workers.append(subprocess.Popen(
                    [dask_command("dask-worker"), self.address, "--nworkers", "1",
                     "--nthreads", "1", "--no-dashboard", "--no-nanny", "--name", f"worker-{i}",
                     "--local-directory", os.path.join(self.folder, f"worker-{i}")] + security,
                    env=env, stdout=subprocess.DEVNULL, stderr=self._log(f"worker-{i}"),
                    start_new_session=True))
            from distributed import Client
            from distributed.security import Security

            security = None
            if self.tls:
                security = Security(tls_ca_file=self.tls["ca"], tls_client_cert=self.tls["cert"],
                                    tls_client_key=self.tls["key"], require_encryption=True)
            self.client = Client(self.address, timeout=30, security=security)
            self._stack.callback(self.client.close)
            self.client.wait_for_workers(self.count, timeout=60)
        except BaseException:
            self._stack.close()
            raise
        return self

    def worker_addresses(self):
        """{worker index: address} of the workers connected now."""
        addresses = {}
        for address, info in self.client.scheduler_info()["workers"].items():
            addresses[int(str(info["name"]).split("-")[-1])] = address
        return addresses

    def _stop_all(self):
        """Ends every process this cluster started."""
        for process in self.workers + ([self.scheduler] if self.scheduler else []):
            stop(process)

    def __exit__(self, *exc):
        """Closes the client and ends the processes."""
        self._stack.__exit__(*exc)
        return False


def freeze_busy_worker(cluster, index, prefix, timeout=60):
    """Stops worker `index` (SIGSTOP) at a moment it holds at least one of this sweep's tasks
    (keys starting with prefix), and returns those keys. A stopped worker can finish nothing,
    so the keys are exactly the tasks that die with it; it is resumed and retried when idle."""
    worker = cluster.workers[index]
    address = cluster.worker_addresses()[index]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        os.kill(worker.pid, signal.SIGSTOP)
        time.sleep(0.3)  # what it sent before the stop reaches the scheduler
        keys = [str(k) for k in cluster.client.processing().get(address, ())
                if str(k).startswith(prefix)]
        if keys:
            return keys
        os.kill(worker.pid, signal.SIGCONT)
        time.sleep(0.05)
    raise AssertionError(f"worker {index} held no task of the sweep within {timeout} s")


def sweep_killing_worker_0(cluster, sweep_file, out):
    """Runs the sweep on `cluster`; once the first rows are in, freezes worker 0 while it holds
    tasks of the sweep and kills it. Returns (held task keys, driver, stdout, stderr) after
    the driver has exited."""
    driver = start_sweep([sweep_file, "--out", out, "--scheduler", cluster.address])
    try:
        wait_until(lambda: os.path.isdir(out / "tasks") and task_files(out), 120,
                   "the first rows")
        held = freeze_busy_worker(cluster, 0, "msdeform-task-")
        os.kill(cluster.workers[0].pid, signal.SIGKILL)
        cluster.workers[0].wait(10)
        stdout, stderr = driver.communicate(timeout=180)
    finally:
        stop(driver)
    return held, driver, stdout, stderr
