"""Operating windows: for a string at a depth, the (W_ob, surface rpm) where drilling is safe.

In steady drilling every element, the top drive included, turns at Ω, so surface rpm and Ω are
one axis. At (W_ob, Ω) the steady state needs the torque u = (c_r + c_b)Ω + W_ob R_b μ_b(Ω);
it is *safe* when it is stable (its Stribeck slope below the string's first destabilising δ_k)
and the bit cannot stay stuck (u > T_s = μ_sb W_ob R_b, Section 3): the paper's intersection
of no-Hopf and no-stuck, on the axes a driller sets.

Both edges have closed forms (:class:`Limits`). With g = γ_b/v_f, Δμ = μ_sb − μ_cb,
c = c_r + c_b and δ_c the first destabilising critical slope of the string:

- stick-slip edge (the first Hopf, or the fold where that comes first: a short string's):
  stable iff W_ob R_b g Δμ e^{−gΩ} < δ_c, i.e. W_ob < δ_c e^{gΩ} / (R_b g Δμ), or
  Ω > ln(W_ob R_b g Δμ / δ_c) / g;
- stall edge: u > T_s iff c Ω > W_ob R_b Δμ (1 − e^{−gΩ}), i.e. W_ob < cΩ / (R_b Δμ (1 − e^{−gΩ})),
  or, with s = W_ob R_b Δμ g / c > 1, Ω > (s + W₀(−s e^{−s})) / g (W₀: Lambert's principal branch;
  for s ≤ 1 the bit can never stay stuck).

Only δ_c depends on the string, hence on depth: the stall edge is the same at every depth.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import lambertw

from .model import Params
from .stability import (
    Crossing,
    _check_crossings,
    _checked,
    _crossing_list,
    _params,
    critical_deltas,
    stribeck_slope,
    unstable_count,
)

RPM = 2 * np.pi / 60


@dataclass(frozen=True)
class Window:
    wob: NDArray[np.float64]  #: N, shape (nw,)
    rpm: NDArray[np.float64]  #: surface rpm, shape (nr,)
    stable: NDArray[np.bool_]  #: (nr, nw): the steady state is stable
    unstick: NDArray[np.bool_]  #: (nr, nw): u > T_s, the bit cannot stay stuck
    torque: NDArray[np.float64]  #: (nr, nw): surface torque of the steady state, N·m

    @property
    def safe(self) -> NDArray[np.bool_]:
        return self.stable & self.unstick

    def min_rpm(self) -> NDArray[np.float64]:
        """Least safe surface rpm at each W_ob (NaN where no rpm of the grid is safe)."""
        out = np.full(self.wob.size, np.nan)
        for j in range(self.wob.size):
            ok = np.flatnonzero(self.safe[:, j])
            if ok.size:  # the least, whatever the grid's order (its first was taken)
                out[j] = self.rpm[ok].min()
        return out


def operating_window(
    params: Params, wob: ArrayLike, rpm: ArrayLike, crossings: Iterable[Crossing] | None = None
) -> Window:
    """Classify every (W_ob, rpm) of a grid, point by point (no closed form used): ``wob``
    (N) and ``rpm`` finite numbers > 0, each a number or an array of them."""
    p = _params(params)
    wob = _checked("wob", wob, 0.0, strict=True)
    rpm = _checked("rpm", rpm, 0.0, strict=True)
    crossings = critical_deltas(p) if crossings is None else _check_crossings(p, crossings)
    omega = rpm[:, None] * RPM
    w = wob[None, :]
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(
        -p.stribeck_decay * omega / p.stribeck_velocity
    )
    torque = (p.top_damping + p.bit_damping) * omega + w * p.bit_radius * mu
    stable = unstable_count(crossings, stribeck_slope(p, w, omega)) == 0
    unstick = torque > p.mu_static * w * p.bit_radius
    return Window(wob, rpm, stable, np.broadcast_to(unstick, stable.shape).copy(), torque)


def stable_delta_limit(crossings: Iterable[Crossing]) -> float:
    """δ_c: the least Stribeck slope at which the steady state has an unstable eigenvalue
    (inf if it never has). Below it, every slope is stable (the count starts at 0)."""
    first = _limiting(_crossing_list(crossings))
    return float("inf") if first is None else float(first.delta)


def _limiting(crossings: list[Crossing]) -> Crossing | None:
    """The crossing at δ_c (None if none makes the steady state unstable)."""
    for c in crossings:
        if unstable_count(crossings, c.delta * (1 + 1e-12) + 1e-300) > 0:
            return c
    return None


@dataclass(frozen=True)
class Limits:
    """The closed-form edges of the window of one string (see the module docstring).

    Every ``rpm`` (surface rpm) and ``wob`` (N) its methods take is a finite number >= 0, or
    an array of them (0 is the limit of the edge there)."""

    params: Params
    delta_limit: float  #: δ_c, N·m·s/rad
    #: what happens at δ_c: "hopf" (an oscillation is born) or "fold" (a real eigenvalue: a
    #: short string's, whose first Hopf comes later); None if unknown or if δ_c is inf
    limit_type: str | None = None

    @classmethod
    def of(cls, params: Params, crossings: Iterable[Crossing] | None = None) -> Limits:
        params = _params(params)
        if crossings is None:
            crossings = critical_deltas(params)
        else:
            crossings = _check_crossings(params, crossings)
        first = _limiting(_crossing_list(crossings))
        if first is None:
            return cls(params, float("inf"))
        return cls(params, float(first.delta), first.type)

    @property
    def _g(self) -> float:
        return self.params.stribeck_decay / self.params.stribeck_velocity

    @property
    def _a(self) -> float:  # W_ob R_b Δμ per newton of W_ob
        p = self.params
        return p.bit_radius * (p.mu_static - p.mu_coulomb)

    def wob_max_stable(self, rpm: ArrayLike) -> NDArray[np.float64]:
        """Heaviest W_ob (N) at which steady drilling at ``rpm`` is stable (stick-slip edge)."""
        omega = _checked("rpm", rpm, 0.0, strict=False) * RPM
        with np.errstate(over="ignore"):  # inf: fast enough, no weight makes it unstable
            return self.delta_limit * np.exp(self._g * omega) / (self._a * self._g)

    def wob_max_unstuck(self, rpm: ArrayLike) -> NDArray[np.float64]:
        """Heaviest W_ob (N) at which the steady torque at ``rpm`` exceeds the static friction
        (stall edge); independent of the string."""
        omega = _checked("rpm", rpm, 0.0, strict=False) * RPM
        c = self.params.top_damping + self.params.bit_damping
        with np.errstate(divide="ignore", invalid="ignore"):
            out = c * omega / (self._a * -np.expm1(-self._g * omega))
        return np.where(omega > 0, out, c / (self._a * self._g))

    def wob_max(self, rpm: ArrayLike) -> NDArray[np.float64]:
        """Heaviest safe W_ob (N) at ``rpm``: every lighter W_ob is safe there too."""
        return np.minimum(self.wob_max_stable(rpm), self.wob_max_unstuck(rpm))

    def rpm_min_stable(self, wob: ArrayLike) -> NDArray[np.float64]:
        """Slowest surface rpm at which steady drilling with ``wob`` (N) is stable."""
        w = _checked("wob", wob, 0.0, strict=False)
        with np.errstate(divide="ignore"):
            omega = np.log(w * self._a * self._g / self.delta_limit) / self._g
        return np.maximum(omega, 0.0) / RPM

    def rpm_min_unstuck(self, wob: ArrayLike) -> NDArray[np.float64]:
        """Slowest surface rpm at which the bit cannot stay stuck under ``wob`` (N)."""
        w = _checked("wob", wob, 0.0, strict=False)
        c = self.params.top_damping + self.params.bit_damping
        if c == 0:  # no damping at the ends: the steady torque never reaches T_s (nan before)
            return np.where(w > 0, np.inf, 0.0)
        s = np.asarray(w * self._a * self._g / c, dtype=float)
        x = np.zeros_like(s)
        big = s > 1
        x[big] = s[big] + lambertw(-s[big] * np.exp(-s[big])).real
        return x / self._g / RPM

    def rpm_min(self, wob: ArrayLike) -> NDArray[np.float64]:
        """Slowest safe surface rpm with ``wob`` (N): every faster rpm is safe too."""
        return np.maximum(self.rpm_min_stable(wob), self.rpm_min_unstuck(wob))

    def torque(self, wob: ArrayLike, rpm: ArrayLike) -> NDArray[np.float64]:
        """Surface torque of steady drilling (N·m)."""
        p = self.params
        w = _checked("wob", wob, 0.0, strict=False)
        omega = _checked("rpm", rpm, 0.0, strict=False) * RPM
        mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-self._g * omega)
        return (p.top_damping + p.bit_damping) * omega + w * p.bit_radius * mu


@dataclass(frozen=True)
class DepthWindow:
    """How the window changes with depth, at reference speeds and weights."""

    name: str
    depth: NDArray[np.float64]  #: m, shape (nd,)
    dof: NDArray[np.int64]  #: inertias of each string
    delta_limit: NDArray[np.float64]  #: δ_c per depth, N·m·s/rad
    rpm: NDArray[np.float64]  #: reference speeds, shape (nr,)
    wob_max: NDArray[np.float64]  #: (nd, nr) heaviest safe W_ob, N
    wob_max_stable: NDArray[np.float64]  #: (nd, nr) the stick-slip edge alone, N
    wob_max_unstuck: NDArray[np.float64]  #: (nr,) the stall edge (the same at every depth), N
    wob: NDArray[np.float64]  #: reference weights, shape (nw,)
    rpm_min: NDArray[np.float64]  #: (nd, nw) slowest safe rpm
    rpm_min_stable: NDArray[np.float64]  #: (nd, nw) the stick-slip edge alone
    rpm_min_unstuck: NDArray[np.float64]  #: (nw,) the stall edge
    #: m, the string built for each depth: of whole joints, so up to one joint longer
    length: NDArray[np.float64]


def window_against_depth(
    tally, depths: ArrayLike, rpm: ArrayLike, wob: ArrayLike, lump: int = 1
) -> DepthWindow:
    """The window's edges for the string of ``tally`` at each depth (m), one element per joint
    (or per ``lump`` drill-pipe joints). ``rpm`` and ``wob`` (N): finite numbers > 0, each a
    number or an array of them."""
    depths = _checked("depths", depths, 0.0, strict=True)
    rpm = _checked("rpm", rpm, 0.0, strict=True)
    wob = _checked("wob", wob, 0.0, strict=True)
    if depths.ndim != 1 or depths.size == 0:
        raise ValueError("depths must be a non-empty list of finite depths > 0 (m)")
    rows, lengths = [], []
    for d in depths:
        string = tally.at_depth(float(d))
        p = string.to_params(lump=lump)
        rows.append((p.dof, Limits.of(p)))
        lengths.append(string.length)
    lims = [lim for _, lim in rows]
    return DepthWindow(
        name=tally.name,
        depth=depths,
        dof=np.array([dof for dof, _ in rows]),
        delta_limit=np.array([lim.delta_limit for lim in lims]),
        rpm=rpm,
        wob_max=np.array([lim.wob_max(rpm) for lim in lims]),
        wob_max_stable=np.array([lim.wob_max_stable(rpm) for lim in lims]),
        wob_max_unstuck=lims[0].wob_max_unstuck(rpm),
        wob=wob,
        rpm_min=np.array([lim.rpm_min(wob) for lim in lims]),
        rpm_min_stable=np.array([lim.rpm_min_stable(wob) for lim in lims]),
        rpm_min_unstuck=lims[0].rpm_min_unstuck(wob),
        length=np.array(lengths),
    )


def longer(depth: float, length: float) -> bool:
    """Whether the string built for ``depth`` (``length`` m, whole joints) is longer than it
    by more than rounding: then the output says both ("4000 m (string 4000.8 m)")."""
    return length - depth > 1e-6 * max(1.0, depth)


def parse_depths(text: str) -> list[float]:
    """``"3000m"``, ``"500m,1000m,3000m"`` or a range ``"500m:5000m:10"`` (start:stop:count,
    both ends included) into depths in m; a bare number is in m."""
    from . import units

    out: list[float] = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            continue
        if ":" in part:
            bits = part.split(":")
            if len(bits) != 3:
                raise ValueError(
                    f"depth range {part!r}: write start:stop:count, e.g. 500m:5000m:10"
                )
            try:
                count = int(bits[2])
            except ValueError:
                raise ValueError(
                    f"depth range {part!r}: count {bits[2]!r} is not an integer"
                ) from None
            if not 2 <= count <= 500:
                raise ValueError(f"depth range {part!r}: count must be 2 ... 500")
            a, b = units.parse(bits[0], "length"), units.parse(bits[1], "length")
            out.extend(np.linspace(a, b, count).tolist())
        else:
            out.append(units.parse(part, "length"))
    if not out:
        raise ValueError("--depth: no depth given")
    bad = [d for d in out if not d > 0]
    if bad:
        raise ValueError(f"--depth: depths must be > 0 m, got {bad[0]:g}")
    # A depth twice ("1000m,1000m", or a range from a depth to itself) printed its rows twice
    # and drew the chart against depth over a span of 0 m: empty, with matplotlib's warning.
    twice = next((d for n, d in enumerate(out) if d in out[:n]), None)
    if twice is not None:
        raise ValueError(f"--depth: {twice:g} m is given more than once; give each depth once")
    return out
