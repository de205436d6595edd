"""A tally's messages name a section as the user counts its [[section]] tables: from 1, top
down, with the kind it gives ("section 3 (drill-collar), od = ..."). They said "section[2]",
an index from 0 that the file does not show: the user, reading the tables top down, looked at
the wrong one. Each message is checked against the table that holds the fault, found here by
counting the [[section]] headers of the text above the faulty line.
"""

import re

import pytest
from cli_running import notes, run

from pydrill.spec import SpecError, parse_spec
from pydrill.tally import TallyError, parse_tally

HEAD = '[top_drive]\ninertia = "2500 kg·m2"\n[bit]\ndiameter = "8.5 in"\n'
SECTIONS = [
    ("drill-pipe", 'count = 300\nlength = "31 ft"\nod = "5.5 in"\nid = "4.778 in"'),
    ("heavy-weight", 'count = 15\nlength = "31 ft"\nod = "5.5 in"\nid = "3.375 in"'),
    ("drill-collar", 'count = 9\nlength = "31 ft"\nod = "8 in"\nid = "2.8125 in"'),
    ("bit", 'length = "1 ft"\nod = "8.5 in"\nid = "2 in"'),
]
MARK = "# the fault\n"


def tally_text(k: int, fault: str, kind: bool = True) -> str:
    """The four-section tally with ``fault`` (TOML lines) in its section ``k`` (from 1, as
    written), marked; without ``kind``, that section gives none."""
    tables = []
    for n, (name, body) in enumerate(SECTIONS, start=1):
        lines = ([f'kind = "{name}"'] if kind or n != k else []) + body.split("\n")
        if n == k:
            keys = {line.split(" = ")[0] for line in fault.strip().split("\n")}
            lines = [line for line in lines if line.split(" = ")[0] not in keys]
            lines.append(MARK + fault.strip())
        tables.append("[[section]]\n" + "\n".join(lines) + "\n")
    return HEAD + "".join(tables)


def counted(text: str) -> int:
    """The section holding the fault, counted by hand: [[section]] headers above its mark."""
    return text[: text.index(MARK)].count("[[section]]")


def named(message: str) -> list[int]:
    """The section numbers a message names."""
    assert "section[" not in message, message
    return [int(n) for n in re.findall(r"\bsection (\d+)\b", message)]


FAULTS = [
    ('odd = "5 in"', "odd: unknown (did you mean 'od'?)"),
    ("count = 0", "count = 0 is not allowed"),
    ("od = 5.5", "od = 5.5 is not allowed"),
    ('id = "9 in"', "id = '9 in' is not allowed: need 0 <= id < od"),
    ("count = 70000000", "count = 70000000 is not allowed: the string reaches"),
    ("shear_modulus = 1e-310", "a joint's stiffness"),
]


@pytest.mark.parametrize("k", [1, 2, 3, 4])
@pytest.mark.parametrize(("fault", "said"), FAULTS, ids=[f for f, _ in FAULTS])
def test_a_refusal_names_the_section_as_the_file_lists_it(k, fault, said):
    text = tally_text(k, fault)
    with pytest.raises(TallyError) as info:
        parse_tally(text)
    message = str(info.value)
    assert said in message
    assert named(message) == [counted(text)] == [k]
    kind = SECTIONS[k - 1][0]
    assert message.startswith(f"section {k} ({kind})")
    # a section that gives no kind is named by its place alone
    with pytest.raises(TallyError) as info:
        parse_tally(tally_text(k, fault, kind=False))
    assert str(info.value).startswith(
        f"section {k}, " if "stiffness" not in said else f"section {k}:"
    )


def test_a_bad_kind_is_named_by_place_alone():
    text = tally_text(3, 'kind = "collar"')
    with pytest.raises(TallyError, match=r"^section 3, kind = 'collar' is not allowed"):
        parse_tally(text)


@pytest.mark.parametrize("k", [1, 2, 3])
def test_a_note_names_the_section_as_the_file_lists_it(k):
    """A bare joint length and a bare diameter noted; a bit listed above other sections."""
    text = tally_text(k, "length = 31\nod = 5\nid = 4.276")
    said = parse_tally(text).notes
    assert len(said) == 3
    for note in said:
        assert named(note) == [k] and note.startswith(f"section {k} ({SECTIONS[k - 1][0]}), ")
    # the bit moved up to place k: the note names it at k
    order = [*SECTIONS[: k - 1], SECTIONS[3], *SECTIONS[k - 1 : 3]]
    moved = HEAD + "".join(f'[[section]]\nkind = "{n}"\n{b}\n' for n, b in order)
    (note,) = parse_tally(moved).notes
    assert note.startswith(f"section {k} is the bit, with {4 - k} section(s) listed below it")


def test_a_malformed_section_is_counted_from_one():
    text = 'section = [{kind = "drill-pipe", length = 9.0, od = 0.1}, 7]\n' + HEAD
    with pytest.raises(TallyError, match=r"^malformed tally: section 2 = 7 is not allowed"):
        parse_tally(text)


def test_the_command_line_and_a_spec_say_it_so_too(tmp_path, capsys):
    """simulate, window and a sweep's spec pass the tally's words on, with the file's name."""
    text = tally_text(3, "count = 0")
    path = tmp_path / "t.toml"
    path.write_text(text)
    code, _, err = run(capsys, "window", path, "--depth", "3000m")
    assert code == 2 and f"{path}: section 3 (drill-collar), count = 0 is not allowed" in err
    spec = '[model]\ntally = "t.toml"\ntorque = 9000.0\n[axes]\nwob = [1e5]\n'
    with pytest.raises(SpecError, match=r"^model\.tally: section 3 \(drill-collar\), count = 0"):
        parse_spec(spec, tally_text=text)
    path.write_text(tally_text(2, "length = 31"))
    code, _, err = run(capsys, "string", path)
    assert code == 0
    (note,) = notes(err)
    assert note.startswith(f"pydrill: note: {path}: section 2 (heavy-weight), length = 31 ")
