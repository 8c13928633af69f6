"""Transports and hints, eleventh pass: the gateway's advice for a machine it cannot talk to
(a TLS port, a port of FOCAS/2 alone), in the file's keys and as the command line gives it; a
server that wants a client certificate; peers that misbehave (half answers, wrong lengths, a
reset mid-frame, slow answers) and the deadlines of both clients; the server's log of odd
clients.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import socket
import ssl
import struct
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Literal

import pytest
from cli_support import fails
from poller_support import QUICK, RecordingSink, config
from support import IO_TIMEOUT, LoopbackPeer, serving, wait_until

from focas_net.cli import EXIT_CONNECTION
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import FocasConnectionError, ProtocolError
from focas_net.gateway import Gateway, GatewayConfig
from focas_net.protocol import FaultKind, FaultScope

#: What a TLS connection closed before any answer adds.
_CLOSED_AFTER_HANDSHAKE = (
    "(a TLS server closes so when it wants a client certificate and gets none, or at its "
    "connection limit)"
)
#: The command line's advice for a server that wants a client certificate.
_NO_CLIENT_CERTIFICATE = (
    "the command line sends no client certificate: connect from Python, with FocasClient's "
    "ssl= a context holding one (SSLContext.load_cert_chain)"
)


def _server_tls(certificate: tuple[Path, Path]) -> ssl.SSLContext:
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(*certificate)
    return context


async def _gateway_reason(port: int, protocol: Literal["native", "packed"]) -> str:
    """Why the gateway's first attempt at the machine on ``port`` of 127.0.0.1 failed."""
    sink = RecordingSink()
    machine = replace(config("m", port, protocol), timeout=1.0)
    gateway = Gateway(GatewayConfig((machine,)), policy=QUICK)
    gateway.add_sink(sink)
    async with gateway:
        await wait_until(lambda: any(not up for _, up, _ in sink.states))
    return next(why for _, up, why in sink.states if not up)


# -- the gateway's advice for a port it cannot talk to ------------------------------------------
_GATEWAY_TLS = (
    "the server uses TLS: the gateway reaches a machine without TLS: give a port of it that is "
    'plain TCP (a focas-net server\'s --native-port, with protocol = "native")'
)


@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_the_gateway_at_a_tls_port_says_it_is_one(
    certificate: tuple[Path, Path], protocol: Literal["native", "packed"]
) -> None:
    """It said `closed: connection closed by ... before any answer` alone, where the command
    line says `the server uses TLS`."""
    async with serving(ssl=_server_tls(certificate)) as served:
        why = await _gateway_reason(served.port, protocol)
        said = await fails(
            EXIT_CONNECTION, "status", "--protocol", protocol, "--port", str(served.port)
        )
    assert why == (
        f"closed: connection closed by 127.0.0.1:{served.port} before any answer; {_GATEWAY_TLS}"
    )
    assert "the server uses TLS" in said


async def test_the_gateway_at_a_port_of_focas2_alone_asks_for_protocol_native() -> None:
    async with serving(native_port=0) as served:
        native = served.listener.native
        assert native is not None
        port = native.address[1]
        why = await _gateway_reason(port, "packed")
        said = await fails(EXIT_CONNECTION, "status", "--port", str(port))
    hint = "the port speaks FOCAS/2 only (serve --native-port): give "
    assert why == (
        f"closed: connection closed by 127.0.0.1:{port} before any answer; "
        f'{hint}protocol = "native"'
    )
    assert said.endswith(f"before any answer; {hint}--protocol native")


# -- a server that wants a client certificate ---------------------------------------------------
def _wants_client_certificate(
    certificate: tuple[Path, Path], version: ssl.TLSVersion
) -> ssl.SSLContext:
    context = _server_tls(certificate)
    context.verify_mode = ssl.CERT_REQUIRED
    context.load_verify_locations(certificate[0])
    context.maximum_version = version
    return context


@contextmanager
def _openssl_server(context: ssl.SSLContext) -> Iterator[int]:
    """A TLS server of OpenSSL's own sockets on 127.0.0.1 (its port), in a thread: unlike an
    asyncio server, it sends the alert of a handshake it refuses. It takes connections until
    the block ends, each handshake bounded."""
    listener = socket.create_server(("127.0.0.1", 0))
    listener.settimeout(0.05)
    done = threading.Event()

    def serve() -> None:
        while not done.is_set():
            try:
                conn, _ = listener.accept()
            except TimeoutError:
                continue
            conn.settimeout(IO_TIMEOUT)
            tls = context.wrap_socket(conn, server_side=True, do_handshake_on_connect=False)
            with contextlib.suppress(OSError):
                tls.do_handshake()  # (TLS 1.3 checks the client's certificate after its Finished)
            with contextlib.suppress(OSError):  # (its alert read before the end: no reset)
                tls.shutdown(socket.SHUT_WR)
                while tls.recv(4096):
                    pass
            tls.close()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield listener.getsockname()[1]
    finally:
        done.set()
        thread.join(IO_TIMEOUT)
        listener.close()


