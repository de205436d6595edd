"""A drilling engineer's second audit of tallies, `pydrill string` and `pydrill window`.

What a person typing a tally sheet into TOML meets: a bare diameter of the commonest pipe
(od = 5.5) refused as "at most 5 m" with no word that it was read as metres; a kind typed
"drill-collars" refused without the near name; a top-level typo answered with an allowed list
that left out `name`; a tally without drill pipe refused, at a --depth, as "at_depth needs a
drill-pipe section"; a density written kg/m³ (as the guide writes steel's) or in field units
(lb/ft3) refused. Expected numbers are computed here from the definitions (1 lb = 0.45359237
kg, 1 ft = 0.3048 m, I_p = π(OD⁴ − ID⁴)/32, c = sqrt(G/ρ)), not taken from pydrill.
"""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_running import run

from pydrill import units
from pydrill.tally import Tally, TallyError, parse_tally

INCH, FT, LBM = 0.0254, 0.3048, 0.45359237
ROOT = Path(__file__).resolve().parents[1]


def tally_text(pipe: str = "", bit: str = 'diameter = "8.5 in"', head: str = "") -> str:
    """A one-section tally of 5 1/2 in drill pipe; ``pipe`` replaces its od/id lines."""
    pipe = pipe or 'od = "5.5 in"\nid = "4.778 in"'
    return (
        f'{head}[top_drive]\ninertia = "2500 kg·m2"\n[bit]\n{bit}\n'
        f'[[section]]\nkind = "drill-pipe"\ncount = 300\nlength = "31 ft"\n{pipe}\n'
    )


@pytest.mark.parametrize(
    ("pipe", "bit", "said"),
    [
        ("od = 5.5\nid = 0.1", 'diameter = "8.5 in"', "section 1 (drill-pipe), od = 5.5 is not"),
        ('od = "5.5 in"', "diameter = 8.5", "bit.diameter = 8.5 is not allowed"),
        ('od = "5.5 in"\nid = 4.778', 'diameter = "8.5 in"', "section 1 (drill-pipe), id = 4.778"),
    ],
)
def test_a_bare_diameter_refused_says_it_was_read_as_metres(pipe, bit, said):
    """od = 5.5 (5 1/2 in pipe, the commonest) was refused as "at most 5 m" alone, where
    od = 5 was noted as most likely inches: the refusal now says what to write."""
    with pytest.raises(TallyError) as info:
        parse_tally(tally_text(pipe, bit))
    message = str(info.value)
    assert message.startswith(said)
    # the key's own name: "bit.diameter" -> diameter, "section 1 (drill-pipe), od" -> od
    key, value = re.split(r"[ .]", said.split(" = ")[0])[-1], said.split(" = ")[1].split()[0]
    assert f'a bare number is m: for inches write {key} = "{value} in"' in message


@pytest.mark.parametrize(
    ("pipe", "bit"),
    [
        ('od = "6 m"', 'diameter = "8.5 in"'),  # with its unit: taken as meant, no hint
        ("od = -5.5", 'diameter = "8.5 in"'),  # not a diameter in any unit
        ('od = "5.5 in"\nid = "6 in"', 'diameter = "8.5 in"'),
    ],
)
def test_a_diameter_with_its_unit_or_negative_gets_no_inches_hint(pipe, bit):
    with pytest.raises(TallyError) as info:
        parse_tally(tally_text(pipe, bit))
    assert "for inches" not in str(info.value)


def test_a_mistyped_kind_is_answered_with_the_near_one():
    text = tally_text().replace('"drill-pipe"', '"drill-pipes"')
    with pytest.raises(TallyError, match=r"\(did you mean 'drill-pipe'\?\)"):
        parse_tally(text)


def test_a_top_level_typo_lists_name_among_the_allowed_keys():
    with pytest.raises(TallyError) as info:
        parse_tally(tally_text(head='nmae = "x"\n'))
    # it suggested 'name' while its allowed list left name out
    assert "(did you mean 'name'?); allowed: name, [top_drive]" in str(info.value)
    assert parse_tally(tally_text(head='name = "x"\n')).name == "x"


