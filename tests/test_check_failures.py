"""A failed simulation of ``map --check`` or ``window --check`` (a ``SolverError``: the step
limit, the chattering guard) is one check counted as "failed", with its message; the others
are computed, as ``pydrill sweep`` does with a failed point. One failure aborted the whole
command, and every other check of up to 1600 was lost.

Failures are forced as the core makes them: ``pydrill.simulate`` with ``max_steps=5`` at
chosen calls (the checks run in the order of the --json "checks" list). What the other checks
give is compared with a run without the failure."""

import json
import re
from pathlib import Path

import pytest

import pydrill
from pydrill.cli import main

ROOT = Path(__file__).resolve().parents[1]
PAPER = str(ROOT / "examples" / "tallies" / "paper-eq53.toml")

MAP = ["map", "--dof", "2", "--check", "3", "--t-end", "20"]
WINDOW = ["window", PAPER, "--depth", "1000m,2000m", "--check", "2", "--check-dof", "6"]
WINDOW += ["--t-end", "20", "--check-from", "rest"]


def forced(monkeypatch, at, raising: type[BaseException] | None = None) -> list[int]:
    """Make the checks' simulations numbered in ``at`` (from 0) fail at the core's step limit,
    or raise ``raising`` there; returns the list of the calls made, which grows as they are."""
    real = pydrill.simulate
    calls: list[int] = []

    def simulate(*args, **kwargs):
        calls.append(len(calls))
        if calls[-1] in at:
            if raising is not None:
                raise raising("forced")
            kwargs["max_steps"] = 5  # (at 20 steps, a stuck bit ran to its end)
        return real(*args, **kwargs)

    monkeypatch.setattr(pydrill, "simulate", simulate)
    return calls


def run(capsys, argv):
    status = main(argv)
    out, err = capsys.readouterr()
    return status, out, err


def map_checks(data):
    return data["checks"]


def window_checks(data):
    return [c for w in data["windows"] for c in w["checks"]]


@pytest.mark.parametrize(
    ("argv", "checks", "key"), [(MAP, map_checks, "regime"), (WINDOW, window_checks, "outcome")]
)
def test_the_other_checks_are_computed_as_without_the_failure(
    argv, checks, key, capsys, monkeypatch
):
    status, out, _ = run(capsys, [*argv, "--json"])
    assert status == 0
    reference = checks(json.loads(out))
    assert all(c["message"] is None for c in reference)
    assert json.loads(out)["failed_checks"] == 0
    n = len(reference)
    forced(monkeypatch, {1})
    status, out, err = run(capsys, [*argv, "--json"])
    assert status == 0
    data = json.loads(out)
    got = checks(data)
    assert [c for k, c in enumerate(got) if k != 1] == [
        c for k, c in enumerate(reference) if k != 1
    ]
    failed = got[1]
    assert failed[key] == "failed"
    assert set(failed) == set(reference[1])  # every key kept, its place and verdict too
    assert {k: failed[k] for k in failed if k not in (key, "message", "bit_rpm")} == {
        k: reference[1][k] for k in failed if k not in (key, "message", "bit_rpm")
    }
    assert "internal steps reached" in failed["message"]
    assert re.search(r"run that point alone with more steps: pydrill simulate ", failed["message"])
    assert data["failed_checks"] == 1
    if argv is WINDOW:
        assert failed["bit_rpm"] is None
        assert [w["failed_checks"] for w in data["windows"]] == [1, 0]
    assert f"pydrill {argv[0]}: 1 of {n} checks failed" in err
    assert failed["message"] in err  # stdout is JSON: stderr gives the first failure's message


def _tally(line: str) -> dict[str, int]:
    """The counts of a text output's line of outcomes ("...: failed 1, steady 3; ...")."""
    text = line.split(": ", 1)[1].split(";")[0]
    return {k: int(v) for k, v in (item.rsplit(" ", 1) for item in text.split(", "))}


