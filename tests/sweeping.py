"""What the sweep tests share: small specs, atlas comparison, waiting for a running sweep.

Not a test module: imported by them (``pythonpath = ["tests"]`` in pyproject.toml)."""

import contextlib
import json
import math
import os
import random
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CMD = [sys.executable, "-m", "pydrill"]

SMALL = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 100.0, 160.0]
torque = [6.0, 8.3]
[simulation]
t_end = 200.0
initial = ["rest", "equilibrium"]
"""

# The same grid, shorter and from rest only.
TINY = SMALL.replace("t_end = 200.0", "t_end = 100.0").replace(
    'initial = ["rest", "equilibrium"]', 'initial = ["rest"]'
)


MEDIUM = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 16 }
torque = { start = 4.0, stop = 14.0, num = 12 }
[simulation]
t_end = 300.0
initial = ["rest"]
"""


# Slow enough per point (5-6 ms) that a sweep is still running when the test interrupts it.
LONGER = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 32 }
torque = { start = 4.0, stop = 14.0, num = 16 }
[simulation]
t_end = 3000.0
initial = ["rest", "equilibrium"]
"""


def atlas_arrays(path):
    with h5py.File(path, "r") as f:
        return {
            name: f[name][...]
            for name in f
            if isinstance(f[name], h5py.Dataset) and name != "wall_time"
        }


def same_atlas(a, b):
    x, y = atlas_arrays(a), atlas_arrays(b)
    assert x.keys() == y.keys()
    for name in x:
        if x[name].dtype.kind == "f":
            np.testing.assert_array_equal(
                np.nan_to_num(x[name], nan=-7.0), np.nan_to_num(y[name], nan=-7.0), err_msg=name
            )
        else:
            np.testing.assert_array_equal(x[name], y[name], err_msg=name)


def wait_for_journal(journal: Path, more_than: int, proc: subprocess.Popen) -> None:
    """Until ``journal`` holds more than ``more_than`` lines, while the sweep ``proc`` runs."""
    deadline = time.time() + 120
    while not (journal.exists() and journal.read_text().count("\n") > more_than):
        assert proc.poll() is None, "the sweep ended before the test could interrupt it"
        assert time.time() < deadline, "the sweep journaled nothing in 120 s"
        time.sleep(0.02)


def free_port() -> int:
    """A loopback port nothing is bound to now, for a server a test must name before it
    starts (a sweep told to wait for a scheduler not started yet). Outside the kernel's
    ephemeral range (/proc/sys/net/ipv4/ip_local_port_range): a port from bind(0), released
    at once, can be handed to any process's next bind(0) (each Dask scheduler, worker, nanny
    and dashboard the other pytest worker starts makes one; measured: one such port in about
    10000 binds) or outgoing connection before the server binds it, and the server then fails
    to start. Below the range, only a bind of that very number can take it. A server that can
    choose its own port should (``dask_scheduler``)."""
    try:
        low = int(Path("/proc/sys/net/ipv4/ip_local_port_range").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        low = 0
    pick = random.Random()  # seeded from the OS: pytest workers pick apart
    for _ in range(200):
        port = pick.randrange(20000, low) if low > 21000 else 0
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return s.getsockname()[1]
    raise AssertionError("no free loopback port below the ephemeral range in 200 tries")


@contextlib.contextmanager
def unserved_port():
    """A loopback port where nothing listens, for as long as the block runs: bound and never
    listening, it refuses every connection, and no other process can take it meanwhile (a port
    from free_port(), released at once, was once taken by a second test run's connection)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        yield s.getsockname()[1]


def dask_process(*args: str, log: Path | None = None) -> subprocess.Popen:
    """A real ``dask scheduler ...`` or ``dask worker ...`` process, in a session of its own
    (stop it with ``stop_processes``), this interpreter's pydrill on its path."""
    dask_bin = Path(sys.executable).parent / "dask"
    return subprocess.Popen(
        [str(dask_bin) if dask_bin.exists() else "dask", *args],
        stdout=subprocess.DEVNULL,
        stderr=log.open("w") if log else subprocess.DEVNULL,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        start_new_session=True,
    )


def dask_scheduler(file: Path, *args: str) -> tuple[subprocess.Popen, str]:
    """A real ``dask scheduler ARGS`` on a loopback port it chooses itself, and its address
    once it listens (it writes its scheduler ``file`` then). A port chosen for it beforehand
    (``free_port``) may be taken by another process before it binds; this one cannot."""
    proc = dask_process(
        "scheduler", "--host", "127.0.0.1", "--port", "0", "--scheduler-file", str(file), *args
    )
    deadline = time.monotonic() + 120  # a few seconds alone; minutes on a loaded machine
    while True:
        try:
            return proc, json.loads(file.read_text())["address"]
        except (OSError, ValueError, KeyError):  # not there yet, or not written whole
            pass
        if proc.poll() is not None or time.monotonic() > deadline:
            stop_processes([proc])
            raise AssertionError(f"the Dask scheduler did not start (exit {proc.returncode})")
        time.sleep(0.02)


def wait_for_workers(address: str, n: int) -> None:
    """Until ``n`` workers have joined the scheduler at ``address``: a ``dask worker`` process
    registers seconds after it starts, more on a loaded machine, and a sweep started at
    once would count fewer (CI once saw 0 where the test expected 1)."""
    from distributed import Client

    with Client(address, timeout="120s") as client:
        client.wait_for_workers(n, timeout=120)


def stop_processes(procs: list[subprocess.Popen]) -> None:
    for p in procs:
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        p.wait()


def interrupt_mid_sweep(tmp_path, sig, *extra):
    """Start ``pydrill sweep`` on LONGER, send ``sig`` to its whole process group (what Ctrl-C
    in a terminal does) once its first batch is journaled; return (rc, stdout, stderr, atlas)."""
    spec_file = tmp_path / "longer.toml"
    spec_file.write_text(LONGER)
    out = tmp_path / "stopped.h5"
    journal = Path(str(out) + ".journal")
    proc = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # A shell's background job ignores SIGINT; a terminal's foreground one does not.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    wait_for_journal(journal, 1, proc)
    os.killpg(proc.pid, sig)
    stdout, err = proc.communicate(timeout=60)
    return proc.returncode, stdout, err, out


def toml_value(v) -> str:
    if isinstance(v, float) and not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, dict):  # an inline table
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return json.dumps(v, ensure_ascii=False)  # JSON strings, numbers and bools are TOML


