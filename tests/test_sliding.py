"""Sliding-mode analysis (paper Section 3) against the simulator."""

import numpy as np
import pytest

import pydrill
from pydrill.sliding import quasi_equilibrium, reference_values, sliding_region_edges


def test_stuck_string_relaxes_to_the_real_quasi_equilibrium():
    """Proposition 3: on Σ̃ the quasi-equilibrium is asymptotically stable. The paper's Fig. 7
    case (dof 4, W_ob 160 N, u 8.3 N·m) stays stuck and winds down to θ_i = u / k_i."""
    p = pydrill.preset("reduced-scale", dof=4)
    qe = quasi_equilibrium(p, 160.0, 8.3)
    assert qe.real and qe.static_torque == pytest.approx(12.8)
    r = pydrill.simulate(p, wob=160.0, torque=8.3, t_end=3000.0, n_out=3001)
    assert r.regime == "stuck"
    final = r.states[-1]
    np.testing.assert_allclose(final[1::2], qe.state[1::2], rtol=1e-3)
    assert np.max(np.abs(final[0::2])) < 1e-3
    # The trajectory never leaves the sliding region: |k θ + c ω| ≤ T_s all along.
    hi, lo = sliding_region_edges(p, 160.0, r.omega[:, -2])
    assert np.all((r.twist[:, -1] <= hi + 1e-12) & (r.twist[:, -1] >= lo - 1e-12))


def test_virtual_quasi_equilibrium_means_the_bit_breaks_free():
    p = pydrill.preset("reduced-scale", dof=4)
    qe = quasi_equilibrium(p, 100.0, 8.3)  # u > T_s = 8: virtual (Eq. 39)
    assert not qe.real
    r = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=100.0)
    first_slip = next(s for s in r.switches if s.kind == "slip")
    # It leaves exactly on the edge ∂Σ̃⁺ (k θ + c ω = T_s), before the string has relaxed.
    assert first_slip.reaction_torque == pytest.approx(qe.static_torque, rel=1e-9)
    assert first_slip.t < 30.0
    ref = reference_values(p, 100.0, 8.3)
    assert ref["torque_star"] == pytest.approx(8.0)
    assert ref["wob_star"] == pytest.approx(103.75)
