"""A refusal at the command line says why, in the machine's words: the EW code the wire carries,
then the reason the command's family gives for it with what to do (``; cycle start refused:
the mode is MDI, not MEM (focas-net sim panel --mode MEM)``), on both transports where the command
runs on both. ``unlock`` says whether the CNC has a password at all.

Each case runs ``focas-net`` as a subprocess against a server this test started on 127.0.0.1
(port 0) and set up through the client; the cases of one server run side by side.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any, Final

import pytest
from cli_support import run_focas_net
from support import IO_TIMEOUT, Served, serving

from focas_net.cli import EXIT_CNC, EXIT_OK, _reasons, _table, program_cmds
from focas_net.client import FocasClient
from focas_net.protocol import AutMode
from focas_net.sim import default_machine

#: ``(argv, the EW code's name, what the reason must say)``.
Case = tuple[tuple[str, ...], str, str]
Setup = Callable[[FocasClient], Awaitable[Any]]


@asynccontextmanager
async def served_as(setup: Setup | None = None, **kwargs: Any) -> AsyncIterator[Served]:
    machine = default_machine()
    if "password" in kwargs:
        machine.set_param_password(kwargs.pop("password"))
    async with serving(machine, **kwargs) as served:
        if setup is not None:
            async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as c:
                await setup(c)
        yield served


async def refusals(served: Served, cases: list[Case]) -> None:
    """Run every case at once; each must fail with exit 1, one line, its code and reason."""
    port = ("--port", str(served.port))
    results = await asyncio.gather(*(run_focas_net(*argv, *port) for argv, _, _ in cases))
    for (argv, ew, why), (code, out, err) in zip(cases, results, strict=True):
        assert (code, out) == (EXIT_CNC, ""), (argv, err)
        assert err.startswith(f"focas-net: EW_{ew} (") and err.count("\n") == 1, (argv, err)
        assert why in err.partition("); ")[2], (argv, err)  # the reason, after the code


@pytest.fixture
def programs(tmp_path: Path) -> Path:
    """A folder with ``o0001.nc`` (the number of the built-in machine's program) and
    ``no_o_line.nc`` (a program without its O line)."""
    (tmp_path / "o0001.nc").write_text("O0001\nG0 X1.\nM30\n")
    (tmp_path / "no_o_line.nc").write_text("G0 X1.\nM30\n")
    (tmp_path / "two.nc").write_text("O0015\nM30\nO0016\nM30\n%\n")
    (tmp_path / "percent.nc").write_text("%\nO0001\nM30\n%\n")
    (tmp_path / "iso.nc").write_text(":0001\nM30\n")
    return tmp_path


async def test_refusals_of_the_built_in_machine_say_why(programs: Path) -> None:
    dup, no_o = str(programs / "o0001.nc"), str(programs / "no_o_line.nc")
    cases: list[Case] = [
        (("program", "load", dup), "REJECT", "O0001 is already stored: give --replace"),
        (("program", "load", no_o), "DATA", "a program starts with O and its number"),
        (("program", "load", str(programs / "two.nc")), "DATA", "one program per text"),
        (("program", "load", str(programs / "percent.nc")), "REJECT", "O0001 is already stored"),
        (("program", "load", str(programs / "iso.nc")), "REJECT", "O0001 is already stored"),
        (("program", "select", "4444"), "NUMBER", "no program O4444"),
        (("macro", "get", "2000"), "NUMBER", "the CNC has no macro variable #2000"),
        (("macro", "set", "5001", "1"), "PROT", "macro variable #5001 is read-only (FANUC's"),
        (("pmc", "read", "R", "7999", "2"), "NUMBER", "R7999..R8000 goes past the end"),
        (("pmc", "write", "X", "0", "1"), "PROT", "X is write-protected"),
        (("pmc", "bit", "X", "0.1", "1"), "PROT", "pmc bit has no --force"),
        (
            ("pmc", "write", "X", "0", "1", "--protocol", "native"),
            "PROT",
            "writing it as the simulator (--force) needs --protocol packed",
        ),
        (("versamax", "0", "9"), "NUMBER", "rack 0 slot 9 holds no module"),
        (("sim", "alarm", "PS0100", "--axis", "9"), "ATTRIB", "give --axis 1..3 (or --axis 0"),
        (("param", "set", "1420", "5", "--axis", "1"), "PASSWD", "need MDI mode and PWE on"),
        (("param", "get", "9999"), "NUMBER", "the CNC has no parameter 9999"),
    ]
    async with served_as() as served:
        await refusals(served, cases)
        native = [(argv, ew, why) for argv, ew, why in cases[6:9]]
        await refusals(served, [((*argv, "--protocol", "native"), e, w) for argv, e, w in native])


async def test_the_native_password_hint_names_the_transport_that_carries_it() -> None:
    async with served_as() as served:
        code, _, err = await run_focas_net(
            "param", "set", "1420", "5", "--axis", "1", "--protocol", "native",
            "--port", str(served.port),
        )  # fmt: skip
    assert code == EXIT_CNC
    assert "FOCAS/2 cannot send a parameter password" in err
    assert err.rstrip().endswith("write with --protocol packed --password")


async def test_cycle_start_and_parameter_ranges_in_mdi() -> None:
    async def mdi(c: FocasClient) -> None:
        await c.sim.set_panel(AutMode.MDI, pwe=True)

    async with served_as(mdi) as served:
        await refusals(
            served,
            [
                (
                    ("sim", "cycle", "start"),
                    "MODE",
                    "cycle start refused: the mode is MDI, not MEM",
                ),
                (
                    ("param", "set", "1420", "1000000000", "--axis", "1"),
                    "DATA",
                    "the CNC refused 1000000000 for parameter 1420 axis 1: outside its range",
                ),
            ],
        )


async def test_cycle_start_with_an_alarm_and_without_a_main_program() -> None:
    async def alarm(c: FocasClient) -> None:
        await c.sim.raise_alarm(3, 100, "TEST")

    async def no_main(c: FocasClient) -> None:
        await c.delete_program(1)

    start = ("sim", "cycle", "start")
    async with served_as(alarm) as served:
        await refusals(served, [(start, "ALARM", "cycle start refused: an alarm is active")])
    async with served_as(no_main) as served:
        await refusals(served, [(start, "DATA", "no main program is selected")])


async def test_read_only_and_no_control_servers_say_so(programs: Path) -> None:
    read_only = "the machine is read-only (a server started with --read-only)"
    no_control = "the server takes no simulator control commands"
    async with served_as(read_only=True) as served:
        await refusals(
            served,
            [
                (("program", "load", str(programs / "o0001.nc"), "--replace"), "PROT", read_only),
                (("sim", "cycle", "start"), "PROT", read_only),
                (("pmc", "write", "R", "0", "1", "--force"), "PROT", read_only),
                (
                    ("pmc", "write", "R", "0", "1"),
                    "PROT",
                    "the machine is read-only, or its machine file write-protects PMC area R",
                ),
            ],
        )
    async with served_as(control=False) as served:
        await refusals(
            served,
            [
                (("sim", "cycle", "start"), "FUNC", no_control),
                (("sim", "faults"), "FUNC", no_control),
                (("macro", "clear", "100"), "FUNC", no_control),
            ],
        )


UNLOCKED: Final = "password accepted"
NO_PASSWORD: Final = "the CNC has no parameter password"


async def test_unlock_says_whether_the_cnc_has_a_password() -> None:
    async with served_as(password="ABCD") as served:
        port = ("--port", str(served.port))
        right, wrong = await asyncio.gather(
            run_focas_net("unlock", "ABCD", *port), run_focas_net("unlock", "ABCE", *port)
        )
    assert right[0] == EXIT_OK and right[1].startswith(UNLOCKED), right
    assert wrong[0] == EXIT_CNC and "the password is not the CNC's" in wrong[2], wrong
    async with served_as() as served:
        code, out, err = await run_focas_net("unlock", "0", "--json", "--port", str(served.port))
        assert (code, err) == (EXIT_OK, "")
        assert out.replace(" ", "").replace("\n", "") == '{"unlocked":true,"password_set":false}'
        code, out, _ = await run_focas_net("unlock", "ABCD", "--port", str(served.port))
        assert code == EXIT_OK and out.startswith(NO_PASSWORD)


def test_every_table_is_the_table_of_a_command() -> None:
    """A family's table is found by the command's name as typed: each name is a command's."""
    names: set[str] = set()
    for row in _table.COMMANDS:
        leaves = row.commands if isinstance(row, _table.Group) else (row,)
        prefix = f"{row.name} " if isinstance(row, _table.Group) else ""
        names.update(f"{prefix}{cmd.name}" for cmd in leaves)
    names.update(f"program {a}" for a in program_cmds.PROGRAM_ACTIONS)
    names.update(f"sim cycle {a}" for a in program_cmds.CYCLE_ACTIONS)
    assert set(_reasons.FAMILIES) <= names
