"""Stability of steady drilling for any string length (DESIGN.md §3).

The Jacobian of the steady state depends on (Ω, W_ob) only through the Stribeck slope
δ = W_ob R_b (γ_b/v_f)(μ_sb − μ_cb) exp(−γ_b Ω/v_f). The critical values δ_k at which eigenvalues
reach the imaginary axis are computed once per string (:func:`critical_deltas`); every stability
boundary is then ``W_ob = δ_k exp(γ_b Ω/v_f) / (R_b (γ_b/v_f)(μ_sb − μ_cb))``, and the verdict
at any point is a lookup.
"""

from __future__ import annotations

import math
import numbers
import reprlib
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from .model import MAX_LOAD, Params, _load, _number, _plain, _show
from .stability_checks import _check_grid_memory, _checked, _finite


def _velocity(omega: float) -> float:
    """A steady velocity Ω (rad/s): a finite number, not 0; < 0 turns the string backwards."""
    omega = _number("omega", omega, "rad/s")
    if not math.isfinite(omega) or omega == 0:
        raise ValueError(
            f"omega = {omega:g} is not allowed: steady drilling needs a finite omega != 0 rad/s "
            "(< 0 turns the string backwards)"
        )
    return omega


def _params(params: Params) -> Params:
    """``params`` if it is a :class:`Params`, else a ``TypeError`` naming it (as
    :func:`pydrill.simulate` does)."""
    if isinstance(params, Params):
        return params
    from .simulate import _type_name

    hint = (
        f" (for a preset by name, write pydrill.preset({params!r}))"
        if isinstance(params, str)
        else ""
    )
    raise TypeError(
        "params must be a pydrill.Params (from pydrill.preset or Params(...)), got "
        f"{_type_name(params)}{hint}"
    )


def criticality(l1: float | None) -> str | None:
    """A Hopf point's criticality from its first Lyapunov coefficient: "subcritical" (l₁ > 0:
    past it the motion jumps to a large oscillation or stick-slip, with hysteresis) or
    "supercritical" (l₁ < 0: a small stable oscillation is born); "degenerate" when l₁ = 0
    (the first coefficient decides nothing there); None without one."""
    if l1 is None:
        return None
    l1 = _plain(l1)  # a numpy number or 0-d array, as every other input takes it
    if isinstance(l1, bool) or not isinstance(l1, numbers.Real):
        raise TypeError(f"l1 = {l1!r} is not allowed: a number (or None)")
    # (an int is finite, and math.isfinite of one beyond a float raised OverflowError)
    if not isinstance(l1, numbers.Integral) and not math.isfinite(l1):
        raise ValueError(f"l1 = {l1!r} is not allowed: must be a finite number (or None)")
    if l1 == 0:
        return "degenerate"
    return "supercritical" if l1 < 0 else "subcritical"


@dataclass(frozen=True)
class Crossing:
    """A value of δ at which eigenvalues of the steady state reach the imaginary axis."""

    type: str  #: "hopf" (a pair ±iω: oscillations are born) or "fold" (λ = 0)
    delta: float  #: N·m·s/rad
    frequency: float | None  #: rad/s of the Hopf pair; None for a fold
    direction: int  #: +1 if the eigenvalues enter the right half-plane as δ grows
    multiplicity: int  #: 2 for Hopf, 1 for fold

    def wob(self, params: Params, omega: ArrayLike) -> NDArray[np.float64]:
        """The boundary W_ob(Ω) on which this crossing happens (N)."""
        return boundary_wob(params, self.delta, omega)

    def criticality(self, params: Params) -> str | None:
        """ "subcritical" or "supercritical" (the sign of :meth:`lyapunov`), "degenerate" where
        it is 0 (every Hopf point of a string with no damping at all); None for a fold. A
        pair that is no Hopf point of ``params`` is refused, as :meth:`lyapunov` says."""
        return criticality(self.lyapunov(params))

    def lyapunov(self, params: Params) -> float | None:
        """The first Lyapunov coefficient l₁ of this Hopf crossing (None for a fold), from the
        normal form on the reduced Jacobian (banded solves, O(dof)): l₁ > 0 subcritical (past
        it the bit jumps to stick-slip; before it the two coexist), l₁ < 0 supercritical (a
        small stable oscillation is born).

        The crossing must be a Hopf point of ``params``: i·frequency an eigenvalue at ``delta``.
        A pair whose i·frequency lies more than 1 % of the frequency from every eigenvalue at
        ``delta`` (a crossing made by hand, or another string's) is refused with
        ``ValueError`` naming both, since its coefficient would belong to no Hopf point. Every
        crossing of :func:`critical_deltas` passes, as does one typed to six digits."""
        core = _params(params).to_core()
        if self.type != "hopf" or self.frequency is None:
            return None
        l1 = _core.first_lyapunov_coefficient(core, self.delta, self.frequency)
        if not math.isfinite(l1):  # (the core's answer was NaN, a Crossing made by hand)
            raise ValueError(
                f"this crossing (delta = {self.delta:g}, frequency = {self.frequency:g} rad/s) "
                "has no finite first Lyapunov coefficient: its normal form overflows a float; "
                "give one of critical_deltas(params)"
            )
        return l1


