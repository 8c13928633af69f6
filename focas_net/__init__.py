"""focas_net: a simulated FANUC CNC and an asyncio FOCAS client over a packed TCP protocol.

The names here are the public surface; the subpackages (``focas_net.protocol``,
``focas_net.client``, ``focas_net.server``, ``focas_net.sim``, ``focas_net.native``) export more
for those who need it.
"""

import logging

from .client import (
    AlarmCleared,
    AlarmEvent,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    ClientState,
    FocasClient,
    NotSentError,
    ProjectionMode,
    ReconnectPolicy,
)
from .native import NativeServer, start_native
from .protocol import (
    EW,
    AccessDeniedError,
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmState,
    AlarmType,
    AutMode,
    BoardId,
    ChunkedWriteError,
    CncError,
    Command,
    EmergencyState,
    FaultKind,
    FaultScope,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    FrameError,
    IOModuleRecord,
    MacroValue,
    MotionState,
    MstbState,
    OpcUaStatus,
    PayloadError,
    PmcArea,
    ProtocolError,
    RefType,
    RunState,
    StatusInfo,
    SysInfo,
)
from .server import FocasServer
from .sim import Machine, MachineError, MachineFileError, default_machine, load_machine

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "EW",
    "AccessDeniedError",
    "ActiveAlarm",
    "AlarmCleared",
    "AlarmEvent",
    "AlarmHistory",
    "AlarmHistoryEntry",
    "AlarmHistoryEvent",
    "AlarmProjection",
    "AlarmRaised",
    "AlarmState",
    "AlarmType",
    "AutMode",
    "BoardId",
    "ChunkedWriteError",
    "ClientState",
    "CncError",
    "Command",
    "EmergencyState",
    "FaultKind",
    "FaultScope",
    "FocasClient",
    "FocasConnectionError",
    "FocasError",
    "FocasServer",
    "FocasTimeoutError",
    "FrameError",
    "IOModuleRecord",
    "Machine",
    "MachineError",
    "MachineFileError",
    "MacroValue",
    "MotionState",
    "MstbState",
    "NativeServer",
    "NotSentError",
    "OpcUaStatus",
    "PayloadError",
    "PmcArea",
    "ProjectionMode",
    "ProtocolError",
    "ReconnectPolicy",
    "RefType",
    "RunState",
    "StatusInfo",
    "SysInfo",
    "__version__",
    "default_machine",
    "load_machine",
    "start_native",
]
