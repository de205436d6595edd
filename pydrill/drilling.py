"""Drilling ahead: the string grows by a stand at every connection, the motion carries over.

Between connections the bit advances at the rate of penetration with the string fixed; when
the drilled length reaches one more stand (``lump`` drill-pipe joints), a new element is added
at the top of the drill pipe, just below the top drive. The new state keeps every velocity
and twist; the new stand turns with the top drive and is twisted so that it carries exactly
the torque the top spring carried (torque is continuous through the connection).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from .simulate import simulate
from .tally import Tally, TallyError


@dataclass(frozen=True)
class DrillingRun:
    t: NDArray[np.float64]  #: s
    depth: NDArray[np.float64]  #: bit depth, m
    top_velocity: NDArray[np.float64]  #: rad/s
    bit_velocity: NDArray[np.float64]  #: rad/s
    connections: list[tuple[float, float, int]]  #: (t, depth, dof after) at each connection
    regimes: list[tuple[float, float, str]]  #: (start depth, end depth, regime) per stand
    #: (state just before, state just after) each connection, in twist coordinates
    carried: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = field(default_factory=list)
    #: the string of each stand, top spring first (for energies and torques of ``carried``)
    strings: list = field(default_factory=list)


def add_stand(state: NDArray[np.float64], k_top: float, k_new: float) -> NDArray[np.float64]:
    """Twist-coordinate state after inserting a stand of stiffness ``k_new`` below the top
    drive: the stand turns with the top drive and carries the top spring's elastic torque."""
    y = np.asarray(state, dtype=float)
    theta_new = k_top * y[1] / k_new
    return np.concatenate([[y[0], theta_new, y[0]], y[1:]])


def drill_ahead(
    tally: Tally,
    *,
    depth_start: float,
    depth_end: float,
    rop: float,
    wob: float,
    torque: float,
    lump: int = 1,
    initial: str | NDArray[np.float64] = "rest",
    n_out_per_stand: int = 200,
    **options,
) -> DrillingRun:
    """Simulate drilling from ``depth_start`` to ``depth_end`` (m) at ``rop`` (m/s), W_ob ``wob``
    (N) and surface torque ``torque`` (N·m) held; ``initial`` is ``"rest"``, ``"equilibrium"`` or
    a twist-coordinate state of the string at ``depth_start``."""
    if not rop > 0:
        raise ValueError(f"rop = {rop!r} is not allowed: the rate of penetration must be > 0")
    if not depth_end > depth_start:
        raise ValueError("depth_end must be deeper than depth_start")
    string = tally.at_depth(depth_start)
    pipe_index = next(i for i, s in enumerate(string.sections) if s.kind == "drill-pipe")
    pipe = string.sections[pipe_index]
    stand = pipe.length * lump
    depth = string.length
    state: NDArray[np.float64] | str = initial
    t0 = 0.0
    before = np.empty(0)
    ts, ds, tops, bits, regimes, carried, strings = [], [], [], [], [], [], []
    connections: list[tuple[float, float, int]] = []
    while depth < depth_end - 1e-9:
        params = string.to_params(lump=lump)
        strings.append(params)
        seg = min(stand, depth_end - depth)
        duration = seg / rop
        r = simulate(
            params,
            wob=wob,
            torque=torque,
            t_end=duration,
            initial=state,
            n_out=n_out_per_stand,
            **options,
        )
        if connections:  # the state the new string actually started from
            carried.append((before, np.array(r.states[0])))
        ts.append(t0 + r.t)
        ds.append(depth + rop * r.t)
        tops.append(np.array(r.top_velocity))
        bits.append(np.array(r.bit_velocity))
        regimes.append((depth, depth + seg, r.regime))
        t0 += duration
        depth += seg
        if depth >= depth_end - 1e-9:
            break
        # Connection: one more stand of drill pipe at the top of the string.
        sections = list(string.sections)
        sections[pipe_index] = replace(pipe, count=sections[pipe_index].count + lump)
        string = replace(string, sections=tuple(sections))
        k_new = pipe.joint_stiffness() / lump
        state = add_stand(r.states[-1], params.stiffnesses[0], k_new)
        before = np.array(r.states[-1])
        connections.append((t0, depth, params.dof + 1))
    if not ts:
        raise TallyError("nothing to drill")
    return DrillingRun(
        np.concatenate(ts),
        np.concatenate(ds),
        np.concatenate(tops),
        np.concatenate(bits),
        connections,
        regimes,
        carried,
        strings,
    )
