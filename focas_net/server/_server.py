"""``FocasServer``: the listener shell of one or more simulated machines.

One :class:`FocasServer` serves a fleet: each machine gets its own listening port and keeps its
own state; nothing is global. The server is an async context manager::

    async with FocasServer(default_machine(), port=0) as server:
        host, port = server.listeners[0].address
        await server.serve_forever()

Each machine's port speaks both protocols, as a real CNC's port 8193 does: the packed protocol
of ``docs/protocol.md`` and FANUC's native FOCAS/2 Ethernet protocol of
``docs/native-protocol.md``. The first four bytes of a connection decide: ``A0 A0 A0 A0`` opens
every native frame, and as a packed little-endian length it is far above any ``max_frame``
(which is kept below it). With ``native_port`` each machine also gets a port that serves the
native protocol only.

This module is the shell, written once for both protocols: binding, TLS, the connection limit,
the idle sweep, graceful shutdown and the counters. The protocol of every socket accepted on a
port serving both is a :class:`_SniffingConnection`: a packed connection that is admitted (or
refused) by its listener and looks at the first bytes; once they say packed, its class becomes
the plain :class:`~._packed.PackedConnection` the transport calls directly, and when they say native
a :class:`~._native.NativeConnection` takes over the transport (``transport.set_protocol``).
Connections know their limits (a frozen :class:`~._base.Limits`) and a close callback, never
the server. It runs on asyncio (uvloop works too); anyio gives the structure.
"""

from __future__ import annotations

import asyncio
import logging
import math
import ssl as _ssl
from collections.abc import Callable, Iterable, Iterator, Sequence
from itertools import chain
from typing import Any, Final, cast

import anyio
import anyio.lowlevel

from focas_net._address import check_host
from focas_net._typed import os_words
from focas_net.adapters import PackedAdapter
from focas_net.native import DEFAULT_MAX_BODY, MAGIC, check_server_max_body
from focas_net.protocol import DEFAULT_MAX_FRAME
from focas_net.sim import Machine

from ._base import (
    DEFAULT_MAX_DELAYED,
    DEFAULT_WRITE_BUFFER_HIGH,
    NATIVE_MAGIC_LENGTH,
    BaseConnection,
    Limits,
    peer_text,
)
from ._durable import Keeper
from ._handshake import Handshakes, tls_factory
from ._native import NativeConnection, NativeFront
from ._options import (
    check_distinct_ports,
    check_fleet_ports,
    check_server_options,
    server_machines,
)
from ._packed import PackedConnection
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
    "ListenError",
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
#: Seconds a graceful shutdown waits for delayed answers and unsent output.
DEFAULT_GRACE_PERIOD: Final = 5.0

#: Seconds the shutdown waits, once every connection is closed, for asyncio's server to say
#: every socket it accepted is closed (on Python 3.12 and later it waits for them).
_UNBIND_BOUND: Final = 1.0
#: The idle timeout is checked this many times per timeout period.
_SWEEPS_PER_TIMEOUT: Final = 4
_MAGIC_SIZE: Final = len(MAGIC)

_AnyConnection = PackedConnection | NativeConnection


class ListenError(OSError):
    """A port that cannot be bound: the operating system's error, with :attr:`where` the
    ``HOST:PORT`` that failed and :attr:`native_only` whether it was a FOCAS/2-only port
    (``native_port``), which may be another than the server's first one."""

    def __init__(self, where: str, native_only: bool, cause: OSError) -> None:
        super().__init__(cause.errno, cause.strerror or str(cause))
        self.where = where
        self.native_only = native_only

    def __str__(self) -> str:
        """``cannot listen on HOST:PORT: name or service not known``: the address tried and
        the system's words (never ``[Errno -2] ...`` alone)."""
        return f"cannot listen on {self.where}: {os_words(self)}"


