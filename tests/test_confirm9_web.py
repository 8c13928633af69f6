"""A confirming pass over the dashboard: refusals the page and the command line worded
differently for the same input on the same machine (a parameter value no wire carries, a fault
without its argument, a PMC bit below 0, a mode or a switch of only spaces), each kept."""

from __future__ import annotations

from typing import Any

import pytest
from cli_support import at, fails
from support import serving
from web_support import page_refusal

from focas_net._typed import whole_number
from focas_net.protocol import AutMode
from focas_net.sim import MachineError
from focas_net.web import Station, perform, pmc_address

#: How ``sim fault`` refuses its ``--arg``: as the parser refuses an option.
FAULT_ARG = "focas-net sim fault: error: argument --arg: "


# -- a parameter value no wire carries ----------------------------------------------------------
@pytest.mark.parametrize(
    ("number", "typed", "words"),
    [
        (
            6711,
            "99999999999",
            "parameter 6711 is a two-word parameter: 99999999999 is outside "
            "-2147483648..2147483647",
        ),
        (
            3216,
            "-40000",
            "parameter 3216 is a word parameter: -40000 is outside -32768..32767",
        ),
        (20, "300", "parameter 20 is a byte parameter: 300 is outside -128..127"),
        (
            1001,
            "0x100",  # (named as typed, as every front end names a number read otherwise)
            "0x100 reads as 256: bit parameter 1001 holds 0..255 (0b00000000..0b11111111), got 256",
        ),
    ],
)
async def test_a_value_no_wire_carries_is_refused_alike_before_the_write_gates(
    number: int, typed: str, words: str
) -> None:
    """``param set 6711 99999999999`` said what a two-word value carries while the page, after
    checking PWE and MDI, said the parameter's range (``0..999999999``): a value no wire
    carries is refused before the write gates (PWE off, the mode not MDI here) in the words
    both transports of the command line give; the parameter's own range is named by the CNC
    for a value the wire carries (FOCAS/2 tells no client a parameter's range)."""
    async with serving() as served:
        before = served.machine.read_param(number, 0)
        line = await fails(2, "param", "set", *at(served), str(number), typed)
        assert line == f"focas-net: {words}"
        station = Station(0, served.machine)
        assert page_refusal(station, "write_param", {"number": number, "value": typed}) == (
            f"value: {words}"
        )
        assert served.machine.read_param(number, 0) == before


async def test_a_value_the_wire_carries_outside_the_range_is_the_machines_after_its_gates() -> None:
    """Within the wire the CNC answers: EW_PASSWD first with PWE off (FANUC's order), and
    EW_DATA for its range with the gate open."""
    async with serving() as served:
        station = Station(0, served.machine)
        with pytest.raises(MachineError) as gated:
            perform(station, "write_param", {"number": 6711, "value": "1000000000"})
        assert gated.value.detail.startswith("parameter writes need MDI mode and PWE on: ")
        served.machine.set_panel(int(AutMode.MDI), 1, None)
        words = "the CNC refused 1000000000 for parameter 6711: outside its range 0..999999999"
        assert (
            page_refusal(station, "write_param", {"number": 6711, "value": "1000000000"}) == words
        )
        line = await fails(1, "param", "set", *at(served), "6711", "1000000000")
        assert line.startswith("focas-net: EW_DATA (5)") and "1000000000" in line
        assert served.machine.read_param(6711, 0) == 0


# -- a fault without its argument ---------------------------------------------------------------
@pytest.mark.parametrize(
    ("kind", "words"),
    [
        ("delay", "a delay fault needs its delay in milliseconds (0..60000)"),
        ("error", "an error fault needs the EW code it answers with (e.g. EW_BUSY or -1)"),
    ],
)
@pytest.mark.parametrize("arg", [None, "", "  "])
async def test_a_fault_without_its_argument_is_refused_in_the_same_words(
    kind: str, words: str, arg: str | None
) -> None:
    """``sim fault delay`` said "needs --arg MILLISECONDS", the page "arg: a number is
    needed": each names its field, then the same reason."""
    async with serving() as served:
        line = await fails(2, "sim", "fault", *at(served), kind, prefix="focas-net")
        assert line == f"{FAULT_ARG}{words}; see focas-net sim fault --help"
        station = Station(0, served.machine)
        args: dict[str, Any] = {"kind": kind} if arg is None else {"kind": kind, "arg": arg}
        assert page_refusal(station, "inject_fault", args) == f"arg: {words}"
        assert len(station.faults) == 0


