"""Sweeps into atlases: specs, what the atlas holds, failed points, damaged files."""

import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from sweeping import CMD, ROOT, SMALL, same_atlas

import pydrill
from pydrill.atlas import Atlas
from pydrill.spec import SpecError, load_spec, parse_spec
from pydrill.sweep import AtlasError, run_sweep


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
        (
            "[axes]\nwob = [1.0]\ntorque = [1.0]\nbit_damping = [-1.0, 0.1]\n",
            "model (at axes.bit_damping = -1): ",
        ),
        (  # pipes = 50 makes dof = 53: the swept value the user wrote is named
            "[model]\npreset = 'real-string'\n[axes]\npipes = [50]\nwob = [1.0]\ntorque = [1.0]\n",
            "model (at axes.pipes = 50): dof = 53 is not allowed for preset 'real-string'",
        ),
        ("[axes]\nwob = [1.0]\ntorque = [1.0]\n[extras]\n", "extras"),
        ("[axes\n", "not valid TOML"),
        # once tracebacks (tests/test_spec.py has the rest of their kind)
        ("model = 5\n[axes]\nwob = [50.0]\ntorque = [6.0]\n", "model"),
        ("[axes]\nwob = [50.0]\ntorque = [6.0]\n[simulation]\nwindow = '0.5'\n", "window"),
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
        assert meanings[codes.index(1)] == "stick-slip"
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
    # It says what differs, key by key, not only that the digests do.
    with pytest.raises(
        AtlasError,
        match=r"holds a different sweep \(simulation.t_end: 100.0 in this spec, 200.0 in the "
        r"atlas\); choose another out=PATH",
    ):
        run_sweep(parse_spec(SMALL.replace("t_end = 200.0", "t_end = 100.0")), out, serial=True)
    other = SMALL.replace("[6.0, 8.3]", "[6.0, 8.3, 9.0]").replace('"equilibrium"]', "]")
    said = (
        r"axes.torque: \[6 N·m, 8.3 N·m, 9 N·m\] in this spec, \[6 N·m, 8.3 N·m\] in the atlas; "
        r"simulation.initial: \['rest'\] in this spec"
    )
    with pytest.raises(AtlasError, match=said):
        run_sweep(parse_spec(other), out, serial=True)
    with pytest.raises(AtlasError, match="resume=True"):  # (the API's words; the CLI's: --resume)
        run_sweep(parse_spec(SMALL), out, serial=True)
    assert out.read_bytes() == before
    # Resuming a finished sweep computes nothing, and the atlas it reads back and writes again
    # keeps every dataset (both starts, coexistence, eigenvalues, caveats) as it was.
    reference = tmp_path / "before.h5"
    reference.write_bytes(before)
    assert run_sweep(parse_spec(SMALL), out, serial=True, resume=True).computed == 0
    same_atlas(out, reference)


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
    # A directory given for the atlas: said so, not "damaged", and nothing written in it.
    folder = tmp_path / "runs.h5"
    folder.mkdir()
    with pytest.raises(AtlasError, match=r"runs\.h5 is a directory, not an atlas file"):
        Atlas(folder)
    with pytest.raises(AtlasError, match=r"runs\.h5 is a directory; give .* e\.g\. .*runs\.h5/atl"):
        run_sweep(parse_spec(SMALL), folder, serial=True)
    assert list(folder.iterdir()) == [] and sorted(tmp_path.glob("runs.h5*")) == [folder]


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


def test_batches_once_timed_are_sized_by_time_and_points_handed_back_come_first():
    from pydrill.batching import BATCH_SECONDS, LEAST_SECONDS, Batcher

    todo = np.arange(10_000)
    deal = Batcher(todo)
    assert deal.size(2) == 256 and deal.point_seconds is None  # by count until timed
    first = deal.take(2)
    deal.timed(4, 4 * 0.5)  # half a second a point: at most BATCH_SECONDS of them
    cap = int(BATCH_SECONDS / 0.5)
    assert deal.size(2) == cap
    deal.give_back(first[4:])  # a batch out of time computed 4 of its points
    again = deal.take(2)
    assert again == first[4 : 4 + cap]  # the points handed back go out first, in order
    rest = deal.rest(2)
    assert all(len(b) <= cap for b in rest) and len(rest[-1]) == 1  # down to one point
    dealt = first[:4] + again + [i for b in rest for i in b]
    assert sorted(dealt) == todo.tolist()  # every point exactly once
    cheap = Batcher(todo)
    cheap.timed(100, 100 * 1e-3)  # a millisecond a point: no batch under LEAST_SECONDS
    sizes = [len(b) for b in cheap.rest(2)]
    assert min(sizes[:-1]) >= min(16, LEAST_SECONDS / 1e-3) and max(sizes) == 256


