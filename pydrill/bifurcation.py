"""Bifurcation diagrams of steady drilling (the equilibrium part of the paper's Fig. 11).

Along the branch of steady states at fixed surface torque (varying W_ob) or fixed weight on bit
(varying u), the Stribeck slope δ(Ω) tells everything: the branch turns (LP, a fold) where
δ = c_r + c_b, and it meets a Hopf point (HB) wherever δ equals one of the string's critical
values δ_k. Both are located by bracketing and Brent's method to ~1e-12 relative.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass, fields, replace
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

#: The smallest Ω sampled, in units of the friction law's velocity scale v_f/γ_b: the branch
#: starts there whatever omega_max (it started at omega_max·1e-4, so that --omega-max 1e5 began
#: at 10 rad/s, past every Hopf and fold point of the laboratory string, and said "stable
#: along all of it").
FLOOR = 1e-6


def crossing_word(direction: int) -> str:
    """What a crossing's ``direction`` means, as the text tables say it: +1 "destabilising"
    (eigenvalues enter Re > 0 as δ grows), -1 "stabilising"."""
    return "destabilising" if direction > 0 else "stabilising"


def point_labels(points: Sequence[tuple[str, float]]) -> list[str]:
    """The names of a branch's special points, given as (type, Ω) pairs: the one rule the
    table, ``--json`` and the figures follow. Hopf points are HB1, HB2, ... from the highest Ω
    down — HB1 is where the stable high-speed branch ends, the first a driller slowing down
    meets; a fold is LP (LP1, LP2, ... in the same order if a branch had several)."""
    order = sorted(range(len(points)), key=lambda i: -points[i][1])
    labels = [""] * len(points)
    for kind in ("HB", "LP"):
        mine = [i for i in order if points[i][0] == kind]
        for n, i in enumerate(mine, 1):
            labels[i] = f"{kind}{n}" if kind == "HB" or len(mine) > 1 else kind
    return labels


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
    #: "HB1", "HB2", ... "LP": its name on the branch (:func:`point_labels`), as the figure
    #: writes it
    label: str = ""

    def to_dict(self) -> dict:
        # "crossing" says in words what "direction" (kept for scripts) says in a sign
        return {**asdict(self), "crossing": crossing_word(self.direction)}


@dataclass(frozen=True, eq=False)
class Branch:
    """Steady states along one parameter, sampled at ``omega``; ``unstable`` counts the
    eigenvalues in the right half-plane at each sample.

    Immutable as a whole: its arrays are read-only copies and ``points`` a tuple. Two branches
    are equal when all their fields are (arrays compared element by element): the generated
    ``==`` compared arrays with ``==`` and raised "truth value of an array is ambiguous". Like
    any value holding arrays, a branch is not hashable."""

    vary: str  #: "wob" or "torque"
    fixed: float  #: the torque (N·m) or weight on bit (N) held fixed
    omega: NDArray[np.float64]
    wob: NDArray[np.float64]
    torque: NDArray[np.float64]
    unstable: NDArray[np.int64]
    points: tuple[SpecialPoint, ...]  #: from the highest Ω down (HB1 first), labelled

    def __post_init__(self) -> None:
        for name, dtype in (
            ("omega", np.float64),
            ("wob", np.float64),
            ("torque", np.float64),
            ("unstable", np.int64),
        ):
            a = np.array(getattr(self, name), dtype=dtype)  # a copy: the caller's stays writeable
            a.flags.writeable = False
            object.__setattr__(self, name, a)
        object.__setattr__(self, "points", tuple(self.points))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Branch):
            return NotImplemented
        return all(
            np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b
            for a, b in ((getattr(self, f.name), getattr(other, f.name)) for f in fields(self))
        )

    __hash__ = None  # type: ignore[assignment]  # equal by value: arrays have no hash

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
      u / (c_r + c_b) with ``vary="wob"`` (where W_ob reaches 0; never beyond it; 100 without
      damping at the ends, where it never does), 40 with ``vary="torque"`` (where its torque
      must be at most ``MAX_LOAD``).
    - ``samples``: the number of Ω sampled, an integer 2 ... ``MAX_SAMPLES`` (1000000): half
      evenly up to ``omega_max``, half geometrically from ``FLOOR`` v_f/γ_b (1e-6 of the
      friction law's velocity scale) up, so that the low speeds where the Hopf and fold points
      lie are sampled alike whatever ``omega_max``. The special points do not depend on it:
      the Stribeck slope is monotonic along the branch, and each is bracketed from Ω = 0 up.
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
        if c > 0:  # W_ob reaches 0 at u / c: nothing beyond it
            omega_max = torque / c if omega_max is None else min(omega_max, torque / c)
        elif omega_max is None:  # no damping at the ends: W_ob > 0 at every Ω
            omega_max = 100.0

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

    scale = p.stribeck_velocity / p.stribeck_decay  # rad/s over which μ_b(Ω) changes
    last = omega_max * (1 - 1e-9)  # (with vary="wob", W_ob is 0 at the default omega_max)
    grid = _omega_grid(min(scale, last) * FLOOR, last, samples)

    def delta_of(w):
        return stribeck_slope(p, wob_of(w), w)

    deltas = delta_of(grid)
    core = p.to_core()
    points: list[SpecialPoint] = []
    for cr in crossings:
        # δ(Ω) > 0 at every finite Ω: a crossing at δ = 0 (no damping at an end) is met only
        # where exp(−γΩ/v_f) underflows, which is no point of the branch.
        if not cr.delta > 0:
            continue
        below = int(unstable_count(crossings, cr.delta))  # strictly below δ_k
        others = min(below, below + cr.direction * cr.multiplicity)
        for w in _roots(lambda x, d=cr.delta: delta_of(x) - d, grid, deltas - cr.delta):
            at = (float(wob_of(w)), float(torque_of(w)), w, cr.delta)
            if cr.type == "fold":
                points.append(SpecialPoint("LP", *at, None, None, None, cr.direction, others))
                continue
            assert cr.frequency is not None  # a Hopf crossing's (None for a fold only)
            l1 = _core.first_lyapunov_coefficient(core, cr.delta, cr.frequency)
            points.append(
                SpecialPoint("HB", *at, cr.frequency, l1, criticality(l1), cr.direction, others)
            )
    omega = grid[1:]  # (Ω = 0 bracketed the points; the branch is Ω > 0)
    W = wob_of(omega)
    U = torque_of(omega)
    # From the highest Ω down, the order of their labels: HB1, where the stable branch ends,
    # first (the table, --json and the figure list them alike)
    points.sort(key=lambda s: -s.omega)
    labels = point_labels([(pt.type, pt.omega) for pt in points])
    named = tuple(replace(pt, label=label) for pt, label in zip(points, labels, strict=True))
    return Branch(vary, fixed, omega, W, U, unstable_count(crossings, deltas[1:]), named)


def _omega_grid(floor: float, top: float, samples: int) -> NDArray[np.float64]:
    """Ω = 0, then ``samples`` values in increasing order up to ``top``: half spaced evenly
    (for the figure, drawn on linear axes), half geometrically from ``floor`` (every decade of
    Ω as finely as the next, whatever ``top``: the Hopf and fold points of the laboratory
    string lie at 1.6 ... 6.5 rad/s, and --omega-max 1e5 sampled nothing below 10 rad/s).
    Ω = 0 is there for the bracketing alone (the branch is Ω > 0): δ(0) is finite, and a point
    between 0 and the floor is found too."""
    geometric = samples // 2
    even = np.linspace(top / (samples - geometric), top, samples - geometric)
    low = np.geomspace(min(floor, top), top, geometric + 1)[:-1]  # (top is the even ones')
    return np.sort(np.concatenate([[0.0], low, even]))


def _roots(f, grid: NDArray[np.float64], values: NDArray[np.float64]) -> list[float]:
    """The Ω > 0 where ``f`` vanishes (``values`` = f(grid)), one in each interval of ``grid``
    where it changes sign, refined by Brent's method to ~1e-14 (a sample exactly at a root is
    the root itself, once: it was found in both intervals around it). δ(Ω) is monotonic along
    a branch (W_ob e^{−γΩ/v_f} decreases with Ω at fixed W_ob, and at fixed u too), so f has
    one root at most, and it is bracketed however coarse the grid."""
    exact = {float(w) for w, v in zip(grid, values, strict=True) if v == 0 and w > 0}
    change = np.nonzero(values[:-1] * values[1:] < 0)[0]
    found = [
        brentq(lambda x: float(f(x)), grid[i], grid[i + 1], xtol=1e-14, rtol=4 * _EPS)
        for i in change
    ]
    return sorted(exact.union(float(w) for w in found if w > 0))


_EPS = float(np.finfo(float).eps)
