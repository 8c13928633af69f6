"""The native FOCAS/2 Ethernet listener: FANUC's own protocol in front of a simulated machine.

:class:`NativeServer` is a plain :class:`asyncio.Protocol` listener (no task per connection or
per request) around a :class:`~focas_net.adapters.native.NativeAdapter`::

    async with NativeServer(machine, port=0) as native:
        host, port = native.address
        ...

or, next to the packed server on the same machine, ``native = await start_native(machine,
host, port)`` and later ``await native.aclose()``.

Per connection: an open request (``0x0101``) is answered with an open response; data requests
(``0x2101``) are answered block for block, each answer in one ``transport.write``; a close
request (``0x0201``) is answered and the connection closed. A framing violation (bad magic, a
body longer than ``max_body``, a broken block list, a data request before the open, a frame type
not served) closes that connection only and is logged at WARNING with the peer's address.
"""

from __future__ import annotations

import asyncio
import logging
import math
from typing import TYPE_CHECKING, Final

from focas_net.adapters.native import NativeAdapter

from .codec import (
    DEFAULT_MAX_BODY,
    DEFAULT_SERVER_VERSION,
    FrameType,
    NativeFrameDecoder,
    NativeFrameError,
    OpenRequest,
    encode_close_response,
    encode_open_response,
)

if TYPE_CHECKING:
    from focas_net.sim import Machine

__all__ = [
    "DEFAULT_NATIVE_IDLE_TIMEOUT",
    "DEFAULT_NATIVE_MAX_CONNECTIONS",
    "NativeConnection",
    "NativeServer",
    "start_native",
]

logger = logging.getLogger(__name__)

DEFAULT_NATIVE_MAX_CONNECTIONS: Final = 256
#: Seconds without a complete frame before a connection is closed (0 = never).
DEFAULT_NATIVE_IDLE_TIMEOUT: Final = 300.0
_WRITE_BUFFER_HIGH: Final = 64 * 1024
_SWEEPS_PER_TIMEOUT: Final = 4
_GRACE: Final = 5.0


