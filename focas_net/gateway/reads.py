"""What the gateway reads of one machine and how the answers become the values of
:data:`~focas_net.gateway.model.ITEMS`: :func:`describe` (the machine's shape, once per
connection) and :class:`Reader` (the reads of each group, started now, turned into values when
their answers come).

A read is a :class:`Read`: a :class:`~focas_net.client.StartedCall` already sent (or queued),
the item keys it gives, and the pure function from its answer to their values. The poller
starts the reads of every machine due, then awaits them in turn (see
:mod:`focas_net.gateway.poller`): no task per machine or per value where the client has a
started form of the call.

**Native (FOCAS/2)**, per path. Fast: ``cnc_statinfo`` (mode, run, motion, emergency, alarm),
``cnc_rddynamic2`` (program, main program, sequence, feed, spindle speed, the four positions
of every axis), ``pmc_rdpmcrng`` of G12..G30 at the path's offset of 1000 bytes (G12 *FV0-*FV7
the feed override, inverted: 255 - G12 %, all 0s 0 %; G14.0-.1 ROV1 ROV2 the rapid override,
00 100 %, 01 50 %, 10 25 %, 11 F0 read as 0 %; G30 SOV0-SOV7 the spindle override in percent).
Slow: #3901/#3902 and parameter 6713 (parts, total, required), ``cnc_rdtimer`` 0..3 (power-on,
operating, cutting, cycle), ``cnc_rdspload`` and ``cnc_rdsvmeter`` (loads), ``cnc_rdcommand``
(the modal T), ``cnc_rdtofs`` of the tool in use (length wear, type 2, of offset T on a
machining centre; X wear, type 0, of offset T mod 100 on a lathe), ``cnc_rdopmsg``.

**Packed**, per path. Fast: status, program numbers, feed, spindle speed, the four position
kinds, the overrides (``read_run_info``). Slow: parts and timers (``read_run_info``), parameter
6713, the loads (``read_loads``). The sequence number, the tool, its offset and the operator
message have no packed call: their samples are BadNotSupported, sent once per connection.

Positions and tool offsets are the CNC's increments scaled by the decimals ``cnc_rdposition``
gives for the path (read once per connection): millimetres on a metric machine. An inch
machine's values are in inches though the unit says mm; the gateway does not convert them.
An EW code on one read gives that read's values the EW's OPC UA status (``errors.EW_TABLE``);
the other reads still deliver.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any, Final

from focas_net._refusals import no_path
from focas_net.client import (
    DynamicData,
    FocasClient,
    NativeClient,
    OperatorMessageText,
    Positions,
    ServoLoad,
    StartedCall,
)
from focas_net.errors import EW, CncError, OpcUaStatus, ew_info
from focas_net.protocol import (
    AlarmState,
    AutMode,
    EmergencyState,
    LabelledValue,
    MotionState,
    PositionKind,
    RunState,
    StatusInfo,
    field_label,
)

from .config import MachineConfig
from .model import MachineShape, PathShape, Value

__all__ = [
    "NOT_SUPPORTED",
    "NO_TOOL",
    "Key",
    "Outcome",
    "Read",
    "Reader",
    "Unavailable",
    "describe",
]

_log = logging.getLogger(__name__)

#: One value of a machine: ``(path, item name, axis or spindle name or "")``.
Key = tuple[int, str, str]
#: A value, or the status that kept it from being read.
Outcome = Value | OpcUaStatus
#: The status of an item a transport cannot read.
NOT_SUPPORTED: Final = ew_info(EW.FUNC).opcua
#: The status of the tool offset while no tool is in use (T0).
NO_TOOL: Final = OpcUaStatus("BadNoDataAvailable", 0x80B10000)

#: The G signals of the overrides (at a path's offset of 1000 bytes) and the rapid override
#: of ROV1 ROV2.
_G_FIRST: Final = 12
_G_LAST: Final = 30
_PATH_STRIDE: Final = 1000
_RAPID_OF_ROV: Final = (100, 50, 25, 0)
_KINDS: Final = ("absolute", "machine", "relative", "distance")
_PARTS_REQUIRED: Final = 6713
_TIMERS: Final = ("power_on_time", "operating_time", "cutting_time", "cycle_time")
_STATUS_ITEMS: Final = ("mode", "run", "motion", "emergency", "alarm")


@dataclass(frozen=True, slots=True)
class Read:
    """A read under way: its call, the keys it gives, and its answer's values by key."""

    call: StartedCall[Any]
    keys: tuple[Key, ...]
    values: Callable[[Any], dict[Key, Outcome]]


