"""A drilling engineer's audit of slow single runs: the --check simulations of window and map
(1200 runs of a 334-inertia string took 1 min 43 s) show their progress on a terminal, and
nothing in a log or a pipe."""

import fcntl
import os
import pty
import struct
import subprocess
import sys
import termios
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
CMD = [sys.executable, "-m", "pydrill"]


def on_terminal(*args, sized=True):
    """(stdout, stderr) of the command run with its stderr on a terminal: 24 x 80, as a
    terminal window, or (``sized=False``) 0 x 0, as a pty nobody sized."""
    master, slave = pty.openpty()
    if sized:
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
    proc = subprocess.Popen([*CMD, *map(str, args)], stdout=subprocess.PIPE, stderr=slave)
    os.close(slave)
    err = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the command has ended: the terminal is closed
            break
        if not chunk:
            break
        err += chunk
    os.close(master)
    with proc.stdout:
        out = proc.stdout.read()
    assert proc.wait() == 0, err
    return out.decode(), err.decode()


@pytest.mark.parametrize(
    "args, runs",
    [
        (
            ["window", PAPER, "--depth", "1000m,2000m", "--check", "2", "--check-dof", "8"],
            2 * 2 * 2,
        ),
        (["map", "--dof", "4", "--check", "3", "--t-end", "20"], 3 * 3),
    ],
)
def test_check_simulations_show_their_progress_on_a_terminal_only(args, runs):
    out, err = on_terminal(*args)
    assert f"{runs}/{runs}" in err and "run" in err, err  # K x K per depth, all done
    assert f"{runs}/{runs}" not in out and "steady" in out  # the results, on stdout
    piped = subprocess.run([*CMD, *map(str, args)], capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == ""  # a log or a pipe gets no bar


def test_the_check_progress_is_drawn_on_an_unsized_terminal():
    """A pty nobody sized says it is 0 x 0 ('script' in a batch job, some CI runners): tqdm
    hid the bar below its zero rows, and a --check of minutes showed nothing there."""
    _, err = on_terminal("map", "--dof", "4", "--check", "2", "--t-end", "20", sized=False)
    bars = [b for b in err.replace("\r", "\n").splitlines() if "4/4" in b]
    assert bars and all(0 < len(b) <= 80 for b in bars), err
