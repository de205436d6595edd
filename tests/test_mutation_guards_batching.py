"""Mutation guards for how a sweep deals its points out (pydrill.batching) and for the dry
run's arithmetic (pydrill.sweep_plan): the batch sizes against the documented rules worked
out by hand, and the plan's estimate on a virtual clock whose every reading the test knows,
so that the mean, the 95 % range, the budget and the encoding share are hand computations."""

import math
import statistics
from types import SimpleNamespace

import numpy as np
import pytest
from sweeping import SMALL

import pydrill.sweep
import pydrill.sweep_plan
import pydrill.sweep_points
from pydrill.batching import BATCH_SECONDS, Batcher, batches, dealing_order
from pydrill.spec import parse_spec
from pydrill.sweep_plan import SweepPlan, plan_sweep

# -- pydrill.batching -------------------------------------------------------------------------


@pytest.mark.parametrize(("n", "workers", "largest", "smallest"), [(997, 3, 64, 5), (40, 1, 8, 3)])
def test_batches_follow_the_guided_rule_worked_out_by_hand(n, workers, largest, smallest):
    """Each batch is ceil(left / (2 x workers)) clamped to [smallest, largest], never more
    than is left; every point once, in the dealing order."""
    todo = np.arange(100, 100 + n)
    parts = batches(todo, workers, largest, smallest)
    left, expected = n, []
    while left:
        expected.append(min(left, largest, max(smallest, -(-left // (2 * workers)))))
        left -= expected[-1]
    assert [len(b) for b in parts] == expected
    assert [i for b in parts for i in b] == dealing_order(todo).tolist()


def test_the_size_of_the_next_batch_is_never_more_than_is_left():
    # size() is what the next batch takes: 5 points left make a batch of 5, not `smallest`
    assert Batcher(np.arange(5)).size(2) == 5
    deal = Batcher(np.arange(40))
    deal.take(2, size=37)
    assert deal.left == 3 and deal.size(4) == 3 == len(deal.take(4))


def test_a_batch_asked_for_more_than_is_left_takes_what_is_left():
    deal = Batcher(np.arange(30))
    first = deal.take(2, size=20)
    deal.give_back(first[15:])  # 5 handed back: 15 left
    rest = deal.take(2, size=1000)
    assert len(rest) == 15 and deal.left == 0 and deal.take(2) == [] and deal.rest(2) == []
    assert sorted(first[:15] + rest) == list(range(30))


def test_the_time_cap_is_the_most_points_that_fit_in_batch_seconds():
    """0.3 s a point: 16 points take 4.8 s <= BATCH_SECONDS = 5 s, 17 would take 5.1 s."""
    deal = Batcher(np.arange(10_000))
    deal.timed(3, 0.9)
    cost = 0.9 / 3
    size = deal.size(1)
    assert size * cost <= BATCH_SECONDS < (size + 1) * cost
    assert len(deal.take(1)) == size


def test_a_point_slower_than_a_batchs_time_makes_batches_of_one():
    deal = Batcher(np.arange(50))
    deal.timed(2, 4 * BATCH_SECONDS)  # 2 x BATCH_SECONDS a point
    assert deal.size(2) == 1
    assert [len(b) for b in deal.rest(2)] == [1] * 50


def test_the_cost_of_a_point_is_the_mean_over_every_batch_timed():
    deal = Batcher(np.arange(100))
    deal.timed(10, 1.0)
    deal.timed(30, 9.0)
    assert deal.point_seconds == pytest.approx(10.0 / 40)


# -- pydrill.sweep_plan on a virtual clock ----------------------------------------------------


@pytest.fixture(scope="module")
def small():
    spec = parse_spec(SMALL)
    return spec, {i: pydrill.sweep.evaluate_point(spec, i) for i in range(spec.size)}


def virtual(monkeypatch, small, cost, encode=0.0, fail=()):
    """Make the plan's clock virtual: evaluating point i takes cost(i) seconds of it, encoding
    a batch ``encode`` seconds a record; the points in ``fail`` fail with their own message."""
    spec, records = small
    clock = [0.0]

    def evaluate_point(spec, i):
        clock[0] += cost(i)
        rec = dict(records[i])
        if i in fail:
            rec.update(status="failed", message=f"point {i} failed")
        return rec

    def encode_batch(spec, recs):
        clock[0] += encode * len(recs)

    monkeypatch.setattr(pydrill.sweep_plan, "time", SimpleNamespace(perf_counter=lambda: clock[0]))
    monkeypatch.setattr(pydrill.sweep, "evaluate_point", evaluate_point)
    monkeypatch.setattr(pydrill.sweep_points, "encode_batch", encode_batch)
    return spec


#: the six points of SMALL in the order the plan times them
ORDER = dealing_order(np.arange(6)).tolist()


def test_the_estimate_is_the_mean_and_its_95_percent_range_by_hand(monkeypatch, small):
    """Four of six points timed at 1 ms, 1 ms, 1 ms and 10 s: the mean, and 1.96 standard
    errors (sample deviation, finite-population correction sqrt((n - k)/(n - 1))) either side,
    the low end held at 0; the encoding's 0.5 s a point added to each."""
    costs = dict.fromkeys(ORDER, 1e-3)
    costs[ORDER[3]] = 10.0
    spec = virtual(monkeypatch, small, costs.__getitem__, encode=0.5)
    plan = plan_sweep(spec, most=4, least=4, budget=1e9)
    times = [costs[i] + 0.5 for i in ORDER[:4]]
    mean = statistics.fmean(times)
    half = 1.96 * statistics.stdev(times) / math.sqrt(4) * math.sqrt((6 - 4) / (6 - 1))
    assert mean - half < 0  # the low end is clamped
    assert plan.sampled == 4 and plan.todo == 6
    assert plan.point_seconds == pytest.approx(mean, rel=1e-12)
    assert plan.point_seconds_high == pytest.approx(mean + half, rel=1e-12)
    assert plan.point_seconds_low == 0.0
    assert plan.compute_seconds == pytest.approx((0.0, 6 * mean, 6 * (mean + half)))


def test_every_point_timed_has_no_range_and_the_whole_journals_size(monkeypatch, small):
    spec = virtual(monkeypatch, small, lambda i: 0.25 * (1 + i))
    plan = plan_sweep(spec, most=100, budget=1e9)
    mean = statistics.fmean(0.25 * (1 + i) for i in range(6))
    assert plan.sampled == 6
    assert plan.point_seconds == plan.point_seconds_low == plan.point_seconds_high
    assert plan.point_seconds == pytest.approx(mean, rel=1e-12)
    lines = [pydrill.sweep_plan.journal_line(r) for r in small[1].values()]
    assert plan.journal_bytes == sum(len(x) for x in lines)


@pytest.mark.parametrize(
    ("least", "budget", "sampled"),
    # 1 s a point: the budget is spent after the third (3 s > 2.5 s), not after the point
    # that alone takes longer than it; `least` points are timed whatever the budget, and no
    # more than those when it is spent
    [(0, 2.5, 3), (0, 0.5, 1), (3, 0.5, 3), (5, 0.5, 5), (0, 1e9, 6)],
)
def test_the_sample_stops_once_the_budget_is_spent(monkeypatch, small, least, budget, sampled):
    spec = virtual(monkeypatch, small, lambda i: 1.0)
    assert plan_sweep(spec, least=least, budget=budget).sampled == sampled


def test_one_point_timed_of_several_has_no_range_rather_than_a_sure_one(monkeypatch, small):
    """A range from one point had zero width, as if the estimate were exact; the spread is
    unknown (one point of six, the budget spent by it), and every point timed has none."""
    spec = virtual(monkeypatch, small, lambda i: 1.0)
    plan = plan_sweep(spec, least=1, budget=0.5)
    assert plan.sampled == 1 and plan.todo == 6
    assert (plan.point_seconds_low, plan.point_seconds_high) == (0.0, math.inf)
    assert plan.point_seconds == pytest.approx(1.0)
    whole = plan_sweep(spec, least=6, budget=0.5)
    assert whole.point_seconds_low == whole.point_seconds_high == whole.point_seconds


def test_failures_are_counted_and_the_first_ones_message_kept(monkeypatch, small):
    spec = virtual(monkeypatch, small, lambda i: 1e-3, fail={ORDER[1], ORDER[2], ORDER[4]})
    plan = plan_sweep(spec, most=5, budget=1e9)
    assert plan.sampled == 5 and plan.failed == 3
    assert plan.message == f"point {ORDER[1]} failed"


def test_wall_time_divides_among_workers_and_refuses_bad_counts_by_type():
    plan = SweepPlan(10, 6, "none", 4, 0, "", 2.0, 1.0, 3.0, 0, 0)
    assert plan.wall_seconds(3) == pytest.approx((2.0, 4.0, 6.0))
    for bad, error in ((0, ValueError), (-2, ValueError), (1.5, TypeError), (True, TypeError)):
        with pytest.raises(error, match=r"workers = .* integer >= 1"):
            plan.wall_seconds(bad)


def test_a_resumed_plan_counts_the_journal_of_the_whole_grid(monkeypatch, small):
    """The journal at its largest holds a line for every point of the grid (those done before
    the resume too), not only for the points still to compute; the atlas's data is the whole
    table's fixed-size columns (the failure messages, variable-length strings, left out)."""
    from pydrill import atlas_format as fmt

    spec = virtual(monkeypatch, small, lambda i: 1e-3)
    todo = np.sort(ORDER[:3])
    monkeypatch.setattr(pydrill.sweep_plan, "_todo", lambda spec, out, resume: (todo, "resume"))
    plan = plan_sweep(spec, "unused.h5", most=100, budget=1e9)
    assert (plan.todo, plan.sampled, plan.atlas) == (3, 3, "resume")
    lines = sum(len(pydrill.sweep_plan.journal_line(small[1][i])) for i in todo)
    assert plan.journal_bytes == round(6 * lines / 3)
    table = fmt.AtlasTable(spec).columns()
    assert plan.atlas_bytes == sum(a.nbytes for a in table.values() if a.dtype != object)
