"""Bad and implausible numbers on the single-run commands' command line. Impossible input (a
load beyond any float's use, a run longer than any clock resolves, a speed that is no number)
is refused before any work in one line naming the option and its range (exit status 2,
nothing on stdout, no figure); implausible input (a depth beyond the longest well, a speed no
top drive turns, a weight no bit takes) earns a one-line ``pydrill: note:`` on stderr and the
command goes on."""

import json
import math
from pathlib import Path

import pytest

from pydrill import cli

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "examples" / "tallies" / "paper-eq53.toml"
AT_3000 = ["--tally", PAPER, "--depth", "3000m"]


def call(capsys, *args):
    """(exit status, stdout, stderr lines) of one command line, run in this process."""
    try:
        code = cli.main([str(a) for a in args])
    except SystemExit as exc:  # argparse's refusal of a value
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err.splitlines()


def refused(capsys, *args):
    """The one line of a refusal: exit status 2, nothing on stdout, no traceback."""
    code, out, err = call(capsys, *args)
    assert code == 2 and not out, (code, out, err)
    assert len(err) == 1 and "Traceback" not in err[0], err
    return err[0]


def noted(capsys, *args):
    """The notes of a command that went on: exit status 0, every stderr line a note."""
    code, out, err = call(capsys, *args)
    assert code == 0 and out, (code, err)
    assert all(line.startswith("pydrill: note: ") for line in err), err
    return [line.removeprefix("pydrill: note: ") for line in err]


# --- impossible: refused in one line ----------------------------------------------------------


@pytest.mark.parametrize(
    "args, option",
    [
        # said a note on the laboratory string, then simulate's own error: two lines
        (["simulate", "--wob", "1e300", "--torque", "8.3"], "--wob"),
        # answered: "Omega = 5.26316e+300 rad/s"
        (["stability", "--dof", "4", "--wob", "40", "--torque", "1e300"], "--torque"),
        (["stability", "--dof", "4", "--wob", "1e300", "--torque", "8.3"], "--wob"),
        (["bifurcation", "--dof", "2", "--vary", "wob", "--torque", "1e300"], "--torque"),
        (["bifurcation", "--dof", "2", "--vary", "torque", "--wob", "1e300kN"], "--wob"),
        # drew a map "W_ob 0..1e+297 kN"
        (["map", "--dof", "4", "--wob-max", "1e300"], "--wob-max"),
        (["map", "--dof", "4", "--torque-max", "2e15"], "--torque-max"),
        (["window", PAPER, "--depth", "3000m", "--wob-max", "1e300N"], "--wob-max"),
        (["window", PAPER, "--depth", "3000m", "--at-wob", "60,1e300N"], "--at-wob"),
    ],
)
def test_a_load_beyond_max_load_is_refused_in_one_line(capsys, args, option):
    line = refused(capsys, *args)
    assert option in line and "at most 1e15" in line, line


def test_a_load_at_max_load_is_taken(capsys):
    code, out, _ = call(capsys, "stability", "--dof", "4", "--wob", "40", "--torque", "1e15")
    assert code == 0 and "steady state" in out


@pytest.mark.parametrize(
    "args",
    [
        # ran for minutes into the step limit (DOP853), or failed at t = 0 (CVODES: h = 1e109)
        ["simulate", "--wob", "100", "--torque", "8.3", "--t-end", "1e300"],
        ["simulate", "--wob", "100", "--torque", "8.3", "--t-end", "2e10"],
        ["map", "--dof", "4", "--check", "1", "--t-end", "1e11"],
        ["window", PAPER, "--depth", "3000m", "--check", "1", "--t-end", "1e300"],
    ],
)
def test_a_run_longer_than_max_t_end_is_refused_before_any_work(capsys, args):
    line = refused(capsys, *args)
    assert "--t-end" in line and "<= 1e10 s" in line, line


def test_a_refused_string_is_one_line_without_the_note_on_its_load(capsys):
    # --wob 100kN on the laboratory string earns a note, but the string is refused first:
    # it said the note and then the error
    line = refused(capsys, "simulate", "--dof", "1", "--wob", "100kN", "--torque", "8.3")
    assert "dof = 1 is not allowed" in line
    line = refused(capsys, "string", PAPER, "--depth", "30000m", "--dof", "1")
    assert "--dof = 1" in line


