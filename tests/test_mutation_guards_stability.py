"""Mutation guards for pydrill.stability and pydrill.sliding (helper "stab", session 34): each
test compares against something computed another way (numpy on the same Jacobian, the paper's
Eqs. 24-25 and 39 by hand, the definition of the sliding region's strictness)."""

import itertools
import math

import numpy as np
import pytest

from pydrill import preset
from pydrill.sliding import quasi_equilibrium, sliding_region_edges
from pydrill.stability import criticality, eigenvalues, jacobian, stability


def test_a_steady_state_at_zero_velocity_is_refused_by_name():
    # Ω = 0 is the stuck bit, not steady drilling (DESIGN.md §3): the API names omega.
    with pytest.raises(ValueError, match="omega = 0"):
        stability(preset("reduced-scale", dof=3), 100.0, omega=0.0)


@pytest.mark.parametrize("l1", [math.inf, -math.inf])
def test_an_infinite_lyapunov_coefficient_is_refused(l1):
    # The sign of an overflowed l1 means nothing: refused, not called sub/supercritical.
    with pytest.raises(ValueError, match="finite"):
        criticality(l1)


def test_to_dict_keeps_the_leading_eigenvalues_and_counts_all():
    p = preset("reduced-scale", dof=4)
    (pt,) = stability(p, 100.0, omega=5.0)
    d = pt.to_dict(n_eigenvalues=2)
    # 2 dof − 1 eigenvalues in all (the reduced Jacobian's size), the first two listed.
    assert d["eigenvalue_count"] == 2 * p.dof - 1
    assert d["eigenvalues"] == [[z.real, z.imag] for z in pt.eigenvalues[:2]]


def test_eigenvalues_are_numpys_of_the_jacobian_larger_imaginary_part_first_in_a_pair():
    p = preset("reduced-scale", dof=5)
    ev = eigenvalues(p, 0.05)
    ref = np.linalg.eigvals(jacobian(p, 0.05))
    assert np.allclose(np.sort_complex(ev), np.sort_complex(ref.astype(complex)))
    # Largest real part first; within a conjugate pair (equal real parts) +iω before −iω.
    for a, b in itertools.pairwise(ev):
        assert a.real >= b.real or math.isclose(a.real, b.real, rel_tol=1e-12)
        if a.real == b.real:
            assert a.imag >= b.imag


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_quasi_equilibrium_is_real_only_strictly_inside_the_sliding_region(sign):
    # Eq. 39: real iff |u| < T_s = μ_sb W_ob R_b; on the line |u| = T_s it is not, and −u
    # mirrors u (twists reversed, the same verdict). Springs all different: the collars' is
    # the last one.
    p = preset("reduced-scale", dof=4).replace(stiffnesses=[0.07, 0.2, 0.5])
    ts = p.mu_static * 100.0 * p.bit_radius
    assert quasi_equilibrium(p, 100.0, sign * 0.9 * ts).real
    assert not quasi_equilibrium(p, 100.0, sign * ts).real
    assert not quasi_equilibrium(p, 100.0, sign * 1.1 * ts).real
    q = quasi_equilibrium(p, 100.0, sign * 0.5 * ts)
    # Every spring carries u: θ_i = u / k_i, velocities zero (Eqs. 28-30).
    assert np.allclose(q.state[1::2], sign * 0.5 * ts / np.asarray(p.stiffnesses))
    assert np.all(q.state[0::2] == 0)
    assert q.collar_twist == pytest.approx(sign * 0.5 * ts / p.stiffnesses[-1])


def test_the_sliding_region_edges_are_the_collars_reaction_at_plus_minus_the_static_torque():
    # Eqs. 24-25: k θ + c ω = ±T_s with the collars' spring (the last one), checked by
    # putting the edges back into the reaction torque.
    p = preset("reduced-scale", dof=4).replace(
        stiffnesses=[0.07, 0.2, 0.5], dampings=[0.001, 0.002, 0.003]
    )
    w = np.array([-2.0, 0.0, 3.0])
    upper, lower = sliding_region_edges(p, 100.0, w)
    k, c = p.stiffnesses[-1], p.dampings[-1]
    ts = p.static_torque(100.0)
    assert np.allclose(k * upper + c * w, ts)
    assert np.allclose(k * lower + c * w, -ts)
