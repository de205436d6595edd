"""The audit of ``pydrill bifurcation``: the branch covers the low speeds whatever --omega-max
(checked against a brute-force scan of the eigenvalues), its points carry the figure's names in
the table and --json, and a Branch compares by value and cannot be changed."""

import json

import numpy as np
import pytest

import pydrill
from pydrill import cli
from pydrill import stability as st
from pydrill.bifurcation import Branch, branch

#: (dof, vary, fixed, scan of the varied parameter): the paper's dof-4 string at W_ob = 100 N,
#: and Fig. 11(a)'s dof-2 string at u = 8.1 N·m; each scan spans all of the branch's points,
#: finely enough to put samples between the nearest two (HB2 and LP of dof 2, 0.08 N apart)
CASES = [
    (4, "torque", 100.0, np.arange(5.70, 6.30, 5e-4)),
    (2, "wob", 8.1, np.arange(130.0, 146.0, 5e-3)),
]


def run(capsys, *args):
    assert cli.main([str(a) for a in args]) == 0
    return capsys.readouterr()


def brute_force(p, vary, fixed, scan):
    """(Ω, unstable eigenvalues, spectral abscissa) of every steady state at every value of the
    scan, in increasing Ω: the dense eigenvalues of pydrill.stability, no crossings used."""
    rows = []
    for x in scan:
        wob, torque = (x, fixed) if vary == "wob" else (fixed, x)
        for pt in st.stability(p, wob, torque=torque):
            re = np.array([z.real for z in pt.eigenvalues])
            assert pt.spectral_abscissa == pytest.approx(re.max(), abs=1e-12)
            rows.append((pt.omega, int((re > 0).sum()), pt.spectral_abscissa))
    return np.array(sorted(rows))


@pytest.mark.parametrize(("dof", "vary", "fixed", "scan"), CASES)
def test_the_points_do_not_depend_on_omega_max_and_match_a_brute_force_scan(dof, vary, fixed, scan):
    """--omega-max 1e5 started the branch at 10 rad/s and found nothing ("stable along all of
    it"); 3e4 lost the fold at 2.95 rad/s and the Hopf point at 1.58. Every omega_max now gives
    the same points, and they are where the eigenvalues of a brute-force scan cross."""
    p = pydrill.preset(dof=dof)
    kw = {"torque": fixed} if vary == "wob" else {"wob": fixed}
    runs = [branch(p, vary=vary, omega_max=m, **kw) for m in (40.0, 1e3, 3e4, 1e5)]
    first = [pt for pt in runs[0].points if pt.omega <= 40]
    for b in runs[1:]:
        same = [pt for pt in b.points if pt.omega <= 40]
        assert [(pt.label, pt.type) for pt in same] == [(pt.label, pt.type) for pt in first]
        for a, c in zip(first, same, strict=True):
            assert c.omega == pytest.approx(a.omega, rel=1e-9)
            assert (c.wob, c.torque) == pytest.approx((a.wob, a.torque), rel=1e-9)

    omega, unstable, abscissa = brute_force(p, vary, fixed, scan).T
    x = np.array([pt.wob if vary == "wob" else pt.torque for pt in first])
    inside = [pt for pt, v in zip(first, x, strict=True) if scan[0] < v < scan[-1]]
    assert len(inside) == len(first) >= 3  # the scan spans every point
    # Where the count of unstable eigenvalues changes along the branch: two (a Hopf pair) or
    # one (the fold), between neighbouring samples; one point of the branch there, and no
    # point elsewhere.
    steps = np.nonzero(np.diff(unstable))[0]
    assert len(steps) == len(inside)
    for i in steps:
        (pt,) = [pt for pt in inside if omega[i] <= pt.omega <= omega[i + 1]]
        assert pt.type == ("HB" if abs(unstable[i + 1] - unstable[i]) == 2 else "LP")
    # HB1 is where the stable branch ends: stable (spectral abscissa < 0) above its Ω only.
    (hb1,) = [pt for pt in inside if pt.label == "HB1"]
    np.testing.assert_array_equal(abscissa < 0, omega > hb1.omega)


