"""What the command line says of a name or a value it cannot take as typed: its "did you
mean" must name something that works, and a note must not contradict what was typed.

--set top_inertia=1 was answered "(did you mean 'inertias'?)", a name --set refuses (a list);
window's --set karnopp_bnd=1 suggested karnopp_band, which window refuses; and --set
"bit_radius=8.5 m" was noted "a bare number is m" of a value written with its unit. Each
suggestion is checked here by doing what it says: the name or option it gives is taken.
"""

import json
import re
from pathlib import Path

import pytest
from cli_running import notes, run

from pydrill.cli_sweep import spec_notes
from pydrill.spec import parse_spec

ROOT = Path(__file__).resolve().parents[1]
TALLY = ROOT / "examples" / "tallies" / "paper-eq53.toml"
INCH = 0.0254

#: each command that takes --set, with the options it needs to run
COMMANDS = {
    "simulate": ["simulate", "--dof", "3", "--wob", "100", "--torque", "8", "--t-end", "1"],
    "stability": ["stability", "--dof", "3", "--wob", "100", "--torque", "8"],
    "string": ["string", "--preset", "reduced-scale", "--dof", "3"],
    "window": ["window", TALLY, "--depth", "3000m", "--at-rpm", "60"],
}


def refusal(capsys, args) -> str:
    code, out, err = run(capsys, *args)
    assert code == 2 and out == "", err
    return err.strip().splitlines()[-1]


def suggested(message: str) -> str | None:
    """The name a refusal's "(did you mean 'NAME'?)" gives, if any."""
    found = re.search(r"did you mean '(\w+)'\?", message)
    return found and found.group(1)


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize("name", ["top_inertia", "inertia", "stiffness", "damping", "karnopp_bnd"])
def test_a_set_name_suggested_is_one_set_takes(command, name, capsys):
    """Whatever --set suggests for a name it refuses, --set takes: the suggestion, typed, runs
    (top_inertia was sent to 'inertias', which --set refuses as a list)."""
    message = refusal(capsys, [*COMMANDS[command], "--set", f"{name}=1"])
    assert f"{name} is not one of the string's parameters" in message
    meant = suggested(message)
    takes = message.rsplit("--set takes ", 1)[1].split(", ")
    if meant is not None:
        assert meant in takes, message
        code, _, err = run(capsys, *COMMANDS[command], "--set", f"{meant}=0.01")
        assert code == 0, err
    # window's checks use the exact law: karnopp_band is none of its --set names
    assert ("karnopp_band" in takes) == (command != "window")
    if command == "window":
        assert meant is None or meant != "karnopp_band"


@pytest.mark.parametrize(
    ("name", "listed", "option"),
    [
        ("top_inertia", "inertias", "--inertias I0,I1,..."),
        ("inertia", "inertias", "--inertias I0,I1,..."),
        ("stiffness", "stiffnesses", "--stiffnesses K0,K1,..."),
    ],
)
def test_a_name_nearest_a_list_points_to_the_list_s_option(name, listed, option, capsys):
    """A name nearest a list of the chain is sent to the option that sets the list (simulate's
    --inertias, and stability's), which then runs; a command without it names those that have
    it (it said "only pydrill simulate" once stability had it too)."""
    values = {"inertias": "0.5,0.02,0.03", "stiffnesses": "1,1"}[listed]
    for command in ("simulate", "stability"):
        message = refusal(capsys, [*COMMANDS[command], "--set", f"{name}=1"])
        assert suggested(message) is None
        assert f"(the {listed} are a list, one value per " in message
        assert f"give {option})" in message
        code, _, err = run(capsys, *COMMANDS[command], f"--{listed}", values)
        assert code == 0, err
    for command in ("string", "window"):
        message = refusal(capsys, [*COMMANDS[command], "--set", f"{name}=1"])
        assert suggested(message) is None, message
        assert "only pydrill simulate" not in message
        assert f"pydrill simulate, stability, hopf, bifurcation and map do, with {option}" in (
            message
        )


def test_a_spec_key_nearest_a_list_says_it_is_a_list():
    """[model] top_inertia = 2500.0 was sent to 'inertias', whose number is refused: the
    suggestion says it is a list, and a list there is taken."""
    grid = "[axes]\nwob = [40.0]\ntorque = [8.0]\n"
    with pytest.raises(ValueError) as info:
        parse_spec("[model]\ndof = 3\ntop_inertia = 0.5\n" + grid)
    message = str(info.value)
    assert "model.top_inertia: unknown parameter (did you mean inertias = [...], a list of one " \
        "value per inertia?)" in message  # fmt: skip
    with pytest.raises(
        ValueError, match=r"model\.inertias: 0\.5 is not allowed: a list of numbers"
    ):
        parse_spec("[model]\ndof = 3\ninertias = 0.5\n" + grid)
    spec = parse_spec("[model]\ndof = 3\ninertias = [0.5, 0.02, 0.03]\n" + grid)
    assert spec.params_at(spec.coords(0)).inertias[0] == 0.5
    # a plain typo is still sent to its name
    with pytest.raises(ValueError, match=r"\(did you mean 'bit_damping'\?\)"):
        parse_spec("[model]\nbit_dampng = 0.1\n" + grid)


