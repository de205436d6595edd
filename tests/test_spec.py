"""Sweep specs: every bad spec is refused with a SpecError naming the key (issue 4), axes are
stored in increasing order, and the digest tells apart what would make a different atlas."""

import numpy as np
import pytest
from sweeping import ROOT

import pydrill
from pydrill.spec import SpecError, load_spec, parse_spec

# The smallest valid grid; each bad spec below changes one thing in it.
GRID = "[axes]\nwob = [50.0]\ntorque = [6.0]\n"
TALLY = (ROOT / "examples" / "tallies" / "paper-eq53.toml").read_text()
DEPTHS = '[model]\ntally = "t.toml"\ndof = 6\ntorque = 9000.0\n[axes]\ndepth = [1000.0, 3000.0]\n'


def refused(text: str, key: str, tally_text: str | None = None) -> str:
    """The message of the SpecError ``text`` raises; it must name ``key``."""
    with pytest.raises(SpecError) as err:
        parse_spec(text, tally_text=tally_text)
    assert key in str(err.value), str(err.value)
    return str(err.value)


# A. Malformed input: a SpecError naming the key, never a raw TypeError or MemoryError.


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("model = 5\n" + GRID, "model: 5 is not a table"),
        ("axes = [1, 2]\n", "axes: [1, 2] is not a table"),
        ('simulation = "fast"\n' + GRID, "simulation: 'fast' is not a table"),
        ("record = 1\n" + GRID, "record: 1 is not a table"),
    ],
)
def test_a_section_that_is_not_a_table_is_refused(text, key):
    refused(text, key)


@pytest.mark.parametrize(
    ("name", "refuse", "accept"),
    [("wob", [1.01e15, 1e300], [1e15]), ("torque", [-1.01e15, 1e300], [-1e15, 1e15])],
)
def test_loads_are_refused_exactly_where_simulate_refuses_them(name, refuse, accept):
    """A W_ob or torque axis (or [model] value) beyond simulate's MAX_LOAD swept every point
    into a failure (a wob axis of [1e300] 'ran'); now refused before anything runs, where
    simulate refuses, and a value simulate takes is kept."""
    other = {"wob": "torque = [6.0]", "torque": "wob = [50.0]"}[name]
    fixed = {"wob": "torque = 6.0", "torque": "wob = 50.0"}[name]
    for value in refuse:
        with pytest.raises(ValueError, match=f"{name} = "):
            pydrill.simulate(dof=2, t_end=1.0, n_out=2, **{"wob": 50.0, "torque": 6.0, name: value})
        msg = refused(f"[axes]\n{name} = [{value!r}]\n{other}\n", f"axes.{name}")
        assert "is not allowed: at most 1e15" in msg
        msg = refused(
            f"[model]\n{name} = {value!r}\n[axes]\n{fixed.replace(' = ', ' = [')}]\n",
            f"model.{name}",
        )
        assert "is not allowed: at most 1e15" in msg
    for value in accept:
        pydrill.simulate(dof=2, t_end=1.0, n_out=2, **{"wob": 50.0, "torque": 6.0, name: value})
        spec = parse_spec(f"[axes]\n{name} = [{value!r}]\n{other}\n")
        assert spec.axes[name].tolist() == [value]


def test_t_end_is_refused_exactly_where_simulate_refuses_it():
    """t_end = 1e11 swept every point into simulate's refusal; now refused by the spec."""
    from pydrill.simulate import MAX_T_END

    for value in (MAX_T_END * 1.01, 1e300):
        with pytest.raises(ValueError, match="t_end = "):
            pydrill.simulate(wob=100, torque=8.3, dof=2, t_end=value, n_out=2)
        msg = refused(GRID + f"[simulation]\nt_end = {value!r}\n", "simulation.t_end")
        assert "is not allowed: 0 < t_end <= 1e10 s" in msg
    spec = parse_spec(GRID + f"[simulation]\nt_end = {MAX_T_END!r}\n")
    assert spec.simulation["t_end"] == MAX_T_END  # simulate takes it (not run: 317 years)


@pytest.mark.parametrize("value", ['"0.5"', "true", "[0.5]"])
def test_window_must_be_a_number(value):
    msg = refused(GRID + f"[simulation]\nwindow = {value}\n", "simulation.window")
    assert "0 < window <= 1" in msg


