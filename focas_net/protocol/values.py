"""Named values of ODBST fields and of the simulator's fault injection, in one place.

The numbers are FANUC's for the 0i/16i/18i/21i/30i series. Every ODBST member carries two
texts: its ``label``, what the CNC screen shows in the status line, and its ``meaning``, a
short description for people. The screen writes "nothing" as asterisks filling the field:
``****`` in the four-character fields (mode, run state, edit state) and ``***`` in the
three-character motion and M/S/T/B fields. The emergency and alarm fields stay blank on the
screen when inactive; their inactive members use ``****`` so that a label is never empty.

This is the one table of those texts: the command line and the dashboard both name a status
through :func:`status_labels` (``tmmode`` by the machine's series, :func:`tmmode_label`).
"""

from __future__ import annotations

import enum
from typing import TYPE_CHECKING, Final, Self

from .._typed import MODE_TYPE

__all__ = [
    "COMPOUND_MT_TYPE",
    "STATUS_FIELDS",
    "AlarmState",
    "AutMode",
    "EditState",
    "EmergencyState",
    "FaultKind",
    "FaultScope",
    "HdckState",
    "LabelledValue",
    "MotionState",
    "MstbState",
    "RunState",
    "TmMode",
    "cnc_type_label",
    "control_type_name",
    "field_label",
    "mt_type_label",
    "status_labels",
    "status_member",
    "tmmode_label",
]


class LabelledValue(enum.IntEnum):
    """An ODBST field value with its screen ``label`` and its ``meaning``.

    Members are written ``NAME = number, label, meaning``; the member's value is the number.
    """

    _value_: int
    label: str
    """The text the CNC screen shows for this value."""
    meaning: str
    """What this value means, in a few words."""

    if TYPE_CHECKING:
        # Calling the class looks a member up by its number (``AutMode(1)``); only the class
        # body passes a label and a meaning, to the constructor below.
        def __new__(cls, value: int) -> Self: ...

    else:

        def __new__(cls, value, label, meaning):
            member = int.__new__(cls, value)
            member._value_ = value
            member.label = label
            member.meaning = meaning
            return member

    @classmethod
    def parse(cls, value: str | int) -> Self:
        """A member from its name (``"MDI"``), its label, or its number; ValueError otherwise."""
        if isinstance(value, bool) or not isinstance(value, str | int):
            raise TypeError(
                f"{cls.__name__} must be a member, its name or its number, got {value!r}"
            )
        if isinstance(value, str):
            # ASCII only, as a CNC's keys: "md\u0131" (a dotless i) upper-cases to MDI but is none
            text = value.strip().upper() if value.isascii() else ""
            for member in cls:
                if text and text in (member.name, member.label.upper()):
                    return member
            if text.lstrip("-").isdigit():  # 0-9, as a CNC's keys
                value = int(text)
            else:
                names = ", ".join(m.name for m in cls)
                raise ValueError(f"unknown {cls.__name__} {value!r} (one of {names})")
        try:
            return cls(value)
        except ValueError:
            raise ValueError(f"unknown {cls.__name__} {value!r}") from None


class AutMode(LabelledValue):
    """ODBST ``aut``: the mode selection."""

    MDI = 0, "MDI", "manual data input"
    MEM = 1, "MEM", "memory (automatic operation)"
    NOSEL = 2, "****", "no selection"  # not a settable mode
    EDIT = 3, "EDIT", "program edit"
    HND = 4, "HND", "manual handle feed"
    JOG = 5, "JOG", "jog feed"
    TJOG = 6, "TJOG", "teach-in jog"
    THND = 7, "THND", "teach-in handle"
    INC = 8, "INC", "incremental feed"
    REF = 9, "REF", "reference position return"
    RMT = 10, "RMT", "remote (DNC) operation"

    @classmethod
    def parse_panel(cls, value: str | int) -> AutMode:
        """A mode the operator panel selects, by name (``"MDI"``), label or number: any but
        NOSEL (2, no selection); ValueError naming the modes it selects otherwise (TypeError
        for what is neither text nor an integer)."""
        if isinstance(value, bool) or not isinstance(value, str | int):
            raise TypeError(f"{MODE_TYPE}, got {value!r}")
        try:
            mode = cls.parse(value)
        except ValueError:
            mode = cls.NOSEL
        if mode is cls.NOSEL:
            modes = ", ".join(m.name for m in cls if m is not cls.NOSEL)
            # a number typed as text is named as the number, as the machine names it
            typed = value.strip() if isinstance(value, str) else ""
            shown = typed if typed.isdigit() else repr(value)
            raise ValueError(f"unknown mode {shown} (one of {modes})")
        return mode


