"""A sweep spec written back as TOML text, with one axis's values replaced: the spec of an
atlas made from others (``atlas_merge``), which must read back as the same sweep but that
axis. Python reads TOML (``tomllib``) but does not write it; a spec holds only tables of
strings, numbers, booleans, lists and inline tables, which this writes."""

from __future__ import annotations

import json
import math
import re
import textwrap
import tomllib
from typing import Any

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")
# What TOML refuses in a comment: the control characters but tab (textwrap has made the
# whitespace ones blanks already). A part's file name holding one (an escape sequence, a DEL)
# made the merged spec text that tomllib refused.
_NOT_IN_COMMENT = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")


def key(name: str) -> str:
    """A TOML key: bare where TOML allows it, else quoted."""
    return name if _BARE.match(name) else value(name)


def value(v: Any) -> str:
    """A TOML value of what ``tomllib`` reads a spec's values as."""
    if isinstance(v, bool):  # before int: True is an int too
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # shortest digits that read back as the same double
    if isinstance(v, str):
        # JSON's escapes are TOML's (quote, backslash, newline, a backslash-u and four hex
        # digits); DEL is a control character TOML refuses in a basic string and JSON leaves
        # as it is.
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, list):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"a spec holds no {type(v).__name__} value: {v!r}")


def with_axis(text: str, axis: str, values: list[Any], header: str = "") -> str:
    """The spec ``text`` with ``[axes] axis`` set to ``values`` (the other keys as they read;
    the comments are not kept), after ``header`` as a comment."""
    doc = tomllib.loads(text)
    doc["axes"][axis] = values
    lines = [
        "# " + _NOT_IN_COMMENT.sub(lambda m: f"\\x{ord(m[0]):02x}", line)
        for line in textwrap.wrap(header, 88)
    ]
    for section, table in doc.items():
        if lines:
            lines.append("")
        lines.append(f"[{key(section)}]")
        lines.extend(f"{key(k)} = {value(v)}" for k, v in table.items())
    return "\n".join(lines) + "\n"
