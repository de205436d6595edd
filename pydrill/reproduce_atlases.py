"""The regime atlases of ``pydrill reproduce``: Fig. 6b's (W_ob, u) map and the periodic orbits
of Fig. 11, swept with :func:`pydrill.sweep.run_sweep` into HDF5 atlases that later runs reuse,
and what they say about the paper's claims (the stick-slip band, ε±, W_ob0/W_ob1, u0/u1)."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np


def _range(start: float, stop: float, step: float) -> list[float]:
    n = round((stop - start) / step) + 1
    return [round(start + k * step, 10) for k in range(n)]


def atlas_plan(quick: bool = False) -> dict[str, dict[str, Any]]:
    """Every atlas the reproduction needs: name -> sweep settings (``quick``: coarser, and no
    100- or 500-pipe strings). Fig. 6b's (W_ob, u) grid holds the paper's Section 3 cases
    (40, 100, 160 N at 8.3 N·m); the Fig. 11 atlases are the diagrams' parameter ranges, both
    starts, simulated long enough for each string to wind up (its torsional time constant
    c_r·Σ1/k_i is 30 s for 10 pipes, 250 s for 100, 1240 s for 500)."""
    s = 2.0 if quick else 1.0
    plan = {
        "fig06b": {
            "model": {"dof": 4},
            "axes": {
                "wob": _range(20.0, 200.0, 5.0 * s),
                "torque": _range(1.3, 16.3, 0.5 * s),
            },
            "t_end": 300.0,
            "parallel": True,
        },
    }
    panels = {"a": (2, "wob"), "b": (2, "torque"), "c": (4, "wob"), "d": (4, "torque")}
    for panel, (dof, vary) in panels.items():
        plan[f"fig11{panel}"] = _fig11_atlas({"dof": dof}, vary, panel, s, 300.0)
    for pipes, t_end, coarse in ((10, 600.0, 1.0), (100, 6000.0, 2.0), (500, 30000.0, 5.0)):
        if quick and pipes > 10:
            continue
        for panel, vary in (("c", "wob"), ("d", "torque")):
            plan[f"pipes{pipes}-fig11{panel}"] = _fig11_atlas(
                {"pipes": pipes}, vary, panel, s * coarse, t_end, parallel=pipes >= 100
            )
    return plan


#: N·m, the largest u of the Fig. 11 atlases varying u (the branch drawn over them reaches it).
TORQUE_MAX = 12.0


def _fig11_atlas(model, vary, panel, step, t_end, parallel=False) -> dict[str, Any]:
    if vary == "wob":
        fixed, axes = {"torque": 8.1}, {"wob": _range(40.0, 160.0, 2.0 * step)}
    else:
        w = 80.0 if panel == "b" else 60.0
        fixed, axes = {"wob": w}, {"torque": _range(2.0, TORQUE_MAX, 0.2 * step)}
    return {
        "model": {**model, **fixed},
        "axes": axes,
        "t_end": t_end,
        "parallel": parallel,
    }


def spec_text(settings: dict[str, Any]) -> str:
    """The sweep spec (TOML) of one planned atlas."""
    lines = ["[model]", 'preset = "reduced-scale"']
    lines += [f"{k} = {v!r}" for k, v in settings["model"].items()]
    lines += ["", "[axes]"]
    lines += [f"{k} = [{', '.join(repr(x) for x in v)}]" for k, v in settings["axes"].items()]
    lines += [
        "",
        "[simulation]",
        f"t_end = {settings['t_end']!r}",
        'initial = ["rest", "equilibrium"]',
        "",
        "[record]",
        "stability = true",
        "eigenvalues = 4",
        "",
    ]
    return "\n".join(lines)


def run_atlas(
    out: Path,
    name: str,
    settings: dict[str, Any],
    *,
    force: bool,
    workers: int | None,
    scheduler: str | None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Path, str]:
    """The atlas ``name`` in ``out/atlases``: reused if it holds this spec, computed by this
    pydrill version and complete; resumed if interrupted; recomputed otherwise."""
    from . import __version__
    from .atlas import Atlas
    from .spec import parse_spec
    from .sweep import AtlasError, run_sweep

    spec = parse_spec(spec_text(settings))
    path = out / "atlases" / f"{name}.h5"
    path.parent.mkdir(parents=True, exist_ok=True)
    journal = path.with_name(path.name + ".journal")
    resume = False
    if path.exists() and not force:
        try:
            with Atlas(path) as atlas:
                same = atlas.spec.digest == spec.digest and atlas.version == __version__
                done = atlas.summary()["status"]["missing"] == 0
            if same and done and not journal.exists():
                return path, "reused"
            resume = same
        except AtlasError:
            resume = False
    if not resume or force:
        path.unlink(missing_ok=True)
        journal.unlink(missing_ok=True)
    # The small atlases run here, serially, whatever the cluster: starting one costs more
    # than their points. ``workers`` sizes the cluster of the others.
    serial = not settings["parallel"] and scheduler is None
    run_sweep(
        spec,
        path,
        workers=None if serial else workers,
        scheduler=scheduler,
        resume=resume,
        progress=progress,
        serial=serial,
    )
    return path, "resumed" if resume else "computed"


def atlas_numbers(path: Path) -> dict[str, Any]:
    """What an atlas says, as plain data: its axes, and per start the regime and the bit's
    velocity range at every point (1-D atlases) or the regime grid (2-D)."""
    from .atlas import Atlas

    with Atlas(path) as atlas:
        f = atlas._f  # the arrays, read once
        data: dict[str, Any] = {
            "axes": {k: v.tolist() for k, v in atlas.axes.items()},
            "fixed": atlas.spec.fixed,
            "dof": atlas.spec.params_at(atlas.spec.coords(0)).dof,
            "t_end": atlas.spec.simulation["t_end"],
            "summary": atlas.summary()["regimes"],
            "initials": atlas.initials,
        }
        for j, init in enumerate(atlas.initials):
            data[init] = {
                "regime": atlas.regimes(init).tolist(),
                **{k: f[k][..., j].tolist() for k in ("bit_min", "bit_max", "period")},
            }
        data["unstable"] = f["unstable"][..., 0].tolist()
    return _plain(data)


def _plain(x: Any) -> Any:
    """JSON-ready: numpy scalars to Python, non-finite floats to None."""
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_plain(v) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def _runs(values: np.ndarray, mask: np.ndarray) -> list[list[float]]:
    """The contiguous stretches of ``values`` where ``mask`` holds, as [first, last]."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        if not m and start is not None:
            out.append([float(values[start]), float(values[i - 1])])
            start = None
    if start is not None:
        out.append([float(values[start]), float(values[-1])])
    return out