def test_a_batch_out_of_time_hands_back_the_points_it_did_not_reach():
    from pydrill.sweep import evaluate_batch

    spec = parse_spec(SMALL)
    done = evaluate_batch(spec.text, [4, 0, 5, 2], None, budget=0.0)
    assert done.indices.tolist() == [4] and done.left == [0, 5, 2]
    assert len(done.lines.splitlines()) == 1


@pytest.mark.parametrize("where", ["serial", "dask"])
def test_a_sweep_of_batches_out_of_time_computes_every_point_once(tmp_path, monkeypatch, where):
    """Every batch stops after its first point (no time at all): the points handed back are
    dealt again, one a batch, and the atlas is the one of an ordinary sweep."""
    import pydrill.batching

    reference = tmp_path / "ref.h5"
    run_sweep(parse_spec(SMALL), reference, serial=True)
    monkeypatch.setattr(pydrill.batching, "BATCH_SECONDS", 0.0)
    sizes = []
    out = tmp_path / f"{where}.h5"
    kw = {"serial": True} if where == "serial" else {"workers": 2}
    report = run_sweep(parse_spec(SMALL), out, progress=lambda n, _: sizes.append(n), **kw)
    assert report.computed == parse_spec(SMALL).size == len(sizes) and set(sizes) == {1}
    same_atlas(out, reference)


def test_each_string_of_a_sweep_has_its_own_crossings():
    """evaluate_point keeps each string's crossings across points (and batches): points of
    strings of 2, 4 and 8 dof, in the sweep's mixed order, analysed as if alone."""
    from pydrill.stability import stability
    from pydrill.sweep import dealing_order, evaluate_point

    spec = parse_spec(
        SMALL.replace("dof = 4\n", "").replace("[axes]\n", "[axes]\ndof = [2, 4, 8]\n")
    )
    assert spec.shape == (3, 3, 2)
    for i in dealing_order(np.arange(spec.size)):
        rec = evaluate_point(spec, int(i))
        coords = spec.coords(int(i))
        wob, torque = spec.operating_point(coords)
        alone = stability(spec.params_at(coords), wob, torque=torque)[::-1]
        assert rec["stability"]["hopf_margin"] == [q.delta_margin for q in alone], coords
        assert rec["stability"]["unstable"] == [q.unstable for q in alone], coords


def test_block_of_records_equals_records_applied_one_by_one():
    from pydrill import atlas_format as fmt
    from pydrill.sweep import evaluate_batch, evaluate_point

    spec = parse_spec(SMALL)
    picked = [4, 0, 5, 2]
    indices, block, lines, seconds, left = evaluate_batch(spec.text, picked)
    assert seconds > 0 and left == []
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


def test_a_sweep_whose_every_point_failed_is_an_error_not_a_result(tmp_path):
    # It used to end "6 computed now (6 failed)" with exit status 0: a batch job, a script or a
    # make rule took an atlas of failures for a finished study.
    spec_file = tmp_path / "fails.toml"
    spec_file.write_text(SMALL.replace("t_end = 200.0", "t_end = 200.0\nmax_steps = 10"))
    out = tmp_path / "fails.h5"
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--serial", "--plot", "m.png"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert proc.returncode == 3, proc.stderr  # as a solver failure (pydrill simulate)
    assert "every point failed (6 of 6)" in proc.stderr
    assert "max_steps = 10 internal steps reached" in proc.stderr  # the first one's why
    assert not (tmp_path / "m.png").exists()  # a map of failures only is not drawn
    with Atlas(out) as atlas:  # the atlas keeps each point's message all the same
        assert atlas.summary()["status"]["failed"] == 6
    report = run_sweep(parse_spec(spec_file.read_text()), tmp_path / "api.h5", serial=True)
    assert report.all_failed and report.failed_in_atlas == 6
    assert report.first_failure.startswith("SolverError: max_steps = 10")


def test_a_sweep_with_some_failed_points_says_why_and_succeeds(tmp_path):
    spec_file = tmp_path / "some.toml"
    spec_file.write_text(
        SMALL.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]\nmax_steps = 900')
    )
    proc = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(tmp_path / "s.h5"), "--serial", "--json"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    assert "points failed (stored as failed, with their messages). The first: " in proc.stderr
    import json

    results = json.loads(proc.stdout)
    assert 0 < results["failed_in_atlas"] < results["points"]
    assert "max_steps" in results["first_failure"]