def test_a_depth_for_a_tally_without_drill_pipe_is_refused_in_its_words(tmp_path, capsys):
    text = tally_text().replace('"drill-pipe"', '"heavy-weight"')
    with pytest.raises(TallyError) as info:
        parse_tally(text).at_depth(3000.0)
    message = str(info.value)
    assert "at_depth" not in message and 'no drill-pipe section (kind = "drill-pipe")' in message
    assert f"its string is {300 * 31 * FT:g} m" in message
    path = tmp_path / "hw.toml"
    path.write_text(text)
    code, out, err = run(capsys, "string", path, "--depth", "3000m")
    assert code == 2 and out == ""
    assert err.startswith("pydrill string: error: --depth 3000 m: the tally has no drill-pipe")


@pytest.mark.parametrize(
    ("written", "si"),
    [
        ("7850 kg/m³", 7850.0),
        ("490 lb/ft3", 490 * LBM / FT**3),
        ("490 lbm/ft3", 490 * LBM / FT**3),
        ("490 lb/ft³", 490 * LBM / FT**3),
        ("490 pcf", 490 * LBM / FT**3),
        ("490 LB/FT3", 490 * LBM / FT**3),
    ],
)
def test_a_density_reads_kg_per_cubic_metre_as_written_and_field_units(written, si):
    assert units.parse(written, "density") == pytest.approx(si, rel=1e-12)


def test_a_tally_all_in_field_units_is_the_si_tally():
    """Every quantity of a tally sheet in oilfield units (ft, in, psi, lb/ft3) builds the
    string of the same tally in SI, joint by joint (hand-computed conversions)."""
    field = tally_text().replace('"drill-pipe"', '"drill-pipe"\nshear_modulus = "11.5e6 psi"')
    field = field.replace("count = 300", 'count = 300\ndensity = "490 lb/ft3"')
    g, rho = 11.5e6 * LBM * 9.80665 / INCH**2, 490 * LBM / FT**3
    si = tally_text('od = "0.1397 m"\nid = "0.1213612 m"', 'diameter = "0.2159 m"')
    si = si.replace('"31 ft"', f'"{31 * FT!r} m"').replace(
        "count = 300", f'count = 300\nshear_modulus = "{g!r} Pa"\ndensity = "{rho!r} kg/m3"'
    )
    a, b = parse_tally(field).to_params(), parse_tally(si).to_params()
    ip = math.pi * ((5.5 * INCH) ** 4 - (4.778 * INCH) ** 4) / 32
    assert a.stiffnesses[0] == pytest.approx(g * ip / (31 * FT), rel=1e-12)
    assert a.inertias[1] == pytest.approx(rho * ip * 31 * FT, rel=1e-12)
    assert np.allclose(a.stiffnesses, b.stiffnesses, rtol=1e-12)
    assert np.allclose(a.inertias, b.inertias, rtol=1e-12)


def test_the_defaults_the_guide_states():
    """docs/guide/real-strings.md lists what a key left out takes: kind other, count 1, id 0,
    no damping at the top drive and bit, beta 0.2 s, the paper's friction law."""
    t = parse_tally('[top_drive]\ninertia = 2500\n[bit]\ndiameter = "8.5 in"\n'
                    '[[section]]\nlength = "31 ft"\nod = "8 in"\n')  # fmt: skip
    (s,) = t.sections
    assert (s.kind, s.count, s.id) == ("other", 1, 0.0)
    assert (t.top_damping, t.bit_damping, t.beta) == (0.0, 0.0, 0.2)
    assert (t.mu_static, t.mu_coulomb, t.stribeck_decay, t.stribeck_velocity) == (
        0.8, 0.5, 0.9, 1.0
    )  # fmt: skip
    for key in ("inertia = 2500\n", 'diameter = "8.5 in"\n', 'length = "31 ft"\n'):
        with pytest.raises(TallyError, match="missing"):
            parse_tally(t_text_without(key))


