"""The dashboard's pure parts without a browser or aiohttp: the view model, the page actions
(the machine's operations and checks), the ``--web`` address, the broadcaster."""

from __future__ import annotations

import asyncio
import json
import re
import sys
from decimal import Decimal
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net._typed import override_unfit
from focas_net.cli._format import parse_aut
from focas_net.errors import EW, ew_name
from focas_net.sim import Machine, MachineError, default_machine, load_machine
from focas_net.sim.machine import MDI, MEM
from focas_net.sim.nc import ManualClock
from focas_net.web import (
    ACTIONS,
    FLEET,
    ActionError,
    Broadcaster,
    PathTrail,
    Station,
    Subscription,
    fleet_view,
    is_loopback,
    machine_tile,
    machine_topic,
    machine_view,
    macro_rows,
    param_rows,
    parse_web_address,
    perform,
    pmc_window,
    refusal,
    status_fields,
)

ROOT = Path(__file__).resolve().parent.parent


def running_machine(clock: ManualClock, name: str = "m") -> Machine:
    machine = default_machine(sim_clock=clock)
    machine.name = name
    machine.cycle_start()
    return machine


# -- the view model -----------------------------------------------------------------------
def test_status_fields_carry_the_focas_names_and_labels() -> None:
    clock = ManualClock()
    machine = running_machine(clock)
    clock.advance(1.0)
    fields = {f["field"]: f for f in status_fields(machine)}
    # in the order the command line lists them
    assert list(fields) == [
        "mode",
        "run",
        "motion",
        "mstb",
        "emergency",
        "alarm",
        "edit",
        "tmmode",
        "hdck",
    ]
    status = machine.status()
    assert fields["mode"]["value"] == status.aut == MEM and fields["mode"]["name"] == "MEM"
    assert fields["run"]["value"] == status.run and fields["run"]["name"] == "STRT"
    # the built-in machine is an M series machine: tmmode selects nothing there
    assert (fields["tmmode"]["value"], fields["tmmode"]["name"]) == (0, "M")


def test_a_tile_follows_the_machine() -> None:
    clock = ManualClock()
    machine = running_machine(clock, "cell-7")
    clock.advance(2.0)
    tile = machine_tile(3, machine, 8199)
    assert (tile["index"], tile["name"], tile["port"]) == (3, "cell-7", 8199)
    assert (tile["mode"], tile["run"], tile["alarm"], tile["alarms"]) == ("MEM", "STRT", None, 0)
    assert tile["program"] == machine.motion.program_running == 1
    machine.raise_alarm(0, 2, 1234, "LUBE LOW")
    tile = machine_tile(3, machine, 8199)
    assert (tile["alarm"], tile["alarms"]) == ("IO1234 LUBE LOW", 1)  # the code as the CLI
    assert tile["run"] != "STRT"  # any alarm stops the cycle


def test_the_fleet_view_has_a_tile_per_machine_and_counts_them() -> None:
    clock = ManualClock()
    machines = [running_machine(clock, f"m{i}") for i in range(5)]
    machines[4].reset()
    machines[2].raise_alarm(0, 3, 10, "x")
    view = fleet_view((i, m, 9000 + i) for i, m in enumerate(machines))
    assert [t["name"] for t in view["machines"]] == [m.name for m in machines]
    assert [t["port"] for t in view["machines"]] == [9000 + i for i in range(5)]
    assert (view["count"], view["running"], view["alarmed"]) == (5, 3, 1)


