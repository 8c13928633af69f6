"""Transports and hints, a confirming pass: what a new user meets with passwords, wrong
peers, odd addresses and ``serve``'s options, in cases the earlier passes did not try.

Servers here bind 127.0.0.1 on ephemeral ports; ``focas-net`` runs as a subprocess where its
exit code is checked.
"""

from __future__ import annotations

import asyncio
import errno
import socket
import ssl
import struct

import pytest
from cli_support import one_line, run_focas_net
from support import LoopbackPeer

from focas_net.client._failures import connect_error


def _closed_port() -> int:
    """A port of 127.0.0.1 nothing listens on (bound, then closed)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (("unlock", ""), "PASSWORD"),
        (("unlock", "ABCDE"), "PASSWORD"),
        (("param", "set", "1020", "5", "--password", "ABCDE"), "--password"),
        (("macro", "set", "100", "5", "--password", "é"), "--password"),
    ],
)
async def test_a_bad_password_is_a_usage_error_naming_its_argument_before_any_connect(
    argv: tuple[str, ...], named: str
) -> None:
    """``unlock ''`` connected first (exit 3 when the CNC was away, as if the password were
    good), and both refusals read `parameter password '': ...`, naming no argument, in words
    other than ``serve --param-password``'s."""
    typed = argv[argv.index("--password") + 1] if "--password" in argv else argv[1]
    command = " ".join(argv[:2]) if argv[0] != "unlock" else "unlock"
    code, out, err = await run_focas_net(*argv, "--port", str(_closed_port()))
    assert (code, out) == (2, "")
    assert one_line(err, f"focas-net {command}: error:") == (
        f"focas-net {command}: error: argument {named}: must be 1..4 ASCII characters, got "
        f"{typed!r}; see focas-net {command} --help"
    )


class _ResettingPeer(LoopbackPeer):
    """Accepts each connection and resets it at once (a close with SO_LINGER 0), as a
    server at its limit may close one: the client's connect may meet the reset."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        sock = writer.get_extra_info("socket")
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        writer.transport.abort()


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_peer_that_resets_each_connection_at_once_reads_as_closed_before_any_answer(
    protocol: str,
) -> None:
    """It read `cannot connect to 127.0.0.1:P: connection reset by peer`, where docs/cli.md
    says a reset reads as a close, and without the probe's advice a close at once gets."""
    async with _ResettingPeer() as peer:
        code, out, err = await run_focas_net(
            "status", "--port", str(peer.port), "--timeout", "1", "--protocol", protocol
        )
    assert (code, out) == (3, "")
    assert one_line(err) == (
        f"focas-net: connection closed by 127.0.0.1:{peer.port} before any answer; the server "
        "refused the connection: it closes new ones at once, as a server at its connection "
        "limit does (focas-net serve --max-connections)"
    )


def test_a_connect_the_peer_resets_is_a_close_before_any_answer() -> None:
    """Whether the reset of a peer that closes at once meets the connect or the request is
    a race: both read the same, without TLS (with TLS it ended the handshake)."""
    exc = ConnectionResetError(errno.ECONNRESET, "Connection reset by peer")
    plain = connect_error("127.0.0.1", 8193, exc, None)
    assert str(plain) == "connection closed by 127.0.0.1:8193 before any answer"
    assert plain.__cause__ is exc
    tls = connect_error("127.0.0.1", 8193, exc, ssl.create_default_context())
    assert str(tls) == (
        "cannot connect to 127.0.0.1:8193: TLS handshake failed (the peer closed it): the peer "
        "may not speak TLS"
    )
    refused = connect_error("::1", 8193, ConnectionRefusedError(errno.ECONNREFUSED, "x"), None)
    assert str(refused) == "cannot connect to [::1]:8193: connection refused"
