"""The short-window note's advice, "judge a larger fraction of the run (...)", names what the
reader can change: ``window_fraction`` to ``simulate`` (which refuses ``window=``), ``--window``
on the command line. It named "(window)", the sweep spec's key, in both.

docs/guide/simulate.md's 13-inertia string at t_end = 100 s: its slowest period (about 72 s)
is longer than the 50 s judged, which the note says."""

import inspect
import json
import subprocess
import sys

import pytest

import pydrill

RUN = dict(wob=40.0, torque=8.3, pipes=10, t_end=100.0, initial="equilibrium")
ARGS = ["--pipes", "10", "--wob", "40", "--torque", "8.3", "--t-end", "100"]
ADVICE = "simulate longer, or judge a larger fraction of the run"


def test_python_names_the_keyword_simulate_takes():
    s = pydrill.simulate(**RUN).summary
    assert s.caveat == "short-window"
    assert s.note.endswith(f"{ADVICE} (window_fraction)"), s.note
    assert "window_fraction" in inspect.signature(pydrill.simulate).parameters
    with pytest.raises(ValueError, match="unknown parameter 'window'"):
        pydrill.simulate(**RUN, window=0.9)
    # and taking the advice lifts the note: the whole 100 s holds the 72 s period
    assert pydrill.simulate(**RUN, window_fraction=1.0).summary.caveat != "short-window"


@pytest.mark.parametrize("json_out", [False, True])
def test_the_command_names_its_option(json_out):
    proc = subprocess.run(
        [sys.executable, "-m", "pydrill", "simulate", *ARGS, "--initial", "equilibrium"]
        + (["--json"] if json_out else []),
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    note = json.loads(proc.stdout)["note"] if json_out else proc.stdout.split("note", 1)[1]
    assert note.strip().endswith(f"{ADVICE} (--window)"), note
