"""Messages name what the user typed, never a payload class, a struct code or a field path."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator, Awaitable, Callable
from decimal import Decimal
from typing import Any

import pytest
from cli_support import Cli
from support import Served, serving

from focas_net.cli import EXIT_USAGE, main
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.protocol import (
    AlarmType,
    DataRequest,
    FaultKind,
    FaultScope,
    InjectFault,
    PmcData,
    RaiseAlarm,
    VersaMaxRequest,
)
from focas_net.sim import MachineError, default_machine
from focas_net.web import ActionError, Station, perform

#: The machine's refusal of an out-of-range override, as every front end words it.
OVERRIDE_WORDS = "rapid override 101 is not a step of FANUC's: 0 (F0), 25, 50 or 100 %"

#: What a message must never show: payload classes, dotted fields, struct's wording.
INTERNAL = re.compile(
    r"[A-Z][a-zA-Z]+(Request|Value|Alarm|Fault|Data|Reply|Range|Panel)\b|\.\w+ = |format requires"
    r"|None for every axis|required argument"
)


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (("param", "get", "40000"), "parameter number 40000 is outside 0..32767"),
        (("param", "set", "40000", "1"), "parameter number 40000 is outside 0..32767"),
        (("diag", "40000"), "diagnostic number 40000 is outside 0..32767"),
        (("macro", "get", "40000"), "macro variable number 40000 is outside -32768..32767"),
        (("macro", "set", "40000", "1"), "macro variable number 40000 is outside -32768..32767"),
        (("sim", "alarm", "PS99999"), "alarm number 99999 is outside 0..32767"),
        (("sim", "clear", "PS99999"), "alarm number 99999 is outside 0..32767"),
        (("position", "--axis", "40000"), "axis 40000 is outside 1..32767"),
        (
            ("sim", "fault", "delay", "--arg", "10000000000"),
            "argument --arg: a delay is 0..60000 ms, got 10000000000",
        ),
    ],
)
async def test_cli_messages_name_what_was_typed(
    cli: Cli, argv: tuple[str, ...], expected: str
) -> None:
    err = await cli.fails(EXIT_USAGE, *argv, prefix="focas-net")
    assert expected in err
    assert not INTERNAL.search(err), err


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        (("versamax", "0", "70000"), "argument SLOT: must be 0..9, got 70000"),
        (("sim", "override", "--rapid", "101"), f"argument --rapid: {OVERRIDE_WORDS}"),
        (
            ("param", "get", "1420", "--axis", "40000"),
            "argument --axis: axis 40000 is outside 0..32767 (0: not an axis parameter)",
        ),
        (
            ("sim", "alarm", "PS0100", "--axis", "40000"),
            "argument --axis: axis 40000 is outside 0..32767 (0: an alarm of no axis)",
        ),
        (("versamax", "300", "1"), "argument RACK: must be 0..7, got 300"),
        (
            ("sim", "fault", "drop", "--count", "100000000000"),
            "argument --count: a fault's count is 1..10000, got 100000000000",
        ),
    ],
)
def test_cli_ranges_the_parser_checks_name_what_was_typed(
    argv: tuple[str, ...], expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as info:
        main(list(argv))
    assert info.value.code == EXIT_USAGE
    err = capsys.readouterr().err
    assert expected in err and err.count("\n") == 1
    assert not INTERNAL.search(err), err


Call = Callable[[FocasClient], Awaitable[Any]]


@pytest.mark.parametrize(
    ("call", "expected"),
    [
        (lambda c: c.read_param(40000), "parameter number 40000 is outside 0..32767"),
        (lambda c: c.read_param(1420, axis=-2), "axis -2 is outside 0..32767"),
        (lambda c: c.read_diag(40000), "diagnostic number 40000 is outside 0..32767"),
        (lambda c: c.write_param(40000, 1), "parameter number 40000 is outside 0..32767"),
        (lambda c: c.read_macro(40000), "macro variable number 40000 is outside"),
        (lambda c: c.read_positions(axis=0), "axis 0 is outside 1..32767"),
        (lambda c: c.read_module_config(0, 70000), "slot 70000 is outside 0..255"),
        (lambda c: c.read_alarms(alm_type=40000), "alarm type 40000 is outside -1..31"),
        (lambda c: c.read_alarms(alm_type="XX"), "unknown alarm type 'XX'"),
        (lambda c: c.sim.raise_alarm("PS", 99999), "alarm number 99999 is outside 0..32767"),
        (lambda c: c.sim.raise_alarm("XX", 1), "unknown alarm type 'XX'"),
        (lambda c: c.sim.raise_alarm(40, 1), "alarm type 40 is outside 0..31"),
        (lambda c: c.sim.inject_fault(1, count=100_000_000_000), "count 100000000000 is outside"),
        (
            lambda c: c.sim.inject_fault("foo"),
            "unknown fault kind 'foo' (one of DELAY ERROR DROP SPLIT, or its number)",
        ),
        (lambda c: c.sim.inject_fault("drop", scope="shop"), "unknown fault scope 'shop'"),
        (
            lambda c: c.sim.set_panel("FOO"),
            "unknown mode 'FOO' (one of MDI, MEM, EDIT, HND, JOG, TJOG, THND, INC, REF, RMT)",
        ),
        (lambda c: c.sim.set_panel(2), "unknown mode 2 (one of MDI, MEM, EDIT"),
        (lambda c: c.sim.set_panel("NOSEL"), "unknown mode 'NOSEL' (one of MDI, MEM, EDIT"),
    ],
)
async def test_client_messages_name_the_argument(server: Served, call: Call, expected: str) -> None:
    async with FocasClient(server.host, server.port) as cnc:
        with pytest.raises(ValueError) as exc:
            await call(cnc)
    assert expected in str(exc.value)
    assert not INTERNAL.search(str(exc.value)), str(exc.value)


async def test_client_names_a_fault_kind_of_the_wrong_type(server: Served) -> None:
    async with FocasClient(server.host, server.port) as cnc:
        with pytest.raises(TypeError, match=r"fault kind must be a FaultKind, its name or its "
                           r"number, got 1\.5"):  # fmt: skip
            await cnc.sim.inject_fault(1.5)  # type: ignore[arg-type]
        with pytest.raises(TypeError, match=r"fault scope must be a FaultScope, .*got None"):
            await cnc.sim.inject_fault("drop", scope=None)  # type: ignore[arg-type]


async def test_client_arms_a_fault_by_kind_name_and_the_server_checks_the_numbers(
    server: Served,
) -> None:
    async with FocasClient(server.host, server.port) as cnc:
        await cnc.sim.inject_fault("split", count=2)
        await cnc.sim.inject_fault(" Delay ", arg=5, scope="machine")
        await cnc.sim.inject_fault(FaultKind.ERROR, arg=5, scope=FaultScope.CONNECTION)
        listed = await cnc.sim.list_faults()
        assert [(f.kind, f.remaining) for f in listed] == [
            (FaultKind.SPLIT, 2), (FaultKind.ERROR, 1)
        ]  # fmt: skip
        assert [f.kind for f in await cnc.sim.list_faults(FaultScope.MACHINE)] == [FaultKind.DELAY]
        assert await cnc.sim.clear_faults() == 2 and await cnc.sim.clear_faults(1) == 1
        for kind, arg in ((9, 0), (FaultKind.DELAY, 60_001)):  # the server's ranges: EW_DATA
            with pytest.raises(CncError) as refused:
                await cnc.sim.inject_fault(kind, arg=arg)
            assert refused.value.ew == EW.DATA


async def test_client_takes_alarm_types_by_name(server: Served) -> None:
    async with FocasClient(server.host, server.port) as cnc:
        await cnc.sim.raise_alarm("PS", 100, "BY NAME")
        await cnc.sim.raise_alarm(AlarmType.OT, 500)
        await cnc.sim.raise_alarm("sv", 401, axis_no=1)
        assert [(a.alm_type, a.alm_no) for a in await cnc.read_alarms()] == [
            (3, 100), (4, 500), (6, 401)
        ]  # fmt: skip
        assert [a.alm_no for a in await cnc.read_alarms(alm_type="OT")] == [500]
        await cnc.sim.clear_alarms("PS")
        assert [a.alm_no for a in await cnc.read_alarms()] == [500, 401]


@pytest.mark.parametrize(
    ("payload", "expected"),
    [
        (lambda: VersaMaxRequest(0, 128, 70000, 0).encode(), "slot 70000 is outside 0..255"),
        (lambda: RaiseAlarm(0, 3, 99999, b"").encode(), "alarm number 99999 is outside"),
        (lambda: PmcData(5, 0, 70000, 70001, b"").encode(), "start address 70000 is outside"),
        (lambda: InjectFault(1, 0, 10**11, 0).encode(), "count 100000000000 is outside"),
        (lambda: DataRequest(40000, 0).encode(), "datano 40000 is outside -32768..32767"),
    ],
)
def test_codec_messages_name_the_field_not_the_class(
    payload: Callable[[], bytes], expected: str
) -> None:
    with pytest.raises(ValueError) as exc:
        payload()
    assert str(exc.value).startswith(expected)
    assert not INTERNAL.search(str(exc.value)), str(exc.value)


@pytest.mark.parametrize("typed", ["1.23456789012345", "2147483648", "-99999999999"])
async def test_a_macro_value_that_does_not_fit_has_one_wording(typed: str) -> None:
    """The client (the command line's), the page (before the write, by the clients' rule) and
    the machine say the same, and what to type: at most 9 decimals and digits within 32
    bits."""
    words = f"{typed} does not fit a macro variable: give at most 9 decimals"
    async with serving(default_machine()) as served:
        async with FocasClient(served.host, served.port) as cnc:
            with pytest.raises(ValueError, match=re.escape(words)) as by_client:
                await cnc.write_macro(500, typed)
        with pytest.raises(ActionError) as by_page:
            perform(Station(0, served.machine), "write_macro", {"number": 500, "value": typed})
        with pytest.raises(MachineError) as exc:
            served.machine.write_macro(500, Decimal(typed))
    assert str(by_page.value) == str(by_client.value)  # "#500: macro value ... does not fit"
    assert exc.value.detail == str(by_client.value)
    assert "does not fit a macro variable: give at most 9 decimals" in str(exc.value)
    assert "within 32 bits" in str(exc.value)


async def test_an_override_out_of_range_has_the_machines_words(server: Served) -> None:
    """The client (the command line's) says what the machine (the page's) says."""
    async with FocasClient(server.host, server.port) as cnc:
        with pytest.raises(ValueError) as exc:
            await cnc.sim.set_overrides(rapid=101)
    with pytest.raises(MachineError) as refused:
        perform(Station(0, server.machine), "overrides", {"rapid": 101})
    assert str(exc.value) == OVERRIDE_WORDS
    assert OVERRIDE_WORDS in str(refused.value)


async def test_fault_queues_take_the_scope_words_of_inject_fault(server: Served) -> None:
    async with FocasClient(server.host, server.port) as cnc:
        await cnc.sim.inject_fault("delay", arg=5, scope="machine")
        assert [f.kind for f in await cnc.sim.list_faults("Machine")] == [FaultKind.DELAY]
        assert await cnc.sim.list_faults("connection") == ()
        assert await cnc.sim.clear_faults(" MACHINE ") == 1
        words = []
        for call in (
            lambda: cnc.sim.inject_fault("drop", scope="shop"),
            lambda: cnc.sim.list_faults("shop"),
            lambda: cnc.sim.clear_faults("shop"),
        ):
            with pytest.raises(ValueError) as exc:
                await call()
            words.append(str(exc.value))
        assert (
            words == ["unknown fault scope 'shop' (one of CONNECTION MACHINE, or its number)"] * 3
        )
        for number in (2, -1):  # a number the server does not know: EW_DATA, as for inject
            with pytest.raises(CncError) as refused:
                await cnc.sim.clear_faults(number)
            assert refused.value.ew == EW.DATA
