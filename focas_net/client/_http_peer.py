"""A peer that is an HTTP server, met where a CNC was expected (a port of a web page, a
proxy): it waits for the end of a request line that a FOCAS frame never sends, and says
nothing, so a client meets a timeout with nothing received; or it answers a request line it
could read with an error page, which breaks the FOCAS framing.

:func:`as_http_peer` asks the port an HTTP request on a new connection, only then, and turns
such a failure into the error of a peer that does not speak the FOCAS protocol, naming it an
HTTP server: the command line and the gateway say the same of the same peer.
"""

from __future__ import annotations

import asyncio
from typing import Final

from focas_net._address import address_text
from focas_net.errors import FocasTimeoutError, PayloadError, ProtocolError

from ._failures import NOTHING_RECEIVED, bytes_text, not_focas_error

__all__ = ["HTTP_PROBE_BOUND", "HTTP_REQUEST", "as_http_peer", "http_answer", "says_nothing"]

#: What the probe sends: the smallest request an HTTP/1 server answers.
HTTP_REQUEST: Final = b"HEAD / HTTP/1.0\r\n\r\n"
#: The longest wait for its answer, in seconds (a shorter call timeout bounds it more).
HTTP_PROBE_BOUND: Final = 2.0


def says_nothing(exc: BaseException) -> bool:
    """Whether ``exc`` leaves open what the peer is: a timeout with nothing received, or a
    framing it broke with what may be an HTTP answer (not a TLS record)."""
    text = str(exc)
    if isinstance(exc, FocasTimeoutError):
        return NOTHING_RECEIVED in text
    return (
        isinstance(exc, ProtocolError)
        and not isinstance(exc, PayloadError)
        and "does not speak the FOCAS protocol" in text
        and "TLS record" not in text
    )


async def http_answer(host: str, port: int, bound: float) -> bytes:
    """The first bytes ``host:port`` answers to an HTTP request within ``bound`` seconds
    (empty: none, or no connection)."""
    try:
        async with asyncio.timeout(bound):
            reader, writer = await asyncio.open_connection(host, port)
            try:
                writer.write(HTTP_REQUEST)
                return await reader.read(64)
            finally:
                writer.close()
    except (OSError, TimeoutError):
        return b""


async def as_http_peer(exc: BaseException, host: str, port: int, bound: float) -> BaseException:
    """``exc``; or, when it :func:`says_nothing` and ``host:port`` answers an HTTP request
    (within ``bound`` seconds), the error of a peer that does not speak the FOCAS protocol,
    an HTTP server."""
    if not says_nothing(exc):
        return exc
    head = await http_answer(host, port, bound)
    if not head.startswith(b"HTTP/"):
        return exc
    why = f"it answers {bytes_text(head[:12])} to an HTTP request and no FOCAS frame"
    return not_focas_error(address_text(host, port), f"{why}: an HTTP server")
