"""A file of one kind given where another is read is named for what it is (not "truncated or
corrupt?", not its first odd key), with what to do with it instead; and an atlas may not take a
figure's, spec's or table's name, since the figure drawn from it next ('pydrill atlas plot
f.png --out f.png', which the sweep itself suggests) was written over the whole sweep. The
files are made by their real writers (matplotlib, h5py, a sweep, the shipped examples), and
every refusal leaves the folder as it was."""

import json
import shutil
from pathlib import Path

import h5py
import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from cli_running import run
from sweeping import TINY

from pydrill.file_kinds import what_is
from pydrill.journal import AtlasError
from pydrill.spec import SpecError, load_spec, parse_spec
from pydrill.sweep import run_sweep
from pydrill.sweep_plan import plan_sweep
from pydrill.tally import TallyError, load_tally

ROOT = Path(__file__).resolve().parents[1]


def folder(path: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(path.iterdir())}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """One file of each kind, written by what writes it in real use."""
    d = tmp_path_factory.mktemp("kinds")
    run_sweep(parse_spec(TINY), d / "atlas.h5", serial=True)
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    for suffix in ("png", "pdf", "jpg"):
        fig.savefig(d / f"figure.{suffix}")
    plt.close(fig)
    with h5py.File(d / "other.h5", "w") as f:  # HDF5, but no atlas
        f["x"] = [1, 2, 3]
    shutil.copy(ROOT / "sweeps" / "minimal.toml", d / "spec.toml")
    shutil.copy(ROOT / "examples" / "tallies" / "paper-eq53.toml", d / "tally.toml")
    (d / "notes.toml").write_text('title = "not ours"\n')
    return d


@pytest.mark.parametrize(
    "name, kind",
    [
        ("atlas.h5", "an HDF5 file (an atlas?)"),
        ("other.h5", "an HDF5 file (an atlas?)"),
        ("figure.png", "a PNG image"),
        ("figure.pdf", "a PDF document"),
        ("figure.jpg", "a JPEG image"),
        ("spec.toml", "a sweep spec (TOML)"),
        ("tally.toml", "a tally (TOML)"),
        ("notes.toml", None),  # TOML, but neither: the reader's own words stand
    ],
)
def test_each_kind_is_recognised_from_its_content_as_its_writer_made_it(files, name, kind):
    assert what_is(files / name) == kind
    moved = files / f"renamed-{name}.dat"  # by content, not by name
    shutil.copy(files / name, moved)
    try:
        assert what_is(moved) == kind
    finally:
        moved.unlink()


@pytest.mark.parametrize(
    "command, message",
    [
        (
            ["atlas", "info", "{spec.toml}"],
            "{spec.toml} is a sweep spec (TOML), not an atlas: make an atlas from it with "
            "'pydrill sweep {spec.toml} --out ATLAS.h5'",
        ),
        (["atlas", "query", "{tally.toml}", "--wob", "100"], "{tally.toml} is a tally (TOML), "),
        (["atlas", "plot", "{figure.png}", "--out", "{new.png}"], "{figure.png} is a PNG image"),
        (
            ["sweep", "{atlas.h5}", "--out", "{new.h5}"],
            "{atlas.h5} is an HDF5 file (an atlas?), not a sweep spec: "
            "'pydrill atlas info {atlas.h5}' reads an atlas",
        ),
        (["sweep", "{figure.pdf}", "--dry-run"], "{figure.pdf} is a PDF document, not a sweep"),
        (
            ["sweep", "{tally.toml}", "--out", "{new.h5}"],
            "{tally.toml} is a tally (TOML), not a sweep spec: a spec names it under [model] as "
            "tally = \"tally.toml\"; 'pydrill window {tally.toml} --depth DEPTH' reads it",
        ),
        (
            ["window", "{spec.toml}", "--depth", "1000"],
            "{spec.toml} is a sweep spec (TOML), not a pipe tally: run it with "
            "'pydrill sweep {spec.toml} --out ATLAS.h5'",
        ),
        (["window", "{atlas.h5}", "--depth", "1000"], "{atlas.h5} is an HDF5 file (an atlas?), "),
    ],
)
def test_the_command_names_the_file_for_what_it_is(files, capsys, command, message):
    before = folder(files)
    names = {f"{{{p.name}}}": str(p) for p in files.iterdir()}
    names |= {"{new.png}": str(files / "new.png"), "{new.h5}": str(files / "new.h5")}

    def fill(text: str) -> str:
        for key, path in names.items():
            text = text.replace(key, path)
        return text

    code, out, err = run(capsys, *map(fill, command))
    assert (code, out) == (2, "")
    assert err.startswith(f"pydrill {' '.join(command[: 2 if command[0] == 'atlas' else 1])}: ")
    assert fill(message) in err, err
    assert "truncated or corrupt" not in err and "not UTF-8" not in err
    assert folder(files) == before


