"""Units in a spec written by hand, as a newcomer writes one: a range with a unit on one end
and a bare number on the other was read as two different units without a word (20 kN ...
120 N); and one point is "1 point"."""

import subprocess

import pytest
from sweeping import CMD

from pydrill.spec import SpecError, parse_spec

BASE = """
[model]
preset = "reduced-scale"
dof = 4
torque = 8.3
[axes]
{axis}
[simulation]
t_end = 20.0
initial = ["rest"]
"""


@pytest.mark.parametrize(
    "axis, said",
    [
        (
            'wob = { start = "0.02 kN", stop = 120, num = 5 }',
            "axes.wob: start = '0.02 kN' has a unit and stop = 120 has none (read as 120 N)",
        ),
        (
            'wob = { start = 20, stop = "0.12 kN", num = 5 }',
            "axes.wob: stop = '0.12 kN' has a unit and start = 20 has none (read as 20 N)",
        ),
    ],
)
def test_a_range_with_a_unit_on_one_end_only_is_refused(axis, said):
    text = BASE.format(axis=axis)
    with pytest.raises(SpecError) as refused:
        parse_spec(text)
    assert said in str(refused.value) and "give both ends their unit, or neither" in str(
        refused.value
    )


@pytest.mark.parametrize(
    "axis, values",
    [
        ('wob = { start = 20.0, stop = "120 N", num = 2 }', [20.0, 120.0]),  # alike: SI both
        ('wob = { start = "20 N", stop = "0.12 kN", num = 2 }', [20.0, 120.0]),
        ("wob = { start = 20.0, stop = 120.0, num = 2 }", [20.0, 120.0]),
    ],
)
def test_ranges_whose_ends_agree_are_read(axis, values):
    assert parse_spec(BASE.format(axis=axis)).axes["wob"].tolist() == values


def test_one_point_is_one_point(tmp_path):
    spec = tmp_path / "one.toml"
    spec.write_text(BASE.format(axis="wob = [100.0]"))
    dry = subprocess.run(
        [*CMD, "sweep", str(spec), "--dry-run"], capture_output=True, text=True, check=True
    )
    assert dry.stdout.startswith(f"{spec}: 1 point (1 wob), from rest\n")
    out = tmp_path / "one.h5"
    run = subprocess.run(
        [*CMD, "sweep", str(spec), "--out", str(out), "--serial"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert run.stdout.startswith(f"{out}: 1 point, 1 computed now (0 failed)")
