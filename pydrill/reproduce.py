"""``pydrill reproduce``: the paper's Sections 3–4 recomputed, drawn and compared in a report.

:func:`reproduce` runs the simulations of Figs. 4, 5, 7, 8, 9 (:mod:`pydrill.reproduce_sims`),
the stability and bifurcation analysis of Figs. 10–12 and of 10-, 100- and 500-pipe strings
(:mod:`pydrill.reproduce_analysis`), and the regime atlases behind Fig. 6b and the periodic
orbits of Fig. 11 (Dask sweeps, :mod:`pydrill.sweep`). It writes one PNG per figure
(:mod:`pydrill.reproduce_figures`, :mod:`pydrill.reproduce_plots`,
:mod:`pydrill.reproduce_plots_long`), ``report.md`` (:mod:`pydrill.reproduce_report`) and
``numbers.json`` into the output directory.

Whatever it computed is kept there and reused on the next run: atlases in ``atlases/`` (each
tied to its sweep's spec digest and the pydrill version, resumed if a run was interrupted),
analysis results in ``cache/`` (keyed by a digest of what was computed: the section, its
arguments, the pydrill version). ``force=True`` recomputes everything.
"""

from __future__ import annotations

import functools
import hashlib
import json
import shutil
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .reproduce_atlases import (
    _plain,
    atlas_numbers,
    atlas_plan,
    band,
    hopf_meets_band,
    orbits,
    run_atlas,
)

#: Raised whenever an analysis computes something new, so that a cache from before is not
#: reused: 2, every Hopf crossing of a long string is located on the branches and gets its
#: Lyapunov coefficient; 3, the Hurwitz check counts the Hopf crossings meeting all of
#: Theorem 5's Eq. (48), and Fig. 11's u-branches reach the atlases' largest u.
CACHE_SCHEMA = 3


class Cache:
    """JSON results in ``DIR/cache``, each stored with the digest of what produced it."""

    def __init__(self, root: Path, force: bool = False) -> None:
        from . import __version__

        self.root = root / "cache"
        self.root.mkdir(parents=True, exist_ok=True)
        self.version = __version__
        self.force = force
        self.hits: list[str] = []
        self.computed: list[str] = []

    def key(self, name: str, args: Any) -> str:
        doc = {"name": name, "args": args, "version": self.version, "schema": CACHE_SCHEMA}
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:16]

    def get(self, name: str, args: Any, compute: Callable[[], Any]) -> Any:
        path = self.root / f"{name}.json"
        key = self.key(name, args)
        if not self.force and path.exists():
            try:
                stored = json.loads(path.read_text())
                if stored.get("key") == key:
                    self.hits.append(name)
                    return stored["data"]
            except (OSError, ValueError):
                pass  # unreadable: recompute
        data = _plain(compute())
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps({"key": key, "name": name, "args": args, "data": data}))
        tmp.replace(path)
        self.computed.append(name)
        return data


