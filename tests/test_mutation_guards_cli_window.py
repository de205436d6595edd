"""What ``pydrill window`` prints, run in-process, against the Python API and by hand.

Found by a mutation audit of the command line's output layer: no test compared a real window
run's document or tables with the analysis. Here the JSON's safe fraction, edges and checks are
checked against the closed-form edges (``Limits``), the eigenvalues and the sliding condition
(as tests/test_window.py judges a point), and the text tables against the same edges converted
by factors written out here (1 klbf = 4.4482216152605 kN, 1 ft = 0.3048 m).
"""

import contextlib
import io
import json
import math

import numpy as np
import pytest
from sweeping import ROOT

import pydrill
from pydrill import cli
from pydrill import stability as st
from pydrill.tally import load_tally
from pydrill.window import Limits

TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
KLBF = 4448.2216152605  # N
FT = 0.3048  # m
RAD_S = math.pi / 30  # one rpm in rad/s
# two depths; a 3 x 3 check of a 4-inertia model for 5 s each (cheap): at 3000 m the stick-slip
# edge binds at 15 and 20 rpm, the stall edge above (the `*` marks differ along a row)
ARGS = ["window", TALLY, "--depth", "3000m,5000m", "--at-rpm", "15,20,30,90"]
CHECK = ["--check", "3", "--check-dof", "4", "--t-end", "5"]


@pytest.fixture(scope="module")
def outputs():
    """The JSON document and the text of the same window run (capsys is per test; the run is
    done once for the module, in this process)."""

    def once(*extra):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = cli.main([str(a) for a in (*ARGS, *CHECK, *extra)])
        assert code == 0, err.getvalue()
        return out.getvalue()

    return json.loads(once("--json")), once()


def _params(depth, dof=None):
    return load_tally(TALLY).at_depth(depth).to_params(dof=dof)


def test_window_json_is_the_closed_form_edges_and_their_safe_fraction(outputs):
    d, _ = outputs
    wob, rpm = np.array(d["wob"]), np.array(d["rpm"])
    assert len(wob) == len(rpm) == 150 and wob[-1] == 3e5 and rpm[-1] == 200.0
    at_rpm = np.array([15.0, 20.0, 30.0, 90.0])
    for win in d["windows"]:
        lim = Limits.of(_params(win["depth"]))
        # the share of the chart's points under the safe edge, counted here (a sum was > 1);
        # a point on a grid line at the edge may fall either way: two rows' worth of slack
        safe = wob[None, :] < lim.wob_max(rpm)[:, None]
        assert 0.2 < win["safe_fraction"] < 0.6
        assert win["safe_fraction"] == pytest.approx(safe.mean(), abs=2 / 150)
        # the stick-slip edge alone, not the heaviest safe W_ob (they differ where stall binds)
        stable, unstuck = lim.wob_max_stable(at_rpm), lim.wob_max_unstuck(at_rpm)
        assert win["wob_max_stable"] == pytest.approx(stable.tolist(), rel=1e-9)
        assert win["wob_max"] == pytest.approx(np.minimum(stable, unstuck).tolist(), rel=1e-9)
        assert np.any(stable > unstuck)  # or the edges could be mixed up unseen
    assert d["wob_max_unstuck"] == pytest.approx(unstuck.tolist(), rel=1e-9)


def test_window_checks_carry_each_points_own_verdicts(outputs):
    """Each check's stable and cannot_stay_stuck judged here: the eigenvalues at the Stribeck
    slope, and the steady torque against the static friction, of the 4-inertia check model."""
    d, _ = outputs
    mixed = 0
    for win in d["windows"]:
        p = _params(win["depth"], dof=4)
        assert len(win["checks"]) == 9
        for c in win["checks"]:
            omega = c["rpm"] * RAD_S
            delta = float(st.stribeck_slope(p, c["wob"], omega))
            assert c["stable"] == bool(np.all(st.eigenvalues(p, delta).real < 0)), c
            torque = pydrill.equilibrium_torque(p, c["wob"], omega)
            assert c["cannot_stay_stuck"] == bool(torque > p.static_torque(c["wob"])), c
            mixed += c["stable"] != c["cannot_stay_stuck"]
            assert c["message"] is None and c["outcome"] != "failed"
        assert win["failed_checks"] == 0
    assert mixed > 0  # points where the two verdicts differ: a swap would show
    # none failed: the total counts failures, not checks (18 were run)
    assert d["failed_checks"] == 0 and sum(len(w["checks"]) for w in d["windows"]) == 18


def test_window_text_tables_in_kn_klbf_ft_and_their_marks(outputs):
    """Both tables rebuilt line by line from the closed-form edges: the heaviest safe W_ob in kN
    and klbf, * where the stick-slip edge is below the stall edge; the slowest safe rpm, * where
    the stick-slip edge is above the stall edge; each depth in m and ft, with its dof."""
    _, text = outputs
    lines = text.splitlines()
    at_rpm, at_wob = np.array([15.0, 20.0, 30.0, 90.0]), np.array([1e4, 2e4, 3e4, 5e4, 1e5])
    first = lines.index(next(s for s in lines if s.startswith(" depth m     ft")))
    second = lines.index("slowest safe surface speed, rpm, at weight on bit")
    stars = set()
    for k, depth in enumerate((3000.0, 5000.0)):
        p = _params(depth)
        lim = Limits.of(p)
        cells = []
        edges = (lim.wob_max(at_rpm), lim.wob_max_stable(at_rpm), lim.wob_max_unstuck(at_rpm))
        for w, s, u in zip(*edges, strict=True):
            star = "*" if s < u else " "
            stars.add(star)
            cells.append(f"{w / 1e3:6.0f}({w / KLBF:3.0f}){star}")
        row = f"{depth:8.0f} {depth / FT:6.0f} {p.dof:4d} " + " ".join(cells)
        assert lines[first + 1 + k] == row.rstrip()
        cells = []
        edges = (lim.rpm_min(at_wob), lim.rpm_min_stable(at_wob), lim.rpm_min_unstuck(at_wob))
        for r, s, u in zip(*edges, strict=True):
            star = "*" if s > u else " "
            stars.add(f"rpm{star}")
            cells.append(f"{r:9.0f}{star}")
        assert lines[second + 2 + k] == f"{depth:8.0f} " + " ".join(cells).rstrip()
    assert stars == {"*", " ", "rpm*", "rpm "}  # both marks on both tables
    # the ft column by hand: 3000 m is 9843 ft
    assert lines[first + 1].split()[:2] == ["3000", "9843"]
