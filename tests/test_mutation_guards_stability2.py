"""Mutation guards for pydrill.stability and pydrill.sliding, second round (helper "gs",
session 35): each test checks a documented contract (the error names the bad parameter, the
given value and the allowed range; crossings must be this string's, in increasing order) or
compares against a value computed another way (numpy's eigenvalues, the steady torque by
hand, the mirror symmetry φ → −φ, an overdamped string's real spectrum)."""

import dataclasses
import math
import re

import numpy as np
import pytest

from pydrill import Params, preset
from pydrill.sliding import reference_values
from pydrill.stability import (
    boundary_wob,
    critical_deltas,
    eigenvalues,
    jacobian,
    stability,
    stability_map,
    unstable_count,
)

WOB = 100.0  # N


@pytest.fixture(scope="module")
def string():
    """A short string and its crossings (computed once: they cost the most here)."""
    p = preset("reduced-scale", dof=3)
    return p, critical_deltas(p)


def test_zero_velocity_is_refused_with_the_range_that_is_really_allowed(string):
    # omega < 0 is accepted (the mirror image), so the refusal of 0 must say "!= 0", not the
    # core's "> 0", which would tell the user that every negative omega is refused too.
    p, _ = string
    assert stability(p, WOB, omega=-0.5)  # a negative velocity is allowed
    with pytest.raises(ValueError, match="omega = 0") as info:
        stability(p, WOB, omega=0.0)
    msg = str(info.value)
    assert "!= 0" in msg
    assert "> 0" not in msg


def test_a_negative_velocity_is_the_mirror_image_of_the_positive_one(string):
    # Documented: a negative omega is the mirror image (φ → −φ) of -omega, with Ω and u
    # reversed and the same eigenvalues; small |omega| < 1 included. The torque is also
    # checked by hand: u = (c_r + c_b) Ω + W R (μ_c + (μ_s − μ_c) exp(−γ Ω / v_f)).
    p, _ = string
    for w in (0.3, 0.999, 2.5):
        (fwd,) = stability(p, WOB, omega=w)
        (back,) = stability(p, WOB, omega=-w)
        assert back.omega == -fwd.omega
        assert back.torque == pytest.approx(-fwd.torque, rel=1e-12)
        assert np.allclose(back.eigenvalues, fwd.eigenvalues, rtol=1e-12, atol=0)
        assert back.unstable == fwd.unstable and back.stable == fwd.stable
        friction = (
            WOB
            * p.bit_radius
            * (
                p.mu_coulomb
                + (p.mu_static - p.mu_coulomb)
                * math.exp(-p.stribeck_decay * w / p.stribeck_velocity)
            )
        )
        assert fwd.torque == pytest.approx((p.top_damping + p.bit_damping) * w + friction)


def test_giving_both_omega_and_torque_is_refused(string):
    # "give exactly one of omega or torque": with both, one of them would be silently ignored.
    p, _ = string
    (pt,) = stability(p, WOB, omega=2.0)
    with pytest.raises(ValueError, match="exactly one"):
        stability(p, WOB, omega=2.0, torque=pt.torque)
    with pytest.raises(ValueError, match="exactly one"):
        stability(p, WOB)


def test_the_repr_lists_the_leading_eigenvalues_and_counts_the_rest(string):
    # Invariant: the eigenvalues shown plus "(k more)" are all of them (2 dof − 1), and the
    # shown ones are the leading ones, in order.
    p, _ = string
    (pt,) = stability(p, WOB, omega=0.5)
    text = repr(pt)
    tail = text.split("eigenvalues ", 1)[1].rstrip(">")
    more = re.search(r" … \((\d+) more\)$", tail)
    shown = (tail[: more.start()] if more else tail).split(", ")
    hidden = int(more.group(1)) if more else 0
    assert len(shown) + hidden == len(pt.eigenvalues) == 2 * p.dof - 1
    assert [complex(s) for s in shown] == pytest.approx(pt.eigenvalues[: len(shown)], rel=1e-3)


def test_an_overflowing_boundary_names_the_omega_and_delta_given(string):
    # The error names the offending Ω (1e6 rad/s: exp(γ Ω / v_f) overflows) and the δ it was
    # asked for, each under its own name; the finite point is the closed form δ e^{γΩ/v_f}/F.
    p, _ = string
    factor = p.bit_radius * p.stribeck_decay / p.stribeck_velocity * (p.mu_static - p.mu_coulomb)
    w = boundary_wob(p, 0.5, [1.0])
    assert w[0] == pytest.approx(0.5 * math.exp(p.stribeck_decay / p.stribeck_velocity) / factor)
    with pytest.raises(ValueError) as info:
        boundary_wob(p, 0.5, [1.0, 1e6])
    msg = str(info.value)
    assert msg.startswith("omega = 1e+06 rad/s")
    assert "delta = 0.5:" in msg


