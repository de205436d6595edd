"""Guards from a mutation audit of pydrill's result layer (result.py, simulate.py,
sweep_points.py, the atlas table, format and journal): behaviour no other test would have
noticed breaking, each checked against something independent (the simulation's own arrays, a
hand computation, a record reread with plain h5py)."""

from pathlib import Path

import numpy as np
import pytest
from sweeping import SMALL

import pydrill
from pydrill.spec import parse_spec
from pydrill.stability import stability
from pydrill.sweep_points import evaluate_batch, evaluate_point

PAPER = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"

# --- sweep points -----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def small():
    spec = parse_spec(SMALL.replace("t_end = 200.0", "t_end = 100.0"))
    return spec, [evaluate_point(spec, i) for i in range(spec.size)]


def test_a_points_record_is_what_simulate_and_stability_give(small):
    """Each run of a record is simulate's summary from that start; coexistence is "the starts
    end in different regimes" (a start with no steady state to begin from is no regime);
    the steady states are stability's, fastest first."""
    spec, records = small
    seen = set()
    for i, rec in enumerate(records):
        params = spec.params_at(spec.coords(i))
        wob, torque = spec.operating_point(spec.coords(i))
        regimes = set()
        for init in spec.initials:
            try:
                r = pydrill.simulate(
                    params, wob=wob, torque=torque, t_end=100.0, initial=init, n_out=2
                )
            except ValueError:
                assert init == "equilibrium" and rec["runs"][init] == {"regime": "no-steady-state"}
                continue
            run = rec["runs"][init]
            assert run["regime"] == r.regime
            s = r.summary
            for key in ("bit_min", "bit_max", "bit_mean", "top_min", "top_max", "top_mean"):
                assert run[key] == getattr(s, key), key
            assert run["stick_events"] == s.stick_events
            assert run["caveat"] == s.caveat
            regimes.add(r.regime)
        assert rec["coexistence"] == (len(regimes) > 1)
        seen.add((len(regimes), rec["coexistence"]))
        pts = stability(params, wob, torque=torque)
        omegas = sorted((p.omega for p in pts), reverse=True)
        assert rec["stability"]["omega_eq"] == pytest.approx(omegas, rel=1e-12)
        assert rec["stability"]["unstable"] == [
            next(p.unstable for p in pts if p.omega == w) for w in omegas
        ]
    # SMALL has both kinds of point: two regimes (stick-slip from rest, steady from the
    # steady state), and one regime from both; and one with two steady states.
    assert (2, True) in seen and (1, False) in seen
    assert max(len(rec["stability"]["omega_eq"]) for rec in records) == 2


def test_a_batch_out_of_time_hands_back_every_point_it_did_not_compute(small):
    """evaluate_batch with a budget: the points computed and the points handed back are
    together the batch, in order, none lost and none twice."""
    spec, records = small
    indices = [5, 0, 3, 2, 4]
    b = evaluate_batch(spec.text, indices, budget=0.0)
    assert b.indices.tolist() == [5]  # the first point runs past a budget of 0
    assert b.indices.tolist() + b.left == indices
    b = evaluate_batch(spec.text, indices)
    assert b.indices.tolist() == indices and b.left == []
    # The batch's block holds each record's regime, as the record has it.
    from pydrill.atlas_schema import REGIMES

    for row, i in enumerate(indices):
        for j, init in enumerate(spec.initials):
            assert b.block["regime"][row, j] == REGIMES[records[i]["runs"][init]["regime"]]


def test_a_string_axis_gives_each_string_its_own_crossings():
    """The crossings cached per string (sweep_points._string_crossings): a sweep over pipes
    records, at each string, the unstable count of that string's own steady state, as
    stability computed afresh gives it."""
    spec = parse_spec(
        '[model]\npreset = "reduced-scale"\ntorque = 8.3\n[axes]\nwob = [60.0, 120.0]\n'
        'pipes = [1, 6]\n[simulation]\nt_end = 5.0\ninitial = ["rest"]\n'
    )
    deltas = set()
    for i in range(spec.size):
        rec = evaluate_point(spec, i)
        coords = spec.coords(i)
        params = spec.params_at(coords)
        wob, torque = spec.operating_point(coords)
        pts = stability(params, wob, torque=torque)[::-1]
        assert rec["stability"]["unstable"] == [p.unstable for p in pts]
        assert rec["stability"]["hopf_margin"] == pytest.approx(
            [p.delta_margin for p in pts], rel=1e-12
        )
        deltas.add(tuple(rec["stability"]["hopf_margin"]))
    assert len(deltas) == spec.size


