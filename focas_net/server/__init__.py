"""The asyncio listener shell of the simulated CNC: listeners, connections, fault injection.

:class:`FocasServer` serves one machine or a fleet, each machine on its own port with its own
state; every port answers both the packed protocol (``docs/protocol.md``) and FANUC's native
FOCAS/2 Ethernet protocol (``docs/native-protocol.md``). The machine logic lives in
:mod:`focas_net.sim` and the native adapter; this package only moves frames.

Modules: ``_server`` (the shell: :class:`FocasServer`, :class:`Listener`, the protocol sniff),
``_base`` (what every connection shares: :class:`Limits`, backpressure, delays, faults,
shutdown), ``_packed`` (:class:`PackedConnection`) and ``_native`` (:class:`NativeConnection`),
``_standalone`` (:class:`NativeServer`, a native-only server of one machine) and :mod:`.faults`
(the fault queues).
"""

from ._base import (
    DEFAULT_MAX_DELAYED,
    DEFAULT_WRITE_BUFFER_HIGH,
    NATIVE_MAGIC_LENGTH,
    BaseConnection,
    Limits,
)
from ._native import NativeConnection, NativeFront
from ._packed import PackedConnection
from ._server import (
    DEFAULT_GRACE_PERIOD,
    DEFAULT_HOST,
    DEFAULT_IDLE_TIMEOUT,
    DEFAULT_MAX_CONNECTIONS,
    DEFAULT_PORT,
    FocasServer,
    Listener,
    ListenError,
)
from ._standalone import (
    DEFAULT_NATIVE_IDLE_TIMEOUT,
    DEFAULT_NATIVE_MAX_CONNECTIONS,
    NativeServer,
    start_native,
)
from .faults import Fault, FaultQueue

__all__ = [
    "DEFAULT_GRACE_PERIOD",
    "DEFAULT_HOST",
    "DEFAULT_IDLE_TIMEOUT",
    "DEFAULT_MAX_CONNECTIONS",
    "DEFAULT_MAX_DELAYED",
    "DEFAULT_NATIVE_IDLE_TIMEOUT",
    "DEFAULT_NATIVE_MAX_CONNECTIONS",
    "DEFAULT_PORT",
    "DEFAULT_WRITE_BUFFER_HIGH",
    "NATIVE_MAGIC_LENGTH",
    "BaseConnection",
    "Fault",
    "FaultQueue",
    "FocasServer",
    "Limits",
    "ListenError",
    "Listener",
    "NativeConnection",
    "NativeFront",
    "NativeServer",
    "PackedConnection",
    "start_native",
]
