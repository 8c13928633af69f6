"""Number text is read by one rule on every front end: the page's API, the command line (a
child process: its exit code and its one line) and the clients' text values give each typed
text the same verdict, and a refusal in the same words naming the text.

The rule is a CNC's MDI keys': ASCII digits, a sign and a decimal point (and ``0x``, ``0b``,
``0o`` for a whole number, as a bit parameter is shown); no exponent, no NaN or infinity, no
digits of other scripts, nothing empty.
"""

from __future__ import annotations

import json
from decimal import Decimal

import pytest
from cli_support import at, fails, ok
from support import Served

from focas_net._typed import decimal_number, typed_number, whole_number
from focas_net.cli import EXIT_USAGE
from focas_net.client._values import macro_write, param_int
from focas_net.protocol import AutMode
from focas_net.sim import default_machine
from focas_net.web import ActionError, Station, parse_web_address, perform

_EXPONENT = "(no exponent: write the digits)"
_NOT_FINITE = "(no NaN or infinity: write the digits)"

#: Macro values as typed -> the value written, or the words of the refusal.
DECIMALS: list[tuple[str, Decimal | str]] = [
    ("12.5", Decimal("12.5")),
    ("-0", Decimal("0")),
    ("+7", Decimal(7)),
    (" 3.25 ", Decimal("3.25")),
    (".5", Decimal("0.5")),
    ("0x10", Decimal(16)),
    ("0b101", Decimal(5)),
    ("1e3", f"not a number: '1e3' {_EXPONENT}"),
    ("-2.5E-4", f"not a number: '-2.5E-4' {_EXPONENT}"),
    ("1e99999999999", f"not a number: '1e99999999999' {_EXPONENT}"),
    ("nan", f"not a number: 'nan' {_NOT_FINITE}"),
    ("-Infinity", f"not a number: '-Infinity' {_NOT_FINITE}"),
    ("\u0661\u0662", "'\u0661\u0662' holds a digit beyond ASCII ('\u0661', U+0661): write 0-9"),
    ("1_000", "not a number: '1_000'"),
    ("12abc", "not a number: '12abc'"),
]

#: Whole numbers as typed -> the number, or the words of the refusal.
WHOLES: list[tuple[str, int | str]] = [
    ("12", 12),
    ("0042", 42),
    ("+3", 3),
    (" 9 ", 9),
    ("0x1F", 31),
    ("0b1011_0000", 176),
    ("0o17", 15),
    ("1e3", f"not a whole number: '1e3' {_EXPONENT}"),
    ("1E+2", f"not a whole number: '1E+2' {_EXPONENT}"),
    ("inf", f"not a whole number: 'inf' {_NOT_FINITE}"),
    ("12.0", "not a whole number: '12.0'"),
    ("1_000", "not a whole number: '1_000'"),
    ("\u0661", "'\u0661' holds a digit beyond ASCII ('\u0661', U+0661): write 0-9"),
    ("0x", "not a whole number: '0x'"),
    ("", "not a whole number: '' (nothing typed)"),
]


#: Where a refusal of ``param set`` points to.
PARAM_SET_HELP = "focas-net param set --help"


@pytest.mark.parametrize(("typed", "verdict"), DECIMALS)
def test_the_reader_of_decimals(typed: str, verdict: Decimal | str) -> None:
    if isinstance(verdict, str):
        with pytest.raises(ValueError) as refused:
            typed_number(typed)
        assert str(refused.value) == verdict
    else:
        assert typed_number(typed) == verdict


@pytest.mark.parametrize(("typed", "verdict"), WHOLES)
def test_the_reader_of_whole_numbers(typed: str, verdict: int | str) -> None:
    if isinstance(verdict, str):
        with pytest.raises(ValueError) as refused:
            whole_number(typed)
        assert str(refused.value) == verdict
    else:
        assert whole_number(typed) == verdict


def test_a_decimal_keeps_the_digits_typed() -> None:
    assert decimal_number("1.50").as_tuple() == (0, (1, 5, 0), -2)
    assert decimal_number("-0").is_signed()


