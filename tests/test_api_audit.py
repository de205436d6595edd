"""The API audit's findings, each checked against what it should be: the energy ledger of a run
with no work put in, the run's constants where the docs name them, a result that cannot be
changed through its parts, specs that compare, one-line reprs, one rule for integers, the
chattering guard as documented, and sweep messages in their caller's words."""

import argparse
import copy
import json
import pickle
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest
from sweeping import CMD, TINY

import pydrill
from pydrill import Params, SpecError, parse_spec, preset, run_sweep, simulate
from pydrill.atlas_lock import AtlasBusy
from pydrill.sweep import AtlasError
from pydrill.window import Limits

ROOT = Path(__file__).resolve().parents[1]
SPIN = [30.0, 0.0, 30.0, 0.0, 30.0, 0.0, 30.0]  # every inertia at 30 rad/s, no twist


# 1. The energy balance, relative to a scale that is 0 only when nothing happens


def ledger_mismatch(r):
    """The largest |work − dissipation − ΔE| since t[0], from the result's arrays."""
    work = r.work_input - r.work_input[0]
    lost = (r.viscous_loss - r.viscous_loss[0]) + (r.friction_loss - r.friction_loss[0])
    return float(np.max(np.abs(work - lost - (r.energy - r.energy[0]))))


def test_a_coast_down_with_no_work_is_judged_against_its_energy():
    """It divided by the work put in, 0 here: 1.5e293 for a ledger balanced to 6e-10."""
    r = simulate(wob=100, torque=0.0, t_end=100, n_out=50, initial=SPIN)
    assert np.all(r.work_input == 0.0)
    energy0 = 0.5 * sum(j * 30.0**2 for j in r.params.inertias)  # all kinetic, no twist
    assert r.energy[0] == pytest.approx(energy0, rel=1e-12)
    error = r.energy_balance_error()
    # the energy only falls (no work in): E(0) is the largest quantity of the ledger
    assert error == pytest.approx(ledger_mismatch(r) / energy0, rel=1e-9)
    assert 0.0 < error < 1e-8


def test_a_ledger_that_does_not_balance_is_still_caught():
    r = simulate(wob=100, torque=0.0, t_end=100, n_out=50, initial=SPIN)
    broken = copy.deepcopy(r)
    energy = broken.energy.copy()
    energy[-1] += 0.01 * energy[0]  # 1 % of the energy appears from nowhere at the end
    broken.__dict__["energy"] = energy
    assert broken.energy_balance_error() == pytest.approx(0.01, rel=0.01)


def test_a_driven_run_is_judged_as_before():
    r = simulate(wob=100, torque=8.3, t_end=100, n_out=201)
    work = float(np.max(np.abs(r.work_input - r.work_input[0])))
    assert work > r.energy.max()  # the work dominates the scale
    assert r.energy_balance_error() == pytest.approx(ledger_mismatch(r) / work, rel=1e-9)
    assert r.energy_balance_error() < 1e-6


def test_a_string_at_rest_with_no_torque_has_no_error_not_nan():
    r = simulate(wob=100, torque=0.0, t_end=10, n_out=11)
    for ledger in (r.work_input, r.viscous_loss, r.friction_loss, r.energy):
        assert np.all(ledger == 0.0)
    assert r.energy_balance_error() == 0.0


# 2. MODES and MAX_T_END, where the docs name them


def test_modes_and_the_longest_run_are_exported_from_the_package():
    module = sys.modules["pydrill.simulate"]  # (pydrill.simulate is the function)
    assert pydrill.MODES is module.MODES and pydrill.MAX_T_END is module.MAX_T_END
    assert {"MODES", "MAX_T_END"} <= set(pydrill.__all__) & set(module.__all__)
    assert pydrill.MODES == ("slip+", "slip-", "stick", "band")
    with pytest.raises(ValueError, match="t_end"):
        simulate(wob=100, torque=8.3, t_end=pydrill.MAX_T_END * 1.01)


def test_no_doc_names_the_module_the_function_shadows():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
    sources = [ROOT / "pydrill" / n for n in ("result.py", "simulate.py")]
    for path in pages + sources:
        text = path.read_text()
        for name in ("pydrill.simulate.MODES", "pydrill.simulate.MAX_T_END"):
            assert name not in text, path


