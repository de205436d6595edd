"""Sweep guards from a mutation audit: each test compares the atlas with something computed
apart from the code that wrote it (a direct stability call, the journal's own lines, the
atlas as it was before a resume), so that a slip in the atlas layer cannot hide behind
itself."""

import errno
import json
import os
import signal
import subprocess

import h5py
import numpy as np
import pytest
from sweeping import CMD, MEDIUM, ROOT, SMALL, TINY

import pydrill
import pydrill.sweep as sweep_module
from pydrill import atlas_format as fmt
from pydrill.atlas import Atlas
from pydrill.journal import journal_path, read_journal
from pydrill.spec import parse_spec
from pydrill.stability import stability
from pydrill.sweep import AtlasError, SweepInterrupted, evaluate_batch, run_sweep
from pydrill.sweep_plan import plan_sweep

# One point fails: stick-slip at W_ob = 100 N, u = 8.3 N·m needs more than 900 steps.
FAILING = SMALL.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]\nmax_steps = 900')


def every_dataset(path):
    """Every dataset of an atlas by name, wall_time included (NaN compares equal to NaN)."""
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f if isinstance(f[name], h5py.Dataset)}


def assert_same_data(a, b):
    assert a.keys() == b.keys()
    for name in a:
        kind = a[name].dtype.kind
        assert np.array_equal(a[name], b[name], equal_nan=kind in "fc"), name


def test_atlas_stability_fields_are_those_of_a_direct_stability_call(tmp_path):
    """Every stored stability field, steady state by steady state (the atlas keeps the
    fastest first; ``stability`` gives the slowest first), against ``stability`` called
    directly, without the sweep's cached crossings. At W_ob = 100 N, u = 6 N·m there are two
    steady states; at W_ob = 160 N none; the others have one."""
    k = 5  # of the 7 eigenvalues of a dof-4 string; not the default 4
    spec = parse_spec(TINY + f"[record]\neigenvalues = {k}\n")
    out = tmp_path / "stab.h5"
    run_sweep(spec, out, serial=True)
    p = pydrill.preset("reduced-scale", dof=4)
    counts = []
    with h5py.File(out, "r") as f, Atlas(out) as atlas:
        assert f["eigenvalues_real"].shape == (3, 2, fmt.N_EQ, k)
        for i, wob in enumerate(spec.axes["wob"]):
            for j, torque in enumerate(spec.axes["torque"]):
                direct = stability(p, float(wob), torque=float(torque))[::-1]  # fastest first
                n = len(direct)
                counts.append(n)
                where = f"wob = {wob}, torque = {torque}"
                expected = {
                    "omega_eq": [q.omega for q in direct],
                    "delta": [q.delta for q in direct],
                    "spectral_abscissa": [q.spectral_abscissa for q in direct],
                    "hopf_margin": [q.delta_margin for q in direct],
                }
                # The file: each steady state in its own slot, unused slots left empty.
                for name, want in expected.items():
                    got = f[name][i, j]
                    np.testing.assert_allclose(got[:n], want, rtol=1e-9, err_msg=f"{name} {where}")
                    assert np.all(np.isnan(got[n:])), f"{name} {where}"
                unstable = f["unstable"][i, j]
                assert unstable[:n].tolist() == [q.unstable for q in direct], where
                assert np.all(unstable[n:] == -1), where
                eig = f["eigenvalues_real"][i, j] + 1j * f["eigenvalues_imag"][i, j]
                for e, q in enumerate(direct):
                    np.testing.assert_allclose(
                        eig[e], q.eigenvalues[:k], rtol=1e-9, atol=1e-12, err_msg=f"eq {e} {where}"
                    )
                assert np.all(np.isnan(eig[n:])), where
                # The reader: lists over the steady states, as many as there are.
                v = atlas.value(wob=float(wob), torque=float(torque))["stability"]
                for name, want in expected.items():
                    assert v[name] == pytest.approx(want, rel=1e-9), f"{name} {where}"
                assert v["unstable"] == [q.unstable for q in direct], where
                assert len(v["eigenvalues"]) == n, where
                for e, q in enumerate(direct):
                    assert [complex(a, b) for a, b in v["eigenvalues"][e]] == pytest.approx(
                        list(q.eigenvalues[:k]), rel=1e-9, abs=1e-12
                    ), f"eq {e} {where}"
    assert counts == [1, 1, 2, 1, 0, 0]  # the grid has each case
    # The two steady states at (100, 6) differ: a slot mix-up cannot pass by equality.
    slow, fast = stability(p, 100.0, torque=6.0)
    assert slow.unstable != fast.unstable and slow.eigenvalues[0] != fast.eigenvalues[0]


