"""An atlas read while its sweep is writing it: every read succeeds and is self-consistent.

Before readers took a copy of the last complete write (``atlas_lock.snapshot``), about one
read in four failed with "filter returned failure during read" or "addr overflow" while a
sweep rewrote the file."""

import contextlib
import subprocess
import sys
import textwrap
import time

import numpy as np

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.atlas_lock import writer_of

SPEC = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 80 }
torque = { start = 2.0, stop = 16.0, num = 40 }
[simulation]
t_end = 300.0
initial = ["rest"]
"""

# A serial sweep that rewrites its atlas after nearly every batch (a real one does so every
# 5 s at the soonest): many rewrites for the reader to run into.
WRITER = textwrap.dedent(
    """
    import sys
    import pydrill.sweep as sweep
    from pydrill.spec import load_spec
    sweep.FLUSH_SECONDS = 0.01
    sweep.FLUSH_SPACING = 1.0
    sweep.run_sweep(load_spec(sys.argv[1]), sys.argv[2], serial=True)
    """
)


@contextlib.contextmanager
def sweep_writing(tmp_path):
    """The sweep above, started; (its process, its atlas) once it writes the atlas. Killed
    on the way out, whatever happened."""
    spec, out = tmp_path / "live.toml", tmp_path / "live.h5"
    spec.write_text(SPEC)
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(spec), str(out)])
    try:
        deadline = time.monotonic() + 60
        while writer_of(out) is None or not out.exists():
            assert writer.poll() is None, "the sweep ended before it could be read"
            assert time.monotonic() < deadline
            time.sleep(0.01)
        yield writer, out
    finally:
        writer.kill()
        writer.wait()


def test_an_atlas_is_readable_while_its_sweep_rewrites_it(tmp_path):
    with sweep_writing(tmp_path) as (writer, out):
        reads_while_writing, done_seen = 0, []
        while writer.poll() is None:
            with Atlas(out) as atlas:
                summary = atlas.summary()
                ds = atlas.to_xarray().load()
                point = atlas.value(wob=20.0, torque=2.0)
            status, regime = ds["status"].values, ds["regime"].values[..., 0]
            # A point marked done has its regime: the copy is one whole write, not a mix.
            assert not np.any((status == fmt.STATUS["done"]) & (regime == fmt.REGIMES["missing"]))
            assert summary["status"]["done"] == int(np.sum(status == fmt.STATUS["done"]))
            assert point["status"] in ("done", "missing")
            done_seen.append(summary["status"]["done"])
            reads_while_writing += 1
        assert writer.wait() == 0
    assert reads_while_writing >= 5
    # The reads saw the atlas grow, not only its first or last state.
    assert len(set(done_seen)) >= 3, done_seen
    assert done_seen == sorted(done_seen)
    with Atlas(out) as atlas:  # and once the sweep is over, the file itself
        assert atlas._image is None
        assert atlas.summary()["status"]["done"] == 3200


EXPORT = [sys.executable, "-m", "pydrill", "atlas", "export"]


def test_an_atlas_exports_while_its_sweep_rewrites_it(tmp_path):
    """The export reads the copy of the last complete write by blocks, through xarray and
    h5py at once (the messages): a netCDF and a CSV export made mid-sweep hold one write,
    each point marked done with its regime, fewer done than in the end."""
    import xarray as xr

    with sweep_writing(tmp_path) as (writer, out):
        for suffix in (".nc", ".csv"):
            target = tmp_path / f"live{suffix}"
            export = subprocess.run(
                [*EXPORT, str(out), "--out", str(target)], capture_output=True, text=True
            )
            assert export.returncode == 0, export.stderr
        midway = writer.poll() is None
        assert writer.wait() == 0
    with xr.open_dataset(tmp_path / "live.nc", engine="h5netcdf") as ds:
        done = ds["status"].values == fmt.STATUS["done"]
        assert np.array_equal(ds["regime"].values[..., 0] >= 0, done)
    rows = (tmp_path / "live.csv").read_text().splitlines()
    assert len(rows) == 1 + 3200 and sum(",done," in r for r in rows) >= int(done.sum())
    assert not midway or int(done.sum()) < 3200