def test_the_constants_import_from_the_module_under_mypy_strict(tmp_path):
    user = tmp_path / "user.py"
    user.write_text(
        "from pydrill.simulate import MAX_T_END, MODES\n"
        "longest: float = MAX_T_END\n"
        "modes: tuple[str, ...] = MODES\n"
    )
    # A cache of its own: in the checkout's, this run's --strict entries for pydrill replaced
    # those of tests/test_packaging.py's mypy run (40 s again for it, 0.7 s warm), and the two
    # ran at once under pytest-xdist on one SQLite cache, which two mypy runs cannot always
    # share ("database is locked": python/mypy#21136).
    cache = ROOT / ".mypy_cache" / "strict-user"
    mypy = [sys.executable, "-m", "mypy", "--strict", "--no-error-summary", str(user)]
    done = subprocess.run(
        [*mypy, "--cache-dir", str(cache)], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stdout + done.stderr


# 3. A result is not changed through its parts


def test_settings_are_read_only_and_inputs_stay_what_ran():
    r = simulate(wob=100, torque=8.3, t_end=20, t_out=[0.0, 10.0, 20.0])
    before = r.inputs()
    with pytest.raises(TypeError):
        r.settings["t_end"] = 1  # type: ignore[index]
    assert r.settings["t_out"] == (0.0, 10.0, 20.0)  # a tuple: no .append either
    assert r.inputs() == before and before["t_end"] == 20.0
    assert before["t_out"] == [0.0, 10.0, 20.0]  # JSON-ready lists, as before
    assert simulate(**before).inputs() == before
    again = pickle.loads(pickle.dumps(r))
    assert again.inputs() == before and dict(again.settings) == dict(r.settings)


def test_switches_are_a_tuple_the_cache_cannot_lose():
    r = simulate(wob=100, torque=8.3, t_end=100)
    assert isinstance(r.switches, tuple) and len(r.switches) == r.stats.switches > 0
    assert not hasattr(r.switches, "clear")
    assert r.switches[0].kind == "slip" and r.switches[-1] is r.switches[len(r.switches) - 1]
    assert pickle.loads(pickle.dumps(r)).switches == r.switches


# 4. Specs compare as the atlas compares them: by digest


def test_specs_are_equal_and_hash_alike_when_they_are_the_same_sweep():
    a, b = parse_spec(TINY), parse_spec(TINY)
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    reformatted = parse_spec(TINY.replace("torque = [6.0, 8.3]", "torque = [ 8.3, 6 ]"))
    assert reformatted.text != a.text and reformatted == a  # the same grid, sorted
    other = parse_spec(TINY.replace("t_end = 100.0", "t_end = 50.0"))
    assert other != a and a.differences(other)
    assert a != TINY and a != None  # noqa: E711


# 5. One-line reprs


def test_a_long_strings_params_repr_is_one_short_line():
    p = pydrill.load_tally(ROOT / "examples/tallies/paper-eq53.toml").at_depth(3000).to_params()
    text = repr(p)
    assert len(text) < 250 and "\n" not in text, text
    assert text.startswith(f"<Params 'paper-eq53' dof={p.dof}: inertias ")
    assert f"{sum(p.inertias):.4g} kg·m² in all" in text
    assert f"{min(p.stiffnesses):.4g} ... {max(p.stiffnesses):.4g} N·m/rad" in text
    assert p == p.replace()  # the dataclass's fields and == are untouched
    limits = repr(Limits.of(preset(dof=4)))
    assert len(limits) < 300 and "<Params 'reduced-scale' dof=4" in limits


def test_a_stability_points_repr_shows_four_eigenvalues_and_counts_the_rest():
    point = pydrill.stability.stability(preset(dof=300), 100, torque=8.3)[0]
    assert len(point.eigenvalues) == 599
    text = repr(point)
    assert len(text) < 400 and "\n" not in text, text
    assert text.endswith("… (595 more)>")
    assert f"{point.eigenvalues[3]:.4g}" in text and f"{point.eigenvalues[4]:.4g}" not in text
    assert text.startswith(f"<StabilityPoint omega={point.omega:.4g} rad/s wob=100 N")
    small = repr(pydrill.stability.stability(preset(dof=2), 100, torque=8.3)[0])
    assert "more)" not in small and small.count("j") == 3  # 2·2 − 1 eigenvalues, all shown


def test_a_tally_specs_repr_is_one_line_without_its_texts():
    spec = pydrill.load_spec(ROOT / "sweeps/paper-string-depth.toml")
    assert spec.tally_text is not None and len(spec.text) + len(spec.tally_text) > 1000
    text = repr(spec)
    assert len(text) < 200 and "\n" not in text, text
    shape = " x ".join(f"{k} {len(v)}" for k, v in spec.axes.items())
    assert text == (
        f"<SweepSpec tally 'paper-eq53' dof={spec.dof}: {spec.size} points ({shape}), from "
        f"rest and equilibrium, t_end {spec.simulation['t_end']:g} s, digest {spec.digest}>"
    )
    assert spec.size == int(np.prod([len(v) for v in spec.axes.values()]))
    small = repr(parse_spec(TINY))
    assert small.startswith("<SweepSpec 'reduced-scale' dof=") and "tally" not in small


# 6. One rule for integers, TypeError for a list that is none


QUICK = {"wob": 100.0, "torque": 8.3, "t_end": 2.0, "n_out": 5}
FIELDS = {k: v for k, v in preset().to_dict().items() if k != "dof"}  # Params(**FIELDS)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda v: simulate(**QUICK, dof=v), "dof"),
        (lambda v: simulate(**QUICK, pipes=v), "pipes"),
        (lambda v: preset(dof=v), "dof"),
        (lambda v: preset(pipes=v), "pipes"),
        (lambda v: simulate(**{**QUICK, "n_out": v}), "n_out"),
        (lambda v: simulate(**QUICK, method="bdf", max_order=v), "max_order"),
    ],
)
def test_every_integer_argument_refuses_floats_and_bools_and_takes_numpy_integers(call, name):
    for bad in (3.0, np.float64(3.0), True):
        with pytest.raises(TypeError, match=rf"^{name} must be an integer, got "):
            call(bad)
    call(np.int64(3))
    call(np.array(3, dtype=np.int32))


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: Params(**{**FIELDS, "inertias": 1.0}), "inertias"),
        (lambda: preset(inertias={1: 2}), "inertias"),
        (lambda: preset(stiffnesses=None), "stiffnesses"),
        (lambda: preset(dampings=np.array(0.5)), "dampings"),
        (lambda: preset(inertias={0.5, 0.03}), "inertias"),
        (lambda: preset().replace(dampings="0.1"), "dampings"),
    ],
)
def test_a_list_field_given_no_list_is_a_type_error(make, name):
    with pytest.raises(TypeError, match=rf"^{name} must be a list of numbers, got "):
        make()