def test_a_point_at_a_thousandth_of_a_rad_per_s_is_found():
    """The branch starts at 1e-6 of the friction law's velocity scale v_f/γ_b, not at a
    fraction of omega_max: at W_ob = 24.25 N the stabilising Hopf point of the dof-4 string
    lies near Ω = 1e-3 rad/s (below even the default's old start, 40e-4), and the eigenvalues
    just either side of it differ by a pair in Re > 0."""
    p = pydrill.preset(dof=4)
    for omega_max in (40.0, 1e5):
        b = branch(p, vary="torque", wob=24.25, omega_max=omega_max)
        (low,) = [pt for pt in b.points if pt.omega < 0.01]
        assert low.type == "HB" and 1e-4 < low.omega < 5e-3
        counts = [st.stability(p, 24.25, omega=low.omega * f)[0].unstable for f in (0.9, 1.1)]
        assert abs(counts[0] - counts[1]) == 2


def test_an_absurd_omega_max_gets_a_note_and_the_same_table(capsys):
    args = ("bifurcation", "--dof", "4", "--vary", "torque", "--wob", "100", "--omega-max")
    plain = run(capsys, *args, "40")
    assert plain.err == ""
    far = run(capsys, *args, "1e5")
    assert "--omega-max is 100000 rad/s" in far.err and "rpm" in far.err
    assert "no Hopf or fold point" not in far.out
    rows = [line.split()[0] for line in far.out.splitlines()[2:]]
    assert rows == ["HB1", "HB2", "HB3", "LP", "HB4"]
    assert far.out.splitlines()[2:] == plain.out.splitlines()[2:]


def test_table_json_and_figure_name_the_points_alike(capsys, tmp_path):
    """The table listed the Hopf point at 144.92 N first, unnamed; the figure calls 137.10 N
    (the higher Ω, where the stable branch ends) HB1 and 144.9 N HB2."""
    import matplotlib

    matplotlib.use("Agg")
    from pydrill.plot_analysis import bifurcation_figure

    args = ("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1")
    text = run(capsys, *args).out.splitlines()
    table = {line.split()[0]: float(line.split()[1]) for line in text[2:]}
    assert table == pytest.approx({"HB1": 137.09953, "LP": 145.00316, "HB2": 144.92154})
    data = json.loads(run(capsys, *args, "--json").out)
    assert [pt["label"] for pt in data["points"]] == list(table)  # in the table's order
    for pt in data["points"]:
        assert pt["wob"] == pytest.approx(table[pt["label"]], rel=1e-7)
        assert pt["crossing"] == {1: "destabilising", -1: "stabilising"}[pt["direction"]]
    p = pydrill.preset("reduced-scale", dof=2)
    fig = bifurcation_figure(p, branch(p, vary="wob", torque=8.1))
    drawn = {t.get_text(): t.xy for ax in fig.axes[0].child_axes for t in ax.texts}
    assert set(drawn) == set(table)
    for name, (wob, _) in drawn.items():
        assert wob == pytest.approx(table[name], rel=1e-7)


def test_hopf_json_says_each_crossing_in_words(capsys):
    data = json.loads(run(capsys, "hopf", "--dof", "2", "--json").out)
    text = run(capsys, "hopf", "--dof", "2").out.splitlines()[2:]
    words = [line.split()[-3] for line in text]  # the direction column, as the text says it
    assert [c["crossing"] for c in data["crossings"]] == words
    assert words == ["destabilising", "destabilising", "stabilising"]
    assert [c["direction"] for c in data["crossings"]] == [1, 1, -1]  # kept for scripts


def test_a_branch_compares_by_value_and_is_read_only():
    p = pydrill.preset(dof=2)
    a = branch(p, vary="wob", torque=8.1, samples=200)
    assert a == branch(p, vary="wob", torque=8.1, samples=200)  # raised "truth value ..."
    assert a != branch(p, vary="wob", torque=8.1, samples=201)
    assert a != branch(p, vary="wob", torque=8.2, samples=200)
    assert a != "a branch"
    for name in ("omega", "wob", "torque", "unstable"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(a, name)[0] = 1
    assert isinstance(a.points, tuple)
    with pytest.raises(TypeError, match="unhashable"):
        hash(a)
    # Made by hand: its own copies are read-only, the caller's arrays stay as they were.
    omega = np.array([1.0, 2.0])
    b = Branch("wob", 8.1, omega, omega, omega, np.array([0, 0]), [])
    assert omega.flags.writeable and not b.omega.flags.writeable
    assert b == Branch("wob", 8.1, omega.copy(), omega, omega, np.zeros(2, int), ())
