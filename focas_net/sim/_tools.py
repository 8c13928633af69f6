"""Tool offsets, work zero offsets and tool life management of one path (protocol-free).

What a FANUC control keeps per path and a program uses:

* **Tool offsets** (:class:`ToolOffsets`): numbered 1..``count``, each with the values of its
  machine type's offset memory. A machining centre (``"M"``) has FANUC's tool offset memory
  C: for each number a cutter radius wear and geometry and a tool length wear and geometry
  (types 0..3, in that order, as ``cnc_rdtofs`` numbers them). A lathe (``"T"``) has for each
  number the X, Z and nose radius wear and geometry and the imaginary tool tip (types 0..6:
  X wear, X geometry, Z wear, Z geometry, R wear, R geometry, tip). Values are in least input
  increments (0.001 mm); a length, radius or axis offset is within +-999.999 mm, a tip
  0..9. On a machining centre the interpreter's G43/G44 H takes the length geometry plus
  the wear of H (kept in step with the engine's table on every change).
* **Work zero offsets**: the engine's own rows (external offset 0, G54..G59 1..6) that the
  program reads and writes as #5201-#5326, read and written here in least input increments.
* **Tool life management** (:class:`ToolLife`): groups 1..``max_groups`` of at most
  ``max_tools`` tools (T number, H and D code each). A group counts its life in uses
  (``"count"``: one per cycle, at M02/M30, for each group whose tool was changed to in that
  cycle; FANUC's counting by the number of times a program is run) or in minutes of cutting
  (``"time"``: the engine's cutting time while a tool of the group is the tool in use). The
  counter is that of the tool in use in the group; when it reaches the life, that tool is
  expired and the next tool of the group takes over with its counter at 0 (the group is
  expired when its last tool is). The T code of a tool change (M6 with T) names the group:
  with FANUC's tool life ignore number (parameter 6810) a T code above it names group
  T - ignore and one at or below it is an ordinary tool, no group's; without one (0) a T
  code names the group that lists that T number. As on FANUC, a T number may be listed in
  several groups when groups are named through the ignore number; without one it could
  name none of them, so it is listed in one group only (:func:`listed_elsewhere`).

Every check of a value lives here (:class:`~._base.MachineError` with the EW code): a number
outside the table is EW_NUMBER, an offset type or axis the path has not is EW_ATTRIB, a value
out of range is EW_DATA, a group that is not declared is EW_NUMBER.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, MutableMapping, Sequence
from dataclasses import dataclass, field
from decimal import Decimal
from typing import Final

from focas_net.errors import EW

from ._base import MachineError, need_int

__all__ = [
    "LIFE_TYPES",
    "MAX_OFFSET",
    "MAX_TOOL_OFFSETS",
    "OFFSET_TYPES",
    "TOOL_STATES",
    "WORK_OFFSET_NAMES",
    "LifeTool",
    "ToolGroup",
    "ToolLife",
    "ToolOffsets",
    "ToolsSpec",
    "offset_problem",
]

#: The offset types of each machine type, in FANUC's numbering (the index is the type).
OFFSET_TYPES: Final[dict[str, tuple[str, ...]]] = {
    "M": ("radius_wear", "radius_geometry", "length_wear", "length_geometry"),
    "T": ("x_wear", "x_geometry", "z_wear", "z_geometry", "nose_wear", "nose_geometry", "tip"),
}
#: A machine type in words.
_KIND_WORDS: Final = {"M": "a machining centre", "T": "a lathe"}
#: Largest offset value in least input increments (999.999 mm).
MAX_OFFSET: Final = 999_999
#: Largest tip number of a lathe's imaginary tool tip.
MAX_TIP: Final = 9
#: Most tool offsets a path can have (FANUC's 0i and 16i: up to 999 with the option).
MAX_TOOL_OFFSETS: Final = 999
#: The work offset rows: external offset 0, then G54..G59.
WORK_OFFSET_NAMES: Final = ("EXT", "G54", "G55", "G56", "G57", "G58", "G59")
#: How a group counts its life.
LIFE_TYPES: Final = ("count", "time")
#: A tool's state in its group (FANUC's tool information): 0 not used yet, 1 in use, 2 life
#: expired, 3 skipped.
TOOL_STATES: Final = ("unused", "in use", "expired", "skipped")
#: Largest life of a group (FANUC: 9999 uses or 4300 minutes).
_MAX_LIFE: Final = {"count": 9999, "time": 4300}
#: Most groups and tools per group a machine file may declare.
MAX_GROUPS: Final = 512
MAX_TOOLS_PER_GROUP: Final = 32
#: Largest T, H and D number.
MAX_T: Final = 99_999_999


def _number(value: int, low: int, high: int, what: str, ew: int = EW.NUMBER) -> int:
    """``value`` within ``low..high``: ``ew`` naming it outside; a number of another type
    (``"3"``, ``1.5``, ``True``) a TypeError naming it, as every other operation of the
    machine refuses one (not a range it would not be outside)."""
    need_int(what, value)
    if not low <= value <= high:
        raise MachineError(ew, f"{what} {value!r} is outside {low}..{high}")
    return value


def offset_problem(kind: str, number: int, name: str, value: int) -> str | None:
    """Why tool offset ``number``'s type ``name`` cannot be ``value`` (least increments) on a
    path of machine type ``kind`` (None: it can): a type of the other kind, or past 999.999."""
    types = OFFSET_TYPES[kind]
    if name not in types:
        owner = " or ".join(_KIND_WORDS[k] for k, n in OFFSET_TYPES.items() if name in n)
        return (
            f"tool offset {number}: {name} is {owner or 'no machine'}'s offset, not "
            f"{_KIND_WORDS[kind]}'s (kind {kind}): {', '.join(types)}"
        )
    if name != "tip" and not -MAX_OFFSET <= value <= MAX_OFFSET:  # as typed: in mm
        mm = Decimal(value).scaleb(-3)
        return f"tool offset {number} {name}: {mm} mm is beyond 999.999 mm"
    return None


class ToolOffsets:
    """The tool offset table of one path (see the module docstring): ``count`` numbers of the
    types of machine type ``kind``; ``lengths`` is the engine's table (H -> length in mm)
    kept in step on a machining centre."""

    __slots__ = ("_lengths", "_values", "count", "kind", "types")

    def __init__(
        self,
        kind: str,
        count: int,
        lengths: MutableMapping[int, float],
        values: Mapping[tuple[int, str], int] | None = None,
    ) -> None:
        self.kind = kind
        #: The names of the types, by type number.
        self.types = OFFSET_TYPES[kind]
        self.count = _number(count, 1, MAX_TOOL_OFFSETS, "tool offset count", EW.DATA)
        self._values: dict[tuple[int, int], int] = {}
        self._lengths = lengths
        for (number, name), value in (values or {}).items():
            problem = offset_problem(kind, number, name, value)
            if problem is not None:
                raise ValueError(problem)
            try:
                self.write(number, self.types.index(name), value)
            except MachineError as exc:
                raise ValueError(exc.detail) from None

    def check(self, number: int, offset_type: int) -> None:
        """EW_NUMBER for a number outside 1..count, EW_ATTRIB for a type the path has not."""
        _number(number, 1, self.count, "tool offset number")
        _number(offset_type, 0, len(self.types) - 1, "tool offset type", EW.ATTRIB)

    def read(self, number: int, offset_type: int) -> int:
        """The value of offset ``number`` of type ``offset_type`` (least input increments)."""
        self.check(number, offset_type)
        return self._values.get((number, offset_type), 0)

    def check_value(self, number: int, offset_type: int, value: int) -> None:
        """:meth:`check`, then EW_DATA for a value out of its type's range."""
        self.check(number, offset_type)
        high = MAX_TIP if self.types[offset_type] == "tip" else MAX_OFFSET
        low = 0 if high == MAX_TIP else -MAX_OFFSET
        _number(value, low, high, f"tool offset {number} {self.types[offset_type]}", EW.DATA)

    def write(self, number: int, offset_type: int, value: int) -> None:
        """Set one value (checks: :meth:`check_value`)."""
        self.check_value(number, offset_type, value)
        if value:
            self._values[(number, offset_type)] = value
        else:
            self._values.pop((number, offset_type), None)
        if self.kind == "M" and offset_type >= 2:  # a length: what G43/G44 H applies
            length = self._values.get((number, 2), 0) + self._values.get((number, 3), 0)
            if length:
                self._lengths[number] = length / 1000
            else:
                self._lengths.pop(number, None)


