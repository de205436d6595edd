"""What makes one sweep spec another sweep: ``SweepSpec.differences``, key by key, in words
an atlas's refusal can show ("simulation.t_end: 300 here, 100 there")."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .spec import SweepSpec

_NONE = object()  # a key one spec has and the other does not


def spec_differences(mine: SweepSpec, other: SweepSpec) -> list[str]:
    """What makes ``other`` another sweep than ``mine``, key by key (the parsed content, as
    the digest)."""

    def flat(spec: SweepSpec) -> dict[str, Any]:
        out: dict[str, Any] = {"model.preset": spec.preset, "model.dof": spec.dof}
        out |= {f"model.{k}": v for k, v in spec.overrides.items()}
        out |= {f"model.{k}": v for k, v in spec.fixed.items()}
        out |= {f"axes.{k}": v.astype(float).tolist() for k, v in spec.axes.items()}
        out |= {f"simulation.{k}": v for k, v in spec.simulation.items()}
        out |= {f"record.{k}": v for k, v in spec.record.items()}
        out["model.tally"] = spec.tally_text is not None and hash(spec.tally_text)
        out["model.lump"] = spec.lump
        return out

    def show(key: str, v: Any) -> str:
        from .atlas_grid import grid_unit, with_unit

        if v is _NONE:
            return "not set"
        section, _, name = key.partition(".")
        # An axis's values, and a fixed W_ob, torque or depth, with their unit (as atlas
        # info gives them): "21 values 20000 ... 120000" read as nothing in particular.
        if section == "axes" and isinstance(v, list):
            unit = grid_unit(name, v)
            shown = [with_unit(name, x, unit) for x in v]
            if len(v) > 4:
                return f"{len(v)} values {shown[0]} ... {shown[-1]}"
            return f"[{', '.join(shown)}]"
        if section == "model" and name in ("wob", "torque", "depth"):
            return with_unit(name, v)
        if isinstance(v, list) and len(v) > 4:
            return f"{len(v)} values {v[0]:g} ... {v[-1]:g}"
        return str(v)

    a, b = flat(mine), flat(other)
    changed = []
    for key in [*a, *(k for k in b if k not in a)]:
        x, y = a.get(key, _NONE), b.get(key, _NONE)
        if x != y:
            what = (
                "differs" if key == "model.tally" else f"{show(key, x)} here, {show(key, y)} there"
            )
            changed.append(f"{key}: {what}")
    return changed