def t_text_without(line: str) -> str:
    text = '[top_drive]\ninertia = 2500\n[bit]\ndiameter = "8.5 in"\n[[section]]\n'
    return (text + 'length = "31 ft"\nod = "8 in"\n').replace(line, "", 1)


def lowest_frequency(tally: Tally, dof: int | None = None) -> float:
    """The lowest non-zero natural frequency, Hz, of the undamped chain."""
    p = tally.to_params(dof=dof)
    j, k = np.array(p.inertias), np.array(p.stiffnesses)
    n = len(j)
    stiff = np.zeros((n, n))
    for i, ki in enumerate(k):
        stiff[i : i + 2, i : i + 2] += ki * np.array([[1.0, -1.0], [-1.0, 1.0]])
    scaled = stiff / np.sqrt(np.outer(j, j))
    w = np.sqrt(np.clip(np.linalg.eigvalsh(scaled), 0.0, None))
    return float(w[w > 1e-6][0] / (2 * math.pi))


def test_a_uniform_5km_string_rings_as_a_fixed_free_rod():
    """530 joints of 5 1/2 in pipe under a top drive heavy enough to hold its top still: the
    chain's lowest frequency is the rod's c/(4L), c = sqrt(G/ρ), and its reductions converge
    to it like 1/N² (the guide's table)."""
    t = parse_tally(
        '[top_drive]\ninertia = "1e12 kg·m2"\n[bit]\ndiameter = "8.5 in"\n[damping]\nbeta = 0\n'
        '[[section]]\nkind = "drill-pipe"\ncount = 530\nlength = "31 ft"\nod = "5.5 in"\n'
        'id = "4.778 in"\n'
    )
    length = 530 * 31 * FT
    assert t.length == pytest.approx(length, rel=1e-12)
    rod = math.sqrt(79.3e9 / 7850.0) / (4 * length)
    assert lowest_frequency(t) == pytest.approx(rod, rel=2e-3)
    errors = [abs(lowest_frequency(t, dof) / rod - 1) for dof in (4, 8, 20)]
    assert errors[0] < 0.015 and errors[1] < 0.004 and errors[2] < 0.002
    assert errors[0] > errors[1] > errors[2]


def test_a_tally_listed_from_the_bit_up_is_said(tmp_path, capsys):
    """A BHA sheet is often written from the bit up: such a tally built the string upside
    down (the bit's joint next to the top drive) without a word. It is read as written, and
    every command says so; a tally listed top down says nothing."""
    collars = '[[section]]\nkind = "drill-collar"\ncount = 9\nlength = "31 ft"\nod = "8 in"\n'
    bit = '[[section]]\nkind = "bit"\nlength = "1 ft"\nod = "8.5 in"\n'
    top_down = tally_text() + collars + bit
    head, rest = top_down.split("[[section]]", 1)
    pipe, collars_, bit_ = ("[[section]]" + x for x in rest.split("[[section]]"))
    bit_up = head + bit_ + collars_ + pipe
    assert parse_tally(top_down).notes == ()
    (note,) = parse_tally(bit_up).notes
    assert note.startswith("section 1 is the bit, with 2 section(s) listed below it")
    kinds = [s.kind for s in parse_tally(bit_up).sections]
    assert kinds == ["bit", "drill-collar", "drill-pipe"]  # read as written, not reordered
    path = tmp_path / "bit-up.toml"
    path.write_text(bit_up)
    code, _, err = run(capsys, "window", path, "--depth", "3000m", "--at-rpm", "60")
    assert code == 0
    assert f"pydrill: note: {path}: section 1 is the bit" in err