def band(a: dict[str, Any], torque: float = 8.3, wob: float = 100.0) -> dict[str, Any]:
    """Fig. 6b from its atlas: the stick-slip band along u = μ_sb R_b W_ob (Eq. 38) from rest,
    its extent along the row u = ``torque`` and the column W_ob = ``wob`` (the paper's ε± and
    ρ±, which it leaves unquantified), and whether every stuck point has u ≤ T_s (Eq. 39)."""
    from .model import preset

    p = preset("reduced-scale", dof=a["dof"])
    w, u = np.array(a["axes"]["wob"]), np.array(a["axes"]["torque"])
    rest = np.array(a["rest"]["regime"], dtype=object)
    eq = np.array(a["equilibrium"]["regime"], dtype=object)
    # static_torque is annotated for a float, and broadcasts over an array of W_ob as well.
    ts = p.static_torque(w)[:, None] * np.ones((1, len(u)))
    uu = np.ones((len(w), 1)) * u[None, :]
    slip = rest == "stick-slip"
    j = int(np.argmin(np.abs(u - torque)))
    i = int(np.argmin(np.abs(w - wob)))
    row, col = slip[:, j], slip[i, :]
    rel = (uu - ts) / ts
    counts = {r: int(np.sum(rest == r)) for r in ("steady", "stick-slip", "stuck", "oscillation")}
    coexist = (rest != eq) & (eq != "no-steady-state")
    return _plain(
        {
            "points": int(rest.size),
            "counts_rest": counts,
            "torque_row": float(u[j]),
            "wob_lo": float(w[row].min()) if row.any() else None,
            "wob_hi": float(w[row].max()) if row.any() else None,
            "wob_star": float(u[j] / (p.mu_static * p.bit_radius)),
            "wob_col": float(w[i]),
            "torque_lo": float(u[col].min()) if col.any() else None,
            "torque_hi": float(u[col].max()) if col.any() else None,
            "torque_star": float(p.static_torque(w[i])),
            "slip_rel_min": float(rel[slip].min()) if slip.any() else None,
            "slip_rel_max": float(rel[slip].max()) if slip.any() else None,
            "stuck_above_ts": int(np.sum((rest == "stuck") & (uu > ts))),
            "coexistence": int(np.sum(coexist)),
            "coexistence_kinds": sorted(
                {f"{a}/{b}" for a, b in zip(rest[coexist], eq[coexist], strict=True)}
            ),
            "t_end": a["t_end"],
        }
    )


