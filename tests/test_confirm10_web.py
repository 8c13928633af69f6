"""A confirming tenth pass over the dashboard: the page's refusals and the command line's and
the clients' for the same input on the same machine (a PMC area the machine has not, a macro
value of ten decimals, a cycle action that is no text, a path past the CNC's), and the page's
HTTP answers to a request the dashboard has no route for, each kept."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from decimal import Decimal
from typing import Any

import pytest
from cli_support import at, fails, ok
from support import serving, with_both_clients
from web_support import page_refusal

from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.server import FocasServer
from focas_net.sim import default_machine
from focas_net.web import Dashboard, Station, perform, stations_of
from focas_net.web.broadcast import Broadcaster, machine_topic

aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard tests need aiohttp")


@asynccontextmanager
async def _dashboard() -> AsyncIterator[Dashboard]:
    """A default machine on 127.0.0.1 and its dashboard, both on ephemeral ports."""
    async with FocasServer(default_machine(), host="127.0.0.1", port=0, grace_period=1.0) as srv:
        async with Dashboard(stations_of(srv), port=0) as web:
            yield web


async def _answer(method: str, url: str, body: Any = None) -> tuple[int, str, Any]:
    """The status, the content type and the JSON of a ``method`` request of ``url``."""
    async with aiohttp.ClientSession() as session:
        async with session.request(method, url, json=body) as response:
            return response.status, response.content_type, await response.json()


def _writable(station: Station) -> Station:
    """``station`` with its panel in MDI and PWE on (parameter writes pass the gates)."""
    perform(station, "panel", {"mode": "MDI", "pwe": 1})
    return station


# -- a PMC area the machine has not, an address past an area ----------------------------------
async def test_a_pmc_area_the_machine_has_not_is_the_cncs_on_the_page_and_the_cli() -> None:
    """``pmc bit E 0.1 1`` said "the CNC has no PMC area E" where the page said "the machine
    has no PMC area E (it has X, Y, ...)": one noun, the page adding the areas the machine
    knows (the wire carries the EW code only)."""
    async with serving() as served:
        page = page_refusal(Station(0, served.machine), "pmc_bit",
                            {"area": "E", "address": 0, "bit": 1, "value": 1})  # fmt: skip
        common = "the CNC has no PMC area E"
        assert page == f"{common} (it has X, Y, F, G, R, T, C, D, K, A)"
        for protocol in ("packed", "native"):
            line = await fails(1, "pmc", "bit", "E", "0.1", "1", "--protocol", protocol,
                               *at(served))  # fmt: skip
            assert line.endswith(f"; {common}")


async def test_an_address_past_an_area_is_worded_alike_the_page_naming_its_range() -> None:
    """``pmc bit R 8000.0``: the command line's words are the page's, which add the range."""
    async with serving() as served:
        page = page_refusal(Station(0, served.machine), "pmc_bit",
                            {"area": "R", "address": 8000, "bit": 0})  # fmt: skip
        common = "R8000 goes past the end of PMC area R"
        assert page == f"{common} (R0..R7999)"
        line = await fails(1, "pmc", "bit", "R", "8000.0", *at(served))
        assert line.endswith(f"; {common}")


# -- a macro value of ten decimals ----------------------------------------------------------------
@pytest.mark.parametrize("value", [1.0000000001, "1.0000000001", "-0.0000000001"])
async def test_a_macro_value_no_wire_carries_is_refused_by_the_page_before_the_write(
    value: object,
) -> None:
    """The JSON number ``1.0000000001`` was a 409 EW_DATA from the machine while the command
    line refuses it before the write (exit 2): the page checks it with the clients' rule,
    before the machine is asked (a read-only machine says the value first too)."""
    async with serving(default_machine(read_only=True)) as served:
        station = Station(0, served.machine)
        typed = str(value)
        words = page_refusal(station, "write_macro", {"number": 100, "value": value})
        line = await fails(2, "macro", "set", "100", typed, *at(served), prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        assert words.startswith(f"#100: macro value {typed} does not fit a macro variable")


async def test_a_macro_value_of_trailing_zeros_is_written_by_the_page_as_by_the_cli() -> None:
    """``macro set 100 1.0000000000`` writes 1 (the clients send the fewest digits that hold
    it); the page refused the same text with the machine's EW_DATA."""
    async with serving() as served:
        station = Station(0, served.machine)
        answer = perform(station, "write_macro", {"number": 100, "value": "1.0000000000"})
        assert answer == {"ok": True, "number": 100, "value": "1"}
        assert served.machine.read_macro(100) == Decimal(1)
        await ok("macro", "set", "101", "1.0000000000", *at(served))
        assert served.machine.read_macro(101) == Decimal(1)


