"""Transports and hints, ninth pass: a path the CNC does not have, a reconnect policy whose
delays are the wrong way round, the words of a failed reconnect in the log, and an HTTP
server met by a client that reconnects.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import logging
from dataclasses import replace
from pathlib import Path
from typing import Any, Literal

import pytest
from cli_support import at, fails
from poller_support import QUICK, RecordingSink, config
from support import IO_TIMEOUT, free_port, serving, wait_until

from focas_net.cli import EXIT_CONNECTION, EXIT_USAGE
from focas_net.client import FocasClient, NativeClient, ReconnectPolicy
from focas_net.errors import EW, CncError
from focas_net.gateway import Gateway, GatewayConfig
from focas_net.sim import Machine


@pytest.mark.parametrize("call", ["read_status", "read_feed", "read_spindle_speed"])
async def test_a_path_beyond_the_cncs_is_named_alike_by_both_clients(
    both_clients: tuple[Machine, FocasClient, NativeClient], call: str
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as caught:
            await getattr(client, call)(path=3)
        assert caught.value.ew == EW.PATH
        assert str(caught.value).endswith("the CNC has no path 3: it has path 1 only"), caught.value
    # the next call on a path the CNC has is answered as before
    assert (await cnc.read_status()).run is not None


async def test_a_path_the_cnc_has_but_refused_keeps_the_refusal_as_it_came(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, _ = both_clients
    assert (await cnc.read_status(path=1)).run is not None


@pytest.mark.parametrize(("initial", "maximum"), [(5, 1), (0.2, 0.1), (10.5, 10)])
def test_a_reconnect_policy_whose_first_delay_exceeds_its_cap_is_refused(
    initial: float, maximum: float
) -> None:
    with pytest.raises(ValueError) as caught:
        ReconnectPolicy(initial_delay=initial, max_delay=maximum)
    text = str(caught.value)
    assert f"initial_delay {initial}" in text
    assert f"max_delay {maximum}" in text


def test_equal_delays_are_a_constant_backoff() -> None:
    policy = ReconnectPolicy(initial_delay=1, max_delay=1, jitter=0)
    assert [policy.delay(n) for n in range(3)] == [1, 1, 1]


async def test_a_reconnect_task_that_failed_is_logged_in_words_not_as_a_repr(
    both_clients: tuple[Machine, FocasClient, NativeClient],
    caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    _, cnc, _ = both_clients
    client = FocasClient(cnc.host, cnc.port, reconnect=ReconnectPolicy(initial_delay=0))
    await client.connect()

    async def fails(attempt: int) -> bool:
        raise ConnectionResetError(errno.ECONNRESET, "Connection reset by peer")

    monkeypatch.setattr(client, "_reconnect_attempt", fails)
    client._reconnecting(None)
    task = client._reconnect_task
    assert task is not None
    await asyncio.wait([task], timeout=5)
    with caplog.at_level(logging.WARNING):
        await client.aclose()
    lines = [r.getMessage() for r in caplog.records if "reconnect to" in r.getMessage()]
    assert lines, caplog.text
    assert all("Error(" not in line and "Errno" not in line for line in lines), lines
    assert any("connection reset by peer" in line for line in lines), lines


@pytest.mark.parametrize("client_type", [FocasClient, NativeClient])
async def test_a_reconnect_attempt_failing_oddly_is_logged_in_words(
    both_clients: tuple[Machine, FocasClient, NativeClient],
    caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
    client_type: type[FocasClient] | type[NativeClient],
) -> None:
    _, cnc, _ = both_clients
    client = client_type(cnc.host, cnc.port, reconnect=ReconnectPolicy(initial_delay=0))
    await client.connect()
    try:

        async def odd(*args: object, **kwargs: object) -> object:
            raise ConnectionResetError(errno.ECONNRESET, "Connection reset by peer")

        name = "_open" if client_type is FocasClient else "open_handle"
        if client_type is FocasClient:
            monkeypatch.setattr(client, name, odd)
        else:
            monkeypatch.setattr("focas_net.client._native_link.open_handle", odd)
        with caplog.at_level(logging.DEBUG, logger="focas_net"):
            assert await client._reconnect_attempt(1) is False
        lines = [r.getMessage() for r in caplog.records if "reconnect attempt" in r.getMessage()]
        assert lines, caplog.text
        assert all("Error(" not in line and "Errno" not in line for line in lines), lines
        assert any("connection reset by peer" in line for line in lines), lines
    finally:
        await client.aclose()


# -- an HTTP server met by a station that reconnects --------------------------------------------
async def _http(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    with contextlib.suppress(OSError, asyncio.IncompleteReadError):
        await reader.readuntil(b"\r\n\r\n")  # (a FOCAS frame never ends a request line)
        writer.write(b"HTTP/1.0 404 Not Found\r\n\r\n")
        await writer.drain()
    writer.close()


@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_an_http_server_met_after_the_first_attempt_is_named_as_on_the_first(
    protocol: Literal["native", "packed"], caplog: pytest.LogCaptureFixture
) -> None:
    port = free_port()
    sink = RecordingSink()
    station = replace(config("web", port, protocol), timeout=0.5)
    gateway = Gateway(GatewayConfig((station,)), policy=QUICK)
    gateway.add_sink(sink)
    named = f"web: protocol: 127.0.0.1:{port} does not speak the FOCAS protocol (it answers "
    named += "'HTTP/1.0 404' to an HTTP request and no FOCAS frame: an HTTP server)"
    server: asyncio.Server | None = None
    try:
        with caplog.at_level(logging.INFO, logger="focas_net.gateway"):
            async with gateway:
                await wait_until(lambda: any(not up for _, up, _ in sink.states))
                assert "refused" in sink.states[-1][2], sink.states
                server = await asyncio.start_server(_http, "127.0.0.1", port)
                await wait_until(lambda: named in caplog.messages)
    finally:  # the server closes after the gateway, which holds no connection to it then
        if server is not None:
            server.close()
            async with asyncio.timeout(IO_TIMEOUT):
                await server.wait_closed()
    # (each attempt's failure is logged; the first one told the sinks the machine is offline)
    assert "refused" in sink.states[0][2]


# -- a host of spaces alone, as each front end names it ------------------------------------------
@pytest.mark.parametrize("typed", [" ", "\t"])
async def test_a_host_of_spaces_alone_is_named_as_typed_on_every_front_end(typed: str) -> None:
    said = await fails(EXIT_USAGE, "status", "--host", typed, "--port", "1", prefix="focas-net")
    with pytest.raises(ValueError) as refused:
        FocasClient(typed, 1)
    assert f"empty host {typed!r}" in str(refused.value)
    assert said == (
        f"focas-net status: error: argument --host: {refused.value}; see focas-net status --help"
    )


# -- a request longer than the server takes: the hint names --max-frame too ----------------------
async def test_a_request_longer_than_the_servers_max_frame_is_not_blamed_on_a_drop_alone(
    tmp_path: Path,
) -> None:
    program = tmp_path / "o1234.nc"
    program.write_text("O1234\nG0 X1.\nM30\n%\n")
    async with serving(max_frame=8) as served:
        said = await fails(EXIT_CONNECTION, "program", "load", str(program), *at(served))
    assert said == (
        f"focas-net: connection closed by 127.0.0.1:{served.port} before any answer; the server "
        "answers a new connection, so it closed this one on purpose (as a drop fault does: "
        "focas-net sim fault drop), or as a server does with a request longer than it takes "
        "(focas-net serve --max-frame)"
    )


# -- a path the CNC lacks is named before an axis of it, and by every path-taking call -----------
@pytest.mark.parametrize(
    ("call", "function"),
    [
        (lambda c: c.read_param(1420, axis=1, path=3), "cnc_rdparam"),
        (lambda c: c.write_param(1420, 8000, axis=1, path=3), "cnc_wrparam"),
        (lambda c: c.read_positions(axis=1, path=3), "cnc_rdposition"),
    ],
)
async def test_an_axis_of_a_path_the_cnc_lacks_is_refused_for_the_path(
    both_clients: tuple[Machine, FocasClient, NativeClient], call: Any, function: str
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as caught:
            await call(client)
        assert caught.value.ew == EW.PATH, caught.value
        assert str(caught.value).endswith(f"{function}: the CNC has no path 3: it has path 1 only")


async def test_the_alarms_of_a_path_the_cnc_lacks_are_refused_alike(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as caught:
            await client.read_alarms(path=2)
        assert caught.value.ew == EW.PATH
        assert str(caught.value).endswith("the CNC has no path 2: it has path 1 only"), caught.value
