"""A drilling engineer's audit of a tally's diameters: every tally sheet gives pipe and bit
diameters in inches, and a bare number is m, so ``od = 5.0`` for 5 in drill pipe built a pipe
5 m across (its inertia some 10⁶ times the real one) and every command answered for it without
a word. Such a diameter is now said in a note, as a bare joint length beyond any joint is
(tests/test_cli_units_audit.py); one written with its unit, or below any bare-inch value, is not.
Expected inertias are computed here from ρ·L·π(OD⁴ − ID⁴)/32 with 1 in = 0.0254 m, not taken
from pydrill."""

import math
from pathlib import Path

import pytest
from cli_running import notes, run

from pydrill.tally import parse_tally

ROOT = Path(__file__).resolve().parents[1]
COLLARS = ROOT / "examples" / "tallies" / "5.5in-dp-8in-collars.toml"
INCH, RHO = 0.0254, 7850.0  # m; kg/m³, the tally's steel (the default)


def pipe_inertia(od: float, inner: float, length: float) -> float:
    """One joint's inertia, kg·m², from its diameters and length in m."""
    return RHO * length * math.pi * (od**4 - inner**4) / 32


def drill_pipe_with(od: str, inner: str) -> str:
    """5.5in-dp-8in-collars.toml with its drill pipe's diameters written ``od`` and ``inner``."""
    text = COLLARS.read_text()
    old = 'od = "5.5 in"\nid = "4.778 in"'
    assert text.count(old) == 1  # the drill pipe's (the heavy-weight's bore differs)
    return text.replace(old, f"od = {od}\nid = {inner}")


def test_bare_inch_diameters_are_read_as_metres_and_said(tmp_path, capsys):
    text = drill_pipe_with("5.0", "4.276")  # 5 in drill pipe, 19.5 lb/ft
    tally = parse_tally(text)
    # What the note will say is what happened: the joint is 5 m across (hand computation).
    joint = tally.sections[0]
    assert joint.joint_inertia() == pytest.approx(pipe_inertia(5.0, 4.276, 31 * 0.3048))
    meant = pipe_inertia(5.0 * INCH, 4.276 * INCH, 31 * 0.3048)
    assert joint.joint_inertia() / meant == pytest.approx(1 / INCH**4)  # 2.4e6 times too heavy
    assert [n.split(" is read as ")[0] for n in tally.notes] == [
        "section 1 (drill-pipe), od = 5.0",
        "section 1 (drill-pipe), id = 4.276",
    ]
    assert "read as 5 m" in tally.notes[0] and 'write od = "5.0 in"' in tally.notes[0]
    # every command that builds the string says it on stderr, and goes on (a note, no refusal)
    path = tmp_path / "bare.toml"
    path.write_text(text)
    code, _, err = run(capsys, "window", path, "--depth", "3000m", "--at-rpm", "60")
    assert code == 0
    said = notes(err)
    od = "section 1 (drill-pipe), od = 5.0"
    assert len(said) == 2 and said[0].startswith(f"pydrill: note: {path}: {od}")


@pytest.mark.parametrize(
    ("od", "inner", "noted"),
    [('"5.5 in"', '"4.778 in"', 0), ('"5 m"', '"4.276 m"', 0), ("0.1397", "0.1214", 0),
     ("1.0", "0.5", 0), ("1.5", "0.5", 1), ("5", "4.276", 2), ("'5'", "0.1214", 1)],
)  # fmt: skip
def test_only_a_bare_diameter_wider_than_any_pipe_is_noted(od, inner, noted):
    """1 m is wider than any drill pipe, collar or bit (36 in conductor bits: 0.91 m) and
    narrower than any pipe written in bare inches; with its unit a diameter is taken as meant."""
    said = parse_tally(drill_pipe_with(od, inner)).notes
    assert len(said) == noted, said


def test_a_bare_bit_diameter_is_noted_too():
    text = COLLARS.read_text()
    assert text.count('diameter = "8.5 in"') == 1
    tally = parse_tally(text.replace('diameter = "8.5 in"', "diameter = 4.75"))  # slim hole
    assert tally.bit_radius == 4.75 / 2  # m: T_s = μ_s W R_b 22 times the 4 3/4 in bit's
    (note,) = tally.notes
    assert note.startswith("bit.diameter = 4.75 is read as 4.75 m")
    assert 'write diameter = "4.75 in"' in note
