"""A damaged atlas with no journal beside it cannot be mended: the refusal says what to do
instead (remove it, or sweep into another file), as pydrill's other refusals of an --out do.
It said only "is damaged (...) and has no journal to rebuild it from", where the user had to
guess that nothing else would take it back. The file is left as it was."""

import subprocess
import sys

import pytest
from sweeping import SMALL

import pydrill
from pydrill.journal import AtlasError
from pydrill.sweep import run_sweep


@pytest.mark.parametrize(
    "content", [b"", b"\x89HDF\r\n\x1a\n" + bytes(40)], ids=["empty", "signature-only"]
)
def test_the_command_says_to_remove_it_or_sweep_elsewhere(tmp_path, content):
    # an empty file (a copy that never began) and a bare HDF5 signature (one cut at once)
    (tmp_path / "s.toml").write_text(SMALL)
    out = tmp_path / "a.h5"
    out.write_bytes(content)
    sweep = [sys.executable, "-m", "pydrill", "sweep", "s.toml", "--out", "a.h5", "--serial"]
    for extra in ([], ["--resume"], ["--dry-run"]):
        proc = subprocess.run(
            [*sweep, *extra],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            timeout=120,
        )
        assert proc.returncode == 2, (extra, proc.stderr)
        # an empty file holds nothing to be damaged: said to be empty
        said = "a.h5 is empty (0 bytes), not an atlas" if not content else "a.h5 is damaged ("
        assert said in proc.stderr
        assert proc.stderr.rstrip().endswith(
            "and has no journal to rebuild it from; remove it to sweep anew, or choose "
            "another --out"
        ), proc.stderr
        assert out.read_bytes() == content


def test_run_sweep_says_it_in_its_own_words(tmp_path):
    out = tmp_path / "a.h5"
    out.write_bytes(b"")
    with pytest.raises(AtlasError, match=r"remove it to sweep anew, or choose another out=PATH$"):
        run_sweep(pydrill.parse_spec(SMALL), out, serial=True)
    assert out.read_bytes() == b""
