"""The Dask cluster of a sweep: a local one on loopback, or a running scheduler, over TLS when
its address is tls://.

A Dask scheduler runs whatever a client sends it (pickled Python functions, executed by every
worker as the user who started it), so who can reach it decides who can run code there. The
local cluster listens on 127.0.0.1 only (scheduler, dashboard, nannies and workers). A remote
scheduler on tls:// takes the cluster's CA and this client's certificate and key
(--tls-ca-file, --tls-cert, --tls-key, the flags dask-scheduler and dask-worker take); the
scheduler then accepts only clients whose certificate its CA signed, and this client only a
scheduler whose certificate that CA signed. README.md, "Sweeps", "On a cluster", shows the
commands.
"""

import ipaddress
import logging
import os
import ssl
import urllib.parse
import urllib.request

import msdeform
from msdeform._sweep_grid import SweepError
from msdeform._sweep_task import probe

# Where the local cluster listens: loopback only. A worker's HTTP server (health and metrics
# pages) binds every interface unless given an address, even with no dashboard.
LOCAL_HOST = "127.0.0.1"
LOCAL_DASHBOARD = LOCAL_HOST + ":8787"
LOCAL_WORKER_HTTP = LOCAL_HOST + ":0"

TLS_FLAGS = ("--tls-ca-file", "--tls-cert", "--tls-key")


def add_security_arguments(parser):
    """The TLS flags of a tls:// --scheduler (dask-scheduler's and dask-worker's names)."""
    parser.add_argument("--tls-ca-file", metavar="PEM",
                        help="the cluster's CA certificate (PEM): the scheduler's certificate "
                             "must be signed by it (with --scheduler tls://HOST:PORT)")
    parser.add_argument("--tls-cert", metavar="PEM",
                        help="this client's certificate (PEM), signed by the cluster's CA "
                             "(with --scheduler tls://HOST:PORT)")
    parser.add_argument("--tls-key", metavar="PEM",
                        help="the private key of --tls-cert (default: in the --tls-cert file)")


def _readable_file(flag, path):
    """An error message when `path` (given to `flag`) is not a readable file, else None."""
    if not os.path.exists(path):
        return f"{flag} {path}: no such file"
    if not os.path.isfile(path):
        return f"{flag} {path}: not a file"
    try:
        with open(path, "rb"):
            pass
    except OSError as error:
        return f"{flag} {path}: cannot read ({error.strerror})"
    return None


def _is_tls(scheduler):
    """Whether a --scheduler address asks for TLS."""
    return scheduler is not None and scheduler.startswith("tls://")


def check_security_arguments(args):
    """The one-line error of the TLS flags and --scheduler together, or None when they fit: a
    tls:// scheduler needs --tls-ca-file and --tls-cert (the key may be in the certificate's
    file), the flags need a tls:// scheduler, and the files must load as PEM."""
    given = [(flag, getattr(args, flag[2:].replace("-", "_"))) for flag in TLS_FLAGS]
    given = [(flag, path) for flag, path in given if path is not None]
    if given and not _is_tls(args.scheduler):
        return ("--tls-ca-file, --tls-cert and --tls-key need --scheduler tls://HOST:PORT (the "
                "local cluster listens on 127.0.0.1 only)")
    if not _is_tls(args.scheduler):
        return None
    if args.tls_ca_file is None or args.tls_cert is None:
        return (f"--scheduler {args.scheduler}: a tls:// scheduler needs --tls-ca-file and "
                f"--tls-cert (and --tls-key unless the key is in the certificate file)")
    for flag, path in given:
        message = _readable_file(flag, path)
        if message:
            return message
    context = ssl.create_default_context(ssl.Purpose.SERVER_AUTH)
    try:
        context.load_verify_locations(cafile=args.tls_ca_file)
    except ssl.SSLError as error:
        return f"--tls-ca-file {args.tls_ca_file}: not a PEM CA certificate ({error})"
    try:
        context.load_cert_chain(args.tls_cert, args.tls_key)
    except ssl.SSLError as error:
        files = f"--tls-cert {args.tls_cert}" + (
            f", --tls-key {args.tls_key}" if args.tls_key is not None else "")
        return f"{files}: cannot load the certificate and its private key ({error})"
    return None


def security_of(args):
    """The distributed Security of --scheduler's TLS flags (checked), or None without TLS."""
    if not _is_tls(args.scheduler):
        return None
    from distributed.security import Security

    return Security(tls_ca_file=args.tls_ca_file, tls_client_cert=args.tls_cert,
                    tls_client_key=args.tls_key, require_encryption=True)


