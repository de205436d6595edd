"""A sweep whose torque axis turns the string backwards (u < 0): the atlas must hold the
mirror image (φ → −φ) of u > 0, its steady states fastest first by |Ω|, so that 'the fastest
steady state' of `safe`, the maps and the profiles is the same steady state either way."""

import numpy as np

import pydrill
from pydrill.spec import parse_spec
from pydrill.sweep import run_sweep

# At (130 N, ±8.3 N·m) the laboratory string has two steady states, |Ω| = 9.47 rad/s (stable)
# and 0.98 rad/s (unstable); from near the fast one the bit drills on.
SPEC = """
[model]
preset = "reduced-scale"
dof = 4
[axes]
wob = [130.0]
torque = [-8.3, 8.3]
[simulation]
t_end = 30.0
initial = ["equilibrium"]
"""


def test_backwards_torque_is_the_mirror_image_fastest_first(tmp_path):
    path = tmp_path / "backwards.h5"
    run_sweep(parse_spec(SPEC), path, serial=True)
    params = pydrill.preset("reduced-scale", dof=4)
    with pydrill.Atlas(path) as atlas:
        ds = atlas.to_xarray()
        omega = ds.omega_eq.sel(wob=130.0).load()
        abscissa = ds.spectral_abscissa.sel(wob=130.0).load()
        safe = atlas.safe_region()[0]
        ds.close()
    # The reference: pydrill.stability at each torque, its steady states ordered by |Ω|.
    for u in (-8.3, 8.3):
        direct = sorted(
            pydrill.stability.stability(params, 130.0, torque=u), key=lambda p: -abs(p.omega)
        )
        assert len(direct) == 2
        np.testing.assert_allclose(
            omega.sel(torque=u).values, [p.omega for p in direct], rtol=1e-12
        )
        assert abscissa.sel(torque=u).values[0] < 0  # the fast one is the stable one
    # The mirror: Ω → −Ω in the same order, and the same verdict (the old order made u < 0
    # unsafe: its "fastest" was the unstable 0.98 rad/s).
    np.testing.assert_allclose(omega.sel(torque=-8.3).values, -omega.sel(torque=8.3).values)
    assert safe.tolist() == [True, True]
