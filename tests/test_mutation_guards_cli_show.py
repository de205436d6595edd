"""``pydrill string``'s text against its own --json and the tally, and ``pydrill sweep
--dry-run``'s lines computed by hand from a plan given to it.

Found by a mutation audit (session 37) of cli_string_show and cli_sweep_dry_run: the chain's
summary past 12 inertias, the top drive's share of the string, the dry run's units, sizes,
worker counts and warnings were checked by no test.
"""

import argparse
import json
import re
from pathlib import Path

import dask.system
import pytest

import pydrill.cli_sweep_dry_run as dry_module
import pydrill.sweep_plan as plan_module
from pydrill.cli import main
from pydrill.spec import parse_spec
from pydrill.sweep_plan import SweepPlan
from pydrill.tally_parse import load_tally

PAPER = str(Path(__file__).resolve().parents[1] / "examples/tallies/paper-eq53.toml")


def _run(capsys, *argv):
    assert main(list(argv)) == 0
    return capsys.readouterr().out


def _lines(text, start):
    return [line for line in text.splitlines() if line.lstrip().startswith(start)]


def test_twelve_inertias_are_listed_and_thirteen_summed(capsys):
    """Up to 12 inertias, one line an element (J of inertias[1:], not the top drive's);
    beyond, the elements' count (dof - 1), their total inertia and series stiffness."""
    for dof in (12, 13):
        data = json.loads(
            _run(capsys, "string", "--preset", "reduced-scale", "--dof", str(dof), "--json")
        )
        j, k = data["inertias"], data["stiffnesses"]
        text = _run(capsys, "string", "--preset", "reduced-scale", "--dof", str(dof))
        elements = _lines(text, "element")
        if dof == 12:
            assert len(elements) == 11
            shown = [float(re.search(r"J = (\S+) kg", e).group(1)) for e in elements]
            assert shown == pytest.approx(j[1:], rel=1e-5)
        else:
            assert elements == []
            total, series = sum(j[1:]), 1 / sum(1 / x for x in k)
            assert f"  {dof - 1} elements; total inertia {total:.6g} kg m^2, " in text
            assert f"series stiffness {series:.6g} N m/rad" in text


def test_a_tallys_top_inertia_is_its_top_drive_and_some_of_the_string(capsys):
    tally = load_tally(PAPER)
    data = json.loads(_run(capsys, "string", PAPER, "--dof", "3", "--json"))
    assert data["length"] == pytest.approx(tally.length)
    text = _run(capsys, "string", PAPER, "--dof", "3")
    j0 = data["inertias"][0]
    assert j0 != tally.top_inertia
    assert f"({tally.top_inertia:g} + {j0 - tally.top_inertia:.4g} of the string)" in text


# --- the dry run, of a plan given to it --------------------------------------------------

SPEC = parse_spec(
    """
[model]
preset = "reduced-scale"
dof = 3
[axes]
wob = [100.0, 120.0]
torque = [6.0, 7.0, 8.0]
[simulation]
t_end = 2.0
initial = ["rest"]
"""
)


def _plan(**kw):
    base = dict(
        points=6, todo=6, atlas="none", sampled=2, failed=0, message="",
        point_seconds=0.5, point_seconds_low=0.25, point_seconds_high=2.0,
        atlas_bytes=1_234_567, journal_bytes=0, memory_bytes=1000,
    )  # fmt: skip
    return SweepPlan(**{**base, **kw})


def _dry(capsys, monkeypatch, plan, *, workers=2, cores=4, free=10**9, json_out=False, out=None):
    monkeypatch.setattr(plan_module, "plan_sweep", lambda *a, **k: plan)
    monkeypatch.setattr(dry_module, "_available", lambda: free)
    monkeypatch.setattr(dry_module, "_busy", lambda: None)
    monkeypatch.setattr(dask.system, "CPU_COUNT", cores)
    monkeypatch.setenv("DASK_SCHEDULER_ADDRESS", "")
    args = argparse.Namespace(
        out=out, resume=False, serial=False, scheduler=None, workers=workers,
        json=json_out, spec="s.toml", part=None,
    )  # fmt: skip
    assert dry_module.dry_run(args, SPEC) == 0
    return capsys.readouterr().out


