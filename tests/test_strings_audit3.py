"""A drilling engineer's audit of tallies (continued from tests/test_strings_audit2.py): a
sweep's spec naming a tally."""

from pathlib import Path

import pytest

from pydrill.spec import SpecError, parse_spec

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"
SPEC = """[model]
tally = "{tally}"
dof = 8
depth = {depth}
[axes]
wob = {{ start = "20 kN", stop = "120 kN", num = 3 }}
torque = {{ start = "4 kN·m", stop = "14 kN·m", num = 3 }}
[simulation]
t_end = 20.0
"""


def test_several_model_depths_are_pointed_to_the_depth_axis(tmp_path):
    """The guide's spec says 'depth = "3000 m"  # ... (or an axis: depth = [...])': a list
    there was refused as 'a depth > 0 (m, or '3000 ft')', which a list of depths > 0 is."""
    text = SPEC.format(tally=PAPER, depth='["1000 m", "3000 m"]')
    with pytest.raises(SpecError) as info:
        parse_spec(text, base=tmp_path)
    assert str(info.value).startswith("model.depth: ['1000 m', '3000 m'] is not allowed")
    assert "for several, make depth an axis: [axes] depth = [...]" in str(info.value)
    # as an axis, the same depths are taken
    axis = text.replace('depth = ["1000 m", "3000 m"]\n', "").replace(
        "[axes]\n", '[axes]\ndepth = ["1000 m", "3000 m"]\n'
    )
    spec = parse_spec(axis, base=tmp_path)
    assert list(spec.axes["depth"]) == [1000.0, 3000.0]
    assert parse_spec(SPEC.format(tally=PAPER, depth='"3000 m"'), base=tmp_path) is not None


def test_window_json_is_si_but_its_speeds_in_rpm(capsys):
    """README and the guide said window --json gives every number in SI: its speeds are rpm,
    as on the chart (its units table said so). Every unit it names is SI or rpm."""
    import json

    from cli_running import run

    code, out, _ = run(capsys, "window", PAPER, "--depth", "3000m", "--check", "1", "--json")
    assert code == 0
    named = json.loads(out)["units"]
    speeds = {k for k, v in named.items() if v == "rpm"}
    assert speeds == {
        "at_rpm", "rpm", "min_rpm", "rpm_min", "rpm_min_stable", "rpm_min_unstuck", "bit_rpm"
    }  # fmt: skip
    assert {v for k, v in named.items() if k not in speeds} <= {"m", "N", "N·m·s/rad", "N·m"}


@pytest.mark.parametrize(
    "written", ["59300 lb·ft2", "59300 lb-ft2", "59300 lbm·ft²", "59300 lb ft^2", "59300 LB-FT2"]
)
def test_a_top_drive_inertia_in_field_units(written, tmp_path):
    """A US top drive's sheet gives its inertia as WR², lb·ft²: the tally took kg·m² only,
    where it reads every other quantity in field units. 1 lb·ft² = 0.45359237 × 0.3048² kg·m²."""
    from pydrill.tally import parse_tally
    from pydrill.units import parse

    text = PAPER.read_text(encoding="utf-8").replace("inertia = 2122.0 ", f'inertia = "{written}" ')
    assert f'inertia = "{written}"' in text
    assert parse_tally(text).top_inertia == pytest.approx(59300 * 0.45359237 * 0.3048**2)
    assert parse(written, "inertia") == pytest.approx(2498.9085, rel=1e-7)
    with pytest.raises(ValueError, match="is not a torque unit"):
        parse(written, "torque")  # lb-ft is a torque; lb-ft2 is not


@pytest.mark.parametrize(
    ("written", "seconds"),
    [('"0.2 s"', 0.2), ('"0.35s"', 0.35), ('"200 ms"', 0.2), ("0.2", 0.2), ('"0.2"', 0.2)],
)
def test_beta_takes_its_unit_as_every_quantity_of_a_tally_does(written, seconds):
    """beta = "0.2 s" was refused as 'not allowed: a finite number of seconds'; the element
    dampings are beta times the stiffnesses (c = beta * k), checked here against that."""
    from pydrill.tally import parse_tally

    text = PAPER.read_text(encoding="utf-8").replace("beta = 0.2 ", f"beta = {written} ")
    assert f"beta = {written}" in text
    tally = parse_tally(text)
    assert tally.beta == pytest.approx(seconds, rel=1e-12)
    p = tally.to_params(dof=4)
    assert p.dampings == pytest.approx([seconds * k for k in p.stiffnesses], rel=1e-12)


@pytest.mark.parametrize("written", ['"-0.2 s"', '"nan s"', '"0.2 h"', '"x s"'])
def test_a_beta_that_is_no_time_is_refused_as_written(written):
    from pydrill.tally import TallyError, parse_tally

    text = PAPER.read_text(encoding="utf-8").replace("beta = 0.2 ", f"beta = {written} ")
    with pytest.raises(TallyError) as info:
        parse_tally(text)
    shown = written.strip('"')
    assert str(info.value).startswith(f"damping.beta = '{shown}' is not allowed: a finite number")
