"""What the analysis API takes: the steady-state, stability, sliding, bifurcation and window
functions check their inputs as ``simulate`` does (``TypeError`` naming the parameter for a
wrong type, ``ValueError`` naming it and its allowed range for a bad value), take crossings
as any iterable, and keep the mirror symmetry of a negative surface torque (DESIGN.md §2)."""

import math

import numpy as np
import pytest

import pydrill
from pydrill import stability as st
from pydrill.bifurcation import branch
from pydrill.sliding import quasi_equilibrium, reference_values, sliding_region_edges
from pydrill.window import Limits, operating_window, window_against_depth

P = pydrill.preset("reduced-scale", dof=4)
P2 = pydrill.preset("reduced-scale", dof=2)
CROSSINGS = st.critical_deltas(P)
CROSSINGS2 = st.critical_deltas(P2)
LIMITS = Limits.of(P)


def refused(kind, text, call, /, *args, **kwargs):
    """``call`` raises ``kind`` whose message holds ``text``; the message."""
    with pytest.raises(kind) as err:
        call(*args, **kwargs)
    message = str(err.value)
    assert text in message, message
    return message


# 1. Crossings may be any iterable of Crossing: an iterator is read once, not used up.


def test_unstable_count_takes_an_iterator_of_crossings():
    assert int(st.unstable_count(iter(CROSSINGS2), 0.1)) == int(st.unstable_count(CROSSINGS2, 0.1))
    assert int(st.unstable_count(CROSSINGS2, 0.1)) > 0
    counts = st.unstable_count((c for c in CROSSINGS2), [0.01, 0.1, 1.0])
    np.testing.assert_array_equal(counts, st.unstable_count(CROSSINGS2, [0.01, 0.1, 1.0]))


def test_functions_taking_crossings_take_a_generator():
    given = st.stability(P, 100.0, torque=8.3, crossings=(c for c in CROSSINGS))
    assert given == st.stability(P, 100.0, torque=8.3)
    np.testing.assert_array_equal(
        st.stability_map(P, [1.0, 20.0], [100.0], iter(CROSSINGS)),
        st.stability_map(P, [1.0, 20.0], [100.0]),
    )
    b = branch(P2, vary="wob", torque=8.1, samples=300, crossings=iter(CROSSINGS2))
    assert b.to_dict() == branch(P2, vary="wob", torque=8.1, samples=300).to_dict()
    assert Limits.of(P, iter(CROSSINGS)) == LIMITS
    w = operating_window(P, [50.0, 100.0], [30.0, 120.0], iter(CROSSINGS))
    np.testing.assert_array_equal(w.safe, operating_window(P, [50.0, 100.0], [30.0, 120.0]).safe)


def test_crossings_of_the_wrong_kind_are_refused_by_name():
    refused(TypeError, "crossings", st.unstable_count, "abc", 0.1)
    refused(TypeError, "crossings", st.unstable_count, 5, 0.1)
    refused(TypeError, "crossings", st.unstable_count, [1.0, 2.0], 0.1)
    refused(TypeError, "crossings", branch, P2, vary="wob", torque=8.1, crossings=5)


