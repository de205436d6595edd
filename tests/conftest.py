import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")
# A tester's own cluster (sweeps go where DASK_SCHEDULER_ADDRESS points, as any Dask client's
# work does) is not the one these tests start; the tests that want it set it themselves.
os.environ.pop("DASK_SCHEDULER_ADDRESS", None)


@pytest.fixture(scope="session")
def paper_dof4():
    """The paper's three dof-4 cases at u = 8.3 N·m from rest (Figs. 4, 7, 9)."""
    import pydrill

    return {
        wob: pydrill.simulate(wob=wob, torque=8.3, dof=4, t_end=300.0)
        for wob in (40.0, 100.0, 160.0)
    }