@pytest.mark.parametrize("argv", [MAP, WINDOW], ids=["map", "window"])
def test_the_text_counts_the_failure_and_says_its_point_and_line(argv, capsys, monkeypatch):
    status, out, _ = run(capsys, argv)
    assert status == 0 and "failed" not in out
    prefix = "simulated from rest: " if argv is MAP else "checks at 1000 m"
    reference = _tally(next(line for line in out.splitlines() if line.startswith(prefix)))
    status, json_out, _ = run(capsys, [*argv, "--json"])
    first = (map_checks if argv is MAP else window_checks)(json.loads(json_out))[0]
    forced(monkeypatch, {0})
    status, out, err = run(capsys, argv)
    assert status == 0
    lines = out.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith(prefix))
    expected = dict(reference)
    outcome = first["regime" if argv is MAP else "outcome"]
    expected[outcome] -= 1
    expected = {g: v for g, v in expected.items() if v} | {"failed": 1}
    assert _tally(lines[k]) == expected
    if argv is WINDOW:
        assert "/3 simulated points" in lines[k] or "where the bit may stay stuck: " in lines[k]
        k += 1  # the other depth's line, then the failures
    said = lines[k + 1]
    point = (
        f"W_ob = {first['wob']:.4g} N, u = {first['torque']:.4g} N m"
        if argv is MAP
        else f"1000 m, W_ob = {first['wob'] / 1e3:.4g} kN, {first['rpm']:.4g} rpm"
    )
    assert said.startswith(f"  the check at {point}") and " failed: " in said
    assert re.search(r"pydrill simulate .* --max-steps 100000000$", said)
    assert f"pydrill {argv[0]}: 1 of " in err and "listed in the output" in err


def test_many_failures_show_the_first_five_and_count_the_rest(capsys, monkeypatch):
    forced(monkeypatch, {0, 1, 2, 3, 4, 5, 6})
    status, out, err = run(capsys, MAP)
    assert status == 0  # two of nine were computed
    lines = out.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("simulated from rest: "))
    assert _tally(lines[k])["failed"] == 7
    assert all(line.startswith("  the check at ") for line in lines[k + 1 : k + 6])
    assert lines[k + 6] == "  ... and 2 more (--json gives each one's message)"
    assert "7 of 9 checks failed" in err


@pytest.mark.parametrize("argv", [MAP, WINDOW], ids=["map", "window"])
@pytest.mark.parametrize("as_json", [False, True], ids=["text", "json"])
def test_when_every_check_fails_the_output_is_given_and_the_status_is_3(
    argv, as_json, capsys, monkeypatch
):
    """As a sweep whose every point failed: exit status 3, the first failure's message on
    stderr; the analysis (the map, the window's edges) is printed before it."""
    forced(monkeypatch, set(range(100)))
    status, out, err = run(capsys, [*argv, "--json"] if as_json else argv)
    assert status == 3
    n = 9 if argv is MAP else 8
    assert f"solver failed: every check failed ({n} of {n})" in err
    assert re.search(r"pydrill simulate .* --max-steps 100000000$", err.strip())
    if as_json:
        data = json.loads(out)
        checks = map_checks(data) if argv is MAP else window_checks(data)
        assert data["failed_checks"] == n == len(checks)
        assert {c["regime" if argv is MAP else "outcome"] for c in checks} == {"failed"}
    else:
        assert f"failed {n if argv is MAP else n // 2}" in out
        assert "/0" not in out  # no agreement said of no simulated point (window's "0/0")
        assert ("safe u at each W_ob" if argv is MAP else "slowest safe surface speed") in out


