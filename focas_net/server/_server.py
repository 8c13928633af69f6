"""``FocasServer``: the listeners of one or more simulated machines.

One :class:`FocasServer` serves a fleet: each machine gets its own listening port and keeps its
own state; nothing is global. The server is an async context manager::

    async with FocasServer(default_machine(), port=0) as server:
        host, port = server.listeners[0].address
        await server.serve_forever()

It runs on asyncio (uvloop works too); anyio gives the structure (cancel scopes, timeouts) and
the per-frame path stays a plain :class:`asyncio.Protocol` (see ``_connection.py``).
"""

from __future__ import annotations

import asyncio
import logging
import math
import ssl as _ssl
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, Final

import anyio
import anyio.lowlevel

from focas_net.adapters import PackedAdapter
from focas_net.protocol import DEFAULT_MAX_FRAME
from focas_net.sim import Machine

from ._connection import Connection

if TYPE_CHECKING:
    from focas_net.native import NativeServer
from .faults import FaultQueue

__all__ = [
    "DEFAULT_GRACE_PERIOD",
    "DEFAULT_HOST",
    "DEFAULT_IDLE_TIMEOUT",
    "DEFAULT_MAX_CONNECTIONS",
    "DEFAULT_MAX_DELAYED",
    "DEFAULT_PORT",
    "DEFAULT_WRITE_BUFFER_HIGH",
    "FocasServer",
    "Listener",
]

_log = logging.getLogger("focas_net.server")

#: Loopback only unless told otherwise.
DEFAULT_HOST: Final = "127.0.0.1"
#: The FOCAS/2 Ethernet port.
DEFAULT_PORT: Final = 8193
DEFAULT_MAX_CONNECTIONS: Final = 256
#: Seconds without a complete request before a connection is closed (0 = never).
DEFAULT_IDLE_TIMEOUT: Final = 300.0
#: Delayed answers one connection may hold before the server stops reading from it.
DEFAULT_MAX_DELAYED: Final = 1024
#: High-water mark of each connection's write buffer; above it the server stops reading.
DEFAULT_WRITE_BUFFER_HIGH: Final = 64 * 1024
#: Seconds a graceful shutdown waits for delayed answers and unsent output.
DEFAULT_GRACE_PERIOD: Final = 5.0

#: The idle timeout is checked this many times per timeout period.
_SWEEPS_PER_TIMEOUT: Final = 4


class Listener:
    """One machine's listening socket and its connections."""

    __slots__ = (
        "_aserver",
        "accepted",
        "accepting",
        "adapter",
        "address",
        "connections",
        "faults",
        "label",
        "machine",
        "native",
        "refused",
        "server",
        "violations",
    )

    def __init__(self, server: FocasServer, machine: Machine) -> None:
        self.server = server
        self.machine = machine
        #: Answers the machine's requests (its answer caches are shared by the connections).
        self.adapter = PackedAdapter(machine)
        self.label = machine.name
        #: Open connections.
        self.connections: set[Connection] = set()
        #: Machine-wide faults (scope 1), one shared count.
        self.faults = FaultQueue()
        self.accepting = True
        #: ``(host, port)`` actually bound (port resolved when 0 was asked).
        self.address: tuple[str, int] = ("", 0)
        #: Counters: connections accepted, refused by the limit, closed for framing violations.
        self.accepted = 0
        self.refused = 0
        self.violations = 0
        self._aserver: asyncio.Server | None = None
        #: The native FOCAS/2 listener on the same machine, when the server has one.
        self.native: NativeServer | None = None

    @property
    def host(self) -> str:
        return self.address[0]

    @property
    def port(self) -> int:
        return self.address[1]

    def __repr__(self) -> str:
        return f"<Listener {self.label} {self.address_text} {len(self.connections)} conns>"

    @property
    def address_text(self) -> str:
        """``HOST:PORT`` (``[HOST]:PORT`` for IPv6)."""
        host, port = self.address
        return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def _machines(machines: Machine | Iterable[Machine] | None) -> list[Machine]:
    if machines is None:
        from focas_net.sim import default_machine

        return [default_machine()]
    if isinstance(machines, Machine):
        return [machines]
    result = list(machines)
    if not result:
        raise ValueError("FocasServer needs at least one machine")
    return result


