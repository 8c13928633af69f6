"""A ninth new user's pass over the dashboard: the page's refusals of alarm numbers, PMC
addresses and fault kinds compared, word for word, with the command line's for the same input
on the same machine; each case that was worded otherwise once, kept."""

from __future__ import annotations

from typing import Any

import pytest
from cli_support import at, fails
from support import serving
from web_support import page_refusal

from focas_net._typed import whole_number
from focas_net.errors import EW
from focas_net.sim import MachineError, default_machine
from focas_net.web import Station, perform, pmc_address
from focas_net.web.broadcast import Broadcaster, machine_topic


# -- an alarm's type and number out of range ---------------------------------------------------
@pytest.mark.parametrize(
    ("typed", "args", "words"),
    [
        (
            "PS99999",
            {"alm_type": "PS", "alm_no": "99999"},
            "alarm number 99999 is outside 0..32767",
        ),
        ("PS32768", {"alm_type": "PS", "alm_no": 32768}, "alarm number 32768 is outside 0..32767"),
        ("32:1", {"alm_type": "32", "alm_no": "1"}, "alarm type 32 is outside 0..31"),
        ("99:1", {"alm_type": 99, "alm_no": 1}, "alarm type 99 is outside 0..31"),
    ],
)
async def test_an_alarm_out_of_range_is_refused_in_the_same_words_on_both(
    typed: str, args: dict[str, Any], words: str
) -> None:
    """``raise_alarm {"alm_no": 99999}`` was EW_DATA "alm_no 99999 outside 0..32767" where
    ``sim alarm PS99999`` says "alarm number 99999 is outside 0..32767": the machine words it
    as the command line and the client do."""
    async with serving() as served:
        line = await fails(2, "sim", "alarm", *at(served), typed, prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        station = Station(0, served.machine)
        assert page_refusal(station, "raise_alarm", args) == words
        assert served.machine.active_alarms() == []


@pytest.mark.parametrize(
    ("typed", "args", "words"),
    [
        (
            "PS40000",
            {"alm_type": "PS", "alm_no": "40000"},
            "alarm number 40000 is outside 0..32767",
        ),
        ("99:1", {"alm_type": "99", "alm_no": "1"}, "alarm type 99 is outside 0..31"),
    ],
)
async def test_a_clear_out_of_range_is_refused_in_the_same_words_on_both(
    typed: str, args: dict[str, Any], words: str
) -> None:
    """The command line's code names an alarm (0..); the page's arguments take -1, any, and
    name the range with it (``-1..32767``)."""
    async with serving() as served:
        served.machine.raise_alarm(0, 3, 100, "x")
        line = await fails(2, "sim", "clear", *at(served), typed, prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        station = Station(0, served.machine)
        assert page_refusal(station, "clear_alarms", args) == words.replace("0..", "-1..")
        assert len(served.machine.active_alarms()) == 1


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ({"alm_type": -2}, "alarm type -2 is outside -1..31"),
        ({"alm_no": -2}, "alarm number -2 is outside -1..32767"),
    ],
)
def test_a_clear_of_minus_two_is_refused_and_minus_one_is_any(
    args: dict[str, int], words: str
) -> None:
    station = Station(0, default_machine())
    station.machine.raise_alarm(0, 3, 100, "x")
    with pytest.raises(MachineError) as refused:
        perform(station, "clear_alarms", args)
    assert (refused.value.ew, refused.value.detail) == (EW.DATA, words)
    assert perform(station, "clear_alarms", {"alm_type": -1, "alm_no": -1})["cleared"] == 1


# -- a fault's kind -----------------------------------------------------------------------------
@pytest.mark.parametrize("typed", ["dely", "Delays", "ERR", "0x1", "délai"])
async def test_a_fault_kind_no_fault_has_is_named_as_typed_in_the_same_words_on_both(
    typed: str,
) -> None:
    """``{"kind": "dely"}`` was "one of DELAY, ERROR, DROP, SPLIT, got 'DELY'" (not what was
    typed) where ``sim fault dely`` was argparse's "invalid choice": one reader words both."""
    words = f"unknown fault kind {typed!r} (one of delay, drop, error, split)"
    async with serving() as served:
        line = await fails(2, "sim", "fault", *at(served), typed, "--arg", "5", prefix="focas-net")
        assert line == (
            f"focas-net sim fault: error: argument KIND: {words}; see focas-net sim fault --help"
        )
        station = Station(0, served.machine)
        assert page_refusal(station, "inject_fault", {"kind": typed, "arg": 5}) == f"kind: {words}"
        assert len(station.faults) == 0