class RunState(LabelledValue):
    """ODBST ``run``: the automatic operation status."""

    RESET = 0, "****", "reset"
    STOP = 1, "STOP", "automatic operation stopped"
    HOLD = 2, "HOLD", "feed hold"
    STRT = 3, "STRT", "cycle start (running)"
    MSTR = 4, "MSTR", "manual numerical command / tool retract and return"


class MotionState(LabelledValue):
    """ODBST ``motion``: axis movement or dwell; 3 (WAIT) on a control of several paths, a path
    waiting at a waiting M code for the others."""

    NONE = 0, "***", "no motion"
    MTN = 1, "MTN", "axis moving"
    DWL = 2, "DWL", "dwell"
    WAIT = 3, "WAIT", "waiting for the other paths (waiting M code)"


class MstbState(LabelledValue):
    """ODBST ``mstb``: M/S/T/B function status."""

    NONE = 0, "***", "no M/S/T/B function"
    FIN = 1, "FIN", "M/S/T/B function waiting for completion (FIN)"


class EmergencyState(LabelledValue):
    """ODBST ``emergency``."""

    NONE = 0, "****", "not in emergency stop"
    EMG = 1, "EMG", "emergency stop"
    RESET = 2, "RESET", "reset signal on"


class AlarmState(LabelledValue):
    """ODBST ``alarm`` (30i numbering beyond 2)."""

    NONE = 0, "****", "no alarm"
    ALM = 1, "ALM", "alarm active"
    BAT = 2, "BAT", "battery low"
    FAN = 3, "FAN", "fan alarm (CNC or servo amplifier)"
    PS = 4, "PS", "PS warning"
    FSSB = 5, "FSSB", "FSSB warning"
    INSU = 6, "INSU", "insulation warning"
    ENC = 7, "ENC", "encoder warning"
    PMC = 8, "PMC", "PMC alarm"


class EditState(LabelledValue):
    """ODBST ``edit``: the program editing status.

    The values common to every series; higher ones differ per series (and model) and have no
    member.
    """

    NONE = 0, "****", "not editing"
    EDIT = 1, "EDIT", "editing"
    SEARCH = 2, "SEARCH", "searching"
    OUTPUT = 3, "OUTPUT", "outputting data"
    INPUT = 4, "INPUT", "inputting data"
    COMPARE = 5, "COMPARE", "comparing data"


class TmMode(LabelledValue):
    """ODBST ``tmmode``: the T/M mode selection of a compound machine."""

    T = 0, "T", "T mode"
    M = 1, "M", "M mode"


class HdckState(LabelledValue):
    """ODBST ``hdck``: the manual handle retrace status."""

    NONE = 0, "****", "manual handle retrace off"
    HDCK = 1, "HDCK", "manual handle retrace on"


#: The ODBST fields in the order every front end lists them, each by the key every front end
#: gives it (the command line, the web page, the gateway), with the enumeration that names its
#: values. The key is the ODBST member's name but for ``mode``, the member ``aut``: the mode
#: selection, as FANUC's operator panel (MODE SELECT) and screens name it, and as ``--mode``
#: sets it.
STATUS_FIELDS: Final[tuple[tuple[str, type[LabelledValue]], ...]] = (
    ("mode", AutMode),
    ("run", RunState),
    ("motion", MotionState),
    ("mstb", MstbState),
    ("emergency", EmergencyState),
    ("alarm", AlarmState),
    ("edit", EditState),
    ("tmmode", TmMode),
    ("hdck", HdckState),
)
#: ODBSYS ``mt_type`` of a compound machine: the one kind whose ``tmmode`` selects T or M.
COMPOUND_MT_TYPE: Final = "MT"


