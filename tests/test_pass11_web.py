"""An eleventh new user's pass over the dashboard: a number typed on the page in another base
(``0x10000``) named as typed in its refusal, as the command line names it, through one rule;
a panel switch or a PMC bit given a number that is no switch, refused in the command line's
words; and the page's other controls with good and bad input, each case that was wrong once,
kept."""

from __future__ import annotations

import re
from typing import Any

import pytest
from cli_support import at, fails, ok
from support import serving, two_path_lathe
from web_support import page_refusal

from focas_net.sim import default_machine
from focas_net.web import Station, perform
from focas_net.web.view import param_rows, pmc_address


def _writable(station: Station) -> Station:
    """``station`` with its panel in MDI and PWE on (parameter writes pass the gates)."""
    perform(station, "panel", {"mode": "MDI", "pwe": 1})
    return station


def _words(line: str) -> str:
    """The words of a command line's refusal, without what names the command and the argument
    (``focas-net param set: error: argument NUMBER[.BIT]: ...; see ...``)."""
    words = re.sub(r"^focas-net(?: [a-z ]+: error: argument \S+)?: ", "", line)
    return words.split("; see focas-net")[0]


# -- a number typed in another base -------------------------------------------------------------
@pytest.mark.parametrize(
    ("action", "args", "key", "argv"),
    [
        ("write_param", {"number": "0x10000", "value": "1"}, "number",
         ["param", "set", "0x10000", "1"]),
        ("write_macro", {"number": "0x10000", "value": "1"}, "number",
         ["macro", "set", "0x10000", "1"]),
        ("write_param", {"number": 6711, "value": "0x80000000"}, "value",
         ["param", "set", "6711", "0x80000000"]),
        ("pmc_bit", {"area": "R", "address": "0x10000", "bit": 1}, "",
         ["pmc", "bit", "R", "0x10000.1", "1"]),
    ],
)  # fmt: skip
async def test_a_number_typed_in_another_base_is_named_as_typed_on_the_page_and_the_cli(
    action: str, args: dict[str, Any], key: str, argv: list[str]
) -> None:
    """``param set 0x10000 1`` says "0x10000 reads as 65536: parameter number 65536 is outside
    0..32767" where the page said "number: parameter number 65536 is outside ...", naming a
    number no one typed; ``param set 6711 0x80000000`` named none typed either. One rule now
    (:func:`focas_net._typed.lead_as_typed`), the page naming the key before it."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        words = _words(await fails(2, *argv, *at(served), prefix="focas-net"))
        assert words.startswith(f"{args.get(key, args.get('address'))} reads as ")
        page = page_refusal(station, action, args)
        assert page == (f"{key}: {words}" if key else words)


async def test_a_macro_value_typed_in_another_base_is_named_as_typed_on_both() -> None:
    """The page said "macro value 2147483648 does not fit" for ``0x80000000`` typed, where
    ``macro set 100 0x80000000`` names the text."""
    async with serving() as served:
        page = page_refusal(
            Station(0, served.machine), "write_macro", {"number": 100, "value": "0x80000000"}
        )
        line = await fails(2, "macro", "set", "100", "0x80000000", *at(served), prefix="focas-net")
        assert page == _words(line)
        assert page.startswith("#100: macro value 0x80000000 does not fit")


async def test_a_pmc_start_typed_in_another_base_is_named_as_typed_on_both() -> None:
    """The page's PMC box of ``0x10000`` said "PMC start address 65536 is outside 0..65535";
    ``pmc read R 0x10000 1`` leads with what was typed."""
    async with serving() as served:
        line = await fails(2, "pmc", "read", "R", "0x10000", "1", *at(served), prefix="focas-net")
    with pytest.raises(ValueError) as refused:
        pmc_address(" 0x10000 ", "R")
    assert str(refused.value) == _words(line)
    assert str(refused.value).startswith("0x10000 reads as 65536: ")


@pytest.mark.parametrize(
    ("action", "args", "words"),
    [
        ("raise_alarm", {"alm_type": "PS", "alm_no": "0x10000"},
         "0x10000 reads as 65536: alarm number 65536 is outside 0..32767"),
        ("raise_alarm", {"alm_type": "0x40", "alm_no": 1},
         "0x40 reads as 64: alarm type 64 is outside 0..31"),
        ("raise_alarm", {"alm_type": "PS", "alm_no": 1, "axis_no": "0x10000"},
         "0x10000 reads as 65536: axis 65536 is outside 0..32767 (0: an alarm of no axis)"),
        ("raise_alarm", {"alm_type": "PS", "alm_no": 1, "axis_no": "0x5"},
         "0x5 reads as 5: axis 5 is outside 0..3: the path has 3 axes"),
        ("clear_alarms", {"alm_no": "0x10000"},
         "0x10000 reads as 65536: alarm number 65536 is outside -1..32767"),
        ("write_param", {"number": 1815, "axis": "0x10000", "value": "1"},
         "axis: 0x10000 reads as 65536: axis 65536 is outside 0..32767 (0: not an axis "
         "parameter)"),
        ("overrides", {"feed": "0x100"},
         "0x100 reads as 256: feed override 256 outside 0..254 %"),
        ("overrides", {"rapid": "0x20"},
         "0x20 reads as 32: rapid override 32 is not a step of FANUC's: 0 (F0), 25, 50 or 100 %"),
        ("overrides", {"spindle": "-0x1"},
         "-0x1 reads as -1: spindle override -1 outside 0..254 %"),
        ("cycle", {"action": "start", "path": "0x0"},
         "path: 0x0 reads as 0: path 0 is outside 1..10"),
        ("cycle", {"action": "start", "path": "0b10"},
         "0b10 reads as 2: the CNC has no path 2: it has path 1 only"),
        ("inject_fault", {"kind": "delay", "arg": "0x1000000"},
         "0x1000000 reads as 16777216: a delay is 0..60000 ms, got 16777216"),
        ("inject_fault", {"kind": "drop", "count": "0o0"},
         "0o0 reads as 0: a fault's count is 1..10000, got 0"),
    ],
)  # fmt: skip
def test_every_typed_number_the_page_refuses_is_named_as_typed(
    action: str, args: dict[str, Any], words: str
) -> None:
    """Each refusal of a number typed in another base, by the page's own checks or by the
    machine's, leads with what was typed, as the command line's ``--axis 0x10000``, ``--feed
    0x100`` and ``--path 0x0`` do; nothing changes."""
    machine = default_machine()
    station = _writable(Station(0, machine))
    before = machine.state_digest()
    assert page_refusal(station, action, args) == words
    assert machine.state_digest() == before


def test_a_number_typed_in_decimal_is_refused_as_before() -> None:
    """A number typed in decimal reads as typed: no lead (``65536`` is what was typed)."""
    station = Station(0, default_machine())
    assert page_refusal(station, "raise_alarm", {"alm_type": "PS", "alm_no": "65536"}) == (
        "alarm number 65536 is outside 0..32767"
    )


# -- a switch given a number that is none -------------------------------------------------------
@pytest.mark.parametrize("switch", ["pwe", "emergency"])
@pytest.mark.parametrize("value", [2, -1])
async def test_a_panel_switch_given_a_number_that_is_none_is_refused_in_the_clis_words(
    switch: str, value: int
) -> None:
    """``{"pwe": 2}`` was refused in the Python API's words, "pwe must be True, False or None
    (unchanged), got 2", where ``sim panel --pwe 2`` names the switch's words: the page says
    those."""
    async with serving() as served:
        line = await fails(2, "sim", "panel", f"--{switch}", str(value), *at(served),
                           prefix="focas-net sim panel: ")  # fmt: skip
        cli = line.split(f"argument --{switch}: ", 1)[1].split("; see ", 1)[0]
        page = page_refusal(Station(0, served.machine), "panel", {switch: value})
        assert page == f"{switch}: {cli}".replace(f"'{value}'", str(value))
        assert (served.machine.panel.pwe, served.machine.panel.emergency) == (0, 0)


def test_a_pmc_bit_given_a_number_that_is_none_is_refused_as_a_switch() -> None:
    """A PMC bit's ``value`` 2 said "value: 0 or 1, got 2", text "2" the switch's words: one
    rule for both."""
    machine = default_machine()
    station = Station(0, machine)
    words = "value: expected 1, on, true, yes or set, or 0, off, false, no or clear, got 2"
    for value in (2, "2"):
        args = {"area": "R", "address": 0, "bit": 1, "value": value}
        got = page_refusal(station, "pmc_bit", args)
        assert got == (words.replace("2", "'2'") if isinstance(value, str) else words)
    assert machine.read_pmc("R", 0, 1) == b"\x00"


# -- what an action that changes nothing says --------------------------------------------------
async def test_raising_an_active_alarm_says_so_on_the_page_as_sim_alarm_does() -> None:
    """``sim alarm PS0100`` of an active alarm says it is active already and keeps its message;
    the page answered ``raise_alarm: done``, its new message left unsaid."""
    async with serving() as served:
        await fails(1, "sim", "clear", "PS0100", *at(served))  # (none active yet)
        station = Station(0, served.machine)
        perform(station, "raise_alarm", {"alm_type": "SV", "alm_no": 411, "axis_no": 2})
        line = (await ok("sim", "alarm", "SV0411", "--axis", "2", *at(served))).strip()
        answer = perform(
            station, "raise_alarm", {"alm_type": "SV", "alm_no": 411, "axis_no": 2, "msg": "NEW"}
        )
        assert answer == {"ok": True, "raised": False, "msg": "", "note": line}
        assert line.startswith("SV0411 (axis 2) is already active (with no message)")


async def test_clearing_when_nothing_matches_says_so_on_the_page_as_sim_clear_does() -> None:
    """``sim clear`` with no alarm says "no active alarms; nothing to clear", ``sim clear
    PS0100`` "no active alarm matches PS0100; nothing cleared", ``sim faults --clear`` "no
    pending faults of this machine; nothing to clear"; the page said ``done`` for each."""
    async with serving() as served:
        station = Station(0, served.machine)
        every = (await ok("sim", "clear", *at(served))).strip()
        assert perform(station, "clear_alarms", {}) == {"ok": True, "cleared": 0, "note": every}
        one = (await fails(1, "sim", "clear", "PS0100", *at(served))).removeprefix("focas-net: ")
        answer = perform(station, "clear_alarms", {"alm_type": "PS", "alm_no": "0100"})
        assert answer == {"ok": True, "cleared": 0, "note": one}
        faults = (await ok("sim", "faults", "--clear", *at(served))).strip()
        assert perform(station, "clear_faults", {}) == {"ok": True, "cleared": 0, "note": faults}


