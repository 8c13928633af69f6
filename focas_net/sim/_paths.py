"""The paths of a machine: how they are described, what each shows of the shared parameters,
and the collection the machine answers through.

A FANUC control runs up to 10 paths (a twin-turret lathe has 2, one per turret): each has its
own axes and spindles, programs and main program, NC engine, panel mode, status and alarms,
while the PMC, most parameters, the macro variables #500-#999 and the alarm history are
shared. A :class:`PathSpec` describes one path for the machine's constructor; the machine
answers :class:`PathInfo` about it.

The parameters as a path sees them (:class:`PathItems`): the axis-type ones are numbered by
the path's own axes (axis 1 of path 2 is that path's first axis), held in one table of every
axis of the machine in path order, as FANUC numbers the controlled axes; the path-type ones
(:data:`PATH_PARAMS`) hold one value per path; the others are shared.
"""

from __future__ import annotations

import copy
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final

from focas_net._refusals import axis_misfit, axis_past, no_item, no_path
from focas_net.errors import EW

from ._base import MachineError, need_int, need_items
from ._identity import axes_problem
from ._items import DataItem, Items, ParamKind

if TYPE_CHECKING:
    from ._identity import Identity
    from ._path import Path
    from ._status import MotionData, Panel
    from .nc.scenario import Scenario

__all__ = [
    "MAX_PATHS",
    "PATH_KINDS",
    "PATH_MACROS",
    "PATH_PARAMS",
    "SETTING_PARAMS",
    "PathInfo",
    "PathItems",
    "PathSpec",
    "Paths",
    "path_specs",
]

#: The most paths a FANUC control has (Series 30i: 10).
MAX_PATHS: Final = 10
#: The machine type of a path: machining centre (M) or lathe (T).
PATH_KINDS: Final = ("M", "T")


def kind_of(mt_type: str) -> str:
    """The machine type of a path from ODBSYS ``mt_type``: "T" for FANUC's T series, whose
    codes end in T (``" T"``, ``"TT"`` of a lathe of several paths, ``"MT"`` of a lathe with
    the compound machining function; case aside), else "M"."""
    return "T" if mt_type.strip().upper().endswith("T") else "M"


#: FANUC's path-type parameters the machine keeps one value of per path (the others are
#: shared): 1401 (rapid traverse bits), 1422 (maximum cutting feed), 6700 (M codes that
#: count parts), 6710 (the M code that counts parts), 6711 parts count, 6712 total parts,
#: 6713 parts required, 6750-6758 (the run-time counters).
PATH_PARAMS: Final = frozenset({1401, 1422, 6700, 6710, 6711, 6712, 6713, *range(6750, 6759)})
#: The parameters a path's engine executes by (``Path._nc_settings``): a write of one is taken
#: at once. Stroke limit 1320/1321, reference 1240, rapid 1420, feed 1422, waiting M codes.
SETTING_PARAMS: Final = frozenset({1240, 1320, 1321, 1420, 1422, 8110, 8111})
#: The macro variables each path has its own of: the locals #1-#33 of its program and the
#: common variables #100-#199 (FANUC's default; #500-#999 are shared).
PATH_MACROS: Final = frozenset((*range(1, 34), *range(100, 200)))


@dataclass(frozen=True, slots=True)
class PathSpec:
    """One path for :class:`~focas_net.sim.Machine`: its axis names (distinct across the
    machine), its name (``"PATH<n>"`` when empty), its machine type (``"M"`` or ``"T"``), its
    number of spindles, its programs (texts; the first is the main program unless
    ``main_program`` names another), its operator panel and its motion figures (None: a panel
    in MEM, figures at 0)."""

    axes: tuple[str, ...]
    name: str = ""
    kind: str = "M"
    spindles: int = 1
    programs: tuple[str, ...] = ()
    main_program: int | None = None
    panel: Panel | None = None
    motion: MotionData | None = None


@dataclass(frozen=True, slots=True)
class PathInfo:
    """What the machine says of one of its paths: its number (1..), its name, its machine
    type (``"M"`` or ``"T"``), its axis names and its number of spindles."""

    number: int
    name: str
    kind: str
    axes: tuple[str, ...]
    spindles: int