def field_label(values: type[LabelledValue], value: int) -> tuple[str, str]:
    """``(label, meaning)`` of ``value`` of a field named by ``values``; a number without a
    member is shown as itself, ``"unknown value"``."""
    try:
        member = values(value)
    except ValueError:
        return str(value), "unknown value"
    return member.label, member.meaning


def tmmode_label(value: int, mt_type: str | None) -> tuple[str, str]:
    """``(label, meaning)`` of ``tmmode`` as the operator reads it. Only a compound machine
    (ODBSYS ``mt_type`` ``"MT"``) selects T or M; on any other the field is 0 and selects
    nothing, so it names the machine's own series (``"M"``, ``"M series machine (no T/M mode
    selection)"``). ``mt_type`` None (not known) reads the field as a compound machine's."""
    series = None if mt_type is None else mt_type.strip()
    if series is None or series == COMPOUND_MT_TYPE:
        return field_label(TmMode, value)
    series = series[:1]
    if series in ("M", "T"):
        return series, f"{series} series machine (no T/M mode selection)"
    return "-", "no T/M mode selection"


def status_member(field: str) -> str:
    """The ODBST member (and :class:`~focas_net.protocol.StatusInfo` attribute) of the field
    every front end keys ``field``: ``aut`` for ``mode``, any other its own name."""
    return "aut" if field == "mode" else field


def status_labels(status: object, mt_type: str | None = None) -> list[tuple[str, int, str, str]]:
    """``(field, value, label, meaning)`` of every ODBST field of ``status`` (a
    :class:`~focas_net.protocol.StatusInfo`, or any record with the same fields) in
    :data:`STATUS_FIELDS` order; ``tmmode`` named by the machine's ``mt_type``
    (:func:`tmmode_label`)."""
    rows = []
    for name, values in STATUS_FIELDS:
        value = int(getattr(status, status_member(name)))
        if values is TmMode:
            label, meaning = tmmode_label(value, mt_type)
        else:
            label, meaning = field_label(values, value)
        rows.append((name, value, label, meaning))
    return rows


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


# -- ODBSYS: what the control says it is ---------------------------------------------------

#: ODBSYS ``mt_type``, FANUC's machine types, in words.
_MT_TYPES: Final[dict[str, str]] = {
    "M": "machining center (M series)",
    "T": "lathe (T series)",
    "MM": "M series, two paths",
    "TT": "T series, two or three paths",
    "MT": "compound machining (T with M)",
    "P": "punch press",
    "L": "laser",
    "W": "wire cut",
}
#: ODBSYS ``cnc_type`` codes that are no series number (FOCAS's cnc_sysinfo table).
_NAMED_TYPES: Final[dict[str, str]] = {
    "PD": "Power Mate i-D",
    "PH": "Power Mate i-H",
    "PM": "Power Motion i",
}
#: The series FANUC made only as i series (the others, 15 16 18 21, were made with and without).
_I_ONLY: Final = frozenset({"0", "30", "31", "32", "35"})


def cnc_type_label(cnc_type: str) -> str:
    """ODBSYS ``cnc_type`` (stripped) in FOCAS's words: ``Series 0i``, ``Series 31i``,
    ``Series 16/16i``, ``Power Mate i-D``; ``""`` for a code without a name. The command line's
    ``sysinfo`` and the gateway's OPC UA ``CncTypeName`` (:func:`control_type_name`)."""
    if cnc_type.isdigit():
        return f"Series {cnc_type}i" if cnc_type in _I_ONLY else f"Series {cnc_type}/{cnc_type}i"
    return _NAMED_TYPES.get(cnc_type, "")


def mt_type_label(mt_type: str) -> str:
    """ODBSYS ``mt_type`` (stripped) in words; ``""`` for a type without a name."""
    return _MT_TYPES.get(mt_type, "")


def control_type_name(cnc_type: str, mt_type: str) -> str:
    """The control's type as one name, :func:`cnc_type_label`'s with the machine type after a
    series (``Series 31i-T``, ``Series 16/16i-M``, ``Power Mate i-D``); the codes themselves
    for a type without a name."""
    label = cnc_type_label(cnc_type)
    if not label:
        return "-".join(code for code in (cnc_type, mt_type) if code)
    return f"{label}-{mt_type}" if mt_type and label.startswith("Series") else label
