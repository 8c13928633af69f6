"""The native client's TCP connections: :class:`Channel`, opened by :func:`open_channel`.

FOCAS/2 keeps one request frame in flight on a connection, so every call of a sequential
caller is a round trip of its own, and what the event loop spends on each read and write is
spent once a call. A channel hands each read to one callback and takes each write as one call,
in one of two ways, whichever costs the loop less:

* :class:`SocketChannel`, on asyncio's selector loops (the default on Linux and macOS): the
  channel owns its non-blocking socket. The loop calls it when the socket is readable, and it
  reads with one ``recv``; a write is one ``send``. asyncio's own transport, written in Python,
  adds its buffering checks to each write and ``get_buffer``, ``recv_into`` and
  ``buffer_updated`` to each read.
* :class:`TransportChannel`, on any other loop (uvloop, asyncio's proactor loop): the loop's own
  transport, read as a buffered protocol (``focas_net/_receive.py``). uvloop's transports are
  compiled and do their system calls without giving up the GIL, which costs less than calling
  a socket from Python.

Before :meth:`Channel.start` and after :meth:`Channel.stop` the bytes read are kept for
:meth:`Channel.readexactly` (the open and close exchanges); in between they go to the
``on_data`` callback. The end of the connection (end of file, a failed read or write) is told
to ``on_end`` once, or, while not started, raised by ``readexactly``. Neither kind ever calls
``on_end`` from inside :meth:`Channel.write`.
"""

from __future__ import annotations

import asyncio
import ipaddress
import socket
from collections import deque
from collections.abc import Callable
from typing import Any, Final, cast

from focas_net._address import address_text
from focas_net._receive import Received, _local
from focas_net._typed import os_reason

#: Bytes one read of a :class:`SocketChannel` may bring: a whole answer frame (at most 10 +
#: 65535 bytes) in one or two.
READ_SIZE: Final = 65536
#: Most bytes kept for :meth:`Channel.readexactly` before the peer is taken as faulty: two of
#: the largest frames.
KEEP_LIMIT: Final = 2 * (10 + 0xFFFF)


class Channel:
    """What both kinds of channel share: the bytes kept while not started, the end."""

    on_data: Callable[[bytes], None] | None
    on_end: Callable[[Exception | None], None] | None
    ended: bool
    closed: bool
    _kept: bytearray
    received: int
    _waiter: asyncio.Future[None] | None
    _error: Exception | None

    def _init_channel(self) -> None:
        #: Where the bytes read go once started, and who hears of the end.
        self.on_data = None
        self.on_end = None
        #: Bytes read while not started, and the :meth:`readexactly` waiting for more.
        self._kept = bytearray()
        #: Bytes read while not started, in all (whether the peer said anything).
        self.received = 0
        self._waiter = None
        #: The connection ended (end of file, or ``_error``); the channel closed.
        self.ended = False
        self.closed = False
        self._error = None

    def write(self, data: bytes) -> None:
        """Send ``data`` (after any write still under way)."""
        raise NotImplementedError

    def close(self) -> None:
        """Close the connection now: nothing more is read or written (writes still queued are
        dropped); the end is not told."""
        if self.closed:
            return
        self.on_data = self.on_end = None
        self.closed = True
        self._shut()
        self._wake()

    def _shut(self) -> None:
        """Close the connection itself (:meth:`close`, once)."""
        raise NotImplementedError

    def _keep(self, data: bytes) -> None:
        if self.ended:
            return  # (a transport may still read after the peer was taken as faulty)
        kept = self._kept
        kept += data
        self.received += len(data)
        if len(kept) > KEEP_LIMIT:
            self._end(ConnectionError(f"the peer sent {len(kept)} bytes nobody asked for"))
            return
        self._wake()

    def _wake(self) -> None:
        waiter = self._waiter
        if waiter is not None and not waiter.done():
            waiter.set_result(None)

    def _end(self, exc: Exception | None) -> None:
        """The connection ended (``exc``: why, None at end of file): nothing more is read; the
        end is told once."""
        if self.ended:
            return
        self.ended = True
        if exc is not None:
            self._error = exc
        self._stop_reading()
        on_end = self.on_end
        if on_end is not None:
            on_end(exc)
        else:
            self._wake()

    def _stop_reading(self) -> None:
        """Read nothing more from the connection (a transport closes itself at the end, and
        bytes after the peer was taken as faulty are not kept)."""

    @property
    def kept(self) -> bytes:
        """The bytes read and kept (before :meth:`start`) that no :meth:`readexactly` took yet
        (the start of a frame that never came whole)."""
        return bytes(self._kept)

    async def readexactly(self, n: int, check: Callable[[bytes], None] | None = None) -> bytes:
        """The next ``n`` bytes read (before :meth:`start` or after :meth:`stop`); ``check``
        sees the bytes kept each time more are waited for, and may raise at once (a start
        that no frame has).

        :raises asyncio.IncompleteReadError: the connection ended first (its error instead,
            an :class:`OSError`, when it failed).
        """
        kept = self._kept
        while len(kept) < n:
            if check is not None:
                check(bytes(kept))
            if self.ended or self.closed:
                if self._error is not None:
                    raise self._error
                raise asyncio.IncompleteReadError(bytes(kept), n)
            waiter = self._waiter = asyncio.get_running_loop().create_future()
            try:
                await waiter
            finally:
                self._waiter = None
        data = bytes(kept[:n])
        del kept[:n]
        return data

    def start(
        self, on_data: Callable[[bytes], None], on_end: Callable[[Exception | None], None]
    ) -> None:
        """Hand every read to ``on_data`` from now on (the bytes kept first), and the end to
        ``on_end`` (at once if the connection has ended already)."""
        self.on_data = on_data
        self.on_end = on_end
        if self._kept:
            kept = bytes(self._kept)
            self._kept.clear()
            on_data(kept)
        if self.ended and self.on_end is on_end:
            on_end(self._error)

    def stop(self) -> None:
        """Keep the bytes read for :meth:`readexactly` again; tell the end to nobody."""
        self.on_data = self.on_end = None


