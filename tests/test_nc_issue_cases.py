"""The cases of the machine-at-work issue's Tests paragraph that ``tests/test_nc_engine.py``
checks on the engine alone, here through a served machine and the packed client, every one
on a hand-stepped clock: what a collector reads is what the engine computed.

The cases already covered end to end in ``tests/test_machine_runs.py`` (feed hold and cycle
start, reset and rewind, M30 counting a part) are not repeated.
"""

from __future__ import annotations

import math
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from support import IO_TIMEOUT, serving

from focas_net.cli._format import alarm_code
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.nc import ManualClock

#: Least input increments per mm of the positions the client reads.
PER_MM = 1000
RUN_RESET, RUN_STOP, RUN_STRT = 0, 1, 3
#: Upper bound of the samples of one run (each loop below is bounded by it).
MAX_SAMPLES = 2_000


@pytest.fixture
def clock() -> ManualClock:
    return ManualClock()


async def _client(machine: Machine) -> AsyncIterator[FocasClient]:
    async with serving(machine) as served:
        async with FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc:
            yield cnc


async def _x_mm(cnc: FocasClient, kind: str = "machine") -> float:
    return (await cnc.read_positions(kind)).increments["X"] / PER_MM


# -- X from 0 to 60 at F1200 ----------------------------------------------------------------

LINE = "O0100 (LINE)\nN10 G90 G21 G1 X60. F1200\nN20 M30\n"
#: 60 mm at 1200 mm/min.
LINE_SECONDS = 60 / 1200 * 60


@pytest.fixture
async def line(clock: ManualClock) -> AsyncIterator[FocasClient]:
    async for cnc in _client(default_machine(sim_clock=clock, programs=(LINE,))):
        yield cnc


async def test_a_60_mm_move_at_f1200_takes_3_s_passes_30_at_1_5_and_cuts_3_s(
    line: FocasClient, clock: ManualClock
) -> None:
    before = await line.read_run_info()
    await line.sim.cycle_start()
    clock.advance(LINE_SECONDS / 2)
    assert await _x_mm(line) == 30.0
    assert await _x_mm(line, "distance") == 30.0
    assert await line.read_feed() == 1200
    clock.set(LINE_SECONDS - 0.001)
    assert (await line.read_status()).run == RUN_STRT
    assert await _x_mm(line) < 60.0
    clock.set(LINE_SECONDS)
    status = await line.read_status()
    assert (status.run, status.motion) == (RUN_RESET, 0)  # M30 ran at 3.0 s and rewound
    assert await _x_mm(line) == 60.0
    after = await line.read_run_info()
    assert after.cutting_ms - before.cutting_ms == LINE_SECONDS * 1000
    assert after.parts_count == before.parts_count + 1


# -- an arc keeps its radius ----------------------------------------------------------------

#: A rapid to (10, 0), then a quarter circle of radius 10 around the origin to (0, 10).
ARC = "O0101 (ARC)\nN10 G90 G17 G0 X10. Y0\nN20 G3 X0 Y10. I-10. J0 F600\nN30 M30\n"
RADIUS = 10.0
#: Half an increment on each axis: the most the rounding to increments can move a radius.
ROUNDING = math.hypot(0.5, 0.5) / PER_MM


async def test_an_arc_read_through_the_client_keeps_its_radius_at_every_sample(
    clock: ManualClock,
) -> None:
    async for cnc in _client(default_machine(sim_clock=clock, programs=(ARC,))):
        await cnc.sim.cycle_start()
        radii = []
        for _ in range(MAX_SAMPLES):
            clock.advance(0.05)
            if (await cnc.read_status()).run != RUN_STRT:
                break
            if await cnc.read_macro(4114) != 20:
                continue  # still in the rapid to the arc's start
            p = (await cnc.read_positions("machine")).increments
            radii.append(math.hypot(p["X"], p["Y"]) / PER_MM)
        end = (await cnc.read_positions("machine")).increments
    quarter = math.pi / 2 * RADIUS / (600 / 60)  # seconds at F600
    assert len(radii) >= int(quarter / 0.05) - 1
    assert all(abs(r - RADIUS) <= ROUNDING for r in radii), radii
    assert (end["X"], end["Y"]) == (0, 10 * PER_MM)


# -- a macro loop runs its body N times -----------------------------------------------------

LOOPS = 7
LOOP = (
    "O0102 (LOOP)\n#500 = 0\n#1 = 0\n"
    f"WHILE [#1 LT {LOOPS}] DO1\nG91 G1 X1. F600\n#500 = #500 + 1\n#1 = #1 + 1\nEND1\nM30\n"
)


async def test_a_macro_loop_runs_its_body_n_times(clock: ManualClock) -> None:
    async for cnc in _client(default_machine(sim_clock=clock, programs=(LOOP,))):
        before = await cnc.read_run_info()
        await cnc.sim.cycle_start()
        for _ in range(MAX_SAMPLES):
            if (await cnc.read_status()).run != RUN_STRT:
                break
            clock.advance(0.25)
        assert await cnc.read_macro(500) == LOOPS  # the common variable the body counts in
        assert await _x_mm(cnc) == float(LOOPS)  # one millimetre per pass
        after = await cnc.read_run_info()
    assert after.cutting_ms - before.cutting_ms == LOOPS * 100  # 1 mm at F600: 0.1 s each


# -- each program error raises its alarm and stops ------------------------------------------


