"""Every command's --json in one layout, for scripts: the inputs it was given (echoed), then the
results, then ``units``, then ``plot`` (the figure written), present iff --plot was given."""

import json
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from sweeping import SMALL, interrupt_mid_sweep

ROOT = Path(__file__).resolve().parents[1]
PAPER = str(ROOT / "examples" / "tallies" / "paper-eq53.toml")
CMD = [sys.executable, "-m", "pydrill"]
ANY = object()  # an input echoed, whatever its value


def run_json(*args, cwd):
    proc = subprocess.run(
        [*CMD, *map(str, args), "--json"], capture_output=True, text=True, cwd=cwd, timeout=300
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def check_layout(data: dict, inputs: dict, plot: str | None) -> None:
    """The rule: ``inputs`` (with their values) first, in that order; ``units`` after every
    result; ``plot`` last, present iff a figure was asked for (and written)."""
    keys = list(data)
    assert keys[: len(inputs)] == list(inputs), keys
    for key, value in inputs.items():
        if value is not ANY:
            assert data[key] == value, (key, data[key])
    tail = ["units", "plot"] if plot else ["units"]
    assert keys[-len(tail) :] == tail, keys
    assert len(keys) > len(inputs) + len(tail), f"no results: {keys}"
    assert isinstance(data["units"], dict) and data["units"]
    if plot:
        assert data["plot"] == plot


STRING = {"preset": "reduced-scale", "dof": 4}
CASES = {
    "simulate": (
        ["simulate", "--wob", "100", "--torque", "8.3", "--t-end", "20", "--plot", "f.png"],
        {"inputs": ANY},
    ),
    "simulate-tally": (
        "simulate --tally PAPER --depth 3000m --wob 60kN --torque 9kN*m --t-end 5".split(),
        {"inputs": ANY, "tally": {"file": PAPER, "depth": 3000.0, "lump": 1}},
    ),
    "hopf": (["hopf", "--dof", "4", "--plot", "f.png"], STRING),
    "stability-torque": (
        ["stability", "--wob", "100", "--torque", "8.3"],
        {**STRING, "wob": 100.0, "omega": None, "torque": 8.3},
    ),
    "stability-omega": (
        ["stability", "--wob", "100", "--omega", "2", "--plot", "f.png"],
        {**STRING, "wob": 100.0, "omega": 2.0, "torque": None},
    ),
    "bifurcation": (
        ["bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1", "--plot", "f.png"],
        {"preset": "reduced-scale", "dof": 2, "vary": "wob", "fixed": 8.1},
    ),
    "map": (
        ["map", "--dof", "2", "--plot", "f.png"],
        {"preset": "reduced-scale", "dof": 2, "wob_max": 250.0, "torque_max": 25.0}
        | {"check": 0, "t_end": None},
    ),
    "string": (
        ["string", PAPER, "--depth", "3000m"],
        {"tally": {"file": PAPER, "depth": 3000.0, "lump": 1}},
    ),
    "string-preset": (
        ["string", "--preset", "reduced-scale", "--dof", "3"],
        {"preset": "reduced-scale"},
    ),
    "window": (
        "window PAPER --depth 3000m --at-rpm 60 --at-wob 50kN --plot f.png".split(),
        {"tally": {"file": PAPER, "lump": 1}, "name": "paper-eq53", "depths": [3000.0]}
        | {"at_rpm": [60.0], "at_wob": [50e3]}
        | {"check": 0, "check_from": None},
    ),
    "sweep": (
        ["sweep", "s.toml", "--out", "s.h5", "--serial", "--plot", "f.png"],
        {"spec": "s.toml", "atlas": "s.h5", "part": None},
    ),
    "sweep-part": (
        ["sweep", "s.toml", "--part", "2/3", "--out", "s2.h5", "--serial"],
        {"spec": "s.toml", "atlas": "s2.h5", "part": "2/3"},
    ),
    "sweep-dry-run": (
        ["sweep", "s.toml", "--dry-run", "--serial"],
        {"dry_run": True, "spec": "s.toml", "part": None, "atlas": {"path": None, "state": "none"}}
        | {"workers": 1},
    ),
    "atlas-info": (["atlas", "info", "s.h5"], {"path": "s.h5"}),
    "atlas-export": (
        ["atlas", "export", "s.h5", "--out", "s.csv"],
        {"atlas": "s.h5", "out": "s.csv"},
    ),
    "atlas-plot": (
        ["atlas", "plot", "s.h5", "--out", "f.png"],
        {"atlas": "s.h5", "initial": "rest", "metric": None},
    ),
    "atlas-merge": (
        ["atlas", "merge", "s.h5", "lo.h5", "--out", "m.h5"],
        {"parts": ["s.h5", "lo.h5"], "out": "m.h5", "spec": None},
    ),
    "atlas-query": (
        ["atlas", "query", "s.h5", "--wob", "100", "--torque", "8.3"],
        {"atlas": "s.h5", "asked": {"wob": 100.0, "torque": 8.3}},
    ),
}


@pytest.fixture(scope="module")
def atlas_dir(tmp_path_factory):
    """A folder holding s.toml, a small sweep's spec, and s.h5, its atlas; and lo.h5, the
    same sweep at a lower W_ob (to merge with it)."""
    folder = tmp_path_factory.mktemp("json")
    (folder / "s.toml").write_text(SMALL.replace("t_end = 200.0", "t_end = 20.0"))
    run_json("sweep", "s.toml", "--out", "s.h5", "--serial", cwd=folder)
    low = (folder / "s.toml").read_text().replace("wob = [40.0, 100.0, 160.0]", "wob = [10.0]")
    (folder / "lo.toml").write_text(low)
    run_json("sweep", "lo.toml", "--out", "lo.h5", "--serial", cwd=folder)
    return folder


@pytest.mark.parametrize("name", list(CASES))
def test_every_commands_json_is_inputs_results_units_plot(name, atlas_dir, tmp_path):
    args, inputs = CASES[name]
    args = [PAPER if a == "PAPER" else a for a in args]
    cwd = atlas_dir if "s.h5" in args and args[0] == "atlas" else tmp_path
    if args[0] == "sweep":
        (tmp_path / "s.toml").write_text((atlas_dir / "s.toml").read_text())
    data = run_json(*args, cwd=cwd)
    plot = "f.png" if "--plot" in args or args[:2] == ["atlas", "plot"] else None
    check_layout(data, inputs, plot)
    if plot:
        assert (cwd / plot).stat().st_size > 0


def test_a_sweep_json_has_the_same_keys_finished_or_interrupted(atlas_dir, tmp_path):
    (tmp_path / "s.toml").write_text((atlas_dir / "s.toml").read_text())
    finished = run_json("sweep", "s.toml", "--out", "s.h5", "--serial", cwd=tmp_path)
    assert finished["interrupted"] is False
    rc, stdout, err, out = interrupt_mid_sweep(tmp_path, signal.SIGTERM, "--serial", "--json")
    assert rc == 128 + signal.SIGTERM, err
    stopped = json.loads(stdout)
    check_layout(stopped, {"spec": ANY, "atlas": str(out)}, None)
    assert set(finished) <= set(stopped), set(finished) - set(stopped)
    assert stopped["interrupted"] is True and stopped["resume"].endswith("--resume")
    assert stopped["already_done"] == 0 and 0 < stopped["computed"] == stopped["done"] < 512
    assert 0 <= stopped["failed"] <= stopped["computed"] and stopped["wall_time"] > 0


def test_the_dry_runs_time_ranges_list_their_ends_in_one_order(atlas_dir, tmp_path):
    (tmp_path / "s.toml").write_text((atlas_dir / "s.toml").read_text())
    data = run_json("sweep", "s.toml", "--dry-run", "--workers", "2", cwd=tmp_path)
    ranges = [data[k] for k in ("point_seconds", "compute_seconds", "wall_seconds")]
    assert [list(r) for r in ranges] == [["low", "estimate", "high"]] * 3
    assert data["failed"] == 0 and data["message"] is None  # null, not "", with no failure


def test_stability_json_says_how_many_eigenvalues_it_leaves_out(tmp_path):
    """stability --json lists a steady state's leading eigenvalues: a tally's string at
    3000 m has 667 and listed 6, without a word that there were more. eigenvalue_count is
    checked against the string's own size (2 dof - 1 states) and the list against the API's
    full list."""
    from pydrill.stability import stability
    from pydrill.tally import load_tally

    data = run_json(
        "stability",
        "--tally",
        PAPER,
        "--depth",
        "3000m",
        "--wob",
        "60kN",
        "--omega",
        "60rpm",
        cwd=tmp_path,
    )
    params = load_tally(PAPER).at_depth(3000.0).to_params()
    (point,) = data["equilibria"]
    assert point["eigenvalue_count"] == 2 * params.dof - 1 == 667
    (full,) = stability(params, 60e3, omega=60 * 3.141592653589793 / 30)
    assert len(full.eigenvalues) == 667
    shown = [complex(re, im) for re, im in point["eigenvalues"]]
    assert shown == pytest.approx(list(full.eigenvalues[: len(shown)]), rel=1e-9)
    assert len(shown) < 667


#: keys of a float (or floats) without a unit: fractions of a map's or a chart's area
DIMENSIONLESS = {"fractions", "safe_fraction"}


def _float_keys(data, found=None):
    """The keys under which ``data`` holds a float, at any depth (not ints, bools, strings)."""
    found = set() if found is None else found
    if isinstance(data, dict):
        for key, value in data.items():
            if key == "units" or key in DIMENSIONLESS:
                continue
            if isinstance(value, float) or (
                isinstance(value, list) and any(isinstance(v, float) for v in value)
            ):
                found.add(key)
            _float_keys(value, found)
    elif isinstance(data, list):
        for value in data:
            _float_keys(value, found)
    return found


@pytest.mark.parametrize(
    "args",
    [
        ("map", "--dof", "4", "--check", "2"),
        ("hopf", "--preset", "real-string"),
        ("stability", "--dof", "4", "--wob", "40", "--torque", "8.3"),
        ("bifurcation", "--preset", "real-string", "--vary", "wob", "--torque", "10kN*m"),
        ("bifurcation", "--preset", "real-string", "--vary", "torque", "--wob", "100kN"),
        ("window", PAPER, "--depth", "1000m,3000m", "--check", "2", "--check-dof", "10"),
    ],
    ids=lambda a: " ".join(a[:1] + a[-2:]),
)
def test_every_number_of_the_analysis_json_has_its_unit(args, tmp_path):
    """bifurcation's 'fixed' (a torque or a weight, by --vary), map's safe_torque_min and
    window's edges (wob_max_stable, rpm_min_unstuck, ...) and checks had none; a script had to
    know them from the text."""
    data = run_json(*args, cwd=tmp_path)
    missing = _float_keys(data) - set(data["units"])
    assert not missing, missing
    if args[0] == "bifurcation":
        assert data["units"]["fixed"] == {"wob": "N·m", "torque": "N"}[data["vary"]]


def test_hopf_and_bifurcation_give_one_lyapunov_coefficient_one_unit(tmp_path):
    """The same crossing's l1 in hopf --json and bifurcation --json is the same number, so in
    the same unit (bifurcation said 1/s per (rad/s)², hopf 1/s per amplitude²)."""
    hopf = run_json("hopf", "--preset", "real-string", cwd=tmp_path)
    branch = run_json(
        "bifurcation", "--preset", "real-string", "--vary", "torque", "--wob", "100kN", cwd=tmp_path
    )
    l1 = {round(c["frequency"], 6): c["lyapunov"] for c in hopf["crossings"] if c["lyapunov"]}
    hb = [p for p in branch["points"] if p["type"] == "HB"]
    assert len(hb) == 2
    for p in hb:
        assert p["lyapunov"] == pytest.approx(l1[round(p["frequency"], 6)], rel=1e-9)
    assert branch["units"]["lyapunov"] == hopf["units"]["lyapunov"]


@pytest.mark.parametrize(
    "args",
    [
        ("hopf",),
        ("stability", "--wob", "60kN", "--omega", "60rpm"),
        ("bifurcation", "--vary", "wob", "--torque", "10kN*m"),
        ("map",),
    ],
    ids=lambda a: a[0],
)
def test_a_tallys_string_is_echoed_as_simulate_echoes_it(args, tmp_path):
    """'preset' held "paper-eq53 at 1003.5 m", no preset: a script reading it as one was
    misled. Now null, with the tally under 'tally' and the string under 'string', as
    simulate --json gives them (the same string: the tally's own length at that depth)."""
    from pydrill.tally import load_tally

    string = ("--tally", PAPER, "--depth", "1000m")
    data = run_json(args[0], *string, *args[1:], cwd=tmp_path)
    sim = run_json("simulate", *string, "--wob", "60kN", "--torque", "9kN*m", cwd=tmp_path)
    length = load_tally(PAPER).at_depth(1000.0).length
    assert data["preset"] is None
    assert data["string"] == sim["string"] == f"paper-eq53 at {length:.1f} m"
    assert data["tally"] == sim["tally"] == {"file": PAPER, "depth": 1000.0, "lump": 1}
    assert list(data).index("string") < list(data).index("dof")
