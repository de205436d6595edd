"""The spec's TOML writing, its tally's rules and its [simulation] and [record] tables, against
tomllib reading what pydrill writes, hand-counted inertias and the documented ranges.

What a mutation audit of spec_toml.py, spec_tally.py and spec_sections.py left alive: escapes
and floats written so that they read back as other values (or not at all), keys that TOML
would split at a dot, a header broken over lines; the inertia count at its bound, the deepest
point of a depth axis, a tally found beside the working folder; the edges of each range.
"""

import math
import tomllib
from pathlib import Path

import pytest

from pydrill.model import MAX_DOF
from pydrill.simulate import MAX_T_END
from pydrill.spec import SpecError, load_spec, parse_spec
from pydrill.spec_toml import key, value, with_axis

TALLY = (Path(__file__).parents[1] / "examples" / "tallies" / "paper-eq53.toml").read_text()

# Values a spec can hold, chosen where a TOML writer goes wrong: escapes (quote, backslash,
# control characters, DEL, which JSON leaves raw and TOML refuses), a character beyond the
# BMP (JSON's ASCII escapes make it a surrogate pair, which TOML refuses), floats whose
# shortest form looks like an int or needs 17 digits, the infinities and NaN, -0.0.
STRINGS = ['q"uote', "back\\slash", "new\nline\ttab", "bell\x07", "del\x7f", "é😀", ""]
FLOATS = [1.0, 0.1, 1 / 3, 1e300, 5e-324, -0.0, 2.5e-7, math.inf, -math.inf]
KEYS = ["plain", "a.b", "a b", "é", 'q"k', "", "1"]


def _same(a, b):
    """Equal with the same types all the way down (1.0 is not 1; NaN is NaN; -0.0 not 0.0)."""
    if isinstance(a, float) and isinstance(b, float):
        return (math.isnan(a) and math.isnan(b)) or (
            a == b and math.copysign(1, a) == math.copysign(1, b)
        )
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, dict) and isinstance(b, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("v", [*STRINGS, *FLOATS, math.nan, 0, -7, 2**62, True, False])
def test_a_value_written_reads_back_as_itself_through_tomllib(v):
    read = tomllib.loads(f"x = {value(v)}\n")["x"]
    assert _same(read, v), (value(v), read)


def test_lists_and_inline_tables_with_awkward_keys_read_back_through_tomllib():
    v = [[1.0, "a\x7fb", [True, -math.inf]], {k: i for i, k in enumerate(KEYS)}]
    assert _same(tomllib.loads(f"x = {value(v)}\n")["x"], v)
    for k in KEYS:  # a dotted or blank key must be quoted, or TOML nests it or refuses it
        assert tomllib.loads(f"{key(k)} = 1\n") == {k: 1}, key(k)


def test_with_axis_is_the_document_with_that_axis_and_the_header_as_comments():
    """What tomllib reads of the text with_axis writes is the original document with one
    axis replaced; a header over several lines stays comments (a newline in a merged part's
    name made the rest of it a TOML line)."""
    text = (
        '[model]\npreset = "reduced-scale"\nbit_radius = "0.1 m"\n'
        "[axes]\nwob = [50.0, 60.0]\ntorque = { start = 6.0, stop = 8.0, num = 3 }\n"
        '[simulation]\nt_end = 5\ninitial = ["rest"]\nrtol = 1e-9\n[record]\nstability = true\n'
    )
    header = "merged from part\nA.h5 and " + " ".join(f"p{i}.h5" for i in range(30))
    out = with_axis(text, "wob", [50.0, 55.0, 1e-300], header)
    doc = tomllib.loads(text)
    doc["axes"]["wob"] = [50.0, 55.0, 1e-300]
    assert _same(tomllib.loads(out), doc), out
    comments = [line for line in out.splitlines() if line.startswith("#")]
    assert " ".join(c[2:] for c in comments) == header.replace("\n", " ")
    again = parse_spec(out)  # and it is still a spec, with the new axis
    assert again.axes["wob"].tolist() == [1e-300, 50.0, 55.0]


@pytest.mark.parametrize("name", ["a\x1b[31m.h5", "b\x7f.h5", "c\x00\x01.h5"])
def test_a_header_with_a_control_character_is_a_comment_tomllib_reads(name):
    """A merge's header names its parts' files: one named with an escape sequence, a DEL or
    a NUL made a comment TOML refuses, and 'atlas merge' failed with "not valid TOML". The
    character is written escaped, as a message shows it."""
    text = '[model]\npreset = "reduced-scale"\n[axes]\nwob = [50.0]\n'
    out = with_axis(text, "wob", [60.0], f"Merged from {name}, z.h5")
    assert tomllib.loads(out) == {"model": {"preset": "reduced-scale"}, "axes": {"wob": [60.0]}}
    assert out.splitlines()[0] == "# Merged from " + repr(name)[1:-1] + ", z.h5"


# --- the tally: inertias counted by hand (the paper's string: drill pipe, heavy-weight,
# two drill collars, a stabilizer, a bit; here with ``hw`` heavy-weight joints)
SPEC = '[model]\ntally = "t.toml"\nlump = {lump}\n[axes]\nwob = ["40 kN"]\ntorque = ["8 kN·m"]\n'


def _tally(pipes, hw=1):
    heavy = 'kind = "heavy-weight"\ncount = 1\n'
    assert heavy in TALLY
    text = TALLY.replace("count = 100\n", f"count = {pipes}\n", 1)
    return text.replace(heavy, f'kind = "heavy-weight"\ncount = {hw}\n')


@pytest.mark.parametrize(
    ("pipes", "hw", "lump"),
    # 1 (top drive) + ceil(pipes / lump) + hw + 2 + 1 + 1 inertias, MAX_DOF at most: each
    # pair is the last string allowed and the first refused
    [
        (MAX_DOF - 6, 1, 1),
        (MAX_DOF - 5, 1, 1),
        (2 * (MAX_DOF - 16) - 1, 11, 2),
        (2 * (MAX_DOF - 16) + 1, 11, 2),
    ],
)
def test_a_tally_string_is_refused_beyond_max_dof_inertias_counted_by_hand(pipes, hw, lump):
    n = 1 + -(-pipes // lump) + hw + 2 + 1 + 1
    text = SPEC.format(lump=lump)
    if n <= MAX_DOF:
        parse_spec(text, tally_text=_tally(pipes, hw))
    else:
        with pytest.raises(SpecError, match=rf"^model\.tally: the string has {n} inertias "):
            parse_spec(text, tally_text=_tally(pipes, hw))


def test_a_depth_axis_is_refused_at_its_deepest_point_naming_it():
    """1000 m of string fits; 10^6 m (1.1e5 joints of 9 m) does not: the axis is refused at
    its deepest value, whatever its order."""
    text = SPEC.format(lump=1) + 'depth = ["1000 km", "1000 m"]\n'
    with pytest.raises(SpecError, match=r"^axes\.depth: the string at 1e\+06 m has \d+ inertias"):
        parse_spec(text, tally_text=TALLY)


@pytest.mark.parametrize(("depth", "shown"), [("0.0", "0.0"), ("inf", "inf"), ("-3.0", "-3.0")])
def test_a_held_depth_must_be_finite_and_above_zero(depth, shown):
    text = SPEC.format(lump=1).replace("lump = 1\n", f"depth = {depth}\n")
    with pytest.raises(SpecError, match=rf"^model\.depth: {shown} is not allowed: a depth > 0"):
        parse_spec(text, tally_text=TALLY)


def test_a_relative_tally_not_beside_the_spec_is_read_from_the_working_folder(
    tmp_path, monkeypatch
):
    """The spec's folder first, then the working folder (spec.parse_spec refuses only a path
    found in neither)."""
    (tmp_path / "specs").mkdir()
    (tmp_path / "work").mkdir()
    (tmp_path / "specs" / "s.toml").write_text(SPEC.format(lump=1))
    (tmp_path / "work" / "t.toml").write_text(TALLY)
    monkeypatch.chdir(tmp_path / "work")
    assert load_spec(tmp_path / "specs" / "s.toml").tally_text == TALLY


def test_a_tally_that_is_an_image_is_refused_as_one(tmp_path):
    (tmp_path / "t.toml").write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)))
    with pytest.raises(SpecError, match=r"^model\.tally: t\.toml is a PNG image, not a pipe tally"):
        parse_spec(SPEC.format(lump=1), base=tmp_path)


