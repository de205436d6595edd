"""Atlas edges found by an audit: failed points, message coordinates, one-value axes,
damaged attributes and datasets, journals without their atlas, refused sweeps' directories."""

import csv
import json
import re
import subprocess

import dask
import h5py
import numpy as np
import pytest
import xarray as xr
from sweeping import CMD, SMALL, TINY

from pydrill.atlas import Atlas
from pydrill.journal import journal_path
from pydrill.spec import parse_spec
from pydrill.sweep import AtlasError, run_sweep

# One point fails: (100 N, 8.3 N·m), whose stick-slip needs more than 900 steps.
FAILING = SMALL.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]\nmax_steps = 900')


def run(*args):
    return subprocess.run([*CMD, *map(str, args)], capture_output=True, text=True)


@pytest.fixture(scope="module")
def failing_atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("failing") / "f.h5"
    report = run_sweep(parse_spec(FAILING), out, serial=True)
    assert 0 < report.failed < report.points
    return out


def test_a_failed_point_reads_as_failed_everywhere(failing_atlas, tmp_path):
    with Atlas(failing_atlas) as atlas:
        bad = atlas.value(wob=100.0, torque=8.3)
        assert bad["status"] == "failed"
        assert bad["regime"] == {"rest": "failed"}  # was "missing": as if never computed
        assert atlas.summary()["regimes"]["rest"].get("missing", 0) == 0
    text = run("atlas", "query", failing_atlas, "--wob", "100", "--torque", "8.3")
    assert text.returncode == 0
    assert "failed" in text.stdout and "max_steps" in text.stdout  # the message, not only JSON
    out = tmp_path / "f.csv"
    assert run("atlas", "export", failing_atlas, "--out", out).returncode == 0
    with out.open() as fh:
        rows = list(csv.DictReader(fh))
    failed = [r for r in rows if r["regime_name"] == "failed"]
    assert failed and all("max_steps" in r["message"] for r in failed)
    assert all(r["message"] == "" for r in rows if r["regime_name"] != "failed")


def test_message_has_the_atlas_axes_in_xarray(failing_atlas):
    # Without its dimension scales h5netcdf named the dimensions of ``message`` after the
    # first of the same length: ('eigenvalue', 'torque') for this 3 x 2 grid.
    ds = xr.open_dataset(failing_atlas, engine="h5netcdf")
    assert ds["message"].dims == ("wob", "torque")
    assert "max_steps" in str(ds["message"].sel(wob=100.0, torque=8.3).item())
    ds.close()


def test_an_older_atlas_without_message_scales_still_gets_the_right_dimensions(
    failing_atlas, tmp_path
):
    old = tmp_path / "old.h5"
    old.write_bytes(failing_atlas.read_bytes())
    with h5py.File(old, "r+") as f:
        for axis, name in enumerate(("wob", "torque")):
            f["message"].dims[axis].detach_scale(f[name])
    with Atlas(old) as atlas:
        ds = atlas.to_xarray()
        assert ds["message"].dims == ("wob", "torque")
        assert "max_steps" in str(ds["message"].sel(wob=100.0, torque=8.3).item())


def test_nearest_on_a_one_value_axis_is_no_wider_than_that_value(tmp_path):
    out = tmp_path / "one.h5"
    spec = SMALL.replace("wob = [40.0, 100.0, 160.0]", "wob = [40.0]").replace(
        "torque = [6.0, 8.3]", "torque = [8.3]"
    )
    run_sweep(parse_spec(spec.replace("t_end = 200.0", "t_end = 20.0")), out, serial=True)
    with Atlas(out) as atlas:
        assert atlas.value("nearest", wob=40.0, torque=8.3)["status"] == "done"
        with pytest.raises(KeyError, match=r"wob = 99999 N is outside the atlas \(only 40 N\)"):
            atlas.value("nearest", wob=99999.0, torque=8.3)
    proc = run("atlas", "query", out, "--wob", "99999", "--torque", "-500", "--nearest")
    assert proc.returncode == 2 and "outside the atlas" in proc.stderr and not proc.stdout