@dataclass(frozen=True)
class StabilityPoint:
    """The steady state at velocity Ω and its linear stability."""

    omega: float  #: rad/s
    wob: float  #: N
    torque: float  #: N·m needed to hold Ω
    delta: float  #: Stribeck slope at (Ω, W_ob), N·m·s/rad
    unstable: int  #: eigenvalues in the right half-plane
    stable: bool  #: no eigenvalue in the right half-plane (``unstable == 0``)
    delta_margin: float  #: distance in δ to the nearest crossing (negative when unstable)
    spectral_abscissa: float  #: largest real part of the eigenvalues, 1/s
    eigenvalues: tuple[complex, ...]  #: sorted by decreasing real part

    def __repr__(self) -> str:
        # One line: the dataclass's own listed every eigenvalue (27119 characters at dof 300).
        shown = ", ".join(f"{z:.4g}" for z in self.eigenvalues[:4])
        more = len(self.eigenvalues) - 4
        return (
            f"<StabilityPoint omega={self.omega:.4g} rad/s wob={self.wob:g} N torque="
            f"{self.torque:.4g} N·m: {'stable' if self.stable else 'unstable'} ({self.unstable} "
            f"unstable), delta {self.delta:.4g}, margin {self.delta_margin:.4g} N·m·s/rad; "
            f"eigenvalues {shown}{f' … ({more} more)' if more > 0 else ''}>"
        )

    def to_dict(self, n_eigenvalues: int | None = 6) -> dict:
        """Plain JSON-ready data (``pydrill stability --json``), eigenvalues as ``[re, im]``
        pairs: the leading ``n_eigenvalues`` of them (an integer >= 0), or all with ``None``;
        ``eigenvalue_count`` says how many there are in all (2 dof - 1)."""
        ev = self.eigenvalues
        if n_eigenvalues is not None:
            n = _plain(n_eigenvalues)
            if isinstance(n, bool) or not isinstance(n, int):
                raise TypeError(
                    f"n_eigenvalues must be an integer >= 0 (or None for all), got "
                    f"{_show(n_eigenvalues)}"
                )
            if n < 0:
                raise ValueError(
                    f"n_eigenvalues = {n} is not allowed: need an integer >= 0 (or None for all)"
                )
            ev = ev[:n]
        return {
            "omega": self.omega,
            "wob": self.wob,
            "torque": self.torque,
            "delta": self.delta,
            "stable": self.stable,
            "unstable_eigenvalues": self.unstable,
            "delta_margin": self.delta_margin,
            "spectral_abscissa": self.spectral_abscissa,
            "eigenvalue_count": len(self.eigenvalues),
            "eigenvalues": [[z.real, z.imag] for z in ev],
        }


def stribeck_slope(params: Params, wob: ArrayLike, omega: ArrayLike) -> NDArray[np.float64]:
    """δ(Ω, W_ob) = −dT_fb/dω at Ω (N·m·s/rad); broadcasts over arrays. Every W_ob must be
    finite and > 0 (N), every Ω finite and >= 0 (rad/s)."""
    p = _params(params)
    wob = _checked("wob", wob, 0.0, strict=True)
    omega = _checked("omega", omega, 0.0, strict=False)
    factor = p.bit_radius * p.stribeck_decay / p.stribeck_velocity * (p.mu_static - p.mu_coulomb)
    return wob * factor * np.exp(-p.stribeck_decay * omega / p.stribeck_velocity)