@pytest.mark.parametrize(
    ("block", "code"),
    [
        ("G123", "PS0010"),  # an improper G code
        ("G1 X5.", "PS0011"),  # a feed move with no feed yet
        ("#1 = 1 / 0", "PS0112"),  # division by zero
        ("GOTO 777", "PS0128"),  # no such sequence number
        ("M98 P9999", "PS0078"),  # no such subprogram
        ("#3000 = 12 (TOOL BROKEN)", "MC3012"),  # a macro alarm
    ],
)
async def test_each_program_error_raises_its_alarm_and_stops(
    clock: ManualClock, block: str, code: str
) -> None:
    program = f"O0103 (ERRORS)\nN10 G90 G0 X1.\nN20 {block}\nN30 G0 X50.\nN40 M30\n"
    async for cnc in _client(default_machine(sim_clock=clock, programs=(program,))):
        await cnc.sim.cycle_start()
        clock.advance(5.0)
        status = await cnc.read_status()
        assert (status.run, status.alarm) == (RUN_STOP, 1)
        alarms = await cnc.read_alarms()
        assert [alarm_code(a.alm_type, a.alm_no) for a in alarms] == [code]
        assert await cnc.read_macro(4114) == 20
        assert await _x_mm(cnc) == 1.0  # N30 never moved
        with pytest.raises(CncError) as refused:
            await cnc.sim.cycle_start()
        assert refused.value.ew == EW.ALARM
        await cnc.sim.reset()
        assert await cnc.read_alarms() == ()


# -- a move past the soft limit -------------------------------------------------------------

LIMITED = """\
[machine]
name = "limited"
axes = ["X", "Y", "Z"]

[parameters.1320]
type = "i32"
axis = true
value = [100000, 50000, 999999999]

[parameters.1321]
type = "i32"
axis = true
value = [-100000, -15000, -999999999]

[[program]]
text = "O0104 (PAST THE LIMIT)\\nN10 G90 G1 X150. F6000\\nN20 M30\\n"
"""


async def test_a_move_past_the_stroke_limit_parameters_stops_on_the_limit_with_ot0500(
    clock: ManualClock, tmp_path: Path
) -> None:
    path = tmp_path / "limited.toml"
    path.write_text(LIMITED)
    machine = load_machine(path, sim_clock=clock)
    limit = machine.read_param(1320, 1) / PER_MM  # X: 100.000 mm
    async for cnc in _client(machine):
        await cnc.sim.cycle_start()
        samples = []
        for _ in range(MAX_SAMPLES):
            clock.advance(0.01)
            samples.append(await _x_mm(cnc))
            if (await cnc.read_status()).run != RUN_STRT:
                break
        alarms = await cnc.read_alarms()
        assert [(alarm_code(a.alm_type, a.alm_no), a.axis_no) for a in alarms] == [("OT0500", 1)]
        assert (await cnc.read_status()).alarm == 1
    assert all(x <= limit for x in samples)  # never past the limit, at any sample
    assert samples[-1] == limit  # stopped on it
    assert len(samples) > 10


async def test_a_stroke_limit_written_while_the_machine_runs_is_the_one_it_stops_at(
    clock: ManualClock,
) -> None:
    """1320 written through FOCAS applies at once (from the next block), as on a control: the
    move stops on the new limit with OT0500, not on the one the machine was built with."""
    machine = default_machine(sim_clock=clock, programs=("O2006\nG90 G0 X99.\nM30\n",))
    async for cnc in _client(machine):
        await cnc.sim.set_panel("MDI", pwe=True)
        await cnc.write_param(1320, 7000, axis=1)  # 7.000 mm
        await cnc.write_param(1420, 6000, axis=1)  # rapid 6 m/min
        await cnc.sim.set_panel("MEM", pwe=False)
        await cnc.select_program(2006)
        await cnc.sim.cycle_start()
        for _ in range(MAX_SAMPLES):
            clock.advance(0.05)
            if (await cnc.read_status()).run != RUN_STRT:
                break
        alarms = await cnc.read_alarms()
        assert [(alarm_code(a.alm_type, a.alm_no), a.axis_no) for a in alarms] == [("OT0500", 1)]
        assert await _x_mm(cnc) == 7.0
        assert clock.now() == pytest.approx(7 / 6000 * 60, abs=0.06)  # at the new rapid rate


async def test_a_running_programs_commons_and_locals_are_the_ones_focas_reads(
    clock: ManualClock,
) -> None:
    """cnc_rdmacro(100) reads the common the program set, and cnc_rdmacro(1) the local of
    the level running (the main program's); a value written by FOCAS before cycle start is the
    one the program reads; a reset vacates #1-#33 and #100-#199 (6001 CLV/CCV = 0)."""
    text = "O3004\n#101=#102+1\n#100=5\n#1=7\n#500=9\nG4 P60000\nM30\n"
    machine = default_machine(sim_clock=clock, programs=(text,))
    async for cnc in _client(machine):
        await cnc.select_program(3004)
        await cnc.write_macro(102, 41)
        await cnc.sim.cycle_start()
        clock.advance(1.0)
        assert (await cnc.read_status()).run == RUN_STRT
        values = [await cnc.read_macro(n) for n in (100, 101, 1, 500)]
        assert values == [5, 42, 7, 9]
        await cnc.sim.reset()
        assert [await cnc.read_macro(n) for n in (100, 101, 1, 500)] == [None, None, None, 9]


def test_a_program_search_sets_the_sequence_number_to_0(clock: ManualClock) -> None:
    """The sequence number of the program run before does not survive a program search: the
    control shows N00000 (read by cnc_rdseqnum and #4114)."""
    machine = default_machine(sim_clock=clock)
    machine.cycle_start()
    for _ in range(MAX_SAMPLES):
        clock.advance(0.5)
        if machine.motion.sequence:
            break
    assert machine.motion.sequence
    machine.reset()
    machine.select_program(machine.store_program("O2004\nG0 X1.\nM30\n"))
    assert machine.motion.program_main == 2004
    assert machine.motion.sequence == 0