def test_a_damaged_attribute_or_a_lost_dataset_is_named(failing_atlas, tmp_path):
    bad_attr = tmp_path / "attr.h5"
    bad_attr.write_bytes(failing_atlas.read_bytes())
    with h5py.File(bad_attr, "r+") as f:
        f.attrs["axes"] = "not json"
    with pytest.raises(AtlasError, match=r"attr\.h5 is damaged"):
        Atlas(bad_attr)
    lost = tmp_path / "lost.h5"
    lost.write_bytes(failing_atlas.read_bytes())
    with h5py.File(lost, "r+") as f:
        del f["coexistence"]
    with pytest.raises(AtlasError, match=r"lost\.h5 is damaged or incomplete: .*coexistence"):
        Atlas(lost)
    for command in ("info", "plot"):
        extra = ["--out", tmp_path / "x.png"] if command == "plot" else []
        proc = run("atlas", command, lost, *extra)
        assert proc.returncode == 2, proc.stderr
        assert "coexistence" in proc.stderr and "Traceback" not in proc.stderr


def test_a_journal_without_its_atlas_is_named_for_what_it_is(tmp_path):
    out = tmp_path / "j.h5"
    journal_path(out).write_text(json.dumps({"spec_digest": "0123456789abcdef"}) + "\n")
    with pytest.raises(AtlasError, match=r"j\.h5\.journal belongs to another sweep"):
        run_sweep(parse_spec(SMALL), out, serial=True, resume=True)
    assert not out.exists()  # an empty atlas used to be left beside it
    spec = parse_spec(SMALL)
    journal_path(out).write_text(json.dumps({"spec_digest": spec.digest}) + "\n")
    with pytest.raises(AtlasError, match=r"holds an interrupted sweep of this spec.*resume=True"):
        run_sweep(spec, out, serial=True)
    assert not out.exists()


def test_a_refused_sweep_leaves_no_directory_behind(tmp_path):
    out = tmp_path / "new" / "deeper" / "x.h5"
    # Nothing listens on port 1; Dask's client would wait its 30 s for a scheduler to start.
    # distributed first: a config.set of a key whose section is not loaded yet deletes the
    # whole section on the way out, defaults loaded meanwhile included (then every later
    # LocalCluster of the session fails with KeyError: 'distributed').
    import distributed  # noqa: F401

    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        with pytest.raises(ConnectionError):
            run_sweep(parse_spec(SMALL), out, scheduler="tcp://127.0.0.1:1")
    assert not (tmp_path / "new").exists()


def test_an_axis_given_twice_to_query_is_refused(failing_atlas):
    proc = run(
        "atlas", "query", failing_atlas, "--wob", "40", "--torque", "8.3", "--set", "wob=160"
    )
    assert proc.returncode == 2 and not proc.stdout
    assert "wob is given twice" in proc.stderr


def test_export_into_a_missing_folder_is_refused_as_every_output_file_is(failing_atlas, tmp_path):
    # A typo in a folder's name made folders where nobody looked: refused, nothing made.
    out = tmp_path / "exports" / "f.nc"
    proc = run("atlas", "export", failing_atlas, "--out", out)
    assert proc.returncode == 2 and "there is no folder" in proc.stderr
    assert not out.parent.exists()
    out.parent.mkdir()
    assert run("atlas", "export", failing_atlas, "--out", out).returncode == 0
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds["regime"].dims == ("wob", "torque", "initial")
    ds.close()


def test_a_map_with_a_one_value_axis_draws_its_cells(tmp_path):
    # shading="nearest" has no step to take along a one-value axis: the map was empty, with a
    # warning about identical limits. Now each value gets its cell.
    from matplotlib.collections import QuadMesh

    out = tmp_path / "row.h5"
    spec = SMALL.replace("torque = [6.0, 8.3]", "torque = [8.3]").replace(
        "t_end = 200.0", "t_end = 100.0"
    )
    run_sweep(parse_spec(spec), out, serial=True)
    with Atlas(out) as atlas:
        regimes = atlas.regimes("rest")[:, 0]
        fig = atlas.plot()
        metric_fig = atlas.plot("severity")
    for f in (fig, metric_fig):
        ax = f.axes[0]
        (mesh,) = [c for c in ax.collections if isinstance(c, QuadMesh)]
        assert mesh.get_array().size == 3  # W_ob 40, 100, 160 at u = 8.3
        lo, hi = ax.get_ylim()
        assert lo < 8.3 < hi and hi - lo > 0.1
    # The cells' colours follow the regimes (steady, stick-slip, stuck: the regime map's first
    # three colours), as the paper's Figs. 4, 7 and 9 have them at u = 8.3 N m.
    assert list(regimes) == ["steady", "stick-slip", "stuck"]
    (mesh,) = [c for c in fig.axes[0].collections if isinstance(c, QuadMesh)]
    assert [int(v) for v in mesh.get_array().ravel()] == [0, 1, 2]


