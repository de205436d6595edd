"""Sweep specs fuzzed: whatever a spec file holds, reading it is a SpecError naming its key, or
a spec whose every point can be built; never another exception, a RuntimeWarning or a hang.
The regressions below are what a randomized search (seeded; some 76000 mutated specs and 36000
spec + tally pairs, by hand) found; the property test is its quick, derandomized version."""

import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sweeping import toml

from pydrill import cli, spec_rules
from pydrill.spec import SpecError, load_spec, parse_spec
from pydrill.spec_toml import with_axis
from pydrill.tally import TallyError, load_tally, parse_tally

TALLY = Path(__file__).parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_a_range_whose_span_overflows_is_refused_naming_it():
    """start = -1e308, stop = 1e308: stop - start overflows, linspace made inf and nan (with
    numpy RuntimeWarnings) and the refusal said 'steps of inf are too fine'."""
    text = "[model]\nwob = 100.0\n[axes]\ntorque = { start = -1e308, stop = 1e308, num = 3 }\n"
    with pytest.raises(SpecError, match=r"^axes\.torque: start = -1e\+308 and stop = 1e\+308 are"):
        parse_spec(text)
    # the widest span that fits: a range of it (which a torque axis then refuses, beyond
    # simulate's MAX_LOAD)
    wide = spec_rules._range("axes.torque", {"start": -8.9e307, "stop": 8.9e307, "num": 3})
    assert wide.tolist() == [-8.9e307, 0.0, 8.9e307]
    with pytest.raises(SpecError, match=r"^axes\.torque: 8\.9e\+307 N·m is not allowed: at most"):
        parse_spec(text.replace("1e308", "8.9e307"))


def test_a_file_longer_than_any_spec_or_tally_is_refused_naming_it(tmp_path, monkeypatch):
    """A spec or tally naming /dev/zero (or a disk image) was read whole: a MemoryError, or
    the machine's memory filled. Now at most MAX_TEXT characters are read."""
    monkeypatch.setattr(spec_rules, "MAX_TEXT", 1000)
    long = tmp_path / "long.toml"
    long.write_text("# " + "x" * 2000 + "\n")
    with pytest.raises(SpecError, match=rf"^cannot read the spec {long}: longer than"):
        load_spec(long)
    with pytest.raises(TallyError, match=rf"^cannot read the tally {long}: longer than"):
        load_tally(long)
    spec = tmp_path / "s.toml"
    spec.write_text('[model]\ntally = "long.toml"\ntorque = 1.0\n[axes]\nwob = [1.0]\n')
    with pytest.raises(SpecError, match=r"^model\.tally: cannot read long\.toml: longer than"):
        load_spec(spec)
    fits = tmp_path / "fits.toml"  # MAX_TEXT characters are read
    fits.write_text("#" * 999 + "\n")
    with pytest.raises(TallyError, match=r"^section: the tally lists no sections"):
        load_tally(fits)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_dev_zero_as_spec_or_tally_is_refused(capsys):
    assert cli.main(["sweep", "/dev/zero", "--dry-run"]) == 2
    assert "cannot read the spec /dev/zero: longer than 64 MiB" in capsys.readouterr().err
    with pytest.raises(SpecError, match=r"^model\.tally: cannot read /dev/zero: longer than"):
        parse_spec('[model]\ntally = "/dev/zero"\ntorque = 1.0\n[axes]\nwob = [1.0]\n')


def test_a_tally_that_is_not_utf8_is_refused_naming_the_file(tmp_path, capsys):
    """load_tally let UnicodeDecodeError through: 'pydrill simulate --tally' printed
    "error: 'utf-8' codec can't decode byte 0xff", naming no file."""
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"\xff\xfe[bit]\n")
    with pytest.raises(TallyError, match=rf"^cannot read the tally {bad}: not UTF-8 text"):
        load_tally(bad)
    assert cli.main(["simulate", "--tally", str(bad), "--wob", "1", "--torque", "1"]) == 2
    assert f"cannot read the tally {bad}: not UTF-8 text" in capsys.readouterr().err


def _raw_control(text: str) -> list[str]:
    """The characters of ``text`` a terminal does not print as themselves."""
    return [c for c in text if not c.isprintable()]


def test_a_tally_path_with_a_nul_is_shown_escaped_not_raw(tmp_path, capsys):
    """A tally path holding a NUL ('tally = "a\u0000b.toml"') was echoed with the raw NUL byte:
    'pydrill sweep: error: model.tally: cannot read a<NUL>b.toml: there is no file ...'. The
    path is now shown as its repr, the NUL as \x00; a path without one stays unquoted."""
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[model]\npreset = "reduced-scale"\ndof = 4\ntally = "a\\u0000b.toml"\n'
        "[axes]\nwob = [100.0]\n[simulation]\nt_end = 10.0\n"
    )
    assert cli.main(["sweep", str(spec), "--out", str(tmp_path / "a.h5")]) == 2
    err = capsys.readouterr().err
    assert _raw_control(err.rstrip("\n")) == []
    assert (
        f"model.tally: cannot read 'a\\x00b.toml': there is no file '{tmp_path}/a\\x00b.toml' "
        f"(a relative path is resolved against the spec file's folder, {tmp_path})" in err
    )
    assert not (tmp_path / "a.h5").exists()
    with pytest.raises(SpecError, match=r"^model\.tally: cannot read 'a\\x00b\.toml': embedded"):
        parse_spec('[model]\ntally = "a\\u0000b.toml"\ntorque = 1.0\n[axes]\nwob = [1.0]\n')