def test_a_list_field_of_another_shape_is_still_a_value_error():
    with pytest.raises(ValueError, match="inertias must be a 1-D list"):
        preset(inertias=np.ones((2, 2)))


def test_the_entry_of_the_wrong_type_is_the_one_blamed():
    with pytest.raises(TypeError, match=r"^t_out must be .*: an entry is str '1'$"):
        simulate(**QUICK, t_out=[0, "1"])
    with pytest.raises(TypeError, match=r"an entry is str 'x'$"):
        simulate(**QUICK, dof=2, initial=(1.0, 0.5, "x"))


def test_n_out_with_t_out_is_documented_as_unused():
    # n_out's default (3001) cannot be told from one given: documented, not refused.
    assert "With ``t_out`` it is not used" in " ".join(pydrill.simulate.__doc__.split())
    r = simulate(**{**QUICK, "n_out": 7}, t_out=[0.0, 1.0, 2.0])
    assert r.t.tolist() == [0.0, 1.0, 2.0]


# 7. The chattering guard, as documented: bursts of 50 switches


def test_the_switch_rate_is_checked_over_50_switches_as_documented():
    doc = " ".join(pydrill.simulate.__doc__.split())
    assert "50 intervals back to the 50th switch before it" in doc
    assert "a run of 50 switches or fewer never is" in doc
    header = (ROOT / "cpp/include/pydrill/simulator.hpp").read_text()
    assert "50 switches or fewer never are" in " ".join(header.replace("//", "").split())
    # 33 switches at 1e-6 /s: far above the limit on average, yet never 50 of them
    quiet = simulate(wob=100, torque=8.3, t_end=300, max_switch_rate=1e-6)
    assert 0 < quiet.stats.switches <= 50
    with pytest.raises(pydrill.SolverError, match="chattering: 50 friction switches"):
        simulate(wob=100, torque=8.3, t_end=600, max_switch_rate=1e-6)


