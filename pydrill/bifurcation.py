"""Bifurcation diagrams of steady drilling (the equilibrium part of the paper's Fig. 11).

Along the branch of steady states at fixed surface torque (varying W_ob) or fixed weight on bit
(varying u), the Stribeck slope δ(Ω) tells everything: the branch turns (LP, a fold) where
δ = c_r + c_b, and it meets a Hopf point (HB) wherever δ equals one of the string's critical
values δ_k. Both are located by bracketing and Brent's method to ~1e-12 relative.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from . import _core
from .model import MAX_LOAD, Params, _integer, _load, _number
from .stability import (
    Crossing,
    _check_crossings,
    _params,
    critical_deltas,
    criticality,
    stribeck_slope,
    unstable_count,
)

#: The most samples along a branch: each costs a few floats per crossing; Brent's method
#: refines every special point to ~1e-12 whatever the sampling.
MAX_SAMPLES = 1_000_000


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


def _positive(name: str, value: float | None, unit: str, why: str) -> float:
    """``value`` as a float, refused by name unless a finite number > 0."""
    value = _number(name, value, unit)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} = {value:g} is not allowed: {why} a finite {name} > 0 ({unit})")
    return _load(name, value, unit) if name in ("wob", "torque") else value


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
    crossings: Iterable[Crossing] | None = None,
) -> Branch:
    """The branch of steady states Ω > 0 with its stability and special points.

    ``vary="wob"`` holds ``torque`` fixed (W_ob(Ω) = (u − (c_r + c_b)Ω) / (R_b μ_b(Ω)));
    ``vary="torque"`` holds ``wob`` fixed (u(Ω) = (c_r + c_b)Ω + W_ob R_b μ_b(Ω)).

    - ``torque`` (N·m) or ``wob`` (N): the one held fixed, a finite number > 0, at most
      ``MAX_LOAD`` (1e15) as in :func:`pydrill.simulate`; the varied one is not given.
    - ``omega_max`` (rad/s): the largest Ω sampled, a finite number > 0; None (default) for
      u / (c_r + c_b) with ``vary="wob"`` (where W_ob reaches 0; never beyond it), 40 with
      ``vary="torque"`` (where its torque must be at most ``MAX_LOAD``).
    - ``samples``: the number of Ω sampled, an integer 2 ... ``MAX_SAMPLES`` (1000000).
    - ``crossings``: the string's ``critical_deltas(params)``, if already at hand.

    A wrong type raises ``TypeError``, a bad value ``ValueError``, naming the parameter.
    """
    p = _params(params)
    c = p.top_damping + p.bit_damping
    if not isinstance(vary, str) or vary not in ("wob", "torque"):
        raise ValueError(f"vary = {vary!r} is not allowed: choose 'wob' or 'torque'")
    held, varied = ("torque", "wob") if vary == "wob" else ("wob", "torque")
    given = {"wob": wob, "torque": torque}
    if given[varied] is not None:
        raise ValueError(
            f"{varied} = {given[varied]!r} is not allowed with vary = {vary!r}: {varied} is "
            f"the varied parameter (give {held} only)"
        )
    if given[held] is None:
        raise ValueError(f"{held} = None is not allowed: varying {vary} needs a {held} > 0")
    if omega_max is not None:
        omega_max = _positive("omega_max", omega_max, "rad/s", "need")
    samples = _integer("samples", samples, 2, MAX_SAMPLES)
    if vary == "wob":
        torque = fixed = _positive("torque", torque, "N·m", "varying wob needs")
        top = torque / c if c > 0 else 100.0
        omega_max = top if omega_max is None else min(omega_max, top)

        def wob_of(w):
            return (torque - c * np.asarray(w)) / (p.bit_radius * _mu(p, w))

        def torque_of(w):
            return np.full_like(np.asarray(w, dtype=float), torque)
    else:
        wob = fixed = _positive("wob", wob, "N", "varying torque needs")
        omega_max = 40.0 if omega_max is None else omega_max

        def wob_of(w):
            return np.full_like(np.asarray(w, dtype=float), wob)

        def torque_of(w):
            return c * np.asarray(w) + wob * p.bit_radius * _mu(p, w)

        with np.errstate(over="ignore"):  # (inf: refused too)
            top = float(torque_of(omega_max))
        if not top <= MAX_LOAD:  # 1e308 rad/s of the real string overflowed to inf N·m
            raise ValueError(
                f"omega_max = {omega_max:g} is not allowed with wob = {wob:g} N: the steady "
                f"torque there, {top:.3g} N·m, is beyond MAX_LOAD (1e15), as in simulate"
            )

    if crossings is None:
        crossings = critical_deltas(p)
    else:
        crossings = _check_crossings(p, crossings)

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
            assert cr.frequency is not None  # a Hopf crossing's (None for a fold only)
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
        fixed,
        omega,
        W,
        U,
        unstable_count(crossings, deltas),
        points,
    )