@pytest.mark.parametrize(
    ("key", "refuse", "accept"),
    [
        ("rtol", [2.0, 1.0, 0.0101, 9.9e-15, 1e-20], [1e-14, 0.01]),
        ("atol", [9.9e-21, 1e-30, 0.00101, 1.0], [1e-20, 1e-3]),
    ],
)
def test_tolerances_are_refused_exactly_where_simulate_refuses_them(key, refuse, accept):
    """A spec simulate would refuse at every point (so that every point of a sweep fails) is
    refused before anything runs; a value simulate takes is kept. Both sides are asked."""
    for value in refuse:
        with pytest.raises(ValueError, match=f"{key} = "):
            pydrill.simulate(wob=100, torque=8.3, dof=2, t_end=1.0, n_out=2, **{key: value})
        msg = refused(GRID + f"[simulation]\n{key} = {value!r}\n", f"simulation.{key}")
        assert "is not allowed" in msg
    for value in accept:
        pydrill.simulate(wob=100, torque=8.3, dof=2, t_end=1.0, n_out=2, **{key: value})
        spec = parse_spec(GRID + f"[simulation]\n{key} = {value!r}\n")
        assert spec.simulation[key] == value


@pytest.mark.parametrize(
    ("line", "key"),
    [
        ("tally = 5", "model.tally: 5 is not allowed: a path"),
        ("mu_static = [0.5]", "model.mu_static: [0.5] is not a finite number"),
        ('bit_radius = "wide"', "model.bit_radius: 'wide' is not a length"),
        ('bit_radius = "0.1 rpm"', "model.bit_radius: '0.1 rpm': unit 'rpm' is not a length"),
        ('mu_static = "0.8"', "model.mu_static: '0.8' is not a finite number"),
        ("bit_radius = true", "model.bit_radius: True is not a finite number"),
        ("bit_radius = " + "9" * 400, "model.bit_radius"),  # an integer beyond any float
        ("inertias = [0.5, true, 0.03, 0.03]", "model.inertias: True is not a finite number"),
        ('inertias = "heavy"', "model.inertias: 'heavy' is not allowed: a list of numbers"),
    ],
)
def test_a_model_parameter_of_the_wrong_type_is_refused(line, key):
    refused(f"[model]\n{line}\n" + GRID, key)


def test_model_parameters_of_the_right_type_still_pass():
    spec = parse_spec("[model]\nbit_radius = 0.12\ninertias = [0.5, 0.02, 0.03, 0.03]\n" + GRID)
    assert spec.params_at(spec.coords(0)).bit_radius == 0.12


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("[axes]\ndof = [4, 1e12]\nwob = [50.0]\ntorque = [6.0]\n", "axes.dof"),
        ("[axes]\npipes = [1, 99998]\nwob = [50.0]\ntorque = [6.0]\n", "axes.pipes"),
        ("[model]\ndof = 400000000\n" + GRID, "model.dof"),
        ("[model]\ndof = 100001\n" + GRID, "model.dof: 100001 is not allowed: an integer 2"),
        ("[model]\npipes = 99998\n" + GRID, "model.pipes"),
    ],
)
def test_a_string_beyond_the_largest_size_is_refused(text, key):
    assert "100000" in refused(text, key)


def test_the_largest_string_passes():
    assert parse_spec("[model]\ndof = 100000\n" + GRID).dof == 100000


def test_a_tally_string_beyond_the_largest_size_is_refused():
    # 2000 km of 9 m joints: some 222000 inertias, unless lumped.
    deep = DEPTHS.replace("3000.0]", "2.0e6]") + "wob = [5e4]\n"
    assert "100000" in refused(deep, "axes.depth", tally_text=TALLY)
    assert parse_spec(deep.replace("dof = 6", "dof = 6\nlump = 5"), tally_text=TALLY).size == 2


def test_a_grid_of_too_many_points_is_refused():
    text = (
        "[axes]\nwob = { start = 1.0, stop = 2.0, num = 1000000 }\n"
        "torque = { start = 1.0, stop = 2.0, num = 1000000 }\n"
    )
    msg = refused(text, "axes: 1000000 x 1000000 = 1000000000000 points")
    assert "100000000" in msg


