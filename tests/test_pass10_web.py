"""A tenth new user's pass over the dashboard: the page's refusals compared, word for word, with
the command line's and the clients' for the same input on the same machine (an alarm's axis,
a parameter's range, a bit parameter's bits, a read-only macro variable); each case that was
worded otherwise once, kept."""

from __future__ import annotations

import json

import pytest
from cli_support import at, fails, ok
from support import serving, with_both_clients
from web_support import page_refusal

from focas_net.sim import default_machine
from focas_net.web import Station, perform
from focas_net.web.broadcast import Broadcaster, machine_topic
from focas_net.web.view import param_rows


def _writable(station: Station) -> Station:
    """``station`` with its panel in MDI and PWE on (parameter writes pass the gates)."""
    perform(station, "panel", {"mode": "MDI", "pwe": 1})
    return station


# -- an alarm's axis ----------------------------------------------------------------------------
@pytest.mark.parametrize("axis", [-1, 40000])
async def test_an_alarm_axis_no_field_carries_is_one_rule_on_every_front_end(axis: int) -> None:
    """``sim alarm --axis -1`` said "must not be negative, got -1" where the page said
    "axis_no -1 outside 0..3: the path has 3 axes" and the client "axis 40000 is outside
    0..32767": one rule, the field's, in the same words on the parser, the page and the
    client."""
    words = f"axis {axis} is outside 0..32767 (0: an alarm of no axis)"
    async with serving() as served:
        line = await fails(
            2,
            "sim",
            "alarm",
            "PS100",
            "--axis",
            str(axis),
            *at(served),
            prefix="focas-net sim alarm: ",
        )
        assert f"argument --axis: {words};" in line
        assert (
            page_refusal(
                Station(0, served.machine),
                "raise_alarm",
                {"axis_no": axis, "alm_type": "PS", "alm_no": 100},
            )
            == words
        )
    async with with_both_clients(default_machine()) as (machine, cnc, _):
        with pytest.raises(ValueError) as refused:  # (the simulator's controls are packed)
            await cnc.sim.raise_alarm("PS", 100, axis_no=axis)
        assert str(refused.value) == words
        assert machine.active_alarms() == []


async def test_an_alarm_axis_past_the_paths_is_worded_as_a_position_axis() -> None:
    """It was "axis_no 5 outside 0..3", where ``position --axis 5`` says "axis 5 is outside
    1..3: the path has 3 axes"; the page and the command line say the machine's words."""
    words = "axis 5 is outside 0..3: the path has 3 axes"
    async with serving() as served:
        line = await fails(1, "sim", "alarm", "PS100", "--axis", "5", *at(served))
        assert f"(sim_raise_alarm: {words})" in line
        assert (
            page_refusal(
                Station(0, served.machine),
                "raise_alarm",
                {"axis_no": 5, "alm_type": "PS", "alm_no": 100},
            )
            == words
        )
        assert served.machine.active_alarms() == []


# -- a parameter's values -----------------------------------------------------------------------
async def test_a_value_past_a_parts_count_names_the_range_on_both() -> None:
    """``param set 6711 1000000000`` (a two-word the wire carries, refused by the machine) gave
    no range on the command line where the page says ``0..999999999``."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        before = served.machine.read_param(6711, 0)
        page = page_refusal(station, "write_param", {"number": 6711, "value": "1000000000"})
        assert page == (
            "the CNC refused 1000000000 for parameter 6711: outside its range 0..999999999"
        )
        line = await fails(1, "param", "set", "6711", "1000000000", *at(served))
        assert line.endswith(
            "the CNC refused 1000000000 for parameter 6711: outside its range 0..999999999"
        )
        assert served.machine.read_param(6711, 0) == before


@pytest.mark.parametrize("typed", ["1011", "1011000", "111111111"])
async def test_a_bit_parameters_bits_not_eight_are_refused_in_one_wording(typed: str) -> None:
    """``param set 3401 1011`` said "bit parameter 3401 holds 0..255 ..., got 1011" (read as
    the decimal 1011) where the page said "write its 8 bits #7..#0 (10110000), 0x.. or 0b..":
    0/1 digits that no byte is as a decimal and that are not eight are bits miscounted, refused
    as the machine file refuses them, each front end naming the other way it takes."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        before = served.machine.read_param(3401, 0)
        page = page_refusal(station, "write_param", {"number": 3401, "value": typed})
        line = await fails(2, "param", "set", "3401", typed, *at(served))
        head = line.removeprefix("focas-net: ").removesuffix(" or an integer 0..255")
        assert head.startswith(f"{typed!r} ") and "0b" in head
        assert page == f'value: {head} or a hexadecimal number with 0x ("0xB0")'
        assert served.machine.read_param(3401, 0) == before


