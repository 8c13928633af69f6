"""``focas-net sim alarm`` and ``sim panel`` tell what they did, and change only what is given."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest
from support import serving
from test_cli_client import Cli

from focas_net.sim import default_machine


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


async def test_sim_alarm_again_says_it_is_already_active(cli: Cli) -> None:
    out = await cli.ok("sim", "alarm", "PS0100", "AAAA")
    assert out.strip() == "raised PS0100 AAAA"
    out = await cli.ok("sim", "alarm", "PS0100", "BBBB")
    assert out.strip() == (
        "PS0100 is already active: AAAA (a CNC shows one entry per alarm: clear it first to "
        "raise it with another message)"
    )
    data = await cli.json("sim", "alarm", "PS0100", "BBBB")
    assert data == {
        "raised": None,
        "active": {"code": "PS0100", "axis_no": 0, "alm_type": 3, "alm_no": 100, "msg": "AAAA"},
    }
    machine = cli.served.machine
    assert [a.msg for a in machine.active_alarms()] == ["AAAA"]
    assert len(machine.alarm_history()) == 1
    # on another axis it is another alarm
    out = await cli.ok("sim", "alarm", "PS0100", "CCCC", "--axis", "2")
    assert out.strip() == "raised PS0100 (axis 2) CCCC"
