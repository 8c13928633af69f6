"""A machine running a part program, read through both protocols with a hand-stepped clock."""

from __future__ import annotations

from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from decimal import Decimal
from typing import Any

import pytest
from support import IO_TIMEOUT, Served, serving

from focas_net.adapters import PackedAdapter
from focas_net.client import FocasClient
from focas_net.client.native import NativeClient
from focas_net.errors import EW, CncError
from focas_net.protocol import Command
from focas_net.sim import DataItem, Machine, MachineError, ParamKind, default_machine
from focas_net.sim.nc import CycleState, ManualClock

#: The spindle started (an M function's 0.5 s), X from 0 to 60 at F1200 (3.0 s), a one-second
#: dwell, a part.
PROGRAM = """O0100 (RUN TEST)
N10 G90 G21 G17 G54 S1000 M3
N20 G1 X60. F1200
N30 G4 P1000
N40 M30
"""

#: A program error (PS0010, improper G code) in its second block.
BAD = """O0200 (BAD)
N10 G1 X10. F600
N20 G123
N30 M30
"""

STAMP = datetime(2026, 12, 1, 8, 0, 0, tzinfo=UTC)


SPINDLE_START = 0.5


def start(machine: Machine, clock: ManualClock) -> None:
    """Cycle start, and the clock past the spindle's start: the motion of N20 begins."""
    machine.cycle_start()
    clock.advance(SPINDLE_START)


@pytest.fixture
def clock() -> ManualClock:
    return ManualClock()


@pytest.fixture
def machine(clock: ManualClock) -> Machine:
    return default_machine(sim_clock=clock, programs=(PROGRAM, BAD), clock=lambda: STAMP)


@pytest.fixture
async def served(machine: Machine) -> AsyncIterator[Served]:
    async with serving(machine) as s:
        yield s


@pytest.fixture
async def client(served: Served) -> AsyncIterator[FocasClient]:
    async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as c:
        yield c