@pytest.mark.parametrize("speed", ["inf", "nan", "-5", "0"])
def test_a_bad_speed_of_at_rpm_names_at_rpm(capsys, speed):
    # "--at-rpm inf" said "--depth: rpm[0] = inf is not allowed"
    line = refused(capsys, "window", PAPER, "--depth", "3000m", "--at-rpm", f"60,{speed}")
    assert "--at-rpm" in line and "--depth" not in line and "> 0 (rpm)" in line, line


def test_the_chart_s_speed_takes_a_unit_as_its_help_says(capsys):
    # --rpm-max 200rpm was refused as "not a number"
    def rpm_max(text):
        code, out, _ = call(
            capsys, "window", PAPER, "--depth", "3000m", "--rpm-max", text, "--json"
        )
        assert code == 0
        return json.loads(out)["rpm"][-1]

    assert rpm_max("200rpm") == rpm_max("200") == 200.0
    assert rpm_max("20rad/s") == pytest.approx(20 * 30 / math.pi)
    line = refused(capsys, "window", PAPER, "--depth", "3000m", "--rpm-max", "20kN")
    assert line.count("--rpm-max") == 2 and "not a velocity unit" in line, line


def test_hopf_omega_max_without_a_plot_is_refused_as_ignored(capsys, tmp_path):
    line = refused(capsys, "hopf", "--dof", "4", "--omega-max", "30")
    assert "--omega-max needs --plot" in line
    png = tmp_path / "h.png"
    code, _, _ = call(capsys, "hopf", "--dof", "4", "--omega-max", "30", "--plot", png)
    assert code == 0 and png.exists()


def test_nothing_is_written_when_input_is_refused(capsys, tmp_path):
    png = tmp_path / "run.png"
    refused(capsys, "simulate", "--wob", "100", "--torque", "1e300", "--plot", png)
    refused(capsys, "window", PAPER, "--depth", "3000m", "--at-rpm", "inf", "--plot", png)
    assert not png.exists() and not list(tmp_path.iterdir())


# --- implausible: a note, and the command goes on ---------------------------------------------


def test_a_depth_beyond_the_longest_well_earns_a_note(capsys):
    # --depth 30000m built a 3334-inertia string and said nothing
    (note,) = noted(capsys, "string", PAPER, "--depth", "30000m")
    assert note.startswith("--depth 30 km is longer than any well ever drilled"), note
    assert "ft" not in note  # typed with its unit: no advice on the unit
    (note,) = noted(capsys, "string", PAPER, "--depth", "16000")
    assert "a bare number is m: for feet write 16000ft" in note, note
    assert noted(capsys, "string", PAPER, "--depth", "12km") == []  # drilled: no note


def test_a_window_beyond_the_longest_well_earns_a_note(capsys):
    (note,) = noted(capsys, "window", PAPER, "--depth", "500m,15.5km", "--at-rpm", "60")
    assert note.startswith("--depth 15.5 km is longer than any well"), note


@pytest.mark.parametrize(
    "options, words",
    [
        # accepted quietly: a chart to 5000 rpm
        (["--rpm-max", "5000"], "--rpm-max 5000 rpm is faster than any top drive turns"),
        (["--at-rpm", "60,400"], "--at-rpm 400 rpm is faster than any top drive turns"),
        (["--wob-max", "3000kN"], "--wob-max 3000 kN is heavier than any drill bit takes"),
        (["--at-wob", "60,2500kN"], "--at-wob 2500 kN is heavier than any drill bit takes"),
    ],
)
def test_a_window_beyond_any_rig_earns_a_note(capsys, options, words):
    (note,) = noted(capsys, "window", PAPER, "--depth", "3000m", *options)
    assert note.startswith(words), note


def test_a_window_within_any_rig_earns_none(capsys):
    args = ["--rpm-max", "300", "--at-rpm", "300", "--wob-max", "2000", "--at-wob", "2000kN"]
    assert noted(capsys, "window", PAPER, "--depth", "3000m", *args) == []


