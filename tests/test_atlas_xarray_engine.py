"""``xarray.open_dataset(path, engine="pydrill")``: the atlas as ``Atlas.to_xarray`` reads it,
through xarray's backend API (the entry point installed with pydrill), checked against the
file's raw datasets read with h5py."""

import importlib.metadata
import io

import h5py
import numpy as np
import pytest
import xarray as xr
from sweeping import SMALL

import pydrill
from pydrill import atlas_format as fmt
from pydrill.journal import AtlasError
from pydrill.sweep import run_sweep
from pydrill.xarray_backend import AtlasBackend

# A point whose solver gives up (3 steps) beside points that run: a failed point's counts are
# the fill (-1), which the engine reads as missing.
SPEC = SMALL.replace("t_end = 200.0", "t_end = 50.0")


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    path = tmp_path_factory.mktemp("engine") / "a.h5"
    run_sweep(pydrill.parse_spec(SPEC), path, serial=True)
    return path


def test_pydrill_is_an_xarray_engine_once_installed():
    (entry,) = [
        e for e in importlib.metadata.entry_points(group="xarray.backends") if e.name == "pydrill"
    ]
    assert entry.load() is AtlasBackend
    assert isinstance(xr.backends.list_engines()["pydrill"], AtlasBackend)


def test_the_engine_reads_what_the_file_holds_as_to_xarray_does(atlas):
    with xr.open_dataset(atlas, engine="pydrill") as ds, pydrill.Atlas(atlas) as a:
        ds.load()
        xr.testing.assert_identical(ds, a.to_xarray().load())
    with xr.open_dataset(atlas, engine="pydrill") as ds, h5py.File(atlas) as f:
        assert list(ds["wob"].values) == [40.0, 100.0, 160.0]
        assert list(ds["torque"].values) == [6.0, 8.3]
        assert list(ds["initial"].values) == ["rest", "equilibrium"]
        np.testing.assert_array_equal(ds["regime"].values, f["regime"][...])
        np.testing.assert_array_equal(ds["bit_mean"].values, f["bit_mean"][...])
        # counts: the file's fill -1 (no steady state to count at, a failed run) is NaN here
        for name in ("stick_events", "unstable"):
            raw = f[name][...]
            assert (raw == -1).any() and (raw >= 0).any(), name  # both kinds are compared
            np.testing.assert_array_equal(np.isnan(ds[name].values), raw == -1)
            np.testing.assert_array_equal(ds[name].values[raw != -1], raw[raw != -1])
        # safe: every start steady, and the fastest steady state stable (no eigenvalue to the
        # right), from the raw codes
        steady = (f["regime"][...] == fmt.REGIMES["steady"]).all(axis=-1)
        stable = f["unstable"][..., 0] == 0
        np.testing.assert_array_equal(ds["safe"].values, (steady & stable).astype("i1"))
        assert ds["safe"].values.any() and not ds["safe"].values.all()


def test_the_engine_takes_xarrays_own_arguments(atlas):
    with xr.open_dataset(atlas, engine="pydrill", chunks="auto") as ds:
        assert type(ds["bit_mean"].data).__name__ == "Array"  # dask: read lazily
        with h5py.File(atlas) as f:
            np.testing.assert_array_equal(ds["bit_mean"].values, f["bit_mean"][...])
    with xr.open_dataset(atlas, engine="pydrill", drop_variables=["message", "safe"]) as ds:
        assert "message" not in ds and "safe" not in ds and "regime" in ds
    with xr.open_dataset(atlas, engine="pydrill", drop_variables="message") as ds:
        assert "message" not in ds and "safe" in ds


def test_the_engine_refuses_what_is_not_an_atlas_naming_it(atlas, tmp_path):
    with pytest.raises(AtlasError, match=r"no-such\.h5: no such atlas"):
        xr.open_dataset(tmp_path / "no-such.h5", engine="pydrill")
    (tmp_path / "junk.h5").write_bytes(b"not an atlas")
    with pytest.raises(AtlasError, match=r"junk\.h5 is not a readable HDF5 atlas"):
        xr.open_dataset(tmp_path / "junk.h5", engine="pydrill")
    with pytest.raises(TypeError, match="opens an atlas by its path, not a BytesIO"):
        xr.open_dataset(io.BytesIO(atlas.read_bytes()), engine="pydrill")
    # not claimed when no engine is named: xarray's own HDF5 engines open it as before
    assert not AtlasBackend().guess_can_open(str(atlas))
