"""The fault queues, first in, first out: 0x0E06 list_faults and 0x0E07 clear_faults on the
wire, ``client.sim.list_faults`` / ``clear_faults``, and ``focas-net sim fault`` / ``sim faults``
as child processes."""

from __future__ import annotations

import asyncio
import json
import sys

from support import IO_TIMEOUT, Served, Wire, killed_at_exit, serving

from focas_net.cli import EXIT_CNC, EXIT_OK
from focas_net.client import FocasClient
from focas_net.errors import EW
from focas_net.protocol import (
    ArmedFault,
    Command,
    FaultKind,
    FaultList,
    FaultsCleared,
    FaultScope,
    FaultsRequest,
    InjectFault,
)
from focas_net.sim import default_machine

LIST = Command.SIM_LIST_FAULTS
CLEAR = Command.SIM_CLEAR_FAULTS
MACHINE = int(FaultScope.MACHINE)
CONNECTION = int(FaultScope.CONNECTION)
DELAY, ERROR = int(FaultKind.DELAY), int(FaultKind.ERROR)


async def arm(w: Wire, kind: int, scope: int, count: int, arg: int) -> None:
    assert await w.ew(Command.SIM_INJECT_FAULT, InjectFault(kind, scope, count, arg).encode()) == 0


async def test_list_shows_the_queue_in_order_and_counts_down(wire: Wire) -> None:
    await arm(wire, ERROR, MACHINE, 2, int(EW.BUSY))
    await arm(wire, ERROR, MACHINE, 1, int(EW.PROT))
    await arm(wire, ERROR, CONNECTION, 1, int(EW.DATA))
    assert await wire.request(LIST, FaultsRequest(MACHINE)) == FaultList(
        (ArmedFault(ERROR, 2, int(EW.BUSY)), ArmedFault(ERROR, 1, int(EW.PROT)))
    )
    assert await wire.request(LIST, FaultsRequest(CONNECTION)) == FaultList(
        (ArmedFault(ERROR, 1, int(EW.DATA)),)
    )
    # the connection's own fault first, then the machine's, in the order they were armed
    assert await wire.ew(Command.RDCNCSTAT) == EW.DATA
    assert await wire.ew(Command.RDCNCSTAT) == EW.BUSY
    assert await wire.request(LIST, FaultsRequest(MACHINE)) == FaultList(
        (ArmedFault(ERROR, 1, int(EW.BUSY)), ArmedFault(ERROR, 1, int(EW.PROT)))
    )
    assert await wire.request(LIST, FaultsRequest(CONNECTION)) == FaultList(())


async def test_clear_empties_one_scope(wire: Wire, server: Served) -> None:
    await arm(wire, DELAY, MACHINE, 3, 100)
    await arm(wire, ERROR, MACHINE, 1, int(EW.BUSY))
    await arm(wire, ERROR, CONNECTION, 1, int(EW.DATA))
    assert await wire.request(CLEAR, FaultsRequest(MACHINE)) == FaultsCleared(2)
    assert await wire.request(CLEAR, FaultsRequest(MACHINE)) == FaultsCleared(0)
    assert await wire.request(LIST, FaultsRequest(CONNECTION)) == FaultList(
        (ArmedFault(ERROR, 1, int(EW.DATA)),)
    )
    async with await server.connect() as other:  # the other connection sees none
        assert await other.request(LIST, FaultsRequest(CONNECTION)) == FaultList(())
        assert await other.ew(Command.RDCNCSTAT) == 0
    assert await wire.request(CLEAR, FaultsRequest(CONNECTION)) == FaultsCleared(1)
    assert await wire.ew(Command.RDCNCSTAT) == 0


async def test_fault_queue_checks(wire: Wire) -> None:
    assert await wire.ew(LIST, b"\x01") == EW.LENGTH
    assert await wire.ew(CLEAR, b"\x01\x00\x00") == EW.LENGTH
    assert await wire.ew(LIST, FaultsRequest(2).encode()) == EW.DATA
    assert await wire.ew(CLEAR, FaultsRequest(-1).encode()) == EW.DATA