# --- SimulationResult: stick intervals ------------------------------------------------------

HELD = ("stick", "band")


def _check_intervals(r):
    """stick_intervals against the friction mode the core reports at every output time: an
    output time inside an interval is held (stick or the Karnopp band), one outside is slipping;
    an interval under way at t[0] starts there, one under way at t[-1] ends there."""
    got = r.stick_intervals()
    t0, t1 = float(r.t[0]), float(r.t[-1])
    edges = [x for iv in got for x in iv]
    assert edges == sorted(edges) and all(t0 <= x <= t1 for x in edges)
    assert all(b > a for a, b in got)
    modes = r.modes
    for t, m in zip(r.t, modes, strict=True):
        if any(abs(t - x) < 1e-9 for x in edges):
            continue
        assert any(a < t < b for a, b in got) == (m in HELD), (t, m)
    if modes[0] in HELD:
        assert got[0][0] == t0
    if modes[-1] in HELD:
        assert got[-1][1] == t1
    return got


@pytest.mark.parametrize("friction", ["exact", "karnopp"])
def test_stick_intervals_are_where_the_bit_is_held(friction):
    """From rest and from output that starts inside a stick phase (not on a switch time:
    see the audit's report for that case)."""
    full = pydrill.simulate(wob=100, torque=8.3, dof=4, t_end=60.0, friction=friction, n_out=601)
    got = _check_intervals(full)
    assert len(got) >= 3 and got[-1][1] == 60.0  # held at the end: closed there
    # Output that starts inside the second stick phase: the phase starts at t[0].
    a, b = got[1]
    start = 0.5 * (a + b)
    part = pydrill.simulate(
        wob=100,
        torque=8.3,
        dof=4,
        t_end=60.0,
        friction=friction,
        t_out=np.linspace(start, 60.0, 351),
    )
    cut = _check_intervals(part)
    assert cut[0] == (start, pytest.approx(b, rel=1e-6))


@pytest.mark.parametrize("friction", ["exact", "karnopp"])
def test_a_bit_that_starts_beyond_static_friction_is_held_only_while_it_is(friction):
    """dof 2 from a state at rest twisted to 2 T_s: the bit breaks away at once (exact), or
    creeps in the Karnopp band until it leaves it (mode "band" at t = 0: held from 0)."""
    p = pydrill.preset("reduced-scale", dof=2)
    theta = 2 * p.static_torque(100.0) / p.stiffnesses[0]
    r = pydrill.simulate(
        p, wob=100, torque=8.3, t_end=30.0, friction=friction, initial=[0.0, theta, 0.0]
    )
    got = _check_intervals(r)
    if friction == "karnopp":
        assert r.modes[0] == "band" and r.switches[0].kind == "band-leave"
        assert got[0] == (0.0, r.switches[0].t)
    else:
        assert r.modes[0] == "slip+" and got[0][0] == r.switches[0].t > 0


# --- the atlas: records in, plain h5py out; the journal ---------------------------------------


def _sweep(spec, out):
    from pydrill.sweep import run_sweep

    return run_sweep(spec, out, serial=True)


FAILING = SMALL.replace("t_end = 200.0", "t_end = 200.0\nmax_steps = 900")


def test_an_atlas_keeps_failures_apart_and_judges_coexistence_only_where_it_can(tmp_path):
    """One point fails (its stick-slip needs more than 900 steps): it reads as failed from
    both starts, with its message and its counts at their CF _FillValue (-1: not measured),
    and its coexistence -1 (not judged); every other point's is its record's."""
    import h5py

    from pydrill.atlas_schema import REGIMES, STATUS

    spec = parse_spec(FAILING)
    records = [evaluate_point(spec, i) for i in range(spec.size)]
    bad = [rec["status"] == "failed" for rec in records]
    assert 0 < sum(bad) < spec.size and not bad[-1]  # points after it too
    out = tmp_path / "f.h5"
    report = _sweep(spec, out)
    assert report.failed == sum(bad)
    with h5py.File(out, "r") as f:
        status = f["status"][...].ravel()
        regime = f["regime"][...].reshape(spec.size, -1)
        coexistence = f["coexistence"][...].ravel()
        message = f["message"][...].ravel()
        events = f["stick_events"][...].reshape(spec.size, -1)
        assert f["stick_events"].attrs["_FillValue"] == -1
    for i, rec in enumerate(records):
        if bad[i]:
            assert status[i] == STATUS["failed"] and coexistence[i] == -1
            assert np.all(regime[i] == REGIMES["failed"]) and np.all(events[i] == -1)
            assert "max_steps" in message[i].decode()
        else:
            assert status[i] == STATUS["done"] and message[i] in (b"", "")
            assert coexistence[i] == int(rec["coexistence"])
    # From one start, coexistence is judged nowhere: -1 (0 would claim "one regime").
    one = parse_spec(FAILING.replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]'))
    _sweep(one, tmp_path / "one.h5")
    with h5py.File(tmp_path / "one.h5", "r") as f:
        assert np.all(f["coexistence"][...] == -1)


