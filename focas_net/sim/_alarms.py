"""The machine's alarms: the active ones and the history, stamped by the wall clock."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from itertools import islice
from typing import Final

from focas_net._typed import (
    MAX_ALARM_NO,
    MAX_ALARM_TEXT,
    MAX_ALARM_TYPE,
    alarm_axis_unfit,
    alarm_key_unfit,
    alarm_text_unfit,
)
from focas_net.errors import EW

from ._base import Counters, MachineError, logger, need_int, need_text
from .nc import ALARM_MESSAGES, AlarmKind, NcAlarm

__all__ = [
    "DEFAULT_HISTORY_CAPACITY",
    "MAX_ALARM_NO",
    "MAX_ALARM_TEXT",
    "MAX_ALARM_TYPE",
    "MAX_HISTORY_CAPACITY",
    "NC_ALARM_TYPES",
    "Alarm",
    "AlarmKey",
    "Alarms",
    "Clock",
    "HistoryEntry",
    "PathAlarmKey",
    "nc_alarm",
    "utc_now",
]

#: A source of the current time; the machine stamps alarms with it (as UTC, whole seconds).
Clock = Callable[[], datetime]
#: An alarm's identity: ``(axis_no, alm_type, alm_no)``.
AlarmKey = tuple[int, int, int]
#: An active alarm's place: the path it is active on and its identity.
PathAlarmKey = tuple[int, AlarmKey]

#: Alarm history capacity of a FANUC 0i/30i.
DEFAULT_HISTORY_CAPACITY: Final = 250
#: The largest alarm history a machine keeps (a machine file's ``history_capacity`` too).
MAX_HISTORY_CAPACITY: Final = 100_000
#: Alarm type numbers of the alarms a program raises (FANUC 0i-D/F, 30i numbering).
NC_ALARM_TYPES: Final = {AlarmKind.PS: 3, AlarmKind.OT: 4, AlarmKind.MC: 8}
_NC_ALARM_KINDS: Final = {number: kind for kind, number in NC_ALARM_TYPES.items()}
#: The message of each alarm in the control's table, by ``(alm_type, alm_no)``: what an alarm
#: raised without a message shows, as the same alarm raised by a part program does.
_TABLE: Final = {(NC_ALARM_TYPES[kind], no): text for (kind, no), text in ALARM_MESSAGES.items()}


def utc_now() -> datetime:
    """The default clock: now, timezone-aware UTC."""
    return datetime.now(UTC)


@dataclass(frozen=True, slots=True)
class Alarm:
    """An active alarm."""

    axis_no: int
    alm_type: int
    alm_no: int
    msg: str

    @property
    def key(self) -> AlarmKey:
        """The identity of an alarm: ``(axis_no, alm_type, alm_no)``."""
        return (self.axis_no, self.alm_type, self.alm_no)


@dataclass(frozen=True, slots=True)
class HistoryEntry:
    """One entry of the alarm history; ``occurred_at`` is timezone-aware UTC, whole seconds."""

    occurred_at: datetime
    axis_no: int
    alm_type: int
    alm_no: int
    msg: str


def nc_alarm(key: AlarmKey, text: str) -> NcAlarm:
    """The engine's alarm for the machine's alarm ``key``: the kind of its type (PS for a
    type no program raises)."""
    axis_no, alm_type, alm_no = key
    kind = _NC_ALARM_KINDS.get(alm_type, AlarmKind.PS)
    return NcAlarm(kind, alm_no, text, axis=axis_no or None)


class Alarms:
    """The active alarms by path and key (oldest raised first) and the history (newest first,
    at most ``capacity`` entries), shared by the paths. An alarm is active on one path (a
    program's alarms on the path that ran it); a read for a path sees that path's. Every
    change moves the alarm and the status counters."""

    __slots__ = ("active", "clock", "counters", "history", "name", "shift")

    def __init__(self, name: str, capacity: int, clock: Clock, counters: Counters) -> None:
        if isinstance(capacity, bool) or not isinstance(capacity, int):
            raise TypeError(f"history_capacity must be an integer, got {capacity!r}")
        if not 1 <= capacity <= MAX_HISTORY_CAPACITY:
            raise ValueError(
                f"history_capacity {capacity} is outside 1..{MAX_HISTORY_CAPACITY} (entries)"
            )
        if not callable(clock):
            raise TypeError(f"clock must be callable (it returns the time), got {clock!r}")
        self.name = name
        self.clock = clock
        self.counters = counters
        self.active: dict[PathAlarmKey, Alarm] = {}
        self.history: deque[HistoryEntry] = deque(maxlen=capacity)
        #: How far the CNC's clock was set from ``clock`` (``cnc_settimer``).
        self.shift = timedelta()

    @property
    def capacity(self) -> int:
        cap = self.history.maxlen
        assert cap is not None
        return cap

    def now(self) -> datetime:
        """The CNC's clock (``clock`` and the :attr:`shift` it was set by) as aware UTC, cut
        to whole seconds."""
        t = self.clock()
        t = t.replace(tzinfo=UTC) if t.tzinfo is None else t.astimezone(UTC)
        return (t + self.shift).replace(microsecond=0)

    def stamp(self, late: float) -> datetime:
        """The stamp of an alarm raised ``late`` seconds of machine time ago."""
        return (self.now() - timedelta(seconds=max(0.0, late))).replace(microsecond=0)

    @staticmethod
    def checked(axis_no: int, alm_type: int, alm_no: int, msg: str, axes: int) -> str:
        """The text an alarm keeps, once its numbers are checked: EW_DATA (alm_type outside
        0..31, alm_no outside 0..32767), EW_ATTRIB (axis_no), EW_DATA (a character beyond
        U+00FF, or a control character: a tab, a line break, NUL...); TypeError for a number
        or a message of another type. An empty message is the one of the control's alarm table
        for an alarm a part program raises too (PS0010 ``IMPROPER G-CODE``), else empty."""
        # named as the clients and the command line name them
        for what, value in (("axis", axis_no), ("alarm type", alm_type), ("alarm number", alm_no)):
            need_int(what, value)
        need_text("alarm message", msg)
        key_unfit = alarm_key_unfit(alm_type, alm_no)  # the words of every front end
        if key_unfit is not None:
            raise MachineError(EW.DATA, key_unfit)
        axis_unfit = alarm_axis_unfit(axis_no, axes)
        if axis_unfit is not None:
            raise MachineError(EW.ATTRIB, axis_unfit)
        text = msg[:MAX_ALARM_TEXT] or _TABLE.get((alm_type, alm_no), "")
        unfit = alarm_text_unfit(text)
        if unfit is not None:
            raise MachineError(EW.DATA, unfit)
        return text

    def add(self, key: AlarmKey, text: str, when: datetime, path: int = 1) -> bool:
        """Raise an alarm on ``path`` and record it in the history; False when it is active
        there already."""
        if (path, key) in self.active:
            return False
        axis_no, alm_type, alm_no = key
        logger.debug(
            "%s: alarm raised: path %d axis %d type %d no %d",
            self.name,
            path,
            axis_no,
            alm_type,
            alm_no,
        )
        self.active[path, key] = Alarm(axis_no, alm_type, alm_no, text)
        self.history.appendleft(HistoryEntry(when, axis_no, alm_type, alm_no, text))
        self.counters.alarm += 1
        self.counters.status_changed()
        return True

    def on(self, path: int) -> bool:
        """Whether an alarm is active on ``path``."""
        return any(p == path for p, _ in self.active)

    def clear(self, alm_type: int, alm_no: int, path: int) -> int:
        """Remove the active alarms of ``path`` matching ``alm_type`` and ``alm_no`` (-1 =
        any): EW_DATA for a number no alarm has (alm_type outside -1..31, alm_no outside
        -1..32767), which would match nothing and say nothing of the typing."""
        need_int("alm_type", alm_type)
        need_int("alm_no", alm_no)
        why = alarm_key_unfit(alm_type, alm_no, every=True)  # -1: any
        if why is not None:
            raise MachineError(EW.DATA, why)
        gone = [
            k
            for p, k in self.active
            if p == path
            and (alm_type == -1 or k[1] == alm_type)
            and (alm_no == -1 or k[2] == alm_no)
        ]
        if self.remove(gone, path):
            logger.debug("%s: %d alarm(s) cleared", self.name, len(gone))
        return len(gone)

    def remove(self, keys: Iterable[AlarmKey], path: int = 1) -> bool:
        """Remove those of ``keys`` that are active on ``path``; True when one was."""
        gone = [(path, k) for k in keys if (path, k) in self.active]
        for k in gone:
            del self.active[k]
        if gone:
            self.counters.alarm += 1
            self.counters.status_changed()
        return bool(gone)

    def read(self, alm_type: int, limit: int | None, path: int = 1) -> list[Alarm]:
        """The active alarms of ``path`` of ``alm_type`` (-1: every type), at most ``limit``."""
        need_int("alm_type", alm_type)
        if limit is not None and need_int("limit", limit) < 0:
            raise ValueError(f"limit must be at least 0 (or None), got {limit}")
        alarms = [a for (p, _), a in self.active.items() if p == path]
        chosen = alarms if alm_type == -1 else (a for a in alarms if a.alm_type == alm_type)
        return list(chosen if limit is None else islice(chosen, min(limit, len(alarms))))

    def read_history(self, depth: int | None) -> tuple[HistoryEntry, ...]:
        if depth is not None and need_int("depth", depth) < 0:
            raise ValueError(f"depth must be at least 0 (or None), got {depth}")
        history = self.history
        return tuple(history if depth is None else islice(history, min(depth, len(history))))
