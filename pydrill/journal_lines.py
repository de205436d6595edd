"""How a journal's lines hold a sweep's records.

The first line names the sweep and the layout of the lines after it::

    {"spec_digest": "…", "layout": 2, "runs": ["regime", "bit_min", …], "stability": [...]}

and each later line is one point, its values in the order the header names, without the
names (half the bytes of the record as a JSON object: 550 against 1060 a dof-4 point, so a
million points' journal takes 0.55 GB of disk, not 1.1)::

    [i, status, message, {start: [regime, bit_min, …], …}, coexistence, [omega_eq, …]]

A run or a stability table that does not hold exactly the header's names (a start without a
steady state: ``{"regime": "no-steady-state"}``) stays an object. A line that is a whole
object is the record as it is: the layout of journals written before this one (their header
names no layout), read as they were.
"""

from __future__ import annotations

import json
from typing import Any

#: a run's values, in the order a line holds them (evaluate_point's)
RUN_KEYS = (
    "regime",
    "bit_min",
    "bit_max",
    "bit_mean",
    "top_mean",
    "top_min",
    "top_max",
    "bit_top_ratio",
    "severity",
    "stuck_fraction",
    "period",
    "stick_events",
    "wall_time",
    "caveat",
)
#: a point's stability values, in that order
STABILITY_KEYS = (
    "omega_eq",
    "delta",
    "spectral_abscissa",
    "hopf_margin",
    "unstable",
    "eigenvalues",
)
LAYOUT = 2
_RECORD_KEYS = {"i", "status", "message", "runs", "coexistence", "stability"}
_ABSENT = None  # coexistence or stability a record does not have


def header(digest: str) -> str:
    """A journal's first line (with its end of line)."""
    return (
        json.dumps(
            {"spec_digest": digest, "layout": LAYOUT, "runs": RUN_KEYS, "stability": STABILITY_KEYS}
        )
        + "\n"
    )


class Layout:
    """How the lines of a journal hold records, from its header (a dict): by position in the
    orders it names (layout 2), or as whole objects (no layout named: journals before it)."""

    def __init__(self, head: dict[str, Any]) -> None:
        self.runs: tuple[str, ...] | None = None
        self.stability: tuple[str, ...] | None = None
        layout = head.get("layout", 1)
        if layout == 1:
            return
        runs, stability = head.get("runs"), head.get("stability")
        if layout != LAYOUT or not (_names(runs) and _names(stability)):
            raise ValueError(
                f"layout {layout!r} with runs {runs!r} and stability {stability!r} is not one "
                "this pydrill reads"
            )
        self.runs, self.stability = tuple(runs), tuple(stability)  # type: ignore[arg-type]

    def record(self, data: Any) -> Any:
        """The record a line's JSON ``data`` holds, as a dict; ``data`` as it is when it is no
        line of this layout (the checks of :mod:`journal_records` then say what is wrong)."""
        if not isinstance(data, list) or self.runs is None or self.stability is None:
            return data
        if len(data) != 6 or not isinstance(data[3], dict):
            return data
        i, status, message, runs, coexistence, stability = data
        rec: dict[str, Any] = {"i": i, "status": status, "message": message, "runs": {}}
        for start, run in runs.items():
            if isinstance(run, list):
                if len(run) != len(self.runs):
                    return data
                run = dict(zip(self.runs, run, strict=True))
            rec["runs"][start] = run
        if coexistence is not _ABSENT:
            rec["coexistence"] = coexistence
        if isinstance(stability, list):
            if len(stability) != len(self.stability):
                return data
            stability = dict(zip(self.stability, stability, strict=True))
        if stability is not _ABSENT:
            rec["stability"] = stability
        return rec


def _names(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, str) for v in value)


def line(rec: dict[str, Any]) -> str:
    """A record as a journal line of this layout (with its end of line); one with names it
    does not know, as a whole object."""
    if not set(rec) <= _RECORD_KEYS or "i" not in rec or "status" not in rec:
        return json.dumps(rec, allow_nan=False) + "\n"
    runs = {
        start: [run[k] for k in RUN_KEYS] if tuple(run) == RUN_KEYS else run
        for start, run in rec.get("runs", {}).items()
    }
    stability = rec.get("stability", _ABSENT)
    if isinstance(stability, dict) and tuple(stability) == STABILITY_KEYS:
        stability = [stability[k] for k in STABILITY_KEYS]
    packed = [
        rec["i"],
        rec["status"],
        rec.get("message", ""),
        runs,
        rec.get("coexistence", _ABSENT),
        stability,
    ]
    return json.dumps(packed, allow_nan=False, separators=(",", ":")) + "\n"