@dataclass(slots=True)
class LifeTool:
    """One tool of a group: its T number, H and D codes and state (:data:`TOOL_STATES`)."""

    number: int
    h: int = 0
    d: int = 0
    state: int = 0


@dataclass(slots=True)
class ToolGroup:
    """One tool life group: its life type and life, the counter of the tool in use, its
    tools in the order they are used, the index of the tool in use and the cutting seconds
    not yet counted."""

    number: int
    life: int
    life_type: str = "count"
    count: int = 0
    tools: list[LifeTool] = field(default_factory=list)
    current: int = 0
    seconds: float = 0.0

    @property
    def expired(self) -> bool:
        """Whether every tool of the group is expired (or skipped)."""
        return bool(self.tools) and all(t.state >= 2 for t in self.tools)

    def select(self) -> None:
        """A T code named the group: from the tool in use on, the first tool whose life has
        not expired is the one in use (its counter from 0 when it is another); the last tool
        when every one has expired."""
        n = len(self.tools)
        for step in range(n):
            i = (self.current + step) % n
            if self.tools[i].state < 2:
                if i != self.current:
                    self.count = 0
                self.current = i
                if self.tools[i].state == 0:
                    self.tools[i].state = 1
                return
        self.current = n - 1

    def advance(self, amount: int) -> None:
        """Add ``amount`` to the counter of the tool in use, up to the life; the tool
        expires when its counter reaches the life (the next selection takes another)."""
        tool = self.tools[self.current]
        if tool.state >= 2 or amount <= 0:
            return
        self.count = min(self.count + amount, self.life)
        if self.count >= self.life:
            tool.state = 2


