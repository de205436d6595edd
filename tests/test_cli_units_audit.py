"""A driller's units audit of the command line: a tally's joint length typed without its unit
("length = 31" for 31 ft) is noted, not silently a 10 km string; the surface torque is printed
with its unit; the oilfield's spellings of weights and torques are read (and the ambiguous
"tonf" refused); help prose is refilled without stubs (tests/test_cli.py checks every --help).
Expected values are computed here from the definitions (1 ft = 0.3048 m, 1 lbf = 4.4482216152605
N, 1 t = 1000 kg × 9.80665 m/s²), not taken from pydrill.units."""

import itertools
import json
import re
from pathlib import Path

import pytest
from cli_running import notes, run

from pydrill import cli, load_tally, units
from pydrill.tally import parse_tally

ROOT = Path(__file__).resolve().parents[1]
TALLIES = sorted((ROOT / "examples" / "tallies").glob("*.toml"))
COLLARS = ROOT / "examples" / "tallies" / "5.5in-dp-8in-collars.toml"
FT, LBF, TONNE_FORCE = 0.3048, 4.4482216152605, 1000 * 9.80665


def collars_with(tmp_path, length) -> Path:
    """examples/tallies/5.5in-dp-8in-collars.toml with its 31 ft joints written ``length``."""
    text = COLLARS.read_text()
    assert text.count('length = "31 ft"') == 3  # drill pipe, heavy-weight, collars
    path = tmp_path / "t4.toml"
    path.write_text(text.replace('length = "31 ft"', f"length = {length}"))
    return path


# 1. a tally's lengths


def test_a_bare_joint_length_longer_than_any_joint_is_noted(tmp_path, capsys):
    path = collars_with(tmp_path, 31)
    code, out, err = run(capsys, "string", path)
    assert code == 0  # a note, not a refusal: a section may list stands
    # 300 + 15 + 9 joints of 31 (m, as written), 2 stabilizers of 6 ft, a 1 ft bit
    metres = (300 + 15 + 9) * 31 + 2 * 6 * FT + 1 * FT
    assert out.startswith(f"5.5in-dp-8in-collars: {metres:.1f} m ")
    said = notes(err)
    assert len(said) == 3, err  # one for each section of 31, none for the total (10 km)
    kinds = ("drill-pipe", "heavy-weight", "drill-collar")  # sections 1, 2, 3 of its file
    for n, note in enumerate(said, start=1):
        length = f"section {n} ({kinds[n - 1]}), length"
        assert note.startswith(f"pydrill: note: {path}: {length} = 31 is read as 31 m")
        assert 'write length = "31 ft"' in note


def test_a_tallys_own_length_beyond_any_well_is_noted_as_depth_is(tmp_path, capsys):
    path = collars_with(tmp_path, 310)
    code, _, err = run(capsys, "string", path)
    assert code == 0
    km = ((300 + 15 + 9) * 310 + 2 * 6 * FT + 1 * FT) / 1e3
    (total,) = [note for note in notes(err) if "longer than any well ever drilled" in note]
    assert total.startswith(f"pydrill: note: {path}: the string is {km:g} km long"), total
    # the same words as --depth 100km earns
    _, _, depth_err = run(capsys, "string", COLLARS, "--depth", "100km")
    assert "longer than any well ever drilled" in depth_err
    # lengthened by --depth (past its 7.4 km BHA), the tally's own length is no longer the
    # string's, and 12 km earns no note; its joints do
    code, _, err = run(capsys, "string", path, "--depth", "12km")
    assert code == 0
    assert not any("longer than any well" in note for note in notes(err))
    assert len(notes(err)) == 3


@pytest.mark.parametrize("tally", TALLIES, ids=lambda p: p.name)
def test_the_shipped_tallies_earn_no_note(tally, capsys):
    """paper-eq53's collars are 18.6 m, longer than any joint: written with their unit, they are
    taken as meant."""
    assert load_tally(tally).notes == ()
    code, _, err = run(capsys, "string", tally)
    assert code == 0 and err == ""


@pytest.mark.parametrize(
    ("length", "noted"),
    [("31", True), ("'31'", True), ("31.0", True), ("15", False), ("13.7", False),
     ('"31 m"', False), ('"31 ft"', False), ('"100 ft"', False)],
)  # fmt: skip
def test_only_a_bare_length_beyond_a_joint_is_noted(length, noted):
    text = COLLARS.read_text().replace('length = "31 ft"', f"length = {length}", 1)
    said = parse_tally(text).notes
    assert len(said) == int(noted), said
    if noted:
        assert said[0].startswith("section 1 (drill-pipe), length = ")


def test_a_length_of_an_integer_beyond_any_float_is_refused(tmp_path, capsys):
    """A TOML integer of 400 digits raised OverflowError (a traceback), not a refusal."""
    with pytest.raises(ValueError, match="is not a finite length: beyond the range of a float"):
        units.parse(10**400, "length")
    path = collars_with(tmp_path, "1" + "0" * 400)
    code, _, err = run(capsys, "string", path)
    assert code == 2 and err.count("\n") == 1
    assert "section 1 (drill-pipe), length: " in err and "beyond the range of a float" in err


