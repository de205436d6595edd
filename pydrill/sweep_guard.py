"""The batch task a sweep sends to a Dask cluster it did not start: a worker that joined after
the sweep checked the workers (``sweep_dask.check_workers``) is checked by each batch."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def guarded_batch(version: str) -> Callable[..., Any]:
    """``evaluate_batch`` for workers this process did not start, refusing (a dict, not a
    batch) on a worker without pydrill ``version``: ``check_workers`` asks only the workers
    there when the sweep starts, and one that joined later ran the sweep unasked: with
    another pydrill, into the same atlas; without pydrill, dying on its first batch while
    the sweep waited for ever. Defined here, the task is pickled by value, so a worker
    without pydrill unpickles it and says so; a refusal is returned, not raised, so that
    Dask does not retry it on another worker."""

    def evaluate_batch(*args: Any) -> Any:
        def worker() -> str:
            try:
                from distributed import get_worker

                return str(get_worker().address)
            except Exception:  # (not in a worker: a caller's own executor)
                return "?"

        try:
            import pydrill
        except Exception as exc:  # (ImportError, or anything its import raised)
            why = f"cannot import pydrill ({type(exc).__name__}: {exc})"
            return {"worker": worker(), "why": why}
        if pydrill.__version__ != version:
            why = f"runs pydrill {pydrill.__version__}, this client {version}"
            return {"worker": worker(), "why": f"{why}: one atlas must come from one version"}
        from pydrill.sweep import evaluate_batch as evaluate

        return evaluate(*args)

    return evaluate_batch


def refused(said: dict[str, str], where: str) -> Exception:
    """The ``SchedulerError`` for a batch refused by ``guarded_batch``'s worker."""
    from . import __version__
    from .sweep import SchedulerError

    exc = SchedulerError(
        f"the Dask worker {said['worker']} at {where}, which joined after the sweep checked "
        f"the workers, {said['why']}"
    )
    exc.then = (
        f"Install pydrill {__version__} where it runs (in the environment its 'dask worker' "
        "starts from), or stop it"
    )
    return exc
