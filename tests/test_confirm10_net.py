"""Transports and hints, a confirming pass (the tenth): the server's log of a plain client on
a port that serves TLS, the gateway's TLS connection error in plain words, a connect timeout
worded once, and a NaN timeout named as not a number.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import asyncio
import logging
import math
import shutil
import ssl
import subprocess
from pathlib import Path

import pytest
from cli_support import at, fails, run_focas_net
from poller_support import Silent
from support import IO_TIMEOUT, LoopbackPeer, serving

from focas_net.cli import EXIT_CONNECTION
from focas_net.client import AlarmProjection, FocasClient, NativeClient, ReconnectPolicy
from focas_net.gateway.config import MqttSettings
from focas_net.gateway.mqtt import MqttSink
from focas_net.native import MAGIC
from focas_net.protocol import Command, encode_frame
from focas_net.server import FocasServer

# -- a plain client on a port that serves TLS --------------------------------------------------


def _server_context(certificate: tuple[Path, Path]) -> ssl.SSLContext:
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(*certificate)
    return context


async def _warnings_for(
    sent: bytes, certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> tuple[int, list[str]]:
    """The server's warnings about a client that sends ``sent`` to its TLS port, and the
    client's own port."""
    with caplog.at_level(logging.WARNING, logger="focas_net.server"):
        async with serving(ssl=_server_context(certificate)) as s:
            reader, writer = await asyncio.open_connection(s.host, s.port)
            local = writer.get_extra_info("sockname")[1]
            writer.write(sent)
            assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) is not None
            writer.close()
            # a TLS client is still served
            context = ssl.create_default_context(cafile=str(certificate[0]))
            async with FocasClient(s.host, s.port, ssl=context, timeout=IO_TIMEOUT) as cnc:
                await cnc.read_status()
    return local, [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]


