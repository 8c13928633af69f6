"""focas_net: a simulated FANUC CNC and an asyncio FOCAS client over a packed TCP protocol."""

import logging

from .protocol import (
    EW,
    AccessDeniedError,
    ActiveAlarm,
    AlarmHistoryEntry,
    AlarmType,
    BoardId,
    ChunkedWriteError,
    CncError,
    Command,
    FocasConnectionError,
    FocasError,
    FocasTimeoutError,
    FrameError,
    IOModuleRecord,
    MacroValue,
    OpcUaStatus,
    PayloadError,
    PmcArea,
    ProtocolError,
    StatusInfo,
    SysInfo,
)

__version__ = "0.1.0"

logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = [
    "EW",
    "AccessDeniedError",
    "ActiveAlarm",
    "AlarmHistoryEntry",
    "AlarmType",
    "BoardId",
    "ChunkedWriteError",
    "CncError",
    "Command",
    "FocasConnectionError",
    "FocasError",
    "FocasTimeoutError",
    "FrameError",
    "IOModuleRecord",
    "MacroValue",
    "OpcUaStatus",
    "PayloadError",
    "PmcArea",
    "ProtocolError",
    "StatusInfo",
    "SysInfo",
    "__version__",
]
