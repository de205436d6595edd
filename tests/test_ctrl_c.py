"""Ctrl-C stops a long simulation at once, not when the C++ core returns.

The core runs without the GIL; it asks Python's signal handlers every 0.1 s (and only from
the main thread), and re-raises what they raise."""

import signal
import subprocess
import sys
import textwrap
import threading
import time

import pydrill

LONG = textwrap.dedent(
    """
    import sys, time, pydrill
    print("start", flush=True)
    t0 = time.perf_counter()
    try:  # 300 pipes for 2e5 s: some 6 s here
        pydrill.simulate(wob=100, torque=8.3, dof=303, t_end=2e5, n_out=11)
        print("finished", time.perf_counter() - t0, flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.perf_counter() - t0, flush=True)
    """
)


def test_ctrl_c_interrupts_a_long_simulation_within_a_fraction_of_a_second():
    proc = subprocess.Popen([sys.executable, "-c", LONG], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "start"
        time.sleep(1.0)  # well inside the run
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        word, ran = proc.stdout.readline().split()
        latency = time.perf_counter() - sent
    finally:
        proc.kill()
        proc.wait()
        proc.stdout.close()
    assert word == "interrupted", f"the run {word} after {ran} s"
    assert latency < 1.0  # polled every 0.1 s; the uninterrupted run takes several seconds


def test_a_simulation_in_another_thread_is_not_stopped_by_the_poll():
    # Signal handlers run in the main thread only: a worker thread's run is left alone,
    # and gives what the main thread gives.
    out = {}

    def run():
        out["r"] = pydrill.simulate(wob=100, torque=8.3, dof=303, t_end=3000, n_out=11)

    worker = threading.Thread(target=run)
    worker.start()
    worker.join()
    main = pydrill.simulate(wob=100, torque=8.3, dof=303, t_end=3000, n_out=11)
    assert out["r"].regime == main.regime
    assert out["r"].stats.steps == main.stats.steps
