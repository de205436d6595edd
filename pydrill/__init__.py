"""pydrill — stick-slip, stuck bits and steady drilling of torsional drillstring models.

The physics and its corrections to the paper are in DESIGN.md; the fast work runs in the C++
core (``pydrill._core``), which this package re-exports with documentation and plain data.
"""

from . import _core, stability, units
from ._core import SolverError
from .atlas import Atlas
from .atlas_grid import CoordinateError
from .atlas_merge import MergeReport, merge_atlases
from .atlas_safe import SafeRow
from .model import MAX_LOAD, PRESETS, Params, _load, _number, preset
from .simulate import (
    MAX_T_END,
    MODES,
    REGIMES,
    SimulationResult,
    SolverStats,
    Summary,
    Switch,
    simulate,
)
from .spec import SpecError, SweepSpec, load_spec, parse_spec
from .sweep import AtlasError, ClusterInfo, SchedulerError, SweepInterrupted, SweepReport, run_sweep
from .sweep_plan import SweepPlan, plan_sweep
from .tally import Tally, TallyError, load_tally

__version__: str = _core.__version__

SolverError.__doc__ = """The integrator failed (too many steps, error test failures, switch storms).

A ``RuntimeError`` raised by :func:`simulate` with the integrator's message; its ``t_reached``
attribute is the simulated time (s) reached before the failure. The command line reports it
with exit status 3.
"""


def equilibrium_velocities(params: Params, wob: float, torque: float) -> list[float]:
    """Every steady velocity Ω (rad/s) at which the surface ``torque`` (N·m, finite) balances
    the string under ``wob`` (N, finite, > 0): 0, 1 or 2 of them, in increasing order. Both
    at most ``MAX_LOAD`` (1e15) in size, as in :func:`simulate`.

    A negative torque turns the string backwards, the mirror image (φ → −φ) of ``-torque``:
    its steady states are those of ``-torque`` reversed, Ω → −Ω (so still in increasing
    order, as :func:`pydrill.stability.stability` and a simulation's ``omega_equilibrium``
    give them).

    >>> p = preset("reduced-scale", dof=4)
    >>> [round(w, 4) for w in equilibrium_velocities(p, 130, 8.3)]
    [0.9805, 9.4696]
    >>> [round(w, 4) for w in equilibrium_velocities(p, 130, -8.3)]
    [-9.4696, -0.9805]
    """
    core = stability._params(params).to_core()
    # Beyond MAX_LOAD (as simulate and stability refuse them): 1e308 N·m answered 1.3e308 rad/s.
    wob = _load("wob", _number("wob", wob, "N"), "N")
    torque = _load("torque", _number("torque", torque, "N·m"), "N·m")
    omegas = list(_core.equilibrium_velocities(core, wob, abs(torque)))
    return [-w for w in reversed(omegas)] if torque < 0 else omegas


def equilibrium_torque(params: Params, wob: float, omega: float) -> float:
    """Surface torque (N·m) that keeps the whole string turning at ``omega`` rad/s (finite,
    not 0) under ``wob`` (N, finite, > 0). A negative ``omega`` turns it backwards: the torque
    of ``-omega`` reversed (the inverse of :func:`equilibrium_velocities` either way). ``wob``
    and the torque are at most ``MAX_LOAD`` (1e15) in size, as in :func:`simulate`: an
    ``omega`` that needs more is refused."""
    core = stability._params(params).to_core()
    wob = _load("wob", _number("wob", wob, "N"), "N")
    omega = stability._velocity(omega)
    held = float(_core.equilibrium_torque(core, wob, abs(omega)))
    if held > MAX_LOAD:  # (1e308 rad/s of the real string answered inf)
        raise ValueError(
            f"omega = {omega:g} is not allowed at wob = {wob:g} N: its steady state needs a "
            f"torque of {held:.3g} N·m, beyond MAX_LOAD (1e15)"
        )
    return -held if omega < 0 else held


# (MODES and MAX_T_END live here too: ``pydrill.simulate`` is the function, not its module.)
__all__ = [
    "MAX_T_END",
    "MODES",
    "PRESETS",
    "REGIMES",
    "Atlas",
    "AtlasError",
    "ClusterInfo",
    "CoordinateError",
    "MergeReport",
    "Params",
    "SafeRow",
    "SchedulerError",
    "SimulationResult",
    "SolverError",
    "SolverStats",
    "SpecError",
    "Summary",
    "SweepInterrupted",
    "SweepPlan",
    "SweepReport",
    "SweepSpec",
    "Switch",
    "Tally",
    "TallyError",
    "equilibrium_torque",
    "equilibrium_velocities",
    "load_spec",
    "load_tally",
    "merge_atlases",
    "parse_spec",
    "plan_sweep",
    "preset",
    "run_sweep",
    "simulate",
    "stability",
    "units",
]
