"""``pydrill window --set``: the tally's string with some of its values changed (what if the mud
damped the bit more, or the rock were more abrasive), said in the text, the JSON and the
figure, and refused naming the option."""

import argparse
import dataclasses
import json
import shlex

import numpy as np
import pytest
from sweeping import ROOT

import pydrill
import pydrill.plot
from pydrill.cli import main
from pydrill.cli_string import point_command
from pydrill.tally import load_tally
from pydrill.window import RPM

PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
WINDOW = ["window", str(PAPER), "--depth", "3000m"]


def window_json(*options: str, capsys) -> dict:
    assert main([*WINDOW, *options, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_the_stall_edge_is_where_the_changed_string_needs_its_static_torque(capsys):
    """The stall edge: the heaviest W_ob whose steady torque at a speed still exceeds the
    static friction T_s = μ_sb W_ob R_b. With μ_sb and c_b changed, each reported edge is
    where the changed string's steady torque equals its own T_s (pydrill.equilibrium_torque),
    and not where the tally's own string's does."""
    asis = window_json(capsys=capsys)
    d = window_json("--set", "bit_damping=100", "--set", "mu_static=0.9", capsys=capsys)
    assert d["set"] == {"bit_damping": 100.0, "mu_static": 0.9}
    assert d["units"]["bit_damping"] == "N·m·s/rad" and d["units"]["mu_static"] == "1"
    tally = load_tally(PAPER)
    changed = dataclasses.replace(tally, bit_damping=100.0, mu_static=0.9)
    p = changed.at_depth(3000.0).to_params()
    own = tally.at_depth(3000.0).to_params()
    checked = 0
    for rpm, wob in zip(d["at_rpm"], d["wob_max_unstuck"], strict=True):
        if wob is None:
            continue
        held = pydrill.equilibrium_torque(p, wob, rpm * RPM)
        assert held == pytest.approx(p.static_torque(wob), rel=1e-6)
        off = pydrill.equilibrium_torque(own, wob, rpm * RPM) / own.static_torque(wob)
        assert abs(off - 1) > 0.01
        checked += 1
    assert checked >= 5
    assert not np.allclose(
        [w or 0.0 for w in asis["wob_max_unstuck"]], [w or 0.0 for w in d["wob_max_unstuck"]]
    )


def test_the_text_and_the_figure_say_what_was_changed(capsys, monkeypatch, tmp_path):
    titles = []

    def keep_title(fig, path, *args, **kwargs):
        titles.extend(t.get_text() for ax in fig.axes for t in [ax.title] if t.get_text())
        titles.extend([fig._suptitle.get_text()] if fig._suptitle else [])

    monkeypatch.setattr(pydrill.plot, "save", keep_title)
    assert main([*WINDOW, "--set", "bit_damping=100", "--plot", str(tmp_path / "w.png")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "changed         bit_damping = 100 N·m·s/rad"
    assert out[1].startswith("paper-eq53: heaviest safe weight on bit")
    assert titles[0].startswith("paper-eq53 (bit_damping = 100 N·m·s/rad) at 3,000 m")
    titles.clear()
    depths = ["window", str(PAPER), "--depth", "1000m,3000m", "--set", "mu_static=0.9"]
    assert main([*depths, "--plot", str(tmp_path / "d.png")]) == 0
    assert any(t.startswith("paper-eq53 (mu_static = 0.9): safe operating window") for t in titles)


def test_a_failed_checks_command_line_carries_the_changes(capsys):
    """A check that fails prints the ``pydrill simulate`` line that runs it alone: with --set,
    that line must build the same changed string."""
    args = argparse.Namespace(
        tally=str(PAPER), depth=None, lump=None, dof=None, set_params=["bit_damping=100"]
    )
    line = point_command(args, 20e3, 9e3, depth="3000m", dof=12, initial="equilibrium")
    assert "--set bit_damping=100" in line
    argv = shlex.split(line)[1:]
    assert main([*argv, "--t-end", "10", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["inputs"]["bit_damping"] == 100.0 and d["set"] == {"bit_damping": 100.0}


@pytest.mark.parametrize(
    ("item", "said"),
    [
        ("karnopp_band=1e-3", "--set karnopp_band: the window and its checks use the exact "
         "friction law, which has no band; window's --set takes top_damping, bit_damping"),
        ("mu_static=0.1", "--set mu_static = 0.1 is not allowed: need mu_static > mu_coulomb"),
        ("bit_dampng=100", "bit_dampng is not one of the string's parameters (did you mean "
         "'bit_damping'?)"),
        ("bit_radius=3 kg", "--set 'bit_radius=3 kg': bit_radius = '3 kg': unit 'kg' is not a "
         "length unit"),
    ],
)  # fmt: skip
def test_a_bad_set_is_refused_before_anything_is_written(item, said, capsys, tmp_path):
    plot = tmp_path / "w.png"
    assert main([*WINDOW, "--set", item, "--plot", str(plot)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and not plot.exists()
    assert said in err and len(err.strip().splitlines()) == 1, err