# -- a PMC bit below 0 --------------------------------------------------------------------------
@pytest.mark.parametrize("bit", [-1, -8])
async def test_a_pmc_bit_below_zero_is_refused_in_the_same_words(bit: int) -> None:
    """``pmc bit R 0.-1`` said "the bit after the dot must be a bit number", the page
    "R0.-1: bit -1 is outside 0..7": a signed bit is a number, refused by its range."""
    words = f"R0.{bit}: bit {bit} is outside 0..7: a PMC address is 1 byte wide"
    async with serving() as served:
        line = await fails(2, "pmc", "bit", *at(served), "R", f"0.{bit}", "1", prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        station = Station(0, served.machine)
        args = {"area": "R", "address": 0, "bit": bit, "value": 1}
        assert page_refusal(station, "pmc_bit", args) == words
        assert served.machine.read_pmc("R", 0, 1) == b"\x00"


async def test_a_parameter_bit_below_zero_is_refused_by_its_range() -> None:
    async with serving() as served:
        line = await fails(2, "param", "get", *at(served), "1815.-1", "--axis", "1")
        assert line == "focas-net: bit -1 is outside 0..7: parameter 1815 is 1 byte wide"


# -- a mode or a switch of only spaces ----------------------------------------------------------
@pytest.mark.parametrize("typed", ["", "  "])
async def test_a_mode_of_no_text_is_refused_as_the_command_line_refuses_it(typed: str) -> None:
    """A mode of only spaces was "leave unchanged" on the page while ``--mode ''`` is refused:
    a mode switch has no blank position, so both refuse text that names no mode (a mode left
    out, or ``null``, leaves it as it is)."""
    words = f"unknown mode {typed!r} (one of MDI, MEM, EDIT, HND, JOG, TJOG, THND, INC, REF, RMT)"
    async with serving() as served:
        before = served.machine.status()
        line = await fails(2, "sim", "panel", *at(served), "--mode", typed, prefix="focas-net")
        assert f"argument --mode: {words};" in line
        station = Station(0, served.machine)
        assert page_refusal(station, "panel", {"mode": typed}) == f"mode: {words}"
        assert perform(station, "panel", {"mode": None}) == {"ok": True}
        assert served.machine.status() == before


@pytest.mark.parametrize("key", ["pwe", "emergency"])
@pytest.mark.parametrize("typed", ["", "  "])
async def test_a_switch_of_no_text_is_refused_as_the_command_line_refuses_it(
    key: str, typed: str
) -> None:
    """``{"pwe": "  "}`` was "pwe: a number is needed" and ``{"pwe": ""}`` left PWE as it
    was, where ``--pwe '  '`` names the words a switch takes."""
    words = f"expected 1, on, true, yes or set, or 0, off, false, no or clear, got {typed!r}"
    async with serving() as served:
        line = await fails(2, "sim", "panel", *at(served), f"--{key}", typed, prefix="focas-net")
        assert f"argument --{key}: {words};" in line
        station = Station(0, served.machine)
        assert page_refusal(station, "panel", {key: typed}) == f"{key}: {words}"


# -- a macro value of more decimals than a variable keeps ---------------------------------------
@pytest.mark.parametrize("typed", ["0.0000000001", "-0.00000000010", "12345678901.5"])
async def test_a_macro_value_no_variable_holds_is_named_as_typed_on_both(typed: str) -> None:
    """``{"value": "0.0000000001"}`` was refused as ``macro value 1E-10`` where ``macro set
    100 0.0000000001`` names the digits typed."""
    words = (
        f"#100: macro value {typed} does not fit a macro variable: give at most 9 decimals and "
        "at most 10 digits, which without the decimal point stay within 32 bits "
        "(-2147483648..2147483647)"
    )
    async with serving() as served:
        line = await fails(2, "macro", "set", *at(served), "100", typed, prefix="focas-net")
        assert f": {words}; see focas-net " in line, line
        station = Station(0, served.machine)
        assert page_refusal(station, "write_macro", {"number": 100, "value": typed}) == words


# -- a negative PMC address ---------------------------------------------------------------------
@pytest.mark.parametrize("typed", ["-1", "-0x10"])
async def test_a_negative_pmc_address_is_refused_as_one_past_the_end_is(typed: str) -> None:
    """The page's PMC window at ``-1`` said "PMC address '-1': must not be negative", ``pmc
    read R -1`` "argument START: must not be negative, got -1", while 70000 was "PMC start
    address 70000 is outside 0..65535" on both (and -1 too in a subscription): one wording."""
    number = whole_number(typed)
    words = f"PMC start address {number} is outside 0..65535"
    # (the command line leads with a number typed otherwise than it reads, as it is typed)
    lead = "" if typed == str(number) else f"{typed} reads as {number}: "
    async with serving() as served:
        for argv in (("pmc", "read", "R", typed, "1"), ("pmc", "write", "R", typed, "5")):
            line = await fails(2, *argv, *at(served), prefix="focas-net")
            assert f": {lead}{words}; see focas-net " in line, line
        with pytest.raises(ValueError, match=f"^{lead}{words}$"):  # (the page alike)
            pmc_address(typed, "R")
        assert served.machine.read_pmc("R", 0, 1) == b"\x00"


# -- a value of spaces, named as typed ----------------------------------------------------------
@pytest.mark.parametrize("typed", ["  ", "   "])
async def test_a_fault_argument_of_spaces_is_named_as_typed_on_the_command_line(typed: str) -> None:
    """``sim fault delay --arg '  '`` named ``' '`` (the one-line message collapsed the value's
    own spaces), where a usage error and the page keep them."""
    async with serving() as served:
        line = await fails(
            2, "sim", "fault", *at(served), "delay", "--arg", typed, prefix="focas-net"
        )
        assert line == (
            f"{FAULT_ARG}not a whole number: {typed!r} (nothing typed); "
            "see focas-net sim fault --help"
        )
