"""The simulated CNC in no protocol's terms: machine state and its operations, the machine built
in and machines from files. Nothing here touches a socket or an event loop, and nothing here
knows either wire protocol: :mod:`focas_net.adapters` translates (``docs/protocol.md``,
``docs/native-protocol.md``)."""

from .default import DEFAULT_NAME, default_machine
from .machine import (
    AUT_MODES,
    DEFAULT_HISTORY_CAPACITY,
    MAX_MACRO_DECIMALS,
    PMC_AREAS,
    POSITION_DECIMALS,
    POSITION_KINDS,
    Alarm,
    Clock,
    DataItem,
    HistoryEntry,
    Identity,
    Machine,
    MachineError,
    MacroRange,
    MotionData,
    Panel,
    ParamKind,
    PmcAreaSpec,
    Session,
    Status,
    utc_now,
)
from .machinefile import MachineFileError, load_machine, machine_from_dict

__all__ = [
    "AUT_MODES",
    "DEFAULT_HISTORY_CAPACITY",
    "DEFAULT_NAME",
    "MAX_MACRO_DECIMALS",
    "PMC_AREAS",
    "POSITION_DECIMALS",
    "POSITION_KINDS",
    "Alarm",
    "Clock",
    "DataItem",
    "HistoryEntry",
    "Identity",
    "Machine",
    "MachineError",
    "MachineFileError",
    "MacroRange",
    "MotionData",
    "Panel",
    "ParamKind",
    "PmcAreaSpec",
    "Session",
    "Status",
    "default_machine",
    "load_machine",
    "machine_from_dict",
    "utc_now",
]
