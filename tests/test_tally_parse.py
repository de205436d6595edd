"""Malformed tallies: every wrong type, unknown key or unphysical value is a TallyError naming
its key (the CLI: exit 2, one line, no traceback); depths and string sizes are bounded."""

import copy
import math
import re
import subprocess
import sys

import numpy as np
import pytest
from sweeping import TALLY_TABLES as BASE
from sweeping import toml, toml_value

from pydrill import spec
from pydrill import tally as tally_module
from pydrill.tally import TallyError, parse_tally


def changed(path: str, value) -> str:
    """The base tally with ``path`` (``bit.mu_static``, ``section[1].od``, ``steel``) set."""
    doc = copy.deepcopy(BASE)
    *parents, last = re.findall(r"[^.\[\]]+", path)
    table = doc
    for part in parents:
        table = table[int(part)] if part.isdigit() else table[part]
    table[int(last) if last.isdigit() else last] = value
    return toml(doc)


def refused(text: str, message: str) -> str:
    """The TallyError of ``text``: its message must hold ``message`` (literally)."""
    with pytest.raises(TallyError, match=re.escape(message)) as err:
        parse_tally(text)
    return str(err.value)


def test_the_base_tally_is_valid():
    tally = parse_tally(toml(BASE))
    assert [s.count for s in tally.sections] == [100, 2]
    assert tally.mu_static == 0.8 and tally.beta == 0.2


# 1. Wrong types anywhere: the module's error naming the key, never a TypeError/AttributeError.


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("bit.mu_static", [0.8], "bit.mu_static = [0.8] is not allowed"),
        ("bit.mu_coulomb", {"a": 1}, "bit.mu_coulomb = {'a': 1} is not allowed"),
        ("bit.stribeck_decay", True, "bit.stribeck_decay = True is not allowed"),
        ("bit", 3, "malformed tally: bit = 3 is not allowed: a table, [bit]"),
        ("steel", 5, "malformed tally: steel = 5 is not allowed: a table, [steel]"),
        ("top_drive", "big", "malformed tally: top_drive = 'big' is not allowed: a table"),
        ("damping", [1], "malformed tally: damping = [1] is not allowed: a table"),
        ("section", 5, "malformed tally: section = 5 is not allowed: an array of tables"),
        ("section", [1, 2], "malformed tally: section 1 = 1 is not allowed: a table"),
        ("section[1].kind", 5, "section 2, kind = 5 is not allowed: choose one of"),
        ("section[0].count", 1.5, "section 1 (drill-pipe), count = 1.5 is not allowed: an integer"),
        ("damping.model", 2, "damping.model = 2 is not allowed: only 'stiffness-proportional'"),
        ("name", 5, "name = 5 is not allowed: a string"),
    ],
)
def test_a_wrong_type_is_refused_naming_the_key(path, value, message):
    refused(changed(path, value), message)


def test_a_single_section_table_is_refused():
    text = toml(BASE).replace("[[section]]", "[section]", 1).split("[[section]]")[0]
    refused(text, "malformed tally: section is a single table: write each one as [[section]]")


# 2. Unknown keys in every table: refused with the keys allowed there, and the one a typo
# was probably meant to be.


@pytest.mark.parametrize(
    ("path", "meant", "allowed"),
    [
        ("bit.mu_statik", "mu_static", "diameter, damping, mu_coulomb, mu_static, stribeck_decay"),
        ("steel.shear_modulous", "shear_modulus", "shear_modulus, density"),
        ("top_drive.intertia", "inertia", "inertia, damping"),
        ("damping.bta", "beta", "model, beta"),
        ("section[1].weight", None, "kind, count, length, od, id, shear_modulus, density"),
    ],
)
def test_an_unknown_key_in_a_table_is_refused(path, meant, allowed):
    value = "19.5 lb/ft" if path.endswith("weight") else 0.8
    hint = f" (did you mean {meant!r}?)" if meant else ""
    named = {"section[1].weight": "section 2 (drill-collar), weight"}.get(path, path)
    refused(changed(path, value), f"{named}: unknown{hint}; allowed: {allowed}")