def test_the_machine_view_shows_what_the_machine_reads() -> None:
    clock = ManualClock()
    machine = running_machine(clock)
    clock.advance(5.0)
    trail = PathTrail()
    trail.record(machine.motion.absolute)
    view = machine_view(0, machine, 8193, trail=trail, faults=[("DELAY", 2, 500)])
    json.dumps(view)  # JSON-able throughout
    motion = machine.motion
    assert [p["axis"] for p in view["positions"]] == machine.axes
    for kind, name in (
        ("absolute", "absolute"),
        ("machine", "machine"),
        ("relative", "relative"),
        ("distance_to_go", "distance"),  # as position --kind and watch name it
    ):
        assert [p[name] for p in view["positions"]] == [v / 1000 for v in getattr(motion, kind)]
    assert view["path"] == [[v / 1000 for v in motion.absolute]]
    assert (view["feed"], view["spindle_speed"]) == (motion.feed, motion.spindle_speed)
    assert view["timers"]["power_on"] == machine.timer(0) == 5.0
    assert view["timers"]["operating"] == machine.timer(1)
    assert view["parts"]["count"] == machine.parts_counts()[0]
    assert view["faults"] == [{"kind": "DELAY", "remaining": 2, "arg": 500, "arg_text": "500 ms"}]
    program = view["program"]
    assert program["number"] == 1
    assert program["lines"] == machine.program_text(1).splitlines()
    block = machine.engine.interpreter.block
    assert block is not None
    interp_program = machine.engine.interpreter.program
    assert interp_program is not None
    assert program["line"] == interp_program.blocks[block].line
    assert [p["number"] for p in view["programs"]] == [
        p.number for p in machine.program_directory()
    ]
    assert view["programs"][0]["running"] and view["programs"][0]["main"]
    assert {a["area"] for a in view["pmc_areas"]} >= {"X", "F", "G", "R", "D"}
    assert view["loads"] == {
        "spindle": list(machine.spindle_loads()),
        "servo": list(machine.servo_loads()),
    }


def test_alarms_and_the_history_newest_first() -> None:
    machine = default_machine()
    machine.raise_alarm(0, 2, 1, "ONE")
    machine.raise_alarm(1, 2, 2, "TWO")
    machine.clear_alarms(2, 1)
    view = machine_view(0, machine, 1)
    assert [a["alm_no"] for a in view["alarms"]] == [2]
    assert [h["alm_no"] for h in view["history"]] == [2, 1]


def test_a_path_trail_is_bounded_and_skips_repeats() -> None:
    trail = PathTrail(size=3)
    for point in ([0, 0], [0, 0], [1000, 0], [2000, 0], [3000, 500]):
        trail.record(point)
    assert list(trail.points) == [(1.0, 0.0), (2.0, 0.0), (3.0, 0.5)]


def test_a_pmc_window_and_its_refusals() -> None:
    machine = default_machine()
    machine.write_pmc("R", 10, b"\x01\x02")
    window = pmc_window(machine, "r", 10, 4)
    assert (window["area"], window["start"], window["bytes"]) == ("R", 10, [1, 2, 0, 0])
    assert window["size"] == machine.pmc_area("R")[0]  # type: ignore[index]
    end = pmc_window(machine, "X", 126)
    assert end["bytes"] == [0, 0]  # cut at the area's end
    with pytest.raises(MachineError) as info:
        pmc_window(machine, "E", 0)
    assert info.value.ew == EW.NOOPT
    with pytest.raises(MachineError) as info:
        pmc_window(machine, "X", 128)
    assert info.value.ew == EW.NUMBER and "X128" in str(info.value)


def test_parameter_rows_search_by_number_or_name() -> None:
    machine = default_machine()
    by_number = param_rows(machine, "671")
    assert [r["number"] for r in by_number] == [6711, 6712, 6713]
    by_name = param_rows(machine, "RAPID")
    assert 1420 in [r["number"] for r in by_name]
    rapid = next(r for r in by_name if r["number"] == 1420)
    assert rapid["axis"] and len(rapid["values"]) == len(machine.axes)
    assert rapid["values"] == [str(machine.read_param(1420, a + 1)) for a in range(3)]
    assert param_rows(machine, "no such name") == []


