"""The MQTT publisher's topics and payloads, its change filter and its bounded buffer: pure and
synchronous, no I/O (the shell, :mod:`focas_net.gateway.mqtt`, moves the bytes).

Topic tree (``P`` the configured prefix, ``M`` a machine, ``G`` the gateway's name; every level
taken from a name is escaped by :func:`topic_level`)::

    P/$gateway/G/state               "online" (birth) / "offline" (will, clean stop)   retained
    P/$gateway/G/dropped             {"dropped": n, "time": t}                          retained
    P/M/$model                       the machine's paths, axes, spindles and items      retained
    P/M/availability                 {"state": "AVAILABLE"|"UNAVAILABLE", ...}          retained
    P/M/ITEM                         a machine item's value                             retained
    P/M/pathN/ITEM                   a path item's value                                retained
    P/M/pathN/ITEM/KEY               an axis or spindle item's value (KEY: its name)    retained
    P/M/pathN/alarms/active          {"alarms": [...], "status": ..., "time": t}        retained
    P/M/pathN/alarms/event           one alarm raised or cleared                        not retained

A value's payload is ``{"value": v, "unit": "mm", "status": "Good", "time": ISO-8601}``: the
status is the sample's OPC UA status name, the value null unless Good. A value is published
when its status changed, or (numeric items named in the deadbands) when it moved by more than
the deadband since the last value published, or (every other item) when it changed. A lost
machine publishes availability UNAVAILABLE with the reason, then every value topic it has
published again with value null and status ``BadCommunicationError`` and its active alarm
lists with ``"alarms": null``: a retained Good value never outlives the connection it was
read on. Its first samples after it is back are published whatever the deadband says.

Each payload is one dataclass whose :meth:`encode` and :meth:`decode` are each other's
inverse (the ``$model`` description is encoded only: it is a document, read by people and
tools, not a value the gateway reads back).
"""

from __future__ import annotations

import json
import math
from collections import OrderedDict
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Any, Final, Literal

from focas_net.errors import OPCUA_BAD_COMMUNICATION_ERROR, OPCUA_GOOD
from focas_net.protocol.alarms import alarm_fields

from .model import ITEMS, AlarmChange, Item, MachineShape, Sample, Scope, Value

__all__ = [
    "ActiveAlarms",
    "AlarmEvent",
    "Availability",
    "Buffer",
    "DroppedCount",
    "Message",
    "Publication",
    "ValuePayload",
    "iso_time",
    "topic_level",
]

ONLINE: Final = b"online"
OFFLINE: Final = b"offline"
AVAILABLE: Final = "AVAILABLE"
UNAVAILABLE: Final = "UNAVAILABLE"
_GOOD: Final = OPCUA_GOOD.name
_BAD_COMMUNICATION: Final = OPCUA_BAD_COMMUNICATION_ERROR.name

#: Characters a topic level cannot hold as they are (MQTT's separator and wildcards, and the
#: escape itself), with their escapes.
_ESCAPES: Final = {"%": "%25", "/": "%2F", "+": "%2B", "#": "%23", "\0": "%00"}


def topic_level(name: str) -> str:
    """``name`` as one topic level: ``/``, ``+``, ``#``, NUL and ``%`` written as ``%XX`` (and a
    leading ``$``, which MQTT keeps for the broker's own topics, as ``%24``), so that any name
    is one level and no level is a wildcard."""
    level = "".join(_ESCAPES.get(c, c) for c in name) if any(c in _ESCAPES for c in name) else name
    return "%24" + level[1:] if level.startswith("$") else level


def iso_time(time: float) -> str:
    """``time`` (seconds since the epoch) in ISO 8601, UTC, to the millisecond."""
    stamp = datetime.fromtimestamp(time, UTC).isoformat(timespec="milliseconds")
    return stamp.removesuffix("+00:00") + "Z"