class Listener:
    """One listening port of one machine, and the connections it accepted.

    A machine's main listener serves both protocols: :attr:`connections` holds its packed
    connections (and those that have not sent four bytes yet), :attr:`native_connections` its
    native ones. A listener with :attr:`native_only` set (a machine's :attr:`native` port)
    serves the native protocol only. The machine-wide fault queue :attr:`faults` is shared by
    every listener of the machine.

    Counters: :attr:`accepted` packed connections (a connection counts as packed until its
    first bytes turn out to be a native frame's, then it counts in :attr:`native_accepted`),
    :attr:`refused` connections over the limit (before any byte is read), :attr:`violations`
    and :attr:`native_violations` connections closed for a framing violation.
    """

    __slots__ = (
        "_aserver",
        "_front",
        "_handshakes",
        "_limits",
        "_native_done",
        "_native_label",
        "_owner",
        "_packed_done",
        "accepted",
        "accepting",
        "adapter",
        "address",
        "connections",
        "faults",
        "label",
        "machine",
        "max_connections",
        "native",
        "native_accepted",
        "native_connections",
        "native_only",
        "native_version",
        "native_violations",
        "refused",
        "server",
        "violations",
    )

    def __init__(
        self,
        server: FocasServer,
        machine: Machine,
        *,
        native_only: bool = False,
        sibling: Listener | None = None,
    ) -> None:
        self.server = server
        self.machine = machine
        #: Answers the machine's requests (its answer caches are shared by the connections).
        self.adapter = PackedAdapter(machine)
        self.label = machine.name
        self.native_only = native_only
        self.max_connections = server.max_connections
        self.native_version = server.native_version
        self._limits = server.limits
        #: Open packed connections (on a port serving both protocols).
        self.connections: set[PackedConnection] = set()
        #: Open native connections.
        self.native_connections: set[NativeConnection] = set()
        #: Machine-wide faults (scope 1), one shared count.
        self.faults: FaultQueue = FaultQueue() if sibling is None else sibling.faults
        #: The listener holding the machine's native front (built on first use).
        self._owner: Listener = self if sibling is None else sibling
        self._front: NativeFront | None = None
        #: True from binding until the shutdown starts.
        self.accepting = False
        #: ``(host, port)`` actually bound (port resolved when 0 was asked).
        self.address: tuple[str, int] = ("", 0)
        self.accepted = 0
        self.refused = 0
        self.violations = 0
        self.native_accepted = 0
        self.native_violations = 0
        self._aserver: asyncio.Server | None = None
        #: The TLS handshakes under way (a port serving TLS: :mod:`._handshake`).
        self._handshakes = Handshakes()
        # The close callbacks, one per protocol, shared by every connection of this listener.
        self._packed_done = _Done(self, native=False)
        self._native_done = _Done(self, native=True)
        self._native_label = f"native {self.label}"
        #: The machine's native-only listener, when the server has ``native_port``.
        self.native: Listener | None = None

    @property
    def host(self) -> str:
        return self.address[0]

    @property
    def port(self) -> int:
        return self.address[1]

    def __repr__(self) -> str:
        kind = " native" if self.native_only else ""
        return (
            f"<Listener{kind} {self.label} {self.address_text} "
            f"{len(self.connections) + len(self.native_connections)} conns>"
        )

    @property
    def address_text(self) -> str:
        """``HOST:PORT`` (``[HOST]:PORT`` for IPv6)."""
        host, port = self.address
        return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"

    @property
    def connection_count(self) -> int:
        """Open connections of either protocol."""
        return len(self.connections) + len(self.native_connections)

    def all_connections(self) -> Iterator[_AnyConnection]:
        """Every open connection, packed then native."""
        return chain(self.connections, self.native_connections)

    # -- admission and the hand-over -------------------------------------------------------

    @property
    def _log_label(self) -> str:
        return self._native_label if self.native_only else self.label

    def _native_front(self) -> NativeFront:
        owner = self._owner
        front = owner._front
        if front is None:
            front = owner._front = NativeFront(self.machine, self.native_version)
        return front

    def _new_connection(self) -> PackedConnection | NativeConnection:
        """The protocol of a socket just accepted (the factory of the asyncio server)."""
        if self.native_only:
            return _NativeOnlyConnection(
                self._native_front(),
                self.faults,
                self._limits,
                self._native_done,
                self._native_label,
            )
        return _SniffingConnection(self.adapter, self.faults, self._limits, self._packed_done)

    def _admit(
        self, conn: PackedConnection | NativeConnection, transport: asyncio.Transport
    ) -> bool:
        """Count ``conn`` in, or refuse it (the transport is aborted, False)."""
        if not self.accepting:
            transport.abort()
            return False
        if self.connection_count >= self.max_connections:
            _log.warning(
                "%s: connection from %s refused: %s the limit",
                self._log_label,
                peer_text(transport.get_extra_info("peername")),
                "1 connection is"
                if self.max_connections == 1
                else f"{self.max_connections} connections are",
            )
            self.refused += 1
            transport.abort()
            return False
        if isinstance(conn, NativeConnection):
            self.native_connections.add(conn)
            self.native_accepted += 1
        else:
            self.connections.add(conn)
            self.accepted += 1
        return True

    def _to_native(
        self, packed: PackedConnection, transport: asyncio.Transport, head: bytes
    ) -> None:
        """The first bytes of ``packed`` are a native frame's: a native connection takes over
        its transport (and ``head``, the bytes received so far)."""
        packed.detach()
        self.connections.discard(packed)
        self.accepted -= 1
        conn = NativeConnection(
            self._native_front(), self.faults, self._limits, self._native_done, self._native_label
        )
        self.native_connections.add(conn)
        self.native_accepted += 1
        transport.set_protocol(conn)
        conn.connection_made(transport)
        conn.data_received(head)

    def _closed(self, conn: BaseConnection[Any], native: bool) -> None:
        if native:
            self.native_connections.discard(cast(NativeConnection, conn))
            if conn.violated:
                self.native_violations += 1
        else:
            self.connections.discard(cast(PackedConnection, conn))
            if conn.violated:
                self.violations += 1
        self.server._connection_done()