async def test_a_decimal_byte_of_zeros_and_ones_is_still_the_byte_on_the_command_line() -> None:
    """``param set 3401 101`` is the decimal 101 (a byte), as before; eight digits are bits."""
    async with serving() as served:
        _writable(Station(0, served.machine))
        for typed, value in (("101", 101), ("00000101", 5), ("0", 0)):
            await ok("param", "set", "3401", typed, *at(served))
            assert served.machine.read_param(3401, 0) == value


# -- a macro variable the CNC only reads ------------------------------------------------------
@pytest.mark.parametrize(
    ("number", "span", "holds"),
    [(5001, "#5001..#5120", "position information"), (4001, "#4001..#4130", "modal information")],
)
async def test_a_read_only_system_variable_is_refused_with_its_reason_on_both(
    number: int, span: str, holds: str
) -> None:
    """``macro set 5001 1`` printed the EW code and a guess ("a read-only variable, or the
    machine is read-only") where the page gives the machine's reason: both give it now."""
    words = f"macro variable #{number} is read-only (FANUC's {span}: {holds})"
    async with serving() as served:
        assert (
            page_refusal(
                Station(0, served.machine), "write_macro", {"number": number, "value": "1"}
            )
            == words
        )
        line = await fails(1, "macro", "set", str(number), "1", *at(served))
        assert line.endswith(f"(cnc_wrmacro); {words}")


async def test_a_read_only_variable_of_no_system_range_keeps_both_causes() -> None:
    """A variable a machine makes read-only outside FANUC's system ranges: the command line
    cannot tell it from a read-only machine, and says both."""
    async with serving(default_machine(read_only=True)) as served:
        line = await fails(1, "macro", "set", "100", "1", *at(served))
        assert line.endswith("macro variable #100 is read-only, or the machine is read-only")


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_bits_separated_by_underscores_are_written_on_both_transports(protocol: str) -> None:
    """The page and the machine file take ``1011_0000`` for a bit parameter; ``param set 1815
    1011_0000`` said "not a number" (the text was checked as a decimal before the parameter's
    type was known). A parameter of another type still refuses it."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        perform(station, "write_param", {"number": 1815, "axis": 2, "value": "1011_0000"})
        assert served.machine.read_param(1815, 2) == 0b1011_0000
        out = await ok("param", "set", "1815", "0000_1100", "--axis", "2",
                       "--protocol", protocol, *at(served))  # fmt: skip
        assert out.strip() == "1815 axis 2 = 12 (00001100), bit parameter (written)"
        line = await fails(2, "param", "set", "6711", "1011_0000",
                           "--protocol", protocol, *at(served))  # fmt: skip
        assert line == "focas-net: parameter 6711: not a number: '1011_0000'"
        assert page_refusal(station, "write_param", {"number": 6711, "value": "1011_0000"}) == (
            "value: not a number: '1011_0000'"
        )


async def test_an_axis_on_an_item_of_no_axis_is_not_an_axis_on_both() -> None:
    """The page said "parameter 6711 is no axis parameter" where the command line says "is not
    an axis parameter": one label."""
    async with serving() as served:
        station = _writable(Station(0, served.machine))
        page = page_refusal(station, "write_param", {"number": 6711, "axis": 1, "value": 5})
        assert page == "parameter 6711 is not an axis parameter: give axis 0, got 1"
        line = await fails(1, "param", "set", "6711", "5", "--axis", "1", *at(served))
        assert line.endswith("parameter 6711 is not an axis parameter: leave out --axis")


