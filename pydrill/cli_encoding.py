"""What the command prints, on a terminal or pipe whose encoding lacks some of its characters.

Output names units as engineers write them (N·m, kg·m², Ω, δ, ≥). Under an ASCII or Latin-1
locale (a minimal container, ``PYTHONIOENCODING=ascii``, a Windows console's code page) one
such character made ``print`` raise UnicodeEncodeError, which the command reported as an
error of the user's input (``pydrill atlas info: error: 'ascii' codec can't encode character
'\\xb7'``, exit 2) after printing half its lines. Characters the stream cannot take are
written as their plain-text spelling instead (N m, kg m2, Omega, delta, >=); any other as a
backslash escape, which loses nothing.
"""

from __future__ import annotations

import codecs
import contextlib
import sys
from collections.abc import Iterator

#: how a character the stream cannot encode is written instead
PLAIN = {
    "·": " ",
    "⋅": " ",
    "²": "2",
    "³": "3",
    "⁻": "-",
    "¹": "1",
    "⁰": "0",
    "⁶": "6",
    "—": " - ",
    "–": "-",
    "−": "-",
    "…": "...",
    "×": "x",
    "≥": ">=",
    "≤": "<=",
    "≈": "~",
    "±": "+/-",
    "→": "->",
    "←": "<-",
    "°": " deg",
    "Ω": "Omega",
    "ω": "omega",
    "δ": "delta",
    "Δ": "Delta",
    "μ": "mu",
    "µ": "u",
    "β": "beta",
    "λ": "lambda",
    "σ": "sigma",
    "ρ": "rho",
    "π": "pi",
    "∞": "inf",
    "√": "sqrt",
    "‘": "'",
    "’": "'",
    "“": '"',
    "”": '"',
    "•": "*",
    "✓": "ok",
    "✗": "x",
    "█": "#",
    "░": ".",
    "▏": "|",
}

HANDLER = "pydrill-plain"


def _plain(exc: UnicodeError) -> tuple[str, int]:
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text = exc.object[exc.start : exc.end]
    out = "".join(PLAIN.get(ch) or ch.encode("ascii", "backslashreplace").decode() for ch in text)
    return out, exc.end


codecs.register_error(HANDLER, _plain)


def _lacks_unicode(stream: object) -> bool:
    encoding = getattr(stream, "encoding", None)
    if not isinstance(encoding, str):
        return False
    try:
        return codecs.lookup(encoding).name not in {"utf-8", "utf-16", "utf-32", "utf-8-sig"}
    except LookupError:
        return False


@contextlib.contextmanager
def writable_output() -> Iterator[None]:
    """Standard output and error write what they cannot encode in plain text (``PLAIN``)
    while the block runs; as they were after it (a program that called ``cli.main`` keeps
    its own settings)."""
    changed = []
    for stream in (sys.stdout, sys.stderr):
        if _lacks_unicode(stream) and hasattr(stream, "reconfigure"):
            try:
                errors = stream.errors
                stream.reconfigure(errors=HANDLER)
            except (AttributeError, OSError, ValueError):  # closed, or not a text file
                continue
            changed.append((stream, errors))
    try:
        yield
    finally:
        for stream, errors in changed:
            with contextlib.suppress(OSError, ValueError):
                stream.reconfigure(errors=errors)
