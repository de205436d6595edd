"""Output into a pipe whose reader has gone (``pydrill map --json | head``): not an error of
pydrill's, so no message and exit status 0; and a program that called ``pydrill.cli.main``
keeps its own standard error."""

import subprocess
import sys

import pytest

# 370 kB of JSON: more than a pipe holds (64 kB), so the writer meets the closed end.
ARGS = ["map", "--dof", "2", "--json"]


def _read_a_little_then_close(cmd: list[str]) -> tuple[int, str]:
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE) as proc:
        assert proc.stdout is not None and proc.stderr is not None
        head = proc.stdout.read(10)
        proc.stdout.close()
        err = proc.stderr.read().decode()
        code = proc.wait(timeout=60)
    assert head.startswith(b"{"), head
    return code, err


def test_the_command_piped_into_head_says_nothing_and_succeeds():
    code, err = _read_a_little_then_close([sys.executable, "-m", "pydrill", *ARGS])
    assert (code, err) == (0, "")


@pytest.mark.parametrize("stream", ["stderr", "stdout"])
def test_a_program_calling_main_keeps_its_stderr_after_a_broken_pipe(stream):
    """``main`` closed sys.stderr: the caller's next message raised "I/O operation on closed
    file". Its stdout, whose reader is gone, writes into /dev/null: no "Exception ignored"
    at exit either."""
    script = (
        "import sys\n"
        "from pydrill.cli import main\n"
        f"code = main({ARGS!r})\n"
        f"print('caller still writes, main returned', code, file=sys.{stream})\n"
        "sys.stderr.flush()\n"
    )
    code, err = _read_a_little_then_close([sys.executable, "-c", script])
    assert code == 0, err
    want = "caller still writes, main returned 0\n" if stream == "stderr" else ""
    assert err == want