@dataclass(frozen=True, slots=True)
class ToolsSpec:
    """What a machine file declares of one path's tools: the offset count and values
    (``(number, type name) -> value``, :data:`OFFSET_TYPES`), the work offsets (a name of
    :data:`WORK_OFFSET_NAMES` -> one value per axis), values in least input increments; the
    tool life limits and groups, and the tool life ignore number (0: none)."""

    offsets: int = 64
    offset_values: Mapping[tuple[int, str], int] = field(default_factory=dict)
    work: Mapping[str, Sequence[int]] = field(default_factory=dict)
    max_groups: int = 16
    max_tools: int = 4
    groups: Sequence[ToolGroup] = ()
    ignore: int = 0


def listed_elsewhere(groups: Iterable[ToolGroup], group: ToolGroup) -> tuple[int, int] | None:
    """The first tool of ``group`` that one of ``groups`` lists too: its index in ``group``
    and the other group's number (None: none). Without an ignore number a T code names the
    group that lists the tool, so such a tool names no group of its own."""
    for other in groups:
        numbers = {t.number for t in other.tools}
        for i, tool in enumerate(group.tools):
            if tool.number in numbers:
                return i, other.number
    return None


def repeated_tool(group: ToolGroup) -> tuple[int, str] | None:
    """The second listing of a tool ``group`` lists twice (its index) and why that cannot be
    (None: none): a tool is listed once in a group, whose next tool is the next one listed."""
    seen: set[int] = set()
    for index, tool in enumerate(group.tools):
        if tool.number in seen:
            return index, f"T{tool.number} is in tool group {group.number} twice: list a tool once"
        seen.add(tool.number)
    return None


def listed_twice(tool: int, other: int) -> str:
    """Why T ``tool`` cannot be in a second group as well as in group ``other``."""
    return (
        f"T{tool} is in tool group {other} too: without an ignore number a T code names the "
        "group that lists the tool, so a tool is in one group (an ignore number, FANUC's "
        "parameter 6810, names groups by T code and lets a tool be in several)"
    )


