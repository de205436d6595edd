"""Bifurcation diagrams of steady drilling (the equilibrium part of the paper's Fig. 11).

Along the branch of steady states at fixed surface torque (varying W_ob) or fixed weight on bit
(varying u), the Stribeck slope δ(Ω) tells everything: the branch turns (LP, a fold) where
δ = c_r + c_b, and it meets a Hopf point (HB) wherever δ equals one of the string's critical
values δ_k. Both are located by bracketing and Brent's method to ~1e-12 relative.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from . import _core
from .model import Params
from .stability import Crossing, critical_deltas, criticality, stribeck_slope, unstable_count


@dataclass(frozen=True)
class SpecialPoint:
    type: str  #: "HB" (Hopf) or "LP" (limit point: the branch folds)
    wob: float  #: N
    torque: float  #: N·m
    omega: float  #: rad/s
    delta: float  #: N·m·s/rad
    frequency: float | None  #: rad/s of the Hopf pair
    lyapunov: float | None  #: first Lyapunov coefficient (1/s per amplitude²)
    criticality: str | None  #: "supercritical" (l1 < 0), "subcritical" (l1 > 0), "degenerate"
    direction: int  #: +1 if the steady state loses stability as δ grows through it
    #: eigenvalues in the right half-plane on both sides of the point, besides its own: > 0
    #: means the steady state is unstable there anyway, so the orbit a Hopf point gives birth
    #: to is unstable whatever its criticality, and nothing is seen to change (no Hopf
    #: bifurcation in the paper's sense, Def. 4: H₁ of the dof-2 string, past the fold)
    others_unstable: int = 0

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Branch:
    """Steady states along one parameter, sampled at ``omega``; ``unstable`` counts the
    eigenvalues in the right half-plane at each sample."""

    vary: str  #: "wob" or "torque"
    fixed: float  #: the torque (N·m) or weight on bit (N) held fixed
    omega: NDArray[np.float64]
    wob: NDArray[np.float64]
    torque: NDArray[np.float64]
    unstable: NDArray[np.int64]
    points: list[SpecialPoint]

    def to_dict(self) -> dict:
        return {
            "vary": self.vary,
            "fixed": self.fixed,
            "points": [p.to_dict() for p in self.points],
            "branch": {
                "omega": self.omega.tolist(),
                "wob": self.wob.tolist(),
                "torque": self.torque.tolist(),
                "unstable": self.unstable.tolist(),
            },
        }


def _mu(params: Params, omega):
    p = params
    return p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(
        -p.stribeck_decay * np.asarray(omega) / p.stribeck_velocity
    )


def branch(
    params: Params,
    *,
    vary: Literal["wob", "torque"],
    torque: float | None = None,
    wob: float | None = None,
    omega_max: float | None = None,
    samples: int = 2000,
    crossings: list[Crossing] | None = None,
) -> Branch:
    """The branch of steady states Ω > 0 with its stability and special points.

    ``vary="wob"`` holds ``torque`` fixed (W_ob(Ω) = (u − (c_r + c_b)Ω) / (R_b μ_b(Ω)));
    ``vary="torque"`` holds ``wob`` fixed (u(Ω) = (c_r + c_b)Ω + W_ob R_b μ_b(Ω)).
    """
    p = params
    c = p.top_damping + p.bit_damping
    if vary == "wob":
        if torque is None or not np.isfinite(torque) or torque <= 0:
            raise ValueError(f"torque = {torque!r} is not allowed: varying wob needs a torque > 0")
        top = torque / c if c > 0 else 100.0
        omega_max = min(omega_max or top, top)

        def wob_of(w):
            return (torque - c * np.asarray(w)) / (p.bit_radius * _mu(p, w))

        def torque_of(w):
            return np.full_like(np.asarray(w, dtype=float), torque)
    elif vary == "torque":
        if wob is None or not np.isfinite(wob) or wob <= 0:
            raise ValueError(f"wob = {wob!r} is not allowed: varying torque needs a wob > 0")
        omega_max = omega_max or 40.0

        def wob_of(w):
            return np.full_like(np.asarray(w, dtype=float), wob)

        def torque_of(w):
            return c * np.asarray(w) + wob * p.bit_radius * _mu(p, w)
    else:
        raise ValueError(f"vary = {vary!r} is not allowed: choose 'wob' or 'torque'")
    if crossings is None:
        crossings = critical_deltas(p)

    omega = np.linspace(omega_max * 1e-4, omega_max * (1 - 1e-9), samples)
    W = wob_of(omega)
    U = torque_of(omega)
    keep = W > 0
    omega, W, U = omega[keep], W[keep], U[keep]

    def delta_of(w):
        return float(stribeck_slope(p, wob_of(w), w))

    deltas = stribeck_slope(p, W, omega)
    points: list[SpecialPoint] = []
    core = p.to_core()
    for cr in crossings:
        f = deltas - cr.delta
        for i in np.nonzero(np.sign(f[1:]) != np.sign(f[:-1]))[0]:
            w = brentq(
                lambda x, d=cr.delta: delta_of(x) - d,
                omega[i],
                omega[i + 1],
                xtol=1e-14,
                rtol=4 * np.finfo(float).eps,
            )
            below = int(unstable_count(crossings, cr.delta))  # strictly below δ_k
            others = min(below, below + cr.direction * cr.multiplicity)
            if cr.type == "fold":
                points.append(
                    SpecialPoint(
                        "LP",
                        float(wob_of(w)),
                        float(torque_of(w)),
                        w,
                        cr.delta,
                        None,
                        None,
                        None,
                        cr.direction,
                        others,
                    )
                )
                continue
            l1 = _core.first_lyapunov_coefficient(core, cr.delta, cr.frequency)
            points.append(
                SpecialPoint(
                    "HB",
                    float(wob_of(w)),
                    float(torque_of(w)),
                    w,
                    cr.delta,
                    cr.frequency,
                    l1,
                    criticality(l1),
                    cr.direction,
                    others,
                )
            )
    points.sort(key=lambda s: s.omega)
    return Branch(
        vary,
        float(torque if vary == "wob" else wob),
        omega,
        W,
        U,
        unstable_count(crossings, deltas),
        points,
    )
