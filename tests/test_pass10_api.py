"""The Python API as a new user meets it, a tenth pass: one rule for what the command line and
the clients both take (the alarm history depth, a parameter's bit numbers), the in-process
machine and the simulator control of a client raising the same alarm, a control class taken
in either case and refused by kind; the machine's parts, paths and motion figures of another
type refused by kind; the two transports refusing a parameter value alike; a date outside the
CNC's calendar named; numbers no float holds (a timeout, a clock's seconds) refused or taken
without an OverflowError; and every alarm history entry of one second reported."""

from __future__ import annotations

from datetime import UTC, date, datetime
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest
from support import REAL_FILE, with_both_clients

from focas_net import EW, CncError, FocasClient, NativeClient, default_machine, load_machine
from focas_net.cli import main
from focas_net.client import AlarmHistoryEvent, AlarmProjection
from focas_net.sim import Machine, MachineError
from focas_net.sim.nc import ManualClock, RealTimeClock


# -- the alarm history depth: one rule for the command line and the clients -------------------
def test_the_command_line_reads_a_depth_above_250_as_the_clients_do(
    capsys: pytest.CaptureFixture[str],
) -> None:
    # no server on port 1: a depth taken goes on to connecting (exit 3), a refused one is a
    # usage error (exit 2) before it
    assert main(["alarms", "--history", "251", "--port", "1", "--timeout", "0.5"]) != 2
    capsys.readouterr()


@pytest.mark.parametrize("depth", ["0", "-1"])
def test_the_command_line_refuses_a_depth_below_one_in_the_clients_words(
    capsys: pytest.CaptureFixture[str], depth: str
) -> None:
    with pytest.raises(SystemExit) as info:
        main(["alarms", "--history", depth])
    assert info.value.code == 2
    assert (
        f"history depth {depth} is below 1 (the latest entries to read; more than 250 reads "
        "the 250 the history holds)"
    ) in capsys.readouterr().err


# -- a bit number outside the parameter's bits: its real range, whatever the side -------------
@pytest.mark.parametrize("native", [False, True])
@pytest.mark.parametrize("bit", [-1, 8, 32, -40, 2**70])
async def test_a_bit_outside_a_byte_parameter_names_its_eight_bits(
    both_clients: tuple[Machine, FocasClient, NativeClient], native: bool, bit: int
) -> None:
    machine, cnc, through_native = both_clients
    client: FocasClient | NativeClient = through_native if native else cnc
    before = machine.read_param(3401, 0)
    with pytest.raises(ValueError) as refused:
        await client.write_param_bit(3401, bit, 1)
    assert str(refused.value) == f"bit {bit} is outside 0..7: parameter 3401 is 1 byte wide"
    assert machine.read_param(3401, 0) == before