def test_axis_values_are_named_and_bit_parameters_show_their_bits() -> None:
    machine = default_machine()
    (apc,) = param_rows(machine, "1815")
    assert (apc["type"], apc["axes"]) == ("bit", ["X", "Y", "Z"])
    assert apc["values"] == ["00110000"] * 3 == apc["bits"]  # shown and edited as 8 bits
    (channel,) = param_rows(machine, "20")
    assert (channel["type"], channel["axes"], channel["bits"]) == ("byte", [], None)
    (rapid,) = [r for r in param_rows(machine, "1420") if r["number"] == 1420]
    assert rapid["type"] == "two-word" and len(rapid["axes"]) == len(rapid["values"]) == 3


def test_macro_rows_by_number_and_range() -> None:
    machine = default_machine()
    machine.write_macro(501, Decimal("1.50"))
    numbers = Station(0, machine).macro_numbers()
    assert {2, 501, 3901, 5021} <= set(numbers) and not {34, 99, 200} & set(numbers)
    assert list(numbers) == sorted(numbers)
    rows = macro_rows(machine, numbers, "500-502")
    assert rows == [
        {"number": 500, "value": None, "writable": True},
        {"number": 501, "value": "1.50", "writable": True},
        {"number": 502, "value": None, "writable": True},
    ]
    assert macro_rows(machine, numbers, "#5021", limit=1)[0]["writable"] is False
    with pytest.raises(ValueError, match="'five'"):
        macro_rows(machine, numbers, "five")


# -- the page actions ---------------------------------------------------------------------
def refused(station: Station, action: str, args: dict[str, object], **kw: bool) -> str:
    with pytest.raises(MachineError) as info:
        perform(station, action, args, **kw)
    return ew_name(info.value.ew)


def test_cycle_start_hold_and_reset_are_the_machines() -> None:
    clock = ManualClock()
    station = Station(0, default_machine(sim_clock=clock))
    assert perform(station, "cycle", {"action": "start"}) == {"ok": True}
    clock.advance(1.0)
    assert station.machine.status().run == 3
    perform(station, "cycle", {"action": "hold"})
    assert station.machine.status().run == 2
    perform(station, "cycle", {"action": "reset"})
    assert station.machine.status().run == 0
    with pytest.raises(ActionError, match="'spin'"):
        perform(station, "cycle", {"action": "spin"})


def test_cycle_start_outside_mem_is_refused_as_on_the_wire() -> None:
    station = Station(0, default_machine())
    perform(station, "panel", {"mode": MDI})
    assert refused(station, "cycle", {"action": "start"}) == "EW_MODE"


def test_a_parameter_write_with_pwe_off_is_refused_with_ew_passwd() -> None:
    station = Station(0, default_machine())
    assert refused(station, "write_param", {"number": 6713, "value": "12"}) == "EW_PASSWD"
    perform(station, "panel", {"mode": MDI, "pwe": 1})
    assert perform(station, "write_param", {"number": "6713", "value": "12"})["value"] == 12
    assert station.machine.read_param(6713, 0) == 12
    assert refused(station, "write_param", {"number": 6713, "value": "-1"}) == "EW_DATA"
    assert refused(station, "write_param", {"number": 9999, "value": "1"}) == "EW_NUMBER"
    assert refused(station, "write_param", {"number": 1420, "value": "1"}) == "EW_ATTRIB"
    with pytest.raises(ActionError, match=r"'1\.5'|1\.5"):
        perform(station, "write_param", {"number": 6713, "value": "1.5"})
    with pytest.raises(ActionError, match="'abc'"):
        perform(station, "write_param", {"number": 6713, "value": "abc"})


def test_a_password_protected_parameter_needs_the_pages_unlock() -> None:
    station = Station(0, default_machine(param_password="1234"))
    perform(station, "panel", {"mode": MDI, "pwe": 1})
    assert refused(station, "write_param", {"number": 6713, "value": "3"}) == "EW_PASSWD"
    assert refused(station, "unlock", {"password": "9999"}) == "EW_PASSWD"
    perform(station, "unlock", {"password": "1234"})
    perform(station, "write_param", {"number": 6713, "value": "3"})
    assert station.machine.read_param(6713, 0) == 3


