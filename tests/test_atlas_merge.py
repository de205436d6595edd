"""``pydrill atlas merge``: parts of a sweep split along an axis, merged, are the atlas one
sweep over the whole grid writes (compared with such a sweep), and parts that are not one
sweep's are refused with nothing written."""

import json
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest
from sweeping import same_atlas

import pydrill
from pydrill import AtlasError, merge_atlases, parse_spec, run_sweep
from pydrill.sweep import SweepInterrupted

WHOLE = """
# the whole grid (the parts below split its wob values)
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = { start = 40.0, stop = 160.0, num = 5 }
torque = [6.0, "8.3 N·m", 10.0]
[simulation]
t_end = 60.0
initial = ["rest", "equilibrium"]
"""


def part(wobs: str, text: str = WHOLE) -> str:
    out = text.replace("wob = { start = 40.0, stop = 160.0, num = 5 }", f"wob = {wobs}")
    assert out != text
    return out


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    """The whole grid swept at once, and in two parts (the higher W_ob first)."""
    d = tmp_path_factory.mktemp("merge")
    run_sweep(parse_spec(WHOLE), d / "whole.h5", serial=True)
    run_sweep(parse_spec(part("[100.0, 130.0, 160.0]")), d / "high.h5", serial=True)
    run_sweep(parse_spec(part("[70.0, 40.0]")), d / "low.h5", serial=True)
    return d


def leftovers(d):
    """Files a refused or failed merge must not leave: a half-written part, a lock."""
    return sorted(p.name for p in d.iterdir() if p.name.endswith((".part", ".lock")))


def test_the_parts_merged_are_the_whole_sweeps_atlas(sweeps, tmp_path):
    out = tmp_path / "merged.h5"
    report = merge_atlases(
        [sweeps / "high.h5", sweeps / "low.h5"], out, spec_out=tmp_path / "m.toml"
    )
    assert (report.axis, report.values, report.points) == ("wob", 5, 15)
    assert report.status == {"done": 15, "failed": 0, "missing": 0}
    same_atlas(out, sweeps / "whole.h5")  # every dataset, the axes in increasing order
    with h5py.File(out) as f, h5py.File(sweeps / "whole.h5") as g:
        assert f.attrs["spec_digest"] == g.attrs["spec_digest"]
        assert f.attrs["params"] == g.attrs["params"]
        parts = json.loads(f.attrs["merged_from"])
    assert [(p["file"], p["values"]) for p in parts] == [("high.h5", 3), ("low.h5", 2)]
    # The whole grid's sweep takes the merged atlas as its own: nothing left to compute.
    again = run_sweep(parse_spec(WHOLE), out, serial=True, resume=True)
    assert again.computed == 0 and again.resumed == 15
    # The spec written reads back as the same sweep.
    spec = parse_spec((tmp_path / "m.toml").read_text())
    assert spec.digest == parse_spec(WHOLE).digest
    assert spec.axes["torque"].tolist() == [6.0, 8.3, 10.0]
    with pydrill.Atlas(out) as atlas, pydrill.Atlas(sweeps / "low.h5") as low:
        assert atlas.value(wob=70.0, torque=8.3) == low.value(wob=70.0, torque=8.3)
        assert atlas.summary()["merged_from"] == parts
        ds = atlas.to_xarray()
        assert ds["wob"].values.tolist() == [40.0, 70.0, 100.0, 130.0, 160.0]
        ds.close()
    assert leftovers(tmp_path) == []


