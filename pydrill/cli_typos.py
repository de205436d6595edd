"""Misspelt command lines: the option or choice a typo was probably meant to be.

argparse reports a misspelt option late and far from its cause: ``pydrill simulate --wob 100
--torqe 8`` says "the following arguments are required: --torque", and a misspelt command
lists every command. These find the typo and the name it is nearest to."""

from __future__ import annotations

import argparse
import ast
import re
from collections.abc import Sequence

from .suggest import did_you_mean

_CHOICE = re.compile(r"invalid choice: (?P<given>.+?) \(choose from (?P<choices>.+)\)$")


def choice_hint(message: str) -> str:
    """argparse's "invalid choice: 'X' (choose from 'a', 'b')" with the nearest choice named
    after X ("(did you mean 'a'?)"); any other message as it is."""
    m = _CHOICE.search(message)
    if not m:
        return message
    try:
        given = ast.literal_eval(m["given"])
        choices = ast.literal_eval(f"[{m['choices']}]")
    except (ValueError, SyntaxError):  # not argparse's reprs: leave it be
        return message
    hint = did_you_mean(given, [str(c) for c in choices])
    return message[: m.start("given")] + m["given"] + hint + message[m.end("given") :]


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _known(parser: argparse.ArgumentParser, name: str) -> bool:
    """Whether argparse takes the long option ``name`` (before any ``=value``): exactly, or
    abbreviated to a prefix (ambiguous prefixes too: argparse says so itself)."""
    options = parser._option_string_actions
    if name in options:
        return True
    return parser.allow_abbrev and any(o.startswith(name) for o in options if o.startswith("--"))


def misspelt_option(
    parser: argparse.ArgumentParser, argv: Sequence[str]
) -> tuple[argparse.ArgumentParser, str] | None:
    """The first long option of ``argv`` that the (sub)command it follows does not know, with
    that (sub)command's parser; None if every one is known. Only ``--name`` tokens are
    looked at (a value that starts with "--" is not pydrill's), up to a bare ``--``."""
    for token in argv:
        if token == "--":
            break
        if token.startswith("--"):
            name = token.split("=", 1)[0]
            if not _known(parser, name):
                return parser, name
            continue
        sub = _subcommands(parser).get(token)
        if sub is not None:
            parser = sub
    return None


def option_hint(parser: argparse.ArgumentParser, name: str) -> str:
    """ "unrecognized argument --torqe (did you mean --torque?)"."""
    options = [o for o in parser._option_string_actions if o.startswith("--")]
    return f"unrecognized argument {name}{did_you_mean(name, options)}"


def _takers(parser: argparse.ArgumentParser, name: str | None, prog: str) -> list[str]:
    """The commands under ``parser`` (``prog``), nested ones as "atlas query", that take
    the long option ``name`` (every command for None)."""
    found: list[str] = []
    for command, sub in _subcommands(parser).items():
        if _subcommands(sub):
            found += _takers(sub, name, f"{prog} {command}")
        elif name is None or _known(sub, name):
            found.append(f"{prog} {command}")
    return found


def misplaced_option(
    parser: argparse.ArgumentParser, argv: Sequence[str]
) -> tuple[argparse.ArgumentParser, str] | None:
    """An option of a command given before the command ("pydrill --wob 100 simulate"): the
    parser it was given to and a message naming the commands that take it. argparse read the
    option's value as the command ("invalid choice: '100'"), or said the option is unknown
    although pydrill has it. None if no option comes before its command."""
    prog = parser.prog
    for token in argv:
        if token == "--":
            break
        if token.startswith("--"):
            name = token.split("=", 1)[0]
            if _known(parser, name):
                continue
            takers = _takers(parser, name, prog)
            if not takers:  # pydrill has no such option: argparse took its value for a command
                return parser, option_hint(parser, name)
            if len(takers) == len(_takers(parser, None, prog)):
                which = f"every command takes {name}"
            else:
                shown = ", ".join(t.removeprefix("pydrill ") for t in takers)
                which = f"commands that take {name}: {shown}"
            return parser, (
                f"{name} is an option of a command and goes after it: {takers[0]} {name} ... "
                f"({which})"
            )
        sub = _subcommands(parser).get(token)
        if sub is None or not _subcommands(sub):
            return None  # a command's own line (or a bad command): not this case
        parser, prog = sub, f"{prog} {token}"
    return None


def stray_value(
    parser: argparse.ArgumentParser, argv: Sequence[str], message: str
) -> tuple[argparse.ArgumentParser, str] | None:
    """argparse's "unrecognized arguments: X" for a value no option took, said by the top
    parser ("pydrill: error:", its usage naming no command): the (sub)command it was given to,
    and what X follows if that is a flag, which takes no value ("--dashboard :0"). None when
    the unrecognized argument is an option (``misspelt_option``'s case)."""
    prefix = "unrecognized arguments: "
    if not message.startswith(prefix):
        return None
    stray = message[len(prefix) :].split(" ")
    if any(s.startswith("-") for s in stray):
        return None
    command = parser
    for token in argv:
        sub = _subcommands(command).get(token)
        if sub is not None:
            command = sub
    hint = ""
    at = [k for k, token in enumerate(argv) if token == stray[0]]
    if at and at[0] > 0:
        action = command._option_string_actions.get(argv[at[0] - 1])
        if action is not None and action.nargs == 0:
            hint = f" ({argv[at[0] - 1]} takes no value)"
    said = ", ".join(repr(s) for s in stray)
    return command, f"unrecognized argument{'s' if len(stray) > 1 else ''} {said}{hint}"
