"""pydrill sweep --dry-run: what a sweep would compute and about how long, writing nothing."""

import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from sweeping import CMD, SMALL

from pydrill.atlas_lock import AtlasBusy
from pydrill.journal_lines import line as journal_line
from pydrill.spec import parse_spec
from pydrill.sweep import AtlasError, evaluate_point, run_sweep
from pydrill.sweep_plan import plan_sweep

# Cheap points first in grid order (W_ob 20-40 N: steady, ~2 ms), then slow ones (stick-slip
# over 2000 s, ~10 ms): a sample of the first points would foretell a quarter of the time.
SKEWED = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [20.0, 30.0, 40.0, 120.0, 125.0, 130.0, 135.0, 140.0, 145.0, 150.0, 155.0, 160.0]
torque = [13.0, 14.0]
[simulation]
t_end = 2000.0
initial = ["rest"]
"""


def test_the_estimate_foretells_the_time_of_every_point(tmp_path):
    """A quarter of the points, timed in the sweep's pseudo-random order, foretell the time
    of all of them, timed one by one: the sample spreads over the whole grid."""
    spec = parse_spec(SKEWED)
    # The machine's speed drifts by tens of percent within a minute, and other work on its two
    # cores can slow the plan's sample or the loop below alone: a factor of 2 still tells
    # this estimate from the one the first six points in grid order would give (checked on
    # every attempt), and a fresh plan and loop are timed again, up to three times, before
    # the estimate is called wrong.
    for _attempt in range(3):
        plan = plan_sweep(spec, most=6, budget=60.0)
        assert (plan.points, plan.todo, plan.sampled, plan.atlas) == (24, 24, 6, "none")
        assert plan.failed == 0 and plan.message == ""
        low, estimate, high = plan.compute_seconds
        assert 0 < low < estimate < high
        assert plan.wall_seconds(2) == pytest.approx((low / 2, estimate / 2, high / 2))
        times, lines = [], 0
        for i in range(spec.size):
            t0 = time.perf_counter()
            rec = evaluate_point(spec, i)
            times.append(time.perf_counter() - t0)
            lines += len(journal_line(rec))  # the point's journal line
        every = sum(times)
        assert 24 * sum(times[:6]) / 6 < 0.5 * every
        assert plan.journal_bytes == pytest.approx(lines, rel=0.2)
        if 0.5 * every < estimate < 2 * every:
            break
    else:
        pytest.fail(
            f"three estimates missed the time of every point by a factor 2: {plan}, {every}"
        )


def test_a_dry_run_refuses_what_the_sweep_would_and_writes_nothing(tmp_path):
    spec = parse_spec(SMALL)
    out = tmp_path / "a.h5"
    assert plan_sweep(spec, out, most=3).atlas == "new"
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    run_sweep(spec, out, serial=True)
    before = out.read_bytes()
    with pytest.raises(AtlasError, match="resume=True"):  # (the API's words: plan_sweep's)
        plan_sweep(spec, out, most=3)
    with pytest.raises(AtlasError, match="different sweep"):
        plan_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 100.0")), out, resume=True)
    done = plan_sweep(spec, out, resume=True)
    assert (done.atlas, done.todo, done.sampled) == ("complete", 0, 0)
    assert done.compute_seconds == (0.0, 0.0, 0.0)
    assert out.read_bytes() == before
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not an atlas")
    with pytest.raises(AtlasError, match=r"is not an atlas \(not an HDF5 file\)"):
        plan_sweep(spec, junk, resume=True)


def test_a_dry_run_of_an_interrupted_sweep_counts_what_resume_computes(tmp_path):
    """Points in the journal count as done; a journal line cut by a kill is left for the
    sweep to cut (the dry run reads only), and the resume then computes what was foretold."""
    spec = parse_spec(SMALL)
    out = tmp_path / "cut.h5"
    journal = Path(str(out) + ".journal")
    header = json.dumps({"spec_digest": spec.digest}) + "\n"
    whole = "".join(json.dumps(evaluate_point(spec, i)) + "\n" for i in (0, 4))
    cut = json.dumps(evaluate_point(spec, 1))[:37]
    journal.write_text(header + whole + cut)
    plan = plan_sweep(spec, out, resume=True, most=2)
    assert (plan.atlas, plan.todo, plan.sampled) == ("resume", spec.size - 2, 2)
    assert journal.read_text() == header + whole + cut and not out.exists()
    report = run_sweep(spec, out, resume=True, serial=True)
    assert (report.resumed, report.computed) == (2, plan.todo)


# A process holding an atlas's lock as a sweep does, naming itself as given (argv[2]).
HOLDER = """
import fcntl, os, sys, time
fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT)
fcntl.flock(fd, fcntl.LOCK_EX)
os.ftruncate(fd, 0)
os.write(fd, sys.argv[2].format(pid=os.getpid()).encode())
print("held", flush=True)
time.sleep(60)
"""


def hold_lock(lock: Path, text: str) -> subprocess.Popen:
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLDER, str(lock), text], stdout=subprocess.PIPE, text=True
    )
    assert holder.stdout.readline() == "held\n"
    return holder


def test_an_atlas_being_written_is_named_by_its_writer_and_host(tmp_path):
    spec = parse_spec(SMALL)
    out = tmp_path / "busy.h5"
    run_sweep(spec, out, serial=True)
    lock = Path(str(out) + ".lock")
    # A sweep on another machine of a shared filesystem: its process number alone would say
    # nothing here (it was all the message gave), nor could this host see whether it lives.
    holder = hold_lock(lock, "{pid} node17.cluster 2026-11-30T22:41:05Z\n")
    try:
        said = rf"being written by another sweep \(process {holder.pid} on host node17.cluster, "
        with pytest.raises(AtlasBusy, match=said + r"since 2026-11-30 22:41:05 UTC\)"):
            plan_sweep(spec, out, resume=True)
        with pytest.raises(AtlasBusy, match=said):
            run_sweep(spec, out, resume=True, serial=True)
    finally:
        holder.kill()
        holder.wait()
        holder.stdout.close()
    # What kill -9 leaves: a lock file naming a process that is gone, and no lock.
    assert plan_sweep(spec, out, resume=True).atlas == "complete"


def test_a_lock_file_naming_a_live_process_that_holds_no_lock_is_free(tmp_path):
    # A sweep killed with kill -9 leaves its lock file; its process number may be taken by
    # another process since (or name one on another host). The dry run asked the number, and
    # called the atlas busy; the lock itself says it is free.
    spec = parse_spec(SMALL)
    out = tmp_path / "left.h5"
    run_sweep(spec, out, serial=True)
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        for left in (f"{sleeper.pid}\n", f"{sleeper.pid} {socket.gethostname()}\n"):
            Path(str(out) + ".lock").write_text(left)  # as an older pydrill's, and as now
            assert plan_sweep(spec, out, resume=True).atlas == "complete"
        assert run_sweep(spec, out, resume=True, serial=True).resumed == spec.size
    finally:
        sleeper.kill()
        sleeper.wait()


def test_the_cli_dry_run_reports_and_warns_of_failing_points(tmp_path):
    spec_file = tmp_path / "s.toml"
    # Stick-slip needs more steps than this: those points would fail.
    spec_file.write_text(SMALL.replace('initial = ["rest", "equilibrium"]', "max_steps = 900"))
    out = tmp_path / "s.h5"
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--dry-run", "--workers", "3"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 0, proc.stderr
    assert "6 points (3 wob x 2 torque), from rest" in proc.stdout
    assert "  axis wob               3 values, 40 N ... 160 N\n" in proc.stdout
    assert f"{out}: a new atlas" in proc.stdout and "on 3 local workers" in proc.stdout
    assert "points timed failed" in proc.stdout and "max_steps" in proc.stdout
    assert "would most likely fail whole" not in proc.stdout  # some points failed, not all
    assert proc.stdout.endswith("dry run: nothing was written\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    data = json.loads(
        subprocess.run(
            [*CMD, "sweep", str(spec_file), "--dry-run", "--serial", "--json"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    )
    assert data["dry_run"] is True and data["atlas"] == {"path": None, "state": "none"}
    assert data["shape"] == {"wob": 3, "torque": 2} and data["initial"] == ["rest"]
    assert data["todo"] == data["sampled"] == 6 and 0 < data["failed"] < 6
    assert "max_steps" in data["message"]
    assert data["workers"] == 1
    c = data["compute_seconds"]
    assert c["low"] == c["estimate"] == c["high"] > 0  # every point timed: no spread left
    assert data["wall_seconds"] == c and data["atlas_bytes"] > 0 and data["journal_bytes"] > 0
    # Without --dry-run, an atlas must be named.
    no_out = subprocess.run([*CMD, "sweep", str(spec_file)], capture_output=True, text=True)
    assert no_out.returncode == 2 and "--out ATLAS.h5 is required" in no_out.stderr
    # An axis of one value is listed as such.
    spec_file.write_text(SMALL.replace("torque = [6.0, 8.3]", "torque = [8.3]"))
    one = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--dry-run"], capture_output=True, text=True
    )
    assert "  axis torque            1 value,  8.3 N·m\n" in one.stdout


BIG = SMALL.replace("wob = [40.0, 100.0, 160.0]", "wob = { start = 1.0, stop = 300.0, num = 500 }")
BIG = BIG.replace("torque = [6.0, 8.3]", "torque = { start = 0.1, stop = 30.0, num = 400 }")


def test_the_memory_estimate_bounds_what_the_client_holds(tmp_path):
    """The sweep's process holds the whole table and writes it whole: measured with
    tracemalloc (numpy's buffers) over making the table of a 200000-point atlas, filling its
    file and writing it again, the peak lies within the estimate and above half of it."""
    import tracemalloc

    from pydrill import atlas_format as fmt
    from pydrill.sweep_plan import memory_bytes

    spec = parse_spec(BIG)
    assert spec.size == 200_000
    tracemalloc.start()
    try:
        fmt.create(tmp_path / "big.h5", spec, "{}", "test")
        table = fmt.AtlasTable(spec)
        fmt.write(tmp_path / "big.h5", table)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    estimate = memory_bytes(spec)
    assert 0.5 * estimate < peak <= estimate, (peak, estimate)


def test_a_sweep_too_big_for_the_memory_is_refused_before_anything_is_written(
    tmp_path, monkeypatch
):
    import psutil

    from pydrill.sweep_plan import memory_bytes

    spec = parse_spec(BIG)
    need = memory_bytes(spec)
    real = psutil.virtual_memory

    def short(*args):
        return real()._replace(available=need // 2)

    monkeypatch.setattr(psutil, "virtual_memory", short)
    out = tmp_path / "sub" / "big.h5"
    with pytest.raises(ValueError, match=r"200000 points needs about 0\.\d GB of memory"):
        run_sweep(spec, out, serial=True)
    assert not (tmp_path / "sub").exists()
    plan = plan_sweep(spec, None, most=2)  # the dry run says so, and still writes nothing
    assert plan.memory_bytes == need


def test_the_dry_run_counts_local_workers_beyond_the_cores_as_sharing_them(tmp_path):
    """--workers 64 on this machine's cores is no faster than a worker per core: the estimate
    divides by the cores, and the line says they share them."""
    import dask.system

    cores = dask.system.CPU_COUNT
    spec = tmp_path / "s.toml"
    spec.write_text(SMALL.replace("t_end = 200.0", "t_end = 20.0"))
    many = cores + 62
    argv = [*CMD, "sweep", str(spec), "--dry-run", "--workers", str(many)]
    data = json.loads(subprocess.run([*argv, "--json"], capture_output=True, text=True,
                                     check=True).stdout)  # fmt: skip
    assert data["workers"] == many
    wall, compute = data["wall_seconds"]["estimate"], data["compute_seconds"]["estimate"]
    assert wall == pytest.approx(compute / cores, rel=1e-12)
    text = subprocess.run(argv, capture_output=True, text=True, check=True).stdout
    assert f"  runs    on {many} local workers sharing {cores} cores: about " in text


def test_the_dry_run_says_when_every_point_timed_failed(tmp_path):
    # A sweep whose every point fails exits with status 3; its dry run says that is coming,
    # not just "some points failed".
    spec_file = tmp_path / "s.toml"
    spec_file.write_text(SMALL.replace("t_end = 200.0", "t_end = 200.0\nmax_steps = 10"))
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--dry-run", "--serial"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert "every one of the 6 points timed failed" in proc.stdout
    assert "fail whole (exit status 3)" in proc.stdout


def test_the_estimate_counts_the_encoding_a_worker_does_for_each_point(monkeypatch):
    # A worker encodes each batch it computed (columns and journal lines) before handing it
    # back: 40 us a point, an eighth of a cheap point, which the estimate left out.
    import pydrill.sweep_points as points

    real = points.encode_batch

    def slow_encoding(spec, records):
        time.sleep(0.02 * len(records))
        return real(spec, records)

    monkeypatch.setattr(points, "encode_batch", slow_encoding)
    plan = plan_sweep(parse_spec(SMALL), most=4, least=4)
    assert plan.sampled == 4 and plan.point_seconds > 0.02


def test_the_dry_run_of_a_complete_atlas_says_what_the_sweep_says(tmp_path):
    # The dry run said "already exists for this sweep; use --resume to complete it" of an
    # atlas with nothing left to complete; the sweep itself says it is complete.
    spec_file = tmp_path / "s.toml"
    spec_file.write_text(SMALL)
    out = tmp_path / "s.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--dry-run"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert f"{out} already holds this sweep, complete: 6 points" in proc.stderr


def test_the_dry_run_names_the_string_and_what_the_spec_holds_fixed(tmp_path):
    """A sweep at a fixed torque ([model] torque) dry-ran as '36 points (6 depth x 6 wob)' with
    no word of the torque: the model line names it, in kN·m as given in N·m, and --json gives
    it in SI with its unit, as atlas info does."""
    import tomllib

    tally = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"
    text = (
        f'[model]\ntally = "{tally}"\ndof = 6\ntorque = 9000.0\n'
        '[axes]\ndepth = ["1000 m", "3000 m"]\nwob = ["40 kN", "80 kN"]\n'
        '[simulation]\nt_end = 20.0\ninitial = ["rest"]\n'
    )
    spec_file = tmp_path / "fixed.toml"
    spec_file.write_text(text)
    torque = tomllib.loads(text)["model"]["torque"]  # N·m, as written
    run = [*CMD, "sweep", str(spec_file), "--dry-run", "--serial"]
    lines = subprocess.run(run, capture_output=True, text=True, check=True).stdout.splitlines()
    model = " ".join(line.strip() for line in lines[1:3])  # the model line, maybe wrapped
    assert lines[1].startswith("  model   string paper-eq53 (tally), 6 inertias")
    assert f"torque {torque / 1e3:g} kN·m; 20 s from each start" in model
    doc = json.loads(
        subprocess.run([*run, "--json"], capture_output=True, text=True, check=True).stdout
    )
    assert doc["model"]["held"] == {"torque": torque} and doc["model"]["inertias"] == 6
    assert doc["units"]["model"] == {"held": {"torque": "N·m"}, "t_end": "s"}
    out = tmp_path / "fixed.h5"
    subprocess.run([*CMD, "sweep", str(spec_file), "--out", str(out), "--serial"], check=True)
    info = subprocess.run(
        [*CMD, "atlas", "info", str(out), "--json"], capture_output=True, text=True, check=True
    )
    assert json.loads(info.stdout)["units"]["model"] == doc["units"]["model"]


@pytest.mark.parametrize(("load", "said"), [(0.9, False), (5.2, True)])
def test_a_dry_run_on_a_busy_machine_says_the_estimate_may_be_short(
    tmp_path, monkeypatch, capsys, load, said
):
    """The estimate times the points on the cores as they are while it runs; a sweep beside
    other work (load 4.5-5.4 on 2 cores) took 2.2 times it, unannounced. A busy machine is
    said, with its load; an idle one (the dry run's own core alone) is not."""
    import os

    import dask.system

    from pydrill import cli

    monkeypatch.setattr(os, "getloadavg", lambda: (load, load, load))
    monkeypatch.setattr(dask.system, "CPU_COUNT", 2)
    spec = tmp_path / "s.toml"
    spec.write_text(SMALL)
    assert cli.main(["sweep", str(spec), "--dry-run", "--workers", "2"]) == 0
    out, err = capsys.readouterr()
    notes = [line for line in err.splitlines() if line.startswith("pydrill: note: ")]
    if said:
        assert notes == [
            f"pydrill: note: this machine is busy (load {load:.1f} on 2 cores, this dry run "
            "included): its other work will share the cores with the sweep, which may take "
            "longer than this"
        ]
    else:
        assert notes == []
    assert "  runs    on 2 local workers: about " in out  # the estimate, said either way