def test_missing_points_stay_missing_and_its_spec_completes_them(tmp_path):
    """A part stopped midway is refused while its journal says so; given up as it is (the
    journal removed), its missing points stay missing in the merged atlas, and the spec the
    merge writes completes them: then it equals the whole sweep."""
    wide = WHOLE.replace('[6.0, "8.3 N·m", 10.0]', "{ start = 6.0, stop = 10.0, num = 12 }")
    stopped = tmp_path / "stopped.h5"

    def stop(done: int, total: int) -> None:  # after the first batch (half the points)
        raise KeyboardInterrupt

    spec = parse_spec(part("[100.0, 130.0, 160.0]", wide))
    with pytest.raises(SweepInterrupted):
        run_sweep(spec, stopped, serial=True, progress=stop)
    run_sweep(parse_spec(part("[40.0, 70.0]", wide)), tmp_path / "low.h5", serial=True)
    with pytest.raises(AtlasError, match="its sweep is running or was stopped"):
        merge_atlases([stopped, tmp_path / "low.h5"], tmp_path / "m.h5")
    assert not (tmp_path / "m.h5").exists()
    (tmp_path / "stopped.h5.journal").unlink()
    with h5py.File(stopped) as f:
        had = int(np.count_nonzero(f["status"][...] == 0))  # missing
    assert 0 < had < 36
    report = merge_atlases(
        [stopped, tmp_path / "low.h5"], tmp_path / "m.h5", spec_out=tmp_path / "m.toml"
    )
    assert report.status == {"done": 60 - had, "failed": 0, "missing": had}
    completed = run_sweep(
        pydrill.load_spec(tmp_path / "m.toml"), tmp_path / "m.h5", serial=True, resume=True
    )
    assert completed.computed == had
    run_sweep(parse_spec(wide), tmp_path / "whole.h5", serial=True)
    same_atlas(tmp_path / "m.h5", tmp_path / "whole.h5")


def test_a_size_axis_merges_as_integers(tmp_path):
    sizes = """
[model]
preset = "reduced-scale"
torque = 8.3
[axes]
dof = DOF
wob = [60.0, 120.0]
[simulation]
t_end = 40.0
"""
    for name, dofs in (("a", "[2, 5]"), ("b", "[3]"), ("whole", "[2, 3, 5]")):
        run_sweep(parse_spec(sizes.replace("DOF", dofs)), tmp_path / f"{name}.h5", serial=True)
    report = merge_atlases([tmp_path / "a.h5", tmp_path / "b.h5"], tmp_path / "m.h5")
    assert "dof = [2, 3, 5]" in report.spec_text
    same_atlas(tmp_path / "m.h5", tmp_path / "whole.h5")
    with h5py.File(tmp_path / "m.h5") as f:
        assert f["dof"].dtype.kind == "i"


OTHER = {
    "t_end": ("t_end = 60.0", "t_end = 30.0", "simulation.t_end: 60.0 here, 30.0 there"),
    "initial": ('"rest", "equilibrium"', '"rest"', "simulation.initial"),
    "two-axes": ('[6.0, "8.3 N·m", 10.0]', "[6.0]", "differ along torque and wob (axes.wob:"),
    "axes-order": (
        'wob = [10.0]\ntorque = [6.0, "8.3 N·m", 10.0]',
        'torque = [6.0, "8.3 N·m", 10.0]\nwob = [10.0]',
        "have other axes (wob x torque against torque x wob)",
    ),
}


@pytest.mark.parametrize(
    ("second", "message"),
    [
        *((part("[10.0]").replace(a, b), m) for a, b, m in OTHER.values()),
        (part("[70.0, 190.0]"), "wob = 70 N is in both"),
        (part("[70.0, 40.0]"), "are the same sweep"),
    ],
    ids=[*OTHER, "overlap", "same"],
)
def test_parts_of_other_sweeps_are_refused_naming_why(sweeps, tmp_path, second, message):
    assert second not in (WHOLE, part("[10.0]"))  # (each replacement found its text)
    run_sweep(parse_spec(second), tmp_path / "other.h5", serial=True)
    with pytest.raises(ValueError, match=re.escape(message)):
        merge_atlases([sweeps / "low.h5", tmp_path / "other.h5"], tmp_path / "m.h5")
    assert not (tmp_path / "m.h5").exists() and leftovers(tmp_path) == []