def reproduce(
    out: str | Path,
    *,
    quick: bool = False,
    force: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool | None = None,
) -> dict[str, Any]:
    """Recompute the paper's Sections 3–4 into ``out``; returns the run's summary (also in
    ``out/numbers.json`` with every number the report quotes)."""
    from tqdm import tqdm

    from . import __version__
    from . import reproduce_analysis as ra
    from . import reproduce_sims as rs
    from .cli_options import bar_size
    from .reproduce_figures import draw_simulations
    from .reproduce_plots import draw_analysis
    from .reproduce_report import write_report

    t0 = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if force and (out / "cache").exists():
        shutil.rmtree(out / "cache")
    cache = Cache(out, force=force)
    plan = atlas_plan(quick)
    pipes = (10,) if quick else (10, 100, 500)
    steps = 5 + 3 + len(pipes) + len(plan) + 2
    bar = tqdm(
        total=steps,
        desc="reproduce",
        unit="step",
        file=sys.stderr,
        disable=(not sys.stderr.isatty()) if progress is None else not progress,
        bar_format="{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}<{remaining}] {postfix}",
        **bar_size(),
    )

    def step(label: str) -> None:
        bar.set_postfix_str(label)

    numbers: dict[str, Any] = {"quick": quick, "pydrill_version": __version__}
    runs: dict[str, Any] = {}
    for name, fn in (
        ("fig04", rs.fig4),
        ("fig05", rs.fig5),
        ("fig07", rs.fig7),
        ("fig09", rs.fig9),
    ):
        step(f"simulating {name}")
        numbers[name], runs[name] = fn()
        bar.update()
    step("simulating fig08")
    numbers["fig08"], runs["fig08"] = rs.fig8(runs["fig04"]["exact"])
    bar.update()
    for preset_name, key in (("reduced-scale", "fig10a"), ("real-string", "fig10b")):
        step(f"analysing {key}")
        numbers[key] = cache.get(
            key, {"preset": preset_name}, functools.partial(ra.fig10, preset_name)
        )
    bar.update()
    for panel, *_ in ra.FIG11:
        numbers[f"fig11{panel}"] = cache.get(
            f"fig11{panel}", {}, functools.partial(ra.fig11, panel)
        )
    bar.update()
    step("analysing the paper's strings (Fig. 12, multiple Hopf)")
    numbers["strings"] = cache.get("strings", {}, ra.paper_strings)
    bar.update()
    for p in pipes:
        step(f"analysing {p} pipes")
        numbers[f"pipes{p}"] = cache.get(
            f"pipes{p}", {"pipes": p}, functools.partial(ra.long_string, p)
        )
        bar.update()
    atlases: dict[str, str] = {}
    for name, settings in plan.items():
        step(f"atlas {name}")

        def sweep_progress(n: int, total: int, name=name) -> None:
            bar.set_postfix_str(f"atlas {name}: {n} points done of {total}")

        path, how = run_atlas(
            out,
            name,
            settings,
            force=force,
            workers=workers,
            scheduler=scheduler,
            progress=sweep_progress,
        )
        atlases[name] = how
        numbers[f"atlas_{name}"] = atlas_numbers(path)
        bar.update()
    numbers["fig06b_band"] = band(numbers["atlas_fig06b"])
    numbers["fig12_meets_band"] = hopf_meets_band(
        numbers["atlas_fig06b"], numbers["strings"]["dof4"]["fig12"]["curves"][0]["delta"]
    )
    for name in plan:
        if "fig11" in name:
            source = name.replace("-fig11", "/fig11").split("/")
            b = numbers[source[0]][source[1]] if len(source) == 2 else numbers[name]
            numbers[f"orbits_{name}"] = orbits(numbers[f"atlas_{name}"], b)
    step("drawing the figures")
    figures = draw_simulations(out, numbers, runs)
    figures += draw_analysis(out, numbers, pipes)
    bar.update()
    step("writing report.md")
    summary = {
        "out": str(out),
        "report": str(out / "report.md"),
        "figures": [str(f) for f in figures],
        "atlases": atlases,
        "cache": {"reused": cache.hits, "computed": cache.computed},
        "quick": quick,
        "pydrill_version": __version__,
    }
    summary["wall_time"] = time.perf_counter() - t0
    write_report(out, numbers, summary)
    (out / "numbers.json").write_text(json.dumps(_plain(numbers), allow_nan=False))
    bar.update()
    bar.close()
    summary["wall_time"] = time.perf_counter() - t0
    summary["highlights"] = highlights(numbers)
    return summary


def highlights(numbers: dict[str, Any]) -> dict[str, Any]:
    """The key numbers of the report, for ``--json``."""
    f4, f10 = numbers["fig04"]["exact"], numbers["fig10a"]
    return {
        "fig4_regime": f4["regime"],
        "fig4_period_s": f4["period"],
        "fig4_bit_max_rad_s": f4["bit_max"],
        "fig7_regime": numbers["fig07"]["loaded"]["regime"],
        "fig9_regime": numbers["fig09"]["run"]["regime"],
        "fig9_omega_rad_s": numbers["fig09"]["omega"],
        "fig10a_hopf_delta": f10["h2_delta"],
        "fig10b_hopf_delta": numbers["fig10b"]["h2_delta"],
        "fig11": {
            p: {
                "first_hopf": (numbers[f"fig11{p}"]["first_hopf"] or {}).get(
                    "wob" if numbers[f"fig11{p}"]["vary"] == "wob" else "torque"
                ),
                "fold": (numbers[f"fig11{p}"]["fold"] or {}).get(
                    "wob" if numbers[f"fig11{p}"]["vary"] == "wob" else "torque"
                ),
            }
            for p in "abcd"
        },
        "hopf_crossings": {
            k: numbers[k]["summary"]["hopf"] for k in numbers if k.startswith("pipes")
        },
    }


