"""Sweeps and who can reach their Dask cluster (python/msdeform/_sweep_cluster.py): the local
cluster listens on loopback only, a sweep runs on a TLS cluster whose certificates openssl
makes here, clients without the cluster's certificate are refused, and bad TLS flags are
one-line errors.
"""

import os
import socket
import ssl

import psutil
import pytest

from msdeform._sweep_cluster import open_scheduler_warning
from msdeform._sweep_grid import load_sweep
from msdeform._sweep_report import NONDETERMINISTIC_COLUMNS, cell
from msdeform._sweep_task import run_task

import sweep_helpers as helpers

# Debian's Dask 2022.12 on tornado 6.2: the test's own Client warns on start; not a finding.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

LOOPBACK = {"127.0.0.1", "::1"}


@pytest.fixture(scope="module")
def cactus_sweep(tmp_path_factory):
    """Two small tasks: the cactus, multi-scale, 3 frames, seeds 1 and 2."""
    source = helpers.required_path("MSDEFORM_SOURCE_DIR")
    scenario = os.path.join(source, "experiments", "scenarios", "cactus.json")
    folder = tmp_path_factory.mktemp("sweep")
    return helpers.write_json(folder / "cactus.json", {
        "scenarios": [scenario], "methods": ["multiscale"], "seeds": [1, 2], "frames": 3})


@pytest.fixture(scope="module")
def certificates(tmp_path_factory):
    """A cluster CA, a certificate it signs, and a stranger's certificate (openssl)."""
    return helpers.make_certificates(tmp_path_factory.mktemp("certificates"))


def listening(process):
    """The (address, port) pairs a process listens on (TCP)."""
    return {(c.laddr.ip, c.laddr.port) for c in process.connections(kind="inet")
            if c.status == psutil.CONN_LISTEN}


def test_local_cluster_listens_on_loopback_only(cactus_sweep, tmp_path):
    """The sweep's local cluster (scheduler, its dashboard's HTTP server, nannies and workers)
    accepts connections on 127.0.0.1 only: a Dask scheduler runs any code a client sends."""
    from msdeform.sweep import parse_args, start_client

    this = psutil.Process()
    before = listening(this)
    args = parse_args([cactus_sweep, "--out", str(tmp_path / "out"), "--workers", "1"])
    client, cluster, _ = start_client(args, lambda text: None, str(tmp_path / "scratch"))
    try:
        ours = listening(this) - before
        workers = [listening(child) for child in this.children(recursive=True)]
        dashboard = client.scheduler_info()["services"]["dashboard"]
    finally:
        client.close()
        cluster.close()
    # The scheduler's comm and its HTTP server here, a listener in the worker process.
    assert len(ours) >= 2 and any(port == dashboard for _, port in ours), ours
    assert any(workers), workers
    for address, port in ours | set().union(*workers):
        assert address in LOOPBACK, f"listening on {address}:{port}"


def test_sweep_on_a_tls_cluster(cactus_sweep, certificates, tmp_path):
    """dask-scheduler and dask-worker with README's TLS flags on 127.0.0.1: the sweep with the
    cluster's certificate runs and gives the rows the tasks give in this process; with a
    stranger's certificate, over plain tcp://, or over TLS without a certificate, the
    scheduler refuses the client."""
    expected = [run_task(task) for task in load_sweep(cactus_sweep).tasks]
    tls = certificates
    with helpers.DaskCluster(tmp_path, workers=1, tls=tls) as cluster:
        address = cluster.address
        assert address.startswith("tls://127.0.0.1:")
        assert all(w.startswith("tls://127.0.0.1:") for w in cluster.worker_addresses().values())
        out = tmp_path / "out"
        done = helpers.run_sweep([cactus_sweep, "--out", out, "--scheduler", address] +
                                 helpers.tls_flags(tls["ca"], tls["cert"], tls["key"]))
        assert f"Dask at {address}, 1 worker(s)" in done.stderr
        rows = helpers.read_rows(out / "results.csv")
        assert [row["status"] for row in rows] == ["ok", "ok"]
        for row, want in zip(rows, expected):
            assert {c: v for c, v in row.items() if c not in NONDETERMINISTIC_COLUMNS} == \
                {c: cell(want.get(c)) for c in row if c not in NONDETERMINISTIC_COLUMNS}

        out = tmp_path / "stranger"
        done = helpers.run_sweep(
            [cactus_sweep, "--out", out, "--scheduler", address, "--worker-timeout", "5"] +
            helpers.tls_flags(tls["ca"], tls["other_cert"], tls["other_key"]), check=False)
        assert done.returncode == 1, done.stderr
        assert done.stderr.splitlines()[-1].startswith(
            f"msdeform.sweep: --scheduler {address}: cannot connect within 5 s"), done.stderr
        assert not out.exists()

        # A plain tcp:// client: the scheduler closes (or resets) the connection, answering at
        # most a TLS alert (record type 21).
        host, port = address[len("tls://"):].rsplit(":", 1)
        received = b""
        with socket.create_connection((host, int(port)), timeout=10) as raw:
            try:
                raw.sendall(b"\0" * 64)
                while chunk := raw.recv(4096):
                    received += chunk
            except ConnectionResetError:
                pass
        assert received[:1] in (b"", b"\x15"), received

        # A TLS 1.3 client that trusts the cluster's CA but shows no certificate of its own:
        # its handshake ends (the scheduler's certificate is the CA's), then the scheduler
        # sends "certificate required" and closes; the client reads nothing else.
        context = ssl.create_default_context(cafile=tls["ca"])
        context.check_hostname = False
        context.minimum_version = ssl.TLSVersion.TLSv1_3
        with socket.create_connection((host, int(port)), timeout=10) as raw:
            with context.wrap_socket(raw) as connection:
                with pytest.raises((ssl.SSLError, ConnectionResetError)) as refusal:
                    connection.sendall(b"\0" * 8)
                    connection.recv(1)
        assert isinstance(refusal.value, (ssl.SSLEOFError, ConnectionResetError)) or \
            "certificate required" in str(refusal.value), refusal.value
        # The scheduler still serves its own clients afterwards.
        assert len(cluster.worker_addresses()) == 1


