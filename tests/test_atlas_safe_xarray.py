"""The safe region as data: ``safe`` in ``Atlas.to_xarray()``, the netCDF export and the CSV,
against a brute-force reading of the raw datasets (every start steady, the fastest steady
state with no eigenvalue in the right half-plane). A researcher plotting the safe W_ob window
against depth had to rebuild it from the regime codes and the eigenvalue counts."""

import csv
import json
import subprocess

import h5py
import numpy as np
import pytest
from sweeping import CMD

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# Three axes, so that the variable's dimensions and their order are tested too.
GRID = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
mu_static = [0.8, 0.85]
wob = [20.0, 40.0, 60.0, 80.0, 100.0, 120.0]
torque = [6.0, 8.3, 10.0, 14.0]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
"""


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("safe-xr") / "grid.h5"
    run_sweep(parse_spec(GRID), out, serial=True)
    return out


def _brute(path):
    with h5py.File(path, "r") as f:
        steady = np.all(f["regime"][...] == fmt.REGIMES["steady"], axis=-1)
        safe = steady & (f["unstable"][..., 0] == 0)
        axes = {n: f[n][...] for n in json.loads(f.attrs["axes"])}
    return safe, axes


def test_to_xarray_holds_the_safe_region_on_the_axes(atlas):
    want, axes = _brute(atlas)
    assert 0 < want.sum() < want.size  # something safe, something not
    with Atlas(atlas) as a:
        ds = a.to_xarray()
        assert ds["safe"].dims == tuple(axes)
        assert np.array_equal(ds["safe"].values.astype(bool), want)
        assert ds["safe"].attrs["flag_meanings"] == "unsafe safe"
        assert "units" not in ds["safe"].attrs  # CF flags: no units (it took unstable's "1")
        # selected by value, as a researcher does
        k = int(np.argmin(np.abs(axes["torque"] - 8.3)))
        row = ds["safe"].sel(mu_static=0.85, torque=8.3).values
        assert np.array_equal(row.astype(bool), want[1, :, k])


def test_the_exports_hold_it_too(atlas, tmp_path):
    want, axes = _brute(atlas)
    nc, table = tmp_path / "grid.nc", tmp_path / "grid.csv"
    for out in (nc, table):
        subprocess.run([*CMD, "atlas", "export", str(atlas), "--out", str(out)], check=True)
    with h5py.File(nc, "r") as f:
        assert np.array_equal(f["safe"][...].astype(bool), want)
    with open(table, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == want.size * 2  # a row per point and start
    for row in rows:
        index = tuple(
            int(np.argmin(np.abs(axes[n] - float(row[n])))) for n in ("mu_static", "wob", "torque")
        )
        assert row["safe"] == str(int(want[index]))


def test_without_stability_there_is_no_safe_variable(tmp_path):
    out = tmp_path / "blind.h5"
    run_sweep(parse_spec(GRID + "[record]\nstability = false\n"), out, serial=True)
    with Atlas(out) as a:
        assert "safe" not in a.to_xarray()


def test_atlas_query_json_says_whether_the_point_is_safe(atlas, tmp_path):
    """A script asking one point had no 'safe' to read: it is what the raw datasets say, at a
    safe point and an unsafe one, and null without stability recorded."""
    want, axes = _brute(atlas)
    picks = [np.argwhere(want)[0], np.argwhere(~want)[-1]]

    def query(path, point):
        options = [f"--set={n}={float(axes[n][k])!r}" for n, k in zip(axes, point, strict=True)]
        proc = [*CMD, "atlas", "query", str(path), *options, "--json"]
        return json.loads(subprocess.run(proc, capture_output=True, text=True, check=True).stdout)

    for point in picks:
        assert query(atlas, point)["safe"] is bool(want[tuple(point)])
    blind = tmp_path / "blind.h5"
    run_sweep(parse_spec(GRID + "[record]\nstability = false\n"), blind, serial=True)
    assert query(blind, picks[0])["safe"] is None