def test_macro_writes_and_vacating() -> None:
    station = Station(0, default_machine())
    assert perform(station, "write_macro", {"number": 500, "value": "2.250"})["value"] == "2.250"
    assert station.machine.read_macro(500) == Decimal("2.250")
    perform(station, "write_macro", {"number": 500, "value": ""})
    assert station.machine.read_macro(500) is None
    assert refused(station, "write_macro", {"number": 5021, "value": "1"}) == "EW_PROT"
    assert refused(station, "write_macro", {"number": 50, "value": "1"}) == "EW_NUMBER"
    with pytest.raises(ActionError, match=r"^#500: macro value 0\.000000000001 does not fit"):
        perform(station, "write_macro", {"number": 500, "value": "0.000000000001"})
    for typed in ("1e-12", "1E3", "\u0661\u0662", "12abc", "inf"):
        with pytest.raises(ActionError, match=re.escape(repr(typed))):  # refused, named, unread
            perform(station, "write_macro", {"number": 500, "value": typed})
    assert station.machine.read_macro(500) is None


def test_pmc_bits_x_and_f_as_the_simulator_others_as_the_protocol() -> None:
    machine = default_machine()
    station = Station(0, machine)
    assert machine.pmc_area("X") == (128, True)  # write-protected for pmc_wrpmcrng
    perform(station, "pmc_bit", {"area": "X", "address": 3, "bit": 5})
    assert machine.read_pmc("X", 3, 1) == bytes([0b0010_0000])
    perform(station, "pmc_bit", {"area": "x", "address": 3, "bit": 5})
    assert machine.read_pmc("X", 3, 1) == b"\x00"
    perform(station, "pmc_bit", {"area": "R", "address": 7, "bit": 0, "value": 1})
    perform(station, "pmc_bit", {"area": "R", "address": 7, "bit": 0, "value": 1})
    assert machine.read_pmc("R", 7, 1) == b"\x01"
    assert refused(station, "pmc_bit", {"area": "E", "address": 0, "bit": 0}) == "EW_NOOPT"
    assert refused(station, "pmc_bit", {"area": "R", "address": 9000, "bit": 0}) == "EW_NUMBER"
    with pytest.raises(ActionError, match=r"^R0\.8: bit 8 is outside 0\.\.7"):
        perform(station, "pmc_bit", {"area": "R", "address": 0, "bit": 8})
    with pytest.raises(ActionError, match="'Q'"):
        perform(station, "pmc_bit", {"area": "Q", "address": 0, "bit": 0})


def test_alarms_raised_and_cleared() -> None:
    station = Station(0, default_machine())
    assert perform(station, "raise_alarm", {"alm_type": "2", "alm_no": 77, "msg": "HI"}) == {
        "ok": True,
        "raised": True,
        "msg": "HI",
    }
    assert [(a.alm_type, a.alm_no, a.msg) for a in station.machine.active_alarms()] == [
        (2, 77, "HI")
    ]
    assert refused(station, "raise_alarm", {"alm_type": 40, "alm_no": 1}) == "EW_DATA"
    assert perform(station, "clear_alarms", {})["cleared"] == 1
    with pytest.raises(ActionError, match="alm_no: a number is needed"):
        perform(station, "raise_alarm", {"alm_type": 2})


def test_overrides_and_panel_switches_with_the_machines_ranges() -> None:
    station = Station(0, default_machine())
    perform(station, "overrides", {"feed": 50, "rapid": "25"})
    assert station.machine.overrides()[:2] == (50, 25)
    assert refused(station, "overrides", {"feed": 300}) == "EW_DATA"
    perform(station, "panel", {"emergency": 1})
    assert station.machine.panel.emergency == 1
    assert refused(station, "panel", {"mode": 2}) == "EW_DATA"