EPILOG = """\
what it does:
  Recomputes every figure of the paper's Sections 3-4 (Figs. 4, 5, 6b, 7, 8, 9, 10a-b, 11a-d,
  12a-b) with pydrill, draws each as a PNG, and writes DIR/report.md: per figure, what the
  paper states, what pydrill computed (regimes, stick-slip periods, Hopf and fold points and
  their criticality) and where and why they differ (including the paper's typos). Beyond the
  paper: Figs. 11 and 12 for 10, 100 and 500 pipes, the multiple Hopf crossings for n' > 3,
  and the first Lyapunov coefficient of every Hopf point.

reuse:
  Atlases (DIR/atlases/*.h5) and analysis results (DIR/cache/*.json) are kept and reused
  when the same computation is asked again (keyed by the sweep spec or the section's
  arguments and the pydrill version); an interrupted run resumes. --force starts over.

time:
  a minute or two on 2 cores from scratch (the 500-pipe string takes a third of it), much
  less when everything is cached; --quick (coarser grids, no 100/500 pipes) less still.
  README.md gives the times measured.

examples:
  pydrill reproduce --out paper/            # then read paper/report.md
  pydrill reproduce --out paper/ --json     # summary and key numbers for scripts
  pydrill reproduce --out /tmp/p --quick    # a fast check
  pydrill reproduce --out paper/ --scheduler tcp://host:8786   # sweeps on a Dask cluster
"""


def register_reproduce(sub) -> None:
    import argparse

    from .cli_options import _whole

    rep = sub.add_parser(
        "reproduce",
        help="recompute the paper's figures and write a report comparing the numbers",
        description="Recompute Navarro-Lopez & Cortes (2007), Sections 3-4, with pydrill: "
        "every figure as a PNG and DIR/report.md comparing the paper's statements with "
        "pydrill's numbers.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    rep.add_argument("--out", required=True, metavar="DIR", help="output directory (created)")
    rep.add_argument(
        "--quick", action="store_true", help="coarser atlases and no 100/500-pipe strings"
    )
    rep.add_argument("--force", action="store_true", help="ignore what DIR already holds")
    rep.add_argument(
        "--workers",
        metavar="N",
        type=_whole("--workers", "1 ... 256"),
        help="Dask worker processes (default: one per core it may use)",
    )
    rep.add_argument("--scheduler", metavar="ADDRESS", help="use an existing Dask scheduler")
    rep.add_argument("--json", action="store_true", help="print one JSON summary for scripts")
    rep.add_argument(
        "--no-progress", action="store_true", help="no progress bar (it goes to stderr)"
    )
    rep.set_defaults(handler=_cmd_reproduce)


def _cmd_reproduce(args) -> int:
    if args.workers is not None and not 1 <= args.workers <= 256:
        raise ValueError(f"--workers = {args.workers} is not allowed: 1 ... 256")
    summary = reproduce(
        args.out,
        quick=args.quick,
        force=args.force,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=False if args.no_progress else None,
    )
    if args.json:
        from .cli_options import json_document, print_json

        # Laid out as every other command's --json: what it was given, then what it made.
        results = _plain(summary)
        inputs = {"out": results.pop("out"), "quick": results.pop("quick"), "force": args.force}
        units = {"wall_time": "s"}
        print_json(json_document(inputs, results, units))
        return 0
    h = summary["highlights"]
    print(f"{summary['report']}: {len(summary['figures'])} figures, {summary['wall_time']:.0f} s")
    print(
        f"  Fig. 4  {h['fig4_regime']}, period {h['fig4_period_s']:.4g} s, "
        f"bit up to {h['fig4_bit_max_rad_s']:.4g} rad/s"
    )
    print(
        f"  Fig. 7  {h['fig7_regime']};  Fig. 9  {h['fig9_regime']} at "
        f"{h['fig9_omega_rad_s']:.4g} rad/s"
    )
    print(
        f"  Fig. 10 Hopf at delta = {h['fig10a_hopf_delta']:.5g} (Eq. 14), "
        f"{h['fig10b_hopf_delta']:.5g} N m s/rad (Eq. 53)"
    )
    reused = [k for k, v in summary["atlases"].items() if v == "reused"]
    print(
        f"  reused {len(reused)} of {len(summary['atlases'])} atlases and "
        f"{len(summary['cache']['reused'])} cached analyses"
    )
    return 0
