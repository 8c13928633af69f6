"""An eighth new user's pass over the dashboard: switches, alarm types, PMC bits and faults
typed into the page or POSTed to its actions, compared with what the command line takes and
answers for the same machine; each case that was wrong once, kept."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from cli_support import at, fails, ok
from support import IO_TIMEOUT, serving

from focas_net._typed import WRONG_PASSWORD, rapid_step, switch
from focas_net.errors import EW
from focas_net.protocol import AutMode, FaultKind, alarm_type_of, ew_of_text
from focas_net.sim import MachineError, default_machine, load_machine
from focas_net.web import (
    ActionError,
    Dashboard,
    Station,
    action_args,
    macro_rows,
    perform,
    stations_of,
)


def _station() -> Station:
    return Station(0, default_machine())


# -- a switch typed as text is read as the command line reads it -----------------------------
@pytest.mark.parametrize("typed", ["+1", "2", "-0", "0x1", "1.0"])
@pytest.mark.parametrize("key", ["pwe", "emergency"])
def test_a_switch_typed_as_text_is_read_as_the_command_line_reads_it(typed: str, key: str) -> None:
    """``{"pwe": "+1"}`` set PWE on, and ``{"pwe": "2"}`` was EW_DATA "panel pwe is 0 or 1",
    where ``sim panel --pwe +1`` and ``--pwe 2`` are refused in :func:`switch`'s words."""
    station = _station()
    before = station.machine.panel
    with pytest.raises(ValueError) as words:
        switch(typed)
    with pytest.raises(ActionError) as refused:
        perform(station, "panel", {key: typed})
    assert str(refused.value) == f"{key}: {words.value}"
    assert station.machine.panel == before
    perform(station, "panel", {key: " On "})  # a word, as --pwe on
    assert getattr(station.machine.panel, key) == 1


async def test_the_page_and_the_command_line_refuse_a_switch_in_the_same_words() -> None:
    async with serving() as served:
        line = await fails(2, "sim", "panel", *at(served), "--pwe", "+1", prefix="focas-net")
        with pytest.raises(ActionError) as refused:
            perform(Station(0, served.machine), "panel", {"pwe": "+1"})
        assert line.endswith(
            f"{str(refused.value).removeprefix('pwe: ')}; see focas-net sim panel --help"
        )


def test_a_pmc_bit_value_typed_as_text_is_a_switch_and_a_json_number_the_wire_value() -> None:
    station = _station()
    with pytest.raises(ActionError, match=r"^value: expected 1, on, .* got '2'$"):
        perform(station, "pmc_bit", {"area": "R", "address": 0, "bit": 0, "value": "2"})
    with pytest.raises(ActionError, match=r"^value: expected 1, on, .* got 2$"):
        perform(station, "pmc_bit", {"area": "R", "address": 0, "bit": 0, "value": 2})
    assert station.machine.read_pmc("R", 0, 1) == b"\x00"


# -- one reader of a typed argument -----------------------------------------------------------
@pytest.mark.parametrize(
    ("action", "args", "key", "parse"),
    [
        ("overrides", {}, "rapid", rapid_step),
        ("inject_fault", {"kind": "ERROR"}, "arg", ew_of_text),
        ("clear_alarms", {}, "alm_type", alarm_type_of),
    ],
)
def test_a_typed_argument_is_refused_in_its_readers_words_naming_its_key(
    action: str, args: dict[str, Any], key: str, parse: Any
) -> None:
    """The rapid override's ``F0``, an error fault's ``EW_BUSY`` and an alarm type's ``PS``
    are read by one helper taking the reader and the fallback; text neither reads is refused
    naming the key, in the reader's words."""
    station = _station()
    with pytest.raises(ValueError) as words:
        parse("Fx7")
    with pytest.raises(ActionError) as refused:
        perform(station, action, {**args, key: "Fx7"})
    assert str(refused.value) == f"{key}: {words.value}"


@pytest.mark.parametrize("typed", ["P S", "T31", "PS0100", "ps-"])
def test_an_alarm_type_that_is_no_number_is_refused_as_no_alarm_type(typed: str) -> None:
    """``{"alm_type": "P S"}`` (or ``T31``, as the page shows a type without a name) was "not
    a whole number", though the box takes names; it names the types now."""
    station = _station()
    for action, args in (
        ("raise_alarm", {"alm_no": 5, "msg": "X"}),
        ("clear_alarms", {}),
    ):
        with pytest.raises(ActionError) as refused:
            perform(station, action, {**args, "alm_type": typed})
        assert str(refused.value) == (
            f"alm_type: unknown alarm type {typed!r} "
            "(one of SW PW IO PS OT OH SV SR MC SP DS IE BG SN EX PC, or 0..31)"
        )
    assert station.machine.active_alarms() == []
    perform(station, "raise_alarm", {"alm_type": " 31 ", "alm_no": 5, "msg": "X"})
    assert [a.key for a in station.machine.active_alarms()] == [(0, 31, 5)]


