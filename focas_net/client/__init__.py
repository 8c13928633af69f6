"""The asyncio client of the packed FOCAS protocol."""

from .client import (
    ClientState,
    FaultKind,
    FaultScope,
    FocasClient,
    Positions,
    ReconnectPolicy,
    SimControl,
)
from .connection import Connection, NotSentError, open_connection
from .projection import (
    AlarmCleared,
    AlarmEvent,
    AlarmHistoryEvent,
    AlarmProjection,
    AlarmRaised,
    ProjectionMode,
)

__all__ = [
    "AlarmCleared",
    "AlarmEvent",
    "AlarmHistoryEvent",
    "AlarmProjection",
    "AlarmRaised",
    "ClientState",
    "Connection",
    "FaultKind",
    "FaultScope",
    "FocasClient",
    "NotSentError",
    "Positions",
    "ProjectionMode",
    "ReconnectPolicy",
    "SimControl",
    "open_connection",
]
