"""Payloads of the fault-queue commands: 0x0E06 list_faults and 0x0E07 clear_faults
(``docs/protocol.md`` section 8, "Extensions: the fault queues")."""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import ClassVar, Final, Self

from .._typed import typed_shown, whole_number
from ..errors import EW, PayloadError
from ._base import I16, FixedPayload
from .values import FaultKind, FaultScope

__all__ = [
    "FAULT_SCOPES",
    "MAX_DELAY_MS",
    "MAX_FAULT_COUNT",
    "ArmedFault",
    "FaultList",
    "FaultsCleared",
    "FaultsRequest",
    "ew_of_text",
    "fault_arg_needed",
    "fault_kind_of",
    "fault_refusal",
    "scope_refusal",
]

#: Longest delay a fault may ask for, in milliseconds.
MAX_DELAY_MS: Final = 60_000
#: Largest ``count`` of one fault.
MAX_FAULT_COUNT: Final = 10_000
#: The scopes a fault queue has, as numbers.
FAULT_SCOPES: Final = frozenset(int(s) for s in FaultScope)
_FAULT_KINDS: Final = frozenset(int(k) for k in FaultKind)
_I16_MIN: Final = -32_768
_I16_MAX: Final = 32_767


def fault_kind_of(typed: object) -> FaultKind:
    """A fault's kind as typed on every front end (``sim fault KIND``, the page's ``kind``): its
    name in any case, spaces around it left out; ValueError naming what was typed (text
    quoted, a JSON value as sent) and the names otherwise (a number is no kind: ``1`` is not
    read as a delay)."""
    found = FaultKind.__members__.get(typed.strip().upper()) if isinstance(typed, str) else None
    if found is None:
        names = ", ".join(sorted(k.name.lower() for k in FaultKind))
        raise ValueError(f"unknown fault kind {typed_shown(typed)} (one of {names})")
    return found


def scope_refusal(scope: int) -> str | None:
    """Why a fault scope number is refused (``EW_DATA``), in the words of
    :func:`fault_refusal`; None for a scope the server has."""
    if scope in FAULT_SCOPES:
        return None
    scopes = ", ".join(f"{int(s)} {s.name}" for s in FaultScope)
    return f"no fault scope {scope} (one of {scopes})"


def fault_arg_needed(kind: int) -> str | None:
    """What a fault of ``kind`` given no argument lacks, in the words every front end shows
    after the argument's own name (the command line's ``--arg``, the dashboard's ``arg``);
    None for a kind that takes none (a drop, a split)."""
    if kind == FaultKind.DELAY:
        return f"a delay fault needs its delay in milliseconds (0..{MAX_DELAY_MS})"
    if kind == FaultKind.ERROR:
        return "an error fault needs the EW code it answers with (e.g. EW_BUSY or -1)"
    return None


def fault_refusal(kind: int, scope: int, count: int, arg: int) -> str | None:
    """Why a fault of these numbers is refused (``EW_DATA``), in the words every front end
    shows (the dashboard, the command line, the client from the EW code alone); None when it
    is armed. The one check of a fault's arguments: the server's ``parse_inject`` answers
    ``EW_DATA`` exactly when this gives a reason."""
    if kind not in _FAULT_KINDS:
        kinds = ", ".join(f"{int(k)} {k.name}" for k in FaultKind)
        return f"no fault kind {kind} (one of {kinds})"
    why = scope_refusal(scope)
    if why is not None:
        return why
    if not 1 <= count <= MAX_FAULT_COUNT:
        return f"a fault's count is 1..{MAX_FAULT_COUNT}, got {count}"
    if kind == FaultKind.DELAY and not 0 <= arg <= MAX_DELAY_MS:
        return f"a delay is 0..{MAX_DELAY_MS} ms, got {arg}"
    if kind == FaultKind.ERROR and (arg == 0 or not _I16_MIN <= arg <= _I16_MAX):
        return f"an error fault's EW code is a nonzero {_I16_MIN}..{_I16_MAX}, got {arg}"
    return None


@dataclass(frozen=True, slots=True)
class FaultsRequest(FixedPayload):
    """Request of 0x0E06 and 0x0E07: ``i16 scope`` (0 this connection, 1 the machine)."""

    FORMAT: ClassVar[str] = "<h"
    scope: int


@dataclass(frozen=True, slots=True)
class ArmedFault(FixedPayload):
    """One pending fault of a 0x0E06 answer: ``i16 kind, i16 remaining, i32 arg``."""

    FORMAT: ClassVar[str] = "<hhi"
    kind: int
    remaining: int  #: answers it still applies to
    arg: int


_ENTRY: Final = ArmedFault.STRUCT


@dataclass(frozen=True, slots=True)
class FaultList:
    """Answer of 0x0E06 after ``ew``: ``i16 count``, then ``count`` :class:`ArmedFault`
    entries of 8 bytes, the one applying to the next answer first."""

    faults: tuple[ArmedFault, ...]

    def encode(self) -> bytes:
        try:
            head = I16.pack(len(self.faults))
        except struct.error:
            raise ValueError(f"FaultList: {len(self.faults)} faults do not fit i16") from None
        return head + b"".join(f.encode() for f in self.faults)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 2:
            raise PayloadError(f"fault list of {len(data)} bytes has no count")
        (count,) = I16.unpack_from(data, 0)
        if count < 0 or len(data) != 2 + count * _ENTRY.size:
            raise PayloadError(f"fault list of {len(data)} bytes for count {count}")
        return cls(tuple(ArmedFault(*e) for e in _ENTRY.iter_unpack(data[2:])))


@dataclass(frozen=True, slots=True)
class FaultsCleared(FixedPayload):
    """Answer of 0x0E07 after ``ew``: ``i16 cleared``, the number of faults removed."""

    FORMAT: ClassVar[str] = "<h"
    cleared: int


def ew_of_text(text: str) -> int:
    """An EW code as typed on every front end (an ERROR fault's argument: the command line's
    ``--arg``, the page's box): by number (``17``, ``-1``, read as every whole number is) or by name
    (``EW_PASSWD``, ``passwd``, any case); ValueError naming the text otherwise, TypeError
    for a value that is no ``str``."""
    if not isinstance(text, str):
        raise TypeError(f"an EW code as typed must be text (str), got {text!r}")
    try:
        return whole_number(text)
    except ValueError:
        pass
    name = text.strip().upper().removeprefix("EW_") if text.isascii() else ""
    try:
        return int(EW[name])
    except KeyError:
        raise ValueError(f"unknown EW code {text!r}") from None
