"""What an audit of the atlas API found: axes and starts that could be changed under the
queries, chunks xarray takes but to_xarray refused, one error class for a coordinate the
atlas has not, type hints, a merge of one path taken letter by letter, the CLI's advice to use
--nearest where it is refused, missing points drawn white and exported without a word."""

import inspect
import json
import re
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest
import xarray as xr
from sweeping import CMD, SMALL

import pydrill
from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas, CoordinateError
from pydrill.journal import journal_path
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

WOB = [40.0, 100.0, 160.0]  # SMALL's grid
TORQUE = [6.0, 8.3]


def run(*args):
    return subprocess.run([*CMD, *map(str, args)], capture_output=True, text=True)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    out = tmp_path_factory.mktemp("audit") / "small.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    return out


@pytest.fixture(scope="module")
def partial(small, tmp_path_factory):
    """``small`` with three of its six points missing, as a stopped sweep leaves them (the
    journal beside it): status and regime marked missing, in the file itself."""
    out = tmp_path_factory.mktemp("partial") / "mid.h5"
    shutil.copy(small, out)
    with h5py.File(out, "r+") as f:
        status, regime = f["status"][...], f["regime"][...]
        status[1:, 0] = fmt.STATUS["missing"]  # (100 N, 6 N·m) and (160 N, 6 N·m)
        status[2, 1] = fmt.STATUS["missing"]
        regime[status == fmt.STATUS["missing"]] = fmt.REGIMES["missing"]
        f["status"][...], f["regime"][...] = status, regime
    journal_path(out).write_text("")
    return out


# 1. axes and initials cannot be changed under the queries


def test_axes_and_initials_are_read_only(small):
    with h5py.File(small, "r") as f:
        on_file = {name: f[name][...].tolist() for name in ("wob", "torque")}
    with Atlas(small) as atlas:
        before = atlas.safe_windows(torque=8.3)
        w = atlas.axes["wob"]
        with pytest.raises(ValueError, match="read-only"):
            w /= 1000
        with pytest.raises(ValueError):
            w.setflags(write=True)  # a view of a read-only array: stays read-only
        with pytest.raises(TypeError):
            atlas.axes["foo"] = np.array([1.0])  # type: ignore[index]
        with pytest.raises(AttributeError):
            atlas.axes = {}  # type: ignore[misc]
        assert isinstance(atlas.initials, tuple)
        with pytest.raises(AttributeError):
            atlas.initials.append("x")  # type: ignore[attr-defined]
        copy = np.array(atlas.axes["wob"])  # a copy to change, changing nothing of the atlas
        copy /= 1000
        assert {n: v.tolist() for n, v in atlas.axes.items()} == on_file
        assert atlas.initials == ("rest", "equilibrium")
        assert atlas.value(wob=100, torque=8.3)["coords"] == {"wob": 100.0, "torque": 8.3}
        with pytest.raises(CoordinateError, match="outside the atlas"):
            atlas.value(wob=0.1, torque=8.3)
        assert atlas.index(wob=160, torque=6) == (2, 0)
        assert atlas.safe_windows(torque=8.3) == before
        assert atlas.summary()["initial"] == ["rest", "equilibrium"]  # JSON-like, as before


# 2. to_xarray takes the chunks xarray.open_dataset takes


@pytest.mark.parametrize("chunks", ["auto", 1, -1, None, {}, {"wob": 2}])
def test_to_xarray_takes_what_xarray_takes(small, chunks):
    with h5py.File(small, "r") as f:
        bit_mean, status = f["bit_mean"][...], f["status"][...]
    with Atlas(small) as atlas, atlas.to_xarray(chunks=chunks) as ds:
        assert (ds["bit_mean"].chunks is None) == (chunks is None)
        if chunks is not None:  # the messages by the same blocks as the other fields
            assert ds["message"].chunks == ds["status"].chunks
        if chunks == 1:
            assert ds["status"].chunks == ((1, 1, 1), (1, 1))
        np.testing.assert_array_equal(ds["bit_mean"].values, bit_mean)
        np.testing.assert_array_equal(ds["status"].values, status)
        assert ds["message"].values.tolist() == [[""] * 2] * 3