class _Done:
    """The close callback of one listener's connections of one protocol (one per listener,
    shared by its connections). The shell's own connection classes below also reach their
    listener through it, to be admitted and to hand a transport over; the packed and native
    connections only call it."""

    __slots__ = ("listener", "native")

    def __init__(self, listener: Listener, native: bool) -> None:
        self.listener = listener
        self.native = native

    def __call__(self, conn: BaseConnection[Any]) -> None:
        self.listener._closed(conn, self.native)


class _SniffingConnection(PackedConnection):
    """A connection on a port serving both protocols, until its first bytes are in.

    It is admitted (counted, swept and shut down) as a packed connection. As soon as one of
    its first four bytes differs from ``A0`` it is one: its class becomes :class:`PackedConnection`
    and the transport calls the packed data path directly from then on, so the sniff costs
    nothing after the first chunk. When the first four bytes are ``A0 A0 A0 A0`` (which the
    packed protocol refuses as a length, ``max_frame`` being below it) a native connection
    takes over the transport. Up to three ``A0`` bytes wait in the packed decoder; a peer that
    stops there is closed by the idle sweep like any other.
    """

    __slots__ = ()

    # Every read goes to data_received (which sniffs the first), not the packed fast path.
    buffer_updated = BaseConnection.buffer_updated

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        # uvloop's transports do not subclass asyncio.Transport, but have its methods
        listener = cast(_Done, self._on_close).listener
        if listener._admit(self, cast(asyncio.Transport, base)):
            keeper = listener.server.keeper
            super().connection_made(base if keeper is None else keeper.hold(base))  # type: ignore[arg-type]

    def data_received(self, data: bytes) -> None:
        if type(self) is not _SniffingConnection:  # a transport that kept the old method
            PackedConnection.data_received(self, data)
            return
        transport = self._transport
        if transport is None or self._closing:
            return
        decoder = self._decoder
        held = decoder.buffered  # A0 bytes received so far, 0..3
        need = _MAGIC_SIZE - held
        if MAGIC[held:].startswith(data[:need]):
            if len(data) < need:
                decoder.feed(data)  # still fewer than four bytes, all A0: nothing decodes
            else:
                listener = cast(_Done, self._on_close).listener
                listener._to_native(self, transport, MAGIC + data[need:])
            return
        self.__class__ = PackedConnection  # type: ignore[assignment]
        transport.set_protocol(self)  # uvloop keeps the bound data_received: renew it
        PackedConnection.data_received(self, data)