class NativeConnection(asyncio.Protocol):
    """One native connection: frames in, answers out."""

    __slots__ = (
        "_closing",
        "_decoder",
        "_opened",
        "_server",
        "_transport",
        "last_active",
        "peer",
    )

    def __init__(self, server: NativeServer) -> None:
        self._server = server
        self._decoder = NativeFrameDecoder(server.max_body)
        self._transport: asyncio.Transport | None = None
        self._opened = False
        self._closing = False
        self.peer = "?"
        self.last_active = 0.0

    # -- asyncio.Protocol ----------------------------------------------------------------

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self._transport = transport
        peer = transport.get_extra_info("peername")
        if peer:
            self.peer = f"[{peer[0]}]:{peer[1]}" if ":" in str(peer[0]) else f"{peer[0]}:{peer[1]}"
        server = self._server
        if not server.accepting or len(server.connections) >= server.max_connections:
            server.refused += 1
            logger.warning(
                "native %s: connection from %s refused (%d open, limit %d)",
                server.label,
                self.peer,
                len(server.connections),
                server.max_connections,
            )
            self._closing = True
            transport.abort()
            return
        server.accepted += 1
        server.connections.add(self)
        self.last_active = server.now()
        transport.set_write_buffer_limits(high=_WRITE_BUFFER_HIGH)
        logger.debug("native %s: connection from %s", server.label, self.peer)

    def connection_lost(self, exc: Exception | None) -> None:
        self._closing = True
        server = self._server
        if self in server.connections:
            server.connections.discard(self)
            logger.debug("native %s: %s disconnected (%s)", server.label, self.peer, exc)
            server._connection_done()

    def pause_writing(self) -> None:
        # The peer does not read its answers: stop reading its requests until it does.
        if self._transport is not None and not self._closing:
            self._transport.pause_reading()

    def resume_writing(self) -> None:
        if self._transport is not None and not self._closing:
            self._transport.resume_reading()

    def eof_received(self) -> bool:
        return False  # close our side too (pyfocas never sends a close request)

    def data_received(self, data: bytes) -> None:
        if self._closing:
            return
        if logger.isEnabledFor(logging.DEBUG):
            logger.debug("native %s: %s >> %s", self._server.label, self.peer, data.hex(" "))
        try:
            frames = self._decoder.feed(data)
        except NativeFrameError as exc:
            self._violation(str(exc))
            return
        if not frames:
            return
        server = self._server
        self.last_active = server.now()
        transport = self._transport
        assert transport is not None
        for version, frame_type, body in frames:
            if frame_type == FrameType.DATA_REQUEST:
                if not self._opened:
                    self._violation("data request before the open request")
                    return
                try:
                    answer = server.adapter.answer(body)
                except NativeFrameError as exc:
                    self._violation(str(exc))
                    return
                self._write(transport, answer)
            elif frame_type == FrameType.OPEN_REQUEST:
                try:
                    OpenRequest.decode(body)
                except NativeFrameError as exc:
                    self._violation(str(exc))
                    return
                self._opened = True
                self._write(transport, server.open_response)
            elif frame_type == FrameType.CLOSE_REQUEST:
                self._write(transport, server.close_response)
                self._closing = True
                transport.close()
                return
            else:
                self._violation(f"frame type 0x{frame_type:04X} (version {version}) not served")
                return

    # -- helpers -------------------------------------------------------------------------

    def _write(self, transport: asyncio.Transport, answer: bytes) -> None:
        if logger.isEnabledFor(logging.DEBUG):
            logger.debug("native %s: %s << %s", self._server.label, self.peer, answer.hex(" "))
        transport.write(answer)

    def _violation(self, reason: str) -> None:
        server = self._server
        server.violations += 1
        logger.warning(
            "native %s: closing the connection from %s: %s", server.label, self.peer, reason
        )
        self._closing = True
        if self._transport is not None:
            self._transport.abort()

    def close(self) -> None:
        """Close after the answers already written are sent."""
        self._closing = True
        if self._transport is not None:
            self._transport.close()

    def abort(self) -> None:
        """Close at once, dropping unsent output."""
        self._closing = True
        if self._transport is not None:
            self._transport.abort()


