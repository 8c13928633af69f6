"""0x0E11 sim_vacate_macro: a macro variable made vacant, through the adapter, the client and
``focas-net macro clear`` (``cnc_wrmacro`` has no way to write a vacant value)."""

from __future__ import annotations

import json
from decimal import Decimal

import pytest
from cli_support import run_focas_net
from support import IO_TIMEOUT, serving

from focas_net.adapters import PackedAdapter
from focas_net.cli import EXIT_CNC, EXIT_OK, EXIT_USAGE
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.protocol import Command, VacateMacro
from focas_net.sim import Machine, default_machine


def _ew(machine: Machine, payload: bytes) -> int:
    answer = PackedAdapter(machine).answer(machine.new_session(), Command.SIM_VACATE_MACRO, payload)
    return int.from_bytes(answer[:2], "little", signed=True)


def test_the_adapter_makes_a_variable_vacant() -> None:
    m = default_machine()
    m.write_macro(100, Decimal("12.5"))
    version = m.macro_version
    assert _ew(m, VacateMacro(100).encode()) == 0
    assert m.read_macro(100) is None and m.macro_version > version
    assert _ew(m, VacateMacro(100).encode()) == 0  # vacant again: nothing changes
    m.write_macro(100, 3)
    before = m.state_digest()
    assert _ew(m, VacateMacro(9999).encode()) == EW.NUMBER
    assert _ew(m, VacateMacro(4001).encode()) == EW.PROT  # a read-only system variable
    assert _ew(m, b"\x64") == EW.LENGTH
    assert m.state_digest() == before
    m.control_enabled = False
    assert _ew(m, VacateMacro(100).encode()) == EW.FUNC
    m.control_enabled = True
    m.read_only = True
    assert _ew(m, VacateMacro(100).encode()) == EW.PROT
    assert m.read_macro(100) == 3


async def test_client_vacate_macro() -> None:
    async with serving() as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            await cnc.write_macro(500, Decimal("-2.5"))
            await cnc.sim.vacate_macro(500)
            assert await cnc.read_macro(500) is None
            with pytest.raises(CncError) as number:
                await cnc.sim.vacate_macro(9999)
            assert number.value.ew == EW.NUMBER
            with pytest.raises(ValueError, match="40000"):
                await cnc.sim.vacate_macro(40000)


async def test_macro_clear_exits_and_says_what_it_did() -> None:
    async with serving() as served:
        at = ["--host", "127.0.0.1", "--port", str(served.port)]
        served.machine.write_macro(100, Decimal("7.25"))
        code, out, err = await run_focas_net("macro", "clear", "100", *at)
        assert (code, err) == (EXIT_OK, "")
        assert out.strip() == "#100 = <vacant> (cleared)"
        assert served.machine.read_macro(100) is None
        code, out, err = await run_focas_net("macro", "clear", "100", "--json", *at)
        assert (code, err, json.loads(out)) == (EXIT_OK, "", {"number": 100, "value": None})
        code, out, err = await run_focas_net("macro", "clear", "4001", *at)
        assert (code, out) == (EXIT_CNC, "") and "EW_PROT" in err
        code, out, err = await run_focas_net("macro", "clear", "9999", *at)
        assert (code, out) == (EXIT_CNC, "") and "EW_NUMBER" in err
        code, out, err = await run_focas_net("macro", "clear", "x", *at)
        assert (code, out) == (EXIT_USAGE, "") and "'x'" in err
    machine = default_machine()
    machine.control_enabled = False
    async with serving(machine) as served:
        at = ["--host", "127.0.0.1", "--port", str(served.port)]
        code, out, err = await run_focas_net("macro", "clear", "100", *at)
        assert (code, out) == (EXIT_CNC, "") and "EW_FUNC" in err
