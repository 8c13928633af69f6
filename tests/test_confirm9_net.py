"""Transports and hints, a confirming pass (the ninth): servers' limits, peers that close,
hang or send garbage, and the command line's connection hints, in cases the earlier passes
did not try.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import pytest
from support import IO_TIMEOUT

from focas_net.client import NativeClient
from focas_net.native import DEFAULT_MAX_BODY, LIBRARY_MAX_REQUEST_BODY
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
