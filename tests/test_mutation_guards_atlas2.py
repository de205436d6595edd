"""An atlas's datasets, units, dimension scales and flags, read with plain h5py and xarray's
h5netcdf engine against hand-written expectations; pydrill's xarray engine against h5netcdf.

What a mutation audit of atlas_schema.py, atlas_objects.py and xarray_backend.py left alive:
a field's unit, a count's fill, an axis's UDUNITS unit, flag values out of step with their
meanings, an engine that kept a variable it was told to drop or kept the file open.
"""

import h5py
import numpy as np
import pytest
import xarray as xr

from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.journal import AtlasError
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# torque not the last axis; a model parameter with a unit as an axis
SPEC = """
[model]
preset = "reduced-scale"
[axes]
torque = [6.0, 7.0]
wob = [100.0]
bit_radius = [0.1, 0.12]
[simulation]
t_end = 5.0
initial = ["rest", "equilibrium"]
"""

# Each field's unit as the physics has it (written out here, not read from the schema)
UNITS = {
    **dict.fromkeys(["bit_min", "bit_max", "bit_mean", "top_mean", "top_min", "top_max"], "rad/s"),
    **dict.fromkeys(["severity", "stuck_fraction", "bit_top_ratio", "stick_events"], "1"),
    "period": "s",
    "wall_time": "s",
    "omega_eq": "rad/s",
    "delta": "N m s/rad",
    "spectral_abscissa": "1/s",
    "hopf_margin": "N m s/rad",
    "unstable": "1",
}
AXES = {"torque": "N m", "wob": "N", "bit_radius": "m"}


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    path = tmp_path_factory.mktemp("atlas2") / "tiny.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    with h5py.File(path, "r+") as f:  # a failed run's counts: the fill, -1
        f["stick_events"][0, 0, 1, 0] = -1
        f["unstable"][1, 0, 0, 0] = -1
    return path


def test_each_field_has_its_unit_and_its_axes_and_start_as_dimension_scales(tiny):
    with h5py.File(tiny, "r") as f:
        for name, unit in UNITS.items():
            ds = f[name]
            assert ds.attrs["units"] == unit, name
            scales = [ds.dims[i][0].name for i in range(ds.ndim)]
            last = "/equilibrium" if name in fmt.EQ_FIELDS else "/initial"
            assert scales == ["/torque", "/wob", "/bit_radius", last], (name, scales)
        for name, unit in AXES.items():
            assert f[name].attrs["units"] == unit, name
        assert f["torque"][...].tolist() == [6.0, 7.0]
        assert f["equilibrium"].attrs["units"] == "1"


def test_a_counts_fill_is_minus_one_and_named_so_for_netcdf_readers(tiny):
    """-1 is 'not measured' (a failed run): h5netcdf reads it as NaN, as pydrill's engine
    does, and every other value as the file holds it."""
    with h5py.File(tiny, "r") as f:
        for name in ("stick_events", "unstable"):
            assert f[name].fillvalue == -1 and f[name].attrs["_FillValue"] == -1, name
            raw = f[name][...]
        events = f["stick_events"][...]
    with (
        xr.open_dataset(tiny, engine="h5netcdf") as plain,
        xr.open_dataset(tiny, engine="pydrill") as ours,
    ):
        for name, stored in (("stick_events", events), ("unstable", raw)):
            want = np.where(stored == -1, np.nan, stored)
            np.testing.assert_array_equal(plain[name].values, want)
            np.testing.assert_array_equal(ours[name].values, want)


def test_flag_values_and_meanings_pair_up_as_the_codes_do(tiny):
    """CF pairs flag_values[i] with the i-th word of flag_meanings: each pair must be the
    code pydrill writes for that name (hand-written here)."""
    codes = {
        "regime": {
            "steady": 0,
            "stick-slip": 1,
            "stuck": 2,
            "oscillation": 3,
            "failed": -1,
            "missing": -2,
            "no-steady-state": -3,
        },
        "status": {"missing": 0, "done": 1, "failed": 2},
        "coexistence": {"unknown": -1, "no-disagreement": 0, "starts-disagree": 1},
        # an atlas stores these codes: a new kind goes last, 0 stays "nothing noted"
        "caveat": {
            "none": 0,
            "first-wind-up": 1,
            "one-stick-phase": 2,
            "one-break-away": 3,
            "growing": 4,
            "short-window": 5,
            "late-stick": 6,
            "run-away": 7,
            "approaching": 8,
        },
    }
    with h5py.File(tiny, "r") as f:
        for name, want in codes.items():
            a = f[name].attrs
            pairs = dict(zip(a["flag_meanings"].split(" "), a["flag_values"].tolist(), strict=True))
            assert pairs == want, name
        done = f["status"][...]
        assert (done == 1).all()  # every point computed: "done"
        names = {v: k for k, v in codes["regime"].items()}
        want = np.vectorize(names.get)(f["regime"][..., 1])
    with Atlas(tiny) as atlas:  # the regimes as pydrill names them, from the codes on file
        assert atlas.regimes("equilibrium").tolist() == want.tolist()


