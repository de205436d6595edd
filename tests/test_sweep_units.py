"""What pydrill sweep says of the values of a spec, with their units: the refusal of an atlas
of another sweep names the values that differ as atlas info gives them (kN, kN·m, m)."""

from pathlib import Path

import pytest

from pydrill.spec import parse_spec
from pydrill.sweep import AtlasError, run_sweep

TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_a_refusal_of_another_sweep_gives_its_values_with_their_units(tmp_path):
    """'holds a different sweep (axes.wob: 22 values 20000 ... 120000 in this spec, ...)': no
    unit, so a real string's 20 kN read as 20000 of nothing. The values differing are given as
    atlas info gives them (kN, kN·m), a fixed torque too."""
    text = (
        f'[model]\ntally = "{TALLY}"\ndof = 4\ntorque = 9000.0\n'
        "[axes]\nwob = { start = 20000.0, stop = 120000.0, num = 5 }\n"
        "depth = [1000.0, 2000.0]\n"
        '[simulation]\nt_end = 5.0\ninitial = ["rest"]\n'
    )
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(text), out, serial=True)
    other = text.replace("num = 5", "num = 6").replace("torque = 9000.0", "torque = 10000.0")
    other = other.replace("[1000.0, 2000.0]", "[1000.0, 3000.0]")
    with pytest.raises(AtlasError) as refused:
        run_sweep(parse_spec(other), out, serial=True)
    message = str(refused.value)
    assert "model.torque: 10 kN·m in this spec, 9 kN·m in the atlas" in message
    assert "axes.wob: 6 values 20 kN ... 120 kN in this spec, 5 values 20 kN ... 120 kN" in message
    assert "axes.depth: [1000 m, 3000 m] in this spec, [1000 m, 2000 m] in the atlas" in message
