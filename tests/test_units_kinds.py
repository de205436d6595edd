"""The quantity kinds pydrill.units reads are listed where a user looks for them (parse's
docstring, so docs/api.md, and the guide), each with its SI unit: the list is read back from
the text and checked against the conversion table and against parse itself."""

import re
from pathlib import Path

from pydrill import units

ROOT = Path(__file__).resolve().parents[1]


def _listed(text: str, quote: str) -> dict[str, str]:
    """kind -> SI unit, as written ``"kind"`` (unit) or `kind` (unit) in ``text``."""
    return dict(re.findall(quote + r"(\w+)" + quote + r"`*\s+\(([^),]+)[,)]", text))


def test_parse_lists_every_kind_with_its_si_unit():
    listed = _listed(" ".join(units.parse.__doc__.split()), '"')
    assert listed == units.SI  # every kind, none made up, each with its SI unit
    for kind, si in listed.items():
        assert units.parse(f"2.5 {si}", kind) == 2.5  # the unit named is the kind's own SI


def test_the_guide_lists_every_kind_with_its_si_unit():
    text = " ".join((ROOT / "docs" / "guide" / "real-strings.md").read_text().split())
    kinds = text[text.index("The `kind` is one of") :]
    assert _listed(kinds[: kinds.index(";")], "`") == units.SI
