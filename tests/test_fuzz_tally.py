"""Pipe tallies fuzzed: whatever a tally file holds, reading it (alone, through a sweep spec, or
through the CLI) gives a TallyError (SpecError, exit 2) naming its key, or a usable string;
never an OverflowError, a RuntimeWarning or a traceback. The regressions below are what a
randomized search (seeded, some 45000 tallies by hand) found; the property test is its quick,
derandomized version."""

import copy
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from sweeping import TALLY_TABLES as BASE
from sweeping import toml

from pydrill import cli
from pydrill.spec import SpecError, parse_spec
from pydrill.tally import TallyError, parse_tally

SPEC = '[model]\ntally = "t.toml"\ntorque = 9000.0\n[axes]\nwob = [1e5]\n'


def with_(**changes) -> dict:
    """BASE with ``section1_count=...`` style changes (table, then key)."""
    doc = copy.deepcopy(BASE)
    for path, value in changes.items():
        table, key = path.split("__")
        if table.startswith("section"):
            doc["section"][int(table[-1])][key] = value
        else:
            doc[table][key] = value
    return doc


def test_a_joint_count_beyond_any_float_is_refused_naming_it(tmp_path, capsys):
    """count = 10**400 made parse_tally raise OverflowError (int too large to convert to
    float) summing the string's length: through a spec and through the CLI too."""
    text = toml(with_(section1__count=10**400))
    beyond = r"section 2 \(drill-collar\), count = 1000.* beyond 6\.371e\+06 m"
    with pytest.raises(TallyError, match=beyond):
        parse_tally(text)
    with pytest.raises(SpecError, match=r"^model\.tally: section 2 \(drill-collar\), count"):
        parse_spec(SPEC, tally_text=text)
    path = tmp_path / "t.toml"
    path.write_text(text)
    assert cli.main(["simulate", "--tally", str(path), "--wob", "1e5", "--torque", "9e3"]) == 2
    err = capsys.readouterr().err
    assert "section 2 (drill-collar), count" in err and "Traceback" not in err


def test_a_depth_that_needs_more_joints_than_any_float_counts_is_refused():
    """A drill pipe of 1e-306 m joints (of a steel of G = 1 Pa: its stiffness and inertia are
    finite normal floats): at_depth(10 km) needed inf joints and raised OverflowError from
    math.ceil, also inside parse_spec."""
    text = toml(
        with_(section0__length=1e-306, section0__od=0.1, section0__id=0.0, steel__shear_modulus=1)
    )
    tally = parse_tally(text)
    with pytest.raises(TallyError, match=r"depth 10000 m needs .* joints of 1e-306 m: too many"):
        tally.at_depth(1e4)
    spec = SPEC.replace("wob = [1e5]", "wob = [1e5]\ndepth = [1e4]")
    with pytest.raises(SpecError, match=r"^model \(at axes\.depth = 10000\): depth 10000 m"):
        parse_spec(spec, tally_text=text)


def test_a_subnormal_joint_stiffness_is_refused_naming_its_section():
    """shear_modulus = 1e-310 Pa gave a subnormal joint stiffness that passed, then overflowed
    1/k lumping springs in series (a RuntimeWarning) and was refused as 'stiffnesses[0] = 0',
    naming no key of the tally."""
    text = toml(with_(steel__shear_modulus=1e-310))
    needle = r"^section 1 \(drill-pipe\): a joint's stiffness .* shear_modulus"
    with pytest.raises(TallyError, match=needle):
        parse_tally(text)


def test_an_extreme_density_lumps_without_a_runtime_warning():
    """density = 1e308 kg/m³: the summed inertias of the 200 collars overflow, as one group;
    Params refuses the inf (pytest makes numpy's RuntimeWarning, which reached users, an
    error here)."""
    doc = with_(steel__density=1e308, section1__count=200, section1__od="12 in")
    tally = parse_tally(toml(doc))
    with pytest.raises(ValueError, match=r"inertias\[1\] = inf is not allowed"):
        tally.to_params(dof=2)
    tally.to_params()  # one joint an element: finite


WEIRD = st.one_of(
    st.sampled_from(
        [
            *(0, -1, 1, 10**400, -(10**400), 2**63, 1e308, -1e308, 5e-324, 1e-310, -0.0),
            *(math.nan, math.inf, -math.inf, True, "", "nan", "1e400 m", "-5 in", "5 parsecs"),
            *("\x00", "é", "stiffness-proportional", "drill-pipe", "bit", [], [1.0], {}, {"a": 1}),
        ]
    ),
    st.floats(),
    st.integers(),
    st.text(max_size=8),
)
LEAVES = [
    (table, key)
    for table, keys in {
        "top_drive": ("inertia", "damping"),
        "bit": (
            "diameter",
            "damping",
            "mu_coulomb",
            "mu_static",
            "stribeck_decay",
            "stribeck_velocity",
        ),
        "damping": ("model", "beta"),
        "steel": ("shear_modulus", "density"),
        "section0": ("kind", "count", "length", "od", "id", "shear_modulus", "density"),
        "section1": ("kind", "count", "length", "od", "id"),
    }.items()
    for key in keys
]


@settings(
    max_examples=150, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
@given(changes=st.lists(st.tuples(st.sampled_from(LEAVES), WEIRD), min_size=1, max_size=3))
def test_any_value_anywhere_is_a_tally_error_or_a_string(changes):
    doc = with_(**{f"{table}__{key}": value for (table, key), value in changes})
    try:
        tally = parse_tally(toml(doc))
    except TallyError as exc:
        assert str(exc)
        return
    for dof in (2, 3):
        try:
            tally.at_depth(3000.0).to_params(dof=dof)
        except ValueError as exc:  # TallyError, or the model's refusal naming the entry
            assert str(exc)