def test_a_speed_faster_than_a_double_s_exponential_warns_nothing_but_the_note(capsys):
    # --at-rpm 1e300 printed numpy's "RuntimeWarning: overflow encountered in exp"
    (note,) = noted(capsys, "window", PAPER, "--depth", "3000m", "--at-rpm", "60,1e300")
    assert "faster than any top drive" in note


def test_a_speed_typed_in_rpm_is_not_told_to_write_rpm(capsys):
    # --omega 6000rpm said "a bare number is rad/s; for rpm write 628.319rpm"
    (note,) = noted(capsys, "stability", *AT_3000, "--wob", "60kN", "--omega", "6000rpm")
    assert note == "--omega is 6000 rpm, faster than any top drive turns (some 300 rpm at most)"
    (note,) = noted(capsys, "stability", *AT_3000, "--wob", "60kN", "--omega", "60")
    assert note.endswith("a bare number is rad/s; for rpm write 60rpm"), note
    assert noted(capsys, "stability", *AT_3000, "--wob", "60kN", "--omega", "250rpm") == []


@pytest.mark.parametrize(
    "point, words",
    [
        # each was taken quietly on a real string
        (["--wob", "60000kN", "--omega", "60rpm"], "--wob is 60000 kN, heavier than any drill bit"),
        (["--wob", "60kN", "--torque", "9000kN*m"], "--torque is 9000 kN m, more than any top"),
        (["--wob", "60kN", "--torque", "9"], "--torque is 9 N m, light for a real string"),
    ],
)
def test_a_real_string_s_load_beyond_any_rig_earns_a_note(capsys, point, words):
    (note,) = noted(capsys, "stability", *AT_3000, *point)
    assert note.startswith(words), note


def test_a_real_string_s_typed_torque_earns_no_unit_advice(capsys):
    assert noted(capsys, "stability", *AT_3000, "--wob", "60kN", "--torque", "9N*m") == []


@pytest.mark.parametrize(
    "args, words",
    [
        (
            ["stability", "--dof", "4", "--wob", "40", "--torque", "8kN*m"],
            "--torque is 8 kN m, on the reduced-scale laboratory string",
        ),
        (["map", "--dof", "4", "--wob-max", "100kN"], "--wob-max is 100 kN, on the reduced-scale"),
        (["map", *AT_3000, "--wob-max", "250"], "--wob-max is 250 N, light for a real string"),
    ],
)
def test_a_load_for_the_other_kind_of_string_earns_a_note(capsys, args, words):
    assert words in noted(capsys, *args)[0]


def test_a_run_longer_than_a_day_earns_a_note(capsys):
    code, _, err = call(
        capsys, "simulate", "--wob", "100", "--torque", "8.3", "--t-end", "1e6", "--max-steps", "50"
    )
    assert code == 3, err  # the step limit, as the note warns
    assert err[0].startswith("pydrill: note: --t-end is 1e+06 s (11.6 days) of drilling"), err
    code, _, err = call(capsys, "simulate", "--wob", "160", "--torque", "8.3", "--t-end", "86400")
    assert code == 0 and err == []


# --- the help states each option's unit and range ---------------------------------------------


@pytest.mark.parametrize(
    "command, words",
    [
        (
            ["simulate"],
            [
                "2 ... 100000",
                "1 ... 99997",
                "joints per element, >= 1",
                "a bare number is m",
                "N, > 0",
                "either sign",
                "at most 1e10",
                "1e-14 ... 0.01",
                "1e-20 ... 0.001",
                "each > 0",
                "each >= 0",
            ],
        ),
        (["stability"], ["N, > 0", "rad/s, > 0", "either sign"]),
        (["bifurcation"], ["N m, > 0", "N, > 0", "rad/s, > 0"]),
        (["hopf"], ["rad/s, > 0"]),
        (["map"], ["N, > 0", "N m, > 0", "at most 1e10"]),
        (["string", "x"], ["2 ... one per element", ">= 1", "a bare number is m"]),
        (
            ["window", "x"],
            ["2 ... 500 depths", ">= 1", "kN, > 0", "rpm, > 0", "each > 0", "at most 1e10"],
        ),
    ],
)
def test_help_states_units_and_ranges(capsys, command, words):
    code, out, _ = call(capsys, *command[:1], "--help")
    assert code == 0
    text = " ".join(out.split())
    for word in words:
        assert word in text, (command, word)