class FocasServer:
    """Serve simulated machines over the packed protocol, one listening port per machine.

    ``machines`` is a machine, several (a fleet), or None for the default machine. With
    ``port`` 0 every machine gets an ephemeral port; otherwise machine *i* listens on
    ``port + i``, or on ``ports[i]`` when ``ports`` is given.

    Limits: ``max_frame`` (a longer or shorter length prefix closes that connection),
    ``max_connections`` per machine (extra connections are closed at once and logged),
    ``idle_timeout`` seconds without a complete request (0 = never), ``max_delayed`` delayed
    answers per connection and ``write_buffer_high`` bytes of unsent output before reading
    from that connection stops. ``ssl`` serves TLS. ``grace_period`` bounds the graceful
    shutdown of :meth:`aclose` (``async with`` exit).

    ``read_only`` and ``control``, when given, set those switches of every machine served
    (``Machine.read_only``: every write answers EW_PROT; ``Machine.control_enabled``: simulator
    control on or off); None leaves each machine as it is.

    ``native_port`` (None = off) adds, for each machine, a listener speaking FANUC's native
    FOCAS/2 Ethernet protocol on the same machine state (see ``docs/native-protocol.md``):
    machine *i* on ``native_port + i``, or an ephemeral port for each when it is 0.
    """

    def __init__(
        self,
        machines: Machine | Iterable[Machine] | None = None,
        *,
        host: str = DEFAULT_HOST,
        port: int = DEFAULT_PORT,
        ports: Sequence[int] | None = None,
        ssl: _ssl.SSLContext | None = None,
        max_frame: int = DEFAULT_MAX_FRAME,
        max_connections: int = DEFAULT_MAX_CONNECTIONS,
        idle_timeout: float = DEFAULT_IDLE_TIMEOUT,
        max_delayed: int = DEFAULT_MAX_DELAYED,
        write_buffer_high: int = DEFAULT_WRITE_BUFFER_HIGH,
        grace_period: float = DEFAULT_GRACE_PERIOD,
        backlog: int = 128,
        native_port: int | None = None,
        read_only: bool | None = None,
        control: bool | None = None,
    ) -> None:
        if max_frame < 4:
            raise ValueError(f"max_frame must be at least 4, got {max_frame}")
        if max_connections < 1:
            raise ValueError(f"max_connections must be at least 1, got {max_connections}")
        if idle_timeout < 0 or math.isnan(idle_timeout):
            raise ValueError(f"idle_timeout must be >= 0, got {idle_timeout}")
        if max_delayed < 1:
            raise ValueError(f"max_delayed must be at least 1, got {max_delayed}")
        if write_buffer_high < 1:
            raise ValueError(f"write_buffer_high must be at least 1, got {write_buffer_high}")
        if grace_period < 0:
            raise ValueError(f"grace_period must be >= 0, got {grace_period}")
        machine_list = _machines(machines)
        for m in machine_list:
            if read_only is not None:
                m.read_only = read_only
            if control is not None:
                m.control_enabled = control
        if ports is not None:
            if len(ports) != len(machine_list):
                raise ValueError(f"{len(ports)} ports for {len(machine_list)} machines")
            self._ports = list(ports)
        elif port == 0:
            self._ports = [0] * len(machine_list)
        else:
            self._ports = [port + i for i in range(len(machine_list))]
        self._native_ports: list[int] | None = None
        if native_port is not None:
            step = 0 if native_port == 0 else 1
            self._native_ports = [native_port + i * step for i in range(len(machine_list))]
        for p in self._ports + (self._native_ports or []):
            if not 0 <= p <= 65_535:
                raise ValueError(f"port {p} outside 0..65535")
        self.host = host
        self.ssl = ssl
        self.max_frame = max_frame
        self.max_connections = max_connections
        self.idle_timeout = float(idle_timeout)
        self.max_delayed = max_delayed
        self.write_buffer_high = write_buffer_high
        self.grace_period = float(grace_period)
        self.backlog = backlog
        self.listeners: list[Listener] = [Listener(self, m) for m in machine_list]
        self._loop: asyncio.AbstractEventLoop = None  # type: ignore[assignment]
        self._tick = 0
        self._sweeper: asyncio.TimerHandle | None = None
        self._started = False
        self._closed = False
        self._all_closed: anyio.Event | None = None

    # -- lifecycle -------------------------------------------------------------------------

    async def __aenter__(self) -> FocasServer:
        await self.start()
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        await self.aclose()

    async def start(self) -> None:
        """Bind every listener. On failure the ones already bound are closed again."""
        if self._started:
            raise RuntimeError("FocasServer already started")
        self._started = True
        self._loop = asyncio.get_running_loop()
        try:
            for listener, port in zip(self.listeners, self._ports, strict=True):
                await self._bind(listener, port)
            if self._native_ports is not None:
                from focas_net.native import start_native

                for listener, port in zip(self.listeners, self._native_ports, strict=True):
                    listener.native = await start_native(
                        listener.machine,
                        self.host,
                        port,
                        max_connections=self.max_connections,
                        idle_timeout=self.idle_timeout,
                        backlog=self.backlog,
                    )
        except BaseException:
            with anyio.CancelScope(shield=True):
                for listener in self.listeners:
                    await self._unbind(listener)
            self._closed = True
            raise
        if self.idle_timeout > 0:
            self._schedule_sweep()
        for listener in self.listeners:
            _log.info("%s listening on %s", listener.label, listener.address_text)
            if listener.native is not None:
                _log.info("%s: native FOCAS/2 on %s", listener.label, listener.native.address_text)

    async def _bind(self, listener: Listener, port: int) -> None:
        def factory() -> Connection:
            return Connection(listener)

        aserver = await self._loop.create_server(
            factory, self.host, port, ssl=self.ssl, backlog=self.backlog, start_serving=True
        )
        listener._aserver = aserver
        sockname = aserver.sockets[0].getsockname()
        listener.address = (str(sockname[0]), int(sockname[1]))

    async def _unbind(self, listener: Listener) -> None:
        listener.accepting = False
        aserver = listener._aserver
        if aserver is not None:
            aserver.close()
        native, listener.native = listener.native, None
        if native is not None:
            await native.aclose(self.grace_period)

    async def serve_forever(self) -> None:
        """Wait until cancelled (the ``async with`` exit then shuts down gracefully)."""
        if not self._started:
            raise RuntimeError("FocasServer not started")
        await anyio.sleep_forever()

    async def aclose(self, grace_period: float | None = None) -> None:
        """Graceful shutdown: stop accepting, answer what is in flight, close.

        Reading stops on every connection; answers held by a delay fault go out when due, or
        all at once when ``grace_period`` is over; each connection closes once its output is
        flushed, and any still open another ``grace_period`` later (a peer that never reads)
        is aborted. Shielded from cancellation.
        """
        if self._closed or not self._started:
            self._closed = True
            return
        self._closed = True
        grace = self.grace_period if grace_period is None else grace_period
        with anyio.CancelScope(shield=True):
            if self._sweeper is not None:
                self._sweeper.cancel()
                self._sweeper = None
            for listener in self.listeners:
                await self._unbind(listener)
            conns = [c for listener in self.listeners for c in listener.connections]
            if conns:
                _log.info("shutting down: %d connections open", len(conns))
            self._all_closed = anyio.Event()
            for conn in conns:
                conn.begin_shutdown()
            if not await self._wait_all_closed(grace):
                for listener in self.listeners:
                    for conn in list(listener.connections):
                        conn.flush_delayed()
                        conn.close()
                if not await self._wait_all_closed(grace):
                    for listener in self.listeners:
                        for conn in list(listener.connections):
                            _log.warning(
                                "%s: connection from %s aborted at shutdown (output not read)",
                                listener.label,
                                conn.peer,
                            )
                            conn.abort()
                    await self._wait_all_closed(1.0)
            # Let the transports' close callbacks run before the loop may be torn down.
            await anyio.lowlevel.checkpoint()
            for listener in self.listeners:
                aserver = listener._aserver
                if aserver is not None:
                    listener._aserver = None
                    await aserver.wait_closed()
            _log.info("server closed")

    async def _wait_all_closed(self, within: float) -> bool:
        event = self._all_closed
        assert event is not None
        if not self.connection_count:
            return True
        with anyio.move_on_after(within):
            await event.wait()
        return not self.connection_count

    def _connection_done(self, conn: Connection) -> None:
        event = self._all_closed
        if event is not None and not self.connection_count:
            event.set()

    # -- idle sweep ------------------------------------------------------------------------

    def _schedule_sweep(self) -> None:
        period = self.idle_timeout / _SWEEPS_PER_TIMEOUT
        self._sweeper = self._loop.call_later(period, self._sweep)

    def _sweep(self) -> None:
        self._tick += 1
        tick = self._tick
        limit = _SWEEPS_PER_TIMEOUT + 1  # idle for at least one whole timeout
        for listener in self.listeners:
            idle = [
                c
                for c in listener.connections
                if tick - c.last_tick >= limit and not c.delayed_count
            ]
            for conn in idle:
                _log.info(
                    "%s: closing the connection from %s: idle for %g s",
                    listener.label,
                    conn.peer,
                    self.idle_timeout,
                )
                conn.abort()
        self._schedule_sweep()

    # -- introspection ---------------------------------------------------------------------

    @property
    def connection_count(self) -> int:
        """Open connections over all listeners."""
        return sum(len(listener.connections) for listener in self.listeners)

    @property
    def machines(self) -> list[Machine]:
        return [listener.machine for listener in self.listeners]

    @property
    def addresses(self) -> list[tuple[str, int]]:
        """``(host, port)`` of every listener, in machine order."""
        return [listener.address for listener in self.listeners]

    def listener_for(self, port: int) -> Listener:
        """The listener bound to ``port``."""
        for listener in self.listeners:
            if listener.port == port:
                return listener
        raise KeyError(port)

    def __repr__(self) -> str:
        state = "closed" if self._closed else "serving" if self._started else "new"
        return f"<FocasServer {state} {len(self.listeners)} machines>"

    def stats(self) -> dict[str, dict[str, Any]]:
        """Per machine: address, open connections and the counters."""
        return {
            listener.label: {
                "address": listener.address_text,
                "connections": len(listener.connections),
                "accepted": listener.accepted,
                "refused": listener.refused,
                "violations": listener.violations,
                "faults": len(listener.faults),
                **({"native": listener.native.stats()} if listener.native is not None else {}),
            }
            for listener in self.listeners
        }