def test_bad_parts_and_paths_are_refused_and_nothing_is_written(sweeps, tmp_path):
    low, high = sweeps / "low.h5", sweeps / "high.h5"
    out = tmp_path / "m.h5"
    with pytest.raises(ValueError, match=r"give two or more atlases to merge \(1 given\)"):
        merge_atlases([low], out)
    with pytest.raises(ValueError, match=re.escape("low.h5 is given twice: each part once")):
        merge_atlases([low, high, low], out)
    with pytest.raises(ValueError, match="is one of the parts"):
        merge_atlases([low, high], high)
    (tmp_path / "taken.h5").write_bytes(b"mine")
    with pytest.raises(ValueError, match=re.escape("taken.h5 exists: give another path")):
        merge_atlases([low, high], tmp_path / "taken.h5")
    assert (tmp_path / "taken.h5").read_bytes() == b"mine"
    (tmp_path / "taken.toml").write_text("mine")
    with pytest.raises(ValueError, match=re.escape("taken.toml exists")):
        merge_atlases([low, high], out, spec_out=tmp_path / "taken.toml")
    # A truncated part, and a file that is no atlas
    cut = tmp_path / "cut.h5"
    cut.write_bytes(high.read_bytes()[:3000])
    with pytest.raises(AtlasError, match=re.escape("cut.h5 is damaged")):
        merge_atlases([low, cut], out)
    with pytest.raises(AtlasError, match=re.escape("taken.h5 is not a readable HDF5 atlas")):
        merge_atlases([low, tmp_path / "taken.h5"], out)
    with pytest.raises(AtlasError, match=re.escape("nowhere.h5: no such atlas")):
        merge_atlases([low, tmp_path / "nowhere.h5"], out)
    assert not out.exists() and leftovers(tmp_path) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "cut.h5", "taken.h5", "taken.toml"
    ]  # fmt: skip


def test_a_merge_that_would_not_fit_in_memory_is_refused_before_reading(
    sweeps, tmp_path, monkeypatch
):
    import psutil

    real = psutil.virtual_memory
    monkeypatch.setattr(psutil, "virtual_memory", lambda: real()._replace(available=1000))
    with pytest.raises(ValueError, match=r"15 points needs about 0\.0 GB .* 0\.0 GB is avail"):
        merge_atlases([sweeps / "low.h5", sweeps / "high.h5"], tmp_path / "m.h5")
    assert list(tmp_path.iterdir()) == []