_AXES = "[axes]\nwob = [1.0]\ntorque = [1.0]\n"


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ('["x\\u001b[2J"]\n' + _AXES, r"'x\x1b[2J': unknown section"),
        ('[model]\n"x\\u0007" = 1\n' + _AXES, r"model.'x\x07': unknown parameter"),
        (_AXES + '"q\\u0000" = [1.0]\n', r"axes.'q\x00': cannot be swept"),
        (_AXES + '[simulation]\n"z\\n" = 1\n', r"simulation.'z\n': unknown; allowed: t_end"),
        (_AXES + '[record]\n"r\\r" = 1\n', r"record.'r\r': unknown; allowed: stability"),
        (
            '[model]\ntally = "t\\u001b[31m.toml"\n' + _AXES,
            r"model.tally: cannot read 't\x1b[31m.toml': there is no file ",
        ),
    ],
)
def test_a_key_or_path_with_control_characters_is_shown_escaped(text, shown, tmp_path):
    """Unknown keys and tally paths were echoed raw in the refusal: an escape sequence in a
    key ('"x\u001b[2J" = 1') cleared the terminal that printed the message."""
    with pytest.raises(SpecError) as info:
        parse_spec(text, base=tmp_path)
    assert str(info.value).startswith(shown)
    assert _raw_control(str(info.value)) == []


@pytest.mark.parametrize(
    ("text", "shown"),
    [
        ('"x\\u0000" = 1\n', r"'x\x00': unknown; allowed: name, [top_drive]"),
        ('[bit]\n"y\\u001b" = 1\n', r"bit.'y\x1b': unknown; allowed: diameter"),
    ],
)
def test_a_tally_key_with_control_characters_is_shown_escaped(text, shown):
    with pytest.raises(TallyError) as info:
        parse_tally(text)
    assert str(info.value).startswith(shown)
    assert _raw_control(str(info.value)) == []


def test_a_spec_or_tally_file_name_with_control_characters_is_shown_escaped(tmp_path, capsys):
    """load_spec and load_tally echoed the file's name raw: a newline in it split the message,
    an escape sequence reached the terminal."""
    name = tmp_path / "x\x1b[31m\n.toml"
    with pytest.raises(SpecError) as info:
        load_spec(name)
    assert str(info.value) == f"cannot read the spec {str(name)!r}: No such file or directory"
    with pytest.raises(TallyError) as info:
        load_tally(name)
    assert str(info.value) == f"cannot read the tally {str(name)!r}: No such file or directory"
    assert cli.main(["sweep", str(name), "--dry-run"]) == 2
    assert _raw_control(capsys.readouterr().err.rstrip("\n")) == []


# -- the property test: any value at any key of a valid spec --------------------------------

BASE = {
    "model": {"preset": "reduced-scale", "dof": 4},
    "axes": {"wob": {"start": 20.0, "stop": 200.0, "num": 3}, "torque": [6.0, 8.3]},
    "simulation": {"t_end": 300.0, "initial": ["rest"]},
    "record": {"stability": True, "eigenvalues": 4},
}
KEYS = {
    "model": ("preset", "dof", "pipes", "wob", "torque", "lump", "mu_static", "inertias", "x"),
    "axes": ("wob", "torque", "dof", "pipes", "depth", "mu_coulomb", "bit_radius", "é"),
    "simulation": ("t_end", "initial", "friction", "method", "rtol", "atol", "window", "max_steps"),
    "record": ("stability", "eigenvalues"),
}
SCALAR = st.one_of(
    st.sampled_from(
        [
            *(0, -1, 1, 2, 3, 10**400, -(10**400), 2**62, 2**63, 1_000_001, 100_001, 1e308),
            *(-1e308, 5e-324, -0.0, math.nan, math.inf, -math.inf, True, "", "nan", "1e400 kN"),
            *("-5 kN", "5 parsecs", "\x00", "é", "rest", "exact", "auto", "full-scale"),
        ]
    ),
    st.floats(),
    st.integers(),
    st.text(max_size=6),
)
VALUE = st.recursive(
    SCALAR,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(st.sampled_from(["start", "stop", "num", "a"]), inner, max_size=4),
    ),
    max_leaves=6,
)


@settings(
    max_examples=200, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
@given(
    changes=st.lists(
        st.sampled_from(list(KEYS)).flatmap(
            lambda t: st.tuples(st.just(t), st.sampled_from(KEYS[t]), st.none() | VALUE)
        ),
        min_size=1,
        max_size=3,
    ),
    with_tally=st.booleans(),
)
def test_any_value_at_any_key_is_a_spec_error_or_a_spec(changes, with_tally):
    doc = {table: dict(keys) for table, keys in BASE.items()}
    for table, key, value in changes:
        if value is None:
            doc[table].pop(key, None)
        else:
            doc[table][key] = value
    try:
        spec = parse_spec(toml(doc), tally_text=TALLY.read_text() if with_tally else None)
    except SpecError as exc:
        assert str(exc)
        return
    for i in (0, spec.size - 1):
        coords = spec.coords(i)
        spec.params_at(coords)
        spec.operating_point(coords)
    assert spec.digest
    # Written back (spec_toml, as 'sweep --part' and 'atlas merge' write specs), it is the same
    # sweep; its parts (sweep --part) share out the first axis's values, each once.
    axis, values = next(iter(spec.axes.items()))
    again = parse_spec(with_axis(spec.text, axis, values.tolist()), spec.tally_text)
    assert again.digest == spec.digest, spec.differences(again)
    n = min(3, len(values))
    parts = [spec.part(k, n) for k in range(1, n + 1)]
    assert sorted(np.concatenate([p.axes[axis] for p in parts]).tolist()) == values.tolist()
    for p in parts:
        assert {d.split(":")[0] for d in spec.differences(p)} <= {f"axes.{axis}"}