def test_crossings_out_of_order_are_refused(string):
    # The lookup is a binary search: crossings in another order gave wrong counts silently.
    _, cs = string
    assert [c.delta for c in cs] == sorted(c.delta for c in cs)
    with pytest.raises(ValueError, match="increasing order"):
        unstable_count(list(reversed(cs)), 0.1)
    # A NaN delta compares false both ways, so the order check alone let it through; where it
    # sits the binary search's answer is arbitrary.
    for k in (0, len(cs) // 2, len(cs) - 1):
        bad = [dataclasses.replace(c, delta=math.nan) if i == k else c for i, c in enumerate(cs)]
        with pytest.raises(ValueError, match="not finite deltas in increasing order"):
            unstable_count(bad, 0.1)


def test_a_mapping_is_not_taken_as_a_list_of_crossings(string):
    # As everywhere in pydrill (Params' lists, hurwitz_determinants), a dict is not a list: a
    # dict keyed by crossings would be read by its keys alone, {} as "no crossings".
    _, cs = string
    for given in ({c: c.delta for c in cs}, {}):
        with pytest.raises(TypeError, match=r"crossings = .* a list of Crossing"):
            unstable_count(given, 0.1)


def _other_damping(p: Params) -> Params:
    # The fold is at δ = c_r + c_b (DESIGN.md §3): 0.18 + 0.05 = 0.23 against 0.19, within
    # 21 % of this string's, and far from equal.
    return p.replace(bit_damping=0.05)


def test_the_crossings_of_a_string_with_other_damping_are_refused_everywhere(string):
    # Documented: crossings without this string's fold (δ = c_r + c_b) are refused, by
    # stability (both entries) and stability_map; the counts would come from them.
    p, _ = string
    other = critical_deltas(_other_damping(p))
    folds = [c.delta for c in other if c.type == "fold"]
    assert folds == [pytest.approx(0.23)]
    (pt,) = stability(p, WOB, omega=2.0)
    calls = [
        lambda: stability(p, WOB, omega=2.0, crossings=other),
        lambda: stability(p, WOB, torque=pt.torque, crossings=other),
        lambda: stability_map(p, [0.5, 2.0], [WOB], crossings=other),
    ]
    for call in calls:
        with pytest.raises(ValueError, match=r"not this string's .*c_r \+ c_b = 0\.19"):
            call()


def test_an_empty_list_of_crossings_is_refused_by_stability(string):
    # Documented: "[] among them, are refused" — at a velocity too, where the crossings are
    # not used: a wrong list passed there silently, and failed only at a torque.
    p, _ = string
    (pt,) = stability(p, WOB, omega=2.0)
    with pytest.raises(ValueError, match="no fold"):
        stability(p, WOB, omega=2.0, crossings=[])
    with pytest.raises(ValueError, match="no fold"):
        stability(p, WOB, torque=pt.torque, crossings=[])


def test_crossings_with_a_second_fold_are_refused(string):
    # Every string has exactly one fold; a second one (here after the right one, so the
    # order holds) changes the counts above it, and is refused by name.
    p, cs = string
    extra = dataclasses.replace(next(c for c in cs if c.type == "fold"), delta=cs[-1].delta + 1)
    with pytest.raises(ValueError, match="2 folds"):
        stability_map(p, [0.5], [WOB], crossings=[*cs, extra])


def test_a_fold_has_no_lyapunov_coefficient_even_with_a_frequency(string):
    # Documented: None for a fold (λ = 0 is no Hopf pair); a hand-made fold carrying a
    # frequency must not be given a Hopf point's normal form.
    p, cs = string
    fold = next(c for c in cs if c.type == "fold")
    hopf = next(c for c in cs if c.type == "hopf")
    fake = dataclasses.replace(fold, frequency=hopf.frequency)
    assert fake.lyapunov(p) is None
    assert fake.criticality(p) is None
    assert isinstance(hopf.lyapunov(p), float)


def test_stability_map_names_a_bad_wob_by_its_own_index(string):
    # The error names the entry as it was given: wob[1] of a 1-D axis, "wob" for a number,
    # not an element of the internal 2-D grid (wob[1, 0]), and the range > 0.
    p, _ = string
    with pytest.raises(ValueError, match=r"^wob\[1\] = 0 is not allowed: each .*> 0$"):
        stability_map(p, [0.5, 2.0], [WOB, 0.0])
    with pytest.raises(ValueError, match=r"^wob = 0 is not allowed: .*> 0$"):
        stability_map(p, 0.5, 0.0)


def test_an_overdamped_strings_eigenvalues_are_complex_and_numpys():
    # Damped far beyond critical, at δ = 0 every eigenvalue is real and numpy returns a real
    # array; eigenvalues() is annotated complex128 and must return it all the same.
    p = Params((1.0, 1.0), (1.0,), (10.0,), 10.0, 10.0, 0.1, 0.5, 0.8, 0.9)
    ref = np.linalg.eigvals(jacobian(p, 0.0))
    assert not np.iscomplexobj(ref)  # the case in point: numpy's answer is real
    ev = eigenvalues(p, 0.0)
    assert ev.dtype == np.complex128
    assert np.allclose(ev, np.sort(ref)[::-1])


@pytest.mark.parametrize("wob", [math.inf, -math.inf, math.nan, 0.0])
def test_reference_values_refuse_a_weight_that_is_not_finite_and_positive(wob):
    # The range is "a finite number > 0 (N)"; an infinite wob gave u* = inf.
    p = preset("reduced-scale", dof=3)
    with pytest.raises(ValueError, match=r"wob = .* must be a finite number > 0"):
        reference_values(p, wob, 1.0)