def test_window_notes_the_joint_length_too(tmp_path, capsys):
    path = collars_with(tmp_path, 31)
    code, _, err = run(capsys, "window", path, "--depth", "3000m")
    assert code == 0
    assert sum("section " in note and "31 ft" in note for note in notes(err)) == 3


def spec_notes(err: str) -> list[str]:
    """The notes of a dry run but the one on the machine's load, which comes and goes."""
    return [n for n in notes(err) if "this machine is busy" not in n]


def test_a_sweep_from_the_tally_notes_it_before_anything_runs(tmp_path, capsys):
    """A sweep's spec naming the tally earns the notes simulate and window give: 31 read as m
    swept a 10 km string without a word."""
    path = collars_with(tmp_path, 310)
    spec = tmp_path / "s.toml"
    body = "[axes]\nwob = [50e3, 100e3]\n[simulation]\nt_end = 5.0\n"
    spec.write_text(f'[model]\ntally = "{path.name}"\ndof = 4\ntorque = 10e3\n{body}')
    code, _, err = run(capsys, "sweep", spec, "--out", tmp_path / "a.h5", "--dry-run")
    assert code == 0
    said = spec_notes(err)
    assert len(said) == 4, err  # three sections of 310 m joints, and the 100 km string
    assert all(n.startswith(f"pydrill: note: {path.name}: ") for n in said)
    assert sum('write length = "310 ft"' in n for n in said) == 3
    assert sum("longer than any well ever drilled" in n for n in said) == 1
    assert not (tmp_path / "a.h5").exists()
    # at a depth the spec sets, the tally's own length is not the string's: the joints only
    spec.write_text(f'[model]\ntally = "{path.name}"\ndof = 4\ndepth = "12 km"\n'
                    f"torque = 10e3\n{body}")  # fmt: skip
    code, _, err = run(capsys, "sweep", spec, "--out", tmp_path / "a.h5", "--dry-run")
    assert code == 0 and len(spec_notes(err)) == 3, err
    # and the shipped tally, written in feet, earns none
    spec.write_text(f'[model]\ntally = "{COLLARS}"\ndof = 4\ntorque = 10e3\n{body}')
    code, _, err = run(capsys, "sweep", spec, "--out", tmp_path / "a.h5", "--dry-run")
    assert code == 0 and spec_notes(err) == [], err


# 2. the surface torque with its unit


def field(text, name):
    (line,) = [x for x in text.splitlines() if x.startswith(name)]
    return line[len(name) :].strip()


def test_the_surface_torque_is_printed_with_its_unit(capsys):
    # the reduced-scale string's bit: mu_s = 0.8, R_b = 0.1 m; 100 kN makes T_s 8 kN m
    args = ["simulate", "--wob", "100kN", "--torque", "8.3", "--t-end", "2"]
    code, out, _ = run(capsys, *args)
    assert code == 0
    t_s = 0.8 * 100e3 * 0.1
    # was "(surface torque 0.0083)", read as 8.3 kN m
    assert field(out, "static torque") == f"T_s = {t_s / 1e3:.4g} kN m (surface torque 8.3 N m)"
    _, out, _ = run(capsys, "simulate", "--wob", "100", "--torque", "8.3", "--t-end", "2")
    want = f"T_s = {0.8 * 100 * 0.1:.4g} N m (surface torque 8.3 N m)"
    assert field(out, "static torque") == want
    _, out, _ = run(capsys, "simulate", "--wob", "100kN", "--torque", "9kN*m", "--t-end", "2")
    assert field(out, "static torque").endswith("(surface torque 9 kN m)")


# 3. oilfield spellings


FOOT_POUND = FT * LBF  # N·m


@pytest.mark.parametrize(
    ("text", "newton_metres"),
    [("6ft-lbs", 6 * FOOT_POUND), ("6ft-lb", 6 * FOOT_POUND), ("6lb-ft", 6 * FOOT_POUND),
     ("6lbf-ft", 6 * FOOT_POUND), ("6 ft-lbf", 6 * FOOT_POUND), ("6 lbs-ft", 6 * FOOT_POUND),
     ("6 ft lbs", 6 * FOOT_POUND), ("6FT-LBS", 6 * FOOT_POUND), ("6kft-lbs", 6e3 * FOOT_POUND),
     ("6 klb-ft", 6e3 * FOOT_POUND), ("6klbf-ft", 6e3 * FOOT_POUND),
     ("9kft*lbf", 9e3 * FOOT_POUND), ("12kN*m", 12e3)],
)  # fmt: skip
def test_oilfield_torque_spellings(text, newton_metres):
    assert units.parse(text, "torque") == pytest.approx(newton_metres, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "newtons"),
    [("25klbs", 25e3 * LBF), ("25klb", 25e3 * LBF), ("25kips", 25e3 * LBF), ("25 kip", 25e3 * LBF),
     ("2500 lbs", 2500 * LBF), ("10tonne", 10 * TONNE_FORCE), ("10t", 10 * TONNE_FORCE),
     ("10 tf", 10 * TONNE_FORCE), ("10 tonnes", 10 * TONNE_FORCE), ("25klbf", 25e3 * LBF)],
)  # fmt: skip
def test_oilfield_weight_spellings(text, newtons):
    assert units.parse(text, "force") == pytest.approx(newtons, rel=1e-12)


