"""Strings from pipe tallies, and driller units."""

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pydrill
from pydrill import units
from pydrill.tally import TallyError, load_tally, parse_tally

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [
        ("5 in", "length", 0.127),
        ("9800 ft", "length", 2987.04),
        ("3000m", "length", 3000.0),
        ("120 rpm", "velocity", 4 * math.pi),
        ("100 kN", "force", 1e5),
        ("25 klbf", "force", 25 * 4448.2216152605),
        ("12 kN·m", "torque", 12e3),
        ("12 kNm", "torque", 12e3),
        ("10 kft·lbf", "torque", 13558.179483314),
        ("79.3 GPa", "modulus", 79.3e9),
        (7850, "density", 7850.0),
    ],
)
def test_units(text, kind, si):
    assert units.parse(text, kind) == pytest.approx(si, rel=1e-12)
    if isinstance(text, str) and " " in text:
        number, unit = text.split(" ", 1)
        if unit in units.UNITS[kind]:
            assert units.convert(si, kind, unit) == pytest.approx(float(number))


def test_bad_units_are_named():
    with pytest.raises(ValueError, match="'furlong' is not a length unit"):
        units.parse("3 furlong", "length")
    with pytest.raises(ValueError, match="not a torque"):
        units.parse("lots", "torque")


def test_paper_tally_reduces_to_eq53_stiffness():
    tally = load_tally(PAPER)
    p = tally.to_params(dof=2)
    # The issue's bar: k_t within 5 % of the paper's 861.5336 N·m/rad.
    assert abs(p.stiffnesses[0] - 861.5336) / 861.5336 < 0.05
    # The drill pipe alone, by hand: G·I_p/L of 900 m of 5 in / 4.408 in pipe.
    ip = math.pi * ((5 * 0.0254) ** 4 - (4.408 * 0.0254) ** 4) / 32
    assert tally.sections[0].joint_stiffness() * 1 == pytest.approx(79.3e9 * ip / 9.0)
    assert p.stiffnesses[0] < 79.3e9 * ip / 900.0  # the BHA adds compliance in series
    assert p.dampings[0] == pytest.approx(0.2 * p.stiffnesses[0])  # c_t = 0.2 k_t as in Eq. 53
    assert p.bit_radius == pytest.approx(0.155575)
    assert p.inertias[0] == 2122.0
    # Our J_b is the steel of string and BHA; the paper's 471.9698 is about four times more
    # (it does not say how it lumped the BHA): reported, not matched.
    assert 100.0 < p.inertias[1] < 471.9698


def test_reduction_keeps_total_inertia_and_compliance():
    tally = load_tally(PAPER)
    full = tally.to_params()
    for dof in (2, 3, 7, 20):
        p = tally.to_params(dof=dof)
        assert p.dof == dof
        assert sum(p.inertias) == pytest.approx(sum(full.inertias), rel=1e-12)
        assert sum(1 / k for k in p.stiffnesses) == pytest.approx(
            sum(1 / k for k in full.stiffnesses), rel=1e-12
        )
    lumped = tally.to_params(lump=10)
    assert lumped.dof == full.dof - 90  # 100 pipe joints become 10 elements
    assert sum(lumped.inertias) == pytest.approx(sum(full.inertias))


OTHER = PAPER.parent / "5.5in-dp-8in-collars.toml"


@pytest.mark.parametrize("path", [PAPER, OTHER], ids=["5in-6.5in", "5.5in-8in"])
@pytest.mark.parametrize("depth", [1000.0, 3000.0, 5000.0])
def test_deeper_strings(path, depth):
    tally = load_tally(path).at_depth(depth)
    assert depth <= tally.length < depth + 9.0
    p = tally.to_params(dof=2)
    # Longer pipe: softer in proportion to its length (the BHA is short and stiff).
    pipe = tally.sections[0]
    expected = 1 / (
        pipe.count / pipe.joint_stiffness()
        + sum(s.count / s.joint_stiffness() for s in tally.sections[1:])
    )
    assert p.stiffnesses[0] == pytest.approx(expected, rel=1e-12)
    # The string at depth is a model the rest of pydrill runs on.
    crossings = pydrill.stability.critical_deltas(tally.to_params(dof=12))
    assert crossings


def test_simulated_real_string_from_the_tally_behaves_like_eq53():
    """Same W_ob and u on the Eq. (53) preset and on the tally's 2-DOF reduction: the
    2.7 % stiffer spring and lighter bit change numbers, not the regime."""
    tally_p = load_tally(PAPER).to_params(dof=2)
    preset = pydrill.preset("real-string")
    for wob, torque in ((5e4, 7e3), (1e5, 1.1e4)):
        a = pydrill.simulate(preset, wob=wob, torque=torque, t_end=200.0)
        b = pydrill.simulate(tally_p, wob=wob, torque=torque, t_end=200.0)
        assert a.regime == b.regime


