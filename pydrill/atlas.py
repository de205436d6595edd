"""Reading atlases: ``pydrill.Atlas``.

Example (an atlas written by ``pydrill sweep``)::

    with pydrill.Atlas("paper.h5") as atlas:
        atlas.value(wob=100, torque=8.3, method="nearest")["regime"]   # {'rest': 'stick-slip', ...}
        atlas.to_xarray().bit_mean.sel(initial="rest").plot()
"""

from __future__ import annotations

import io
import json
from collections.abc import Mapping
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import h5py
import numpy as np

from . import atlas_format as fmt
from .atlas_check import code_problem, layout_problem
from .atlas_grid import CoordinateError, coordinate, grid_index, not_an_axis, selection
from .atlas_grid import without_held as _without_held
from .atlas_heap import OPENING_BYTES, refuse_damaged_heap
from .atlas_lock import snapshot
from .atlas_objects import DATASETS as _DATASETS
from .atlas_objects import Objects as _Objects
from .atlas_summary import summary as _summary
from .atlas_xarray import COUNT_FIELDS, Chunks, with_regime_names  # noqa: F401 (pydrill.atlas.*)
from .atlas_xarray import to_xarray as _to_xarray
from .file_kinds import misplaced
from .journal import AtlasError, empty_file, journal_hint
from .spec import SpecError, parse_spec

if TYPE_CHECKING:
    import xarray
    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike, NDArray

    from .atlas_safe import SafeRow


