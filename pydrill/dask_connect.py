"""Finding the Dask cluster a sweep runs on: a scheduler's address (from the caller, a
scheduler file or Dask's config), whether it answers, its workers, the caller's own client,
and a dashboard that can be served. ``sweep_dask`` runs the points there.
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import os
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import dask


class ConfiguredAddress(str):
    """A scheduler address from the Dask config rather than from the caller: messages name
    where it came from (``source``), as the user may not remember setting it."""

    source = "Dask's config (scheduler-address)"


def configured_scheduler() -> ConfiguredAddress | None:
    """The cluster a Dask user has named for all their work, as ``distributed.Client()`` finds
    it: the config's ``scheduler-address``, from ``DASK_SCHEDULER_ADDRESS`` or a YAML file."""
    address = dask.config.get("scheduler-address", None)
    if not address:
        return None
    found = ConfiguredAddress(address)
    if os.environ.get("DASK_SCHEDULER_ADDRESS") == address:
        found.source = "DASK_SCHEDULER_ADDRESS"
    return found


def connect_timeout() -> float:
    """How long (s) a Dask client keeps trying to reach its scheduler:
    ``distributed.comm.timeouts.connect`` (30 s unless configured)."""
    import distributed  # noqa: F401 - its config defaults, which name the timeout
    from dask.utils import parse_timedelta

    return float(parse_timedelta(dask.config.get("distributed.comm.timeouts.connect"), "s"))


def scheduler_file(scheduler: Any) -> Path | None:
    """``scheduler`` (an address or a path) as a scheduler file: a name ending in ``.json``
    (waited for if not there yet), or any file that exists. Batch systems name it as they
    like (``--scheduler-file $HOME/scheduler``); taken for an address, such a file was
    refused as "missing port number in address"."""
    text = str(scheduler)
    if text.endswith(".json"):
        return Path(text)
    if "://" not in text and Path(text).is_file():
        return Path(text)
    return None


def scheduler_file_address(file: Path, wait: float) -> str:
    """The scheduler's address in ``file`` (``dask scheduler --scheduler-file FILE.json``),
    waiting up to ``wait`` s for the file to appear: a job script may start the scheduler and
    the sweep together. Dask's own client would wait for ever, and take a file without an
    address for one not written yet. Raises ``SchedulerError`` naming the file."""
    import json

    from .sweep import SchedulerError

    how = "it is written by 'dask scheduler --scheduler-file FILE.json'"
    deadline = time.monotonic() + wait
    while not file.is_file():
        if file.exists() or time.monotonic() > deadline:
            raise SchedulerError(
                f"--scheduler {file}: no such scheduler file"
                + ("" if file.exists() else f" after waiting {wait:g} s")
                + f" ({how}; distributed.comm.timeouts.connect sets the wait)"
            )
        time.sleep(0.1)
    for _ in range(20):  # it may be there but not written whole yet
        try:
            address = json.loads(file.read_text())["address"]
            if isinstance(address, str) and address:
                return address
        except (OSError, ValueError, KeyError, TypeError):
            pass
        time.sleep(0.05)
    raise SchedulerError(
        f'--scheduler {file}: not a Dask scheduler file (no scheduler "address" in it; {how})'
    )


def unanswered(address: str, within: float = 0.5) -> float | None:
    """When nothing answers at the scheduler address ``address`` right now (refused,
    unreachable, or silent ``within`` seconds): how long Dask's client will keep trying
    (``distributed.comm.timeouts.connect``, s), in case a scheduler is starting. None when
    one answers, or for an address this cannot probe (not TCP, a scheduler file)."""
    import socket

    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, where = parse_address(str(address))
        if scheme not in ("tcp", "tls"):
            return None
        host, port = parse_host_port(where)
    except ValueError:
        return None
    try:
        with socket.create_connection((host, port), timeout=within):
            return None
    except OSError:
        return connect_timeout()


def connect(scheduler: Any) -> Any:
    """A ``distributed.Client`` of ``scheduler`` (an address or a cluster), never the caller's
    default: Dask makes a Client the default before it connects, and one that failed to stayed
    so, half made, with dask's scheduler set to it (the caller's next dask.compute went there).
    One that fails to connect leaves nothing running: Dask's own left its event loop's thread
    ("IO loop") and three descriptors in the caller's process, more at each refused sweep."""
    from distributed import Client

    class SweepClient(Client):
        def start(self, **kwargs: Any) -> None:
            try:
                super().start(**kwargs)
            except BaseException:
                # A refused address leaves it "connecting": closed while its loop runs (at
                # exit, Dask's finalizer waited 2 s on it and printed a TimeoutError). A timeout
                # leaves it closed but its loop running: close() stops the loop only when it
                # closes. (Dask adds a client to Client._instances only once it has started.)
                with contextlib.suppress(Exception):
                    self.close()
                runner = getattr(self, "_loop_runner", None)
                if runner is not None:
                    runner.stop()
                raise

    return SweepClient(scheduler, set_as_default=False)


