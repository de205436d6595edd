"""Atlases through netCDF-C: the netCDF4 package (its own netCDF-C) and xarray's "netcdf4"
engine open real atlases of every shape, and find what h5py and pydrill.Atlas find in them:
each dataset a variable on the right dimensions, with its values, units and names, the regime
an enum whose names are pydrill's, the counts' fill read as missing. The .nc export too.
Debian's ncdump (an older netCDF-C on HDF5 1.10) is checked where it is installed.

The CF checker (cfchecker, which needs the udunits2 C library and the CF tables) is run by
hand: docs/guide/sweeps.md says what it reports and why what is left is left."""

import shutil
import subprocess

import h5py
import netCDF4
import numpy as np
import pytest
import xarray as xr
from sweeping import CMD, SMALL, same_atlas

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

SPECS = {
    # the main job's kind: (wob, torque), two starts, stability and eigenvalues
    "wob-torque": SMALL,
    "one-axis": """
[model]
preset = "reduced-scale"
dof = 4
torque = 8.3
[axes]
wob = [40.0, 100.0, 160.0]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
""",
    "three-axes": """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 160.0]
torque = [6.0, 8.3]
bit_damping = [0.02, 0.05]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
[record]
eigenvalues = 3
""",
    "size-axis": """
[model]
preset = "reduced-scale"
torque = 8.3
[axes]
dof = [2, 4]
wob = [40.0, 160.0]
[simulation]
t_end = 100.0
initial = ["rest"]
""",
    "depth": """
[model]
tally = "examples/tallies/paper-eq53.toml"
dof = 6
torque = "9 kN·m"
[axes]
depth = [1000.0, 3000.0]
wob = ["40 kN", "100 kN"]
[simulation]
t_end = 100.0
initial = ["rest", "equilibrium"]
""",
    # (100 N, 8.3 N·m) fails: its stick-slip needs more than 900 steps
    "failed": SMALL.replace(
        'initial = ["rest", "equilibrium"]', 'initial = ["rest"]\nmax_steps = 900'
    ),
}


@pytest.fixture(scope="module")
def atlases(tmp_path_factory, request):
    folder = tmp_path_factory.mktemp("netcdf")
    out = {}
    root = request.config.rootpath
    for name, text in SPECS.items():
        if name != "failed":  # (whose point fails for its t_end)
            text = text.replace("t_end = 200.0", "t_end = 100.0")
        text = text.replace('"examples/', f'"{root}/examples/')
        path = folder / f"{name}.h5"
        run_sweep(parse_spec(text), path, serial=True)
        out[name] = path
    return out


def _h5_dims(ds: h5py.Dataset) -> tuple[str, ...]:
    """A dataset's dimensions as h5py reads its dimension scales (a scale: its own)."""
    if ds.is_scale:
        return (ds.name.lstrip("/"),)
    return tuple(d[0].name.lstrip("/") for d in ds.dims)


@pytest.mark.parametrize("name", list(SPECS))
def test_every_dataset_is_a_netcdf_variable_with_its_dims_values_and_attributes(atlases, name):
    path = atlases[name]
    with h5py.File(path, "r") as f, netCDF4.Dataset(path) as nc:
        datasets = [k for k in f if isinstance(f[k], h5py.Dataset)]
        assert sorted(nc.variables) == sorted(datasets)
        for key in datasets:
            h5, var = f[key], nc.variables[key]
            assert var.dimensions == _h5_dims(h5), key
            var.set_auto_mask(False)
            got, want = var[...], h5[...]
            if h5.dtype.kind in "OS":  # strings: the starts, the failed points' messages
                want = np.vectorize(lambda s: s.decode() if isinstance(s, bytes) else s)(want)
                assert np.array_equal(np.asarray(got, dtype=object), want.astype(object)), key
            else:
                np.testing.assert_array_equal(np.asarray(got), want, err_msg=key)
            for attr in ("units", "long_name", "flag_meanings"):
                if attr in h5.attrs:
                    assert var.getncattr(attr) == h5.attrs[attr], (key, attr)
            # a CF checker asks every variable for a long_name (the axes, the indices too)
            assert var.getncattr("long_name"), key
        assert nc.getncattr("Conventions") == f.attrs["Conventions"] == "CF-1.8"
        for attr in ("title", "source", "references"):
            assert nc.getncattr(attr) == f.attrs[attr]


