"""Messages a user met that pointed the wrong way or said too little: --set friction=0.5 sent
to --friction (a law, not a coefficient), --set mu and beta without a hint; a failed atlas
point called "failed" three times by query and "not computed" by safe; an empty atlas file
called "truncated or corrupt?"; Params.replace(inertias=[5 values]) blaming the stiffnesses;
window's note on several bare depths without the "a bare number is m" a single one gets."""

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import pydrill
from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.cli import main
from pydrill.journal import AtlasError
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"
OP = ["--dof", "4", "--wob", "100", "--torque", "8.3"]


def refused(capsys, *argv) -> str:
    """The last line of a command's refusal (argparse's exits; a handler's returns 2)."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exit_:
        code = exit_.code
    out, err = capsys.readouterr()
    assert code == 2 and out == "", (code, out, err)
    return err.strip().splitlines()[-1]


def ran(capsys, *argv) -> tuple[str, str]:
    assert main([str(a) for a in argv]) == 0
    return capsys.readouterr()


# --- 1. --set names that are not the string's -------------------------------------------------


def test_set_friction_names_the_coefficients_not_the_law_option(capsys):
    """--friction takes exact|karnopp: "give --friction" for --set friction=0.5 sent a
    coefficient where a law is asked. The coefficients --set takes are named instead."""
    said = refused(capsys, "simulate", *OP, "--set", "friction=0.5")
    assert "give --friction" not in said
    assert "--friction picks the friction law, exact or karnopp, not a coefficient" in said
    assert "mu_coulomb (sliding) and mu_static (at rest)" in said
    assert "e.g. --set mu_coulomb=0.5" in said
    # a law typed to --set: that one is --friction's
    said = refused(capsys, "simulate", *OP, "--set", "friction=karnopp")
    assert "give --friction karnopp" in said
    # a command without --friction: the coefficients, and no option it has not
    said = refused(capsys, "stability", *OP, "--set", "friction=0.5")
    assert "--friction" not in said and "mu_coulomb (sliding) and mu_static" in said


@pytest.mark.parametrize("command", ["simulate", "stability"])
def test_set_mu_is_sent_to_the_two_coefficients(capsys, command):
    said = refused(capsys, command, *OP, "--set", "mu=0.4")
    assert "mu is not one of the string's parameters: the bit's friction coefficients are " in said
    assert "mu_coulomb (sliding) and mu_static (at rest), e.g. --set mu_coulomb=0.4" in said
    # a typo of one keeps its did-you-mean
    said = refused(capsys, command, *OP, "--set", "mu_coulom=0.3")
    assert "(did you mean 'mu_coulomb'?)" in said and "sliding" not in said


@pytest.mark.parametrize("name", ["beta", "damping.beta"])
def test_set_beta_says_where_beta_is_set(capsys, name):
    """beta is a tally's [damping] beta (tally.py reads it there), no Params field."""
    assert "beta" in {f.name for f in __import__("dataclasses").fields(pydrill.Tally)}
    said = refused(capsys, "window", PAPER, "--depth", "3000m", "--set", f"{name}=0.2")
    assert "beta is a tally's element damping" in said
    assert "set as beta in the [damping] table of the TALLY.toml, which --set does not change" in (
        said
    )


# --- 2. a failed point: said once by query, counted as failed by safe ---------------------------

FAILING = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [20.0, 100.0, 180.0]
torque = [6.0, 14.0]
[simulation]
t_end = 100.0
max_steps = 500
initial = ["rest", "equilibrium"]
"""


@pytest.fixture(scope="module")
def failing(tmp_path_factory):
    """A small sweep whose step limit fails some of its points (the hardest stick-slip)."""
    out = tmp_path_factory.mktemp("audit4") / "failing.h5"
    report = run_sweep(parse_spec(FAILING), out, serial=True)
    assert 0 < report.failed < report.points
    return out


def _status(path):
    with h5py.File(path, "r") as f:
        return f["status"][...], f["wob"][...], f["torque"][...]


def test_query_says_a_failed_point_failed_once(failing, capsys):
    status, wobs, torques = _status(failing)
    i, j = (int(k[0]) for k in np.nonzero(status == fmt.STATUS["failed"]))
    out, _ = ran(capsys, "atlas", "query", failing, "--wob", wobs[i], "--torque", torques[j])
    (verdict,) = [line for line in out.splitlines() if line.startswith("  safe:")]
    assert verdict.count("failed") == 1, verdict
    assert verdict == (
        "  safe: no (the point failed from rest and from equilibrium: the solver gave up, no "
        "result to judge)"
    )


def test_safe_counts_failed_points_apart_from_those_not_computed(failing, tmp_path, capsys):
    """Against the status dataset: each row's failed and missing points, counted apart; the
    JSON's not_done (failed + missing) kept for the scripts that read it."""
    holed = tmp_path / "holed.h5"
    shutil.copy(failing, holed)
    with h5py.File(holed, "r+") as f:  # a point not computed yet, as an interrupted sweep's
        f["status"][0, 0] = fmt.STATUS["missing"]
        f["regime"][0, 0] = fmt.REGIMES["missing"]
    status, _, torques = _status(holed)
    out, _ = ran(capsys, "atlas", "safe", holed, "--json")
    rows = json.loads(out)["rows"]
    for row in rows:
        j = int(np.flatnonzero(torques == row["at"]["torque"])[0])
        failed = int((status[:, j] == fmt.STATUS["failed"]).sum())
        missing = int((status[:, j] == fmt.STATUS["missing"]).sum())
        assert (row["failed"], row["missing"]) == (failed, missing)
        assert row["not_done"] == failed + missing
    assert sum(r["failed"] for r in rows) >= 1 and sum(r["missing"] for r in rows) == 1
    with Atlas(holed) as atlas:
        assert [r.failed for r in atlas.safe_windows()] == [r["failed"] for r in rows]
    text, _ = ran(capsys, "atlas", "safe", holed)
    for row in rows:
        (line,) = [ln for ln in text.splitlines() if f"torque = {row['at']['torque']:g} " in ln]
        assert (f"; {row['failed']} failed" in line) == (row["failed"] > 0), line
        assert (f"; {row['missing']} not computed" in line) == (row["missing"] > 0), line