# -- a PMC bit's answer names what the command line names ------------------------------------
async def test_a_pmc_bit_written_on_the_page_answers_as_pmc_bit_json() -> None:
    """The page's answer was ``{"area": "R", "address": 3, "byte": 128}``, where the command
    line's ``"byte"`` is the address: one name, two meanings. It answers the bit now."""
    async with serving() as served:
        station = Station(0, served.machine)
        served.machine.write_pmc("R", 3, b"\x01")
        answer = perform(station, "pmc_bit", {"area": "r", "address": "0x3", "bit": 7})
        assert answer == {"ok": True, "area": "R", "address": 3, "bit": 7, "value": 1}
        cli = json.loads(await ok("pmc", "bit", *at(served), "R", "3.7", "--json"))
        assert cli == {"area": "R", "byte": 3, "bit": 7, "value": 1}
        assert served.machine.read_pmc("R", 3, 1) == b"\x81"  # the other bit kept


# -- a drop or a split takes no argument -------------------------------------------------------
@pytest.mark.parametrize("kind", ["DROP", "SPLIT"])
@pytest.mark.parametrize("arg", [5, "5", "abc", 0])
async def test_an_arg_of_a_drop_is_refused_as_the_command_line_refuses_it(
    kind: str, arg: object
) -> None:
    """``{"kind": "DROP", "arg": "abc"}`` armed a drop, the argument unread, where ``sim fault
    drop --arg 5`` is refused: the argument of a kind that takes none is refused alike."""
    async with serving() as served:
        line = await fails(
            2, "sim", "fault", kind.lower(), *at(served), "--arg", "5", prefix="focas-net"
        )
        station = Station(0, served.machine)
        with pytest.raises(ActionError) as refused:
            perform(station, "inject_fault", {"kind": kind, "arg": arg})
        assert str(refused.value) == f"arg does not apply to a {kind.lower()} fault"
        # (the command line words it as its parser refuses an option: argument --arg: ...)
        why = str(refused.value).removeprefix("arg ")
        assert line == (
            f"focas-net sim fault: error: argument --arg: {why}; see focas-net sim fault --help"
        )
        assert len(station.faults) == 0
    for given in ({}, {"arg": None}, {"arg": ""}):  # none given: armed
        perform(station, "inject_fault", {"kind": kind, **given})
    assert station.fault_listing() == [(kind, 1, 0)] * 3
    assert FaultKind[kind] in (FaultKind.DROP, FaultKind.SPLIT)


def test_the_docs_say_where_the_fault_form_is_that_a_drop_takes_no_arg() -> None:
    text = (Path(__file__).resolve().parent.parent / "docs" / "web.md").read_text()
    assert "DROP and SPLIT take no argument" in text


# -- a PMC bit past 7, and an unlock of no password, named as typed ---------------------------
async def test_a_pmc_bit_past_7_is_refused_in_the_words_of_pmc_bit() -> None:
    """The page said "bit: 0..7, got 8" where ``pmc bit R 1.8`` says which address and why."""
    async with serving() as served:
        line = await fails(2, "pmc", "bit", "r", "1.8", "1", *at(served), prefix="focas-net")
        with pytest.raises(ActionError) as refused:
            perform(Station(0, served.machine), "pmc_bit", {"area": "r", "address": 1, "bit": 8})
        assert line == (
            f"focas-net pmc bit: error: argument BYTE.BIT: {refused.value}; "
            "see focas-net pmc bit --help"
        )
        assert str(refused.value) == "R1.8: bit 8 is outside 0..7: a PMC address is 1 byte wide"
        assert served.machine.read_pmc("R", 1, 1) == b"\x00"


@pytest.mark.parametrize("args", [{}, {"password": None}])
def test_an_unlock_without_a_password_says_one_is_needed(args: dict[str, Any]) -> None:
    """``{}`` was refused as "parameter password ''", a password no one typed."""
    with pytest.raises(ActionError) as refused:
        perform(_station(), "unlock", args)
    assert str(refused.value) == (
        "password: a parameter password (1..4 ASCII characters) is needed"
    )


