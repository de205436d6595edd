"""The Python API's bounds, one per quantity wherever it is taken: a weight on bit or torque at
most ``MAX_LOAD`` (simulate refused 1e300 N, stability and branch answered for it), a run at most
``MAX_T_END`` long (t_end = 1e300 ran into the step limit or failed at t = 0), and the window's
edges at any finite speed without numpy's overflow warning."""

import warnings

import pytest

import pydrill
from pydrill import tally
from pydrill.bifurcation import branch
from pydrill.model import MAX_LOAD
from pydrill.simulate import MAX_T_END
from pydrill.stability import stability
from pydrill.window import Limits, operating_window

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
P = pydrill.preset("reduced-scale", dof=4)


def refused(text, call, /, *args, **kwargs):
    with pytest.raises(ValueError) as err:
        call(*args, **kwargs)
    message = str(err.value)
    assert text in message, message
    return message


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda v: stability(P, v, torque=8.3), "wob"),
        (lambda v: stability(P, v, omega=2.0), "wob"),
        (lambda v: stability(P, 40.0, torque=v), "torque"),
        (lambda v: stability(P, 40.0, torque=-v), "torque"),
        (lambda v: branch(P, vary="wob", torque=v), "torque"),
        (lambda v: branch(P, vary="torque", wob=v), "wob"),
        (lambda v: pydrill.simulate(P, wob=v, torque=8.3, t_end=1.0), "wob"),
    ],
)
def test_a_load_beyond_max_load_is_refused_by_name(call, name):
    for value in (1e300, 2 * MAX_LOAD):
        message = refused(f"{name} = ", call, value)
        assert "1e15" in message, message


def test_a_load_at_max_load_is_taken():
    assert stability(P, 40.0, torque=MAX_LOAD)[0].omega > 0
    assert stability(P, MAX_LOAD, torque=8.3) == []  # stuck under it: no steady rotation


@pytest.mark.parametrize("t_end", [1e300, 2 * MAX_T_END])
@pytest.mark.parametrize("method", ["dop853", "bdf"])
def test_a_run_longer_than_max_t_end_is_refused_by_name(t_end, method):
    # DOP853 ran into its step limit (minutes at the default), CVODES failed at t = 0
    message = refused(
        "t_end = ", pydrill.simulate, P, wob=100, torque=8.3, t_end=t_end, method=method
    )
    assert "0 < t_end <= 1e10 s" in message, message


def test_a_run_of_max_t_end_starts():
    # taken, and stopped by its step limit, not refused
    with pytest.raises(pydrill.SolverError, match="max_steps"):
        pydrill.simulate(P, wob=160, torque=8.3, t_end=MAX_T_END, max_steps=100)


def test_the_stick_slip_edge_at_any_finite_speed_warns_nothing():
    # "RuntimeWarning: overflow encountered in exp" (an error under the tests' filter)
    params = tally.load_tally(ROOT / "examples" / "tallies" / "paper-eq53.toml").to_params()
    lim = Limits.of(params)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        edge = lim.wob_max_stable([60.0, 1e6, 1e300])
        window = operating_window(params, [1e4, 1e5], [60.0, 1e300])
    assert edge[0] < edge[1] == edge[2] == float("inf")
    assert lim.wob_max([1e300])[0] == lim.wob_max_unstuck([1e300])[0]
    assert window.safe.shape == (2, 2)


@pytest.mark.parametrize("depth", ["3000m", "3000", b"3000", [3000.0]])
def test_a_depth_that_is_no_number_is_refused_without_a_unit_after_it(depth):
    # "depth = '3000m' m is not allowed": the unit after a value that has one
    paper = tally.load_tally(ROOT / "examples" / "tallies" / "paper-eq53.toml")
    message = refused("depth = ", paper.at_depth, depth)
    assert f"{depth!r} m " not in message and "a number of metres" in message, message
    if isinstance(depth, str):
        assert f"pydrill.units.parse({depth!r}, 'length')" in message, message


def test_an_output_larger_than_the_machine_s_memory_is_refused_before_the_run():
    # --dof 100000 --n-out 1000000 (1.6 TB) ended in "MemoryError: std::bad_alloc"
    message = refused(
        "n_out = 100000000 is not allowed with dof = 100000",
        pydrill.simulate,
        dof=100_000,
        wob=100,
        torque=8.3,
        t_end=1e-3,
        n_out=10**8,
    )
    assert "more than this machine's" in message and "TB" in message, message


@pytest.mark.parametrize("omega", [1e300, -1e300, 1e16])
def test_a_velocity_whose_torque_is_beyond_max_load_is_refused_by_name(omega):
    # answered "Omega = 1e+300 rad/s, u = 1.9e+299 N m"
    message = refused(
        f"omega = {omega:g} is not allowed at wob = 40 N", stability, P, 40.0, omega=omega
    )
    assert "beyond MAX_LOAD (1e15)" in message, message
    assert stability(P, 40.0, omega=1e14)[0].torque < MAX_LOAD  # within it: answered
