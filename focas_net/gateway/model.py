"""What the gateway's parts exchange: the data items it reads, the samples and events its poller
produces, the shape of each machine, and the two interfaces between the poller and its outputs.

The poller (:mod:`focas_net.gateway.poller`) reads machines through
:class:`~focas_net.client.CncClient` and hands every change to each :class:`Sink` (the OPC UA
server, the MQTT publisher) synchronously, in the poller's task: a sink never blocks the poll,
it buffers and does its own I/O in its own task. Sinks write to machines only through a
:class:`Writer`, which applies the configuration's write gates.

Nothing here does I/O; everything is a frozen value.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence
from dataclasses import dataclass
from decimal import Decimal
from typing import Final, Protocol

from focas_net.errors import OpcUaStatus

__all__ = [
    "ITEMS",
    "AlarmChange",
    "Group",
    "Item",
    "MachineShape",
    "PathShape",
    "Sample",
    "Scope",
    "Sink",
    "Unit",
    "Value",
    "Writer",
    "item",
]

#: A sample's value: what JSON and OPC UA both carry.
Value = bool | int | float | str | None


class Group(enum.Enum):
    """How often an item is read: each group has its own poll interval in the configuration."""

    FAST = "fast"
    SLOW = "slow"


class Scope(enum.Enum):
    """What one sample of an item belongs to: the machine, one path, or one axis or spindle of
    a path (then :attr:`Sample.key` names it)."""

    MACHINE = "machine"
    PATH = "path"
    AXIS = "axis"
    SPINDLE = "spindle"


@dataclass(frozen=True, slots=True)
class Unit:
    """An engineering unit: its display symbol and its UN/CEFACT common code, from which OPC UA
    derives ``EUInformation.UnitId``."""

    symbol: str
    code: str
    description: str


MILLIMETRE: Final = Unit("mm", "MMT", "millimetre")
MM_PER_MINUTE: Final = Unit("mm/min", "H81", "millimetre per minute")
PER_MINUTE: Final = Unit("1/min", "RPM", "revolutions per minute")
PERCENT: Final = Unit("%", "P1", "percent")
SECOND: Final = Unit("s", "SEC", "second")
ONE: Final = Unit("", "C62", "one")


@dataclass(frozen=True, slots=True)
class Item:
    """One data item the gateway reads: its name (the last part of an MQTT topic, the browse
    name's base in OPC UA), its group, its scope, the Python type of its values, and its unit
    (None for states and texts)."""

    name: str
    group: Group
    scope: Scope
    kind: type[bool] | type[int] | type[float] | type[str]
    unit: Unit | None
    description: str


def _items(*rows: Item) -> dict[str, Item]:
    table: dict[str, Item] = {}
    for row in rows:
        if row.name in table:
            raise ValueError(f"item {row.name!r} is declared twice")
        table[row.name] = row
    return table


_F, _S = Group.FAST, Group.SLOW
_P, _A, _SP = Scope.PATH, Scope.AXIS, Scope.SPINDLE

#: Every item the gateway reads, by name: the one table the poller, the OPC UA model and the
#: MQTT topics share.
ITEMS: Final[dict[str, Item]] = _items(
    Item("mode", _F, _P, str, None, "operating mode (cnc_statinfo aut: MEM, EDIT, MDI, ...)"),
    Item("run", _F, _P, str, None, "automatic operation state (cnc_statinfo run)"),
    Item("motion", _F, _P, str, None, "axis motion state (cnc_statinfo motion)"),
    Item("emergency", _F, _P, bool, None, "emergency stop active"),
    Item("alarm", _F, _P, bool, None, "an alarm is active on the path"),
    Item("program", _F, _P, int, ONE, "number of the running program (O number)"),
    Item("main_program", _F, _P, int, ONE, "number of the main program"),
    Item("sequence", _F, _P, int, ONE, "sequence number (N) being executed"),
    Item("feed", _F, _P, float, MM_PER_MINUTE, "actual feed rate"),
    Item("spindle_speed", _F, _P, float, PER_MINUTE, "actual spindle speed"),
    Item("feed_override", _F, _P, int, PERCENT, "feed override"),
    Item("rapid_override", _F, _P, int, PERCENT, "rapid traverse override"),
    Item("spindle_override", _F, _P, int, PERCENT, "spindle override"),
    Item("absolute", _F, _A, float, MILLIMETRE, "absolute position"),
    Item("machine", _F, _A, float, MILLIMETRE, "machine position"),
    Item("relative", _F, _A, float, MILLIMETRE, "relative position"),
    Item("distance", _F, _A, float, MILLIMETRE, "distance to go"),
    Item("parts", _S, _P, int, ONE, "parts count"),
    Item("parts_total", _S, _P, int, ONE, "total parts count"),
    Item("parts_required", _S, _P, int, ONE, "required parts count"),
    Item("power_on_time", _S, _P, float, SECOND, "power-on time"),
    Item("operating_time", _S, _P, float, SECOND, "operating (automatic run) time"),
    Item("cutting_time", _S, _P, float, SECOND, "cutting time"),
    Item("cycle_time", _S, _P, float, SECOND, "cycle time of the current cycle"),
    Item("tool", _S, _P, int, ONE, "number of the tool in use (modal T)"),
    Item("message", _S, _P, str, None, "operator message shown, empty when none"),
    Item("servo_load", _S, _A, float, PERCENT, "servo load meter"),
    Item("tool_offset", _S, _P, float, MILLIMETRE, "wear offset of the tool in use"),
    Item("spindle_load", _S, _SP, float, PERCENT, "spindle load meter"),
)


def item(name: str) -> Item:
    """The item called ``name``; a ``KeyError`` that lists the names otherwise."""
    try:
        return ITEMS[name]
    except KeyError:
        raise KeyError(f"no item {name!r} (items: {', '.join(ITEMS)})") from None


@dataclass(frozen=True, slots=True)
class PathShape:
    """One path (an OPC 40502 channel) of a machine: its number (1..), its axis names and its
    spindle names, in the CNC's order."""

    number: int
    axes: tuple[str, ...]
    spindles: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class MachineShape:
    """What a connected machine is: its configured name, address and protocol, what
    ``cnc_sysinfo`` says of it, and its paths. The poller describes each machine to the sinks
    when it first connects (and again if the shape changed after a reconnect)."""

    name: str
    host: str
    port: int
    protocol: str
    cnc_type: str
    mt_type: str
    series: str
    version: str
    paths: tuple[PathShape, ...]


@dataclass(frozen=True, slots=True)
class Sample:
    """One value of one item, read at ``time`` (seconds since the epoch): ``path`` 0 for a
    machine item, ``key`` the axis or spindle name for an axis or spindle item (else "").
    ``status`` is Good with a value, or the status of the EW code (or of the lost connection)
    that kept the value from being read, with ``value`` None."""

    machine: str
    path: int
    item: Item
    key: str
    value: Value
    status: OpcUaStatus
    time: float


@dataclass(frozen=True, slots=True)
class AlarmChange:
    """An alarm entered (``active``) or left the active list of a path: identified by its FOCAS
    type and number (and axis, 0 for none), with its message; named as ``ActiveAlarm`` and
    every front end name them (``alm_type``, ``alm_no``, ``axis_no``, ``msg``)."""

    machine: str
    path: int
    alm_type: int
    alm_no: int
    axis_no: int
    msg: str
    active: bool
    time: float


class Sink(Protocol):
    """An output of the gateway. Every method is called from the poller's task, must return
    at once, and must not raise for any value it is given."""

    def described(self, shape: MachineShape) -> None:
        """``shape`` connected (first, or again with a different shape)."""

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        """The machine became reachable (``online``) or was lost (``reason`` says why). While
        a machine is lost no samples come for it: a sink shows every value of it as Bad
        (communication), never a stale Good."""

    def samples(self, samples: Sequence[Sample]) -> None:
        """Changed values, in the order they were read."""

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        """Alarm changes, in the order they were seen."""


class Writer(Protocol):
    """Writes to a machine through the configuration's write gates: each call raises
    :class:`~focas_net.errors.FocasError` (an EW code, a lost connection) or ``PermissionError``
    naming the gate that refused it."""

    async def write_macro(self, machine: str, number: int, value: Decimal, path: int) -> None:
        """``cnc_wrmacro``."""

    async def write_param(self, machine: str, number: int, value: int, axis: int) -> None:
        """``cnc_wrparam`` (axis 0: not an axis parameter)."""

    async def write_pmc(self, machine: str, area: str, address: int, value: int) -> None:
        """``pmc_wrpmcrng`` of one byte."""