def checked_specs(specs: Sequence[PathSpec]) -> list[PathInfo]:
    """The paths' descriptions once checked (ValueError naming the path otherwise): 1..10
    paths, each with 1..20 axes, axis names distinct across the machine, a kind of
    :data:`PATH_KINDS`, 1..8 spindles, names distinct."""
    if not 1 <= len(specs) <= MAX_PATHS:
        raise ValueError(f"a machine has 1..{MAX_PATHS} paths, got {len(specs)}")
    infos: list[PathInfo] = []
    owner: dict[str, int] = {}
    names: dict[str, int] = {}
    for number, spec in enumerate(specs, 1):
        where = f"path {number}"
        _check_types(spec, where)
        axes = tuple(spec.axes)
        problem = axes_problem(axes)
        if problem is not None:
            raise ValueError(f"{where}: {problem}" if len(specs) > 1 else problem)
        for axis in axes:
            if axis in owner:
                first = owner[axis]
                also = "twice" if first == number else f"also on path {first}"
                raise ValueError(f"{where}: axis {axis!r} is named {also}")
            owner[axis] = number
        if spec.kind not in PATH_KINDS:
            raise ValueError(f"{where}: kind {spec.kind!r} is not one of {PATH_KINDS}")
        if not 1 <= spec.spindles <= 8:
            raise ValueError(f"{where}: 1..8 spindles, got {spec.spindles!r}")
        name = spec.name or f"PATH{number}"
        if name in names:
            raise ValueError(f"{where}: name {name!r} is path {names[name]}'s")
        names[name] = number
        infos.append(PathInfo(number, name, spec.kind, axes, spec.spindles))
    return infos


def _check_types(spec: PathSpec, where: str) -> None:
    """TypeError naming ``where`` (``path 1``) and the value for a field of ``spec`` of
    another type than it takes; ValueError for a name that is not one line of printable
    text (it shows on the page and in the logs, ``machine/name``)."""
    if isinstance(spec.axes, bytes) or not isinstance(spec.axes, Iterable):
        raise TypeError(f"{where}: axes must be a list of axis names, got {spec.axes!r}")
    for what, value in (("kind", spec.kind), ("name", spec.name)):
        if not isinstance(value, str):
            raise TypeError(f"{where}: {what} must be text (str), got {value!r}")
    bad = next((c for c in spec.name if not c.isprintable()), None)
    if bad is not None:
        raise ValueError(f"{where}: name {spec.name!r}: {bad!r} is not printable")
    try:
        need_int("spindles", spec.spindles)
    except TypeError as exc:
        raise TypeError(f"{where}: {exc}") from None


def own_params(items: Items, number: int) -> dict[int, DataItem]:
    """The path-type parameters path ``number`` holds its own values of: none for path 1,
    which keeps the machine's table's, copies of them for the others."""
    if number == 1:
        return {}
    return {n: copy.deepcopy(items.params[n]) for n in PATH_PARAMS if n in items.params}


class PathItems:
    """The parameters and diagnostics as one path reads them: axis items by the path's own
    axis numbers (``offset`` axes of earlier paths before them), path-type parameters from
    ``own`` when the path has its own (see :func:`own_params`)."""

    __slots__ = ("axes", "items", "offset", "own")

    def __init__(self, items: Items, offset: int, axes: int, own: dict[int, DataItem]) -> None:
        self.items = items
        self.offset = offset
        self.axes = axes
        self.own = own

    def param(self, number: int) -> DataItem | None:
        item = self.own.get(number)
        return item if item is not None else self.items.params.get(number)

    def lookup(self, diag: bool, datano: int, axis: int) -> tuple[DataItem, int]:
        """A parameter (a diagnostic when ``diag``) and the index of the value of the path's
        ``axis``: EW_NUMBER (no such item), then EW_ATTRIB (axis 0 for an axis item, an axis
        for another, an axis beyond the path's), in the packed contract's order; TypeError
        for a number of another type. (The clients name an axis beyond the path's first,
        as FANUC's library does before sending.)"""
        need_int("number", datano)
        need_int("axis", axis)
        item = self.items.diags.get(datano) if diag else self.param(datano)
        what = "diagnostic" if diag else "parameter"  # named as every front end names it
        if item is None:
            raise MachineError(EW.NUMBER, no_item(what, datano))
        if item.axis:
            if axis > self.axes:  # as a position's axis past the path's is worded
                raise MachineError(EW.ATTRIB, axis_past(axis, self.axes))
            if axis < 1:
                why = f"{axis_misfit(what, datano, 0)}: give an axis 1..{self.axes}, got {axis}"
                raise MachineError(EW.ATTRIB, why)
            return item, self.offset + axis - 1
        if axis != 0:
            why = f"{axis_misfit(what, datano, axis)}: give axis 0, got {axis}"
            raise MachineError(EW.ATTRIB, why)
        return item, 0

    def param_or(self, number: int, default: int, axis: int = 0) -> int:
        """The value of parameter ``number`` (of the path's ``axis``; 0 for a non-axis one),
        ``default`` when the machine has none such."""
        item = self.param(number)
        if item is None or (axis == 0) == item.axis:
            return default
        return item.values[self.offset + axis - 1 if axis else 0]

    def param_float(self, number: int, default: float, axis: int, unit: float) -> float:
        """Parameter ``number`` of the path's ``axis`` as a number (see
        :meth:`Items.param_float`)."""
        item = self.param(number)
        if item is None or (axis == 0) == item.axis:
            return default
        raw = item.values[self.offset + axis - 1 if axis else 0]
        if item.kind is ParamKind.REAL:
            return raw / float(10**item.decimals)
        return raw * unit

    def clamp(self, number: int, value: int) -> bool:
        """Set non-axis parameter ``number`` to ``value`` held within its range; False when
        the machine has no such parameter."""
        item = self.param(number)
        if item is None:
            return False
        assert item.high is not None and item.low is not None
        item.values[0] = max(item.low, min(item.high, value))
        counters = self.items.counters
        counters.data += 1
        counters.version += 1
        return True


