"""A communication error answered to a read (EW_SOCKET, EW_HANDLE) is a lost connection, as
FANUC's practice has it (free the handle, connect again), not one read's error: the machine is
lost, its client closed and a new one connected. Another EW code stays one read's. A simulated
machine on 127.0.0.1; the poller stepped by hand on a ManualClock."""

from __future__ import annotations

import pytest
from poller_support import QUICK, RecordingSink, all_online, config, until
from support import serving

from focas_net.client import ClientState, FocasClient
from focas_net.errors import EW, ew_info
from focas_net.gateway.poller import Poller
from focas_net.protocol import FaultKind, FaultScope
from focas_net.sim.nc import ManualClock


async def fault(port: int, code: int) -> None:
    """The machine's next answer, on any connection, is EW code ``code``."""
    async with FocasClient("127.0.0.1", port) as packed:
        await packed.sim.inject_fault(FaultKind.ERROR, count=1, arg=code, scope=FaultScope.MACHINE)


@pytest.mark.parametrize("code", [EW.SOCKET, EW.HANDLE])
async def test_a_communication_error_on_a_read_is_a_lost_connection(code: EW) -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with serving() as one:
        async with Poller([config("one", one.port)], [sink], clock=clock.now, policy=QUICK) as p:
            await until(p, clock, all_online(p))
            first = p.client("one")
            await fault(one.port, int(code))
            await until(p, clock, lambda: p.is_online("one") is False, step=1.0)
            lost = [reason for name, up, reason in sink.states if not up]
            assert len(lost) == 1 and code.name in lost[0]
            await until(p, clock, all_online(p), step=1.0)
            assert p.client("one") is not first  # the handle freed, a new one connected
            assert first.state is ClientState.CLOSED
            assert p.client("one").state is ClientState.CONNECTED


async def test_another_ew_code_on_a_read_is_that_reads_error() -> None:
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with serving() as one:
        async with Poller([config("one", one.port)], [sink], clock=clock.now, policy=QUICK) as p:
            await until(p, clock, all_online(p))
            first = p.client("one")
            await fault(one.port, int(EW.BUSY))
            for _ in range(5):
                clock.advance(1.0)
                await p.step()
            assert p.is_online("one") and p.client("one") is first
            assert all(up for _, up, _ in sink.states)
            busy = ew_info(EW.BUSY).opcua
            assert any(s.status == busy for s in sink.got)  # the read it hit: that read's status
