"""What ``map --check`` and ``window --check`` do with a check whose simulation failed (a
``SolverError``: the step limit, the chattering guard): as ``pydrill sweep`` does with a failed
point, it is recorded as "failed" with its message (which point, and the ``pydrill simulate``
line that runs it alone, from :func:`~pydrill.cli_options.check_failed`) and the other checks
go on. One failure aborted the whole command, and every other check of up to 1600 was lost.

The exit status follows the sweep's: 0 when some checks were computed (the failures counted on
stderr), 3 (a solver failure) when every check failed, after the command's output."""

from __future__ import annotations

import sys

from .atlas_schema import FAILED  # the outcome (regime) of a check whose simulation failed

#: the failures listed in the text output; the rest are counted ("... and 12 more")
SHOWN = 5


def failure_lines(messages: list[str], shown: int = SHOWN) -> list[str]:
    """The text output's lines on the failed checks, after the tally of outcomes: the first
    ``shown`` messages whole, then how many more there are."""
    lines = [f"  {m}" for m in messages[:shown]]
    if len(messages) > shown:
        lines.append(f"  ... and {len(messages) - shown} more (--json gives each one's message)")
    return lines


def say_failed_checks(command: str, messages: list[str], total: int, json: bool) -> None:
    """After the output of ``pydrill command``: how many of its ``total`` checks failed, on
    stderr (nothing when none did). When every one failed, a ``SolverError`` saying so, with
    the first failure's message: the command then ends with exit status 3, as a sweep whose
    every point failed (none of its --check is a result; the analysis printed before it is)."""
    n = len(messages)
    if not n:
        return
    if n == total:
        from . import SolverError

        raise SolverError(
            f"every check failed ({n} of {total}), so none of them is a result; the first: "
            f"{messages[0]}"
        )
    where = (
        f'each one\'s entry says "{FAILED}", with its message; the first: {messages[0]}'
        if json
        else "listed in the output with their messages"
    )
    sys.stderr.write(
        f"pydrill {command}: {n} of {total} checks failed and are counted as {FAILED} ({where})\n"
    )
    sys.stderr.flush()
