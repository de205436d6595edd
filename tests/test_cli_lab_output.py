"""The text of simulate, stability and hopf as a newcomer reads it: speeds in rpm beside rad/s,
units on every number, plain words beside the jargon, and counts of one in the singular.

Each check compares the text with something computed apart from it: the rpm from the
``--json`` velocities (rpm = omega * 60 / (2 pi)), the unit from ``--json``'s own unit table,
counts of one from runs that have exactly one (checked in ``--json`` too)."""

import json
import math
import re
from pathlib import Path

import pytest

from pydrill import cli, stability

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
NUMBER = r"-?\d+(?:\.\d*)?(?:e[+-]?\d+)?"


def run(capsys, *args):
    assert cli.main([str(a) for a in args]) == 0
    return capsys.readouterr().out


def both(capsys, *args):
    """The text and the --json of one command line."""
    return run(capsys, *args), json.loads(run(capsys, *args, "--json"))


def line(text, label):
    [found] = [x for x in text.splitlines() if x.startswith(label)]
    return found


def rpm(omega):
    return omega * 60 / (2 * math.pi)


def close(shown, exact, digits=4):
    """``shown`` is ``exact`` written to ``digits`` significant digits."""
    if exact == 0:
        return float(shown) == 0
    unit = 10 ** (math.floor(math.log10(abs(exact))) - digits + 1)
    return abs(float(shown) - exact) <= 0.5 * unit * (1 + 1e-9)


@pytest.mark.parametrize(
    "args",
    [
        ("--dof", 4, "--wob", 100, "--torque", 8.3),  # stick-slip, one steady state
        ("--dof", 4, "--wob", 130, "--torque", 8.3, "--t-end", 100),  # two steady states
    ],
)
def test_simulate_gives_rpm_beside_the_top_and_steady_speeds(capsys, args):
    text, data = both(capsys, "simulate", *args)
    top = line(text, "top velocity")
    [mean_rpm] = re.findall(rf"\(mean ({NUMBER}) rpm\)", top)
    assert close(mean_rpm, rpm(data["top_velocity"]["mean"]))
    steady = line(text, "steady states")
    # (a steady state past the fold says so after its rpm: tests/test_steady_states_past_fold.py)
    pairs = re.findall(
        rf"({NUMBER}) rad/s \(({NUMBER}) rpm(?:, unstable: past the fold)?\)", steady
    )
    assert len(pairs) == len(data["omega_equilibrium"]) >= 1
    for (rad, r), omega in zip(pairs, data["omega_equilibrium"], strict=True):
        assert close(rad, omega, 6) and close(r, rpm(omega))
    # the bit line's rpm, as it was, in the same form
    [bit_rpm] = re.findall(rf"\(mean ({NUMBER}) rpm\)", line(text, "bit velocity"))
    assert close(bit_rpm, rpm(data["bit_velocity"]["mean"]))


@pytest.mark.parametrize(
    "args, wob",
    [
        (("--dof", 4, "--wob", 40, "--torque", 8.3), "40 N"),
        (("--dof", 2, "--wob", 100, "--omega", 2), "100 N"),
        (("--tally", PAPER, "--depth", "3000m", "--wob", "60kN", "--omega", "60rpm"), "60 kN"),
    ],
)
def test_stability_states_units_and_plain_words(capsys, args, wob):
    text, data = both(capsys, "stability", *args)
    [point] = data["equilibria"]
    unit = data["units"]["delta"].replace("·", " ")  # N·m·s/rad, as the text writes units
    assert unit == "N m s/rad"
    verdict = line(text, "verdict")
    [margin] = re.findall(rf"delta margin ({NUMBER}) {re.escape(unit)},", verdict)
    assert close(margin, point["delta_margin"])
    [abscissa] = re.findall(rf"spectral abscissa ({NUMBER}) 1/s", verdict)
    assert close(abscissa, point["spectral_abscissa"])
    # what the two mean, in words, right under them: the abscissa's sign says which mode
    mode = "fastest-growing" if point["spectral_abscissa"] > 0 else "slowest-decaying"
    assert f"spectral abscissa: the growth rate of the {mode} mode" in text
    assert "delta margin: delta's distance to the nearest critical slope" in text
    # the operating point names its weight on bit, as --json does
    assert line(text, "steady state").endswith(f"at W_ob = {wob}")
    assert point["wob"] == pytest.approx(float(wob.split()[0]) * (1e3 if "kN" in wob else 1))


