"""A seventh new user's pass over the dashboard: each action's fields at their edges and of
wrong types, request bodies and addresses a page never sends, the live updates' subscription,
and the page in a browser; each case that was wrong once, kept."""

from __future__ import annotations

import json
from typing import Any

import pytest
from cli_support import at, fails, ok
from support import serving

from focas_net._typed import NO_PASSWORD_NOTE, decimal_number
from focas_net.errors import EW
from focas_net.protocol import AutMode, FaultKind, alarm_time_text, alarm_type_of, ew_of_text
from focas_net.sim import DataItem, MachineError, ParamKind, default_machine
from focas_net.web import (
    ActionError,
    Dashboard,
    Station,
    machine_view,
    macro_rows,
    param_text,
    parse_web_address,
    perform,
    pmc_address,
    stations_of,
)


def _station() -> Station:
    return Station(0, default_machine())


# -- what was typed, read alike by the page and the command line ----------------------------
@pytest.mark.parametrize("typed", ["md\u0131", "MD\u0130", "m\u0435m"])
def test_a_mode_name_of_other_letters_is_no_mode(typed: str) -> None:
    """``{"mode": "md\u0131"}`` (a dotless i) set MDI, as ``sim panel --mode md\u0131`` did:
    upper-cased, the name read as MDI."""
    with pytest.raises(ValueError, match="unknown mode"):
        AutMode.parse_panel(typed)
    station = _station()
    before = station.machine.panel.mode
    with pytest.raises(ActionError, match=r"^mode: unknown mode '.*' \(one of MDI, MEM"):
        perform(station, "panel", {"mode": typed})
    assert station.machine.panel.mode == before


@pytest.mark.parametrize("typed", ["+1", "99", "-1", "0x1"])
def test_a_mode_typed_as_text_is_read_as_the_command_line_reads_it(typed: str) -> None:
    """``{"mode": "+1"}`` set MEM and ``{"mode": "99"}`` was EW_DATA, where ``--mode +1`` and
    ``--mode 99`` are "unknown mode"; text is now read as ``--mode`` reads it."""
    station = _station()
    station.machine.set_panel(mode=int(AutMode.MDI))
    with pytest.raises(ActionError) as refused:
        perform(station, "panel", {"mode": typed})
    shown = typed if typed.isdigit() else repr(typed)  # (digits: a mode's number, as --mode 99)
    assert str(refused.value) == (
        f"mode: unknown mode {shown} (one of MDI, MEM, EDIT, HND, JOG, TJOG, THND, INC, REF, RMT)"
    )
    assert station.machine.panel.mode == AutMode.MDI
    perform(station, "panel", {"mode": "1"})  # an aut number as text, as --mode 1
    assert station.machine.panel.mode == AutMode.MEM


@pytest.mark.parametrize("typed", ["F0", "f0", " F0 "])
def test_the_rapid_override_takes_f0_as_the_command_line_does(typed: str) -> None:
    """``{"rapid": "F0"}`` was "not a whole number: 'F0'" though ``sim override --rapid F0``
    sets it."""
    station = _station()
    perform(station, "overrides", {"rapid": 50})
    perform(station, "overrides", {"rapid": typed})
    assert station.machine.overrides(path=1)[1] == 0


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ({"alm_type": 99}, "alarm type 99 is outside -1..31"),
        ({"alm_type": -2}, "alarm type -2 is outside -1..31"),
        ({"alm_no": -2}, "alarm number -2 is outside -1..32767"),
        ({"alm_type": 0, "alm_no": 40000}, "alarm number 40000 is outside -1..32767"),
    ],
)
def test_a_clear_of_a_number_no_alarm_has_is_refused_by_the_machine(
    args: dict[str, int], words: str
) -> None:
    """``clear_alarms {"alm_type": 99}`` answered ``cleared: 0`` (the command line refuses
    type 99 itself; the machine said nothing): the machine now refuses it, for every front
    end."""
    station = _station()
    station.machine.raise_alarm(0, 0, 100, "x")
    with pytest.raises(MachineError) as refused:
        perform(station, "clear_alarms", args)
    assert (refused.value.ew, refused.value.detail) == (EW.DATA, words)
    assert len(station.machine.active_alarms()) == 1


