"""The machine's operations of tool offsets, work zero offsets and tool life, a part of
:class:`~focas_net.sim.Machine` (the model: :mod:`._tools`).

Each takes ``path`` (keyword, 1 by default) and answers for that path (EW_PATH for one the
machine has not). Check order of a read: EW_PATH, then the ranges (:mod:`._tools`); of a
write: EW_PROT (read-only machine), EW_PATH, the ranges, the value. Values are in least input
increments (0.001 mm). A tool life read first brings the path to the clock's time, so the
counters follow the running program.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Final

from focas_net._refusals import axis_past
from focas_net.errors import EW

from ._base import Counters, MachineError, n_values, need_int
from ._path import Path
from ._paths import Paths
from ._tools import (
    WORK_OFFSET_NAMES,
    ToolLife,
    ToolOffsets,
    ToolsSpec,
    _number,
)
from .nc import EngineEvent

__all__ = [
    "MAX_WORK_OFFSET",
    "GroupStatus",
    "LifeInfo",
    "PathTools",
    "ToolOffsetInfo",
    "ToolOperations",
    "build_tools",
    "work_problem",
]

#: Largest work zero offset in least input increments (99999.999 mm).
MAX_WORK_OFFSET: Final = 99_999_999
#: The largest life of each type: FANUC's 9999 uses and 4300 minutes.
_MAX_MINUTES: Final = 4300
_MAX_CYCLES: Final = 9999


def _values(values: object, what: str) -> Sequence[int]:
    """``values`` when it is a non-empty sequence (a list, a tuple): a write of no values is
    EW_LENGTH, as a PMC write of no bytes is; TypeError naming ``what`` for another type (a
    number, text, bytes). Each value is checked by the write."""
    if isinstance(values, str | bytes | bytearray) or not isinstance(values, Sequence):
        raise TypeError(f"{what} must be a list or tuple of integers, got {values!r}")
    if not values:
        raise MachineError(EW.LENGTH, f"{what}: a write of no values")
    return values


def _rows(rows: object) -> Sequence[object]:
    """``rows`` when it is a non-empty sequence of rows (EW_LENGTH for none, TypeError for
    another type)."""
    if isinstance(rows, str | bytes | bytearray) or not isinstance(rows, Sequence):
        raise TypeError(f"work offset rows must be a list or tuple of rows, got {rows!r}")
    if not rows:
        raise MachineError(EW.LENGTH, "work offset rows: a write of no rows")
    return rows


@dataclass(frozen=True, slots=True)
class ToolOffsetInfo:
    """The kind of a path's tool offset memory and its size: ``kind`` ``"M"`` (memory C: 4
    types) or ``"T"`` (7 types), ``types`` their names by number, ``count`` the numbers."""

    kind: str
    types: tuple[str, ...]
    count: int


@dataclass(frozen=True, slots=True)
class LifeInfo:
    """The tool life management of a path: groups declared, the most groups and tools per
    group, the largest life in minutes and in uses, and the groups of the tool in use."""

    groups: int
    max_groups: int
    max_tools: int
    max_minutes: int
    max_cycles: int
    selected: int


@dataclass(frozen=True, slots=True)
class GroupStatus:
    """One tool life group as it is now: its life type and life, the counter of the tool in
    use, the index (1..) of that tool, and each tool ``(T, H, D, state)``."""

    number: int
    life_type: str
    life: int
    count: int
    in_use: int
    tools: tuple[tuple[int, int, int, int], ...]


def work_problem(name: str, values: Sequence[int], axes: int) -> str | None:
    """Why work offset ``name`` (``G54``, ``EXT`` ...) cannot be ``values`` (least increments,
    one per axis of a path of ``axes`` axes); None: it can."""
    if name not in WORK_OFFSET_NAMES:
        return f"work offset {name!r}: not one of {WORK_OFFSET_NAMES}"
    if len(values) != axes:
        return f"work offset {name}: {n_values(len(values), axes)}"
    for value in values:
        if not -MAX_WORK_OFFSET <= value <= MAX_WORK_OFFSET:
            mm = Decimal(value).scaleb(-3)
            return f"work offset {name}: {mm} mm is beyond 99999.999 mm"
    return None


class PathTools:
    """The tool offsets and tool life of one path, following its engine's events."""

    __slots__ = ("life", "offsets", "path")

    def __init__(self, path: Path, kind: str, spec: ToolsSpec) -> None:
        self.path = path
        engine = path.engine
        self.offsets = ToolOffsets(kind, spec.offsets, engine.tool_offsets, spec.offset_values)
        self.life = ToolLife(spec.max_groups, spec.max_tools, spec.groups, spec.ignore)
        for name, values in spec.work.items():
            problem = work_problem(name, values, len(path.axes))
            if problem is not None:
                raise ValueError(problem)
            for axis, value in enumerate(values):
                engine.work_offsets[WORK_OFFSET_NAMES.index(name)][axis] = value / 1000
        path.listeners.append(self.engine_event)

    def engine_event(self, event: EngineEvent, now: float) -> None:
        """A tool change selects the group of its tool, a program's end counts the cycle."""
        life = self.life
        if event.kind == "tool":
            life.cutting(self.path.engine.cutting_time)
            life.tool_changed(event.value)
        elif event.kind == "end":
            life.cutting(self.path.engine.cutting_time)
            life.cycle_ended()