def test_a_window_s_json_stays_strict_at_a_speed_no_weight_destabilises(capsys, tmp_path):
    # failed after the work (and after saving the figure) with "Out of range float values are
    # not JSON compliant: inf": the stick-slip edge at 10000 rpm is beyond every number
    png = tmp_path / "w.png"
    args = ["window", PAPER, "--depth", "3000m", "--at-rpm", "60,10000", "--plot", png, "--json"]
    code, out, err = call(capsys, *args)
    assert code == 0 and len(err) == 1 and "faster than any top drive" in err[0], err
    data = json.loads(out)  # strict: no Infinity
    window = data["windows"][0]
    assert window["wob_max_stable"][0] > 0 and window["wob_max_stable"][1] is None
    assert window["wob_max"][1] == data["wob_max_unstuck"][1] > 0  # the stall edge binds
    assert data["plot"] == str(png) and png.exists()


@pytest.mark.parametrize("text", ["1,,2", ",", "0.5,0.03,0.03,"])
def test_a_list_with_an_empty_entry_is_refused_naming_it(capsys, text):
    # "1,,2" dropped the gap and ran a string of two inertias; "," said "dof = 0 is not
    # allowed" of no option
    line = refused(capsys, "simulate", "--wob", "100", "--torque", "8.3", "--inertias", text)
    assert "--inertias must be comma-separated numbers" in line and "an entry is empty" in line


def test_an_output_larger_than_memory_is_refused_naming_n_out(capsys):
    args = ["--dof", "100000", "--n-out", "100000000", "--t-end", "1e-3"]
    line = refused(capsys, "simulate", "--wob", "100", "--torque", "8.3", *args)
    assert "--n-out = 100000000 is not allowed with dof = 100000" in line, line


def test_a_gigabyte_of_output_earns_a_note_before_the_run(capsys, monkeypatch):
    import pydrill

    def run(*args, **kwargs):  # the run itself is not what is tested (it takes 1.3 GB)
        raise MemoryError

    monkeypatch.setattr(pydrill, "simulate", run)
    args = ["--dof", "40000", "--n-out", "2000", "--t-end", "1e-3"]
    code, out, err = call(capsys, "simulate", "--wob", "100", "--torque", "8.3", *args)
    assert code == 2 and not out
    assert (
        err[0]
        == "pydrill: note: --n-out 2000 output times of 40000 inertias take 1.28 GB of memory"
    )
    # out of memory anyway: one line, no traceback (was "MemoryError: std::bad_alloc")
    assert err[1:] == [
        "pydrill simulate: error: out of memory: ask for a smaller string or fewer output times"
    ]
    code, _, err = call(capsys, "simulate", "--wob", "100", "--torque", "8.3", "--dof", "400")
    assert code == 2 and err == [err[-1]] and "out of memory" in err[-1]  # no note: 19 MB


def test_a_velocity_whose_torque_is_beyond_max_load_is_refused_naming_omega(capsys):
    line = refused(capsys, "stability", "--dof", "4", "--wob", "40", "--omega", "1e300")
    assert line.startswith("pydrill stability: error: --omega = 1e+300 is not allowed"), line


@pytest.mark.parametrize(
    "options, words",
    [
        (["--rpm-max", "1e-300"], "--rpm-max 1e-300 rpm: the chart ends below 1 rpm"),
        (["--wob-max", "1e-300"], "--wob-max 1e-300 kN: the chart ends below 1 kN"),
    ],
)
def test_a_chart_that_ends_before_any_drilling_earns_a_note_and_no_warning(
    capsys, tmp_path, options, words
):
    # --rpm-max 1e-300 --plot drew empty axes and printed matplotlib's "UserWarning:
    # constrained_layout not applied" (here, under the tests' filter, a traceback)
    png = tmp_path / "w.png"
    assert noted(capsys, "window", PAPER, "--depth", "3000m", *options, "--plot", png) == [words]
    assert png.exists()