@pytest.mark.parametrize(
    ("action", "args"),
    [
        ("pmc_bit", {"area": "R", "address": 0, "bit": 0}),
        ("unlock", {"password": "1234"}),
        ("inject_fault", {"kind": "drop"}),
        ("clear_faults", {}),
    ],
)
def test_a_machine_wide_action_of_a_path_the_machine_has_not_is_refused(
    action: str, args: dict[str, Any]
) -> None:
    """``pmc_bit {..., "path": 2}`` of a one-path machine flipped the bit: the docs say a path
    the machine has not is EW_PATH, for every action."""
    station = _station()
    digest = station.machine.state_digest()
    with pytest.raises(MachineError) as refused:
        perform(station, action, {**args, "path": 2})
    assert refused.value.ew == EW.PATH
    assert refused.value.detail == "the CNC has no path 2: it has path 1 only"
    assert station.machine.state_digest() == digest
    assert len(station.faults) == 0


@pytest.mark.parametrize(
    ("action", "args", "words"),
    [
        ("cycle", {"action": 5}, "action: unknown cycle action 5 (one of start, hold, reset)"),
        ("cycle", {"action": None}, "action: start, hold or reset is needed"),
        ("cycle", {}, "action: start, hold or reset is needed"),
        ("inject_fault", {}, "kind: one of delay, drop, error, split is needed"),
        ("pmc_bit", {"address": 0, "bit": 0}, "area: a PMC area's letter (X, R, ...) is needed"),
        (
            "panel",
            {"pwe": [1]},
            "pwe: expected 1, on, true, yes or set, or 0, off, false, no or clear, got [1]",
        ),
        ("panel", {"mode": {"a": 1}}, 'mode: not a whole number: {"a": 1}'),
        ("overrides", {"feed": True}, "feed: a number is needed, got true"),
        ("write_macro", {"number": 500, "value": False}, "value: a number is needed, got false"),
        ("unlock", {"password": False}, "password: text is needed, got false"),
        ("select_program", {}, "number: a program number is needed (e.g. O1000)"),
        ("select_program", {"number": None}, "number: a program number is needed (e.g. O1000)"),
        (
            "select_program",
            {"number": 1.0},
            "number: 1.0 is not a program number (O1..O99999999, e.g. O1000)",
        ),
        (
            "select_program",
            {"number": True},
            "number: true is not a program number (O1..O99999999, e.g. O1000)",
        ),
    ],
)
def test_a_json_value_is_named_as_json_not_as_python(
    action: str, args: dict[str, Any], words: str
) -> None:
    """``{"action": null}`` was "got None", ``true`` "got True", ``{"a": 1}`` "{'a': 1}":
    Python's words for what the page sent as JSON; a key not given was "got ''" (nothing
    typed) or "unknown PMC area ''"."""
    station = _station()
    station.machine.set_panel(mode=int(AutMode.MDI), pwe=1)
    digest = station.machine.state_digest()
    with pytest.raises(ActionError) as refused:
        perform(station, action, args)
    assert str(refused.value) == words
    assert station.machine.state_digest() == digest


# -- requests no page sends ------------------------------------------------------------------
aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard tests need aiohttp")


async def test_requests_no_page_sends_are_answered_in_json_and_change_nothing() -> None:
    """A body nested 100000 deep was a 500 and a traceback on the server's log; a body over
    the size limit a plain-text 413; ``/api/machines/\uff11`` (a full-width 1) was machine 1."""
    machines = [default_machine(), default_machine()]
    async with serving(machines[0]) as served:
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            url = f"{web.url}api/machines/0/actions/cycle"
            headers = {"Content-Type": "application/json"}
            for body in ("[" * 100_000 + "]" * 100_000, '{"a":' * 100_000 + "1" + "}" * 100_000):
                async with session.post(url, data=body.encode(), headers=headers) as answer:
                    assert answer.status == 400
                    assert await answer.json() == {
                        "ok": False,
                        "error": "the body nests too deep to be an action's arguments",
                    }
            huge = json.dumps({"msg": "A" * (2 * 1024 * 1024)}).encode()
            alarm = f"{web.url}api/machines/0/actions/raise_alarm"
            async with session.post(alarm, data=huge, headers=headers) as answer:
                assert answer.status == 413
                assert (await answer.json())["error"] == (
                    "the body is more than 1048576 bytes: an action takes a small JSON object"
                )
            for index in ("%EF%BC%90", "%D9%A0"):  # a full-width 0, an Arabic-Indic 0
                async with session.get(f"{web.url}api/machines/{index}") as answer:
                    assert answer.status == 404
                    assert (await answer.json())["ok"] is False
        assert served.machine.active_alarms() == []


