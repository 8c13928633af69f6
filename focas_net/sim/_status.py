"""The words of a path's status: the panel's modes, the status (FANUC's ODBST), the panel,
the motion figures and the position and timer kinds (what :mod:`._path` and the front ends'
checks share)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Final

__all__ = [
    "AUT_MODES",
    "EDIT",
    "MDI",
    "MEM",
    "MODE_NAMES",
    "MOTION_NUMBERS",
    "POSITION_DECIMALS",
    "POSITION_KINDS",
    "TIMER_KINDS",
    "MotionData",
    "Panel",
    "Status",
    "mode_name",
    "panel_conflict",
    "panel_mode",
    "switch_unfit",
    "unknown_mode",
]

#: The panel's modes by name (``aut`` values of ``cnc_statinfo``: 6 and 7 are teach-in JOG and
#: HND; 2 is no mode).
MODE_NAMES: Final[dict[str, int]] = {
    "MDI": 0,
    "MEM": 1,
    "EDIT": 3,
    "HND": 4,
    "JOG": 5,
    "TJOG": 6,
    "THND": 7,
    "INC": 8,
    "REF": 9,
    "RMT": 10,
}
#: The ``aut`` values a panel selects.
AUT_MODES: Final = frozenset(MODE_NAMES.values())


def unknown_mode(given: object) -> str:
    """The words for a panel mode the panel does not select, alike on every front end."""
    return f"unknown mode {given!r} (one of {', '.join(MODE_NAMES)})"


#: A panel mode typed as its number: ASCII digits, a minus sign before them at most.
_DIGITS: Final = re.compile(r"-?[0-9]+")


def panel_mode(given: int | str) -> int:
    """The ``aut`` value of a panel mode given by number or by name (``"MDI"``, ASCII letters
    in any case, spaces around it), or by its number as text (``"5"``, ASCII digits, as a
    CNC's keys and as every front end reads it); ValueError in :func:`unknown_mode`'s words
    for a name it has not (a number is the panel's to check)."""
    if isinstance(given, str):
        word = given.strip().upper() if given.isascii() else ""  # (ASCII letters only)
        value = MODE_NAMES.get(word)
        if value is None and _DIGITS.fullmatch(word):
            return int(word)
        if value is None:
            raise ValueError(unknown_mode(given))
        return value
    return given


def switch_unfit(name: str, given: object) -> str:
    """The words for a panel switch (``pwe``, ``emergency``) that is neither on nor off."""
    return f"{name} must be True, False or None (unchanged), got {given!r}"


def mode_name(aut: int) -> str:
    """The name of panel mode ``aut`` (``"EDIT"``), or its number when it has none."""
    return next((name for name, value in MODE_NAMES.items() if value == aut), str(aut))


MDI: Final = 0
MEM: Final = 1
EDIT: Final = 3
#: The run states (ODBST ``run``) by number, as the status shows them.
RUN_NAMES: Final = ("reset", "STOP", "HOLD", "STRT", "MSTR")
#: The modes a cycle runs in (STRT): memory, MDI and remote (DNC) operation.
_CYCLE_MODES: Final = frozenset({MDI, MEM, MODE_NAMES["RMT"]})


def panel_conflict(mode: int, emergency: int, run: int) -> str | None:
    """Why no CNC shows run state ``run`` with panel ``mode`` and ``emergency`` (None: it
    may): a cycle runs (STRT) in MEM, MDI or RMT only, and an emergency stop resets the CNC."""
    name = f"{run} ({RUN_NAMES[run]})" if run in range(len(RUN_NAMES)) else str(run)
    if emergency and run != 0:
        return f"{name} cannot be with emergency = true: an emergency stop resets the CNC (run 0)"
    if run == 3 and mode not in _CYCLE_MODES:
        return f"{name} cannot be with mode {mode_name(mode)}: a cycle runs in MEM, MDI or RMT"
    return None


#: Decimals of the least input increment of the positions (0.001 mm, IS-B).
POSITION_DECIMALS: Final = 3
#: The position kinds :meth:`Machine.positions` serves (``"skip"`` answers EW_NOOPT).
POSITION_KINDS: Final = ("absolute", "machine", "relative", "distance_to_go")
#: The timers :meth:`Machine.timer` reads, by FANUC's ``cnc_rdtimer`` type number.
TIMER_KINDS: Final = ("power_on", "operating", "cutting", "cycle")


@dataclass(frozen=True, slots=True)
class Status:
    """The status of the CNC (FANUC's ODBST fields), derived from the panel and the alarms."""

    hdck: int
    tmmode: int
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int


@dataclass(slots=True)
class Panel:
    """The operator panel and the run state shown by the status."""

    mode: int = MEM
    pwe: int = 0
    emergency: int = 0
    run: int = 0
    motion: int = 0
    mstb: int = 0
    edit: int = 0
    hdck: int = 0
    tmmode: int = 0


#: The bounds of each motion figure that is one number: a program number is FANUC's four digits
#: (O1..O9999) and a sequence number its five (N1..N99999), 0 for none, as a program's own O
#: and N words are read; feed and spindle speed are unsigned 32-bit figures.
MOTION_NUMBERS: Final = {
    "feed": (0, 0x7FFFFFFF),
    "spindle_speed": (0, 0x7FFFFFFF),
    "program_running": (0, 9999),
    "program_main": (0, 9999),
    "sequence": (0, 99999),
}


@dataclass(slots=True)
class MotionData:
    """Motion figures: positions per axis in least input increments (:data:`POSITION_DECIMALS`
    decimals), actual feed, spindle speed, program numbers and the sequence number."""

    absolute: list[int]
    machine: list[int]
    relative: list[int]
    distance_to_go: list[int]
    feed: int = 0
    spindle_speed: int = 0
    program_running: int = 0
    program_main: int = 0
    sequence: int = 0
