"""A part's sweep (``--part K/N``) stopped midway: every command pydrill prints to complete
it must be one that the sweep accepts. Its atlas holds the part's spec, which the whole spec
is not (a --resume without --part is refused as another sweep), so the commands must carry
--part K/N; and the refusal itself says which part the atlas is."""

import json
import re
import shlex
import signal

import pytest
from sweeping import interrupt_mid_sweep

from pydrill.atlas_merge import merge_atlases
from pydrill.cli import main
from pydrill.journal import read_existing
from pydrill.spec import load_spec
from pydrill.sweep import AtlasError


def _accepted(spec, out) -> bool:
    """Whether ``--resume`` of ``spec`` into ``out`` gets past the check of the atlas."""
    try:
        read_existing(spec, out, resume=True)
    except AtlasError:
        return False
    return True


def test_a_stopped_part_is_resumed_with_its_part(tmp_path, capsys):
    rc, stdout, err, out = interrupt_mid_sweep(
        tmp_path, signal.SIGTERM, "--serial", "--part", "1/2", "--json"
    )
    assert rc == 128 + signal.SIGTERM, err
    whole = load_spec(tmp_path / "longer.toml")
    part = whole.part(1, 2)
    # The reference: the part's spec resumes this atlas, the whole spec does not.
    assert _accepted(part, out) and not _accepted(whole, out)
    with pytest.raises(AtlasError, match=r"it is part 1 of 2 of this spec: resume it as that"):
        read_existing(whole, out, resume=True)

    # What the stopped sweep prints (stderr and --json) resumes it as that part.
    resume = json.loads(stdout)["resume"]
    assert resume in err
    words = shlex.split(resume)
    assert words[words.index("--part") + 1] == "1/2"  # (was missing: refused as above)

    # atlas info, the export's note and merge's refusal name the same command.
    assert main(["atlas", "info", str(out)]) == 0
    info = capsys.readouterr().out
    assert main(["atlas", "export", str(out), "--out", str(tmp_path / "p.csv")]) == 0
    export = capsys.readouterr().err
    with pytest.raises(AtlasError) as merge:
        merge_atlases([out, tmp_path / "other.h5"], tmp_path / "merged.h5")
    want = f"'pydrill sweep SPEC.toml --part 1/2 --out {out} --resume'"
    for said in (info, export, str(merge.value)):
        assert want in re.sub(r"\s+", " ", said), said