@pytest.mark.parametrize("name", list(SPECS))
def test_engine_netcdf4_reads_what_pydrill_atlas_reads(atlases, name):
    path = atlases[name]
    with Atlas(path) as atlas, xr.open_dataset(path, engine="netcdf4") as ds:
        assert list(ds["regime"].dims) == [*atlas.axes, "initial"]
        for axis, values in atlas.axes.items():
            np.testing.assert_array_equal(ds[axis].values, values)
            assert ds[axis].attrs["units"] == fmt.axis_units(axis)
        assert tuple(ds["initial"].values) == atlas.initials
        meanings = dict(
            zip(
                ds["regime"].attrs["flag_values"].tolist(),
                ds["regime"].attrs["flag_meanings"].split(),
                strict=True,
            )
        )
        for point in np.ndindex(*atlas.shape):
            coords = {a: v[i].item() for (a, v), i in zip(atlas.axes.items(), point, strict=True)}
            value = atlas.value(**coords)
            at = ds.isel(dict(zip(atlas.axes, point, strict=True)))
            for j, init in enumerate(atlas.initials):
                code = int(at["regime"].values[j])
                assert meanings[code] == value["regime"][init], (coords, init)
                mean = float(at["bit_mean"].values[j])
                assert value["metrics"]["bit_mean"][init] == (None if np.isnan(mean) else mean)
                # a count's -1 (not measured) is CF's _FillValue: missing, not a count
                events = at["stick_events"].values[j]
                want = value["metrics"]["stick_events"][init]
                assert np.isnan(events) if want is None else events == want, (coords, init)
            if value["status"] == "failed":
                assert str(at["message"].values) == value["message"]
            elif value["status"] == "done" and value["stability"]["omega_eq"]:
                omega = at["omega_eq"].values[: len(value["stability"]["omega_eq"])]
                assert omega.tolist() == value["stability"]["omega_eq"]


def test_regime_is_an_enum_netcdf_c_names_as_pydrill_does(atlases):
    with netCDF4.Dataset(atlases["failed"]) as nc:
        regime = nc.variables["regime"]
        assert isinstance(regime.datatype, netCDF4.EnumType)
        assert regime.datatype.enum_dict == fmt.REGIMES
        codes = regime[...]
        assert fmt.REGIMES["failed"] in codes and fmt.REGIMES["steady"] in codes
        assert not np.ma.is_masked(codes)  # steady (0) is a code, not a fill