@pytest.mark.parametrize("command", ["string", "window", "stability"])
def test_a_bit_radius_wider_than_any_bit_is_said(command, capsys):
    """--set bit_radius=8.5 (8.5 in meant; a bare number is m) built a bit 17 m across without
    a word, where a tally refuses a bit diameter beyond 5 m. Said; the command goes on."""
    tally = ROOT / "examples" / "tallies" / "paper-eq53.toml"
    args = {
        "string": ["string", tally, "--dof", "2"],
        "window": ["window", tally, "--depth", "3000m", "--at-rpm", "60"],
        "stability": ["stability", "--tally", tally, "--dof", "4", "--wob", "60kN",
                      "--omega", "60rpm"],
    }[command]  # fmt: skip
    code, out, err = run(capsys, *args, "--set", "bit_radius=8.5")
    assert code == 0 and "bit_radius = 8.5 m" in out
    assert "pydrill: note: --set bit_radius = 8.5 m: a bit 17 m across" in err
    assert "for inches write bit_radius=8.5in" in err
    # a real bit's radius (6 in, 0.1524 m) is no note
    code, _, err = run(capsys, *args, "--set", "bit_radius=6in")
    assert code == 0 and "bit_radius" not in err


@pytest.mark.parametrize("depth", ["1000m,1000m", "1000m:1000m:3", "1000m,3000m,3km"])
def test_a_depth_given_twice_is_refused(depth, tmp_path, capsys):
    """A depth twice printed its rows twice and drew the chart against depth over a span of
    0 m (empty, and matplotlib's 'identical low and high ylims' warning on stderr)."""
    tally = ROOT / "examples" / "tallies" / "paper-eq53.toml"
    plot = tmp_path / "w.png"
    code, out, err = run(capsys, "window", tally, "--depth", depth, "--plot", plot)
    assert code == 2 and out == "" and not plot.exists()
    twice = "3000" if "3km" in depth else "1000"
    assert err.strip().endswith(f"--depth: {twice} m is given more than once; give each depth once")
    code, out, _ = run(capsys, "window", tally, "--depth", "1000m,3000m", "--at-rpm", "60")
    assert code == 0 and "\n    1000   3281" in out and "\n    3000   9843" in out


def _saved_figure(monkeypatch, capsys, argv, tmp_path):
    """The figure ``pydrill ARGV --plot`` saves, kept."""
    import pydrill.plot

    figures, save = [], pydrill.plot.save
    monkeypatch.setattr(
        pydrill.plot, "save", lambda fig, path: figures.append(fig) or save(fig, path)
    )
    code, out, err = run(capsys, *argv, "--plot", tmp_path / "w.png")
    assert code == 0, err
    (fig,) = figures
    return fig, out


def test_checks_on_a_reduced_string_say_so(monkeypatch, capsys, tmp_path):
    """window --check --check-dof 4 simulated a 4-inertia string and judged it by that string's
    edges, while the tables, the chart and its title ('lumped model 334 inertias') are the full
    string's: nothing said the checks were another model's, not even the JSON."""
    paper = ROOT / "examples" / "tallies" / "paper-eq53.toml"
    one = ["window", paper, "--depth", "3000m", "--at-rpm", "60", "--check", "2"]
    fig, out = _saved_figure(monkeypatch, capsys, [*one, "--check-dof", "4"], tmp_path)
    said = "checks simulated on the string reduced to 4 inertias (--check-dof 4)"
    assert said + "; the window itself is the full string's" in out.splitlines()
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert any(s.startswith("simulated from equilibrium, 4 inertias: ") for s in labels)
    assert "lumped model 334 inertias" in fig.axes[0].get_title()  # the drawn string's
    code, out, _ = run(capsys, *one, "--check-dof", "4", "--json")
    assert code == 0 and json.loads(out)["check_dof"] == 4
    # the full string checked: nothing to say, and the JSON's check_dof is null
    fig, out = _saved_figure(monkeypatch, capsys, one, tmp_path)
    assert "reduced to" not in out
    labels = fig.axes[0].get_legend_handles_labels()[1]
    assert not any("inertias" in s for s in labels)
    assert json.loads(run(capsys, *one, "--json")[1])["check_dof"] is None
    # the chart against depth says it in its footnote
    two = ["window", paper, "--depth", "1000m,3000m", "--at-rpm", "60", "--check", "2"]
    fig, _ = _saved_figure(monkeypatch, capsys, [*two, "--check-dof", "4"], tmp_path)
    note = " ".join(fig._supxlabel.get_text().split())
    assert "Checks simulated on the string reduced to 4 inertias (--check-dof 4)" in note