async def test_cycle_start_moves_what_the_client_reads(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    assert (await client.read_status()).run == 0
    start(machine, clock)
    clock.advance(1.5)
    status = await client.read_status()
    assert (status.run, status.motion) == (3, 1)  # STRT, MTN
    positions = await client.read_positions("absolute")
    assert list(positions.increments.values()) == [30000, 0, 0]  # X30.000 half way
    assert await client.read_feed() == 1200
    assert await client.read_spindle_speed() == 1000
    numbers = await client.read_program_numbers()
    assert (numbers.running, numbers.main) == (100, 100)
    assert await client.read_macro(5021) == Decimal("30.000")
    distance = await client.read_positions("distance")
    assert list(distance.increments.values()) == [30000, 0, 0]
    clock.advance(2.0)  # in the dwell
    status = await client.read_status()
    assert (status.run, status.motion) == (3, 2)  # STRT, DWL
    assert await client.read_feed() == 0
    assert machine.timer(2) == pytest.approx(3.0)  # cutting time: the 3 s of G1


async def test_feed_hold_stops_the_axes_and_cycle_start_resumes(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    start(machine, clock)
    clock.advance(1.0)
    machine.feed_hold()
    held = list((await client.read_positions("machine")).increments.values())
    assert held == [20000, 0, 0]
    clock.advance(10.0)
    assert (await client.read_status()).run == 2  # HOLD
    assert list((await client.read_positions("machine")).increments.values()) == held
    assert await client.read_feed() == 0
    machine.cycle_start()
    clock.advance(0.5)
    assert (await client.read_status()).run == 3
    assert list((await client.read_positions("machine")).increments.values()) == [30000, 0, 0]


async def test_reset_rewinds(machine: Machine, clock: ManualClock, client: FocasClient) -> None:
    start(machine, clock)
    clock.advance(1.0)
    machine.reset()
    status = await client.read_status()
    assert (status.run, status.motion) == (0, 0)
    assert list((await client.read_positions("machine")).increments.values()) == [20000, 0, 0]
    start(machine, clock)  # from the head again: X from 20 to 60 takes 2 s
    clock.advance(2.0)
    assert list((await client.read_positions("machine")).increments.values()) == [60000, 0, 0]


async def test_m30_counts_one_part(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    before = await client.read_param(6711)
    machine.cycle_start()
    clock.advance(10.0)
    assert (await client.read_status()).run == 0  # rewound after M30
    assert await client.read_param(6711) == before + 1
    assert await client.read_param(6712) == before + 1
    assert await client.read_macro(3901) == Decimal(before + 1)
    machine.cycle_start()
    clock.advance(10.0)
    assert await client.read_macro(3901) == Decimal(before + 2)


async def test_program_error_raises_its_alarm_and_stops(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    machine.programs.select(200)
    machine.cycle_start()
    clock.advance(5.0)
    status = await client.read_status()
    assert (status.run, status.alarm) == (1, 1)  # STOP with an alarm
    alarms = await client.read_alarms()
    assert [(a.alm_type, a.alm_no) for a in alarms] == [(3, 10)]
    history = await client.read_alarm_history()
    assert [(e.alm_type, e.alm_no) for e in history.entries][:1] == [(3, 10)]
    # raised at 1.0 s of machine time (N10 takes 1 s), recorded at 5.0 s: stamped 4 s back
    assert history.entries[0].occurred_at == STAMP - timedelta(seconds=4)
    with pytest.raises(MachineError) as refused:
        machine.cycle_start()
    assert refused.value.ew == EW.ALARM
    machine.reset()  # clears the program's alarm, the history keeps it
    assert await client.read_alarms() == ()
    assert [(e.alm_type, e.alm_no) for e in (await client.read_alarm_history()).entries][:1] == [
        (3, 10)
    ]


#: A program error in its first block: the cycle start itself runs into it.
FIRST_BLOCK_BAD = "O1005\nG999\nM30\n"


@pytest.mark.parametrize("later", [0.0, 5.0])
def test_a_program_error_in_the_first_block_raises_its_alarm(
    machine: Machine, clock: ManualClock, later: float
) -> None:
    machine.select_program(machine.store_program(FIRST_BLOCK_BAD))
    machine.cycle_start()
    clock.advance(later)
    status = machine.status()
    assert (status.run, status.alarm) == (1, 1)  # STOP with an alarm
    assert [(a.alm_type, a.alm_no) for a in machine.active_alarms()] == [(3, 10)]
    history = machine.alarm_history()
    assert [(e.alm_type, e.alm_no, e.occurred_at) for e in history] == [(3, 10, STAMP)]
    with pytest.raises(MachineError) as refused:
        machine.cycle_start()
    assert refused.value.ew == EW.ALARM
    machine.reset()  # clears the program's alarm: the next program runs without it
    assert machine.active_alarms() == []
    machine.select_program(100)
    machine.cycle_start()
    clock.advance(10.0)
    status = machine.status()
    assert (status.run, status.alarm) == (0, 0)  # ran to its end, rewound
    assert len(machine.alarm_history()) == 1


def test_a_program_of_one_m30_counts_its_part_at_the_cycle_start(
    machine: Machine, clock: ManualClock
) -> None:
    before = machine.read_param(6711, 0)  # the parts count
    machine.select_program(machine.store_program("O1006\nM30\n"))
    machine.cycle_start()
    assert machine.read_param(6711, 0) == before + 1
    assert machine.read_macro(3901) == before + 1


async def test_emergency_stop_and_any_alarm_stop_the_cycle(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    start(machine, clock)
    clock.advance(1.0)
    machine.raise_alarm(0, 6, 401, "SERVO ALARM")
    clock.advance(1.0)
    assert (await client.read_status()).run == 1
    assert list((await client.read_positions("machine")).increments.values()) == [20000, 0, 0]
    machine.clear_alarms()
    machine.reset()
    start(machine, clock)
    clock.advance(0.5)
    machine.set_panel(emergency=1)
    assert (await client.read_status()).run == 0
    with pytest.raises(MachineError) as refused:
        machine.cycle_start()
    assert refused.value.ew == EW.ALARM


async def test_cycle_start_needs_mem(machine: Machine) -> None:
    machine.set_panel(mode=0)
    with pytest.raises(MachineError) as refused:
        machine.cycle_start()
    assert refused.value.ew == EW.MODE


async def test_native_reads_give_the_same_numbers(
    machine: Machine, clock: ManualClock, served: Served, client: FocasClient
) -> None:
    start(machine, clock)
    clock.advance(1.5)
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        n_status = await native.read_status()
        p_status = await client.read_status()
        assert (n_status.run, n_status.motion) == (p_status.run, p_status.motion) == (3, 1)
        n_pos = await native.read_positions("absolute")
        p_pos = await client.read_positions("absolute")
        assert list(n_pos.increments.values()) == list(p_pos.increments.values()) == [30000, 0, 0]
        assert await native.read_feed() == await client.read_feed() == 1200
        assert await native.read_spindle_speed() == 1000
        assert await native.read_sequence_number() == 20
        assert (await native.read_program_numbers()).running == 100
        assert await native.read_macro(5021) == Decimal("30.000")
        clock.advance(10.0)
        assert await native.read_param(6711) == await client.read_param(6711) == 1
        info = await client.read_run_info()
        packed_ms = (info.power_on_ms, info.operating_ms, info.cutting_ms, info.cycle_ms)
        assert info.cutting_ms == 3000  # the 3 s of G1
        for kind, ms in enumerate(packed_ms):  # cnc_rdtimer: whole minutes and the ms past them
            timer = await native.read_timer(kind)
            assert 60_000 * timer.minute + timer.msec == ms


async def test_a_moving_machine_is_never_served_a_cached_answer(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    start(machine, clock)
    seen = []
    for _ in range(4):
        clock.advance(0.5)
        seen.append((await client.read_positions("absolute")).increments["X"])
    assert seen == [10000, 20000, 30000, 40000]


def test_set_motion_wins_until_the_next_cycle_start(machine: Machine, clock: ManualClock) -> None:
    start(machine, clock)
    clock.advance(1.0)
    machine.set_motion(feed=77)
    assert machine.motion.feed == 77 and not machine.driven
    start(machine, clock)
    assert machine.driven and machine.motion.feed == 1200  # back in N20


def test_a_machine_goes_on_from_where_it_is_on_the_clock_it_is_given(
    machine: Machine, clock: ManualClock
) -> None:
    start(machine, clock)
    clock.advance(1.0)  # X20. of N20's X60. at 20 mm/s
    assert machine.motion.absolute[0] == 20000
    ahead = ManualClock(clock.now() + 0.5)
    machine.set_clock(ahead)
    assert machine.sim_clock is ahead
    clock.advance(10.0)  # the clock it had moves it no more
    assert machine.motion.absolute[0] == 30000  # the half second ahead went by at once
    version = machine.status_version
    ahead.advance(2.0)  # N20 ended at 3.5 s: the dwell of N30
    assert machine.status_version != version and machine.status().motion == 2
    assert machine.timer(0) == ahead.now()


def test_a_clock_behind_the_machine_is_refused(machine: Machine, clock: ManualClock) -> None:
    start(machine, clock)
    clock.advance(1.0)
    before = machine.state_digest()
    with pytest.raises(ValueError, match="behind"):
        machine.set_clock(ManualClock(clock.now() - 0.001))
    assert machine.sim_clock is clock and machine.state_digest() == before


# -- the same through the protocol: programs and the cycle ------------------------------------

LOADED = """O0300 (LOADED)
N10 G90 G21 S500 M3
N20 G1 X10. F600
N30 M30
"""


async def test_load_select_start_hold_reset_through_the_client(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    assert await client.write_program(LOADED) == 300
    assert [(p.number, p.name) for p in await client.read_program_directory()] == [
        (100, "RUN TEST"),
        (200, "BAD"),
        (300, "LOADED"),
    ]
    assert await client.read_program(300) == machine.programs.text(300)
    await client.select_program(300)
    assert (await client.read_program_numbers()).main == 300
    await client.sim.cycle_start()
    clock.advance(SPINDLE_START + 0.5)  # 5 mm at F600
    assert (await client.read_status()).run == 3
    assert (await client.read_positions("absolute")).increments["X"] == 5000
    assert await client.read_feed() == 600
    await client.sim.feed_hold()
    clock.advance(1.0)
    assert (await client.read_status()).run == 2
    assert (await client.read_positions("absolute")).increments["X"] == 5000
    await client.sim.set_overrides(feed=50)
    await client.sim.cycle_start()
    clock.advance(0.5)  # 2.5 mm at half the feed
    assert (await client.read_positions("absolute")).increments["X"] == 7500
    assert await client.read_feed() == 300
    info = await client.read_run_info()
    assert (info.feed, info.cutting_ms) == (50, 1000)
    await client.sim.reset()
    assert (await client.read_status()).run == 0


async def test_program_refusals_answer_their_ew_codes(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    async def ew_of(call: Any) -> int:
        with pytest.raises(CncError) as refused:
            await call
        return refused.value.ew

    assert await ew_of(client.write_program(PROGRAM)) == EW.REJECT  # O0100 is stored
    assert await ew_of(client.write_program("G1 X1.")) == EW.DATA  # no O number
    assert await ew_of(client.read_program(4321)) == EW.NUMBER
    assert await ew_of(client.delete_program(4321)) == EW.NUMBER
    assert await ew_of(client.select_program(4321)) == EW.NUMBER
    await client.sim.cycle_start()  # O0100, the main program
    clock.advance(SPINDLE_START)
    assert await ew_of(client.delete_program(100)) == EW.BUSY
    assert await ew_of(client.write_program(PROGRAM, replace=True)) == EW.BUSY
    assert await ew_of(client.select_program(200)) == EW.BUSY
    await client.sim.reset()
    await client.sim.set_panel("MDI")
    assert await ew_of(client.sim.cycle_start()) == EW.MODE
    assert await ew_of(client.select_program(200)) == EW.MODE
    await client.sim.set_panel("MEM")
    await client.delete_program(100)
    assert 100 not in machine.programs
    assert await ew_of(client.sim.cycle_start()) == EW.DATA  # the main program is gone


def test_cycle_control_checks_in_order() -> None:
    def answer(machine: Machine, command: int, payload: bytes) -> bytes:
        adapter = PackedAdapter(machine)
        return adapter.answer(machine.new_session(), command, payload)

    off = default_machine(control_enabled=False)
    assert answer(off, Command.SIM_CYCLE, b"\x00") == b"\x01\x00"  # EW_FUNC before the size
    running = default_machine(sim_clock=ManualClock())
    assert answer(running, Command.SIM_CYCLE, b"\x00") == b"\x02\x00"  # EW_LENGTH
    assert answer(running, Command.SIM_CYCLE, b"\x03\x00") == b"\x05\x00"  # EW_DATA
    assert answer(running, Command.SIM_SET_OVERRIDES, b"\xff\x00\xff\xff\xff\xff") == b"\x05\x00"
    frozen = default_machine(read_only=True)
    assert answer(frozen, Command.SIM_CYCLE, b"\x03\x00") == b"\x07\x00"  # EW_PROT first
    assert answer(frozen, Command.WRPROGRAM, b"\x00\x00\x02\x00O1") == b"\x07\x00"
    assert answer(running, Command.SIM_CYCLE, b"\x00\x00") == b"\x00\x00"
    assert running.engine.state is CycleState.START


# -- the PMC signals a ladder uses ----------------------------------------------------------


def _bit(machine: Machine, area: str, byte: int, bit: int) -> int:
    return machine.read_pmc(area, byte, 1)[0] >> bit & 1


def _set_bit(machine: Machine, area: str, byte: int, bit: int, on: bool) -> None:
    old = machine.read_pmc(area, byte, 1)[0]
    new = old | 1 << bit if on else old & ~(1 << bit)
    machine.write_pmc(area, byte, bytes([new]))


def test_g_signals_drive_the_cycle_and_f_signals_show_it(
    machine: Machine, clock: ManualClock
) -> None:
    _set_bit(machine, "G", 8, 5, True)  # *SP off (negative logic: 1 = no feed hold)
    _set_bit(machine, "G", 7, 2, True)  # ST pressed: nothing yet
    assert machine.status().run == 0
    _set_bit(machine, "G", 7, 2, False)  # ST released: cycle start
    clock.advance(SPINDLE_START + 1.0)
    assert machine.status().run == 3 and machine.motion.absolute[0] == 20000
    assert (_bit(machine, "F", 0, 7), _bit(machine, "F", 0, 5), _bit(machine, "F", 0, 4)) == (
        1,
        1,
        0,
    )  # OP, STL, SPL
    _set_bit(machine, "G", 8, 5, False)  # *SP on: feed hold
    clock.advance(1.0)
    assert machine.status().run == 2 and machine.motion.absolute[0] == 20000
    assert (_bit(machine, "F", 0, 5), _bit(machine, "F", 0, 4)) == (0, 1)
    _set_bit(machine, "G", 8, 5, True)
    _set_bit(machine, "G", 7, 2, True)
    _set_bit(machine, "G", 7, 2, False)  # resumes
    clock.advance(0.5)
    assert machine.status().run == 3 and machine.motion.absolute[0] == 30000
    machine.write_pmc("G", 12, bytes([255 - 50]))  # feed override 50 %
    assert machine.overrides()[0] == 50
    _set_bit(machine, "G", 8, 7, True)  # ERS: reset, RST on while it is held
    assert machine.status().run == 0 and _bit(machine, "F", 1, 1) == 1
    assert _bit(machine, "F", 0, 7) == 0
    _set_bit(machine, "G", 8, 7, False)
    assert _bit(machine, "F", 1, 1) == 0
    machine.write_pmc("G", 43, b"\x03")  # MD1 MD2: EDIT
    assert machine.panel.mode == 3
    machine.write_pmc("G", 43, b"\x01")  # MD1: MEM
    assert machine.panel.mode == 1


async def test_f_signals_are_not_served_from_a_stale_cache(
    machine: Machine, clock: ManualClock, client: FocasClient
) -> None:
    assert (await client.read_pmc("F", 0, 1))[0] == 0x40  # SA (servo ready) alone
    start(machine, clock)
    assert (await client.read_pmc("F", 0, 1))[0] >> 5 & 1 == 1  # STL
    clock.advance(10.0)  # past M30
    assert (await client.read_pmc("F", 0, 1))[0] == 0x40


@pytest.mark.parametrize(
    ("decimals", "values", "expected"),
    [
        (1, [15000, 20000, 31000], (1500.0, 2000.0, 3100.0)),  # a real 1420: mm/min as it reads
        (0, [-5, 0, 8000], (24000.0, 24000.0, 8000.0)),  # not above 0: the default rate
    ],
)
def test_rapid_rates_come_from_parameter_1420_as_it_reads(
    decimals: int, values: list[int], expected: tuple[float, ...]
) -> None:
    item = DataItem(
        1420,
        kind=ParamKind.REAL,
        axis=True,
        low=-99999999,
        high=99999999,
        values=values,
        decimals=decimals,
    )
    machine = Machine("rates", axes=("X", "Y", "Z"), params=[item], sim_clock=ManualClock())
    assert machine.engine.settings.rapid_rates == expected


async def test_both_protocols_count_the_same_whole_milliseconds_of_a_timer() -> None:
    """A timer shows the milliseconds that have gone by: 61.2349 s is 61234 ms, never rounded
    up to 61235, and the packed 0x0032 and the native cnc_rdtimer answer the same figure."""
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    async with serving(machine) as served:
        async with (
            FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
            NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
        ):
            for seconds in (0.0009, 1.234, 61.2349, 120.0):
                clock.set(seconds)
                want = machine.timer_ms(0)
                assert want == int(Decimal(str(seconds)) * 1000)
                assert (await packed.read_run_info()).power_on_ms == want
                value = await native.read_timer(0)
                assert 60_000 * value.minute + value.msec == want
