"""The documentation runs: every snippet of README.md and docs/**/*.md is executed here.

What runs, page by page, in a fresh temporary directory per page (holding links to the
repository's ``examples/`` and ``sweeps/``), in the order of the page:

- ```python blocks: ``>>>`` blocks through :mod:`doctest` (ELLIPSIS, NORMALIZE_WHITESPACE);
  other blocks are executed in a fresh namespace. A plain ``` block right after a python
  block is its expected output.
- ```console / ```bash blocks: every ``$ pydrill …`` line (in ```bash blocks without ``$``,
  every ``pydrill …`` line) through the CLI; it must exit with status 0, the lines shown after
  it must appear in its output in that order, and the files it was asked to write
  (``--plot``, ``--out``) must exist. Any other command makes the block unrunnable: it must
  be marked.
- ```toml blocks are parsed; a tally or a sweep spec is checked by pydrill's own parser.
- ```cpp (with the ```cmake lines of the same page) are compiled against the installed C++
  library, when the CMake build tree ``build/`` exists.

Markers (an HTML comment on the line(s) right before a block; invisible on the page):

- ``<!-- skip-test: why -->``: not run; reported as a skipped test with the reason.
- ``<!-- write-file: NAME -->``: the block's text is written to ``NAME`` in the page's
  directory before anything after it runs (a spec shown on the page is the spec it runs).

Comparing shown output: the lines shown are the output's lines, whole, in order and none left
out, from its first line to its last (blank lines aside). A line of ``...`` stands for any
number of lines (the only way to leave lines out), ``...`` within a line for anything there;
whitespace is ignored, and a number matches within one unit of its last shown digit
(``67.12`` accepts 67.11 … 67.13), a whole number exactly (a count: ``6`` is not 7). So
machine-dependent figures (wall times) are written as ``...`` and everything else must be
what pydrill prints. A command shown without output is
run, its output not compared.
"""

from __future__ import annotations

import contextlib
import doctest
import functools
import importlib.util
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
GUIDE = [
    "index.md",
    "api.md",
    *(f"guide/{p}.md" for p in ("simulate", "stability", "sweeps", "real-strings", "cpp")),
]
LINKED = ("examples", "sweeps")  # repository folders the snippets refer to
SHELL = {"console", "bash", "sh", "shell"}
PYTHON = {"python", "py", "pycon"}
TEXT = {"", "text", "output", "json"}
KNOWN = SHELL | PYTHON | TEXT | {"toml", "cpp", "c++", "cmake"}
OPERATORS = {"|", "||", "&&", ";", ">", ">>", "<", "&"}
MARKER = re.compile(r"^\s*<!--\s*(skip-test|write-file)\s*:?\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(`{3,}|~{3,})\s*([\w+-]*)[^`]*$")


