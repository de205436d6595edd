"""The "did you mean …?" of a message that refuses a name: a key in a spec or a tally, a
parameter, an option, a ``--set`` name. A typo is the commonest reason a name is unknown, and
the list of allowed names that the message gives as well is long."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def _one_edit(a: str, b: str) -> bool:
    """Whether ``a`` becomes ``b`` by one edit: a letter left out, added, changed, or two
    neighbours swapped ("bfd" for "bdf", which difflib's ratio, 0.67, does not find close)."""
    if a == b or abs(len(a) - len(b)) > 1:
        return False
    if len(a) == len(b):
        diff = [k for k in range(len(a)) if a[k] != b[k]]
        return len(diff) == 1 or (
            len(diff) == 2 and diff[1] == diff[0] + 1 and a[diff[0]] == b[diff[1]]
            and a[diff[1]] == b[diff[0]]
        )  # fmt: skip
    short, long = (a, b) if len(a) < len(b) else (b, a)
    k = next((k for k in range(len(short)) if short[k] != long[k]), len(short))
    return short[k:] == long[k + 1 :]


def did_you_mean(name: object, choices: Iterable[str]) -> str:
    """``" (did you mean 'torque'?)"`` for ``name`` within a typo or two of one of
    ``choices`` (the closest), else ``""``."""
    text, options = str(name), list(choices)
    close = difflib.get_close_matches(text, options, n=1, cutoff=0.7)
    if not close and len(text) >= 3:  # (two letters are one edit from too much)
        close = [c for c in options if _one_edit(text.lower(), c.lower())][:1]
    return f" (did you mean {close[0]!r}?)" if close else ""


def radius_hint(value: object, toml: bool = False) -> str:
    """For a bit's diameter given where its radius belongs (a tally's bit.diameter, typed to
    --set or a spec's [model]): the radius, half of it in the unit written,
    ``" (the bit is given by its radius: bit_radius=4.25in)"``; in a spec's words with
    ``toml`` (``bit_radius = "4.25 in"``)."""
    from .units import _NUMBER

    match = _NUMBER.match(value) if isinstance(value, str) else None
    if match:
        number, unit = float(match.group(1)) / 2, match.group(2)
    elif isinstance(value, int | float) and not isinstance(value, bool):
        number, unit = value / 2, ""
    else:
        return " (the bit is given by its radius: bit_radius)"
    if toml:
        half = f'"{number:g} {unit}"' if unit else f"{number:g}"
        return f" (the bit is given by its radius: bit_radius = {half})"
    return f" (the bit is given by its radius: bit_radius={number:g}{unit})"


#: names that mean a tally's element damping (its [damping] beta)
BETA_NAMES = ("beta", "damping.beta", "damping_beta", "β")


def meant_hint(name: object, law: str = "") -> str:
    """What a name no typo-hint serves most likely meant, for a spec's key: a friction
    coefficient (friction, mu: mu_coulomb and mu_static; ``law`` says where the friction law
    is picked, for "friction"), or a tally's beta, which is the tally's to set; else ""."""
    lower = str(name).lower()
    if lower in BETA_NAMES:
        return (
            " (beta is a tally's element damping, every element's c = beta·k: set it as "
            "beta in the [damping] table of the TALLY.toml)"
        )
    if "friction" in lower or lower.startswith("mu") or lower in ("coulomb", "static"):
        where = f"; {law} picks the friction law, 'exact' or 'karnopp'" if law else ""
        return (
            " (the bit's friction coefficients are mu_coulomb, sliding, and mu_static, at rest"
            f"{where})"
        )
    return ""


def key_hint(key: str, value: object, keys: Iterable[str]) -> str:
    """The "did you mean" of an unknown key of a spec's [model] (``keys`` its keys): one
    nearest a list of the chain says it is a list (top_inertia = 2500.0 was sent to
    'inertias', whose number is refused), and a bit's diameter the radius [model] takes."""
    if str(key).lower().endswith("diameter"):
        return radius_hint(value, toml=True)
    hint = did_you_mean(key, keys)
    for name, each in (("inertias", "inertia"), ("stiffnesses", "link"), ("dampings", "link")):
        if hint == f" (did you mean {name!r}?)":
            return f" (did you mean {name} = [...], a list of one value per {each}?)"
    # model.friction = 0.5, model.mu, model.beta: no typo, a name from elsewhere
    return hint or meant_hint(key, law="[simulation] friction" if key == "friction" else "")


def param_hint(name: object, choices: Iterable[str]) -> str:
    """The hint of the Python API's refusal of a model parameter ``name`` (``choices`` the
    allowed ones): a typo's "did you mean", else what a name from elsewhere meant, as the
    CLI's --set and a spec's [model] say it (preset(friction=0.5): the coefficients, and
    simulate's friction= picks the law; Params.replace(mu=...); beta, a tally's)."""
    law = "simulate(..., friction=...)" if str(name).lower() == "friction" else ""
    return did_you_mean(name, choices) or meant_hint(name, law=law)
