"""The ``pydrill`` command's argument parser: one-line errors with a hint for a misspelt option,
negative numbers taken as values, and help whose prose is refilled to the terminal."""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

EXIT_USAGE = 2


def wants_json(argv: Sequence[str]) -> bool:
    """Whether the command line asked for --json (before a "--", which ends the options),
    abbreviated too: argparse takes --js (no other option starts --j) for --json, and an error
    then left stdout empty where a script expects the JSON error object."""
    for token in argv:
        if token == "--":
            return False
        if len(token) >= 3 and "--json".startswith(token):
            return True
    return False


def say_error(
    prog: str, kind: str, message: str, status: int, where: str = "", **extra: Any
) -> None:
    """One failure, said on stderr (``prog: kind: message``) and, for a script that gave --json
    and parses stdout, also as the one JSON object stdout then holds (:func:`error_json`).
    ``where`` is for people ("solver failed (reached t = 1.9 s)"); its number is in ``extra``."""
    sys.stderr.write(f"{prog}: {kind}{where}: {message}\n")
    error_json(kind, message, status, **extra)


def error_json(kind: str, message: str, status: int, **extra: Any) -> None:
    """A failure as ``{"error": {"kind", "message", "exit_status", ...}}`` on stdout when the
    command line gave --json: ``json.loads`` meets the failure, not an empty string. Not when
    the command's own document is out already (its results came before the failure, e.g. a
    figure that could not be saved): stdout stays one object."""
    if _Parser.argv is not None and wants_json(_Parser.argv) and not _Parser.json_sent:
        import json

        error = {"kind": kind, "message": message, "exit_status": status, **extra}
        # Flushed here, in the handler: a reader gone (| head, a closed pipe) raised from it a
        # traceback over the message just said (PYTHONUNBUFFERED), or made the flush at exit
        # fail, with exit status 120 for the command's 2.
        try:
            print(json.dumps({"error": error}, indent=2, allow_nan=False), flush=True)
        except BrokenPipeError:
            from .cli import quiet_stdout

            quiet_stdout()


# The metavar of the sub-command argument (pydrill COMMAND; 'pydrill atlas' alone is
# answered by its own handler, cli_atlas._atlas_usage).
_WHAT = {"COMMAND": "command"}


class _Wrapped(argparse.RawDescriptionHelpFormatter):
    """Descriptions and epilogs keep their layout where it matters (an example stays one
    command a line, to copy; a table under a header ending in ":" its columns), and every
    paragraph of prose is refilled to the terminal: its unindented lines, with the indented
    ones continuing one that does not end in ":" ("JSON fields: ...," then "  severity, ...")
    under that hanging indent. Wrapped line by line, the source's breaks left stubs
    ("top_mean," alone on a line); kept when they fitted, they stayed ragged on a wide one."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        import textwrap

        out: list[str] = []
        para: list[str] = []  # a paragraph's lines, its first one unindented
        hang = ""  # the indent of its continuation lines, once one is indented

        def flush() -> None:
            nonlocal hang
            joined = " ".join(line.strip() for line in para)
            # whole words: an option is never broken after a hyphen ("--t-" / "end")
            out.extend(textwrap.wrap(joined, width, initial_indent=indent,
                                     subsequent_indent=indent + hang, break_long_words=False,
                                     break_on_hyphens=False))  # fmt: skip
            para.clear()
            hang = ""

        for line in text.splitlines():
            lead = line[: len(line) - len(line.lstrip())]
            if line.strip() and not lead:
                if hang:  # an unindented line after a hanging paragraph starts the next one
                    flush()
                para.append(line)
            elif line.strip() and para and not para[-1].endswith(":") and lead == (hang or lead):
                hang = lead
                para.append(line)
            else:  # blank, or indented under a header (an example, a table row): kept whole
                flush()
                out.append(indent + line)
        flush()
        return "\n".join(out)


class _Parser(argparse.ArgumentParser):
    #: the whole command line and the top parser, while ``main`` parses it: a subcommand's
    #: parser that errs sees only its own part
    line: tuple[argparse.ArgumentParser, Sequence[str]] | None = None
    #: the whole command line, while ``main`` runs: --json on it makes errors JSON too
    argv: Sequence[str] | None = None
    #: whether the command printed its --json document (see :func:`error_json`)
    json_sent = False

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        if kwargs.get("formatter_class") is argparse.RawDescriptionHelpFormatter:
            kwargs["formatter_class"] = _Wrapped
        super().__init__(*args, **kwargs)
        # A value that starts with a minus and a digit is a value, not an option: argparse's
        # own pattern takes "-1" and "-0.5" but not "-1e9", "-3000m" or "-1,1,1", and said
        # "expected one argument" instead of the range check's message. (No option of
        # pydrill starts with a digit.)
        self._negative_number_matcher = re.compile(r"^-\.?\d")

    def error(self, message: str) -> NoReturn:  # exit 2 with a one-line message
        # A bad value of a known option is said in one line (the check names the option and
        # its range); the usage block, ten lines for simulate, only helps when the command
        # line itself is malformed: an option missing, unknown, or a choice not offered.
        from .cli_typos import (
            choice_hint,
            misplaced_option,
            misspelt_option,
            option_hint,
            stray_value,
        )

        parser: argparse.ArgumentParser = self
        misplaced = misplaced_option(*_Parser.line) if _Parser.line is not None else None
        stray = stray_value(*_Parser.line, message) if _Parser.line is not None else None
        if misplaced is not None:
            parser, message = misplaced
        elif stray is not None:  # said by the top parser: said here by the command's
            parser, message = stray
        elif _Parser.line is not None and (
            message.startswith("the following arguments are required")
            or message.startswith("unrecognized arguments")
        ):
            # A misspelt option is the likelier cause: "--torqe 8" left --torque missing.
            found = misspelt_option(*_Parser.line)
            if found is not None:
                parser, name = found
                message = option_hint(parser, name)
        message = choice_hint(message)
        missing = message.rpartition(": ")[2]
        if parser is self and message.startswith("the following") and missing in _WHAT:
            # Only 'pydrill' or 'pydrill atlas' typed: the list of what it does is the answer
            # (the usage line alone named no command).
            parser.print_help(sys.stderr)
            message = f"say which {_WHAT[missing]}: {parser.prog} {missing} ..."
        elif not message.startswith("argument ") or "invalid choice" in message:
            parser.print_usage(sys.stderr)
        say_error(parser.prog, "error", message, EXIT_USAGE)
        raise SystemExit(EXIT_USAGE)
