"""pydrill as a library in a notebook or a script, found by a user's audit (session 38): what
survives a trip through pickle (Dask, multiprocessing, concurrent.futures) and copy (the
exception a stopped sweep raises, a spec's frozen axes), SweepSpec.coords's refusals, and a
tally's repr."""

import copy
import pickle
import signal
from pathlib import Path

import numpy as np
import pytest
from sweeping import SMALL

from pydrill import SweepInterrupted, load_tally, parse_spec

TALLIES = Path(__file__).parent.parent / "examples" / "tallies"

TRIPS = {
    "pickle": lambda x: pickle.loads(pickle.dumps(x)),
    "copy": copy.copy,
    "deepcopy": copy.deepcopy,
}


@pytest.mark.parametrize("trip", TRIPS.values(), ids=TRIPS.keys())
def test_sweep_interrupted_survives_pickle_and_copy(trip):
    # An exception pickles as type(self)(*self.args): the message alone, which
    # SweepInterrupted's __init__ does not take, so a sweep stopped in a worker process (or
    # copy.copy of the exception) raised TypeError instead. Compared field by field with the
    # one raised, whose values are all distinct from the defaults.
    raised = SweepInterrupted(
        Path("atlas.h5"),
        12,
        5,
        signal.SIGTERM,
        computed=4,
        failed=1,
        resumed=1,
        wall_time=2.5,
        write_time=0.5,
        failed_in_atlas=2,
        first_failure="max_steps reached",
    )
    again = trip(raised)
    assert type(again) is SweepInterrupted and isinstance(again, KeyboardInterrupt)
    assert vars(again) == vars(raised) and again.args == raised.args
    assert str(again) == str(raised) and "5 of 12 points are saved" in str(again)


@pytest.fixture(scope="module")
def spec():
    return parse_spec(SMALL)


@pytest.mark.parametrize("trip", TRIPS.values(), ids=TRIPS.keys())
def test_spec_axes_stay_read_only_through_pickle_and_copy(spec, trip):
    # parse_spec freezes the axes (an axis changed in place would make an atlas whose
    # coordinates disagree with what its points computed), but numpy's pickle drops the
    # flag: the spec a Dask worker or deepcopy got had writable axes.
    again = trip(spec)
    assert again.digest == spec.digest and list(again.axes) == list(spec.axes)
    for name, values in again.axes.items():
        np.testing.assert_array_equal(values, spec.axes[name])
        assert not values.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            values[0] = -1.0
    assert again.digest == spec.digest  # (the refusal changed nothing)
    assert again.params_at(again.coords(3)) == spec.params_at(spec.coords(3))


def test_a_spec_built_from_writable_arrays_freezes_copies(spec):
    # A SweepSpec made directly from a caller's array: frozen too, but the caller's own array
    # is left writable (copied, not frozen under them).
    wob = np.array([40.0, 100.0])
    made = type(spec)(
        spec.text,
        spec.preset,
        spec.dof,
        dict(spec.overrides),
        {"wob": wob, "torque": np.array([6.0])},
        dict(spec.simulation),
        dict(spec.record),
    )
    assert wob.flags.writeable and not made.axes["wob"].flags.writeable
    wob[0] = 1.0
    assert made.axes["wob"].tolist() == [40.0, 100.0]


def test_coords_numbers_points_in_c_order_and_names_its_range(spec):
    # Every point against a grid built independently (itertools-style nested loops, last
    # axis fastest), then the refusals: numpy's own "index 6 is out of bounds for array with
    # size 6" named neither the argument nor its range, -1 the same, and True was point 1.
    grid = [{"wob": w, "torque": u} for w in spec.axes["wob"] for u in spec.axes["torque"]]
    assert [spec.coords(i) for i in range(spec.size)] == grid
    assert spec.coords(np.int64(4)) == grid[4]
    for bad in (-1, spec.size):
        with pytest.raises(ValueError, match=rf"flat_index = {bad} .*0 \.\.\. {spec.size - 1}"):
            spec.coords(bad)
    for bad in (True, 2.0, "3"):
        with pytest.raises(TypeError, match="flat_index must be an integer"):
            spec.coords(bad)


@pytest.mark.parametrize("depth", [None, 3000.0])
def test_tally_repr_is_one_line_of_its_totals(depth):
    # The dataclass's repr listed every section field by field (870 characters for the
    # 5-section example, 0.12136119999999999 m and all). One line now, its totals checked
    # against the sections summed here.
    tally = load_tally(TALLIES / "5.5in-dp-8in-collars.toml")
    if depth is not None:
        tally = tally.at_depth(depth)
    text = repr(tally)
    joints = sum(s.count for s in tally.sections)
    length = sum(s.count * s.length for s in tally.sections)
    bha = sum(s.count * s.length for s in tally.sections if s.kind != "drill-pipe")
    assert "\n" not in text and len(text) < 160
    assert text.startswith(f"<Tally '5.5in-dp-8in-collars': {len(tally.sections)} sections, ")
    assert f"{joints} joints, {length:.6g} m (BHA {bha:.6g} m)" in text
    assert (depth is None) == (joints == 327)  # at_depth changed the drill pipe, shown


def test_an_interrupt_before_any_point_keeps_its_message_through_pickle(tmp_path):
    """Stopped before any point, the message says nothing was written; its copy must say the
    same, not "0 of 10 points are saved in" an atlas that is not there."""
    exc = SweepInterrupted(tmp_path / "a.h5", 10, 0, written=False)
    for again in (pickle.loads(pickle.dumps(exc)), copy.copy(exc), copy.deepcopy(exc)):
        assert str(again) == str(exc) and "nothing was written" in str(again)
        assert again.written is False and again.points == 10
