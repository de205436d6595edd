"""The rules of a sweep specification's tally (``[model] tally = "well.toml"``): the file read
(relative to the spec's folder), its faults said as the spec's, and the deepest string it makes
within ``MAX_DOF`` inertias. ``spec.parse_spec`` applies them; each refusal a
:class:`SpecError` naming the key."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .file_kinds import misplaced
from .spec_rules import MAX_DOF, TextTooLong, _fail, _is_number, in_si, printable, read_text


def _read_tally(tally_path: Any, base: Path | None) -> str:
    if not isinstance(tally_path, str):
        raise _fail(
            "model.tally",
            f"{tally_path!r} is not allowed: a path to a tally file, e.g. 'well.toml'",
        )
    path = Path(tally_path)
    if not path.is_absolute() and base is not None and (base / path).exists():
        path = base / path
    shown = printable(tally_path)
    try:
        return read_text(path)
    except UnicodeDecodeError:
        message = misplaced(path, "tally", shown) or f"cannot read {shown}: not UTF-8 text"
        raise _fail("model.tally", message) from None
    except OSError as exc:
        raise _fail("model.tally", f"cannot read {shown}: {exc.strerror}") from None
    except TextTooLong as exc:
        raise _fail("model.tally", f"cannot read {shown}: {exc}") from None
    except ValueError as exc:  # a NUL in the name
        raise _fail("model.tally", f"cannot read {shown}: {exc}") from None


def _check_tally(tally_text: str) -> None:
    from .tally import TallyError, parse_tally

    try:
        parse_tally(tally_text)
    except TallyError as exc:
        raise _fail("model.tally", str(exc)) from None
    except (TypeError, AttributeError, ValueError) as exc:
        # A table or value of the wrong type that the tally's own checks miss: still the
        # tally's fault, not a traceback.
        raise _fail("model.tally", f"malformed tally: {exc}") from None


def _check_tally_size(
    tally_text: str, lump: int, depths: np.ndarray | None, where: str = "axes.depth"
) -> None:
    """The deepest string of a tally within MAX_DOF inertias, counted without building it
    (``Tally.elements``: one per ``lump`` drill-pipe joints, one per other joint)."""
    from .tally import TallyError, parse_tally

    tally = parse_tally(tally_text)
    if depths is not None:
        try:
            tally = tally.at_depth(float(depths.max()))
        except TallyError:
            return  # no drill pipe to lengthen: the corners say so
    per = {True: lump, False: 1}
    n = 1 + sum(-(-s.count // per[s.kind == "drill-pipe"]) for s in tally.sections)
    if n > MAX_DOF:
        key, where = (
            (where, f" at {depths.max():g} m") if depths is not None else ("model.tally", "")
        )
        raise _fail(
            key,
            f"the string{where} has {n} inertias with lump = {lump}, at most {MAX_DOF} are "
            "allowed: lump more drill-pipe joints (model.lump) or reduce the depth",
        )


def _fixed_depth(value: Any, tally_text: str | None, axes_doc: dict[str, Any]) -> float:
    """``[model] depth``: the bit depth of a tally string (m, or with a unit), held for the
    whole sweep; refused without a tally, beside a depth axis, or not > 0."""
    if tally_text is None:
        raise _fail(
            "model.depth",
            'needs a tally string ([model] tally = "FILE.toml"); a preset\'s length is its dof '
            "or pipes",
        )
    if "depth" in axes_doc:
        raise _fail("model.depth", "depth is also an axis: give it in one place only")
    if isinstance(value, list):  # the guide's "(or an axis: depth = [...])" read as here
        raise _fail(
            "model.depth",
            f"{value!r} is not allowed: one depth, held for the whole sweep; for several, make "
            "depth an axis: [axes] depth = [...]",
        )
    depth = in_si("model.depth", "depth", value)
    if not _is_number(depth) or not 0 < depth < math.inf:
        raise _fail("model.depth", f"{value!r} is not allowed: a depth > 0 (m, or '3000 ft')")
    return float(depth)


def _check_lists(over: dict[str, Any], dof: int) -> None:
    """[model]'s inertias, stiffnesses or dampings against a tally's string of ``dof``
    inertias: a list of another length said "stiffnesses has 321 entries: dof = 2 needs 1" of
    inertias = [a, b], naming a list the spec did not give (as --inertias did)."""
    for key in ("inertias", "stiffnesses", "dampings"):
        need = dof - (key != "inertias")
        given = len(over.get(key, ()))
        if key in over and given != need:
            raise ValueError(
                f"{key} has {given} value{'' if given == 1 else 's'}, but the tally's string "
                f"has {dof} inertias: give {need} (one per "
                f"{'inertia' if key == 'inertias' else 'link'}; dof sets how many), or leave "
                f"{key} out"
            )
