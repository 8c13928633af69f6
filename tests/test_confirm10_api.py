"""The Python API as a new user meets it, a confirming tenth pass: a clear's filter is worded
with the -1 it takes, an axis past the path's is EW_ATTRIB before the number on both
transports (a spindle diagnostic's axis being its spindle), and the machine's own calls refuse
a value of another type with TypeError and take a position kind in any case."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from support import with_both_clients

from focas_net import EW, ChunkedWriteError, CncError, FocasClient, NativeClient, default_machine
from focas_net._refusals import axis_past
from focas_net.sim import Machine, MachineError, PathSpec
from focas_net.sim.default import _diags, _params
from focas_net.sim.nc import ManualClock
from focas_net.web.operations import Station, perform

DOCS = Path(__file__).resolve().parent.parent / "docs"

Both = tuple[Machine, FocasClient, NativeClient]


# -- a clear's filter: -1 is any, and the range says so ----------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"alm_type": -2}, "alarm type -2 is outside -1..31"),
        ({"alm_type": 32}, "alarm type 32 is outside -1..31"),
        ({"alm_no": -2}, "alarm number -2 is outside -1..32767"),
        ({"alm_no": 40000}, "alarm number 40000 is outside -1..32767"),
    ],
)
async def test_a_clear_filter_out_of_range_names_the_range_with_any(
    both_clients: Both, kwargs: dict[str, int], words: str
) -> None:
    """``clear_alarms(alm_type=-2)`` said ``outside 0..31`` though -1 (any) is taken: the
    machine, the page and the client name the range an argument takes."""
    machine, cnc, _ = both_clients
    machine.raise_alarm(0, 3, 100, "x")
    with pytest.raises(MachineError) as refused:
        machine.clear_alarms(**kwargs)
    assert (refused.value.ew, refused.value.detail) == (EW.DATA, words)
    with pytest.raises(MachineError) as on_page:
        perform(Station(0, machine), "clear_alarms", kwargs)
    assert on_page.value.detail == words
    with pytest.raises(ValueError, match=f"^{words}$"):
        await cnc.sim.clear_alarms(**kwargs)
    assert len(machine.active_alarms()) == 1
    assert machine.clear_alarms(-1, -1) == 1


# -- an axis past the path's axes, before the number ----------------------------------------
def _spindle_lathe() -> Machine:
    """One path of two axes and three spindles, with the default machine's items."""
    return Machine(
        "lathe",
        paths=[PathSpec(("X", "Y"), kind="T", spindles=3)],
        params=_params(2),
        diags=_diags(),
        sim_clock=ManualClock(),
    )


Call = Callable[[FocasClient | NativeClient], Awaitable[Any]]


