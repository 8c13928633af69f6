"""Counted alarm lists: ``cnc_rdalmmsg`` (0x0006) and ``cnc_rdalmhistry`` (0x0F1A).

Both start with ``i16 count``; ``count = -1`` is followed by ``i16 ew`` and nothing else.
Decoding follows the rules of ``docs/protocol.md`` section 3 and never raises:

* a negative count gives no entries (``ew`` carries the code; ``EW_PROTOCOL`` when the count is
  negative but no code follows, or the count is below -1);
* a history entry with an impossible timestamp (month 0, day 32, ...) is skipped;
* an entry whose ``msg_len`` is negative or runs past the payload ends the list there, keeping
  the entries before it.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from typing import Final, Self

from .._typed import MAX_ALARM_TEXT, MAX_ALARM_TYPE, alarm_text_unfit
from ..errors import EW

__all__ = [
    "ALARM_TYPES",
    "ALARM_TYPE_NAMES",
    "MAX_ALARM_MSG",
    "MAX_HISTORY_DEPTH",
    "ActiveAlarm",
    "ActiveAlarmList",
    "AlarmHistory",
    "AlarmHistoryEntry",
    "AlarmType",
    "alarm_active_already",
    "alarm_code",
    "alarm_fields",
    "alarm_filter_text",
    "alarm_message",
    "alarm_text",
    "alarm_time_text",
    "alarm_type_of",
    "nothing_cleared",
]

#: Longest message the CNC keeps for an alarm.
MAX_ALARM_MSG: Final = 32
#: Deepest alarm-history read (``cnc_rdalmhistry`` depth 1..250).
MAX_HISTORY_DEPTH: Final = 250

_I16: Final = struct.Struct("<h")
_COUNT_ERROR: Final = struct.Struct("<hh")
_MSG_HEAD: Final = struct.Struct("<hhhh")  # axis_no, alm_type, alm_no, msg_len
_HIST_HEAD: Final = struct.Struct("<10h")  # 6 x time, axis_no, alm_type, alm_no, msg_len


class AlarmType(enum.IntEnum):
    """Alarm type numbers (FANUC 0i-D/F, 30i numbering)."""

    SW = 0
    PW = 1
    IO = 2
    PS = 3
    OT = 4
    OH = 5
    SV = 6
    SR = 7
    MC = 8
    SP = 9
    DS = 10
    IE = 11
    BG = 12
    SN = 13
    EX = 15
    PC = 19


#: alm_type -> its two-letter prefix, as the CNC screen shows it.
ALARM_TYPE_NAMES: Final[dict[int, str]] = {t.value: t.name for t in AlarmType}


def alarm_time_text(when: datetime) -> str:
    """When an alarm occurred, as every front end writes a history entry's time (UTC, whole
    seconds): ``2024-05-01T12:00:00Z``."""
    t = when.astimezone(UTC) if when.tzinfo else when
    return t.strftime("%Y-%m-%dT%H:%M:%SZ")


#: The alarm types every front end takes, as a refusal names them.
ALARM_TYPES: Final = f"one of {' '.join(t.name for t in AlarmType)}, or 0..{MAX_ALARM_TYPE}"


def alarm_type_of(name: str) -> int:
    """An alarm type's number from its two-letter name as every front end takes it (``PS``,
    ``ps``: ASCII letters, spaces around); ValueError naming what was given and the names,
    TypeError for a name that is no ``str``."""
    if not isinstance(name, str):
        raise TypeError(f"an alarm type's name must be text (str), got {name!r}")
    text = name.strip().upper() if name.isascii() else ""
    if text in AlarmType.__members__:
        return int(AlarmType[text])
    raise ValueError(f"unknown alarm type {name!r} ({ALARM_TYPES})")


def alarm_code(alm_type: int, alm_no: int) -> str:
    """An alarm's code as the CNC screen shows it: ``PS0100`` for type 3, number 100; a type
    without a name is ``T<n>:`` (``T14:0001``). TypeError for a type or number that is no
    ``int`` (a name, ``"SV"``, is :func:`alarm_type_of`'s)."""
    for what, value in (("alm_type", alm_type), ("alm_no", alm_no)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise TypeError(f"{what} must be an integer, got {value!r}")
    prefix = ALARM_TYPE_NAMES.get(alm_type)
    if prefix is None:
        return f"T{alm_type}:{alm_no:04d}"
    return f"{prefix}{alm_no:04d}"


def alarm_fields(axis_no: int, alm_type: int, alm_no: int, msg: str) -> dict[str, int | str]:
    """One alarm as every front end writes it in JSON (``alarms --json``, the web page's
    API, the gateway's MQTT alarm events): its code as the CNC screen shows it, then the
    FOCAS names of ``ODBALMMSG2``'s fields (``axis_no``, ``alm_type``, ``alm_no``, ``msg``)."""
    code = alarm_code(alm_type, alm_no)
    return {"code": code, "axis_no": axis_no, "alm_type": alm_type, "alm_no": alm_no, "msg": msg}


def alarm_active_already(
    alm_type: int, alm_no: int, msg: str, axis_no: int = 0, *, on: str = ""
) -> str:
    """What every front end says of an alarm raised while it is active (its message ``msg``
    kept; ``on``: `` on path 2`` on a machine of several paths): a CNC shows one entry per
    alarm, so nothing changes."""
    return (
        f"{alarm_text(alm_type, alm_no, '', axis_no)} is already active{on}"
        + (f": {msg}" if msg else " (with no message)")
        + " (a CNC shows one entry per alarm: clear it first to raise it with another message)"
    )


def alarm_filter_text(alm_type: int, alm_no: int) -> str | None:
    """The alarms a clear asks for as the CNC names them, for :func:`nothing_cleared`: a code
    (``PS0100``), a type (``PS``, ``T31`` for one of no name), ``number 100`` of any type, or
    None for every alarm (-1 matches any)."""
    if alm_no == -1:
        return None if alm_type == -1 else ALARM_TYPE_NAMES.get(alm_type, f"T{alm_type}")
    return f"number {alm_no}" if alm_type == -1 else alarm_code(alm_type, alm_no)


def nothing_cleared(
    given: str | None,
    *,
    on: str = "",
    elsewhere: Sequence[tuple[int, int]] = (),
    advice: str = "",
) -> str:
    """What every front end says of a clear of alarms that cleared none: ``given`` the alarms
    asked for as the CNC names them (``PS0100``, ``PS``), None for every one; ``on`` as
    :func:`alarm_active_already` takes it; ``elsewhere`` the other paths with such alarms and
    how many each has (``(1 active on path 2)``, ``(PS is active on path 2)``, ``advice``
    after the first: what the front end offers to clear them)."""
    if given is None:
        others = "; ".join(f"{n} active on path {p}" for p, n in elsewhere)
        return f"no active alarms{on}; nothing to clear" + (f" ({others})" if others else "")
    where = f" ({given} is active on path {elsewhere[0][0]}{advice})" if elsewhere else ""
    return f"no active alarm matches {given}{on}; nothing cleared{where}"


def alarm_text(alm_type: int, alm_no: int, msg: str = "", axis_no: int = 0) -> str:
    """One alarm as every front end writes it: its code, `` (axis n)`` for an axis's alarm,
    then its message (``SV0411 (axis 1) EXCESS ERROR IN MOVE``). A message that begins with
    the code itself, as the screen shows it (``EX1001 COOLANT LEVEL LOW``), gives the code
    once."""
    code = alarm_code(alm_type, alm_no)
    text = msg.strip()
    if text == code or text.startswith(code + " "):
        text = text[len(code) :].lstrip()
    axis = f" (axis {axis_no})" if axis_no else ""
    return f"{code}{axis} {text}".rstrip()


def alarm_message(msg: str) -> bytes:
    """The bytes of an alarm message given as text (``raise_alarm``): ASCII only, as the
    packed protocol carries it, and one line (a control character is refused in the
    machine's words, :func:`~focas_net._typed.alarm_text_unfit`, of the part the machine
    keeps); ValueError, naming the text, for any other character. Every front end that takes
    a message as text (the client, the command line, the dashboard) refuses with this rule;
    the wire itself carries any bytes. TypeError for a message that is no ``str``."""
    if not isinstance(msg, str):
        raise TypeError(f"alarm message must be text (str), got {msg!r}")
    try:
        raw = msg.encode("ascii")
    except UnicodeEncodeError:
        raise ValueError(f"alarm message must be ASCII: {msg!r}") from None
    unfit = alarm_text_unfit(msg[:MAX_ALARM_TEXT])
    if unfit is not None:
        raise ValueError(unfit)
    return raw


def _text(raw: bytes) -> str:
    return raw.decode("latin-1")


def _raw(msg: str) -> bytes:
    try:
        return msg.encode("latin-1")
    except UnicodeEncodeError as exc:
        raise ValueError(f"alarm message must be ASCII: {msg!r}") from exc


def _pad(n: int) -> bytes:
    return b"\x00" * (-n % 4)


def _encode_list(ew: int, heads_and_msgs: list[tuple[bytes, bytes]]) -> bytes:
    """``count`` then each entry (its packed head, its message, the pad); or ``-1, ew``."""
    if ew:
        if heads_and_msgs:
            raise ValueError("an error answer carries no entries")
        return _COUNT_ERROR.pack(-1, ew)
    try:
        parts = [_I16.pack(len(heads_and_msgs))]
    except struct.error as exc:
        raise ValueError(f"alarm list of {len(heads_and_msgs)} entries: {exc}") from None
    for head, raw in heads_and_msgs:
        parts += (head, raw, _pad(len(raw)))
    return b"".join(parts)


def _count(payload: bytes) -> tuple[int, int]:
    """``(count, 0)`` of a list answer, or ``(0, ew)`` when the count is negative (with the
    code that follows ``count = -1``, else EW_PROTOCOL). Never raises."""
    if len(payload) < 2:
        return 0, int(EW.PROTOCOL)
    (count,) = _I16.unpack_from(payload, 0)
    if count >= 0:
        return count, 0
    if count == -1 and len(payload) >= 4:
        ew = int(_I16.unpack_from(payload, 2)[0])
        if ew:
            return 0, ew
    return 0, int(EW.PROTOCOL)


@dataclass(frozen=True, slots=True)
class ActiveAlarm:
    """One active alarm (an entry of ``cnc_rdalmmsg``)."""

    axis_no: int
    alm_type: int
    alm_no: int
    msg: str

    @property
    def key(self) -> tuple[int, int, int]:
        """The identity of an alarm: ``(axis_no, alm_type, alm_no)``."""
        return (self.axis_no, self.alm_type, self.alm_no)


@dataclass(frozen=True, slots=True)
class ActiveAlarmList:
    """``cnc_rdalmmsg`` answer: the entries, or ``ew != 0`` (count = -1) and no entries."""

    entries: tuple[ActiveAlarm, ...] = ()
    ew: int = 0

    def encode(self) -> bytes:
        entries = []
        for e in self.entries:
            raw = _raw(e.msg)
            try:
                entries.append((_MSG_HEAD.pack(e.axis_no, e.alm_type, e.alm_no, len(raw)), raw))
            except struct.error as exc:
                raise ValueError(f"active alarm entry: {exc}") from None
        return _encode_list(self.ew, entries)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        count, ew = _count(data)
        if ew:
            return cls((), ew)
        entries: list[ActiveAlarm] = []
        pos, size = 2, len(data)
        for _ in range(count):
            if pos + 8 > size:
                break
            axis_no, alm_type, alm_no, msg_len = _MSG_HEAD.unpack_from(data, pos)
            end = pos + 8 + msg_len
            if msg_len < 0 or end > size:
                break
            entries.append(ActiveAlarm(axis_no, alm_type, alm_no, _text(data[pos + 8 : end])))
            pos = end + (-msg_len % 4)
        return cls(tuple(entries))


@dataclass(frozen=True, slots=True)
class AlarmHistoryEntry:
    """One entry of the alarm history (ODBAHIS); ``occurred_at`` is timezone-aware UTC."""

    occurred_at: datetime
    axis_no: int
    alm_type: int
    alm_no: int
    msg: str

    @property
    def key(self) -> tuple[datetime, int, int, int]:
        """Deduplication key: ``(occurred_at, alm_no, alm_type, axis_no)`` (one alarm of two
        axes in one second is two entries; the same alarm twice in one second has one key,
        and counts as often as the history holds it)."""
        return (self.occurred_at, self.alm_no, self.alm_type, self.axis_no)


@dataclass(frozen=True, slots=True)
class AlarmHistory:
    """``cnc_rdalmhistry`` answer, newest first; ``ew != 0`` (count < 0) means no entries."""

    entries: tuple[AlarmHistoryEntry, ...] = ()
    ew: int = 0

    def encode(self) -> bytes:
        entries = []
        for e in self.entries:
            t = e.occurred_at.astimezone(UTC) if e.occurred_at.tzinfo else e.occurred_at
            raw = _raw(e.msg)
            try:
                head = _HIST_HEAD.pack(
                    t.year, t.month, t.day, t.hour, t.minute, t.second,
                    e.axis_no, e.alm_type, e.alm_no, len(raw),
                )  # fmt: skip
            except struct.error as exc:
                raise ValueError(f"alarm history entry: {exc}") from None
            entries.append((head, raw))
        return _encode_list(self.ew, entries)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        count, ew = _count(data)
        if ew:
            return cls((), ew)
        entries: list[AlarmHistoryEntry] = []
        pos, size = 2, len(data)
        for _ in range(count):
            if pos + 20 > size:
                break
            y, mo, d, h, mi, s, axis_no, alm_type, alm_no, msg_len = _HIST_HEAD.unpack_from(
                data, pos
            )
            end = pos + 20 + msg_len
            if msg_len < 0 or end > size:
                break
            pos = end + (-msg_len % 4)
            try:
                when = datetime(y, mo, d, h, mi, s, tzinfo=UTC)
            except ValueError:
                continue  # impossible timestamp: skip this entry, keep the rest
            entries.append(
                AlarmHistoryEntry(when, axis_no, alm_type, alm_no, _text(data[end - msg_len : end]))
            )
        return cls(tuple(entries))
