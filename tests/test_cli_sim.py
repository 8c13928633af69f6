"""``focas-net sim alarm`` and ``sim panel`` tell what they did, and change only what is given."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest
from cli_support import Cli
from support import serving

from focas_net.client import FocasClient, PanelSwitches
from focas_net.errors import EW, CncError
from focas_net.protocol import AutMode, FaultKind
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


async def test_sim_panel_changes_only_the_switches_given(cli: Cli) -> None:
    machine = cli.served.machine
    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    assert (machine.panel.mode, machine.panel.pwe, machine.panel.emergency) == (0, 1, 0)
    out = await cli.ok("sim", "panel", "--emergency", "on")
    assert (machine.panel.mode, machine.panel.pwe, machine.panel.emergency) == (0, 1, 1)
    assert out.startswith("mode=MDI ") and "emergency=EMG" in out and out.endswith(" pwe=on\n")
    await cli.ok("sim", "panel", "--pwe", "off")
    assert (machine.panel.mode, machine.panel.pwe, machine.panel.emergency) == (0, 0, 1)


async def test_bare_sim_panel_reads_without_writing(cli: Cli) -> None:
    machine = cli.served.machine
    machine.set_panel(0, 1, 0)
    version = machine.version
    out = await cli.ok("sim", "panel")
    assert out.startswith("mode=MDI ") and "emergency=****" in out and out.endswith(" pwe=on\n")
    data = await cli.json("sim", "panel")
    assert (data["mode"], data["pwe"], data["emergency"]) == (0, 1, 0)
    assert data["status"]["mode"]["name"] == "MDI"
    assert machine.version == version


async def test_client_set_panel_leaves_what_is_not_given(cli: Cli) -> None:
    served = cli.served
    async with FocasClient(served.host, served.port) as cnc:
        await cnc.sim.set_panel("MDI", pwe=True)
        await cnc.sim.set_panel(emergency=True)
        assert await cnc.sim.read_panel() == PanelSwitches(AutMode.MDI, pwe=True, emergency=True)
        await cnc.sim.set_panel("EDIT")
        panel = await cnc.sim.read_panel()
        assert (panel.mode, panel.pwe, panel.emergency) == (AutMode.EDIT, True, True)


async def test_read_panel_is_a_control_answer_never_faulted(cli: Cli) -> None:
    served = cli.served
    async with FocasClient(served.host, served.port) as cnc:
        await cnc.sim.inject_fault(FaultKind.ERROR, arg=int(EW.BUSY))
        panel = await cnc.sim.read_panel()  # not faulted, and the fault stays armed
        assert panel.mode == AutMode.MEM
        with pytest.raises(CncError) as exc:
            await cnc.read_status()
        assert exc.value.ew == EW.BUSY