# 2. Numbers and params are checked by name, as simulate checks them.


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: pydrill.equilibrium_velocities(P, "100", "8.3"), "wob"),
        (lambda: pydrill.equilibrium_velocities(P, 100, "8.3"), "torque"),
        (lambda: pydrill.equilibrium_velocities(P, True, 8.3), "wob"),
        (lambda: pydrill.equilibrium_velocities(P, 100, [8.3]), "torque"),
        (lambda: pydrill.equilibrium_torque(P, "100", 1.0), "wob"),
        (lambda: pydrill.equilibrium_torque(P, 100, "1"), "omega"),
        (lambda: pydrill.equilibrium_torque(P, 100, False), "omega"),
        (lambda: st.stability(P, "100", torque=8.3), "wob"),
        (lambda: st.stability(P, 100, torque="8.3"), "torque"),
        (lambda: st.stability(P, 100, omega="1"), "omega"),
        (lambda: st.stability(P, True, omega=1.0), "wob"),
        (lambda: st.jacobian(P, "0.1"), "delta"),
        (lambda: st.jacobian(P, True), "delta"),
        (lambda: st.eigenvalues(P, "0.1"), "delta"),
        (lambda: st.characteristic_polynomial(P, "0.1"), "delta"),
        (lambda: st.hurwitz_determinants("abc"), "ascending"),
        (lambda: st.hurwitz_determinants([1.0, "2", 3.0]), "ascending"),
        (lambda: st.hurwitz_determinants([True, 1.0]), "ascending"),
    ],
)
def test_a_number_of_the_wrong_type_is_refused_by_name(call, name):
    message = refused(TypeError, name, call)
    assert message.startswith(name), message


def test_the_message_is_simulate_s():
    from_simulate = refused(TypeError, "wob", pydrill.simulate, wob="100", torque=8.3)
    here = refused(TypeError, "wob", pydrill.equilibrium_velocities, P, "100", 8.3)
    assert here == from_simulate


def test_hurwitz_determinants_needs_a_flat_list():
    refused(ValueError, "ascending", st.hurwitz_determinants, [[1.0, 2.0], [3.0, 4.0]])
    refused(ValueError, "ascending", st.hurwitz_determinants, 1.0)
    np.testing.assert_allclose(st.hurwitz_determinants(np.array([1, 2, 3, 1])), [3.0, 5.0])


@pytest.mark.parametrize(
    "call",
    [
        lambda p: pydrill.equilibrium_velocities(p, 100, 8.3),
        lambda p: pydrill.equilibrium_torque(p, 100, 1.0),
        lambda p: st.stability(p, 100, torque=8.3),
        lambda p: st.stability(p, 100, omega=1.0),
        lambda p: st.critical_deltas(p),
        lambda p: st.jacobian(p, 0.1),
        lambda p: st.eigenvalues(p, 0.1),
        lambda p: st.characteristic_polynomial(p, 0.1),
        lambda p: st.hopf_deltas_dof2(p),
        lambda p: st.stribeck_slope(p, 100, 1.0),
        lambda p: st.boundary_wob(p, 0.1, 1.0),
        lambda p: st.stability_map(p, [1.0], [100.0]),
        lambda p: CROSSINGS[0].wob(p, 1.0),
        lambda p: CROSSINGS[0].lyapunov(p),
        lambda p: quasi_equilibrium(p, 100, 8.3),
        lambda p: reference_values(p, 100, 8.3),
        lambda p: sliding_region_edges(p, 100, [0.0]),
        lambda p: branch(p, vary="wob", torque=8.1),
        lambda p: Limits.of(p),
        lambda p: operating_window(p, [100.0], [60.0]),
    ],
)
@pytest.mark.parametrize(
    ("make", "got"),
    [
        (lambda p: "reduced-scale", "got str (for a preset by name, write pydrill.preset("),
        (lambda p: p.to_core(), "got pydrill._core.Params"),
        (lambda p: p.to_dict(), "got dict"),
    ],
)
def test_params_must_be_a_params(call, make, got):
    message = refused(TypeError, "params must be a pydrill.Params", call, make(P))
    assert got in message


