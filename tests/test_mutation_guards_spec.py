"""Sweep spec axes and limits against their documented rules, with hand-computed values.

Found by a mutation audit of pydrill/spec_rules.py, spec.py and spec_parts.py: an axis from
start/stop/num that dropped its stop, a range or list left in the order given, repeated values
or a zero W_ob accepted, limits off by one, a mixed-unit range read silently, or a parameter
axis checked at its low end only, passed every other test.
"""

import re

import numpy as np
import pytest

from pydrill.spec import SpecError, parse_spec
from pydrill.spec_rules import MAX_DOF, MAX_POINTS

HEAD = '[model]\npreset = "reduced-scale"\ndof = 4\n[axes]\n'


def spec(axes: str, head: str = HEAD):
    """A spec of these [axes] lines (torque [6.0] and wob [50.0] unless given)."""
    lines = axes
    if not any(line.startswith("torque") for line in axes.splitlines()):
        lines += "\ntorque = [6.0]"
    if not any(line.startswith("wob") for line in axes.splitlines()):
        lines += "\nwob = [50.0]"
    return parse_spec(head + lines + "\n")


def refused(axes: str, match: str, head: str = HEAD) -> None:
    with pytest.raises(SpecError, match=match):
        spec(axes, head)


# -- ranges: start, stop and num --------------------------------------------------------------


def test_a_range_holds_start_and_stop_and_evenly_spaced_values_between():
    axes = spec("wob = { start = 20.0, stop = 200.0, num = 19 }").axes
    assert axes["wob"].tolist() == pytest.approx([20.0 + 10.0 * i for i in range(19)], abs=1e-12)
    assert axes["wob"][0] == 20.0 and axes["wob"][-1] == 200.0


def test_a_range_given_from_the_top_down_is_the_same_increasing_grid():
    down = spec("wob = { start = 200.0, stop = 20.0, num = 4 }")
    up = spec("wob = { start = 20.0, stop = 200.0, num = 4 }")
    assert down.axes["wob"].tolist() == [20.0, 80.0, 140.0, 200.0]
    assert down.digest == up.digest


def test_a_list_is_sorted_and_its_repeats_refused():
    assert spec("wob = [160.0, 40.0, 100.0]").axes["wob"].tolist() == [40.0, 100.0, 160.0]
    assert spec('wob = ["0.1 kN", 40.0]').axes["wob"].tolist() == [40.0, 100.0]
    refused("wob = [40.0, 100.0, 40.0]", "repeated values")
    refused('wob = [100.0, "0.1 kN"]', "repeated values")


def test_num_one_needs_start_equal_to_stop():
    """num = 1 would keep start and silently drop stop."""
    assert spec("wob = { start = 70.0, stop = 70.0, num = 1 }").axes["wob"].tolist() == [70.0]
    refused("wob = { start = 10.0, stop = 20.0, num = 1 }", "drops stop")


def test_num_limits_are_inclusive():
    big = spec("wob = { start = 1.0, stop = 1000000.0, num = 1000000 }")
    assert big.shape == (1_000_000, 1)
    assert big.axes["wob"][1] == 2.0 and big.axes["wob"][-1] == 1e6
    refused("wob = { start = 1.0, stop = 2000000.0, num = 1000001 }", re.escape("1 ... 1000000"))
    refused("wob = { start = 1.0, stop = 2.0, num = 0 }", re.escape("1 ... 1000000"))


def test_a_range_with_a_unit_on_one_end_only_is_refused():
    """{ start = "20 kN", stop = 120 } would read 20 kN ... 120 N (the bare end in SI)."""
    refused('wob = { start = "20 kN", stop = 120.0, num = 3 }', "has a unit and stop")
    refused('wob = { start = 20.0, stop = "120 kN", num = 3 }', "has a unit and start")
    # the same number in SI on both ends is what was meant: taken
    ok = spec('wob = { start = "120 N", stop = 20.0, num = 3 }')
    assert ok.axes["wob"].tolist() == [20.0, 70.0, 120.0]
    both = spec('wob = { start = "20 kN", stop = "120 kN", num = 3 }')
    assert both.axes["wob"].tolist() == [20e3, 70e3, 120e3]


