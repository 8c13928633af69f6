"""The asyncio shell of the simulated CNC: listeners, connections, fault injection.

:class:`FocasServer` serves one machine or a fleet, each machine on its own port with its own
state. The machine logic lives in :mod:`focas_net.sim`; this package only moves frames.
"""

from ._connection import Connection
from ._server import (
    DEFAULT_GRACE_PERIOD,
    DEFAULT_HOST,
    DEFAULT_IDLE_TIMEOUT,
    DEFAULT_MAX_CONNECTIONS,
    DEFAULT_MAX_DELAYED,
    DEFAULT_PORT,
    DEFAULT_WRITE_BUFFER_HIGH,
    FocasServer,
    Listener,
)
from .faults import Fault, FaultKind, FaultQueue, FaultScope

__all__ = [
    "DEFAULT_GRACE_PERIOD",
    "DEFAULT_HOST",
    "DEFAULT_IDLE_TIMEOUT",
    "DEFAULT_MAX_CONNECTIONS",
    "DEFAULT_MAX_DELAYED",
    "DEFAULT_PORT",
    "DEFAULT_WRITE_BUFFER_HIGH",
    "Connection",
    "Fault",
    "FaultKind",
    "FaultQueue",
    "FaultScope",
    "FocasServer",
    "Listener",
]