def radius_note(err: str) -> str:
    said = [n for n in notes(err) if "bit_radius" in n]
    assert len(said) == 1, err
    return said[0]


@pytest.mark.parametrize("command", COMMANDS)
def test_a_wide_bit_radius_with_its_unit_is_not_called_bare(command, capsys):
    """--set "bit_radius=8.5 m" was noted "a bare number is m": it has its unit, and is read
    as written; inches are suggested as what may have been meant. A bare 8.5 is still said to
    be m. A unit that is inches already suggests no inches."""
    code, _, err = run(capsys, *COMMANDS[command], "--set", "bit_radius=8.5 m")
    assert code == 0, err
    note = radius_note(err)
    assert "a bare number" not in note and "a bit 17 m across" in note
    assert note.endswith("read as written, in m: if inches were meant, write bit_radius=8.5in")
    code, _, err = run(capsys, *COMMANDS[command], "--set", "bit_radius=8.5")
    assert radius_note(err).endswith("; a bare number is m: for inches write bit_radius=8.5in")
    code, _, err = run(capsys, *COMMANDS[command], "--set", "bit_radius=8.5 ft")
    note = radius_note(err)
    assert f"bit_radius = 8.5 ft ({8.5 * 0.3048:.4g} m): a bit {2 * 8.5 * 0.3048:g} m" in note
    assert note.endswith("read as written, in ft: if inches were meant, write bit_radius=8.5in")
    code, _, err = run(capsys, *COMMANDS[command], "--set", "bit_radius=25 in")
    note = radius_note(err)
    wide = f"a bit {2 * 25 * INCH:g} m across, wider than any bit (at most some 1 m)"
    assert note.endswith(f"{wide}; read as written")


@pytest.mark.parametrize(
    ("written", "ending"),
    [
        ('"8.5 m"', 'read as written, in m: if inches were meant, write "8.5 in"'),
        ("8.5", 'a bare number is m: for inches write "8.5 in"'),
        ('"8.5 ft"', 'read as written, in ft: if inches were meant, write "8.5 in"'),
        # 850 in would be wider still: no inches suggested
        ('"850 mm"', "wider than any bit (at most some 1 m); read as written"),
    ],
)
def test_a_spec_s_wide_bit_radius_is_said_as_written(written, ending, capsys):
    """The same note on a spec's [model] bit_radius: "8.5 ft" was said as "2.5908 m ... a
    bare number is m: for inches write "2.5908 in"", neither what was written nor meant."""
    spec_notes(
        parse_spec(
            f"[model]\ndof = 3\nbit_radius = {written}\n[axes]\nwob = [40.0]\ntorque = [8.0]\n"
        )
    )
    note = radius_note(capsys.readouterr().err)
    assert note.startswith("pydrill: note: model.bit_radius = ") and note.endswith(ending)


TALLY_SPEC = f'[model]\ntally = "{TALLY}"\n[axes]\nwob = ["100 kN"]\ntorque = ["10 kN*m"]\n'


@pytest.mark.parametrize(
    ("depth", "km", "bare"),
    [
        ('["30 km"]', 30, False),
        ('["100000 ft", 1000.0]', 30.48, False),
        ("[30000.0]", 30, True),
        ("{ start = 1000.0, stop = 30000.0, num = 2 }", 30, True),
    ],
)
def test_a_spec_s_depth_beyond_any_well_is_called_bare_only_if_it_is(depth, km, bare, capsys):
    """depth = "30 km" was noted "a bare number is m"; a bare 30000 still is, with the feet
    that may have been meant, as --depth says it."""
    spec_notes(parse_spec(TALLY_SPEC + f"depth = {depth}\n", tally_text=TALLY.read_text()))
    (note,) = [n for n in notes(capsys.readouterr().err) if "depth" in n]
    assert note.startswith(f"pydrill: note: axes.depth reaches {km:g} km, longer than any well")
    assert ("a bare number is m" in note) == bare
    if bare:
        assert note.endswith('; a bare number is m: for feet write "30000 ft"')
    held = TALLY_SPEC.replace("[axes]", 'depth = "30 km"\n[axes]')
    spec_notes(parse_spec(held, tally_text=TALLY.read_text()))
    (note,) = [n for n in notes(capsys.readouterr().err) if "depth" in n]
    assert note.startswith("pydrill: note: model.depth reaches 30 km") and "bare" not in note


