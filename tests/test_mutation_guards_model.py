"""Guards for pydrill/model.py found by mutation testing: parameter validation at its documented
limits (MAX_DOF, 0 < mu_coulomb < mu_static, dof = pipes + 3, list shapes), derived quantities
(pipes, static_torque) and the float-scale check of the friction law.

Each test checks a documented range from both sides (just inside accepted, just outside refused
with a message naming the parameter) or compares against an analytic value."""

import dataclasses
import math
import re

import numpy as np
import pytest

from pydrill import MAX_LOAD, Params, preset
from pydrill.model import MAX_DOF

# mu_static of the strings below: a value distinct from every other number in them, so a
# message quoting it quotes the bound of mu_coulomb's range (0, mu_static).
MU_S = 0.75


def _fields(**changes):
    """Every field of a valid reduced-scale string, with some replaced (for Params(...))."""
    d = preset("reduced-scale", dof=4, mu_static=MU_S).to_dict()
    del d["dof"], d["name"]
    d.update(changes)
    return d


# --- MAX_DOF ------------------------------------------------------------------------------


def test_an_iterator_of_inertias_is_held_to_max_dof():
    # A generator has no len(): only the count after reading it can refuse MAX_DOF + 1.
    def chain(n):
        return _fields(
            inertias=(0.1 for _ in range(n)),
            stiffnesses=[0.073] * (n - 1),
            dampings=[0.0] * (n - 1),
        )

    assert Params(**chain(MAX_DOF)).dof == MAX_DOF  # just inside
    with pytest.raises(ValueError, match=rf"inertias has {MAX_DOF + 1} entries.*{MAX_DOF}"):
        Params(**chain(MAX_DOF + 1))


# --- friction ordering 0 < mu_coulomb < mu_static ------------------------------------------


def _refusal(make) -> str:
    with pytest.raises(ValueError) as info:
        make()
    return str(info.value)


@pytest.mark.parametrize("coulomb", [0.0, -0.0, -0.1])
def test_a_new_string_with_mu_coulomb_at_or_below_zero_blames_mu_coulomb_with_its_range(coulomb):
    # Params(...) and from_dict (no "changed" coefficient): the bad one is mu_coulomb, not
    # mu_static, and the message gives its range's upper bound, the mu_static in force.
    for make in (
        lambda: Params(**_fields(mu_coulomb=coulomb)),
        lambda: Params.from_dict(_fields(mu_coulomb=coulomb)),
    ):
        msg = _refusal(make)
        assert msg.startswith(f"mu_coulomb = {coulomb:g} "), msg
        assert f"{MU_S:g}" in msg and "0 < mu_coulomb" in msg, msg
    assert Params(**_fields(mu_coulomb=1e-300)).mu_coulomb == 1e-300  # just inside (normal)


def test_a_new_string_with_mu_coulomb_not_below_mu_static_is_refused_first_by_friction():
    # mu_static = mu_coulomb is outside (strict inequality); the friction law is named, with
    # the mu_coulomb it must exceed, before any other field's error (here bit_radius < 0).
    msg = _refusal(lambda: Params(**_fields(mu_coulomb=MU_S)))
    assert msg.startswith(f"mu_static = {MU_S:g} ") and "mu_coulomb" in msg, msg
    msg = _refusal(lambda: Params(**_fields(mu_coulomb=0.9, bit_radius=-1.0)))
    assert msg.startswith(f"mu_static = {MU_S:g} ") and "(0.9)" in msg, msg
    below = math.nextafter(MU_S, 0.0)
    assert Params(**_fields(mu_coulomb=below)).mu_coulomb == below  # just inside


def test_replace_blames_the_coefficient_changed_at_both_ends_of_its_range():
    p = preset("reduced-scale", dof=4, mu_static=MU_S)
    for coulomb in (0.0, MU_S, 1.0):  # at or beyond both ends of (0, mu_static)
        msg = _refusal(lambda: p.replace(mu_coulomb=coulomb))  # noqa: B023 (called at once)
        assert msg.startswith(f"mu_coulomb = {coulomb:g} "), msg
        assert f"0 < mu_coulomb < mu_static ({MU_S:g})" in msg, msg
    # preset's overrides go through replace: mu_coulomb = the preset's mu_static (0.8) is too
    # large, and the coefficient named is the one the caller changed.
    msg = _refusal(lambda: preset("reduced-scale", dof=4, mu_coulomb=0.8))
    assert msg.startswith("mu_coulomb = 0.8 ") and "(0.8)" in msg, msg
    msg = _refusal(lambda: p.replace(mu_static=p.mu_coulomb))
    assert msg.startswith(f"mu_static = {p.mu_coulomb:g} "), msg
    assert p.replace(mu_coulomb=math.nextafter(MU_S, 0.0)).mu_coulomb < MU_S  # just inside
    assert p.replace(mu_static=math.nextafter(p.mu_coulomb, 1.0)).mu_static > p.mu_coulomb


# --- float scale of the friction law (documented: mu_static * bit_radius <= 1.8e293) ----------


