"""The Python API's refusals of a model parameter named from elsewhere point where the CLI's
--set and a spec's [model] point (tests/test_messages_audit4.py): ``mu`` and ``friction`` to
the coefficients mu_coulomb and mu_static, ``beta`` to a tally's [damping] table. Before,
Params.replace(mu=0.5) and preset(..., friction=0.5) said only "unknown parameter" and the list."""

from __future__ import annotations

import pytest

import pydrill

P = pydrill.preset("reduced-scale")
COEFFICIENTS = r"friction coefficients are mu_coulomb, sliding, and mu_static, at rest"


def _refusal(call) -> str:
    with pytest.raises(ValueError) as err:
        call()
    return str(err.value)


@pytest.mark.parametrize(
    "call",
    [
        lambda: P.replace(mu=0.5),
        lambda: pydrill.preset("reduced-scale", mu=0.5),
        lambda: pydrill.Params.from_dict({**P.to_dict(), "mu": 0.5}),
        lambda: pydrill.simulate(P, wob=100, torque=8.3, t_end=1, mu=0.5),
    ],
)
def test_a_friction_coefficient_by_another_name_is_pointed_to_mu_coulomb_and_mu_static(call):
    message = _refusal(call)
    assert "unknown parameter" in message and COEFFICIENTS in message


def test_friction_as_a_parameter_also_says_where_the_law_is_picked():
    message = _refusal(lambda: pydrill.preset("reduced-scale", friction=0.5))
    assert COEFFICIENTS in message
    assert "simulate(..., friction=...) picks the friction law, 'exact' or 'karnopp'" in message
    # the law named there is what simulate takes
    r = pydrill.simulate(P, wob=100, torque=8.3, t_end=1, friction="karnopp")
    assert r.summary.regime in ("steady", "stick-slip", "stuck")


@pytest.mark.parametrize(
    "call",
    [lambda: P.replace(beta=0.2), lambda: pydrill.Params.from_dict({**P.to_dict(), "beta": 0.2})],
)
def test_beta_is_said_to_be_a_tallys(call):
    assert "set it as beta in the [damping] table of the TALLY.toml" in _refusal(call)


def test_a_typo_keeps_its_did_you_mean_and_no_other_hint():
    message = _refusal(lambda: P.replace(mu_coulom=0.5))
    assert "(did you mean 'mu_coulomb'?)" in message and COEFFICIENTS not in message