def boundary_wob(params: Params, delta: float, omega: ArrayLike) -> NDArray[np.float64]:
    """W_ob at which δ(Ω, W_ob) = delta (N); broadcasts over Ω. ``delta`` must be finite and
    >= 0 (a crossing's, :func:`critical_deltas`), every Ω finite and >= 0 (rad/s). A crossing
    at δ = 0 (a string without damping at an end) has its boundary on the Ω axis: W_ob = 0."""
    p = _params(params)
    slope = _checked("delta", delta, 0.0, strict=False)
    omega = _checked("omega", omega, 0.0, strict=False)
    factor = p.bit_radius * p.stribeck_decay / p.stribeck_velocity * (p.mu_static - p.mu_coulomb)
    with np.errstate(over="ignore"):  # refused below, by name: inf was returned, with a warning
        wob = slope * np.exp(p.stribeck_decay * omega / p.stribeck_velocity) / factor
    if not np.all(np.isfinite(wob)):
        k = np.unravel_index(int(np.argmin(np.isfinite(wob))), wob.shape)
        d, w = (float(np.broadcast_to(a, wob.shape)[k]) for a in (slope, omega))
        raise ValueError(
            f"omega = {w:g} rad/s is not allowed with delta = {d:g}: the boundary W_ob there "
            "(growing as exp(stribeck_decay omega / stribeck_velocity)) is beyond the range "
            "of a float"
        )
    return wob


def critical_deltas(params: Params) -> list[Crossing]:
    """Every δ >= 0 at which the steady state changes stability, in increasing order.

    With c_r = c_b = 0 the fold is at δ = 0 (the string turns freely as one body), and on a
    string with no damping at all every Hopf point is there too: each of its modes grows at any
    slope δ > 0 (those Hopf points are degenerate, l₁ = 0: at δ = 0 the friction is flat).

    >>> from pydrill import preset
    >>> [c.type for c in critical_deltas(preset("reduced-scale", dof=2))]
    ['hopf', 'fold', 'hopf']
    """
    return [Crossing(**c) for c in _core.critical_deltas(_params(params).to_core())]


def unstable_count(crossings: Iterable[Crossing], delta: ArrayLike) -> NDArray[np.int64]:
    """Eigenvalues in the right half-plane at slope(s) δ (finite, >= 0), from the crossings
    alone: a string's :func:`critical_deltas`, in increasing order (a list, or any iterable
    of them)."""
    crossings = _crossing_list(crossings)
    deltas = np.array([c.delta for c in crossings], dtype=float)
    # (NaN compares false both ways: the order check alone let a NaN delta through.)
    if not np.all(np.isfinite(deltas)) or np.any(np.diff(deltas) < 0):
        raise ValueError(
            "crossings are not finite deltas in increasing order: give critical_deltas(params)"
        )
    delta = _checked("delta", delta, 0.0, strict=False)
    steps = np.array([c.direction * c.multiplicity for c in crossings], dtype=np.int64)
    cumulative = np.concatenate([[0], np.cumsum(steps)])
    return cumulative[np.searchsorted(deltas, delta, side="left")]


def _crossing_list(crossings: Iterable[Crossing]) -> list[Crossing]:
    """``crossings`` as a list (read once: an iterator is not used up by the check), every
    entry a :class:`Crossing`; else a ``TypeError`` naming them."""
    given = crossings
    try:
        if isinstance(given, (str, bytes, dict)):
            raise TypeError
        crossings = list(given)
        if not all(isinstance(c, Crossing) for c in crossings):
            raise TypeError
    except TypeError:
        raise TypeError(
            f"crossings = {reprlib.repr(given)} is not allowed: a list of Crossing, as "
            "critical_deltas(params) gives"
        ) from None
    return crossings


