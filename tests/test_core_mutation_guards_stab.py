"""Guards from a second mutation audit of the C++ core's stability side (session 37).

Each test failed on a small change to the core (a dropped or flipped Jacobian term, a loose
root tolerance, a wrong sort, a transposed solve) that no other test noticed, and checks the
core against something that shares no code with it: the Jacobian assembled here by hand from
DESIGN.md's equations of motion, numpy's eigenvalues and characteristic polynomial of that
matrix, a bisection on numpy's count of unstable eigenvalues, Hurwitz determinants written
out by hand, the analytic modes of a uniform chain, and the paper's stated Hopf point.
"""

import numpy as np
import pytest

import pydrill
from pydrill import _core
from pydrill import stability as st


def _string():
    """Five inertias with every value distinct, so that an entry taken from the wrong
    neighbour (inertia, spring or end damping) changes the matrix."""
    return pydrill.preset("reduced-scale", dof=5).replace(
        inertias=(0.5, 0.031, 0.027, 0.022, 0.04),
        stiffnesses=(0.07, 0.09, 0.06, 0.11),
        dampings=(1e-3, 2e-3, 5e-4, 3e-3),
        top_damping=0.18,
        bit_damping=0.013,
    )


def _hand_jacobian(p, delta):
    """DESIGN.md section 2-3 in twist coordinates x' = (w_0, th_0, w_1, ..., th_{N-2}, w_b):
    I_i dw_i/dt = k_{i-1} th_{i-1} + c_{i-1}(w_{i-1} - w_i) - k_i th_i - c_i(w_i - w_{i+1}),
    minus c_r w_0 at the top, minus c_b w_b - T_fb at the bit (-dT_fb/dw = +delta), and
    dth_i/dt = w_i - w_{i+1}."""
    n_dof = len(p.inertias)
    n = 2 * n_dof - 1
    a = np.zeros((n, n))
    k, c, inertia = p.stiffnesses, p.dampings, p.inertias
    for i in range(n_dof):
        r = 2 * i
        row = np.zeros(n)
        if i == 0:
            row[r] -= p.top_damping
        if i == n_dof - 1:
            row[r] += -p.bit_damping + delta
        if i > 0:
            row[r - 1] += k[i - 1]
            row[r - 2] += c[i - 1]
            row[r] -= c[i - 1]
        if i < n_dof - 1:
            row[r + 1] -= k[i]
            row[r] -= c[i]
            row[r + 2] += c[i]
            a[r + 1, r], a[r + 1, r + 2] = 1.0, -1.0
        a[r] = row / inertia[i]
    return a


@pytest.mark.parametrize("delta", [0.0, 0.004, 0.05, 0.3])
def test_jacobian_and_eigenvalues_are_those_of_the_hand_assembled_matrix(delta):
    """The core's Jacobian entry by entry, and its dense eigenvalues (sorted by decreasing real
    part, as documented) against numpy's of the hand-built matrix."""
    p = _string()
    a = _hand_jacobian(p, delta)
    core = np.array(_core.jacobian(p.to_core(), delta)).reshape(a.shape)
    np.testing.assert_allclose(core, a, rtol=1e-14, atol=0)
    ev = np.array(_core.eigenvalues(p.to_core(), delta))
    # Decreasing real part, and a conjugate pair upper first: the order stability.eigenvalues
    # gives numpy's (lexsort on -real, then -imag), so both lists read alike.
    assert np.array_equal(ev, ev[np.lexsort((-ev.imag, -ev.real))])
    want = np.linalg.eigvals(a)
    assert np.sort_complex(ev) == pytest.approx(np.sort_complex(want), rel=1e-9, abs=1e-12)


def test_characteristic_polynomial_is_numpys_of_the_hand_assembled_matrix():
    """det(lambda I - J) in ascending powers, against numpy's poly of the same matrix."""
    p = _string()
    for delta in (0.0, 0.02, 0.4):
        want = np.poly(_hand_jacobian(p, delta))[::-1]
        got = np.array(_core.characteristic_polynomial(p.to_core(), delta))
        np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-12 * np.max(np.abs(want)))


