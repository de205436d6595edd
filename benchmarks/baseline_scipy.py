#!/usr/bin/env python3
"""Pure-Python/scipy baseline of pydrill's exact event-driven stick-slip simulation.

This is the reference that the C++/SUNDIALS core is benchmarked (and checked) against: the
same model as DESIGN.md section 2, integrated with ``scipy.integrate.solve_ivp`` and terminal
events, written to be as fast as plain Python + numpy reasonably allow:

* twist coordinates ``y = (w_0, th_0, w_1, th_1, ..., th_{N-2}, w_{N-1})`` (length 2N-1);
* the right-hand side is ``A_mode @ y + b`` plus one scalar friction term (one BLAS call) for
  up to 150 states, and a sliced, loop-free numpy expression above that;
* analytic Jacobian, banded (``lband = uband = 2``) for LSODA, dense or sparse (CSC) for
  Radau/BDF;
* the mode (slip+, slip-, stick) is fixed inside one ``solve_ivp`` call, so the right-hand side
  is pure and smooth; every mode switch is a terminal event after which ``solve_ivp`` is
  restarted from the event state.

Friction in slip mode ``s = +1/-1`` is ``T_fb = s R_b W_ob (mu_cb + (mu_sb - mu_cb)
exp(-gamma_b s w_b / v_f))`` -- identical to ``R_b W_ob mu_b(w_b) sgn(w_b)`` while ``s w_b >= 0``
and a smooth (analytic) continuation just past the zero crossing, so the integrator never
steps over a kink before the event is located.

Usage::

    python benchmarks/baseline_scipy.py --dof 4 --wob 100 --torque 8.3 --t-end 100
"""

from __future__ import annotations

import argparse
import collections
import math
import time

import numpy as np
import scipy.sparse as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["DEFAULT_METHOD", "equilibrium_velocity", "reduced_scale", "simulate_baseline"]

# Fastest accurate method measured on this machine (see the benchmark notes in the report /
# ``--compare``): explicit DOP853 for every string length.  The chain is not stiff (its highest
# natural frequency is ~2 sqrt(k/J) = 3.4 rad/s whatever the number of pipes), so implicit
# methods only pay for linear algebra.
DEFAULT_METHOD = "DOP853"

# Above this many states the sliced RHS beats the dense matrix-vector product (measured:
# 2-3 us vs ~5 us per call for small strings, crossover near 150 states).
_DENSE_MAX_STATES = 150
# Above this many states Radau/BDF get a sparse (CSC, splu) Jacobian instead of a dense one.
_DENSE_JAC_MAX_STATES = 60

SLIP_POS, SLIP_NEG, STICK = "slip+", "slip-", "stick"
_SIGN = {SLIP_POS: 1.0, SLIP_NEG: -1.0}


# --------------------------------------------------------------------------------------------
# parameters
# --------------------------------------------------------------------------------------------
def reduced_scale(dof: int) -> dict:
    """Reduced-scale (laboratory) preset of DESIGN.md section 4 for ``dof`` inertias.

    Returns a dict that can be splatted into :func:`simulate_baseline`.
    """
    dof = int(dof)
    if dof < 2:
        raise ValueError("dof must be >= 2")
    J_r, J_b, J = 0.518, 0.0318, 0.025
    J_l = J_b
    if dof == 2:
        inertias = [J_r, J_b]
    elif dof == 3:
        inertias = [J_r, J_l, J_b]
    else:
        inertias = [J_r] + [J] * (dof - 3) + [J_l, J_b]
    return dict(
        inertias=np.array(inertias, dtype=float),
        stiffnesses=np.full(dof - 1, 0.073),
        dampings=np.full(dof - 1, 1e-4),
        c_r=0.18,
        c_b=0.01,
        mu_cb=0.5,
        mu_sb=0.8,
        R_b=0.1,
        gamma_b=0.9,
        v_f=1.0,
    )