@dataclass
class Block:
    page: Path
    line: int  # 1-based line of the opening fence
    lang: str
    text: str
    markers: dict[str, str] = field(default_factory=dict)
    output: Block | None = None  # the plain block right after a python block

    @property
    def where(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"


def parse_blocks(page: Path) -> list[Block]:
    """Every fenced block of a Markdown page, with the markers right before it."""
    lines = page.read_text().splitlines()
    blocks: list[Block] = []
    markers: dict[str, str] = {}
    previous_end = -10  # line index where the last block closed
    i = 0
    while i < len(lines):
        fence = FENCE.match(lines[i])
        marker = MARKER.match(lines[i])
        if marker:
            markers[marker.group(1)] = marker.group(2)
        elif fence:
            indent, ticks, lang = fence.group(1), fence.group(2), fence.group(3).lower()
            body = []
            j = i + 1
            while j < len(lines) and not (
                lines[j].strip().startswith(ticks[0] * len(ticks))
                and lines[j].strip().strip(ticks[0]) == ""
            ):
                line = lines[j]
                body.append(line[len(indent) :] if line.startswith(indent) else line.lstrip())
                j += 1
            block = Block(page, i + 1, lang, "\n".join(body) + "\n", markers)
            between = lines[previous_end + 1 : i]
            if (
                blocks
                and lang in ("", "text", "output")
                and blocks[-1].lang in PYTHON
                and not markers
                and all(not s.strip() for s in between)
            ):
                blocks[-1].output = block
            else:
                blocks.append(block)
            markers = {}
            previous_end = j
            i = j
        elif lines[i].strip():
            markers = {}  # a marker must sit right before its block
        i += 1
    return blocks


# --- comparing shown output with what ran --------------------------------------------------

_TOKEN = re.compile(r"\.\.\.|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|\S")


def _tokens(line: str) -> list[str]:
    return _TOKEN.findall(line)


def _number(token: str) -> tuple[float, float] | None:
    """The value of a numeric token and one unit of its last digit."""
    if not token or not (token[-1].isdigit() or token[-1] == "."):
        return None
    try:
        value = float(token)
    except ValueError:
        return None
    mantissa, _, exponent = token.lower().partition("e")
    if "." not in mantissa and not exponent:
        # A whole number is a count (points, events, switches) or printed whole: exact, or
        # "(6 of 11 points)" would also accept 7.
        return value, 0.0
    decimals = len(mantissa.partition(".")[2])
    return value, 10.0 ** (int(exponent or 0) - decimals)


def _same(shown: str, actual: str) -> bool:
    if shown == actual:
        return True
    a, b = _number(shown), _number(actual)
    return a is not None and b is not None and abs(a[0] - b[0]) <= 1.0001 * a[1]


def line_matches(shown: str, actual: str, whole: bool = False) -> bool:
    """``shown`` (with ``...`` wildcards) appears in ``actual``, whitespace ignored; with
    ``whole``, it is all of ``actual``."""
    s, a = _tokens(shown), _tokens(actual)

    def match(si: int, ai: int) -> bool:
        while si < len(s):
            if s[si] == "...":
                return any(match(si + 1, k) for k in range(ai, len(a) + 1))
            if ai >= len(a) or not _same(s[si], a[ai]):
                return False
            si, ai = si + 1, ai + 1
        return not whole or ai == len(a)

    return match(0, 0) if whole else any(match(0, start) for start in range(len(a) + 1))


def check_shown(shown: str, actual: str, what: str) -> None:
    """The output a page shows is ``actual``, line for line (see the module's docstring): a
    line of ``...`` is the only way to leave lines out. Nothing shown: nothing to compare."""
    want = [x for x in shown.splitlines() if x.strip()]
    have = [x for x in actual.splitlines() if x.strip()]
    if not want:
        return

    @functools.cache
    def fits(i: int, k: int) -> bool:  # want[i:] is have[k:]
        if i == len(want):
            return k == len(have)
        if want[i].strip() == "...":
            return any(fits(i + 1, j) for j in range(k, len(have) + 1))
        return k < len(have) and line_matches(want[i], have[k], whole=True) and fits(i + 1, k + 1)

    if fits(0, 0):
        return
    absent = [
        x
        for x in want
        if x.strip() != "..." and not any(line_matches(x, y, whole=True) for y in have)
    ]
    why = (
        f"the documented line\n    {absent[0].strip()}\nis no whole line of the output"
        if absent
        else "its lines are all there, but some are out of order, or lines of the output are "
        "left out without a line of '...' in their place"
    )
    raise AssertionError(
        f"{what}: {why}\nshown:\n"
        + "\n".join("    " + x for x in want)
        + "\noutput:\n"
        + "\n".join("    " + x for x in have)
    )


def check_output(shown: str, actual: str, what: str) -> None:
    """Every shown line appears in ``actual``, in the same order (a C++ snippet's
    ``// prints:`` comment, a part of a line)."""
    lines = actual.splitlines()
    at = 0
    for expected in shown.splitlines():
        if not expected.strip() or expected.strip() == "...":
            continue
        for k in range(at, len(lines)):
            if line_matches(expected, lines[k]):
                at = k + 1
                break
        else:
            raise AssertionError(
                f"{what}: the documented line\n    {expected.strip()}\nis not in the output "
                f"(after line {at}):\n" + "\n".join("    " + x for x in lines)
            )


# --- running blocks --------------------------------------------------------------------------


@dataclass
class Command:
    argv: list[str]
    shown: str  # the output lines written under it


def shell_commands(block: Block) -> list[Command]:
    lines = block.text.splitlines()
    prompted = any(line.startswith("$ ") for line in lines)
    commands: list[Command] = []
    pending = ""
    for line in lines:
        if prompted and not line.startswith("$ ") and not pending:
            if commands:
                commands[-1].shown += line + "\n"
            continue
        text = line[2:] if prompted and not pending else line
        if not pending and (not text.strip() or text.lstrip().startswith("#")):
            continue
        pending += text.rstrip()
        if pending.endswith("\\"):
            pending = pending[:-1] + " "
            continue
        commands.append(Command(shlex.split(pending, comments=True), ""))
        pending = ""
    return commands


def unrunnable(command: Command) -> str | None:
    """Why a command cannot run here, or None."""
    argv = command.argv
    if not argv or not (argv[0] == "pydrill" or argv[0].endswith("/pydrill")):
        return "not a pydrill command"
    if OPERATORS & set(argv):
        return "uses the shell (pipes, redirection, &&)"
    return None


def run_cli(command: Command, cwd: Path, where: str) -> None:
    argv = command.argv[1:]
    shown = " ".join(command.argv)
    proc = subprocess.run(
        [sys.executable, "-m", "pydrill", *argv],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert proc.returncode == 0, (
        f"{where}: `{shown}` exited with {proc.returncode}\n{proc.stderr}{proc.stdout}"
    )
    check_shown(command.shown, proc.stdout, f"{where}: `{shown}`")
    if argv[:1] == ["simulate"] and "note" not in command.shown:
        # A caveat on the verdict ("too short to judge the regime") is not for a "..." to hide:
        # a documented run is judged without one, or the page shows it.
        notes = [x for x in proc.stdout.splitlines() if re.match(r'\s*("note": "|note )', x)]
        assert not notes, f"{where}: `{shown}` is judged with a note the page hides: {notes}"
    for flag in ("--plot", "--out"):
        if flag in argv[:-1]:
            target = cwd / argv[argv.index(flag) + 1]
            if "--dry-run" in argv:  # names what a sweep would write, and writes nothing
                assert not target.exists(), f"{where}: `{shown}` wrote {target.name}"
                continue
            assert target.exists(), f"{where}: `{shown}` did not write {target.name}"
            assert target.is_dir() or target.stat().st_size > 0, f"{where}: {target} is empty"


def run_python(block: Block, cwd: Path) -> None:
    namespace: dict = {"__name__": "__doc__"}
    if ">>>" in block.text:
        parser = doctest.DocTestParser()
        test = parser.get_doctest(block.text, namespace, block.where, str(block.page), block.line)
        flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
        runner = doctest.DocTestRunner(optionflags=flags)
        report = io.StringIO()
        result = runner.run(test, out=report.write)
        assert result.attempted > 0, f"{block.where}: no examples in the doctest block"
        assert result.failed == 0, f"{block.where}: doctest failed\n{report.getvalue()}"
        return
    code = compile(block.text, block.where, "exec")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(code, namespace)
    if block.output is not None:
        check_shown(block.output.text, printed.getvalue(), f"{block.where} (its printed output)")


def check_toml(block: Block) -> None:
    from pydrill.spec import parse_spec
    from pydrill.tally import parse_tally

    data = tomllib.loads(block.text)
    if "section" in data:
        parse_tally(block.text, name="doc")
    elif "axes" in data:
        parse_spec(block.text)


def page_dir(tmp_path: Path) -> Path:
    for name in LINKED:
        (tmp_path / name).symlink_to(ROOT / name, target_is_directory=True)
    return tmp_path


def all_blocks() -> list[Block]:
    return [b for page in PAGES for b in parse_blocks(page)]


def skipped_blocks() -> list[Block]:
    return [b for b in all_blocks() if "skip-test" in b.markers]


# --- the tests ---------------------------------------------------------------------------------


def test_the_guide_exists():
    for name in GUIDE:
        assert (ROOT / "docs" / name).is_file(), f"docs/{name} is missing"
    readme = (ROOT / "README.md").read_text()
    for name in GUIDE:
        assert f"docs/{name}" in readme, f"README.md does not link docs/{name}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_page_runs(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """Every runnable block of the page, in order, in one scratch directory."""
    cwd = page_dir(tmp_path)
    monkeypatch.chdir(cwd)
    ran = 0
    for block in parse_blocks(page):
        assert block.lang in KNOWN, (
            f"{block.where}: unknown block language {block.lang!r} (known: {sorted(KNOWN)})"
        )
        if "write-file" in block.markers:
            (cwd / block.markers["write-file"]).write_text(block.text)
        if "skip-test" in block.markers:
            assert block.markers["skip-test"], f"{block.where}: say why in <!-- skip-test: … -->"
            continue
        if block.lang in PYTHON:
            run_python(block, cwd)
            ran += 1
        elif block.lang in SHELL:
            commands = shell_commands(block)
            for command in commands:
                why = unrunnable(command)
                assert why is None, (
                    f"{block.where}: `{' '.join(command.argv)}` cannot run in the tests ({why});"
                    " mark the block <!-- skip-test: why --> or show a runnable variant"
                )
            for command in commands:
                run_cli(command, cwd, block.where)
                ran += 1
        elif block.lang == "toml":
            check_toml(block)
        elif block.lang == "json":
            import json

            json.loads(block.text)
    compiled = any(b.lang in ("cpp", "c++") for b in parse_blocks(page))  # the C++ test's
    if page.name != "api.md" and not compiled:
        assert ran > 0, f"{page.relative_to(ROOT)} has no runnable snippet"


@pytest.mark.parametrize("block", skipped_blocks(), ids=lambda b: b.where)
def test_marked_not_runnable(block: Block):
    """Listed so that every block the tests do not run shows up in the report, with why."""
    pytest.skip(f"{block.where} ({block.lang or 'text'}): {block.markers['skip-test']}")


def test_links_resolve():
    """Relative links between the pages and to repository files point at something."""
    link = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")
    for page in PAGES:
        for target in link.findall(page.read_text()):
            if "://" in target or target.startswith("mailto:"):
                continue
            assert (page.parent / target).exists(), f"{page.relative_to(ROOT)}: broken {target}"


def test_api_reference_is_current():
    spec = importlib.util.spec_from_file_location("gen_api_docs", ROOT / "tools/gen_api_docs.py")
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gen)
    current = (ROOT / "docs" / "api.md").read_text()
    assert current == gen.render(), "docs/api.md is out of date: run `python tools/gen_api_docs.py`"


def test_output_comparison_rules():
    """The comparison the page tests rely on: strict on words, one last-digit unit on
    numbers, ``...`` for anything."""
    actual = "bit velocity    min 0  max 67.12  mean 13.42 rad/s  (mean 128.1 rpm)"
    assert line_matches("bit velocity min 0 max 67.12 mean 13.42 rad/s", actual)
    assert line_matches("max 67.13", actual)
    assert not line_matches("max 67.15", actual)
    assert not line_matches("top velocity", actual)
    assert line_matches("bit ... (mean ... rpm)", actual)
    assert not line_matches("mean 13.42 rpm", actual)
    assert line_matches("delta = 1.18e-13", "delta = 1.18348e-13 N m s/rad")
    assert not line_matches("delta = 1.20e-13", "delta = 1.18348e-13 N m s/rad")
    with pytest.raises(AssertionError):
        check_output("b 2\na 1", "a 1\nb 2", "order")
    check_output("a 1\n...\nb 2", "a 1\nx\nb 2", "order")
    assert line_matches("bit velocity ... (mean ... rpm)", actual, whole=True)
    assert not line_matches("bit velocity min 0 max 67.12 mean 13.42 rad/s", actual, whole=True)
    assert not line_matches("max 67.12", actual, whole=True)
    # a whole number is a count, or printed whole: exact (a count off by one was accepted)
    assert line_matches("(6 of 11 points)", "(6 of 11 points)")
    assert not line_matches("(6 of 11 points)", "(7 of 11 points)")
    assert not line_matches("max 67", actual)


@pytest.mark.parametrize(
    "shown, ok",
    [
        ("a 1\nb 2\nc 3", True),
        ("a 1\n\nb 2\nc 3\n", True),  # blank lines aside
        ("a 1\n...\nc 3", True),
        ("...\nc 3", True),
        ("a 1\n...", True),
        ("...", True),
        ("a 1\nb ...\nc 3", True),
        ("a 1\nc 3", False),  # b 2 left out without a "..."
        ("b 2\nc 3", False),  # the first line left out
        ("a 1\nb 2", False),  # the last line left out
        ("a 1\nb\nc 3", False),  # part of a line: "b 2" is not "b"
        ("b 2\na 1\n...", False),  # out of order
        ("a 1\nb 2\nc 3\nd 4", False),  # a line the output does not have
    ],
)
def test_shown_output_is_the_output_line_for_line(shown, ok):
    """README's simulate output lacked "(mean 128.1 rpm)" and two lines, and passed."""
    actual = "a 1\nb 2\n\nc 3\n"
    if ok:
        check_shown(shown, actual, "rule")
    else:
        with pytest.raises(AssertionError):
            check_shown(shown, actual, "rule")


# --- C++ ---------------------------------------------------------------------------------------

BUILD = ROOT / "build" / "cpp"


def cpp_program(snippet: str) -> str:
    """A snippet as a program: complete ones as they are, statements wrapped in main()."""
    if re.search(r"\bint\s+main\s*\(", snippet):
        return snippet
    includes = [s for s in snippet.splitlines() if s.startswith("#include")]
    body = [s for s in snippet.splitlines() if not s.startswith("#include")]
    return "\n".join(
        ["#include <cstdio>", *includes, "int main() {", *body, "  return 0;", "}", ""]
    )


@pytest.mark.skipif(
    shutil.which("cmake") is None or not (BUILD / "cmake_install.cmake").exists(),
    reason="needs cmake and the C++ build tree build/cpp (bash tools/test.sh makes it)",
)
def test_cpp_snippets_compile_and_run(tmp_path: Path):
    """Every ```cpp block, built with the ```cmake lines of its page against the installed
    package (find_package(pydrill)), and run."""
    prefix = tmp_path / "prefix"
    subprocess.run(
        ["cmake", "--install", str(BUILD), "--prefix", str(prefix)],
        check=True,
        capture_output=True,
    )
    lists = [
        "cmake_minimum_required(VERSION 3.18)",
        "project(doc_snippets LANGUAGES C CXX)",
        "set(CMAKE_CXX_STANDARD 17)",
    ]
    programs = []
    for page in PAGES:
        blocks = parse_blocks(page)
        cmake_lines = [
            s
            for b in blocks
            if b.lang == "cmake" and "skip-test" not in b.markers
            for s in b.text.splitlines()
            if s.lstrip().startswith(("find_package(", "target_link_libraries("))
        ]
        for b in blocks:
            if b.lang not in ("cpp", "c++") or "skip-test" in b.markers:
                continue
            name = f"snippet{len(programs)}"
            (tmp_path / f"{name}.cpp").write_text(cpp_program(b.text))
            lists.append(f"add_executable({name} {name}.cpp)")
            # the page's own CMake lines, for this program (they say `app`)
            lists += [re.sub(r"\bapp\b", name, s) for s in cmake_lines] or [
                f"target_link_libraries({name} PRIVATE pydrill::pydrill)"
            ]
            programs.append((name, b))
    lists = list(dict.fromkeys(lists))  # find_package once
    (tmp_path / "CMakeLists.txt").write_text("\n".join(lists) + "\n")
    assert programs, "no C++ snippet in the docs"
    build = tmp_path / "build"
    for cmd in (
        [
            "cmake",
            "-S",
            str(tmp_path),
            "-B",
            str(build),
            f"-DCMAKE_PREFIX_PATH={prefix}",
            "-DCMAKE_BUILD_TYPE=Release",
        ],
        ["cmake", "--build", str(build), "-j", "1"],
    ):
        proc = subprocess.run(cmd, capture_output=True, text=True)
        assert proc.returncode == 0, f"{' '.join(cmd)}\n{proc.stdout}\n{proc.stderr}"
    for name, block in programs:
        proc = subprocess.run([str(build / name)], capture_output=True, text=True, timeout=60)
        assert proc.returncode == 0, f"{block.where}: the program exited {proc.returncode}"
        for comment in re.findall(r"//\s*(?:prints|output):\s*(.+)", block.text):
            check_output(comment, proc.stdout, f"{block.where}")
