"""The CSV export's cells (``_core.csv_rows``, pydrill.export_csv): the text pandas' to_csv
writes, byte for byte; floats as Python's repr writes them."""

import io
import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from pydrill import _core, export_csv
from pydrill.atlas import COUNT_FIELDS
from pydrill.export_csv import name_codes, write_csv

EDGES = [0.0, -0.0, 1.0, -1.0, 0.1, 2.5, 100.0, 1e-4, 1e-5, 9.999e-5, 1e15, 1e16, 123456789.0]
EDGES += [9999999999999998.0, 1e22, 1e-300, 5e-324, 2.2250738585072014e-308]
EDGES += [1.7976931348623157e308, -1e-5, 1 / 3, 2**53, 2**53 + 2, math.pi * 1e-7]


def cells(columns, rows) -> list[list[str]]:
    text = _core.csv_rows(columns, rows).decode()
    assert text.endswith("\n") or rows == 0
    return [line.split(",") for line in text.splitlines()]


def test_floats_are_written_as_pythons_repr():
    """Against Python's own repr (David Gay's shortest digits, its own layout): any bit
    pattern of a double (subnormals and huge exponents among them) and the layout's edges
    (where fixed turns scientific: 1e-4 / 1e-5, 1e15 / 1e16)."""
    rng = np.random.default_rng(7)
    patterns = rng.integers(0, 2**63, size=50_000, dtype=np.int64).view(np.float64)
    patterns = patterns[np.isfinite(patterns)]
    patterns *= rng.choice([-1.0, 1.0], patterns.size)  # and the sign bit
    scaled = rng.random(50_000) * 10.0 ** rng.integers(-25, 25, 50_000).astype(float)
    values = np.concatenate([EDGES, patterns, scaled, np.round(scaled, 3)])
    got = [row[0] for row in cells([("float", values)], values.size)]
    assert got == [repr(float(v)) for v in values]


def test_missing_and_infinite_values_and_the_other_kinds():
    floats = np.array([np.nan, np.inf, -np.inf, 1.5])
    counts = np.array([3.0, np.nan, 0.0, 2.0**52])
    ints = np.array([-128, 0, 255, 2**62], dtype=np.int64)
    codes = np.array([1, -1, 0, 2])
    labels = ["steady", "", '"a, b"']
    columns = [("float", floats), ("count", counts), ("int", ints), ("text", (codes, labels))]
    assert cells(columns, 4) == [
        ["", "3", "-128", ""],
        ["inf", "", "0", ""],
        ["-inf", "0", "255", "steady"],
        ["1.5", str(2**52), str(2**62), '"a', ' b"'],  # (split on the quoted comma)
    ]
    assert _core.csv_rows([], 3) == b"\n\n\n" and _core.csv_rows([("int", ints[:0])], 0) == b""


@pytest.mark.parametrize(
    ("columns", "said"),
    [
        ([("real", np.zeros(2))], "kind must be float, int, count or text, got real"),
        ([("float", np.zeros(3))], "one value per row"),
        ([("float", np.zeros((2, 1)))], "1-D"),
        ([("text", (np.array([0, 2]), ["a", "b"]))], "a text code has no label"),
        ([("text", (np.array([0, -2]), ["a"]))], "a text code has no label"),
        ([("float",)], "a column is (kind, values)"),
    ],
)
def test_a_malformed_column_is_refused(columns, said):
    with pytest.raises(ValueError, match=said.replace("(", r"\(").replace(")", r"\)")):
        _core.csv_rows(columns, 2)


class Bar:
    def __init__(self, total):
        self.total, self.n = total, 0

    def update(self, k):
        self.n += k