@pytest.mark.parametrize(
    ("message", "reason"),
    [
        ("[" * 100_000 + "]" * 100_000, "bad subscription: not JSON: '" + "[" * 40 + "'"),
        (
            '{"subscribe": "machine", "index": null}',
            'bad subscription: "index" is a machine\'s number, got null',
        ),
        (
            '{"subscribe": "machine", "index": 0, "path": true}',
            'bad subscription: "path" is a whole number, got true',
        ),
        ('{"subscribe": null}', 'bad subscription: "subscribe" is "fleet" or "machine", got null'),
        (
            '{"subscribe": "fleet", "subscribe": "machine", "index": 0}',
            "bad subscription: the key 'subscribe' is given twice",
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_strat": 100}',
            "bad subscription: a machine subscription takes no 'pmc_strat' (it takes index, "
            "path, pmc_area, pmc_start, subscribe)",
        ),
        (
            '{"subscribe": "fleet", "index": 0}',
            "bad subscription: a fleet subscription takes no 'index' (it takes subscribe)",
        ),
        ('{"subscribe": []}', 'bad subscription: "subscribe" is "fleet" or "machine", got []'),
    ],
)
async def test_a_subscription_no_page_sends_is_refused_and_the_socket_lives(
    message: str, reason: str
) -> None:
    """A subscription nested 100000 deep closed the socket with a traceback on the server's
    log; ``null`` was named ``None``; a key given twice was read as its last and a misspelt key
    was left unread (actions refuse both)."""
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0, interval=0.02)
        async with web, aiohttp.ClientSession() as session:
            async with session.ws_connect(f"{web.url}ws") as ws:
                await ws.send_str(message)
                for _ in range(50):
                    frame = json.loads(await ws.receive_str(timeout=5.0))
                    if frame["type"] == "error":
                        break
                assert frame == {"type": "error", "error": reason}
                await ws.send_json({"subscribe": "machine", "index": 0})
                for _ in range(50):
                    frame = json.loads(await ws.receive_str(timeout=5.0))
                    if frame["type"] == "machine":
                        break
                assert frame["data"]["index"] == 0


# -- the command line, where the fix lives in a table both read ------------------------------
async def test_the_command_line_refuses_a_mode_of_other_letters_and_takes_f0() -> None:
    async with serving() as served:
        line = await fails(2, "sim", "panel", *at(served), "--mode", "md\u0131", prefix="focas-net")
        assert line.startswith(
            "focas-net sim panel: error: argument --mode: unknown mode 'md\u0131' (one of MDI, MEM"
        )
        assert served.machine.panel.mode == AutMode.MEM
        assert "rapid F0," in await ok("sim", "override", *at(served), "--rapid", "F0")


# -- the page says what the command line says -----------------------------------------------
def test_an_unlock_without_a_password_says_what_it_means_as_the_command_line_does() -> None:
    """The page answered "unlock: done" where ``focas-net unlock`` says the CNC has no
    password and what a parameter write needs instead."""
    station = _station()
    answer = perform(station, "unlock", {"password": "ab"})
    assert answer == {"ok": True, "password_set": False, "note": NO_PASSWORD_NOTE}
    assert NO_PASSWORD_NOTE.startswith("the CNC has no parameter password: it accepts any")
    station.machine.set_param_password("1234")
    assert perform(station, "unlock", {"password": "1234"}) == {"ok": True, "password_set": True}


@pytest.mark.parametrize(
    ("typed", "address"), [("0x10", ("R", 16)), ("+16", ("R", 16)), (" 0b1 ", ("R", 1))]
)
def test_a_pmc_address_is_a_whole_number_as_pmc_read_takes_it(
    typed: str, address: tuple[str, int]
) -> None:
    """PMC **from** refused ``0x10``, which ``focas-net pmc read R 0x10`` reads as R16."""
    assert pmc_address(typed, "R") == address
    with pytest.raises(ValueError, match=r"^PMC start address -1 is outside 0\.\.65535$"):
        pmc_address("-1", "R")


@pytest.mark.parametrize(("typed", "number"), [("PS", 3), ("ex", 15), (" SV ", 6), ("0xF", 15)])
def test_an_alarm_type_is_taken_by_its_name_as_the_command_line_takes_it(
    typed: str, number: int
) -> None:
    """The page's type box refused ``PS``, though the alarms it lists are named so and the
    command line and the client take the name."""
    station = _station()
    perform(station, "raise_alarm", {"alm_type": typed, "alm_no": 1, "msg": "x"})
    (alarm,) = station.machine.active_alarms()
    assert alarm.alm_type == number
    assert perform(station, "clear_alarms", {"alm_type": typed}) == {"ok": True, "cleared": 1}


