"""The in-memory table a sweep fills: every field of every point, as numpy arrays, updated
from the workers' records (one at a time or a batch's block at once) before the client
writes it whole (``atlas_format.write``)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .atlas_schema import CAVEATS, EQ_FIELDS, N_EQ, REGIMES, RUN_FIELDS, STATUS
from .spec import SweepSpec

#: records a journal's replay holds and stores at a time (``AtlasTable.apply_all``): ~5 kB of
#: Python objects each, 20 MB in all, whatever the journal's length
REPLAY_CHUNK = 4096


@dataclass
class AtlasTable:
    """All of an atlas's point data in memory; a sweep updates it, then writes it whole.

    With ``points=m`` the table has m rows instead of the grid's shape: a worker fills such a
    block with its batch, and the client puts the block into the grid in one assignment per
    field (applying records one by one cost the client, which shares the cores with the
    workers, about 5 % of a sweep's wall time)."""

    spec: SweepSpec
    points: int | None = None
    status: np.ndarray = field(init=False)
    message: np.ndarray = field(init=False)
    regime: np.ndarray = field(init=False)
    runs: dict[str, np.ndarray] = field(init=False)
    eqs: dict[str, np.ndarray] = field(init=False)
    eig: np.ndarray = field(init=False)
    coexistence: np.ndarray = field(init=False)
    caveat: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        shape = self.spec.shape if self.points is None else (self.points,)
        n_init = len(self.spec.initials)
        k = self.spec.record["eigenvalues"]
        self.status = np.zeros(shape, dtype="u1")
        self.message = np.full(shape, "", dtype=object)
        self.regime = np.full((*shape, n_init), REGIMES["missing"], dtype="i1")
        self.runs = {n: np.full((*shape, n_init), f[1], dtype=f[0]) for n, f in RUN_FIELDS.items()}
        self.eqs = {n: np.full((*shape, N_EQ), f[1], dtype=f[0]) for n, f in EQ_FIELDS.items()}
        self.eig = np.full((*shape, N_EQ, k), complex(math.nan, math.nan), dtype="c16")
        self.coexistence = np.full(shape, -1, dtype="i1")
        self.caveat = np.zeros((*shape, n_init), dtype="i1")

    def columns(self) -> dict[str, np.ndarray]:
        """Every per-point array by name; the point axes come first."""
        return {
            "status": self.status,
            "message": self.message,
            "regime": self.regime,
            **{f"run:{k}": v for k, v in self.runs.items()},
            **{f"eq:{k}": v for k, v in self.eqs.items()},
            "eig": self.eig,
            "coexistence": self.coexistence,
            "caveat": self.caveat,
        }

    def put(self, indices: np.ndarray, block: dict[str, np.ndarray]) -> None:
        """Put the rows of a block (``AtlasTable(spec, points=m).columns()``) at the flat
        grid indices ``indices``."""
        n = self.status.size
        for name, array in self.columns().items():
            array.reshape(n, *array.shape[self.status.ndim :])[indices] = block[name]

    def apply(self, rec: dict[str, Any], row: int | None = None) -> None:
        """Store one point's record at its flat index (or at ``row`` of a block)."""
        self._apply(rec, rec["i"] if row is None else row, self._flat())

    def apply_all(self, records: Iterable[dict[str, Any]], chunk: int | None = None) -> int:
        """Store every record of ``records``, as ``put`` stores a block: each field of
        ``chunk`` records at a time in one assignment (an iterator is read ``chunk`` records
        at a time, so a journal of millions of points is never held whole); returns how many.
        Record by record, a million-point journal's replay took over a minute, most of it in
        numpy's per-element assignments (~50 a record)."""
        flat, n = self._flat(), 0
        it = iter(records)
        while part := list(itertools.islice(it, chunk or REPLAY_CHUNK)):
            self._apply_block(part, flat)
            n += len(part)
        return n

    def fill(self, records: list[dict[str, Any]]) -> None:
        """Store ``records`` in rows 0, 1, ... of a block (``points=len(records)``), field by
        field as ``apply_all`` does: a worker encodes its batch so (record by record, the
        encoding cost a tenth of what computing the points did)."""
        self._apply_block(records, self._flat(), np.arange(len(records)))

    def _apply_block(
        self,
        part: list[dict[str, Any]],
        flat: dict[str, np.ndarray],
        idx: np.ndarray | None = None,
    ) -> None:
        """``_apply`` of each record of ``part``, field by field, at the flat indices ``idx``
        (their own, ``rec["i"]``, by default); a record's absent values are stored as their
        fill, as ``put`` stores a block's.

        At their own indices (a journal's replay) a point's last record is all the table
        holds of it, as if it were the only one: pydrill journals each point once, but a
        journal joined by hand can hold a point twice, and a failed record after a done one
        must not keep the done run's steady states or eigenvalues."""
        if idx is None:
            idx = np.array([rec["i"] for rec in part], dtype=np.int64)
            _, first = np.unique(idx[::-1], return_index=True)
            if len(first) < len(idx):  # keep each point's last record of the chunk
                keep = np.sort(len(idx) - 1 - first)
                part, idx = [part[k] for k in keep], idx[keep]
            self._blank_rows(idx, flat)
        flat["status"][idx] = [STATUS[rec["status"]] for rec in part]
        messages = np.empty(len(part), dtype=object)
        messages[:] = [rec.get("message", "") for rec in part]
        flat["message"][idx] = messages
        for j, init in enumerate(self.spec.initials):
            runs = [rec.get("runs", {}).get(init) for rec in part]
            # the point failed before this start ran
            gone = [
                r is None and rec["status"] == "failed" for r, rec in zip(runs, part, strict=True)
            ]
            flat["regime"][idx[np.array(gone, dtype=bool)], j] = REGIMES["failed"]
            ran = np.array([r is not None for r in runs], dtype=bool)
            got = [r for r in runs if r is not None]
            if not got:
                continue
            at = idx[ran]
            flat["regime"][at, j] = [REGIMES[r["regime"]] for r in got]
            flat["caveat"][at, j] = [CAVEATS[r.get("caveat") or ""] for r in got]
            for name, (_, fill, _, _) in RUN_FIELDS.items():
                values = [r.get(name) for r in got]
                flat[f"run:{name}"][at, j] = [fill if v is None else v for v in values]
        stabs = [(k, rec["stability"]) for k, rec in enumerate(part) if rec.get("stability")]
        if stabs:
            at = idx[[k for k, _ in stabs]]
            for name, (_, fill, _, _) in EQ_FIELDS.items():
                rows = []
                for _, stab in stabs:
                    vals = [fill if v is None else v for v in list(stab.get(name, []))[:N_EQ]]
                    rows.append(vals + [fill] * (N_EQ - len(vals)))
                flat[f"eq:{name}"][at] = rows
            eig = flat["eig"]
            k = eig.shape[-1]
            block = np.full((len(stabs), N_EQ, k), complex(math.nan, math.nan))
            for row, (_, stab) in enumerate(stabs):
                for e, values in enumerate(stab.get("eigenvalues", [])[:N_EQ]):
                    for m, (re, im) in enumerate(values[:k]):
                        block[row, e, m] = complex(re, im)
            eig[at] = block
        co = [
            (k, rec["coexistence"])
            for k, rec in enumerate(part)
            if rec.get("coexistence") is not None
        ]
        if co:
            flat["coexistence"][idx[[k for k, _ in co]]] = [int(v) for _, v in co]

    def _blank_rows(self, idx: np.ndarray, flat: dict[str, np.ndarray]) -> None:
        """Put the rows ``idx`` back to a fresh table's values (a point never computed)."""
        fresh = AtlasTable(self.spec, points=1)._flat()
        for name, array in flat.items():
            array[idx] = fresh[name][0]

    def _flat(self) -> dict[str, np.ndarray]:
        """Views of the arrays with the point axes flattened (they share memory with them)."""
        n = self.status.size
        k = self.eig.shape[-1]
        return {
            "status": self.status.reshape(n),
            "message": self.message.reshape(n),
            "regime": self.regime.reshape(n, -1),
            "caveat": self.caveat.reshape(n, -1),
            "coexistence": self.coexistence.reshape(n),
            "eig": self.eig.reshape(n, N_EQ, k),
            **{f"run:{name}": a.reshape(n, -1) for name, a in self.runs.items()},
            **{f"eq:{name}": a.reshape(n, N_EQ) for name, a in self.eqs.items()},
        }

    def _apply(self, rec: dict[str, Any], i: int, flat: dict[str, np.ndarray]) -> None:
        self._blank_rows(np.array([i]), flat)  # the record is all the table holds of i
        flat["status"][i] = STATUS[rec["status"]]
        flat["message"][i] = rec.get("message", "")
        runs = rec.get("runs", {})
        for j, init in enumerate(self.spec.initials):
            run = runs.get(init)
            if run is None:
                if rec["status"] == "failed":  # the point failed before this start ran
                    flat["regime"][i, j] = REGIMES["failed"]
                continue
            flat["regime"][i, j] = REGIMES[run["regime"]]
            flat["caveat"][i, j] = CAVEATS[run.get("caveat") or ""]
            for name, (_, fill, _, _) in RUN_FIELDS.items():
                v = run.get(name)
                flat[f"run:{name}"][i, j] = fill if v is None else v
        stab = rec.get("stability")
        if stab:
            for name, (_, fill, _, _) in EQ_FIELDS.items():
                vals = list(stab.get(name, []))[:N_EQ]
                row = [fill if v is None else v for v in vals] + [fill] * (N_EQ - len(vals))
                flat[f"eq:{name}"][i] = row
            eig = flat["eig"]
            k = eig.shape[-1]
            for e, row in enumerate(stab.get("eigenvalues", [])[:N_EQ]):
                for m, (re, im) in enumerate(row[:k]):
                    eig[i, e, m] = complex(re, im)
        if rec.get("coexistence") is not None:
            flat["coexistence"][i] = int(rec["coexistence"])

    def missing(self) -> np.ndarray:
        """Flat indices of the points still to compute."""
        return np.flatnonzero(self.status.ravel() == STATUS["missing"])