# -- a request of a method or a URL the dashboard has not ---------------------------------------
@pytest.mark.parametrize(
    ("method", "path", "status", "words"),
    [
        ("GET", "api/machines/0/actions/cycle", 405,
         "GET /api/machines/0/actions/cycle: this URL takes POST"),
        ("DELETE", "api/fleet", 405, "DELETE /api/fleet: this URL takes GET"),
        ("GET", "api/machine/0", 404, "/api/machine/0: the dashboard has no such URL"),
    ],
)  # fmt: skip
async def test_a_method_or_url_the_api_has_not_is_answered_in_json(
    method: str, path: str, status: int, words: str
) -> None:
    """A GET of an action's URL answered aiohttp's plain text ``405: Method Not Allowed``, not
    JSON as the dashboard's other refusals are."""
    async with _dashboard() as web:
        got = await _answer(method, f"{web.url}{path}")
        assert got == (status, "application/json", {"ok": False, "error": words})


# -- a cycle action that is no text -----------------------------------------------------------
@pytest.mark.parametrize(("typed", "shown"), [(1, "1"), (True, "true"), ([], "[]")])
async def test_a_cycle_action_that_is_no_text_is_worded_as_the_cli_words_one(
    typed: object, shown: str
) -> None:
    """``{"action": 1}`` said "action: text is needed, got 1" where ``sim cycle 1`` says
    "unknown cycle action '1' (one of start, hold, reset)": one wording, the JSON value named."""
    async with serving() as served:
        words = "(one of start, hold, reset)"
        page = page_refusal(Station(0, served.machine), "cycle", {"action": typed})
        assert page == f"action: unknown cycle action {shown} {words}"
        line = await fails(2, "sim", "cycle", "1", *at(served), prefix="focas-net sim cycle: ")
        assert f"unknown cycle action '1' {words}" in line


# -- a path past the CNC's ----------------------------------------------------------------------
async def test_a_path_past_the_cncs_is_refused_by_both_clients_in_the_machines_words() -> None:
    """The clients said "cnc_statinfo: path 3, the CNC has paths 1..1" where the machine, the
    command line and the page say "the CNC has no path 3: it has path 1 only": one wording,
    from one function."""
    async with with_both_clients(default_machine()) as (machine, cnc, native):
        page = page_refusal(Station(0, machine), "cycle", {"action": "reset", "path": 3})
        assert page == "the CNC has no path 3: it has path 1 only"
        for client in (cnc, native):  # (each names FANUC's function first)
            with pytest.raises(CncError) as refused:
                await client.read_status(path=3)
            assert refused.value.ew == EW.PATH
            assert str(refused.value).endswith(f": {page}")
            assert "paths 1.." not in str(refused.value)


async def test_a_fault_kind_that_is_no_text_is_worded_as_the_cli_words_one() -> None:
    """``{"kind": 1}`` said "kind: text is needed, got 1" where ``sim fault 1`` says "unknown
    fault kind '1' (one of ...)": one wording, and nothing armed."""
    async with serving() as served:
        words = "(one of delay, drop, error, split)"
        station = Station(0, served.machine)
        assert page_refusal(station, "inject_fault", {"kind": 1}) == (
            f"kind: unknown fault kind 1 {words}"
        )
        line = await fails(2, "sim", "fault", "1", *at(served), prefix="focas-net sim fault: ")
        assert f"unknown fault kind '1' {words}" in line
        assert len(station.faults) == 0


# -- an alarm raised with no message ----------------------------------------------------------
async def test_an_alarm_of_no_message_takes_the_tables_text_without_a_note_of_a_cut() -> None:
    """``raise_alarm`` PS5 with no message answered "the CNC keeps 21 characters of a message:
    'NO DATA AFTER ADDRESS'", as if the text given had been cut: the machine took its alarm
    table's text, as ``sim alarm PS5`` shows it, and nothing was cut."""
    async with serving() as served:
        station = Station(0, served.machine)
        answer = perform(station, "raise_alarm", {"alm_type": "PS", "alm_no": 5, "msg": ""})
        assert answer == {"ok": True, "raised": True, "msg": "NO DATA AFTER ADDRESS"}
        out = await ok("sim", "alarm", "PS6", *at(served))
        assert out == "raised PS0006 ILLEGAL USE OF NEGATIVE SIGN\n"
        assert perform(station, "raise_alarm", {"alm_type": "PS", "alm_no": 7}) == {
            "ok": True,
            "raised": True,
            "msg": "ILLEGAL USE OF DECIMAL POINT",
        }
        cut = perform(station, "raise_alarm", {"alm_type": "PS", "alm_no": 8, "msg": "A" * 40})
        assert cut["note"] == f"the CNC keeps 32 characters of a message: {'A' * 32!r}"


# -- a cycle start or a program search in a mode that does not take it -------------------------
@pytest.mark.parametrize(
    ("action", "args", "argv", "words"),
    [
        ("cycle", {"action": "start"}, ("sim", "cycle", "start"), "cycle start refused"),
        ("select_program", {"number": "O1"}, ("program", "select", "O1"),
         "program search refused"),
    ],
)  # fmt: skip
async def test_a_mode_that_does_not_take_it_is_worded_alike_on_the_page_and_the_cli(
    action: str, args: dict[str, Any], argv: tuple[str, ...], words: str
) -> None:
    """In JOG mode the page said "cycle start refused: the mode is JOG, not MEM" and "program
    search in JOG mode: MEM or EDIT" where the command line said "cycle start runs in MEM mode
    only" and "program search needs MEM or EDIT mode": one wording, the page naming the mode
    the machine is in (the wire carries the EW code only), the command line what to type."""
    modes = "MEM" if action == "cycle" else "MEM or EDIT"
    async with serving() as served:
        station = Station(0, served.machine)
        perform(station, "panel", {"mode": "JOG"})
        assert page_refusal(station, action, args) == f"{words}: the mode is JOG, not {modes}"
        line = await fails(1, *argv, *at(served))
        assert line.endswith(
            f"; {words}: the mode is JOG, not {modes} (focas-net sim panel --mode MEM)"
        )


