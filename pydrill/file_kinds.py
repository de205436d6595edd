"""What a file given in the wrong place is, so that the refusal can say so.

``pydrill atlas info study.toml`` was answered "not a readable HDF5 atlas (truncated or
corrupt?): ... file signature not found", which sends the user looking for damage; the spec
is whole, it only wants ``pydrill sweep`` first. And a sweep's atlas named ``f.png`` (taken
without a word) was written over by the figure ``pydrill atlas plot f.png --out f.png`` draws
from it, the very command the sweep suggests next.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

# What matplotlib writes, by suffix (figure_path accepts exactly these for --plot/--out).
FIGURE_SUFFIXES = tuple(".png .pdf .svg .svgz .eps .ps .jpg .jpeg .tif .tiff .webp".split())

# Names an atlas must not take: pydrill (or the user's next command) writes files of these
# kinds, and a figure or export drawn from the atlas would be written over it.
OTHER_KINDS = {
    **dict.fromkeys(FIGURE_SUFFIXES, "a figure"),
    ".toml": "a sweep spec or tally (TOML)",
    ".csv": "a CSV table",
    ".json": "a JSON document",
    ".txt": "a text file",
}

# First bytes of the binary files a user is likely to hand over by mistake.
_MAGIC = (
    (b"\x89HDF\r\n\x1a\n", "an HDF5 file (an atlas?)"),
    (b"\x89PNG\r\n\x1a\n", "a PNG image"),
    (b"%PDF-", "a PDF document"),
    (b"\xff\xd8\xff", "a JPEG image"),
    (b"CDF\x01", "a netCDF-3 file"),
    (b"CDF\x02", "a netCDF-3 file"),
)
_SNIFF = 1 << 16  # a spec or tally is a few kB; a bigger text is not one of ours anyway


def what_is(path: str | Path) -> str | None:
    """``"a PNG image"``, ``"an HDF5 file (an atlas?)"``, ``"a sweep spec (TOML)"``,
    ``"a tally (TOML)"``... for a file of a kind pydrill recognises; None for anything else
    (or a file that cannot be read), where the caller's own words stand."""
    try:
        with open(path, "rb") as f:
            head = f.read(_SNIFF + 1)
    except OSError:
        return None
    for magic, kind in _MAGIC:
        if head.startswith(magic):
            return kind
    if len(head) > _SNIFF:
        return None
    try:
        data = tomllib.loads(head.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError):
        return None
    # The tables only a spec has, and a tally's [[section]] list (spec / tally_parse).
    if isinstance(data.get("axes"), dict) or isinstance(data.get("simulation"), dict):
        return "a sweep spec (TOML)"
    if isinstance(data.get("section"), list):
        return "a tally (TOML)"
    return None


def atlas_name_problem(out: Path) -> str | None:
    """Why a *new* atlas must not be called ``out`` (None if it may): a name that says it is
    another kind of file. An existing file keeps the rules for existing files."""
    kind = OTHER_KINDS.get(out.suffix.lower())
    if kind is None:
        return None
    return (
        f"{out}: a name ending {out.suffix} is taken for {kind}, not an atlas (a figure or "
        f"export drawn from it could be written over it); give out=PATH a name ending .h5"
    )


# What each reader wants, what its own kind is called, and what to do with each kind of file
# given to it instead.
_WANTED = {"atlas": "an atlas", "spec": "a sweep spec", "tally": "a pipe tally"}
_OWN = {"atlas": "an HDF5", "spec": "a sweep spec", "tally": "a tally"}
_INSTEAD = {
    ("atlas", "a sweep spec (TOML)"): "make an atlas from it with "
    "'pydrill sweep {} --out ATLAS.h5'",
    ("spec", "an HDF5 file (an atlas?)"): "'pydrill atlas info {}' reads an atlas",
    ("spec", "a tally (TOML)"): 'a spec names it under [model] as tally = "{name}"; '
    "'pydrill window {} --depth DEPTH' reads it",
    ("tally", "a sweep spec (TOML)"): "run it with 'pydrill sweep {} --out ATLAS.h5'",
}


def misplaced(path: str | Path, wanted: str, shown: str | None = None) -> str | None:
    """The refusal for a whole file of another kind given where ``wanted`` (``"atlas"``,
    ``"spec"`` or ``"tally"``) is read, with what to do with it instead; None when the file is
    not of a kind recognised, or is of the kind wanted (then its own faults are the news)."""
    kind = what_is(path)
    if kind is None or kind.startswith(_OWN[wanted]):
        return None
    shown = str(path) if shown is None else shown
    message = f"{shown} is {kind}, not {_WANTED[wanted]}"
    todo = _INSTEAD.get((wanted, kind))
    if todo:
        message += ": " + todo.format(shown, name=Path(path).name)
    return message
