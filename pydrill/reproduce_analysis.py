"""The paper's Section 4 (Figs. 10, 11, 12) and what it leaves out, recomputed with pydrill.

Every function returns plain JSON-ready data (numbers for the report and the tests, and the
arrays the figures draw). The stability work rests on :func:`pydrill.stability.critical_deltas`
(the string's critical Stribeck slopes δ_k, DESIGN.md §3), :func:`pydrill.bifurcation.branch`
(Hopf and fold points with their first Lyapunov coefficients) and brute-force eigenvalues and
Hurwitz determinants as independent checks.
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from . import _core
from .bifurcation import branch
from .model import Params, preset
from .operating import hopf_curve_wu
from .reproduce_atlases import TORQUE_MAX
from .stability import (
    Crossing,
    boundary_wob,
    characteristic_polynomial,
    critical_deltas,
    eigenvalues,
    hopf_deltas_dof2,
    hurwitz_determinants,
    jacobian,
    stribeck_slope,
    unstable_count,
)

#: Fig. 11's four diagrams: (panel, dof, parameter varied, value held fixed).
FIG11: tuple[tuple[str, int, Literal["wob", "torque"], float], ...] = (
    ("a", 2, "wob", 8.1),
    ("b", 2, "torque", 80.0),
    ("c", 4, "wob", 8.1),
    ("d", 4, "torque", 60.0),
)
#: Dense eigenvalues check every Hopf crossing up to 100 pipes; beyond, the first two only,
#: as they cost O(n'³) a crossing (1 s a call at 500 pipes, and 339 crossings). Everything
#: else is done for every crossing: locating it on the branches and its first Lyapunov
#: coefficient (the core's banded solves take about a millisecond at 500 pipes).


def eigenvalue_check_limit(dof: int) -> int | None:
    """How many crossings of a string of ``dof`` inertias the dense eigenvalues check; None: all."""
    return None if dof <= 103 else 2


def _crossing(c: Crossing) -> dict[str, Any]:
    return {"type": c.type, "delta": c.delta, "frequency": c.frequency, "direction": c.direction}


def _affine_coefficients(params: Params) -> tuple[np.ndarray, np.ndarray]:
    """The characteristic polynomial's coefficients are affine in δ: a(δ) = a0 + δ·a1."""
    c0 = characteristic_polynomial(params, 0.0)
    return c0, characteristic_polynomial(params, 1.0) - c0


def fig10(name: str) -> dict[str, Any]:
    """Fig. 10 (n' = 3): the stability region in (Ω, W_ob) for Eq. (14) or Eq. (53); the curves
    H_1, H_2 where the Hurwitz determinant Δ_2 = a_2 a_1 − a_0 vanishes (as DESIGN.md corrects
    the paper's Eq. 50), and what the paper's printed Δ_2 = a_1 − a_2 − a_0 would give."""
    p = preset(name, dof=2)
    crossings = critical_deltas(p)
    a, b = _affine_coefficients(p)  # ascending: a0, a1, a2, 1
    # Δ_2 = a2·a1 − a0 as a quadratic in δ.
    quad = np.polynomial.Polynomial([a[2], b[2]]) * np.polynomial.Polynomial([a[1], b[1]])
    quad = quad - np.polynomial.Polynomial([a[0], b[0]])
    qroots = np.asarray(quad.roots(), dtype=complex)
    roots = sorted(float(r.real) for r in qroots if abs(r.imag) < 1e-12 and r.real > 0)
    typo = np.asarray(
        np.polynomial.Polynomial([a[1] - a[2] - a[0], b[1] - b[2] - b[0]]).roots(), dtype=float
    )  # a1 − a2 − a0 = 0: linear in δ
    hopf = [c for c in crossings if c.type == "hopf"]
    fold = next(c for c in crossings if c.type == "fold")
    h2 = hopf[0]
    assert h2.frequency is not None  # a Hopf crossing's (None for a fold only)
    row = jacobian(p, 0.0)[0]  # ω̇_r row in twist coordinates (ω_r, θ, ω_b)
    jr, kt, ct, cr = p.inertias[0], p.stiffnesses[0], p.dampings[0], p.top_damping
    return {
        "preset": name,
        "crossings": [_crossing(c) for c in crossings],
        "h2_delta": h2.delta,
        "h2_frequency": h2.frequency,
        "h1_delta": hopf[-1].delta,
        "h1_frequency": hopf[-1].frequency,
        "fold_delta": fold.delta,
        "c_r_plus_c_b": p.top_damping + p.bit_damping,
        "eq51_deltas": hopf_deltas_dof2(p),
        "hurwitz_roots": roots,
        "typo_roots": [float(r.real) for r in typo if r.real > 0],
        "h2_wob": {f"{w:g}": float(boundary_wob(p, h2.delta, w)) for w in (0.0, 1.0, 2.0, 5.0)},
        "lyapunov_h2": _core.first_lyapunov_coefficient(p.to_core(), h2.delta, h2.frequency),
        "eq7_row": row.tolist(),
        "eq7_expected": [-(ct + cr) / jr, -kt / jr, ct / jr],
    }


