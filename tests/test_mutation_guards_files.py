"""Atlas files: the writer's lock against a real second process, a damaged atlas made by hand
with h5py, global heaps built byte by byte from the HDF5 format, file kinds from their
magic bytes, and the stability checks' and sweep report's documented rules.

Found by a mutation audit (session 37) of atlas_lock, atlas_check, atlas_heap, file_kinds,
stability_checks and sweep_results: each test below kills mutants the suite let live.
"""

import os
import socket
import struct
import subprocess
import sys
import threading
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

import pydrill.atlas_lock as lock_module
from pydrill.atlas_check import layout_problem
from pydrill.atlas_heap import HEADER, MIN_SIZE, SIGNATURE, heap_problem
from pydrill.atlas_lock import LOCK_SUFFIX, AtlasBusy, Holder, snapshot, writer_lock
from pydrill.file_kinds import atlas_name_problem, misplaced, what_is
from pydrill.spec import parse_spec
from pydrill.stability_checks import _check_grid_memory, _checked, _finite
from pydrill.sweep import run_sweep
from pydrill.sweep_results import SweepInterrupted, SweepReport

# --- the writer's lock, held by a real second process --------------------------------------

# Takes the lock, says so, and inside ``writing`` writes the atlas in two halves 0.4 s apart.
HOLDER = """
import sys, time
from pathlib import Path
from pydrill.atlas_lock import writer_lock, writing
atlas = Path(sys.argv[1])
with writer_lock(atlas):
    with writing(atlas):
        print("writing", flush=True)
        atlas.write_bytes(b"half")
        time.sleep(0.4)
        atlas.write_bytes(b"whole")
    print("held", flush=True)
    sys.stdin.readline()
"""


@pytest.fixture
def held(tmp_path):
    atlas = tmp_path / "a.h5"
    atlas.write_bytes(b"before")
    proc = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(atlas)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout.readline() == "writing\n"
    yield atlas, proc
    proc.communicate("\n", timeout=10)


def test_a_reader_waits_for_a_whole_write_and_a_second_writer_is_refused(held, monkeypatch):
    """snapshot takes the record lock shared: it waits out the other process's ``writing``
    and reads the whole write, never the half; a second writer_lock is refused, naming the
    holder's process and host, as the lock file written by the holder says."""
    atlas, proc = held
    assert snapshot(atlas) == b"whole"
    assert proc.stdout.readline() == "held\n"
    text = (atlas.parent / ("a.h5" + LOCK_SUFFIX)).read_text()
    since = text.split()[2]
    # the file holds one line, the holder's (not left over from an older, longer one)
    assert text == f"{proc.pid} {socket.gethostname()} {since}\n"
    monkeypatch.setattr(lock_module, "BUSY_PATIENCE", 0.1)
    # In a thread with a deadline: a lock that waited for the holder (a blocking flock) would
    # hang the suite until the holder lets go, which it does only after this test.
    outcome: list[BaseException | None] = []

    def second_writer() -> None:
        try:
            with writer_lock(atlas):
                outcome.append(None)
        except BaseException as exc:  # handed to the test's thread
            outcome.append(exc)

    thread = threading.Thread(target=second_writer, daemon=True)
    thread.start()
    thread.join(timeout=20)
    assert outcome, "a second writer_lock waited for the holder instead of being refused"
    with pytest.raises(AtlasBusy, match=rf"another sweep \(process {proc.pid} on host "):
        if outcome[0] is not None:
            raise outcome[0]


def test_the_lock_file_is_one_line_and_gone_after(tmp_path):
    """A lock file left by a killed sweep, longer than the new line, is rewritten whole; and
    the file is removed when the lock is let go. Nobody writes then: snapshot is None."""
    atlas = tmp_path / "a.h5"
    atlas.write_bytes(b"data")
    lock = tmp_path / ("a.h5" + LOCK_SUFFIX)
    lock.write_text("999999999 some-long-host-name-of-old 2020-01-01T00:00:00Z trailing words\n")
    assert snapshot(atlas) is None  # a file, but no flock on it
    with writer_lock(atlas):
        words = lock.read_text().split()
        assert words[:2] == [str(os.getpid()), socket.gethostname()] and len(words) == 3
    assert not lock.exists()
    assert snapshot(atlas) is None


def test_a_holder_on_this_host_that_has_ended_is_said_so():
    """A lock file naming a process of this host that is gone: its child holds the lock."""
    gone = Holder(_pid_of_ended(), socket.gethostname(), "")
    assert "which has ended" in str(gone)
    assert "which has ended" not in str(Holder(os.getpid(), socket.gethostname(), ""))