# -- what an axis may hold --------------------------------------------------------------------


def test_a_zero_weight_on_bit_is_refused():
    refused("wob = [0.0, 10.0]", "weights on bit must be > 0")
    refused("wob = { start = 0.0, stop = 10.0, num = 3 }", "weights on bit must be > 0")


def test_size_axes_limits_are_inclusive():
    head = '[model]\npreset = "reduced-scale"\n[axes]\n'
    assert spec(f"pipes = [1, {MAX_DOF - 3}]", head).axes["pipes"].tolist() == [1, MAX_DOF - 3]
    refused(f"pipes = [{MAX_DOF - 2}]", re.escape(f"1 ... {MAX_DOF - 3}"), head)
    refused("pipes = [0, 1]", "must be >= 1", head)
    assert spec(f"dof = [2, {MAX_DOF}]", head).axes["dof"].tolist() == [2, MAX_DOF]
    refused(f"dof = [{MAX_DOF + 1}]", re.escape(f"2 ... {MAX_DOF}"), head)
    refused("dof = [1, 2]", "must be >= 2", head)


def test_pipes_p_is_a_string_of_p_plus_3_inertias():
    head = '[model]\npreset = "reduced-scale"\n[axes]\n'
    s = spec("pipes = [1, 6]", head)
    for pipes in (1, 6):
        params = s.params_at({"wob": 50.0, "torque": 6.0, "pipes": pipes})
        assert len(params.inertias) == pipes + 3


def test_friction_axes_need_mu_coulomb_below_mu_static_at_every_pair():
    ok = spec(
        "mu_coulomb = { start = 0.3, stop = 0.5, num = 3 }\n"
        "mu_static = { start = 0.6, stop = 0.9, num = 4 }"
    )
    assert ok.shape == (3, 4, 1, 1)
    # equal at one pair (0.6 and 0.6): refused, the model needs mu_coulomb < mu_static
    refused(
        "mu_coulomb = { start = 0.3, stop = 0.6, num = 4 }\n"
        "mu_static = { start = 0.6, stop = 0.9, num = 4 }",
        "not above the largest",
    )


def test_a_parameter_axis_is_checked_at_its_high_end_too():
    """mu_coulomb up to 0.9 against the preset's mu_static 0.8: refused, though its low end
    (0.1) is allowed."""
    refused("mu_coulomb = { start = 0.1, stop = 0.9, num = 3 }", "mu_coulomb = 0.9")
    refused("mu_static = [0.1, 0.9]", "mu_static = 0.1")


def test_the_largest_grid_is_allowed_and_one_more_point_is_not():
    side = round(MAX_POINTS**0.5)
    assert side * side == MAX_POINTS
    grid = f"wob = {{ start = 1.0, stop = {side}.0, num = {side} }}\n"
    assert spec(grid + f"torque = {{ start = 1.0, stop = {side}.0, num = {side} }}").size == (
        MAX_POINTS
    )
    refused(
        grid + f"torque = {{ start = 1.0, stop = {side + 1}.0, num = {side + 1} }}",
        "points is too many",
    )


# -- parts of a sweep -------------------------------------------------------------------------


def test_parts_take_every_nth_value_from_the_kth_and_cover_the_grid_once():
    whole = spec("wob = { start = 10.0, stop = 70.0, num = 7 }\ntorque = [6.0, 8.3]")
    assert whole.axes["wob"].tolist() == [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0]
    expected = {1: [10.0, 40.0, 70.0], 2: [20.0, 50.0], 3: [30.0, 60.0]}
    seen = []
    for k, values in expected.items():
        part = whole.part(k, 3)
        assert part.axes["wob"].tolist() == values
        assert part.axes["torque"].tolist() == [6.0, 8.3]
        seen += values
    assert sorted(seen) == whole.axes["wob"].tolist()
    assert whole.part(1, 1).axes["wob"].tolist() == whole.axes["wob"].tolist()
    assert whole.part(7, 7).axes["wob"].tolist() == [70.0]
    with pytest.raises(ValueError):
        whole.part(8, 8)  # a part of no value


