"""Mutation guards for the pipe tally and its lumping (pydrill/tally.py, tally_parse.py,
drilling.py): each test compares against numbers computed here by hand from the geometry and
the steel (I_p = π(OD⁴ − ID⁴)/32, k = G·I_p/L, J = ρ·I_p·L), an invariant of lumping, or the
continuous rod's analytic frequency; the boundaries are checked on both sides."""

import math

import numpy as np
import pytest
from scipy.linalg import eigh_tridiagonal

from pydrill.drilling import drill_ahead
from pydrill.tally import MAX_DEPTH, MAX_DIAMETER, MAX_DOF, TallyError, parse_tally

INCH = 0.0254

HEAD = """name = "guard"
[top_drive]
inertia = 1000.0
[bit]
diameter = "10 in"
"""


def section(kind: str, count: int, length: float, od: float, bore: float, extra: str = "") -> str:
    """One [[section]]: ``od`` and ``bore`` in inches, ``length`` in m (exact in binary)."""
    return (
        f'[[section]]\nkind = "{kind}"\ncount = {count}\nlength = {length!r}\n'
        f'od = "{od} in"\nid = "{bore} in"\n{extra}'
    )


def polar(od_in: float, id_in: float) -> float:
    return math.pi * ((od_in * INCH) ** 4 - (id_in * INCH) ** 4) / 32


# --- a joint's spring and inertia come from its own steel ---------------------------------------


def test_each_joint_is_its_own_steels_spring_and_inertia():
    """[steel] sets the default for every section (aluminium pipe here); a section's own
    shear_modulus/density override it (a titanium collar). Solid collars (id = 0) are allowed."""
    text = (
        HEAD
        + '[steel]\nshear_modulus = "26 GPa"\ndensity = "2700 kg/m3"\n'
        + section("drill-pipe", 3, 8.0, 5.5, 4.5)
        + section("drill-collar", 2, 4.0, 7.0, 0, 'shear_modulus = "44 GPa"\ndensity = 4500\n')
    )
    tally = parse_tally(text)
    k, j, lengths = tally.elements()
    ip_pipe, ip_collar = polar(5.5, 4.5), polar(7.0, 0.0)
    assert k == pytest.approx([26e9 * ip_pipe / 8] * 3 + [44e9 * ip_collar / 4] * 2, rel=1e-12)
    assert j == pytest.approx([2700 * ip_pipe * 8] * 3 + [4500 * ip_collar * 4] * 2, rel=1e-12)
    assert lengths.tolist() == [8.0] * 3 + [4.0] * 2


def test_what_a_tally_leaves_out_takes_the_documented_defaults():
    """No [damping], no friction law, no top-drive or bit damping: beta 0.2 s (Eq. 53's
    c_t = 0.2 k_t), mu_c 0.5, mu_s 0.8, gamma_b 0.9, v_f 1 rad/s, c_r = c_b = 0; the bit's
    radius is half its diameter."""
    p = parse_tally(HEAD + section("drill-pipe", 4, 9.0, 5, 4)).to_params()
    assert p.dampings == pytest.approx([0.2 * k for k in p.stiffnesses], rel=1e-15)
    assert (p.mu_coulomb, p.mu_static, p.stribeck_decay, p.stribeck_velocity) == (
        0.5,
        0.8,
        0.9,
        1.0,
    )
    assert p.top_damping == 0.0 and p.bit_damping == 0.0
    assert p.bit_radius == pytest.approx(5 * INCH, rel=1e-15)


# --- depth -----------------------------------------------------------------------------------


def test_the_deepest_allowed_depth_is_the_earths_radius_itself():
    tally = parse_tally(HEAD + section("drill-pipe", 3, 10.0, 5, 4))
    assert tally.at_depth(MAX_DEPTH).length >= MAX_DEPTH
    with pytest.raises(TallyError, match=r"at most 6\.371e\+06 m"):
        tally.at_depth(math.nextafter(MAX_DEPTH, math.inf))


# --- the largest string: MAX_DOF inertias, a partial last stand counted -----------------------


