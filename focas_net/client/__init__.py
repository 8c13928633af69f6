"""The asyncio client of the packed FOCAS protocol (``docs/client.md``, ``docs/protocol.md``).

Each name below has one home: :mod:`.client` (the packed client), :mod:`._values`
(:class:`Positions`, and the checks and conversions both clients share), :mod:`.reconnect`
(states and the reconnect policy), :mod:`.sim_control` (``client.sim``), :mod:`.connection`
(one pipelined connection), :mod:`.projection` (alarm events), :mod:`.native` (the FOCAS/2
Ethernet client, :class:`NativeClient`; :mod:`._native_files` its program folders'
results, :mod:`._native_offsets` its tool life results, :class:`ToolGroupData`;
:mod:`._native_info` those of its reads of the CNC's information: :class:`SoftwareInfo`,
:class:`PmcTitleInfo`...), :mod:`._started` (:class:`StartedCall`, a read started now and
finished later), :mod:`.many` (:func:`read_status_all`, :func:`read_dynamic_all`: many
clients read from one task),
:mod:`.cnc` (:class:`CncClient`, the calls both clients carry, as a static type).
``FaultKind`` and ``FaultScope``, the arguments of ``client.sim.inject_fault``, are imported
from :mod:`focas_net.protocol` (or :mod:`focas_net`).
"""

from ._native_files import DriveUsage, FolderCounts, FolderEntry, ProgramFileInfo
from ._native_info import (
    EthernetInfo,
    ItemAttributes,
    ItemRange,
    PmcAreaSpan,
    PmcTitleInfo,
    RestartInfo,
    SoftwareInfo,
    SoftwareSlot,
    StatusInfo2,
    ValidFigures,
)
from ._native_modal import CommandValue, GCode, ModalGroup, ModalValue, OperatorMessageText
from ._native_offsets import ToolGroupData
from ._native_spindles import SpindleMeter
from ._started import StartedCall
from ._values import Paths, Positions
from .client import FocasClient
from .cnc import CncClient
from .connection import Connection, NotSentError, open_connection
from .many import read_dynamic_all, read_status_all, read_status_paths_all
from .native import DynamicData, NativeClient, NativeUnsupportedError, ServoLoad
from .projection import (
    AlarmCleared,
    AlarmEvent,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    ProjectionMode,
    alarm_changes,
)
from .reconnect import ClientState, ReconnectPolicy
from .sim_control import PanelSwitches, SimControl

__all__ = [
    "AlarmCleared",
    "AlarmEvent",
    "AlarmHistoryEvent",
    "AlarmProjection",
    "AlarmRaised",
    "ClientState",
    "CncClient",
    "CommandValue",
    "Connection",
    "DriveUsage",
    "DynamicData",
    "EthernetInfo",
    "FocasClient",
    "FolderCounts",
    "FolderEntry",
    "GCode",
    "ItemAttributes",
    "ItemRange",
    "ModalGroup",
    "ModalValue",
    "NativeClient",
    "NativeUnsupportedError",
    "NotSentError",
    "OperatorMessageText",
    "PanelSwitches",
    "Paths",
    "PmcAreaSpan",
    "PmcTitleInfo",
    "Positions",
    "ProgramFileInfo",
    "ProjectionMode",
    "ReconnectPolicy",
    "RestartInfo",
    "ServoLoad",
    "SimControl",
    "SoftwareInfo",
    "SoftwareSlot",
    "SpindleMeter",
    "StartedCall",
    "StatusInfo2",
    "ToolGroupData",
    "ValidFigures",
    "alarm_changes",
    "open_connection",
    "read_dynamic_all",
    "read_status_all",
    "read_status_paths_all",
]