def test_to_xarray_chunks_auto_as_the_engine_does(small):
    with Atlas(small) as atlas, atlas.to_xarray(chunks="auto") as ours:
        with xr.open_dataset(small, engine="pydrill", chunks="auto") as theirs:
            assert ours["bit_mean"].chunks == theirs["bit_mean"].chunks
            xr.testing.assert_identical(ours.load(), theirs.load())


@pytest.mark.parametrize(
    ("chunks", "error", "match"),
    [
        ({"foo": 2}, ValueError, r"'foo' is not a dimension .*: wob, torque, initial"),
        ("big", ValueError, r"chunks = 'big' is not allowed: the only name is 'auto'"),
        (0, ValueError, r"chunks = 0 is not allowed: a size of 1 or more, or -1"),
        (True, TypeError, r"chunks must be a dict .*, got True"),
        ([1], TypeError, r"chunks must be a dict .*, got \[1\]"),
    ],
)
def test_to_xarray_refuses_chunks_it_cannot_make(small, chunks, error, match):
    with Atlas(small) as atlas, pytest.raises(error, match=match):
        atlas.to_xarray(chunks=chunks)


# 3. one error for a coordinate, start or axis the atlas has not


def _raised(call):
    with pytest.raises(Exception) as info:
        call()
    return info.value


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda a: a.regimes("eq"), r"^initial = 'eq' is not in this atlas: \['rest', 'equil"),
        (lambda a: a.plot(initial="eq"), r"^initial = 'eq' is not in this atlas"),
        (lambda a: a.sel(initial="eq"), r"^initial = 'eq' is not in this atlas"),
        (lambda a: a.index(torqe=8.3, wob=40), r"^torqe is not an axis .*'torque'\?\); axes:"),
        (lambda a: a.value(torqe=8.3, wob=40), r"^torqe is not an axis"),
        (lambda a: a.sel(torqe=8.3), r"^torqe is not an axis .*; axes: wob, torque, initial"),
        (lambda a: a.safe_windows("torqe"), r"^torqe is not an axis .*; axes: wob, torque$"),
        (lambda a: a.safe_windows(torqe=8.3), r"^torqe is not an axis"),
        (lambda a: a.plot(x="dof"), r"^x = 'dof' is not an axis of this atlas; axes: wob"),
        # (dof = 4, what the spec holds, is taken, as the CLI's query takes it; another not)
        (lambda a: a.plot(at={"dof": 3}), r"is not an axis of this atlas: its spec holds dof = 4"),
        (lambda a: a.index(wob=40), r"^give a value for every axis; missing: torque$"),
        (lambda a: a.index(wob=float("nan"), torque=8.3), r"^wob = nan is not a number"),
        (lambda a: a.value(wob=40, torque=np.nan, method="nearest"), r"^torque = nan is not a"),
        (lambda a: a.sel(wob=np.nan), r"^wob = nan is not a number"),
        (lambda a: a.safe_windows(torque=np.nan), r"^torque = nan is not a number"),
        (lambda a: a.index(wob=41, torque=8.3), r"^wob = 41 N is not on the grid \(nearest 40"),
        (lambda a: a.sel(wob=41), r"^wob = 41 N is not on the grid \(nearest 40 N\)"),
        (lambda a: a.index(wob="20 kN", torque=8.3), r"^wob = 20000 N is outside the atlas"),
        (lambda a: a.plot(at={"torque": 20}), r"^torque = 20 N·m is outside the atlas"),
    ],
)
def test_a_bad_coordinate_is_one_error_both_key_and_value(small, call, match):
    with Atlas(small) as atlas:
        exc = _raised(lambda: call(atlas))
    assert type(exc) is CoordinateError, exc
    assert isinstance(exc, KeyError) and isinstance(exc, ValueError)
    assert not str(exc).startswith(("'", '"'))  # not KeyError's repr of the message
    assert "nearest" not in str(exc) or "not on the grid" in str(exc)
    assert re.search(match, str(exc)), str(exc)