class SocketChannel(Channel):
    """A connected non-blocking TCP socket read and written by the channel itself, watched
    by a selector loop from when the channel is made."""

    def __init__(self, sock: socket.socket, loop: asyncio.AbstractEventLoop) -> None:
        self._init_channel()
        self.sock = sock
        self._loop = loop
        self._recv = sock.recv
        self._send = sock.send
        #: Writes waiting behind one the kernel did not take whole (it holds far more than a
        #: frame: only a peer that stops reading makes one), and the task sending them.
        self._pending: deque[bytes] = deque()
        self._flusher: asyncio.Task[None] | None = None
        #: A write is sent at once (False while one is under way, after a failed one, once
        #: closed).
        self._direct = True
        loop.add_reader(sock.fileno(), self._readable)
        self._watched = True

    def _readable(self) -> None:
        try:
            data = self._recv(READ_SIZE)
        except (BlockingIOError, InterruptedError):
            return
        except OSError as exc:
            self._end(exc)
            return
        if data:
            on_data = self.on_data
            if on_data is not None:
                try:
                    on_data(data)
                except Exception as exc:  # reported, and the end, as by asyncio's transports
                    self._loop.call_exception_handler(
                        {"message": "the handler of a read failed", "exception": exc}
                    )
                    self._end(exc)
            else:
                self._keep(data)
        else:
            self._end(None)

    def _stop_reading(self) -> None:
        if self._watched:
            self._watched = False
            self._loop.remove_reader(self.sock.fileno())

    def write(self, data: bytes) -> None:
        """Send ``data`` (after any write still under way). A failed send ends the
        connection from a callback of its own."""
        if not self._direct:
            if self._flusher is not None:
                self._pending.append(data)
            return  # (closed or failed: dropped)
        try:
            sent = self._send(data)
        except (BlockingIOError, InterruptedError):
            sent = 0
        except OSError as exc:
            self._direct = False  # later writes are dropped
            self._error = exc
            self._loop.call_soon(self._end, exc)
            return
        if sent != len(data):
            self._direct = False
            self._pending.append(data[sent:])
            self._flusher = self._loop.create_task(self._flush())

    async def _flush(self) -> None:
        pending = self._pending
        try:
            while pending:
                await self._loop.sock_sendall(self.sock, pending[0])
                pending.popleft()
        except OSError as exc:
            pending.clear()
            self._end(exc)
        else:
            self._direct = not self.closed
        finally:
            self._flusher = None

    def _shut(self) -> None:
        self._stop_reading()
        self._direct = False
        flusher, self._flusher = self._flusher, None
        if flusher is not None:
            flusher.cancel()
            # Its send's watch of the socket goes now, not a loop turn later: a socket made
            # before then may get the same fd number, whose watch that would remove.
            self._loop.remove_writer(self.sock.fileno())
        self._pending.clear()
        self.sock.close()