def test_the_api_says_the_same(files):
    with pytest.raises(SpecError, match=r"atlas\.h5 is an HDF5 file \(an atlas\?\), not a sweep"):
        load_spec(files / "atlas.h5")
    with pytest.raises(TallyError, match=r"spec\.toml is a sweep spec \(TOML\), not a pipe tally"):
        load_tally(files / "spec.toml")
    # A spec naming a figure for its tally says so under the key that names it.
    text = (files / "spec.toml").read_text().replace("dof = 4", 'tally = "figure.png"')
    (files / "uses-figure.toml").write_text(text)
    try:
        with pytest.raises(SpecError, match=r"model\.tally.*figure\.png is a PNG image"):
            load_spec(files / "uses-figure.toml")
    finally:
        (files / "uses-figure.toml").unlink()


def test_damage_and_unknown_files_keep_their_own_words(files, tmp_path):
    """Only whole files of a recognised kind are renamed: a cut atlas is still 'truncated or
    corrupt?' and a TOML file of no kind of ours still fails on its first key."""
    cut = tmp_path / "cut.h5"
    cut.write_bytes((files / "atlas.h5").read_bytes()[:100])
    from pydrill import Atlas

    with pytest.raises(AtlasError, match="not a readable HDF5 atlas"):
        Atlas(cut)
    with pytest.raises(AtlasError, match="is an HDF5 file but not a pydrill atlas"):
        Atlas(files / "other.h5")
    with pytest.raises(SpecError, match="title"):
        load_spec(files / "notes.toml")


@pytest.mark.parametrize("name", ["a.png", "a.PDF", "a.svg", "a.toml", "a.csv", "a.json"])
def test_a_new_atlas_may_not_take_another_kinds_name(tmp_path, capsys, name):
    spec = parse_spec(TINY)
    out = tmp_path / "new" / name
    with pytest.raises(AtlasError, match=rf"{name}: a name ending \.\w+ is taken for .*\.h5$"):
        run_sweep(spec, out, serial=True)
    with pytest.raises(AtlasError, match=r"give out=PATH a name ending \.h5"):
        plan_sweep(spec, out)
    (tmp_path / "spec.toml").write_text(TINY)
    for extra in (["--serial"], ["--dry-run"]):
        # (the CLI refuses a folder that does not exist first: the atlas goes beside the spec)
        code, _, err = run(
            capsys, "sweep", tmp_path / "spec.toml", "--out", tmp_path / name, *extra
        )
        assert code == 2 and "give --out a name ending .h5" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]  # no folder "new"


def test_an_atlas_already_named_like_a_figure_is_read_but_never_drawn_over_itself(
    files, tmp_path, capsys
):
    """One made before names were checked (or renamed by hand) still opens and resumes; a
    figure of it goes elsewhere, and the sweep's next steps suggest elsewhere."""
    atlas = tmp_path / "old.png"
    shutil.copy(files / "atlas.h5", atlas)
    data = atlas.read_bytes()
    code, out, _ = run(capsys, "atlas", "info", atlas, "--json")
    assert code == 0 and json.loads(out)["points"] == 6
    code, _, err = run(capsys, "atlas", "plot", atlas, "--out", atlas)
    assert code == 2 and f"--out {atlas} is the atlas itself; give another file" in err
    assert atlas.read_bytes() == data
    (tmp_path / "spec.toml").write_text(TINY)
    code, _, err = run(capsys, "sweep", tmp_path / "spec.toml", "--out", atlas, "--resume")
    assert code == 0 and "6 of 6 points are done, 0 to compute" in err
    assert f"pydrill atlas plot {atlas} --out {tmp_path / 'old-map.png'}" in err
    code, _, _ = run(capsys, "atlas", "plot", atlas, "--out", tmp_path / "old-map.png")
    assert code == 0 and what_is(tmp_path / "old-map.png") == "a PNG image"