@contextlib.contextmanager
def kept_environ() -> Iterator[None]:
    """The caller's environment variables, as they were, after the block. A local cluster's
    nanny sets in the process that starts it what its workers must have from birth
    (``distributed.nanny.pre-spawn-environ``: OMP_NUM_THREADS, MKL_NUM_THREADS and
    OPENBLAS_NUM_THREADS = 1, MALLOC_TRIM_THRESHOLD_; and PYTHONHASHSEED, __DASK_PARENT_PID),
    and leaves them: after a sweep, every program the caller started ran its BLAS on one
    thread, with a fixed hash seed."""
    before = dict(os.environ)
    try:
        yield
    finally:
        for name in set(os.environ) - set(before):
            os.environ.pop(name, None)
        for name, value in before.items():
            if os.environ.get(name) != value:
                os.environ[name] = value


def worker_count(client: Any) -> int:
    """Workers connected to the cluster of ``client``. Not ``len(scheduler_info()["workers"])``:
    distributed 2025.4 ... 2026.6 lists at most 5 workers there by default (dask/distributed
    #9065), which would size a hundred workers' batches for five. The count is in
    ``n_workers`` where that cap exists; before it, the list is whole."""
    info = client.scheduler_info()
    n = info.get("n_workers")
    return n if isinstance(n, int) and n >= 0 else len(info.get("workers", {}))


def default_dask_client() -> Any:
    """The caller's default ``distributed.Client`` (the last one made, unless told
    otherwise), which ``dask.compute`` would use; None without one. Without distributed
    imported there can be none, and this does not import it."""
    if "distributed" not in sys.modules:
        return None
    from distributed import default_client

    try:
        return default_client()
    except ValueError:
        return None


def check_dashboard(address: str, name: str = "dashboard") -> None:
    """Refuse, before anything runs, a dashboard address that is not ``HOST:PORT`` (or
    ``:PORT``), or a dashboard that cannot be served: Dask needs bokeh for it, and without
    bokeh would only log a warning and serve nothing."""
    _host, sep, port = str(address).rpartition(":")
    if not sep or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise ValueError(
            f"{name} = {address!r} is not allowed: HOST:PORT or :PORT, the port 0 ... 65535 "
            "(0: any free port), e.g. 127.0.0.1:8787"
        )
    try:
        version = importlib.metadata.version("bokeh")
    except importlib.metadata.PackageNotFoundError:
        version = None
    from packaging.version import Version  # a dependency of dask's

    if version is None or Version(version) < Version("3.1"):
        found = "it is not installed" if version is None else f"found {version}"
        raise ValueError(
            f"{name}: Dask's dashboard needs bokeh >= 3.1 ({found}): "
            "pip install 'pydrill[dashboard]'"
        )


def served_dashboard(link: str | None, within: float = 1.0) -> str | None:
    """``link`` (a client's ``dashboard_link``), or None when the scheduler there answers that it
    serves no dashboard. Dask names a link for every scheduler with an HTTP server, which one
    started with ``dask scheduler --no-dashboard`` still runs (health, metrics): its ``/status``
    is then "404 Not Found", and the sweep printed that dead link as the place to watch it.
    Asked with HEAD: a GET of a real dashboard opens a bokeh session (0.45 s of the scheduler's
    time, measured), a HEAD answers "405 Method Not Allowed" in milliseconds. A link that does
    not answer (another network's view of the host, a firewall) is kept: only a scheduler that
    says so takes it away. Asked directly, not through an HTTP proxy of the environment
    (``http_proxy``), whose own 404 for a host it cannot see would say nothing of the
    scheduler."""
    import urllib.error
    import urllib.request

    if not link:
        return None
    direct = urllib.request.build_opener(urllib.request.ProxyHandler({}))
    try:
        with direct.open(urllib.request.Request(link, method="HEAD"), timeout=within):
            return link
    except urllib.error.HTTPError as exc:
        return None if exc.code == 404 else link
    except (OSError, ValueError):
        return link