async def test_sim_alarm_axis_help_names_an_alarms_axis_as_the_page_does() -> None:
    """``sim alarm --help`` said "axis 1..n for an axis item; 0 for a non-axis item" (a
    parameter's words) where the page's axis box says "0: an alarm of no axis"."""
    out = await ok("sim", "alarm", "--help")
    assert "axis item" not in out
    assert "0: an alarm of no axis" in " ".join(out.split())


# -- a parameter's axis, a number the CNC has not -----------------------------------------------
@pytest.mark.parametrize(("number", "axis"), [(1320, -1), (6711, 40000)])
async def test_an_axis_no_field_carries_is_refused_by_the_page_before_the_write(
    number: int, axis: int
) -> None:
    """``param set 1320 1 --axis -1`` is refused by the parser in the clients' words ("axis -1
    is outside 0..32767 (0: not an axis parameter)") where the page asked the machine, which
    said "parameter 1320 is an axis parameter: give an axis 1..3, got -1" (409 EW_ATTRIB)."""
    words = f"axis {axis} is outside 0..32767 (0: not an axis parameter)"
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        args = {"number": number, "axis": axis, "value": "1"}
        assert page_refusal(station, "write_param", args) == f"axis: {words}"
        line = await fails(2, "param", "set", str(number), "1", "--axis", str(axis),
                           *at(served), prefix="focas-net param set: ")  # fmt: skip
        assert f"argument --axis: {words};" in line


@pytest.mark.parametrize(
    ("action", "args", "argv", "what"),
    [
        ("write_param", {"number": 1234, "value": "1"}, ("param", "set", "1234", "1"),
         "parameter 1234"),
        ("write_macro", {"number": 50, "value": 1}, ("macro", "set", "50", "1"),
         "macro variable #50"),
    ],
)  # fmt: skip
async def test_a_number_the_cnc_has_not_is_worded_alike_on_the_page_and_the_cli(
    action: str, args: dict[str, Any], argv: tuple[str, ...], what: str
) -> None:
    """The page said "no parameter 1234" and "no macro variable #50" where the command line
    says "the CNC has no parameter 1234": one wording, the machine's."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        assert page_refusal(station, action, args) == f"the CNC has no {what}"
        line = await fails(1, *argv, *at(served))
        assert line.endswith(f"; the CNC has no {what}")


# -- a path no CNC has ----------------------------------------------------------------------------
@pytest.mark.parametrize("path", [0, -1, 11])
async def test_a_path_no_field_carries_is_refused_as_the_cli_and_the_clients_refuse_it(
    path: int,
) -> None:
    """``--path 0`` is refused by the parser, as the clients refuse ``path=0``: "path 0 is
    outside 1..10"; the page asked the machine, which said "the CNC has no path 0: it has path
    1 only" (409), of an action, a view and a live view alike. A path within 1..10 that the
    machine has not is still the machine's to word."""
    words = f"path {path} is outside 1..10"
    async with serving() as served:
        station = Station(0, served.machine)
        page = page_refusal(station, "cycle", {"action": "reset", "path": path})
        assert page == f"path: {words}"
        line = await fails(2, "sim", "cycle", "reset", "--path", str(path), *at(served),
                           prefix="focas-net sim cycle: ")  # fmt: skip
        assert f"argument --path: {words};" in line
        async with FocasClient("127.0.0.1", served.port) as cnc:
            with pytest.raises(ValueError) as refused:
                await cnc.read_status(path=path)
            assert str(refused.value) == words
        b = Broadcaster([station])
        assert b.refusal(machine_topic(0, path=path)) == f"{words} (machine 0)"
        async with Dashboard([station], port=0) as web:
            got = await _answer("GET", f"{web.url}api/machines/0?path={path}")
            assert got == (400, "application/json", {"ok": False, "error": f"path: {words}"})


async def test_an_axis_past_the_paths_is_worded_as_the_cli_and_a_position_word_it() -> None:
    """The page said "parameter 1320 is an axis parameter: give an axis 1..3, got 9" where
    ``param set 1320 1 --axis 9`` says "the path has 3 axes: give --axis 1..3" and ``position
    --axis 9`` "axis 9 is outside 1..3: the path has 3 axes": the machine words it so."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        words = "axis 9 is outside 1..3: the path has 3 axes"
        page = page_refusal(station, "write_param", {"number": 1320, "axis": 9, "value": "1"})
        assert page == words
        line = await fails(1, "param", "set", "1320", "1", "--axis", "9", *at(served))
        assert line.endswith(f"{words}); give --axis 1..3")