@pytest.mark.parametrize("value", ["1e400", "9" * 400])
def test_a_number_beyond_any_float_is_refused(value):
    refused(f"[axes]\nwob = [{value}]\ntorque = [6.0]\n", "axes.wob")


# B. Accepted before, failing at run time or silently ignored: refused now.


@pytest.mark.parametrize("value", ["-5", "0", '"lots"', "1.5", "true", "4611686018427387904"])
def test_max_steps_must_be_a_positive_integer(value):
    msg = refused(GRID + f"[simulation]\nmax_steps = {value}\n", "simulation.max_steps")
    assert "an integer >= 1" in msg


def test_max_steps_is_kept():
    assert parse_spec(GRID + "[simulation]\nmax_steps = 1000\n").simulation["max_steps"] == 1000


def test_a_range_of_equal_ends_must_have_one_point():
    refused("[axes]\nwob = { start = 50.0, stop = 50.0, num = 3 }\ntorque = [6.0]\n", "axes.wob")
    one = parse_spec("[axes]\nwob = { start = 50.0, stop = 50.0, num = 1 }\ntorque = [6.0]\n")
    assert one.axes["wob"].tolist() == [50.0]


def test_a_range_of_one_point_must_not_drop_its_stop():
    msg = refused(
        "[axes]\nwob = { start = 40.0, stop = 80.0, num = 1 }\ntorque = [6.0]\n", "axes.wob"
    )
    assert "use a list" in msg


def test_a_range_finer_than_its_numbers_is_refused():
    text = (
        "[axes]\nwob = { start = 1e16, stop = 1.0000000000000004e16, num = 100 }\ntorque = [6.0]\n"
    )
    assert "repeated values" in refused(text, "axes.wob")


def test_a_malformed_tally_is_refused(tmp_path):
    tally = tmp_path / "t.toml"
    tally.write_text("steel = 5\n")  # a table of the wrong type
    spec = DEPTHS + "wob = [5e4]\n"
    refused(spec.replace('"t.toml"', f'"{tally}"'), "model.tally: malformed tally")
    refused(spec.replace('"t.toml"', '"t\\u0000.toml"'), "model.tally: cannot read")  # a NUL


def test_lump_needs_a_tally():
    refused("[model]\nlump = 3\n" + GRID, "model.lump: lump needs tally")


def test_a_parameter_both_in_model_and_axes_is_refused():
    text = "[model]\nbit_radius = 0.12\n[axes]\nwob = [50.0]\ntorque = [6.0]\nbit_radius = [0.1]\n"
    msg = refused(text, "model.bit_radius")
    assert "give it in one place only" in msg


def test_every_pair_of_friction_coefficients_on_the_grid_is_valid():
    axes = "[axes]\nwob = [50.0]\ntorque = [6.0]\nmu_coulomb = [0.3, 0.7]\n"
    # The corners (0.3, 0.6) and (0.7, 0.9) are valid; the point (0.7, 0.6) is not.
    msg = refused(axes + "mu_static = [0.6, 0.9]\n", "axes.mu_static")
    assert "mu_coulomb" in msg and "0.7" in msg and "0.6" in msg
    assert parse_spec(axes + "mu_static = [0.75, 0.9]\n").size == 4
    # One of the two in [model]: the largest mu_coulomb against it.
    refused("[model]\nmu_static = 0.6\n" + axes, "mu_static")


# C. Axes in increasing order.


def test_axes_are_stored_in_increasing_order():
    spec = parse_spec("[axes]\nwob = [160.0, 40.0, 120.0, 80.0]\ntorque = [8.0, 6.0]\n")
    assert spec.axes["wob"].tolist() == [40.0, 80.0, 120.0, 160.0]
    assert spec.axes["torque"].tolist() == [6.0, 8.0]
    assert spec.coords(0) == {"wob": 40.0, "torque": 6.0}
    assert spec.coords(7) == {"wob": 160.0, "torque": 8.0}
    sizes = parse_spec("[axes]\ndof = [8, 2, 4]\nwob = [50.0]\ntorque = [6.0]\n")
    assert sizes.axes["dof"].tolist() == [2, 4, 8] and sizes.coords(0)["dof"] == 2