def test_an_atlas_whose_spec_is_now_refused_says_so_and_still_reads(failing_atlas, tmp_path):
    # An older pydrill took specs this one refuses (here a lump without a tally): the atlas
    # used to be called "damaged or incomplete", as if its data were lost.
    old = tmp_path / "old.h5"
    old.write_bytes(failing_atlas.read_bytes())
    with h5py.File(old, "r+") as f:
        f.attrs["spec"] = f.attrs["spec"].replace("[model]", "[model]\nlump = 3", 1)
    with pytest.raises(AtlasError, match=r"old\.h5: its sweep spec .* is refused by .*lump") as e:
        Atlas(old)
    assert "damaged" not in str(e.value) and "xarray.open_dataset" in str(e.value)
    proc = run("atlas", "info", old)
    assert proc.returncode == 2 and "is refused by pydrill" in proc.stderr
    with xr.open_dataset(old, engine="h5netcdf") as ds, Atlas(failing_atlas) as atlas:
        assert ds["regime"].shape == atlas.to_xarray()["regime"].shape


def test_without_stability_there_is_no_safe_region_rather_than_an_empty_one(tmp_path):
    """``[record] stability = false``: the runs are there (steady ones too), but no point can be
    called safe or unsafe. The region and its count say so instead of "none"."""
    out = tmp_path / "nostab.h5"
    run_sweep(parse_spec(SMALL + "[record]\nstability = false\n"), out, serial=True)
    with Atlas(out) as atlas:
        assert atlas.summary()["regimes"]["rest"]["steady"] > 0
        with pytest.raises(ValueError, match="did not record stability"):
            atlas.safe_region()
        assert atlas.summary()["safe_points"] is None
    info = subprocess.run(
        [*CMD, "atlas", "info", str(out)], capture_output=True, text=True, check=True
    ).stdout
    assert "safe points unknown (stability not recorded)" in info
    out2 = tmp_path / "stab.h5"  # the same sweep with stability: a region, and steady points in it
    run_sweep(parse_spec(SMALL), out2, serial=True)
    with Atlas(out2) as atlas:
        assert 0 < atlas.summary()["safe_points"] == int(atlas.safe_region().sum())


def test_sel_nearest_refuses_what_value_refuses(tmp_path):
    """``sel(method="nearest")`` once answered torque = 100 with the grid's 8.3 (the grid runs
    6 ... 8.3), where ``value`` says it is outside the atlas."""
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    with Atlas(out) as atlas:
        for coords in ({"torque": 100.0}, {"torque": [6.0, 100.0]}, {"wob": -50.0}):
            with pytest.raises(KeyError, match="is outside the atlas"):
                atlas.sel(method="nearest", **coords)
        with pytest.raises(KeyError, match="is outside the atlas"):
            atlas.value(method="nearest", wob=100.0, torque=100.0)
        # within half a grid step of an end it is the end, as value() says
        near = atlas.sel(method="nearest", torque=8.9, initial="rest")
        assert float(near.torque) == 8.3
        assert atlas.value(method="nearest", wob=100.0, torque=8.9)["coords"]["torque"] == 8.3


def test_an_atlas_shows_its_file_grid_and_starts_in_a_notebook(tmp_path):
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    atlas = Atlas(out)
    assert repr(atlas) == (
        f"<pydrill.Atlas {str(out)!r}: 6 points (wob 3 x torque 2), from rest, equilibrium>"
    )
    atlas.close()
    assert repr(atlas).endswith("from rest, equilibrium, closed>")


def test_coordinates_take_units_as_the_command_line_does(tmp_path):
    """``value(wob="0.1 kN")`` is the point at 100 N (as ``--wob '0.1 kN'``); a unit of the
    wrong kind, or a coordinate that is not a number, is refused by name."""
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    with Atlas(out) as atlas:
        plain = atlas.value(wob=100.0, torque=8.3)
        assert atlas.value(wob="0.1 kN", torque="8.3 N*m") == plain
        assert atlas.value(wob=np.float32(100.0), torque=np.array(8.3)) == plain
        sliced = atlas.sel(wob="0.1 kN", initial="rest")
        assert float(sliced.wob) == 100.0
        with pytest.raises(ValueError, match="wob = '80 m': unit 'm' is not a force unit"):
            atlas.value(wob="80 m", torque=8.3)
        with pytest.raises(TypeError, match="torque = None is not allowed: a number"):
            atlas.value(wob=100.0, torque=None)
        with pytest.raises(TypeError, match="wob = True is not allowed"):
            atlas.value(wob=True, torque=8.3)