@pytest.mark.parametrize("typed", ["XX", "P\u017f", "\u03a1\u03a3"])
def test_an_unknown_alarm_type_name_is_refused_in_one_set_of_words(typed: str) -> None:
    """The command line said ``(known: SW PW ...)``, the client ``(one of SW PW ..., or
    0..31)``; the page took no name. One reader now, for all three (a long s that upper-cases
    to ``PS`` is no name)."""
    words = (
        f"unknown alarm type {typed!r} (one of SW PW IO PS OT OH SV SR MC SP DS IE BG SN EX PC, "
        "or 0..31)"
    )
    with pytest.raises(ValueError) as refused:
        alarm_type_of(typed)
    assert str(refused.value) == words
    with pytest.raises(ActionError) as refused_page:
        perform(_station(), "raise_alarm", {"alm_type": typed, "alm_no": 1})
    assert str(refused_page.value) == f"alm_type: {words}"


async def test_the_command_line_names_an_unknown_alarm_type_in_the_same_words() -> None:
    async with serving() as served:
        line = await fails(2, "sim", "alarm", *at(served), "XX0100", "msg", prefix="focas-net")
        assert line == (
            "focas-net sim alarm: error: argument ALARM: unknown alarm type 'XX' (one of SW PW "
            "IO PS OT OH SV SR MC SP DS IE BG SN EX PC, or 0..31); see focas-net sim alarm --help"
        )
        assert served.machine.active_alarms() == []


@pytest.mark.parametrize(
    ("typed", "address"),
    [("0x1F90", ("127.0.0.1", 8080)), ("+80", ("127.0.0.1", 80)), ("[::1]:0b0", ("::1", 0))],
)
def test_the_web_port_is_read_as_port_reads_a_number(typed: str, address: tuple[str, int]) -> None:
    """``serve --port 0x10`` listens on 16, ``--web 0x10`` was "the port must be a number"."""
    assert parse_web_address(typed) == address
    with pytest.raises(ValueError, match=r"the port must be a number 0\.\.65535"):
        parse_web_address("\uff11")


@pytest.mark.parametrize(
    ("query", "words"),
    [
        ("api/machines/0?pth=2", "/api/machines/0 takes no query key 'pth' (it takes path)"),
        ("api/machines/0?path=1&path=2", "the query key 'path' is given twice"),
        ("api/machines/0/params?q=13&q=20", "the query key 'q' is given twice"),
        (
            "api/machines/0/macros?q=500&Path=1",
            "/api/machines/0/macros takes no query key 'Path' (it takes path, q)",
        ),
        (
            "api/machines/0/pmc?area=R&start=0&path=1",
            "/api/machines/0/pmc takes no query key 'path' (it takes area, start)",
        ),
        ("api/fleet?machine=1", "/api/fleet takes no query key 'machine' (it takes none)"),
    ],
)
async def test_a_query_key_not_taken_or_given_twice_is_refused(query: str, words: str) -> None:
    """``?path=1&path=2`` showed path 1 and ``?pth=2`` path 1 too: the reads refuse what the
    actions refuse (a key given twice, a key they do not take)."""
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            async with session.get(f"{web.url}{query}") as answer:
                assert answer.status == 400
                assert await answer.json() == {"ok": False, "error": words}


@pytest.mark.parametrize("typed", ["\u0661\u0663\u0662\u0660", "13\uff12"])
async def test_a_parameter_search_in_digits_of_another_script_says_why(typed: str) -> None:
    """``\u0661\u0663\u0662\u0660`` (1320 in Arabic-Indic digits) in the parameter search said
    "no parameter found"; the macro search and every number box name such digits."""
    async with serving() as served:
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            url = f"{web.url}api/machines/0/params"
            async with session.get(url, params={"q": typed}) as answer:
                assert answer.status == 400
                error = (await answer.json())["error"]
                assert error.startswith(f"parameter search: {typed!r} holds a digit beyond ASCII")
            async with session.get(url, params={"q": "1320"}) as answer:
                assert [p["number"] for p in (await answer.json())["params"]] == [1320]


