"""pydrill — stick-slip, stuck bits and steady drilling of torsional drillstring models.

The physics and its corrections to the paper are in DESIGN.md; the fast work runs in the C++
core (``pydrill._core``), which this package re-exports with documentation and plain data.
"""

from . import _core, stability, units
from ._core import SolverError
from .atlas import Atlas
from .model import PRESETS, Params, preset
from .simulate import REGIMES, SimulationResult, SolverStats, Summary, Switch, simulate
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
    """Every steady bit velocity Ω > 0 (rad/s) at which ``torque`` balances the string."""
    return list(_core.equilibrium_velocities(params.to_core(), float(wob), float(torque)))


def equilibrium_torque(params: Params, wob: float, omega: float) -> float:
    """Surface torque (N·m) that keeps the whole string turning at ``omega`` rad/s."""
    return float(_core.equilibrium_torque(params.to_core(), float(wob), float(omega)))


__all__ = [
    "PRESETS",
    "REGIMES",
    "Atlas",
    "AtlasError",
    "ClusterInfo",
    "Params",
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
    "parse_spec",
    "plan_sweep",
    "preset",
    "run_sweep",
    "simulate",
    "stability",
    "units",
]
