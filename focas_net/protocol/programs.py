"""Payloads of the part-program commands and of the cycle's simulator control
(``docs/protocol.md`` section 8, "Extensions: part programs" and "Simulator control: the
cycle"): 0x0030 program directory, 0x0031 program text, 0x0032 run figures, 0x0033 loads,
0x0110 store,
0x0111 delete, 0x0112 select main, 0x0E20 cycle, 0x0E21 overrides."""

from __future__ import annotations

import enum
import struct
from dataclasses import dataclass
from typing import ClassVar, Final, Self

from .._typed import program_text_unfit, typed_shown
from ..errors import PayloadError
from ._base import I16, FixedPayload

__all__ = [
    "MAX_DIRECTORY_ENTRIES",
    "MAX_PROGRAM_CHUNK",
    "MAX_PROGRAM_NAME",
    "MAX_PROGRAM_TEXT",
    "CycleAction",
    "CycleControl",
    "DirectoryRequest",
    "LoadMeters",
    "Overrides",
    "ProgramChunk",
    "ProgramChunkRequest",
    "ProgramDirectory",
    "ProgramEntry",
    "ProgramNumber",
    "ProgramText",
    "RunInfo",
    "cycle_action_of",
]

#: Most entries of one directory answer (``max`` 1..64).
MAX_DIRECTORY_ENTRIES: Final = 64
#: Most bytes of a program name in a directory entry.
MAX_PROGRAM_NAME: Final = 255
#: Most bytes of program text one 0x0031 answer carries.
MAX_PROGRAM_CHUNK: Final = 4096
#: Most bytes of program text one 0x0110 request carries.
MAX_PROGRAM_TEXT: Final = 60_000

_ENTRY_HEAD: Final = struct.Struct("<iiH")  # number, size, name_len
_CHUNK_HEAD: Final = struct.Struct("<iH")  # total, length
_TEXT_HEAD: Final = struct.Struct("<hH")  # replace, length
_LOADS_HEAD: Final = struct.Struct("<BB")  # spindles, axes
_LOAD: Final = struct.Struct("<h")


def _ascii(raw: bytes, what: str) -> str:
    try:
        return raw.decode("ascii")
    except UnicodeDecodeError:
        raise PayloadError(f"{what} is not ASCII text") from None


def _raw(text: str, what: str) -> bytes:
    try:
        return text.encode("ascii")
    except UnicodeEncodeError:
        raise ValueError(f"{what} must be ASCII text: {text[:40]!r}") from None


@dataclass(frozen=True, slots=True)
class DirectoryRequest(FixedPayload):
    """0x0030 request: ``i32 first`` (programs from this number on), ``i16 max`` (1..64)."""

    FORMAT: ClassVar[str] = "<ih"
    first: int
    max: int


@dataclass(frozen=True, slots=True)
class ProgramEntry:
    """One directory entry: O number, characters stored, name (the O line's comment)."""

    number: int
    size: int
    name: str


@dataclass(frozen=True, slots=True)
class ProgramDirectory:
    """0x0030 answer after ``ew``: ``i16 count``, then ``count`` entries of ``i32 number,
    i32 size, u16 name_len, name[name_len]`` (ASCII), by number."""

    entries: tuple[ProgramEntry, ...]

    def encode(self) -> bytes:
        parts = [I16.pack(len(self.entries))]
        for e in self.entries:
            name = _raw(e.name, "a program name")
            if len(name) > MAX_PROGRAM_NAME:
                raise ValueError(f"program name of {len(name)} bytes: {MAX_PROGRAM_NAME} at most")
            try:
                parts.append(_ENTRY_HEAD.pack(e.number, e.size, len(name)))
            except struct.error as exc:
                raise ValueError(f"program entry O{e.number}: {exc}") from None
            parts.append(name)
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 2:
            raise PayloadError(f"program directory of {len(data)} bytes has no count")
        (count,) = I16.unpack_from(data, 0)
        if count < 0:
            raise PayloadError(f"program directory count {count}")
        pos, entries = 2, []
        for _ in range(count):
            if pos + _ENTRY_HEAD.size > len(data):
                raise PayloadError(f"program directory of {len(data)} bytes for count {count}")
            number, size, name_len = _ENTRY_HEAD.unpack_from(data, pos)
            pos += _ENTRY_HEAD.size
            if pos + name_len > len(data):
                raise PayloadError(f"program directory entry O{number} runs past the payload")
            entries.append(ProgramEntry(number, size, _ascii(data[pos : pos + name_len], "name")))
            pos += name_len
        if pos != len(data):
            raise PayloadError(f"program directory: {len(data) - pos} bytes after the entries")
        return cls(tuple(entries))