@pytest.mark.parametrize(
    "call",
    [
        lambda a: a.regimes(0),
        lambda a: a.plot(initial=0),
        lambda a: a.safe_windows(0),
        lambda a: a.index(wob=None, torque=8.3),
    ],
)
def test_a_coordinate_of_the_wrong_type_is_a_type_error(small, call):
    with Atlas(small) as atlas, pytest.raises(TypeError):
        call(atlas)


def test_sel_takes_a_slice_of_grid_values(small):
    with Atlas(small) as atlas:
        by_slice = atlas.sel(wob=slice(40, 100), torque=8.3)
        by_list = atlas.sel(wob=[40.0, 100.0], torque=8.3)
        xr.testing.assert_identical(by_slice, by_list)
        # the ends need not be grid values; a unit, an open end
        assert atlas.sel(wob=slice("0.05 kN", None)).wob.values.tolist() == [100.0, 160.0]
        assert atlas.sel(wob=slice(None, 99)).wob.values.tolist() == [40.0]
        names = atlas.sel(wob=slice(None, None), initial="rest").regime_name.values
        assert names.tolist() == atlas.regimes("rest").tolist()
        for bad, match in [
            (dict(wob=slice(41, 99)), r"selects nothing: no grid value between its ends"),
            (dict(wob=slice(40, 160, 2)), r"a step is not allowed"),
            (dict(wob=slice(40, 160), method="nearest"), r"'nearest' has no meaning.*to_xarray"),
            (dict(initial=slice("rest", None)), r"initial takes names, not a slice"),
        ]:
            with pytest.raises(ValueError, match=match):
                atlas.sel(**bad)


# 4. type hints: what the methods take and return


def test_hints_say_what_is_taken_and_returned():
    def hint(method, name):
        return inspect.signature(method).parameters[name].annotation

    assert hint(Atlas.value, "coords") == hint(Atlas.index, "coords") == "float | str"
    assert inspect.signature(Atlas.sel).return_annotation == "xarray.Dataset"
    assert inspect.signature(Atlas.to_xarray).return_annotation == "xarray.Dataset"
    assert inspect.signature(Atlas.plot).return_annotation == "Figure"
    assert Atlas.axes.fget.__annotations__["return"] == "Mapping[str, NDArray[Any]]"
    assert Atlas.initials.fget.__annotations__["return"] == "tuple[str, ...]"
    # ... named for the type checker alone: importing pydrill imports neither
    code = "import sys, pydrill; print(sorted({'xarray', 'matplotlib'} & set(sys.modules)))"
    assert (
        subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, check=True
        ).stdout.strip()
        == "[]"
    )


# 5. merge_atlases of one path


@pytest.mark.parametrize("parts", ["p1.h5", b"p1.h5"])
def test_merge_of_one_path_is_a_type_error(tmp_path, parts):
    out = tmp_path / "m4.h5"
    with pytest.raises(TypeError, match=r"parts must be a list of atlas paths .*'p1.h5'"):
        pydrill.merge_atlases(parts, out)
    with pytest.raises(TypeError, match="parts must be a list"):
        pydrill.merge_atlases(tmp_path / "p1.h5", out)
    assert not out.exists()


# 6. beyond the grid: outside the atlas, without advising --nearest