def test_resuming_a_sweep_with_failed_points_computes_nothing(tmp_path):
    """Failed points are done, with their message: --resume does not compute them again, and
    the atlas stays as it was (nor does a dry run count them to do)."""
    spec = parse_spec(FAILING)
    out = tmp_path / "f.h5"
    first = run_sweep(spec, out, serial=True)
    assert 0 < first.failed < first.points
    before = every_dataset(out)
    assert np.count_nonzero(before["status"] == fmt.STATUS["failed"]) == first.failed
    again = run_sweep(spec, out, serial=True, resume=True)
    assert (again.computed, again.failed, again.resumed) == (0, 0, spec.size)
    assert_same_data(every_dataset(out), before)
    assert not journal_path(out).exists()
    plan = plan_sweep(spec, out, resume=True)
    assert (plan.todo, plan.atlas, plan.sampled) == (0, "complete", 0)
    spec_file = tmp_path / "f.toml"
    spec_file.write_text(FAILING)
    proc = subprocess.run(
        [*CMD, "sweep", spec_file, "--out", out, "--resume", "--dry-run", "--json"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    dry = json.loads(proc.stdout)
    assert (dry["todo"], dry["atlas"]["state"], dry["points"]) == (0, "complete", spec.size)
    assert_same_data(every_dataset(out), before)


@pytest.mark.parametrize(
    ("section", "a_lines", "b_lines"),
    [
        ("record", "", "eigenvalues = 2"),
        ("record", "", "stability = false"),
        ("record", "eigenvalues = 2", "eigenvalues = 4"),
        ("simulation", "", 'method = "dop853"'),
        ("simulation", "max_steps = 5000000", "max_steps = 900"),
    ],
    ids=["eigenvalues", "stability", "eigenvalues-2-vs-4", "method", "max_steps"],
)
def test_specs_differing_in_one_record_or_simulation_key_are_different_sweeps(
    tmp_path, section, a_lines, b_lines
):
    """The digest is the sweep's identity: what is recorded and how it is simulated are part
    of it, and an atlas of one is refused to the other, nothing written."""

    def text(lines):
        if section == "record":
            return TINY + f"[record]\n{lines}\n"
        return TINY.replace("[simulation]\n", f"[simulation]\n{lines}\n")

    a, b = parse_spec(text(a_lines)), parse_spec(text(b_lines))
    tables = ("preset", "dof", "overrides", "axes", "simulation", "record", "fixed")
    differing = [name for name in tables if str(getattr(a, name)) != str(getattr(b, name))]
    assert differing == [section]  # the two differ there alone
    assert a.digest != b.digest
    out = tmp_path / "a.h5"
    run_sweep(a, out, serial=True)
    before = out.read_bytes()
    with pytest.raises(AtlasError, match="holds a different sweep"):
        run_sweep(b, out, serial=True, resume=True)
    with pytest.raises(AtlasError, match="holds a different sweep"):
        plan_sweep(b, out, resume=True)
    assert out.read_bytes() == before
    assert not journal_path(out).exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["spec_digest"] == a.digest


def test_resume_replays_a_journal_ahead_of_its_atlas(tmp_path, monkeypatch):
    """A sweep interrupted after two points leaves them in its atlas and its journal; a kill
    then, before the next flush, leaves more in the journal than in the atlas (appended here
    in the journal's own format: the lines a batch brings the client). Resuming takes every
    journaled point from the journal, into the atlas with the journal's values, and computes
    only the rest."""
    import pydrill.batching

    spec = parse_spec(SMALL)
    out = tmp_path / "j.h5"
    monkeypatch.setattr(pydrill.batching, "BATCH_SECONDS", 0.0)  # a batch is one point
    seen = []

    def stop_after_two(n, _):
        seen.append(n)
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(SweepInterrupted):
        run_sweep(spec, out, serial=True, progress=stop_after_two)
    monkeypatch.undo()
    jp = journal_path(out)
    lines = jp.read_text().splitlines()
    first = [json.loads(line)[0] for line in lines[1:]]  # [i, status, ...]: journal_lines
    assert len(first) == 2
    with h5py.File(out, "r") as f:  # flushed on the way out: the atlas has these two
        assert np.flatnonzero(f["status"][...].ravel()).tolist() == sorted(first)
    # Two more points finish and are journaled; the kill comes before the atlas is flushed.
    extra = [i for i in range(spec.size) if i not in first][:2]
    batch = evaluate_batch(spec.text, extra)
    assert batch.indices.tolist() == extra
    with jp.open("a") as fh:
        fh.write(batch.lines)
    lines = [json.loads(line) for line in jp.read_text().splitlines()[1:]]
    assert [r[0] for r in lines] == first + extra
    journaled = read_journal(out, spec)  # the same records, as dicts
    assert [r["i"] for r in journaled] == first + extra
    with h5py.File(out, "r") as f:
        assert np.count_nonzero(f["status"][...]) == 2  # the atlas is behind its journal

    report = run_sweep(spec, out, serial=True, resume=True)
    assert report.resumed == len(journaled) == 4
    assert report.computed == spec.size - 4 and report.failed == 0
    assert not jp.exists()
    # The journal's points hold the journal's values (not recomputed ones: wall_time too).
    with h5py.File(out, "r") as f, Atlas(out) as atlas:
        assert np.all(f["status"][...] == fmt.STATUS["done"])
        for rec in journaled:
            coords = spec.coords(rec["i"])
            v = atlas.value(**coords)
            assert v["status"] == "done", coords
            for init, run in rec["runs"].items():
                assert v["regime"][init] == run["regime"], (coords, init)
                for name in ("bit_mean", "bit_min", "bit_max", "stick_events", "wall_time"):
                    if run.get(name) is not None:
                        assert v["metrics"][name][init] == run[name], (coords, init, name)
            assert v["stability"]["omega_eq"] == rec["stability"]["omega_eq"], coords
            assert v["stability"]["unstable"] == rec["stability"]["unstable"], coords
            assert v["coexistence"] == rec["coexistence"], coords


CAVEATS = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [50.0, 100.0, 145.0]
torque = [3.5, 8.3, 8.5]
[simulation]
t_end = 300.0
initial = ["rest", "equilibrium"]
"""


def test_each_runs_caveat_is_kept_in_the_atlas_as_simulate_gives_it(tmp_path):
    # The atlas kept a regime but not the run's note: an "oscillation" that was still growing
    # away from an unstable steady state read like a limit cycle. Reference: simulate() at
    # every point and start.
    out = tmp_path / "c.h5"
    spec = parse_spec(CAVEATS)
    run_sweep(spec, out, serial=True)
    seen = set()
    with Atlas(out) as atlas:
        for i in range(spec.size):
            coords = spec.coords(i)
            wob, torque = spec.operating_point(coords)
            v = atlas.value(**coords)
            for init in spec.initials:
                try:
                    r = pydrill.simulate(spec.params_at(coords), wob=wob, torque=torque,
                                         t_end=300.0, initial=init, n_out=2)  # fmt: skip
                    want = r.summary.caveat or None
                    # DESIGN §2's metrics beside the label, the top drive's range too
                    for name in ("top_min", "top_max", "bit_top_ratio", "bit_max", "severity"):
                        got = v["metrics"][name][init]
                        assert got == pytest.approx(getattr(r.summary, name), rel=1e-9), name
                except ValueError:  # no steady state to start from
                    want = None
                assert v["caveat"][init] == want, (coords, init)
                seen.add(want)
        summary = atlas.summary()
        assert atlas.to_xarray()["caveat"].dims == ("wob", "torque", "initial")
    assert "growing" in seen  # the grid meets one
    counts = summary["caveats"]["equilibrium"]
    assert counts["growing"] == sum(
        atlas_v == "growing" for atlas_v in _caveats(out, "equilibrium")
    )
    info = subprocess.run([*CMD, "atlas", "info", out], capture_output=True, text=True)
    assert f"caveats from equilibrium: growing {counts['growing']}" in info.stdout
    query = subprocess.run(
        [*CMD, "atlas", "query", out, "--wob", "145", "--torque", "8.5", "--json"],
        capture_output=True,
        text=True,
    )
    data = json.loads(query.stdout)
    assert data["by_initial"]["caveat"]["equilibrium"] == "growing"


def _caveats(path, init):
    with Atlas(path) as atlas:
        spec = atlas.spec
        return [atlas.value(**spec.coords(i))["caveat"][init] for i in range(spec.size)]


def test_an_atlas_from_before_caveats_reads_none_and_gains_them_on_resume(tmp_path):
    out = tmp_path / "old.h5"
    spec = parse_spec(CAVEATS)
    run_sweep(spec, out, serial=True)
    with h5py.File(out, "r+") as f:  # as written before the datasets existed, half done
        for name in ("caveat", *fmt.ADDED_RUN_FIELDS):
            del f[name]
        f["status"][2, :] = fmt.STATUS["missing"]
    with Atlas(out) as atlas:
        v = atlas.value(wob=50.0, torque=3.5)
        assert v["caveat"] == {"rest": None, "equilibrium": None}
        assert v["metrics"]["top_max"] == {"rest": None, "equilibrium": None}
        assert v["metrics"]["bit_max"]["rest"] is not None
        assert atlas.summary()["caveats"] == {}
        with pytest.raises(AtlasError, match="metric = 'bit_top_ratio' is not in this atlas"):
            atlas.plot("bit_top_ratio")
    report = run_sweep(spec, out, serial=True, resume=True)
    assert report.computed == 3
    with Atlas(out) as atlas:
        v = atlas.value(wob=145.0, torque=8.5)
        assert v["caveat"]["equilibrium"] == "growing"
        assert v["metrics"]["bit_top_ratio"]["rest"] is not None  # computed now: recorded
        assert atlas.value(wob=50.0, torque=3.5)["metrics"]["top_max"]["rest"] is None
        assert set(fmt.ADDED_RUN_FIELDS) <= set(atlas.to_xarray().data_vars)


@pytest.mark.parametrize(
    ("kwargs", "error", "says"),
    [
        ({"stop_on": (99999,)}, ValueError, "stop_on = .* 99999 is not a signal"),
        ({"stop_on": (signal.SIGKILL,)}, ValueError, "is not a signal that can be caught"),
        ({"stop_on": signal.SIGINT}, TypeError, "stop_on = .* a tuple of signals"),
        ({"progress": 5}, TypeError, "progress = 5 is not allowed: None or a function"),
        ({"on_cluster": "x"}, TypeError, "on_cluster = 'x' is not allowed"),
    ],
)
def test_bad_arguments_are_refused_before_anything_is_written(tmp_path, kwargs, error, says):
    """They once failed after the atlas and its journal were made, and the next run was
    refused as if a sweep were there to resume."""
    out = tmp_path / "sub" / "a.h5"
    with pytest.raises(error, match=says):
        run_sweep(parse_spec(SMALL), out, serial=True, **kwargs)
    assert not (tmp_path / "sub").exists()
    assert run_sweep(parse_spec(TINY), out, serial=True, stop_on=[signal.SIGTERM]).computed == 6


def test_a_complete_atlas_resumed_is_not_written_again(tmp_path, monkeypatch):
    """Nothing to compute, nothing to write: a finished atlas that is read-only (archived,
    shared) can be resumed as a check, where opening it for writing failed."""
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(TINY), out, serial=True)

    def refuse(*args):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(fmt, "write", refuse)
    report = run_sweep(parse_spec(TINY), out, serial=True, resume=True)
    assert (report.computed, report.resumed) == (0, 6)


def test_a_full_disk_is_named_with_the_file_and_what_is_kept(tmp_path, monkeypatch):
    """The journal's write fails part way (ENOSPC): one message naming the journal and saying
    that the points before are kept, not a bare "[Errno 28]"; --resume then completes it."""
    out = tmp_path / "a.h5"
    real, calls = os.fsync, []

    def fsync(fd):
        calls.append(fd)
        if len(calls) == 3:  # the journal's header, the first batch, then the disk is full
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(sweep_module, "SYNC_SECONDS", 0.0)  # every batch synced, as on a slow run
    spec = parse_spec(MEDIUM)  # 192 points: a first batch of 96 is saved, the second is not
    with pytest.raises(AtlasError) as err:
        run_sweep(spec, out, serial=True)
    said = str(err.value)
    assert said.startswith(f"{journal_path(out)}: cannot write the journal (No space left")
    assert "the 96 points computed before are kept in it" in said and "resume=True" in said
    monkeypatch.setattr(os, "fsync", real)
    report = run_sweep(spec, out, serial=True, resume=True)
    # at least those 96 (here the failed batch's lines were written before the fsync failed)
    assert report.resumed >= 96 and report.resumed + report.computed == 192


def test_the_journal_is_synced_at_most_once_a_second(tmp_path, monkeypatch):
    """A sync per batch cost 1.5 ms each: the journal is synced once a second at most (a
    crash of the machine loses that second; kill -9 loses nothing, the kernel has it)."""
    real, calls = os.fsync, []

    def fsync(fd):
        calls.append(fd)
        real(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    counts = {}
    for every in (0.0, 1e9):
        monkeypatch.setattr(sweep_module, "SYNC_SECONDS", every)
        calls.clear()
        report = run_sweep(parse_spec(MEDIUM), tmp_path / f"a{every:g}.h5", serial=True)
        counts[every] = len(calls)
    assert report.computed == 192 and sweep_module.SYNC_SECONDS == 1e9
    assert counts[0.0] - counts[1e9] >= 2  # a sync per batch (two batches of 96), or none
    monkeypatch.undo()
    assert sweep_module.SYNC_SECONDS == 1.0


def test_an_atlas_that_cannot_be_written_is_named_with_what_is_kept(tmp_path, monkeypatch):
    out = tmp_path / "a.h5"

    def refuse(*args):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(fmt, "write", refuse)
    with pytest.raises(AtlasError) as err:
        run_sweep(parse_spec(TINY), out, serial=True)
    assert str(err.value).startswith(f"{out}: cannot write the atlas (Read-only file system)")
    assert f"kept in {journal_path(out).name}" in str(err.value)


def test_a_spec_s_implausible_depth_and_loads_are_noted_before_it_runs(tmp_path):
    """depth = "30 km" swept a 3334-inertia string without a word, where 'simulate --depth
    30000m' notes it: a spec gets the single-run commands' notes (the longest well, the
    heaviest W_ob a bit takes, the strongest top drive), on stderr, and runs on."""
    from pydrill.cli_options import HEAVIEST_WOB, LONGEST_WELL, TOP_DRIVE_TORQUE

    tally = ROOT / "examples" / "tallies" / "paper-eq53.toml"
    spec = tmp_path / "deep.toml"
    spec.write_text(
        f'[model]\ntally = "{tally}"\ndof = 4\n'
        f"torque = {TOP_DRIVE_TORQUE * 1.5!r}\n"
        f"[axes]\ndepth = [1000.0, {LONGEST_WELL * 2!r}]\nwob = [60000.0, {HEAVIEST_WOB * 1.5!r}]\n"
    )
    proc = subprocess.run([*CMD, "sweep", str(spec), "--dry-run"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    # (a note that the machine is busy may come too: not the spec's)
    notes = [line for line in proc.stderr.splitlines() if " reaches " in line]
    assert [n.split(": ")[2].split(" reaches ")[0] for n in notes] == [
        "axes.depth",
        "axes.wob",
        "model.torque",
    ]
    assert f"reaches {LONGEST_WELL * 2 / 1e3:g} km" in notes[0]
    plain = spec.read_text().replace(f"{LONGEST_WELL * 2!r}", "3000.0")
    plain = plain.replace(f"{HEAVIEST_WOB * 1.5!r}", "90000.0").replace(
        f"{TOP_DRIVE_TORQUE * 1.5!r}", "9000.0"
    )
    spec.write_text(plain)
    proc = subprocess.run([*CMD, "sweep", str(spec), "--dry-run"], capture_output=True, text=True)
    assert proc.returncode == 0 and " reaches " not in proc.stderr, proc.stderr
