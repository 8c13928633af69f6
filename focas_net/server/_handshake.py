"""The TLS handshake of a port that serves TLS, done by the listener shell itself.

asyncio's own TLS server drops a failed handshake at its debug level, so a plain client on a
TLS port left nothing in the server's log. Here each socket accepted on such a port is first a
:class:`TlsHandshake`: it stops reading at once (the TLS layer reads first) and a task runs
``loop.start_tls`` with the connection the port's factory made, which is made (admitted) only
once the handshake is done. A failed handshake is logged in words, naming what the client was
when OpenSSL can tell (a plain client, an HTTP one). The listener holds the handshakes under
way (:class:`Handshakes`), each bounded by the handshake timeout; at shutdown each is ended,
its task cancelled and its socket closed, and a socket accepted as the shutdown began is
closed as its handshake would begin: no socket is left open that no connection holds (on
Python 3.12 and later, asyncio's server waits for every socket it accepted to close).
"""

from __future__ import annotations

import asyncio
import logging
import ssl as _ssl
from collections.abc import Callable
from typing import Final, Protocol, cast, runtime_checkable

from focas_net._tls import ssl_error_text

from ._base import peer_text

__all__ = ["HANDSHAKE_TIMEOUT", "Handshakes", "TlsHandshake", "handshake_failure", "tls_factory"]

_log = logging.getLogger("focas_net.server")

#: Seconds a client has to complete its TLS handshake (asyncio's own default).
HANDSHAKE_TIMEOUT: Final = 60.0

_HTTP_CLIENT: Final = "it sent an HTTP request: a plain HTTP client, on a port that serves TLS"
#: OpenSSL's reasons for a first record that is none of TLS's, with what the client was.
_PLAIN_CLIENTS: Final = {
    "WRONG_VERSION_NUMBER": "it sent no TLS handshake: a plain client, on a port that serves TLS",
    "HTTP_REQUEST": _HTTP_CLIENT,
    "HTTPS_PROXY_REQUEST": _HTTP_CLIENT,  # (CONNECT)
}


@runtime_checkable
class _Buffered(Protocol):
    """A buffered protocol by its methods (uvloop's TLS layer subclasses no asyncio class)."""

    def get_buffer(self, sizehint: int) -> memoryview: ...

    def buffer_updated(self, nbytes: int) -> None: ...


def handshake_failure(exc: BaseException) -> tuple[int, str]:
    """The log level and the words of a TLS handshake that failed with ``exc``: a plain
    client (warning), OpenSSL's reason (warning), a client that closed or never finished
    (debug and info: a port probe does that too)."""
    if isinstance(exc, _ssl.SSLError):
        plain = _PLAIN_CLIENTS.get(str(exc.reason))
        if plain is not None:
            return logging.WARNING, plain
        return logging.WARNING, f"TLS handshake failed ({ssl_error_text(exc)})"
    if isinstance(exc, ConnectionAbortedError):
        return logging.INFO, f"no TLS handshake within {HANDSHAKE_TIMEOUT:g} s"
    return logging.DEBUG, "it closed the connection during the TLS handshake"


class Handshakes:
    """The TLS handshakes under way on one port. Once :meth:`close` is called (the port
    shuts down) each is ended, and one that would begin later is refused."""

    __slots__ = ("_open", "_under_way")

    def __init__(self) -> None:
        self._under_way: set[TlsHandshake] = set()
        self._open = True

    def __len__(self) -> int:
        return len(self._under_way)

    def begin(self, handshake: TlsHandshake) -> bool:
        """Hold ``handshake`` until it ends; False once the port shuts down."""
        if self._open:
            self._under_way.add(handshake)
        return self._open

    def end(self, handshake: TlsHandshake) -> None:
        self._under_way.discard(handshake)

    def close(self) -> None:
        """End every handshake under way, and refuse any later one."""
        self._open = False
        for handshake in list(self._under_way):
            handshake.abort()


