"""Watching a sweep: Dask's dashboard served from the local cluster, and where it runs
(including a cluster named in DASK_SCHEDULER_ADDRESS, as any Dask client finds it)."""

import importlib.metadata
import json
import os
import re
import socket
import subprocess
import sys
import urllib.error
import urllib.request

import h5py
import numpy as np
import pytest
from sweeping import CMD, TINY, dask_process, dask_scheduler, stop_processes, unserved_port

from pydrill.dask_connect import served_dashboard
from pydrill.spec import parse_spec
from pydrill.sweep import ClusterInfo, run_sweep


def _get(url: str) -> tuple[int, str]:
    with urllib.request.urlopen(url, timeout=30) as page:
        return page.status, page.read().decode("utf-8", "replace")


def test_the_dashboard_is_served_while_the_sweep_runs(tmp_path):
    """The link handed to on_cluster answers with Dask's dashboard during the sweep, and the
    sweep's atlas is the serial one's."""
    seen: list[tuple[ClusterInfo, int, str]] = []

    def watch(info: ClusterInfo) -> None:
        seen.append((info, *_get(info.dashboard)))

    spec = parse_spec(TINY)
    report = run_sweep(spec, tmp_path / "watched.h5", dashboard="127.0.0.1:0", on_cluster=watch)
    assert report.computed == spec.size and report.failed == 0
    [(info, status, page)] = seen
    assert info.workers >= 1 and info.scheduler.startswith("tcp://127.0.0.1:")
    assert re.fullmatch(r"http://127\.0\.0\.1:\d+/status", info.dashboard)
    assert status == 200 and "Dask" in page
    # Gone with the sweep's cluster.
    with pytest.raises(OSError):
        _get(info.dashboard)
    run_sweep(spec, tmp_path / "serial.h5", serial=True)
    with h5py.File(tmp_path / "watched.h5") as a, h5py.File(tmp_path / "serial.h5") as b:
        np.testing.assert_array_equal(a["regime"][()], b["regime"][()])


def test_without_a_dashboard_there_is_no_link(tmp_path):
    seen: list[ClusterInfo] = []
    run_sweep(parse_spec(TINY), tmp_path / "plain.h5", workers=1, on_cluster=seen.append)
    assert [(i.workers, i.dashboard) for i in seen] == [(1, None)]


@pytest.mark.parametrize("address", ["8787", "host:port", ":70000", ""])
def test_a_bad_dashboard_address_is_refused_and_nothing_is_written(tmp_path, address):
    out = tmp_path / "never.h5"
    with pytest.raises(ValueError, match=r"dashboard = .* is not allowed: HOST:PORT"):
        run_sweep(parse_spec(TINY), out, dashboard=address)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("installed", "said"), [(None, "it is not installed"), ("2.4.3", "found 2.4.3")]
)
def test_no_bokeh_for_the_dashboard_is_one_clear_error(tmp_path, monkeypatch, installed, said):
    real = importlib.metadata.version

    def version(name: str) -> str:
        if name != "bokeh":
            return real(name)
        if installed is None:
            raise importlib.metadata.PackageNotFoundError(name)
        return installed

    monkeypatch.setattr(importlib.metadata, "version", version)
    with pytest.raises(ValueError, match=rf"bokeh >= 3.1 \({said}\): pip install 'pydrill\["):
        run_sweep(parse_spec(TINY), tmp_path / "never.h5", dashboard="127.0.0.1:0")
    assert list(tmp_path.iterdir()) == []


def test_dashboard_beside_a_scheduler_or_serial_is_refused(tmp_path):
    with pytest.raises(ValueError, match="an existing cluster serves its own"):
        run_sweep(
            parse_spec(TINY), tmp_path / "x.h5", scheduler="tcp://127.0.0.1:1", dashboard=":0"
        )
    with pytest.raises(ValueError, match="serial runs use no Dask"):
        run_sweep(parse_spec(TINY), tmp_path / "x.h5", serial=True, dashboard=":0")
    assert list(tmp_path.iterdir()) == []


def _sweep_cli(tmp_path, *extra, env=None) -> subprocess.CompletedProcess:
    spec = tmp_path / "tiny.toml"
    spec.write_text(TINY)
    return subprocess.run(
        [*CMD, "sweep", str(spec), "--out", str(tmp_path / "cli.h5"), *extra],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )


