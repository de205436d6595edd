"""Sweeps into atlases: specs, streaming, resume after kill -9, a real Dask cluster."""

import contextlib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import h5py
import numpy as np
import pytest

import pydrill
from pydrill.atlas import Atlas
from pydrill.spec import SpecError, load_spec, parse_spec
from pydrill.sweep import AtlasError, SweepInterrupted, run_sweep

ROOT = Path(__file__).resolve().parents[1]
CMD = [sys.executable, "-m", "pydrill"]

SMALL = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [40.0, 100.0, 160.0]
torque = [6.0, 8.3]
[simulation]
t_end = 200.0
initial = ["rest", "equilibrium"]
"""


def test_shipped_specs_parse():
    minimal = load_spec(ROOT / "sweeps" / "minimal.toml")
    assert minimal.shape == (19, 3) and minimal.initials == ["rest"]
    assert load_spec(ROOT / "sweeps" / "paper-wob-torque.toml").size == 37 * 29


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("[axes]\nwob = [1.0]\n", "axes.torque"),
        ("[model]\nspring = 1\n[axes]\nwob = [1.0]\ntorque = [1.0]\n", "model.spring"),
        ("[axes]\nwob = { start = 1.0, stop = 2.0 }\ntorque = [1.0]\n", "axes.wob"),
        ("[axes]\nwob = [0.0, 1.0]\ntorque = [1.0]\n", "axes.wob"),
        ("[axes]\nwob = [1.0]\ntorque = [1.0]\nheight = [2.0]\n", "axes.height"),
        (
            "[axes]\nwob = [1.0]\ntorque = [1.0]\n[simulation]\ninitial = ['spin']\n",
            "simulation.initial",
        ),
        ("[axes]\nwob = [1.0]\ntorque = [1.0]\n[simulation]\nt_end = -3\n", "simulation.t_end"),
        ("[axes]\nwob = [1.0]\ntorque = [1.0]\nbit_damping = [-1.0, 0.1]\n", "model"),
        ("[axes]\nwob = [1.0]\ntorque = [1.0]\n[extras]\n", "extras"),
        ("[axes\n", "not valid TOML"),
    ],
)
def test_bad_spec_is_refused_naming_the_key_and_nothing_is_written(tmp_path, text, key):
    with pytest.raises(SpecError) as err:
        parse_spec(text)
    assert key in str(err.value)
    spec_file = tmp_path / "bad.toml"
    spec_file.write_text(text)
    out = tmp_path / "bad.h5"
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out)], capture_output=True, text=True
    )
    assert proc.returncode == 2 and key in proc.stderr and "Traceback" not in proc.stderr
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_atlas_holds_what_was_computed(tmp_path):
    out = tmp_path / "small.h5"
    spec = parse_spec(SMALL)
    report = run_sweep(spec, out, serial=True)
    assert report.computed == 6 and report.failed == 0
    assert not Path(str(out) + ".journal").exists()
    p = pydrill.preset("reduced-scale", dof=4)
    with h5py.File(out, "r") as f:  # plain h5py: dimension scales and enum
        assert f["regime"].dims[0][0].name == "/wob" and f["regime"].dims[2][0].name == "/initial"
        assert h5py.check_enum_dtype(f["regime"].dtype)["stick-slip"] == 1
        assert f["bit_mean"].compression == "gzip" or f["bit_mean"].chunks is None
    with Atlas(out) as atlas:
        for wob in (40.0, 100.0, 160.0):
            for torque in (6.0, 8.3):
                v = atlas.value(wob=wob, torque=torque)
                direct = pydrill.simulate(p, wob=wob, torque=torque, t_end=200.0)
                assert v["regime"]["rest"] == direct.regime
                assert v["metrics"]["bit_mean"]["rest"] == pytest.approx(direct.summary.bit_mean)
                eqs = pydrill.stability.stability(p, wob, torque=torque)
                assert len(v["stability"]["omega_eq"]) == len(eqs)
        ds = atlas.to_xarray()
        assert list(ds.regime.dims) == ["wob", "torque", "initial"]
        np.testing.assert_allclose(ds.wob.values, [40.0, 100.0, 160.0])
        assert int(ds.regime.sel(wob=100.0, torque=8.3, initial="rest")) == 1  # stick-slip
        assert ds.omega_eq.sel(wob=40.0, torque=8.3).values[0] == pytest.approx(33.15789473684)
        # A slice: the regime from rest against W_ob at u = 8.3 N·m.
        row = atlas.sel(torque=8.3, initial="rest")
        assert row.regime.values.tolist() == [0, 1, 2]
        assert row.regime_name.values.tolist() == ["steady", "stick-slip", "stuck"]
        meanings = ds.regime.attrs["flag_meanings"].split()
        codes = ds.regime.attrs["flag_values"].tolist()
        assert meanings[codes.index(1)] == "stick_slip"
        # Paper: at W_ob = 100 N, u = 8.3 N·m the steady state coexists with stick-slip.
        assert atlas.value(wob=100.0, torque=8.3)["coexistence"] is True
        ds.close()


def test_failing_point_is_recorded_and_the_rest_done(tmp_path):
    text = SMALL.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]\nmax_steps = 900')
    report = run_sweep(parse_spec(text), tmp_path / "f.h5", serial=True)
    assert 0 < report.failed < report.points
    with Atlas(tmp_path / "f.h5") as atlas:
        bad = atlas.value(wob=100.0, torque=8.3)  # stick-slip needs more steps
        assert bad["status"] == "failed" and "max_steps" in bad["message"]
        good = atlas.value(wob=160.0, torque=8.3)
        assert good["status"] == "done" and good["regime"]["rest"] == "stuck"


def test_other_spec_is_never_overwritten(tmp_path):
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    before = out.read_bytes()
    with pytest.raises(AtlasError, match="different sweep"):
        run_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 100.0")), out, serial=True)
    with pytest.raises(AtlasError, match="--resume"):
        run_sweep(parse_spec(SMALL), out, serial=True)
    assert out.read_bytes() == before
    # Resuming a finished sweep computes nothing.
    assert run_sweep(parse_spec(SMALL), out, serial=True, resume=True).computed == 0


def test_damaged_atlas_gives_a_clear_error(tmp_path):
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    data = out.read_bytes()
    out.write_bytes(data[: len(data) // 3])
    with pytest.raises(AtlasError, match="not a readable HDF5 atlas"):
        Atlas(out)
    proc = subprocess.run([*CMD, "atlas", "info", str(out)], capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    junk = tmp_path / "junk.h5"
    with h5py.File(junk, "w") as f:
        f["x"] = 1
    with pytest.raises(AtlasError, match="not a pydrill atlas"):
        Atlas(junk)


def test_query_command_json(tmp_path):
    out = tmp_path / "a.h5"
    run_sweep(parse_spec(SMALL), out, serial=True)
    proc = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "100", "--torque", "8.3", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(proc.stdout)
    assert data["regime"] == "stick-slip"
    assert data["period"] > 0 and data["units"]["period"] == "s"
    kn = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "0.1kN", "--torque", "0.0083 kN·m", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(kn.stdout)["regime"] == "stick-slip"
    miss = subprocess.run(
        [*CMD, "atlas", "query", str(out), "--wob", "99", "--torque", "8.3"],
        capture_output=True,
        text=True,
    )
    assert miss.returncode == 2 and "not on the grid" in miss.stderr
    assert miss.stderr.startswith("pydrill atlas query: error: ") and "--nearest" in miss.stderr
    with Atlas(out) as atlas:  # SMALL's wob: 40, 100, 160 (steps of 60)
        assert atlas.value("nearest", wob=189.0, torque=8.3)["coords"]["wob"] == 160.0
        with pytest.raises(KeyError, match=r"wob = 191 is outside the atlas \(40 \.\.\. 160\)"):
            atlas.value("nearest", wob=191.0, torque=8.3)  # more than half a step beyond


def _atlas_arrays(path):
    with h5py.File(path, "r") as f:
        return {name: f[name][...] for name in f if name not in ("wall_time",)}


def _same_atlas(a, b):
    x, y = _atlas_arrays(a), _atlas_arrays(b)
    assert x.keys() == y.keys()
    for name in x:
        if x[name].dtype.kind == "f":
            np.testing.assert_array_equal(
                np.nan_to_num(x[name], nan=-7.0), np.nan_to_num(y[name], nan=-7.0), err_msg=name
            )
        else:
            np.testing.assert_array_equal(x[name], y[name], err_msg=name)


def _wait_for_journal(journal: Path, more_than: int, proc: subprocess.Popen) -> None:
    """Until ``journal`` holds more than ``more_than`` lines, while the sweep ``proc`` runs."""
    deadline = time.time() + 120
    while not (journal.exists() and journal.read_text().count("\n") > more_than):
        assert proc.poll() is None, "the sweep ended before the test could interrupt it"
        assert time.time() < deadline, "the sweep journaled nothing in 120 s"
        time.sleep(0.02)


MEDIUM = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 16 }
torque = { start = 4.0, stop = 14.0, num = 12 }
[simulation]
t_end = 300.0
initial = ["rest"]
"""


