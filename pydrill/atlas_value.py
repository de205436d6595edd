"""``Atlas.value``: everything recorded at one grid point of an atlas, as plain data (SI
numbers, None for what was not measured, names for codes)."""

from __future__ import annotations

import math
from typing import Any

from . import atlas_format as fmt

#: coexistence codes, by what they say (as the CSV export names them)
_COEXISTENCE = {"unknown": -1, "no": 0, "yes": 1}


def _clean(v: Any) -> Any:
    v = v.item() if hasattr(v, "item") else v
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, int) and v == -1:
        return None
    return v


def point_value(atlas: Any, f: Any, idx: tuple[int, ...]) -> dict[str, Any]:
    """``atlas.value`` at the grid index ``idx`` of its open file ``f``: see there."""
    status = atlas._name(fmt.STATUS, "status", f["status"][idx])
    out: dict[str, Any] = {
        "coords": {
            # an int on a size axis (dof, pipes), else a float
            name: v[i].item()
            for (name, v), i in zip(atlas.axes.items(), idx, strict=True)
        },
        "status": status,
    }
    if status == "failed":
        # The messages sit in heaps written late, past what opening checked (OPENING_BYTES):
        # a damaged one would hang HDF5 here. The whole file once, so only when it is needed.
        atlas._heap()
        msg = f["message"][idx]
        out["message"] = msg.decode() if isinstance(msg, bytes) else str(msg)
    regimes = f["regime"][idx]
    out["regime"] = {
        init: atlas._name(fmt.REGIMES, "regime", r)
        for init, r in zip(atlas.initials, regimes, strict=True)
    }
    metrics = {}
    for name in fmt.RUN_FIELDS:
        # (not recorded by the pydrill that wrote an older atlas: None)
        vals = f[name][idx] if name in f else [math.nan] * len(atlas.initials)
        metrics[name] = {init: _clean(v) for init, v in zip(atlas.initials, vals, strict=True)}
    out["metrics"] = metrics
    if atlas.spec.record["stability"]:
        eq = {name: [_clean(v) for v in f[name][idx]] for name in fmt.EQ_FIELDS}
        re, im = f["eigenvalues_real"][idx], f["eigenvalues_imag"][idx]
        eq["eigenvalues"] = [
            [[float(a), float(b)] for a, b in zip(r, i, strict=True) if math.isfinite(a)]
            for r, i in zip(re, im, strict=True)
        ]
        n = sum(1 for w in eq["omega_eq"] if w is not None)
        out["stability"] = {k: v[:n] for k, v in eq.items()}
    else:  # not recorded: None, not empty lists, which say "no steady state" at this point
        out["stability"] = None
    co = atlas._name(_COEXISTENCE, "coexistence", f["coexistence"][idx])
    out["coexistence"] = None if co == "unknown" else co == "yes"
    # Older atlases have no caveats: None, as for a run without one.
    notes = f["caveat"][idx] if "caveat" in f else [0] * len(atlas.initials)
    out["caveat"] = {
        init: atlas._name(fmt.CAVEATS, "caveat", c) or None
        for init, c in zip(atlas.initials, notes, strict=True)
    }
    return out
