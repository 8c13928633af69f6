"""The rapid traverse override takes FANUC's steps only: F0 (kept as 0 %), 25, 50, 100 %, the
four values of G14's ROV1 ROV2. The machine refuses any other value, so the command line, the
page, both protocols and both clients say the same."""

from __future__ import annotations

import pytest
from cli_support import at, fails, ok
from support import IO_TIMEOUT, serving

from focas_net._typed import RAPID_STEPS, override_unfit
from focas_net.adapters import PackedAdapter
from focas_net.cli import EXIT_USAGE
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW
from focas_net.protocol import Command
from focas_net.sim import MachineError, default_machine
from focas_net.web import Station, perform

#: What the machine says of a rapid override of 7 %.
WORDS_7 = "rapid override 7 is not a step of FANUC's: 0 (F0), 25, 50 or 100 %"


@pytest.mark.parametrize("typed", [7, 1, 24, 75, 99, 101, -1, 255])
def test_the_machine_refuses_a_rapid_override_between_the_steps(typed: int) -> None:
    m = default_machine()
    with pytest.raises(MachineError) as refused:
        m.set_overrides(rapid=typed)
    assert refused.value.ew == EW.DATA
    assert str(refused.value).endswith(
        f"rapid override {typed} is not a step of FANUC's: 0 (F0), 25, 50 or 100 %"
    )
    assert m.overrides() == (100, 100, 100)


def test_the_machine_takes_each_step_and_g14_shows_it() -> None:
    m = default_machine()
    for rapid, rov in ((0, 3), (25, 2), (50, 1), (100, 0)):
        m.set_overrides(rapid=rapid)
        assert m.overrides()[1] == rapid
        assert m.read_pmc("G", 14, 1)[0] & 3 == rov
        assert m.panel_signals().rapid == rov
    assert RAPID_STEPS == (0, 25, 50, 100)
    assert override_unfit("rapid", 50) is None


@pytest.mark.parametrize("typed", [50.0, True, "50"])
def test_a_rapid_override_that_is_no_whole_number_is_a_type_error(typed: object) -> None:
    m = default_machine()
    with pytest.raises(TypeError, match="rapid override must be a whole number"):
        m.set_overrides(rapid=typed)  # type: ignore[arg-type]


def test_the_page_and_the_packed_command_say_the_machines_words() -> None:
    m = default_machine()
    with pytest.raises(MachineError) as refused:
        perform(Station(0, m), "overrides", {"rapid": 7})
    assert WORDS_7 in str(refused.value)
    # the packed control command as the wire carries it, past the client's own check
    adapter = PackedAdapter(m)
    payload = (100).to_bytes(2, "little") + (7).to_bytes(2, "little") + b"\xff\xff"
    assert adapter.answer(m.new_session(), Command.SIM_SET_OVERRIDES, payload) == b"\x05\x00"
    assert m.overrides() == (100, 100, 100)


async def test_both_clients_and_protocols_agree_on_the_steps() -> None:
    m = default_machine()
    async with (
        serving(m) as served,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
    ):
        with pytest.raises(ValueError) as refused:
            await packed.sim.set_overrides(rapid=7)
        assert str(refused.value) == WORDS_7
        await packed.sim.set_overrides(rapid=25)
        assert (await packed.read_run_info()).rapid == 25
        assert (await native.read_panel_signals()).rapid == 2
        # G14 written over FOCAS/2: each ROV1 ROV2 is one step, read back on both protocols
        for rov, rapid in ((0, 100), (1, 50), (2, 25), (3, 0)):
            await native.write_pmc("G", 14, bytes([0x80 | rov]))
            assert (await packed.read_run_info()).rapid == rapid
            assert (await native.read_panel_signals()).rapid == rov
        assert m.read_pmc("G", 14, 1)[0] == 0x83


async def test_the_command_line_refuses_7_and_takes_f0() -> None:
    async with serving(default_machine()) as served:
        line = await fails(
            EXIT_USAGE, "sim", "override", "--rapid", "7", *at(served), prefix="focas-net"
        )
        assert line == (
            f"focas-net sim override: error: argument --rapid: {WORDS_7}; see focas-net sim "
            "override --help"
        )
        assert served.machine.overrides()[1] == 100
        out = await ok("sim", "override", "--rapid", "F0", "--json", *at(served))
        assert '"rapid": "F0"' in out
        assert served.machine.panel_signals().rapid == 3