async def test_fault_queues_with_control_off_and_read_only() -> None:
    off = default_machine()
    off.control_enabled = False
    async with serving(off) as served, await served.connect() as w:
        assert await w.ew(LIST, FaultsRequest(MACHINE).encode()) == EW.FUNC
        assert await w.ew(CLEAR, FaultsRequest(MACHINE).encode()) == EW.FUNC
    locked = default_machine()
    locked.read_only = True
    async with serving(locked) as served, await served.connect() as w:
        assert await w.request(LIST, FaultsRequest(MACHINE)) == FaultList(())
        assert await w.ew(CLEAR, FaultsRequest(MACHINE).encode()) == EW.PROT


async def test_client_lists_and_clears(server: Served) -> None:
    async with FocasClient(server.host, server.port, timeout=IO_TIMEOUT) as c:
        await c.sim.inject_fault(FaultKind.DELAY, count=2, arg=10, scope=FaultScope.MACHINE)
        await c.sim.inject_fault(FaultKind.ERROR, arg=int(EW.BUSY), scope=FaultScope.MACHINE)
        pending = await c.sim.list_faults(FaultScope.MACHINE)
        assert pending == (
            ArmedFault(FaultKind.DELAY, 2, 10),
            ArmedFault(FaultKind.ERROR, 1, int(EW.BUSY)),
        )
        assert all(isinstance(f.kind, FaultKind) for f in pending)
        assert await c.sim.list_faults() == ()  # this connection's own: none
        assert await c.sim.clear_faults(FaultScope.MACHINE) == 2
        assert await c.sim.list_faults(FaultScope.MACHINE) == ()
        await c.read_status()  # nothing pending any more


async def focas_net(served: Served, *argv: str) -> tuple[int, str, str]:
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", *argv, "--port", str(served.port),
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with killed_at_exit(proc), asyncio.timeout(6 * IO_TIMEOUT):
        out, err = await proc.communicate()
    assert proc.returncode is not None
    return proc.returncode, out.decode(), err.decode()


async def test_cli_says_which_answers_a_queued_fault_applies_to(server: Served) -> None:
    for _ in range(3):
        code, out, _err = await focas_net(server, "sim", "fault", "delay", "--arg", "1")
        assert code == EXIT_OK
    assert out.strip() == (
        "queued behind 2 pending faults: answer 3 of this machine from now: delayed 1 ms"
    )
    code, out, err = await focas_net(server, "sim", "fault", "error", "--arg", "EW_BUSY", "--json")
    assert (code, err) == (EXIT_OK, "")
    data = json.loads(out)
    assert (data["queued_behind"], data["first_answer"], data["last_answer"]) == (3, 4, 4)

    code, out, err = await focas_net(server, "sim", "faults")
    assert (code, err) == (EXIT_OK, "")
    lines = out.splitlines()
    assert lines[0] == "4 pending faults of this machine, first in, first out:"
    assert lines[-1].split()[:2] == ["4", "error"] and lines[-1].endswith("answer 4")
    code, out, _err = await focas_net(server, "sim", "faults", "--json")
    rows = json.loads(out)["faults"]
    assert [(r["kind"], r["first_answer"]) for r in rows] == [
        ("delay", 1),
        ("delay", 2),
        ("delay", 3),
        ("error", 4),
    ]

    code, out, _err = await focas_net(server, "sim", "faults", "--clear")
    assert (code, out.strip()) == (EXIT_OK, "cleared 4 pending faults of this machine")
    code, out, _err = await focas_net(server, "sim", "faults")
    assert (code, out.strip()) == (EXIT_OK, "no pending faults of this machine")


async def test_cli_sim_clear_says_when_nothing_matched(server: Served) -> None:
    code, out, err = await focas_net(server, "sim", "clear", "PS9999")
    assert (code, out) == (EXIT_CNC, "")
    assert err == "focas-net: no active alarm matches PS9999; nothing cleared\n"
    server.machine.raise_alarm(0, 3, 100, "PARAMETER WRITE ENABLE")
    code, out, _err = await focas_net(server, "sim", "clear", "PS")
    assert (code, out.strip()) == (EXIT_OK, "cleared PS0100; 0 still active")
