"""check_workers on what Dask's ``client.run(..., on_error="return")`` answers: a version, the
probe's own exception (pydrill cannot be imported there), or the scheduler's failure to reach
a worker that has just left (an OSError: Dask's CommClosedError, a connect timeout)."""

import pytest
from distributed.comm.core import CommClosedError

from pydrill import __version__
from pydrill.sweep import SchedulerError
from pydrill.sweep_dask import check_workers


class FakeClient:
    """Answers client.run as a scheduler with these workers would."""

    def __init__(self, answers):
        self.answers = answers
        self.scheduler = type("S", (), {"address": "tcp://10.0.0.1:8786"})()

    def run(self, function, on_error):
        assert on_error == "return" and callable(function)
        assert function() == __version__  # the probe itself imports pydrill here
        return dict(self.answers)


GONE = [
    CommClosedError("in <TCP (closed) Scheduler Broadcast local=tcp://10.0.0.1:8786>"),
    OSError("Timed out trying to connect to tcp://10.0.0.3:4000 after 30 s"),
]


@pytest.mark.parametrize("gone", GONE, ids=["comm-closed", "connect-timeout"])
def test_a_worker_that_left_before_the_probe_is_not_said_to_lack_pydrill(gone):
    """A batch job's worker reaching its time limit between the count and the probe: the
    sweep went on being refused with "1 of 2 Dask workers ... cannot import pydrill"."""
    check_workers(FakeClient({"tcp://10.0.0.2:4000": __version__, "tcp://10.0.0.3:4000": gone}))
    check_workers(FakeClient({"tcp://10.0.0.3:4000": gone}))  # none left: the sweep waits


@pytest.mark.parametrize("gone", GONE, ids=["comm-closed", "connect-timeout"])
def test_a_worker_without_pydrill_is_refused_beside_one_that_left(gone):
    answers = {
        "tcp://10.0.0.2:4000": ModuleNotFoundError("No module named 'pydrill'"),
        "tcp://10.0.0.3:4000": gone,
        "tcp://10.0.0.4:4000": __version__,
    }
    with pytest.raises(SchedulerError) as caught:
        check_workers(FakeClient(answers))
    said = str(caught.value)
    assert said.startswith("1 of 2 Dask workers at tcp://10.0.0.1:8786 cannot import pydrill")
    assert "tcp://10.0.0.2:4000: ModuleNotFoundError: No module named 'pydrill'" in said


def test_another_version_beside_one_that_left_is_refused():
    answers = {"tcp://10.0.0.2:4000": "0.0.1", "tcp://10.0.0.3:4000": GONE[0]}
    with pytest.raises(SchedulerError, match=r"run pydrill 0\.0\.1, this client "):
        check_workers(FakeClient(answers))
