"""pydrill map's text answers an engineer's question: at a given weight on bit, which surface
torques drill safely (a stable steady state, and the bit unable to stay stuck). It gave only
the percentages of the rectangle drawn in each category."""

import re

import pytest

import pydrill
from pydrill.cli import main
from pydrill.stability import stability


def rows(text: str) -> list[list[str]]:
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("safe u at each W_ob"))
    return [line.split() for line in lines[start + 2 : start + 7]]


@pytest.mark.parametrize(
    ("argv", "name", "dof", "scale"),
    [
        (["--dof", "4"], "reduced-scale", 4, 1.0),
        (["--dof", "12", "--wob-max", "100"], "reduced-scale", 12, 1.0),
        (["--preset", "real-string"], "real-string", 2, 1e3),
    ],
)
def test_map_says_the_safe_torques_at_five_weights(argv, name, dof, scale, capsys):
    assert main(["map", *argv]) == 0
    table = rows(capsys.readouterr().out)
    assert len(table) == 5
    p = pydrill.preset(name, dof=dof)

    def stable_at(wob, torque):
        return any(pt.stable for pt in stability(p, wob, torque=torque))

    for w, ts, start, gt, safe in table:
        wob, ts, start, safe = (float(v) * scale for v in (w, ts, start, safe))
        assert gt == ">"
        assert ts == pytest.approx(p.mu_static * wob * p.bit_radius, rel=1e-3)  # T_s (Eq. 38)
        # 'stable from': the eigenvalues of the steady states (not the crossings) say so
        assert stable_at(wob, start * 1.002) and not stable_at(wob, start * 0.998)
        assert safe == pytest.approx(max(ts, start), rel=1e-3)


def test_map_safe_torques_are_in_kilo_units_for_a_real_string(capsys):
    assert main(["map", "--preset", "real-string"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"W_ob \(kN\)\s+T_s \(kN m\)\s+stable from\s+safe u \(kN m\)", out)


def test_the_map_counts_unstable_eigenvalues_once_per_weight_not_once_per_piece(monkeypatch):
    """map --dof 2000 took 100 s, nearly all in checking the list of crossings again for each
    piece of Omega between them (O(crossings²) per W_ob); now 2.6 s. Counted, not timed: the
    count of unstable eigenvalues is asked once per W_ob of the grid."""
    import numpy as np

    from pydrill import operating, stability

    calls = []
    real = stability.unstable_count
    monkeypatch.setattr(operating, "unstable_count", lambda c, d: calls.append(1) or real(c, d))
    p = pydrill.preset("reduced-scale", dof=200)
    crossings = stability.critical_deltas(p)
    assert len(crossings) > 50
    m = operating.operating_map(p, np.linspace(1, 250, 20), np.linspace(0.1, 25, 30), crossings)
    assert len(calls) == 20
    # and what it counts is what each piece's own count says
    for j, w in enumerate(m.wob):
        for i, u in enumerate(m.torque):
            stable = any(pt.stable for pt in stability.stability(p, w, torque=u))
            assert (m.category[i, j] in (0, 1)) == stable, (w, u)


@pytest.mark.parametrize(
    ("argv", "stable"),
    [
        (["--vary", "wob", "--torque", "0.01"], True),
        (["--vary", "torque", "--wob", "100", "--omega-max", "2"], False),
    ],
)
def test_a_branch_without_special_points_says_its_stability(argv, stable, capsys):
    """bifurcation printed the header of an empty table and "no Hopf or fold point on this
    branch": nothing of whether the steady states along it drill steadily. Now their Omega
    range and stability, checked here against the eigenvalues (stability()) at its ends."""
    from pydrill.bifurcation import branch

    assert main(["bifurcation", "--dof", "2", *argv]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 2, out
    m = re.fullmatch(
        r"no Hopf or fold point on this branch \(Omega (\S+) \.\.\. (\S+) rad/s\): "
        r"the steady state is (stable|unstable) along all of it",
        out[1],
    )
    assert m, out[1]
    assert (m.group(3) == "stable") == stable
    p = pydrill.preset("reduced-scale", dof=2)
    fixed = {"torque": 0.01} if argv[1] == "wob" else {"wob": 100.0, "omega_max": 2.0}
    b = branch(p, vary=argv[1], **fixed)
    for i in (b.omega.argmin(), b.omega.argmax()):
        assert f"{b.omega[i]:.4g}" == m.group(1 if i == b.omega.argmin() else 2)
        (pt,) = stability(p, b.wob[i], omega=b.omega[i])
        assert pt.stable == stable, (b.omega[i], pt)


def test_map_json_says_the_order_of_its_category_axes(capsys):
    """--json's category array is indexed [torque][wob], which the JSON did not say. Read by
    its category_axes, two points come out as the eigenvalues and T_s = μ_sb W_ob R_b say:
    read the other way round, each would be another category."""
    import json

    import numpy as np

    assert main(["map", "--dof", "4", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["category_axes"] == ["torque", "wob"]
    p = pydrill.preset("reduced-scale", dof=4)
    for w, u in ((200.0, 5.0), (100.0, 20.0)):  # below T_s and unstable; above T_s and stable
        at = {
            name: int(np.abs(np.array(doc[name]) - v).argmin())
            for name, v in (("wob", w), ("torque", u))
        }
        w, u = doc["wob"][at["wob"]], doc["torque"][at["torque"]]
        outer, inner = doc["category_axes"]
        got = doc["categories"][doc["category"][at[outer]][at[inner]]]
        stable = any(pt.stable for pt in stability(p, w, torque=u))
        stuck = u <= p.mu_static * w * p.bit_radius
        can = "can" if stuck else "cannot"
        want = f"{'' if stable else 'no '}stable steady state, {can} stay stuck"
        assert got == want, (w, u)
        assert (stable, stuck) == ((False, True) if w > 150 else (True, False))  # both kinds
    with pytest.raises(SystemExit):  # and --help says so
        main(["map", "--help"])
    assert 'as category_axes says: ["torque", "wob"]' in " ".join(capsys.readouterr().out.split())