@dataclass(frozen=True, slots=True)
class _Plan:
    """One read of a group as the connection makes it at every poll, made once per
    connection: how it starts, the keys it gives, its answer's values."""

    start: Callable[[], StartedCall[Any]]
    keys: tuple[Key, ...]
    values: Callable[[Any], dict[Key, Outcome]]

    def read(self) -> Read:
        """The read started now."""
        return Read(self.start(), self.keys, self.values)


def _name(values: type[LabelledValue], value: int) -> str:
    """The field's value as the CNC screen, the command line and the web page label it (the
    one table's :func:`~focas_net.protocol.values.field_label`: ``MEM``, ``****``; a number
    without a name as its digits)."""
    return field_label(values, value)[0]


def _status(path: int, s: StatusInfo) -> dict[Key, Outcome]:
    return {
        (path, "mode", ""): _name(AutMode, s.aut),
        (path, "run", ""): _name(RunState, s.run),
        (path, "motion", ""): _name(MotionState, s.motion),
        (path, "emergency", ""): s.emergency == EmergencyState.EMG,
        (path, "alarm", ""): s.alarm == AlarmState.ALM,
    }


def _overrides(path: int, g: bytes) -> dict[Key, Outcome]:
    """G12..G30 -> the three overrides in percent (see the module docstring)."""
    fv, rov, sov = g[0], g[14 - _G_FIRST], g[_G_LAST - _G_FIRST]
    return {
        (path, "feed_override", ""): 0 if fv == 0 else 0xFF - fv,
        (path, "rapid_override", ""): _RAPID_OF_ROV[rov & 3],
        (path, "spindle_override", ""): sov,
    }


def _positions(p: int, kind: str) -> Callable[[Positions], dict[Key, Outcome]]:
    def values(pos: Positions) -> dict[Key, Outcome]:
        return {(p, kind, name): float(v) for name, v in pos.values.items()}

    return values


def _timer(p: int, item: str) -> Callable[[Any], dict[Key, Outcome]]:
    """The seconds of a ``cnc_rdtimer`` answer (minutes and milliseconds)."""

    def values(v: Any) -> dict[Key, Outcome]:
        return {(p, item, ""): v.minute * 60.0 + v.msec / 1000.0}

    return values


def _scaled(increments: int, decimals: int) -> float:
    """``increments / 10**decimals``, the float nearest the exact quotient (true division of
    integers rounds once)."""
    return increments / 10**decimals if decimals >= 0 else float(increments * 10**-decimals)


def _text(raw: bytes) -> str:
    return raw.split(b"\x00", 1)[0].decode("latin-1").strip()


def _paths_missing(count: int, missing: list[int], wanted: int) -> str:
    """``the CNC has no paths 2, 3: it has path 1 only (machine.paths); ...``: the machine's
    and the command line's words (:func:`~focas_net._refusals.no_path`), with the key."""
    rest = "; nothing of it is read" if len(missing) == wanted else ""
    return f"{no_path(missing, count)} (machine.paths){rest}"


