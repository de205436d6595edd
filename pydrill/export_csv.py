"""An atlas as a CSV table, a block of rows at a time: the eigenvalues and steady states left
out, each code's name beside it. The cells are made by ``_core.csv_rows`` (the text pandas'
``to_csv`` writes, byte for byte, ten times faster: 10^6 points took a minute)."""

from __future__ import annotations

import csv
import io
from typing import Any

import numpy as np

#: lines of text made at a time: a block's whole text (130,000 lines, 40 MB, and its copy as
#: bytes) raised an export's peak memory by a quarter
LINES = 16384


def write_csv(ds, fh, first: str, rows: int, bar: Any) -> int:
    """``ds`` as a CSV table into the binary file ``fh``, ``rows`` rows of the axis ``first``
    at a time, ``bar`` moved by each block's points; the table's rows (the header aside)."""
    from ._core import csv_rows
    from .atlas import COUNT_FIELDS

    keep = [
        v
        for v in ds.data_vars
        if "eigenvalue" not in ds[v].dims
        and "equilibrium" not in ds[v].dims
        and (ds[v].dtype.kind != "O" or v == "message")
    ]
    ds = ds[keep]
    dims = list(ds.dims)  # the table's row order, as to_dataframe takes it
    per_row = bar.total // ds.sizes[first]  # points
    assert dims[0] == first, dims  # blocks of the first axis are blocks of the table's rows
    lines = 0
    for start in range(0, ds.sizes[first], rows):
        table = ds.isel({first: slice(start, start + rows)}).load().to_dataframe(dims)
        for name in COUNT_FIELDS:  # counts as integers, an empty cell where not measured
            if name in table:
                table[name] = table[name].astype("Int64")
        name_codes(table)
        table = table.reset_index()  # the axes are the first columns, as to_csv writes them
        if start == 0:
            fh.write(_line([str(c) for c in table.columns]).encode("utf-8"))
        columns = [_column(table[c]) for c in table.columns]
        for lo in range(0, len(table), LINES):  # its text a few MB at a time
            part = [_rows(col, lo, lo + LINES) for col in columns]
            fh.write(csv_rows(part, min(LINES, len(table) - lo)))
        bar.update((min(start + rows, ds.sizes[first]) - start) * per_row)
        lines += len(table)
    return lines


def _line(fields: list[str]) -> str:
    """One CSV line of ``fields``, quoted as Python's csv module (and so pandas) quotes."""
    text = io.StringIO()
    csv.writer(text, lineterminator="\n").writerow(fields)
    return text.getvalue()


def _quoted(label: str) -> str:
    """A cell's text as it goes into a line of several cells ("" stays empty: csv quotes an
    empty field only when it is a row's one field)."""
    return _line([label])[:-1] if label else ""


def _column(series) -> tuple[str, Any]:
    """A column of the table as ``_core.csv_rows`` takes it, written as pandas writes it."""
    import pandas as pd

    dtype = series.dtype
    if dtype == np.float64:
        return "float", series.to_numpy()
    if isinstance(dtype, pd.Int64Dtype):  # counts; NA an empty cell
        return "count", series.to_numpy(dtype=np.float64, na_value=np.nan)
    if dtype.kind in "iu" and dtype != np.uint64:
        return "int", series.to_numpy().astype(np.int64)
    if dtype.kind == "b":
        return "text", (series.to_numpy().astype(np.int64), ["False", "True"])
    if dtype.kind == "f":  # float32, float16: as numpy prints them ("0.1", not 0.100000001)
        series = series.astype(str).where(series.notna())
    codes, labels = pd.factorize(series, use_na_sentinel=True)  # missing: -1, an empty cell
    return "text", (codes.astype(np.int64), [_quoted(str(v)) for v in labels])


def _rows(column: tuple[str, Any], lo: int, hi: int) -> tuple[str, Any]:
    """Rows ``lo`` ... ``hi - 1`` of a column as :func:`_column` makes it."""
    kind, values = column
    if kind == "text":
        codes, labels = values
        return kind, (codes[lo:hi], labels)
    return kind, values[lo:hi]


def name_codes(table) -> None:
    """Put beside each coded column of an exported table (a DataFrame) its names: regime_name,
    caveat_name ("none" without one), status_name and coexistence_name ("unknown" with one
    start or a point not done), each right after its codes."""
    from . import atlas_format as fmt

    names = {
        "regime": fmt.REGIME_NAMES,
        "caveat": {c: n or "none" for c, n in fmt.CAVEAT_NAMES.items()},
        "status": {c: n for n, c in fmt.STATUS.items()},
        "coexistence": {c: n for n, c in fmt.COEXISTENCE.items()},  # its flag_meanings
    }
    for column, meaning in names.items():
        if column not in table:
            continue
        # A dict, not a function: pandas looks the codes up at once (a function, called for
        # each of 2 million rows, took 8 of an export's 60 s); a code without a name: "?"
        named = table[column].map(meaning).fillna("?")
        table.insert(table.columns.get_loc(column) + 1, f"{column}_name", named)