class TlsHandshake(asyncio.Protocol):
    """A socket accepted on a port that serves TLS, until its handshake is done: then
    ``connection`` (the port's own protocol) is made on the TLS transport.

    Reading stops when the socket is made; uvloop starts it again right after, so the first
    read may come here before the TLS layer is in place: it is held (reading stops again) and
    given to the TLS layer first. What the TLS layer passes on before the task resumes (at most
    one read with the handshake's end) is held and given to the connection once it is made.
    """

    __slots__ = (
        "_connection",
        "_context",
        "_eof",
        "_handshakes",
        "_held",
        "_label",
        "_lost",
        "_raw",
        "_socket",
        "_task",
    )

    def __init__(
        self,
        connection: asyncio.BaseProtocol,
        context: _ssl.SSLContext,
        label: str,
        handshakes: Handshakes,
    ) -> None:
        self._connection = connection
        self._context = context
        self._label = label
        self._handshakes = handshakes
        self._raw: asyncio.Transport | None = None  # (until the TLS layer is in place)
        #: The accepted socket's transport, until the connection holds it.
        self._socket: asyncio.Transport | None = None
        self._task: asyncio.Task[None] | None = None
        self._held: list[bytes] = []
        self._eof = False
        self._lost = False

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        # uvloop's transports do not subclass asyncio.Transport, but have its methods
        raw = cast(asyncio.Transport, transport)
        if not self._handshakes.begin(self):  # accepted as the port shut down
            raw.abort()
            return
        self._raw = self._socket = raw
        raw.pause_reading()  # not a byte before the TLS layer reads
        task = self._task = asyncio.get_running_loop().create_task(self._handshake(raw))
        task.add_done_callback(self._ended)

    def _ended(self, task: asyncio.Task[None]) -> None:
        self._handshakes.end(self)

    def abort(self) -> None:
        """End the handshake (the port shuts down): its task cancelled, and its socket closed
        unless a connection holds it already (a task cancelled before it began never would)."""
        if self._task is not None:
            self._task.cancel()
        raw, self._socket = self._socket, None
        if raw is not None:
            raw.abort()

    def data_received(self, data: bytes) -> None:
        self._held.append(data)
        if self._raw is not None:  # (uvloop: read before the TLS layer was in place)
            self._raw.pause_reading()

    def eof_received(self) -> bool:
        self._eof = True
        return False  # (the TLS layer closes after an end of stream whatever is returned)

    def connection_lost(self, exc: Exception | None) -> None:
        self._lost = True

    def _give_first_read(self, raw: asyncio.Transport, first: bytes) -> None:
        """Give ``first`` to the TLS layer ``start_tls`` has put in place, before it starts
        the handshake (a call scheduled ahead of its own)."""
        tls = raw.get_protocol()
        if tls is self or not isinstance(tls, _Buffered):
            return  # (start_tls failed at once)
        rest = memoryview(first)
        while rest:
            buffer = tls.get_buffer(len(rest))
            size = min(len(buffer), len(rest))
            buffer[:size] = rest[:size]
            tls.buffer_updated(size)
            rest = rest[size:]

    async def _handshake(self, raw: asyncio.Transport) -> None:
        loop = asyncio.get_running_loop()
        self._raw = None
        if self._held:
            loop.call_soon(self._give_first_read, raw, b"".join(self._held))
            self._held = []
        try:
            tls = await loop.start_tls(
                raw, self, self._context, server_side=True, ssl_handshake_timeout=HANDSHAKE_TIMEOUT
            )
        except OSError as exc:  # (TimeoutError too)
            level, why = handshake_failure(exc)
            peer = peer_text(raw.get_extra_info("peername"))
            _log.log(level, "%s: closing the connection from %s: %s", self._label, peer, why)
            raw.close()
            return
        self._socket = None  # the TLS layer holds it, then the connection
        if self._lost or tls is None:
            return
        connection = cast(asyncio.Protocol, self._connection)  # (its data_received too)
        tls.set_protocol(connection)
        connection.connection_made(tls)
        for data in self._held:
            connection.data_received(data)
        self._held.clear()
        if self._eof and not connection.eof_received():
            tls.close()


def tls_factory(
    factory: Callable[[], asyncio.BaseProtocol],
    context: _ssl.SSLContext,
    label: str,
    handshakes: Handshakes,
) -> Callable[[], TlsHandshake]:
    """The protocol factory of a port serving TLS with ``context`` over ``factory``'s
    connections (``label``: the port's name in the log; ``handshakes``: the port's)."""
    return lambda: TlsHandshake(factory(), context, label, handshakes)