@pytest.fixture(scope="module")
def unstable_free_atlas(tmp_path_factory):
    """An atlas swept with ``[record] stability = false``: runs, no steady states."""
    out = tmp_path_factory.mktemp("nostab") / "nostab.h5"
    spec = SMALL.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]')
    run_sweep(parse_spec(spec + "[record]\nstability = false\n"), out, serial=True)
    return out


@pytest.fixture(scope="module")
def unstable_free_plain_map(unstable_free_atlas, tmp_path_factory):
    """``pydrill atlas plot`` of that atlas with no --metric (the same command for every case
    below, run once): the finished process."""
    out = tmp_path_factory.mktemp("nostab-map") / "p.png"
    return run("atlas", "plot", unstable_free_atlas, "--out", out)


@pytest.mark.parametrize("metric", ["omega_eq", "spectral_abscissa", "hopf_margin", "unstable"])
def test_a_stability_metric_of_an_atlas_without_stability_is_refused(
    unstable_free_atlas, unstable_free_plain_map, tmp_path, metric
):
    """``--metric omega_eq`` on such an atlas drew an all-grey map with a 0-1 colour bar."""
    out = tmp_path / "p.png"
    proc = run("atlas", "plot", unstable_free_atlas, "--out", out, "--metric", metric)
    assert proc.returncode == 2 and not out.exists()
    assert proc.stderr.strip() == (
        f"pydrill atlas plot: error: --metric {metric}: this atlas did not record stability "
        "([record] stability = false)"
    )
    with Atlas(unstable_free_atlas) as atlas:
        with pytest.raises(ValueError, match="this atlas did not record stability"):
            atlas.plot(metric=metric)
        atlas.plot(metric="severity")  # what the runs hold is still mapped
    assert unstable_free_plain_map.returncode == 0, unstable_free_plain_map.stderr


def test_regime_flags_are_named_alike_in_every_format(failing_atlas, tmp_path):
    """The .h5 said ``stick-slip no-steady-state``, to_xarray() and the .nc export
    ``stick_slip no_steady_state``: the names pydrill reports (simulate, CSV, the CLI) are the
    hyphenated ones, and CF's flag_meanings only need blanks between them."""
    from pydrill import atlas_format as fmt

    names = " ".join(fmt.REGIMES)
    with h5py.File(failing_atlas, "r") as f:
        h5 = dict(f["regime"].attrs), dict(f["caveat"].attrs)
    nc = tmp_path / "f.nc"
    assert run("atlas", "export", failing_atlas, "--out", nc).returncode == 0
    with Atlas(failing_atlas) as atlas, xr.open_dataset(nc, engine="h5netcdf") as exported:
        xa = atlas.to_xarray()
        found = [(h5[0], h5[1]), (xa.regime.attrs, xa.caveat.attrs)]
        found.append((exported.regime.attrs, exported.caveat.attrs))
        for regime, caveat in found:
            assert regime["flag_meanings"] == names
            assert regime["flag_values"].tolist() == list(fmt.REGIMES.values())
            assert caveat["flag_meanings"] == " ".join(k or "none" for k in fmt.CAVEATS)
            assert regime["long_name"] and caveat["long_name"]
        # The codes read through the meanings are the names pydrill gives.
        meanings = dict(zip(regime["flag_values"].tolist(), names.split(), strict=True))
        code = int(exported.regime.sel(wob=40.0, torque=6.0, initial="rest"))
        assert meanings[code] == atlas.value(wob=40.0, torque=6.0)["regime"]["rest"]


def test_sel_off_the_grid_says_so_as_value_does(tmp_path):
    """``sel(torque=8.4)`` passed on xarray's bare ``KeyError: 8.4``."""
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    with Atlas(out) as atlas:
        message = re.escape(
            "torque = 8.4 N·m is not on the grid (nearest 8.3 N·m); use method='nearest'"
        )
        with pytest.raises(KeyError, match=message):
            atlas.value(wob=100.0, torque=8.4)
        with pytest.raises(KeyError, match=message):
            atlas.sel(torque=8.4)
        with pytest.raises(KeyError, match=message):
            atlas.sel(torque=[6.0, 8.4])
        # On the grid as value() takes it (float32's 8.3 is 8.30000019): that grid point.
        row = atlas.sel(torque=np.float32(8.3), initial="rest")
        assert float(row.torque) == 8.3 and row.regime.shape == (3,)
        assert float(atlas.sel(wob="0.1 kN", torque=8.3, initial="rest").wob) == 100.0