def test_the_command_line_reads_them(capsys):
    args = ["simulate", "--wob", "10t", "--torque", "6600ft-lbs", "--t-end", "1", "--json"]
    code, out, _ = run(capsys, *args)
    assert code == 0
    inputs = json.loads(out)["inputs"]
    assert inputs["wob"] == pytest.approx(10 * TONNE_FORCE)
    assert inputs["torque"] == pytest.approx(6600 * FOOT_POUND)


@pytest.mark.parametrize("text", ["10tonf", "10 ton", "10 tons", "10 TONF"])
def test_a_ton_force_of_two_meanings_is_refused_naming_both(text, capsys):
    with pytest.raises(ValueError, match="ambiguous") as info:
        units.parse(text, "force")
    for choice in ("'t'", "'tf'", "'tonne'", "9.80665 kN", "2000 lbf", "8.896 kN", "klbf"):
        assert choice in str(info.value)
    assert 2000 * LBF / 1e3 == pytest.approx(8.896, abs=5e-4)  # the message's short ton
    with pytest.raises(ValueError, match="ambiguous"):
        units.convert(1.0, "force", "tonf")
    code, _, err = run(capsys, "simulate", "--wob", text, "--torque", "8.3")
    assert code == 2 and "--wob" in err and "ambiguous" in err and "\n" == err[-1:]


def listed_units(err: str) -> list[str]:
    """The units a refusal lists after "use one of", each spelling on its own."""
    listed = err.split("use one of ", 1)[1].replace(": metric", "")
    return [u.strip() for u in re.split(r"[(),]", listed) if u.strip()]


def test_the_refusal_lists_the_spellings_read(capsys):
    code, _, err = run(capsys, "simulate", "--wob", "100", "--torque", "6 furlongs")
    assert code == 2
    assert "unit 'furlongs' is not a torque unit" in err
    listed = listed_units(err)
    for spelling in ("kN·m", "ft-lbs", "lb-ft", "lbf-ft", "kft·lbf", "klb-ft"):
        assert spelling in listed
    for spelling in listed:  # every unit listed is read, as the one it names
        assert units.parse(f"1 {spelling}", "torque") in (1.0, 1e3, FOOT_POUND, 1e3 * FOOT_POUND)
    code, _, err = run(capsys, "simulate", "--wob", "3 furlong", "--torque", "8.3")
    assert code == 2
    listed = listed_units(err)
    for spelling in ("kN", "klbf", "klbs", "kips", "tf", "tonne"):
        assert spelling in listed
    for spelling in listed:
        newtons = units.parse(f"1 {spelling}", "force")
        assert newtons == pytest.approx(min((1.0, 1e3, LBF, 1e3 * LBF, TONNE_FORCE),
                                            key=lambda n: abs(n - newtons)), rel=1e-12)  # fmt: skip


def test_the_help_names_the_spellings(capsys):
    with pytest.raises(SystemExit):
        cli.main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for needle in ("25klbs", "25kips", "10t", "6600ft-lbs", "6.6klb-ft", '"tonf"'):
        assert needle in text, needle
    for example in re.findall(r"\b(\d[\d.]*(?:klbs|kips|t|ft-lbs|klb-ft))\b", text):
        assert units.parse(example, "torque" if "ft" in example else "force") > 0


# 4. the help formatter


def test_a_hanging_paragraph_is_refilled_and_an_example_kept(monkeypatch):
    from pydrill.cli_parser import _Wrapped

    text = (
        "JSON fields: regime, caveat and the metrics (bit_min, bit_max, bit_mean, top_mean,\n"
        "  severity, stuck_fraction) from the first initial\n"
        "  condition; coords, status\n"
        "\n"
        "examples:\n"
        "  pydrill atlas query paper.h5 --wob 100 --torque 8.5 --initial rest --json --x y\n"
    )
    lines = _Wrapped("pydrill")._fill_text(text, 40, "").splitlines()
    words = text.split("\n\n")[0].split()
    assert " ".join(" ".join(lines[: lines.index("")]).split()) == " ".join(words)
    prose = lines[: lines.index("")]
    assert not prose[0][:1].isspace() and all(line.startswith("  ") for line in prose[1:])
    assert all(len(line) <= 40 for line in prose)
    for a, b in itertools.pairwise(prose):  # filled: the next word did not fit
        assert len(a) + 1 + len(b.split()[0]) > 40
    assert lines[-1] == text.splitlines()[-1]  # an example longer than the width: kept whole