# 3. Physical quantities checked in the tally, named by their key, values as written.


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("steel.shear_modulus", "-79.3 GPa", "steel.shear_modulus = '-79.3 GPa' is not allowed"),
        ("steel.density", 0, "steel.density = 0 is not allowed: a finite density > 0"),
        ("section[0].shear_modulus", -1.0, "section 1 (drill-pipe), shear_modulus = -1.0 is not"),
        ("section[1].density", "-7.85 g/cm3", "section 2 (drill-collar), density = '-7.85 g/cm3'"),
        ("section[0].od", "50 m", "section 1 (drill-pipe), od = '50 m' is not allowed: a finite"),
        ("section[0].od", 1e100, "section 1 (drill-pipe), od = 1e+100 is not allowed"),
        ("section[1].id", "-1 in", "section 2 (drill-collar), id = '-1 in' is not allowed"),
        ("section[1].id", "6.5 in", "section 2 (drill-collar), id = '6.5 in' is not allowed: need"),
        ("section[0].length", 1e-310, "section 1 (drill-pipe): a joint's stiffness"),
        ("bit.diameter", "100 ft", "bit.diameter = '100 ft' is not allowed"),
        ("bit.damping", -1.0, "bit.damping = -1.0 is not allowed: a finite damping >= 0"),
        ("top_drive.damping", -425, "top_drive.damping = -425 is not allowed"),
        ("top_drive.inertia", 0.0, "top_drive.inertia = 0.0 is not allowed"),
        ("bit.mu_coulomb", 0.0, "bit.mu_coulomb = 0.0 is not allowed"),
        ("bit.mu_static", 0.3, "bit.mu_static = 0.3 is not allowed: need mu_static > mu_coulomb"),
        ("bit.mu_static", "high", "bit.mu_static = 'high' is not allowed"),
        ("bit.mu_static", math.nan, "bit.mu_static = 'nan' is not allowed"),
        ("bit.stribeck_decay", -0.9, "bit.stribeck_decay = -0.9 is not allowed"),
        ("bit.stribeck_velocity", 0.0, "bit.stribeck_velocity = 0.0 is not allowed"),
        ("damping.beta", "0.2 h", "damping.beta = '0.2 h' is not allowed: a finite number of"),
        ("damping.beta", math.inf, "damping.beta = 'inf' is not allowed"),
    ],
)
def test_an_unphysical_value_is_refused_naming_the_key(path, value, message):
    if isinstance(value, float) and not math.isfinite(value):
        value = toml_value(value)  # the TOML spelling: shown as the string the tally gave
        text = changed(path, 0.125).replace("= 0.125", f"= {value}")
        message = message.replace(f"'{value}'", repr(float(value)))
    else:
        text = changed(path, value)
    refused(text, message)


def test_a_coulomb_coefficient_above_the_default_static_one_names_itself():
    doc = copy.deepcopy(BASE)
    doc["bit"] = {"diameter": "12.25 in", "mu_coulomb": 0.9}
    refused(toml(doc), "bit.mu_coulomb = 0.9 is not allowed: need mu_coulomb < mu_static = 0.8")


def test_a_negative_top_drive_inertia_names_the_key_and_the_chain_entry():
    msg = refused(changed("top_drive.inertia", -1.0), "top_drive.inertia = -1.0 is not allowed")
    assert "inertias[0]" in msg  # what tests/test_tally.py has always matched


def test_the_inertia_unit_error_reads_an_inertia():
    msg = refused(changed("top_drive.inertia", "2122 kg"), "top_drive.inertia: '2122 kg'")
    assert "is not an inertia unit" in msg and " a inertia" not in msg


# 4. Depth and size: bounded, so a typo cannot grow the string until memory runs out.


@pytest.mark.parametrize("depth", [math.nan, math.inf, -math.inf, -3000.0, 0.0, 1e8, 10**400])
def test_at_depth_refuses_a_depth_that_is_not_finite_positive_and_earthly(depth):
    tally = parse_tally(toml(BASE))
    with pytest.raises(TallyError, match=r"^depth = \S+ m is not allowed: a finite depth > 0"):
        tally.at_depth(depth)