def _pid_of_ended() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


# --- a damaged atlas, made by hand with h5py ------------------------------------------------

SPEC = """
[model]
preset = "reduced-scale"
dof = 3
[axes]
wob = [100.0, 120.0]
torque = [6.0]
[simulation]
t_end = 2.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    path = tmp_path_factory.mktemp("atlas") / "a.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    return path


def _problem(src, tmp_path, damage, codes=True):
    """What layout_problem says of a copy of ``src`` damaged by ``damage(f)``."""
    path = tmp_path / "d.h5"
    path.write_bytes(src.read_bytes())
    with h5py.File(path, "r+") as f:
        damage(f)
    with h5py.File(path, "r") as f:
        return layout_problem(f, parse_spec(SPEC), codes=codes)


def _replace(name, data):
    def damage(f):
        del f[name]
        f[name] = data

    return damage


def test_the_whole_atlas_passes(atlas):
    with h5py.File(atlas, "r") as f:
        assert layout_problem(f, parse_spec(SPEC)) is None


def test_each_kind_of_damage_is_named(atlas, tmp_path):
    def attr(name, value):
        return lambda f: f.attrs.__setitem__(name, value)

    assert _problem(atlas, tmp_path, attr("title", 3)).endswith("(3) is not text")
    assert _problem(atlas, tmp_path, attr("format_version", True)) == (
        "attribute format_version = np.True_ is not an integer"  # h5py reads it back as numpy's
    )
    # the axes in another order: the grid's order is the datasets' order
    assert _problem(atlas, tmp_path, attr("axes", '["torque", "wob"]')).startswith(
        "attribute axes = "
    )
    with h5py.File(atlas, "r") as f:
        caveat, regime, status = f["caveat"][...], f["regime"][...], f["status"][...]
    # an optional dataset present but of another shape (its last axis, the starts, wrong)
    assert _problem(atlas, tmp_path, _replace("caveat", caveat[..., :0])) == (
        f"caveat has shape {caveat[..., :0].shape}, not {caveat.shape}"
    )
    assert _problem(atlas, tmp_path, lambda f: f.__delitem__("regime")) == "no dataset regime"
    assert _problem(atlas, tmp_path, _replace("message", np.zeros(status.shape))) == (
        "message: no text"
    )
    # an axis off in its sixth digit is not the spec's axis
    assert _problem(atlas, tmp_path, _replace("wob", [100.0, 120.0001])) == (
        "axis wob is not the spec's 2 values"
    )
    # a status code that is none: found by the codes check, and only by it
    bad = _replace("status", np.full(status.shape, 77, status.dtype))
    assert _problem(atlas, tmp_path, bad).startswith("status holds codes other than")
    assert _problem(atlas, tmp_path, bad, codes=False) is None
    assert regime.dtype.kind in "iu"


# --- global heaps, byte by byte from the format ("Global Heap": GCOL, objects of 16-byte
# headers, their data padded to 8 bytes; free space, index 0, counts its own header) ---------


def _object(index, length, data=b""):
    body = data.ljust(-(-length // 8) * 8, b"\0") if index else b""
    return struct.pack("<HHIQ", index, 1, 0, length) + body


def _collection(*objects, size=MIN_SIZE, free=True):
    body = b"".join(objects)
    if free:  # the rest of the collection: one free-space object, its size counting itself
        body += struct.pack("<HHIQ", 0, 0, 0, size - HEADER - len(body))
    head = SIGNATURE + struct.pack("<Q", size)
    return (head + body).ljust(size, b"\0")


def test_a_whole_collection_of_padded_objects_passes():
    # 5 bytes padded to 8, then free space ending exactly at the collection's end
    assert heap_problem(b"x" * 100 + _collection(_object(1, 5, b"hello"))) is None


def test_an_object_whose_header_just_fits_is_still_read():
    # the last 16 bytes: an object claiming 100 bytes past the end
    at = MIN_SIZE - 16
    data = _collection(_object(1, at - 2 * HEADER), _object(2, 100)[:16], free=False)
    assert len(data) == MIN_SIZE
    assert heap_problem(data) == (
        f"its global heap at byte 0: object 2 at byte {at} claims 100 bytes, past the "
        f"collection's end (byte {MIN_SIZE})"
    )


def test_a_collection_of_a_size_too_small_or_too_large_is_refused():
    small = SIGNATURE + struct.pack("<Q", 100) + bytes(200)
    assert (
        heap_problem(small)
        == "its global heap at byte 0 claims 100 bytes, fewer than any HDF5 writes (4096)"
    )
    big = _collection(_object(1, 8, b"abcdefgh"))
    big = big[:8] + struct.pack("<Q", 10**6) + big[16:]
    assert heap_problem(big).startswith("its global heap at byte 0 claims 1000000 bytes")


def test_the_signature_inside_an_object_is_data_not_a_collection():
    # text that happens to be a collection's signature, with a size of 8
    inner = SIGNATURE + struct.pack("<Q", 8)
    assert heap_problem(_collection(_object(1, len(inner), inner))) is None


def test_only_collections_before_the_limit_are_walked():
    whole = _collection(_object(1, 8, b"abcdefgh"))
    broken = bytearray(_collection(_object(1, 8, b"abcdefgh")))
    broken[HEADER + 8 : HEADER + 16] = struct.pack("<Q", 10**5)  # its object's size
    data = whole + bytes(broken)
    assert heap_problem(data, limit=MIN_SIZE) is None
    assert heap_problem(data).startswith(f"its global heap at byte {MIN_SIZE}: object 1")


# --- file kinds -------------------------------------------------------------------------------


def test_kinds_by_magic_bytes_and_by_tables(tmp_path):
    h5 = tmp_path / "x.h5"
    with h5py.File(h5, "w") as f:
        f["a"] = [1]
    assert what_is(h5) == "an HDF5 file (an atlas?)"
    assert misplaced(h5, "atlas") is None  # the kind wanted: its own faults are the news
    cdf = tmp_path / "x.nc"
    cdf.write_bytes(b"CDF\x02" + bytes(20))  # netCDF-3, 64-bit offsets
    assert what_is(cdf) == "a netCDF-3 file"
    sim = tmp_path / "s.toml"
    sim.write_text("[simulation]\nt_end = 5.0\n")  # a spec with no [axes] yet
    assert what_is(sim) == "a sweep spec (TOML)"
    section = tmp_path / "t.toml"
    section.write_text('section = "drill-pipe"\n')  # a key, not a tally's [[section]] list
    assert what_is(section) is None
    # exactly 64 kiB of a spec is still read (only a bigger file is passed over)
    padded = tmp_path / "p.toml"
    text = "[axes]\nwob = [1.0]\n"
    padded.write_text(text + "#" * (65536 - len(text) - 1) + "\n")
    assert padded.stat().st_size == 65536 and what_is(padded) == "a sweep spec (TOML)"
    assert atlas_name_problem(tmp_path / "F.PNG").startswith(f"{tmp_path / 'F.PNG'}: a name")


# --- the stability functions' checks ---------------------------------------------------------


def test_strict_and_not_strict_bounds_and_where_the_bad_element_is():
    with pytest.raises(ValueError, match=r"^x = 0 is not allowed: must be a finite number > 0$"):
        _checked("x", 0.0, 0.0, True)
    assert _checked("x", 0.0, 0.0, False) == 0.0
    with pytest.raises(ValueError, match=r"^x\[1, 0\] = inf is not allowed: each must be a"):
        _checked("x", [[1.0, 2.0], [np.inf, 3.0]], 0.0, True)
    with pytest.raises(ValueError, match="beyond the range of a float"):
        _finite("delta", 1e308, "Jacobian", [1.0, -np.inf])


def test_the_grid_memory_is_32_bytes_a_point_against_what_is_available(monkeypatch):
    import psutil

    need = 32 * 300 * 200  # the slopes, a temporary, indices and counts: 8 bytes each
    for free, refused in ((need, False), (need - 1, True)):
        monkeypatch.setattr(
            psutil, "virtual_memory", lambda free=free: SimpleNamespace(available=free)
        )
        if refused:
            with pytest.raises(ValueError, match=rf"needs about {need / 1e9:.3g} GB"):
                _check_grid_memory(300, 200)
        else:
            _check_grid_memory(300, 200)


# --- what a sweep reports ---------------------------------------------------------------------


def test_all_failed_counts_the_atlas_and_an_empty_grid_is_not_all_failed(tmp_path):
    report = SweepReport(tmp_path, 4, 0, 0, 4, 1.0, 0.1, failed_in_atlas=4)
    assert report.all_failed  # failed before, found done by this resume
    assert not SweepReport(tmp_path, 0, 0, 0, 0, 0.0, 0.0).all_failed
    stop = SweepInterrupted(tmp_path, 10, 3)
    assert str(stop).endswith("computes the other 7")