def test_coords_of_a_flat_index_follow_the_axes_order():
    s = spec("wob = [40.0, 100.0, 160.0]\ntorque = [6.0, 8.3]")
    flat = [s.coords(i) for i in range(s.size)]
    # C order: the last axis (torque) varies fastest
    grid = [{"wob": w, "torque": t} for w in (40.0, 100.0, 160.0) for t in (6.0, 8.3)]
    assert flat == grid
    assert np.prod(s.shape) == len(grid)


# -- real strings from a tally (what a spec's depth axis builds) ------------------------------

G, RHO = 79.3e9, 7850.0
STRING = """
name = "guard"
[top_drive]
inertia = 2000.0
damping = 400.0
[bit]
diameter = "12 in"
damping = 50.0
[damping]
model = "stiffness-proportional"
beta = 0.2
[[section]]
kind = "drill-pipe"
count = 10
length = 10.0
od = "5 in"
id = "4 in"
[[section]]
kind = "heavy-weight"
count = 2
length = 10.0
od = "6.5 in"
id = "3 in"
[[section]]
kind = "drill-pipe"
count = 3
length = 10.0
od = "5.5 in"
id = "4.5 in"
[[section]]
kind = "drill-collar"
count = 5
length = 10.0
od = "8 in"
id = "3 in"
"""


def _joint(od_in, id_in, length=10.0):
    """A joint's (stiffness G·I_p/L, inertia ρ·I_p·L) by hand, I_p = π(OD⁴ − ID⁴)/32."""
    ip = np.pi * ((od_in * 0.0254) ** 4 - (id_in * 0.0254) ** 4) / 32
    return G * ip / length, RHO * ip * length


def test_tally_elements_are_each_joints_spring_and_inertia():
    from pydrill.tally import parse_tally

    tally = parse_tally(STRING)
    k, j, lengths = tally.elements()
    assert lengths.tolist() == [10.0] * 20
    joints = [(5, 4)] * 10 + [(6.5, 3)] * 2 + [(5.5, 4.5)] * 3 + [(8, 3)] * 5
    assert k == pytest.approx([_joint(*d)[0] for d in joints], rel=1e-12)
    assert j == pytest.approx([_joint(*d)[1] for d in joints], rel=1e-12)
    assert tally.length == 200.0 and tally.bha_length == 70.0
    # lumped 4 drill-pipe joints an element: 4 + 4 + 2 joints in series, their inertias summed
    k4, j4, l4 = tally.elements(lump=4)
    assert l4[:3].tolist() == [40.0, 40.0, 20.0]
    assert k4[:3] == pytest.approx([_joint(5, 4)[0] / n for n in (4, 4, 2)], rel=1e-12)
    assert j4[:3] == pytest.approx([_joint(5, 4)[1] * n for n in (4, 4, 2)], rel=1e-12)
    # drill pipe only: 3 + 1 elements of it, the heavy-weight and the collars a joint each
    assert l4.tolist() == [40.0, 40.0, 20.0, 10.0, 10.0, 30.0] + [10.0] * 5


def test_at_depth_adds_whole_joints_to_the_first_drill_pipe_section():
    from pydrill.tally import TallyError, parse_tally

    tally = parse_tally(STRING)  # 200 m, of which 100 m of 10 m joints in section 1
    exact = tally.at_depth(1000.0)  # 900 m of pipe: 90 joints, not 91
    assert [s.count for s in exact.sections] == [90, 2, 3, 5]
    assert exact.length == 1000.0
    # a depth between joints: the next whole joint (the string reaches it)
    assert [s.count for s in tally.at_depth(1001.0).sections] == [91, 2, 3, 5]
    assert [s.count for s in tally.at_depth(110.5).sections] == [2, 2, 3, 5]
    assert [s.count for s in tally.at_depth(105.0).sections] == [1, 2, 3, 5]
    # at or above what the other sections reach: refused
    for depth in (100.0, 50.0):
        with pytest.raises(TallyError, match="shallower than the BHA"):
            tally.at_depth(depth)


