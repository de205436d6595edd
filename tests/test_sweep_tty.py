"""The sweep's progress bar on a terminal: drawn on one that says it is 0 x 0 (a pty nobody
sized, as `script` in a batch job or some CI runners make), where tqdm hid it below its zero
rows and the sweep ran without a sign of progress; and as wide as a sized terminal."""

import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import termios

import pytest
from sweeping import CMD, TINY


def _stderr_on_a_pty(argv, size=None):
    """Run ``argv`` with its stderr on a new pty (of ``size`` (rows, columns), or unsized: 0 x
    0) and return what it wrote there."""
    master, slave = pty.openpty()
    if size is not None:
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", *size, 0, 0))
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    chunks, exited = [], False
    while True:
        ready, _, _ = select.select([master], [], [], 0.2)
        if ready:
            try:
                data = os.read(master, 65536)
            except OSError:  # the child closed the pty: all is read
                break
            if not data:
                break
            chunks.append(data)
        elif exited:  # and nothing came in the 0.2 s since: all is read
            break
        else:  # a child that wrote its last bar and exited just after the select above left
            exited = proc.poll() is not None  # it unread: one more look before stopping
    proc.wait(timeout=60)
    os.close(master)
    assert proc.returncode == 0
    return b"".join(chunks).decode(errors="replace")


@pytest.mark.parametrize("size", [None, (30, 100)], ids=["unsized", "100-columns"])
def test_the_progress_bar_is_drawn_on_any_terminal(tmp_path, size):
    spec = tmp_path / "tiny.toml"
    spec.write_text(TINY)
    argv = [*CMD, "sweep", str(spec), "--out", str(tmp_path / "t.h5"), "--serial"]
    err = _stderr_on_a_pty(argv, size)
    bars = [b for b in re.split(r"[\r\n]+", err) if b.startswith("sweep:") and "pt/s" in b]
    assert bars, f"no progress bar on the terminal: {err!r}"
    assert "6/6" in bars[-1]  # TINY's 6 points, all done
    assert all(len(b) <= (size[1] if size else 80) for b in bars)
