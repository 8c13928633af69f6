"""The set-up the capture scripts share (``tests/fwlib_capture.py``, ``fwlib_capture_paths.py``):
the simulator served in a thread of its own, every FOCAS/2 data request and its answer recorded
in order. Checked here without FANUC's library, by a client on this thread's loop."""

from __future__ import annotations

import asyncio
from decimal import Decimal

from fwlib_support import recorded_server

from focas_net.client import NativeClient
from focas_net.server import NativeFront
from focas_net.sim import default_machine


async def _read(port: int) -> Decimal | None:
    async with NativeClient("127.0.0.1", port, timeout=5.0) as client:
        return await client.read_macro(500)


def test_a_recorded_server_records_each_exchange_and_restores_the_front() -> None:
    original = NativeFront.answer
    machine = default_machine()
    machine.write_macro(500, Decimal("1.5"))
    with recorded_server(machine) as recorded:
        assert asyncio.run(_read(recorded.port)) == Decimal("1.5")
        assert recorded.exchanges, "no exchange recorded"
        taken = recorded.take()
        assert all(isinstance(q, bytes) and isinstance(a, bytes) for q, a in taken)
        assert recorded.take() == []  # taken once
        assert recorded.open_response  # what the open of FOCAS/2 was answered
    assert NativeFront.answer is original
