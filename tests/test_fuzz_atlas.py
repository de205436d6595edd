"""Atlases and journals fuzzed: a damaged journal line or atlas file is an AtlasError naming
the file (and the line, the key), from ``pydrill.Atlas``, ``pydrill atlas info/query/export``,
``pydrill sweep --resume`` and its ``--dry-run``; never a KeyError, TypeError, IndexError or
OverflowError from inside the replay, and never a record silently written to another point.
The cases are those a by-hand search found (57 journal damages, each with and without the
atlas; some 250 random ones), kept as specific examples."""

import copy
import json

import h5py
import numpy as np
import pytest
from sweeping import SMALL

import pydrill
from pydrill import cli
from pydrill.journal import AtlasError
from pydrill.sweep import run_sweep
from pydrill.sweep_plan import plan_sweep
from pydrill.sweep_points import evaluate_point

SPEC = SMALL.replace("t_end = 200.0", "t_end = 50.0")


@pytest.fixture(scope="module")
def spec():
    return pydrill.parse_spec(SPEC)


@pytest.fixture(scope="module")
def records(spec):
    """Every point's journal record, as a sweep writes them."""
    return [json.loads(json.dumps(evaluate_point(spec, i))) for i in range(spec.size)]


@pytest.fixture(scope="module")
def reference(spec, tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "ref.h5"
    run_sweep(spec, out, serial=True)
    return out


def interrupted(tmp_path, spec, records, damage=None, line=None, atlas=True):
    """An atlas (all points missing, as a sweep killed before its first flush leaves it, or
    none with ``atlas=False``) and its journal of every record, the first one changed by
    ``damage(record)`` or replaced by the text ``line``."""
    out = tmp_path / "a.h5"
    if atlas:
        run_sweep(spec, out, serial=True)
        with h5py.File(out, "r+") as f:
            f["status"][...] = 0
    lines = [json.dumps(r) for r in records]
    if damage is not None:
        rec = copy.deepcopy(records[0])
        damage(rec)
        lines[0] = json.dumps(rec)
    if line is not None:
        lines[0] = line
    journal = tmp_path / "a.h5.journal"
    journal.write_text(
        "".join(x + "\n" for x in [json.dumps({"spec_digest": spec.digest}), *lines])
    )
    return out, journal


def _set(path, value):
    def damage(rec):
        table = rec
        for key in path[:-1]:
            table = table[key]
        table[path[-1]] = value

    return damage


DAMAGED_LINES = {
    # name: (how, what the refusal says after "line 2, is damaged (")
    "a list": (None, "[]", r"\[\] is not a point's record"),
    "a number": (None, "7", r"7 is not a point's record"),
    "i = -1": (_set(["i"], -1), None, r"point i = -1 is not allowed: an integer 0 \.\.\. 5"),
    "i = 6": (_set(["i"], 6), None, r"point i = 6 is not allowed"),
    "i = 10**30": (_set(["i"], 10**30), None, r"point i = 1000000000000000000000000000000"),
    "i = 2.5": (_set(["i"], 2.5), None, r"point i = 2\.5 is not allowed"),
    "i = true": (_set(["i"], True), None, r"point i = True is not allowed"),
    "i = '3'": (_set(["i"], "3"), None, r"point i = '3' is not allowed"),
    "status": (_set(["status"], "weird"), None, r"status = 'weird' is not one of missing"),
    "status list": (_set(["status"], []), None, r"status = \[\] is not one of"),
    "message": (_set(["message"], 5), None, r"message = 5 is not text"),
    "runs": (_set(["runs"], []), None, r"runs = \[\] is not a table of runs"),
    "run": (_set(["runs", "rest"], 5), None, r"runs\.rest = 5 is not a run"),
    "regime": (_set(["runs", "rest", "regime"], "wobbly"), None, r"runs\.rest\.regime = 'wob"),
    "caveat": (_set(["runs", "rest", "caveat"], "meh"), None, r"runs\.rest\.caveat = 'meh'"),
    "metric": (
        _set(["runs", "rest", "bit_mean"], "abc"),
        None,
        r"runs\.rest\.bit_mean = 'abc' is not",
    ),
    "count": (
        _set(["runs", "rest", "stick_events"], 10**30),
        None,
        r"runs\.rest\.stick_events = 1000",
    ),
    "stability": (_set(["stability"], "x"), None, r"stability = 'x' is not a table"),
    "omega_eq": (
        _set(["stability", "omega_eq"], "abc"),
        None,
        r"stability\.omega_eq = 'abc' is not",
    ),
    "unstable": (_set(["stability", "unstable"], [10**30]), None, r"stability\.unstable = 1000"),
    "eigenvalues": (
        _set(["stability", "eigenvalues"], [[1, 2]]),
        None,
        r"stability\.eigenvalues = \[\[",
    ),
    "coexistence": (_set(["coexistence"], 500), None, r"coexistence = 500 is not one of true"),
}


@pytest.mark.parametrize("name", list(DAMAGED_LINES))
def test_a_damaged_journal_line_is_refused_naming_line_and_key(name, tmp_path, spec, records):
    """Each of these was a KeyError, TypeError, AttributeError, ValueError, IndexError or
    OverflowError from inside the replay (AtlasTable.apply_all), or, for i = -1, 2.5 or true,
    a record silently stored at another point; a message not text failed the atlas's write
    half-way. Now --resume refuses, and writes nothing: the atlas stays as it was."""
    damage, line, message = DAMAGED_LINES[name]
    out, _ = interrupted(tmp_path, spec, records, damage, line)
    before = out.read_bytes()
    with pytest.raises(AtlasError, match=rf"a\.h5\.journal, line 2, is damaged \({message}"):
        run_sweep(spec, out, resume=True, serial=True)
    assert out.read_bytes() == before


@pytest.mark.parametrize("name", ["a list", "i = 6", "i = 10**30", "i = '3'", "metric"])
def test_a_journal_alone_that_is_damaged_leaves_no_atlas(name, tmp_path, spec, records):
    """Without its atlas, --resume created an empty atlas before the replay failed."""
    damage, line, message = DAMAGED_LINES[name]
    out, _ = interrupted(tmp_path, spec, records, damage, line, atlas=False)
    with pytest.raises(AtlasError, match=rf"line 2, is damaged \({message}"):
        run_sweep(spec, out, resume=True, serial=True)
    assert not out.exists()


@pytest.mark.parametrize("name", ["a list", "i = 6", "i = 10**30", "i = '3'", "i = 2.5"])
def test_a_damaged_journal_line_in_a_dry_run(name, tmp_path, spec, records, capsys):
    """plan_sweep (``pydrill sweep --resume --dry-run``) marked ``done[rec["i"]]``: an
    IndexError or TypeError traceback."""
    damage, line, message = DAMAGED_LINES[name]
    out, _ = interrupted(tmp_path, spec, records, damage, line)
    with pytest.raises(AtlasError, match=rf"line 2, is damaged \({message}"):
        plan_sweep(spec, out, resume=True)
    (tmp_path / "s.toml").write_text(SPEC)
    args = ["sweep", str(tmp_path / "s.toml"), "--out", str(out), "--resume", "--dry-run"]
    assert cli.main(args) == 2
    assert "line 2, is damaged" in capsys.readouterr().err


@pytest.mark.parametrize("header", ["[]", "5", '"x"'])
def test_a_journal_header_that_is_no_table_is_refused(header, tmp_path, spec, records):
    """A first line of JSON that is not an object was an AttributeError ('list' object has
    no attribute 'get')."""
    out, journal = interrupted(tmp_path, spec, records)
    journal.write_text(header + "\n" + journal.read_text().split("\n", 1)[1])
    with pytest.raises(AtlasError, match=r"a\.h5\.journal belongs to another sweep \(spec dig"):
        run_sweep(spec, out, resume=True, serial=True)
    with pytest.raises(AtlasError, match=r"belongs to another sweep"):
        plan_sweep(spec, out, resume=True)


@pytest.mark.parametrize("i", ['"3"', "2.5", "true", "NaN", "1" + "0" * 30, "-1"])
def test_atlas_info_counts_a_journal_whatever_its_indices(i, tmp_path, spec, records, capsys):
    """journaled() read '{"i": "3", ...}' with int() (a ValueError: Atlas.summary and
    'pydrill atlas info' failed with "invalid literal for int()") and '{"i": 1e30' into an
    int64 array (OverflowError). An index that names no point is not counted."""
    out, journal = interrupted(tmp_path, spec, records)
    text = journal.read_text().split("\n")
    text[1] = text[1].replace(f'{{"i": {records[0]["i"]},', f'{{"i": {i},', 1)
    journal.write_text("\n".join(text))
    with pydrill.Atlas(out) as atlas:
        assert atlas.summary()["journal_points"] == spec.size - 1
    assert cli.main(["atlas", "info", str(out)]) == 0


def test_a_sound_journal_still_rebuilds_the_atlas(tmp_path, spec, records, reference):
    """The checks refuse nothing a sweep writes: the replay gives the uninterrupted atlas."""
    out, _ = interrupted(tmp_path, spec, records)
    report = run_sweep(spec, out, resume=True, serial=True)
    assert (report.computed, report.resumed) == (0, spec.size)
    with h5py.File(out) as f, h5py.File(reference) as g:
        for name in ("status", "regime", "bit_mean", "stick_events", "eigenvalues_real"):
            np.testing.assert_array_equal(
                np.nan_to_num(f[name][...], nan=-7), np.nan_to_num(g[name][...], nan=-7)
            )


# -- damaged atlas files --------------------------------------------------------------------


def _replace(name, data):
    def damage(f):
        del f[name]
        f[name] = data

    return damage


def _write(name, value):
    def damage(f):
        f[name][...] = value

    return damage


def _attr(name, value):
    def damage(f):
        f.attrs[name] = value

    return damage


def _edit_spec(edit):
    """The spec attribute rewritten by ``edit(text)``; its spec_digest left as it is."""

    def damage(f):
        f.attrs["spec"] = edit(f.attrs["spec"])

    return damage


DAMAGED_ATLASES = {
    # name: (damage, what the refusal names)
    "status of another shape": (_replace("status", np.ones((2, 2), "u1")), r"status has shape"),
    "status a scalar": (_replace("status", np.uint8(1)), r"status has shape \(\), not \(3, 2\)"),
    "status a group": (lambda f: (f.__delitem__("status"), f.create_group("status")), "status is"),
    "status code 7": (_write("status", 7), r"status holds codes other than those of missing"),
    "regime code 99": (_write("regime", 99), r"regime holds codes other than"),
    "regime as floats": (_replace("regime", np.zeros((3, 2, 2))), r"regime holds float64"),
    "bit_mean of another shape": (_replace("bit_mean", np.zeros(2)), r"bit_mean has shape"),
    "caveat of another shape": (_replace("caveat", np.zeros(3, "i1")), r"caveat has shape"),
    "omega_eq of another shape": (_replace("omega_eq", np.zeros(3)), r"omega_eq has shape"),
    "coexistence NaN": (_replace("coexistence", np.full((3, 2), np.nan)), r"coexistence holds"),
    "wob values": (_write("wob", [1.0, 2.0, 3.0]), r"axis wob is not the spec's 3 values"),
    "starts": (_replace("initial", np.array([1, 2])), r"initial is not the spec's starts"),
    "axes attribute": (_attr("axes", 5), r"attribute axes = np\.int64\(5\) is not text"),
    "format_version": (_attr("format_version", np.void(b"\x00")), r"attribute format_version = np"),
    "title": (_attr("title", np.arange(3)), r"attribute title = array\(\[0, 1, 2\]\) is not text"),
    "no eigenvalue scale": (lambda f: f.__delitem__("eigenvalue"), r"no dataset eigenvalue"),
    "spec edited": (
        _edit_spec(lambda text: text.replace("t_end = 50.0", "t_end = 300.0")),
        r"its spec attribute was changed after pydrill wrote it: its spec_digest is this spec's, "
        r"\w{16}, but the spec it holds differs: simulation\.t_end: 50\.0 in this spec, 300\.0 in "
        r"the atlas",
    ),
    "spec no TOML": (
        _attr("spec", "[model"),
        r"its spec attribute was changed .* differs: its spec cannot be read here",
    ),
}


def damaged_copy(tmp_path, reference, damage):
    out = tmp_path / "a.h5"
    out.write_bytes(reference.read_bytes())
    with h5py.File(out, "r+") as f:
        damage(f)
    return out


@pytest.mark.parametrize("name", list(DAMAGED_ATLASES))
def test_resume_refuses_a_damaged_atlas_without_journal(name, tmp_path, spec, reference):
    """A dataset of another shape was a ValueError or IndexError from inside the replay; a
    group for a dataset, an attribute of another type a TypeError; codes that are none (status
    7, regime 99) were left as they were, and --resume called the atlas complete. Now each is
    refused naming the file and what is wrong, and the file is left untouched."""
    damage, what = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    before = out.read_bytes()
    with pytest.raises(AtlasError, match=rf"a\.h5 is damaged \({what}.*\) and has no journal"):
        run_sweep(spec, out, resume=True, serial=True)
    with pytest.raises(AtlasError, match=r"a\.h5 is damaged"):
        plan_sweep(spec, out, resume=True)
    assert out.read_bytes() == before


@pytest.mark.parametrize("name", ["status of another shape", "regime code 99", "spec edited"])
def test_the_command_says_resuming_only_what_it_resumes(
    name, tmp_path, spec, records, reference, capsys
):
    """'pydrill sweep --resume' said 'resuming a.h5: 6 of 6 points are done' of a damaged atlas
    it then refused, for want of a journal; of one it rebuilds, the journal's points are those
    done."""
    damage, _ = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    (tmp_path / "s.toml").write_text(SPEC)
    args = ["sweep", str(tmp_path / "s.toml"), "--out", str(out), "--resume", "--serial"]
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert "is damaged" in err and "sweep: resuming" not in err
    (tmp_path / "a.h5.journal").write_text(
        "".join(json.dumps(x) + "\n" for x in [{"spec_digest": spec.digest}, *records[:4]])
    )
    assert cli.main(args) == 0
    assert f"resuming {out}: 4 of {spec.size} points are done, {spec.size - 4} to compute" in (
        capsys.readouterr().err
    )


@pytest.mark.parametrize(
    "name", ["status of another shape", "regime code 99", "wob values", "spec edited"]
)
def test_resume_rebuilds_a_damaged_atlas_from_its_journal(name, tmp_path, spec, records, reference):
    damage, _ = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    (tmp_path / "a.h5.journal").write_text(
        "".join(json.dumps(x) + "\n" for x in [{"spec_digest": spec.digest}, *records])
    )
    report = run_sweep(spec, out, resume=True, serial=True)
    assert (report.computed, report.resumed) == (0, spec.size)
    with h5py.File(out) as f, h5py.File(reference) as g:
        for ds in ("status", "regime", "wob", "bit_mean"):
            np.testing.assert_array_equal(
                np.nan_to_num(f[ds][...], nan=-7), np.nan_to_num(g[ds][...], nan=-7)
            )
        assert (f.attrs["spec"], f.attrs["spec_digest"]) == (spec.text, spec.digest)


def test_an_atlas_whose_spec_digest_was_changed_says_so(tmp_path, spec, reference):
    """The refusal read 'holds a different sweep (spec digest dd1f..., this spec dd1f...)':
    the same digest twice. An edit is one cause; a pydrill that made another model of the same
    text (the rules of a tally's reduction changed in 0.2.0's life) is the other, and the
    version that wrote the atlas is named."""
    out = damaged_copy(tmp_path, reference, _attr("spec_digest", "0" * 16))
    with h5py.File(out, "r+") as f:
        f.attrs["pydrill_version"] = "0.1.7"
    with pytest.raises(AtlasError) as err:
        run_sweep(spec, out, resume=True, serial=True)
    assert (
        f"its spec is this one, but its spec_digest '{'0' * 16}' is not that spec's "
        f"({spec.digest}): the file was changed after pydrill wrote it, or the pydrill that "
        "wrote it (version '0.1.7') made another model of this spec; sweep again into another "
        "out=PATH"
    ) in str(err.value)


def test_an_atlas_whose_spec_was_edited_is_not_resumed_as_this_sweep(
    tmp_path, spec, records, reference, capsys
):
    """An atlas whose spec attribute was rewritten (t_end = 300) but whose spec_digest was left
    was resumed as this sweep's: 'pydrill sweep --resume' said '6 of 6 points are done' and
    left an atlas whose spec (t_end = 300, digest ...) disagreed with its spec_digest, its
    points those of t_end = 50. Now it is damaged: refused without a journal (the file left
    as it is), and with one rebuilt, its spec the sweep's again."""
    damage, _ = DAMAGED_ATLASES["spec edited"]
    out = damaged_copy(tmp_path, reference, damage)
    before = out.read_bytes()
    (tmp_path / "s.toml").write_text(SPEC)
    assert cli.main(["sweep", str(tmp_path / "s.toml"), "--out", str(out), "--resume"]) == 2
    assert (
        "a.h5 is damaged (its spec attribute was changed after pydrill wrote it: its spec_digest "
        f"is this spec's, {spec.digest}, but the spec it holds differs: simulation.t_end: 50.0 "
        "in this spec, 300.0 in the atlas) and has no journal to rebuild it from"
    ) in capsys.readouterr().err
    assert out.read_bytes() == before
    (tmp_path / "a.h5.journal").write_text(
        "".join(json.dumps(x) + "\n" for x in [{"spec_digest": spec.digest}, *records])
    )
    run_sweep(spec, out, resume=True, serial=True)
    with h5py.File(out) as f:
        assert f.attrs["spec"] == spec.text
        assert pydrill.parse_spec(f.attrs["spec"]).digest == f.attrs["spec_digest"] == spec.digest


def test_an_atlas_whose_spec_was_only_reformatted_is_still_resumed(tmp_path, spec, reference):
    """The check compares sweeps, not texts: a comment added to the spec attribute is the
    same sweep (the same digest), and the atlas is resumed as before."""
    out = damaged_copy(tmp_path, reference, _edit_spec(lambda text: "# a note\n" + text))
    report = run_sweep(spec, out, resume=True, serial=True)
    assert (report.computed, report.resumed) == (0, spec.size)


def test_an_atlas_whose_spec_is_no_text_is_refused_on_opening(tmp_path, reference, capsys):
    """parse_spec(np.int64(5)) raised AttributeError from tomllib: pydrill.Atlas and every
    'pydrill atlas' command printed a traceback."""
    out = damaged_copy(tmp_path, reference, _attr("spec", 5))
    with pytest.raises(AtlasError, match=r"its sweep spec .* the spec is np\.int64\(5\) \(int64\)"):
        pydrill.Atlas(out)
    assert cli.main(["atlas", "info", str(out)]) == 2
    assert "not TOML text" in capsys.readouterr().err


# pydrill.Atlas and 'pydrill atlas ...' on the same damage: Atlas() checks the file's
# structure (atlas_check.layout_problem without the codes), a query the codes it reads, and
# summary (atlas info) and atlas export every code (Atlas.check).


@pytest.mark.parametrize(
    "name", ["status a group", "axes attribute", "status code 7", "coexistence NaN", "starts"]
)
def test_opening_a_damaged_atlas_is_an_atlas_error(name, tmp_path, reference):
    """Atlas(...) and a query of it: AttributeError ('Group' object has no attribute
    'shape'), TypeError (json.loads of an int), KeyError 7 from value(), ValueError (int(NaN)),
    or a zip() ValueError, where an AtlasError naming the file and the problem is promised."""
    damage, what = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    with pytest.raises(AtlasError, match=rf"a\.h5 is damaged or incomplete: {what}"):
        with pydrill.Atlas(out) as atlas:
            atlas.value(wob=100.0, torque=8.3)


@pytest.mark.parametrize("name", ["status code 7", "title", "no eigenvalue scale"])
def test_cli_on_a_damaged_atlas_prints_an_error_not_a_traceback(name, tmp_path, reference):
    """'pydrill atlas query' on status 7 raised AttributeError in cli_atlas ('int' object has
    no attribute 'replace', a KeyError(7)'s argument); 'atlas export x.nc' with an attribute
    that is not text a TypeError from xarray's netCDF writer; a deleted dimension scale a
    KeyError from h5py's dimension lists."""
    damage, _ = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    query = ["atlas", "query", str(out), "--wob", "100", "--torque", "8.3"]
    assert cli.main(query) == 2
    assert cli.main(["atlas", "export", str(out), "--out", str(tmp_path / "x.nc")]) == 2


@pytest.fixture(scope="module")
def other_part(tmp_path_factory):
    """An atlas to merge with the reference: the same sweep at a lower W_ob."""
    out = tmp_path_factory.mktemp("part") / "low.h5"
    run_sweep(pydrill.parse_spec(SPEC.replace("[40.0, 100.0, 160.0]", "[10.0]")), out, serial=True)
    return out


@pytest.mark.parametrize("name", list(DAMAGED_ATLASES))
def test_a_damaged_part_is_not_merged(name, tmp_path, reference, other_part):
    """atlas merge reads each part whole: a damaged one is refused naming it, and no atlas is
    written (an edited spec too: its points would pass for the edited spec's)."""
    damage, _ = DAMAGED_ATLASES[name]
    out = damaged_copy(tmp_path, reference, damage)
    with pytest.raises(AtlasError, match=r"a\.h5"):
        pydrill.merge_atlases([out, other_part], tmp_path / "m.h5")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.h5"]
    # the sound reference merges (the damage, not the pair, was refused)
    assert pydrill.merge_atlases([reference, other_part], tmp_path / "m.h5").points == 8