#: One encoder for every payload (``json.dumps`` with options would build one per call).
_ENCODER: Final = json.JSONEncoder(separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def _dumps(document: object) -> bytes:
    return _ENCODER.encode(document).encode()


def _loads(payload: bytes) -> dict[str, Any]:
    document = json.loads(payload)
    if not isinstance(document, dict):
        raise ValueError(f"not a JSON object: {payload[:60]!r}")
    return document


def _json_value(value: Value) -> Value:
    """``value`` as JSON carries it: a float that is not finite has no JSON form (null)."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


@dataclass(frozen=True, slots=True)
class ValuePayload:
    """The payload of a value topic."""

    value: Value
    unit: str | None
    status: str
    time: str

    def encode(self) -> bytes:
        return _dumps(
            {"value": self.value, "unit": self.unit, "status": self.status, "time": self.time}
        )

    @classmethod
    def decode(cls, payload: bytes) -> ValuePayload:
        d = _loads(payload)
        return cls(d["value"], d["unit"], d["status"], d["time"])


@dataclass(frozen=True, slots=True)
class Availability:
    """The payload of ``P/M/availability``: AVAILABLE or UNAVAILABLE, why (empty when
    available), since when, and which gateway publishes the machine."""

    state: Literal["AVAILABLE", "UNAVAILABLE"]
    reason: str
    time: str
    gateway: str

    def encode(self) -> bytes:
        return _dumps(
            {"state": self.state, "reason": self.reason, "time": self.time, "gateway": self.gateway}
        )

    @classmethod
    def decode(cls, payload: bytes) -> Availability:
        d = _loads(payload)
        if d["state"] not in (AVAILABLE, UNAVAILABLE):
            raise ValueError(f"availability state {d['state']!r}")
        return cls(d["state"], d["reason"], d["time"], d["gateway"])


@dataclass(frozen=True, slots=True)
class AlarmEvent:
    """The payload of ``P/M/pathN/alarms/event`` (and one entry of the active list): the alarm
    with the keys every front end gives it (:func:`~focas_net.protocol.alarms.alarm_fields`:
    ``code`` as the CNC screen shows it, ``axis_no`` (0: none), ``alm_type``, ``alm_no``,
    ``msg``, as the command line's ``alarms --json`` and the web page's API), whether it was
    raised (``active``) or cleared, and when."""

    alm_type: int
    alm_no: int
    axis_no: int
    msg: str
    active: bool
    time: str

    @property
    def key(self) -> tuple[int, int, int]:
        """The identity of an alarm: ``(axis_no, alm_type, alm_no)``, as ``ActiveAlarm.key``."""
        return (self.axis_no, self.alm_type, self.alm_no)

    def document(self) -> dict[str, Value]:
        fields = alarm_fields(self.axis_no, self.alm_type, self.alm_no, self.msg)
        return {**fields, "active": self.active, "time": self.time}

    def encode(self) -> bytes:
        return _dumps(self.document())

    @classmethod
    def from_document(cls, d: Mapping[str, Any]) -> AlarmEvent:
        return cls(d["alm_type"], d["alm_no"], d["axis_no"], d["msg"], d["active"], d["time"])

    @classmethod
    def decode(cls, payload: bytes) -> AlarmEvent:
        return cls.from_document(_loads(payload))


@dataclass(frozen=True, slots=True)
class ActiveAlarms:
    """The payload of ``P/M/pathN/alarms/active``: the alarms active on the path, in the order
    they were raised (None while the machine is lost: not known), with a status as values
    have."""

    alarms: tuple[AlarmEvent, ...] | None
    status: str
    time: str

    def encode(self) -> bytes:
        alarms = None if self.alarms is None else [a.document() for a in self.alarms]
        return _dumps({"alarms": alarms, "status": self.status, "time": self.time})

    @classmethod
    def decode(cls, payload: bytes) -> ActiveAlarms:
        d = _loads(payload)
        rows = d["alarms"]
        alarms = None if rows is None else tuple(AlarmEvent.from_document(r) for r in rows)
        return cls(alarms, d["status"], d["time"])


@dataclass(frozen=True, slots=True)
class DroppedCount:
    """The payload of ``P/$gateway/G/dropped``: messages dropped since the gateway started
    because the buffer was full while the broker was away."""

    dropped: int
    time: str

    def encode(self) -> bytes:
        return _dumps({"dropped": self.dropped, "time": self.time})

    @classmethod
    def decode(cls, payload: bytes) -> DroppedCount:
        d = _loads(payload)
        return cls(d["dropped"], d["time"])


@dataclass(frozen=True, slots=True)
class Message:
    """One MQTT message to publish."""

    topic: str
    payload: bytes
    retain: bool


def _unit(row: Item) -> str | None:
    return None if row.unit is None else row.unit.symbol


class Publication:
    """What the gateway publishes, as messages: one method per :class:`~.model.Sink` call, each
    returning the messages it makes, in order. It keeps what it last published per value topic
    (for the deadbands, and to mark a lost machine's values Bad) and each path's active alarms.

    ``prefix`` and ``deadbands`` are taken as :meth:`MqttSettings.check
    <focas_net.gateway.config.MqttSettings.check>` passes them."""

    def __init__(
        self, prefix: str, gateway_name: str, deadbands: Mapping[str, float] | None = None
    ) -> None:
        self.prefix = prefix
        if not gateway_name:
            raise ValueError("gateway name: empty")
        self.gateway_name = gateway_name
        self.deadbands = {name: float(band) for name, band in (deadbands or {}).items()}
        self._gateway = f"{self.prefix}/$gateway/{topic_level(gateway_name)}"
        self._machine_topics: dict[str, str] = {}
        self._topics: dict[tuple[str, int, str, str], str] = {}
        #: per machine, per value topic: the value and status last published (and the unit)
        self._published: dict[str, dict[str, tuple[Value, str, str | None]]] = {}
        #: per machine, per path: the active alarms by (type, number, axis)
        self._active: dict[str, dict[int, dict[tuple[int, int, int], AlarmEvent]]] = {}
        #: the latest retained message of every machine topic
        self._retained: dict[str, Message] = {}
        #: the machines lost now (their values and alarm lists already published as Bad)
        self._lost: set[str] = set()

    # --- topics -------------------------------------------------------------------------------

    @property
    def state_topic(self) -> str:
        return f"{self._gateway}/state"

    @property
    def dropped_topic(self) -> str:
        return f"{self._gateway}/dropped"

    def machine_topic(self, machine: str) -> str:
        """``P/M``."""
        topic = self._machine_topics.get(machine)
        if topic is None:
            topic = self._machine_topics[machine] = f"{self.prefix}/{topic_level(machine)}"
        return topic

    def path_topic(self, machine: str, path: int) -> str:
        """``P/M/pathN`` (``P/M`` for path 0, the machine's own items)."""
        base = self.machine_topic(machine)
        return f"{base}/path{path}" if path else base

    def value_topic(self, machine: str, path: int, name: str, key: str) -> str:
        """The topic of one value: ``P/M/pathN/ITEM`` or ``P/M/pathN/ITEM/KEY``."""
        index = (machine, path, name, key)
        topic = self._topics.get(index)
        if topic is None:
            topic = f"{self.path_topic(machine, path)}/{topic_level(name)}"
            if key:
                topic = f"{topic}/{topic_level(key)}"
            self._topics[index] = topic
        return topic

    # --- the gateway's own messages -----------------------------------------------------------

    def birth(self) -> Message:
        """``online`` on the gateway's state topic, retained: sent first on every connection."""
        return Message(self.state_topic, ONLINE, True)

    def will(self) -> Message:
        """``offline`` on the same topic, retained: the broker's last will for the connection,
        and what a clean stop sends itself."""
        return Message(self.state_topic, OFFLINE, True)

    def dropped(self, count: int, time: float) -> Message:
        return Message(self.dropped_topic, DroppedCount(count, iso_time(time)).encode(), True)

    # --- the sink's calls ---------------------------------------------------------------------

    def described(self, shape: MachineShape) -> list[Message]:
        """The machine's ``$model``, retained; when the machine changed, an empty retained
        message (which deletes the broker's) on each topic it published that its new shape has
        no more: the values of an axis, a spindle or a path it lost, and a lost path's alarm
        list, so that no subscriber is shown a value of what is gone."""
        return self._forgotten(shape) + self._kept(self._model(shape))

    def _forgotten(self, shape: MachineShape) -> list[Message]:
        machine = shape.name
        paths = {p.number: p for p in shape.paths}
        gone: list[str] = []
        for (m, path, name, key), topic in list(self._topics.items()):
            if m != machine or path == 0:
                continue
            now = paths.get(path)
            scope = ITEMS[name].scope
            if (
                now is None
                or (scope is Scope.AXIS and key not in now.axes)
                or (scope is Scope.SPINDLE and key not in now.spindles)
            ):
                gone.append(topic)
                del self._topics[(m, path, name, key)]
        for path in [p for p in self._active.get(machine, {}) if p not in paths]:
            gone.append(f"{self.path_topic(machine, path)}/alarms/active")
            del self._active[machine][path]
        published = self._published.get(machine, {})
        for topic in gone:
            published.pop(topic, None)
            self._retained.pop(topic, None)
        return [Message(topic, b"", True) for topic in gone]

    def _model(self, shape: MachineShape) -> list[Message]:
        base = self.machine_topic(shape.name)
        items = {
            name: {
                "scope": row.scope.value,
                "group": row.group.value,
                "type": row.kind.__name__,
                "unit": _unit(row),
                "unit_code": None if row.unit is None else row.unit.code,
                "deadband": self.deadbands.get(name),
                "description": row.description,
            }
            for name, row in ITEMS.items()
        }
        model = {
            "machine": shape.name,
            "gateway": self.gateway_name,
            "topic": base,
            "host": shape.host,
            "port": shape.port,
            "protocol": shape.protocol,
            "cnc_type": shape.cnc_type,
            "mt_type": shape.mt_type,
            "series": shape.series,
            "version": shape.version,
            "paths": [
                {
                    "number": p.number,
                    "topic": self.path_topic(shape.name, p.number),
                    "axes": list(p.axes),
                    "spindles": list(p.spindles),
                }
                for p in shape.paths
            ],
            "items": items,
        }
        return [Message(f"{base}/$model", _dumps(model), True)]

    def online(self, machine: str, online: bool, reason: str, time: float) -> list[Message]:
        """Availability; for a lost machine, every value it published again as Bad and its
        active alarm lists as unknown; for a machine back, its active alarm lists again."""
        return self._kept(self._availability(machine, online, reason, time))

    def _availability(self, machine: str, online: bool, reason: str, time: float) -> list[Message]:
        stamp = iso_time(time)
        base = self.machine_topic(machine)
        state: Literal["AVAILABLE", "UNAVAILABLE"] = AVAILABLE if online else UNAVAILABLE
        payload = Availability(state, "" if online else reason, stamp, self.gateway_name)
        messages = [Message(f"{base}/availability", payload.encode(), True)]
        paths = self._active.get(machine, {})
        if online:
            self._lost.discard(machine)
            messages.extend(self._active_list(machine, path, stamp) for path in paths)
            return messages
        if machine in self._lost:
            return messages
        self._lost.add(machine)
        published = self._published.get(machine, {})
        for topic, (value, status, unit) in published.items():
            if value is None and status == _BAD_COMMUNICATION:
                continue
            published[topic] = (None, _BAD_COMMUNICATION, unit)
            bad = ValuePayload(None, unit, _BAD_COMMUNICATION, stamp)
            messages.append(Message(topic, bad.encode(), True))
        for path in paths:
            unknown = ActiveAlarms(None, _BAD_COMMUNICATION, stamp)
            topic = f"{self.path_topic(machine, path)}/alarms/active"
            messages.append(Message(topic, unknown.encode(), True))
        return messages

    def samples(self, samples: Sequence[Sample]) -> list[Message]:
        """The samples that pass the change filter, each on its value topic, retained."""
        messages: list[Message] = []
        lost = self._lost
        read_at, stamp = math.nan, ""
        for s in samples:
            if lost:
                lost.discard(s.machine)  # read again: the next loss marks its values again
            row = s.item
            topic = self.value_topic(s.machine, s.path, row.name, s.key)
            status = s.status.name
            value = _json_value(s.value) if status == _GOOD else None
            published = self._published.get(s.machine)
            if published is None:
                published = self._published[s.machine] = {}
            last = published.get(topic)
            if last is not None and not self._changed(row, last[0], last[1], value, status):
                continue
            unit = _unit(row)
            published[topic] = (value, status, unit)
            if s.time != read_at:  # the samples of one read share their time
                read_at, stamp = s.time, iso_time(s.time)
            payload = ValuePayload(value, unit, status, stamp)
            message = Message(topic, payload.encode(), True)
            messages.append(message)
            self._retained[topic] = message
        return messages

    def _changed(self, row: Item, old: Value, status: str, new: Value, new_status: str) -> bool:
        if status != new_status:
            return True
        band = self.deadbands.get(row.name)
        if (
            band is None
            or isinstance(old, bool)
            or isinstance(new, bool)
            or not isinstance(old, int | float)
            or not isinstance(new, int | float)
        ):
            return bool(old != new or type(old) is not type(new))
        return abs(new - old) > band

    def alarms(self, changes: Sequence[AlarmChange]) -> list[Message]:
        """Each change as an event (not retained), then each path's active list once (retained)."""
        messages: list[Message] = []
        touched: dict[tuple[str, int], str] = {}
        for c in changes:
            stamp = iso_time(c.time)
            event = AlarmEvent(c.alm_type, c.alm_no, c.axis_no, c.msg, c.active, stamp)
            topic = f"{self.path_topic(c.machine, c.path)}/alarms/event"
            messages.append(Message(topic, event.encode(), False))
            active = self._active.setdefault(c.machine, {}).setdefault(c.path, {})
            key = (c.alm_type, c.alm_no, c.axis_no)
            if c.active:
                active[key] = event
            else:
                active.pop(key, None)
            touched[(c.machine, c.path)] = stamp
        lists = [self._active_list(m, p, stamp) for (m, p), stamp in touched.items()]
        messages.extend(self._kept(lists))
        return messages

    def _kept(self, messages: list[Message]) -> list[Message]:
        for message in messages:
            if message.retain:
                self._retained[message.topic] = message
        return messages

    def retained(self) -> list[Message]:
        """The latest retained message of every topic published so far (the gateway's own
        state topics aside), oldest topic first: what the broker should hold. Published again
        after messages were dropped, it makes the broker's retained state whole again."""
        return list(self._retained.values())

    def _active_list(self, machine: str, path: int, stamp: str) -> Message:
        alarms = tuple(self._active.get(machine, {}).get(path, {}).values())
        topic = f"{self.path_topic(machine, path)}/alarms/active"
        return Message(topic, ActiveAlarms(alarms, _GOOD, stamp).encode(), True)


class Buffer:
    """The messages waiting for the broker, at most ``bound`` of them, oldest first.

    A retained message replaces one still waiting for the same topic (the latest wins, and it
    takes the newer place in the order: the broker would keep only the latest anyway); such a
    replacement is counted in :attr:`coalesced`. When full, the oldest message is dropped and
    counted in :attr:`dropped`: memory stays bounded however long the broker is away."""

    def __init__(self, bound: int) -> None:
        self.bound = bound  # (1 or more: MqttSettings.check)
        self.dropped = 0
        self.coalesced = 0
        self._next = 0
        self._waiting: OrderedDict[str | int, Message] = OrderedDict()

    def __len__(self) -> int:
        return len(self._waiting)

    def _key(self, message: Message) -> str | int:
        if message.retain:
            return message.topic
        self._next += 1
        return self._next

    def put(self, message: Message) -> None:
        key = self._key(message)
        if self._waiting.pop(key, None) is not None:
            self.coalesced += 1
        self._waiting[key] = message
        self._bound()

    def extend(self, messages: Iterable[Message]) -> None:
        for message in messages:
            self.put(message)

    def discard_retained(self) -> None:
        """Forget the waiting retained messages (not counted as dropped): a full copy of the
        retained state is about to be published in their place."""
        for key in [k for k, m in self._waiting.items() if m.retain]:
            del self._waiting[key]

    def take(self, count: int) -> list[Message]:
        """Up to ``count`` messages from the front; :meth:`restore` puts them back if they could
        not be sent."""
        taken: list[Message] = []
        waiting = self._waiting
        while waiting and len(taken) < count:
            taken.append(waiting.popitem(last=False)[1])
        return taken

    def restore(self, messages: Sequence[Message]) -> None:
        """Put taken messages back at the front, in their order: a retained one whose topic
        got a newer message meanwhile is left out (and counted as coalesced)."""
        for message in reversed(messages):
            key = self._key(message)
            if key in self._waiting:
                self.coalesced += 1
                continue
            self._waiting[key] = message
            self._waiting.move_to_end(key, last=False)
        self._bound()

    def _bound(self) -> None:
        while len(self._waiting) > self.bound:
            self._waiting.popitem(last=False)
            self.dropped += 1
