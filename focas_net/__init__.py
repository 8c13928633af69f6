"""focas_net: a simulated FANUC CNC and an asyncio FOCAS client over a packed TCP protocol.

The names here are the public surface; the subpackages (``focas_net.protocol``,
``focas_net.client``, ``focas_net.server``, ``focas_net.sim``, ``focas_net.adapters``,
``focas_net.native``) and the modules ``focas_net.errors`` and ``focas_net.versamax`` export more
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
    Positions,
    ProjectionMode,
    ReconnectPolicy,
)
from .errors import (
    EW,
    AccessDeniedError,
    ChunkedWriteError,
    CncError,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    FrameError,
    OpcUaStatus,
    PayloadError,
    ProtocolError,
)
from .native import NativeServer, start_native
from .protocol import (
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    AlarmState,
    AlarmType,
    AutMode,
    Command,
    EditState,
    EmergencyState,
    FaultKind,
    FaultScope,
    HdckState,
    MacroValue,
    MotionState,
    MstbState,
    PmcArea,
    PositionKind,
    ProgramNumbers,
    RunState,
    StatusInfo,
    SysInfo,
    TmMode,
)
from .server import FocasServer
from .sim import Machine, MachineError, MachineFileError, default_machine, load_machine
from .versamax import BoardId, IOModuleRecord, RefType

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
    "EditState",
    "EmergencyState",
    "FaultKind",
    "FaultScope",
    "FocasClient",
    "FocasConnectionError",
    "FocasError",
    "FocasServer",
    "FocasTimeoutError",
    "FrameError",
    "HdckState",
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
    "PositionKind",
    "Positions",
    "ProgramNumbers",
    "ProjectionMode",
    "ProtocolError",
    "ReconnectPolicy",
    "RefType",
    "RunState",
    "StatusInfo",
    "SysInfo",
    "TmMode",
    "__version__",
    "default_machine",
    "load_machine",
    "start_native",
]