class _NativeOnlyConnection(NativeConnection):
    """A connection on a native-only port: admitted as a native connection."""

    __slots__ = ()

    def connection_made(self, base: asyncio.BaseTransport) -> None:
        listener = cast(_Done, self._on_close).listener
        if listener._admit(self, cast(asyncio.Transport, base)):
            keeper = listener.server.keeper
            super().connection_made(base if keeper is None else keeper.hold(base))  # type: ignore[arg-type]


class FocasServer:
    """Serve simulated machines over both protocols, one listening port per machine.

    ``machines`` is a machine, several in order (a fleet: a list or any iterable but a dict
    or a set; one Machine object given twice is refused, naming both places), or None for
    the default machine. With
    ``port`` 0 every machine gets an ephemeral port; otherwise machine *i* listens on
    ``port + i``, or on ``ports[i]`` when ``ports`` is given (``port`` left out). Each such
    port answers the packed protocol (``docs/protocol.md``) and FANUC's native FOCAS/2
    Ethernet protocol (``docs/native-protocol.md``) alike: the first four bytes of a
    connection decide.

    ``native_port`` (None = off) adds, for each machine, a port serving the native protocol
    only: machine *i* on ``native_port + i``, or an ephemeral port for each when it is 0 (see
    :attr:`Listener.native`). ``port=None`` (with no ``ports``) leaves the two-protocol ports
    out, so that only the native ports are served. ``native_version`` overrides the version word
    of every native answer, which each machine's control class picks otherwise (it also picks
    the command set FANUC's library uses), ``native_max_body`` the largest
    native frame body accepted (checked on the header before any of the body is buffered; at
    least :data:`~focas_net.native.LIBRARY_MAX_REQUEST_BODY`, 1450, the longest request body
    FANUC's library sends).

    Limits: ``max_frame`` (a longer or shorter packed length prefix closes that connection; at
    least 4 and below 0xA0A0A0A0, which is how a native frame's first four bytes read),
    ``max_connections`` per port (extra connections are closed at once and logged),
    ``idle_timeout`` seconds without a complete request (0 = never), ``max_delayed`` delayed
    answers per connection and ``write_buffer_high`` bytes of unsent output before reading
    from that connection stops. ``ssl`` serves TLS (on the two-protocol ports). ``grace_period``
    bounds the graceful shutdown of :meth:`aclose` (``async with`` exit).

    ``read_only`` and ``control``, when given, set those switches of every machine served
    (``Machine.read_only``: every write answers EW_PROT; ``Machine.control_enabled``: simulator
    control on or off); None leaves each machine as it is.

    ``durable`` (``serve --state``) makes the machines' changes durable (it raises OSError
    when it cannot): the answers of each loop turn are held until one call of it at the end of
    the turn (:attr:`keeper`, :mod:`._durable`), so an answer leaves only once the write it
    acknowledges is kept.
    """

    def __init__(
        self,
        machines: Machine | Iterable[Machine] | None = None,
        *,
        host: str = DEFAULT_HOST,
        port: int | None = DEFAULT_PORT,
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
        native_version: int | None = None,
        native_max_body: int = DEFAULT_MAX_BODY,
        read_only: bool | None = None,
        control: bool | None = None,
        durable: Callable[[], object] | None = None,
    ) -> None:
        check_server_options(locals())
        if max_frame < 4:
            raise ValueError(f"max_frame must be at least 4, got {max_frame}")
        if max_frame >= NATIVE_MAGIC_LENGTH:
            raise ValueError(
                f"max_frame must be below 0xA0A0A0A0 ({NATIVE_MAGIC_LENGTH}), the length a "
                f"native FOCAS/2 frame's first four bytes read as, got {max_frame}"
            )
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
        if native_version is not None and not 1 <= native_version <= 0xFFFF:
            raise ValueError(f"native_version must be within 1..65535, got {native_version}")
        check_server_max_body(native_max_body, "native_max_body")
        machine_list = server_machines(machines)
        for m in machine_list:
            if read_only is not None:
                m.read_only = read_only
            if control is not None:
                m.control_enabled = control
        self._ports: list[int] | None
        if ports is not None:
            if port not in (None, DEFAULT_PORT):
                raise ValueError(
                    f"port={port} and ports={list(ports)} both given: ports names each "
                    "machine's port, leave port out"
                )
            if len(ports) != len(machine_list):
                given, count = len(ports), len(machine_list)
                raise ValueError(
                    f"{given} port{'s' * (given != 1)} for {count} machine{'s' * (count != 1)}: "
                    "ports names each machine's port, one each"
                )
            self._ports = list(ports)
        elif port is None:
            if native_port is None:
                raise ValueError("port=None serves nothing without native_port")
            self._ports = None
        elif port == 0:
            self._ports = [0] * len(machine_list)
        else:
            self._ports = [port + i for i in range(len(machine_list))]
        self._native_ports: list[int] | None = None
        if native_port is not None:
            step = 0 if native_port == 0 else 1
            self._native_ports = [native_port + i * step for i in range(len(machine_list))]
        check_fleet_ports(port, self._ports if ports is None else None, "port")
        check_fleet_ports(native_port, self._native_ports, "native_port")
        for p in (self._ports or []) + (self._native_ports or []):
            if not 0 <= p <= 65_535:
                raise ValueError(f"port {p} outside 0..65535")
        check_distinct_ports(self._ports, self._native_ports)
        self.host = check_host(host, 0)  # an IPv6 address without its brackets
        self.ssl = ssl
        self.max_frame = max_frame
        self.max_connections = max_connections
        self.idle_timeout = float(idle_timeout)
        self.max_delayed = max_delayed
        self.write_buffer_high = write_buffer_high
        self.grace_period = float(grace_period)
        self.backlog = backlog
        self.native_version = native_version
        self.native_max_body = native_max_body
        #: Holds each loop turn's answers until ``durable()`` made the changes they
        #: acknowledge durable (``serve --state``; :mod:`._durable`); None: answers leave at
        #: once.
        self.keeper: Keeper | None = None if durable is None else Keeper(durable)
        #: The bounds every connection works within.
        self.limits = Limits(max_frame, native_max_body, max_delayed, write_buffer_high)
        #: One listener per machine, in machine order: its port serving both protocols (or,
        #: with ``port=None``, its native-only port).
        self.listeners: list[Listener] = []
        for machine in machine_list:
            if self._ports is None:
                self.listeners.append(Listener(self, machine, native_only=True))
                continue
            listener = Listener(self, machine)
            if self._native_ports is not None:
                listener.native = Listener(self, machine, native_only=True, sibling=listener)
            self.listeners.append(listener)
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

    def _bindings(self) -> Iterator[tuple[Listener, int, _ssl.SSLContext | None]]:
        """Every listener with the port it binds and its TLS context, machine by machine."""
        if self._ports is None:
            assert self._native_ports is not None
            for listener, port in zip(self.listeners, self._native_ports, strict=True):
                yield listener, port, None
            return
        for listener, port in zip(self.listeners, self._ports, strict=True):
            yield listener, port, self.ssl
        if self._native_ports is not None:
            for listener, port in zip(self.listeners, self._native_ports, strict=True):
                assert listener.native is not None
                yield listener.native, port, None

    def _all_listeners(self) -> Iterator[Listener]:
        for listener in self.listeners:
            yield listener
            if listener.native is not None:
                yield listener.native

    async def start(self) -> None:
        """Bind every listener. On failure the ones already bound are closed again."""
        if self._started:
            raise RuntimeError("FocasServer already started")
        self._started = True
        loop = asyncio.get_running_loop()
        try:
            for listener, port, ssl in self._bindings():
                await self._bind(loop, listener, port, ssl)
        except BaseException:
            with anyio.CancelScope(shield=True):
                for listener in self._all_listeners():
                    self._unbind(listener)
                for listener in self._all_listeners():
                    await self._wait_unbound(listener)
            self._closed = True
            raise
        if self.idle_timeout > 0:
            self._schedule_sweep(loop)
        for listener in self.listeners:
            if listener.native_only:
                _log.info("%s: native FOCAS/2 on %s", listener.label, listener.address_text)
                continue
            _log.info("%s listening on %s", listener.label, listener.address_text)
            if listener.native is not None:
                _log.info("%s: native FOCAS/2 on %s", listener.label, listener.native.address_text)

    async def _bind(
        self,
        loop: asyncio.AbstractEventLoop,
        listener: Listener,
        port: int,
        ssl: _ssl.SSLContext | None,
    ) -> None:
        factory: Callable[[], asyncio.BaseProtocol] = listener._new_connection
        if ssl is not None:  # the handshake is the shell's own, to log one that fails
            factory = tls_factory(factory, ssl, listener._log_label, listener._handshakes)
        try:
            aserver = await loop.create_server(
                factory,
                self.host,
                port,
                backlog=self.backlog,
                start_serving=True,
            )
        except OSError as exc:
            where = f"[{self.host}]:{port}" if ":" in self.host else f"{self.host}:{port}"
            raise ListenError(where, listener.native_only, exc) from exc
        listener._aserver = aserver
        sockname = aserver.sockets[0].getsockname()
        listener.address = (str(sockname[0]), int(sockname[1]))
        listener.accepting = True

    @staticmethod
    def _unbind(listener: Listener) -> None:
        listener.accepting = False
        aserver = listener._aserver
        if aserver is not None:
            aserver.close()
        listener._handshakes.close()

    @staticmethod
    async def _wait_unbound(listener: Listener) -> None:
        """Wait for ``listener``'s asyncio server to be closed, by a deadline. From Python
        3.12 on it waits for every socket it accepted to close: the connections are closed
        (or aborted) by now, and so are the TLS handshakes; a socket nothing of the shell
        holds any more is aborted (Python 3.13's ``abort_clients``), and one left still does
        not hold the shutdown past :data:`_UNBIND_BOUND` seconds."""
        aserver = listener._aserver
        if aserver is None:
            return
        listener._aserver = None
        abort_clients: Callable[[], None] | None = getattr(aserver, "abort_clients", None)
        if abort_clients is not None:
            abort_clients()
        with anyio.move_on_after(_UNBIND_BOUND) as scope:
            await aserver.wait_closed()
        if scope.cancelled_caught:
            _log.warning(
                "%s: a socket it accepted was still open %g s after its connections closed",
                listener._log_label,
                _UNBIND_BOUND,
            )

    async def serve_forever(self) -> None:
        """Wait until cancelled (the ``async with`` exit then shuts down gracefully)."""
        if not self._started:
            raise RuntimeError("FocasServer not started")
        await anyio.sleep_forever()

    async def aclose(self, grace_period: float | None = None) -> None:
        """Graceful shutdown: stop accepting, answer what is in flight, close.

        Reading stops on every connection (both protocols, every port); answers held by a delay
        fault go out when due, or all at once when ``grace_period`` is over; each connection
        closes once its output is flushed, and any still open another ``grace_period`` later
        (a peer that never reads) is aborted. Shielded from cancellation.
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
            for listener in self._all_listeners():
                self._unbind(listener)
            conns = list(self._connections())
            if conns:
                _log.info("shutting down: %d connections open", len(conns))
            self._all_closed = anyio.Event()
            for conn in conns:
                conn.begin_shutdown()
            if not await self._wait_all_closed(grace):
                for conn in list(self._connections()):
                    conn.flush_delayed()
                    conn.close()
                if not await self._wait_all_closed(grace):
                    for conn in list(self._connections()):
                        _log.warning(
                            "%s: connection from %s aborted at shutdown (output not read)",
                            conn.label,
                            conn.peer_text,
                        )
                        conn.abort()
                    await self._wait_all_closed(1.0)
            # Let the transports' close callbacks run before the loop may be torn down.
            await anyio.lowlevel.checkpoint()
            for listener in self._all_listeners():
                await self._wait_unbound(listener)
            if self.keeper is not None:
                self.keeper.flush()  # what the machines did since the last answer
            _log.info("server closed")

    def _connections(self) -> Iterator[_AnyConnection]:
        for listener in self._all_listeners():
            yield from listener.all_connections()

    async def _wait_all_closed(self, within: float) -> bool:
        event = self._all_closed
        assert event is not None
        if not self.connection_count:
            return True
        with anyio.move_on_after(within):
            await event.wait()
        return not self.connection_count

    def _connection_done(self) -> None:
        event = self._all_closed
        if event is not None and not self.connection_count:
            event.set()

    # -- idle sweep ------------------------------------------------------------------------

    def _schedule_sweep(self, loop: asyncio.AbstractEventLoop) -> None:
        period = self.idle_timeout / _SWEEPS_PER_TIMEOUT
        self._sweeper = loop.call_later(period, self._sweep, loop)

    def _sweep(self, loop: asyncio.AbstractEventLoop) -> None:
        limit = _SWEEPS_PER_TIMEOUT + 1  # idle for at least one whole timeout
        idle: list[_AnyConnection] = []
        for conn in self._connections():
            conn.idle_sweeps += 1
            if conn.idle_sweeps >= limit and not conn.delayed_count:
                idle.append(conn)
        for conn in idle:
            conn.close_idle(self.idle_timeout)
        self._schedule_sweep(loop)

    # -- introspection ---------------------------------------------------------------------

    @property
    def connection_count(self) -> int:
        """Open connections over all listeners, both protocols."""
        return sum(listener.connection_count for listener in self._all_listeners())

    @property
    def machines(self) -> list[Machine]:
        return [listener.machine for listener in self.listeners]

    @property
    def addresses(self) -> list[tuple[str, int]]:
        """``(host, port)`` of every listener, in machine order."""
        return [listener.address for listener in self.listeners]

    def listener_for(self, port: int) -> Listener:
        """The listener bound to ``port`` (a native-only one too)."""
        for listener in self._all_listeners():
            if listener.port == port:
                return listener
        raise KeyError(port)

    def __repr__(self) -> str:
        state = "closed" if self._closed else "serving" if self._started else "new"
        count = len(self.listeners)
        return f"<FocasServer {state} {count} machine{'' if count == 1 else 's'}>"

    def stats(self) -> dict[str, dict[str, Any]]:
        """Per machine: address, open packed connections and the packed counters, the
        machine-wide faults armed, and under ``"native"`` the same for native connections
        (over the machine's ports; ``address`` is its native-only port when it has one)."""
        result: dict[str, dict[str, Any]] = {}
        for listener in self.listeners:
            ports = [listener] if listener.native is None else [listener, listener.native]
            native_port = next((p for p in ports if p.native_only), listener)
            result[listener.label] = {
                "address": listener.address_text,
                "connections": len(listener.connections),
                "accepted": listener.accepted,
                "refused": sum(p.refused for p in ports if not p.native_only),
                "violations": listener.violations,
                "faults": len(listener.faults),
                "native": {
                    "address": native_port.address_text,
                    "connections": sum(len(p.native_connections) for p in ports),
                    "accepted": sum(p.native_accepted for p in ports),
                    "refused": sum(p.refused for p in ports if p.native_only),
                    "violations": sum(p.native_violations for p in ports),
                },
            }
        return result
