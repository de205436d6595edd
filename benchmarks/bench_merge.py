#!/usr/bin/env python3
"""What ``pydrill atlas merge`` costs on a large atlas: wall time and peak memory, against
copying an atlas of the merged size through pydrill's table (read it whole, write it anew: the
least any merge does) in the same run.

    python benchmarks/bench_merge.py                  # 10^6 points: about a minute
    python benchmarks/bench_merge.py --points 250000  # a quarter

The whole atlas is bench_sweep's 10^6-point one (1000 x 1000, from rest and equilibrium,
smooth values); the parts are its spec's ``part(1, 2)`` and ``part(2, 2)`` (every other W_ob),
filled the same way, so the merge of the parts must hold the whole atlas's data (checked).
Each run is a process of its own, its peak resident memory read from the kernel (``wait4``):
that includes the interpreter and its libraries (about 100 MB).
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from bench_export import measure  # (this folder: the script's own)

FILL = """
import sys
sys.path.insert(0, sys.argv[1])
from pathlib import Path
from bench_sweep import BIG, fill_atlas
from pydrill.spec import parse_spec
whole = parse_spec(BIG.replace("num = 1000", "num = " + sys.argv[3]))
out = Path(sys.argv[2])
fill_atlas(out / "whole.h5", whole)
for k in (1, 2):
    fill_atlas(out / f"part{k}.h5", whole.part(k, 2))
"""

#: the floor: an atlas of the merged size read whole and written anew, as the merge writes
COPY = """
import sys
from pathlib import Path
from pydrill import Atlas, atlas_format as fmt
from pydrill.sweep import model_json
source, out = map(Path, sys.argv[1:])
with Atlas(source) as atlas:
    atlas.check()
    spec = atlas.spec
table = fmt.read_table(source, spec)
fmt.create(out, spec, model_json(spec), "bench")
fmt.write(out, table)
"""

#: whether the merged atlas holds the whole one's data (every dataset)
SAME = """
import sys
import h5py, numpy as np
with h5py.File(sys.argv[1]) as a, h5py.File(sys.argv[2]) as b:
    names = [n for n in a if isinstance(a[n], h5py.Dataset)]
    assert sorted(names) == sorted(n for n in b if isinstance(b[n], h5py.Dataset))
    for n in names:
        x, y = a[n][...], b[n][...]
        if x.dtype.kind == "f":
            x, y = np.nan_to_num(x, nan=-7.0), np.nan_to_num(y, nan=-7.0)
        if not np.array_equal(x, y):
            sys.exit(n)
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=10**6, help="points of the atlas (a square)")
    n = round(math.sqrt(parser.parse_args().points))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        here = str(Path(__file__).resolve().parent)
        subprocess.run([sys.executable, "-c", FILL, here, str(tmp), str(n)], check=True)
        print(f"atlas of {n * n:,} points, and its two parts (every other W_ob)")
        rows: dict[str, list[tuple[float, float]]] = {"merge": [], "copy": []}
        for k in range(2):  # bracketed: merge, copy, merge, copy (the machine drifts)
            merged = tmp / f"merged{k}.h5"
            parts = [str(tmp / "part2.h5"), str(tmp / "part1.h5")]
            argv = [sys.executable, "-m", "pydrill", "atlas", "merge", *parts, "--out", str(merged)]
            rows["merge"].append(measure(argv))
            copy = [sys.executable, "-c", COPY, str(tmp / "whole.h5"), str(tmp / f"copy{k}.h5")]
            rows["copy"].append(measure(copy))
        check = [sys.executable, "-c", SAME, str(tmp / "merged0.h5"), str(tmp / "whole.h5")]
        differs = subprocess.run(check, capture_output=True, text=True)
        ok = "the whole atlas's data" if differs.returncode == 0 else f"DIFFERS: {differs.stdout}"
        t_merge, t_copy = (float(np.mean([t for t, _ in rows[w]])) for w in ("merge", "copy"))
        m_merge, m_copy = (max(m for _, m in rows[w]) for w in ("merge", "copy"))
        print(
            f"  merge {t_merge:.1f} s, {m_merge:.0f} MB; copy {t_copy:.1f} s, {m_copy:.0f} MB; "
            f"time x{t_merge / t_copy:.2f}, peak memory x{m_merge / m_copy:.2f} ({ok})"
        )


if __name__ == "__main__":
    main()