@pytest.mark.slow
def test_kill_minus_9_then_resume_gives_the_same_atlas(tmp_path):
    spec_file = tmp_path / "m.toml"
    spec_file.write_text(MEDIUM)
    reference = tmp_path / "ref.h5"
    run_sweep(parse_spec(MEDIUM), reference, serial=True)
    out = tmp_path / "killed.h5"
    journal = Path(str(out) + ".journal")
    proc = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    _wait_for_journal(journal, 40, proc)  # some, not all, points are journaled
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    assert journal.exists()
    done_before = journal.read_text().count("\n") - 1
    assert 0 < done_before < 16 * 12
    report = run_sweep(parse_spec(MEDIUM), out, resume=True, serial=True)
    assert report.resumed >= done_before
    assert report.resumed + report.computed == 16 * 12
    _same_atlas(out, reference)


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow
def test_real_dask_cluster_and_a_worker_killed_mid_sweep(tmp_path):
    dask_bin = Path(sys.executable).parent / "dask"
    if not dask_bin.exists():
        dask_bin = shutil.which("dask")
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    procs = [
        subprocess.Popen(
            [
                str(dask_bin),
                "scheduler",
                "--host",
                "127.0.0.1",
                "--port",
                str(port),
                "--dashboard-address",
                ":0",
                "--scheduler-file",
                str(tmp_path / "scheduler.json"),
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
            start_new_session=True,
        )
    ]
    try:
        time.sleep(2.0)
        for _ in range(2):
            procs.append(
                subprocess.Popen(
                    [
                        str(dask_bin),
                        "worker",
                        address,
                        "--nthreads",
                        "1",
                        "--no-nanny",
                        "--host",
                        "127.0.0.1",
                    ],
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                    env=env,
                    start_new_session=True,
                )
            )
        from distributed import Client

        with Client(address, timeout="30s") as client:
            client.wait_for_workers(2, timeout=60)
        spec_file = tmp_path / "m.toml"
        spec_file.write_text(MEDIUM)
        out = tmp_path / "cluster.h5"
        journal = Path(str(out) + ".journal")
        sweep = subprocess.Popen(
            [*CMD, "sweep", str(spec_file), "--out", str(out), "--scheduler", address, "--json"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        deadline = time.time() + 120
        while time.time() < deadline:
            if journal.exists() and journal.read_text().count("\n") > 20:
                break
            time.sleep(0.05)
        os.killpg(procs[1].pid, signal.SIGKILL)  # a worker dies mid-sweep
        stdout, stderr = sweep.communicate(timeout=300)
        assert sweep.returncode == 0, stderr
        report = json.loads(stdout)
        assert report["computed"] == 16 * 12 and report["failed"] == 0
        reference = tmp_path / "ref.h5"
        run_sweep(parse_spec(MEDIUM), reference, serial=True)
        _same_atlas(out, reference)
        # The same cluster found through its scheduler file, as on a batch system.
        small = tmp_path / "small.toml"
        small.write_text(SMALL)
        args = ["sweep", str(small), "--out", str(tmp_path / "file.h5"), "--json"]
        via_file = subprocess.run(
            [*CMD, *args, "--scheduler", str(tmp_path / "scheduler.json")],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert via_file.returncode == 0, via_file.stderr
        assert json.loads(via_file.stdout)["computed"] == parse_spec(SMALL).size
        # The cluster's own dashboard, its link printed for the user, answers.
        link = re.search(rf"scheduler {address}, dashboard (\S+)", via_file.stderr)
        assert link, via_file.stderr
        with urllib.request.urlopen(link[1], timeout=30) as page:
            assert page.status == 200 and b"Dask" in page.read()
        # Named in the environment, as a Dask user names their cluster for every client.
        via_env = subprocess.run(
            [*CMD, "sweep", str(small), "--out", str(tmp_path / "env.h5"), "--json"],
            capture_output=True,
            text=True,
            timeout=120,
            env={**os.environ, "DASK_SCHEDULER_ADDRESS": address},
        )
        assert via_env.returncode == 0, via_env.stderr
        assert json.loads(via_env.stdout)["computed"] == parse_spec(SMALL).size
        assert f"scheduler {address} (from DASK_SCHEDULER_ADDRESS" in via_env.stderr
    finally:
        for p in procs:
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()


def test_depth_sweep_of_a_tally_string(tmp_path):
    spec = load_spec(ROOT / "sweeps" / "paper-string-depth.toml")
    assert spec.tally_text and "depth" in spec.axes
    shallow = spec.params_at({"depth": 500.0, "wob": 5e4})
    deep = spec.params_at({"depth": 5000.0, "wob": 5e4})
    assert shallow.dof == deep.dof == 12  # reduced, as the spec asks
    # Deeper string: softer (springs in series) and heavier.
    assert sum(1 / k for k in deep.stiffnesses) > 5 * sum(1 / k for k in shallow.stiffnesses)
    assert sum(deep.inertias) > sum(shallow.inertias)
    small = spec.text.replace("[500.0, 1000.0, 2000.0, 3000.0, 4000.0, 5000.0]", "[500.0, 4000.0]")
    small = small.replace("num = 6", "num = 2")
    s2 = parse_spec(small, tally_text=spec.tally_text)
    out = tmp_path / "depth.h5"
    run_sweep(s2, out, serial=True)
    with Atlas(out) as atlas:  # reopened without the tally file: its text is in the atlas
        assert atlas.spec.tally_text == spec.tally_text
        assert set(atlas.axes) == {"depth", "wob"}
        v = atlas.value(depth=4000.0, wob=20000.0)
        assert v["status"] == "done"
    with pytest.raises(SpecError, match=r"model\.tally"):
        parse_spec(
            '[model]\ntally = "nowhere.toml"\n[axes]\ndepth = [1000.0]\nwob = [1.0]\n'
            "torque = [1.0]\n"
        )


def test_batches_deal_every_point_once_in_shrinking_batches():
    from pydrill.sweep import batches

    todo = np.arange(3, 2003)
    parts = batches(todo, 2)
    flat = np.concatenate(parts)
    assert sorted(flat.tolist()) == todo.tolist()  # each point exactly once
    sizes = [len(p) for p in parts]
    assert sizes[0] == 256 and all(16 <= s <= 256 for s in sizes[:-1])
    assert sizes == sorted(sizes, reverse=True)  # guided: the tail is made of small batches
    # Pseudo-random, not contiguous: the first batch samples the whole grid.
    assert np.ptp(parts[0]) > 0.9 * np.ptp(todo)
    assert batches(todo, 2)[3] == parts[3]  # the same deal every time
    assert batches(np.array([], dtype=int), 2) == []


def test_block_of_records_equals_records_applied_one_by_one():
    from pydrill import atlas_format as fmt
    from pydrill.sweep import evaluate_batch, evaluate_point

    spec = parse_spec(SMALL)
    picked = [4, 0, 5, 2]
    indices, block, lines = evaluate_batch(spec.text, picked)
    assert indices.tolist() == picked and len(lines.splitlines()) == len(picked)
    by_block, by_record = fmt.AtlasTable(spec), fmt.AtlasTable(spec)
    by_block.put(indices, block)
    for i in picked:
        by_record.apply(evaluate_point(spec, i))
    for name, a in by_block.columns().items():
        b = by_record.columns()[name]
        if name in ("message", "run:wall_time"):
            assert a.shape == b.shape
            continue
        assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), name
    assert sorted(by_block.missing().tolist()) == [1, 3]


def test_a_reader_holding_the_atlas_open_does_not_stop_the_writer(tmp_path):
    # The sweep writes without HDF5's file lock: a `pydrill atlas info` during a flush, or a
    # worker forked while the file was open, must not make the next flush fail.
    from pydrill import atlas_format as fmt

    spec = parse_spec(SMALL)
    out = tmp_path / "a.h5"
    fmt.create(out, spec, "{}", "test")
    table = fmt.AtlasTable(spec)
    table.status[...] = fmt.STATUS["failed"]
    reader = subprocess.Popen(  # another process reads, with HDF5's default lock
        [
            sys.executable,
            "-c",
            "import h5py,sys,time; f=h5py.File(sys.argv[1]); print(1); "
            "sys.stdout.flush(); time.sleep(60)",
            str(out),
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert reader.stdout.readline().strip() == "1"
        fmt.write(out, table)
    finally:
        reader.kill()
        reader.wait()
        reader.stdout.close()
    with h5py.File(out, "r") as f:
        assert np.all(f["status"][...] == fmt.STATUS["failed"])


def test_a_sweep_beside_another_cluster_on_port_8787_stays_quiet(tmp_path):
    """Dask's HTTP port 8787 is often held by a user's own cluster (or its dashboard). The
    sweep's throwaway cluster then used to warn "Port 8787 is already in use"; with pytest's
    warnings-as-errors this test failed before the sweep asked for any free port."""
    holder = socket.socket()
    try:
        holder.bind(("", 8787))
        holder.listen()
    except OSError:
        pass  # somebody else holds it already: the same situation
    try:
        spec = parse_spec(SMALL.replace("[40.0, 100.0, 160.0]", "[40.0, 160.0]"))
        report = run_sweep(spec, tmp_path / "beside.h5", workers=2)
        assert report.computed == 4 and report.failed == 0
    finally:
        holder.close()


# Slow enough per point (5-6 ms) that a sweep is still running when the test interrupts it.
LONGER = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 20.0, stop = 200.0, num = 32 }
torque = { start = 4.0, stop = 14.0, num = 16 }
[simulation]
t_end = 3000.0
initial = ["rest", "equilibrium"]
"""


def _interrupt_mid_sweep(tmp_path, sig, *extra):
    """Start ``pydrill sweep`` on LONGER, send ``sig`` to its whole process group (what Ctrl-C
    in a terminal does) once its first batch is journaled; return (rc, stdout, stderr, atlas)."""
    spec_file = tmp_path / "longer.toml"
    spec_file.write_text(LONGER)
    out = tmp_path / "stopped.h5"
    journal = Path(str(out) + ".journal")
    proc = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        # A shell's background job ignores SIGINT; a terminal's foreground one does not.
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    _wait_for_journal(journal, 1, proc)
    os.killpg(proc.pid, sig)
    stdout, err = proc.communicate(timeout=60)
    return proc.returncode, stdout, err, out


def test_ctrl_c_stops_a_dask_sweep_quietly_and_keeps_every_finished_point(tmp_path):
    rc, _, err, out = _interrupt_mid_sweep(tmp_path, signal.SIGINT, "--workers", "2")
    assert rc == 130, err
    assert "Traceback" not in err  # neither the client's nor the workers'
    assert "interrupted" in err and "--resume" in err
    journal = Path(str(out) + ".journal")
    journaled = {json.loads(line)["i"] for line in journal.read_text().splitlines()[1:]}
    total = 32 * 16
    assert 0 < len(journaled) < total
    with h5py.File(out, "r") as f:  # flushed on the way out: the atlas shows them already
        done = np.flatnonzero(f["status"][...].ravel() != 0)
    assert set(done.tolist()) == journaled
    assert f"{len(journaled)} of {total} points are saved" in err
    report = run_sweep(parse_spec(LONGER), out, resume=True, serial=True)
    assert report.resumed == len(journaled) and report.computed == total - len(journaled)
    assert not journal.exists()


def test_sigterm_stops_a_serial_sweep_like_ctrl_c(tmp_path):
    rc, stdout, err, out = _interrupt_mid_sweep(tmp_path, signal.SIGTERM, "--serial", "--json")
    assert rc == 128 + signal.SIGTERM, err
    assert "Traceback" not in err and "--resume" in err
    from pydrill.plot_atlas import atlas_figure

    with Atlas(out) as atlas:
        s = atlas.summary()
        title = atlas_figure(atlas).axes[0].get_title()
    assert 0 < s["status"]["done"] < 32 * 16
    assert s["journal"] == str(out) + ".journal"
    assert f"({s['status']['done']} of 512 points done)" in title  # blank cells explained
    data = json.loads(stdout)  # --json: scripts learn of the stop too
    assert data["interrupted"] is True and data["done"] == s["status"]["done"]
    assert data["resume"].endswith(f"--out {out} --resume")


def test_a_journal_line_cut_mid_write_is_recomputed_and_cut_off(tmp_path):
    """A kill while a batch was being appended leaves a last line without its end. Resuming
    drops it, and must cut it off the file: the next batch appended after it would otherwise
    share its line, and the journal could never be read again."""
    spec = parse_spec(SMALL)
    out = tmp_path / "cut.h5"
    reference = tmp_path / "ref.h5"
    run_sweep(spec, reference, serial=True)
    journal = Path(str(out) + ".journal")
    from pydrill.sweep import evaluate_point

    header = json.dumps({"spec_digest": spec.digest}) + "\n"
    whole = json.dumps(evaluate_point(spec, 0)) + "\n"
    cut = json.dumps(evaluate_point(spec, 1))[:37]
    journal.write_text(header + whole + cut)
    report = run_sweep(spec, out, resume=True, serial=True)
    assert report.resumed == 1 and report.computed == spec.size - 1
    _same_atlas(out, reference)
    # The same, interrupted again right after the resume appended: readable, nothing lost.
    journal.write_text(header + whole + cut)
    out.unlink()
    from pydrill.journal import read_journal

    assert [r["i"] for r in read_journal(out, spec)] == [0]
    with journal.open("a") as fh:
        fh.write(json.dumps(evaluate_point(spec, 2)) + "\n")
    assert [r["i"] for r in read_journal(out, spec)] == [0, 2]


def test_a_damaged_journal_line_is_named(tmp_path):
    spec = parse_spec(SMALL)
    out = tmp_path / "bad.h5"
    from pydrill.sweep import evaluate_point

    Path(str(out) + ".journal").write_text(
        json.dumps({"spec_digest": spec.digest})
        + "\n{not json\n"
        + json.dumps(evaluate_point(spec, 0))
        + "\n"
    )
    with pytest.raises(AtlasError, match=r"journal, line 2, is damaged"):
        run_sweep(spec, out, resume=True, serial=True)


def test_no_scheduler_at_the_address_is_one_clear_error_and_leaves_no_files(tmp_path):
    out = tmp_path / "never.h5"
    nobody = f"tcp://127.0.0.1:{_free_port()}"
    proc = subprocess.run(
        [
            *CMD,
            "sweep",
            str(ROOT / "sweeps" / "minimal.toml"),
            "--out",
            str(out),
            "--scheduler",
            nobody,
        ],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "2s"},
    )
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert "--scheduler tcp://127.0.0.1:" in proc.stderr and "dask scheduler" in proc.stderr
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    # So the same command, once the address is right, needs no --resume nor any cleaning up.
    report = run_sweep(load_spec(ROOT / "sweeps" / "minimal.toml"), out, serial=True)
    assert report.computed == report.points


def test_local_workers_that_cannot_start_are_one_clear_error(tmp_path):
    import dask

    from pydrill.sweep import SchedulerError

    out = tmp_path / "never.h5"
    # A worker preloads this module before it registers; there is none, so none starts.
    broken = {"distributed.worker.preload": ["pydrill_test_no_such_module"]}
    with (
        dask.config.set(broken),
        pytest.raises(SchedulerError, match=r"workers did not start \(.*pydrill_test_no_such"),
    ):
        run_sweep(parse_spec(SMALL), out, workers=1)
    assert not out.exists() and not Path(str(out) + ".journal").exists()


def test_a_missing_scheduler_file_is_named_and_nothing_is_written(tmp_path):
    from pydrill.sweep import SchedulerError

    out = tmp_path / "never.h5"
    with pytest.raises(SchedulerError, match=r"no such scheduler file.*--scheduler-file"):
        run_sweep(parse_spec(SMALL), out, scheduler=str(tmp_path / "gone.json"))
    assert not out.exists() and not Path(str(out) + ".journal").exists()


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="needs two cores to pin to one")
def test_default_workers_are_the_cores_this_process_may_use(tmp_path):
    # Pinned to one core (as a container's --cpus or a batch job's allocation would), the local
    # cluster gets one worker, not one per core of the host.
    script = f"""
import distributed
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep
asked = []
class Recording(distributed.LocalCluster):
    def __init__(self, *args, **kwargs):
        asked.append(kwargs["n_workers"])
        super().__init__(*args, **kwargs)
distributed.LocalCluster = Recording
run_sweep(parse_spec({SMALL!r}), {str(tmp_path / "pinned.h5")!r})
print(asked)
"""
    proc = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        timeout=120,
        preexec_fn=lambda: os.sched_setaffinity(0, {min(os.sched_getaffinity(0))}),
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[1]"


def test_conflicting_places_to_run_are_refused_before_anything_is_written(tmp_path):
    out = tmp_path / "never.h5"
    with pytest.raises(ValueError, match="at most one of workers"):
        run_sweep(parse_spec(SMALL), out, serial=True, workers=2)
    assert not out.exists() and not Path(str(out) + ".journal").exists()
    proc = subprocess.run(
        [
            *CMD,
            "sweep",
            str(ROOT / "sweeps" / "minimal.toml"),
            "--out",
            str(out),
            "--serial",
            "--scheduler",
            "tcp://127.0.0.1:8786",
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and "not allowed with argument --serial" in proc.stderr
    assert not out.exists()


def test_a_second_sweep_into_an_atlas_being_written_is_refused(tmp_path):
    """Before the lock, ``--resume`` from a second terminal ran beside the first sweep: two
    writers appending to one journal and overwriting each other's atlas flushes."""
    spec_file = tmp_path / "longer.toml"
    spec_file.write_text(LONGER)
    out = tmp_path / "busy.h5"
    journal = Path(str(out) + ".journal")
    first = subprocess.Popen(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        _wait_for_journal(journal, 1, first)
        before = journal.read_bytes()
        with pytest.raises(
            AtlasError, match=rf"being written by another sweep \(process {first.pid}\)"
        ):
            run_sweep(parse_spec(LONGER), out, resume=True, serial=True)
        assert journal.read_bytes()[: len(before)] == before  # untouched by the refused one
        # kill -9 of the sweep alone: its lock file stays, but the kernel drops the lock
        # with the process, though its workers may still be finishing their batches.
        os.kill(first.pid, signal.SIGKILL)
        first.wait()
        report = run_sweep(parse_spec(LONGER), out, resume=True, serial=True)
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(first.pid, signal.SIGKILL)
    assert report.resumed + report.computed == 32 * 16
    assert not Path(str(out) + ".lock").exists()


def test_a_dask_client_of_the_callers_runs_the_sweep_and_stays_open(tmp_path):
    """In a notebook the Dask cluster already exists: pass its Client, as Dask users do."""
    from distributed import Client, LocalCluster

    reference = tmp_path / "ref.h5"
    run_sweep(parse_spec(SMALL), reference, serial=True)
    with (
        LocalCluster(n_workers=1, processes=False, dashboard_address=":0") as cluster,
        Client(cluster) as client,
    ):
        report = run_sweep(parse_spec(SMALL), tmp_path / "client.h5", scheduler=client)
        assert report.computed == 6
        assert not client.futures  # nothing of the sweep's left behind on it
        assert client.submit(sum, [1, 2], pure=False).result() == 3  # still the caller's

        def stop_after_the_first_batch(n, total):
            raise KeyboardInterrupt

        with pytest.raises(SweepInterrupted) as stopped:
            run_sweep(
                parse_spec(MEDIUM),
                tmp_path / "stopped.h5",
                scheduler=client,
                progress=stop_after_the_first_batch,
            )
        assert 0 < stopped.value.done < 16 * 12
        assert not client.futures  # the batches not yet done were cancelled, not left running
        assert client.submit(sum, [3, 4], pure=False).result() == 7
    _same_atlas(tmp_path / "client.h5", reference)


SIZES = """
[model]
preset = "reduced-scale"
[axes]
dof = [4, 8]
wob = [40.0, 100.0, 160.0, 220.0]
torque = [6.0, 8.3, 12.0]
[simulation]
t_end = 200.0
initial = ["rest"]
"""


def test_atlas_plot_draws_the_chosen_axes_at_the_held_values(tmp_path):
    from pydrill.plot_atlas import atlas_figure

    out = tmp_path / "sizes.h5"
    run_sweep(parse_spec(SIZES), out, serial=True)
    shown = ["steady", "stick-slip", "stuck", "oscillation", "failed", "missing", "no-steady-state"]
    with Atlas(out) as atlas:
        names = atlas.regimes("rest")  # (dof, wob, torque)
        fig = atlas_figure(atlas, x="torque", y="wob", at={"dof": 7.2})  # nearest: dof 8
        ax = fig.axes[0]
        image = np.asarray(ax.collections[0].get_array()).reshape(4, 3)  # rows: wob
        assert (np.array(shown)[image] == names[1]).all()
        assert "dof = 8" in ax.get_title()
        assert ax.get_xlabel() == "surface torque $u$ (N·m)"
        # (W_ob, u) with the string held: the stuck boundary and the Hopf curve on top
        assert [line.get_label()[:5] for line in ax.get_lines()] == ["stuck", "first"]
        default = atlas_figure(atlas).axes[0]  # the first two swept axes, dof and wob
        assert default.get_xlabel() == "degrees of freedom" and "torque = 6" in default.get_title()
        assert list(default.get_xticks()) == [4, 8]
        for bad, message in [
            (dict(x="wob", y="wob"), "two different axes"),
            (dict(x="depth"), "x = 'depth' is not an axis"),
            (dict(x="wob", at={"wob": 100.0}), "'wob' is drawn"),
            (dict(at={"dof": 4, "torque": 6, "wob": 40}), "no axis left"),
        ]:
            with pytest.raises(ValueError, match=message):
                atlas_figure(atlas, **bad)
    chosen = ["--x", "wob", "--y", "torque", "--set", "dof=8"]
    proc = subprocess.run(
        [*CMD, "atlas", "plot", str(out), "--out", str(tmp_path / "m.png"), *chosen],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0 and (tmp_path / "m.png").stat().st_size > 10_000