@pytest.mark.parametrize(
    ("change", "key"),
    [
        (('od = "5 in"', 'od = "5 stone"'), "section 1 (drill-pipe), od"),
        (('id = "4.408 in"', 'id = "6 in"'), "section 1 (drill-pipe), id"),
        (("count = 100", "count = 0"), "section 1 (drill-pipe), count"),
        (('kind = "drill-pipe"', 'kind = "banana"'), "section 1, kind"),
        (("inertia = 2122.0", "inertia = -1.0"), "inertias[0]"),
    ],
)
def test_bad_tally_is_refused_naming_the_key(change, key):
    text = PAPER.read_text().replace(*change)
    with pytest.raises(TallyError, match=re.escape(key)):
        parse_tally(text)


def test_string_command_json():
    out = subprocess.run(
        [sys.executable, "-m", "pydrill", "string", str(PAPER), "--dof", "2", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    data = json.loads(out.stdout)
    assert data["dof"] == 2 and len(data["inertias"]) == 2 and len(data["stiffnesses"]) == 1
    assert data["length"] == pytest.approx(949.5)
    assert data["units"]["stiffnesses"] == "N·m/rad"
    assert np.isclose(data["stiffnesses"][0], 884.37, rtol=1e-3)


# --- Both shipped tallies at 1000, 3000 and 5000 m, against numbers computed by hand -----------

import tomllib  # noqa: E402
from dataclasses import replace  # noqa: E402

from scipy.linalg import eigh_tridiagonal  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

from pydrill.spec import parse_spec  # noqa: E402

TALLIES = [PAPER, OTHER]
TALLY_IDS = ["paper-eq53", "5.5in-dp-8in-collars"]
_TO_M = {"m": 1.0, "ft": 0.3048, "in": 0.0254}


def _metres(value) -> float:
    if isinstance(value, int | float):
        return float(value)
    number, unit = value.split()
    return float(number) * _TO_M[unit]


def _hand_sections(path: Path, depth: float) -> list[tuple[int, float, float, float, float]]:
    """(count, length, I_p, G, rho) per section straight from the TOML, the drill pipe
    lengthened by whole joints to reach ``depth``: no pydrill code involved."""
    doc = tomllib.loads(path.read_text())
    g = 79.3e9
    rho = 7850.0
    rows = []
    for s in doc["section"]:
        od, bore = _metres(s["od"]), _metres(s.get("id", 0.0))
        rows.append([s["count"], _metres(s["length"]), math.pi * (od**4 - bore**4) / 32, g, rho])
    bha = sum(c * length for c, length, *_ in rows[1:])
    rows[0][0] = math.ceil((depth - bha) / rows[0][1] - 1e-9)
    return [tuple(r) for r in rows]


@pytest.mark.parametrize("path", TALLIES, ids=TALLY_IDS)
@pytest.mark.parametrize("depth", [1000.0, 3000.0, 5000.0])
def test_lumped_totals_equal_the_hand_sums(path, depth):
    rows = _hand_sections(path, depth)
    compliance = sum(n * length / (g * ip) for n, length, ip, g, _ in rows)  # Σ L / (G I_p)
    inertia = sum(n * rho * ip * length for n, length, ip, _, rho in rows)  # Σ ρ I_p L
    length = sum(n * length for n, length, *_ in rows)
    tally = load_tally(path).at_depth(depth)
    assert tally.length == pytest.approx(length, rel=1e-12)
    assert depth <= length < depth + rows[0][1]
    for p in (tally.to_params(), tally.to_params(lump=7), tally.to_params(dof=2)):
        assert 1 / sum(1 / k for k in p.stiffnesses) == pytest.approx(1 / compliance, rel=1e-10)
        assert sum(p.inertias[1:]) == pytest.approx(inertia, rel=1e-10)
    full = tally.to_params()
    assert full.dof == 1 + sum(n for n, *_ in rows)  # one element per joint, plus the top drive
    # Each drill-pipe element is one joint: k = G I_p / L, J = ρ I_p L.
    _, length, ip, g, rho = rows[0]
    assert full.stiffnesses[0] == pytest.approx(g * ip / length, rel=1e-12)
    assert full.inertias[1] == pytest.approx(rho * ip * length, rel=1e-12)


def _lumped_fundamental(p) -> float:
    """First non-zero natural frequency of the undamped chain (free top drive, free bit)."""
    j = np.array(p.inertias)
    k = np.array(p.stiffnesses)
    diag = np.zeros(j.size)
    diag[:-1] += k
    diag[1:] += k
    s = 1 / np.sqrt(j)
    w2 = eigh_tridiagonal(
        diag * s * s, -k * s[:-1] * s[1:], eigvals_only=True, select="i", select_range=(1, 1)
    )
    return float(np.sqrt(w2[0]))


def _continuous_fundamental(path: Path, depth: float) -> float:
    """The same string as continuous shafts: transfer matrices of (twist angle, torque) through
    each uniform section, the top drive J_r at the top, a free end at the bit."""
    rows = _hand_sections(path, depth)
    j_top = tomllib.loads(path.read_text())["top_drive"]["inertia"]
    j_top = float(j_top.split()[0]) if isinstance(j_top, str) else float(j_top)  # "2500 kg·m2"

    def bit_torque(w):
        theta, torque = 1.0, -j_top * w**2
        for n, length, ip, g, rho in rows:
            kappa, span = w * math.sqrt(rho / g), n * length
            c, s = math.cos(kappa * span), math.sin(kappa * span)
            theta, torque = (
                theta * c + torque * s / (g * ip * kappa),
                -g * ip * kappa * s * theta + torque * c,
            )
        return torque

    grid = np.linspace(0.05, 20.0, 800)
    values = [bit_torque(w) for w in grid]
    lo = next(i for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0)
    return brentq(bit_torque, grid[lo], grid[lo + 1], xtol=1e-13)


@pytest.mark.parametrize("path", TALLIES, ids=TALLY_IDS)
@pytest.mark.parametrize("depth", [1000.0, 3000.0, 5000.0])
def test_fundamental_frequency_approaches_the_continuous_shaft(path, depth):
    """Lumping each element's inertia at its lower end is first-order accurate: splitting every
    joint into m elements divides the error in the fundamental by m."""
    exact = _continuous_fundamental(path, depth)
    tally = load_tally(path).at_depth(depth)
    errors = []
    for m in (1, 2, 4):
        fine = replace(
            tally,
            sections=tuple(
                replace(s, count=s.count * m, length=s.length / m) for s in tally.sections
            ),
        )
        errors.append(abs(_lumped_fundamental(fine.to_params()) / exact - 1))
    assert errors[0] < 3e-3  # one element per joint: within 0.3 %
    assert errors[1] == pytest.approx(errors[0] / 2, rel=0.05)
    assert errors[2] == pytest.approx(errors[0] / 4, rel=0.05)
    # Coarser elements (stands of 10 joints) are worse than joints.
    coarse = abs(_lumped_fundamental(tally.to_params(lump=10)) / exact - 1)
    assert coarse > 3 * errors[0]


@pytest.mark.parametrize("path", TALLIES, ids=TALLY_IDS)
@pytest.mark.parametrize("depth", [1000.0, 3000.0])
def test_a_reduced_string_keeps_the_fundamental_to_second_order(path, depth):
    """dof = N shares each element's inertia between its group's two ends: the reduced
    string's fundamental nears the full string's like 1/N², 4x closer each time the groups
    halve. Summed at the groups' lower ends, it neared like 1/N (2x), 5 % low at dof 9."""
    tally = load_tally(path).at_depth(depth)
    full = _lumped_fundamental(tally.to_params())
    error = {n: abs(_lumped_fundamental(tally.to_params(dof=n)) / full - 1) for n in (5, 9, 17)}
    assert error[9] < 4e-3
    assert error[5] / error[9] > 3.0
    assert error[9] / error[17] > 3.0


def test_a_reduced_strings_top_drive_carries_the_share_of_the_pipe_above_its_first_group():
    tally = load_tally(OTHER)
    k, j, _ = tally.elements(1)
    p = tally.to_params(dof=3)
    first = np.array_split(np.arange(len(k)), 2)[0]
    compliance = np.cumsum(1 / k[first])
    upper = float(np.sum(j[first] * (1 - compliance / compliance[-1])))
    assert p.inertias[0] == pytest.approx(tally.top_inertia + upper, rel=1e-12)
    assert 0 < upper < np.sum(j[first]) / 2 + 1e-9  # pipe, not collars, hangs from the top
    # The paper's two-inertia model keeps the top drive as it is, the rest at the bit.
    assert tally.to_params(dof=2).inertias[0] == tally.top_inertia


def test_string_command_says_what_a_reduced_top_drive_carries():
    out = subprocess.run(
        [sys.executable, "-m", "pydrill", "string", str(OTHER), "--dof", "4"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    top = load_tally(OTHER).to_params(dof=4).inertias[0]
    assert f"top drive   J = {top:.6g} kg m^2 (2500 + {top - 2500:.4g} of the string)" in out


@pytest.mark.parametrize("path", TALLIES, ids=TALLY_IDS)
def test_sweep_depth_axis_builds_the_at_depth_string(path):
    spec = parse_spec(
        "[model]\ndof = 9\ntorque = 9000.0\n[axes]\ndepth = [1000.0, 3000.0, 5000.0]\n"
        "wob = [5e4]\n[simulation]\nt_end = 10.0\n",
        tally_text=path.read_text(),
    )
    tally = load_tally(path)
    for depth in (1000.0, 3000.0, 5000.0):
        a = spec.params_at({"depth": depth, "wob": 5e4})
        b = tally.at_depth(depth).to_params(dof=9)
        assert a.inertias == b.inertias and a.stiffnesses == b.stiffnesses
        assert a.dampings == b.dampings and a.bit_radius == b.bit_radius


def test_shipped_tallies_are_the_designs_the_issue_names():
    """5 in drill pipe with 6.5 in collars (the paper's), and 5.5 in pipe with 8 in collars."""
    for path, pipe_od, collar_od in ((PAPER, 5.0, 6.5), (OTHER, 5.5, 8.0)):
        tally = load_tally(path)
        kinds = [s.kind for s in tally.sections]
        assert kinds[0] == "drill-pipe" and "drill-collar" in kinds and kinds[-1] == "bit"
        collar = tally.sections[kinds.index("drill-collar")]
        assert tally.sections[0].od == pytest.approx(pipe_od * 0.0254)
        assert collar.od == pytest.approx(collar_od * 0.0254)


# --- The analysis commands on a tally's string ------------------------------------------------


def _pydrill(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pydrill", *args], capture_output=True, text=True, timeout=300
    )


def test_stability_and_hopf_commands_take_a_tally():
    """``--tally FILE --depth D`` gives the commands the string ``Tally.at_depth(D)`` builds,
    at full resolution (334 inertias at 3000 m) or reduced (``--dof``)."""
    from pydrill.stability import critical_deltas, stability

    out = _pydrill(
        "stability", "--tally", str(PAPER), "--depth", "3000m", "--wob", "60kN",
        "--omega", "60rpm", "--json",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    p = load_tally(PAPER).at_depth(3000.0).to_params()
    assert data["dof"] == p.dof == 334
    assert data["tally"] == {"file": str(PAPER), "depth": 3000.0, "lump": 1}
    assert data["string"] == "paper-eq53 at 3001.5 m"  # whole joints: the string's own length
    assert data["preset"] is None
    (want,) = stability(p, 60e3, omega=2 * math.pi)
    (got,) = data["equilibria"]
    assert got["delta"] == pytest.approx(want.delta, rel=1e-14)
    assert got["spectral_abscissa"] == pytest.approx(want.spectral_abscissa, rel=1e-12)
    assert got["stable"] == want.stable

    out = _pydrill("hopf", "--tally", str(PAPER), "--depth", "9800ft", "--dof", "12", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    p12 = load_tally(PAPER).at_depth(9800 * 0.3048).to_params(dof=12)
    assert data["dof"] == 12
    want = [c.delta for c in critical_deltas(p12)]
    assert [c["delta"] for c in data["crossings"]] == pytest.approx(want, rel=1e-12)


def test_simulate_command_takes_a_tally():
    out = _pydrill(
        "simulate", "--tally", str(PAPER), "--depth", "1000m", "--lump", "3", "--wob", "80kN",
        "--torque", "9kN*m", "--t-end", "40", "--json",
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    p = load_tally(PAPER).at_depth(1000.0).to_params(lump=3)
    r = pydrill.simulate(p, wob=80e3, torque=9e3, t_end=40.0, n_out=3001)
    # top drive + 106 joints of drill pipe by 3 (36 elements) + the BHA's 5 = 42 inertias
    assert data["inputs"]["dof"] == p.dof == 42
    assert data["regime"] == r.regime
    assert data["bit_velocity"]["mean"] == pytest.approx(r.summary.bit_mean, rel=1e-12)
    assert data["tally"]["lump"] == 3


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--tally", str(PAPER), "--preset", "real-string"], "give --preset or --tally, not both"),
        (["--depth", "3000m"], "--depth needs --tally"),
        (["--lump", "2"], "--lump needs --tally"),
        (["--tally", str(PAPER), "--pipes", "10"], "--pipes is not allowed with --tally"),
        (["--tally", str(PAPER), "--lump", "0"], "--lump = 0 is not allowed"),
        (["--tally", str(PAPER), "--depth", "3 parsecs"], "3 parsecs"),
        (["--tally", "no-such-tally.toml"], "no-such-tally.toml"),
    ],
)
def test_tally_options_that_cannot_work_are_refused(args, needle):
    out = _pydrill("stability", *args, "--wob", "60kN", "--omega", "60rpm")
    assert out.returncode == 2
    assert needle in out.stderr and "Traceback" not in out.stderr
    assert out.stdout == ""