def test_numpy_numbers_are_numbers():
    assert pydrill.equilibrium_velocities(P, np.int64(100), np.float64(8.3)) == (
        pydrill.equilibrium_velocities(P, 100.0, 8.3)
    )
    assert pydrill.equilibrium_torque(P, np.float32(100), np.array(1.0)) == (
        pydrill.equilibrium_torque(P, 100.0, 1.0)
    )
    assert st.stability(P, np.int64(100), torque=np.float64(8.3)) == st.stability(
        P, 100.0, torque=8.3
    )
    assert st.stability(P, np.int64(100), omega=np.float64(2.0)) == st.stability(
        P, 100.0, omega=2.0
    )
    np.testing.assert_array_equal(st.jacobian(P, np.float64(0.1)), st.jacobian(P, 0.1))
    np.testing.assert_array_equal(
        st.characteristic_polynomial(P, np.int64(1)), st.characteristic_polynomial(P, 1.0)
    )
    assert quasi_equilibrium(P, np.int64(100), np.float64(8.3)).static_torque == pytest.approx(8.0)
    b = branch(P2, vary="wob", torque=np.float64(8.1), omega_max=np.int64(30), samples=np.int64(50))
    assert b.fixed == 8.1 and b.omega.size > 0


# 3. The analysis modules refuse bad values by name, with the allowed range.


@pytest.mark.parametrize(
    ("call", "kind", "text"),
    [
        (lambda: quasi_equilibrium(P, -100, 8.3), ValueError, "wob = -100 is not allowed"),
        (lambda: quasi_equilibrium(P, 0, 8.3), ValueError, "wob = 0 is not allowed"),
        (lambda: quasi_equilibrium(P, 100, math.nan), ValueError, "torque = nan is not allowed"),
        (lambda: quasi_equilibrium(P, 100, math.inf), ValueError, "torque = inf is not allowed"),
        (lambda: quasi_equilibrium(P, "100", 8.3), TypeError, "wob must be a number"),
        (lambda: quasi_equilibrium(P, 100, "8.3"), TypeError, "torque must be a number"),
        (lambda: reference_values(P, -100, 8.3), ValueError, "wob = -100 is not allowed"),
        (lambda: reference_values(P, 100, math.nan), ValueError, "torque = nan is not allowed"),
        (lambda: reference_values(P, 100, "8.3"), TypeError, "torque must be a number"),
        (lambda: sliding_region_edges(P, -1, [0.0]), ValueError, "wob = -1 is not allowed"),
        (
            lambda: sliding_region_edges(P, 100, [0.0, math.nan]),
            ValueError,
            "collar_velocity[1] = nan is not allowed",
        ),
        (lambda: sliding_region_edges(P, 100, "0"), TypeError, "collar_velocity"),
    ],
)
def test_sliding_refuses_bad_inputs(call, kind, text):
    message = refused(kind, text, call)
    if kind is ValueError:
        assert "finite" in message, message


def test_sliding_keeps_the_mirror_of_a_negative_torque():
    qe = quasi_equilibrium(P, 100, -8.3)
    assert not qe.real and qe.static_torque == pytest.approx(8.0)
    np.testing.assert_array_equal(qe.state, -quasi_equilibrium(P, 100, 8.3).state)
    # W_ob* is where |u| = T_s: a weight, the same for ±u (the lines u = ±μ_sb W_ob R_b).
    assert reference_values(P, 100, -8.3) == reference_values(P, 100, 8.3)
    assert reference_values(P, 100, 8.3)["wob_star"] == pytest.approx(103.75)


