"""``--inertias``, ``--stiffnesses``, ``--dampings`` on the analyses of a string (hopf,
stability, bifurcation, map), as simulate takes them: the string they give is the one the
Python API builds from the same lists (``pydrill.Params``, every other value typed here from
the reduced-scale preset's documented values, not read from the preset), a list of the wrong
length is refused naming its option, and --set's hint on a list's name points to the option."""

from pathlib import Path

import pytest
from cli_running import spawn as run
from cli_running import spawn_json as run_json

import pydrill
from pydrill import stability as st
from pydrill.cli import build_parser

TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"

INERTIAS, STIFFNESSES, DAMPINGS = (0.5, 0.3, 0.4), (2.0, 3.0), (0.01, 0.02)
LISTS = ["--inertias", "0.5,0.3,0.4", "--stiffnesses", "2,3", "--dampings", "0.01,0.02"]
#: the custom string: the chain given, the bit and friction of reduced-scale (pydrill string
#: --preset reduced-scale: c_r 0.18, c_b 0.01, R_b 0.1 m, mu_s 0.8, mu_c 0.5, gamma_b 0.9)
CUSTOM = pydrill.Params(
    inertias=INERTIAS,
    stiffnesses=STIFFNESSES,
    dampings=DAMPINGS,
    top_damping=0.18,
    bit_damping=0.01,
    bit_radius=0.1,
    mu_coulomb=0.5,
    mu_static=0.8,
    stribeck_decay=0.9,
)
#: one analysis command line per command, with its operating point
COMMANDS = {
    "hopf": ["hopf"],
    "stability": ["stability", "--wob", "100", "--torque", "8.3"],
    "bifurcation": ["bifurcation", "--vary", "wob", "--torque", "8.3"],
    "map": ["map"],
}


def test_stability_of_lists_is_the_apis_of_that_string():
    d = run_json(*COMMANDS["stability"], *LISTS)
    points = st.stability(CUSTOM, 100.0, torque=8.3)
    assert len(d["equilibria"]) == len(points) == 1
    got, want = d["equilibria"][0], points[0]
    assert got["omega"] == pytest.approx(want.omega, rel=1e-9)
    assert got["stable"] == want.stable and got["unstable_eigenvalues"] == want.unstable
    assert got["delta_margin"] == pytest.approx(want.delta_margin, rel=1e-9)
    assert got["spectral_abscissa"] == pytest.approx(want.spectral_abscissa, rel=1e-6)
    assert got["eigenvalue_count"] == 2 * 3 - 1  # a 3-inertia string's state
    # the lists changed the string: the 3-inertia preset's margin is another
    [preset] = st.stability(pydrill.preset("reduced-scale", dof=3), 100.0, torque=8.3)
    assert preset.delta_margin != pytest.approx(want.delta_margin, rel=1e-3)
    assert (d["inertias"], d["stiffnesses"], d["dampings"]) == (
        list(INERTIAS), list(STIFFNESSES), list(DAMPINGS)
    )  # fmt: skip
    assert d["dof"] == 3 and d["units"]["inertias"] == "kg·m2"


def test_hopf_of_lists_is_the_apis_of_that_string():
    d = run_json("hopf", *LISTS)
    crossings = st.critical_deltas(CUSTOM)
    assert [c["type"] for c in d["crossings"]] == [c.type for c in crossings]
    assert [c["delta"] for c in d["crossings"]] == pytest.approx(
        [c.delta for c in crossings], rel=1e-9
    )
    freq = [c.frequency for c in crossings if c.frequency is not None]
    assert [c["frequency"] for c in d["crossings"] if c["frequency"] is not None] == (
        pytest.approx(freq, rel=1e-9)
    )
    other = st.critical_deltas(pydrill.preset("reduced-scale", dof=3))
    assert [c.delta for c in other] != pytest.approx([c.delta for c in crossings], rel=1e-3)
    assert d["inertias"] == list(INERTIAS) and d["stiffnesses"] == list(STIFFNESSES)


def test_bifurcation_and_map_echo_the_lists_and_use_them():
    b = run_json(*COMMANDS["bifurcation"], *LISTS)
    hopf = [c.delta for c in st.critical_deltas(CUSTOM) if c.type == "hopf"]
    for point in (p for p in b["points"] if p["type"] == "HB"):  # each on a crossing's slope
        assert min(abs(point["delta"] - h) for h in hopf) < 1e-9 * max(hopf)
    assert b["inertias"] == list(INERTIAS) and b["dampings"] == list(DAMPINGS)
    m = run_json("map", "--inertias", "0.5,0.3,0.4")
    assert m["inertias"] == list(INERTIAS) and "stiffnesses" not in m
    assert m["dof"] == 3 and m["units"]["inertias"] == "kg·m2"


@pytest.mark.parametrize("command", COMMANDS)
def test_a_list_of_the_wrong_length_is_refused_naming_its_option(command):
    proc = run(*COMMANDS[command], "--inertias", "1,2,3", "--stiffnesses", "1,2,3")
    assert proc.returncode == 2
    assert "--stiffnesses has 3 entries: dof = 3 needs 2" in proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("command", ["hopf", "stability", "simulate"])
def test_a_bad_entry_is_refused_naming_its_option(command):
    """On a preset's string and on a tally's, an entry out of range names its option (as
    "--inertias has 2 entries" does), not the API's list: simulate said "inertias[1] = -2"."""
    line = COMMANDS.get(command, ["simulate", "--wob", "100", "--torque", "8.3"])
    proc = run(*line, "--inertias", "1,-2,3")
    assert proc.returncode == 2 and "--inertias[1] = -2 is not allowed" in proc.stderr
    proc = run(*line, "--tally", str(TALLY), "--dof", "2", "--dampings", "-1")
    assert proc.returncode == 2 and "--dampings[0] = -1 is not allowed" in proc.stderr


@pytest.mark.parametrize("command", COMMANDS)
def test_set_hint_on_a_list_names_this_commands_option(command):
    proc = run(*COMMANDS[command], "--set", "inertia=3")
    assert proc.returncode == 2
    assert "give --inertias I0,I1,..." in proc.stderr
    assert "only pydrill simulate" not in proc.stderr


@pytest.mark.parametrize("command", COMMANDS)
def test_help_lists_the_three(command):
    proc = run(command, "--help")
    assert proc.returncode == 0
    for option in ("--inertias I0,I1,...", "--stiffnesses K0,...", "--dampings C0,..."):
        assert option in proc.stdout


def test_a_checks_simulate_line_keeps_the_lists():
    """map's failed check advises a ``pydrill simulate`` line of its point: the string it
    names must be the one checked, lists included (parsed back by the real parser)."""
    from pydrill.cli_string import point_command

    args = build_parser().parse_args(["map", *LISTS[:4], "--check", "2"])
    line = point_command(args, 100.0, 8.3)
    back = build_parser().parse_args(line.split()[1:])
    assert back.command == "simulate"
    assert (back.inertias, back.stiffnesses, back.dampings) == (
        list(INERTIAS), list(STIFFNESSES), None
    )  # fmt: skip