def equilibrium_velocity(*, torque, wob, c_r, c_b, mu_cb, mu_sb, R_b, gamma_b, v_f, **_):
    """Largest Omega > 0 with ``u = (c_r + c_b) Omega + R_b W_ob mu_b(Omega)``, or None."""
    c = c_r + c_b
    if c <= 0:
        return None
    a = R_b * wob * (mu_sb - mu_cb)  # amplitude of the Stribeck term

    def f(om):
        return c * om + R_b * wob * mu_cb + a * math.exp(-gamma_b * om / v_f) - torque

    # f is convex; its minimum is at om_min (0 if f is increasing on [0, inf)).
    arg = a * gamma_b / (v_f * c)
    om_min = (v_f / gamma_b) * math.log(arg) if arg > 1.0 else 0.0
    if f(om_min) > 0.0:
        return None
    hi = max(om_min, (torque - R_b * wob * mu_cb) / c) + 1.0
    while f(hi) <= 0.0:
        hi *= 2.0
    if f(om_min) == 0.0:
        return om_min if om_min > 0 else None
    om = brentq(f, om_min, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=500)
    return om if om > 0 else None


# --------------------------------------------------------------------------------------------
# model assembly
# --------------------------------------------------------------------------------------------
class _Model:
    """Matrices, right-hand sides, Jacobians and event functions for one parameter set."""

    def __init__(
        self,
        inertias,
        stiffnesses,
        dampings,
        c_r,
        c_b,
        mu_cb,
        mu_sb,
        R_b,
        gamma_b,
        v_f,
        wob,
        torque,
    ):
        I = np.asarray(inertias, dtype=float).ravel()
        k = np.asarray(stiffnesses, dtype=float).ravel()
        c = np.asarray(dampings, dtype=float).ravel()
        N = I.size
        if N < 2:
            raise ValueError("need at least 2 inertias")
        if k.size != N - 1 or c.size != N - 1:
            raise ValueError("stiffnesses and dampings need len(inertias) - 1 entries")
        if np.any(I <= 0):
            raise ValueError("inertias must be positive")
        if wob < 0:
            raise ValueError("wob must be >= 0")
        self.N, self.n = N, 2 * N - 1
        self.I, self.k, self.c = I, k, c
        self.c_r, self.c_b = float(c_r), float(c_b)
        self.mu_cb, self.mu_sb = float(mu_cb), float(mu_sb)
        self.R_b, self.gamma_b, self.v_f = float(R_b), float(gamma_b), float(v_f)
        self.wob, self.u = float(wob), float(torque)
        self.T_s = self.mu_sb * self.wob * self.R_b
        self.k_last, self.c_last = float(k[-1]), float(c[-1])

        n = self.n
        A = np.zeros((n, n))
        for i in range(N):
            r = 2 * i
            diag = 0.0
            if i > 0:
                A[r, r - 2] = c[i - 1] / I[i]
                A[r, r - 1] = k[i - 1] / I[i]
                diag += c[i - 1]
            if i < N - 1:
                A[r, r + 2] = c[i] / I[i]
                A[r, r + 1] = -k[i] / I[i]
                diag += c[i]
            if i == 0:
                diag += self.c_r
            if i == N - 1:
                diag += self.c_b
            A[r, r] = -diag / I[i]
        for j in range(N - 1):
            A[2 * j + 1, 2 * j] = 1.0
            A[2 * j + 1, 2 * j + 2] = -1.0
        self.A_slip = A
        self.A_stick = A.copy()
        self.A_stick[-1, :] = 0.0
        self.lband = self.uband = 2

    # ---- small helpers ----------------------------------------------------------------
    def reaction_torque(self, y):
        """T_e = k_{N-2} th_{N-2} + c_{N-2} (w_{N-2} - w_b) - c_b w_b."""
        return self.k_last * y[-2] + self.c_last * (y[-3] - y[-1]) - self.c_b * y[-1]

    def friction(self, wb):
        """Slip friction T_fb(w_b) = R_b W_ob mu_b(w_b) sgn(w_b)."""
        if wb == 0.0:
            return 0.0
        mu = self.mu_cb + (self.mu_sb - self.mu_cb) * math.exp(-self.gamma_b * abs(wb) / self.v_f)
        return math.copysign(self.R_b * self.wob * mu, wb)

    def mode_from_state(self, y):
        wb = float(y[-1])
        if wb > 0.0:
            return SLIP_POS
        if wb < 0.0:
            return SLIP_NEG
        if self.wob == 0.0:
            return SLIP_POS  # no friction: the slip sign only labels a zero term
        Te = self.reaction_torque(y)
        if abs(Te) <= self.T_s:
            return STICK
        return SLIP_POS if Te > 0 else SLIP_NEG

    def energy(self, y):
        """Kinetic + elastic energy."""
        w, th = y[0::2], y[1::2]
        return 0.5 * float(np.dot(self.I, w * w)) + 0.5 * float(np.dot(self.k, th * th))

    # ---- right-hand sides -------------------------------------------------------------
    def rhs(self, mode, energy=False):
        """Pure right-hand side for a fixed mode (a closure; no state changes)."""
        if energy:
            return self._rhs_energy(mode)
        exp = math.exp
        n = self.n
        u = self.u
        stick = mode == STICK
        s = 0.0 if stick else _SIGN[mode]
        # friction constants: T_fb / I_b = fs * (mu_cb + dmu * exp(-gs * w_b))
        fs = s * self.R_b * self.wob / self.I[-1]
        mu_cb, dmu = self.mu_cb, self.mu_sb - self.mu_cb
        gs = s * self.gamma_b / self.v_f
        no_friction = stick or self.wob == 0.0

        if n <= _DENSE_MAX_STATES:
            A = self.A_stick if stick else self.A_slip
            b0 = u / self.I[0]
            if no_friction:

                def f(t, y):
                    out = A @ y
                    out[0] += b0
                    return out
            else:

                def f(t, y):
                    out = A @ y
                    out[0] += b0
                    out[-1] -= fs * (mu_cb + dmu * exp(min(-gs * y[-1], 700.0)))
                    return out

            return f

        invI = 1.0 / self.I
        k, c = self.k, self.c
        c_r, c_b = self.c_r, self.c_b
        empty = np.empty

        def f(t, y):
            w = y[0::2]
            dw = w[:-1] - w[1:]
            s_ = k * y[1::2]
            s_ += c * dw  # spring torques, length N-1
            out = empty(n)
            tor = out[0::2]  # view: net torques on the N inertias
            tor[1:] = s_
            tor[0] = u - c_r * w[0]
            tor[:-1] -= s_
            if stick:
                tor *= invI
                tor[-1] = 0.0
            else:
                fr = 0.0 if no_friction else fs * (mu_cb + dmu * exp(min(-gs * y[-1], 700.0)))
                tor[-1] -= c_b * w[-1]
                tor *= invI
                tor[-1] -= fr
            out[1::2] = dw
            return out

        return f

    def _rhs_energy(self, mode):
        """Checking variant: appends work of u, viscous and friction dissipation as states."""
        n = self.n
        stick = mode == STICK
        s = 0.0 if stick else _SIGN[mode]
        A = self.A_stick if stick else self.A_slip
        I, c = self.I, self.c
        u, c_r, c_b = self.u, self.c_r, self.c_b
        R, W, mu_cb, dmu = self.R_b, self.wob, self.mu_cb, self.mu_sb - self.mu_cb
        gs = s * self.gamma_b / self.v_f

        def f(t, z):
            y = z[:n]
            out = np.empty(n + 3)
            out[:n] = A @ y
            out[0] += u / I[0]
            wb = y[-1]
            Tfb = 0.0 if stick else s * R * W * (mu_cb + dmu * math.exp(min(-gs * wb, 700.0)))
            out[n - 1] -= Tfb / I[-1]
            w = y[0::2]
            dw = w[:-1] - w[1:]
            out[n] = u * w[0]  # work of u
            out[n + 1] = c_r * w[0] ** 2 + c_b * wb**2 + np.dot(c, dw * dw)  # viscous
            out[n + 2] = Tfb * wb  # friction
            return out

        return f

    # ---- Jacobians --------------------------------------------------------------------
    def jac_options(self, mode, method):
        """Keyword options (``jac`` and possibly ``lband``/``uband``) for ``solve_ivp``."""
        if method in ("RK23", "RK45", "DOP853"):
            return {}
        stick = mode == STICK
        exp = math.exp
        s = 0.0 if stick else _SIGN[mode]
        # d(w_b')/d(w_b) from friction: +delta(w_b)/I_b,
        # delta = R W (mu_sb - mu_cb) (gamma/v_f) exp(-gamma s w_b / v_f)
        dcoef = (
            self.R_b * self.wob * (self.mu_sb - self.mu_cb) * self.gamma_b / self.v_f / self.I[-1]
        )
        gs = s * self.gamma_b / self.v_f
        A = self.A_stick if stick else self.A_slip
        n = self.n

        if method == "LSODA":
            lb, ub = self.lband, self.uband
            P0 = np.zeros((lb + ub + 1, n))
            for d in range(-ub, lb + 1):  # d = i - j
                j = np.arange(max(0, -d), min(n, n - d))
                P0[ub + d, j] = A[j + d, j]
            if stick or self.wob == 0.0:

                def jac(t, y):
                    return P0
            else:

                def jac(t, y):
                    P = P0.copy()
                    P[ub, -1] += dcoef * exp(min(-gs * y[-1], 700.0))
                    return P

            return dict(jac=jac, lband=lb, uband=ub)

        # Radau / BDF
        if n <= _DENSE_JAC_MAX_STATES:
            if stick or self.wob == 0.0:
                return dict(jac=A)

            def jac(t, y):
                J = A.copy()
                J[-1, -1] += dcoef * exp(min(-gs * y[-1], 700.0))
                return J

            return dict(jac=jac)
        As = sp.csc_matrix(A)
        As.sort_indices()
        if stick or self.wob == 0.0:
            return dict(jac=As)
        # position of (n-1, n-1) in the CSC data (the last column holds it last)
        col = As.indptr[n - 1], As.indptr[n]
        pos = col[0] + int(np.nonzero(As.indices[col[0] : col[1]] == n - 1)[0][0])

        def jac(t, y):
            J = As.copy()
            J.data[pos] += dcoef * exp(min(-gs * y[-1], 700.0))
            return J

        return dict(jac=jac)

    # ---- events -------------------------------------------------------------------------
    def events(self, mode):
        """Terminal event functions of a mode and the mode each one leads to (None: decide
        in the switch handler).  Indices are absolute so that the checking variant's extra
        states (appended at the end) do not shift them."""
        ib, it, iw = self.n - 1, self.n - 2, self.n - 3  # w_b, th_{N-2}, w_{N-2}
        if mode == STICK:
            kl, cl, cb, Ts = self.k_last, self.c_last, self.c_b, self.T_s

            def rise(t, y):  # T_e - T_s, rising -> slip+
                return kl * y[it] + cl * (y[iw] - y[ib]) - cb * y[ib] - Ts

            def fall(t, y):  # T_e + T_s, falling -> slip-
                return kl * y[it] + cl * (y[iw] - y[ib]) - cb * y[ib] + Ts

            rise.terminal = fall.terminal = True
            rise.direction, fall.direction = 1.0, -1.0
            return [rise, fall], [SLIP_POS, SLIP_NEG]

        def zero(t, y):  # w_b crosses zero against the slip direction
            return y[ib]

        zero.terminal = True
        zero.direction = -_SIGN[mode]
        return [zero], [None]


