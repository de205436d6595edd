"""``pydrill atlas plot --json``: what the figure drew, against the atlas read by h5py."""

import json

import h5py
import numpy as np
import pytest
from sweeping import SMALL

from pydrill.cli import main
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    out = tmp_path_factory.mktemp("plot") / "small.h5"
    spec = SMALL.replace("t_end = 200.0", "t_end = 20.0")
    run_sweep(parse_spec(spec), out, serial=True)
    return out


def plot_json(*args: str, capsys) -> dict:
    assert main(["atlas", "plot", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def raw_counts(path, initial: str, **at: int) -> dict[str, int]:
    """Regimes of one start, by name, straight from HDF5 (the enum's own names)."""
    with h5py.File(path, "r") as f:
        names = {v: k for k, v in h5py.check_enum_dtype(f["regime"].dtype).items()}
        starts = [x.decode() if isinstance(x, bytes) else x for x in f["initial"][...]]
        codes = f["regime"][..., starts.index(initial)]
        index = tuple(at.get(name, slice(None)) for name in ("wob", "torque"))
        codes = codes[index]
    found, counts = np.unique(codes, return_counts=True)
    return {names[int(c)]: int(n) for c, n in zip(found, counts, strict=True)}


def test_a_map_counts_its_regimes_as_the_file_holds_them(atlas, tmp_path, capsys):
    figure = tmp_path / "map.png"
    data = plot_json(str(atlas), "--out", str(figure), "--initial", "equilibrium", capsys=capsys)
    assert figure.stat().st_size > 0 and data["plot"] == str(figure)
    assert (data["x"], data["y"], data["profile"], data["held"]) == ("wob", "torque", False, {})
    assert data["initial"] == "equilibrium" and data["points"] == 6
    assert data["regimes"] == raw_counts(atlas, "equilibrium")


def test_a_profile_holds_the_grid_value_nearest_the_one_asked(atlas, tmp_path, capsys):
    figure = tmp_path / "line.png"
    data = plot_json(str(atlas), "--out", str(figure), "--set", "torque=8", capsys=capsys)
    assert data["profile"] is True and data["y"] is None and data["x"] == "wob"
    assert data["held"] == {"torque": 8.3} and data["units"]["held"] == {"torque": "N·m"}
    assert data["points"] == 3 and data["initial"] == "rest"
    assert data["regimes"] == raw_counts(atlas, "rest", torque=1)