# --- 3. an empty atlas file ---------------------------------------------------------------------


def test_an_empty_atlas_file_is_called_empty(tmp_path, capsys):
    empty = tmp_path / "empty.h5"
    empty.touch()
    with pytest.raises(AtlasError) as exc:
        Atlas(empty)
    assert str(exc.value).startswith(f"{empty} is empty (0 bytes), not an atlas")
    assert "corrupt" not in str(exc.value) and "--out" in str(exc.value)
    for argv in (
        ["atlas", "info", empty],
        ["atlas", "query", empty, "--wob", "1", "--torque", "2"],
    ):
        said = refused(capsys, *argv)
        assert "is empty (0 bytes), not an atlas" in said and "corrupt" not in said, said
    spec = tmp_path / "spec.toml"
    spec.write_text(FAILING)
    for more in ([], ["--resume"]):
        said = refused(capsys, "sweep", spec, "--out", empty, "--serial", "--no-progress", *more)
        assert "is empty (0 bytes), not an atlas" in said and "damaged" not in said, said
        assert "remove it to sweep anew" in said
    assert empty.stat().st_size == 0  # refused: left as it was


# --- 4. Params.replace with inertias of another count -------------------------------------------


def test_replace_with_more_inertias_says_what_else_is_needed():
    p = pydrill.preset("reduced-scale", dof=4)
    with pytest.raises(ValueError) as exc:
        p.replace(inertias=[1.0] * 5)
    said = str(exc.value)
    assert said.startswith("inertias has 5 entries, where the string has 4"), said
    assert "give stiffnesses and dampings of 4 entries as well" in said
    assert "pydrill.preset('reduced-scale', dof=5)" in said
    # what it advises works: every list of the new length, or the preset built so
    five = pydrill.preset("reduced-scale", dof=5)
    assert p.replace(inertias=[1.0] * 5, stiffnesses=[1.0] * 4, dampings=[0.0] * 4).dof == 5
    assert five.dof == 5
    with pytest.raises(ValueError, match="give dampings of 4 entries as well"):
        p.replace(inertias=[1.0] * 5, stiffnesses=[1.0] * 4)
    assert p.replace(inertias=[2.0] * 4).inertias == (2.0,) * 4  # the same count: no change


# --- 5. window's note on several bare depths ----------------------------------------------------


def test_several_bare_depths_get_the_bare_number_hint(capsys):
    """As --depth 16000 alone gets it (the string command's note on one depth)."""
    _, err = ran(capsys, "string", PAPER, "--depth", "16000")
    single = err.strip().removeprefix("pydrill: note: ")
    assert single.endswith("; a bare number is m: for feet write 16000ft"), single
    _, err = ran(capsys, "window", PAPER, "--depth", "16000,1000", "--at-rpm", "60")
    (note,) = [ln for ln in err.splitlines() if "--depth" in ln]
    note = note.removeprefix("pydrill: note: ")
    assert note == single.replace("16000ft", "16000ft,1000ft"), note
    _, err = ran(capsys, "window", PAPER, "--depth", "16km,1000", "--at-rpm", "60")
    assert "a bare number is m" not in err  # the deepest written with its unit


# --- 1b. the same names in a sweep's spec -------------------------------------------------------

SPEC = """
[model]
preset = "reduced-scale"
dof = 4
{model}
[axes]
wob = [20.0, 100.0]
torque = [6.0]
{axes}
[simulation]
{simulation}
"""


@pytest.mark.parametrize(
    ("parts", "said"),
    [
        (dict(model="mu = 0.5"), "model.mu: unknown parameter (the bit's friction coefficients "
         "are mu_coulomb, sliding, and mu_static, at rest); allowed: "),
        (dict(model="friction = 0.5"), "mu_static, at rest; [simulation] friction picks the "
         "friction law, 'exact' or 'karnopp'); allowed: "),
        (dict(model="beta = 0.2"), "model.beta: unknown parameter (beta is a tally's element "
         "damping, every element's c = beta·k: set it as beta in the [damping] table of the "
         "TALLY.toml); allowed: "),
        (dict(axes="mu = [0.3, 0.5]"), "axes.mu: cannot be swept (the bit's friction "
         "coefficients are mu_coulomb, sliding, and mu_static, at rest); allowed: "),
        (dict(simulation="friction = 0.5"), "simulation.friction: 0.5: choose 'exact' or "
         "'karnopp' (the law; the bit's friction coefficients are [model] mu_coulomb, "),
    ],
)  # fmt: skip
def test_a_spec_names_the_coefficients_and_where_beta_is_set(parts, said):
    text = SPEC.format(**{"model": "", "axes": "", "simulation": "", **parts})
    with pytest.raises(pydrill.SpecError) as exc:
        parse_spec(text)
    assert said in str(exc.value), str(exc.value)
    # a typo of a coefficient keeps its did-you-mean
    with pytest.raises(pydrill.SpecError, match=r"\(did you mean 'mu_coulomb'\?\); allowed"):
        parse_spec(SPEC.format(model="mu_coulom = 0.5", axes="", simulation=""))