def test_the_static_torque_limit_is_on_mu_static_times_bit_radius():
    # bit_radius 0.5 keeps the product, not mu_static alone, at the limit; a small Stribeck
    # decay keeps the slope check out of the way.
    p = preset("reduced-scale", dof=4, stribeck_decay=1e-3)
    inside = p.replace(mu_static=3.4e293, bit_radius=0.5)  # product 1.7e293: accepted
    # ... and its torque at every allowed weight on bit is a float: T_s = mu_s R_b W_ob.
    ts = inside.static_torque(MAX_LOAD)
    assert math.isfinite(ts) and ts == pytest.approx(1.7e293 * MAX_LOAD, rel=1e-12)
    both = inside.static_torque(np.array([1.0, MAX_LOAD]))
    assert np.all(np.isfinite(both)) and both[0] == pytest.approx(1.7e293, rel=1e-12)
    assert p.replace(mu_static=1e294, bit_radius=1e-3).mu_static == 1e294  # product 1e291
    msg = _refusal(lambda: p.replace(mu_static=3.8e293, bit_radius=0.5))  # 1.9e293: outside
    assert "mu_static = 3.8e+293, bit_radius = 0.5 are not allowed" in msg, msg


def test_the_stribeck_slope_limit_is_on_the_difference_of_the_coefficients():
    # The slope at rest, W R_b (mu_s - mu_c) gamma / v_f (DESIGN.md §3), stays a float at
    # MAX_LOAD although mu_s R_b gamma / v_f alone would not: mu_s - mu_c = 1e294.
    p = preset("reduced-scale", dof=4)
    big = dict(mu_static=1e300, mu_coulomb=1e300 - 1e294, bit_radius=1e-10)
    inside = p.replace(**big, stribeck_decay=1e8)
    slope = inside.bit_radius * inside.stribeck_decay * (inside.mu_static - inside.mu_coulomb)
    assert slope == pytest.approx(1e292, rel=1e-6) and math.isfinite(slope * MAX_LOAD)
    msg = _refusal(lambda: p.replace(**big, stribeck_decay=1e10))  # slope 1e294: outside
    assert msg.startswith("bit_radius = 1e-10, stribeck_decay = 1e+10"), msg


# --- derived quantities ---------------------------------------------------------------------


def test_static_torque_of_a_number_is_a_python_float_equal_to_mu_s_w_r():
    p = preset("real-string")
    for wob in (0.0, 1e5, np.float64(2.5e4), np.array(3e4)):
        ts = p.static_torque(wob)
        assert type(ts) is float  # documented "-> float" for a number, not numpy's scalar
        assert ts == pytest.approx(0.8 * float(wob) * 0.155575, rel=1e-15, abs=0.0)


@pytest.mark.parametrize("dof, pipes", [(2, 0), (3, 0), (4, 1), (13, 10)])
def test_pipes_is_dof_minus_three_and_never_negative(dof, pipes):
    p = preset("reduced-scale", dof=dof)
    assert p.pipes == pipes
    if pipes:  # the inverse: a string of that many pipes has this dof
        assert preset("reduced-scale", pipes=pipes).dof == dof


@pytest.mark.parametrize("pipes", [1, 2, 10])
def test_dof_and_pipes_given_together_agree_only_as_dof_equals_pipes_plus_three(pipes):
    assert preset("reduced-scale", dof=pipes + 3, pipes=pipes).dof == pipes + 3
    for dof in (pipes + 2, pipes + 4):
        with pytest.raises(ValueError, match=f"dof = {dof} and pipes = {pipes} disagree"):
            preset("reduced-scale", dof=dof, pipes=pipes)


@pytest.mark.parametrize("springs", [1, 3, 7])
def test_a_full_stiffness_list_must_agree_with_dof_as_a_damping_list_must(springs):
    # One spring joins each pair of neighbouring inertias: with dof = springs + 1 (given, or
    # 4 by default) the list is taken; alone it does not set dof (test_spring_lists_dof.py).
    k = [0.05 + 0.01 * i for i in range(springs)]
    p = preset("reduced-scale", dof=springs + 1, stiffnesses=k)
    assert p.dof == springs + 1 and p.stiffnesses == tuple(k) and len(p.dampings) == springs
    if springs != 3:
        with pytest.raises(ValueError, match=r"stiffnesses has .*dof = 4 needs 3"):
            preset("reduced-scale", stiffnesses=k)


# --- from_dict and list shapes --------------------------------------------------------------


def test_from_dict_names_each_missing_required_field_and_defaults_the_rest():
    # Required = the dataclass fields without a default (read from the class, not the module's
    # lists); dropping one is a ValueError naming it, dropping a defaulted one takes the default.
    full = preset("reduced-scale", dof=3).to_dict()
    for f in dataclasses.fields(Params):
        if f.name == "name":
            continue
        data = {k: v for k, v in full.items() if k != f.name}
        if f.default is dataclasses.MISSING:
            with pytest.raises(ValueError, match=rf"^{f.name} is missing"):
                Params.from_dict(data)
        else:
            assert getattr(Params.from_dict(data), f.name) == f.default


@pytest.mark.parametrize("shape", [(1, 4), (4, 1), (2, 2, 1)])
def test_a_list_field_of_more_than_one_dimension_is_a_value_error_naming_its_shape(shape):
    values = np.full(shape, 0.1)
    for make in (
        lambda: preset("reduced-scale", dof=4, inertias=values),
        lambda: Params(**_fields(inertias=values)),
    ):
        msg = _refusal(make)
        assert re.match(r"inertias must be a 1-D list", msg) and str(shape) in msg, msg
    assert preset("reduced-scale", dof=4, inertias=np.full(4, 0.1)).inertias == (0.1,) * 4
