"""The simulated CNC: machine state, the packed-protocol adapter, machines built in and from
files. Nothing here touches a socket or an event loop."""

from .default import DEFAULT_NAME, default_machine
from .machine import (
    AUT_MODES,
    DEFAULT_HISTORY_CAPACITY,
    Clock,
    DataItem,
    Machine,
    MachineError,
    MacroRange,
    MotionData,
    Panel,
    PmcAreaSpec,
    Session,
    utc_now,
)
from .machinefile import MachineFileError, load_machine, machine_from_dict
from .packed import error_payload, handle, handled_commands

__all__ = [
    "AUT_MODES",
    "DEFAULT_HISTORY_CAPACITY",
    "DEFAULT_NAME",
    "Clock",
    "DataItem",
    "Machine",
    "MachineError",
    "MachineFileError",
    "MacroRange",
    "MotionData",
    "Panel",
    "PmcAreaSpec",
    "Session",
    "default_machine",
    "error_payload",
    "handle",
    "handled_commands",
    "load_machine",
    "machine_from_dict",
    "utc_now",
]