def test_the_engine_is_h5netcdfs_reading_with_what_it_is_told_to_drop(tiny):
    """Coordinates in the file's order, the same dims and values as h5netcdf reads (pydrill
    adds ``safe``); a name given alone is dropped as a list of one is, and a name the file
    lacks is ignored, as xarray's engines do."""
    with xr.open_dataset(tiny, engine="h5netcdf") as plain:
        for drop in ("bit_min", ["bit_min", "no_such_variable"]):
            with xr.open_dataset(tiny, engine="pydrill", drop_variables=drop) as ours:
                assert "bit_min" not in ours and "bit_max" in ours
                assert ours["torque"].values.tolist() == [6.0, 7.0]
                assert ours["bit_radius"].values.tolist() == [0.1, 0.12]
                for name in ("regime", "bit_max", "omega_eq", "period", "status"):
                    assert ours[name].dims == plain[name].dims, name
                    np.testing.assert_array_equal(ours[name].values, plain[name].values)
                    assert ours[name].attrs.get("units") == plain[name].attrs.get("units")


def test_closing_the_engines_dataset_lets_go_of_the_file(tiny):
    ds = xr.open_dataset(tiny, engine="pydrill")
    ds.close()
    with h5py.File(tiny, "r+"):  # HDF5 refuses r+ while this process holds it open read-only
        pass


def test_the_engine_opens_by_path_only(tiny):
    with open(tiny, "rb") as handle, pytest.raises(TypeError, match="by its path"):
        xr.open_dataset(handle, engine="pydrill")


@pytest.mark.parametrize("name", ["coexistence", "message", "omega_eq", "bit_top_ratio"])
def test_an_atlas_without_a_dataset_queries_read_is_refused_but_not_without_a_newer_field(
    tiny, tmp_path, name
):
    """What the queries read must be there (the atlas is damaged without it); a run field
    added after the format's first version (bit_top_ratio) may be missing: read as NaN."""
    path = tmp_path / "cut.h5"
    path.write_bytes(tiny.read_bytes())
    with h5py.File(path, "r+") as f:
        del f[name]
    if name == "bit_top_ratio":  # (named here: the schema's list is what is checked)
        with Atlas(path) as atlas:  # opens, and answers a query
            assert atlas.value(torque=6.0, wob=100.0, bit_radius=0.1)["regime"]
    else:
        with pytest.raises(AtlasError, match=name):
            Atlas(path).close()


def test_each_axis_unit_is_the_udunits_spelling_of_its_si_unit():
    """UDUNITS (CF) spells a product with blanks and a power after its base, negative below
    the line: written out here by hand for each kind of axis and model parameter."""
    want = {
        "wob": "N",
        "torque": "N m",
        "depth": "m",
        "dof": "1",
        "pipes": "1",
        "top_damping": "N m s rad-1",
        "bit_damping": "N m s rad-1",
        "stribeck_velocity": "rad s-1",
        "karnopp_band": "rad s-1",
        "bit_radius": "m",
        "mu_coulomb": "1",
        "mu_static": "1",
        "stribeck_decay": "1",
        "inertias": "kg m2",
        "stiffnesses": "N m rad-1",
    }
    assert {name: fmt.axis_units(name) for name in want} == want


def test_a_power_below_the_line_is_negated_with_its_base(monkeypatch):
    """No parameter's unit has a power below the line, or a bare 1 above it, yet; one that
    does (an angular acceleration, a rate) must read as UDUNITS has it."""
    from pydrill import model

    monkeypatch.setitem(model._UNITS, "spin_up", "rad/s²")
    monkeypatch.setitem(model._UNITS, "drag", "N·m·s²/rad²")
    monkeypatch.setitem(model._UNITS, "rate", "1/s")  # a bare 1 above the line is dropped
    assert fmt.axis_units("spin_up") == "rad s-2"
    assert fmt.axis_units("drag") == "N m s2 rad-2"
    assert fmt.axis_units("rate") == "s-1"