def _journal_only(spec, out, records):
    """An atlas and its journal as a kill left them: the journal flushed, the atlas not."""
    from pydrill.journal import journal_path, prepare
    from pydrill.journal_lines import line

    prepare(spec, out, resume=False, params_json="{}", version="test")
    with journal_path(out).open("a") as fh:
        fh.write("".join(line(rec) for rec in records))
    return journal_path(out)


def test_a_resumed_sweep_writes_the_journals_points_into_the_atlas(small, tmp_path):
    """After a kill between the journal's flush and the atlas's write, a resume puts every
    point of the journal into the atlas (reread with plain h5py) and counts them done."""
    import h5py

    from pydrill.atlas_schema import REGIMES
    from pydrill.journal import prepare

    spec, records = small
    out = tmp_path / "r.h5"
    _journal_only(spec, out, records[:4])
    with h5py.File(out, "r") as f:  # the atlas as created: every point missing
        assert np.all(f["regime"][...] == REGIMES["missing"]) and not np.any(f["status"][...])
    _, done = prepare(spec, out, resume=True, params_json="{}", version="test")
    assert done == 4
    with h5py.File(out, "r") as f:
        status, regime = f["status"][...].ravel(), f["regime"][...].reshape(spec.size, -1)
    assert status.tolist() == [1] * 4 + [0] * (spec.size - 4)
    for i, rec in enumerate(records[:4]):
        assert regime[i].tolist() == [REGIMES[rec["runs"][k]["regime"]] for k in spec.initials]
    # A failed point is done too (not computed again): counted with the others.
    failing = parse_spec(FAILING)
    recs = [evaluate_point(failing, i) for i in range(4)]
    assert any(rec["status"] == "failed" for rec in recs)
    _journal_only(failing, tmp_path / "g.h5", recs)
    assert prepare(failing, tmp_path / "g.h5", resume=True, params_json="{}", version="t")[1] == 4


def test_the_journal_lists_every_point_and_cuts_a_torn_last_line(tmp_path):
    """journaled (what ``atlas info`` counts): every point of a 12-point sweep, 0 and the
    two-digit ones included. A last line torn by a kill is skipped, then cut off the file so
    that the next append starts a line of its own."""
    from pydrill.journal import journaled, read_journal

    spec = parse_spec(
        SMALL.replace("wob = [40.0, 100.0, 160.0]", "wob = [40.0, 60.0, 80.0, 100.0, 120.0, 160.0]")
        .replace('initial = ["rest", "equilibrium"]', 'initial = ["rest"]')
        .replace("t_end = 200.0", "t_end = 20.0")
    )
    out = tmp_path / "j.h5"
    order = [11, 0, 10, 5, 1, 2, 3, 4, 6, 7, 8, 9]
    jp = _journal_only(spec, out, [evaluate_point(spec, i) for i in order])
    assert journaled(out).tolist() == order
    size = jp.stat().st_size
    with jp.open("ab") as fh:
        fh.write(b'[3, "done", ')  # torn mid-write
    assert journaled(out).tolist() == order
    assert [rec["i"] for rec in read_journal(out, spec)] == order
    assert jp.stat().st_size == size  # cut back to its last whole line


# --- SimulationResult's derived quantities ------------------------------------------------------


def test_reaction_torque_of_a_steady_run_of_a_real_string():
    """A tally string (c_b > 0) drilling steadily: the rock's reaction T_e is the bit friction
    W_ob R_b μ_b(Ω) (DESIGN.md: the steady state)."""
    from pydrill.tally import load_tally

    p = load_tally(PAPER).at_depth(1000.0).to_params(lump=10)
    wob, omega = 3e4, 150 * 2 * np.pi / 60
    u = pydrill.equilibrium_torque(p, wob, omega)
    r = pydrill.simulate(p, wob=wob, torque=u, initial="equilibrium", t_end=40.0, n_out=401)
    assert r.regime == "steady"
    g = p.stribeck_decay / p.stribeck_velocity
    mu = p.mu_coulomb + (p.mu_static - p.mu_coulomb) * np.exp(-g * omega)
    assert r.reaction_torque[-1] == pytest.approx(wob * p.bit_radius * mu, rel=1e-5)
    assert r.reaction_torque[-1] < u - 1e-3 * u  # c_r Ω and c_b Ω are taken off on the way


