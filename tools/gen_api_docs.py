"""Write docs/api.md, the API reference, from the docstrings of ``pydrill.__all__``.

    python tools/gen_api_docs.py           # rewrite docs/api.md
    python tools/gen_api_docs.py --check   # exit 1 if docs/api.md is out of date

Standard library only (``inspect``). ``tests/test_docs.py`` regenerates the page and compares,
so the reference cannot drift from the code: change a docstring or ``__all__``, run this.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import re
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "api.md"

#: Sections of the page, in order; a public name in none of them lands in "Other".
GROUPS: list[tuple[str, str, list[str]]] = [
    (
        "Simulating one operating point",
        "The guide: [Simulating](guide/simulate.md).",
        [
            "simulate",
            "SimulationResult",
            "Summary",
            "Switch",
            "SolverStats",
            "REGIMES",
            "MODES",
            "MAX_T_END",
            "SolverError",
        ],
    ),
    (
        "Strings",
        "Presets, explicit chains and pipe tallies. The guide: "
        "[Real strings](guide/real-strings.md).",
        ["preset", "PRESETS", "Params", "Tally", "load_tally", "TallyError"],
    ),
    (
        "Steady states",
        "",
        ["equilibrium_velocities", "equilibrium_torque"],
    ),
    (
        "Stability",
        "The guide: [Stability and bifurcations](guide/stability.md).",
        ["stability"],
    ),
    (
        "Sweeps",
        "The guide: [Sweeps and atlases](guide/sweeps.md).",
        [
            "load_spec",
            "parse_spec",
            "SweepSpec",
            "SpecError",
            "run_sweep",
            "SweepReport",
            "plan_sweep",
            "SweepPlan",
            "SweepInterrupted",
            "SchedulerError",
            "ClusterInfo",
        ],
    ),
    (
        "Atlases",
        "The guide: [Sweeps and atlases](guide/sweeps.md).",
        ["Atlas", "SafeRow", "AtlasError", "CoordinateError"],
    ),
    (
        "Units",
        "",
        ["units"],
    ),
]


def _rst_to_md(text: str) -> str:
    """The little reStructuredText our docstrings use, as Markdown."""
    text = re.sub(r":(?:func|class|meth|data|attr|mod):`~?([^`]+)`", r"`\1`", text)
    text = re.sub(r"``([^`]+)``", r"`\1`", text)
    out: list[str] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.lstrip().startswith(">>>"):  # a doctest: as a text block (run by pytest)
            out.append("```text")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append("```")
            continue
        if line.rstrip().endswith("::"):  # a literal block follows
            head = line.rstrip()[:-2].rstrip()
            out.append(head + ":" if head else "")
            i += 1
            block: list[str] = []
            while i < len(lines) and (not lines[i].strip() or lines[i].startswith((" ", "\t"))):
                block.append(lines[i])
                i += 1
            while block and not block[-1].strip():
                block.pop()
            while block and not block[0].strip():
                block.pop(0)
            indent = min(len(s) - len(s.lstrip()) for s in block if s.strip())
            out += ["", "```text", *(s[indent:] for s in block), "```", ""]
            continue
        out.append(line)
        i += 1
    return "\n".join(out).strip()


def _annotation(ann: Any) -> str:
    if ann is inspect.Parameter.empty:
        return ""
    if isinstance(ann, str):
        return ann
    return inspect.formatannotation(ann)


def signature(obj: Any, name: str) -> str:
    """``name(a: float, *, b: int = 1) -> R`` with annotations as written in the source."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return name
    parts = []
    star = False
    for p in sig.parameters.values():
        if p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        prefix = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
        if p.kind is p.VAR_POSITIONAL:
            star = True
        text = prefix + p.name
        ann = _annotation(p.annotation)
        if ann:
            text += f": {ann}"
        if p.default is not inspect.Parameter.empty:
            text += f" = {p.default!r}" if ann else f"={p.default!r}"
        parts.append(text)
    ret = _annotation(sig.return_annotation)
    return f"{name}({', '.join(parts)})" + (f" -> {ret}" if ret else "")


