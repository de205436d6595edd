"""The atlas commands and figures: query, plot, info, export."""

import csv
import json
import stat
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from sweeping import CMD, SMALL

from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep


def test_query_command_json(tmp_path):
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    proc = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "100", "--torque", "8.3", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(proc.stdout)
    assert data["regime"] == "stick-slip"
    assert data["period"] > 0 and data["units"]["period"] == "s"
    kn = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "0.1kN", "--torque", "0.0083 kN·m", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(kn.stdout)["regime"] == "stick-slip"
    miss = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "99", "--torque", "8.3"],
        capture_output=True,
        text=True,
    )
    assert miss.returncode == 2 and "not on the grid" in miss.stderr
    assert miss.stderr.startswith("pydrill atlas query: error: ") and "--nearest" in miss.stderr
    with Atlas(out) as atlas:  # SMALL's wob: 40, 100, 160 (steps of 60)
        assert atlas.value("nearest", wob=189.0, torque=8.3)["coords"]["wob"] == 160.0
        with pytest.raises(
            KeyError, match=r"wob = 191 N is outside the atlas \(40 N \.\.\. 160 N\)"
        ):
            atlas.value("nearest", wob=191.0, torque=8.3)  # more than half a step beyond


SIZES = """
[model]
preset = "reduced-scale"
[axes]
dof = [4, 8]
wob = [40.0, 100.0, 160.0, 220.0]
torque = [6.0, 8.3, 12.0]
[simulation]
t_end = 200.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def sizes_atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("atlas") / "sizes.h5"
    run_sweep(parse_spec(SIZES), out, serial=True)
    return out


def test_atlas_plot_draws_the_chosen_axes_at_the_held_values(sizes_atlas, tmp_path):
    from pydrill.plot_atlas import atlas_figure

    out = sizes_atlas
    shown = ["steady", "stick-slip", "stuck", "oscillation", "failed", "missing", "no-steady-state"]
    with Atlas(out) as atlas:
        names = atlas.regimes("rest")  # (dof, wob, torque)
        fig = atlas_figure(atlas, x="torque", y="wob", at={"dof": 7.2})  # nearest: dof 8
        ax = fig.axes[0]
        image = np.asarray(ax.collections[0].get_array()).reshape(4, 3)  # rows: wob
        assert (np.array(shown)[image] == names[1]).all()
        assert "dof = 8" in ax.get_title()
        assert ax.get_xlabel() == "surface torque $u$ (N·m)"
        # (W_ob, u) with the string held: the stuck boundary and the Hopf curve on top
        assert [line.get_label()[:5] for line in ax.get_lines()] == ["stuck", "first"]
        default = atlas_figure(atlas).axes[0]  # the first two swept axes, dof and wob
        assert default.get_xlabel() == "degrees of freedom" and "torque = 6" in default.get_title()
        assert list(default.get_xticks()) == [4, 8]
        for bad, message in [
            (dict(x="wob", y="wob"), "two different axes"),
            (dict(x="depth"), "x = 'depth' is not an axis"),
            (dict(x="wob", at={"wob": 100.0}), "'wob' is drawn"),
            (dict(at={"dof": 4, "torque": 6, "wob": 40}), "no axis left"),
        ]:
            with pytest.raises(ValueError, match=message):
                atlas_figure(atlas, **bad)
    chosen = ["--x", "wob", "--y", "torque", "--set", "dof=8"]
    proc = subprocess.run(
        [*CMD, "atlas", "plot", str(out), "--out", str(tmp_path / "m.png"), *chosen],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0 and (tmp_path / "m.png").stat().st_size > 10_000


def test_size_axes_are_whole_numbers_in_the_file_xarray_and_queries(sizes_atlas):
    import xarray as xr

    with h5py.File(sizes_atlas, "r") as f:
        assert f["dof"].dtype.kind == "i" and f["dof"][...].tolist() == [4, 8]
        assert f["wob"].dtype.kind == "f"
        # The atlas's identity is the one written before dof was stored as integers: atlases
        # of older versions still resume (digest from pydrill 0.1.0 at 7f36144).
        assert f.attrs["spec_digest"] == parse_spec(SIZES).digest == "21554d1232d9cd73"
    with xr.open_dataset(sizes_atlas, engine="h5netcdf") as ds:
        assert ds["dof"].dtype.kind == "i" and ds["dof"].values.tolist() == [4, 8]
        assert int(ds["regime"].sel(dof=8, wob=100.0, torque=8.3, initial="rest")) >= 0
    with Atlas(sizes_atlas) as atlas:
        coords = atlas.value(dof=8, wob=100.0, torque=8.3)["coords"]
        assert coords == {"dof": 8, "wob": 100.0, "torque": 8.3}
        assert type(coords["dof"]) is int and type(coords["wob"]) is float
    proc = subprocess.run(
        [
            *CMD,
            "atlas",
            "query",
            str(sizes_atlas),
            "--dof",
            "8",
            "--wob",
            "100",
            "--torque",
            "8.3",
            "--json",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    data = json.loads(proc.stdout)
    dof = data["coords"]["dof"]
    assert dof == 8 and type(dof) is int  # written as 8, not 8.0
    assert data["asked"] == data["coords"] and type(data["asked"]["dof"]) is int  # was 8.0
    assert data["units"]["coords"] == {"dof": "1", "wob": "N", "torque": "N·m"}
    # Every number the document holds has its unit, dimensionless ones too.
    flat = [k for k, x in data.items() if isinstance(x, (int, float)) and not isinstance(x, bool)]
    assert set(flat) | set(data["stability"]) <= set(data["units"]), data["units"]
    info = subprocess.run(
        [*CMD, "atlas", "info", str(sizes_atlas), "--json"], capture_output=True, text=True
    )
    axis = json.loads(info.stdout)["axes"]["dof"]
    assert axis == {"size": 2, "min": 4, "max": 8}
    assert type(axis["min"]) is int and type(axis["max"]) is int


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("atlas") / "small.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    return out


@pytest.fixture(scope="module")
def small_csv(small_atlas, tmp_path_factory):
    """``pydrill atlas export small.h5 --out small.csv``, run once for the tests that read
    that export: (the finished process, the table)."""
    table = tmp_path_factory.mktemp("export") / "small.csv"
    proc = subprocess.run(
        [*CMD, "atlas", "export", str(small_atlas), "--out", str(table)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    return proc, table


def _raw(atlas):
    """Regime names, bit means and status straight from HDF5, not through pydrill."""
    with h5py.File(atlas, "r") as f:
        codes = {v: k for k, v in h5py.check_enum_dtype(f["regime"].dtype).items()}
        names = np.vectorize(codes.get, otypes=[object])(f["regime"][...])
        axes = {k: f[k][...] for k in ("wob", "torque")}
        initials = [x.decode() if isinstance(x, bytes) else x for x in f["initial"][...]]
        return names, f["bit_mean"][...], f["status"][...], axes, initials


def test_info_json_counts_what_the_file_holds(small_atlas):
    proc = subprocess.run(
        [*CMD, "atlas", "info", str(small_atlas), "--json"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    info = json.loads(proc.stdout)
    names, _, status, axes, initials = _raw(small_atlas)
    assert info["points"] == status.size == 6 and info["status"]["done"] == 6
    assert info["initial"] == initials == ["rest", "equilibrium"]
    for name, values in axes.items():
        assert info["axes"][name] == {"size": len(values), "min": values[0], "max": values[-1]}
    for j, init in enumerate(initials):
        found, counts = np.unique(names[..., j], return_counts=True)
        assert info["regimes"][init] == dict(zip(found.tolist(), counts.tolist(), strict=True))
    assert info["journal"] is None
    with h5py.File(small_atlas, "r") as f:
        written = f.attrs["spec_digest"]
    assert info["spec_digest"] == info["spec_digest_here"] == written == parse_spec(SMALL).digest
    assert (
        "note:"
        not in subprocess.run(
            [*CMD, "atlas", "info", str(small_atlas)], capture_output=True, text=True, check=True
        ).stdout
    )


def test_info_says_when_the_written_digest_is_not_its_specs(small_atlas, tmp_path):
    """An atlas whose spec_digest is not the one this pydrill makes of its spec (edited, or
    written by a pydrill that modelled the spec otherwise): info printed the digest made here,
    not the one a --resume compares, and said nothing of the difference."""
    out = tmp_path / "a.h5"
    out.write_bytes(small_atlas.read_bytes())
    with h5py.File(out, "r+") as f:
        f.attrs["spec_digest"] = "0123456789abcdef"
        f.attrs["pydrill_version"] = "0.1.7"
    here = parse_spec(SMALL).digest
    info = json.loads(
        subprocess.run(
            [*CMD, "atlas", "info", str(out), "--json"], capture_output=True, text=True, check=True
        ).stdout
    )
    assert (info["spec_digest"], info["spec_digest_here"]) == ("0123456789abcdef", here)
    text = subprocess.run(
        [*CMD, "atlas", "info", str(out)], capture_output=True, text=True, check=True
    ).stdout
    assert "spec 0123456789abcdef\n  note: its spec makes digest " + here in text
    assert f"digest {here} in this pydrill: the file was changed" in " ".join(text.split())
    assert "or pydrill 0.1.7 made another model of" in " ".join(text.split())


def test_export_writes_netcdf_and_csv_with_what_the_atlas_holds(small_atlas, small_csv, tmp_path):
    import xarray as xr

    names, bit_mean, _, axes, initials = _raw(small_atlas)
    nc = tmp_path / "small.nc"
    to_nc = subprocess.run(
        [*CMD, "atlas", "export", str(small_atlas), "--out", str(nc)],
        capture_output=True,
        text=True,
    )
    for proc, out in ((to_nc, nc), small_csv):  # the CSV: exported once for the module
        assert proc.returncode == 0 and proc.stdout == f"wrote {out}\n", proc.stderr
    table = small_csv[1]
    with xr.open_dataset(nc) as ds:  # a plain netCDF reader, no pydrill
        assert list(ds.regime.dims) == ["wob", "torque", "initial"]
        np.testing.assert_array_equal(ds.wob.values, axes["wob"])
        np.testing.assert_array_equal(ds.bit_mean.values, bit_mean)
        assert "eigenvalues_real" in ds and "omega_eq" in ds
        flags = ds.regime.attrs
        meanings = dict(
            zip(flags["flag_values"].tolist(), flags["flag_meanings"].split(), strict=True)
        )
        spelled = np.vectorize(lambda c: meanings[int(c)].replace("_", "-"))(ds.regime.values)
        assert (spelled == names).all()
    with table.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == names.size == 12  # one row per point and initial condition
    assert not any("eigen" in column for column in rows[0])
    for row in rows:
        i = axes["wob"].tolist().index(float(row["wob"]))
        k = axes["torque"].tolist().index(float(row["torque"]))
        j = initials.index(row["initial"])
        assert row["regime_name"] == names[i, k, j]
        mean = float(row["bit_mean"] or "nan")  # no simulation (no steady state): empty
        assert mean == pytest.approx(bit_mean[i, k, j], rel=1e-12, nan_ok=True)


def test_export_to_an_unknown_format_is_refused_before_the_atlas_is_read(tmp_path):
    out = tmp_path / "small.txt"
    proc = subprocess.run(
        [*CMD, "atlas", "export", str(tmp_path / "no-such.h5"), "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "argument --out" in proc.stderr and ".nc (netCDF) or .csv" in proc.stderr
    assert not out.exists()


def _limit_file_size():
    """In the child: files of at most 1 KiB, a write beyond fails (EFBIG; Python ignores
    SIGXFSZ), as on a full disk."""
    import resource

    resource.setrlimit(resource.RLIMIT_FSIZE, (1024, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))


@pytest.mark.skipif(sys.platform == "win32", reason="RLIMIT_FSIZE is POSIX")
@pytest.mark.parametrize("suffix", [".nc", ".csv"])
@pytest.mark.parametrize("before", [None, b"an earlier export\n"])
def test_an_export_that_fails_midway_leaves_no_half_written_file(
    small_atlas, tmp_path, suffix, before
):
    """A write that failed midway (here a file size limit; a full disk alike) left the part
    written under --out, over an earlier export if there was one; the .nc export then crashed
    Python with a segmentation fault (h5netcdf closing the file whose write had failed). Now
    the export is written beside --out and put in its place once whole: the failure is an
    error naming --out, and --out is as it was (absent, or the earlier file)."""
    out = tmp_path / f"small{suffix}"
    if before is not None:
        out.write_bytes(before)
    proc = subprocess.run(
        [*CMD, "atlas", "export", str(small_atlas), "--out", str(out)],
        capture_output=True,
        text=True,
        preexec_fn=_limit_file_size,
        timeout=120,
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == f"pydrill atlas export: error: --out {out}: File too large\n"
    assert sorted(tmp_path.iterdir()) == ([] if before is None else [out])
    assert before is None or out.read_bytes() == before


def test_an_export_that_fails_leaves_the_atlas_closed(small_atlas, tmp_path, monkeypatch):
    """An error from the netCDF writer skipped the close of the atlas's xarray view: the
    atlas stayed open for as long as the error was held (a caller's except block, a
    notebook's last traceback). Now it is closed whatever fails."""
    import errno

    import psutil
    import xarray as xr

    from pydrill import cli

    def no_space(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "small.nc"))

    def open_atlases():
        return [f for f in psutil.Process().open_files() if Path(f.path) == small_atlas]

    monkeypatch.setattr(xr.Dataset, "to_netcdf", no_space)
    assert open_atlases() == []
    args = cli.build_parser().parse_args(
        ["atlas", "export", str(small_atlas), "--out", str(tmp_path / "small.nc")]
    )
    with pytest.raises(OSError, match="No space left on device") as held:
        args.handler(args)
    assert held.value is not None and open_atlases() == []
    assert list(tmp_path.iterdir()) == []