def open_scheduler_warning(scheduler):
    """The warning line for a --scheduler anyone on the network may reach without a
    certificate (tcp:// to an address other than loopback), else None."""
    address = scheduler if "://" in scheduler else "tcp://" + scheduler  # Dask's default
    scheme, host = address.split("://", 1)[0], urllib.parse.urlsplit(address).hostname
    if scheme != "tcp" or host == "localhost":
        return None
    try:
        if ipaddress.ip_address(host or "").is_loopback:
            return None
    except ValueError:
        pass
    return (f"sweep: warning: {scheduler} has no TLS: whoever reaches it can run any code on "
            f"its workers; README.md, 'Sweeps', 'On a cluster', shows a tls:// cluster")


def _dashboard(client):
    """The scheduler's dashboard address, or None when there is none up: no HTTP service, or
    Debian's Dask without bokeh, whose page only says that bokeh is needed."""

    port = client.scheduler_info().get("services", {}).get("dashboard")
    if not port:
        return None
    host = client.scheduler.address.split("://")[-1].rsplit(":", 1)[0]
    link = f"http://{host}:{port}/status"
    try:
        with urllib.request.urlopen(link, timeout=2) as page:
            if b"needs bokeh" in page.read(4096):
                return None
    except OSError:
        return None
    return link


def _check_workers(client, timeout):
    """Waits for a worker, then checks that every worker imports this msdeform build."""
    try:
        client.wait_for_workers(1, timeout=timeout)
    except TimeoutError:
        raise SweepError(f"no Dask worker joined the scheduler within {timeout:g} s (start "
                         f"dask-worker {client.scheduler.address} with "
                         f"PYTHONPATH=<build>/python)") from None
    answers = client.run(probe, on_error="return")
    for worker, answer in sorted(answers.items()):
        if isinstance(answer, BaseException):
            raise SweepError(f"Dask worker {worker} cannot import msdeform "
                             f"({type(answer).__name__}: {answer}); start it with "
                             f"PYTHONPATH=<build>/python")
        if answer["commit"] != msdeform.COMMIT:
            raise SweepError(f"Dask worker {worker} runs msdeform {answer['commit']} from "
                             f"{answer['package']}; this driver is {msdeform.COMMIT}")
    return len(answers)


def _worker_environment():
    """PYTHONPATH with this msdeform's folder first, for local worker processes."""
    folder = os.path.dirname(os.path.dirname(os.path.abspath(msdeform.__file__)))
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    if folder not in paths:
        os.environ["PYTHONPATH"] = os.pathsep.join([folder] + paths)


def _connect(args, say):
    """A Client on --scheduler, over TLS with the TLS flags when it is tls://."""
    from distributed import Client

    warning = open_scheduler_warning(args.scheduler)
    if warning:
        say(warning)
    try:
        return Client(args.scheduler, timeout=args.worker_timeout, security=security_of(args))
    except (OSError, TimeoutError, ValueError) as error:
        hint = ""
        if _is_tls(args.scheduler):
            hint = ("; the scheduler accepts only certificates its --tls-ca-file signed, and "
                    "this client only a scheduler certificate --tls-ca-file signed")
        raise SweepError(f"--scheduler {args.scheduler}: cannot connect within "
                         f"{args.worker_timeout:g} s ({type(error).__name__}: "
                         f"{error}){hint}") from None


def start_client(args, say, scratch):
    """(client, cluster, engine description): a Client on --scheduler, or on a LocalCluster of
    --workers processes (default: one per core) with one thread each, listening on 127.0.0.1
    only (its dashboard too), their scratch files in the folder `scratch`."""
    from distributed import Client, LocalCluster

    if args.scheduler:
        client = _connect(args, say)
        cluster = None
    else:
        import dask

        _worker_environment()
        for name in ("distributed", "distributed.diskutils", "distributed.nanny"):
            logging.getLogger(name).setLevel(logging.WARNING)
        # How many worker deaths a task may see before Dask gives up on it (the scheduler's
        # setting; a running scheduler keeps its own).
        dask.config.set({"distributed.scheduler.allowed-failures": args.retries})
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               host=LOCAL_HOST, dashboard_address=LOCAL_DASHBOARD,
                               worker_dashboard_address=LOCAL_WORKER_HTTP,
                               silence_logs=logging.ERROR, local_directory=scratch)
        client = Client(cluster)
    workers = _check_workers(client, args.worker_timeout)
    where = args.scheduler or "a local cluster on 127.0.0.1"
    engine = f"Dask at {where}, {workers} worker(s)"
    link = _dashboard(client)
    say(f"sweep: {engine}; dashboard: " +
        (link if link else "none (the Dask dashboard needs bokeh on the scheduler)"))
    return client, cluster, engine
