"""Alarms of the part-program interpreter: FANUC's numbers and the record one carries.

Numbers follow FANUC's program-error (PS), overtravel (OT) and macro (MC) tables of the
Series 0i/16i/30i operator's manuals. Where the public tables do not say which number a case
raises, the choice is marked *inferred* in :data:`ALARM_MESSAGES`' comments and in the package
docstring.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from typing import Final

__all__ = [
    "ALARM_MESSAGES",
    "AlarmKind",
    "NcAlarm",
    "ProgramError",
    "ProgramErrorReason",
]


class AlarmKind(Enum):
    """The alarm type a CNC shows before the number."""

    PS = "PS"  #: program error
    OT = "OT"  #: overtravel
    MC = "MC"  #: macro alarm raised by ``#3000 = n``


#: Message of each PS and OT alarm the interpreter raises, keyed by (kind, number).
ALARM_MESSAGES: Final[dict[tuple[AlarmKind, int], str]] = {
    (AlarmKind.PS, 3): "TOO MANY DIGITS",
    (AlarmKind.PS, 4): "ADDRESS NOT FOUND",
    (AlarmKind.PS, 5): "NO DATA AFTER ADDRESS",
    (AlarmKind.PS, 6): "ILLEGAL USE OF NEGATIVE SIGN",
    (AlarmKind.PS, 7): "ILLEGAL USE OF DECIMAL POINT",
    (AlarmKind.PS, 9): "ILLEGAL ADDRESS INPUT",
    (AlarmKind.PS, 10): "IMPROPER G-CODE",
    (AlarmKind.PS, 11): "FEED ZERO (COMMAND FEED)",
    (AlarmKind.PS, 20): "OVER TOLERANCE OF RADIUS",  # also R smaller than half the chord: inferred
    (AlarmKind.PS, 21): "ILLEGAL PLANE SELECTED",
    (AlarmKind.PS, 22): "R OR I,J,K COMMAND NOT FOUND",
    (AlarmKind.PS, 30): "ILLEGAL OFFSET NUMBER",
    (AlarmKind.PS, 76): "ADDRESS P NOT DEFINED",
    (AlarmKind.PS, 77): "SUB PROGRAM NESTING ERROR",
    (AlarmKind.PS, 78): "NUMBER NOT FOUND",
    (AlarmKind.PS, 111): "CALCULATED DATA OVERFLOW",
    (AlarmKind.PS, 112): "DIVIDED BY ZERO",
    (AlarmKind.PS, 114): "FORMAT ERROR IN MACRO",
    (AlarmKind.PS, 115): "ILLEGAL VARIABLE NUMBER",
    (AlarmKind.PS, 116): "WRITE PROTECTED VARIABLE",
    (AlarmKind.PS, 118): "PARENTHESIS NESTING ERROR",
    (AlarmKind.PS, 119): "ILLEGAL ARGUMENT",
    (AlarmKind.PS, 124): "MISSING END STATEMENT",
    (AlarmKind.PS, 126): "ILLEGAL LOOP NUMBER",
    (AlarmKind.PS, 127): "NC, MACRO STATEMENT IN SAME BLOCK",
    (AlarmKind.PS, 128): "ILLEGAL MACRO SEQUENCE NUMBER",
    (AlarmKind.PS, 160): "MISMATCH WAITING M-CODE",
    (AlarmKind.PS, 161): "ILLEGAL P OF WAITING M-CODE",
    (AlarmKind.PS, 5074): "ADDRESS DUPLICATION ERROR",  # also two M codes: one M a block
    (AlarmKind.OT, 500): "+ OVERTRAVEL ( SOFT 1 )",
    (AlarmKind.OT, 501): "- OVERTRAVEL ( SOFT 1 )",
}


@dataclass(frozen=True, slots=True)
class NcAlarm:
    """One alarm: its kind and number, the message a CNC shows, where it happened (program
    number and the sequence number last read, ``None`` when there was none), the axis
    (1-based) of an overtravel, and the detail that names what the program said."""

    kind: AlarmKind
    number: int
    message: str
    program: int | None = None
    sequence: int | None = None
    axis: int | None = None
    detail: str = ""

    @property
    def code(self) -> str:
        """``PS0010``, ``OT0500``, ``MC3001``: the kind and four digits."""
        return f"{self.kind.value}{self.number:04d}"

    def __str__(self) -> str:
        sequence = "" if self.sequence is None else f" N{self.sequence}"
        where = f" (O{self.program:04d}{sequence})" if self.program is not None else ""
        detail = f": {self.detail}" if self.detail else ""
        return f"{self.code} {self.message}{where}{detail}"


class ProgramErrorReason(Enum):
    """Why the program store refused an edit."""

    FORMAT = "format"  #: the text is not one O-number program
    RANGE = "range"  #: program number outside the store's range (FANUC PS0074)
    DUPLICATE = "duplicate"  #: the number is already stored (PS0073)
    NOT_FOUND = "not_found"  #: no program of that number (PS0071 on a search)
    IN_USE = "in_use"  #: the program is being executed
    NO_SPACE = "no_space"  #: the store's character capacity is exceeded (PS0070)
    TOO_MANY = "too_many"  #: the store holds its maximum number of programs (PS0072)


#: FANUC's alarm number for each refusal of the store, where it has one.
_REASON_ALARMS: Final = {
    ProgramErrorReason.RANGE: 74,
    ProgramErrorReason.DUPLICATE: 73,
    ProgramErrorReason.NOT_FOUND: 71,
    ProgramErrorReason.NO_SPACE: 70,
    ProgramErrorReason.TOO_MANY: 72,
}


class ProgramError(ValueError):
    """The program store refused an edit; ``reason`` says why, ``number`` is the program
    number concerned (``None`` when the text had none) and ``alarm`` FANUC's PS number for
    the same refusal at the control's panel (``None`` when it has none)."""

    def __init__(self, reason: ProgramErrorReason, message: str, number: int | None = None):
        super().__init__(message)
        self.reason = reason
        self.number = number
        self.alarm: int | None = _REASON_ALARMS.get(reason)


class AlarmRaised(Exception):
    """Internal: carries an alarm out of the evaluation of one block."""

    def __init__(self, number: int, detail: str = "", kind: AlarmKind = AlarmKind.PS) -> None:
        super().__init__(detail)
        self.kind = kind
        self.number = number
        self.detail = detail


def number_text(value: float) -> str:
    """A value in an alarm's detail as a CNC's screen writes a number: plain decimals, no
    exponent and no trailing zeros (``99999999``, ``-1234.5678``, ``90``), never Python's
    ``1e+08`` or ``90.0``; an absurdly long one is cut short with ``...``."""
    text = f"{value:.10f}".rstrip("0").rstrip(".")
    text = "0" if text in ("", "-0") else text
    return text if len(text) <= 24 else text[:21] + "..."


def word_text(address: str, value: float, literal: bool) -> str:
    """A word of a block as a CNC's screen writes it: ``X10.`` for a value with a decimal
    point (``literal`` False), ``X10`` for increments without one, ``P1000``."""
    text = number_text(value)
    return f"{address}{text}" if literal or "." in text else f"{address}{text}."
