"""Damaged global heaps: HDF5 loops for ever on some (reading a text attribute of an atlas with
one bit flipped in a heap object's size hung ``xarray.open_dataset``, ``Atlas.to_xarray`` and
``pydrill atlas export``); pydrill finds them first and raises an AtlasError naming the file.
The damage is made by walking the file's heap collections by the HDF5 format specification
("Global Heap"), written out here apart from pydrill's own walk."""

import json
import struct
import subprocess
import sys
import textwrap

import h5py
import numpy as np
import pytest
from sweeping import SMALL

import pydrill
from pydrill.atlas_heap import heap_problem
from pydrill.journal import AtlasError
from pydrill.sweep import run_sweep
from pydrill.sweep_points import evaluate_point

SPEC = SMALL.replace("t_end = 200.0", "t_end = 50.0")


@pytest.fixture(scope="module")
def atlases(tmp_path_factory):
    """A whole atlas, and one whose points all failed (each with a message in the heap)."""
    tmp = tmp_path_factory.mktemp("heap")
    whole, failed = tmp / "whole.h5", tmp / "failed.h5"
    run_sweep(pydrill.parse_spec(SPEC), whole, serial=True)
    run_sweep(pydrill.parse_spec(SPEC + "max_steps = 3\n"), failed, serial=True)
    return whole, failed


def heap_objects(data: bytes) -> list[tuple[int, int, int]]:
    """(collection start, object offset, object index) of every object with data in every
    collection of ``data``: signature "GCOL", version 1, 3 reserved bytes, 8-byte size; objects
    of a 2-byte index, 2-byte count, 4 reserved bytes, 8-byte size and data padded to 8."""
    found, at = [], data.find(b"GCOL")
    while at >= 0:
        assert data[at + 4] == 1, "a global heap of version 1"
        (size,) = struct.unpack_from("<Q", data, at + 8)
        p = at + 16
        while p + 16 <= at + size:
            index, _, _, length = struct.unpack_from("<HHIQ", data, p)
            if index == 0:
                break  # the free space, last
            found.append((at, p, index))
            p += 16 + (length + 7) // 8 * 8
        at = data.find(b"GCOL", at + size)
    return found


def test_whole_atlases_have_whole_heaps(atlases):
    """No false alarm: pydrill's own atlases, messages and all, pass (and open)."""
    for path in atlases:
        assert heap_objects(path.read_bytes()), f"{path.name} keeps text in a global heap"
        assert heap_problem(path) is None
        with pydrill.Atlas(path) as atlas:
            atlas.check()
    with h5py.File(atlases[1]) as f:
        assert "max_steps" in f["message"][0, 0].decode()  # the messages are there


def flipped(src, dst, offset: int) -> None:
    data = bytearray(src.read_bytes())
    data[offset] ^= 1
    dst.write_bytes(bytes(data))


CHILD = textwrap.dedent(
    """
    import sys
    import pydrill
    from pydrill.journal import AtlasError
    for path in sys.argv[1:]:
        try:
            with pydrill.Atlas(path) as atlas:
                atlas.check()
                atlas.to_xarray().load()
            print("opened")
        except AtlasError as exc:
            print("refused", exc)
    """
)


