"""Guards from a mutation audit of the C++ core (session 32), through the Python API.

Each test failed on a small change to the core that no other test noticed (a flipped
comparison, a dropped sign, a filter removed), and checks the core against something of its
own: a brute-force scan in numpy, numpy's eigenvalues, or the mirror symmetry u -> -u.
"""

import numpy as np
import pytest

import pydrill
from pydrill import stability


def _scanned_steady_states(p, wob, torque):
    """Sign changes of g(Omega) - u on a fine geometric grid of Omega > 0, with
    g = (c_r + c_b) Omega + f_b(Omega) written out from DESIGN.md section 3."""
    w = np.geomspace(1e-9, 1e6, 40000)
    decay = p.stribeck_decay / p.stribeck_velocity
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-decay * w)
    friction = mu * wob * p.bit_radius
    g = (p.top_damping + p.bit_damping) * w + friction - torque
    return int(np.count_nonzero(np.diff(np.sign(g)) != 0))


@pytest.mark.parametrize("top_damping, bit_damping", [(0.18, 0.01), (10.0, 0.01), (0.0, 0.0)])
def test_no_steady_rotation_at_zero_when_torque_is_the_static_torque(top_damping, bit_damping):
    """u = T_s balances the friction only as Omega -> 0+, which is stick: the steady states are
    the scan's, each a rotation that balances u."""
    p = pydrill.preset("reduced-scale", dof=4)
    p = p.replace(top_damping=top_damping, bit_damping=bit_damping)
    wob = 100.0
    ts = p.mu_static * (wob * p.bit_radius)  # T_s as the core forms it
    omegas = pydrill.equilibrium_velocities(p, wob, ts)
    assert len(omegas) == _scanned_steady_states(p, wob, ts)
    for w in omegas:
        assert w > 1e-6
        assert pydrill.equilibrium_torque(p, wob, w) == pytest.approx(ts, rel=1e-12)


def test_unstable_count_matches_numpy_eigenvalues_when_the_fold_restabilises():
    """With c_r^2 > k (J_r + J_b) (dof 2) the real eigenvalue returns to the left half-plane
    at the fold: its direction is -1, and the counts follow numpy's eigenvalues."""
    p = pydrill.preset("reduced-scale", dof=2).replace(top_damping=0.3)
    crossings = stability.critical_deltas(p)
    folds = [c for c in crossings if c.type == "fold"]
    assert [c.direction for c in folds] == [-1]
    for delta in (0.005, 0.1, 0.3, 0.305, 0.32, 1.0, 5.0):
        rhp = int(np.sum(np.linalg.eigvals(stability.jacobian(p, delta)).real > 0))
        assert int(stability.unstable_count(crossings, delta)) == rhp, delta


def test_closed_form_hopf_points_are_those_below_the_fold():
    """Eq. (51) keeps the paper's H+ (a_1 > 0, a_0 > 0: below the fold). On this string the phase
    search finds two Hopf points above the fold, where a_0 < 0: the closed form returns none;
    on the presets it returns the phase search's."""
    odd = pydrill.preset("reduced-scale", dof=2).replace(
        inertias=[1.9357097937073138, 0.010146544398270231],
        stiffnesses=[0.21685107636708736],
        dampings=[0.07694140798003772],
        top_damping=0.006319282554652413,
        bit_damping=0.6851916891429525,
    )
    for p in (pydrill.preset("reduced-scale", dof=2), pydrill.preset("real-string", dof=2), odd):
        fold = p.top_damping + p.bit_damping
        crossings = stability.critical_deltas(p)
        below = [c.delta for c in crossings if c.type == "hopf" and c.delta < fold]
        assert stability.hopf_deltas_dof2(p) == pytest.approx(below, rel=1e-7)
    assert any(c.type == "hopf" for c in stability.critical_deltas(odd))


@pytest.mark.parametrize("friction", ["exact", "karnopp"])
def test_runs_at_plus_and_minus_torque_are_mirror_images(friction):
    """phi -> -phi maps the run at u onto the run at -u: the same regime and switches, the
    bit's velocities reversed (the slip- friction and the negative break-away take part)."""
    p = pydrill.preset("reduced-scale", dof=4)
    kw = dict(wob=100.0, t_end=150.0, n_out=301, friction=friction)
    f = pydrill.simulate(p, torque=8.3, **kw)
    b = pydrill.simulate(p, torque=-8.3, **kw)
    assert f.regime == "stick-slip"
    assert b.regime == f.regime
    assert len(b.switches) == len(f.switches)
    assert [s.kind for s in b.switches] == [s.kind for s in f.switches]
    np.testing.assert_allclose([s.t for s in b.switches], [s.t for s in f.switches], rtol=1e-6)
    assert b.summary.bit_top_ratio == pytest.approx(f.summary.bit_top_ratio, rel=1e-6)
    assert b.summary.bit_mean == pytest.approx(-f.summary.bit_mean, rel=1e-6)
    np.testing.assert_allclose(b.states, -f.states, rtol=1e-5, atol=1e-6)


def test_negative_torque_stability_points_carry_that_torque():
    """Each steady state of u < 0 is the mirror of one of |u|, with the torque u itself."""
    p = pydrill.preset("reduced-scale", dof=4)
    fwd = stability.stability(p, wob=100.0, torque=7.0)
    back = stability.stability(p, wob=100.0, torque=-7.0)
    assert len(fwd) == len(back) == 2
    for b, f in zip(back, reversed(fwd), strict=True):
        assert b.torque == pytest.approx(-7.0, rel=1e-9)
        assert b.omega == pytest.approx(-f.omega)