# -- an alarm type left out ---------------------------------------------------------------------
@pytest.mark.parametrize("args", [{"alm_no": 5}, {"alm_type": "", "alm_no": 5}, {"alm_type": " "}])
def test_an_alarm_type_left_out_is_asked_for_by_its_names_too(args: dict[str, Any]) -> None:
    """The type box left empty said "alm_type: a number is needed", where the box takes a name
    (``PS``) as well: the page asks for a type, naming both, as an unknown type's refusal
    names them."""
    action = "raise_alarm" if "alm_no" in args else "clear_alarms"
    words = page_refusal(Station(0, default_machine()), action, args)
    assert words == (
        "alm_type: an alarm type is needed (one of SW PW IO PS OT OH SV SR MC SP DS IE BG SN EX "
        "PC, or 0..31)"
    )


async def test_a_clear_of_one_path_names_the_alarms_active_on_another_as_sim_clear_does() -> None:
    """``sim clear --path 1`` adds "(1 active on path 2)" when the alarms are on the other
    path, ``sim clear PS --path 1`` "(PS is active on path 2: ...)"; the page said nothing of
    them."""
    async with serving(two_path_lathe()) as served:
        station = Station(0, served.machine)
        perform(station, "raise_alarm", {"alm_type": "PS", "alm_no": 100, "path": 2})
        every = (await ok("sim", "clear", "--path", "1", *at(served))).strip()
        assert every.endswith("(1 active on path 2)")
        answer = perform(station, "clear_alarms", {"path": 1})
        assert answer == {"ok": True, "cleared": 0, "note": every}
        line = await fails(1, "sim", "clear", "PS", "--path", "1", *at(served))
        answer = perform(station, "clear_alarms", {"alm_type": "PS", "path": 1})
        words = "no active alarm matches PS on path 1; nothing cleared (PS is active on path 2"
        assert answer["note"] == f"{words})"
        assert line == f"focas-net: {words}: focas-net sim clear PS --path 2)"
        assert len(served.machine.active_alarms(path=2)) == 1


def test_a_parameter_number_typed_in_another_base_finds_the_parameter() -> None:
    """``param get 0x717`` reads parameter 1815; the page's search of ``0x717`` found nothing
    ("no parameter found"), as if no parameter had that number."""
    machine = default_machine()
    assert [row["number"] for row in param_rows(machine, " 0x717 ")] == [1815]
    assert [row["number"] for row in param_rows(machine, "0b1111101001")] == [1001]
    assert param_rows(machine, "0x7FFF") == []  # a number the machine has not