@pytest.mark.parametrize(
    ("sent", "why"),
    [
        (
            encode_frame(Command.RDCNCSTAT, 1, b""),
            "it sent no TLS handshake: a plain client, on a port that serves TLS",
        ),
        (
            MAGIC + bytes(6),
            "it sent no TLS handshake: a plain client, on a port that serves TLS",
        ),
        (
            b"GET / HTTP/1.1\r\nHost: cnc\r\n\r\n",
            "it sent an HTTP request: a plain HTTP client, on a port that serves TLS",
        ),
        (
            b"CONNECT cnc:8193 HTTP/1.1\r\n\r\n",
            "it sent an HTTP request: a plain HTTP client, on a port that serves TLS",
        ),
        (
            b"SSH-2.0-OpenSSH_9.6\r\n",
            "it sent no TLS handshake: a plain client, on a port that serves TLS",
        ),
    ],
)
async def test_a_plain_client_on_a_tls_port_is_named_in_the_servers_log(
    sent: bytes, why: str, certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> None:
    """`status --port <TLS port>` against `serve --tls-cert ...` left nothing in the server's
    log: asyncio dropped the failed handshake at its debug level."""
    local, warnings = await _warnings_for(sent, certificate, caplog)
    assert warnings == [f"focas-sim-0i: closing the connection from 127.0.0.1:{local}: {why}"]


async def test_a_tls_handshake_that_fails_otherwise_says_why_in_openssls_words(
    certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> None:
    """A TLS record that is no handshake: OpenSSL's reason, without its code and source."""
    local, warnings = await _warnings_for(b"\x15\x03\x01\x00\x02\x02\x46", certificate, caplog)
    assert warnings == [
        f"focas-sim-0i: closing the connection from 127.0.0.1:{local}: TLS handshake failed "
        "(unexpected message)"
    ]


def test_a_plain_client_on_a_tls_port_is_named_on_uvloop_too(
    certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> None:
    pytest.importorskip("uvloop")
    import anyio

    async def main() -> tuple[int, list[str]]:
        return await _warnings_for(encode_frame(Command.RDCNCSTAT, 1, b""), certificate, caplog)

    local, warnings = anyio.run(main, backend="asyncio", backend_options={"use_uvloop": True})
    assert warnings == [
        f"focas-sim-0i: closing the connection from 127.0.0.1:{local}: it sent no TLS "
        "handshake: a plain client, on a port that serves TLS"
    ]


async def test_a_handshake_under_way_ends_with_the_server(
    certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> None:
    """A client that connected and sent nothing: its handshake task is cancelled at shutdown
    and its socket closed, nothing logged above DEBUG."""
    with caplog.at_level(logging.DEBUG, logger="focas_net.server"):
        async with serving(ssl=_server_context(certificate)) as s:
            reader, writer = await asyncio.open_connection(s.host, s.port)
            listener = s.server.listeners[0]
            for _ in range(100):  # (bounded: the accept is one loop turn away)
                if listener._handshakes:
                    break
                await asyncio.sleep(0.01)
            assert len(listener._handshakes) == 1
        assert await asyncio.wait_for(reader.read(), IO_TIMEOUT) == b""
        writer.close()
    assert not listener._handshakes
    assert [r.getMessage() for r in caplog.records if r.levelno > logging.INFO] == []


async def test_a_tls_client_that_closes_at_once_leaves_no_asyncio_warning(
    certificate: tuple[Path, Path], caplog: pytest.LogCaptureFixture
) -> None:
    """A client (the command line's probe) that closes right after its handshake: asyncio
    warned `returning true from eof_received() has no effect when using ssl`."""
    context = ssl.create_default_context(cafile=str(certificate[0]))
    with caplog.at_level(logging.DEBUG):
        async with serving(ssl=_server_context(certificate)) as s:
            for _ in range(20):  # (the close must meet the hand-over: tried a few times)
                _, writer = await asyncio.open_connection(s.host, s.port, ssl=context)
                writer.close()
                await writer.wait_closed()
            async with FocasClient(s.host, s.port, ssl=context, timeout=IO_TIMEOUT) as cnc:
                await cnc.read_status()
    assert [r.getMessage() for r in caplog.records if r.name == "asyncio"] == []


# -- the gateway's MQTT broker over TLS, on a plain port ----------------------------------------


class _PlainAnswer(LoopbackPeer):
    """Answers whatever comes with a line of plain text (a port that does not speak TLS)."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.read(1)
        writer.write(b"HTTP/1.1 400 Bad Request\r\n\r\n")
        await writer.drain()
        writer.close()


async def test_a_tls_broker_on_a_plain_port_is_worded_without_openssls_code(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """It read `[SSL: WRONG_VERSION_NUMBER] wrong version number (_ssl.c:1000) (tls = true:
    ...)`: OpenSSL's code and its C source line, where the clients say `TLS handshake failed
    (wrong version number)`."""
    caplog.set_level(logging.WARNING, logger="focas_net.gateway.mqtt")
    async with _PlainAnswer() as peer:
        settings = MqttSettings(host="127.0.0.1", port=peer.port, tls=True)
        async with MqttSink(settings, reconnect=(5.0, 5.0), timeout=2.0):
            for _ in range(2000):  # bounded: 20 s
                warned = [r.getMessage() for r in caplog.records if r.name.endswith("mqtt")]
                if warned:
                    break
                await asyncio.sleep(0.01)
    assert warned[:1] == [
        f"MQTT broker 127.0.0.1:{peer.port}: TLS handshake failed (wrong version number) "
        "(tls = true: is that the broker's TLS port?)"
    ]


# -- a connect that times out, on the command line ---------------------------------------------


async def test_a_connect_that_times_out_says_timed_out_once() -> None:
    """It read `timed out after 0.3 s: connecting to 127.0.0.1:PORT timed out`."""
    async with Silent() as peer:  # (TCP accepted, the TLS handshake never answered)
        line = await fails(
            EXIT_CONNECTION, "status", *at(peer), "--tls-insecure", "--timeout", "0.3"
        )
    assert line.startswith(
        f"focas-net: connecting to 127.0.0.1:{peer.port} timed out after 0.3 s"
    ), line
    assert line.count("timed out") == 1, line


# -- a NaN where a number of seconds is wanted --------------------------------------------------


@pytest.mark.parametrize("client", [FocasClient, NativeClient])
async def test_a_nan_timeout_is_named_not_a_number(client: type[FocasClient]) -> None:
    """It read `timeout must be positive, got nan`: as if NaN were a number below zero."""
    said = "timeout must be a positive number of seconds, got nan (not a number)"
    with pytest.raises(ValueError) as caught:
        client("127.0.0.1", 8193, timeout=math.nan)
    assert str(caught.value) == said
    unconnected = client("127.0.0.1", 8193)  # (a call's own timeout, checked first)
    with pytest.raises(ValueError) as caught:
        await unconnected.read_status(timeout=math.nan)
    assert str(caught.value) == said


def test_every_api_names_a_nan_number_of_seconds_alike() -> None:
    """The server, the reconnect policy and the alarm projection: one wording."""
    with pytest.raises(ValueError) as caught:
        FocasServer(port=0, idle_timeout=math.nan)
    assert str(caught.value) == "idle_timeout must be a number of seconds, got nan (not a number)"
    with pytest.raises(ValueError) as caught:
        ReconnectPolicy(max_delay=math.nan)
    assert str(caught.value) == "max_delay must be a number, got nan (not a number)"
    with pytest.raises(ValueError) as caught:
        AlarmProjection(FocasClient("127.0.0.1", 8193), interval=math.nan)
    assert str(caught.value) == (
        "interval must be a positive, finite number of seconds, got nan (not a number)"
    )


# -- serve --tls-key with a key under a pass phrase ----------------------------------------------


@pytest.fixture(params=["--tls-key", "--tls-cert"])
def locked(
    request: pytest.FixtureRequest, certificate: tuple[Path, Path], tmp_path: Path
) -> tuple[list[str], str, Path]:
    """The certificate fixture's key encrypted under the pass phrase ``x``, in a file of its
    own (``--tls-key``) or after the certificate (``--tls-cert`` alone): the options of
    serve, the option named and the file."""
    openssl = shutil.which("openssl")
    assert openssl is not None  # (the certificate fixture needs it too)
    cert, key = certificate
    locked = tmp_path / "locked.pem"
    subprocess.run(
        [openssl, "pkey", "-in", str(key), "-out", str(locked), "-aes256", "-passout", "pass:x"],
        check=True, capture_output=True, timeout=60,
    )  # fmt: skip
    if request.param == "--tls-key":
        return ["--tls-cert", str(cert), "--tls-key", str(locked)], request.param, locked
    locked.write_text(cert.read_text() + locked.read_text())
    return ["--tls-cert", str(locked)], request.param, locked


async def test_a_private_key_under_a_pass_phrase_is_named_without_a_prompt(
    locked: tuple[list[str], str, Path],
) -> None:
    """OpenSSL asked `Enter PEM pass phrase:` on the terminal (twice), then the command said
    `TLS certificate/key (c.pem, k.pem): invalid argument`."""
    options, flag, path = locked
    code, out, err = await run_focas_net("serve", "--port", "0", *options)
    assert (code, out) == (2, "")
    assert err == (
        f"focas-net serve: error: {flag} {path}: its private key is encrypted (under a pass "
        "phrase), which serve cannot ask for: give it unencrypted (openssl pkey -in "
        f"{path} -out KEY.pem)\n"
    )
