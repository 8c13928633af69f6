"""Transports and hints, eleventh pass: the gateway's advice for a machine it cannot talk to
(a TLS port, a port of FOCAS/2 alone), in the file's keys and as the command line gives it; a
server that wants a client certificate; peers that misbehave (half answers, wrong lengths, a
reset mid-frame, slow answers) and the deadlines of both clients; the server's log of odd
clients.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import ssl
from dataclasses import replace
from pathlib import Path
from typing import Literal

import pytest
from cli_support import fails
from poller_support import QUICK, RecordingSink, config
from support import serving, wait_until

from focas_net.cli import EXIT_CONNECTION
from focas_net.gateway import Gateway, GatewayConfig


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
