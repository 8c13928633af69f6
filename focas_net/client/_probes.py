"""Why a connection failed before the peer said anything: a few probes, run only then, and
the advice they give, the same for the command line and the gateway.

A connection the peer closed before any answer, or that timed out with nothing received,
cannot tell from itself what it met. The probes ask the same port on new connections, each
bounded by the caller's bound (the command's ``--timeout``, the machine's ``timeout``, and
:data:`PROBE_TIMEOUT` at most):

* does it close a connection at once, before anything is sent? (a server at its connection
  limit, ``focas-net serve --max-connections``, refuses so);
* does it complete a TLS handshake? (a TLS server closes a plain client's connection);
* does it answer a packed request, and does it answer the open of FOCAS/2? (a port of
  ``focas-net serve --native-port`` speaks FOCAS/2 only; a port answering the failed
  transport's request on a new connection closed the first one on purpose: a drop fault);
* after a timeout with nothing received: does it answer an HTTP request? (an HTTP server
  waits for the end of a request line that a FOCAS frame never sends, and says nothing:
  :mod:`._http_peer`).

No probe takes a fault armed on the server (``focas-net sim fault``): the packed one asks a
control command, the FOCAS/2 one sends the open alone, answers a fault never touches, and the
others send no request at all.

:func:`diagnosed` turns the findings into the error to report (an HTTP server is a peer that
does not speak the FOCAS protocol) and advice, worded in the options of the front end that
asks (:class:`Wording`: the command line's ``--protocol native``, the gateway file's
``protocol = "native"``), so that both say the same of the same port.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import ssl
from collections.abc import Awaitable
from dataclasses import dataclass
from typing import Final

from focas_net.errors import CncError, FocasConnectionError
from focas_net.protocol import FaultScope

from ._failures import BEFORE_ANY_ANSWER
from ._http_peer import as_http_peer, says_nothing
from ._native_link import _open_channel
from .client import FocasClient

__all__ = [
    "COMMAND_LINE",
    "GATEWAY",
    "PROBE_TIMEOUT",
    "Findings",
    "Wording",
    "advice",
    "diagnosed",
    "probed",
]

#: Longest wait of one probe, in seconds (the caller's timeout when shorter).
PROBE_TIMEOUT: Final = 2.0


@dataclass(frozen=True, slots=True)
class Findings:
    """What the probes found on a port."""

    refused: bool  #: it closed a connection at once, before anything was sent
    tls: bool  #: it completed a TLS handshake
    packed: bool  #: it answered a packed request
    native: bool  #: it answered the open of FOCAS/2
    packed_tls: bool = False  #: it answered a packed request over TLS (asked with TLS only)


@dataclass(frozen=True, slots=True)
class Wording:
    """How a front end names what the advice asks for: ``protocol`` gives a transport
    (formatted with ``packed`` or ``native``); ``tls`` asks for TLS of the packed protocol,
    and ``trust`` says how its certificate is trusted (``tls`` None: the front end has no
    TLS to a CNC, and ``trust`` is the advice for a TLS port)."""

    protocol: str
    tls: str | None
    trust: str


#: The command line's options.
COMMAND_LINE: Final = Wording("--protocol {}", "--tls", "with --tls-ca FILE or --tls-insecure")
#: The gateway file's keys of a machine (it reaches every machine without TLS).
GATEWAY: Final = Wording(
    'protocol = "{}"',
    None,
    "the gateway reaches a machine without TLS: give a port of it that is plain TCP (a "
    'focas-net server\'s --native-port, with protocol = "native")',
)


def advice(
    found: Findings,
    protocol: str,
    tls: bool,
    packed_only: str | None = None,
    wording: Wording = COMMAND_LINE,
) -> str | None:
    """The advice for a connection of ``protocol`` (``tls``: it asked for TLS) that was
    closed before any answer, from what the probes ``found`` (None: nothing certain), in
    ``wording``; ``packed_only`` names what the caller needs that FOCAS/2 cannot carry (a
    command, or ``--password``), which a port of FOCAS/2 alone cannot serve."""
    give = wording.protocol.format
    if packed_only is not None and found.native and not found.packed:
        plain = ", without TLS" if tls else ""
        return (
            f"the port speaks FOCAS/2 only (serve --native-port){plain}, which cannot carry "
            f"{packed_only}: connect to the server's main port, which speaks both"
        )
    if found.refused and not (found.tls or found.packed or found.native):
        return (
            "the server refused the connection: it closes new ones at once, as a server at its "
            "connection limit does (focas-net serve --max-connections)"
        )
    if tls:  # (asked for by a front end that has TLS: wording.tls)
        if found.packed_tls:
            return _on_purpose(protocol)
        if found.packed:
            return f"the server is plain TCP: drop {wording.tls}"
        if found.native:
            return (
                f"the port speaks FOCAS/2 only, without TLS: drop {wording.tls}, give "
                f"{give('native')}"
            )
        return None
    if found.tls:
        if wording.tls is None:
            return f"the server uses TLS: {wording.trust}"
        if protocol == "native":
            return (
                "the server uses TLS, which FOCAS/2 does not have: give "
                f"{give('packed')} {wording.tls}"
            )
        return f"the server uses TLS: give {wording.tls} ({wording.trust})"
    if protocol == "packed" and found.native and not found.packed:
        return f"the port speaks FOCAS/2 only (serve --native-port): give {give('native')}"
    if protocol == "native" and found.packed and not found.native:
        return (
            "the server answers one connection but not FOCAS/2's open, which takes two: a "
            "server with one connection free refuses the second (focas-net serve "
            f"--max-connections 1, or other clients holding the others); give {give('packed')}, "
            "or free a connection or raise the limit"
        )
    if found.packed if protocol == "packed" else found.native:
        return _on_purpose(protocol)
    return None


def _on_purpose(protocol: str) -> str:
    """The advice for a port of ``protocol`` that answers the request a new connection
    sends: it closed the failed one on purpose."""
    # (a packed server closes a connection whose frame is longer than its max_frame,
    # answering nothing: the probes' requests are short and answered)
    longer = (
        ", or as a server does with a request longer than it takes (focas-net serve --max-frame)"
        if protocol == "packed"
        else ""
    )
    return (
        "the server answers a new connection, so it closed this one on purpose (as a drop "
        f"fault does: focas-net sim fault drop){longer}"
    )


async def _bounded(probe: Awaitable[bool], bound: float) -> bool:
    """``probe``'s finding, False when it fails or takes longer than ``bound`` seconds."""
    try:
        async with asyncio.timeout(bound):
            return await probe
    except Exception:  # refused, closed, reset, timed out, not decoded: not found
        return False