def test_faults_are_armed_with_the_checks_of_inject_fault() -> None:
    station = Station(0, default_machine())
    assert perform(station, "inject_fault", {"kind": "DELAY", "count": 2, "arg": 300}) == {
        "ok": True,
        "armed": 1,
    }
    perform(station, "inject_fault", {"kind": "error", "arg": int(EW.BUSY)})
    assert station.fault_listing() == [("DELAY", 2, 300), ("ERROR", 1, int(EW.BUSY))]
    assert refused(station, "inject_fault", {"kind": "DELAY", "arg": 70_000}) == "EW_DATA"
    assert refused(station, "inject_fault", {"kind": "ERROR", "arg": 0}) == "EW_DATA"
    with pytest.raises(ActionError, match="unknown fault kind 'slow'"):
        perform(station, "inject_fault", {"kind": "slow"})
    assert perform(station, "clear_faults", {})["cleared"] == 2
    assert station.fault_listing() == []


def test_a_fault_argument_that_is_not_a_number_is_refused() -> None:
    station = Station(0, default_machine())
    for args in (
        {"kind": "DELAY", "arg": "abc"},
        {"kind": "DELAY", "arg": ""},  # what a number field with letters in it sends
        {"kind": "DELAY"},
        {"kind": "ERROR", "count": "1", "arg": " "},
        {"kind": "DROP", "count": "abc"},
        {"kind": "DROP", "count": ""},
    ):
        with pytest.raises(ActionError, match=r"^(count|arg): "):
            perform(station, "inject_fault", args)
    assert station.fault_listing() == []
    # a drop or a split ignores the argument it does not need
    perform(station, "inject_fault", {"kind": "SPLIT"})
    perform(station, "inject_fault", {"kind": "DROP", "count": "0x2"})
    assert station.fault_listing() == [("SPLIT", 1, 0), ("DROP", 2, 0)]
    view = machine_view(0, station.machine, 8193, faults=station.fault_listing())
    assert view["fault_kinds"] == ["DELAY", "ERROR", "DROP", "SPLIT"]  # the page's choices


def test_bit_parameters_are_written_as_the_command_line_writes_them() -> None:
    station = Station(0, default_machine())
    perform(station, "panel", {"mode": MDI, "pwe": 1})
    for text, value in (("0xB0", 0xB0), ("0b1011_0001", 0b1011_0001), ("00001100", 12), (7, 7)):
        answer = perform(station, "write_param", {"number": 1815, "axis": 2, "value": text})
        assert answer["value"] == station.machine.read_param(1815, 2) == value
    with pytest.raises(ActionError, match="'0xZZ'"):
        perform(station, "write_param", {"number": 1815, "axis": 2, "value": "0xZZ"})
    for typed in ("12", "0o7", "\u0661\u0662"):  # bits are eight, a decimal is none
        with pytest.raises(ActionError, match=r"8 bits #7\.\.#0"):
            perform(station, "write_param", {"number": 1815, "axis": 2, "value": typed})
    assert station.machine.read_param(1815, 2) == 7


def test_an_alarm_message_is_text_the_client_can_send() -> None:
    station = Station(0, default_machine())
    with pytest.raises(ActionError, match="msg: alarm message must be ASCII"):
        perform(station, "raise_alarm", {"alm_type": 3, "alm_no": 100, "msg": "TEMP 40\xb0C"})
    assert station.machine.active_alarms() == [] and station.machine.alarm_history() == ()
    perform(station, "raise_alarm", {"alm_type": 3, "alm_no": 100, "msg": "TEMP 40 C"})
    assert [a.msg for a in station.machine.active_alarms()] == ["TEMP 40 C"]


def test_select_program_is_a_program_search() -> None:
    station = Station(0, default_machine())
    assert refused(station, "select_program", {"number": 4242}) == "EW_NUMBER"
    perform(station, "panel", {"mode": MDI})
    assert refused(station, "select_program", {"number": 1}) == "EW_MODE"