@pytest.mark.parametrize("typed", ["-5", "1.5"])
async def test_a_parts_count_refused_gives_one_reason_on_both(typed: str) -> None:
    """``macro set 3901 -5`` said "#3901 cannot hold -5" where the page said "#3901 = -5: a
    count of parts": both say what a parts count holds."""
    words = f"#3901 is a parts count: it holds a whole number of 0 or more, not {typed}"
    async with serving() as served:
        page = page_refusal(Station(0, served.machine), "write_macro",
                            {"number": 3901, "value": typed})  # fmt: skip
        assert page == words
        line = await fails(1, "macro", "set", "3901", typed, *at(served))
        assert line.endswith(f"(cnc_wrmacro); {words}")


async def test_clear_alarms_takes_all_as_sim_clear_does() -> None:
    """``sim clear all`` clears every alarm; the page's ``{"alm_type": "all"}`` was refused as
    an unknown alarm type."""
    machine = default_machine()
    machine.raise_alarm(0, 3, 100, "")
    machine.raise_alarm(0, 15, 1001, "COOLANT")
    answer = perform(Station(0, machine), "clear_alarms", {"alm_type": " ALL "})
    assert answer == {"ok": True, "cleared": 2}
    assert machine.active_alarms() == []


def test_a_parameter_search_of_a_bit_as_the_command_line_names_it_finds_the_parameter() -> None:
    """``1815.1`` typed in the page's parameter search (as ``param get 1815.1`` names the bit)
    found nothing; it finds parameter 1815, whose bits the page shows."""
    machine = default_machine()
    assert [row["number"] for row in param_rows(machine, "1815.1")] == [1815]
    assert [row["number"] for row in param_rows(machine, " 3401.7 ")] == [3401]
    assert param_rows(machine, "1815.8") == []  # a bit no byte has


async def test_a_path_the_machine_has_not_is_worded_alike_on_the_page_and_the_cli() -> None:
    """The page said "path 2: this machine has paths 1..1" where ``--path 2`` says "the CNC has
    no path 2: it has path 1 only (leave out --path)": one rule, the command line adding its
    advice."""
    async with serving() as served:
        page = page_refusal(Station(0, served.machine), "raise_alarm",
                            {"alm_type": "PS", "alm_no": 100, "path": 2})  # fmt: skip
        assert page == "the CNC has no path 2: it has path 1 only"
        line = await fails(1, "sim", "alarm", "PS0100", "--path", "2", *at(served))
        assert line.endswith(f"; {page} (leave out --path)")
        assert served.machine.active_alarms() == []


def test_a_live_view_of_a_path_the_machine_has_not_is_worded_as_the_actions_word_it() -> None:
    """A subscription of path 5 said "path 5: machine 0 has paths 1..2", written twice in the
    broadcaster, where an action of that path says the machine's words: now one helper
    gives those, naming the machine; an unknown machine's frame names the fleet as the
    subscription's refusal does."""
    machine = default_machine()
    b = Broadcaster([Station(0, machine)])
    words = "the CNC has no path 5: it has path 1 only (machine 0)"
    assert b.refusal(machine_topic(0, path=5)) == words
    sub = b.subscribe(machine_topic(0, path=5))
    b.tick()
    assert json.loads(sub.take() or "") == {"type": "error", "error": words}
    other = b.subscribe(machine_topic(3))
    b.tick()
    assert json.loads(other.take() or "") == {
        "type": "error",
        "error": "no machine 3 (this dashboard shows machine 0)",
    }
