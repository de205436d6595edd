"""Output into a pipe already closed by its reader, as ``| head`` leaves it: a refusal said
with --json (its JSON on stdout) raised a traceback over the message (PYTHONUNBUFFERED set)
or failed the flush at exit, exit status 120 with "Exception ignored ... BrokenPipeError";
so did a short document that fitted the buffer. The refusal keeps its status, 2, and its one
line; a success, 0 and silence (as tests/test_cli_pipe.py holds for a long document)."""

import os
import subprocess
import sys

import pytest


def _into_closed_pipe(args: list[str], unbuffered: bool) -> tuple[int, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    if unbuffered:
        env["PYTHONUNBUFFERED"] = "1"
    read, write = os.pipe()
    os.close(read)  # the reader is gone before pydrill writes a byte
    try:
        proc = subprocess.run(
            [sys.executable, "-m", "pydrill", *args],
            stdout=write,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
            timeout=120,
        )
    finally:
        os.close(write)
    return proc.returncode, proc.stderr


@pytest.mark.parametrize("unbuffered", [False, True], ids=["buffered", "unbuffered"])
def test_a_refusal_with_json_keeps_its_status_and_message(tmp_path, unbuffered):
    gone = tmp_path / "gone.h5"
    code, err = _into_closed_pipe(["atlas", "info", str(gone), "--json"], unbuffered)
    assert (code, err) == (2, f"pydrill atlas info: error: {gone}: no such atlas\n")


def test_a_short_document_succeeds_silently():
    """Buffered whole until exit (unbuffered, its first write fails in the command, as a long
    document's does, and was already answered so)."""
    args = ["simulate", "--dof", "2", "--wob", "100", "--torque", "8.3", "--t-end", "1", "--json"]
    assert _into_closed_pipe(args, unbuffered=False) == (0, "")
