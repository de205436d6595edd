"""``--set NAME=VALUE``: the string's scalar parameters changed from the command line, for
every command that builds a string (simulate, stability, hopf, map, bifurcation). Each is
compared with the Python API on the same parameters, built independently."""

import json
from pathlib import Path

import pytest
from cli_running import spawn as run
from cli_running import spawn_json as run_json

import pydrill
from pydrill import stability as st

TALLY = Path(__file__).resolve().parents[1] / "examples" / "tallies" / "paper-eq53.toml"


def test_simulate_takes_set_values_with_their_units():
    """bit_damping in SI, the bit's radius in inches: the run is the API's on the preset with
    those two fields changed (0.1016 m), and --json says what --set changed, in SI."""
    d = run_json(
        "simulate", "--dof", "4", "--wob", "100", "--torque", "8.3", "--t-end", "100",
        "--set", "bit_damping=0.05", "--set", "bit_radius = 4 in",
    )  # fmt: skip
    p = pydrill.preset("reduced-scale", dof=4, bit_damping=0.05, bit_radius=0.1016)
    s = pydrill.simulate(p, wob=100.0, torque=8.3, t_end=100.0).summary
    assert d["set"] == {"bit_damping": 0.05, "bit_radius": pytest.approx(0.1016, rel=1e-12)}
    assert d["units"]["bit_damping"] == "N·m·s/rad" and d["units"]["bit_radius"] == "m"
    assert d["regime"] == s.regime
    assert d["bit_velocity"]["mean"] == pytest.approx(s.bit_mean, rel=1e-9)
    assert d["static_torque"] == pytest.approx(s.static_torque, rel=1e-12)
    plain = run_json("simulate", "--dof", "4", "--wob", "100", "--torque", "8.3", "--t-end", "100")
    assert "set" not in plain and plain["static_torque"] != pytest.approx(d["static_torque"])


def test_the_analyses_take_set_too():
    """stability, hopf and map on a string whose friction and top damping --set changed:
    the API's answers on the same Params."""
    p = pydrill.preset("reduced-scale", dof=4, mu_static=0.9, top_damping=0.5)
    sets = ("--set", "mu_static=0.9", "--set", "top_damping=0.5")
    d = run_json("stability", "--dof", "4", "--wob", "100", "--torque", "8.3", *sets)
    points = st.stability(p, 100.0, torque=8.3)
    assert d["set"] == {"mu_static": 0.9, "top_damping": 0.5} and d["units"]["mu_static"] == "1"
    assert len(d["equilibria"]) == len(points) == 2  # (one without the changes)
    for eq, point in zip(d["equilibria"], points, strict=True):
        assert eq["omega"] == pytest.approx(point.omega, rel=1e-12)
        assert eq["spectral_abscissa"] == pytest.approx(point.spectral_abscissa, rel=1e-9)
    h = run_json("hopf", "--dof", "4", *sets)
    assert [c["delta"] for c in h["crossings"]] == pytest.approx(
        [c.delta for c in st.critical_deltas(p)], rel=1e-9
    )
    b = run_json("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1", *sets)
    assert b["set"] == d["set"]
    assert b != run_json("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1")
    m = run_json("map", "--dof", "4", *sets)
    assert m["set"] == d["set"]
    # the stuck boundary u = mu_sb W_ob R_b moves with mu_static
    assert json.dumps(m) != json.dumps(run_json("map", "--dof", "4"))


def test_a_tally_string_takes_set_too():
    """A tally's string with its bit damping changed: the API's tally string, replaced."""
    d = run_json(
        "stability", "--tally", str(TALLY), "--dof", "12", "--wob", "60kN", "--torque", "9kN*m",
        "--set", "bit_damping=50 N·m·s/rad",
    )  # fmt: skip
    p = pydrill.load_tally(TALLY).to_params(dof=12).replace(bit_damping=50.0)
    points = st.stability(p, 60e3, torque=9e3)
    assert d["set"] == {"bit_damping": 50.0} and d["tally"]["file"] == str(TALLY)
    assert [e["omega"] for e in d["equilibria"]] == pytest.approx([q.omega for q in points])


