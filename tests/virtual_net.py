"""An event loop whose clock moves only when nothing else can happen, and a network in memory.

:class:`VirtualLoop` runs asyncio code (the server, both clients) with no socket and no real
time: its clock stands still while callbacks are ready, and when the loop would wait, it jumps
to the next timer instead. A test therefore sees every timeout, delay and backoff happen at
exactly its machine time, in no real time, and the same way on every run. A loop that would
wait with no timer set is stuck for good (something waits for what can never come): it raises
:class:`Stuck` rather than hang.

``create_server`` and ``create_connection`` connect the two ends' protocols through
:class:`MemoryTransport` pairs: bytes written on one end are delivered to the other on the next
loop turn, in order, to a plain or a buffered protocol; ``close`` and ``abort`` end both
sides (the peer sees the end of the stream). Nothing listens anywhere.
"""

from __future__ import annotations

import asyncio
import itertools
from collections import deque
from collections.abc import Callable
from typing import Any

__all__ = ["MemoryTransport", "Stuck", "VirtualLoop"]


class Stuck(RuntimeError):
    """The loop would wait for ever: nothing is ready and no timer is set."""


class _Selector:
    """Stands in for the loop's selector: there is no file to wait for; waiting is time."""

    def __init__(self, loop: VirtualLoop) -> None:
        self._loop = loop

    def select(self, timeout: float | None) -> list[Any]:
        if timeout is None:
            raise Stuck("the loop would wait for ever: nothing is ready and no timer is set")
        if timeout > 0:
            self._loop.now += timeout
        return []

    def close(self) -> None:
        pass


class MemoryTransport(asyncio.Transport):
    """One end of an in-memory stream between two protocols of one :class:`VirtualLoop`."""

    def __init__(self, loop: VirtualLoop, protocol: asyncio.BaseProtocol, name: tuple[str, int]):
        super().__init__()
        self._loop = loop
        self._protocol = protocol
        self._name = name
        self.peer: MemoryTransport | None = None
        self._closing = False
        self._lost = False
        self._paused = False
        self._held: deque[bytes] = deque()

    # -- what the protocols call -------------------------------------------------------------
    def get_extra_info(self, name: str, default: Any = None) -> Any:
        if name == "peername":
            return None if self.peer is None else self.peer._name
        if name == "sockname":
            return self._name
        return default

    def is_closing(self) -> bool:
        return self._closing

    def close(self) -> None:
        self._end()

    def abort(self) -> None:
        self._end()

    def set_protocol(self, protocol: asyncio.BaseProtocol) -> None:
        self._protocol = protocol

    def get_protocol(self) -> asyncio.BaseProtocol:
        return self._protocol

    def is_reading(self) -> bool:
        return not self._paused

    def pause_reading(self) -> None:
        self._paused = True

    def resume_reading(self) -> None:
        if self._paused:
            self._paused = False
            while self._held and not self._paused and not self._lost:
                self._receive(self._held.popleft())

    def set_write_buffer_limits(self, high: int | None = None, low: int | None = None) -> None:
        pass

    def get_write_buffer_size(self) -> int:
        return 0

    def get_write_buffer_limits(self) -> tuple[int, int]:
        return (0, 0)

    def write(self, data: bytes | bytearray | memoryview) -> None:
        if self._closing or not data:
            return
        peer = self.peer
        if peer is not None:
            self._loop.call_soon(peer._arrive, bytes(data))

    def writelines(self, list_of_data: Any) -> None:
        self.write(b"".join(bytes(d) for d in list_of_data))

    def can_write_eof(self) -> bool:
        return False

    # -- delivery -------------------------------------------------------------------------
    def _arrive(self, data: bytes) -> None:
        if self._lost:
            return
        if self._paused:
            self._held.append(data)
            return
        self._receive(data)

    def _receive(self, data: bytes) -> None:
        protocol = self._protocol
        if isinstance(protocol, asyncio.BufferedProtocol):
            view = memoryview(data)
            while view:
                buf = memoryview(protocol.get_buffer(len(view)))
                n = min(len(buf), len(view))
                buf[:n] = view[:n]
                protocol.buffer_updated(n)
                view = view[n:]
        else:
            assert isinstance(protocol, asyncio.Protocol)
            protocol.data_received(data)

    def _end(self) -> None:
        if self._closing:
            return
        self._closing = True
        self._loop.call_soon(self._gone, None)
        peer = self.peer
        if peer is not None and not peer._closing:
            self._loop.call_soon(peer._eof)

    def _eof(self) -> None:
        if self._closing:
            return
        keep_open = False
        protocol = self._protocol
        if isinstance(protocol, asyncio.Protocol | asyncio.BufferedProtocol):
            keep_open = bool(protocol.eof_received())
        if not keep_open:
            self._end()

    def _gone(self, exc: Exception | None) -> None:
        if self._lost:
            return
        self._lost = True
        self._protocol.connection_lost(exc)


class _Socket:
    """What ``Server.sockets`` shows of a listener: its address."""

    def __init__(self, name: tuple[str, int]) -> None:
        self._name = name

    def getsockname(self) -> tuple[str, int]:
        return self._name


class _Server:
    """A listener of the memory network (what ``create_server`` returns)."""

    def __init__(self, loop: VirtualLoop, factory: Callable[[], Any], name: tuple[str, int]):
        self._loop = loop
        self.factory = factory
        self.sockets = [_Socket(name)]
        self.name = name
        self.serving = True

    def close(self) -> None:
        self.serving = False
        self._loop.listeners.pop(self.name, None)

    async def wait_closed(self) -> None:
        return None

    def is_serving(self) -> bool:
        return self.serving


class VirtualLoop(asyncio.BaseEventLoop):
    """An event loop on machine time, with a network in memory (see the module docstring)."""

    def __init__(self) -> None:
        super().__init__()
        self._selector = _Selector(self)
        #: The loop's clock, seconds.
        self.now = 0.0
        self.listeners: dict[tuple[str, int], _Server] = {}
        self._ports = itertools.count(40000)

    def time(self) -> float:
        return self.now

    def _process_events(self, event_list: list[Any]) -> None:
        pass

    def _write_to_self(self) -> None:
        pass

    async def create_server(  # type: ignore[override]
        self, protocol_factory: Callable[[], Any], host: str = "127.0.0.1", port: int = 0,
        **_: Any,
    ) -> _Server:  # fmt: skip
        name = (host, port or next(self._ports))
        if name in self.listeners:
            raise OSError(98, f"address {name} already in use")
        server = _Server(self, protocol_factory, name)
        self.listeners[name] = server
        return server

    async def create_connection(  # type: ignore[override]
        self, protocol_factory: Callable[[], Any], host: str = "127.0.0.1", port: int = 0,
        **_: Any,
    ) -> tuple[MemoryTransport, Any]:  # fmt: skip
        server = self.listeners.get((host, port))
        if server is None or not server.serving:
            raise ConnectionRefusedError(111, f"connect to {host}:{port} refused")
        await asyncio.sleep(0)
        client_protocol = protocol_factory()
        server_protocol = server.factory()
        here = MemoryTransport(self, client_protocol, (host, next(self._ports)))
        there = MemoryTransport(self, server_protocol, (host, port))
        here.peer, there.peer = there, here
        server_protocol.connection_made(there)
        client_protocol.connection_made(here)
        return here, client_protocol