def test_counts_of_one_are_singular(capsys):
    # One slip from rest, then steady drilling: a single switch in all.
    text, data = both(capsys, "simulate", "--dof", 4, "--wob", 40, "--torque", 8.3)
    assert data["solver"]["switches"] == 1
    assert ", 1 switch," in line(text, "solver")
    # One stick in the judged window of a short run.
    text, data = both(capsys, "simulate", "--dof", 4, "--wob", 100, "--torque", 8.3, "--t-end", 30)
    assert data["stick_events"] == 1
    assert "s, 1 stick event" in line(text, "stuck")
    assert re.search(r"\b1 stick event\b(?!s)", text)
    # One eigenvalue in the right half-plane.
    text, data = both(capsys, "stability", "--dof", 2, "--wob", 100, "--omega", 2)
    [point] = data["equilibria"]
    assert point["unstable_eigenvalues"] == 1
    assert "UNSTABLE (1 eigenvalue in Re > 0)" in line(text, "verdict")


def test_hopf_counts_one_crossing_in_the_singular(capsys, monkeypatch):
    # No preset has a single Hopf crossing: keep the first of the 2-inertia string's and its fold.
    real = stability.critical_deltas

    def one_hopf(params):
        crossings = real(params)
        hopf = next(c for c in crossings if c.type == "hopf")
        return [hopf, *(c for c in crossings if c.type == "fold")]

    monkeypatch.setattr(stability, "critical_deltas", one_hopf)
    text = run(capsys, "hopf", "--dof", 2)
    assert text.splitlines()[0] == "reduced-scale, dof 2: 1 Hopf crossing, 1 fold"
    monkeypatch.undo()
    assert run(capsys, "hopf", "--dof", 2).splitlines()[0].endswith("2 Hopf crossings, 1 fold")


def test_no_count_of_one_takes_a_plural(capsys):
    """Across the runs above that count one of something, no "1 <plural>" is left."""
    plural = re.compile(
        r"(?<![\d.,/])1 (switches|stick events|eigenvalues|Hopf crossings|folds|steps)\b"
    )
    for args in (
        ("simulate", "--dof", 4, "--wob", 40, "--torque", 8.3),
        ("simulate", "--dof", 4, "--wob", 100, "--torque", 8.3, "--t-end", 30),
        ("stability", "--dof", 2, "--wob", 100, "--omega", 2),
    ):
        text = run(capsys, *args)
        assert not plural.search(text), text


@pytest.mark.parametrize(
    ("args", "real"),
    [
        (["--dof", "4", "--wob", "40", "--torque", "8.3"], False),
        (["--dof", "2", "--wob", "100", "--omega", "2"], False),
        (["--tally", PAPER, "--depth", "1000m", "--wob", "60kN", "--omega", "60rpm"], True),
    ],
)
def test_stability_torque_in_kilo_only_for_a_real_string_and_every_eigenvalue_said(
    capsys, args, real
):
    """A laboratory string's 'u = 8.3 N m (0.0083 kN m)' lost its kN m; the eigenvalue line
    ended ', ...' even where it showed all of them (dof 2 has three)."""
    text, data = both(capsys, "stability", *args)
    (eq,) = data["equilibria"]
    head = line(text, "steady state")
    kn = re.search(rf"\(({NUMBER}) kN m\)", head)
    assert (kn is not None) == real
    if real:
        assert float(kn.group(1)) == pytest.approx(eq["torque"] / 1e3, rel=1e-3)
    shown = line(text, "eigenvalues").removeprefix("eigenvalues").strip()
    values = [v for v in shown.split(", ") if v != "..."]
    assert len(values) == min(4, len(eq["eigenvalues"]))
    assert shown.endswith(", ...") == (len(eq["eigenvalues"]) > 4)
