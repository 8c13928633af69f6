"""Transports and hints, a confirming pass (the ninth): servers' limits, peers that close,
hang or send garbage, and the command line's connection hints, in cases the earlier passes
did not try.

Servers here bind 127.0.0.1 on ephemeral ports.
"""

from __future__ import annotations

import pytest

from focas_net.native import LIBRARY_MAX_REQUEST_BODY
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