async def test_a_wrong_password_is_refused_in_the_same_words_on_the_page_and_the_command_line() -> (
    None
):
    """The page said "parameter password mismatch" where ``focas-net unlock 123`` says "the
    password is not the CNC's"."""
    async with serving(default_machine(param_password="1234")) as served:
        line = await fails(1, "unlock", "123", *at(served))
        with pytest.raises(MachineError) as refused:
            perform(Station(0, served.machine), "unlock", {"password": "123"})
        assert (refused.value.ew, refused.value.detail) == (EW.PASSWD, WRONG_PASSWORD)
        assert line.endswith(f"(cnc_wrunlockparam); {WRONG_PASSWORD}")


@pytest.mark.parametrize("number", [3011, 3012, 4001])
def test_a_read_only_macro_variable_is_named_alike_whatever_makes_it_so(number: int) -> None:
    """The page said "#3011 is read-only" of the clock and "macro variable #4001 is
    read-only" of a modal variable."""
    with pytest.raises(MachineError) as refused:
        perform(_station(), "write_macro", {"number": number, "value": 1})
    assert refused.value.ew == EW.PROT
    assert refused.value.detail.startswith(f"macro variable #{number} is read-only")


# -- the live updates --------------------------------------------------------------------------
BINARY_REFUSED = "bad subscription: a text frame of JSON is expected, got a binary frame"


async def test_a_subscription_in_a_binary_frame_is_refused_saying_so() -> None:
    """A subscription sent as a binary frame (``websocat --binary``) went unanswered: the
    page's frames went on as before, nothing said why."""
    aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard needs aiohttp")
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0, interval=0.05)
        async with web, aiohttp.ClientSession() as session:
            async with session.ws_connect(f"{web.url}ws") as ws:
                await ws.send_bytes(b'{"subscribe": "machine", "index": 0}')
                for _ in range(50):  # fleet frames first, then the answer to the frame sent
                    frame = json.loads(await ws.receive_str(timeout=IO_TIMEOUT))
                    if frame["type"] != "fleet":
                        break
                assert frame == {"type": "error", "error": BINARY_REFUSED}
                await ws.send_str('{"subscribe": "machine", "index": 0}')  # as text: shown
                for _ in range(50):
                    frame = json.loads(await ws.receive_str(timeout=IO_TIMEOUT))
                    if frame["type"] == "machine":
                        break
                assert frame["data"]["index"] == 0


# -- a macro variable: vacant as the command line gives it, and only when told -------------------
async def test_a_vacant_variable_is_null_on_the_page_as_in_macro_get_json() -> None:
    """The page's answers had ``"value": ""`` for a vacant variable where ``macro get --json``
    has ``null``."""
    async with serving() as served:
        station = Station(0, served.machine)
        answer = perform(station, "write_macro", {"number": 500, "value": ""})
        cli = json.loads(await ok("macro", "get", "500", *at(served), "--json"))
        assert cli == {"number": 500, "value": None}
        assert answer == {"ok": True, **cli}
        rows = macro_rows(served.machine, station.macro_numbers(), "500-500")
        assert rows == [{"number": 500, "value": None, "writable": True}]
        perform(station, "write_macro", {"number": 500, "value": "1.50"})
        cli = json.loads(await ok("macro", "get", "500", *at(served), "--json"))
        assert (
            macro_rows(served.machine, station.macro_numbers(), "500-500")[0]["value"]
            == (cli["value"])
        )


def test_a_write_without_a_value_leaves_the_variable_as_it_was() -> None:
    """``{"number": 500}`` made #500 vacant: a value left out was read as the empty box."""
    station = _station()
    perform(station, "write_macro", {"number": 500, "value": "7"})
    with pytest.raises(ActionError) as refused:
        perform(station, "write_macro", {"number": 500})
    assert str(refused.value) == 'value: a number is needed (null or "" makes the variable vacant)'
    assert station.machine.read_macro(500) == 7
    for vacant in (None, "", "  "):  # told: vacant
        station.machine.write_macro(500, 7)
        assert perform(station, "write_macro", {"number": 500, "value": vacant})["value"] is None
        assert station.machine.read_macro(500) is None


# -- a parameter written on the page answers as param get --json -------------------------------
EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "machine.toml"