def test_a_start_from_a_steady_state_that_does_not_exist_names_initial(capsys):
    # said "initial = 'equilibrium' is not possible", the API's name of --initial
    args = ["--wob", "160", "--torque", "8.3", "--initial", "equilibrium"]
    line = refused(capsys, "simulate", *args)
    assert line.startswith("pydrill simulate: error: --initial = 'equilibrium' is not possible")
    assert "start from 'rest' instead" in line


@pytest.mark.parametrize(
    "args, words",
    [
        (["simulate", "--dof", "1e9.5", "--wob", "100", "--torque", "8.3"], "2 ... 100000"),
        (["hopf", "--pipes", "4.5"], "1 ... 99997"),
        (["string", PAPER, "--lump", "2.5"], ">= 1"),
        (["window", PAPER, "--depth", "3000m", "--check", "1", "--check-dof", "four"], "2 ... "),
    ],
)
def test_a_size_that_is_no_integer_is_refused_with_its_range(capsys, args, words):
    # said "argument --dof: invalid int value: '1e9'", no range (1e9 is now taken as a whole
    # number, refused by the string's own range: tests/test_cli_newcomer.py)
    line = refused(capsys, *args)
    option = next(a for a in args if a in ("--dof", "--pipes", "--lump", "--check-dof"))
    assert f"{option} must be a whole number, {words}" in line, line


@pytest.mark.parametrize(
    ("option", "values", "need"), [("--inertias", "1,2", 112), ("--dampings", "1,2", 3)]
)
def test_an_override_of_another_length_than_the_tally_s_string_names_its_option(
    capsys, option, values, need
):
    """--inertias 1,2 on a 112-inertia tally string said 'stiffnesses has 111 entries: dof = 2
    needs 1', of no option given; now the option, its count and the count the string needs.
    The string's own size is counted apart, from the tally at the depth asked."""
    from pydrill.tally import load_tally

    string = load_tally(PAPER).at_depth(1000.0).to_params(dof=None if need == 112 else 4)
    size = ["--dof", "4"] if need == 3 else []
    run = ["simulate", "--tally", PAPER, "--depth", "1000m", *size, "--wob", "60kN"]
    run += ["--torque", "9kN*m"]
    line = refused(capsys, *run, option, values)
    assert line == (
        f"pydrill simulate: error: {option} has 2 values, but the tally's string has "
        f"{string.dof} inertias: give {need} (one per "
        f"{'inertia' if option == '--inertias' else 'link'}), or leave {option} out"
    )
    assert (string.dof if option == "--inertias" else string.dof - 1) == need
    good = ",".join(["0.5"] * need)
    code, out, _ = call(capsys, *run, option, good, "--t-end", "1")
    assert code == 0 and "regime" in out


@pytest.mark.parametrize("command", ["stability", "hopf", "bifurcation", "map"])
def test_an_analysis_of_minutes_says_so_before_it_starts(capsys, monkeypatch, command):
    """stability and hopf grow as the square of the inertias: --dof 100000 computed for an
    hour and a half without a word (bifurcation and map too: 54 s and 23 s at 8000). A run of
    a minute or more is noted first (its time from the constant measured, here made large
    enough for 4 inertias to take 100 s); the work then runs as asked."""
    from pydrill import cli_analysis

    extra = {
        "stability": ["--wob", "100", "--torque", "8.3"],
        "bifurcation": ["--vary", "wob", "--torque", "8.1"],
    }.get(command, [])
    code, out, err = call(capsys, command, "--dof", "4", *extra)
    assert code == 0 and out and err == []  # a laboratory string: no note
    monkeypatch.setitem(cli_analysis.SQUARE_SECONDS, command, 100.0 / 16)
    code, out, err = call(capsys, command, "--dof", "4", *extra)
    assert code == 0 and out
    assert err == [
        f"pydrill: note: {command} of 4 inertias takes roughly 1 min 40 s (the time grows as "
        "the square of the inertias); --dof N reduces the string"
    ]
