"""The "did you mean …?" of a message that refuses a name: a key in a spec or a tally, a
parameter, a ``--set`` name. A typo is the commonest reason a name is unknown, and the list
of allowed names that the message gives as well is long."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def did_you_mean(name: object, choices: Iterable[str]) -> str:
    """``" (did you mean 'torque'?)"`` for ``name`` within a typo or two of one of
    ``choices`` (the closest), else ``""``."""
    close = difflib.get_close_matches(str(name), list(choices), n=1, cutoff=0.7)
    return f" (did you mean {close[0]!r}?)" if close else ""