def test_an_atlas_like_table_is_what_pandas_writes(monkeypatch):
    """Every kind of column an atlas's table has (float64 with NaN, int8/uint8 codes, counts
    with missing ones, the start's names, messages with commas, quotes and line breaks, a
    bool, a float32), written in blocks of rows: the bytes pandas' to_csv writes of the whole
    table (pydrill's export until December 2026)."""
    rng = np.random.default_rng(3)
    wob, torque, initial = np.linspace(1, 300, 7), np.array([0.1, 8.3, 30.0]), ["rest", "eq"]
    shape = (7, 3, 2)
    size = math.prod(shape)
    metric = rng.normal(size=shape) * 10.0 ** rng.integers(-6, 18, shape).astype(float)
    metric[rng.random(shape) < 0.2] = np.nan
    events = rng.integers(0, 40, shape).astype(float)
    events[rng.random(shape) < 0.3] = np.nan
    messages = np.array(
        ["", "solver failed at t = 3.2, step 1e-12", 'said "no"', "two\nlines", "é ü"], dtype=object
    )[rng.integers(0, 5, shape)]
    dims = ("wob", "torque", "initial")
    ds = xr.Dataset(
        {
            "regime": (dims, rng.integers(0, 3, shape).astype(np.int8)),
            "status": (dims, rng.integers(0, 3, shape).astype(np.uint8)),
            "message": (dims, messages),
            "bit_mean": (dims, metric),
            "stick_events": (dims, events),
            "ratio32": (dims, rng.random(shape).astype(np.float32)),
            "flag": (dims, rng.random(shape) < 0.5),
            "caveat": (dims, rng.integers(0, 2, shape).astype(np.int8)),
            "eigenvalues_real": ((*dims, "eigenvalue"), rng.random((*shape, 2))),
        },
        coords={"wob": wob, "torque": torque, "initial": initial},
    )
    assert "stick_events" in COUNT_FIELDS
    expected = ds.drop_vars("eigenvalues_real").to_dataframe(list(dims))
    expected["stick_events"] = expected["stick_events"].astype("Int64")
    name_codes(expected)
    monkeypatch.setattr(export_csv, "LINES", 5)  # each block's text in several pieces
    out = io.BytesIO()
    bar = Bar(size // 2)  # points: (wob, torque) pairs
    write_csv(ds, out, "wob", 3, bar)  # blocks of 3, 3 and 1 rows of wob
    assert out.getvalue().decode() == expected.to_csv()
    assert bar.n == bar.total
    back = pd.read_csv(io.BytesIO(out.getvalue()), keep_default_na=False)
    assert len(back) == size and list(back.columns[:3]) == list(dims)


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    from sweeping import SMALL

    from pydrill.spec import parse_spec
    from pydrill.sweep import run_sweep

    out = tmp_path_factory.mktemp("atlas") / "small.h5"
    run_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 20.0")), out, serial=True)
    return out


@pytest.mark.parametrize("suffix", [".csv", ".nc"])
def test_export_json_says_what_the_file_holds(small_atlas, suffix, tmp_path, capsys):
    """Against the file itself: its rows (CSV, read back by pandas) or variables (netCDF,
    read back by h5py), its size on disk, the atlas's points."""
    import json

    import h5py

    from pydrill.atlas import Atlas
    from pydrill.cli import main

    out = tmp_path / f"small{suffix}"
    assert main(["atlas", "export", str(small_atlas), "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["atlas"] == str(small_atlas) and data["out"] == str(out)
    assert data["bytes"] == out.stat().st_size and data["units"] == {"bytes": "B"}
    with Atlas(small_atlas) as atlas:
        assert data["points"] == math.prod(atlas.shape)
        starts = len(atlas.initials)
    if suffix == ".csv":
        assert data["format"] == "csv"
        assert data["rows"] == len(pd.read_csv(out)) == data["points"] * starts
    else:
        assert data["format"] == "netcdf"
        with h5py.File(out, "r") as f:
            written = {k for k, v in f.items() if isinstance(v, h5py.Dataset)}
        assert set(data["variables"]) <= written and "regime" in data["variables"]
        axes = {"wob", "torque", "initial", "eigenvalue", "equilibrium"}  # dimensions
        assert written - set(data["variables"]) <= axes