@pytest.mark.parametrize(
    ("command", "item", "said"),
    [
        ("stability", "wobble=3", "--set 'wobble=3': wobble is not one of the string's "
         "parameters; --set takes top_damping, bit_damping, bit_radius, mu_coulomb, mu_static, "
         "stribeck_decay, stribeck_velocity, karnopp_band"),
        ("simulate", "bit_dampng=0.1", "bit_dampng is not one of the string's parameters (did "
         "you mean 'bit_damping'?); --set takes top_damping"),
        ("stability", "wob=3", "--set 'wob=3': wob has an option of its own: give --wob"),
        ("simulate", "inertias=1", "inertias is a list, one value per inertia: give --inertias"),
        ("stability", "stiffnesses=1", "stiffnesses is a list, one value per link: give "
         "--stiffnesses K0,K1,...; --set"),
        ("stability", "bit_radius=3 kg", "--set 'bit_radius=3 kg': bit_radius = '3 kg': unit "
         "'kg' is not a length unit"),
        ("stability", "bit_radius", "--set 'bit_radius': expected NAME=VALUE"),
        ("stability", "mu_static=0.1", "--set mu_static = 0.1 is not allowed: need mu_static > "
         "mu_coulomb (0.5)"),
        ("stability", "bit_damping=-1", "--set bit_damping = -1 is not allowed: must be a "
         "finite number >= 0"),
    ],
)  # fmt: skip
def test_a_bad_set_is_one_line_naming_it(command, item, said, tmp_path):
    """Refused before anything runs or is written: exit 2, one line on stderr, no stdout."""
    plot = tmp_path / "f.png"
    proc = run(
        command, "--dof", "4", "--wob", "100", "--torque", "8.3", "--set", item,
        "--plot", str(plot),
    )  # fmt: skip
    assert proc.returncode == 2 and proc.stdout == ""
    assert said in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert not plot.exists()


def test_a_parameter_set_twice_is_refused():
    proc = run("hopf", "--dof", "4", "--set", "top_damping=1", "--set", "top_damping=2")
    assert proc.returncode == 2
    assert "top_damping is given twice; give each parameter once" in proc.stderr


@pytest.mark.parametrize(
    "command",
    [
        ("simulate", "--dof", "4", "--wob", "100", "--torque", "8.3", "--t-end", "20"),
        ("stability", "--dof", "4", "--wob", "100", "--torque", "8.3"),
        ("hopf", "--dof", "4"),
        ("map", "--dof", "4"),
        ("bifurcation", "--dof", "2", "--vary", "wob", "--torque", "8.1"),
    ],
)
def test_the_text_says_first_what_set_changed(command):
    """A report read later says which string it was: what --set changed, in SI (10 rpm is
    1.0472 rad/s), on its first line; nothing of it without --set."""
    sets = ("--set", "mu_static=0.9", "--set", "stribeck_velocity=10rpm")
    proc = run(*command, *sets)
    assert proc.returncode == 0, proc.stderr
    first = proc.stdout.splitlines()[0]
    assert first == "changed         mu_static = 0.9, stribeck_velocity = 1.0472 rad/s"
    assert "changed" not in run(*command).stdout


def test_the_figure_says_what_changed_from_the_preset_clear_of_the_caveat():
    """A figure of a changed string says so under its title, wrapped within the figure, and
    the caveat above stays clear of it; a preset's own string says nothing of the kind."""
    from pydrill.plot import simulation_figure

    def drawn(result):
        fig = simulation_figure(result)
        fig.canvas.draw()
        return fig, fig.axes[0]

    one = pydrill.simulate(dof=4, mu_static=0.85, wob=100.0, torque=8.3, t_end=20.0)
    assert one.summary.caveat  # a short run: a caveat line above the title
    fig, ax = drawn(one)
    assert ax.get_title().splitlines()[1] == "changed from reduced-scale: mu_static = 0.85"
    (caveat,) = [t for t in ax.texts if t.get_text().startswith("caveat:")]
    title, note = ax.title.get_window_extent(), caveat.get_window_extent()
    assert note.y0 >= title.y1 and note.y1 <= fig._suptitle.get_window_extent().y0
    every = {
        "top_damping": 0.2, "bit_damping": 0.02, "bit_radius": 0.11, "mu_coulomb": 0.45,
        "mu_static": 0.85, "stribeck_decay": 0.8, "stribeck_velocity": 1.2,
    }  # fmt: skip
    many = pydrill.simulate(dof=4, wob=100.0, torque=8.3, t_end=20.0, **every)
    fig, ax = drawn(many)
    lines = ax.get_title().splitlines()[1:]
    assert len(lines) == 2 and "stribeck_velocity = 1.2 rad/s" in lines[1]
    box = ax.title.get_window_extent()
    assert 0 <= box.x0 and box.x1 <= fig.bbox.x1
    fig, ax = drawn(pydrill.simulate(dof=4, wob=100.0, torque=8.3, t_end=20.0))
    assert "changed" not in ax.get_title()