def _check_crossings(params: Params, crossings: Iterable[Crossing]) -> list[Crossing]:
    """``crossings`` as a list, refused when they cannot be the string's: every string has
    its one fold at δ = c_r + c_b (DESIGN.md §3; at 0 without damping at the ends). Crossings
    carry nothing else to compare: those of another string with the same damping pass."""
    crossings = _crossing_list(crossings)
    fold = params.top_damping + params.bit_damping
    folds = [c.delta for c in crossings if c.type == "fold"]
    if len(folds) != 1 or not math.isclose(folds[0], fold, rel_tol=1e-9):
        had = (
            "no fold"
            if not folds
            else f"a fold at delta = {folds[0]:g}"
            if len(folds) == 1
            else f"{len(folds)} folds"
        )
        want = f"one at c_r + c_b = {fold:g}"
        raise ValueError(
            f"crossings are not this string's ({had}; its own have {want}): give "
            "critical_deltas(params) of the same params"
        )
    return crossings


def eigenvalues(params: Params, delta: float) -> NDArray[np.complex128]:
    """Eigenvalues of the reduced Jacobian at slope δ, largest real part first (brute force,
    O(dof³)). LAPACK's dense solver (numpy's), not the core's: a check that shares no code
    with the core's eigenvalues, and 3.5× faster at 500 pipes. ``delta`` a finite number
    (N·m·s/rad)."""
    # Complex always: numpy gives a real array when every eigenvalue is real (an overdamped
    # string), against the annotation and the dtype a caller expects.
    ev = np.linalg.eigvals(jacobian(params, delta)).astype(np.complex128)
    return ev[np.lexsort((-ev.imag, -ev.real))]


def jacobian(params: Params, delta: float) -> NDArray[np.float64]:
    """The reduced Jacobian (twist coordinates, n' = 2·dof − 1) at slope δ (a finite number,
    N·m·s/rad)."""
    params = _params(params)
    delta = _number("delta", delta, "N·m·s/rad")
    n = 2 * params.dof - 1
    return _finite("delta", delta, "Jacobian", _core.jacobian(params.to_core(), delta)).reshape(
        n, n
    )


def characteristic_polynomial(params: Params, delta: float) -> NDArray[np.float64]:
    """det(λI − J) at slope δ (a finite number, N·m·s/rad), monic, coefficients in ascending
    powers (dof ≤ 12)."""
    core = _params(params).to_core()
    delta = _number("delta", delta, "N·m·s/rad")
    return _finite(
        "delta", delta, "characteristic polynomial", _core.characteristic_polynomial(core, delta)
    )


def hurwitz_determinants(ascending: ArrayLike) -> NDArray[np.float64]:
    """Hurwitz determinants Δ_1 … Δ_{n−1} of a polynomial in ascending powers: ``ascending``
    a 1-D list of finite numbers, degree >= 1."""
    if isinstance(ascending, (str, bytes, dict)):
        raise TypeError(f"ascending must be a 1-D list of numbers, got {_show(ascending)}")
    # As objects: each entry is checked as it was given (a string stays a string).
    a = ascending if isinstance(ascending, np.ndarray) else np.asarray(ascending, dtype=object)
    if a.ndim != 1:
        raise ValueError(f"ascending has shape {a.shape}: must be a 1-D list of numbers")
    coefficients = [_number(f"ascending[{i}]", v, "a coefficient") for i, v in enumerate(a)]
    return _finite(
        "ascending", coefficients, "Hurwitz determinants", _core.hurwitz_determinants(coefficients)
    )


def hopf_deltas_dof2(params: Params) -> list[float]:
    """The paper's closed form (Eq. 51, n' = 3): δ where Δ_2 = a_2 a_1 − a_0 = 0 inside H_+
    (a_1 > 0, a_0 > 0: below the fold δ = c_r + c_b), 0, 1 or 2 values. A Hopf point above
    the fold is not among them; :func:`critical_deltas` finds every crossing."""
    return list(_core.hopf_deltas_dof2(_params(params).to_core()))


