"""Named values of ODBST fields and of the simulator's fault injection, in one place.

The numbers are FANUC's for the 0i/16i/18i/21i/30i series; the ``label`` of each member is what
the CNC screen shows (``****`` for "nothing").
"""

from __future__ import annotations

import enum

__all__ = [
    "AlarmState",
    "AutMode",
    "EmergencyState",
    "FaultKind",
    "FaultScope",
    "MotionState",
    "MstbState",
    "RunState",
    "label_of",
]


class _Labelled(enum.IntEnum):
    @property
    def label(self) -> str:
        """The text the CNC screen shows for this value."""
        return _LABELS.get((type(self).__name__, self.value), self.name)

    @classmethod
    def parse(cls, value: str | int) -> _Labelled:
        """A member from its name (``"MDI"``), its label, or its number; ValueError otherwise."""
        if isinstance(value, str):
            text = value.strip().upper()
            for member in cls:
                if text in (member.name, member.label.upper()):
                    return member
            if text.lstrip("-").isdigit():
                value = int(text)
            else:
                names = ", ".join(m.name for m in cls)
                raise ValueError(f"unknown {cls.__name__} {value!r} (one of {names})")
        try:
            return cls(value)
        except ValueError:
            raise ValueError(f"unknown {cls.__name__} {value!r}") from None


class AutMode(_Labelled):
    """ODBST ``aut``: the mode selection."""

    MDI = 0
    MEM = 1
    NOSEL = 2  # "****": no selection; not a settable mode
    EDIT = 3
    HND = 4
    JOG = 5
    TJOG = 6  # teach-in JOG
    THND = 7  # teach-in handle
    INC = 8
    REF = 9
    RMT = 10


class RunState(_Labelled):
    """ODBST ``run``: the automatic operation status."""

    RESET = 0
    STOP = 1
    HOLD = 2
    STRT = 3
    MSTR = 4


class MotionState(_Labelled):
    """ODBST ``motion``."""

    NONE = 0
    MTN = 1
    DWL = 2


class MstbState(_Labelled):
    """ODBST ``mstb``: M/S/T/B function status."""

    NONE = 0
    FIN = 1


class EmergencyState(_Labelled):
    """ODBST ``emergency``."""

    NONE = 0
    EMG = 1
    RESET = 2


class AlarmState(_Labelled):
    """ODBST ``alarm`` (30i numbering beyond 2)."""

    NONE = 0
    ALM = 1
    BAT = 2
    FAN = 3
    PS = 4
    FSSB = 5
    INSU = 6
    ENC = 7
    PMC = 8


class FaultKind(enum.IntEnum):
    """``kind`` of the simulator's fault injection (0x0E05)."""

    DELAY = 1  #: answer ``arg`` milliseconds late (other answers may overtake it)
    ERROR = 2  #: answer with EW code ``arg`` instead
    DROP = 3  #: close the connection instead of answering
    SPLIT = 4  #: send the answer one byte per write


class FaultScope(enum.IntEnum):
    """``scope`` of the simulator's fault injection (0x0E05)."""

    CONNECTION = 0  #: the next answers on this connection
    MACHINE = 1  #: the next answers of this machine on any connection (one shared count)


_LABELS: dict[tuple[str, int], str] = {
    ("AutMode", 2): "****",
    ("AutMode", 6): "TJOG",
    ("AutMode", 7): "THND",
    ("RunState", 0): "****",
    ("MotionState", 0): "****",
    ("MstbState", 0): "****",
    ("EmergencyState", 0): "****",
    ("EmergencyState", 2): "RESET",
    ("AlarmState", 0): "****",
}


def label_of(enum_type: type[_Labelled], value: int) -> str:
    """The screen text of ``value`` for ``enum_type``, or the number itself when unknown."""
    try:
        return enum_type(value).label
    except ValueError:
        return str(value)