def test_a_reversed_range_is_the_same_grid_as_the_forward_one():
    forward = parse_spec("[axes]\nwob = { start = 20.0, stop = 200.0, num = 19 }\ntorque = [6.0]\n")
    back = parse_spec("[axes]\nwob = { start = 200.0, stop = 20.0, num = 19 }\ntorque = [6.0]\n")
    assert np.all(np.diff(back.axes["wob"]) > 0)
    assert back.axes["wob"].tolist() == forward.axes["wob"].tolist()
    assert back.digest == forward.digest


# D. The digest: the tally and lump of a tally string; nothing new for any other spec.


def test_digests_of_specs_without_a_tally_are_unchanged():
    # Computed before the tally entered the digest: existing atlases stay resumable.
    assert load_spec(ROOT / "sweeps" / "paper-wob-torque.toml").digest == "81ca80b1a6f6e4c1"
    assert load_spec(ROOT / "sweeps" / "minimal.toml").digest == "44c4413bd4277a8a"
    text = (
        '[model]\npreset = "reduced-scale"\ndof = 5\nbit_radius = 0.12\ntorque = 8.0\n'
        "[axes]\nwob = { start = 40.0, stop = 160.0, num = 4 }\nmu_static = [0.8, 0.9]\n"
        "[simulation]\nt_end = 100.0\nmax_steps = 100000\n[record]\neigenvalues = 2\n"
    )
    assert parse_spec(text).digest == "807684b1fab66d1f"
    assert parse_spec("[axes]\ndof = [2, 4, 8]\n" + GRID[7:]).digest == "a8ddc8803623e4dd"


def test_the_digest_of_a_tally_string_follows_lump_and_the_tally():
    spec = DEPTHS + "wob = [5e4]\n"
    base = parse_spec(spec, tally_text=TALLY).digest
    assert parse_spec(spec, tally_text=TALLY).digest == base
    assert parse_spec(spec.replace("dof = 6", "dof = 6\nlump = 2"), tally_text=TALLY).digest != base
    other = TALLY.replace("beta = 0.2 ", "beta = 0.3 ")
    assert other != TALLY
    assert parse_spec(spec, tally_text=other).digest != base


def test_the_depth_sweep_shipped_still_parses():
    spec = load_spec(ROOT / "sweeps" / "paper-string-depth.toml")
    assert spec.shape == (6, 6) and spec.lump == 1
    # Its strings are reduced (dof = 12): since reductions share their inertias between the
    # groups' ends, its digest says so, and an atlas of the older rule is not resumed into.
    assert spec.dof == 12 and spec.digest == "0db8e9c0d5e0f871"


def test_a_spec_file_that_is_not_text_is_refused(tmp_path):
    spec_file = tmp_path / "bad.toml"
    spec_file.write_bytes(b"\xff\xfe[axes]\n")
    with pytest.raises(SpecError, match=r"bad\.toml"):
        load_spec(spec_file)


def test_values_may_carry_units_and_make_the_same_sweep_as_si():
    """As everywhere a person types them (DESIGN §4): weights, torques, depths and the
    parameters that have a unit. The grid, the fixed values and the identity (digest) are
    those of the same sweep written in SI."""
    si = parse_spec(
        "[model]\ntorque = 6779.0897\nbit_radius = 0.1524\n"
        "[axes]\nwob = { start = 20000.0, stop = 120000.0, num = 6 }\n"
    )
    typed = parse_spec(
        '[model]\ntorque = "5 kft·lbf"\nbit_radius = "6 in"\n'
        '[axes]\nwob = { start = "20 kN", stop = "120 kN", num = 6 }\n'
    )
    assert typed.axes["wob"].tolist() == si.axes["wob"].tolist()
    # 1 ft·lbf = 0.3048 m x 4.4482216152605 N (international foot and pound-force)
    assert typed.fixed["torque"] == pytest.approx(5000 * 0.3048 * 4.4482216152605, rel=1e-12)
    assert typed.fixed["torque"] == pytest.approx(si.fixed["torque"], rel=1e-8)
    assert typed.overrides["bit_radius"] == pytest.approx(0.1524, rel=1e-12)
    lbf = parse_spec('[axes]\nwob = ["1 lbf", 50.0]\ntorque = [6.0]\n')
    assert lbf.axes["wob"].tolist() == pytest.approx([4.4482216152605, 50.0])
    exact = parse_spec('[model]\ntorque = "8 kN·m"\n[axes]\nwob = ["20 kN", "30 kN"]\n')
    assert exact.digest == parse_spec("[model]\ntorque = 8000.0\n[axes]\nwob = [2e4, 3e4]\n").digest


