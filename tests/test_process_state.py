"""What pydrill leaves behind in the caller's process (a notebook, a script calling it in a
loop): its environment, child processes, event-loop threads and pyplot figures as they were,
whether the call succeeded or failed."""

import errno
import gc
import multiprocessing
import os
import threading

import dask
import distributed  # noqa: F401 - its config defaults (the nanny's variables)
import pytest
from sweeping import TINY, unserved_port

from pydrill.spec import parse_spec
from pydrill.sweep import SchedulerError, SweepInterrupted, run_sweep


def test_a_local_sweep_leaves_the_callers_environment_as_it_was(tmp_path, monkeypatch):
    """Dask's nanny sets its workers' variables in the process that starts the cluster and
    left them there: after a sweep, every program the caller started got OMP_NUM_THREADS=1
    (one BLAS thread) and PYTHONHASHSEED=6640."""
    set_by_nanny = [*dask.config.get("distributed.nanny.pre-spawn-environ"), "PYTHONHASHSEED"]
    for name in set_by_nanny:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("PYDRILL_TEST_KEPT", "mine")  # the caller's own: untouched
    before = dict(os.environ)
    report = run_sweep(parse_spec(TINY), tmp_path / "a.h5", workers=1)
    assert report.computed == 6
    assert dict(os.environ) == before


def test_ctrl_c_while_connecting_to_the_local_cluster_leaves_no_worker_running(
    tmp_path, monkeypatch
):
    """Ctrl-C is held while the cluster starts, not while the sweep's client then connects to
    it: one there left the cluster up, its worker processes running in the caller's session."""
    from distributed import Client

    def interrupted(self, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(Client, "start", interrupted)
    with pytest.raises(SweepInterrupted):
        run_sweep(parse_spec(TINY), tmp_path / "a.h5", workers=1)
    assert multiprocessing.active_children() == []


def test_a_refused_scheduler_leaves_no_event_loop_running(tmp_path):
    """Each sweep refused for want of a scheduler left Dask's client's event loop running in
    a thread of its own, with three file descriptors: one more at each retry in a session."""

    def loops():
        return sum(t.name == "IO loop" for t in threading.enumerate())

    gc.collect()  # earlier tests' sockets closed now, not while this one counts
    before, fds = loops(), len(os.listdir("/proc/self/fd"))
    spec = parse_spec(TINY)
    with unserved_port() as port, dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        for _ in range(2):
            with pytest.raises(SchedulerError, match="no Dask scheduler answered"):
                run_sweep(spec, tmp_path / "never.h5", scheduler=f"tcp://127.0.0.1:{port}")
    assert loops() == before
    assert len(os.listdir("/proc/self/fd")) <= fds  # 3 more at each refusal when leaked


def test_a_figure_that_could_not_be_saved_is_closed(tmp_path, monkeypatch, capsys):
    """pyplot keeps each figure until it is closed: `pydrill simulate --plot` run in-process
    on a full disk left its figure open (drawn again at the end of a notebook cell)."""
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure

    from pydrill import cli

    def full_disk(self, path, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.setattr(Figure, "savefig", full_disk)
    plt.close("all")
    png = tmp_path / "x.png"
    args = ["simulate", "--wob", "100", "--torque", "8.3", "--t-end", "5", "--plot", str(png)]
    assert cli.main(args) == 2
    assert f"--plot {png}: No space left on device" in capsys.readouterr().err
    assert plt.get_fignums() == []
