"""Ctrl-C stops a long stability analysis at once, not when the C++ core returns.

The analyses are O(dof²): critical_deltas takes some 8 s at 6000 pipes, the roots of
Z_b(λ) = δ as long. As in simulate (tests/test_ctrl_c.py), the core runs without the GIL and
asks Python's signal handlers every 0.1 s (only from the main thread), and re-raises what
they raise."""

import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

import pydrill
from pydrill import stability as st

PIPES = 6000

LONG = textwrap.dedent(
    """
    import sys, time, pydrill
    from pydrill import _core, stability
    params = pydrill.preset(pipes=int(sys.argv[2]))
    calls = {
        "critical_deltas": lambda: stability.critical_deltas(params),
        "stability": lambda: stability.stability(params, 100.0, omega=5.0),
        "roots_of_impedance": lambda: _core.roots_of_impedance(params.to_core(), 0.01),
    }
    call = calls[sys.argv[1]]
    print("start", flush=True)
    t0 = time.perf_counter()
    try:
        call()
        print("finished", time.perf_counter() - t0, flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.perf_counter() - t0, flush=True)
    """
)


def run(call, interrupt_after=None):
    """(word, seconds in the call, seconds from the SIGINT to the word) of LONG running
    ``call`` on a string of PIPES pipes; SIGINT ``interrupt_after`` s into the call."""
    proc = subprocess.Popen(
        [sys.executable, "-c", LONG, call, str(PIPES)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout.readline().strip() == "start"
        sent = None
        if interrupt_after is not None:
            time.sleep(interrupt_after)  # well inside the call
            sent = time.perf_counter()
            proc.send_signal(signal.SIGINT)
        word, ran = proc.stdout.readline().split()
        latency = None if sent is None else time.perf_counter() - sent
    finally:
        proc.kill()
        proc.wait()
        proc.stdout.close()
    return word, float(ran), latency


@pytest.fixture(scope="module")
def uninterrupted():
    """Seconds critical_deltas takes on the long string here, uninterrupted (some 8 s)."""
    word, ran, _ = run("critical_deltas")
    assert word == "finished"
    return ran


@pytest.mark.slow
@pytest.mark.parametrize("call", ["critical_deltas", "stability", "roots_of_impedance"])
def test_ctrl_c_interrupts_a_long_stability_analysis_within_a_fraction_of_a_second(
    call, uninterrupted
):
    # Each of these takes at least as long as critical_deltas uninterrupted (stability does
    # critical_deltas, then the roots; the roots alone take about as long).
    word, ran, latency = run(call, interrupt_after=1.0)
    assert word == "interrupted", f"{call} {word} after {ran} s"
    # A KeyboardInterrupt raised only when the core returned would also say "interrupted",
    # but after the whole computation.
    assert latency < 1.0  # polled every 0.1 s
    assert ran < 0.4 * uninterrupted, f"{call} interrupted after {ran} s of {uninterrupted} s"


def test_an_analysis_in_another_thread_is_not_stopped_by_the_poll():
    # Signal handlers run in the main thread only: a worker thread's analysis is left alone,
    # and gives what the main thread gives.
    p = pydrill.preset(pipes=500)
    out = {}

    def analyse():
        out["crossings"] = st.critical_deltas(p)
        out["points"] = st.stability(p, 100.0, torque=8.3, crossings=out["crossings"])

    worker = threading.Thread(target=analyse)
    worker.start()
    worker.join()
    crossings = st.critical_deltas(p)
    assert out["crossings"] == crossings
    assert out["points"] == st.stability(p, 100.0, torque=8.3, crossings=crossings)
