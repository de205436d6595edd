"""Running ``pydrill`` in the test's own process, for tests of what it prints."""

from pydrill import cli


def run(capsys, *args):
    """Exit status, stdout and stderr of ``pydrill ARGS`` (a bad option value exits at once)."""
    try:
        code = cli.main([str(a) for a in args])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def notes(err: str) -> list[str]:
    """The notes among a command's stderr lines."""
    return [line for line in err.splitlines() if line.startswith("pydrill: note: ")]