# --------------------------------------------------------------------------------------------
# simulation
# --------------------------------------------------------------------------------------------
def simulate_baseline(
    inertias,
    stiffnesses,
    dampings,
    *,
    c_r,
    c_b,
    mu_cb,
    mu_sb,
    R_b,
    gamma_b,
    v_f,
    wob,
    torque,
    t_end,
    initial="rest",
    y0=None,
    method=DEFAULT_METHOD,
    rtol=1e-8,
    atol=1e-8,
    t_eval=None,
    max_switches_per_second=1e4,
    t0=0.0,
    track_energy=False,
):
    """Exact event-driven stick-slip simulation with ``scipy.integrate.solve_ivp``.

    Parameters follow DESIGN.md section 2 (SI units).  ``initial`` is ``"rest"`` or
    ``"equilibrium"`` (largest steady Omega, bit velocity perturbed by ``+1e-3 Omega``);
    ``y0`` (twist coordinates, length 2N-1) overrides it.  ``method`` is any ``solve_ivp``
    method; LSODA gets a banded analytic Jacobian, Radau/BDF a dense or sparse one.

    ``track_energy`` (checking only, slower) appends three quadrature states -- work of the
    top torque, viscous dissipation, friction dissipation -- and returns them under
    ``"energy"`` with the mechanical energy, so that ``work = dissipation + dE``.

    Returns a dict with ``t``, ``y`` (shape ``(len(t), 2N-1)``), ``switch_times``,
    ``switch_kinds`` (mode entered: ``"stick"``, ``"slip+"``, ``"slip-"``), ``mode_initial``,
    ``mode_final``, ``nfev``, ``njev``, ``nlu``, ``n_segments``, ``wall_time`` (s), ``omega_eq``
    (for ``initial="equilibrium"``), ``method``, ``rtol``, ``atol``.

    Raises ``RuntimeError`` if the solver fails or the bit chatters (more than
    ``max_switches_per_second`` switches within any one-second window, or more than 100
    consecutive switches without the time advancing).

    Limitation shared with any sign-change root finder: a zero of ``w_b`` that is entered
    and left within one solver step (a grazing touch) is not seen.
    """
    wall0, cpu0 = time.perf_counter(), time.process_time()
    params = dict(c_r=c_r, c_b=c_b, mu_cb=mu_cb, mu_sb=mu_sb, R_b=R_b, gamma_b=gamma_b, v_f=v_f)
    m = _Model(inertias, stiffnesses, dampings, wob=wob, torque=torque, **params)
    n = m.n
    t0, t_end = float(t0), float(t_end)
    if not t_end > t0:
        raise ValueError("t_end must be greater than t0")

    omega_eq = None
    if y0 is not None:
        y = np.array(y0, dtype=float).ravel()
        if y.size != n:
            raise ValueError(f"y0 must have length 2*dof-1 = {n}")
    elif initial == "rest":
        y = np.zeros(n)
    elif initial == "equilibrium":
        omega_eq = equilibrium_velocity(torque=m.u, wob=m.wob, **params)
        if omega_eq is None:
            raise ValueError(f"no steady rotation Omega > 0 for torque={torque}, wob={wob}")
        h = m.c_b * omega_eq + m.friction(omega_eq)
        y = np.empty(n)
        y[0::2] = omega_eq
        y[1::2] = h / m.k
        y[-1] = omega_eq * (1.0 + 1e-3)
    else:
        raise ValueError("initial must be 'rest' or 'equilibrium'")

    if t_eval is not None:
        t_eval = np.asarray(t_eval, dtype=float).ravel()
        if t_eval.size and (t_eval[0] < t0 or t_eval[-1] > t_end or np.any(np.diff(t_eval) <= 0)):
            raise ValueError("t_eval must be increasing and inside [t0, t_end]")

    if track_energy:
        E0 = m.energy(y)
        y = np.concatenate([y, np.zeros(3)])
    nz = y.size

    mode = m.mode_from_state(y[:n])
    if mode == STICK:
        y[n - 1] = 0.0
    mode_initial = mode

    # Per-mode solver setup is built once and reused at every restart.
    cache = {}

    def setup(md):
        if md not in cache:
            fun = m.rhs(md, energy=track_energy)
            evs, targets = m.events(md)
            opts = {} if track_energy else m.jac_options(md, method)
            if m.wob == 0.0 and md != STICK:
                evs, targets = [], []  # no friction at all: nothing to switch
            cache[md] = (fun, evs, targets, opts)
        return cache[md]

    ts, ys = [], []
    switch_times, switch_kinds, switch_Te = [], [], []
    nfev = njev = nlu = nseg = 0
    t = t0
    stalled = 0
    window = collections.deque()  # switch times of the last second (chattering guard)
    first = True
    while True:
        fun, evs, targets, opts = setup(mode)
        if t_eval is not None:
            lo = np.searchsorted(t_eval, t, side="left" if first else "right")
            seg_eval = t_eval[lo:]
        else:
            seg_eval = None
        # A restart right at break-away has f(w_b) ~ 0, and solve_ivp's initial-step
        # heuristic may then try an absurdly long step; it is rejected (inf error norm) and
        # retried, but numpy would warn about the overflow on the way.
        with np.errstate(over="ignore", invalid="ignore"):
            sol = solve_ivp(
                fun,
                (t, t_end),
                y,
                method=method,
                t_eval=seg_eval,
                events=evs or None,
                rtol=rtol,
                atol=atol,
                **opts,
            )
        nseg += 1
        nfev += sol.nfev
        njev += sol.njev
        nlu += sol.nlu
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp ({method}) failed at t={t}: {sol.message}")
        if len(sol.t):  # (a list when no t_eval point falls in it)
            if seg_eval is None and not first:
                ts.append(sol.t[1:])
                ys.append(sol.y[:, 1:])
            else:
                ts.append(sol.t)
                ys.append(sol.y)
        first = False
        if sol.status != 1:
            break

        # ---- a terminal event: decide the new mode -----------------------------------
        hit = [i for i, te in enumerate(sol.t_events) if te.size]
        i_ev = min(hit, key=lambda i: sol.t_events[i][0])
        t_new = float(sol.t_events[i_ev][0])
        y = np.array(sol.y_events[i_ev][0], dtype=float)
        y[n - 1] = 0.0  # the bit is exactly at rest at every switch
        Te = m.reaction_torque(y[:n])
        if mode == STICK:
            new_mode = targets[i_ev]
        elif abs(Te) <= m.T_s:
            new_mode = STICK
        else:
            new_mode = SLIP_POS if Te > 0 else SLIP_NEG

        # chattering guards
        stalled = stalled + 1 if t_new - t <= 1e-12 * max(1.0, abs(t_new)) else 0
        window.append(t_new)
        while window and window[0] < t_new - 1.0:
            window.popleft()
        if len(window) > max_switches_per_second or stalled > 100:
            raise RuntimeError(
                f"chattering at t={t_new:.9g}: {len(window)} mode switches within 1 s "
                f"({stalled} without progress); cap max_switches_per_second="
                f"{max_switches_per_second:g}"
            )

        switch_times.append(t_new)
        switch_kinds.append(new_mode)
        switch_Te.append(float(Te))
        if seg_eval is None and ys and ys[-1].shape[1]:
            ys[-1][:, -1] = y  # show the post-switch state at the switch time
        t, mode = t_new, new_mode
        if t >= t_end:
            break

    if ts:
        t_out = np.concatenate(ts)
        Y = np.concatenate(ys, axis=1).T
    else:
        t_out = np.empty(0)
        Y = np.empty((0, nz))

    res = dict(
        t=t_out,
        y=np.ascontiguousarray(Y[:, :n]),
        switch_times=np.array(switch_times),
        switch_kinds=switch_kinds,
        switch_Te=np.array(switch_Te),
        mode_initial=mode_initial,
        mode_final=mode,
        nfev=int(nfev),
        njev=int(njev),
        nlu=int(nlu),
        n_segments=nseg,
        omega_eq=omega_eq,
        method=method,
        rtol=rtol,
        atol=atol,
        T_s=m.T_s,
    )
    if track_energy:
        Eq = Y[:, n:]
        E = np.array([m.energy(row[:n]) for row in Y])
        res["energy"] = dict(
            work=Eq[:, 0], viscous=Eq[:, 1], friction=Eq[:, 2], mechanical=E, E0=E0
        )
    res["wall_time"] = time.perf_counter() - wall0
    res["cpu_time"] = time.process_time() - cpu0
    return res