@pytest.mark.parametrize(
    "call",
    [
        lambda c: c.read_param(9999, axis=9),
        lambda c: c.read_diag(9999, axis=9),
        lambda c: c.write_param(9999, 1, axis=9),
        lambda c: c.read_param(1320, axis=9),
    ],
    ids=["read_param", "read_diag", "write_param", "known"],
)
async def test_an_axis_past_the_paths_is_refused_alike_before_the_number(
    both_clients: Both, call: Call
) -> None:
    """``read_param(9999, axis=9)`` was EW_NUMBER on the packed transport and EW_ATTRIB
    (``axis 9 is outside 1..3``) on the native one, where FANUC's library checks the axis
    first."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await call(client)
        assert refused.value.ew == EW.ATTRIB, (type(client).__name__, refused.value)
        assert str(refused.value).endswith(axis_past(9, 3)), str(refused.value)


def test_the_machine_keeps_the_packed_contracts_order_number_first() -> None:
    """The packed contract checks the number before the axis (the clients, not the machine,
    turn an axis past the path's into EW_ATTRIB, as FANUC's library does before sending)."""
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(MachineError) as unknown:
        machine.read_param(9999, 9)
    assert unknown.value.ew == EW.NUMBER
    with pytest.raises(MachineError) as refused:
        machine.read_param(1420, 9)
    assert refused.value.ew == EW.ATTRIB


@pytest.mark.parametrize("spindle", [0, 1, 2, 3])
async def test_a_spindle_diagnostic_takes_every_spindle_of_the_path(spindle: int) -> None:
    """The machine answers a spindle diagnostic by spindle: the packed client reads all
    three spindles of a path of two axes. The native client does what FANUC's library does
    with a per-axis argument, checks it against the path's axes before sending: spindle 3
    of that path is EW_ATTRIB ``axis 3 is outside 1..2`` there."""
    async with with_both_clients(_spindle_lathe()) as (_, cnc, native):
        assert await cnc.read_diag(410, axis=spindle) == 0
        if spindle <= 2:
            assert await native.read_diag(410, axis=spindle) == 0
        else:
            with pytest.raises(CncError) as refused:
                await native.read_diag(410, axis=spindle)
            assert str(refused.value).endswith(f"cnc_diagnoss: {axis_past(3, 2)}"), refused.value


async def test_a_spindle_past_the_paths_is_named_as_a_spindle_by_the_packed_client() -> None:
    async with with_both_clients(_spindle_lathe()) as (_, cnc, _native):
        with pytest.raises(CncError) as refused:
            await cnc.read_diag(410, axis=4)
        assert refused.value.ew == EW.ATTRIB
        assert axis_past(4, 2) not in str(refused.value), str(refused.value)


def test_the_protocol_docs_say_which_comes_first() -> None:
    text = " ".join((DOCS / "protocol.md").read_text().split())
    assert "FANUC's library checks the axis before it sends" in text
    assert "in this order (the contract's): unknown number → EW_NUMBER" in text


# -- the machine's own calls --------------------------------------------------------------------
@pytest.mark.parametrize(
    "call",
    [
        lambda m: m.select_main_file(5),
        lambda m: m.folder_entries(5),
        lambda m: m.set_current_folder(None),
        lambda m: m.delete_file(b"//CNC_MEM/USER/PATH1/O0001"),
        lambda m: m.drive_usage(3),
        lambda m: m.current_folder("1"),
    ],
)
def test_a_folder_call_given_no_text_is_a_type_error(call: Callable[[Machine], Any]) -> None:
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError):
        call(machine)


@pytest.mark.parametrize("kind", ["ABSOLUTE", "Machine", " relative "])
def test_the_machine_takes_a_position_kind_in_any_case(kind: str) -> None:
    machine = default_machine(sim_clock=ManualClock())
    assert machine.positions(kind) == machine.positions(kind.strip().lower())


# -- a program the store refuses: the reason on the client and once on the command line --------
@pytest.mark.parametrize(
    ("text", "ew", "words"),
    [
        ("", EW.DATA, "the program text is empty"),
        ("  \n", EW.DATA, "the program text is empty"),
        ("G01 X1\nM30\n", EW.DATA, "a program starts with O and its number, not 'G01 X1'"),
        ("%\nG1X1\n%", EW.DATA, "a program starts with O and its number, not 'G1X1'"),
        ("O1\nM30\nO2\nM30\n", EW.DATA, "one part program"),
        ("O0\nM30\n", EW.NUMBER, "program number O0 is outside the program store's range"),
    ],
)
async def test_a_program_the_store_refuses_carries_its_reason(
    both_clients: Both, text: str, ew: int, words: str
) -> None:
    """``write_program("")`` raised ``EW_DATA: cnc_download`` with no reason, where the command
    line names the store's."""
    machine, cnc, _ = both_clients
    before = [p.number for p in machine.program_directory()]
    with pytest.raises(CncError) as refused:
        await cnc.write_program(text)
    assert refused.value.ew == ew
    assert refused.value.detail.startswith("cnc_download: "), refused.value.detail
    assert words in refused.value.detail
    assert [p.number for p in machine.program_directory()] == before


@pytest.mark.parametrize(
    ("text", "words"),
    [("", "the program text is empty"), ("G01 X1\n", "a program starts with O and its number")],
)
async def test_the_command_line_names_the_stores_reason_once(
    tmp_path: Path, text: str, words: str
) -> None:
    from cli_support import at, fails
    from support import serving

    program = tmp_path / "part.nc"
    program.write_text(text)
    async with serving() as served:
        line = await fails(1, "program", "load", str(program), *at(served))
    assert line.count(words) == 1, line
    assert f"{program}: {words}" in line, line