def test_dry_run_lines_by_hand(capsys, monkeypatch):
    text = _dry(capsys, monkeypatch, _plan())
    # 0.5 s a point, its 95 % range reaching 2 s: all three in s, not ms
    assert (
        "  timed   2 of the 6 points to compute: 0.5 s each on one core (95 %: 0.25 ... 2 s)"
        in text
    )
    assert "  needs   about 3 s of computing (95 %: 1.5 s ... 12 s)" in text
    # 2 workers on 4 cores: 3 s / 2
    assert "  runs    on 2 local workers: about 1.5 s at best, plus Dask's start" in text
    assert "  writes  about 1.23 MB of data, before compression" in text
    assert "journal" not in text and "warning" not in text
    ms = _dry(
        capsys,
        monkeypatch,
        _plan(point_seconds=0.002, point_seconds_low=0.001, point_seconds_high=0.004),
    )
    assert "0.002" not in ms and "2 ms each on one core (95 %: 1 ... 4 ms)" in ms
    # 2 workers on 2 cores are not "sharing"; 5 on 2 are, and run no faster than 2
    assert "sharing" not in _dry(capsys, monkeypatch, _plan(), workers=2, cores=2)
    five = _dry(capsys, monkeypatch, _plan(), workers=5, cores=2)
    assert "on 5 local workers sharing 2 cores: about 1.5 s at best" in five


def test_dry_run_of_an_atlas_to_resume_and_every_point_timed(capsys, monkeypatch):
    text = _dry(capsys, monkeypatch, _plan(atlas="resume", todo=2, sampled=2), out="a.h5")
    assert "  atlas   a.h5: 4 points done, --resume computes the other 2" in text
    assert "  timed   all 2 points to compute: 0.5 s each on one core" in text
    assert "  needs   1 s of computing" in text
    # 12 minutes of computing: shown as a duration, as the sweep's report does
    long = _dry(capsys, monkeypatch, _plan(todo=6, point_seconds=120.0, point_seconds_high=200.0))
    assert "  needs   about 12 min 00 s of computing" in long


def test_dry_run_warnings_and_sizes(capsys, monkeypatch):
    # memory: 999 kB is below 1 MB (decimal units), and more than is free is warned of
    text = _dry(capsys, monkeypatch, _plan(memory_bytes=999_999, atlas_bytes=1000), free=999_998)
    assert "  memory  about 1e+03 kB in this process" in text and "; 1e+03 kB available now" in text
    assert "  writes  about 1 kB of data" in text
    assert "warning that is more than is available" in text
    assert "warning that is" not in _dry(capsys, monkeypatch, _plan(memory_bytes=10), free=10)
    one = _dry(capsys, monkeypatch, _plan(sampled=3, failed=2, message="boom"))
    assert "  warning 2 of the 3 points timed failed; the sweep would store them" in one
    every = _dry(capsys, monkeypatch, _plan(sampled=3, failed=3, message="boom"))
    assert "  warning every one of the 3 points timed failed" in every


def test_dry_run_json_keeps_the_order_low_estimate_high(capsys, monkeypatch):
    data = json.loads(_dry(capsys, monkeypatch, _plan(), json_out=True))
    results = data.get("results", data)
    assert results["point_seconds"] == {"low": 0.25, "estimate": 0.5, "high": 2.0}
    assert results["compute_seconds"] == {"low": 1.5, "estimate": 3.0, "high": 12.0}
    assert results["wall_seconds"] == {"low": 0.75, "estimate": 1.5, "high": 6.0}
    assert results["shape"] == {"wob": 2, "torque": 3}


def test_a_tallys_mistyped_friction_is_noted_as_a_presets_is(capsys):
    """--set mu_static=8 (above MOST_FRICTION, 2; a tenth of it, 0.8, is a bit's on rock):
    noted on stderr for a tally's string as for a preset's, and the string keeps it."""
    note = "pydrill: note: --set mu_static = 8: a friction coefficient above any bit's on rock"
    for source in ([PAPER, "--dof", "2"], ["--preset", "reduced-scale", "--dof", "2"]):
        assert main(["string", *source, "--set", "mu_static=8"]) == 0
        out, err = capsys.readouterr()
        assert note in err and "0.8 meant?" in err
        assert "  friction    mu_s = 8, " in out


def test_the_machine_is_busy_from_half_its_cores_taken_by_other_work(monkeypatch):
    """The load less this dry run's own core is other work; from half the cores (1 of 2)
    on, the estimate is said to be likely short."""
    monkeypatch.setattr(dask.system, "CPU_COUNT", 2)
    for load, busy in ((1.9, False), (2.0, True), (2.9, True)):
        monkeypatch.setattr(dry_module.os, "getloadavg", lambda load=load: (load, 0.0, 0.0))
        said = dry_module._busy()
        assert (said is not None) == busy, load
        if busy:
            assert said.startswith(f"this machine is busy (load {load:.1f} on 2 cores")