def test_an_alarms_time_is_written_as_the_command_line_writes_it() -> None:
    """The page's history said ``2026-12-07 10:54:37Z`` and its JSON ``"time":
    "2026-12-07T10:54:37+00:00"``, where ``alarms --history`` writes ``"occurred_at":
    "2026-12-07T10:54:37Z"``: one spelling, one key."""
    station = _station()
    station.machine.raise_alarm(0, 15, 1001, "COOLANT LEVEL LOW")
    (entry,) = station.machine.alarm_history()
    view = machine_view(0, station.machine, 8193)
    (shown,) = view["history"]
    assert shown["occurred_at"] == entry.occurred_at.strftime("%Y-%m-%dT%H:%M:%SZ")
    assert "time" not in shown
    assert alarm_time_text(entry.occurred_at) == shown["occurred_at"]


@pytest.mark.parametrize(("typed", "code"), [("EW_BUSY", -1), ("passwd", 17), ("-1", -1)])
def test_an_error_faults_code_is_taken_by_its_name_as_the_command_line_takes_it(
    typed: str, code: int
) -> None:
    """``{"kind": "ERROR", "arg": "EW_BUSY"}`` was "not a whole number", though the box's hint
    says "the EW code" and ``sim fault error --arg EW_BUSY`` takes it."""
    station = _station()
    perform(station, "inject_fault", {"kind": "ERROR", "arg": typed})
    assert [(f.kind, f.arg) for f in station.faults.listing().faults] == [(FaultKind.ERROR, code)]


def test_an_unknown_ew_name_is_refused_in_the_command_lines_words() -> None:
    station = _station()
    with pytest.raises(ActionError) as refused:
        perform(station, "inject_fault", {"kind": "ERROR", "arg": "EW_BUZY"})
    assert str(refused.value) == "arg: unknown EW code 'EW_BUZY'"
    with pytest.raises(ValueError, match=r"^unknown EW code 'EW_BUZY'$"):
        ew_of_text("EW_BUZY")
    assert len(station.faults) == 0


def test_a_position_kind_is_named_as_position_kind_and_watch_name_it() -> None:
    """The page's column and its JSON said ``distance to go`` / ``distance_to_go`` where
    ``position --kind distance`` and ``watch --json`` say ``distance``."""
    view = machine_view(0, default_machine(), 8193)
    assert [set(p) for p in view["positions"]] == [
        {"axis", "absolute", "machine", "relative", "distance"}
    ] * 3


@pytest.mark.parametrize(("typed", "shown"), [("-0.000000001", "-0.000000001"), ("1.50", "1.50")])
def test_a_macro_value_is_shown_as_the_command_line_shows_it(typed: str, shown: str) -> None:
    """``-0.000000001`` written from the page came back as ``-1E-9`` (in its answer and its
    list), which ``macro get`` shows as ``-0.000000001`` and the page's own box refuses (no
    exponent)."""
    station = _station()
    answer = perform(station, "write_macro", {"number": 500, "value": typed})
    assert answer["value"] == shown
    (row,) = macro_rows(station.machine, station.macro_numbers(), "500-500")
    assert row["value"] == shown
    assert decimal_number(row["value"]) == decimal_number(typed)  # the box reads it back


def test_a_real_parameter_of_many_decimals_is_shown_without_an_exponent() -> None:
    item = DataItem(7000, 4, low=0, high=10**9, values=[1], kind=ParamKind.REAL, decimals=9)
    assert param_text(item, 1) == "0.000000001"


@pytest.mark.parametrize(
    ("number", "axis", "words"),
    [
        (1320, 4, "axis 4 is outside 1..3: the path has 3 axes"),
        (1320, 0, "parameter 1320 is an axis parameter: give an axis 1..3, got 0"),
        (9968, 1, "parameter 9968 is not an axis parameter: give axis 0, got 1"),
    ],
)
def test_a_parameters_axis_is_refused_naming_the_parameter_not_an_item(
    number: int, axis: int, words: str
) -> None:
    """The page said ``item 1320 needs an axis 1..3`` and ``item 9968 is not an axis item``:
    the machine's word for its table, where every front end says parameter."""
    station = _station()
    station.machine.set_panel(mode=int(AutMode.MDI), pwe=1)
    with pytest.raises(MachineError) as refused:
        perform(station, "write_param", {"number": number, "axis": axis, "value": "0x1"})
    assert (refused.value.ew, refused.value.detail) == (EW.ATTRIB, words)
    with pytest.raises(MachineError) as read:
        station.machine.read_param(number, axis)
    assert read.value.detail == words
    with pytest.raises(MachineError, match=r": the CNC has no diagnostic 99999$"):
        station.machine.read_diag(99999, 0)