def in_a_child(code: str, *args: str, doing: str) -> list[str]:
    """The lines ``code`` printed, run with ``args`` in a child process: a hang there fails the
    test (after a minute, naming what it was ``doing``) instead of hanging the suite."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=60
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"{doing} hung")
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def opened_in_a_child(paths: list[str]) -> list[str]:
    """What opening each of ``paths`` (check, to_xarray) came to, in a child process."""
    return in_a_child(CHILD, *paths, doing="opening a damaged atlas")


def test_a_heap_object_a_bit_longer_is_refused_not_a_hang(atlases, tmp_path):
    """Each text object's size + 256 (bit 0 of its second byte): the objects after it fall out
    of line, which HDF5 met with an endless loop on the zeros of some padding. Every such file
    is refused, by the heap's check or as one xarray cannot read (h5py's RuntimeError from
    H5DSget_num_scales was a traceback from to_xarray): never a hang or another exception."""
    whole = atlases[0]
    objects = heap_objects(whole.read_bytes())
    paths = []
    for n, (_, p, _) in enumerate(objects):
        flipped(whole, tmp_path / f"f{n}.h5", p + 8 + 1)
        paths.append(str(tmp_path / f"f{n}.h5"))
    lines = opened_in_a_child(paths)
    assert len(lines) == len(paths)
    assert all(line.startswith("refused ") for line in lines), lines
    assert any("is damaged: its global heap at byte" in line for line in lines)
    assert any("is damaged: xarray cannot read it" in line for line in lines)


def hanging_copy(atlas, dst, holding: bytes = b"") -> tuple[int, str]:
    """A copy of ``atlas`` at ``dst`` with one bit of a heap object's size flipped so that
    HDF5's walk would step by nothing for ever (of an object whose data starts with text
    ``holding``, if given): the start of its collection, and what pydrill says of it."""
    data = atlas.read_bytes()
    for start, p, _ in heap_objects(data):
        if holding not in data[p + 16 : p + 16 + 64]:
            continue
        flipped(atlas, dst, p + 9)
        problem = heap_problem(dst)
        if problem and "has size 0" in problem:
            return start, problem
    pytest.fail("no object whose longer size makes HDF5's walk step by nothing")


def test_the_hang_xarray_met_is_an_atlas_error(atlases, tmp_path):
    """The case found by fuzzing: a heap object's size grown by 256 threw HDF5's walk onto an
    object of index 0 and size 0, where it stepped by nothing for ever."""
    start, problem = hanging_copy(atlases[0], tmp_path / "a.h5")
    assert problem.startswith(f"its global heap at byte {start}: object 0 at byte ")
    (line,) = opened_in_a_child([str(tmp_path / "a.h5")])
    assert line == f"refused {tmp_path / 'a.h5'} is damaged: {problem}"


def test_a_damaged_root_object_header_is_an_atlas_error(atlases, tmp_path):
    """The root group's object header (its address at byte 36 of a version-2 superblock) with
    its version byte changed: h5py's KeyError 'bad object header version number' was a
    traceback from Atlas() and every 'pydrill atlas' command."""
    whole = atlases[0]
    data = bytearray(whole.read_bytes())
    assert data[8] in (2, 3), "a version 2 or 3 superblock"
    (root,) = struct.unpack_from("<Q", data, 36)
    assert data[root : root + 4] == b"OHDR"
    data[root + 4] ^= 0x20
    (tmp_path / "a.h5").write_bytes(bytes(data))
    with pytest.raises(AtlasError, match=r"a\.h5 is damaged or incomplete: .*object header"):
        pydrill.Atlas(tmp_path / "a.h5")


RESUME = [sys.executable, "-m", "pydrill", "sweep", "--serial", "--resume"]


def test_resume_rebuilds_an_atlas_whose_heap_hangs_hdf5_from_its_journal(atlases, tmp_path):
    """--resume read the atlas's attributes with h5py first, and hung there; now the atlas is
    damaged as any other is: rebuilt from its journal, the points the journal holds kept."""
    spec = pydrill.parse_spec(SPEC)
    (tmp_path / "s.toml").write_text(SPEC)
    out = tmp_path / "a.h5"
    hanging_copy(atlases[0], out)
    records = [json.dumps(evaluate_point(spec, i)) for i in range(spec.size)]
    header = json.dumps({"spec_digest": spec.digest})
    (tmp_path / "a.h5.journal").write_text("".join(x + "\n" for x in [header, *records]))
    done = subprocess.run(
        [*RESUME, str(tmp_path / "s.toml"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert f"0 computed now (0 failed), {spec.size} already done" in done.stdout + done.stderr
    assert heap_problem(out) is None
    with h5py.File(out) as f, h5py.File(atlases[0]) as g:
        for name in ("status", "regime", "bit_mean", "omega_eq"):
            np.testing.assert_array_equal(f[name][...], g[name][...])


def test_resume_refuses_an_atlas_whose_heap_hangs_hdf5_without_journal(atlases, tmp_path):
    (tmp_path / "s.toml").write_text(SPEC)
    out = tmp_path / "a.h5"
    _, problem = hanging_copy(atlases[0], out)
    before = out.read_bytes()
    done = subprocess.run(
        [*RESUME, str(tmp_path / "s.toml"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode != 0
    assert f"is damaged ({problem}) and has no journal to rebuild it from" in done.stderr
    assert out.read_bytes() == before  # left as it was


QUERY = textwrap.dedent(
    """
    import sys
    import pydrill.atlas
    from pydrill.journal import AtlasError
    pydrill.atlas.OPENING_BYTES = int(sys.argv[2])  # as if the messages' heap were far in
    with pydrill.Atlas(sys.argv[1]) as atlas:
        print("opened")
        try:
            atlas.value(wob=atlas.axes["wob"][0], torque=atlas.axes["torque"][0])
            print("read")
        except AtlasError as exc:
            print("refused", exc)
    """
)


def test_a_failed_points_message_in_a_damaged_heap_past_the_opening_is_refused(atlases, tmp_path):
    """The failed points' messages are written last, in a heap of their own: on a large atlas
    past the first OPENING_BYTES, which opening checks. A point query that reads a message
    from a damaged one hung HDF5; it checks the whole file first, and is refused."""
    start, problem = hanging_copy(atlases[1], tmp_path / "a.h5", holding=b"SolverError")
    assert heap_problem(tmp_path / "a.h5", limit=start) is None  # opening cannot see it
    lines = in_a_child(QUERY, str(tmp_path / "a.h5"), str(start), doing="the point query")
    assert lines == ["opened", f"refused {tmp_path / 'a.h5'} is damaged: {problem}"]


def test_xarray_through_the_pydrill_engine_refuses_a_heap_hdf5_hangs_on(atlases, tmp_path):
    """``xarray.open_dataset(path, engine="h5netcdf")`` hangs on such a file; the pydrill
    engine checks the heaps first."""
    _, problem = hanging_copy(atlases[0], tmp_path / "a.h5")
    child = (
        "import sys, xarray\n"
        "from pydrill.journal import AtlasError\n"
        "try:\n"
        "    xarray.open_dataset(sys.argv[1], engine='pydrill').load()\n"
        "    print('opened')\n"
        "except AtlasError as exc:\n"
        "    print('refused', exc)\n"
    )
    lines = in_a_child(child, str(tmp_path / "a.h5"), doing="xarray's pydrill engine")
    assert lines == [f"refused {tmp_path / 'a.h5'} is damaged: {problem}"]
