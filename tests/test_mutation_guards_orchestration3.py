"""Mutation guards of finding a Dask cluster (dask_connect.py) and of stopping between
batches (interrupt.py), called directly: a real socket or HTTP server where an answer is
needed, real signals sent to this process (SIGUSR1, which nothing else here uses) or to a
child forked from it."""

import http.server
import os
import signal
import socket
import threading
import time
import types

import dask
import distributed  # its config defaults, loaded before any dask.config.set here
import pytest
from sweeping import unserved_port

import pydrill.sweep_dask as sweep_dask
from pydrill import dask_connect
from pydrill.interrupt import stop_between_batches
from pydrill.sweep import SchedulerError


def test_the_config_s_scheduler_is_named_by_where_it_came_from(monkeypatch):
    monkeypatch.delenv("DASK_SCHEDULER_ADDRESS", raising=False)
    with dask.config.set({"scheduler-address": "tcp://10.0.0.1:8786"}):
        assert dask_connect.configured_scheduler().source == "Dask's config (scheduler-address)"
        monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", "tcp://10.0.0.1:8786")
        assert dask_connect.configured_scheduler().source == "DASK_SCHEDULER_ADDRESS"
    with dask.config.set({"scheduler-address": None}):
        assert dask_connect.configured_scheduler() is None


def test_a_scheduler_file_that_is_a_folder_is_refused_at_once(tmp_path):
    folder = tmp_path / "sched.json"
    folder.mkdir()
    t0 = time.monotonic()
    with pytest.raises(SchedulerError) as info:
        dask_connect.scheduler_file_address(folder, 5.0)
    assert time.monotonic() - t0 < 2.0  # no wait: it exists, and is no file
    assert "no such scheduler file (" in str(info.value) and "after waiting" not in str(info.value)


def test_a_scheduler_file_with_an_empty_address_is_no_scheduler_file(tmp_path):
    file = tmp_path / "s.json"
    file.write_text('{"address": ""}')
    with pytest.raises(SchedulerError, match="not a Dask scheduler file"):
        dask_connect.scheduler_file_address(file, 0.0)


def test_unanswered_probes_tcp_and_tls_and_says_how_long_dask_will_try():
    with dask.config.set({"distributed.comm.timeouts.connect": "7s"}):
        with unserved_port() as port:
            assert dask_connect.unanswered(f"tcp://127.0.0.1:{port}") == 7.0
            assert dask_connect.unanswered(f"tls://127.0.0.1:{port}") == 7.0
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            s.listen()
            assert dask_connect.unanswered(f"tcp://127.0.0.1:{s.getsockname()[1]}") is None
        assert dask_connect.unanswered("inproc://x/1/2") is None


def test_workers_are_counted_from_n_workers_where_the_list_is_capped():
    def client(info):
        return types.SimpleNamespace(scheduler_info=lambda: info)

    five = {f"tcp://w{i}": {} for i in range(5)}
    assert dask_connect.worker_count(client({"n_workers": 12, "workers": five})) == 12
    assert dask_connect.worker_count(client({"workers": five})) == 5  # older: the list is whole


def test_a_dashboard_port_is_0_to_65535(monkeypatch):
    monkeypatch.setattr(dask_connect.importlib.metadata, "version", lambda name: "3.1.0")
    dask_connect.check_dashboard(":65535")
    with pytest.raises(ValueError, match=r"0 \.\.\. 65535"):
        dask_connect.check_dashboard(":65536")
    monkeypatch.setattr(dask_connect.importlib.metadata, "version", lambda name: "3.0.2")
    with pytest.raises(ValueError, match=r"bokeh >= 3.1 \(found 3.0.2\)"):
        dask_connect.check_dashboard(":8787")


@pytest.mark.parametrize(("code", "kept"), [(404, False), (405, True), (500, True)])
def test_only_a_scheduler_s_404_takes_the_dashboard_link_away(code, kept):
    class Answer(http.server.BaseHTTPRequestHandler):
        def do_HEAD(self):
            self.send_response(code)
            self.end_headers()

        def log_message(self, *args):
            pass

    server = http.server.HTTPServer(("127.0.0.1", 0), Answer)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        link = f"http://127.0.0.1:{server.server_address[1]}/status"
        assert dask_connect.served_dashboard(link) == (link if kept else None)
    finally:
        server.shutdown()
        server.server_close()
    with unserved_port() as port:  # no answer: kept
        assert dask_connect.served_dashboard(f"http://127.0.0.1:{port}/status") is not None


def test_without_a_default_client_there_is_none(monkeypatch):
    def none():
        raise ValueError("No clients found")

    monkeypatch.setattr(distributed, "default_client", none)
    assert dask_connect.default_dask_client() is None