@pytest.mark.parametrize("bit", ["1", 1.0, None, True])
async def test_a_bit_of_another_type_is_a_type_error_before_anything_is_read(
    both_clients: tuple[Machine, FocasClient, NativeClient], bit: Any
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(TypeError, match=r"^bit must be an integer, got "):
            await client.write_param_bit(3401, bit, 1)


# -- a control class: in either case, as a machine file takes it; another type a TypeError -----
@pytest.mark.parametrize(("given", "kept"), [("30I", "30i"), ("0I-c", "0i-C"), (" 16i ", "16i")])
def test_a_control_class_is_taken_in_either_case(given: str, kept: str) -> None:
    assert Machine("m", axes=["X"], control_class=given).control_class == kept


@pytest.mark.parametrize("given", [5, None, b"30i", 30.0])
def test_a_control_class_of_another_type_is_a_type_error(given: Any) -> None:
    with pytest.raises(TypeError) as refused:
        Machine("m", axes=["X"], control_class=given)
    assert str(refused.value) == f"control_class must be a str, got {given!r}"


def test_an_unknown_control_class_is_worded_as_in_a_machine_file() -> None:
    with pytest.raises(ValueError) as refused:
        Machine("m", axes=["X"], control_class="40i")
    assert str(refused.value) == (
        "unknown control class '40i' (expected one of: 16i, 18i, 21i, 0i-C, 0i-D, 0i-F, "
        "30i, 31i, 32i)"
    )


# -- raising an alarm: the machine's and the client's calls, with their arguments named ---------
async def test_the_machine_and_the_client_raise_the_same_alarm_by_keywords(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, _ = both_clients
    key: dict[str, Any] = {"alm_type": 4, "alm_no": 100, "msg": "DOOR OPEN", "axis_no": 1}
    assert machine.raise_alarm(**key)
    machine.clear_alarms()
    await cnc.sim.raise_alarm(**key)
    (active,) = machine.active_alarms()
    assert (active.axis_no, active.alm_type, active.alm_no, active.msg) == (1, 4, 100, "DOOR OPEN")
    docs = (Path(__file__).parents[1] / "docs" / "client.md").read_text(encoding="utf-8")
    assert "`Machine.raise_alarm(axis_no, alm_type, alm_no, msg)`" in docs


# -- the machine's constructor and its path argument: a wrong type is a TypeError naming it ----
@pytest.mark.parametrize(
    ("given", "words"),
    [
        ({"params": [1]}, "params[0] must be a DataItem, got 1"),
        ({"params": None}, "params must be a list of DataItem, got None"),
        ({"diags": {"a": 1}}, "diags must be a list of DataItem, got {'a': 1}"),
        ({"macro_ranges": [(1, 0)]}, "macro_ranges[0] must be a MacroRange, got (1, 0)"),
        ({"macro_values": {"100": 1}}, "macro_values: a key must be an int, got '100'"),
        (
            {"macro_values": {100: 1.5}},
            "macro_values[100] must be a Decimal, an int or None, got 1.5",
        ),
        ({"pmc": [1]}, "pmc[0] must be a PmcAreaSpec, got 1"),
        ({"station": {(0, 0): 5}}, "station[(0, 0)] must be an IOModuleRecord, got 5"),
        ({"tools": {1: 5}}, "tools[1] must be a ToolsSpec, got 5"),
        ({"motion": 5}, "motion must be a MotionData or None, got 5"),
        ({"identity": 5}, "identity must be an Identity or None, got 5"),
        ({"panel": 5}, "panel must be a Panel or None, got 5"),
        ({"paths": [5], "axes": None}, "paths[0] must be a PathSpec, got 5"),
    ],
)
def test_a_machine_part_of_another_type_is_a_type_error_naming_it(
    given: dict[str, Any], words: str
) -> None:
    with pytest.raises(TypeError) as refused:
        Machine("m", **{"axes": ["X"], **given})
    assert str(refused.value) == words


@pytest.mark.parametrize("path", ["1", 1.0, True, None])
def test_a_path_of_another_type_is_a_type_error_not_a_path_the_machine_lacks(path: Any) -> None:
    machine = default_machine()
    with pytest.raises(TypeError) as refused:
        machine.status(path=path)
    assert str(refused.value) == f"path must be an integer, got {path!r}"
    with pytest.raises(TypeError):
        machine.raise_alarm(0, 4, 100, "x", path=path)
    assert machine.active_alarms() == []


# -- a date the CNC's calendar has not: the reason the machine refuses it ----------------------
@pytest.mark.parametrize("year", [1900, 1986, 2038])
async def test_a_date_outside_the_cnc_calendar_names_its_years(
    both_clients: tuple[Machine, FocasClient, NativeClient], year: int
) -> None:
    machine, _, native = both_clients
    machine.clock = lambda: datetime(2026, 3, 4, 5, 6, 7, tzinfo=UTC)  # (held: nothing ticks)
    before = machine.now()
    with pytest.raises(CncError) as refused:
        await native.write_date(date(year, 1, 1))
    assert refused.value.ew == EW.DATA
    assert refused.value.detail == f"cnc_settimer: year {year} is outside 1987..2037"
    assert machine.now() == before
    with pytest.raises(MachineError) as by_machine:
        machine.set_cnc_date(year, 1, 1)
    assert by_machine.value.detail == f"year {year} is outside 1987..2037"


# -- a value no parameter type carries: refused in the words of the parameter's own type ----------
@pytest.mark.parametrize("value", ["100.123456789", Decimal("0.0000000001"), "99999999999.5"])
async def test_a_value_of_no_type_is_refused_alike_on_both_transports(
    both_clients: tuple[Machine, FocasClient, NativeClient], value: str | Decimal
) -> None:
    machine, cnc, native = both_clients
    machine.set_panel(0, True)  # MDI, PWE on: the value is what is refused
    before = machine.read_param(1320, 1)
    words = []
    for client in (cnc, native):
        with pytest.raises(ValueError) as refused:
            await client.write_param(1320, value, axis=1)
        words.append(str(refused.value))
    assert words[0] == words[1]
    assert words[0].startswith("parameter 1320 is not a real parameter: ")
    assert machine.read_param(1320, 1) == before


# -- a real parameter written with decimals and a width that is not its own -------------------


@pytest.mark.parametrize("width", [1, 2, 4])
async def test_a_real_parameter_given_another_width_is_its_width_refused_on_both_transports(
    tmp_path: Path, width: int
) -> None:
    """The packed client said "parameter 1420 is not a real parameter: 1.5 is no integer" of
    a real parameter; the native one, as FANUC's library, EW_LENGTH naming its width."""
    (tmp_path / "real.toml").write_text(REAL_FILE, encoding="utf-8")
    machine = load_machine(tmp_path / "real.toml")
    machine.set_panel(0, True)
    async with with_both_clients(machine) as (_, cnc, native):
        for client in (cnc, native):
            with pytest.raises(CncError) as refused:
                await client.write_param(1420, "1.5", axis=1, width=width)
            assert refused.value.ew == EW.LENGTH
            wide = f"cnc_wrparam: parameter 1420 is 8 bytes wide, not {width}"
            assert refused.value.detail == wide
    assert machine.read_param(1420, 1) == 12345


# -- a timeout too large for a float: no deadline, as inf, never an OverflowError ---------------
async def test_a_timeout_beyond_a_float_is_no_deadline_as_infinity_is(
    both_clients: tuple[Machine, FocasClient, NativeClient],
) -> None:
    _, cnc, native = both_clients
    huge = 10**400
    for client in (cnc, native):
        assert (await client.read_status(timeout=huge)).aut == 1
        assert (await client.start_read_status(timeout=huge).result()).aut == 1
    assert FocasClient("127.0.0.1", timeout=huge).timeout is None
    assert NativeClient("127.0.0.1", timeout=huge).timeout is None
    assert AlarmProjection(cnc, timeout=huge).client is cnc
    with pytest.raises(ValueError, match=r"^interval must be a positive, finite number of seconds"):
        AlarmProjection(cnc, interval=huge)  # its first poll added it to the loop's clock


# -- motion figures of another type: a TypeError naming the value, nothing changed -------------
@pytest.mark.parametrize(
    ("given", "words"),
    [
        ({"absolute": [1, 2, 3.5]}, "absolute[2] must be an integer, got 3.5"),
        ({"machine": "123"}, "machine must be a list of integers, got '123'"),
        ({"relative": 5}, "relative must be a list of integers, got 5"),
        ({"feed": 1.5}, "feed must be an integer, got 1.5"),
        ({"sequence": "10"}, "sequence must be an integer, got '10'"),
        ({"absolute": [1, 2, True]}, "absolute[2] must be an integer, got True"),
    ],
)
def test_motion_figures_of_another_type_are_a_type_error(given: dict[str, Any], words: str) -> None:
    machine = default_machine()
    before = machine.path_motion()
    with pytest.raises(TypeError) as refused:
        machine.set_motion(**given)
    assert str(refused.value) == words
    assert machine.path_motion() == before


# -- a clock given a whole number no float holds: refused as not finite, never OverflowError ----
@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: ManualClock().advance(10**400), "a clock advances by a finite number of seconds"),
        (lambda: ManualClock().set(10**400), "a clock is set to a finite time"),
        (lambda: ManualClock(10**400), "start must be a finite number of seconds"),
        (lambda: RealTimeClock(speed=10**400), "the clock speed must be a positive number"),
    ],
)
def test_a_clock_refuses_a_number_no_float_holds(call: Any, words: str) -> None:
    with pytest.raises(ValueError, match=f"^{words}"):
        call()


