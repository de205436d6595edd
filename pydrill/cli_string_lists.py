"""``--inertias``, ``--stiffnesses``, ``--dampings``: the chain's lists given value by value,
for every command that builds one string from ``--preset`` or ``--tally`` (simulate, and the
analyses of the string it simulated: hopf, stability, bifurcation, map). One definition, so
that each command takes, refuses and echoes them alike."""

from __future__ import annotations

import argparse
from typing import Any

from .cli_options import _list
from .model import _LISTS

#: the unit of each list, as ``pydrill string --json`` gives them
LIST_UNITS = {"inertias": "kg·m2", "stiffnesses": "N·m/rad", "dampings": "N·m·s/rad"}


def add_list_options(group: Any) -> None:
    """The three options, into ``group`` (the command's "string" group of ``_string_options``)."""
    group.add_argument(
        "--inertias",
        type=_list("--inertias"),
        metavar="I0,I1,...",
        help="override every inertia (kg m^2, each > 0), top drive first; without --dof "
        "their number is the dof, with it they must agree",
    )
    group.add_argument(
        "--stiffnesses",
        type=_list("--stiffnesses"),
        metavar="K0,...",
        help="override every spring stiffness (N m/rad, each > 0), one fewer than the inertias",
    )
    group.add_argument(
        "--dampings",
        type=_list("--dampings"),
        metavar="C0,...",
        help="override every spring damping (N m s/rad, each >= 0), one per spring",
    )


def list_overrides(args: argparse.Namespace) -> dict[str, list[float]]:
    """The lists given, ``{name: values}``, for ``string_params``'s overrides and the echo of
    ``--json`` (none for a command without the options)."""
    return {key: v for key in _LISTS if (v := getattr(args, key, None)) is not None}


def list_refused(exc: ValueError, overrides: dict[str, Any]) -> ValueError | None:
    """``exc`` naming the option when it refuses one of the lists given (the API's "inertias
    has 2 entries", "inertias[1] = -2 is not allowed" named no option); None if it is about
    something else."""
    message = str(exc)
    for key in overrides:
        if message.startswith((f"{key} ", f"{key}[")):
            return type(exc)(f"--{message}")
    return None