def test_an_export_over_a_link_or_a_file_writes_as_writing_into_it_would(small_atlas, tmp_path):
    """Put in place whole (da79aa1), the export replaced a symlink at --out by a file, and a
    file there by one of the default permissions. Now the link is followed, the file it names
    replaced and the link kept; a file keeps its permissions."""
    target = tmp_path / "runs" / "2026-12-01.csv"
    target.parent.mkdir()
    target.write_text("old\n")
    target.chmod(0o640)
    link = tmp_path / "latest.csv"
    link.symlink_to(target)
    for out in (link, target):
        proc = subprocess.run(
            [*CMD, "atlas", "export", str(small_atlas), "--out", str(out)],
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 0, proc.stderr
        assert link.is_symlink() and link.resolve() == target
        assert target.read_text().startswith("wob,torque,initial,")
        assert stat.S_IMODE(target.stat().st_mode) == 0o640
        assert sorted(p.name for p in target.parent.iterdir()) == [target.name]


def test_a_metric_map_shows_the_values_the_atlas_holds(small_atlas, tmp_path):
    from pydrill.plot_atlas import atlas_figure

    with h5py.File(small_atlas, "r") as f:  # (wob, torque, initial | steady state)
        severity = f["severity"][:, :, 1]  # from equilibrium
        abscissa = f["spectral_abscissa"][:, :, 0]  # the fastest steady state
    with Atlas(small_atlas) as atlas:
        fig = atlas_figure(atlas, metric="severity", initial="equilibrium")
        mesh = fig.axes[0].collections[0]
        shown = np.ma.filled(mesh.get_array().astype(float), np.nan).reshape(2, 3)  # (u, W_ob)
        np.testing.assert_array_equal(shown, severity.T)
        assert "severity from equilibrium after 200 s" in fig.axes[0].get_title()
        # From rest, the bit sticks at W_ob = 160 N: severity 0 as when drilling steadily, so
        # those cells are hatched and named.
        legend = atlas_figure(atlas, metric="severity").axes[0].get_legend()
        assert "bit stuck" in [t.get_text() for t in legend.get_texts()]
        assert atlas.regimes("rest")[2].tolist() == ["stuck", "stuck"]
        fig = atlas_figure(atlas, metric="spectral_abscissa")
        ax, bar = fig.axes
        mesh = ax.collections[0]
        shown = np.ma.filled(mesh.get_array().astype(float), np.nan).reshape(2, 3)
        np.testing.assert_array_equal(shown, abscissa.T)
        at = atlas.value(wob=100.0, torque=8.3)["stability"]["spectral_abscissa"][0]
        assert shown[1, 1] == pytest.approx(at)
        assert bar.get_ylabel().startswith("spectral_abscissa (1/s)")
        assert "of the fastest steady state" in ax.get_title()
        # Red where a steady state grows (abscissa > 0), blue where it decays.
        grows = mesh.cmap(mesh.norm(0.1 * mesh.norm.vmax))
        decays = mesh.cmap(mesh.norm(-0.1 * mesh.norm.vmax))
        assert grows[0] > grows[2] and decays[2] > decays[0]
        with pytest.raises(ValueError, match="metric = 'speed' is not allowed: one of bit_min"):
            atlas_figure(atlas, metric="speed")
    out = tmp_path / "severity.png"
    proc = subprocess.run(
        [*CMD, "atlas", "plot", str(small_atlas), "--out", str(out), "--metric", "severity"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    assert out.stat().st_size > 10_000


def test_info_counts_the_points_a_running_sweep_journaled_since_its_last_flush(tmp_path):
    """Between two flushes of the atlas (or after a kill -9), the journal holds the newest
    points: `atlas info` counts those not yet in the atlas, as --resume would take them."""
    from pydrill import atlas_format as fmt
    from pydrill.sweep import evaluate_point

    spec = parse_spec(SMALL)
    out = tmp_path / "running.h5"
    fmt.create(out, spec, "{}", "test")
    table = fmt.AtlasTable(spec)
    table.apply(evaluate_point(spec, 4))  # flushed already: in the atlas and the journal
    fmt.write(out, table)
    records = [evaluate_point(spec, i) for i in (0, 4, 1)]
    reordered = {"status": records[2]["status"], **records[2]}  # "i" not first: parsed whole
    lines = [json.dumps({"spec_digest": spec.digest})]
    lines += [json.dumps(r) for r in records[:2]] + [json.dumps(reordered)]
    cut = json.dumps(evaluate_point(spec, 5))[:40]  # a kill mid-append
    Path(str(out) + ".journal").write_text("\n".join(lines) + "\n" + cut)
    with Atlas(out) as atlas:
        s = atlas.summary()
    assert s["status"]["done"] == 1 and s["journal_points"] == 2  # points 0 and 1
    proc = subprocess.run([*CMD, "atlas", "info", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0 and "holds 2 more points, not yet in the atlas" in proc.stdout
    # What --resume then finds done: the atlas's point and the journal's two.
    assert run_sweep(spec, out, resume=True, serial=True).resumed == 3


def test_atlas_plot_set_refuses_a_value_off_the_atlas_and_says_when_it_snaps(sizes_atlas, tmp_path):
    """--set dof=100 on a grid of 4 and 8 drew dof 8 without a word."""

    def plot(value):
        out = tmp_path / f"map-{value}.png"
        argv = ["atlas", "plot", str(sizes_atlas), "--out", str(out), "--set", f"dof={value}"]
        proc = subprocess.run([*CMD, *argv], capture_output=True, text=True)
        return proc, out

    far, out = plot(100)
    assert far.returncode == 2 and not out.exists()
    assert far.stderr.strip() == (
        "pydrill atlas plot: error: --set dof=100: dof = 100 is outside the atlas (4 ... 8)"
    )
    near, out = plot(7)
    assert near.returncode == 0 and out.exists()
    assert near.stderr.strip() == (
        "pydrill atlas plot: note: --set dof=7 is not a grid value; drawn at the nearest, dof = 8"
    )
    exact, out = plot(8)
    assert exact.returncode == 0 and exact.stderr == "" and out.exists()


def test_export_csv_names_every_coded_column_beside_its_codes(small_atlas, small_csv, tmp_path):
    """caveat, status and coexistence were bare codes (1, 3; 1; -1) in the CSV."""
    from sweeping import TINY

    from pydrill import atlas_format as fmt

    one = tmp_path / "one.h5"  # one start: coexistence unknown
    run_sweep(parse_spec(TINY), one, serial=True)
    assert small_csv[0].returncode == 0, small_csv[0].stderr  # small.h5's, exported once
    for atlas in (small_atlas, one):
        table = small_csv[1] if atlas == small_atlas else tmp_path / f"{atlas.stem}.csv"
        if atlas == one:
            subprocess.run(
                [*CMD, "atlas", "export", str(atlas), "--out", str(table)], check=True, timeout=120
            )
        with table.open(newline="") as fh:
            reader = csv.DictReader(fh)
            rows, columns = list(reader), reader.fieldnames
        for code in ("regime", "caveat", "status", "coexistence"):
            assert columns[columns.index(code) + 1] == f"{code}_name"
        with h5py.File(atlas, "r") as f:
            caveats = set(f["caveat"][...].ravel().tolist())
        meaning = {1: "starts-disagree", 0: "no-disagreement", -1: "unknown"}
        for row in rows:
            assert row["regime_name"] == fmt.REGIME_NAMES[int(row["regime"])]
            caveat = fmt.CAVEAT_NAMES[int(row["caveat"])]
            assert row["caveat_name"] == (caveat or "none")
            assert row["status_name"] == {"1": "done", "2": "failed", "0": "missing"}[row["status"]]
            assert row["coexistence_name"] == meaning[int(row["coexistence"])]
        if atlas == one:
            assert {r["coexistence_name"] for r in rows} == {"unknown"}
        else:
            assert "unknown" not in {r["coexistence_name"] for r in rows}
        assert {r["caveat_name"] for r in rows} == {fmt.CAVEAT_NAMES[c] or "none" for c in caveats}


def test_counts_not_measured_are_empty_not_minus_one(tmp_path):
    """A failed point's stick_events read -1 in the CSV and in xarray (a mean over the atlas
    counted it); a count is now NaN / an empty cell there, and stays an integer elsewhere."""
    import xarray as xr
    from sweeping import TINY

    atlas = tmp_path / "fail.h5"
    failing = TINY.replace("[simulation]", "[simulation]\nmax_steps = 20")
    run_sweep(parse_spec(failing), atlas, serial=True)
    with h5py.File(atlas, "r") as f:
        assert (
            set(f["status"][...].ravel().tolist()) == {2} and (f["stick_events"][...] == -1).all()
        )
    table, nc = tmp_path / "fail.csv", tmp_path / "fail.nc"
    for out in (table, nc):
        subprocess.run([*CMD, "atlas", "export", str(atlas), "--out", str(out)], check=True)
    with table.open(newline="") as fh:
        assert {row["stick_events"] for row in csv.DictReader(fh)} == {""}
    with Atlas(atlas) as a:
        assert np.isnan(a.to_xarray()["stick_events"].values).all()
    with xr.open_dataset(atlas, engine="h5netcdf") as ds:  # the file read as it is, CF
        assert np.isnan(ds["stick_events"].values).all() and np.isnan(ds["unstable"]).all()
    with h5py.File(nc, "r") as f:  # the netCDF keeps the integer and names its fill
        assert f["stick_events"].dtype.kind == "i" and (f["stick_events"][...] == -1).all()
    with xr.open_dataset(nc) as ds:
        assert np.isnan(ds["stick_events"].values).all()


def test_exported_counts_are_integers_where_measured(small_atlas, small_csv):
    proc, table = small_csv  # small.h5 exported to CSV (once for the module)
    assert proc.returncode == 0, proc.stderr
    with h5py.File(small_atlas, "r") as f:
        raw = f["stick_events"][...]
    with table.open(newline="") as fh:
        cells = [row["stick_events"] for row in csv.DictReader(fh)]
    assert sorted(cells) == sorted("" if n == -1 else str(n) for n in raw.ravel().tolist())
    assert any(c not in ("", "0") for c in cells)  # stick-slip points count their sticks


def test_info_and_query_text_give_the_axes_units(small_atlas):
    info = subprocess.run(
        [*CMD, "atlas", "info", str(small_atlas)], capture_output=True, text=True, check=True
    ).stdout
    assert "axis wob               3 values, 40 N ... 160 N" in info
    assert "axis torque            2 values, 6 N·m ... 8.3 N·m" in info


def test_the_file_says_what_it_is_to_a_netcdf_reader(small_atlas):
    import xarray as xr

    with xr.open_dataset(small_atlas, engine="h5netcdf") as ds:
        assert ds.attrs["Conventions"] == "CF-1.8"
        title = "pydrill regime atlas: reduced-scale, dof 4, over wob x torque, from rest and"
        assert ds.attrs["title"].startswith(title)
        assert ds.attrs["source"].startswith("pydrill ") and "2007" in ds.attrs["references"]
        assert ds["wob"].attrs == {"units": "N", "long_name": "weight on bit"}
        assert ds["torque"].attrs["long_name"] == "surface torque of the top drive"
        # measured counts stay whole numbers where measured
        events = ds["stick_events"].values
        assert np.all(events[np.isfinite(events)] == np.round(events[np.isfinite(events)]))


def test_axis_lines_align_whatever_the_names():
    """'axis stribeck_velocity      4 values' pushed its counts out of line with wob's."""
    from pydrill.cli_atlas_info import axis_line

    names = ["wob", "stribeck_velocity"]
    lines = [axis_line(n, 12, 1.0, 2.0, max(map(len, names))) for n in names]
    assert len({line.index(" values,") for line in lines}) == 1
    assert lines[1].startswith("  axis stribeck_velocity     12 values, 1 rad/s")


def test_a_real_string_axis_reads_in_kilonewtons():
    from pydrill.atlas_grid import with_unit
    from pydrill.cli_atlas_info import axis_line

    assert with_unit("wob", 120e3) == "120 kN" and with_unit("wob", 80.0) == "80 N"
    assert with_unit("torque", 15e3) == "15 kN·m" and with_unit("pipes", 40) == "40"
    # one unit along an axis, even where its first value alone would read in N
    assert axis_line("wob", 3, 5e3, 2e5).endswith("5 kN ... 200 kN")


def test_info_of_a_one_start_atlas_counts_no_disagreement(tmp_path):
    """'rest/equilibrium disagree at 0' was printed for atlases with one start."""
    from sweeping import TINY

    one = tmp_path / "one.h5"
    run_sweep(parse_spec(TINY), one, serial=True)
    text = subprocess.run(
        [*CMD, "atlas", "info", str(one)], capture_output=True, text=True, check=True
    ).stdout
    assert "safe points" in text and "disagree" not in text


def test_query_nearest_says_it_moved_to_the_grid_point(small_atlas):
    """SMALL's grid: wob 40, 100, 160; torque 6, 8.3."""

    def query(*args):
        argv = [*CMD, "atlas", "query", str(small_atlas), *args]
        return subprocess.run(argv, capture_output=True, text=True, check=True).stdout

    moved = query("--wob", "97", "--torque", "8.3", "--nearest").splitlines()
    assert moved[0] == "wob = 100 N, torque = 8.3 N·m: done"
    assert moved[1] == "  (the grid point nearest wob = 97 N)"
    exact = query("--wob", "100", "--torque", "8.3", "--nearest")
    assert "nearest" not in exact
    data = json.loads(query("--wob", "97", "--torque", "8.2", "--nearest", "--json"))
    assert data["coords"] == {"wob": 100.0, "torque": 8.3}
    assert data["asked"] == {"wob": 97.0, "torque": 8.2}


PARAMETERS = """
[model]
preset = "reduced-scale"
dof = 4
wob = 100.0
torque = 8.3
[axes]
bit_damping = [0.01, 0.05]
mu_static = [0.7, 0.8]
[simulation]
t_end = 100.0
initial = ["rest"]
"""


@pytest.fixture(scope="module")
def parameter_atlas(tmp_path_factory):
    """An atlas over two model parameters: a damping and a friction coefficient."""
    out = tmp_path_factory.mktemp("parameters") / "par.h5"
    run_sweep(parse_spec(PARAMETERS), out, serial=True)
    return out


def test_swept_parameters_carry_their_units_into_the_atlas_netcdf_and_maps(
    parameter_atlas, tmp_path
):
    """Their unit was "SI" in the atlas, the netCDF export and the map's labels: no unit
    UDUNITS (CF) knows, and no help to a reader."""
    import xarray as xr

    from pydrill.plot_atlas import atlas_figure

    want = {"bit_damping": "N m s rad-1", "mu_static": "1"}
    with h5py.File(parameter_atlas, "r") as f:
        assert {name: f[name].attrs["units"] for name in want} == want
    nc = tmp_path / "par.nc"
    proc = subprocess.run(
        [*CMD, "atlas", "export", str(parameter_atlas), "--out", str(nc)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert {name: ds[name].attrs["units"] for name in want} == want
    with Atlas(parameter_atlas) as atlas:
        assert {name: atlas.to_xarray()[name].attrs["units"] for name in want} == want
        fig = atlas_figure(atlas)
    ax = fig.axes[0]
    assert ax.get_xlabel() == "bit_damping (N·m·s/rad)"
    assert ax.get_ylabel() == "mu_static"  # a friction coefficient: no unit
    # An atlas written before says "SI": it still reads, and xarray gets the unit.
    old = tmp_path / "old.h5"
    old.write_bytes(parameter_atlas.read_bytes())
    with h5py.File(old, "r+") as f:
        for name in want:
            f[name].attrs["units"] = "SI"
    with Atlas(old) as atlas:
        assert {name: atlas.to_xarray()[name].attrs["units"] for name in want} == want
        assert atlas.value(bit_damping=0.05, mu_static=0.8)["status"] == "done"
        atlas_figure(atlas)


def test_set_takes_values_with_units_as_the_other_options_do(parameter_atlas, tmp_path):
    """``--set "bit_damping=0.055 N·m·s/rad"``, ``--set depth=3000ft`` were refused with
    "expected AXIS=NUMBER" although ``--wob '0.1 kN'`` and the spec take units."""

    def pydrill(*args):
        return subprocess.run([*CMD, *map(str, args)], capture_output=True, text=True)

    query = ["atlas", "query", parameter_atlas, "--json"]
    plain = pydrill(*query, "--set", "bit_damping=0.05", "--set", "mu_static=0.8")
    assert plain.returncode == 0, plain.stderr
    given = pydrill(*query, "--set", "bit_damping=0.05 N·m·s/rad", "--set", "mu_static=0.8")
    assert given.returncode == 0, given.stderr
    assert json.loads(given.stdout) == json.loads(plain.stdout)
    wrong = pydrill(*query, "--set", "bit_damping=0.05 kN", "--set", "mu_static=0.8")
    assert wrong.returncode == 2
    assert wrong.stderr.strip() == (
        "pydrill atlas query: error: --set 'bit_damping=0.05 kN': "
        "bit_damping = '0.05 kN': unit 'kN' is not a damping unit; use one of N·m·s/rad "
        "(N m s/rad, Nms/rad, N-m-s/rad)"
    )
    bare = pydrill(*query, "--set", "bit_damping", "--set", "mu_static=0.8")
    assert bare.returncode == 2 and "--set 'bit_damping': expected AXIS=VALUE" in bare.stderr
    # A map held at a wob with its unit (the spec's [model] fixes torque; wob is swept).
    spec = PARAMETERS.replace("wob = 100.0\n", "").replace(
        "[axes]\n", "[axes]\nwob = [60.0, 100.0]\n"
    )
    three = tmp_path / "three.h5"
    run_sweep(parse_spec(spec), three, serial=True)
    out = tmp_path / "held.png"
    argv = ["atlas", "plot", three, "--out", out, "--x", "mu_static", "--y", "bit_damping"]
    held = pydrill(*argv, "--set", "wob=0.1 kN")
    assert held.returncode == 0 and held.stderr == "" and out.exists(), held.stderr
    off = pydrill(*argv, "--set", "wob=0.09kN")
    assert off.returncode == 0 and off.stderr.strip() == (
        "pydrill atlas plot: note: --set wob=0.09kN is not a grid value; "
        "drawn at the nearest, wob = 100 N"
    )
