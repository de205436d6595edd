#!/usr/bin/env python3
"""How often a 300 s run's regime is the one a run ten times longer finds.

    python tools/judge_agreement.py                   # seeds 1-30: 7376 runs, about 35 s
    python tools/judge_agreement.py --seeds 1-10 --preset real-string --wob 10000,200000

Random strings around a preset (each inertia, stiffness and element damping scaled by a
log-uniform factor, the end dampings and the friction law drawn at random), each at a random
(W_ob, u) with u between 0.3 and 1.5 times the static torque T_s, simulated from rest and from
equilibrium for 300 s and for 3000 s. The 3000 s run's window lies long after the 300 s run's
transients: where the two disagree, the 300 s judgement should carry a caveat (simulate
longer). Prints the counts and every disagreement without one.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math

import numpy as np

import pydrill


def _seeds(text: str) -> list[int]:
    first, _, last = text.partition("-")
    return list(range(int(first), int(last or first) + 1))


def random_string(rng: np.random.Generator, preset: str, dofs: tuple[int, int]) -> pydrill.Params:
    dof = 2 if preset == "real-string" else int(rng.integers(dofs[0], dofs[1] + 1))
    base = pydrill.preset(preset, dof=dof)

    def scaled(values: tuple[float, ...], lo: float, hi: float) -> tuple[float, ...]:
        factors = np.exp(rng.uniform(math.log(lo), math.log(hi), len(values)))
        return tuple(float(v) for v in np.array(values) * factors)

    mu_c = float(rng.uniform(0.2, 0.7))
    return dataclasses.replace(
        base,
        inertias=scaled(base.inertias, 0.3, 3),
        stiffnesses=scaled(base.stiffnesses, 0.3, 3),
        dampings=scaled(base.dampings, 0.1, 10),
        top_damping=scaled((base.top_damping,), 0.1, 3)[0],
        bit_damping=float(base.bit_damping * rng.uniform(0, 3)),
        mu_coulomb=mu_c,
        mu_static=float(mu_c + rng.uniform(0.05, 0.5)),
        stribeck_decay=float(np.exp(rng.uniform(math.log(0.3), math.log(3)))),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", default="1-30", help="seeds, e.g. 1-30 or 7 (default 1-30)")
    ap.add_argument("--strings", type=int, default=150, help="strings per seed (default 150)")
    ap.add_argument("--preset", default="reduced-scale", choices=pydrill.PRESETS)
    ap.add_argument("--dofs", default="2,6", help="least and most inertias (default 2,6)")
    ap.add_argument("--wob", default="20,200", help="W_ob range, N (default 20,200)")
    ap.add_argument("--json", metavar="FILE", help="write every run's verdicts there")
    args = ap.parse_args()
    dofs = tuple(int(x) for x in args.dofs.split(","))
    wob_lo, wob_hi = (float(x) for x in args.wob.split(","))
    runs = []
    for seed in _seeds(args.seeds):
        rng = np.random.default_rng(seed)
        for k in range(args.strings):
            p = random_string(rng, args.preset, dofs)  # type: ignore[arg-type]
            wob = float(rng.uniform(wob_lo, wob_hi))
            torque = float(rng.uniform(0.3, 1.5) * p.static_torque(wob))
            for initial in ("rest", "equilibrium"):
                try:
                    short, long = (
                        pydrill.simulate(
                            p, wob=wob, torque=torque, t_end=t, initial=initial, n_out=2
                        ).summary
                        for t in (300.0, 3000.0)
                    )
                except ValueError:  # no steady state to start from
                    continue
                runs.append(
                    {
                        "seed": seed, "string": k, "dof": p.dof, "wob": wob, "torque": torque,
                        "initial": initial, "at_300s": short.regime, "caveat": short.caveat,
                        "at_3000s": long.regime, "params": p.to_dict(),
                    }
                )  # fmt: skip
    differ = [r for r in runs if r["at_300s"] != r["at_3000s"]]
    silent = [r for r in differ if not r["caveat"]]
    print(
        f"{len(runs)} runs: the 300 s regime is the 3000 s one in {len(runs) - len(differ)}; "
        f"of the {len(differ)} others, {len(differ) - len(silent)} carry a caveat, "
        f"{len(silent)} do not"
    )
    for r in silent:
        print(
            f"  seed {r['seed']} string {r['string']} (dof {r['dof']}), W_ob {r['wob']:.4g} N, "
            f"u {r['torque']:.4g} N m, from {r['initial']}: {r['at_300s']} at 300 s, "
            f"{r['at_3000s']} at 3000 s"
        )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(runs, fh)


if __name__ == "__main__":
    main()
