"""One line for a file the operating system would not read or write, naming the option that
led to it (``--plot /proc/x.png: No such file or directory``), not ``[Errno 2] ...``."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path


def os_error_message(exc: OSError, argv: Sequence[str]) -> str:
    """A one-line message for a file that could not be read or written: the option that named
    it (``--plot /proc/x.png: No such file or directory``), not ``[Errno 2] ...``."""
    path = exc.filename
    if path is None or not exc.strerror:
        return str(exc)
    path = os.fsdecode(path)
    reason = exc.strerror
    in_the_way = (
        isinstance(exc, FileExistsError) and Path(path).exists() and not Path(path).is_dir()
    )
    if in_the_way:
        reason = "a file of that name exists; give a folder"
    for k, token in enumerate(argv):
        option, eq, value = token.partition("=")
        if not (eq and option.startswith("--")):
            option, value = (argv[k - 1], token) if k else ("", "")
        if not option.startswith("--"):
            continue
        where = _same_path(value, path)
        if where == "same":
            return f"{option} {path}: {reason}"
        if where == "inside":
            # A file the command makes inside the folder given (reproduce's DIR/cache): the
            # option and what was typed first, then what is in the way there.
            if in_the_way:
                return (
                    f"{option} {value}: {path} is a file where pydrill keeps a folder; "
                    f"move it away or give another {option}"
                )
            return f"{option} {value}: cannot write {path}: {reason}"
    return f"{path}: {reason}"


def _same_path(given: str, path: str) -> str | None:
    """Whether the command line's ``given`` is ``path`` ("same"), a folder it lies in
    ("inside"), or neither (None)."""
    try:
        a, b = Path(given).absolute(), Path(path).absolute()
    except (OSError, ValueError):
        return None
    return "same" if a == b else "inside" if a in b.parents else None