def fig11_branch(
    params: Params, vary: Literal["wob", "torque"], fixed: float, crossings: list[Crossing]
) -> dict[str, Any]:
    """One bifurcation diagram: the branch of steady states with its HB and LP points."""
    # Up to the Fig. 11 atlases' largest u and no further: the branch's default Ω ≤ 40 rad/s
    # stopped the stable branch short of it (u = 11.6 N·m at W_ob = 80 N), as if no steady
    # drilling lay beyond, and a branch past it stretches the figure's Ω axis. At large Ω,
    # u(Ω) = (c_r + c_b)Ω + W_ob R_b μ_cb + W_ob R_b (μ_sb − μ_cb) e^{−γ_b Ω/v_f}, the last term
    # negligible there (e^{−38} at W_ob = 80 N).
    top = (TORQUE_MAX - fixed * params.bit_radius * params.mu_coulomb) / (
        params.top_damping + params.bit_damping
    )
    if vary == "wob":
        b = branch(params, vary=vary, torque=fixed, crossings=crossings, samples=1500)
    elif top > 0:
        b = branch(params, vary=vary, wob=fixed, omega_max=top, crossings=crossings, samples=1500)
    else:  # every steady state needs more than TORQUE_MAX
        b = branch(params, vary=vary, wob=fixed, crossings=crossings, samples=1500)
    delta = stribeck_slope(params, b.wob, b.omega)
    unstable = unstable_count(crossings, delta)
    x = b.wob if vary == "wob" else b.torque
    points = [pt.to_dict() for pt in b.points]
    hb = [pt for pt in points if pt["type"] == "HB"]
    lp = [pt for pt in points if pt["type"] == "LP"]
    first = [pt for pt in hb if pt["delta"] == crossings[0].delta and crossings[0].type == "hopf"]
    return {
        "dof": params.dof,
        "vary": vary,
        "fixed": fixed,
        "points": points,
        "hopf_points": len(hb),
        "first_hopf": max(first, key=lambda pt: pt["omega"]) if first else None,
        "fold": lp[0] if lp else None,
        "branch": {"omega": b.omega.tolist(), "x": x.tolist(), "unstable": unstable.tolist()},
    }


def fig11(panel: str) -> dict[str, Any]:
    """Fig. 11 (a)–(d): Eq. (14) with n' = 3 (dof 2) or n' = 7 (dof 4)."""
    _, dof, vary, fixed = next(f for f in FIG11 if f[0] == panel)
    p = preset("reduced-scale", dof=dof)
    return {"panel": panel, **fig11_branch(p, vary, fixed, critical_deltas(p))}