async def _status_over_tls(port: int, cafile: Path) -> FocasConnectionError:
    context = ssl.create_default_context(cafile=cafile)
    with pytest.raises(FocasConnectionError) as caught:
        async with FocasClient("127.0.0.1", port, ssl=context, timeout=IO_TIMEOUT) as client:
            await client.read_status()
    return caught.value


@pytest.mark.parametrize(
    ("version", "words"),
    [
        # It read `connection to ... lost before any answer: [SSL:
        # TLSV13_ALERT_CERTIFICATE_REQUIRED] tlsv13 alert certificate required (_ssl.c:2580)`.
        (
            ssl.TLSVersion.TLSv1_3,
            "connection to 127.0.0.1:{port} lost before any answer: the server wants a client "
            "certificate (tlsv13 alert certificate required)",
        ),
        # It read `TLS handshake failed (sslv3 alert handshake failure): the peer may not
        # speak TLS`, and the command line advised "drop --tls": a peer that sends an alert
        # speaks TLS.
        (
            ssl.TLSVersion.TLSv1_2,
            "cannot connect to 127.0.0.1:{port}: TLS handshake failed (sslv3 alert handshake "
            "failure): the server refused it: it may want a client certificate, or share no "
            "TLS version or cipher with this client",
        ),
    ],
)
async def test_the_alert_of_a_tls_server_that_wants_a_client_certificate_is_worded(
    certificate: tuple[Path, Path], version: ssl.TLSVersion, words: str
) -> None:
    context = _wants_client_certificate(certificate, version)
    with _openssl_server(context) as port:
        said = str(await _status_over_tls(port, certificate[0]))
        line = await fails(
            EXIT_CONNECTION, "status", "--port", str(port), "--tls-ca", str(certificate[0])
        )
    assert said == words.format(port=port)
    assert line == f"focas-net: {said}; {_NO_CLIENT_CERTIFICATE}"


async def test_a_tls_connection_closed_after_its_handshake_names_a_client_certificate(
    certificate: tuple[Path, Path],
) -> None:
    """An asyncio server drops its alert: the client reads an end of stream alone."""
    context = _wants_client_certificate(certificate, ssl.TLSVersion.TLSv1_3)
    async with serving(ssl=context) as served:
        said = str(await _status_over_tls(served.port, certificate[0]))
        line = await fails(
            EXIT_CONNECTION, "status", "--port", str(served.port), "--tls-ca", str(certificate[0])
        )
    assert line == f"focas-net: {said}"  # (a cause among others: no advice of one)
    assert said == (
        f"connection closed by 127.0.0.1:{served.port} before any answer {_CLOSED_AFTER_HANDSHAKE}"
    )


async def test_a_tls_server_at_its_connection_limit_is_not_said_to_want_a_certificate(
    certificate: tuple[Path, Path],
) -> None:
    """It completes the handshake, then closes: the command line told to load a client
    certificate."""
    async with serving(ssl=_server_tls(certificate), max_connections=1) as served:
        insecure = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        insecure.check_hostname, insecure.verify_mode = False, ssl.CERT_NONE
        async with FocasClient("127.0.0.1", served.port, ssl=insecure, timeout=IO_TIMEOUT):
            line = await fails(
                EXIT_CONNECTION, "status", "--port", str(served.port), "--tls-insecure"
            )
    assert line == (
        f"focas-net: connection closed by 127.0.0.1:{served.port} before any answer "
        f"{_CLOSED_AFTER_HANDSHAKE}"
    )


