"""How a sweep's points are dealt out in batches, sized by count and by measured time.

A batch is one Dask task: big enough to hide Dask's per-task cost (~1-5 ms of scheduling and
transfer), small enough that the progress bar moves, that an interruption or a lost worker
costs little recomputation, and that at the end no worker waits long for the others. For
cheap points (a dof-4 string: ~1.5 ms) a count does it: 16 ... 256 points. A string of
hundreds of inertias takes a tenth of a second a point or more, and 256 of them make a batch
of minutes. So a batch stops after ``BATCH_SECONDS`` of work (``evaluate_batch``'s
``budget``) and hands back the points it did not reach, which are dealt again in batches
sized by the time the points have taken so far.
"""

from __future__ import annotations

import math

import numpy as np

#: the longest a batch computes (s) before it hands back the points it did not reach: the
#: progress bar moves, and an interruption or a lost worker recomputes little
BATCH_SECONDS = 5.0
#: the shortest a batch should take (s): Dask's per-task cost stays a few per cent of it
LEAST_SECONDS = 0.1


def dealing_order(indices: np.ndarray) -> np.ndarray:
    """The points in the order a sweep deals them out: a fixed pseudo-random permutation, so
    that any first part of it samples the whole grid."""
    return np.asarray(indices)[np.random.default_rng(0).permutation(len(indices))]


class Batcher:
    """Deals the points ``indices`` out in batches of decreasing size ("guided" scheduling):
    each takes 1/(2 x workers) of what is left, between ``smallest`` and ``largest`` points.
    Once ``timed`` has been told what batches took, at most ``BATCH_SECONDS`` of work (down to
    one point), and the least is ``smallest`` points or ``LEAST_SECONDS`` of work, whichever
    is fewer points: slow points make batches of fewer than ``smallest``, cheap ones do not
    make them bigger (16 points of 1 ms are a 16 ms batch: only the last few batches are so
    small, and a big last batch would leave a worker idle). Big early batches hide Dask's per-task
    overhead (measured: 8 batches of 250 points ran a 2000-point sweep 15 % faster than 125
    of 16); small last ones let every worker finish within a few points of the others. The
    points are dealt in ``dealing_order``, so every batch samples the whole grid and costs
    about its size: no worker draws a batch of slow stick-slip points. Points a batch did not
    reach are handed back (``give_back``) and dealt again before the others."""

    def __init__(self, indices: np.ndarray, largest: int = 256, smallest: int = 16) -> None:
        self.order = dealing_order(indices)
        self.dealt = 0
        self.returned: list[int] = []  # handed back, dealt first
        self.largest, self.smallest = largest, smallest
        self.points = 0  # timed so far
        self.seconds = 0.0

    @property
    def left(self) -> int:
        """Points not dealt yet."""
        return len(self.returned) + len(self.order) - self.dealt

    def give_back(self, indices: list[int] | np.ndarray) -> None:
        """Points dealt that were not computed (a batch out of time): to deal again."""
        self.returned.extend(int(i) for i in indices)

    def timed(self, points: int, seconds: float) -> None:
        """A batch of ``points`` took ``seconds`` to compute (on a worker, or here)."""
        self.points += points
        self.seconds += seconds

    @property
    def point_seconds(self) -> float | None:
        """The mean time of a point over the batches timed so far (None before any)."""
        return self.seconds / self.points if self.points and self.seconds > 0 else None

    def size(self, workers: int) -> int:
        """How many points the next batch takes, with ``workers`` sharing the rest."""
        hi, lo = self.largest, self.smallest
        cost = self.point_seconds
        if cost is not None:
            hi = max(1, min(hi, math.floor(BATCH_SECONDS / cost)))
            lo = max(1, min(lo, hi, math.ceil(LEAST_SECONDS / cost)))
        return min(self.left, hi, max(lo, math.ceil(self.left / (2 * max(workers, 1)))))

    def take(self, workers: int, size: int | None = None) -> list[int]:
        """The next batch (``size`` points, or as ``size(workers)`` says); [] when all are
        dealt."""
        n = min(self.left, self.size(workers) if size is None else size)
        batch, self.returned = self.returned[:n], self.returned[n:]
        n -= len(batch)
        batch += self.order[self.dealt : self.dealt + n].tolist()
        self.dealt += n
        return batch

    def rest(self, workers: int) -> list[list[int]]:
        """Every batch still to deal, sized now."""
        out = []
        while self.left:
            out.append(self.take(workers))
        return out


def batches(
    indices: np.ndarray, workers: int, largest: int = 256, smallest: int = 16
) -> list[list[int]]:
    """All of ``indices`` in batches sized by count alone (see ``Batcher``)."""
    return Batcher(indices, largest, smallest).rest(workers)