# --- [simulation] and [record]: each documented range at its edges
BASE = '[model]\npreset = "reduced-scale"\n[axes]\nwob = [100.0]\ntorque = [6.0]\n'


@pytest.mark.parametrize(
    ("table", "line", "read"),
    [
        ("simulation", 'initial = "equilibrium"', ("initial", ["equilibrium"])),
        ("simulation", f"t_end = {MAX_T_END!r}", ("t_end", MAX_T_END)),
        ("simulation", "t_end = 7", ("t_end", 7.0)),
        ("simulation", "rtol = 1e-14", ("rtol", 1e-14)),
        ("simulation", "rtol = 1e-2", ("rtol", 1e-2)),
        ("simulation", "atol = 1e-20", ("atol", 1e-20)),
        ("simulation", "atol = 1e-3", ("atol", 1e-3)),
        ("simulation", "window = 1", ("window", 1)),
        ("simulation", "max_steps = 1", ("max_steps", 1)),
        ("simulation", 'method = "erk"', ("method", "erk")),
        ("simulation", 'friction = "karnopp"', ("friction", "karnopp")),
        ("record", "eigenvalues = 0", ("eigenvalues", 0)),
        ("record", "eigenvalues = 64", ("eigenvalues", 64)),
    ],
)
def test_the_edges_of_each_range_are_accepted(table, line, read):
    spec = parse_spec(BASE + f"[{table}]\n{line}\n")
    got = getattr(spec, table)[read[0]]
    assert _same(got, read[1]), got


@pytest.mark.parametrize(
    ("table", "line", "where"),
    [
        ("simulation", "initial = []", "simulation.initial"),
        ("simulation", 'initial = ["rest", "rest"]', "simulation.initial"),
        ("simulation", "t_end = 1.0000001e10", "simulation.t_end"),
        ("simulation", "rtol = 9.9e-15", "simulation.rtol"),
        ("simulation", "rtol = 0.011", "simulation.rtol"),
        ("simulation", "atol = 0.0011", "simulation.atol"),
        ("simulation", "window = 0", "simulation.window"),
        ("simulation", "max_steps = 0", "simulation.max_steps"),
        ("simulation", "max_steps = true", "simulation.max_steps"),
        ("simulation", 'friction = "coulomb"', "simulation.friction"),
        ("record", "stability = 1", "record.stability"),
        ("record", "eigenvalues = 65", "record.eigenvalues"),
        ("record", "eigenvalues = true", "record.eigenvalues"),
    ],
)
def test_just_beyond_each_range_is_refused_naming_the_key(table, line, where):
    with pytest.raises(SpecError, match=rf"^{where}: "):
        parse_spec(BASE + f"[{table}]\n{line}\n")