# -- a PMC address no request carries ----------------------------------------------------------
@pytest.mark.parametrize("address", [-1, 65536, 99999])
async def test_a_pmc_bit_of_an_address_no_request_carries_is_refused_alike(address: int) -> None:
    """``pmc_bit {"address": 99999}`` was EW_NUMBER "R99999 goes past the end of PMC area R"
    where ``pmc bit R 99999.0 1`` says "PMC start address 99999 is outside 0..65535" (and
    ``R -1.0`` only "expected BYTE.BIT"): both give the field's words now."""
    words = f"PMC start address {address} is outside 0..65535"
    async with serving() as served:
        line = await fails(
            2, "pmc", "bit", *at(served), "R", f"{address}.0", "1", prefix="focas-net"
        )
        assert f": {words}; see focas-net " in line, line
        station = Station(0, served.machine)
        args = {"area": "R", "address": str(address), "bit": "0", "value": "1"}
        assert page_refusal(station, "pmc_bit", args) == words
        assert served.machine.read_pmc("R", 0, 1) == b"\x00"


@pytest.mark.parametrize("start", ["65536", "R70000", "0x10000"])
async def test_the_pmc_window_of_an_address_no_request_carries_says_so(start: str) -> None:
    """The page's PMC window at ``70000`` was the machine's "goes past the end of PMC area R",
    where ``pmc read R 70000`` says the field's words."""
    number = whole_number(start.lstrip("R"))
    words = f"PMC start address {number} is outside 0..65535"
    async with serving() as served:
        line = await fails(2, "pmc", "read", *at(served), "R", str(number), "1", prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        # (a number typed otherwise than it reads is named as typed, as the command line does)
        lead = f"{start} reads as {number}: " if start.startswith("0x") else ""
        with pytest.raises(ValueError, match=f"^{lead}{words}$"):
            pmc_address(start, "R")


# -- a cycle action -----------------------------------------------------------------------------
@pytest.mark.parametrize("typed", ["Start", " start ", "START"])
def test_a_cycle_action_is_read_in_any_case_as_the_command_line_reads_it(typed: str) -> None:
    """``{"action": "Start"}`` was refused ("one of start, hold, reset, got 'Start'") where
    ``sim cycle Start`` starts the cycle."""
    station = Station(0, default_machine())
    assert station.machine.status().run == 0  # reset
    assert perform(station, "cycle", {"action": typed}) == {"ok": True}
    assert station.machine.status().run == 3  # started


@pytest.mark.parametrize("typed", ["go", "Stat", "5", "stärt"])
async def test_a_cycle_action_no_cnc_has_is_refused_in_the_same_words_on_both(typed: str) -> None:
    words = f"unknown cycle action {typed!r} (one of start, hold, reset)"
    async with serving() as served:
        line = await fails(2, "sim", "cycle", *at(served), typed, prefix="focas-net")
        assert line == (
            f"focas-net sim cycle: error: argument ACTION: {words}; see focas-net sim cycle --help"
        )
        station = Station(0, served.machine)
        assert page_refusal(station, "cycle", {"action": typed}) == f"action: {words}"


@pytest.mark.parametrize("start", [-1, 65536, 70000])
def test_a_pmc_window_subscribed_beyond_every_request_is_refused_as_the_get_refuses_it(
    start: int,
) -> None:
    """A subscription's ``pmc_start`` 70000 was "R70000 goes past the end of PMC area R"
    where the page's GET of the same window and ``pmc read R 70000`` say the field's words."""
    stations = [Station(0, default_machine())]
    words = f"PMC start address {start} is outside 0..65535"
    assert Broadcaster(stations).refusal(machine_topic(0, "R", start)) == f"PMC window: {words}"
    if start >= 0:
        with pytest.raises(ValueError, match=f"^{words}$"):
            pmc_address(str(start), "R")