class NativeServer:
    """A native FOCAS/2 Ethernet listener for one machine (an async context manager).

    ``machine`` is shared: give the packed server the same instance and what one front end
    writes, the other reads. ``port`` 0 picks an ephemeral port (see :attr:`address`).
    ``version`` is the version word of every answer (2 keeps answers within 1450 bytes);
    ``max_body`` bounds an incoming frame's body, checked on its header before any of it is
    buffered; ``max_connections`` open connections at most (more are closed at once);
    ``idle_timeout`` seconds without a complete frame close a connection (0 = never).
    """

    def __init__(
        self,
        machine: Machine,
        host: str = "127.0.0.1",
        port: int = 0,
        *,
        version: int = DEFAULT_SERVER_VERSION,
        max_body: int = DEFAULT_MAX_BODY,
        max_connections: int = DEFAULT_NATIVE_MAX_CONNECTIONS,
        idle_timeout: float = DEFAULT_NATIVE_IDLE_TIMEOUT,
        backlog: int = 128,
    ) -> None:
        if not 0 <= port <= 65_535:
            raise ValueError(f"port {port} outside 0..65535")
        if not 1 <= version <= 0xFFFF:
            raise ValueError(f"version must be within 1..65535, got {version}")
        if not 0 <= max_body <= 0xFFFF:
            raise ValueError(f"max_body must be within 0..65535, got {max_body}")
        if max_connections < 1:
            raise ValueError(f"max_connections must be at least 1, got {max_connections}")
        if idle_timeout < 0 or math.isnan(idle_timeout):
            raise ValueError(f"idle_timeout must be >= 0, got {idle_timeout}")
        self.machine = machine
        self.label = machine.name
        self.host = host
        self.port = port
        self.max_body = max_body
        self.max_connections = max_connections
        self.idle_timeout = float(idle_timeout)
        self.backlog = backlog
        self.adapter = NativeAdapter(machine, version=version)
        self.open_response = encode_open_response(version=version)
        self.close_response = encode_close_response(version=version)
        #: Open connections.
        self.connections: set[NativeConnection] = set()
        #: Counters: connections accepted, refused by the limit, closed for violations.
        self.accepted = 0
        self.refused = 0
        self.violations = 0
        self.accepting = False
        #: ``(host, port)`` actually bound.
        self.address: tuple[str, int] = ("", 0)
        self._aserver: asyncio.Server | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._sweeper: asyncio.TimerHandle | None = None
        self._all_closed: asyncio.Event | None = None
        self._closed = False

    def __repr__(self) -> str:
        return f"<NativeServer {self.label} {self.address_text} {len(self.connections)} conns>"

    @property
    def address_text(self) -> str:
        """``HOST:PORT`` (``[HOST]:PORT`` for IPv6)."""
        host, port = self.address
        return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"

    def now(self) -> float:
        loop = self._loop
        return loop.time() if loop is not None else 0.0

    # -- lifecycle -----------------------------------------------------------------------

    async def __aenter__(self) -> NativeServer:
        await self.start()
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.aclose()

    async def start(self) -> None:
        """Bind and start accepting."""
        if self._loop is not None:
            raise RuntimeError("NativeServer already started")
        loop = self._loop = asyncio.get_running_loop()
        self._aserver = await loop.create_server(
            lambda: NativeConnection(self),
            self.host,
            self.port,
            backlog=self.backlog,
            start_serving=True,
        )
        sockname = self._aserver.sockets[0].getsockname()
        self.address = (str(sockname[0]), int(sockname[1]))
        self.accepting = True
        if self.idle_timeout > 0:
            self._schedule_sweep()
        logger.info("%s: native FOCAS/2 listening on %s", self.label, self.address_text)

    async def serve_forever(self) -> None:
        """Wait until cancelled."""
        if self._aserver is None:
            raise RuntimeError("NativeServer not started")
        await asyncio.Event().wait()

    async def aclose(self, grace_period: float = _GRACE) -> None:
        """Stop accepting, let the connections flush what they were sent and close them
        (aborting any still open after ``grace_period`` seconds)."""
        if self._closed:
            return
        self._closed = True
        self.accepting = False
        if self._sweeper is not None:
            self._sweeper.cancel()
            self._sweeper = None
        aserver = self._aserver
        if aserver is None:
            return
        aserver.close()
        self._all_closed = asyncio.Event()
        for conn in list(self.connections):
            conn.close()
        if self.connections:
            try:
                await asyncio.wait_for(asyncio.shield(self._all_closed.wait()), grace_period)
            except TimeoutError:
                for conn in list(self.connections):
                    conn.abort()
        await asyncio.sleep(0)
        await aserver.wait_closed()
        self._aserver = None
        logger.info("%s: native FOCAS/2 listener closed", self.label)

    def _connection_done(self) -> None:
        if self._all_closed is not None and not self.connections:
            self._all_closed.set()

    # -- idle sweep ----------------------------------------------------------------------

    def _schedule_sweep(self) -> None:
        assert self._loop is not None
        self._sweeper = self._loop.call_later(self.idle_timeout / _SWEEPS_PER_TIMEOUT, self._sweep)

    def _sweep(self) -> None:
        limit = self.now() - self.idle_timeout
        for conn in [c for c in self.connections if c.last_active < limit]:
            logger.info(
                "native %s: closing the connection from %s: idle for %g s",
                self.label,
                conn.peer,
                self.idle_timeout,
            )
            conn.abort()
        self._schedule_sweep()

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
    version: int = DEFAULT_SERVER_VERSION,
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