class TransportChannel(Received, asyncio.Protocol, Channel):
    """A channel over the loop's own stream transport, read as a buffered protocol."""

    def __init__(self) -> None:
        self._init_channel()
        self.transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # a stream transport (uvloop's is not a subclass of asyncio.Transport)
        self.transport = stream = cast(asyncio.Transport, transport)
        self.write = stream.write  # type: ignore[method-assign]  # (a call less per write)

    def buffer_updated(self, nbytes: int) -> None:
        # Received.buffer_updated and data_received in one: one call less per read
        data = bytes(_local.view[:nbytes])
        on_data = self.on_data
        if on_data is not None:
            on_data(data)
        else:
            self._keep(data)

    def data_received(self, data: bytes) -> None:  # (a transport reading unbuffered)
        on_data = self.on_data
        if on_data is not None:
            on_data(data)
        else:
            self._keep(data)

    def eof_received(self) -> bool:
        self._end(None)
        return False  # the transport closes itself

    def connection_lost(self, exc: Exception | None) -> None:
        if not self.closed:
            self._end(exc)

    def _shut(self) -> None:
        if self.transport is not None:
            self.transport.abort()


def own_sockets(loop: asyncio.AbstractEventLoop) -> bool:
    """Whether :func:`open_channel` opens a :class:`SocketChannel` on ``loop`` (an asyncio
    selector loop), not a :class:`TransportChannel`."""
    return isinstance(loop, asyncio.SelectorEventLoop)


#: Where to connect: family, socket type, protocol, address (what ``getaddrinfo`` gives).
_Target = tuple[socket.AddressFamily, int, int, tuple[Any, ...]]


def literal_target(host: str, port: int) -> _Target | None:
    """Where to connect for an IPv4 ``host`` written as a number (nothing to resolve), else
    None."""
    try:
        ip = ipaddress.ip_address(host)
    except ValueError:
        return None
    if ip.version == 4:
        return socket.AF_INET, socket.SOCK_STREAM, 0, (host, port)
    return None  # (IPv6: resolved, which also finds its scope)


async def open_channel(host: str, port: int) -> Channel:
    """A channel connected to ``host``:``port`` (each address ``host`` resolves to, in turn).

    :raises OSError: no address could be connected (:func:`connect_socket`).
    """
    loop = asyncio.get_running_loop()
    if not own_sockets(loop):
        if literal_target(host, port) is not None:
            _, channel = await loop.create_connection(TransportChannel, host, port)
        else:
            sock = await connect_socket(host, port)
            _, channel = await loop.create_connection(TransportChannel, sock=sock)
        return channel
    return SocketChannel(await connect_socket(host, port), loop)


async def connect_socket(host: str, port: int) -> socket.socket:
    """A non-blocking TCP socket connected to ``host``:``port``, trying each address ``host``
    resolves to in turn (an IPv4 address as written is not resolved), for both clients.

    :raises OSError: no address could be connected: the error of the one tried, or one naming
        each address and why it failed (one error when all failed alike: ``localhost``
        refused on ``::1`` and on ``127.0.0.1`` is a refused connect).
    """
    loop = asyncio.get_running_loop()
    literal = literal_target(host, port)
    targets: list[_Target]
    if literal is not None:
        targets = [literal]
    else:
        infos = await loop.getaddrinfo(host, port, type=socket.SOCK_STREAM)
        targets = [(family, kind, proto, address) for family, kind, proto, _, address in infos]
        if not targets:
            raise OSError(f"{host!r} resolves to no address")
    errors: list[tuple[tuple[Any, ...], OSError]] = []
    for family, kind, proto, address in targets:
        try:
            sock = socket.socket(family, kind, proto)
        except OSError as exc:  # (a family the kernel does not have: the next address)
            errors.append((address, exc))
            continue
        try:
            sock.setblocking(False)
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            await loop.sock_connect(sock, address)
        except OSError as exc:
            sock.close()
            errors.append((address, exc))
            continue
        except BaseException:
            sock.close()
            raise
        return sock
    raise _one_error(errors)


def _one_error(errors: list[tuple[tuple[Any, ...], OSError]]) -> OSError:
    """The error of a connect that failed on each of its addresses: the first when all failed
    alike (the same code), else one saying, per address, why (never Python's text of an
    exception with its address tuple)."""
    first = errors[0][1]
    if len({exc.errno for _, exc in errors}) == 1 and (first.errno or len(errors) == 1):
        return first
    return OSError(
        "; ".join(
            f"{address_text(str(address[0]), int(address[1]))}: {os_reason(exc)}"
            for address, exc in errors
        )
    )