async def _closes_at_once(host: str, port: int) -> bool:
    """A connection on which nothing is sent ends (the peer refused it): by an end of
    stream or a reset, which may meet the connect itself (a refused connect is no peer)."""
    try:
        reader, writer = await asyncio.open_connection(host, port)
    except ConnectionResetError:
        return True
    try:
        return await reader.read(1) == b""
    except ConnectionError:
        return True
    finally:
        writer.close()


def _any_certificate() -> ssl.SSLContext:
    """A client context that checks no certificate: a probe asks only whether TLS is spoken."""
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    context.check_hostname = False
    context.verify_mode = ssl.CERT_NONE
    return context


async def _speaks_tls(host: str, port: int) -> bool:
    """A TLS handshake completes (no certificate checked: only whether TLS is spoken)."""
    _, writer = await asyncio.open_connection(host, port, ssl=_any_certificate())
    writer.close()
    return True


class _ProbeClient(FocasClient):
    """The packed probe's client: its connections are the probe's, not the caller's, and are
    never told in the log (a gateway at WARNING would say a machine never reached was lost,
    at INFO that it connected)."""

    _logger = logging.getLogger("focas_net.client.probe")


_ProbeClient._logger.setLevel(logging.CRITICAL + 1)


async def _answers_packed(host: str, port: int, bound: float, tls: bool = False) -> bool:
    """A packed request is answered (over TLS with ``tls``, no certificate checked): the
    listing of this connection's own faults, a control command, whose answer a fault armed
    on the server never replaces nor counts (a probe must not take the fault meant for the
    caller's next call); an EW code answers too (a real CNC, ``serve --no-control``)."""
    context = _any_certificate() if tls else None
    async with _ProbeClient(host, port, timeout=bound, ssl=context) as client:
        try:
            await client.sim.list_faults(FaultScope.CONNECTION)
        except CncError:
            pass
    return True


async def _answers_native(host: str, port: int, bound: float) -> bool:
    """The open of FOCAS/2 is answered on both its connections, as a client opens them (the
    opens alone: their answers are never faulted, while the requests a client sends after
    them are)."""
    deadline = asyncio.get_running_loop().time() + bound
    first, _ = await _open_channel(host, port, 1, deadline)
    try:
        second, _ = await _open_channel(host, port, 2, deadline)
        second.close()
    finally:
        first.close()
    return True


async def probed(host: str, port: int, bound: float, tls: bool = False) -> Findings:
    """Probe ``host:port`` (each probe ``bound`` seconds at most): the one waiting for a
    close at once is waited for only when no other probe found the peer answering. A peer
    that answers the packed protocol is then asked the open of FOCAS/2 alone, so that a
    server of one connection at a time answers it if it can (FOCAS/2 takes two). For a
    connection of TLS (``tls``), a packed request over TLS is asked first: a server that
    answers it closed the failed connection on purpose (one that closes a TLS connection
    before any answer may want a client certificate)."""
    if tls and await _bounded(_answers_packed(host, port, bound, tls=True), bound):
        return Findings(refused=False, tls=True, packed=False, native=False, packed_tls=True)
    if await _bounded(_answers_packed(host, port, bound), bound):
        native = await _bounded(_answers_native(host, port, bound), bound)
        return Findings(refused=False, tls=False, packed=True, native=native)
    at_once = asyncio.ensure_future(_bounded(_closes_at_once(host, port), bound))
    try:
        tls, native = await asyncio.gather(
            _bounded(_speaks_tls(host, port), bound),
            _bounded(_answers_native(host, port, bound), bound),
        )
        refused = False if tls or native else await at_once
    finally:
        at_once.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await at_once
    return Findings(refused, tls, False, native)


async def diagnosed(
    exc: BaseException,
    host: str,
    port: int,
    protocol: str,
    tls: bool,
    within: float,
    packed_only: str | None = None,
    wording: Wording = COMMAND_LINE,
) -> tuple[BaseException, str | None]:
    """The error to report for ``exc`` and advice in ``wording`` (None: none), probing
    ``host:port`` when ``exc`` says the peer said nothing: a connection closed before any
    answer, a TLS handshake it ended, a timeout with nothing received (an HTTP server
    becomes a peer that does not speak the FOCAS protocol); each probe takes ``within``
    seconds (the failed call's timeout) or :data:`PROBE_TIMEOUT` at most."""
    text = str(exc)
    bound = min(within, PROBE_TIMEOUT)
    if says_nothing(exc):
        return await as_http_peer(exc, host, port, bound), None
    closed = isinstance(exc, FocasConnectionError) and (
        BEFORE_ANY_ANSWER in text or (tls and "TLS handshake failed" in text)
    )
    if not closed:
        return exc, None
    found = await probed(host, port, bound, tls)
    return exc, advice(found, protocol, tls, packed_only, wording)