def hopf_curves(
    params: Params,
    crossings: list[Crossing],
    torques: tuple[float, ...] = (4.0, 6.0, 8.1, 10.0, 12.0),
) -> dict[str, Any]:
    """Fig. 12: the (W_ob, u) at which a Hopf point can appear — one curve δ(Ω, W_ob) = δ_k per
    crossing, parametrised by Ω — each with its frequency and first Lyapunov coefficient (the
    Jacobian depends on (Ω, W_ob) only through δ, so a whole curve shares one criticality)."""
    core = params.to_core()
    hopf = [c for c in crossings if c.type == "hopf"]
    curves = []
    for c in hopf:
        assert c.frequency is not None  # a Hopf crossing's (None for a fold only)
        l1 = _core.first_lyapunov_coefficient(core, c.delta, c.frequency)
        curves.append({**_crossing(c), "lyapunov": l1})
    first = next((c for c in hopf if c.direction > 0), None)
    at_torque = {}
    if first is not None:
        omega = np.linspace(1e-4, 120.0, 20001)
        w, u = hopf_curve_wu(params, first.delta, omega)
        for t in torques:
            f = u - t
            hits = np.nonzero(np.sign(f[1:]) != np.sign(f[:-1]))[0]
            at_torque[f"{t:g}"] = [
                float(w[i] + f[i] / (f[i] - f[i + 1]) * (w[i + 1] - w[i])) for i in hits
            ]
    fold = next((c for c in crossings if c.type == "fold"), None)
    return {
        "dof": params.dof,
        "curves": curves,
        "fold_delta": fold.delta if fold else None,
        "first_hopf_wob_at_torque": at_torque,
    }


def verify_crossings(params: Params, crossings: list[Crossing], limit: int | None = None) -> dict:
    """Brute-force check of the δ_k: at each, an eigenvalue pair sits on the imaginary axis at
    ±iω_k (or λ = 0 for the fold), and the count of unstable eigenvalues just below and above
    δ_k changes as :func:`~pydrill.stability.unstable_count` predicts."""
    worst_axis, mismatches, checked = 0.0, 0, 0
    for c in crossings[:limit]:
        ev = eigenvalues(params, c.delta)
        target = 1j * (c.frequency or 0.0)
        worst_axis = max(worst_axis, float(np.min(np.abs(ev - target))) / max(1.0, abs(target)))
        for side in (1 - 1e-6, 1 + 1e-6):
            counted = int(np.sum(eigenvalues(params, c.delta * side).real > 0))
            mismatches += counted != int(unstable_count(crossings, c.delta * side))
        checked += 1
    return {"checked": checked, "worst_axis_distance": worst_axis, "count_mismatches": mismatches}