def test_plot_errors_list_axes_as_query_does_and_one_point_is_a_point(tmp_path):
    """The map's errors printed ``['wob', 'torque']`` (query: ``wob, torque``); a one-point
    atlas's title said "(1 points)"."""
    out = tmp_path / "one.h5"
    one = TINY.replace("wob = [40.0, 100.0, 160.0]", "wob = [100.0]")
    run_sweep(parse_spec(one.replace("torque = [6.0, 8.3]", "torque = [8.3]")), out, serial=True)
    with Atlas(out) as atlas:
        with pytest.raises(ValueError) as e:
            atlas.plot(x="depth")
        assert str(e.value) == "x = 'depth' is not an axis of this atlas; axes: wob, torque"
        # a misspelt axis: named with the one it was probably meant to be, in every call
        with pytest.raises(ValueError) as e:
            atlas.plot(x="torqe")
        hint = "is not an axis of this atlas (did you mean 'torque'?); axes: wob, torque"
        assert str(e.value) == f"x = 'torqe' {hint}"
        for call in (
            lambda: atlas.value(wob=100.0, torqe=8.3),
            lambda: atlas.sel(torqe=8.3),
            lambda: atlas.safe_windows("torqe"),
            lambda: atlas.safe_windows(torqe=8.3),
        ):
            with pytest.raises(KeyError) as e:
                call()
            assert e.value.args[0].removesuffix(", initial") == f"torqe {hint}"  # sel: initial too
        with pytest.raises(ValueError) as e:
            atlas.plot(at={"wob": 100.0, "torque": 8.3})
        assert str(e.value) == "no axis left to draw: wob, torque are all given as x, y or held"
        title = atlas.plot().axes[0].get_title()
    assert title.endswith("(1 point)"), title


@pytest.mark.parametrize("damage", ["removed", "truncated"])
def test_an_atlas_lost_beside_its_journal_says_the_journal_rebuilds_it(tmp_path, damage):
    """A kill can leave the journal with the points and no (or a cut) atlas: reading it says
    what the journal holds and how to rebuild, where it said only "no such atlas"."""
    out = tmp_path / "a.h5"
    journal = journal_path(out)
    run_sweep(parse_spec(SMALL), out, serial=True)
    lines = [json.dumps({"spec_digest": parse_spec(SMALL).digest})]
    lines += [json.dumps({"i": i, "status": "done", "runs": {}}) for i in (0, 3, 3)]
    journal.write_text("\n".join(lines) + "\n")
    if damage == "removed":
        out.unlink()
    else:
        out.write_bytes(out.read_bytes()[:1000])
    with pytest.raises(AtlasError, match=r"a.h5.journal, holds 2 points of a sweep: 'pydrill"):
        Atlas(out)
    journal.unlink()
    with pytest.raises(AtlasError) as err:
        Atlas(out)
    assert "journal" not in str(err.value)


def test_an_atlas_written_before_caveats_and_added_fields_reads_them_as_unmeasured(tmp_path):
    """read_table gives an atlas without the caveat dataset or the run fields added since
    (top_min, top_max, bit_top_ratio) those columns as not measured (caveat 0, the field's
    fill), its other columns as written (--resume and merge read atlases so)."""
    from pydrill import atlas_format as fmt

    spec = parse_spec(TINY)
    out = tmp_path / "old.h5"
    run_sweep(spec, out, serial=True)
    whole = fmt.read_table(out, spec)
    with h5py.File(out, "r+") as f:
        for name in ("caveat", *fmt.ADDED_RUN_FIELDS):
            del f[name]
    old = fmt.read_table(out, spec)
    assert not old.caveat.any() and old.caveat.shape == whole.caveat.shape
    for name in fmt.ADDED_RUN_FIELDS:
        fill = fmt.RUN_FIELDS[name][1]
        assert old.runs[name].shape == whole.runs[name].shape
        np.testing.assert_array_equal(old.runs[name], np.full_like(whole.runs[name], fill))
    for name, column in whole.columns().items():
        if name != "caveat" and name.removeprefix("run:") not in fmt.ADDED_RUN_FIELDS:
            np.testing.assert_array_equal(old.columns()[name], column, err_msg=name)
    assert old.points is None and old.eig.dtype == np.complex128