async def describe(config: MachineConfig, client: FocasClient | NativeClient) -> Reader:
    """The reader of ``client``'s machine, with its shape read now: ``cnc_sysinfo``, the
    paths (the configured ones the CNC has), each path's axis names and position decimals
    and its spindle names. Raises what the reads raise."""
    timeout = config.timeout
    info = await client.read_sysinfo(timeout=timeout)
    if isinstance(client, NativeClient):
        count = client.path_count or 1
    else:
        count = (await client.read_paths(timeout=timeout)).count
    wanted = config.paths or tuple(range(1, max(count, 1) + 1))
    missing = [p for p in wanted if p > count]
    if missing:
        _log.warning("%s: %s", config.name, _paths_missing(count, missing, len(wanted)))
    paths: list[PathShape] = []
    decimals: dict[int, int] = {}
    for p in (p for p in wanted if p <= count):
        positions: Positions = await client.read_positions(path=p, timeout=timeout)
        decimals[p] = positions.decimals
        if isinstance(client, NativeClient):
            try:
                spindles = await client.read_spindle_names(path=p, timeout=timeout)
            except CncError:
                spindles = ()
        else:
            loads = await client.read_loads(path=p, timeout=timeout)
            spindles = tuple(f"S{i + 1}" for i in range(len(loads.spindle)))
        paths.append(PathShape(p, tuple(positions.values), tuple(spindles)))
    shape = MachineShape(
        config.name, config.host, config.port, config.protocol, _text(info.cnc_type),
        _text(info.mt_type), _text(info.series), _text(info.version), tuple(paths),
    )  # fmt: skip
    return Reader(client, shape, decimals, timeout)