def test_a_read_only_dashboard_refuses_every_write_with_ew_prot() -> None:
    machine = default_machine()
    station = Station(0, machine)
    before = machine.state_digest()
    for action in ACTIONS:
        if action == "clear_path":
            continue
        assert refused(station, action, {}, read_only=True) == "EW_PROT"
    assert machine.state_digest() == before
    assert perform(station, "clear_path", {}, read_only=True) == {"ok": True}


def test_a_read_only_machine_refuses_the_page_too() -> None:
    machine = default_machine()
    machine.read_only = True
    station = Station(0, machine)
    assert refused(station, "cycle", {"action": "start"}) == "EW_PROT"
    assert refused(station, "pmc_bit", {"area": "X", "address": 0, "bit": 0}) == "EW_PROT"
    assert refused(station, "inject_fault", {"kind": "DROP"}) == "EW_PROT"
    assert refused(station, "clear_faults", {}) == "EW_PROT"


def test_an_unknown_action_names_itself() -> None:
    with pytest.raises(ActionError, match="'fly'"):
        perform(Station(0, default_machine()), "fly", {})


def test_a_refusal_as_the_page_sees_it() -> None:
    answer = refusal(MachineError(EW.PASSWD, "parameter write not enabled"))
    assert answer == {
        "ok": False,
        "ew": int(EW.PASSWD),
        "ew_name": "EW_PASSWD",
        "error": "parameter write not enabled",
    }


# -- the --web address --------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "address"),
    [
        ("8080", ("127.0.0.1", 8080)),
        ("0", ("127.0.0.1", 0)),
        ("0.0.0.0:80", ("0.0.0.0", 80)),
        ("localhost:9000", ("localhost", 9000)),
        ("[::1]:8080", ("::1", 8080)),
    ],
)
def test_web_addresses(text: str, address: tuple[str, int]) -> None:
    assert parse_web_address(text) == address


@pytest.mark.parametrize("text", ["", "http", "80800", ":80", "host:", "::1:80", "a b:1", "-1"])
def test_bad_web_addresses_are_named(text: str) -> None:
    with pytest.raises(ValueError) as info:
        parse_web_address(text)
    assert repr(text) in str(info.value)


@given(st.integers(0, 65_535))
def test_any_port_round_trips(port: int) -> None:
    assert parse_web_address(str(port)) == ("127.0.0.1", port)
    assert parse_web_address(f"10.0.0.1:{port}") == ("10.0.0.1", port)


def test_loopback_hosts() -> None:
    assert all(is_loopback(h) for h in ("127.0.0.1", "127.1.2.3", "::1", "localhost"))
    assert not any(is_loopback(h) for h in ("0.0.0.0", "192.168.1.5", "::", "example.com"))


# -- the broadcaster ----------------------------------------------------------------------
def fleet(n: int, clock: ManualClock) -> list[Station]:
    return [Station(i, running_machine(clock, f"m{i}"), port=9000 + i) for i in range(n)]


def test_one_tick_computes_each_view_once_for_every_page() -> None:
    clock = ManualClock()
    stations = fleet(4, clock)
    b = Broadcaster(stations)
    fleet_pages = [b.subscribe(FLEET) for _ in range(5)]
    machine_pages = [b.subscribe(machine_topic(1)) for _ in range(3)]
    other_window = b.subscribe(machine_topic(1, "R", 16))
    assert b.tick() == 3  # three topics
    assert b.views_computed == 2  # the fleet once, machine 1 once (shared by both windows)
    frames = {sub.take() for sub in fleet_pages}
    assert len(frames) == 1  # the very same frame for every fleet page
    (frame,) = frames
    assert frame is not None
    message = json.loads(frame)
    assert message["type"] == "fleet" and message["data"]["count"] == 4
    machine_frames = [json.loads(s.take() or "") for s in [*machine_pages, other_window]]
    assert {m["data"]["name"] for m in machine_frames} == {"m1"}
    assert machine_frames[0]["pmc"]["area"] == "X" and machine_frames[-1]["pmc"]["start"] == 16