def test_the_command_line(sweeps, tmp_path):
    def run(*args):
        return subprocess.run(
            [sys.executable, "-m", "pydrill", "atlas", "merge", *map(str, args)],
            capture_output=True,
            text=True,
            cwd=tmp_path,
        )

    done = run(sweeps / "high.h5", sweeps / "low.h5", "--out", "m.h5", "--spec", "m.toml")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "wrote m.h5: 15 points, 5 values of wob (40 N ... 160 N) from 2 atlases",
        "wrote m.toml: its sweep spec",
    ]
    again = run(sweeps / "high.h5", sweeps / "low.h5", "--out", "m.h5")
    assert again.returncode == 2 and again.stdout == ""
    assert again.stderr.startswith("pydrill atlas merge: error: m.h5 exists")
    assert len(again.stderr.splitlines()) == 1
    nowhere = run(sweeps / "high.h5", sweeps / "low.h5", "--out", "no/such/m.h5")
    assert nowhere.returncode == 2 and "there is no folder" in nowhere.stderr
    data = json.loads(run(sweeps / "low.h5", sweeps / "high.h5", "--out", "j.h5", "--json").stdout)
    assert data["axis"] == "wob" and data["points"] == 15 and data["spec"] is None
    assert data["status"] == {"done": 15, "failed": 0, "missing": 0}
    info = subprocess.run(
        [sys.executable, "-m", "pydrill", "atlas", "info", "j.h5"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert "merged from low.h5, high.h5 (pydrill atlas merge)" in info.stdout


def test_the_parts_of_a_spec_share_out_its_first_axis():
    from pydrill.spec_parts import parse_part

    spec = parse_spec(WHOLE)
    parts = [spec.part(k, 3) for k in (1, 2, 3)]
    assert [p.axes["wob"].tolist() for p in parts] == [[40.0, 130.0], [70.0, 160.0], [100.0]]
    for p in parts:  # all else is the spec's
        assert [d.split(":")[0] for d in spec.differences(p)] == ["axes.wob"]
        assert p.axes["torque"].tolist() == [6.0, 8.3, 10.0]
    assert spec.part(1, 1).digest == spec.digest
    assert parse_part(" 3 / 16 ") == (3, 16)
    for bad in ("0/3", "4/3", "3", "1/0", "a/b", "-1/3", "1.5/3"):
        with pytest.raises(ValueError, match="is not allowed: K/N"):
            parse_part(bad)
    with pytest.raises(ValueError, match="6 parts of the first axis, wob, which has 5 values"):
        spec.part(1, 6)
    with pytest.raises(ValueError, match=r"part 4 of 3 is not allowed"):
        spec.part(4, 3)
    with pytest.raises(TypeError, match="k = True is not allowed"):
        spec.part(True, 3)


def test_a_sweep_in_parts_merged_is_the_whole_sweep(sweeps, tmp_path):
    """The job-array way: 'pydrill sweep SPEC --part K/3' three times, then 'atlas merge': the
    atlas of 'pydrill sweep SPEC', and that sweep's --resume takes it as its own."""
    (tmp_path / "whole.toml").write_text(WHOLE)

    def pydrill_(*args):
        proc = subprocess.run(
            [sys.executable, "-m", "pydrill", *args], capture_output=True, text=True, cwd=tmp_path
        )
        assert proc.returncode == 0, proc.stderr
        return proc

    for k in (3, 1, 2):
        swept = pydrill_("sweep", "whole.toml", "--part", f"{k}/3", "--out", f"p{k}.h5", "--serial")
        assert swept.stdout.startswith(f"p{k}.h5: {(2, 2, 1)[k - 1] * 3} points")
        assert f"pydrill atlas merge p{k}.h5 OTHER-PARTS.h5 --out WHOLE.h5" in swept.stderr
    with h5py.File(tmp_path / "p3.h5") as f:
        assert f.attrs["spec"].startswith(
            "# Part 3 of 3 of whole.toml: values 3, 6, 9, ... of wob (1 of its 5"
        )
    info = pydrill_("atlas", "info", "p3.h5").stdout
    assert "  part    3 of 3 of whole.toml (pydrill sweep --part): 'pydrill" in info
    assert json.loads(pydrill_("atlas", "info", "p1.h5", "--json").stdout)["part"] == {
        "k": 1, "n": 3, "of": "whole.toml"
    }  # fmt: skip
    pydrill_("atlas", "merge", "p2.h5", "p3.h5", "p1.h5", "--out", "all.h5")
    merged = json.loads(pydrill_("atlas", "info", "all.h5", "--json").stdout)
    assert merged["part"] is None and [p["file"] for p in merged["merged_from"]] == [
        "p2.h5", "p3.h5", "p1.h5"
    ]  # fmt: skip
    same_atlas(tmp_path / "all.h5", sweeps / "whole.h5")
    # xarray reads the parts as one without a merge, as the guide says
    import xarray as xr

    parts = [xr.open_dataset(tmp_path / f"p{k}.h5", engine="pydrill") for k in (1, 2, 3)]
    whole = xr.open_dataset(sweeps / "whole.h5", engine="pydrill")
    joined = xr.concat(parts, dim="wob").sortby("wob")
    for name in ("regime", "safe", "bit_mean", "omega_eq"):
        xr.testing.assert_equal(joined[name], whole[name])
    for ds in (*parts, whole):
        ds.close()
    again = pydrill_("sweep", "whole.toml", "--out", "all.h5", "--resume", "--serial")
    assert again.stdout.startswith("all.h5: 15 points, 0 computed now (0 failed), 15 already done")
    plan = json.loads(
        pydrill_("sweep", "whole.toml", "--part", "2/3", "--dry-run", "--serial", "--json").stdout
    )
    assert (
        plan["part"] == "2/3" and plan["points"] == 6 and plan["shape"] == {"wob": 2, "torque": 3}
    )
    # A part's atlas is that part's sweep: another part is refused there, the same resumed.
    other = subprocess.run(
        [sys.executable, "-m", "pydrill", *"sweep whole.toml --part 2/3 --out p1.h5".split()],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert other.returncode == 2 and "p1.h5 holds a different sweep (axes.wob" in other.stderr
    same = pydrill_("sweep", "whole.toml", "--part", "1/3", "--out", "p1.h5", "--resume")
    assert "0 computed now" in same.stdout


@pytest.mark.parametrize("step", ["write", "replace"])
def test_a_merge_that_fails_while_writing_leaves_nothing(sweeps, tmp_path, monkeypatch, step):
    """A full disk while the atlas is written, or a failure putting it in place (after its spec
    was written), leaves neither a half atlas nor the spec, and no lock."""
    import errno

    from pydrill import atlas_format, atlas_merge

    def full(*args):
        raise OSError(errno.ENOSPC, "No space left on device")

    if step == "write":
        monkeypatch.setattr(atlas_format, "write", full)
    else:
        monkeypatch.setattr(atlas_merge.os, "replace", full)
    with pytest.raises(OSError, match="No space left"):
        merge_atlases(
            [sweeps / "low.h5", sweeps / "high.h5"], tmp_path / "m.h5", spec_out=tmp_path / "m.toml"
        )
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []


def test_a_tally_strings_depth_parts_merge_into_the_whole(tmp_path):
    """A string from a tally (its text travels in the atlases), a torque held in [model]
    with its unit, the depth cut by --part: the merge is the whole sweep's atlas."""
    from pathlib import Path

    tally = Path(__file__).parents[1] / "examples" / "tallies" / "paper-eq53.toml"
    text = f"""
[model]
tally = {json.dumps(str(tally))}
dof = 3
torque = "9 kN·m"
[axes]
depth = ["500 m", "1000 m", "2000 m"]
wob = {{ start = "20 kN", stop = "120 kN", num = 2 }}
[simulation]
t_end = 20.0
"""
    whole = parse_spec(text)
    run_sweep(whole, tmp_path / "whole.h5", serial=True)
    for k in (1, 2):
        run_sweep(whole.part(k, 2), tmp_path / f"p{k}.h5", serial=True)
    report = merge_atlases([tmp_path / "p2.h5", tmp_path / "p1.h5"], tmp_path / "m.h5")
    assert report.axis == "depth" and report.span == (500.0, 2000.0)
    same_atlas(tmp_path / "m.h5", tmp_path / "whole.h5")
    with h5py.File(tmp_path / "m.h5") as f, h5py.File(tmp_path / "whole.h5") as g:
        assert f.attrs["spec_digest"] == g.attrs["spec_digest"]
        assert f.attrs["tally"] == g.attrs["tally"] == tally.read_text()


def test_a_grid_split_along_two_axes_merges_one_axis_at_a_time(tmp_path):
    """Four blocks of a (wob, torque) grid: merging all four at once is refused, saying how;
    merged along wob at each torque, then along torque, they are the whole sweep."""
    blocks = {}
    for w in ("[40.0, 70.0]", "[100.0, 130.0, 160.0]"):
        for u in ("[6.0]", '["8.3 N·m", 10.0]'):
            name = tmp_path / f"w{len(blocks) // 2}u{len(blocks) % 2}.h5"
            text = part(w).replace('torque = [6.0, "8.3 N·m", 10.0]', f"torque = {u}")
            run_sweep(parse_spec(text), name, serial=True)
            blocks[name.stem] = name
    run_sweep(parse_spec(WHOLE), tmp_path / "whole.h5", serial=True)
    how = r"w0u0\.h5 and \S*w1u0\.h5 differ along wob, .* along torque: a merge joins"
    with pytest.raises(ValueError, match=how):
        merge_atlases([blocks["w0u0"], blocks["w1u0"], blocks["w0u1"]], tmp_path / "m.h5")
    for u in ("u0", "u1"):
        merge_atlases([blocks[f"w0{u}"], blocks[f"w1{u}"]], tmp_path / f"{u}.h5")
    report = merge_atlases([tmp_path / "u1.h5", tmp_path / "u0.h5"], tmp_path / "m.h5")
    assert report.axis == "torque"
    same_atlas(tmp_path / "m.h5", tmp_path / "whole.h5")


def test_failed_points_keep_their_messages(tmp_path):
    """Points whose solver failed (max_steps too small for the stick-slip runs) are merged as
    failed, each with its own message: the merge is the whole sweep's atlas, failures and all."""
    text = WHOLE.replace("t_end = 60.0", "t_end = 60.0\nmax_steps = 300")
    whole = parse_spec(text)
    report = run_sweep(whole, tmp_path / "whole.h5", serial=True)
    assert 0 < report.failed < whole.size  # some points failed, not all
    for k in (1, 2):
        run_sweep(whole.part(k, 2), tmp_path / f"p{k}.h5", serial=True)
    merged = merge_atlases([tmp_path / "p1.h5", tmp_path / "p2.h5"], tmp_path / "m.h5")
    assert merged.status["failed"] == report.failed
    same_atlas(tmp_path / "m.h5", tmp_path / "whole.h5")
    with h5py.File(tmp_path / "m.h5") as f:
        failed = f["message"][...][f["status"][...] == 2]
    assert len(failed) == report.failed and all(b"max_steps = 300" in m for m in failed)
