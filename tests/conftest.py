import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(scope="session")
def paper_dof4():
    """The paper's three dof-4 cases at u = 8.3 N·m from rest (Figs. 4, 7, 9)."""
    import pydrill

    return {
        wob: pydrill.simulate(wob=wob, torque=8.3, dof=4, t_end=300.0)
        for wob in (40.0, 100.0, 160.0)
    }
