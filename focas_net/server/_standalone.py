"""The standalone native FOCAS/2 Ethernet listener (``docs/native-protocol.md``).

The native protocol is served by :class:`focas_net.server.FocasServer`: on every machine's port
(next to the packed protocol, the first four bytes of a connection decide) and, with its
``native_port``, on a port of its own. This module keeps the standalone form: a
:class:`NativeServer` is a ``FocasServer`` serving one machine on one native-only port::

    async with NativeServer(machine, port=0) as native:
        host, port = native.address
        ...

or ``native = await start_native(machine, host, port)`` and later ``await native.aclose()``.
The connection itself is :class:`focas_net.server.NativeConnection`.
"""

from __future__ import annotations

from typing import Final

from focas_net.native import DEFAULT_MAX_BODY, check_server_max_body
from focas_net.sim import Machine

from ._native import NativeConnection
from ._server import FocasServer

__all__ = [
    "DEFAULT_NATIVE_IDLE_TIMEOUT",
    "DEFAULT_NATIVE_MAX_CONNECTIONS",
    "NativeServer",
    "start_native",
]

DEFAULT_NATIVE_MAX_CONNECTIONS: Final = 256
#: Seconds without a complete frame before a connection is closed (0 = never).
DEFAULT_NATIVE_IDLE_TIMEOUT: Final = 300.0
_GRACE: Final = 5.0


class NativeServer:
    """A native FOCAS/2 Ethernet listener for one machine (an async context manager).

    ``machine`` is shared: give a :class:`~focas_net.server.FocasServer` the same instance and
    what one front end writes, the other reads. ``port`` 0 picks an ephemeral port (see
    :attr:`address`). ``version`` overrides the version word of every answer, which the
    machine's control class picks otherwise; ``max_body`` bounds an incoming frame's body,
    checked on its header before any of it is buffered (1450..65535: FANUC's library sends
    request bodies of up to 1450 bytes); ``max_connections`` open connections
    at most (more are closed at once); ``idle_timeout`` seconds without a complete frame close
    a connection (0 = never).
    """

    def __init__(
        self,
        machine: Machine,
        host: str = "127.0.0.1",
        port: int = 0,
        *,
        version: int | None = None,
        max_body: int = DEFAULT_MAX_BODY,
        max_connections: int = DEFAULT_NATIVE_MAX_CONNECTIONS,
        idle_timeout: float = DEFAULT_NATIVE_IDLE_TIMEOUT,
        backlog: int = 128,
    ) -> None:
        if not isinstance(machine, Machine):
            raise TypeError(f"machine must be a Machine, got {machine!r}")
        for name, value in (("version", version), ("max_body", max_body)):
            if isinstance(value, bool) or not isinstance(value, int | None):
                raise TypeError(f"{name} must be an integer, got {value!r}")
        if max_body is None:
            raise TypeError("max_body must be an integer, got None")
        # (FocasServer would name it native_port, and None its two-protocol port)
        if isinstance(port, bool) or not isinstance(port, int):
            raise TypeError(f"port must be an integer, got {port!r}")
        if not 0 <= port <= 0xFFFF:
            raise ValueError(f"port {port} is outside 0..65535 (0: any free port)")
        if version is not None and not 1 <= version <= 0xFFFF:
            raise ValueError(f"version must be within 1..65535, got {version}")
        check_server_max_body(max_body, "max_body")
        self._server = FocasServer(
            machine,
            host=host,
            port=None,
            native_port=port,
            native_version=version,
            native_max_body=max_body,
            max_connections=max_connections,
            idle_timeout=idle_timeout,
            backlog=backlog,
            grace_period=_GRACE,
        )
        (self._listener,) = self._server.listeners
        self.machine = machine
        self.label = machine.name
        self.host = host
        self.port = port
        self.version = version
        self.max_body = max_body
        self.max_connections = max_connections
        self.idle_timeout = float(idle_timeout)
        self.backlog = backlog

    def __repr__(self) -> str:
        return f"<NativeServer {self.label} {self.address_text} {len(self.connections)} conns>"

    @property
    def address(self) -> tuple[str, int]:
        """``(host, port)`` actually bound."""
        return self._listener.address

    @property
    def address_text(self) -> str:
        """``HOST:PORT`` (``[HOST]:PORT`` for IPv6)."""
        return self._listener.address_text

    @property
    def connections(self) -> set[NativeConnection]:
        """Open connections."""
        return self._listener.native_connections

    @property
    def accepting(self) -> bool:
        return self._listener.accepting

    @property
    def accepted(self) -> int:
        return self._listener.native_accepted

    @property
    def refused(self) -> int:
        return self._listener.refused

    @property
    def violations(self) -> int:
        return self._listener.native_violations

    # -- lifecycle -----------------------------------------------------------------------

    async def __aenter__(self) -> NativeServer:
        await self.start()
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.aclose()

    async def start(self) -> None:
        """Bind and start accepting."""
        await self._server.start()

    async def serve_forever(self) -> None:
        """Wait until cancelled."""
        await self._server.serve_forever()

    async def aclose(self, grace_period: float = _GRACE) -> None:
        """Stop accepting, let the connections flush what they were sent and close them
        (aborting any still open after ``grace_period`` seconds)."""
        await self._server.aclose(grace_period)

    def stats(self) -> dict[str, object]:
        """Address, open connections and the counters."""
        return {
            "address": self.address_text,
            "connections": len(self.connections),
            "accepted": self.accepted,
            "refused": self.refused,
            "violations": self.violations,
        }


async def start_native(
    machine: Machine,
    host: str = "127.0.0.1",
    port: int = 0,
    *,
    version: int | None = None,
    max_body: int = DEFAULT_MAX_BODY,
    max_connections: int = DEFAULT_NATIVE_MAX_CONNECTIONS,
    idle_timeout: float = DEFAULT_NATIVE_IDLE_TIMEOUT,
    backlog: int = 128,
) -> NativeServer:
    """Start a :class:`NativeServer` on ``machine`` and return it, listening (the options are
    those of :class:`NativeServer`). Stop it with ``await server.aclose()``."""
    server = NativeServer(
        machine,
        host,
        port,
        version=version,
        max_body=max_body,
        max_connections=max_connections,
        idle_timeout=idle_timeout,
        backlog=backlog,
    )
    await server.start()
    return server