@dataclass(frozen=True, slots=True)
class ProgramChunkRequest(FixedPayload):
    """0x0031 request: ``i32 number``, ``i32 offset`` (the first character wanted)."""

    FORMAT: ClassVar[str] = "<ii"
    number: int
    offset: int


#: How the two text payloads name themselves in messages: (the payload, a text too long).
_TEXT_NAMES: Final = {"chunk": ("program chunk", "a chunk"), "text": ("program text", "a program")}


def _pack_text(head: struct.Struct, first: int, text: str, limit: int, kind: str) -> bytes:
    """``head`` (``first``, the text's length), then the ASCII text, at most ``limit`` bytes;
    ``kind`` (``chunk`` or ``text``) names the payload in messages."""
    name, too_long = _TEXT_NAMES[kind]
    why = program_text_unfit(text) if isinstance(text, str) else None
    if why is not None:  # the program store's words, naming the line and the character
        raise ValueError(why)
    raw = _raw(text, "program text")
    if len(raw) > limit:
        raise ValueError(f"{too_long} of {len(raw)} bytes: {limit} at most")
    try:
        return head.pack(first, len(raw)) + raw
    except struct.error as exc:
        raise ValueError(f"{name}: {exc}") from None


def _unpack_text(head: struct.Struct, data: bytes, limit: int, kind: str) -> tuple[int, str]:
    """The inverse of :func:`_pack_text`: the head's first field and the text."""
    name = _TEXT_NAMES[kind][0]
    if len(data) < head.size:
        raise PayloadError(f"{name} of {len(data)} bytes is shorter than its head")
    first, length = head.unpack_from(data, 0)
    if len(data) != head.size + length or length > limit:
        raise PayloadError(f"{name} of {len(data)} bytes for length {length}")
    return first, _ascii(data[head.size :], "program text")


@dataclass(frozen=True, slots=True)
class ProgramChunk:
    """0x0031 answer after ``ew``: ``i32 total`` (characters of the program), ``u16 length``,
    then ``length`` bytes of its text (ASCII) from the offset asked, at most 4096."""

    total: int
    text: str

    def encode(self) -> bytes:
        return _pack_text(_CHUNK_HEAD, self.total, self.text, MAX_PROGRAM_CHUNK, "chunk")

    @classmethod
    def decode(cls, data: bytes) -> Self:
        return cls(*_unpack_text(_CHUNK_HEAD, data, MAX_PROGRAM_CHUNK, "chunk"))


@dataclass(frozen=True, slots=True)
class ProgramText:
    """0x0110 request: ``i16 replace`` (1: replace a stored program of the same number, 0:
    refuse it), ``u16 length``, then ``length`` bytes of program text (ASCII, at most
    60,000: one O-number program)."""

    replace: int
    text: str

    def encode(self) -> bytes:
        return _pack_text(_TEXT_HEAD, self.replace, self.text, MAX_PROGRAM_TEXT, "text")

    @classmethod
    def decode(cls, data: bytes) -> Self:
        return cls(*_unpack_text(_TEXT_HEAD, data, MAX_PROGRAM_TEXT, "text"))