class Paths:
    """The machine's paths, numbered from 1."""

    __slots__ = ("all", "count", "infos", "stopped")

    def __init__(self, paths: list[Path], infos: list[PathInfo]) -> None:
        self.all = paths
        self.infos = infos
        self.count = len(paths)
        #: How many :meth:`stop_time` calls are not yet matched by :meth:`go_time`.
        self.stopped = 0

    def stop_time(self) -> None:
        """Every path's machine time stands at one reading of its clock until the matching
        :meth:`go_time` (nested calls keep the first reading): the instant of one answer.
        Paths reading one clock read it once, so they stand at the same moment."""
        self.stopped += 1
        if self.stopped > 1:
            return
        if self.count == 1:
            time = self.all[0].time
            time.stop(time.source.now())
            return
        readings: list[tuple[object, float]] = []  # (clock, its reading): a path or two
        for p in self.all:
            source = p.time.source
            at = next((at for clock, at in readings if clock is source), None)
            if at is None:
                at = source.now()
                readings.append((source, at))
            p.time.stop(at)

    def go_time(self) -> None:
        """Undo one :meth:`stop_time`; the last one lets machine time run again."""
        if self.stopped <= 0:
            raise RuntimeError("machine time is not stopped")
        self.stopped -= 1
        if not self.stopped:
            for p in self.all:
                p.time.go()

    def __enter__(self) -> None:
        """``with paths:`` is the instant of one answer (:meth:`stop_time`, then
        :meth:`go_time`): what :meth:`Machine.instant` gives."""
        self.stop_time()

    def __exit__(self, *exc: object) -> None:
        self.go_time()

    def __iter__(self) -> Iterator[Path]:
        return iter(self.all)

    def at(self, path: int) -> Path:
        """Path ``path``: EW_PATH naming it and the machine's range when there is none; a
        TypeError for a path of another type (``"1"``, ``1.0``), as every other number."""
        if 1 <= need_int("path", path) <= self.count:
            return self.all[path - 1]
        raise MachineError(EW.PATH, no_path(path, self.count))

    def info(self, path: int) -> PathInfo:
        self.at(path)
        return self.infos[path - 1]

    def sync(self) -> None:
        """Bring every path to the clock's time (the waiting M codes tie them together)."""
        for p in self.all:
            p.sync()

    @property
    def live(self) -> bool:
        """Whether time alone may change what a path shows."""
        if self.count == 1:
            return self.all[0].live
        return any(p.live for p in self.all)

    def start_production(self, scenario: Scenario) -> None:
        """Run ``scenario`` on path 1 and produce alongside on every other path from the same
        moment (see :meth:`~._production.Production.start`)."""
        first = self.all[0]
        if self.count == 1:
            first.production.start(scenario)
            return
        for p in self.all[1:]:
            p.production.check_start()
        origin = first.production.start(scenario, settle=False)
        for p in self.all[1:]:
            p.production.follow(origin, first.engine.parts_to_go)
        self.sync()

    def stop_production(self) -> None:
        """Stop the scenario (the cycles go on as they are, without its part limit: the
        other paths' too)."""
        self.all[0].production.stop()
        for p in self.all[1:]:
            p.sync()
            p.engine.parts_to_go = None


def path_specs(
    paths: Sequence[PathSpec] | None,
    axes: Iterable[str] | None,
    panel: Panel | None,
    motion: MotionData | None,
    programs: Iterable[str],
    main_program: int | None,
    identity: Identity | None,
) -> list[PathSpec]:
    """The machine's paths: ``paths``, or one path of the single-path arguments (ValueError
    when both are given; TypeError for ``programs`` that are no list of texts)."""
    programs = tuple(
        need_items("programs", programs, str, items="program texts", item="a program's text (str)")
    )
    if paths is None:
        return [
            PathSpec(
                tuple(axes if axes is not None else ("X", "Y", "Z")),
                kind=kind_of(identity.mt_type) if identity is not None else "M",
                programs=tuple(programs),
                main_program=main_program,
                panel=panel,
                motion=motion,
            )
        ]
    given = [
        what
        for what, value in (
            ("axes", axes),
            ("panel", panel),
            ("motion", motion),
            ("main_program", main_program),
        )
        if value is not None
    ]
    if programs:
        given.append("programs")
    if given:
        raise ValueError(f"{', '.join(given)} given with paths: each path has its own")
    if not 1 <= len(paths) <= MAX_PATHS:
        raise ValueError(f"a machine has 1..{MAX_PATHS} paths, got {len(paths)}")
    return list(paths)