# --------------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------------
def _compare(a, t_eval):
    """Time every solve_ivp method on one case against a DOP853 rtol=atol=1e-12 reference."""
    kw = dict(
        reduced_scale(a.dof),
        wob=a.wob,
        torque=a.torque,
        t_end=a.t_end,
        initial=a.initial,
        t_eval=t_eval,
    )
    ref = simulate_baseline(**kw, method="DOP853", rtol=1e-12, atol=1e-12)
    Yr = ref["y"]
    sw, sth = np.abs(Yr[:, 0::2]).max(), np.abs(Yr[:, 1::2]).max()
    print(
        f"reference DOP853 rtol=atol=1e-12: {ref['wall_time']:.3f} s, "
        f"{len(ref['switch_times'])} switches"
    )
    print(
        "timings: best of --repeat runs without t_eval (solver steps only); errors from one "
        "run on the --dt grid, relative to max |w| and max |theta|"
    )
    print(
        f"{'method':8s} {'wall [s]':>9s} {'cpu [s]':>9s} {'nfev':>8s} {'njev':>6s} "
        f"{'switches':>8s} {'max rel err':>11s} {'max |dt_switch|':>15s}"
    )
    kw_t = dict(kw, t_eval=None)
    for meth in ("DOP853", "RK45", "LSODA", "Radau", "BDF"):
        walls, cpus = [], []
        for _ in range(a.repeat):
            r0 = simulate_baseline(**kw_t, method=meth, rtol=a.rtol, atol=a.atol)
            walls.append(r0["wall_time"])
            cpus.append(r0["cpu_time"])
        r = simulate_baseline(**kw, method=meth, rtol=a.rtol, atol=a.atol)
        Y = r["y"]
        err = max(
            np.abs(Y[:, 0::2] - Yr[:, 0::2]).max() / max(sw, 1e-300),
            np.abs(Y[:, 1::2] - Yr[:, 1::2]).max() / max(sth, 1e-300),
        )
        ns = len(r["switch_times"])
        dts = (
            np.abs(r["switch_times"] - ref["switch_times"]).max()
            if ns == len(ref["switch_times"]) and ns
            else float("nan")
        )
        print(
            f"{meth:8s} {min(walls):9.4f} {min(cpus):9.4f} {r0['nfev']:8d} {r0['njev']:6d} {ns:8d} "
            f"{err:11.1e} {dts:15.1e}"
        )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dof", type=int, default=4)
    ap.add_argument("--wob", type=float, default=100.0, help="weight on bit [N]")
    ap.add_argument("--torque", type=float, default=8.3, help="top torque u [N m]")
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--initial", choices=["rest", "equilibrium"], default="rest")
    ap.add_argument("--method", default=DEFAULT_METHOD)
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--atol", type=float, default=1e-8)
    ap.add_argument(
        "--dt",
        type=float,
        default=0.01,
        help="output spacing for the bit-velocity statistics (0: solver steps)",
    )
    ap.add_argument(
        "--compare",
        action="store_true",
        help="time all solve_ivp methods on this case against a 1e-12 reference",
    )
    ap.add_argument("--repeat", type=int, default=3, help="timing repeats for --compare")
    a = ap.parse_args(argv)

    t_eval = None
    if a.dt > 0:
        t_eval = np.linspace(0.0, a.t_end, round(a.t_end / a.dt) + 1)
    if a.compare:
        if t_eval is None:
            ap.error("--compare needs --dt > 0")
        _compare(a, t_eval)
        return 0
    r = simulate_baseline(
        **reduced_scale(a.dof),
        wob=a.wob,
        torque=a.torque,
        t_end=a.t_end,
        initial=a.initial,
        method=a.method,
        rtol=a.rtol,
        atol=a.atol,
        t_eval=t_eval,
    )
    half = r["t"] >= 0.5 * a.t_end
    wb = r["y"][half, -1]
    n_stick = sum(1 for k in r["switch_kinds"] if k == "stick")
    print(
        f"dof {a.dof}  wob {a.wob:g} N  torque {a.torque:g} N m  t_end {a.t_end:g} s  "
        f"initial {a.initial}  method {a.method}  rtol {a.rtol:g}  atol {a.atol:g}"
    )
    print(f"wall time      {r['wall_time']:.4f} s   (nfev {r['nfev']}, segments {r['n_segments']})")
    print(
        f"switches       {len(r['switch_times'])}   (stick events {n_stick}; final mode "
        f"{r['mode_final']})"
    )
    print(
        f"bit velocity over t >= {0.5 * a.t_end:g} s: min {wb.min():.6g}  max {wb.max():.6g}  "
        f"mean {wb.mean():.6g} rad/s"
    )
    return 0


def from_params(p) -> dict:
    """Keyword arguments of :func:`simulate_baseline` for a ``pydrill.Params``."""
    return dict(
        inertias=np.array(p.inertias),
        stiffnesses=np.array(p.stiffnesses),
        dampings=np.array(p.dampings),
        c_r=p.top_damping,
        c_b=p.bit_damping,
        mu_cb=p.mu_coulomb,
        mu_sb=p.mu_static,
        R_b=p.bit_radius,
        gamma_b=p.stribeck_decay,
        v_f=p.stribeck_velocity,
    )


if __name__ == "__main__":
    raise SystemExit(main())