@dataclass(frozen=True, slots=True)
class ProgramNumber(FixedPayload):
    """``i32 number``: the request of 0x0111 and 0x0112, the answer of 0x0110 after ``ew``."""

    FORMAT: ClassVar[str] = "<i"
    number: int


class CycleAction(enum.IntEnum):
    """The ``action`` of 0x0E20."""

    START = 0  #: cycle start
    HOLD = 1  #: feed hold
    RESET = 2  #: reset


def cycle_action_of(typed: object) -> CycleAction:
    """A cycle action as typed on every front end (``sim cycle ACTION``, the page's
    ``action``): its name in any case, spaces around it left out; ValueError naming what was
    typed (text quoted, a JSON value as sent: ``1``) and the names otherwise."""
    found = CycleAction.__members__.get(typed.strip().upper()) if isinstance(typed, str) else None
    if found is None:
        names = ", ".join(a.name.lower() for a in CycleAction)
        raise ValueError(f"unknown cycle action {typed_shown(typed)} (one of {names})")
    return found


@dataclass(frozen=True, slots=True)
class CycleControl(FixedPayload):
    """0x0E20 request: ``i16 action`` (:class:`CycleAction`)."""

    FORMAT: ClassVar[str] = "<h"
    action: int


@dataclass(frozen=True, slots=True)
class Overrides(FixedPayload):
    """0x0E21 request (-1: leave it): ``i16 feed`` (0..254 %),
    ``i16 rapid`` (0 (F0), 25, 50 or 100 %), ``i16 spindle`` (0..254 %)."""

    FORMAT: ClassVar[str] = "<hhh"
    feed: int
    rapid: int
    spindle: int


@dataclass(frozen=True, slots=True)
class RunInfo(FixedPayload):
    """0x0032 answer after ``ew``: the overrides ``i16 feed, i16 rapid, i16 spindle`` (%), then
    ``i32`` parts count and total parts, and the timers in milliseconds ``i64 power_on,
    i64 operating, i64 cutting, i64 cycle``."""

    FORMAT: ClassVar[str] = "<hhhiiqqqq"
    feed: int
    rapid: int
    spindle: int
    parts_count: int
    parts_total: int
    power_on_ms: int
    operating_ms: int
    cutting_ms: int
    cycle_ms: int


@dataclass(frozen=True, slots=True)
class LoadMeters:
    """0x0033 answer after ``ew``: ``u8 spindles, u8 axes``, then ``i16`` load (%) of each
    spindle and ``i16`` servo load (%) of each axis."""

    spindle: tuple[int, ...]
    servo: tuple[int, ...]

    def encode(self) -> bytes:
        for what, values in (("spindle", self.spindle), ("servo", self.servo)):
            if len(values) > 0xFF:
                raise ValueError(f"{len(values)} {what} loads: at most 255")
            for i, v in enumerate(values):
                if isinstance(v, bool) or not isinstance(v, int):
                    raise ValueError(f"{what} load [{i}] must be an integer, got {v!r}")
                if not -0x8000 <= v <= 0x7FFF:
                    raise ValueError(f"{what} load [{i}] {v} is outside -32768..32767")
        values = (*self.spindle, *self.servo)
        head = _LOADS_HEAD.pack(len(self.spindle), len(self.servo))
        return head + struct.pack(f"<{len(values)}h", *values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < _LOADS_HEAD.size:
            raise PayloadError(f"loads answer of {len(data)} bytes has no counts")
        spindles, axes = _LOADS_HEAD.unpack_from(data, 0)
        want = _LOADS_HEAD.size + (spindles + axes) * _LOAD.size
        if len(data) != want:
            raise PayloadError(
                f"loads answer of {len(data)} bytes for {spindles} spindles and {axes} axes "
                f"({want} expected)"
            )
        values = struct.unpack_from(f"<{spindles + axes}h", data, _LOADS_HEAD.size)
        return cls(tuple(values[:spindles]), tuple(values[spindles:]))