@pytest.mark.parametrize(
    ("radii", "ending"),
    [
        ("[0.1, 8.5]", 'a bare number is m: for inches write "8.5 in"'),
        ('["8.5 m", 0.1]', 'read as written, in m: if inches were meant, write "8.5 in"'),
        ('{ start = "0.1 m", stop = "8.5 ft", num = 3 }', 'if inches were meant, write "8.5 in"'),
    ],
)
def test_a_swept_bit_radius_wider_than_any_bit_is_said(radii, ending, capsys):
    """A swept bit_radius reaching 8.5 m was said nothing of, where --set and [model] say it."""
    grid = "[axes]\nwob = [40.0]\ntorque = [8.0]\n"
    spec_notes(parse_spec(f"[model]\ndof = 3\n{grid}bit_radius = {radii}\n"))
    note = radius_note(capsys.readouterr().err)
    assert note.startswith("pydrill: note: axes.bit_radius reaches ") and note.endswith(ending)
    assert "a bit 17 m across" in note or f"a bit {2 * 8.5 * 0.3048:g} m across" in note
    spec_notes(parse_spec(f"[model]\ndof = 3\n{grid}bit_radius = [0.1, 0.2]\n"))
    assert notes(capsys.readouterr().err) == []


def test_a_spec_s_list_of_another_length_on_a_tally_names_that_list():
    """[model] inertias = [a, b] on a tally's string was refused as "stiffnesses has N
    entries: dof = 2 needs 1", a list the spec did not give; the count asked is the string's
    (the tally reduced to dof inertias), and a list of that length is taken."""
    held = TALLY_SPEC.replace("[axes]", 'depth = "3000 m"\ndof = 3\n{}[axes]')
    text = TALLY.read_text()
    for line, key, given, need in [
        ("inertias = [2500.0, 100.0]\n", "inertias", "2 values", 3),
        ("dampings = [1.0]\n", "dampings", "1 value", 2),
    ]:
        with pytest.raises(ValueError) as info:
            parse_spec(held.format(line), tally_text=text)
        assert str(info.value) == (
            f"model: {key} has {given}, but the tally's string has 3 inertias: give {need} (one "
            f"per {'inertia' if need == 3 else 'link'}; dof sets how many), or leave {key} out"
        )
    spec = parse_spec(held.format("dampings = [1.0, 2.0]\n"), tally_text=text)
    assert list(spec.params_at({}).dampings) == [1.0, 2.0]


@pytest.mark.parametrize(
    ("given", "said"),
    [
        (["--dof", "4", "--inertias", "1,2"], "--inertias has 2 entries: dof = 4 needs 4"),
        (["--dampings", "1"], "--dampings has 1 entry: dof = 4 needs 3"),
        (["--dof", "3", "--stiffnesses", "1,2,3"], "--stiffnesses has 3 entries: dof = 3 needs 2"),
    ],
)
def test_simulate_s_list_of_another_length_names_its_option(given, said, capsys):
    """simulate --dof 4 --inertias 1,2 said "inertias has 2 entries", of no option; --set's
    refusals already named theirs. A list of the right length runs."""
    point = ["simulate", "--wob", "100", "--torque", "8", "--t-end", "1"]
    assert refusal(capsys, [*point, *given]).startswith(f"pydrill simulate: error: {said} (one per")
    code, _, err = run(capsys, *point, "--dof", "3", "--dampings", "1,1")
    assert code == 0, err


@pytest.mark.parametrize("command", COMMANDS)
@pytest.mark.parametrize(
    "name", ["t_end", "wob_max", "rpm_max", "at_rpm", "check_dof", "tally", "n_out", "max_steps"]
)
def test_a_set_name_that_is_an_option_points_to_the_option_as_typed(command, name, capsys):
    """window --set wob_max=1 said "give --wob_max" (the option is --wob-max), --set tally=1
    "give --tally" (window takes its tally as an argument), simulate --set t_end=1 quoted
    "--set '--t-end=1'", which was not typed: the option given is in the command's --help."""
    message = refusal(capsys, [*COMMANDS[command], "--set", f"{name}=1"])
    assert message.split(": ")[1:3] == ["error", f"--set '{name}=1'"]
    found = re.search(r"give (\S+);|is given as (\S+), the command's argument", message)
    if found is None:
        assert f"{name} is not one of the string's parameters;" in message
        return
    option = found.group(1) or found.group(2)
    code, out, _ = run(capsys, *COMMANDS[command][:1], "--help")
    assert code == 0 and re.search(rf"(^|[\s\[]){re.escape(option)}([\s\]]|$)", out), option
    assert "_" not in option.lstrip("-") or option.isupper()