def stability(
    params: Params,
    wob: float,
    *,
    omega: float | None = None,
    torque: float | None = None,
    crossings: Iterable[Crossing] | None = None,
) -> list[StabilityPoint]:
    """Stability of the steady state at velocity ``omega``, or of every steady state that the
    surface ``torque`` can hold (0, 1 or 2 of them) at weight on bit ``wob``.

    ``crossings``: the string's ``critical_deltas(params)``, if already at hand. They depend
    on the string alone, and on a short one cost more than the rest: a loop over many
    (W_ob, u) of one string computes them once. They must be *this* string's: the counts
    of unstable eigenvalues and ``delta_margin`` come from them. They carry nothing that
    names their string; those without this string's fold (δ = c_r + c_b), ``[]`` among
    them, are refused, but those of another string of the same damping (another ``dof``)
    would pass and answer for it.

    ``wob`` (N) must be finite and > 0, ``omega`` (rad/s) finite and non-zero, ``torque``
    (N·m) finite; ``wob`` and ``torque`` (or the torque ``omega`` needs) at most ``MAX_LOAD``
    (1e15) in size, as in :func:`pydrill.simulate`. A negative ``torque`` or ``omega`` turns
    the string backwards: the mirror image (φ → −φ) of ``-torque`` or ``-omega``, the same
    steady states with Ω and u reversed and the same eigenvalues; the points come in
    increasing Ω either way."""
    params = _params(params)
    if (omega is None) == (torque is None):
        raise ValueError("give exactly one of omega (rad/s) or torque (N·m)")
    wob = _load("wob", _number("wob", wob, "N"), "N")
    if crossings is not None:
        crossings = _check_crossings(params, crossings)
    core = params._core_params()
    if omega is not None:
        omega = _velocity(omega)
        held = abs(_core.equilibrium_torque(core, wob, abs(omega)))
        if held > MAX_LOAD:  # answered "Omega = 1e+300 rad/s, u = 1.9e+299 N m"
            raise ValueError(
                f"omega = {omega:g} is not allowed at wob = {wob:g} N: its steady state needs a "
                f"torque of {held:.3g} N·m, beyond MAX_LOAD (1e15)"
            )
        if omega < 0:  # the core takes Ω > 0: the mirror image of |Ω|, reversed back
            pt = _core.stability_at_velocity(core, wob, -omega)
            points = [{**pt, "omega": -pt["omega"], "torque": -pt["torque"]}]
        else:
            points = [_core.stability_at_velocity(core, wob, omega)]
    elif crossings is not None:
        torque = _load("torque", _number("torque", torque, "N·m"), "N·m")
        known = [vars(c) for c in crossings]  # their fields, as the core takes them
        points = _core.stability_at_torque(core, wob, torque, known)
    else:
        torque = _load("torque", _number("torque", torque, "N·m"), "N·m")
        points = _core.stability_at_torque(core, wob, torque)
    return [
        StabilityPoint(
            **{k: v for k, v in pt.items() if k != "eigenvalues"},
            eigenvalues=tuple(complex(z) for z in pt["eigenvalues"]),
        )
        for pt in points
    ]


def stability_map(
    params: Params, omega: ArrayLike, wob: ArrayLike, crossings: Iterable[Crossing] | None = None
) -> NDArray[np.int64]:
    """Unstable-eigenvalue counts on the grid ``omega`` × ``wob`` (shape (len(wob), len(omega)))
    — one lookup per point, whatever the string's length. ``omega`` (rad/s, finite, >= 0) and
    ``wob`` (N, finite, > 0) are 1-D, or numbers (an axis of one value); ``crossings``, if
    given, this string's ``critical_deltas(params)`` (see :func:`stability`). A grid that would
    not fit in the memory available (about 32 bytes a point) is refused before it is made."""
    params = _params(params)
    axes = []
    for name, values, strict in (("omega", omega, False), ("wob", wob, True)):
        a = _checked(name, values, 0.0, strict=strict)
        if a.ndim > 1:
            raise ValueError(
                f"{name} has shape {a.shape}: must be 1-D (the grid's axis) or a number"
            )
        axes.append(np.atleast_1d(a))
    omega, wob = axes
    _check_grid_memory(omega.size, wob.size)
    if crossings is None:
        crossings = critical_deltas(params)
    else:
        crossings = _check_crossings(params, crossings)
    delta = stribeck_slope(params, wob[:, None], omega[None, :])
    return unstable_count(crossings, delta)
