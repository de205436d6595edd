"""The rules of a sweep specification's [simulation] and [record] tables (``spec.parse_spec``
applies them, after ``spec_rules``'s of the model and axes): each key's allowed values and
defaults, each refusal a :class:`SpecError` naming the key."""

from __future__ import annotations

from typing import Any

from .spec_rules import (
    MAX_STEPS,
    RECORD_KEYS,
    SIMULATION_KEYS,
    _fail,
    _is_number,
    printable,
)
from .suggest import did_you_mean


def with_defaults(doc: dict[str, Any], section: str, defaults: dict[str, Any]) -> dict[str, Any]:
    """A table's values over its defaults; a key it does not know is refused."""
    unknown = [key for key in doc if key not in defaults]
    if unknown:
        raise _fail(
            f"{section}.{printable(unknown[0])}",
            "unknown" + did_you_mean(unknown[0], defaults) + "; allowed: " + ", ".join(defaults),
        )
    return {**defaults, **doc}


#: The simulator's tolerance floors and ceilings (kMinRtol, kMaxRtol, kMinAtol, kMaxAtol in
#: cpp/include/pydrill/simulator.hpp; tests/test_spec.py checks that simulate refuses just
#: beyond them and accepts them). Beyond the ceilings a step's error misjudges the regime.
RTOL_MIN, RTOL_MAX = 1e-14, 1e-2
ATOL_MIN, ATOL_MAX = 1e-20, 1e-3


def simulation(doc: dict[str, Any]) -> dict[str, Any]:
    from .simulate import MAX_T_END

    longest = f"{MAX_T_END:.0e}".replace("e+", "e")
    sim = with_defaults(doc, "simulation", SIMULATION_KEYS)
    initial = sim["initial"]
    if isinstance(initial, str):
        initial = [initial]
    if (
        not isinstance(initial, list)
        or not initial
        or any(i not in ("rest", "equilibrium") for i in initial)
        or len(set(initial)) != len(initial)
    ):
        raise _fail(
            "simulation.initial",
            f"{sim['initial']!r}: a list of distinct values from 'rest', 'equilibrium'",
        )
    sim["initial"] = initial
    # simulate's own ranges, so that a spec it would refuse at every point is refused here.
    for key, ok, allowed in (
        (
            "t_end",
            lambda v: 0 < v <= MAX_T_END,
            f"0 < t_end <= {longest} s (simulate's limit)",
        ),
        ("rtol", lambda v: RTOL_MIN <= v <= RTOL_MAX, f"{RTOL_MIN:g} <= rtol <= {RTOL_MAX:g}"),
        ("atol", lambda v: ATOL_MIN <= v <= ATOL_MAX, f"{ATOL_MIN:g} <= atol <= {ATOL_MAX:g}"),
    ):
        v = sim[key]
        if not _is_number(v) or not ok(v):
            raise _fail(
                f"simulation.{key}", f"{v!r} is not allowed: {_plain_number(key, v)}{allowed}"
            )
        sim[key] = float(v)
    # window and max_steps kept as written (1, not 1.0): the digest of existing specs with them.
    if not _is_number(sim["window"]) or not 0 < sim["window"] <= 1:
        window = sim["window"]
        raise _fail(
            "simulation.window",
            f"{window!r} is not allowed: {_plain_number('window', window)}0 < window <= 1",
        )
    steps = sim["max_steps"]
    if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps < MAX_STEPS:
        raise _fail(
            "simulation.max_steps",
            f"{steps!r} is not allowed: an integer >= 1 (below 2**62)",
        )
    if sim["friction"] not in ("exact", "karnopp"):
        # friction = 0.5: a coefficient given where the law is picked
        number = isinstance(sim["friction"], int | float) and not isinstance(sim["friction"], bool)
        coefficient = (
            " (the law; the bit's friction coefficients are [model] mu_coulomb, sliding, and "
            "mu_static, at rest)"
            if number
            else ""
        )
        raise _fail(
            "simulation.friction",
            f"{sim['friction']!r}: choose 'exact' or 'karnopp'{coefficient}",
        )
    if sim["method"] not in ("auto", "dop853", "bdf", "adams", "erk"):
        raise _fail(
            "simulation.method", f"{sim['method']!r}: choose auto, dop853, bdf, adams or erk"
        )
    return sim


def swept_in_vain(axes: dict[str, Any], sim: dict[str, Any]) -> None:
    """Refuse an axis that changes nothing with these [simulation] settings: every value of it
    computes the same points (karnopp_band swept with the exact friction law, which has no
    band, made an atlas of identical rows). Held in [model], it is only noted (cli_sweep)."""
    if "karnopp_band" in axes and sim["friction"] != "karnopp":
        raise _fail(
            "axes.karnopp_band",
            f"has no effect with [simulation] friction = {sim['friction']!r} (the band is the "
            "Karnopp law's): every value computes the same points; sweep it with friction = "
            "'karnopp', or remove the axis",
        )


def held_in_vain(spec: Any) -> list[str]:
    """Notes on what ``spec`` holds in [model] to no effect with its [simulation] settings:
    karnopp_band with the exact friction law (one value: nothing computed in vain, but the
    value set is not the one the runs use; ``swept_in_vain`` refuses it as an axis)."""
    law = spec.simulation["friction"]
    if "karnopp_band" in spec.overrides and law != "karnopp":
        return [
            f"model.karnopp_band has no effect with [simulation] friction = {law!r} (the band "
            "is the Karnopp law's); set friction = 'karnopp' to use it"
        ]
    return []


def _plain_number(key: str, value: Any) -> str:
    """For a string where a number belongs: that it takes a bare number (no unit parser
    reads these keys; "200 s" was refused as if out of range), ``""`` for anything else."""
    if not isinstance(value, str):
        return ""
    return "must be a number of seconds (no unit), " if key == "t_end" else "a number (no unit), "


def record(doc: dict[str, Any]) -> dict[str, Any]:
    rec = with_defaults(doc, "record", RECORD_KEYS)
    if not isinstance(rec["stability"], bool):
        raise _fail("record.stability", "true or false")
    if (
        isinstance(rec["eigenvalues"], bool)
        or not isinstance(rec["eigenvalues"], int)
        or not (0 <= rec["eigenvalues"] <= 64)
    ):
        raise _fail("record.eigenvalues", "an integer 0 ... 64")
    return rec
