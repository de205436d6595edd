"""Sliding-mode analysis of the stuck bit (paper Section 3, Eqs. 22–39).

On Σ = {ω_b = 0} the rock holds the bit while the reaction torque T_e = k θ_{N−2} + c ω_{N−2}
(collars' twist and velocity; Eq. 22 with the bit still) stays within ±T_s, T_s = μ_sb W_ob R_b:
that strip of the (θ_{N−2}, ω_{N−2}) plane is the sliding region Σ̃, its edges ∂Σ̃± are the lines
k θ + c ω = ±T_s. While stuck, the string relaxes to the quasi-equilibrium (Eqs. 28–30): every
velocity zero and every spring carrying the surface torque, θ_i = u / k_i. It is *real* (inside
Σ̃: the bit stays stuck for good) when |u| < T_s and *virtual* otherwise (Eq. 39).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .model import Params, _number
from .stability import _params


def _operating_point(wob: float, torque: float) -> tuple[float, float]:
    """(W_ob, u) checked by name: W_ob a finite number > 0 (N), u a finite number (N·m; < 0
    turns the string backwards)."""
    wob = _number("wob", wob, "N")
    torque = _number("torque", torque, "N·m")
    if not (math.isfinite(wob) and wob > 0):
        raise ValueError(f"wob = {wob:g} is not allowed: must be a finite number > 0 (N)")
    if not math.isfinite(torque):
        raise ValueError(f"torque = {torque:g} is not allowed: must be a finite number (N·m)")
    return wob, torque


def _wob(wob: float) -> float:
    return _operating_point(wob, 0.0)[0]


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
    """The quasi-equilibrium of the sliding motion for (W_ob, u) (Eqs. 28–30): ``wob`` a
    finite number > 0 (N), ``torque`` a finite number (N·m; a negative one winds the string
    the other way, the mirror image: twists reversed, the same static torque)."""
    params = _params(params)
    wob, torque = _operating_point(wob, torque)
    n = 2 * params.dof - 1
    state = np.zeros(n)
    state[1::2] = torque / np.asarray(params.stiffnesses)
    ts = params.static_torque(wob)
    return QuasiEquilibrium(torque, wob, state, ts, abs(torque) < ts)


def sliding_region_edges(
    params: Params, wob: float, collar_velocity: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The edges ∂Σ̃⁺ and ∂Σ̃⁻ as collar twist θ_{N−2} against collar velocity ω_{N−2}
    (Eqs. 24–25 in twist coordinates): θ = (±T_s − c ω) / k. ``wob`` a finite number > 0
    (N), ``collar_velocity`` a number or an array of finite numbers (rad/s)."""
    params = _params(params)
    k, c = params.stiffnesses[-1], params.dampings[-1]
    ts = params.static_torque(_wob(wob))
    w = np.asarray(collar_velocity)
    if w.dtype.kind not in "iuf":
        raise TypeError(
            f"collar_velocity = {collar_velocity!r} is not allowed: must be a number or an "
            "array of them (rad/s)"
        )
    w = w.astype(float, copy=False)
    if not np.all(np.isfinite(w)):
        if w.ndim == 0:
            raise ValueError(
                f"collar_velocity = {float(w):g} is not allowed: must be a finite number (rad/s)"
            )
        where = np.unravel_index(int(np.argmin(np.isfinite(w))), w.shape)
        at = ", ".join(map(str, where))
        raise ValueError(
            f"collar_velocity[{at}] = {float(w[where]):g} is not allowed: each must be a "
            "finite number (rad/s)"
        )
    return (ts - c * w) / k, (-ts - c * w) / k


def reference_values(params: Params, wob: float, torque: float) -> dict[str, float]:
    """The reference values of Eq. (38): u* = μ_sb W_ob R_b (the static torque T_s) and
    W_ob* = |u| / (μ_sb R_b) (the weight at which T_s = |u|: on the lines u = ±μ_sb W_ob R_b,
    the same for ±u). ``wob`` a finite number > 0 (N), ``torque`` a finite number (N·m)."""
    params = _params(params)
    wob, torque = _operating_point(wob, torque)
    return {
        "torque_star": params.mu_static * wob * params.bit_radius,
        "wob_star": abs(torque) / (params.mu_static * params.bit_radius),
    }
