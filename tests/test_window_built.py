"""pydrill window says what its stick-slip edge is and how long the string it built is.

At shallow depth the steady state's first instability is the fold (a real eigenvalue), not a
Hopf pair, yet the chart's legend said "first Hopf"; and the string of whole joints is up to a
joint longer than the depth asked, which the tables, the title and the JSON did not say. Both
are checked against what is computed here another way: the eigenvalues just past δ_c (LAPACK,
not the crossings), and the joint count from the tally's file."""

import json
import math
import tomllib
from pathlib import Path

import matplotlib
import numpy as np
import pytest

import pydrill
from pydrill.cli import main
from pydrill.stability import eigenvalues
from pydrill.units import parse
from pydrill.window import Limits

matplotlib.use("Agg")
TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def _built(depth: float) -> float:
    """The string's length at ``depth`` from the file: the BHA, then whole drill-pipe joints."""
    sections = tomllib.loads(TALLY.read_text())["section"]
    rest = sum(s["count"] * parse(s["length"], "length") for s in sections[1:])
    joint = parse(sections[0]["length"], "length")
    assert sections[0]["kind"] == "drill-pipe"
    return rest + math.ceil((depth - rest) / joint) * joint


@pytest.mark.parametrize(("depth", "edge"), [(300.0, "fold"), (1000.0, "first Hopf")])
def test_the_legend_names_the_edge_the_eigenvalues_show(depth, edge):
    from pydrill.plot_window import window_figure

    p = pydrill.load_tally(TALLY).at_depth(depth).to_params()
    limits = Limits.of(p)
    # just past δ_c the steady state's unstable eigenvalue is real at a fold, a pair at a Hopf
    lam = eigenvalues(p, limits.delta_limit * (1 + 1e-6))
    unstable = lam[lam.real > 0]
    assert unstable.size in (1, 2)
    assert (np.abs(unstable.imag).max() < 1e-6 * np.abs(unstable).max()) == (edge == "fold")
    fig = window_figure("t", depth, limits, 300e3, 200.0, length=_built(depth))
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert f"stick-slip edge ({edge})" in labels
    title = fig.axes[0].get_title()
    assert f"{depth:,.0f} m ({depth / 0.3048:,.0f} ft; string {_built(depth):,.6g} m)" in title


def test_text_and_json_give_the_length_of_the_string_built(capsys):
    exact = _built(1000.0)  # 1003.5 m: a depth of whole joints, so no note for it
    depths = f"300m,{exact}m"
    assert main(["window", str(TALLY), "--depth", depths, "--at-rpm", "60"]) == 0
    lines = capsys.readouterr().out.splitlines()
    # the note names the depth built longer and only that one
    assert f"strings of whole joints: 300 m (string {_built(300.0):g} m)" in lines
    assert _built(300.0) == 301.5
    assert main(["window", str(TALLY), "--depth", depths, "--at-rpm", "60", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    got = [(w["depth"], w["string_length"]) for w in doc["windows"]]
    np.testing.assert_allclose(got, [(300.0, 301.5), (exact, exact)], rtol=1e-12)
    assert doc["units"]["string_length"] == "m"