MY_WELL = """name = "my-well"
[top_drive]
inertia = "2500 kg·m2"
[bit]
diameter = "8.5 in"
[[section]]
kind = "drill-pipe"
count = 300
length = "31 ft"
od = "5.5 in"
id = "4.778 in"
[[section]]
kind = "drill-collar"
count = 20
length = "31 ft"
od = "8 in"
id = "2.8125 in"
"""


def test_a_tally_is_utf8_whatever_the_locale(tmp_path):
    """A tally was read in the locale's encoding: the guide's own "2500 kg·m2" was "not UTF-8
    text" under an ASCII locale (and mojibake, an unknown unit, under a Latin-1 one)."""
    import os
    import subprocess
    import sys

    path = tmp_path / "my-well.toml"
    path.write_text(MY_WELL, encoding="utf-8")
    # a locale not installed leaves Python's locale encoding ASCII; one installed, Latin-1
    env = {**os.environ, "LC_ALL": "en_US.ISO-8859-1", "PYTHONUTF8": "0"}
    env.pop("PYTHONIOENCODING", None)
    done = subprocess.run(
        [sys.executable, "-m", "pydrill", "string", str(path), "--dof", "2"],
        capture_output=True, text=True, encoding="utf-8", errors="replace", env=env,
        cwd=tmp_path, timeout=120,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"my-well: {320 * 31 * FT:.1f} m ({20 * 31 * FT:.1f} m BHA)")


def test_a_tally_saved_with_a_byte_order_mark_is_read(tmp_path):
    """Windows editors may begin a UTF-8 file with a byte-order mark: tomllib refused it as
    'Invalid statement (at line 1, column 1)'."""
    from pydrill import load_tally

    plain, marked = tmp_path / "plain.toml", tmp_path / "marked.toml"
    plain.write_text(MY_WELL, encoding="utf-8")
    marked.write_bytes(b"\xef\xbb\xbf" + MY_WELL.encode("utf-8"))
    assert load_tally(marked) == load_tally(plain)
    assert load_tally(marked).name == "my-well" and load_tally(marked).top_inertia == 2500.0


@pytest.mark.parametrize("name", ["", "  ", "a\\nb", "x\\u001b[2J"])
def test_a_tally_name_that_cannot_head_a_line_is_refused(name, tmp_path, capsys):
    """Every output line and figure title begins with the tally's name: an empty one printed
    ': 3023.6 m ...', and a newline or an escape sequence (clearing the screen) reached the
    terminal as it was."""
    path = tmp_path / "t.toml"
    path.write_text(MY_WELL.replace('name = "my-well"', f'name = "{name}"'), encoding="utf-8")
    code, out, err = run(capsys, "string", path, "--dof", "2")
    assert code == 2 and out == ""
    assert "name = " in err and "a string of printable characters, not empty" in err
    assert "\x1b" not in err and err.count("\n") == 1


def test_a_printable_tally_name_is_kept(tmp_path, capsys):
    path = tmp_path / "t.toml"
    path.write_text(MY_WELL.replace('"my-well"', '"Bohrung Süd-3 (8½ in)"'), encoding="utf-8")
    code, out, _ = run(capsys, "string", path, "--dof", "2")
    assert code == 0 and out.startswith("Bohrung Süd-3 (8½ in): ")


def test_string_help_lists_the_density_units_a_tally_reads(capsys):
    """The help's list of a tally's units is what units.parse reads for a density."""
    code, out, _ = run(capsys, "string", "-h")
    assert code == 0
    listed = " ".join(out.split()).split("Pa, GPa, psi; ")[1].split(". Output")[0].split("; ")
    assert [part.split(", ") for part in listed] == [["kg/m3", "lb/ft3"], ["kg·m2", "lb·ft2"]]
    for kind, part in zip(("density", "inertia"), listed, strict=True):
        for unit in part.split(", "):
            assert units.parse(f"1 {unit}", kind) > 0
