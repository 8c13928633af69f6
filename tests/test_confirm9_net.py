"""Transports and hints, a confirming pass (the ninth): servers' limits, peers that close,
hang or send garbage, and the command line's connection hints, in cases the earlier passes
did not try.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import logging
import struct

import pytest
from cli_support import one_line, run_focas_net
from fwlib_support import LIBRARY, connect, i32, s16
from support import IO_TIMEOUT, LoopbackPeer, sent_until_closed, serving, the_warning

from focas_net.adapters import NativeAdapter
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import FocasConnectionError, FocasTimeoutError, ProtocolError
from focas_net.native import (
    DEFAULT_MAX_BODY,
    LIBRARY_MAX_REQUEST_BODY,
    MAGIC_WORD,
    NATIVE_HEADER,
    PROGRAM_CHUNK,
    FrameType,
    NativeFrameDecoder,
)
from focas_net.server import FocasServer, NativeServer
from focas_net.sim import default_machine


@pytest.mark.parametrize("limit", [0, 1, 12, 64, LIBRARY_MAX_REQUEST_BODY - 1])
def test_a_native_body_limit_below_the_librarys_largest_request_is_refused(limit: int) -> None:
    """With such a limit every FOCAS/2 request closed the connection, and the client saw only
    "connection closed by ... before any answer"."""
    for build, name in (
        (lambda: FocasServer(default_machine(), port=0, native_max_body=limit), "native_max_body"),
        (lambda: NativeServer(default_machine(), max_body=limit), "max_body"),
    ):
        with pytest.raises(ValueError) as caught:
            build()
        assert str(caught.value) == (
            f"{name} must be within 1450..65535, got {limit}: FANUC's library sends request "
            "bodies of up to 1450 bytes (a PMC write is cut into requests of that size)"
        )


def test_the_librarys_largest_request_is_a_body_limit_both_servers_take() -> None:
    assert LIBRARY_MAX_REQUEST_BODY == 1450
    assert FocasServer(default_machine(), port=0, native_max_body=1450).limits.max_body == 1450
    assert NativeServer(default_machine(), max_body=1450).max_body == 1450


@pytest.mark.parametrize(("version", "max_body"), [(5, DEFAULT_MAX_BODY), (3, 1450), (2, 1450)])
async def test_a_long_pmc_write_keeps_each_request_within_the_librarys_size(
    version: int, max_body: int
) -> None:
    """The client cut a PMC write into requests as long as the answer version allows (4950
    bytes at version 5): a server of the default 4096-byte limit closed the connection, and
    the write failed as "connection closed". FANUC's library cuts it at 1450 whatever the
    version (1420 data bytes a request), and so does the client now."""
    data = bytes(i % 251 for i in range(6000))
    machine = default_machine()
    async with (
        FocasServer(machine, port=0, native_version=version, native_max_body=max_body) as server,
        NativeClient("127.0.0.1", server.listeners[0].port, timeout=IO_TIMEOUT) as client,
    ):
        await client.write_pmc("D", 0, data)
        assert client.frames_sent == 5  # 6000 bytes, 1420 a request
        assert await client.read_pmc("D", 0, len(data)) == data


class _OpenAnswering(LoopbackPeer):
    """A FOCAS/2 peer answering each open request with ``frame`` (header and body), and
    nothing else."""

    def __init__(self, frame: bytes) -> None:
        self.frame = frame

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            await reader.readexactly(12)  # the open request
            writer.write(self.frame)
            await writer.drain()
            await reader.read(1)  # until the client closes
        finally:
            writer.close()


_V3_OPEN = NativeAdapter(default_machine()).open_answer()


@pytest.mark.parametrize(
    ("frame", "why"),
    [
        (
            NATIVE_HEADER.pack(MAGIC_WORD, 3, FrameType.OPEN_RESPONSE, 0),
            "open answer refused: open answer of 0 bytes at version 3, shorter than the 12 "
            "bytes that hold its path count; it sent A0 A0 A0 A0 00 03 01 02",
        ),
        (
            NATIVE_HEADER.pack(MAGIC_WORD, 3, FrameType.OPEN_RESPONSE, 20) + _V3_OPEN[:20],
            "open answer refused: open answer of 20 bytes at version 3, not the 72 bytes its "
            "path count of 1 makes; it sent A0 A0 A0 A0 00 03 01 02",
        ),
        (
            NATIVE_HEADER.pack(MAGIC_WORD, 3, FrameType.DATA_RESPONSE, len(_V3_OPEN)) + _V3_OPEN,
            "its answer to the open is a frame of type 0x2102; it sent A0 A0 A0 A0 00 03 21 02",
        ),
    ],
)
async def test_an_open_answer_the_library_refuses_is_a_peer_not_speaking_focas2(
    frame: bytes, why: str
) -> None:
    """FANUC's library refuses such an open answer as it refuses a data answer of no block
    (EW_PROTOCOL); the client said `open answer refused: ... expected None` (a Python None)
    or `answered the open with type 0x2102`, a connection error (exit 3), where a refused data
    answer is a peer that does not speak the FOCAS protocol (exit 4)."""
    async with _OpenAnswering(frame) as peer:
        with pytest.raises(ProtocolError) as caught:
            async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT):
                pass
        assert str(caught.value) == (
            f"127.0.0.1:{peer.port} does not speak the FOCAS protocol ({why})"
        )
        code, out, err = await run_focas_net(
            "status", "--protocol", "native", "--port", str(peer.port)
        )
        assert (code, out) == (4, "")
        assert one_line(err) == f"focas-net: {caught.value}"


class _PmcMisanswering(LoopbackPeer):
    """A FOCAS/2 peer of the default machine that answers a PMC read twice (``twice``) or
    never (else); everything else as the simulator."""

    def __init__(self, twice: bool) -> None:
        self.twice = twice
        self.adapter = NativeAdapter(default_machine())

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        decoder = NativeFrameDecoder()
        try:
            for _ in range(100):
                data = await reader.read(65536)
                if not data:
                    return
                for frame in decoder.feed(data):
                    if frame.type == FrameType.OPEN_REQUEST:
                        writer.write(self.adapter.open_response())
                        continue
                    answer = self.adapter.answer(frame.body)
                    if frame.body[8:10] == b"\x80\x01":  # the first block's command
                        if not self.twice:
                            continue
                        answer += answer
                    writer.write(answer)
        finally:
            writer.close()


async def test_bytes_no_request_asked_for_name_the_peer_that_sent_them() -> None:
    """A read of three chunks whose first answer came twice failed with `bytes no request
    asked for (the request was never sent)`, naming no peer."""
    async with (
        _PmcMisanswering(twice=True) as peer,
        NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as client,
    ):
        with pytest.raises(FocasConnectionError) as caught:
            await client.read_pmc("D", 0, 8000)
    assert str(caught.value) == (
        f"127.0.0.1:{peer.port} sent bytes no request asked for (the request was never sent)"
    )


async def test_a_chunked_read_left_unanswered_names_the_chunk_that_was_sent() -> None:
    """The first chunk went out and was never answered, the others waited behind it: the read
    failed with `no answer to pmc_rdpmcrng (the request was never sent)`, a later chunk's
    words, as if nothing had been sent."""
    async with (
        _PmcMisanswering(twice=False) as peer,
        NativeClient("127.0.0.1", peer.port, timeout=0.5) as client,
    ):
        with pytest.raises(FocasTimeoutError) as caught:
            await client.read_pmc("D", 0, 8000)
    assert "never sent" not in str(caught.value)
    assert str(caught.value).endswith("no answer to pmc_rdpmcrng")


@pytest.mark.parametrize(
    ("sent", "why"),
    [
        (struct.pack("<I", 0), "frame length 0 outside 4..65536"),
        (
            b"\x16\x03\x01\x00\x05hello",
            "frame length 66326 outside 4..65536; it sent a TLS record: a TLS client, on a port "
            "that does not serve TLS",
        ),
        (
            b"\xa0\xa0\xa0\xa0\x00\x01\x01\x01\x00\x03\x00\x01\x00",
            "open request body: 3 bytes, expected 2",
        ),
    ],
)
async def test_a_closed_connection_is_logged_with_its_peer_as_host_port_on_both_protocols(
    sent: bytes, why: str, caplog: pytest.LogCaptureFixture
) -> None:
    """The packed side logged `focas-sim-0i: framing violation from ('127.0.0.1', 52948): ...;
    closing the connection` (a Python tuple), the FOCAS/2 side `native focas-sim-0i: closing
    the connection from 127.0.0.1:45130: OpenRequest: 3 bytes, expected 2` (a class name)."""
    async with FocasServer(default_machine(), port=0) as server:
        local = await sent_until_closed(server.listeners[0].port, sent, caplog)
    label = "native focas-sim-0i" if sent.startswith(b"\xa0") else "focas-sim-0i"
    assert the_warning(caplog) == f"{label}: closing the connection from 127.0.0.1:{local}: {why}"


async def test_a_connection_over_the_limit_is_logged_with_its_peer_as_host_port(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """It read `connection from ('127.0.0.1', 50000) refused: ...` (a Python tuple)."""
    async with FocasServer(default_machine(), port=0, max_connections=1) as server:
        port = server.listeners[0].port
        _, first = await asyncio.open_connection("127.0.0.1", port)
        with caplog.at_level(logging.WARNING, logger="focas_net.server"):
            reader, second = await asyncio.open_connection("127.0.0.1", port)
            local = second.get_extra_info("sockname")[1]
            with contextlib.suppress(ConnectionResetError):
                assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) == b""
        first.close()
        second.close()
    (record,) = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert record.getMessage().startswith(
        f"focas-sim-0i: connection from 127.0.0.1:{local} refused: "
    )


@pytest.mark.skipif(
    not LIBRARY,
    reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 (e.g. libfwlib32.so.1) "
    "to run FANUC's library against the simulator",
)
@pytest.mark.parametrize("version", [2, 3, 5])
async def test_the_library_writes_and_downloads_within_the_smallest_body_limit(
    version: int,
) -> None:
    """FANUC's library cuts a long PMC write into requests of 1450 body bytes and a download
    into data frames of 1280, whatever the answer version: a server of the smallest limit
    it accepts takes both."""
    data = bytes(i % 251 for i in range(6000))
    program = "O0777\n" + "".join(f"N{n} G0 X{n}.\n" for n in range(1, 500)) + "M30\n"
    async with serving(native_max_body=LIBRARY_MAX_REQUEST_BODY, native_version=version) as served:
        handle = await connect(served)
        try:
            # IODBPMC: D (9), bytes (0), 0..5999, then the bytes
            head = struct.pack("<hhhh", 9, 0, 0, len(data) - 1)
            iodbpmc = ctypes.create_string_buffer(head + data)
            assert await handle.call("pmc_wrpmcrng", s16(8 + len(data)), iodbpmc) == 0
            assert served.machine.read_pmc("D", 0, len(data)) == data
            assert len(program) > 4 * PROGRAM_CHUNK
            assert await handle.call("cnc_dwnstart3", s16(0)) == 0
            text = ("\n" + program + "%").encode()
            n = i32(len(text))
            piece = ctypes.create_string_buffer(text)
            assert await handle.call("cnc_download3", ctypes.byref(n), piece) == 0
            assert await handle.call("cnc_dwnend3") == 0
        finally:
            await handle.free()
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed:
            assert await packed.read_program(777) == program


async def test_serve_help_does_not_promise_focas2_on_a_tls_main_port() -> None:
    """`--native-port` said `off by default (the main port speaks it anyway)`, also with
    `--tls-cert`, where the main port speaks TLS, which no FOCAS/2 client does."""
    code, out, _ = await run_focas_net("serve", "--help")
    assert code == 0
    words = " ".join(out.split())
    assert "(the main port speaks it too, unless --tls-cert makes it TLS" in words