@pytest.mark.parametrize(("typed", "verdict"), DECIMALS)
async def test_a_macro_value_gets_one_verdict_on_every_front_end(
    server: Served, typed: str, verdict: Decimal | str
) -> None:
    machine = server.machine
    station = Station(0, machine)
    if isinstance(verdict, str):
        with pytest.raises(ActionError) as page:
            perform(station, "write_macro", {"number": 500, "value": typed})
        assert str(page.value) == f"value: {verdict}"
        with pytest.raises(ValueError) as client:
            macro_write(500, typed)
        assert str(client.value) == f"#500: {verdict}"
        machine.write_macro(500, Decimal(7))
        line = await fails(
            EXIT_USAGE, "macro", "set", "500", typed, *at(server), prefix="focas-net"
        )
        assert line == (
            f"focas-net macro set: error: argument VALUE: #500: {verdict}; "
            "see focas-net macro set --help"
        )
        assert machine.read_macro(500) == 7  # nothing written
        return
    assert perform(station, "write_macro", {"number": 500, "value": typed})["ok"]
    assert machine.read_macro(500) == verdict
    mcr, dec = macro_write(500, typed)
    assert Decimal(mcr).scaleb(-dec) == verdict
    machine.write_macro(500, None)
    out = json.loads(await ok("macro", "set", "500", typed, "--json", *at(server)))
    assert Decimal(out["value"]) == verdict == machine.read_macro(500)


@pytest.mark.parametrize(("typed", "verdict"), WHOLES)
async def test_a_whole_number_gets_one_verdict_on_every_front_end(
    server: Served, typed: str, verdict: int | str
) -> None:
    """The page's PMC address and the command line's START; a client's parameter value takes
    the whole numbers alike (text that is none is read as a number, as ``param set`` reads
    it: tests/test_confirm8_api.py)."""
    station = Station(0, default_machine())
    page_args = {"area": "R", "address": typed, "bit": 0, "value": 1}
    if isinstance(verdict, str):
        with pytest.raises(ActionError) as page:
            perform(station, "pmc_bit", page_args)
        # the page names an empty field as one with no number at all
        words = "a number is needed" if not typed.strip() else verdict
        assert str(page.value) == f"address: {words}"
        line = await fails(EXIT_USAGE, "pmc", "read", "R", typed, *at(server), prefix="focas-net")
        assert line.endswith(f"argument START: {verdict}; see focas-net pmc read --help"), line
        return
    assert perform(station, "pmc_bit", page_args)["address"] == verdict
    assert param_int(6711, typed) == verdict
    out = json.loads(await ok("pmc", "read", "R", typed, "--json", *at(server)))
    assert out["start"] == verdict


@pytest.mark.parametrize("typed", ["1e3", "1E+3", "nan", "inf"])
async def test_a_parameter_value_with_an_exponent_is_refused_on_every_front_end(
    server: Served, typed: str
) -> None:
    """``param set 1420 1e3`` wrote 1000 while the page refused the same text."""
    machine = server.machine
    before = machine.read_param(1420, 1)
    with pytest.raises(ValueError) as refused:
        typed_number(typed)
    verdict = str(refused.value)
    with pytest.raises(ActionError) as page:
        perform(Station(0, machine), "write_param", {"number": 1420, "axis": 1, "value": typed})
    assert str(page.value) == f"value: {verdict}"
    line = await fails(
        EXIT_USAGE, "param", "set", "1420", typed, "--axis", "1", *at(server), prefix="focas-net"
    )
    # (named as --help names it; the page: value)
    assert line == f"focas-net param set: error: argument VALUE: {verdict}; see {PARAM_SET_HELP}"
    assert machine.read_param(1420, 1) == before


def test_digits_of_other_scripts_are_no_number_where_a_name_may_stand() -> None:
    """A mode, a fault kind and a port may be typed as a name or a number: ``'\u0663'`` was
    read as 3 (``str.isdigit`` takes every script's digits)."""
    with pytest.raises(ValueError, match="unknown AutMode"):
        AutMode.parse("\u0663")
    assert AutMode.parse("3") is AutMode.EDIT
    with pytest.raises(ActionError, match=r"kind: unknown fault kind '\u0661' \(one of "):
        perform(Station(0, default_machine()), "inject_fault", {"kind": "\u0661", "count": "1"})
    with pytest.raises(ValueError, match="the port must be a number"):
        parse_web_address("\u0668\u0660")
    assert parse_web_address("80")[1] == 80