@pytest.mark.parametrize(
    ("line", "key"),
    [
        ('wob = ["20 kN·m"]\ntorque = [6.0]', "axes.wob: '20 kN·m': unit 'kN·m' is not a force"),
        ('wob = { start = "1 kN", stop = "2 rpm", num = 3 }\ntorque = [6.0]', "axes.wob.stop"),
        ('wob = [50.0]\ntorque = "6 N"', "axes.torque: '6 N': unit 'N' is not a torque"),
        ('wob = ["-5 kN"]\ntorque = [6.0]', "axes.wob: weights on bit must be > 0"),
    ],
)
def test_a_unit_that_does_not_measure_the_key_is_refused(line, key):
    refused(f"[axes]\n{line}\n", key)


def test_a_missing_relative_tally_names_the_path_it_was_looked_for_at(tmp_path, monkeypatch):
    """The error showed the path as written, not where it was looked for nor the rule."""
    folder = tmp_path / "specs"
    folder.mkdir()
    spec = folder / "depth.toml"
    spec.write_text(DEPTHS.replace('"t.toml"', '"tallies/t.toml"'))
    monkeypatch.chdir(tmp_path)  # run from elsewhere: the path is the spec's folder's
    with pytest.raises(SpecError) as err:
        load_spec("specs/depth.toml")
    message = str(err.value)
    assert message.startswith("model.tally: cannot read tallies/t.toml: ")
    assert str(folder / "tallies" / "t.toml") in message
    assert f"resolved against the spec file's folder, {folder}" in message


def test_the_string_of_each_point_is_built_once_and_is_the_one_built_afresh():
    """params_at keeps the strings it built: one for a whole (W_ob, u) grid, one per value of
    any other axis; each equal to the string built afresh from the preset."""
    spec = parse_spec(
        """
[model]
preset = "reduced-scale"
[axes]
wob = [50.0, 100.0]
torque = [6.0, 8.3]
dof = [3, 4, 6]
top_damping = [0.1, 0.2]
"""
    )
    seen = {}
    for i in range(spec.size):
        c = spec.coords(i)
        p = spec.params_at(c)
        assert p == pydrill.preset("reduced-scale", dof=c["dof"], top_damping=c["top_damping"])
        seen.setdefault((c["dof"], c["top_damping"]), set()).add(id(p))
    assert len(seen) == 6 and all(len(ids) == 1 for ids in seen.values())  # once per string
    many = parse_spec(
        '[model]\npreset = "reduced-scale"\ndof = 4\n[axes]\nwob = [60.0]\ntorque = [8.3]\n'
        "top_damping = { start = 0.1, stop = 0.5, num = 200 }"
    )
    for i in range(many.size):  # 200 strings: the spec keeps a few, not all
        assert many.params_at(many.coords(i)).top_damping == many.axes["top_damping"][i]
    assert 0 < len(many.__dict__["_params"]) <= 16


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[modle]\n" + GRID, "modle: unknown section (did you mean 'model'?); allowed: [model]"),
        ("[model]\nprset = 'reduced-scale'\n" + GRID, "model.prset: unknown parameter (did you "
         "mean 'preset'?); allowed: preset, dof"),
        (GRID + "torqe = [1.0]\n", "axes.torqe: cannot be swept (did you mean 'torque'?); "
         "allowed: wob, torque"),
        (GRID + "[simulation]\nt_ned = 10.0\n", "simulation.t_ned: unknown (did you mean "
         "'t_end'?); allowed: t_end"),
        (GRID + "[record]\neigenvalue = 4\n", "record.eigenvalue: unknown (did you mean "
         "'eigenvalues'?); allowed: stability, eigenvalues"),
        # nothing near: no guess
        (GRID + "[simulation]\nspeed = 10.0\n", "simulation.speed: unknown; allowed: t_end"),
    ],
)  # fmt: skip
def test_a_misspelt_key_is_refused_with_the_key_it_was_probably_meant_to_be(text, message):
    assert message in refused(text, message)