@pytest.mark.parametrize("depth", ["3000", True, None])
def test_at_depth_refuses_a_depth_that_is_not_a_number(depth):
    with pytest.raises(TallyError, match=r"depth = .* is not allowed"):
        parse_tally(toml(BASE)).at_depth(depth)


def test_the_deepest_earthly_string_is_built_lumped():
    tally = parse_tally(toml(BASE)).at_depth(6.3e6)
    assert tally.to_params(dof=2, lump=1000).dof == 2


def test_a_listed_string_beyond_any_depth_is_refused_without_building_it():
    # 1e6 joints of 9 m: 9000 km. The old parser built all of them before answering.
    msg = refused(
        changed("section[0].count", 10**6), "section 1 (drill-pipe), count = 1000000 is not allowed"
    )
    assert "9e+06 m" in msg


def test_a_string_of_too_many_inertias_is_refused_naming_the_lump_that_fits():
    assert tally_module.MAX_DOF == spec.MAX_DOF == 100_000  # one limit for sweeps and strings
    tally = parse_tally(toml(BASE)).at_depth(1e6)  # 111107 joints of 9 m under 37.2 m of collars
    needle = r"lump = 1: .* 111110 inertias, at most 100000 .*lump >= 2;"
    with pytest.raises(TallyError, match=needle):
        tally.to_params(dof=4)
    assert tally.to_params(dof=4, lump=2).dof == 4


def test_bad_lump_and_dof_arguments_are_refused_naming_them():
    tally = parse_tally(toml(BASE))
    for lump in (0, -3):
        with pytest.raises(TallyError, match=r"lump = \S+ is not allowed: an integer >= 1"):
            tally.to_params(lump=lump)
    for dof in (1, 200):
        with pytest.raises(TallyError, match=r"dof = \S+ is not allowed: 2 \.\.\. 103"):
            tally.to_params(dof=dof)
    # not integers at all: TypeError, as every integer argument of the API (a float of
    # integer value too; 1.5 first: the old loop never ended on it)
    for name, bad, shown in (("lump", 1.5, "float 1.5"), ("lump", True, "bool True"),
                             ("lump", "2", "str '2'"), ("dof", 2.0, "float 2.0"),
                             ("dof", "3", "str '3'"), ("dof", False, "bool False")):  # fmt: skip
        with pytest.raises(TypeError, match=rf"^{name} must be an integer, got {shown}$"):
            tally.to_params(**{name: bad})
    assert tally.to_params(dof=np.int64(3), lump=np.int32(2)).dof == 3  # numpy integers are taken


# The CLI: exit 2, one line naming the key, no traceback, nothing on stdout.


@pytest.mark.parametrize(
    ("path", "value", "depth", "needle"),
    [
        ("bit.mu_static", [0.8], None, "bit.mu_static = [0.8] is not allowed"),
        ("section", 5, None, "section = 5 is not allowed"),
        ("bit", 3, None, "bit = 3 is not allowed"),
        ("section", [1, 2], None, "section 1 = 1 is not allowed"),
        ("steel", 5, None, "steel = 5 is not allowed"),
        ("bit.mu_statik", 0.8, None, "bit.mu_statik: unknown (did you mean 'mu_static'?)"),
        ("steel.shear_modulus", "-79.3 GPa", None, "steel.shear_modulus = '-79.3 GPa' is not"),
        ("damping.beta", "0.2 h", None, "damping.beta = '0.2 h' is not allowed"),
        ("bit.mu_static", 0.3, None, "bit.mu_static = 0.3 is not allowed"),
        ("name", "t", "1e8m", "depth = 100000000.0 m is not allowed"),
        ("name", "t", "1000km", "lump = 1: the string (1e+06 m) has 111110 inertias"),
    ],
)
def test_the_string_command_refuses_in_one_line(tmp_path, path, value, depth, needle):
    tally = tmp_path / "t.toml"
    tally.write_text(changed(path, value))
    extra = [] if depth is None else ["--depth", depth]
    out = subprocess.run(
        [sys.executable, "-m", "pydrill", "string", str(tally), *extra],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2, out.stderr
    assert out.stdout == "" and "Traceback" not in out.stderr
    assert out.stderr.startswith("pydrill string: error: ") and out.stderr.count("\n") == 1
    assert needle in out.stderr