class Reader:
    """The reads of one connected machine, by group (see the module docstring). Each method
    starts its reads now and returns them; :meth:`unsupported` lists the keys the transport
    cannot read."""

    def __init__(
        self,
        client: FocasClient | NativeClient,
        shape: MachineShape,
        decimals: dict[int, int],
        timeout: float,
    ) -> None:
        self.client = client
        self.shape = shape
        self.decimals = decimals
        self.timeout = timeout
        self.native = isinstance(client, NativeClient)
        #: The tool in use per path, as the last slow read saw it.
        self.tools: dict[int, int] = {}
        # Each group's reads are planned once: a poll only starts them.
        self._fast: tuple[_Plan, ...] = tuple(
            plan
            for path in shape.paths
            for plan in (self._fast_native(path) if self.native else self._fast_packed(path))
        )
        self._slow: tuple[tuple[PathShape, tuple[_Plan, ...]], ...] = tuple(
            (path, tuple(self._slow_native(path) if self.native else self._slow_packed(path)))
            for path in shape.paths
        )

    # -- keys ----------------------------------------------------------------------------
    def _axis_keys(self, path: PathShape, items: Sequence[str]) -> tuple[Key, ...]:
        return tuple((path.number, i, a) for i in items for a in path.axes)

    def unsupported(self) -> list[Key]:
        """The keys the transport cannot read (their samples are BadNotSupported)."""
        if self.native:
            return []
        return [
            (p.number, name, "")
            for p in self.shape.paths
            for name in ("sequence", "tool", "tool_offset", "message")
        ]

    # -- fast ----------------------------------------------------------------------------
    def fast(self) -> list[Read]:
        """Status, program, feed, spindle, positions and overrides of every path, started
        now."""
        return [plan.read() for plan in self._fast]

    def _status_read(self, p: int) -> _Plan:
        keys = tuple((p, i, "") for i in _STATUS_ITEMS)
        return _Plan(
            partial(self.client.start_read_status, path=p, timeout=self.timeout),
            keys,
            lambda s: _status(p, s),
        )

    def _fast_native(self, path: PathShape) -> list[_Plan]:
        client = self.client
        assert isinstance(client, NativeClient)
        p, t = path.number, self.timeout
        dec = self.decimals.get(p, 0)
        axis_keys = [[(p, kind, name) for name in path.axes] for kind in _KINDS]

        def dynamic(d: DynamicData) -> dict[Key, Outcome]:
            out: dict[Key, Outcome] = {
                (p, "program", ""): d.running,
                (p, "main_program", ""): d.main,
                (p, "sequence", ""): d.sequence,
                (p, "feed", ""): float(d.feed),
                (p, "spindle_speed", ""): float(d.spindle_speed),
            }
            for keys, values in zip(
                axis_keys, (d.absolute, d.machine, d.relative, d.distance), strict=True
            ):
                for key, v in zip(keys, values, strict=False):
                    out[key] = _scaled(v, dec)
            return out

        base = _PATH_STRIDE * (p - 1)
        scalar = ("program", "main_program", "sequence", "feed", "spindle_speed")
        return [
            self._status_read(p),
            _Plan(
                partial(client.start_read_dynamic, path=p, timeout=t),
                (*((p, i, "") for i in scalar), *self._axis_keys(path, _KINDS)),
                dynamic,
            ),
            _Plan(
                partial(
                    client.start_read_pmc, "G", base + _G_FIRST, _G_LAST - _G_FIRST + 1, timeout=t
                ),
                tuple((p, i, "") for i in ("feed_override", "rapid_override", "spindle_override")),
                lambda g: _overrides(p, g),
            ),
        ]

    def _fast_packed(self, path: PathShape) -> list[_Plan]:
        client = self.client
        assert isinstance(client, FocasClient)
        p, t = path.number, self.timeout
        reads = [
            self._status_read(p),
            _Plan(
                lambda: StartedCall.running(client.read_program_numbers(path=p, timeout=t)),
                ((p, "program", ""), (p, "main_program", "")),
                lambda n: {(p, "program", ""): n.running, (p, "main_program", ""): n.main},
            ),
            _Plan(
                lambda: StartedCall.running(client.read_feed(path=p, timeout=t)),
                ((p, "feed", ""),),
                lambda f: {(p, "feed", ""): float(f)},
            ),
            _Plan(
                lambda: StartedCall.running(client.read_spindle_speed(path=p, timeout=t)),
                ((p, "spindle_speed", ""),),
                lambda s: {(p, "spindle_speed", ""): float(s)},
            ),
            _Plan(
                lambda: StartedCall.running(client.read_run_info(path=p, timeout=t)),
                tuple((p, i, "") for i in ("feed_override", "rapid_override", "spindle_override")),
                lambda r: {
                    (p, "feed_override", ""): r.feed,
                    (p, "rapid_override", ""): r.rapid,
                    (p, "spindle_override", ""): r.spindle,
                },
            ),
        ]
        for kind in _KINDS:
            reads.append(
                _Plan(
                    partial(_start_positions, client, PositionKind.parse(kind), p, t),
                    self._axis_keys(path, (kind,)),
                    _positions(p, kind),
                )
            )
        return reads

    # -- slow ----------------------------------------------------------------------------
    def slow(self) -> list[Read]:
        """Parts, timers, loads, tool, tool offset and message of every path, started now."""
        reads: list[Read] = []
        for path, plans in self._slow:
            reads.extend(plan.read() for plan in plans)
            if self.native:
                reads.append(self._tool_offset(path))
        return reads

    def _loads(self, path: PathShape, spindle: Sequence[int], servo: Sequence[Any]) -> Any:
        p = path.number
        out: dict[Key, Outcome] = {}
        for name, v in zip(path.spindles, spindle, strict=False):
            out[(p, "spindle_load", name)] = float(v)
        for name, v in zip(path.axes, servo, strict=False):
            out[(p, "servo_load", name)] = float(v.load if isinstance(v, ServoLoad) else v)
        return out

    def _slow_native(self, path: PathShape) -> list[_Plan]:
        client = self.client
        assert isinstance(client, NativeClient)
        p, t = path.number, self.timeout
        run = StartedCall.running

        def one(item: str) -> tuple[Key, ...]:
            return ((p, item, ""),)

        def tool(commands: Any) -> dict[Key, Outcome]:
            number = next((int(c.value) for c in commands if c.address == "T"), 0)
            self.tools[p] = number
            return {(p, "tool", ""): number}

        def message(m: OperatorMessageText) -> dict[Key, Outcome]:
            return {(p, "message", ""): "" if m.number < 0 else m.text}

        reads = [
            _Plan(
                partial(client.start_read_macro, 3901, path=p, timeout=t),
                one("parts"),
                lambda v: {(p, "parts", ""): 0 if v is None else int(v)},
            ),
            _Plan(
                partial(client.start_read_macro, 3902, path=p, timeout=t),
                one("parts_total"),
                lambda v: {(p, "parts_total", ""): 0 if v is None else int(v)},
            ),
            _Plan(
                lambda: run(client.read_param(_PARTS_REQUIRED, path=p, timeout=t)),
                one("parts_required"),
                lambda v: {(p, "parts_required", ""): v},
            ),
            *(
                _Plan(
                    partial(_start_timer, client, kind, p, t),
                    one(item),
                    _timer(p, item),
                )
                for kind, item in enumerate(_TIMERS)
            ),
            _Plan(
                lambda: run(client.read_spindle_loads(path=p, timeout=t)),
                tuple((p, "spindle_load", s) for s in path.spindles),
                lambda v: self._loads(path, v, ()),
            ),
            _Plan(
                lambda: run(client.read_servo_meters(path=p, timeout=t)),
                self._axis_keys(path, ("servo_load",)),
                lambda v: self._loads(path, (), v),
            ),
            _Plan(lambda: run(client.read_commands(path=p, timeout=t)), one("tool"), tool),
            _Plan(
                lambda: run(client.read_operator_message(path=p, timeout=t)),
                one("message"),
                message,
            ),
        ]
        return reads

    def _tool_offset(self, path: PathShape) -> Read:
        """The wear offset of the tool the last slow read saw (see the module docstring)."""
        client = self.client
        assert isinstance(client, NativeClient)
        p = path.number
        key = (p, "tool_offset", "")
        tool = self.tools.get(p, 0)
        lathe = self.shape.mt_type.strip().startswith("T")
        number = tool % 100 if lathe else tool
        if not 1 <= number <= 0x7FFF:
            return Read(StartedCall.failed(Unavailable()), (key,), lambda _: {})
        dec = self.decimals.get(p, 0)
        offset_type = 0 if lathe else 2
        call = client.read_tool_offset(number, offset_type, path=p, timeout=self.timeout)
        return Read(StartedCall.running(call), (key,), lambda v: {key: _scaled(v, dec)})

    def _slow_packed(self, path: PathShape) -> list[_Plan]:
        client = self.client
        assert isinstance(client, FocasClient)
        p, t = path.number, self.timeout

        def info(r: Any) -> dict[Key, Outcome]:
            out: dict[Key, Outcome] = {
                (p, "parts", ""): r.parts_count,
                (p, "parts_total", ""): r.parts_total,
            }
            ms = (r.power_on_ms, r.operating_ms, r.cutting_ms, r.cycle_ms)
            for item, v in zip(_TIMERS, ms, strict=True):
                out[(p, item, "")] = v / 1000.0
            return out

        return [
            _Plan(
                lambda: StartedCall.running(client.read_run_info(path=p, timeout=t)),
                tuple((p, i, "") for i in ("parts", "parts_total", *_TIMERS)),
                info,
            ),
            _Plan(
                lambda: StartedCall.running(client.read_param(_PARTS_REQUIRED, path=p, timeout=t)),
                ((p, "parts_required", ""),),
                lambda v: {(p, "parts_required", ""): v},
            ),
            _Plan(
                lambda: StartedCall.running(client.read_loads(path=p, timeout=t)),
                (
                    *((p, "spindle_load", s) for s in path.spindles),
                    *self._axis_keys(path, ("servo_load",)),
                ),
                lambda v: self._loads(path, v.spindle, v.servo),
            ),
        ]

    # -- alarms --------------------------------------------------------------------------
    def alarms(self) -> list[tuple[int, StartedCall[Any]]]:
        """The active alarm list of every path: ``(path, started read)``."""
        client = self.client
        t = self.timeout
        if isinstance(client, NativeClient):
            return [
                (p.number, client.start_read_alarms(path=p.number, timeout=t))
                for p in self.shape.paths
            ]
        return [
            (p.number, StartedCall.running(client.read_alarms(path=p.number, timeout=t)))
            for p in self.shape.paths
        ]


def _start_positions(
    client: FocasClient, kind: PositionKind, path: int, timeout: float
) -> StartedCall[Positions]:
    return StartedCall.running(client.read_positions(kind, path=path, timeout=timeout))


def _start_timer(client: NativeClient, kind: int, path: int, timeout: float) -> StartedCall[Any]:
    return StartedCall.running(client.read_timer(kind, path=path, timeout=timeout))


class Unavailable(Exception):
    """An item that has no value now (no tool in use: the tool offset), with its status."""

    opcua_status = NO_TOOL