class Atlas:
    """An atlas file, opened read-only. Use as a context manager or call :meth:`close`.

    ``axes`` maps each swept axis to its values (grid order; read-only, as the mapping is),
    ``initials`` lists the starts (``"rest"``, ``"equilibrium"``; a tuple), ``spec`` is the
    sweep specification it was made from and ``version`` the pydrill that wrote it. A
    missing, damaged or foreign file raises ``pydrill.sweep.AtlasError`` naming the problem,
    and so does a read after :meth:`close`.
    An Atlas pickles as its path: unpickled (e.g. on a Dask worker), it opens that file again.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        if not self.path.exists():
            raise AtlasError(f"{self.path}: no such atlas" + journal_hint(self.path))
        if self.path.is_dir():
            raise AtlasError(f"{self.path} is a directory, not an atlas file")
        # While a sweep writes the atlas, read a copy of its last complete write: the file
        # itself may be half rewritten at any moment (atlas_lock).
        self._image = snapshot(self.path)
        # Before HDF5 reads a variable-length value: a damaged global heap hangs it.
        self._heap_checked = False
        self._heap(OPENING_BYTES)
        try:
            self._f = h5py.File(self._source(), "r")
        except OSError as exc:
            # A whole spec, tally or figure given for the atlas: not "truncated or corrupt?";
            # nor a file of 0 bytes (touched, or a shell's > made it), which holds nothing
            raise AtlasError(
                misplaced(self.path, "atlas")
                or (empty_file(self.path) if self._empty() else None)
                or f"{self.path} is not a readable HDF5 atlas (truncated or corrupt?): {exc}"
                + journal_hint(self.path)
            ) from None
        try:
            # A damaged root object header fails here (h5py's KeyError "bad object header
            # version number"), inside the handler that closes the file and names the damage.
            self._objects = _Objects(self._f)
            if self._f.attrs.get("format") != fmt.FORMAT:
                raise AtlasError(f"{self.path} is an HDF5 file but not a pydrill atlas")
            try:
                self.spec = parse_spec(
                    self._f.attrs["spec"], tally_text=self._f.attrs.get("tally") or None
                )
            except SpecError as exc:
                # Written by a pydrill that took a spec this one refuses: the file is whole,
                # only its recipe is not accepted any more. Say so, and how to read it anyway.
                from . import __version__

                written = self._f.attrs.get("pydrill_version", "?")
                raise AtlasError(
                    f"{self.path}: its sweep spec (written by pydrill {written}) is refused by "
                    f"pydrill {__version__}: {exc}. The data are intact: read them with "
                    f"xarray.open_dataset({str(self.path)!r}, engine='h5netcdf') or h5py"
                ) from None
            # The file's structure against its spec's (shapes, types, axes, starts, attributes):
            # a damaged file is refused here, naming what is wrong, not met as a TypeError or
            # AttributeError from deep inside a query. The codes are checked where they are
            # read (``check``): reading them all here would cost a point query 30 ms at 10^6.
            problem = layout_problem(self._objects, self.spec, codes=False)
            if problem:
                raise ValueError(problem)
            named = json.loads(self._f.attrs["axes"])
            self._axes = MappingProxyType(
                {name: _frozen(self._objects[name][...]) for name in named}
            )
            self._initials = tuple(
                s.decode() if isinstance(s, bytes) else s for s in self._objects["initial"][...]
            )
            self.version = str(self._f.attrs.get("pydrill_version", "?"))
            # Every dataset a query reads, up front: a missing one is a damaged atlas here,
            # not a KeyError from deep inside info, plot or value later.
            lost = [name for name in _DATASETS if name not in self._objects]
            if lost:
                raise KeyError(f"no dataset {', '.join(lost)}")
            for name in ("status", "regime", "bit_mean"):
                self._objects[name].shape  # noqa: B018 - touch: a damaged file fails here, not later
        except AtlasError:
            self._f.close()
            raise
        # RuntimeError: h5py's, for a damaged B-tree or checksum
        except (KeyError, OSError, ValueError, TypeError, AttributeError, RuntimeError) as exc:
            self._f.close()
            raise AtlasError(f"{self.path} is damaged or incomplete: {exc}") from None

    def __repr__(self) -> str:
        """One line for a notebook: the file, the grid and the starts (no file read)."""
        grid = " x ".join(f"{name} {len(v)}" for name, v in self.axes.items())
        state = ", closed" if self.closed else ""
        return (
            f"<pydrill.Atlas {str(self.path)!r}: {self.spec.size} points ({grid}), "
            f"from {', '.join(self.initials)}{state}>"
        )

    def _empty(self) -> bool:
        """Whether what was opened (the file, or its copy) has no bytes at all."""
        try:
            return len(self._image or self.path.read_bytes()[:1]) == 0
        except OSError:
            return False

    def _source(self) -> Path | io.BytesIO:
        """What to open: the file, or the copy taken while a sweep was writing it."""
        return self.path if self._image is None else io.BytesIO(self._image)

    def close(self) -> None:
        """Close the HDF5 file (done by ``with``); reading the atlas after raises AtlasError."""
        self._f.close()
        self._image = None

    @property
    def closed(self) -> bool:
        """True once :meth:`close` (or the end of ``with``) has closed the file."""
        return not self._f

    def _file(self) -> _Objects:
        """The open HDF5 file's objects; AtlasError once closed (h5py's own error names no
        atlas)."""
        if self.closed:
            raise AtlasError(
                f"{self.path}: this Atlas is closed; read it inside its `with` block, or open "
                "it again with pydrill.Atlas(path)"
            )
        return self._objects

    def __reduce__(self) -> tuple[type[Atlas], tuple[str]]:
        # h5py files cannot be pickled: an Atlas travels as its path and opens it again.
        return (type(self), (str(self.path.absolute()),))

    def __enter__(self) -> Atlas:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def axes(self) -> Mapping[str, NDArray[Any]]:
        """Each swept axis's grid values (SI, grid order), by name, in the order of the grid's
        dimensions. Read-only, the arrays too: every query reads them (``np.array(v)`` is a
        copy to change)."""
        return self._axes

    @property
    def initials(self) -> tuple[str, ...]:
        """The starts each point was simulated from (``"rest"``, ``"equilibrium"``)."""
        return self._initials

    @property
    def shape(self) -> tuple[int, ...]:
        """Grid size along each axis, in the order of :attr:`axes`."""
        return tuple(len(v) for v in self.axes.values())

    def index(self, method: str = "exact", **coords: float | str) -> tuple[int, ...]:
        """Grid index of the given coordinates (numbers in SI, or strings with a unit:
        ``wob="80 N"``): every axis must be given, but for an axis of one value (a depth swept
        as ``["3000 m"]``), which may be left out. A ``CoordinateError`` (both a KeyError and a
        ValueError) names an axis the atlas has not, one left out, or a value off the grid
        (exact), NaN, or more than half a grid step past either end (whatever the method).
        What the spec holds at every point (a torque in [model]) may be given too, at its
        value (as ``pydrill atlas query --torque`` takes it); another value is refused."""
        coords = _without_held(self, coords)
        extra = sorted(set(coords) - set(self.axes))
        if extra:
            raise not_an_axis(extra[0], self.axes)
        coords = {n: v[0].item() for n, v in self.axes.items() if len(v) == 1} | coords
        missing = set(self.axes) - set(coords)
        if missing:
            raise CoordinateError(
                f"give a value for every axis; missing: {', '.join(sorted(missing))}"
            )
        if method not in ("exact", "nearest"):
            raise ValueError(f"method = {method!r}: choose 'exact' or 'nearest'")
        return tuple(
            grid_index(name, values, coordinate(name, coords[name]), method)
            for name, values in self.axes.items()
        )

    def value(self, method: str = "exact", **coords: float | str) -> dict[str, Any]:
        """Everything recorded at one point, as plain data.

        Give a value for every axis (``wob=100, torque=8.3``; one of a single value may be
        left out); ``method="nearest"`` takes the nearest grid point instead of requiring an
        exact one. Keys: ``coords``, ``status``
        (``"done"``, ``"failed"`` with ``message``, ``"missing"``), ``regime`` and ``metrics``
        (each by start), ``stability`` (lists over the steady states: ``omega_eq``, ``delta``,
        ``spectral_abscissa``, ``hopf_margin``, ``unstable``, ``eigenvalues``; ``None`` in an
        atlas swept without stability) and
        ``coexistence`` (the starts disagree; ``None`` with one start) and ``caveat`` (what
        each start's judgement notes, by kind — ``"growing"``, ``"short-window"``, … — or
        ``None``; see ``SimulationResult.summary.note`` for what each means).
        """
        from .atlas_value import point_value

        return point_value(self, self._file(), self.index(method, **coords))

    def _name(self, known: dict[str, int], dataset: str, code: Any) -> str:
        """The name of ``code`` read from ``dataset``; a code that is none of ``known`` is a
        damaged atlas (status 7 was a KeyError from here)."""
        for name, value in known.items():
            if code == value:
                return name
        raise AtlasError(f"{self.path} is damaged or incomplete: {code_problem(dataset, known)}")

    def check(self) -> None:
        """Raise AtlasError if any status, regime, caveat or coexistence code in the atlas is
        none that pydrill writes (what opening it leaves out, to keep point queries fast);
        ``summary``, ``to_xarray`` and the atlas commands that read it whole call it."""
        problem = layout_problem(self._file(), self.spec)
        if problem:
            raise AtlasError(f"{self.path} is damaged or incomplete: {problem}")
        self._heap()

    def _heap(self, limit: int | None = None) -> None:
        """AtlasError if a global heap starting before byte ``limit`` (None: any) is damaged."""
        if not self._heap_checked:
            refuse_damaged_heap(self.path, self._image, limit)
            self._heap_checked = limit is None  # the whole file: once per Atlas

    def regimes(self, initial: str | None = None) -> np.ndarray:
        """Regime names on the whole grid for one initial condition (default: the first); a
        ``CoordinateError`` (a KeyError and a ValueError) for a start the atlas has not."""
        f = self._file()
        j = self._initial_index(initial)
        self.check()
        codes = f["regime"][..., j]
        names = np.array([fmt.REGIME_NAMES[c] for c in sorted(fmt.REGIME_NAMES)], dtype=object)
        return names[np.searchsorted(sorted(fmt.REGIME_NAMES), codes)]

    def _initial_index(self, initial: str | None) -> int:
        if initial is None:
            return 0
        if not isinstance(initial, str):
            raise TypeError(
                f"initial must be the name of a start ({', '.join(map(repr, self.initials))}) "
                f"or None, got {initial!r}"
            )
        if initial not in self.initials:
            raise CoordinateError(
                f"initial = {initial!r} is not in this atlas: {list(self.initials)}"
            )
        return self.initials.index(initial)

    def safe_region(self) -> np.ndarray:
        """Points where every start drills steadily and the fastest steady state is stable.
        Raises ``ValueError`` for an atlas whose sweep did not record stability
        (``[record] stability = false``): without it no point can be called safe."""
        f = self._file()
        if not self.spec.record["stability"]:
            raise ValueError(
                f"{self.path} has no safe region: its sweep did not record stability "
                "([record] stability = false), and a steady run alone does not say the steady "
                "state is stable. Sweep the spec with stability = true into a new atlas"
            )
        codes = f["regime"][...]
        steady = np.all(codes == fmt.REGIMES["steady"], axis=-1)
        stable = f["unstable"][..., 0] == 0
        return steady & stable

    def safe_windows(self, along: str | None = None, **at: Any) -> list[SafeRow]:
        """The safe operating windows along axis ``along`` (default: ``wob`` if swept, else
        the first axis): for every value of the other axes, or the grid value nearest each
        given in ``at`` (numbers, or strings with a unit: ``torque="9 kN·m"``), the runs of
        consecutive grid points of :meth:`safe_region` as (first, last) grid values, in SI
        (split where the grid jumps over 0: u = 0 is stuck). The true edges lie within one
        grid step beyond them. Points without a result (missing, failed) are not safe; each
        row counts them (``not_done``), and of them those that failed (``failed``). An axis
        the atlas has not, or a value of ``at`` past the grid, is a ``CoordinateError``; what
        the spec holds may be given at its value."""
        from .atlas_safe import safe_windows

        coords = {name: coordinate(name, v) for name, v in _without_held(self, at).items()}
        return safe_windows(self, along, coords)

    def summary(self) -> dict[str, Any]:
        """What ``pydrill atlas info`` prints, as data: the model (the string's name, its
        inertias, what is held fixed, ``t_end``), axes, point status, regime counts per start,
        safe and coexistence points, version and spec digest."""
        return _summary(self)

    def sel(self, method: str | None = None, **coords: ArrayLike | str | slice) -> xarray.Dataset:
        """A slice of the atlas as an ``xarray.Dataset``: fix some axes (or ``initial``),
        keep the others, e.g. ``atlas.sel(torque=8.3).regime_name`` is the regime against W_ob
        (``regime`` holds the same as codes, named in its ``flag_meanings`` attribute). An
        axis takes a value or a list of them: numbers, or strings with a unit (``"20 kN"``);
        or a ``slice(first, last)`` of them (inclusive, either end None: open), which keeps the
        grid values between, as a list of them would. Without ``method`` (or with ``"exact"``)
        each value must be on the grid, as :meth:`value` has it; ``method="nearest"`` takes
        the nearest grid value (not with a slice). A value off the grid, or more than half a
        step beyond it, an axis or a start the atlas has not, is a ``CoordinateError`` (a
        KeyError and a ValueError) saying why; an empty list or slice is a ValueError."""
        chosen = selection(self.axes, self.initials, method, _without_held(self, coords))
        method = None if method == "exact" else method
        # Selected before it is read: a row of an atlas of 10^6 points, not all of it (5 s
        # and 750 MB); and the file let go of at once, not whenever the view is collected.
        with self.to_xarray() as ds:
            if "initial" in chosen:
                ds = ds.sel(initial=chosen.pop("initial"))
            ds = (ds.sel(method=method, **chosen) if chosen else ds).load()
        return with_regime_names(ds)

    def plot(
        self,
        metric: str | None = None,
        *,
        initial: str | None = None,
        x: str | None = None,
        y: str | None = None,
        at: Mapping[str, float | str] | None = None,
        profile: bool = False,
    ) -> Figure:
        """The atlas as a map, a matplotlib ``Figure`` (what ``pydrill atlas plot`` saves):
        the regime, or ``metric`` (e.g. ``"severity"``, ``"spectral_abscissa"``; any of
        ``pydrill.plot_atlas.METRICS``) with a colour bar, on the axes ``x`` and ``y``
        (default: the first two swept), any other held at its grid value nearest ``at[name]``
        (default: its first), from the start ``initial`` (default: the first). On (W_ob, u)
        the stuck boundary and the first Hopf curve are drawn on top, and on a regime map the
        safe region (:meth:`safe_region`) is outlined in white. With ``profile`` (and
        always when one axis is left: an atlas of one axis, or every other held by ``at``) a
        profile along ``x`` instead, the other axes held
        as for a map: bit velocities from each start (or ``metric``), the fastest steady
        state (dashed where unstable) and the regimes in a strip below."""
        from .plot_atlas import atlas_figure

        f = self._file()  # closed: refused like every other read
        # (a list was "unhashable type: 'list'", at=[1] dict()'s own complaint)
        if not (metric is None or isinstance(metric, str)):
            raise TypeError(f"metric must be a name (e.g. 'severity') or None, got {metric!r}")
        if not (at is None or isinstance(at, Mapping)):
            raise TypeError(f"at must be a dict of axis values, e.g. {{'torque': 8.3}}, got {at!r}")
        if metric in fmt.ADDED_RUN_FIELDS and metric not in f:
            raise AtlasError(
                f"{self.path}: metric = {metric!r} is not in this atlas: the pydrill that wrote "
                "it did not record it; sweep the spec again into a new atlas to map it"
            )
        at = None if at is None else _without_held(self, dict(at))
        return atlas_figure(self, initial=initial, x=x, y=y, at=at, metric=metric, profile=profile)

    def to_xarray(self, chunks: Chunks = None) -> xarray.Dataset:
        """The atlas as an ``xarray.Dataset`` (through h5netcdf), axes as coordinates, read
        lazily. ``regime`` is an integer code; its CF attributes ``flag_values`` and
        ``flag_meanings`` name them (``with_regime_names`` adds a ``regime_name`` variable).
        ``safe`` (int8 on the axes, computed on opening: not in the file) is
        :meth:`safe_region`, 1 where safe, when the sweep recorded stability.
        ``chunks``: read into dask arrays of these chunks, as ``xarray.open_dataset`` takes
        them (a dict by dimension, ``{}``: the atlas's own; ``"auto"``: blocks of dask's
        size; an int, -1: whole), for atlases larger than memory; None: each variable is read
        whole the first time it is used. A dimension the atlas has not is a ValueError."""
        self._file()  # closed: refused like every other read
        self._heap()  # xarray reads every attribute and dimension list
        try:
            return _to_xarray(self._source(), self.axes, chunks)
        except (OSError, RuntimeError, KeyError) as exc:  # h5py's, on a damaged file
            raise AtlasError(f"{self.path} is damaged: xarray cannot read it ({exc})") from None


def _frozen(values: np.ndarray) -> np.ndarray:
    """A read-only view of ``values`` (an array of its own, made read-only too): a view of a
    read-only array cannot be made writeable again (``setflags(write=True)`` is refused)."""
    values.setflags(write=False)
    return values.view()