@pytest.mark.parametrize(
    ("kwargs", "kind", "text"),
    [
        (
            {"vary": "wob", "torque": 8.1, "samples": 1},
            ValueError,
            "samples = 1 is not allowed: need an integer 2 ... 1000000",
        ),
        ({"vary": "wob", "torque": 8.1, "samples": 0}, ValueError, "samples = 0 is not allowed"),
        ({"vary": "wob", "torque": 8.1, "samples": 10.0}, TypeError, "samples must be an integer"),
        ({"vary": "wob", "torque": 8.1, "samples": True}, TypeError, "samples must be an integer"),
        (
            {"vary": "wob", "torque": 8.1, "wob": 100},
            ValueError,
            "wob = 100 is not allowed with vary = 'wob'",
        ),
        (
            {"vary": "torque", "wob": 100, "torque": 8.3},
            ValueError,
            "torque = 8.3 is not allowed with vary = 'torque'",
        ),
        (
            {"vary": "torque", "wob": 100, "omega_max": 0},
            ValueError,
            "omega_max = 0 is not allowed: need a finite omega_max > 0",
        ),
        (
            {"vary": "wob", "torque": 8.1, "omega_max": -5},
            ValueError,
            "omega_max = -5 is not allowed",
        ),
        (
            {"vary": "wob", "torque": 8.1, "omega_max": math.nan},
            ValueError,
            "omega_max = nan is not allowed",
        ),
        ({"vary": "wob", "torque": 8.1, "omega_max": "9"}, TypeError, "omega_max must be a number"),
        ({"vary": "wob", "torque": "8.1"}, TypeError, "torque must be a number"),
        ({"vary": "torque", "wob": "100"}, TypeError, "wob must be a number"),
        ({"vary": "wob", "torque": -8.1}, ValueError, "torque = -8.1 is not allowed"),
        ({"vary": "torque", "wob": math.inf}, ValueError, "wob = inf is not allowed"),
        ({"vary": "wob"}, ValueError, "torque"),
        ({"vary": 5, "torque": 8.1}, ValueError, "vary = 5 is not allowed"),
    ],
)
def test_branch_refuses_bad_inputs(kwargs, kind, text):
    refused(kind, text, branch, P2, **kwargs)


def test_branch_takes_its_defaults_from_none_only():
    b = branch(P, vary="torque", wob=100, samples=50)
    assert b.omega[-1] == pytest.approx(40.0, rel=1e-6)  # the default omega_max
    b = branch(P, vary="torque", wob=100, samples=50, omega_max=10.0)
    assert b.omega[-1] == pytest.approx(10.0, rel=1e-6)
    assert branch(P2, vary="wob", torque=8.1, samples=2).omega.size == 2


LIMIT_METHODS = ("wob_max", "wob_max_stable", "wob_max_unstuck")
RPM_METHODS = ("rpm_min", "rpm_min_stable", "rpm_min_unstuck")


@pytest.mark.parametrize("method", LIMIT_METHODS)
def test_limits_refuse_a_bad_rpm_by_name(method):
    call = getattr(LIMITS, method)
    refused(
        ValueError, "rpm[0] = -20 is not allowed: each must be a finite number >= 0", call, [-20.0]
    )
    refused(ValueError, "rpm = nan is not allowed", call, math.nan)
    refused(TypeError, "rpm = '20' is not allowed", call, "20")
    refused(TypeError, "rpm", call, [True])
    assert np.isfinite(call([0.0, 20.0])).all()  # 0 rpm is allowed: the limit as Ω → 0


@pytest.mark.parametrize("method", RPM_METHODS)
def test_limits_refuse_a_bad_wob_by_name(method):
    call = getattr(LIMITS, method)
    refused(
        ValueError, "wob[1] = -1 is not allowed: each must be a finite number >= 0", call, [1, -1]
    )
    refused(ValueError, "wob = inf is not allowed", call, math.inf)
    refused(TypeError, "wob = '100' is not allowed", call, "100")
    assert np.isfinite(call([0.0, 100.0])).all()


def test_limits_torque_and_grids_refuse_bad_values_by_name():
    refused(TypeError, "wob = '100' is not allowed", LIMITS.torque, "100", 60.0)
    refused(ValueError, "rpm = -60 is not allowed", LIMITS.torque, 100.0, -60.0)
    refused(TypeError, "wob = '100' is not allowed", operating_window, P, "100", [60.0])
    refused(ValueError, "rpm[0] = 0 is not allowed", operating_window, P, [100.0], [0.0])
    refused(ValueError, "wob[0] = nan is not allowed", operating_window, P, [math.nan], [60.0])
    # window_against_depth checks its grids before it reads the tally.
    refused(TypeError, "rpm = '60' is not allowed", window_against_depth, None, [1000.0], "60", [1])
    refused(
        ValueError, "wob[0] = -1 is not allowed", window_against_depth, None, [1000.0], 60, [-1]
    )