def build_tools(paths: Paths, specs: Mapping[int, ToolsSpec]) -> dict[int, PathTools]:
    """The tools of every path of ``paths``, as ``specs`` declares them per path number (the
    defaults for a path not given; ValueError for a path the machine has not)."""
    unknown = sorted(set(specs) - set(range(1, paths.count + 1)))
    if unknown:
        raise ValueError(f"tools of path {unknown[0]}: the machine has {paths.count} paths")
    return {
        n: PathTools(paths.at(n), paths.info(n).kind, specs.get(n, ToolsSpec()))
        for n in range(1, paths.count + 1)
    }


class ToolOperations:
    """The tool and work offset and tool life operations of the machine (a base of
    :class:`~focas_net.sim.Machine`, which builds :attr:`_tools`)."""

    _paths: Paths
    _tools: dict[int, PathTools]
    _counters: Counters

    def check_writable(self) -> None:  # pragma: no cover - the machine's
        raise NotImplementedError

    def _tools_of(self, path: int) -> PathTools:
        self._paths.at(path)  # EW_PATH naming the path
        return self._tools[path]

    # -- tool offsets --------------------------------------------------------------------
    def tool_offset_info(self, *, path: int = 1) -> ToolOffsetInfo:
        """The kind of the path's tool offset memory and how many numbers it has."""
        offsets = self._tools_of(path).offsets
        return ToolOffsetInfo(offsets.kind, offsets.types, offsets.count)

    def tool_offsets(
        self, first: int, last: int, offset_type: int | None, *, path: int = 1
    ) -> list[tuple[int, ...]]:
        """The values of tool offsets ``first..last`` (inclusive): of type ``offset_type``, or
        every type in type order (None). EW_NUMBER for a number outside 1..count or ``last``
        before ``first``, EW_ATTRIB for a type the path has not."""
        offsets = self._tools_of(path).offsets
        _number(first, 1, offsets.count, "tool offset number")
        _number(last, first, offsets.count, "last tool offset number")
        kinds = range(len(offsets.types)) if offset_type is None else (offset_type,)
        for kind in kinds:
            offsets.check(first, kind)
        return [tuple(offsets.read(n, k) for k in kinds) for n in range(first, last + 1)]

    def write_tool_offset(
        self, number: int, offset_type: int, value: int, *, path: int = 1
    ) -> None:
        """Set one tool offset value (EW_PROT, EW_PATH, EW_NUMBER, EW_ATTRIB, EW_DATA); a
        machining centre's length is what G43/G44 applies from its next H."""
        self.write_tool_offsets(number, offset_type, (value,), path=path)

    def write_tool_offsets(
        self, first: int, offset_type: int, values: Sequence[int], *, path: int = 1
    ) -> None:
        """Set tool offsets ``first``, ``first + 1``... of type ``offset_type``, one value
        each: every number and value is checked before any is set (EW_PROT, EW_PATH,
        EW_NUMBER, EW_LENGTH for no values, EW_ATTRIB, EW_DATA; TypeError for values that are
        no list or tuple), so a refused write changes nothing."""
        self.check_writable()
        offsets = self._tools_of(path).offsets
        _number(first, 1, offsets.count, "tool offset number")
        values = _values(values, "tool offset values")
        for number, value in enumerate(values, first):
            offsets.check_value(number, offset_type, value)
        for number, value in enumerate(values, first):
            offsets.write(number, offset_type, value)
        self._moved()

    # -- work zero offsets -----------------------------------------------------------------
    def work_offsets(
        self, first: int, last: int, axis: int | None, *, path: int = 1
    ) -> list[tuple[int, ...]]:
        """Work zero offsets ``first..last`` (0 external, 1..6 G54..G59), each the values of
        every axis (``axis`` None) or of axis ``axis`` (1..n). EW_NUMBER outside 0..6 or for
        ``last`` before ``first``, EW_ATTRIB for an axis the path has not."""
        rows = self._work_rows(first, last, path)
        axes = self._axes(axis, path)
        return [tuple(round(row[a] * 1000) for a in axes) for row in rows]

    def write_work_offset(
        self, number: int, axis: int | None, values: Sequence[int], *, path: int = 1
    ) -> None:
        """Set work zero offset ``number`` of every axis (``axis`` None, one value per axis)
        or of axis ``axis`` (one value): EW_PROT, EW_PATH, EW_NUMBER, EW_ATTRIB, EW_LENGTH
        (a count of values that does not fit), EW_DATA (a value beyond 99999.999 mm). The
        program's work positions follow at once."""
        self.write_work_offsets(number, axis, (values,), path=path)

    def write_work_offsets(
        self, first: int, axis: int | None, rows: Sequence[Sequence[int]], *, path: int = 1
    ) -> None:
        """Set work zero offsets ``first``, ``first + 1``..., one row of values each (as
        :meth:`write_work_offset`; EW_LENGTH for no rows, TypeError for rows that are no list
        or tuple): every row is checked before any is set, so a refused write changes
        nothing."""
        self.check_writable()
        _number(first, 0, len(WORK_OFFSET_NAMES) - 1, "work offset number")
        rows = [_values(values, "work offset values") for values in _rows(rows)]
        targets = self._work_rows(first, first + len(rows) - 1, path)
        axes = self._axes(axis, path)
        for values in rows:
            if len(values) != len(axes):
                raise MachineError(EW.LENGTH, n_values(len(values), len(axes)))
            for value in values:
                _number(value, -MAX_WORK_OFFSET, MAX_WORK_OFFSET, "work offset", EW.DATA)
        for row, values in zip(targets, rows, strict=True):
            for a, value in zip(axes, values, strict=True):
                row[a] = value / 1000
        self._moved()

    def _work_rows(self, first: int, last: int, path: int) -> list[list[float]]:
        engine = self._tools_of(path).path.engine
        top = len(WORK_OFFSET_NAMES) - 1
        _number(first, 0, top, "work offset number")
        _number(last, first, top, "last work offset number")
        return engine.work_offsets[first : last + 1]

    def _axes(self, axis: int | None, path: int) -> range:
        count = len(self._paths.at(path).axes)
        if axis is None:
            return range(count)
        if not 1 <= need_int("axis", axis) <= count:
            raise MachineError(EW.ATTRIB, axis_past(axis, count))
        return range(axis - 1, axis)

    def _moved(self) -> None:
        c = self._counters
        c.motion += 1
        c.macro += 1
        c.version += 1

    # -- tool life -----------------------------------------------------------------------
    def _life(self, path: int) -> ToolLife:
        tools = self._tools_of(path)
        tools.path.sync()
        life = tools.life
        life.cutting(tools.path.engine.cutting_time)
        return life

    def tool_life_info(self, *, path: int = 1) -> LifeInfo:
        """The path's tool life management limits, its groups and the group in use."""
        life = self._life(path)
        return LifeInfo(
            len(life.groups),
            life.max_groups,
            life.max_tools,
            _MAX_MINUTES,
            _MAX_CYCLES,
            life.selected,
        )

    def tool_group(self, number: int, *, path: int = 1) -> GroupStatus:
        """Tool life group ``number`` now: EW_NUMBER outside 1..max groups or undeclared."""
        group = self._life(path).group(number)
        return GroupStatus(
            group.number,
            group.life_type,
            group.life,
            group.count,
            group.current + 1,
            tuple((t.number, t.h, t.d, t.state) for t in group.tools),
        )

    def group_tools(
        self, number: int, first: int, last: int, *, path: int = 1
    ) -> tuple[tuple[int, int, int, int], ...]:
        """Tools ``first..last`` (1.., in the order the group uses them) of group ``number``,
        each ``(T, H, D, state)``: the group's refusals, then EW_NUMBER for a tool the group
        has not or ``last`` before ``first``."""
        tools = self.tool_group(number, path=path).tools
        _number(first, 1, len(tools), f"group {number}'s tool")
        _number(last, first, len(tools), f"group {number}'s last tool")
        return tools[first - 1 : last]

    def set_tool_life_count(self, number: int, count: int, *, path: int = 1) -> None:
        """Set the counter of group ``number``'s tool in use (EW_PROT, EW_PATH, EW_NUMBER,
        EW_DATA outside 0..life)."""
        self.check_writable()
        self._life(path).set_count(number, count)
        self._counters.version += 1  # kept across power-off: the state file sees the change
