"""A drilling engineer's audit of ``pydrill simulate``: where (W_ob, u) has two steady states,
the slower lies past the fold (its Stribeck slope above c_r + c_b) and is unstable on any
string, yet the text listed "0.496476 rad/s (4.741 rpm), 6.75917 rad/s (64.55 rpm)" alike and
the figure drew both as "steady state Ω": a bit that could settle at 4.7 rpm. Now the text
says which is past the fold and the figure draws it apart. The verdicts are checked against
the eigenvalues of the 2-DOF Jacobian written out here by hand from the equations of motion,
not pydrill's stability code."""

import matplotlib
import numpy as np
import pytest
from cli_running import run

import pydrill

matplotlib.use("Agg")

WOB, TORQUE = 100e3, 11e3  # N, N·m: real-string (Eq. 53) below its T_s = 12.45 kN·m


def jacobian_2dof(p, wob, omega):
    """d/dt (ω_0, θ, ω_b) linearised at the steady state Ω: J_r ω_0' = u − c_r ω_0 − k θ
    − c (ω_0 − ω_b), θ' = ω_0 − ω_b, J_b ω_b' = k θ + c (ω_0 − ω_b) − c_b ω_b − T_f(ω_b),
    with T_f = W_ob R_b (μ_c + (μ_s − μ_c) e^{−γ ω / v_f}), so −dT_f/dω = δ."""
    jr, jb = p.inertias
    (k,), (c,) = p.stiffnesses, p.dampings
    g = p.stribeck_decay / p.stribeck_velocity
    delta = wob * p.bit_radius * (p.mu_static - p.mu_coulomb) * g * np.exp(-g * abs(omega))
    return np.array(
        [
            [-(p.top_damping + c) / jr, -k / jr, c / jr],
            [1.0, 0.0, -1.0],
            [c / jb, k / jb, (delta - c - p.bit_damping) / jb],
        ]
    )


@pytest.mark.parametrize("sign", [1, -1])
def test_the_steady_state_past_the_fold_is_marked_and_is_unstable(sign):
    r = pydrill.simulate(preset="real-string", wob=WOB, torque=sign * TORQUE, t_end=10.0)
    omegas = r.summary.omega_equilibrium
    assert len(omegas) == 2
    growth = [np.linalg.eigvals(jacobian_2dof(r.params, WOB, w)).real.max() for w in omegas]
    # past the fold exactly where an eigenvalue grows (here: the slower one, by |Ω|)
    assert r.past_fold() == tuple(rate > 0 for rate in growth)
    assert sum(r.past_fold()) == 1
    slow = min(range(2), key=lambda i: abs(omegas[i]))
    assert r.past_fold()[slow] and growth[slow] > 0 > growth[1 - slow]


def test_the_text_and_the_figure_say_which_steady_state_is_unstable(capsys):
    code, out, _ = run(
        capsys, "simulate", "--preset", "real-string", "--wob", "100kN", "--torque", "11kN*m",
        "--t-end", "10",
    )  # fmt: skip
    assert code == 0
    (line,) = [x for x in out.splitlines() if x.startswith("steady states")]
    slow, fast = line.split("   ", 1)[1].split("), ")
    assert slow.endswith("rpm, unstable: past the fold") and slow.startswith("0.496476 rad/s")
    assert fast == "6.75917 rad/s (64.55 rpm)"  # 6.75917 · 60/2π; not past the fold
    from pydrill.plot import simulation_figure

    r = pydrill.simulate(preset="real-string", wob=WOB, torque=TORQUE, t_end=10.0)
    ax = simulation_figure(r).axes[0]
    drawn = {line.get_label(): line.get_ydata()[0] for line in ax.get_lines()}
    assert drawn["unstable steady state (past the fold)"] == pytest.approx(0.496476, abs=1e-6)
    assert drawn["steady state $\\Omega$"] == pytest.approx(6.75917, abs=1e-5)


def test_a_single_stable_steady_state_is_not_marked(capsys):
    """The paper's Fig. 4 case: stick-slip from rest about a steady state that is stable (its
    slope below c_r + c_b = 0.19 N·m·s/rad by five orders)."""
    r = pydrill.simulate(preset="reduced-scale", dof=4, wob=100.0, torque=8.3, t_end=10.0)
    assert r.past_fold() == (False,)
    (w,) = r.summary.omega_equilibrium
    p = r.params
    g = p.stribeck_decay / p.stribeck_velocity
    slope = 100.0 * p.bit_radius * (p.mu_static - p.mu_coulomb) * g * np.exp(-g * w)
    assert slope < 1e-5 * (p.top_damping + p.bit_damping)
