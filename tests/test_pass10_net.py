"""Transports and hints, tenth pass: an answer that does not decode, named by the peer, the
call and the sizes on both transports (never a Python class), and the server's log of a TLS
or HTTP client met on a plain port.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import ssl
from collections.abc import Callable

import pytest
from cli_support import at, fails, ok
from support import IO_TIMEOUT, LoopbackPeer, sent_until_closed, serving, the_warning

from focas_net.adapters._native_cnc import CncHandlers
from focas_net.cli import EXIT_CONNECTION
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError, FocasConnectionError, PayloadError
from focas_net.native import RequestBlock
from focas_net.protocol import Command, encode_frame
from focas_net.sim import Machine, Session

# -- an answer that does not decode ------------------------------------------------------------


def _cut(monkeypatch: pytest.MonkeyPatch, handler: str, size: int) -> None:
    """Have the simulator's FOCAS/2 ``handler`` answer only its first ``size`` bytes."""
    whole = getattr(CncHandlers, handler)

    def cut(self: CncHandlers, block: RequestBlock, room: int, session: Session) -> bytes:
        data: bytes = whole(self, block, room, session)
        return data[:size]

    monkeypatch.setattr(CncHandlers, handler, cut)


async def test_a_status_answer_cut_short_names_the_peer_the_call_and_the_sizes(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """It read `cnc_statinfo: answer to 0x19 does not decode: StatInfo: 7 bytes, expected
    14`: no peer, and the codec's class name."""
    _cut(monkeypatch, "read_status", 7)
    async with serving() as s, NativeClient(s.host, s.port, timeout=IO_TIMEOUT) as client:
        with pytest.raises(PayloadError) as caught:
            await client.read_status()
    assert str(caught.value) == (
        f"127.0.0.1:{s.port} sent an answer to cnc_statinfo (0x19) that does not decode: "
        "7 bytes, expected 14"
    )


async def test_a_system_information_cut_short_names_the_peer_and_the_connect_call(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The connect failed with `NativeSysInfo: 10 bytes, expected 18` alone."""
    _cut(monkeypatch, "read_sysinfo", 10)
    async with serving() as s:
        with pytest.raises(PayloadError) as caught:
            async with NativeClient(s.host, s.port, timeout=IO_TIMEOUT):
                pass
    assert str(caught.value) == (
        f"127.0.0.1:{s.port} sent an answer to cnc_allclibhndl3 (0x18) that does not decode: "
        "10 bytes, expected 18"
    )


@pytest.mark.parametrize(
    ("value", "width"), [(1, None), ("1.5", None), ("00000011", None), (1, 1), (1, 8)]
)
async def test_a_write_of_a_parameter_the_cnc_lacks_is_its_ew_number_whatever_the_value(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: int | str, width: int | None
) -> None:
    """The refusal of a write by the next parameter's type or width is the CNC's EW_NUMBER,
    named by the write, on both transports."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as caught:
            await client.write_param(9999, value, width=width)
        assert (caught.value.ew, caught.value.detail) == (
            EW.NUMBER,
            "cnc_wrparam: the CNC has no parameter 9999",
        )


# -- a TLS or HTTP client on a plain port ------------------------------------------------------


@pytest.mark.parametrize(
    ("sent", "why"),
    [
        (
            b"\x16\x03\x01\x00\xa5\x01\x00\x00\xa1\x03\x03",
            "frame length 66326 outside 4..65536; it sent a TLS record: a TLS client, on a "
            "port that does not serve TLS",
        ),
        (
            b"GET / HTTP/1.1\r\nHost: cnc\r\n\r\n",
            "frame length 542393671 outside 4..65536; it sent an HTTP request (GET): an HTTP "
            "client, on a port that serves FOCAS",
        ),
        (
            b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n",
            "frame length 541676112 outside 4..65536; it sent an HTTP request (PRI): an HTTP "
            "client, on a port that serves FOCAS",
        ),
        # other bytes are not shown (a chunk could hold part of an unlock's password)
        (b"SSH-2.0-OpenSSH_9.6\r\n", "frame length 759714643 outside 4..65536"),
        (b"GETX / HTTP/1.1\r\n\r\n", "frame length 1481917767 outside 4..65536"),
    ],
)
async def test_a_tls_or_http_client_on_a_plain_port_is_named_in_the_servers_log(
    sent: bytes, why: str, caplog: pytest.LogCaptureFixture
) -> None:
    """The packed side logged only `frame length 66326 outside 4..65536`, where the client
    names a TLS record it meets."""
    async with serving() as s:
        local = await sent_until_closed(s.port, sent, caplog)
    assert (
        the_warning(caplog) == f"focas-sim-0i: closing the connection from 127.0.0.1:{local}: {why}"
    )


@pytest.mark.parametrize(
    ("sent", "why"),
    [
        (
            encode_frame(Command.RDCNCSTAT, 1, b""),
            "it sent a packed frame (cnc_rdcncstat): a packed client, on a port that speaks "
            "FOCAS/2 only",
        ),
        (
            b"\x16\x03\x01\x00\xa5\x01\x00\x00\xa1\x03\x03",
            "it sent a TLS record: a TLS client, on a port that does not serve TLS",
        ),
        (
            b"GET / HTTP/1.1\r\nHost: cnc\r\n\r\n",
            "it sent an HTTP request (GET): an HTTP client, on a port that serves FOCAS",
        ),
    ],
)
async def test_a_client_of_another_protocol_on_a_focas2_only_port_is_named_in_the_log(
    sent: bytes, why: str, caplog: pytest.LogCaptureFixture
) -> None:
    """The FOCAS/2-only port logged `frame does not start with A0 A0 A0 A0` alone, whatever
    the client was."""
    async with serving(native_port=0) as s:
        native = s.listener.native
        assert native is not None
        local = await sent_until_closed(native.port, sent, caplog)
    assert the_warning(caplog) == (
        f"native focas-sim-0i: closing the connection from 127.0.0.1:{local}: frame does not "
        f"start with A0 A0 A0 A0; {why}"
    )


@pytest.mark.parametrize(("limit", "words"), [(1, "1 connection is"), (2, "2 connections are")])
async def test_a_connection_over_the_limit_is_logged_in_plain_english(
    limit: int, words: str, caplog: pytest.LogCaptureFixture
) -> None:
    """It read `refused: 1 connections is the limit`."""
    async with serving(max_connections=limit) as s:
        held = [await asyncio.open_connection(s.host, s.port) for _ in range(limit)]
        with caplog.at_level(logging.WARNING, logger="focas_net.server"):
            reader, writer = await asyncio.open_connection(s.host, s.port)
            with contextlib.suppress(ConnectionResetError):
                assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) == b""
        writer.close()
        for _, w in held:
            w.close()
    (record,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert record.getMessage().endswith(f"refused: {words} the limit")


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_timeout_on_the_command_line_names_the_peer_once(protocol: str) -> None:
    """It read `timed out after 0.5 s (127.0.0.1:PORT): no answer to cnc_rdcncstat (0x0001):
    nothing received since connecting to 127.0.0.1:PORT`, the peer twice."""
    async with serving() as s:
        await ok("sim", "fault", "delay", "--arg", "3000", *at(s))
        line = await fails(
            EXIT_CONNECTION, "status", "--protocol", protocol, "--timeout", "0.5", *at(s)
        )
    assert line.count(f"127.0.0.1:{s.port}") == 1, line
    assert line.startswith("focas-net: timed out after 0.5 s: no answer to "), line


# -- a connection lost, in the client's log -----------------------------------------------------


@pytest.mark.parametrize("native", [False, True])
async def test_a_connection_the_server_closed_is_logged_alike_by_both_clients(
    native: bool, caplog: pytest.LogCaptureFixture
) -> None:
    """The packed client logged `connection to HOST:PORT lost: closed`, the FOCAS/2 one
    `lost: connection closed by HOST:PORT`."""
    async with serving() as s, FocasClient(s.host, s.port, timeout=IO_TIMEOUT) as control:
        cls = NativeClient if native else FocasClient
        async with cls(s.host, s.port, timeout=IO_TIMEOUT) as client:
            await control.sim.inject_fault("drop", scope="machine")
            with caplog.at_level(logging.WARNING, logger="focas_net.client"):
                with pytest.raises(FocasConnectionError) as caught:
                    await client.read_status()
    (record,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    # (in the words the call got: the packed connection had received nothing yet)
    assert record.getMessage() == f"connection to 127.0.0.1:{s.port} lost: {caught.value}"
    assert str(caught.value).startswith(f"connection closed by 127.0.0.1:{s.port}")


# -- a client's limits, in one wording ----------------------------------------------------------


@pytest.mark.parametrize(
    ("make", "why"),
    [
        (lambda: FocasClient("127.0.0.1", max_in_flight=0), "max_in_flight 0 is outside 1..32768"),
        (
            lambda: FocasClient("127.0.0.1", max_in_flight=70000),
            "max_in_flight 70000 is outside 1..32768",
        ),
        (lambda: NativeClient("127.0.0.1", max_blocks=0), "max_blocks 0 is outside 1..65535"),
        (lambda: FocasClient("127.0.0.1", max_frame=3), "max_frame 3 is outside 4..4294967295"),
    ],
)
async def test_a_clients_limit_out_of_range_is_worded_as_every_range(
    make: Callable[[], object], why: str
) -> None:
    """`max_in_flight must be within 1..32768, got 0` and `max_blocks must be within 1..65535,
    got 0`, where `max_frame 3 is outside 4..4294967295` and `port 0 is outside 1..65535`."""
    with pytest.raises(ValueError) as caught:
        make()
    assert str(caught.value) == why


# -- a TLS handshake met by a plain peer --------------------------------------------------------


class _PlainAnswer(LoopbackPeer):
    """A plain peer answering whatever comes with an HTTP error, then closing."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.read(4096)
        writer.write(b"HTTP/1.0 400 Bad Request\r\n\r\n")
        await writer.drain()
        writer.close()


async def test_a_tls_handshake_a_plain_peer_answers_is_worded_without_openssls_source() -> None:
    """It read `TLS handshake failed ([SSL: WRONG_VERSION_NUMBER] wrong version number
    (_ssl.c:1006))`: OpenSSL's code and its C source line."""
    context = ssl.create_default_context()
    context.check_hostname = False
    context.verify_mode = ssl.CERT_NONE
    async with _PlainAnswer() as peer:
        with pytest.raises(FocasConnectionError) as caught:
            async with FocasClient("127.0.0.1", peer.port, ssl=context, timeout=IO_TIMEOUT):
                pass
    assert str(caught.value) == (
        f"cannot connect to 127.0.0.1:{peer.port}: TLS handshake failed (wrong version number): "
        "the peer may not speak TLS"
    )
