"""What an atlas swept with ``[record] stability = false`` says of a point's steady states:
not recorded (None, null, a line saying so), never the empty lists that mean "this point has
no steady state" in an atlas that recorded them."""

import json
import subprocess

from sweeping import CMD

import pydrill
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# 100 N, 8 N·m: one steady state (15.8 rad/s); 150 N: none (u below the Coulomb torque).
SPEC = """
[model]
preset = "reduced-scale"
dof = 3
[axes]
wob = [100.0, 150.0]
torque = [8.0]
[simulation]
t_end = 20.0
initial = ["rest"]
"""


def test_steady_states_not_recorded_are_none_not_an_empty_list(tmp_path):
    blind, seeing = tmp_path / "blind.h5", tmp_path / "seeing.h5"
    run_sweep(parse_spec(SPEC + "[record]\nstability = false\n"), blind, serial=True)
    run_sweep(parse_spec(SPEC), seeing, serial=True)
    params = pydrill.preset("reduced-scale", dof=3)
    with pydrill.Atlas(blind) as a, pydrill.Atlas(seeing) as b:
        for wob in (100.0, 150.0):
            # the reference: the steady states pydrill.stability finds there
            direct = [p.omega for p in pydrill.stability.stability(params, wob, torque=8.0)]
            assert b.value(wob=wob)["stability"]["omega_eq"] == direct
            assert a.value(wob=wob)["stability"] is None  # was [] at 100 N: "none"
        assert direct == []  # (150 N: the recorded atlas's [] is a true "none")
    proc = subprocess.run(
        [*CMD, "atlas", "query", str(blind), "--wob", "100"], capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stderr
    assert "steady states: not recorded ([record] stability = false)" in proc.stdout
    proc = subprocess.run(
        [*CMD, "atlas", "query", str(blind), "--wob", "100", "--json"],
        capture_output=True,
        text=True,
    )
    data = json.loads(proc.stdout)
    assert data["stability"] is None and data["safe"] is None