def test_the_netcdf_export_opens_in_netcdf_c_with_a_named_regime_type(atlases, tmp_path):
    atlas = atlases["failed"]
    nc_path = tmp_path / "f.nc"
    proc = subprocess.run(
        [*CMD, "atlas", "export", atlas, "--out", nc_path], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""  # (h5netcdf's warning on the enum's default fill is not the user's)
    with h5py.File(atlas, "r") as f, netCDF4.Dataset(nc_path) as nc:
        # named, as netCDF-C before 4.9.2 needs to read the variable at all
        assert nc.enumtypes["regime_t"].enum_dict == fmt.REGIMES
        assert nc.variables["regime"].datatype.name == "regime_t"
        for key in ("regime", "status", "bit_mean", "stick_events", "omega_eq", "caveat"):
            var = nc.variables[key]
            var.set_auto_mask(False)
            assert var.dimensions == _h5_dims(f[key]), key
            np.testing.assert_array_equal(var[...], f[key][...], err_msg=key)
        for axis in ("wob", "torque", "initial", "equilibrium", "eigenvalue"):
            # CF: coordinates have no missing values (xarray gave float ones a NaN fill)
            assert "_FillValue" not in nc.variables[axis].ncattrs(), axis
        assert nc.variables["stick_events"].getncattr("_FillValue") == -1
        flags = nc.variables["coexistence"]
        assert flags.getncattr("flag_meanings") == " ".join(fmt.COEXISTENCE)
    with xr.open_dataset(nc_path, engine="netcdf4") as ds, Atlas(atlas) as a:
        assert ds["regime"].dtype == np.int8
        assert ds["regime"].sel(wob=100.0, torque=8.3, initial="rest") == fmt.REGIMES["failed"]
        assert (
            str(ds["message"].sel(wob=100.0, torque=8.3).values)
            == a.value(wob=100.0, torque=8.3)["message"]
        )


def test_an_atlas_is_written_in_hdf5_objects_an_hdf5_1_10_reads(atlases):
    # "latest" wrote HDF5 2.0's objects (h5py 3.16), behind a version-3 superblock, and
    # netCDF-C on HDF5 1.10 refused the whole file; 1.8..1.10's objects have version 2.
    for path in atlases.values():
        assert path.read_bytes()[8] == 2, path


@pytest.mark.skipif(shutil.which("ncdump") is None, reason="no ncdump (Debian: netcdf-bin)")
def test_the_system_ncdump_lists_every_variable_of_atlas_and_export(atlases, tmp_path):
    """Debian 12's ncdump is netCDF-C 4.9.0 on HDF5 1.10: it refused atlases written with
    libver="latest", and left out a variable of an unnamed enum (the atlas's regime, until
    its type was named regime_t and created first)."""
    atlas = atlases["failed"]
    header = subprocess.run(["ncdump", "-h", atlas], capture_output=True, text=True)
    assert header.returncode == 0, header.stderr
    with h5py.File(atlas, "r") as f:
        variables = [k for k in f if isinstance(f[k], h5py.Dataset)]
        assert [k for k in variables if f"{k}(" not in header.stdout] == []
        assert isinstance(f["regime_t"], h5py.Datatype)
    assert "regime_t regime(wob, torque, initial)" in header.stdout
    values = subprocess.run(["ncdump", "-v", "regime", atlas], capture_output=True, text=True)
    assert "failed" in values.stdout.split("regime =")[1]
    nc_path = tmp_path / "f.nc"
    subprocess.run([*CMD, "atlas", "export", atlas, "--out", nc_path], check=True)
    dump = subprocess.run(["ncdump", "-v", "regime", nc_path], capture_output=True, text=True)
    assert dump.returncode == 0, dump.stderr
    assert "regime_t regime(wob, torque, initial)" in dump.stdout
    assert "failed" in dump.stdout.split("regime =")[1]


def test_an_atlas_written_with_libver_latest_still_opens_and_resumes(tmp_path, monkeypatch):
    """Atlases written before libver was pinned: read as before, and --resume completes one."""
    spec = parse_spec(SMALL.replace("t_end = 200.0", "t_end = 100.0"))
    fresh = tmp_path / "fresh.h5"
    run_sweep(spec, fresh, serial=True)
    old = tmp_path / "old.h5"
    monkeypatch.setattr(fmt, "LIBVER", "latest")
    with h5py.File(fresh, "r") as f:
        params, version = f.attrs["params"], f.attrs["pydrill_version"]
    fmt.create(old, spec, params, version)
    monkeypatch.undo()
    assert old.read_bytes()[8] == 3  # as h5py 3.16 wrote it (HDF5 2.0)
    report = run_sweep(spec, old, serial=True, resume=True)
    assert report.computed == spec.size
    same_atlas(old, fresh)
    with Atlas(old) as a, Atlas(fresh) as b:
        got, want = a.value(wob=100.0, torque=8.3), b.value(wob=100.0, torque=8.3)
        for point in (got, want):
            del point["metrics"]["wall_time"]  # (the time in the C++ core of each run)
        assert got == want


def test_older_atlases_get_the_index_attributes_in_xarray(atlases, tmp_path):
    old = tmp_path / "old.h5"
    shutil.copy(atlases["wob-torque"], old)
    with h5py.File(old, "r+") as f:  # as written before they had them
        for name in ("initial", "eigenvalue", "status", "coexistence"):
            for attr in ("long_name", "units", "flag_values", "flag_meanings"):
                if attr in f[name].attrs:
                    del f[name].attrs[attr]
    with Atlas(old) as atlas:
        ds = atlas.to_xarray()
        for name, attrs in fmt.index_attrs().items():
            assert ds[name].attrs["long_name"] == attrs["long_name"]
        assert ds["coexistence"].attrs["flag_meanings"] == " ".join(fmt.COEXISTENCE)
        ds.close()