def _field_comments(cls: type) -> dict[str, str]:
    """The ``#:`` comments on a dataclass's fields (units, meanings)."""
    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):
        return {}
    return _comments(source, r"(\w+):[^#\n=]*(?:=[^#\n]*)?")


def _comments(source: str, target: str) -> dict[str, str]:
    """``#:`` comments of the names ``target`` matches at the start of a line (its group 1):
    after it on the same line, or on the ``#:`` lines just above it (Sphinx's two forms)."""
    found: dict[str, str] = {}
    above: list[str] = []
    for line in source.splitlines():
        stripped = line.strip()
        if stripped.startswith("#:"):
            above.append(stripped[2:].strip())
            continue
        m = re.match(rf"\s*{target}\s*(?:#:\s*(.+))?$", line)
        if m and (above or m.group(2)):
            found.setdefault(m.group(1), " ".join([*above, m.group(2) or ""]).strip())
        above = []
    return found


def _attribute_comments(cls: type) -> dict[str, tuple[str, str]]:
    """The documented attributes ``__init__`` sets (``self.x: T = ...  #: meaning``, or the
    ``#:`` lines above), with their annotations."""
    init = vars(cls).get("__init__")
    if not inspect.isfunction(init):
        return {}
    try:
        source = inspect.getsource(init)
    except (OSError, TypeError):
        return {}
    types = dict(re.findall(r"^\s*self\.(\w+):\s*([^=#\n]+?)\s*=", source, re.M))
    notes = _comments(source, r"self\.(\w+)(?::[^=#\n]+)?\s*=[^#\n]*")
    return {name: (types.get(name, ""), note) for name, note in notes.items()}


def _doc(obj: Any) -> str:
    doc = inspect.getdoc(obj)
    if doc and inspect.isclass(obj) and doc.startswith(obj.__name__ + "("):
        doc = None  # the signature dataclasses write when there is no docstring
    return _rst_to_md(doc) if doc else "*(no docstring)*"


def _members(cls: type) -> list[tuple[str, Any]]:
    out = []
    for name, value in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(
            value, (property, functools.cached_property, staticmethod, classmethod)
        ) or inspect.isfunction(value):
            out.append((name, value))
    return out


def render_class(qual: str, cls: type, level: int) -> list[str]:
    h = "#" * level
    lines: list[str] = []
    if issubclass(cls, BaseException):
        bases = ", ".join(b.__name__ for b in cls.__bases__)
        lines += [
            f"{h} `{qual}`",
            "",
            f"```text\nexception {qual}({bases})\n```",
            "",
            _doc(cls),
            "",
        ]
        return lines
    init_sig = signature(cls, qual).removesuffix(" -> None")
    lines += [f"{h} `{qual}`", "", f"```text\nclass {init_sig}\n```", "", _doc(cls), ""]
    if dataclasses.is_dataclass(cls):
        comments = _field_comments(cls)
        fields = [f for f in dataclasses.fields(cls) if f.repr or f.name in comments]
        lines += ["| field | type | meaning |", "|---|---|---|"]
        for f in fields:
            ann = f.type if isinstance(f.type, str) else _annotation(f.type)
            note = _rst_to_md(comments.get(f.name, "")).replace("|", "\\|")
            # GitHub's tables split a row at every "|", code spans too: `int \| None`
            ann = ann.replace("|", "\\|")
            lines.append(f"| `{f.name}` | `{ann}` | {note} |")
        lines.append("")
    attributes = _attribute_comments(cls)
    if attributes:
        lines += ["| attribute | type | meaning |", "|---|---|---|"]
        for name, (ann, note) in attributes.items():
            note = _rst_to_md(note).replace("|", "\\|")
            ann = ann.replace("|", "\\|")  # as the fields' above
            lines.append(f"| `{name}` | `{ann}` | {note} |")
        lines.append("")
    for name, member in _members(cls):
        if isinstance(member, (property, functools.cached_property)):
            fget = member.fget if isinstance(member, property) else member.func
            ret = _annotation(inspect.signature(fget).return_annotation)
            head = f"property {qual}.{name}" + (f" -> {ret}" if ret else "")
            doc = _doc(fget)
        else:
            func = member.__func__ if isinstance(member, (staticmethod, classmethod)) else member
            sig = signature(func, f"{qual}.{name}").replace("(self, ", "(").replace("(self)", "()")
            sig = sig.replace("(cls, ", "(").replace("(cls)", "()")
            head = sig
            doc = _doc(func)
        lines += [f"- `{head}`", "", "  " + doc.replace("\n", "\n  ").replace("\n  \n", "\n\n"), ""]
    return lines