# -- the server's log of a client that goes away ------------------------------------------------
@pytest.mark.parametrize("reset", [False, True])
@pytest.mark.parametrize("native", [False, True])
async def test_the_server_logs_a_client_gone_in_words_never_none_nor_an_errno(
    caplog: pytest.LogCaptureFixture, reset: bool, native: bool
) -> None:
    """It logged `connection from 127.0.0.1:PORT closed (None)` and `closed ([Errno 104]
    Connection reset by peer)`."""
    caplog.set_level(logging.DEBUG, logger="focas_net.server")
    async with serving(native_port=0) as served:
        listener = served.listener.native if native else None
        port = served.port if listener is None else listener.address[1]
        _, writer = await asyncio.open_connection("127.0.0.1", port)
        here = "127.0.0.1:{}".format(writer.get_extra_info("sockname")[1])
        if reset:
            linger = struct.pack("ii", 1, 0)
            writer.get_extra_info("socket").setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, linger)
            writer.transport.abort()
        else:
            writer.close()
        gone = f"connection from {here} closed"
        await wait_until(lambda: any(gone in r.getMessage() for r in caplog.records))
    said = next(r.getMessage() for r in caplog.records if gone in r.getMessage())
    assert said.endswith(gone + (": connection reset by peer" if reset else ""))


# -- a peer that breaks an answer after the connect ---------------------------------------------
class _Relay(LoopbackPeer):
    """A peer passing each connection on to ``upstream`` (a port of 127.0.0.1) and its answers
    back; ``change``, once set, is applied to the next chunk of answers, then the relay says
    nothing more on that connection."""

    def __init__(self, upstream: int) -> None:
        self.upstream = upstream
        self.change: Callable[[bytes], bytes] | None = None

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        up_reader, up_writer = await asyncio.open_connection("127.0.0.1", self.upstream)

        async def requests() -> None:
            with contextlib.suppress(OSError):
                while data := await reader.read(65536):
                    up_writer.write(data)
            up_writer.close()

        task = asyncio.ensure_future(requests())
        try:
            with contextlib.suppress(OSError):
                while data := await up_reader.read(65536):
                    change, self.change = self.change, None
                    writer.write(data if change is None else change(data))
                    if change is not None:
                        await reader.read()  # (nothing more: until the client leaves)
                        break
        finally:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
            writer.close()


async def test_a_native_answer_that_is_no_frame_reads_alike_at_the_connect_and_after_it() -> None:
    """After the connect it read `(answer does not start with A0 A0 A0 A0; ...)`, at it `(its
    answer does not start ...)`."""
    async with serving() as served, _Relay(served.port) as relay:
        async with NativeClient("127.0.0.1", relay.port, timeout=IO_TIMEOUT) as native:
            relay.change = lambda data: bytes(len(data))
            with pytest.raises(ProtocolError) as caught:
                await native.read_status()
    assert str(caught.value) == (
        f"127.0.0.1:{relay.port} does not speak the FOCAS protocol (its answer does not start "
        "with A0 A0 A0 A0; it sent 00 00 00 00 00 00 00 00)"
    )


async def test_a_drop_fault_over_tls_is_named_a_drop_not_a_client_certificate(
    certificate: tuple[Path, Path],
) -> None:
    """A TLS connection closed before any answer may be a server that wants a client
    certificate; the probes ask a packed request over TLS too, which a drop answers."""
    async with serving(ssl=_server_tls(certificate)) as served:
        insecure = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        insecure.check_hostname, insecure.verify_mode = False, ssl.CERT_NONE
        async with FocasClient("127.0.0.1", served.port, ssl=insecure, timeout=IO_TIMEOUT) as c:
            await c.sim.inject_fault(FaultKind.DROP, scope=FaultScope.MACHINE)
        line = await fails(
            EXIT_CONNECTION, "status", "--port", str(served.port), "--tls-ca", str(certificate[0])
        )
    assert line == (
        f"focas-net: connection closed by 127.0.0.1:{served.port} before any answer "
        f"{_CLOSED_AFTER_HANDSHAKE}; the server answers a new connection, so it closed this "
        "one on purpose (as a drop fault does: "
        "focas-net sim fault drop), or as a server does with a request longer than it takes "
        "(focas-net serve --max-frame)"
    )


async def test_the_gateway_at_a_server_of_one_connection_asks_for_the_packed_protocol() -> None:
    """FOCAS/2 takes two connections: the advice names the file's key, not `--protocol`."""
    async with serving(max_connections=1) as served:
        why = await _gateway_reason(served.port, "native")
    assert why.startswith(f"closed: connection closed by 127.0.0.1:{served.port} before any answer")
    assert why.endswith(
        "FOCAS/2's open, which takes two: a server with one connection free refuses the second "
        "(focas-net serve --max-connections 1, or other clients holding the others); give "
        'protocol = "packed", or free a connection or raise the limit'
    )