@pytest.mark.parametrize(
    ("argv", "raising", "status", "said"),
    [
        (MAP, KeyboardInterrupt, 130, "interrupted"),
        (WINDOW, KeyboardInterrupt, 130, "interrupted"),
        (MAP, ValueError, 2, "error: forced"),
        (WINDOW, ValueError, 2, "error: forced"),
    ],
    ids=["map-ctrl-c", "window-ctrl-c", "map-bad-input", "window-bad-input"],
)
def test_ctrl_c_and_bad_input_still_stop_the_checks(
    argv, raising, status, said, capsys, monkeypatch
):
    """Only a solver failure is a failed check: Ctrl-C stops the command (exit status 130),
    and any other error is said as before (bad input: 2), no check run after it."""
    calls = forced(monkeypatch, {1}, raising)
    got, out, err = run(capsys, argv)
    assert got == status
    assert len(calls) == 2 and out == ""
    assert said in err and "failed" not in err


def _drawn(monkeypatch, argv, tmp_path):
    """The figure the command saves, drawn (kept, not only written)."""
    import pydrill.plot

    figures = []
    save = pydrill.plot.save

    def keep(fig, path):
        figures.append(fig)
        return save(fig, path)

    monkeypatch.setattr(pydrill.plot, "save", keep)
    assert main([*argv, "--plot", str(tmp_path / "f.png")]) == 0
    (fig,) = figures
    fig.draw_without_rendering()
    return fig


@pytest.mark.parametrize(
    "argv",
    [MAP, [*WINDOW[:3], "1000m", *WINDOW[4:]]],  # window draws its checks at one depth
    ids=["map", "window"],
)
def test_the_figure_marks_the_failed_check(argv, tmp_path, capsys, monkeypatch):
    from matplotlib.collections import PathCollection

    status, out, _ = run(capsys, [*argv, "--json"])
    assert status == 0
    data = json.loads(out)
    checks = map_checks(data) if argv is MAP else window_checks(data)
    forced(monkeypatch, {2})
    fig = _drawn(monkeypatch, argv, tmp_path)
    capsys.readouterr()
    ax = fig.axes[0]
    scatters = [c for c in ax.collections if isinstance(c, PathCollection)]
    failed = [
        c for c in scatters if c.get_label().endswith("failed (no result; the output says why)")
    ]
    assert len(failed) == 1 and len(failed[0].get_offsets()) == 1
    x = checks[2]["wob"] / (1.0 if argv is MAP else 1e3)  # the window's axis is in kN
    y = checks[2]["torque" if argv is MAP else "rpm"]
    assert failed[0].get_offsets().tolist()[0] == pytest.approx([x, y])
    assert sum(len(c.get_offsets()) for c in scatters) == len(checks)  # none left out
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert failed[0].get_label() in legend


def test_the_depth_chart_says_how_each_depths_checks_came_out(tmp_path, capsys, monkeypatch):
    """With several depths the chart's curves are at --at-rpm/--at-wob, away from the checks'
    points: its footnote gives each depth's outcome as the text output does (it showed no
    checks at all), the failed one counted, and how to see them on a window."""
    forced(monkeypatch, {1})
    status, out, _ = run(capsys, WINDOW)
    assert status == 0
    said = dict(re.findall(r"checks at (\d+) m from rest: .*?; (safe points .*)", out))
    assert set(said) == {"1000", "2000"}
    forced(monkeypatch, {1})
    fig = _drawn(monkeypatch, WINDOW, tmp_path)
    note = " ".join(fig._supxlabel.get_text().split())  # the note, unwrapped
    assert "checks (2 x 2 simulations per depth from rest)" in note
    assert f"1,000 m: {said['1000']} (1 failed)" in note
    assert f"2,000 m: {said['2000']}." in note and "--depth 1000m" in note
    capsys.readouterr()
    plain = _drawn(monkeypatch, WINDOW[:4], tmp_path)
    assert plain._supxlabel is None  # no checks, no note
    # Every check of a depth failed: said once ("every check failed (4 failed)" said it twice).
    forced(monkeypatch, {0, 1, 2, 3})
    note = " ".join(_drawn(monkeypatch, WINDOW, tmp_path)._supxlabel.get_text().split())
    assert "1,000 m: all 4 checks failed;" in note and "(4 failed)" not in note