def test_no_page_no_view() -> None:
    b = Broadcaster(fleet(3, ManualClock()))
    assert b.tick() == 0 and b.views_computed == 0
    assert all(not s.trail.points for s in b.stations)  # no page: no machine is read


@pytest.mark.parametrize("topic", [FLEET, machine_topic(0)])
def test_the_paths_move_with_machine_time(topic: tuple[str, ...]) -> None:
    """The fleet view records every machine's path, a machine view its own."""
    clock = ManualClock()
    stations = fleet(2, clock)
    b = Broadcaster(stations)
    b.subscribe(topic)
    for _ in range(20):
        clock.advance(0.5)
        b.tick()
    points = stations[0].trail.points
    assert len(points) > 5
    assert points[-1] == tuple(v / 1000 for v in stations[0].machine.motion.absolute)
    assert bool(stations[1].trail.points) == (topic == FLEET)


def test_a_slow_page_drops_its_oldest_frames_and_holds_up_no_one() -> None:
    clock = ManualClock()
    b = Broadcaster(fleet(2, clock))
    slow = b.subscribe(FLEET, depth=2)
    fast = b.subscribe(FLEET, depth=2)
    seen = []
    for _ in range(10):
        clock.advance(1.0)
        b.tick()
        seen.append(fast.take())
    assert len(slow) == 2 and slow.dropped == 8
    assert slow.take() == seen[-2] and slow.take() == seen[-1]
    assert fast.dropped == 0


def test_an_unknown_machine_topic_answers_an_error_frame() -> None:
    b = Broadcaster(fleet(1, ManualClock()))
    sub = b.subscribe(machine_topic(7))
    b.tick()
    assert json.loads(sub.take() or "") == {
        "type": "error",
        "error": "no machine 7 (this dashboard shows machine 0)",
    }


async def test_a_closed_subscription_ends_its_sender() -> None:
    sub = Subscription(FLEET)
    sub.offer("a")
    assert await sub.next() == "a"
    waiting = asyncio.ensure_future(sub.next())
    await asyncio.sleep(0)
    sub.offer("b")
    assert await asyncio.wait_for(waiting, 5.0) == "b"
    waiting = asyncio.ensure_future(sub.next())
    await asyncio.sleep(0)
    sub.close()
    assert await asyncio.wait_for(waiting, 5.0) is None
    sub.offer("c")  # dropped: closed
    assert len(sub) == 0


def test_bad_intervals_and_depths() -> None:
    with pytest.raises(ValueError, match="0"):
        Broadcaster([], interval=0)
    with pytest.raises(ValueError, match="0"):
        Subscription(FLEET, depth=0)


# -- packaging and layering ---------------------------------------------------------------
def test_importing_the_dashboard_needs_no_aiohttp() -> None:
    import subprocess

    code = "import sys, focas_net.web, focas_net.cli; print('aiohttp' in sys.modules)"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    )
    assert out.stdout.strip() == "False"


def test_the_page_is_package_data() -> None:
    import tomllib

    static = ROOT / "focas_net" / "web" / "static"
    assert {p.name for p in static.iterdir()} >= {"index.html", "app.js", "style.css"}
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    data = config["tool"]["setuptools"]["package-data"]["focas_net"]
    assert {"web/static/*.html", "web/static/*.js", "web/static/*.css"} <= set(data)
    assert config["project"]["optional-dependencies"]["web"] == ["aiohttp>=3.9"]