# -- a chunked PMC write past its area's end: what each transport writes, as documented -----
async def test_a_pmc_write_past_the_end_lists_what_each_transport_wrote(
    both_clients: Both,
) -> None:
    """``write_pmc("R", 7000, 2000 bytes)`` writes R7000..R7991 over the packed protocol and
    nothing over FOCAS/2: the docs say so, and the error lists what was written."""
    machine, cnc, native = both_clients
    expected = {cnc: [(7000, 7991)], native: []}
    for client in (native, cnc):
        with pytest.raises(ChunkedWriteError) as refused:
            await client.write_pmc("R", 7000, b"\x01" * 2000)
        assert refused.value.written == expected[client]
        assert isinstance(refused.value.cause, CncError)
        assert refused.value.cause.ew == EW.NUMBER
    assert bytes(machine.read_pmc("R", 7000, 1000)) == b"\x01" * 992 + bytes(8)
    text = " ".join((DOCS / "client.md").read_text().split())
    assert "`written` R7000..R7991 and `not_written` R7992..R8999" in text
    assert "(`not_written` R7000..R8999)" in text


# -- a program the CNC has not: named by the client, once on the command line ---------------
@pytest.mark.parametrize("call", ["select_program", "delete_program", "read_program"])
async def test_a_program_the_cnc_has_not_is_named(both_clients: Both, call: str) -> None:
    """``select_program(1234)`` raised ``EW_NUMBER: cnc_search`` with no reason, where the
    command line and the page say ``no program O1234``."""
    _, cnc, _ = both_clients
    with pytest.raises(CncError) as refused:
        await getattr(cnc, call)(1234)
    assert refused.value.ew == EW.NUMBER
    assert refused.value.detail.endswith(": no program O1234"), refused.value.detail


@pytest.mark.parametrize("command", ["select", "delete", "show"])
async def test_the_command_line_names_a_missing_program_once(command: str) -> None:
    from cli_support import at, fails
    from support import serving

    async with serving() as served:
        line = await fails(1, "program", command, "1234", *at(served))
    assert line.count("no program O1234") == 1, line


# -- a PMC range or a variable the CNC refuses: the reason on the client's error -------------
Refused = Callable[[FocasClient | NativeClient], Awaitable[Any]]


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda c: c.read_pmc("R", 7990, 20), "R7990..R8009 goes past the end of PMC area R"),
        (lambda c: c.write_pmc("X", 120, bytes(16)), "X120..X135 goes past the end of PMC area X"),
        (lambda c: c.write_pmc("F", 0, b"\x01"), "PMC area F is write-protected"),
        (lambda c: c.write_pmc_bit("R", 8000, 0, True), "R8000 goes past the end of PMC area R"),
    ],
)
async def test_a_pmc_range_the_cnc_refuses_is_named_on_both(
    both_clients: Both, call: Refused, words: str
) -> None:
    """``read_pmc("R", 7990, 20)`` raised ``EW_NUMBER: pmc_rdpmcrng`` with no reason, where the
    command line names the range and the area."""
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await call(client)
        assert words in refused.value.detail, (type(client).__name__, refused.value.detail)


async def test_the_simulators_pmc_write_past_the_end_is_named(both_clients: Both) -> None:
    _, cnc, _ = both_clients
    with pytest.raises(CncError) as refused:
        await cnc.sim.set_pmc("X", 120, bytes(16))
    assert refused.value.detail == "sim_set_pmc: X120..X135 goes past the end of PMC area X"


async def test_vacating_a_read_only_variable_is_named(both_clients: Both) -> None:
    """``sim.vacate_macro(5001)`` raised ``EW_PROT: sim_vacate_macro`` with no reason."""
    _, cnc, _ = both_clients
    with pytest.raises(CncError) as refused:
        await cnc.sim.vacate_macro(5001)
    assert refused.value.detail == (
        "sim_vacate_macro: macro variable #5001 is read-only (FANUC's #5001..#5120: position "
        "information)"
    )


async def test_the_command_line_names_a_pmc_range_once() -> None:
    from cli_support import at, fails
    from support import serving

    async with serving() as served:
        line = await fails(1, "pmc", "read", "R", "7990", "20", *at(served))
    assert line.count("goes past the end of PMC area R") == 1, line