# -- the alarm history: alarms of one second are each reported -------------------------------------
@pytest.mark.parametrize("native", [False, True])
async def test_one_alarm_on_two_axes_in_one_second_is_two_history_events(
    both_clients: tuple[Machine, FocasClient, NativeClient], native: bool
) -> None:
    """SV0401 on X and on Y in one second: the projection reported one history entry, its
    key leaving out the axis; and an alarm raised, cleared and raised again within the second
    is two entries of the history, each reported."""
    machine, cnc, through_native = both_clients
    client: FocasClient | NativeClient = through_native if native else cnc
    projection = AlarmProjection(client, "active+history", replay_history=False)
    assert await projection.poll() == []
    machine.raise_alarm(1, 6, 401, "SV0401")
    machine.raise_alarm(2, 6, 401, "SV0401")
    machine.clear_alarms()
    machine.raise_alarm(0, 3, 10, "PS0010")
    machine.clear_alarms()
    machine.raise_alarm(0, 3, 10, "PS0010")
    events = await projection.poll()
    history = [e.entry for e in events if isinstance(e, AlarmHistoryEvent)]
    assert [(e.axis_no, e.alm_type, e.alm_no) for e in history] == [
        (1, 6, 401),
        (2, 6, 401),
        (0, 3, 10),
        (0, 3, 10),
    ]
    assert [e for e in await projection.poll() if isinstance(e, AlarmHistoryEvent)] == []