def toml(doc: dict) -> str:
    """``doc`` as TOML, any value the tests make (NaN, inf, unicode keys) included: top-level
    values first, then tables and arrays of tables."""
    head, body = [], []
    for key, value in doc.items():
        if isinstance(value, dict):
            body += [f"[{key}]", *(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items())]
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for item in value:
                body += [f"[[{key}]]"]
                body += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in item.items()]
        else:
            head.append(f"{key} = {toml_value(value)}")
    return "\n".join(head + body) + "\n"


# The paper's design (examples/tallies/paper-eq53.toml), as the tables a tally holds.
TALLY_TABLES = {
    "name": "t",
    "top_drive": {"inertia": 2122.0, "damping": 425.0},
    "bit": {"diameter": "12.25 in", "damping": 50.0, "mu_coulomb": 0.5, "mu_static": 0.8},
    "damping": {"model": "stiffness-proportional", "beta": 0.2},
    "steel": {"shear_modulus": "79.3 GPa", "density": "7850 kg/m3"},
    "section": [
        {"kind": "drill-pipe", "count": 100, "length": "9 m", "od": "5 in", "id": "4.408 in"},
        {"kind": "drill-collar", "count": 2, "length": "18.6 m", "od": "6.5 in", "id": "2.8 in"},
    ],
}
