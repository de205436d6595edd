"""Type stubs for the private C++ extension (use the pydrill package instead)."""

from typing import Any

import numpy as np
from numpy.typing import NDArray

__version__: str

class SolverError(RuntimeError):
    t_reached: float

class Params:
    inertias: list[float]
    stiffnesses: list[float]
    dampings: list[float]
    top_damping: float
    bit_damping: float
    bit_radius: float
    mu_coulomb: float
    mu_static: float
    stribeck_decay: float
    stribeck_velocity: float
    karnopp_band: float
    @property
    def dof(self) -> int: ...
    def validate(self) -> None: ...

class SimulationOptions:
    t_end: float
    t_out: list[float]
    n_out: int
    state: list[float]
    perturbation: float
    rtol: float
    atol: float
    max_step: float
    max_order: int
    max_steps: int
    window_fraction: float
    max_switch_rate: float
    method: str
    friction: str
    initial: str

class Result:
    dof: int
    wob: float
    torque: float
    t: NDArray[np.float64]
    states: NDArray[np.float64]
    top_angle: NDArray[np.float64]
    work_input: NDArray[np.float64]
    viscous_loss: NDArray[np.float64]
    friction_loss: NDArray[np.float64]
    energy: NDArray[np.float64]
    modes: NDArray[np.int32]
    switches: list[dict[str, Any]]
    stats: dict[str, Any]
    summary: dict[str, Any]

def preset(name: str, dof: int) -> Params: ...
def preset_names() -> list[str]: ...
def equilibrium_velocities(params: Params, wob: float, torque: float) -> list[float]: ...
def equilibrium_torque(params: Params, wob: float, omega: float) -> float: ...
def equilibrium_state(params: Params, wob: float, omega: float) -> list[float]: ...
def simulate(params: Params, wob: float, torque: float, options: SimulationOptions) -> Result: ...
def stiffness_ratio(params: Params) -> float: ...

class StiffnessEstimate:
    @property
    def fastest_decay(self) -> float: ...
    @property
    def fastest_frequency(self) -> float: ...
    @property
    def fundamental(self) -> float: ...

def estimate_stiffness(params: Params) -> StiffnessEstimate: ...
def mode_names() -> list[str]: ...

# stability (bind_stability.cpp): crossings and points as plain dicts, wrapped by
# pydrill.stability into Crossing and StabilityPoint
def stribeck_slope(params: Params, wob: float, omega: float) -> float: ...
def boundary_wob(params: Params, delta: float, omega: float) -> float: ...
def bit_impedance(params: Params, lam: complex) -> complex: ...
def jacobian(params: Params, delta: float) -> list[float]: ...
def eigenvalues(params: Params, delta: float) -> list[complex]: ...
def structured_eigenvalues(params: Params, delta: float) -> list[complex]: ...
def roots_of_impedance(params: Params, delta: float) -> list[complex] | None: ...
def characteristic_polynomial(params: Params, delta: float) -> list[float]: ...
def hurwitz_determinants(ascending: list[float]) -> list[float]: ...
def hopf_deltas_dof2(params: Params) -> list[float]: ...
def first_lyapunov_coefficient(params: Params, delta: float, frequency: float) -> float: ...
def critical_deltas(params: Params) -> list[dict[str, Any]]: ...
def stability_at_velocity(params: Params, wob: float, omega: float) -> dict[str, Any]: ...
def stability_at_torque(
    params: Params, wob: float, torque: float, crossings: list[dict[str, Any]] | None = None
) -> list[dict[str, Any]]: ...