def test_hurwitz_determinants_of_a_quartic_written_out_by_hand():
    """lambda^4 + a3 lambda^3 + a2 lambda^2 + a1 lambda + a0: Delta_1 = a3,
    Delta_2 = a3 a2 - a1, Delta_3 = a1 Delta_2 - a3^2 a0 (and no Delta_4)."""
    a0, a1, a2, a3 = 2.0, 3.0, 5.0, 7.0
    got = st.hurwitz_determinants([a0, a1, a2, a3, 1.0])
    d2 = a3 * a2 - a1
    np.testing.assert_allclose(got, [a3, d2, a1 * d2 - a3**2 * a0], rtol=1e-14)


def test_every_crossing_is_where_the_brute_force_unstable_count_changes():
    """Each crossing of the paper's dof-4 string to 1e-9, by bisection on the count of
    right-half-plane eigenvalues (numpy's, of the hand-built matrix) across it, and its
    direction is the way that count jumps there. The first Hopf point is the
    paper's, delta = 0.01079 (cpp/tests/CMakeLists.txt's example test)."""
    p = pydrill.preset("reduced-scale", dof=4)
    crossings = st.critical_deltas(p)
    hopf = [c for c in crossings if c.type == "hopf"]
    assert hopf[0].delta == pytest.approx(0.01079, abs=5e-6)

    def rhp(d):
        return int(np.sum(np.linalg.eigvals(_hand_jacobian(p, d)).real > 0))

    for c in crossings:
        lo, hi = 0.999 * c.delta, 1.001 * c.delta
        below, above = rhp(lo), rhp(hi)
        assert above - below == c.direction * c.multiplicity, c
        for _ in range(60):  # bisect on the count, which changes at the crossing alone
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if rhp(mid) == below else (lo, mid)
        assert c.delta == pytest.approx(0.5 * (lo + hi), rel=1e-9), c
        if c.type == "hopf":
            ev = np.linalg.eigvals(_hand_jacobian(p, c.delta))
            lead = ev[np.argmin(np.abs(ev.real))]
            assert c.frequency == pytest.approx(abs(lead.imag), rel=1e-7)


def test_steady_state_is_designs_twists_and_torque():
    """DESIGN.md section 3: every w_i = Omega, th_i = h(Omega)/k_i with h = c_b Omega +
    T_fb(Omega), and u = c_r Omega + h (the friction law of section 2 written out here)."""
    p = _string()
    wob, omega = 100.0, 2.0
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(
        -p.stribeck_decay * omega / p.stribeck_velocity
    )
    h = p.bit_damping * omega + wob * p.bit_radius * mu
    want = np.full(2 * len(p.inertias) - 1, omega)
    want[1::2] = h / np.array(p.stiffnesses)
    got = np.array(_core.equilibrium_state(p.to_core(), wob, omega))
    np.testing.assert_allclose(got, want, rtol=1e-13)
    assert _core.equilibrium_torque(p.to_core(), wob, omega) == pytest.approx(
        p.top_damping * omega + h, rel=1e-13
    )


def test_an_undamped_chains_hopf_points_at_zero_are_its_modes_to_the_last_bit():
    """A uniform free chain of N inertias J and springs k with no damping anywhere has its
    Hopf points at delta = 0 (documented), one per nonzero mode, at the analytic frequencies
    2 sqrt(k/J) sin(j pi / 2N), each a pair leaving to the right. A tridiagonal eigensolver's
    frequencies carry an error of eps * lambda_max, 7e-12 of the lowest at N = 300 (numpy's
    eigvalsh: the same); polished on Im Z_b they are exact to rounding."""
    n = 300
    p = pydrill.preset("reduced-scale", dof=4).replace(
        inertias=(1.0,) * n,
        stiffnesses=(1.0,) * (n - 1),
        dampings=(0.0,) * (n - 1),
        top_damping=0.0,
        bit_damping=0.0,
    )
    hopf = [c for c in st.critical_deltas(p) if c.type == "hopf"]
    assert all(c.delta == 0.0 and c.direction == 1 and c.multiplicity == 2 for c in hopf)
    w = np.sort([c.frequency for c in hopf])
    want = 2.0 * np.sin(np.arange(1, n) * np.pi / (2 * n))
    np.testing.assert_allclose(w, want, rtol=1e-13)