def test_cli_prints_the_link_and_says_when_the_port_was_taken(tmp_path):
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        taken = holder.getsockname()[1]
        run = _sweep_cli(tmp_path, "--dashboard-address", f"127.0.0.1:{taken}", "--workers", "1")
    assert run.returncode == 0, run.stderr
    line = re.search(r"sweep: 1 Dask worker, scheduler tcp://\S+, dashboard (\S+)(.*)", run.stderr)
    assert line, run.stderr
    link, note = line.groups()
    assert re.fullmatch(r"http://127\.0\.0\.1:\d+/status", link) and f":{taken}/" not in link
    assert note == f" (port {taken} is taken)"
    assert "Warning" not in run.stderr  # Dask's "Port ... is already in use" is not shown


@pytest.mark.parametrize(
    ("extra", "said"),
    [
        (["--dashboard", "--serial"], "a --serial sweep has no Dask to watch"),
        (["--dashboard", "--scheduler", "tcp://127.0.0.1:1"], "serves its own"),
        (["--dashboard-address", "8787"], "--dashboard-address = '8787' is not allowed"),
    ],
)
def test_cli_refuses_a_dashboard_it_cannot_serve(tmp_path, extra, said):
    run = _sweep_cli(tmp_path, *extra)
    assert run.returncode == 2 and said in run.stderr, run.stderr
    assert not (tmp_path / "cli.h5").exists()


def test_a_configured_scheduler_that_does_not_answer_is_named_and_nothing_is_written(tmp_path):
    """DASK_SCHEDULER_ADDRESS is where a Dask user's work goes, so the sweep goes there too;
    when nothing answers, the error names the variable (the user may have forgotten it) and
    how to run locally instead, which works with the variable still set."""
    # Held, not listening, for the whole test: a port released at once may be taken, even by
    # the local cluster of the --workers run below, which must not be the one named.
    with unserved_port() as port:
        nobody = f"tcp://127.0.0.1:{port}"
        env = {
            **os.environ,
            "DASK_SCHEDULER_ADDRESS": nobody,
            "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "2s",
        }
        run = _sweep_cli(tmp_path, env=env)
        assert run.returncode == 2 and "Traceback" not in run.stderr
        assert f"DASK_SCHEDULER_ADDRESS is {nobody}, but no Dask scheduler answered" in run.stderr
        assert "--workers N" in run.stderr
        assert list(tmp_path.iterdir()) == [tmp_path / "tiny.toml"]
        run = _sweep_cli(tmp_path, "--dashboard", env=env)
        assert (
            run.returncode == 2
            and "runs on the cluster of DASK_SCHEDULER_ADDRESS, which serves its own" in run.stderr
        )
        run = _sweep_cli(tmp_path, "--workers", "1", "--json", env=env)
        assert run.returncode == 0, run.stderr
        assert "sweep: 1 Dask worker, scheduler tcp://127.0.0.1:" in run.stderr
        assert "from DASK_SCHEDULER_ADDRESS" not in run.stderr
        cluster = json.loads(run.stdout)["cluster"]  # where it ran, for scripts
        assert cluster["workers"] == 1 and cluster["dashboard"] is None
        assert (
            cluster["scheduler"].startswith("tcp://127.0.0.1:") and cluster["scheduler"] != nobody
        )
        run = _sweep_cli(tmp_path, "--serial", "--json", "--resume", env=env)
        assert run.returncode == 0 and json.loads(run.stdout)["cluster"] is None


def test_a_scheduler_address_in_the_dask_config_is_named_as_such(tmp_path):
    import dask

    with (
        dask.config.set({"scheduler-address": "tcp://127.0.0.1:1"}),
        pytest.raises(
            ValueError, match=r"the cluster of Dask's config \(scheduler-address\), which"
        ),
    ):
        run_sweep(parse_spec(TINY), tmp_path / "never.h5", dashboard="127.0.0.1:0")
    assert list(tmp_path.iterdir()) == []


