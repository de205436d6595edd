"""Large atlases are read by parts. ``pydrill atlas export`` reads, converts and writes one
a block of rows at a time: its memory is a block's whatever the atlas's size, and the file is
the one a whole export makes. A write that fails midway (a full disk) is an error naming
--out, with nothing left behind and no crash (``SinkFile``). ``Atlas.sel`` reads what it
selects. ``Atlas.to_xarray``'s close (and the xarray engine's) releases the file, with or
without dask chunks."""

import errno
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np
import psutil
import pytest
import xarray as xr
from sweeping import CMD

from pydrill import atlas_format as fmt
from pydrill import cli, cli_atlas_export, export_file
from pydrill.atlas import Atlas
from pydrill.atlas_table import AtlasTable
from pydrill.export_file import SinkFile
from pydrill.spec import parse_spec

# Three axes of sizes no block divides, two starts, four eigenvalues: 23 x 19 x 3 points.
SPEC = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 23 }
torque = { start = 2.0, stop = 16.0, num = 19 }
bit_damping = [0.02, 0.05, 0.08]
[simulation]
initial = ["rest", "equilibrium"]
"""


def synthetic_atlas(path, spec_text, seed=0):
    """An atlas of ``spec_text`` with every point done and random values in every field
    (a few failed, with messages): what a sweep of its size would write, made in a second."""
    spec = parse_spec(spec_text)
    rng = np.random.default_rng(seed)
    table = AtlasTable(spec)
    table.status[...] = fmt.STATUS["done"]
    table.regime[...] = rng.integers(0, 4, table.regime.shape)
    table.caveat[...] = rng.integers(0, 3, table.caveat.shape)
    for a in [*table.runs.values(), *table.eqs.values()]:
        a[...] = rng.normal(size=a.shape) if a.dtype.kind == "f" else rng.integers(0, 9, a.shape)
    table.eig[...] = rng.normal(size=table.eig.shape) + 1j * rng.normal(size=table.eig.shape)
    table.coexistence[...] = rng.integers(0, 2, table.coexistence.shape)
    failed = rng.random(spec.shape) < 0.01
    table.status[failed] = fmt.STATUS["failed"]
    table.regime[failed] = fmt.REGIMES["failed"]
    table.message[failed] = "the solver gave up"
    fmt.create(path, spec, "{}", "test")
    fmt.write(path, table)
    return path


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    return synthetic_atlas(tmp_path_factory.mktemp("blocks") / "three.h5", SPEC)


def export(atlas, out):
    args = cli.build_parser().parse_args(["atlas", "export", str(atlas), "--out", str(out)])
    assert args.handler(args) == 0
    return out


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_an_export_by_blocks_is_the_export_made_whole(atlas, tmp_path, monkeypatch, suffix):
    """Blocks of 7 points (rows of the first axis: one row, 114 points, at a time) and one
    block of all 1311: the same CSV, byte for byte; the same netCDF variables, values,
    attributes and HDF5 chunks, and the regime still a named enum."""
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 10**9)
    whole = export(atlas, tmp_path / f"whole{suffix}")
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 7)
    blocks = export(atlas, tmp_path / f"blocks{suffix}")
    if suffix == ".csv":
        assert blocks.read_bytes() == whole.read_bytes()
        assert len(blocks.read_text().splitlines()) == 1 + 23 * 19 * 3 * 2
        return
    with (
        xr.open_dataset(whole, engine="h5netcdf") as a,
        xr.open_dataset(blocks, engine="h5netcdf") as b,
    ):
        xr.testing.assert_identical(a.load(), b.load())
        with Atlas(atlas) as source:
            np.testing.assert_array_equal(b["regime"].values, source._file()["regime"][...])
    with h5py.File(whole) as a, h5py.File(blocks) as b:
        chunks = [
            {k: d.chunks for k, d in f.items() if isinstance(d, h5py.Dataset)} for f in (a, b)
        ]
        assert chunks[0] == chunks[1] and chunks[0]["bit_mean"] is not None
        assert h5py.check_enum_dtype(b["regime"].dtype) == dict(fmt.REGIMES)


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_an_export_reads_the_atlas_a_block_of_rows_at_a_time(atlas, tmp_path, monkeypatch, suffix):
    """Every read of a field on the grid (a metric, the eigenvalues, the messages) takes at
    most a block's rows of the first axis: 2 rows (2 x 57 points) in blocks of 120 points.
    Only the codes, a byte a point, are read whole (checked, and the regime kept whole for
    its enum type). Made whole, the export read every field whole, then held the whole file
    it made (1 GB for 10^6 points; benchmarks/bench_export.py measures it)."""
    codes = {"status", "regime", "caveat", "coexistence"}
    rows: dict[str, int] = {}
    read = h5py.Dataset.__getitem__

    def counted(self, key, *args, **kwargs):
        out = read(self, key, *args, **kwargs)
        name = self.name.lstrip("/")
        if self.ndim > 1 and name not in codes and isinstance(out, np.ndarray) and out.size:
            rows[name] = max(rows.get(name, 0), out.size * self.shape[0] // self.size)
        return out

    monkeypatch.setattr(h5py.Dataset, "__getitem__", counted)
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 120)
    export(atlas, tmp_path / f"three{suffix}")
    fields = {"bit_mean", "stick_events", "message"}
    fields |= set() if suffix == ".csv" else {"eigenvalues_real", "omega_eq"}
    assert fields <= set(rows), rows
    assert max(rows.values()) == 2, rows


def test_a_sink_reads_back_what_was_written_after_a_write_failed(tmp_path):
    """HDF5 must find the file as it wrote it, a failed write or not: before the failure
    from the file, after it from memory; the error kept for the caller."""
    path = tmp_path / "sink"
    fd = os.open(path, os.O_RDWR | os.O_CREAT)
    full = os.open("/dev/full", os.O_RDWR)  # every write: ENOSPC
    try:
        sink = SinkFile(fd)
        assert sink.write(b"header") == 6 and sink.error is None
        sink.fd = full  # the disk fills up
        sink.seek(20)
        assert sink.write(b"data") == 4  # HDF5 is told it went well
        assert sink.error is not None and sink.error.errno == errno.ENOSPC
        sink.seek(2)
        assert sink.write(b"AD") == 2  # over what reached the file
        sink.fd = fd  # reads come from the file as it is, then what memory holds
        sink.seek(0)
        assert sink.read(100) == b"heADer" + bytes(14) + b"data"
        assert sink.seek(0, os.SEEK_END) == 24 and path.read_bytes() == b"header"
        sink.close()
    finally:
        os.close(fd)
        os.close(full)


def _limit_file_size(limit):
    def preexec():
        import resource

        hard = resource.getrlimit(resource.RLIMIT_FSIZE)[1]
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, hard))

    return preexec


@pytest.mark.skipif(sys.platform == "win32", reason="RLIMIT_FSIZE is POSIX")
@pytest.mark.parametrize("share", [0.3, 0.7, 0.97])
def test_a_netcdf_export_cut_off_midway_is_a_clean_error(atlas, tmp_path, share):
    """The disk fills up (a file size limit) with a share of the netCDF file written, in
    its data or its last metadata: HDF5 never hears of it, the export says it in one line
    and leaves nothing (told, HDF5's half-flushed file crashed Python as h5py closed it)."""
    size = export(atlas, tmp_path / "whole.nc").stat().st_size
    out = tmp_path / "cut" / "three.nc"
    out.parent.mkdir()
    proc = subprocess.run(
        [*CMD, "atlas", "export", str(atlas), "--out", str(out)],
        capture_output=True,
        text=True,
        preexec_fn=_limit_file_size(int(share * size)),
        timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == f"pydrill atlas export: error: --out {out}: File too large\n"
    assert list(out.parent.iterdir()) == []


def _open(path):
    return [f for f in psutil.Process().open_files() if f.path == str(path)]


@pytest.mark.parametrize("chunks", [None, {}, {"wob": -1}])
def test_closing_the_xarray_view_lets_go_of_the_atlas(atlas, chunks):
    """``ds.close()`` did nothing: what ``safe`` was assigned into had no close of its own,
    and the file stayed open for as long as the dataset lived. With ``chunks``, the view
    holds dask arrays of the atlas's values."""
    with Atlas(atlas) as a:
        ds = a.to_xarray(chunks=chunks)
        assert (ds["bit_mean"].chunks is None) == (chunks is None)
        if chunks is not None:
            with a.to_xarray() as whole:
                assert list(ds.variables) == list(whole.variables)  # the CSV's columns
                xr.testing.assert_identical(ds.load(), whole.load())
    assert _open(atlas) != []  # held by the view
    ds.close()
    assert _open(atlas) == []


@pytest.mark.skipif(shutil.which("ncdump") is None, reason="no ncdump (Debian: netcdf-bin)")
def test_netcdf_c_reads_an_export_made_by_blocks(atlas, tmp_path, monkeypatch):
    """Debian's ncdump (netCDF-C) prints the blocks' export as the whole one's."""
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 10**9)
    whole = export(atlas, tmp_path / "whole.nc")
    monkeypatch.setattr(cli_atlas_export, "BLOCK_POINTS", 50)
    blocks = export(atlas, tmp_path / "blocks.nc")

    def dump(path):
        text = subprocess.run(["ncdump", str(path)], capture_output=True, text=True, check=True)
        return text.stdout.split("\n", 1)[1]  # after "netcdf NAME {"

    shown = dump(blocks)
    assert shown == dump(whole) and "regime_t regime(wob, torque, bit_damping, initial)" in shown


@pytest.mark.parametrize("chunks", [None, {}])
def test_closing_a_dataset_of_the_pydrill_engine_lets_go_of_the_atlas(atlas, chunks):
    """As ``to_xarray``'s, the engine's dataset (``drop_vars`` of it) had no close: xarray's
    ``close()`` left the file open."""
    ds = xr.open_dataset(atlas, engine="pydrill", chunks=chunks, drop_variables="message")
    assert _open(atlas) != [] and "message" not in ds
    ds.close()
    assert _open(atlas) == []


def test_a_selection_reads_what_it_selects_and_lets_go_of_the_file(atlas, monkeypatch):
    """``Atlas.sel(torque=...)`` read the whole atlas, then selected (5 s and 750 MB on one of
    10^6 points), and left its view open. A metric is now read at the selected torque only
    (the codes and counts, read whole on opening, aside), and the file let go of."""
    rows: dict[str, int] = {}
    read = h5py.Dataset.__getitem__

    def counted(self, key, *args, **kwargs):
        out = read(self, key, *args, **kwargs)
        if self.name in ("/bit_mean", "/eigenvalues_real") and isinstance(out, np.ndarray):
            rows[self.name] = max(rows.get(self.name, 0), out.size)
        return out

    monkeypatch.setattr(h5py.Dataset, "__getitem__", counted)
    with Atlas(atlas) as a:
        ds = a.sel(torque=8.3, method="nearest", initial="rest")
        assert _open(atlas) != []  # the Atlas's own
    assert _open(atlas) == []
    assert dict(ds.sizes) == {"wob": 23, "bit_damping": 3, "equilibrium": 2, "eigenvalue": 4}
    # one torque, one start: 23 x 3 points (the eigenvalues: x 2 steady states x 4)
    assert rows == {"/bit_mean": 23 * 3, "/eigenvalues_real": 23 * 3 * 2 * 4}
    with Atlas(atlas) as a:
        whole = a.to_xarray().load()
    picked = whole.sel(torque=8.3, method="nearest").sel(initial="rest")
    np.testing.assert_array_equal(ds["bit_mean"].values, picked["bit_mean"].values)
    assert ds["regime_name"].dims == ("wob", "bit_damping")


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_an_export_shows_its_progress_on_a_terminal_only(atlas, tmp_path, suffix):
    """10^6 points take a minute to CSV, which the command spent silent: on a terminal a bar
    counts the points (1311) to the end; a pipe or a log gets none."""
    from test_cli_field_progress import on_terminal

    out, err = on_terminal("atlas", "export", atlas, "--out", tmp_path / f"a{suffix}")
    assert "export: 100%" in err and "1311/1311" in err and "pt/s" in err, err
    assert out == f"wrote {tmp_path / f'a{suffix}'}\n"
    piped = subprocess.run(
        [*CMD, "atlas", "export", str(atlas), "--out", str(tmp_path / f"b{suffix}")],
        capture_output=True,
        text=True,
    )
    assert piped.returncode == 0 and piped.stderr == ""


def test_a_netcdf_export_stops_soon_after_the_disk_fills_up(tmp_path, monkeypatch):
    """The disk fills up with 30 % of the file written: the export stops at its next task,
    HDF5 closing the file into memory (what its caches held), and says so. It went on to the
    end, all of the rest kept in memory for nothing: 24 MB of this 32 MB file (and 190 MB,
    13 s, of an atlas of 10^6 points)."""
    spec = SPEC.replace("num = 23", "num = 400").replace("num = 19", "num = 200")
    source = synthetic_atlas(
        tmp_path / "big.h5", spec.replace("bit_damping = [0.02, 0.05, 0.08]", "")
    )
    whole = export(source, tmp_path / "whole.nc").stat().st_size
    limit = int(0.3 * whole)
    write = os.pwrite

    def full_disk(fd, data, offset):
        if offset + len(data) > limit:
            raise OSError(errno.ENOSPC, "No space left on device")
        return write(fd, data, offset)

    kept: list[int] = []
    close = SinkFile.close

    def closing(self):
        kept.append(sum(len(chunk) for _, chunk in self.later))
        close(self)

    monkeypatch.setattr(export_file.os, "pwrite", full_disk)
    monkeypatch.setattr(SinkFile, "close", closing)
    out = tmp_path / "cut" / "big.nc"
    out.parent.mkdir()
    with pytest.raises(OSError, match="No space left on device") as failed:
        export(source, out)
    assert failed.value.filename == str(out) and list(out.parent.iterdir()) == []
    assert len(kept) == 1 and 0 < kept[0] < 0.25 * (whole - limit), (kept, whole - limit)