def test_beyond_the_grid_says_outside_at_once(small):
    far = run("atlas", "query", small, "--wob", "500", "--torque", "8.3")
    assert far.returncode == 2
    assert "wob = 500 N is outside the atlas (40 N ... 160 N)" in far.stderr
    assert "nearest" not in far.stderr
    near = run("atlas", "query", small, "--wob", "101", "--torque", "8.3")
    assert "wob = 101 N is not on the grid (nearest 100 N); use --nearest" in near.stderr
    # within half a step past an end: not on the grid, and --nearest answers it
    edge = run("atlas", "query", small, "--wob", "189", "--torque", "8.3", "--nearest", "--json")
    assert edge.returncode == 0 and json.loads(edge.stdout)["coords"]["wob"] == 160
    with Atlas(small) as atlas:
        for method in ("exact", "nearest"):
            with pytest.raises(KeyError, match=r"^wob = 500 N is outside the atlas \(40 N"):
                atlas.index(method, wob=500, torque=8.3)
            with pytest.raises(KeyError, match=r"^wob = -1000 N is outside the atlas"):
                atlas.value(method, wob=-1000, torque=8.3)


# 7. missing points drawn grey, with a legend swatch that shows


def test_missing_points_are_drawn_grey_not_white(partial):
    from matplotlib.colors import to_rgba

    with h5py.File(partial, "r") as f:
        missing = f["status"][...] == fmt.STATUS["missing"]  # (wob, torque)
    with Atlas(partial) as atlas:
        fig = atlas.plot()
    ax = fig.axes[0]
    mesh = ax.collections[0]
    colors = mesh.to_rgba(mesh.get_array()).reshape(len(TORQUE), len(WOB), 4)  # (y, x)
    white = np.array(to_rgba("white"))
    for (i, k), gone in np.ndenumerate(missing):
        cell = colors[k, i]
        if gone:
            assert not np.allclose(cell, white), (i, k)
            assert np.ptp(cell[:3]) < 0.05 and 0.6 < cell[0] < 0.95  # a light grey
        else:  # a regime's colour, not the missing grey
            assert not np.allclose(cell, to_rgba("#d5d8dc")), (i, k)
    (swatch,) = [h for h in ax.get_legend().get_patches() if h.get_label() == "missing"]
    assert np.allclose(swatch.get_facecolor(), to_rgba("#d5d8dc"))
    assert not np.allclose(swatch.get_edgecolor(), swatch.get_facecolor())  # edged
    assert not np.allclose(swatch.get_facecolor(), to_rgba(fig.get_facecolor()))


# 8. an export of an atlas with missing points says so


def test_export_of_a_stopped_sweep_says_what_is_missing(partial, small, tmp_path):
    with h5py.File(partial, "r") as f:
        missing = int(np.sum(f["status"][...] == fmt.STATUS["missing"]))
    assert missing == 3
    text = run("atlas", "export", partial, "--out", tmp_path / "mid.csv")
    assert text.returncode == 0 and text.stdout == f"wrote {tmp_path / 'mid.csv'}\n"
    assert text.stderr == (
        "pydrill atlas export: note: 3 of 6 points are missing (exported as missing): a sweep "
        f"into this atlas was stopped; 'pydrill sweep SPEC.toml --out {partial} --resume' "
        "completes it (SPEC.toml: the spec it was swept from)\n"
    )
    as_json = run("atlas", "export", partial, "--out", tmp_path / "mid.nc", "--json")
    results = json.loads(as_json.stdout)
    assert results["missing"] == 3 and results["points"] == 6 and results["format"] == "netcdf"
    assert "3 of 6 points are missing" in as_json.stderr
    whole = run("atlas", "export", small, "--out", tmp_path / "whole.csv", "--json")
    assert whole.stderr == "" and json.loads(whole.stdout)["missing"] == 0
    # without the journal: a guess, and the same remedy
    alone = tmp_path / "alone.h5"
    shutil.copy(partial, alone)
    lone = run("atlas", "export", alone, "--out", tmp_path / "alone.csv")
    assert "3 of 6 points are missing (exported as missing): a stopped sweep? 'pydrill" in (
        lone.stderr
    )