def test_two_inertia_reduction_is_the_whole_string_at_the_bit():
    from pydrill.tally import parse_tally

    tally = parse_tally(STRING)
    k, j, _ = tally.elements()
    params = tally.to_params(dof=2)
    assert params.bit_radius == pytest.approx(6 * 0.0254, rel=1e-14)  # half the 12 in bit
    assert params.inertias == pytest.approx((2000.0, float(np.sum(j))), rel=1e-12)
    assert params.stiffnesses == pytest.approx((1 / float(np.sum(1 / k)),), rel=1e-12)
    assert params.dampings == pytest.approx((0.2 / float(np.sum(1 / k)),), rel=1e-12)


@pytest.mark.parametrize("dof", [3, 4, 7, 21])
def test_reduced_strings_keep_the_whole_inertia_and_compliance(dof):
    from pydrill.tally import parse_tally

    tally = parse_tally(STRING)
    k, j, _ = tally.elements()
    params = tally.to_params(dof=dof)
    assert len(params.inertias) == dof
    assert sum(params.inertias) == pytest.approx(2000.0 + float(np.sum(j)), rel=1e-12)
    assert sum(1 / np.array(params.stiffnesses)) == pytest.approx(float(np.sum(1 / k)), rel=1e-12)


def test_an_elements_inertia_is_shared_by_where_it_sits_on_the_compliance():
    """Two equal elements in one group (dof 2 + 1 = 3, elements 0-9 and 10-19 split in two
    groups): by hand for a string of 4 equal joints in 2 groups of 2: compliances c, 2c;
    the upper joint's J splits 1/2 : 1/2 between the group's ends, the lower one's all below."""
    from pydrill.tally import parse_tally

    text = STRING.split("[[section]]")[0] + (
        '[[section]]\nkind = "drill-pipe"\ncount = 4\nlength = 10.0\nod = "5 in"\nid = "4 in"\n'
    )
    params = parse_tally(text).to_params(dof=3)
    kj, jj = _joint(5, 4)
    assert params.inertias == pytest.approx((2000.0 + jj / 2, jj + jj / 2 + jj / 2, jj + jj / 2))
    assert params.stiffnesses == pytest.approx((kj / 2, kj / 2), rel=1e-12)


def test_dof_may_be_as_large_as_the_elements_allow():
    from pydrill.tally import TallyError, parse_tally

    tally = parse_tally(STRING)  # 20 elements: 21 inertias at most
    assert len(tally.to_params(dof=21).inertias) == 21
    assert tally.to_params(dof=21).inertias == tally.to_params().inertias
    with pytest.raises(TallyError, match=re.escape("2 ... 21")):
        tally.to_params(dof=22)


def test_the_largest_string_is_max_dof_inertias_and_the_lump_hint_is_the_least_that_fits():
    from pydrill.tally import TallyError, parse_tally

    head = STRING.split("[[section]]")[0]
    pipe = '[[section]]\nkind = "drill-pipe"\ncount = {n}\nlength = 1.0\nod = "5 in"\nid = "4 in"\n'
    largest = parse_tally(head + pipe.format(n=MAX_DOF - 1))  # with the top drive: MAX_DOF
    assert len(largest.elements()[0]) == MAX_DOF - 1
    with pytest.raises(TallyError, match="at most"):
        parse_tally(head + pipe.format(n=MAX_DOF)).elements()
    # 2 (MAX_DOF - 1) joints: lump 2 gives exactly MAX_DOF inertias, the least lump that fits
    big = parse_tally(head + pipe.format(n=2 * (MAX_DOF - 1)))
    with pytest.raises(TallyError) as err:
        big.elements()
    least = int(re.search(r"lump >= (\d+)", str(err.value)).group(1))
    assert least == 2
    assert len(big.elements(lump=least)[0]) + 1 == MAX_DOF
    with pytest.raises(TallyError):
        big.elements(lump=least - 1)


