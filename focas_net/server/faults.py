"""Fault injection (simulator control 0x0E05, docs/protocol.md section 4): the pure part.

``inject_fault`` carries ``i16 kind, i16 scope, i16 count, i32 arg``. This module validates it
and keeps the queues of armed faults; the connections (``_base.py``, ``_packed.py``,
``_native.py``) apply a fault to the answers they send, on packed and native connections alike
(``docs/native-protocol.md`` says how a native answer carries each kind).

* kind 1 :attr:`FaultKind.DELAY` - the answer is sent ``arg`` ms later (0..60,000); answers to
  later requests may overtake it.
* kind 2 :attr:`FaultKind.ERROR` - the answer is replaced by the EW code ``arg`` (non-zero,
  within i16); a counted list answers ``count = -1`` and that code; a native data request
  answers that code in every block, with no data.
* kind 3 :attr:`FaultKind.DROP` - the connection is closed instead of answering.
* kind 4 :attr:`FaultKind.SPLIT` - the answer is sent one byte per write.

``arg`` is ignored by kinds 3 and 4. ``scope`` 0 arms the fault for the connection that sent the
command; scope 1 for the next ``count`` answers of the machine on any connection (one shared
count). ``count`` is 1..10,000. A bad kind, scope, count or arg answers ``EW_DATA``.

Faults armed in one scope form a queue, first in, first out: the first fault applies to the
next answers until its count is used up, then the next one takes over (a fault armed behind
three pending delays of one answer each applies to the fourth answer). 0x0E06 list_faults
answers a scope's queue in that order, each fault with the answers it still applies to; 0x0E07
clear_faults empties it. When both scopes hold a fault, the connection's
own fault applies (and only its count goes down). The answers of control commands, and the
native open and close answers, are never faulted and never count. Faults are armed only with
the packed command; a native connection sees the machine's (scope 1).
"""

from __future__ import annotations

from collections import deque
from typing import Final

from focas_net.errors import EW, PayloadError, ew_label
from focas_net.protocol import (
    ArmedFault,
    FaultKind,
    FaultList,
    FaultScope,
    FaultsRequest,
    InjectFault,
)
from focas_net.protocol.faults import (
    FAULT_SCOPES,
    MAX_DELAY_MS,
    MAX_FAULT_COUNT,
    fault_refusal,
)

__all__ = [
    "MAX_ARMED_FAULTS",
    "MAX_DELAY_MS",
    "MAX_FAULT_COUNT",
    "Fault",
    "FaultKind",
    "FaultQueue",
    "FaultScope",
    "fault_arg_text",
    "fault_refusal",
    "no_faults_cleared",
    "parse_inject",
    "parse_scope",
]

#: Most faults one queue holds at once; arming one more answers ``EW_OVRFLOW``.
MAX_ARMED_FAULTS: Final = 64


class Fault:
    """One armed fault: its kind, its argument and how many answers it still applies to."""

    __slots__ = ("arg", "kind", "remaining")

    def __init__(self, kind: FaultKind, arg: int, remaining: int) -> None:
        self.kind = kind
        self.arg = arg
        self.remaining = remaining

    def __repr__(self) -> str:
        return f"Fault({self.kind.name}, arg={self.arg}, remaining={self.remaining})"


class FaultQueue:
    """Faults armed in one scope, applied in the order they were armed."""

    __slots__ = ("armed",)

    def __init__(self) -> None:
        #: The armed faults, the one applying now first.
        self.armed: deque[Fault] = deque()

    def __bool__(self) -> bool:
        return bool(self.armed)

    def __len__(self) -> int:
        return len(self.armed)

    def arm(self, fault: Fault) -> int:
        """Queue ``fault``; returns ``EW_OK``, or ``EW_OVRFLOW`` when the queue is full."""
        if len(self.armed) >= MAX_ARMED_FAULTS:
            return EW.OVRFLOW
        self.armed.append(fault)
        return EW.OK

    def take(self) -> tuple[FaultKind, int] | None:
        """The fault for the next answer as ``(kind, arg)``, counting it; None when none."""
        faults = self.armed
        if not faults:
            return None
        fault = faults[0]
        fault.remaining -= 1
        if fault.remaining <= 0:
            faults.popleft()
        return fault.kind, fault.arg

    def clear(self) -> int:
        """Remove every armed fault; returns how many there were."""
        count = len(self.armed)
        self.armed.clear()
        return count

    def listing(self) -> FaultList:
        """The armed faults in the order they apply, as 0x0E06 carries them."""
        return FaultList(tuple(ArmedFault(int(f.kind), f.remaining, f.arg) for f in self.armed))


def parse_scope(payload: bytes, *, refused: bool = False) -> FaultScope | int:
    """Validate the ``i16 scope`` request of 0x0E06 list_faults or 0x0E07 clear_faults.

    Returns the scope, or the EW code to answer, in the order of every control command:
    ``EW_LENGTH`` for a payload that is not 2 bytes, ``EW_PROT`` when ``refused`` (a clear on
    a read-only machine), ``EW_DATA`` for a scope other than 0 and 1.
    """
    try:
        req = FaultsRequest.decode(payload)
    except PayloadError:
        return EW.LENGTH
    if refused:
        return EW.PROT
    if req.scope not in FAULT_SCOPES:
        return EW.DATA
    return FaultScope(req.scope)


def parse_inject(payload: bytes, *, read_only: bool = False) -> tuple[FaultScope, Fault] | int:
    """Validate an ``inject_fault`` payload.

    Returns ``(scope, fault)``, or the EW code to answer, checked in the order of every control
    command: ``EW_LENGTH`` for a payload that is not 10 bytes, ``EW_PROT`` on a read-only
    machine, ``EW_DATA`` for a bad kind, scope, count or arg. (Control switched off, answered
    ``EW_FUNC`` before anything else, is the caller's check.)
    """
    try:
        req = InjectFault.decode(payload)
    except PayloadError:
        return EW.LENGTH
    if read_only:
        return EW.PROT
    kind, scope, count, arg = req.kind, req.scope, req.count, req.arg
    if fault_refusal(kind, scope, count, arg) is not None:
        return EW.DATA
    return FaultScope(scope), Fault(FaultKind(kind), arg, count)


def no_faults_cleared(whose: str) -> str:
    """What every front end says of a clear of faults that cleared none (``whose``: ``of this
    machine``, ``on this connection``)."""
    return f"no pending faults {whose}; nothing to clear"


def fault_arg_text(kind: int, arg: int) -> str:
    """A fault's argument as every front end lists it (the command line's ``sim faults``, the
    dashboard): a delay's ``500 ms``, an error's ``EW_BUSY (-1)``, ``-`` for a drop or a split
    (they take none)."""
    if kind == FaultKind.DELAY:
        return f"{arg} ms"
    if kind == FaultKind.ERROR:
        return ew_label(arg)
    return "-"