def hurwitz_check(params: Params, crossings: list[Crossing]) -> dict[str, Any]:
    """For n' ≤ 23: the paper's Theorem 5 criterion — the Hurwitz determinant Δ_{n'−1} changes
    sign at every Hopf δ_k; the rest of its Eq. (48), Δ_1 … Δ_{n'−2} > 0 and a_0 > 0, holds only
    at the δ_k where no other eigenvalue is unstable (``theorem5_deltas``) — and its Eq. (55)
    relations a_l − a_{n'−1} a_k = 0 (each quadratic in δ), evaluated at the δ_k and solved for
    δ, with how far the eigenvalues there are from the imaginary axis."""
    a, b = _affine_coefficients(params)
    n = len(a) - 1  # n'

    def coeffs(d):
        return a + d * b

    hopf = [c for c in crossings if c.type == "hopf"]
    sign_changes = 0
    full: list[float] = []
    for c in hopf:
        lo = hurwitz_determinants(coeffs(c.delta * (1 - 1e-7)))[-1]
        hi = hurwitz_determinants(coeffs(c.delta * (1 + 1e-7)))[-1]
        sign_changes += bool(np.sign(lo) != np.sign(hi))
        # The rest of Eq. (48): Δ_1 … Δ_{n'−2} > 0 and a_0 > 0 at δ_k, i.e. every eigenvalue
        # but the pair on the axis stable (Definition 4). Past the first crossing the steady
        # state is already unstable, so Δ_{n'−1} changing sign alone is not Theorem 5.
        at = coeffs(c.delta)
        if at[0] > 0 and bool(np.all(hurwitz_determinants(at)[:-1] > 0)):
            full.append(c.delta)
    relations = []
    P = np.polynomial.Polynomial
    for j in range(1, (n - 1) // 2 + 1):
        ell, k = (n - 1) - 2 * j, n - 2 * j
        rel = P([a[ell], b[ell]]) - P([a[n - 1], b[n - 1]]) * P([a[k], b[k]])
        rroots = np.asarray(rel.roots(), dtype=complex)
        roots = [float(r.real) for r in rroots if abs(r.imag) < 1e-9 and r.real > 0]
        at_hopf = [abs(rel(c.delta)) / max(abs(a[ell]), 1e-300) for c in hopf]
        off_axis = [float(np.min(np.abs(eigenvalues(params, r).real))) for r in roots]
        relations.append(
            {
                "j": j,
                "l": ell,
                "k": k,
                "roots": roots,
                "min_abs_real_at_roots": off_axis,
                "min_relative_residual_at_hopf": float(min(at_hopf)) if at_hopf else None,
            }
        )
    return {
        "n_prime": n,
        "hopf": len(hopf),
        "sign_changes": sign_changes,
        "theorem5_deltas": full,
        "eq55": relations,
    }


def string_summary(params: Params, crossings: list[Crossing]) -> dict[str, Any]:
    """How many crossings a string has, the stability boundary δ_1 and what δ does past it."""
    hopf = [c for c in crossings if c.type == "hopf"]
    frequencies = [c.frequency for c in hopf if c.frequency is not None]  # every Hopf's
    steps = np.cumsum([c.direction * c.multiplicity for c in crossings])
    return {
        "dof": params.dof,
        "pipes": params.pipes,
        "n_prime": 2 * params.dof - 1,
        "hopf": len(hopf),
        "destabilising": sum(c.direction > 0 for c in hopf),
        "folds": len(crossings) - len(hopf),
        "max_unstable": int(steps.max()) if len(steps) else 0,
        "first": _crossing(crossings[0]),
        "delta_range": [hopf[0].delta, hopf[-1].delta] if hopf else None,
        "frequency_range": [min(frequencies), max(frequencies)] if frequencies else None,
        "crossings": [_crossing(c) for c in crossings],
    }


def long_string(pipes: int) -> dict[str, Any]:
    """Beyond the paper: Figs. 11 (c, d) and 12 for a string of ``pipes`` drill pipes, its
    multiple Hopf crossings checked by eigenvalues, and their criticality."""
    p = preset("reduced-scale", pipes=pipes)
    crossings = critical_deltas(p)
    return {
        "pipes": pipes,
        "summary": string_summary(p, crossings),
        "verify": verify_crossings(p, crossings, limit=eigenvalue_check_limit(p.dof)),
        "fig11c": fig11_branch(p, "wob", 8.1, crossings),
        "fig11d": fig11_branch(p, "torque", 60.0, crossings),
        "fig12": hopf_curves(p, crossings),
    }


def paper_strings() -> dict[str, Any]:
    """Figs. 12 (a, b) and the multiple-Hopf analysis of the paper's own strings (dof 2, 4)."""
    out = {}
    for dof in (2, 4):
        p = preset("reduced-scale", dof=dof)
        crossings = critical_deltas(p)
        out[f"dof{dof}"] = {
            "summary": string_summary(p, crossings),
            "verify": verify_crossings(p, crossings),
            "hurwitz": hurwitz_check(p, crossings),
            "fig12": hopf_curves(p, crossings),
        }
    return out