def orbits(a: dict[str, Any], branch: dict[str, Any]) -> dict[str, Any]:
    """Fig. 11's periodic orbits from its atlas: where each start ends in stick-slip (or a
    sustained oscillation), stays stuck or drills steadily, along the varied parameter; where
    the two starts disagree (coexistence: the subcritical Hopf's hysteresis); and the paper's
    W_ob1 (u1), the far end of the largest branch of periodic orbits."""
    key = "wob" if branch["vary"] == "wob" else "torque"
    x = np.array(a["axes"][key])
    out: dict[str, Any] = {"vary": key, "step": float(x[1] - x[0]) if len(x) > 1 else None}
    periodic_any = np.zeros(len(x), dtype=bool)
    for init in ("rest", "equilibrium"):
        reg = np.array(a[init]["regime"], dtype=object)
        periodic = (reg == "stick-slip") | (reg == "oscillation")
        periodic_any |= periodic
        top = np.array(a[init]["bit_max"], dtype=float)
        period = np.array(a[init]["period"], dtype=float)
        out[init] = {
            "stick_slip": _runs(x, reg == "stick-slip"),
            "oscillation": _runs(x, reg == "oscillation"),
            "stuck": _runs(x, reg == "stuck"),
            "steady": _runs(x, reg == "steady"),
            "bit_max": [float(np.nanmin(top[periodic])), float(np.nanmax(top[periodic]))]
            if periodic.any()
            else None,
            "period": [float(np.nanmin(period[periodic])), float(np.nanmax(period[periodic]))]
            if periodic.any() and np.isfinite(period[periodic]).any()
            else None,
        }
    rest = np.array(a["rest"]["regime"], dtype=object)
    eq = np.array(a["equilibrium"]["regime"], dtype=object)
    both = (rest != eq) & (eq != "no-steady-state")
    out["coexistence"] = _runs(x, both)
    # The largest periodic-orbit branch ends where periodic motion stops, on the side of the
    # stable steady states: lowest W_ob (u1 for torque: highest u).
    if periodic_any.any():
        out["end"] = float(x[periodic_any].min() if key == "wob" else x[periodic_any].max())
    else:
        out["end"] = None
    return _plain(out)


def hopf_meets_band(a: dict[str, Any], delta: float) -> dict[str, Any]:
    """Where the first Hopf curve δ(Ω, W_ob) = δ crosses the sliding line u = T_s(W_ob), and the
    W_ob columns of the Fig. 6b atlas whose cell nearest to the curve is stick-slip from rest
    (the paper: the Hopf set of Fig. 12 intersects the stick-slip region Δ of Fig. 6b)."""
    from .model import preset
    from .operating import hopf_curve_wu

    p = preset("reduced-scale", dof=a["dof"])
    w_ax, u_ax = np.array(a["axes"]["wob"]), np.array(a["axes"]["torque"])
    rest = np.array(a["rest"]["regime"], dtype=object)
    w, u = hopf_curve_wu(p, delta, np.linspace(1e-4, 60.0, 60001))
    order = np.argsort(w)
    w, u = w[order], u[order]
    above = u - p.static_torque(w)  # broadcasts over W_ob
    flips = np.nonzero(np.sign(above[1:]) != np.sign(above[:-1]))[0]
    hits = []
    for i, wi in enumerate(w_ax):
        if wi < w[0] or wi > w[-1]:
            continue
        uh = float(np.interp(wi, w, u))
        if (
            u_ax.min() <= uh <= u_ax.max()
            and rest[i, int(np.argmin(np.abs(u_ax - uh)))] == "stick-slip"
        ):
            hits.append(float(wi))
    return _plain(
        {
            "crosses_line_at": float(w[flips[0]]) if len(flips) else None,
            "stick_slip_wob": hits,
            "columns": len(w_ax),
        }
    )
