"""Mutation guards of ``pydrill map`` (cli_map.py): its defaults and grid as --help states them,
its JSON against operating_map recomputed here on the grid the help describes, its text (units,
percentages, the checks' tally) and its option checks."""

import json
import re

import numpy as np
import pytest

import pydrill
from pydrill.cli import main
from pydrill.operating import CATEGORIES, operating_map


def _json(argv, capsys):
    assert main(["map", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_map_json_is_the_operating_map_on_the_grid_the_help_gives(capsys):
    doc = _json(["--dof", "2"], capsys)
    inputs = results = doc  # one flat object: the inputs echoed, then the results
    # --help: "default 250 N for reduced-scale", torque "a tenth of --wob-max: 25 N m at 250 N"
    assert (inputs["wob_max"], inputs["torque_max"]) == (250.0, 25.0)
    assert inputs["check"] == 0 and inputs["t_end"] is None  # no checks, no simulated time
    # 200 weights and torques from a two-hundredth of the largest up to it
    wob, torque = np.linspace(1.25, 250.0, 200), np.linspace(0.125, 25.0, 200)
    np.testing.assert_allclose(results["wob"], wob)
    np.testing.assert_allclose(results["torque"], torque)
    p = pydrill.preset("reduced-scale", dof=2)
    omap = operating_map(p, wob, torque)
    assert results["categories"] == list(CATEGORIES)
    np.testing.assert_array_equal(results["category"], omap.category)
    # a weight with no safe torque on the grid's range is null, not Infinity (not JSON)
    safe = results["safe_torque_min"]
    assert [v is None for v in safe] == list(~np.isfinite(omap.safe_torque_min))
    assert None in safe or all(np.isfinite(omap.safe_torque_min))
    assert results["checks"] == [] and results["failed_checks"] == 0
    assert doc["units"]["torque"] == "N·m" and doc["units"]["wob"] == "N"


def test_map_of_a_real_string_defaults_to_200_kn_and_20_kn_m(capsys):
    doc = _json(["--preset", "real-string"], capsys)
    assert (doc["wob_max"], doc["torque_max"]) == (2e5, 2e4)
    assert main(["map", "--preset", "real-string"]) == 0
    out = capsys.readouterr().out
    assert "W_ob 0..200 kN, u 0..20 kN m" in out


def test_map_text_percentages_are_the_fractions_and_units_follow_the_weight(capsys):
    # W_ob up to 20 kN (a real string's) and u up to 100 N m: both written in kilo units.
    argv = ["--dof", "2", "--wob-max", "20000", "--torque-max", "100"]
    doc = _json(argv, capsys)
    assert main(["map", *argv]) == 0
    out = capsys.readouterr().out
    assert "W_ob 0..20 kN, u 0..0.1 kN m" in out
    fractions = doc["fractions"]
    assert sum(fractions.values()) == pytest.approx(1.0)
    for name, frac in fractions.items():
        assert f"{100 * frac:5.1f} %  {name}" in out


def test_map_checks_are_on_the_k_by_k_grid_and_tallied(capsys):
    doc = _json(["--dof", "2", "--check", "2", "--t-end", "20"], capsys)
    inputs = results = doc  # one flat object: the inputs echoed, then the results
    assert inputs["t_end"] == 20.0 and inputs["check"] == 2
    checks = results["checks"]
    # K x K points from a K-th of each maximum up to it: W_ob 125, 250 N; u 12.5, 25 N m
    assert [(c["wob"], c["torque"]) for c in checks] == [
        (125.0, 12.5),
        (125.0, 25.0),
        (250.0, 12.5),
        (250.0, 25.0),
    ]
    p = pydrill.preset("reduced-scale", dof=2)
    for c in checks:
        r = pydrill.simulate(p, wob=c["wob"], torque=c["torque"], t_end=20.0, n_out=301)
        assert c["regime"] == r.regime and c["message"] is None
    assert results["failed_checks"] == 0
    assert main(["map", "--dof", "2", "--check", "2", "--t-end", "20"]) == 0
    out = capsys.readouterr().out
    tally: dict[str, int] = {}
    for c in checks:
        tally[c["regime"]] = tally.get(c["regime"], 0) + 1
    line = "simulated from rest: " + ", ".join(f"{k} {v}" for k, v in sorted(tally.items()))
    assert line in out.splitlines()


def test_map_options_are_checked_as_the_help_says(capsys):
    # --t-end without --check is refused by name; --check K above 40 too.
    assert main(["map", "--dof", "2", "--t-end", "10"]) != 0
    assert "--t-end" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["map", "--dof", "2", "--check", "41"])
    err = capsys.readouterr().err
    assert re.search(r"--check.*40", err)
