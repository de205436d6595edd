"""The C++ core at the edges: absurd-but-finite parameters and tolerances refused before a run,
with the parameter and its range named, and the BDF solver's setup count."""

import pydrill


def test_bdf_counts_its_setups_the_times_it_refactored():
    """lin_setups was 0 for BDF since the chain solver replaced CVODES's linear solver (CVODES
    calls no setup for a solver that forms its own matrix). It counts the refactorisations:
    at least one per smooth piece (each restart starts a new step size), at most one per step
    attempt, far fewer than the solves, and none without a linear solver."""
    kw = dict(wob=100.0, torque=8.3, t_end=300.0, dof=12, dampings=[0.05] * 11, n_out=301)
    s = pydrill.simulate(method="bdf", **kw).stats
    assert s.switches >= 4 and s.reinits == s.switches
    assert s.reinits < s.lin_setups <= s.steps + s.err_test_fails + s.nonlin_conv_fails
    assert 2 * s.lin_setups < s.lin_solves <= s.nonlin_iters
    assert s.lin_setups == s.jac_evals  # forming I - gamma*J and factoring it are one step here
    for method in ("adams", "dop853", "erk"):
        assert pydrill.simulate(method=method, **kw).stats.lin_setups == 0
