"""An atlas cut short (a disk that filled, a copy stopped half-way: docs/guide/sweeps.md) is
refused naming what is wrong with it. The first thing pydrill reads of it is a global heap
collection whose stated size runs past the file's end; that was reported as "claims 4096
bytes, where 4096 ... 2952 fit", a range that is empty and says nothing of the file's end.
The heap's position and the file's length are read here with struct, apart from pydrill."""

import struct
import subprocess
import sys

import pytest
from sweeping import SMALL

import pydrill
from pydrill.atlas_heap import MIN_SIZE, heap_problem
from pydrill.journal import AtlasError
from pydrill.sweep import run_sweep

SPEC = SMALL.replace("t_end = 200.0", "t_end = 50.0")


@pytest.fixture(scope="module")
def cut(tmp_path_factory):
    """A whole atlas cut 1000 bytes into its first global heap: (path, heap's byte, length)."""
    tmp = tmp_path_factory.mktemp("cut")
    whole = tmp / "whole.h5"
    run_sweep(pydrill.parse_spec(SPEC), whole, serial=True)
    data = whole.read_bytes()
    at = data.find(b"GCOL\x01\x00\x00\x00")
    assert at > 0 and struct.unpack_from("<Q", data, at + 8)[0] >= MIN_SIZE
    path = tmp / "cut.h5"
    path.write_bytes(data[: at + 1000])
    return path, at, at + 1000


def test_the_message_says_the_file_ends_before_the_heap_does(cut):
    path, at, length = cut
    problem = heap_problem(path)
    assert problem.startswith(f"its global heap at byte {at} claims ")
    assert f"past the file's end (byte {length}): the file is cut short" in problem
    assert " fit" not in problem  # no range of sizes, empty here (MIN_SIZE > 1000)


def test_atlas_and_the_command_refuse_it_with_that_line(cut):
    path, _, length = cut
    with pytest.raises(AtlasError, match=rf"{path.name} is damaged: .*byte {length}\): the file"):
        pydrill.Atlas(path)
    proc = subprocess.run(
        [sys.executable, "-m", "pydrill", "atlas", "info", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2 and proc.stdout == ""
    assert "the file is cut short" in proc.stderr and "Traceback" not in proc.stderr


def test_a_size_below_any_hdf5_collection_is_said_so_not_as_a_range():
    small = b"GCOL\x01\x00\x00\x00" + struct.pack("<Q", 64) + bytes(MIN_SIZE)
    assert heap_problem(small) == (
        f"its global heap at byte 0 claims 64 bytes, fewer than any HDF5 writes ({MIN_SIZE})"
    )