def test_a_partial_last_stand_is_an_inertia_of_its_own_when_counting_to_max_dof():
    """2 (MAX_DOF - 1) + 1 joints by 2: MAX_DOF - 1 full stands and one of a single joint,
    MAX_DOF + 1 inertias with the top drive: refused, naming lump 3 as the least that fits."""
    n = 2 * (MAX_DOF - 1) + 1
    tally = parse_tally(HEAD + section("drill-pipe", n, 1.0, 5, 4))
    with pytest.raises(TallyError, match=rf"has {MAX_DOF + 1} inertias, .*\(lump >= 3;"):
        tally.elements(lump=2)
    assert len(tally.elements(lump=3)[0]) == -(-n // 3)


def test_a_bha_that_fits_only_with_all_the_pipe_in_one_stand_says_so():
    """MAX_DOF - 2 collar joints under 3 joints of pipe: all the pipe as one element makes
    exactly MAX_DOF inertias, so lumping (lump >= 3) is the advice, not 'list fewer joints'."""
    text = (
        HEAD + section("drill-pipe", 3, 9.0, 5, 4) + section("drill-collar", MAX_DOF - 2, 1.0, 8, 3)
    )
    with pytest.raises(TallyError, match=r"\(lump >= 3;"):
        parse_tally(text).elements()
    with pytest.raises(TallyError, match="list fewer joints"):
        parse_tally(text.replace(f"count = {MAX_DOF - 2}", f"count = {MAX_DOF - 1}")).elements()


# --- limits of the parser, on both sides -------------------------------------------------------


def test_the_widest_pipe_and_bit_are_allowed_and_no_wider():
    wide = 'od = "5 m"'
    text = HEAD.replace('"10 in"', '"5 m"') + section("drill-pipe", 2, 9.0, 5, 4).replace(
        'od = "5 in"', wide
    )
    tally = parse_tally(text)
    assert tally.sections[0].od == MAX_DIAMETER and tally.bit_radius == MAX_DIAMETER / 2
    with pytest.raises(TallyError, match=r"section 1 \(drill-pipe\), od = '5.001 m' is not"):
        parse_tally(text.replace(wide, 'od = "5.001 m"'))


def test_zero_dampings_are_allowed():
    """beta, c_r and c_b may be 0 (an undamped string), not below."""
    text = HEAD.replace("inertia = 1000.0", "inertia = 1000.0\ndamping = 0.0") + (
        "[damping]\nbeta = 0.0\n" + section("drill-pipe", 2, 9.0, 5, 4)
    )
    p = parse_tally(text).to_params()
    assert p.top_damping == 0.0 and p.dampings == (0.0, 0.0)
    with pytest.raises(TallyError, match=r"damping\.beta = -0\.1 is not allowed"):
        parse_tally(text.replace("beta = 0.0", "beta = -0.1"))


def test_equal_static_and_coulomb_friction_are_refused():
    text = HEAD.replace('"10 in"', '"10 in"\nmu_coulomb = 0.6\nmu_static = 0.6')
    with pytest.raises(TallyError, match=r"bit\.mu_static = 0\.6 is not allowed: need mu_static >"):
        parse_tally(text + section("drill-pipe", 2, 9.0, 5, 4))


def test_a_string_exactly_as_long_as_the_earths_radius_is_allowed():
    """637100 joints of 10 m: 6.371e6 m, MAX_DEPTH itself; one more joint is refused."""
    tally = parse_tally(HEAD + section("drill-pipe", 637_100, 10.0, 5, 4))
    assert tally.length == MAX_DEPTH
    with pytest.raises(TallyError, match=r"section 1 \(drill-pipe\), count = 637101 is not"):
        parse_tally(HEAD + section("drill-pipe", 637_101, 10.0, 5, 4))


def test_a_friction_law_the_model_refuses_is_refused_when_the_tally_is_read():
    """mu_static = 1e300 on a 5 in bit overflows the static torque at the largest W_ob: the
    model refuses it, and so does the parser, before any string is built from it."""
    text = HEAD.replace('"10 in"', '"10 in"\nmu_static = 1e300')
    with pytest.raises(TallyError, match="mu_static"):
        parse_tally(text + section("drill-pipe", 2, 9.0, 5, 4))


# --- the lumped chain against the continuous rod -----------------------------------------------


def _fixed_free_fundamental(inertias, stiffnesses) -> float:
    """Lowest natural frequency of the chain with its top held (the top drive's inertia left
    out) and its bit free: eigenvalues of M^-1/2 K M^-1/2, tridiagonal."""
    j = np.asarray(inertias[1:], dtype=float)
    k = np.asarray(stiffnesses, dtype=float)
    diag = k.copy()
    diag[:-1] += k[1:]
    s = 1 / np.sqrt(j)
    w2 = eigh_tridiagonal(diag * s * s, -k[1:] * s[:-1] * s[1:], eigvals_only=True)
    return float(np.sqrt(w2[0]))


def test_a_finely_lumped_uniform_string_rings_at_the_continuous_rods_frequency():
    """A uniform rod held at the top, free at the bit: ω = (π / 2L)·sqrt(G/ρ), whatever its
    section (I_p cancels). 1000 joints of 2 m (of 1 m, k = G·I_p·L would pass unseen): each
    inertia at its joint's lower end makes the chain slower by about 1/(2N) = 0.05 %. The
    reductions (shared inertias) near the full chain like 1/N²: 0.16 % low at dof 9, 4x
    closer each time the groups halve."""
    tally = parse_tally(HEAD + section("drill-pipe", 1000, 2.0, 5, 4.276))
    exact = math.pi / (2 * 2000.0) * math.sqrt(79.3e9 / 7850.0)
    full = tally.to_params()
    w_full = _fixed_free_fundamental(full.inertias, full.stiffnesses)
    assert 0 < 1 - w_full / exact < 6e-4
    error = {}
    for dof in (5, 9, 17):
        p = tally.to_params(dof=dof)
        error[dof] = 1 - _fixed_free_fundamental(p.inertias, p.stiffnesses) / w_full
    assert 0 < error[9] < 2e-3
    assert 3.5 < error[5] / error[9] < 4.5 and 3.5 < error[9] / error[17] < 4.5


# --- drilling ahead: a stand at every connection ------------------------------------------------


def test_drilling_adds_a_stand_of_lump_joints_at_every_stands_depth():
    """From 100 m to 150 m in stands of 2 × 10 m joints at 0.05 m/s: stands end at 120 and
    140 m (connections at 400 s and 800 s), the last one drills the 10 m left; each
    connection's string is the tally with two joints more, its new top element two joints in
    series; the bit's depth grows as rop · t."""
    tally = parse_tally(
        HEAD + section("drill-pipe", 3, 10.0, 5, 4) + section("drill-collar", 2, 10.0, 8, 3)
    )
    run = drill_ahead(
        tally, depth_start=100.0, depth_end=150.0, rop=0.05, wob=2e4, torque=3e3, lump=2,
        n_out_per_stand=20,
    )  # fmt: skip
    assert run.regimes[0][:2] == (100.0, 120.0) and run.regimes[1][:2] == (120.0, 140.0)
    assert run.regimes[2][:2] == (140.0, 150.0)
    strings = [tally.at_depth(d).to_params(lump=2) for d in (100.0, 120.0, 140.0)]
    assert [s.dof for s in strings] == [7, 8, 9]  # top, 8-12 pipe by 2, 2 collars
    assert [n for *_, n in run.connections] == [8, 9]
    times_depths = [x for t, d, _ in run.connections for x in (t, d)]
    assert times_depths == pytest.approx([400.0, 120.0, 800.0, 140.0], rel=1e-12)
    for got, want in zip(run.strings, strings, strict=True):
        assert got.inertias == want.inertias and got.stiffnesses == want.stiffnesses
    joint = tally.sections[0]
    assert strings[1].stiffnesses[0] == pytest.approx(joint.joint_stiffness() / 2, rel=1e-12)
    assert run.t[-1] == pytest.approx(1000.0, rel=1e-12)
    np.testing.assert_allclose(run.depth, 100.0 + 0.05 * run.t, rtol=1e-12)