def test_the_callers_default_dask_client_runs_the_sweep_and_stays_open(tmp_path):
    """As dask.compute would: a sweep told nowhere runs on the caller's client, not on a
    second cluster beside it; told where, it goes there."""
    from distributed import Client, LocalCluster

    spec = parse_spec(TINY)
    seen: list[ClusterInfo] = []
    with (
        LocalCluster(n_workers=1, processes=False, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        report = run_sweep(spec, tmp_path / "default.h5", on_cluster=seen.append)
        assert report.computed == spec.size and client.status == "running"
        assert [i.scheduler for i in seen] == [cluster.scheduler_address]
        with pytest.raises(ValueError, match="the cluster of your default Dask client"):
            run_sweep(spec, tmp_path / "never.h5", dashboard="127.0.0.1:0")
        run_sweep(spec, tmp_path / "local.h5", workers=1, on_cluster=seen.append)
        assert seen[1].scheduler != cluster.scheduler_address
    run_sweep(spec, tmp_path / "after.h5", on_cluster=seen.append)  # its own cluster again
    assert seen[2].scheduler not in (seen[0].scheduler, seen[1].scheduler)
    assert not (tmp_path / "never.h5").exists()


def _head(url: str) -> int:
    try:
        with urllib.request.urlopen(urllib.request.Request(url, method="HEAD"), timeout=30) as r:
            return r.status
    except urllib.error.HTTPError as exc:
        return exc.code


def test_a_scheduler_without_a_dashboard_gets_no_dead_link(tmp_path):
    """``dask scheduler --no-dashboard`` still serves HTTP (health, metrics), and Dask's client
    names a dashboard link there that answers 404: the sweep printed it as the place to watch.
    Now it says no dashboard; one with a dashboard keeps its link, which answers."""
    from distributed import Client, LocalCluster

    file = tmp_path / "scheduler.json"
    scheduler, address = dask_scheduler(
        file, "--dashboard-address", "127.0.0.1:0", "--no-dashboard"
    )
    procs = [scheduler]
    try:
        procs.append(dask_process("worker", address, "--nthreads", "1", "--no-nanny"))
        with Client(address, timeout=60) as client:
            # The worker joined before the sweep looks (it said "0 Dask workers ... none yet"
            # once, in CI, when the worker was slower to start than the sweep).
            client.wait_for_workers(1, timeout=60)
            dead = client.dashboard_link
            assert dead and _head(dead) == 404  # what Dask offers for such a scheduler
        run = _sweep_cli(tmp_path, "--scheduler", address, "--json")
    finally:
        stop_processes(procs)
    assert run.returncode == 0, run.stderr
    assert re.search(rf"^sweep: 1 Dask worker, scheduler {address}$", run.stderr, re.M), run.stderr
    assert "dashboard" not in run.stderr
    assert json.loads(run.stdout)["cluster"]["dashboard"] is None

    seen: list[ClusterInfo] = []
    with LocalCluster(n_workers=1, processes=False, dashboard_address="127.0.0.1:0") as cluster:
        run_sweep(
            parse_spec(TINY),
            tmp_path / "watched.h5",
            scheduler=cluster.scheduler_address,
            on_cluster=seen.append,
        )
        [info] = seen
        assert info.dashboard and _head(info.dashboard) == 405  # served: bokeh takes GET only
        assert _get(info.dashboard)[0] == 200


def test_a_dashboard_link_that_does_not_answer_is_kept():
    """Only a scheduler that says it serves no dashboard takes the link away: one that does not
    answer from here (another network's view of the host) may answer in the user's browser."""
    with unserved_port() as closed:
        assert served_dashboard(f"http://127.0.0.1:{closed}/status", within=2) is not None
    assert served_dashboard(None) is None


def test_the_dashboard_is_asked_of_the_scheduler_not_of_an_http_proxy():
    """With http_proxy set (here to a port where nothing answers), the scheduler itself is
    asked: its 404 takes the link away. In a process of its own, as urllib reads the proxy
    settings once."""
    code = (
        "from distributed import LocalCluster\n"
        "from pydrill.dask_connect import served_dashboard\n"
        "kw = dict(n_workers=0, processes=False, dashboard_address='127.0.0.1:0')\n"
        "with LocalCluster(**kw, scheduler_kwargs={'dashboard': False}) as c:\n"
        "    port = c.scheduler.http_server.port\n"
        "    print(served_dashboard(f'http://127.0.0.1:{port}/status'))\n"
    )
    env = {k: v for k, v in os.environ.items() if k.lower() not in ("no_proxy", "http_proxy")}
    with unserved_port() as port:
        env["http_proxy"] = f"http://127.0.0.1:{port}"
        run = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env
        )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "None", run.stdout + run.stderr