class ToolLife:
    """The tool life management of one path (see the module docstring)."""

    __slots__ = ("_cutting", "_used", "groups", "ignore", "max_groups", "max_tools", "selected")

    def __init__(
        self, max_groups: int, max_tools: int, groups: Iterable[ToolGroup], ignore: int = 0
    ) -> None:
        self.max_groups = _number(max_groups, 1, MAX_GROUPS, "max tool groups", EW.DATA)
        self.max_tools = _number(max_tools, 1, MAX_TOOLS_PER_GROUP, "max tools", EW.DATA)
        #: FANUC's tool life ignore number (parameter 6810): a T code above it names group
        #: T - ignore, one at or below it no group; 0: a T code names the group listing it.
        self.ignore = _number(ignore, 0, MAX_T, "tool life ignore number", EW.DATA)
        self.groups: dict[int, ToolGroup] = {}
        for group in groups:
            self.add(group)
        #: The group of the tool in use (0: none), and the groups used in this cycle.
        self.selected = 0
        self._used: set[int] = set()
        self._cutting = 0.0

    def add(self, group: ToolGroup) -> None:
        """Declare ``group`` (ValueError for what a machine builder got wrong)."""
        if not 1 <= group.number <= self.max_groups:
            raise ValueError(f"tool group {group.number} is outside 1..{self.max_groups}")
        if group.number in self.groups:
            raise ValueError(f"tool group {group.number} is declared twice")
        if group.life_type not in LIFE_TYPES:
            raise ValueError(f"tool group {group.number}: life type {group.life_type!r}")
        if not 1 <= group.life <= _MAX_LIFE[group.life_type]:
            limit = _MAX_LIFE[group.life_type]
            raise ValueError(f"tool group {group.number}: life {group.life} is outside 1..{limit}")
        if not 0 <= group.count <= group.life:
            raise ValueError(
                f"tool group {group.number}: count {group.count} is outside 0..{group.life} "
                "(the life)"
            )
        tools = len(group.tools)
        if not 1 <= tools <= self.max_tools:
            raise ValueError(
                f"tool group {group.number} has {tools} tools: 1..{self.max_tools} are allowed"
            )
        if not 0 <= group.current < tools:
            raise ValueError(
                f"tool group {group.number}: the tool in use, current={group.current}, is "
                f"outside 0..{tools - 1} (the index among its {tools} tools)"
            )
        for tool in group.tools:
            for what, value in (("T", tool.number), ("H", tool.h), ("D", tool.d)):
                if not 0 <= value <= MAX_T or (what == "T" and value == 0):
                    raise ValueError(f"tool group {group.number}: {what}{value} out of range")
        repeated = repeated_tool(group)
        if repeated is not None:
            raise ValueError(repeated[1])
        shared = None if self.ignore else listed_elsewhere(self.groups.values(), group)
        if shared is not None:
            index, other = shared
            raise ValueError(
                f"tool group {group.number}: {listed_twice(group.tools[index].number, other)}"
            )
        self.groups[group.number] = group

    def group(self, number: int) -> ToolGroup:
        """Group ``number``: EW_NUMBER outside 1..max_groups or for one not declared."""
        _number(number, 1, self.max_groups, "tool group")
        found = self.groups.get(number)
        if found is None:
            raise MachineError(EW.NUMBER, f"tool group {number} has no tools")
        return found

    def group_of(self, tool: int) -> int:
        """The group whose tools include T ``tool`` (0: none)."""
        for group in self.groups.values():
            if any(t.number == tool for t in group.tools):
                return group.number
        return 0

    # -- what the program does ------------------------------------------------------------
    def tool_changed(self, tool: int) -> None:
        """M6 with T code ``tool``: the group it names is the group in use. The first time a
        group is changed to in a cycle (since the reset state) a tool whose life has not
        expired is selected from it, and a count-type group counts one use."""
        if self.ignore:  # FANUC: a T code at or below the ignore number is no group's
            named = tool - self.ignore if tool > self.ignore else 0
            self.selected = named if named in self.groups else 0
        else:
            self.selected = self.group_of(tool)
        if not self.selected or self.selected in self._used:
            return
        group = self.groups[self.selected]
        self._used.add(self.selected)
        group.select()
        if group.life_type == "count":
            group.advance(1)

    def cycle_ended(self) -> None:
        """M02/M30 (the reset state): the next cycle counts its groups again."""
        self._used.clear()

    def cutting(self, total_seconds: float) -> None:
        """The engine's cutting time is now ``total_seconds``: the time since the last call
        counts for the time-type group in use, in whole minutes."""
        delta = total_seconds - self._cutting
        self._cutting = total_seconds
        if delta <= 0 or not self.selected:
            return
        group = self.groups[self.selected]
        if group.life_type != "time":
            return
        group.seconds += delta
        minutes = int(group.seconds // 60)
        if minutes:
            group.seconds -= 60 * minutes
            group.advance(minutes)

    # -- what the operator sets -----------------------------------------------------------
    def set_count(self, number: int, count: int) -> None:
        """Set group ``number``'s counter (EW_NUMBER, then EW_DATA outside 0..life)."""
        group = self.group(number)
        _number(count, 0, group.life, f"tool group {number} count", EW.DATA)
        group.count = count
        tool = group.tools[group.current]
        if count < group.life and tool.state == 2:
            tool.state = 1