@pytest.mark.parametrize(
    ("number", "axis", "typed", "cli_typed"),
    [
        (1430, 1, "1.5", "1.5"),  # real: its value was 15, the count of its least units
        (1006, 1, "00000101", "0b101"),  # bit, an axis
        (1420, 2, "0x10", "16"),  # two-word, an axis
    ],
)
async def test_a_parameter_written_on_the_page_answers_as_param_get_json(
    number: int, axis: int, typed: str, cli_typed: str
) -> None:
    machine = load_machine(EXAMPLE)
    machine.set_panel(mode=int(AutMode.MDI), pwe=1)
    async with serving(machine) as served:
        station = Station(0, machine)
        perform(station, "unlock", {"password": "5810"})
        answer = perform(station, "write_param", {"number": number, "axis": axis, "value": typed})
        on_axis = ["--axis", str(axis)] if axis else []
        got = await ok("param", "get", str(number), *on_axis, *at(served), "--json")
        cli = json.loads(got)
        assert answer == {"ok": True, **cli, "text": answer["text"]}
        written = await ok(
            "param",
            "set",
            str(number),
            cli_typed,
            *on_axis,
            *at(served),
            "--password",
            "5810",
            "--json",
        )
        assert json.loads(written) == cli  # the same value written by the command line


# -- a number of thousands of digits ------------------------------------------------------------
@pytest.mark.parametrize("typed", ["1" * 5000, "O" + "9" * 9, "0" * 5000])
async def test_a_program_number_of_thousands_of_digits_is_refused_as_no_program_number(
    typed: str,
) -> None:
    """``{"number": "111...1"}`` (5,000 digits), as ``program select 111...1``, said "Exceeds
    the limit (4300 digits) for integer string conversion: ... use
    sys.set_int_max_str_digits()", Python's words; leading zeros are no digits of it."""
    async with serving() as served:
        station = Station(0, served.machine)
        with pytest.raises(ActionError) as refused:
            perform(station, "select_program", {"number": typed})
        assert (
            str(refused.value)
            == f"number: {typed!r} is not a program number (O1..O99999999, e.g. O1000)"
        )
        line = await fails(2, "program", "select", typed, *at(served), prefix="focas-net")
        assert line == (
            f"focas-net program: error: argument N|FILE: {typed!r} is not a program number "
            "(O1..O99999999, e.g. O1000); see focas-net program --help"
        )
    leading = perform(_station(), "select_program", {"number": "O" + "0" * 4999 + "1"})
    assert leading == {"ok": True}


def test_a_json_number_of_thousands_of_digits_is_refused_saying_so_not_as_no_json() -> None:
    """A body ``{"number": 111...1}`` (5,000 digits, a JSON number) was "the body is not
    JSON": Python refuses to read it, and that refusal read as no JSON."""
    for digits, sign in ((5000, ""), (101, "-")):
        body = f'{{"number": {sign}{"1" * digits}, "value": 1}}'.encode()
        with pytest.raises(ActionError) as refused:
            action_args(body)
        shown_digits = f"{sign}{'1' * 12}"[:12]
        assert str(refused.value) == (
            f"a JSON number of {digits} digits ({shown_digits}...): no value holds more than 100"
        )
    assert action_args(b'{"number": -' + b"9" * 100 + b"}")["number"] == -int("9" * 100)


async def test_a_subscription_with_a_number_of_thousands_of_digits_says_so() -> None:
    aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard needs aiohttp")
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0, interval=0.05)
        async with web, aiohttp.ClientSession() as session:
            async with session.ws_connect(f"{web.url}ws") as ws:
                await ws.send_str('{"subscribe": "machine", "index": ' + "1" * 5000 + "}")
                for _ in range(50):
                    frame = json.loads(await ws.receive_str(timeout=IO_TIMEOUT))
                    if frame["type"] != "fleet":
                        break
                assert frame == {
                    "type": "error",
                    "error": "bad subscription: a JSON number of 5000 digits (111111111111...): "
                    "no value holds more than 100",
                }


@pytest.mark.parametrize("typed", ["1", "2", " 3 ", "4"])
async def test_a_fault_kind_is_a_name_as_on_the_command_line(typed: str) -> None:
    """``{"kind": "1"}`` armed a delay, though the refusal of ``"5"`` named the kinds only and
    ``sim fault 1`` is refused: a kind is its name on both."""
    async with serving() as served:
        await fails(2, "sim", "fault", typed.strip(), *at(served), prefix="focas-net sim fault")
        station = Station(0, served.machine)
        with pytest.raises(ActionError) as refused:
            perform(station, "inject_fault", {"kind": typed, "arg": 5})
        assert str(refused.value) == (
            f"kind: unknown fault kind {typed!r} (one of delay, drop, error, split)"
        )
        assert len(station.faults) == 0