def test_the_shared_inertia_rule_changed_the_digest_of_reduced_strings_only():
    """dof 2 is the paper's two-inertia model, unchanged when reduced strings (dof >= 3) began
    to share inertias (commit 3b6573c): its atlases stay resumable, the others' do not. The
    digests below are what pydrill computed for these specs before that commit."""
    spec = '[model]\ntally = "t.toml"\ndof = {}\ntorque = 9000.0\nwob = 5e4\n[axes]\n'
    spec += "depth = [1000.0, 3000.0]\n"
    assert parse_spec(spec.format(2), tally_text=STRING).digest == "bc5aacc9e0a4475d"
    assert parse_spec(spec.format(6), tally_text=STRING).digest != "d68382e0193ee257"


# -- how a sweep's points are dealt out (pydrill.batching) ------------------------------------


def test_each_batch_takes_a_half_workers_share_of_what_is_left():
    """1000 points, 4 workers: 1/(2 x 4) of what is left, rounded up: 125 of 1000, 110 of
    875, 96 of 765; every point once."""
    from pydrill.batching import Batcher

    deal = Batcher(np.arange(1000))
    sizes = [len(deal.take(4)) for _ in range(3)]
    assert sizes == [125, 110, 96]
    rest = deal.rest(4)
    assert sorted(i for b in rest for i in b) == sorted(set(range(1000)) - set(deal.order[:331]))


def test_batches_timed_at_no_time_are_still_sized_by_count():
    """A batch whose clock read 0 s (a coarse timer) says nothing of a point's cost."""
    from pydrill.batching import Batcher

    deal = Batcher(np.arange(1000))
    deal.timed(16, 0.0)
    assert deal.point_seconds is None
    assert deal.size(4) == 125


def test_a_string_of_one_more_inertia_than_allowed_is_refused_at_any_lump():
    """Lumping joins drill pipe only: with 5 collars, 2 (MAX_DOF - 5) joints of pipe at
    lump 2 make 1 + (MAX_DOF - 5) + 5 = MAX_DOF + 1 inertias."""
    from pydrill.tally import TallyError, parse_tally

    head = STRING.split("[[section]]")[0]
    pipe = '[[section]]\nkind = "drill-pipe"\ncount = {n}\nlength = 1.0\nod = "5 in"\nid = "4 in"\n'
    collars = (
        '[[section]]\nkind = "drill-collar"\ncount = 5\nlength = 9.0\nod = "8 in"\nid = "3 in"\n'
    )
    tally = parse_tally(head + pipe.format(n=2 * (MAX_DOF - 5)) + collars)
    with pytest.raises(TallyError, match=r"lump >= 3"):
        tally.elements(lump=2)
    assert len(tally.elements(lump=3)[0]) == -(-2 * (MAX_DOF - 5) // 3) + 5


def test_tally_sections_need_a_joint_and_long_joints_are_noted_past_15_m():
    from pydrill.tally import TallyError, parse_tally

    head = STRING.split("[[section]]")[0]
    pipe = '[[section]]\nkind = "drill-pipe"\ncount = {n}\nlength = {m}\nod = "5 in"\nid = "4 in"\n'
    with pytest.raises(TallyError, match="count"):
        parse_tally(head + pipe.format(n=0, m=9.0) + pipe.format(n=3, m=9.0))
    assert parse_tally(head + pipe.format(n=3, m=15.0)).notes == ()
    (note,) = parse_tally(head + pipe.format(n=3, m=15.5)).notes
    assert "15.5 m per joint" in note


def test_a_parameter_axis_applies_to_a_tally_string_too():
    spec = '[model]\ntally = "t.toml"\ndof = 4\ntorque = 9000.0\nwob = 5e4\ndepth = 1000.0\n'
    swept = parse_spec(spec + "[axes]\nmu_static = [0.85, 0.95]\n", tally_text=STRING)
    for mu in (0.85, 0.95):
        params = swept.params_at({"mu_static": mu})
        assert params.mu_static == mu
        assert params.inertias == swept.params_at({"mu_static": 0.85}).inertias