def bad_flag_cases(sweep, certificates, folder):
    """(command-line arguments, expected start of the one-line error) of bad TLS flags."""
    tls = certificates
    missing = os.path.join(folder, "nowhere.pem")
    scheduler = ["--scheduler", "tls://127.0.0.1:1"]
    good = helpers.tls_flags(tls["ca"], tls["cert"], tls["key"])
    return [
        (scheduler, "--scheduler tls://127.0.0.1:1: a tls:// scheduler needs --tls-ca-file and "
                    "--tls-cert (and --tls-key unless the key is in the certificate file)"),
        (scheduler + ["--tls-ca-file", tls["ca"]], "--scheduler tls://127.0.0.1:1: a tls:// "
                                                   "scheduler needs --tls-ca-file and --tls-cert"),
        (scheduler + helpers.tls_flags(missing, tls["cert"], tls["key"]),
         f"--tls-ca-file {missing}: no such file"),
        (scheduler + helpers.tls_flags(tls["ca"], missing, tls["key"]),
         f"--tls-cert {missing}: no such file"),
        (scheduler + helpers.tls_flags(tls["ca"], tls["cert"], missing),
         f"--tls-key {missing}: no such file"),
        (scheduler + helpers.tls_flags(tls["ca"], tls["cert"], folder),
         f"--tls-key {folder}: not a file"),
        (scheduler + helpers.tls_flags(sweep, tls["cert"], tls["key"]),
         f"--tls-ca-file {sweep}: not a PEM CA certificate ("),
        (scheduler + helpers.tls_flags(tls["ca"], sweep, tls["key"]),
         f"--tls-cert {sweep}, --tls-key {tls['key']}: cannot load the certificate and its "
         f"private key ("),
        (scheduler + helpers.tls_flags(tls["ca"], tls["cert"], tls["other_key"]),
         f"--tls-cert {tls['cert']}, --tls-key {tls['other_key']}: cannot load the certificate "
         f"and its private key ("),
        (scheduler + ["--tls-ca-file", tls["ca"], "--tls-cert", tls["cert"]],
         f"--tls-cert {tls['cert']}: cannot load the certificate and its private key ("),
        (good, "--tls-ca-file, --tls-cert and --tls-key need --scheduler tls://HOST:PORT"),
        (["--scheduler", "tcp://127.0.0.1:1"] + good,
         "--tls-ca-file, --tls-cert and --tls-key need --scheduler tls://HOST:PORT"),
        (["--serial", "--tls-cert", tls["cert"]],
         "--tls-ca-file, --tls-cert and --tls-key need --scheduler tls://HOST:PORT"),
    ]


def test_bad_tls_flags(cactus_sweep, certificates, tmp_path, capsys):
    """A missing or unreadable file names its flag; a tls:// scheduler without the certificate
    flags, or TLS flags without one, is refused: one line, exit 1 (the command line checked
    in this process; the first case also through the command, which writes nothing)."""
    from msdeform.sweep import parse_args

    out = tmp_path / "out"
    cases = bad_flag_cases(cactus_sweep, certificates, str(tmp_path))
    for args, message in cases:
        with pytest.raises(SystemExit) as exit:
            parse_args([cactus_sweep, "--out", str(out)] + args)
        error = capsys.readouterr().err
        assert exit.value.code == 1, (args, error)
        assert len(error.splitlines()) == 1, (args, error)
        assert error.startswith("msdeform.sweep: " + message), (args, error)
    assert len(cases) == 13
    args, message = cases[0]
    done = helpers.run_sweep([cactus_sweep, "--out", out] + args, check=False)
    assert (done.returncode, done.stderr) == (
        1, f"msdeform.sweep: {message} (--help lists the options)\n")
    assert not out.exists()


def test_open_scheduler_warning():
    """A tcp:// scheduler (or one without a scheme, which Dask reads as tcp://) off loopback
    gets a warning line; loopback and tls:// do not."""
    for address in ("tcp://10.1.2.3:8786", "node7:8786", "tcp://[2001:db8::1]:8786"):
        assert open_scheduler_warning(address).startswith(f"sweep: warning: {address} has no TLS")
    for address in ("tcp://127.0.0.1:8786", "tcp://localhost:8786", "tcp://[::1]:8786",
                    "127.0.0.2:8786", "tls://10.1.2.3:8786"):
        assert open_scheduler_warning(address) is None, address
