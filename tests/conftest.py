import os
import signal
import sys

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# A tester's own cluster (sweeps go where DASK_SCHEDULER_ADDRESS points, as any Dask client's
# work does) is not the one these tests start; the tests that want it set it themselves.
os.environ.pop("DASK_SCHEDULER_ADDRESS", None)
# Started in the background by a shell without job control (`bash tools/test.sh &` in a script,
# nohup), the suite inherits SIGINT ignored, and so would every process it starts: the tests
# that press Ctrl-C on a run in a subprocess then saw it run to the end. A terminal's Ctrl-C is
# what they test, so the suite takes SIGINT as Python does by default, and its children start
# with it at the default (a handler is reset by exec, an ignored signal is not).
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
# netCDF4 sets HDF5_PLUGIN_PATH to its bundled plugins the first time it is imported (once
# per process, never undone): a test reading a file with xarray's default engine imported it
# and failed the environment check below for a library's doing, not pydrill's. Imported here,
# before any test, it has set it once for the whole run.
try:
    import netCDF4  # noqa: F401
except ImportError:  # not installed: then nothing sets the variable
    pass


@pytest.fixture(autouse=True)
def _close_figures():
    """Each test's figures are closed after it: pyplot keeps them, and past 20 open it warns,
    which these settings make an error in whichever test happens to open the 21st."""
    yield
    plt = sys.modules.get("matplotlib.pyplot")  # not imported by a test that drew nothing
    if plt is not None:
        plt.close("all")


@pytest.fixture(autouse=True)
def _leaves_the_process_as_it_was():
    """A test that leaves an environment variable changed or a default Dask client behind
    fails itself, not whichever test pytest-xdist happens to run next in its process (8
    dashboard tests failed so, after a sweep's half-made Client had stayed the default; the
    nanny's OMP_NUM_THREADS=1 reached later subprocesses). pydrill leaves neither in a
    caller's process (tests/test_process_state.py); a test changes them with monkeypatch."""
    environ = dict(os.environ)
    yield
    names = {*environ, *os.environ} - {"PYTEST_CURRENT_TEST"}  # pytest's, set at each phase
    changed = sorted(k for k in names if environ.get(k) != os.environ.get(k))
    for k in changed:  # the next test starts clean either way
        if k in environ:
            os.environ[k] = environ[k]
        else:
            del os.environ[k]
    assert not changed, f"the test left environment variables changed: {changed}"
    client = sys.modules.get("distributed.client")
    if client is not None:
        leftover = client._get_global_client()
        assert leftover is None, f"the test left a default Dask client: {leftover!r}"


@pytest.fixture(scope="session")
def paper_dof4():
    """The paper's three dof-4 cases at u = 8.3 N·m from rest (Figs. 4, 7, 9)."""
    import pydrill

    return {
        wob: pydrill.simulate(wob=wob, torque=8.3, dof=4, t_end=300.0)
        for wob in (40.0, 100.0, 160.0)
    }


@pytest.fixture(scope="session")
def reproduce_quick(tmp_path_factory):
    """One real ``pydrill reproduce --quick --json`` run (a subprocess of the CLI), shared by
    the tests that read what it writes (tests/test_reproduce.py, test_reproduce_figures.py):
    (its output directory, its JSON summary). Read only: a test that runs in it again copies
    it first."""
    import json
    import subprocess

    out = tmp_path_factory.mktemp("reproduce")
    cmd = [sys.executable, "-m", "pydrill", "reproduce", "--out", str(out), "--quick", "--json"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    return out, json.loads(proc.stdout)


@pytest.fixture(scope="session")
def longer_reference(tmp_path_factory):
    """tests/sweeping.py's LONGER swept serially, uninterrupted: the atlas an interrupted or
    disconnected sweep of LONGER, resumed, must equal (tests/test_sweep_interrupt.py,
    test_sweep_connect.py). Read only."""
    from sweeping import LONGER

    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    out = tmp_path_factory.mktemp("longer") / "uninterrupted.h5"
    run_sweep(parse_spec(LONGER), out, serial=True)
    return out
