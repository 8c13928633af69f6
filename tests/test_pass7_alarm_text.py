"""An alarm raised without a message shows the message of the control's alarm table, as the
same alarm raised by a part program does (PS0010 ``IMPROPER G-CODE`` from ``G999`` and from
``sim alarm PS0010`` alike); a number the table has not stays without one; a message given
is kept as given. The command line prints what the machine kept."""

from __future__ import annotations

import pytest
from cli_support import ok
from support import serving

from focas_net.sim import default_machine
from focas_net.sim.nc import ALARM_MESSAGES, AlarmKind, ManualClock


@pytest.mark.parametrize(("kind", "number"), sorted(ALARM_MESSAGES, key=str)[:8])
def test_an_alarm_raised_without_a_message_has_the_tables(kind: AlarmKind, number: int) -> None:
    machine = default_machine()
    alm_type = {AlarmKind.PS: 3, AlarmKind.OT: 4}[kind]
    axis = 1 if kind is AlarmKind.OT else 0
    assert machine.raise_alarm(axis, alm_type, number)
    (alarm,) = machine.active_alarms()
    assert alarm.msg == ALARM_MESSAGES[(kind, number)]


def test_a_number_the_table_has_not_and_a_given_message() -> None:
    machine = default_machine()
    machine.raise_alarm(0, 6, 411)  # SV0411: no text in the simulated control's table
    machine.raise_alarm(0, 3, 10, "MY OWN TEXT")
    assert [(a.alm_no, a.msg) for a in machine.active_alarms()] == [(411, ""), (10, "MY OWN TEXT")]


def test_a_program_error_and_sim_alarm_show_the_same_text() -> None:
    by_program = default_machine(sim_clock=ManualClock())
    by_program.select_program(by_program.store_program("O1005\nG999\nM30\n"))
    by_program.cycle_start()  # the first block's error: PS0010
    by_hand = default_machine()
    by_hand.raise_alarm(0, 3, 10)
    shown = [[(a.alm_no, a.msg) for a in m.active_alarms()] for m in (by_program, by_hand)]
    assert shown[0] == shown[1] == [(10, "IMPROPER G-CODE")]


async def test_sim_alarm_prints_what_the_machine_kept() -> None:
    async with serving() as served:
        port = str(served.port)
        assert await ok("sim", "alarm", "PS0010", "--port", port) == (
            "raised PS0010 IMPROPER G-CODE\n"
        )
        assert await ok("sim", "alarm", "OT0500", "--axis", "1", "--port", port) == (
            "raised OT0500 (axis 1) + OVERTRAVEL ( SOFT 1 )\n"
        )
        assert await ok("sim", "alarm", "SV0411", "--port", port) == "raised SV0411\n"
        long = "X" * 40
        assert await ok("sim", "alarm", "PS0011", long, "--port", port) == (
            f"raised PS0011 {long[:32]}\n"
        )
        listed = await ok("alarms", "--port", port)
        assert "PS0010 IMPROPER G-CODE" in listed