@pytest.mark.parametrize(
    ("command", "name", "said"),
    [
        ("window", "wob_max", "wob_max has an option of its own: give --wob-max;"),
        ("window", "tally", "tally is given as TALLY.toml, the command's argument;"),
        ("simulate", "t_end", "t_end has an option of its own: give --t-end;"),
        ("simulate", "handler", "handler is not one of the string's parameters;"),
        ("window", "set_params", "set_params is not one of the string's parameters;"),
    ],
)
def test_the_option_named_is_the_one_typed(command, name, said, capsys):
    assert said in refusal(capsys, [*COMMANDS[command], "--set", f"{name}=1"])


@pytest.mark.parametrize("command", ["simulate", "stability", "string"])
def test_a_karnopp_band_that_nothing_uses_is_said(command, capsys):
    """--set karnopp_band=0.1 was taken and printed as changed, silently changing nothing,
    except in simulate --friction karnopp (a spec's is noted): what the command computes is
    the same without it, and the note says so; with --friction karnopp it is used, unnoted."""
    code, out, err = run(capsys, *COMMANDS[command], "--set", "karnopp_band=0.1", "--json")
    assert code == 0, err
    (note,) = notes(err)
    assert note.startswith("pydrill: note: --set karnopp_band = 0.1 rad/s has no effect ")
    code, plain, _ = run(capsys, *COMMANDS[command], "--json")
    changed = json.loads(out)
    assert changed.pop("set") == {"karnopp_band": 0.1}
    # what was computed (the inputs echo the band, the solver its own timing)
    kept = ("units", "inputs", "solver")
    assert {k: v for k, v in changed.items() if k not in kept} == {
        k: v for k, v in json.loads(plain).items() if k not in kept
    }
    if command == "simulate":
        assert note.endswith("give --friction karnopp to use it")
        # in stick-slip under the Karnopp law the band is the bit's least speed: used
        karnopp = ["simulate", "--dof", "3", "--wob", "60", "--torque", "8.3", "--t-end", "30"]
        karnopp += ["--friction", "karnopp", "--json"]
        code, out, err = run(capsys, *karnopp, "--set", "karnopp_band=0.5")
        assert code == 0 and notes(err) == []
        slowest = json.loads(out)["bit_velocity"]["min"]
        assert slowest == pytest.approx(0.5, rel=1e-6)
        assert json.loads(run(capsys, *karnopp)[1])["bit_velocity"]["min"] != pytest.approx(0.5)


@pytest.mark.parametrize(
    ("given", "half"), [("bit_diameter=8.5in", "4.25in"), ("diameter=0.2", "0.1")]
)
def test_a_bit_diameter_points_to_the_radius_it_takes(given, half, capsys):
    """--set bit_diameter=8.5in (a tally's bit.diameter) was refused with no word of
    bit_radius: the hint gives half of it, which builds the same bit (8.5 in across)."""
    message = refusal(capsys, [*COMMANDS["simulate"], "--set", given])
    assert f"(the bit is given by its radius: bit_radius={half})" in message
    code, out, err = run(capsys, *COMMANDS["simulate"], "--set", f"bit_radius={half}", "--json")
    assert code == 0, err
    across = 8.5 * INCH if "in" in half else 0.2
    assert 2 * json.loads(out)["set"]["bit_radius"] == pytest.approx(across, rel=1e-12)


@pytest.mark.parametrize(
    ("line", "hint", "radius"),
    [
        ('bit_diameter = "8.5 in"', 'bit_radius = "4.25 in"', 4.25 * INCH),
        ("diameter = 0.2", "bit_radius = 0.1", 0.1),
    ],
)
def test_a_spec_s_bit_diameter_points_to_the_radius_it_takes(line, hint, radius):
    """The same in a spec's [model]: the radius hinted, written there, is the bit's."""
    grid = "[axes]\nwob = [40.0]\ntorque = [8.0]\n"
    with pytest.raises(ValueError, match=re.escape(f"(the bit is given by its radius: {hint})")):
        parse_spec(f"[model]\ndof = 3\n{line}\n{grid}")
    spec = parse_spec(f"[model]\ndof = 3\n{hint}\n{grid}")
    assert spec.params_at({}).bit_radius == pytest.approx(radius, rel=1e-12)
