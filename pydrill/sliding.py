"""Sliding-mode analysis of the stuck bit (paper Section 3, Eqs. 22–39).

On Σ = {ω_b = 0} the rock holds the bit while the reaction torque T_e = k θ_{N−2} + c ω_{N−2}
(collars' twist and velocity; Eq. 22 with the bit still) stays within ±T_s, T_s = μ_sb W_ob R_b:
that strip of the (θ_{N−2}, ω_{N−2}) plane is the sliding region Σ̃, its edges ∂Σ̃± are the lines
k θ + c ω = ±T_s. While stuck, the string relaxes to the quasi-equilibrium (Eqs. 28–30): every
velocity zero and every spring carrying the surface torque, θ_i = u / k_i. It is *real* (inside
Σ̃: the bit stays stuck for good) when |u| < T_s and *virtual* otherwise (Eq. 39).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .model import Params


@dataclass(frozen=True)
class QuasiEquilibrium:
    torque: float  #: N·m
    wob: float  #: N
    state: NDArray[np.float64]  #: twist coordinates (ω_0, θ_0, …, ω_b): velocities 0, θ_i = u/k_i
    static_torque: float  #: T_s = μ_sb W_ob R_b
    real: bool  #: inside the sliding region: |u| < T_s (Eq. 39)

    @property
    def collar_twist(self) -> float:
        """θ_{N−2} = u / k_{N−2}: the paper's x̃_{n−3} − φ̄_b."""
        return float(self.state[-2])


def quasi_equilibrium(params: Params, wob: float, torque: float) -> QuasiEquilibrium:
    """The quasi-equilibrium of the sliding motion for (W_ob, u) (Eqs. 28–30)."""
    n = 2 * params.dof - 1
    state = np.zeros(n)
    state[1::2] = torque / np.asarray(params.stiffnesses)
    ts = params.static_torque(wob)
    return QuasiEquilibrium(float(torque), float(wob), state, ts, abs(torque) < ts)


def sliding_region_edges(
    params: Params, wob: float, collar_velocity: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The edges ∂Σ̃⁺ and ∂Σ̃⁻ as collar twist θ_{N−2} against collar velocity ω_{N−2}
    (Eqs. 24–25 in twist coordinates): θ = (±T_s − c ω) / k."""
    k, c = params.stiffnesses[-1], params.dampings[-1]
    ts = params.static_torque(wob)
    w = np.asarray(collar_velocity, dtype=float)
    return (ts - c * w) / k, (-ts - c * w) / k


def reference_values(params: Params, wob: float, torque: float) -> dict[str, float]:
    """The reference values of Eq. (38): u* = μ_sb W_ob R_b and W_ob* = u / (μ_sb R_b)."""
    return {
        "torque_star": params.mu_static * wob * params.bit_radius,
        "wob_star": torque / (params.mu_static * params.bit_radius),
    }
