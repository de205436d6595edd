#!/usr/bin/env python3
"""What ``pydrill atlas export`` costs on a large atlas: wall time and peak memory, against
the export made whole in memory (as it was before it went by blocks) in the same run.

    python benchmarks/bench_export.py                 # 10^6 points: about three minutes
    python benchmarks/bench_export.py --points 250000 # a quarter: under a minute

The atlas is bench_sweep's 10^6-point one (1000 x 1000, from rest and equilibrium, smooth
values, 400 MB of data, 176 MB on disk), or a smaller square. Each export runs in a process
of its own, its peak resident memory read from the kernel (``wait4``): that includes the
interpreter and its libraries (about 100 MB) and the atlas's pages mapped for its heap check,
the same for both ways. The whole way: the atlas read into memory, the netCDF file made in
memory (``to_netcdf(None)``) or the CSV table as one DataFrame and one string by pandas'
``to_csv`` (whose text the export's own writer, ``_core.csv_rows``, matches byte for byte in a
fraction of the time), then written.
Both must make the same file (checked). This process stays small (about 30 MB): a child's peak
as ``wait4`` reports it is at least its parent's at the fork.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

#: the whole way, run in a process of its own: the export as it was made before blocks
WHOLE = """
import sys, warnings
from pydrill.atlas import Atlas, COUNT_FIELDS
from pydrill.cli_atlas_export import _netcdf_encoding
from pydrill.export_csv import name_codes
source, out = sys.argv[1:]
with Atlas(source) as atlas:
    atlas.check()
    ds = atlas.to_xarray()
    if out.endswith(".nc"):
        warnings.filterwarnings("ignore", "Creating variable with default fill_value 0")
        data = ds.load().to_netcdf(None, engine="h5netcdf", encoding=_netcdf_encoding(ds))
    else:
        ds.load()
        keep = [v for v in ds.data_vars if "eigenvalue" not in ds[v].dims
                and "equilibrium" not in ds[v].dims and (ds[v].dtype.kind != "O" or v == "message")]
        table = ds[keep].to_dataframe()
        for name in COUNT_FIELDS:
            if name in table:
                table[name] = table[name].astype("Int64")
        name_codes(table)
        data = table.to_csv().encode()
    ds.close()
with open(out, "wb") as fh:
    fh.write(data)
"""


def measure(argv: list[str]) -> tuple[float, float]:
    """Wall time (s) and peak resident memory (MB) of a process running ``argv``."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode:
        raise SystemExit(f"{argv} failed ({proc.returncode})")
    return time.perf_counter() - t0, usage.ru_maxrss / 1024


#: whether two exports hold the same (run in a process of its own, as the atlas is made: a
#: child's peak memory as the kernel reports it starts from its parent's at the fork)
SAME = """
import sys
from pathlib import Path
a, b = map(Path, sys.argv[1:])
if a.suffix == ".csv":
    sys.exit(a.read_bytes() != b.read_bytes())
import xarray as xr
with xr.open_dataset(a, engine="h5netcdf") as x, xr.open_dataset(b, engine="h5netcdf") as y:
    sys.exit(not x.load().identical(y.load()))
"""

FILL = """
import sys
sys.path.insert(0, sys.argv[1])
from pathlib import Path
from bench_sweep import BIG, fill_atlas
from pydrill.spec import parse_spec
fill_atlas(Path(sys.argv[2]), parse_spec(BIG.replace("num = 1000", "num = " + sys.argv[3])))
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--points", type=int, default=10**6, help="points of the atlas (a square)")
    n = round(math.sqrt(parser.parse_args().points))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        atlas = tmp / "big.h5"
        here = str(Path(__file__).resolve().parent)
        subprocess.run([sys.executable, "-c", FILL, here, str(atlas), str(n)], check=True)
        mb = atlas.stat().st_size / 1e6
        print(f"atlas of {n * n:,} points ({mb:.0f} MB on disk)")
        for suffix in (".nc", ".csv"):
            rows = {}
            for way in ("blocks", "whole", "blocks again"):  # bracketed: the machine drifts
                out = tmp / f"{way.split()[0]}{suffix}"
                if way == "whole":
                    argv = [sys.executable, "-c", WHOLE, str(atlas), str(out)]
                else:
                    argv = [sys.executable, "-m", "pydrill", "atlas", "export", str(atlas)]
                    argv += ["--out", str(out)]
                rows[way] = measure(argv)
            blocks = [rows["blocks"], rows["blocks again"]]
            t_blocks = float(np.mean([t for t, _ in blocks]))
            m_blocks = max(m for _, m in blocks)
            t_whole, m_whole = rows["whole"]
            files = [str(tmp / f"blocks{suffix}"), str(tmp / f"whole{suffix}")]
            same = subprocess.run([sys.executable, "-c", SAME, *files]).returncode == 0
            ok = "same file" if same else "DIFFER"
            print(
                f"  {suffix[1:]:>3}: by blocks {t_blocks:.1f} s, {m_blocks:.0f} MB; whole "
                f"{t_whole:.1f} s, {m_whole:.0f} MB; time x{t_blocks / t_whole:.2f}, peak "
                f"memory x{m_blocks / m_whole:.2f} ({ok})"
            )


if __name__ == "__main__":
    main()