def test_the_web_package_exports_its_names_once_and_imports_no_client() -> None:
    import ast
    import importlib

    import focas_net.web as web

    assert len(web.__all__) == len(set(web.__all__))
    assert [n for n in web.__all__ if not hasattr(web, n)] == []
    for name in ("address", "broadcast", "operations", "shell", "view"):
        module = importlib.import_module(f"focas_net.web.{name}")
        assert set(module.__all__) <= set(web.__all__), name
    for path in (ROOT / "focas_net" / "web").glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module:
                assert not node.module.startswith(("focas_net.client", "focas_net.adapters"))


LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


def test_a_machine_of_two_paths_is_viewed_and_worked_per_path() -> None:
    lathe = load_machine(LATHE)
    station = Station(0, lathe)
    tile = machine_tile(0, lathe, 8193)
    assert [(p["path_no"], p["path_name"], p["mode"]) for p in tile["paths"]] == [
        (1, "TURRET1", "MEM"),
        (2, "TURRET2", "MEM"),
    ]
    perform(station, "cycle", {"action": "start", "path": 2})
    assert (lathe.status(path=1).run, lathe.status(path=2).run) == (0, 3)
    tile = machine_tile(0, lathe, 8193)
    assert tile["running"] and tile["run"] == "****"  # path 1's run; the tile runs with path 2
    assert (tile["paths"][1]["run"], tile["paths"][1]["program"]) == ("STRT", 2001)
    view = machine_view(0, lathe, 8193, path=2)
    assert (view["path_no"], view["path_count"], view["axes"]) == (2, 2, ["X2", "Z2"])
    assert [p["axis"] for p in view["positions"]] == ["X2", "Z2"]
    assert [p["number"] for p in view["programs"]] == [2001]
    perform(station, "raise_alarm", {"alm_type": 3, "alm_no": 1234, "path": 2})
    assert [a["alm_no"] for a in machine_view(0, lathe, 8193, path=2)["alarms"]] == [1234]
    assert machine_view(0, lathe, 8193)["alarms"] == []
    perform(station, "panel", {"mode": MDI, "pwe": 1, "path": 2})
    perform(station, "write_param", {"number": 6711, "value": "7", "path": 2})
    assert (lathe.read_param(6711, 0, path=1), lathe.read_param(6711, 0, path=2)) == (0, 7)
    (row,) = param_rows(lathe, "6711", path=2)
    assert row["values"] == ["7"]
    with pytest.raises(MachineError, match="path 3") as info:
        perform(station, "cycle", {"action": "start", "path": 3})
    assert info.value.ew == EW.PATH
    with pytest.raises(ActionError, match="path: "):
        perform(station, "cycle", {"action": "start", "path": "\u0662"})
    single = machine_tile(0, default_machine(), 8193)
    assert len(single["paths"]) == 1 and single["paths"][0]["path_no"] == 1


def test_panel_mode_is_read_as_the_command_line_reads_it() -> None:
    station = Station(0, default_machine())
    perform(station, "panel", {"mode": "mdi"})
    assert station.machine.panel.mode == MDI
    perform(station, "panel", {"mode": " MEM "})
    assert station.machine.panel.mode == MEM
    with pytest.raises(ActionError) as info:
        perform(station, "panel", {"mode": "milling"})
    assert str(info.value) == f"mode: {parse_aut_refusal('milling')}"
    assert "'milling'" in str(info.value) and "MDI, MEM, EDIT" in str(info.value)


def parse_aut_refusal(typed: str) -> str:
    """What the command line says of a mode it does not know."""
    with pytest.raises(ValueError) as info:
        parse_aut(typed)
    return str(info.value)


def test_override_refusal_is_the_machines_on_the_page_and_the_client() -> None:
    station = Station(0, default_machine())
    with pytest.raises(MachineError) as info:
        perform(station, "overrides", {"rapid": 101})
    assert info.value.ew == EW.DATA
    assert str(info.value).endswith(str(override_unfit("rapid", 101)))
    assert "rapid override 101 is not a step of FANUC's: 0 (F0), 25, 50 or 100 %" in str(info.value)
    assert override_unfit("rapid", 100) is None