# 4. A negative torque turns the string backwards: the mirror image of the positive one.


def test_equilibrium_velocities_of_a_negative_torque_are_the_mirror_image():
    assert pydrill.equilibrium_velocities(P, 100, -8.3) == [
        -w for w in pydrill.equilibrium_velocities(P, 100, 8.3)
    ]
    assert pydrill.equilibrium_velocities(P, 100, -8.3) == pytest.approx([-17.3684184842])
    # Two steady states: in the order stability() and simulate() give them (increasing Ω).
    forward = pydrill.equilibrium_velocities(P, 130, 8.3)
    backward = pydrill.equilibrium_velocities(P, 130, -8.3)
    assert len(forward) == 2
    assert backward == [-w for w in reversed(forward)]
    assert backward == sorted(backward)
    assert backward == [pt.omega for pt in st.stability(P, 130, torque=-8.3)]
    assert pydrill.equilibrium_velocities(P, 100, -0.0) == []


def test_equilibrium_torque_is_odd_in_omega():
    for wob, u in ((100, 8.3), (130, 8.3)):
        for omega in pydrill.equilibrium_velocities(P, wob, -u):
            assert omega < 0
            assert pydrill.equilibrium_torque(P, wob, omega) == pytest.approx(-u, rel=1e-12)
    assert pydrill.equilibrium_torque(P, 100, -3.0) == -pydrill.equilibrium_torque(P, 100, 3.0)
    refused(ValueError, "omega = 0 is not allowed", pydrill.equilibrium_torque, P, 100, 0.0)


def test_stability_at_a_negative_velocity_is_the_mirrored_point():
    (back,) = st.stability(P, 100, torque=-8.3)
    (at,) = st.stability(P, 100, omega=back.omega)
    assert at.omega == back.omega and at.torque == pytest.approx(-8.3, rel=1e-12)
    assert at.eigenvalues == pytest.approx(back.eigenvalues)
    (fwd,) = st.stability(P, 100, omega=-back.omega)
    assert (at.delta, at.unstable, at.eigenvalues) == (fwd.delta, fwd.unstable, fwd.eigenvalues)


def test_a_run_from_the_backward_equilibrium_ends_at_one_of_them():
    r = pydrill.simulate(P, wob=100, torque=-8.3, initial="equilibrium", t_end=200.0)
    velocities = pydrill.equilibrium_velocities(P, 100, -8.3)
    assert r.regime == "steady"
    assert list(r.summary.omega_equilibrium) == pytest.approx(velocities, rel=1e-14)
    assert min(abs(r.bit_velocity[-1] - w) for w in velocities) < 1e-4 * abs(velocities[0])


# 5. StabilityPoint.to_dict: the leading n_eigenvalues >= 0, or all with None.


def test_to_dict_counts_eigenvalues_by_name():
    (pt,) = st.stability(P, 100, torque=8.3)
    assert len(pt.eigenvalues) == 7
    assert len(pt.to_dict()["eigenvalues"]) == 6
    assert len(pt.to_dict(None)["eigenvalues"]) == 7
    assert len(pt.to_dict(0)["eigenvalues"]) == 0
    assert len(pt.to_dict(np.int64(2))["eigenvalues"]) == 2
    assert len(pt.to_dict(100)["eigenvalues"]) == 7
    message = refused(ValueError, "n_eigenvalues = -1 is not allowed", pt.to_dict, -1)
    assert ">= 0" in message and "None" in message
    refused(TypeError, "n_eigenvalues must be an integer", pt.to_dict, "a")
    refused(TypeError, "n_eigenvalues must be an integer", pt.to_dict, 2.0)
    refused(TypeError, "n_eigenvalues must be an integer", pt.to_dict, True)