def render_function(qual: str, func: Any, level: int) -> list[str]:
    h = "#" * level
    return [f"{h} `{qual}`", "", f"```text\n{signature(func, qual)}\n```", "", _doc(func), ""]


def render_constant(qual: str, value: Any, level: int, comment: str = "") -> list[str]:
    h = "#" * level
    lines = [f"{h} `{qual}`", "", f"```text\n{qual} = {value!r}\n```", ""]
    if comment:
        lines += [comment, ""]
    return lines


def render_module(qual: str, module: Any, level: int) -> list[str]:
    h = "#" * level
    lines = [f"{h} `{qual}`", "", _doc(module), ""]
    names = getattr(module, "__all__", None) or [
        n
        for n, v in vars(module).items()
        if not n.startswith("_")
        and (inspect.isfunction(v) or inspect.isclass(v))
        and getattr(v, "__module__", "") == module.__name__
    ]
    for name in names:
        lines += render_object(f"{qual}.{name}", getattr(module, name), level + 1)
    return lines


def render_object(qual: str, obj: Any, level: int) -> list[str]:
    if inspect.ismodule(obj):
        return render_module(qual, obj, level)
    if inspect.isclass(obj):
        return render_class(qual, obj, level)
    if callable(obj):
        return render_function(qual, obj, level)
    return render_constant(qual, obj, level, CONSTANTS.get(qual, ""))


CONSTANTS = {
    "pydrill.REGIMES": "The regimes `simulate` can judge (`SimulationResult.regime`).",
    "pydrill.PRESETS": "The names `preset` accepts (DESIGN.md §4).",
    "pydrill.MODES": "The bit's friction modes: the codes of `SimulationResult.mode_index`.",
    "pydrill.MAX_T_END": "The longest simulated time `simulate` takes (s).",
}


def render_page() -> str:
    import pydrill

    public = list(pydrill.__all__)
    placed = {n for _, _, names in GROUPS for n in names}
    groups = [*GROUPS]
    rest = [n for n in public if n not in placed]
    if rest:
        groups.append(("Other", "", rest))
    lines = [
        "# API reference",
        "",
        "<!-- Generated by tools/gen_api_docs.py from the docstrings; do not edit by hand. -->",
        "",
        "Everything `import pydrill` exports (`pydrill.__all__`), with its signature and "
        "docstring. Units are SI throughout (N, N·m, rad/s, s, kg·m²) unless a name says "
        "otherwise. Start with the [user guide](index.md) for worked examples.",
        "",
    ]
    lines += ["Contents:", ""]
    for title, _, names in groups:
        present = [n for n in names if n in public]
        if present:
            anchors = ", ".join(f"`{n}`" for n in present)
            lines.append(f"- {title}: {anchors}")
    lines.append("")
    for title, intro, names in groups:
        present = [n for n in names if n in public]
        if not present:
            continue
        lines += [f"## {title}", ""]
        if intro:
            lines += [intro, ""]
        for name in present:
            lines += render_object(f"pydrill.{name}", getattr(pydrill, name), 3)
    text = "\n".join(lines)
    text = re.sub(r"\n{3,}", "\n\n", text).rstrip() + "\n"
    return text


def render() -> str:  # the name tests/test_docs.py calls
    return render_page()


def main(argv: list[str]) -> int:
    text = render()
    if "--check" in argv:
        if OUT.read_text() != text:
            print(f"{OUT} is out of date: run python tools/gen_api_docs.py", file=sys.stderr)
            return 1
        return 0
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(text)
    print(f"wrote {OUT.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