def test_to_dict_is_the_summary_and_is_strict_json():
    """to_dict: the summary's numbers under their names, and JSON without NaN or inf (a stuck
    bit's severity, (max − min) / (2 mean) with mean 0, is no number: null)."""
    import json

    for wob, torque in ((100.0, 8.3), (100.0, 5.0)):
        r = pydrill.simulate(wob=wob, torque=torque, dof=4, t_end=60.0, n_out=2)
        d = json.loads(json.dumps(r.to_dict(), allow_nan=False))
        s = r.summary
        for part, name in (("bit_velocity", "bit"), ("top_velocity", "top")):
            for key in ("min", "max", "mean"):
                assert d[part][key] == getattr(s, f"{name}_{key}")
        if np.isfinite(s.severity):
            assert d["severity"] == s.severity
        else:
            assert r.regime == "stuck" and d["severity"] is None


def test_reaction_torque_at_each_switch_is_the_cores():
    """T_e from the output states, at output times put on the switches of the same run, is
    the T_e the core judged each switch with (T_s at a break-away); in stick-slip the element
    above the bit still turns at a stick, so the damping of the bit's own spring counts."""
    from pydrill.tally import load_tally

    p = load_tally(PAPER).at_depth(3000.0).to_params(lump=10)
    op = {"wob": 1e5, "torque": 1.1e4, "t_end": 60.0}
    switches = pydrill.simulate(p, **op).switches[:6]
    r = pydrill.simulate(p, **op, t_out=[s.t for s in switches])
    assert {s.kind for s in switches} == {"slip", "stick"}
    for s, te in zip(switches, r.reaction_torque, strict=True):
        assert te == pytest.approx(s.reaction_torque, rel=1e-6)
        if s.kind == "slip":
            assert te == pytest.approx(p.static_torque(op["wob"]), rel=1e-9)
    assert np.min(r.omega[:, -2] - r.omega[:, -1]) > 0 and p.dampings[-1] != p.dampings[0]


def test_the_bit_turns_through_its_mean_velocity_in_stick_slip():
    """bit_angle (φ_top − Σ θ): over the judged window it turns through bit_mean × the window,
    bit_mean being "exact: from the angle turned over the window", computed in the core."""
    r = pydrill.simulate(wob=100.0, torque=8.3, dof=4, t_end=300.0, n_out=3001)
    s = r.summary
    assert r.regime == "stick-slip"
    k = int(np.searchsorted(r.t, s.window_start))
    assert r.t[k] == s.window_start
    turned = (r.bit_angle[-1] - r.bit_angle[k]) / (r.t[-1] - r.t[k])
    assert turned == pytest.approx(s.bit_mean, rel=1e-9)
    np.testing.assert_allclose(r.angles[:, -1], r.bit_angle, rtol=1e-12)


# --- simulate's arguments ------------------------------------------------------------------


def test_overrides_change_a_given_string():
    """simulate(params, ..., bit_radius=...): the run is of the string with the field replaced:
    its static torque T_s = μ_sb W_ob R_b by hand, and its inputs() repeat it."""
    p = pydrill.preset("reduced-scale", dof=4)
    r = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=10.0, n_out=2, bit_radius=0.12)
    assert r.params.bit_radius == 0.12 and p.bit_radius != 0.12
    assert r.summary.static_torque == pytest.approx(p.mu_static * 100.0 * 0.12, rel=1e-12)
    assert r.inputs()["bit_radius"] == 0.12


def test_max_steps_takes_the_documented_range():
    """max_steps: 1 ... 2**62 (docstring), kept as given."""
    r = pydrill.simulate(wob=100.0, torque=8.3, dof=2, t_end=1.0, n_out=2, max_steps=2**40)
    assert r.settings["max_steps"] == 2**40
    with pytest.raises(ValueError, match="max_steps"):
        pydrill.simulate(wob=100.0, torque=8.3, dof=2, t_end=1.0, max_steps=2**62 + 1)