@pytest.mark.parametrize("error", [OSError("refused"), ValueError("bad address")])
def test_a_scheduler_that_does_not_answer_is_one_error_naming_where_it_was_given(
    tmp_path, monkeypatch, error
):
    asked = []

    def client(address):
        asked.append(address)
        raise error

    monkeypatch.setattr(sweep_dask, "connect", client)
    file = tmp_path / "s.json"
    file.write_text('{"address": "tcp://10.0.0.2:8786"}')
    with pytest.raises(SchedulerError, match=f"--scheduler {file} \\(address tcp://10.0.0.2"):
        sweep_dask._run_dask(None, None, None, str(file), None)
    assert asked == ["tcp://10.0.0.2:8786"]  # the address in the file, not the file
    configured = dask_connect.ConfiguredAddress("tcp://10.0.0.3:8786")
    configured.source = "DASK_SCHEDULER_ADDRESS"
    with pytest.raises(SchedulerError, match=r"^DASK_SCHEDULER_ADDRESS is tcp://10\.0\.0\.3"):
        sweep_dask._run_dask(None, None, None, configured, None)


def test_a_worker_count_that_changes_is_told_once_per_change(monkeypatch):
    monkeypatch.setattr(sweep_dask, "WATCH_SECONDS", 0.01)
    counts = iter([2, 3, 3, 3, 0, 0])
    told, done = [], threading.Event()

    def count(client):
        n = next(counts, None)
        if n is None:
            done.set()
            return 0
        return n

    monkeypatch.setattr(sweep_dask, "worker_count", count)
    info = types.SimpleNamespace(workers=2)
    monkeypatch.setattr("dataclasses.replace", lambda i, workers: workers)
    watch = sweep_dask.WorkerWatch(None, info, told.append)
    assert done.wait(5)
    watch.stop()
    assert told == [3, 0] and not watch.is_alive()


def test_a_signal_while_held_waits_for_the_block_then_stops_once():
    previous = signal.getsignal(signal.SIGUSR1)
    ran = []
    with stop_between_batches((signal.SIGUSR1,)) as stop:
        with pytest.raises(KeyboardInterrupt):
            with stop.hold():
                os.kill(os.getpid(), signal.SIGUSR1)
                ran.append("the rest of the block")
        assert ran and stop.signum == signal.SIGUSR1
        with stop.hold():  # acted on once: the next block runs without a stop
            pass
        with pytest.raises(KeyboardInterrupt):  # outside a block: at once
            os.kill(os.getpid(), signal.SIGUSR1)
            time.sleep(1)
            pytest.fail("not stopped")
    assert signal.getsignal(signal.SIGUSR1) is previous  # the handler is put back


def test_a_signal_the_process_ignores_stays_ignored():
    # (a shell's background job ignores SIGINT: Ctrl-C in another window must not stop it)
    old = signal.signal(signal.SIGUSR1, signal.SIG_IGN)
    try:
        with stop_between_batches((signal.SIGUSR1,)) as stop:
            os.kill(os.getpid(), signal.SIGUSR1)
            time.sleep(0.05)
        assert stop.signum == 0
    finally:
        signal.signal(signal.SIGUSR1, old)


def test_a_forked_worker_ignores_sigint_and_dies_of_other_signals():
    with stop_between_batches((signal.SIGINT, signal.SIGUSR1)):
        statuses = []
        for sig in (signal.SIGINT, signal.SIGUSR1):
            pid = os.fork()
            if pid == 0:  # the worker: survives SIGINT (exit 0), dies of SIGUSR1
                try:
                    os.kill(os.getpid(), sig)
                    time.sleep(0.05)
                finally:
                    os._exit(0)
            statuses.append(os.waitpid(pid, 0)[1])
    assert os.waitstatus_to_exitcode(statuses[0]) == 0
    assert os.waitstatus_to_exitcode(statuses[1]) == -signal.SIGUSR1


def test_outside_the_main_thread_it_only_holds():
    found = []

    def run():
        with stop_between_batches((signal.SIGUSR1,)) as stop, stop.hold():
            found.append(stop.signum)

    t = threading.Thread(target=run)
    t.start()
    t.join()
    assert found == [0]


def test_only_children_forked_inside_the_guard_get_fresh_streams():
    """As fork_stdio says: inside ``forking_workers`` a child's sys.stderr and sys.__stderr__
    are new streams (one object, as they were one before); after the block, a child keeps
    the parent's. The child reports over a pipe, by exit status bits."""
    import sys

    from pydrill.fork_stdio import forking_workers

    def child_status(guarded):
        with forking_workers() if guarded else open(os.devnull):
            before = (sys.stderr, sys.__stderr__, sys.stdout)
            pid = os.fork()
            if pid == 0:
                bits = (sys.stderr is before[0]) | (sys.__stderr__ is before[1]) << 1
                bits |= (sys.stdout is before[2]) << 2
                os._exit(bits | (sys.stderr is sys.__stderr__) << 3)
        return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])

    same = sys.stderr is sys.__stderr__  # under pytest's capture they differ
    assert child_status(True) == (8 if same else 0)
    assert child_status(False) == (7 | (8 if same else 0))
