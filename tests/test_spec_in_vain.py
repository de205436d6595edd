"""A spec key that changes nothing (a Karnopp band under the exact friction law), and a part's
atlas resumed as another part of the same spec. Checked against simulations that show the
band has no effect, and against the part the atlas really is (which resumes it)."""

import numpy as np
import pytest

import pydrill
from pydrill.cli_sweep import spec_notes
from pydrill.journal import read_existing
from pydrill.model import preset
from pydrill.spec import SpecError, parse_spec
from pydrill.sweep import AtlasError, run_sweep

BAND = """
[model]
preset = "reduced-scale"
dof = 3
torque = 8.3
[axes]
wob = [60.0, 100.0]
karnopp_band = [1e-6, 0.1]
[simulation]
t_end = 30.0
initial = ["rest"]
"""


def _bit(friction: str, band: float) -> np.ndarray:
    p = preset("reduced-scale", dof=3).replace(karnopp_band=band)
    run = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=30.0, friction=friction, n_out=301)
    return run.bit_velocity


def test_a_karnopp_band_axis_is_refused_with_the_exact_law_where_it_changes_nothing():
    # The reason, by brute force: under the exact law the band's values run alike to the
    # last bit, under Karnopp's they do not (so the axis means something there).
    np.testing.assert_array_equal(_bit("exact", 1e-6), _bit("exact", 0.1))
    assert not np.array_equal(_bit("karnopp", 1e-6), _bit("karnopp", 0.1))
    with pytest.raises(SpecError, match=r"^axes\.karnopp_band: .*friction = 'karnopp'"):
        parse_spec(BAND)
    karnopp = parse_spec(
        BAND.replace('initial = ["rest"]', 'initial = ["rest"]\nfriction = "karnopp"')
    )
    assert list(karnopp.axes) == ["wob", "karnopp_band"]


def test_a_karnopp_band_held_in_model_with_the_exact_law_is_noted(capsys):
    held = BAND.replace("karnopp_band = [1e-6, 0.1]\n", "").replace(
        "torque = 8.3\n", "torque = 8.3\nkarnopp_band = 0.1\n"
    )
    spec_notes(parse_spec(held))
    assert capsys.readouterr().err == (
        "pydrill: note: model.karnopp_band has no effect with [simulation] friction = 'exact' "
        "(the band is the Karnopp law's); set friction = 'karnopp' to use it\n"
    )
    spec_notes(parse_spec(held.replace("t_end = 30.0", 't_end = 30.0\nfriction = "karnopp"')))
    assert capsys.readouterr().err == ""  # where it acts: nothing to say


WHOLE = """
[model]
preset = "reduced-scale"
dof = 3
torque = 8.3
[axes]
wob = [40.0, 60.0, 100.0, 120.0]
[simulation]
t_end = 30.0
initial = ["rest"]
"""


def test_a_part_resumed_as_another_part_is_told_which_it_is(tmp_path):
    whole = parse_spec(WHOLE)
    out = tmp_path / "part1.h5"
    run_sweep(whole.part(1, 2), out, serial=True)
    assert read_existing(whole.part(1, 2), out, resume=True) is not None  # the part it is
    with pytest.raises(AtlasError, match=r"it is part 1 of 2 of .*, not part 2: resume it as "):
        read_existing(whole.part(2, 2), out, resume=True)
    # another spec's part 2 of 2 (t_end differs): not this atlas's spec, no hint
    other = parse_spec(WHOLE.replace("t_end = 30.0", "t_end = 31.0")).part(2, 2)
    with pytest.raises(AtlasError) as refused:
        read_existing(other, out, resume=True)
    assert "it is part" not in str(refused.value)