# 8. Sweep messages in their caller's words


def test_an_existing_atlas_is_refused_in_the_api_words_and_the_cli_words(tmp_path):
    out = tmp_path / "tiny.h5"
    run_sweep(parse_spec(TINY), out, serial=True)
    with pytest.raises(AtlasError) as err:
        run_sweep(parse_spec(TINY), out, serial=True)
    assert str(err.value) == (
        f"{out} already exists for this sweep; use resume=True to complete it or remove it to "
        "start over"
    )
    # the command line's words: a journal of this spec whose atlas is gone, without --resume
    spec_file = tmp_path / "tiny.toml"
    spec_file.write_text(TINY)
    journal = out.with_name(out.name + ".journal")
    journal.write_text(json.dumps({"spec_digest": parse_spec(TINY).digest}) + "\n")
    out.unlink()
    with pytest.raises(AtlasError, match="use resume=True to complete it from the journal"):
        run_sweep(parse_spec(TINY), out, serial=True)
    done = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(out), "--serial"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2, done.stderr
    assert "use --resume to complete it from the journal" in done.stderr
    assert "resume=True" not in done.stderr


def test_a_busy_atlas_is_said_in_the_callers_words():
    from pydrill.cli_sweep import cli_words

    api = str(AtlasBusy.of(Path("a.h5"), "process 1 on host h"))
    assert api.endswith("run again with resume=True") and "--resume" not in api
    assert cli_words(api).endswith("run again with --resume")


def test_a_file_that_is_no_hdf5_is_not_called_damaged(tmp_path):
    spec_file = tmp_path / "small.toml"
    spec_file.write_text(TINY)
    table = tmp_path / "small.csv"
    table.write_text("wob,torque,regime\n100,8.3,stick-slip\n")
    with pytest.raises(AtlasError, match=r"small\.csv is not an atlas \(not an HDF5 file\)"):
        run_sweep(parse_spec(TINY), table, serial=True)
    done = subprocess.run(
        [*CMD, "sweep", str(spec_file), "--out", str(table)], capture_output=True, text=True
    )
    assert done.returncode == 2
    assert done.stderr.strip().endswith(
        "small.csv is not an atlas (not an HDF5 file); choose another --out"
    )
    assert table.read_text().startswith("wob,torque")  # untouched
    # a truncated atlas keeps the HDF5 signature: damaged, as before
    cut = tmp_path / "cut.h5"
    run_sweep(parse_spec(TINY), cut, serial=True)
    cut.write_bytes(cut.read_bytes()[:3000])
    with pytest.raises(AtlasError, match=r"cut\.h5 is damaged .* no journal"):
        run_sweep(parse_spec(TINY), cut, serial=True)


@pytest.mark.parametrize(
    ("parts", "said"),
    [(2, "once the other part is swept"), (3, "once the other 2 parts are swept")],
)
def test_the_next_step_of_a_part_is_grammatical(parts, said, capsys):
    from pydrill.cli_sweep_report import next_steps

    args = argparse.Namespace(json=False, part=f"1/{parts}", plot="map.png")
    report = types.SimpleNamespace(all_failed=False, atlas="p1.h5")
    spec = types.SimpleNamespace(record={"stability": False}, axes={})
    next_steps(args, report, spec)
    err = capsys.readouterr().err
    assert f"# {said}\n" in err and "part are" not in err


# 9. A unit where the spec takes a bare number


@pytest.mark.parametrize(
    ("line", "said"),
    [
        ('t_end = "200 s"', "'200 s' is not allowed: must be a number of seconds (no unit), "),
        ('rtol = "1e-8"', "'1e-8' is not allowed: a number (no unit), 1e-14 <= rtol"),
        ('window = "half"', "'half' is not allowed: a number (no unit), 0 < window <= 1"),
    ],
)
def test_a_string_for_a_simulation_number_says_it_takes_no_unit(line, said):
    with pytest.raises(SpecError) as err:
        parse_spec(TINY.replace("t_end = 100.0\n", "") + line + "\n")  # in [simulation]
    assert said in str(err.value)


def test_a_number_out_of_range_says_only_the_range():
    with pytest.raises(SpecError) as err:
        parse_spec(TINY.replace("t_end = 100.0", "t_end = 0"))
    assert "0 is not allowed: 0 < t_end <= 1e10 s" in str(err.value)
    assert "no unit" not in str(err.value)
