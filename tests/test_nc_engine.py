"""The execution engine with a hand-stepped clock: motion in time, holds, resets, parts,
subprograms, offsets, alarms and soft limits."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.sim.nc import (
    AlarmKind,
    ArcMove,
    CycleState,
    Engine,
    ManualClock,
    MotionKind,
    NcAlarm,
    NcSettings,
    NcStateError,
    ProgramError,
    ProgramErrorReason,
    RealTimeClock,
)


def state_of(engine: Engine) -> CycleState:
    """The state read now (a call, so that no earlier check narrows it)."""
    return engine.state


def started(text: str, *subprograms: str, **settings: object) -> tuple[Engine, ManualClock]:
    clock = ManualClock()
    engine = Engine(clock, NcSettings(**settings))  # type: ignore[arg-type]
    main = engine.store.store(text)
    for sub in subprograms:
        engine.store.store(sub)
    engine.store.select(main.number)
    engine.cycle_start()
    return engine, clock


def run_out(engine: Engine, clock: ManualClock, step: float = 0.5, limit: int = 10_000) -> None:
    """Step until the engine leaves START (bounded)."""
    for _ in range(limit):
        if state_of(engine) is not CycleState.START:
            return
        clock.advance(step)
    raise AssertionError("the program did not stop")


def test_a_linear_move_takes_its_time_and_passes_its_midpoint() -> None:
    engine, clock = started("O1\nG90 G21 G1 X60. F1200\nM30\n")
    clock.set(1.5)
    assert engine.machine_position()[0] == pytest.approx(30.0)
    assert engine.actual_feed == pytest.approx(1200.0)
    assert engine.motion is MotionKind.MOTION
    assert engine.distance_to_go()[0] == pytest.approx(30.0)
    clock.set(2.999)
    assert state_of(engine) is CycleState.START
    clock.set(3.0)
    assert engine.machine_position()[0] == pytest.approx(60.0)
    assert engine.cutting_time == pytest.approx(3.0)
    assert state_of(engine) is CycleState.RESET


def test_rapid_moves_do_not_count_as_cutting_and_follow_the_rapid_rate() -> None:
    engine, clock = started("O1\nG0 X100.\nM30\n", rapid_rates=(6000.0, 6000.0, 6000.0))
    clock.set(0.5)
    assert engine.machine_position()[0] == pytest.approx(50.0)
    engine.set_rapid_override(50)
    clock.set(1.0)
    assert engine.machine_position()[0] == pytest.approx(75.0)
    assert engine.actual_feed == pytest.approx(3000.0)
    clock.set(1.5)
    assert state_of(engine) is CycleState.RESET and engine.cutting_time == 0.0
    assert engine.operating_time == pytest.approx(1.5)


def test_feed_override_scales_the_feed() -> None:
    engine, clock = started("O1\nG1 X60. F1200\nM30\n")
    engine.set_feed_override(50)
    clock.set(2.0)
    assert engine.machine_position()[0] == pytest.approx(20.0)
    assert engine.actual_feed == pytest.approx(600.0)


def test_no_decimal_point_means_least_input_increments() -> None:
    engine, clock = started("O1\nG1 X60000 F1200\nM30\n")
    clock.set(1.5)
    assert engine.machine_position()[0] == pytest.approx(30.0)


def _radius_samples(
    engine: Engine, clock: ManualClock, a: int, b: int, center: tuple[float, float]
) -> list[float]:
    radii = []
    for _ in range(200):
        if state_of(engine) is not CycleState.START:
            break
        p = engine.machine_position()
        radii.append(math.hypot(p[a] - center[0], p[b] - center[1]))
        clock.advance(0.05)
    return radii


@pytest.mark.parametrize(
    ("plane", "a", "b", "words"),
    [
        ("G17", 0, 1, ("X", "Y", "I", "J")),
        ("G18", 2, 0, ("Z", "X", "K", "I")),
        ("G19", 1, 2, ("Y", "Z", "J", "K")),
    ],
)
@pytest.mark.parametrize("code", ["G2", "G3"])
@pytest.mark.parametrize("form", ["center", "radius", "negative radius"])
def test_an_arc_keeps_its_radius_and_reaches_its_end(
    plane: str, a: int, b: int, words: tuple[str, str, str, str], code: str, form: str
) -> None:
    wa, wb, ca, cb = words
    # from (10, 0) of the plane to (0, 10), radius 10 around the origin of the plane
    if form == "center":
        arc = f"{code} {wa}0 {wb}10. {ca}-10. {cb}0 F600"
    else:
        r = 10.0 if code == "G3" else -10.0  # around the origin: 90 or 270 degrees
        r = -r if form == "negative radius" else r
        arc = f"{code} {wa}0 {wb}10. R{r} F600"
    program = f"O1\n{plane} G90 G0 {wa}10. {wb}0\n{arc}\nM30\n"
    engine, clock = started(program)
    # move through the positioning first
    for _ in range(100):
        engine.advance()
        if isinstance(engine._action, ArcMove):
            break
        clock.advance(0.01)
    # the long way (negative R) goes around the other center of the two
    center = (10.0, 10.0) if form == "negative radius" else (0.0, 0.0)
    radii = _radius_samples(engine, clock, a, b, center)
    assert len(radii) > 10
    assert all(r == pytest.approx(10.0, abs=1e-6) for r in radii)
    end = engine.machine_position()
    assert (end[a], end[b]) == pytest.approx((0.0, 10.0), abs=1e-9)
    assert engine.alarm is None


def test_arc_direction_counter_clockwise_goes_the_short_way() -> None:
    engine, clock = started("O1\nG0 X10.\nG3 X0 Y10. I-10. F600\nM30\n")
    clock.set(0.1)
    clock.advance(1.0)  # 1 s of a quarter circle of length 15.7 at 10 mm/s
    x, y, _ = engine.machine_position()
    assert x > 0 and y > 0  # the first quadrant, counter-clockwise from (10, 0)


def test_a_full_circle_with_center_words() -> None:
    engine, clock = started("O1\nG0 X10.\nG2 X10. Y0 I-10. F600\nM30\n")
    run_out(engine, clock, 0.25)
    assert engine.cutting_time == pytest.approx(2 * math.pi * 10 / 10.0)


def test_feed_hold_stops_the_axes_and_cycle_start_resumes() -> None:
    engine, clock = started("O1\nG1 X60. F1200\nM30\n")
    clock.set(1.0)
    engine.feed_hold()
    held = engine.machine_position()
    clock.set(5.0)
    assert state_of(engine) is CycleState.HOLD
    assert engine.machine_position() == held
    assert engine.actual_feed == 0.0
    assert engine.cutting_time == pytest.approx(1.0)
    engine.cycle_start()
    clock.set(6.0)
    assert engine.machine_position()[0] == pytest.approx(40.0)
    clock.set(7.0)
    assert state_of(engine) is CycleState.RESET
    assert engine.cutting_time == pytest.approx(3.0)


def test_reset_mid_program_stops_and_rewinds() -> None:
    engine, clock = started("O1\nN10 G1 X60. F1200\nN20 G1 X0\nM30\n")
    clock.set(1.0)
    assert engine.sequence_number == 10
    engine.reset()
    stopped = engine.machine_position()
    clock.set(10.0)
    assert state_of(engine) is CycleState.RESET
    assert engine.machine_position() == stopped
    assert engine.distance_to_go() == (0.0, 0.0, 0.0)
    engine.cycle_start()  # from the head again: N10 moves to X60 from where it stopped
    assert engine.sequence_number == 10
    clock.advance(2.0)
    assert engine.machine_position()[0] == pytest.approx(60.0)


def test_m30_adds_one_part_and_rewinds() -> None:
    engine, clock = started("O1\nG1 X1. F600\nG1 X0\nM30\n")
    run_out(engine, clock, 0.1)
    assert (engine.parts_count, engine.parts_total) == (1, 1)
    assert state_of(engine) is CycleState.RESET
    kinds = [e.kind for e in engine.take_events()]
    assert kinds == ["part", "end"]
    engine.cycle_start()
    run_out(engine, clock, 0.1)
    assert engine.parts_count == 2


def test_m0_stops_and_cycle_start_continues() -> None:
    engine, clock = started("O1\nG1 X1. F600\nM0\nG1 X2.\nM30\n")
    clock.set(1.0)
    assert state_of(engine) is CycleState.STOP
    clock.set(5.0)
    assert engine.machine_position()[0] == pytest.approx(1.0)
    engine.cycle_start()
    clock.advance(1.0)
    assert engine.machine_position()[0] == pytest.approx(2.0)


def test_m1_stops_only_with_the_optional_stop_switch() -> None:
    engine, clock = started("O1\nM1\nG1 X10. F600\nM30\n")
    clock.set(0.2)
    assert state_of(engine) is CycleState.START
    engine.reset()
    engine.set_optional_stop(True)
    engine.cycle_start()
    assert state_of(engine) is CycleState.STOP


def test_single_block_stops_after_each_nc_block() -> None:
    engine, clock = started("O1\nG1 X1. F600\n#1 = 2\nG1 X2.\nM30\n")
    engine.set_single_block(True)
    clock.set(0.5)
    assert state_of(engine) is CycleState.STOP
    engine.cycle_start()
    clock.advance(0.5)
    assert state_of(engine) is CycleState.STOP
    assert engine.machine_position()[0] == pytest.approx(2.0)


def test_dwell_in_ms_and_seconds() -> None:
    engine, clock = started("O1\nG4 P1500\nG4 X2.\nG4 X500\nM30\n")
    clock.set(1.0)
    assert engine.motion is MotionKind.DWELL
    clock.set(3.9)
    assert state_of(engine) is CycleState.START
    clock.set(4.0)
    assert state_of(engine) is CycleState.RESET
    assert engine.operating_time == pytest.approx(4.0)


def test_a_macro_loop_runs_its_body_n_times() -> None:
    n = 7
    text = f"O1\n#1 = 0\n#2 = {n}\nWHILE [#1 LT #2] DO1\nG91 G1 X1. F600\n#1 = #1 + 1\nEND1\nM30\n"
    engine, clock = started(text)
    run_out(engine, clock, 0.25)
    assert engine.machine_position()[0] == pytest.approx(float(n))
    assert engine.cutting_time == pytest.approx(n * 0.1)


def test_goto_and_if_branches() -> None:
    text = (
        "O1\n#1 = 3\nN5 IF [#1 EQ 0] GOTO 20\nG91 G1 X1. F600\n#1 = #1 - 1\nGOTO 5\n"
        "N20 IF [#1 EQ 0] THEN #3 = 5\nG90 G1 Y#3\nM30\n"
    )
    engine, clock = started(text)
    run_out(engine, clock, 0.25)
    assert engine.machine_position()[:2] == pytest.approx((3.0, 5.0))


def test_vacant_variable_leaves_its_address_out() -> None:
    engine, clock = started("O1\nG1 X1. Y#1 F600\nM30\n")
    run_out(engine, clock, 0.25)
    assert engine.machine_position()[:2] == pytest.approx((1.0, 0.0))


def test_m98_m99_nesting_and_repeats() -> None:
    main = "O1\nM98 P2 L2\nM98 P30003\nM30\n"
    sub2 = "O2\nG91 G1 X1. F600\nM98 P3\nM99\n"
    sub3 = "O3\nG91 G1 Y1. F600\nM99\n"
    engine, clock = started(main, sub2, sub3)
    seen = set()
    for _ in range(200):
        if state_of(engine) is not CycleState.START:
            break
        seen.add(engine.program_number)
        clock.advance(0.05)
    assert seen >= {2, 3}
    assert engine.machine_position()[:2] == pytest.approx((2.0, 5.0))
    assert engine.alarm is None


def test_m99_with_p_returns_to_a_sequence_number() -> None:
    main = "O1\nM98 P2\nG90 G1 X5. F600\nN50 G90 G1 Y5. F600\nM30\n"
    engine, clock = started(main, "O2\nM99 P50\n")
    run_out(engine, clock, 0.25)
    assert engine.machine_position()[:2] == pytest.approx((0.0, 5.0))


def test_subprogram_nesting_beyond_the_limit_is_ps0077() -> None:
    engine, clock = started("O1\nM98 P2\nM30\n", "O2\nM98 P2\nM99\n")
    clock.advance(1.0)
    assert engine.alarm is not None and engine.alarm.code == "PS0077"


def test_g91_and_g90() -> None:
    engine, clock = started("O1\nG91 G1 X10. F600\nX10.\nG90 X5.\nM30\n")
    clock.set(1.0)
    assert engine.machine_position()[0] == pytest.approx(10.0)
    clock.set(2.0)
    assert engine.machine_position()[0] == pytest.approx(20.0)
    run_out(engine, clock)
    assert engine.machine_position()[0] == pytest.approx(5.0)


def test_work_offsets_g54_g55() -> None:
    clock = ManualClock()
    offsets = [[0.0] * 3 for _ in range(7)]
    offsets[1] = [100.0, 50.0, 0.0]  # G54
    offsets[2] = [-10.0, 0.0, 0.0]  # G55
    engine = Engine(clock, NcSettings(rapid_rates=(6000.0,) * 3), work_offsets=offsets)
    engine.store.store("O1\nG90 G54 G0 X10. Y0\nG55 G0 X10.\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    clock.set(1.0)  # 100 of 110 mm at 100 mm/s, Y there after 0.5 s
    assert engine.machine_position()[:2] == pytest.approx((100.0, 50.0))
    assert engine.absolute_position()[:2] == pytest.approx((0.0, 0.0))
    run_out(engine, clock)
    assert engine.machine_position()[0] == pytest.approx(0.0)


def test_work_offset_variables_read_and_write() -> None:
    engine, clock = started("O1\n#5221 = 20.\n#1 = #5221\nG90 G54 G0 X#1\nM30\n")
    run_out(engine, clock)
    assert engine.work_offsets[1][0] == 20.0
    assert engine.machine_position()[0] == pytest.approx(40.0)


def test_g20_reads_inches() -> None:
    engine, clock = started("O1\nG20 G90 G1 X1. F10.\nM30\n")
    clock.set(3.0)
    assert engine.machine_position()[0] == pytest.approx(12.7)
    run_out(engine, clock)
    assert engine.machine_position()[0] == pytest.approx(25.4)
    engine2, clock2 = started("O1\nG20 G0 X10000\nM30\n")
    run_out(engine2, clock2)
    assert engine2.machine_position()[0] == pytest.approx(25.4)


def test_g28_goes_through_the_intermediate_point_to_the_reference() -> None:
    engine, clock = started(
        "O1\nG90 G0 X50. Y50.\nG91 G28 X0 Y-20.\nM30\n",
        reference=(-5.0, -5.0, 0.0),
        rapid_rates=(6000.0, 6000.0, 6000.0),
    )
    ys = []
    for _ in range(200):
        if state_of(engine) is not CycleState.START:
            break
        ys.append(engine.machine_position()[1])
        clock.advance(0.02)
    assert min(ys) == pytest.approx(-5.0) and 30.0 in [pytest.approx(y, abs=0.2) for y in ys]
    assert engine.machine_position()[:2] == pytest.approx((-5.0, -5.0))


def test_g53_moves_in_machine_coordinates() -> None:
    clock = ManualClock()
    offsets = [[0.0] * 3 for _ in range(7)]
    offsets[1] = [100.0, 0.0, 0.0]
    engine = Engine(clock, work_offsets=offsets)
    engine.store.store("O1\nG54 G90 G0 X10.\nG53 X3.\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    run_out(engine, clock)
    assert engine.machine_position()[0] == pytest.approx(3.0)


def test_tool_change_and_spindle() -> None:
    engine, clock = started("O1\nT5 M6\nS1000 M3\nG4 P1000\nM5\nM30\n", tool_change_time=2.0)
    clock.set(1.0)
    assert engine.actual_spindle_speed == 0.0
    clock.set(2.6)
    assert engine.actual_spindle_speed == 1000.0
    engine.set_spindle_override(50)
    assert engine.actual_spindle_speed == 500.0
    run_out(engine, clock, 0.25)
    assert engine.actual_spindle_speed == 0.0
    assert engine.interpreter.tool == 5
    assert [e.value for e in engine.take_events() if e.kind == "tool"] == [5]


@pytest.mark.parametrize(
    ("block", "code"),
    [
        ("G1 X10.", "PS0011"),
        ("G5 X1.", "PS0010"),
        ("G41 X1.", "PS0010"),
        ("G2 X10. Y10. R2. F100", "PS0020"),
        ("G2 X10. I3. F100", "PS0020"),
        ("G2 X10. F100", "PS0022"),
        ("M98 P9999", "PS0078"),
        ("M98", "PS0076"),
        ("#1 = 1 / 0", "PS0112"),
        ("#1 = SQRT[-1]", "PS0119"),
        ("#1 = [1 + 2", "PS0114"),
        ("#1 = #0 + #[-1]", "PS0115"),
        ("#4001 = 1", "PS0116"),
        ("#3000 = 12 (TOOL BROKEN)", "MC3012"),
        ("GOTO 777", "PS0128"),
        ("X1.2.3", "PS0007"),
        ("X1. -5", "PS0004"),
        ("X1. $", "PS0009"),
        ("A10.", "PS0009"),
        ("G01 X", "PS0005"),
        ("X1234567890", "PS0003"),
        ("G1 X1. #1 = 2", "PS0127"),
        ("END1", "PS0124"),
        ("WHILE [1] DO4", "PS0126"),
        ("T-1", "PS0006"),
        ("G4 P1.5", "PS0007"),
        ("G1 H999 F100", "PS0030"),
        ("G17 G2 X1. K1. F100", "PS0021"),
        ("#1 = [[[[[[1]]]]]]", "PS0118"),
    ],
)
def test_a_program_error_raises_its_alarm_with_the_sequence_number_and_stops(
    block: str, code: str
) -> None:
    engine, clock = started(f"O12\nN10 G90\nN20 {block}\nN30 G1 X50. F100\nM30\n")
    clock.advance(1.0)
    alarm = engine.alarm
    assert alarm is not None, block
    assert alarm.code == code
    assert (alarm.program, alarm.sequence) == (12, 20)
    assert state_of(engine) is CycleState.STOP
    assert engine.machine_position()[0] < 50.0
    with pytest.raises(NcStateError, match=code):
        engine.cycle_start()
    assert [e.alarm for e in engine.take_events()] == [alarm]
    engine.reset()
    assert engine.alarm is None and state_of(engine) is CycleState.RESET


def test_the_macro_alarm_carries_its_message() -> None:
    engine, _ = started("O1\nN5 #3000 = 1 (SPINDLE NOT READY)\nM30\n")
    assert engine.alarm is not None
    assert (engine.alarm.kind, engine.alarm.number) == (AlarmKind.MC, 3001)
    assert engine.alarm.message == "SPINDLE NOT READY"


@pytest.mark.parametrize(
    ("move", "axis", "side", "code"),
    [
        ("G1 X150. F600", 0, 100.0, "OT0500"),
        ("G1 X-150. F600", 0, -100.0, "OT0501"),
        ("G0 Y80.", 1, 50.0, "OT0500"),
        ("G2 X0 Y-20. J-10. F600", 1, -15.0, "OT0501"),
    ],
)
def test_a_move_past_the_soft_limit_raises_overtravel_before_the_axis_leaves(
    move: str, axis: int, side: float, code: str
) -> None:
    limits = ((-100.0, 100.0), (-15.0, 50.0), None)
    engine, clock = started(f"O1\nN7 {move}\nM30\n", stroke_limits=limits)
    for _ in range(2000):
        if state_of(engine) is not CycleState.START:
            break
        position = engine.machine_position()
        for i, limit in enumerate(limits):
            if limit is not None:
                assert limit[0] - 1e-9 <= position[i] <= limit[1] + 1e-9
        clock.advance(0.05)
    alarm = engine.alarm
    assert alarm is not None and alarm.code == code and alarm.axis == axis + 1
    assert alarm.sequence == 7
    assert engine.machine_position()[axis] == pytest.approx(side, abs=1e-6)


def test_cycle_start_without_a_main_program_is_refused() -> None:
    engine = Engine(ManualClock())
    with pytest.raises(NcStateError, match="no main program"):
        engine.cycle_start()


def test_a_program_in_use_cannot_be_deleted_or_replaced() -> None:
    engine, clock = started("O1\nG1 X60. F1200\nM30\n")
    clock.set(1.0)
    with pytest.raises(ProgramError) as info:
        engine.store.delete(1)
    assert info.value.reason is ProgramErrorReason.IN_USE
    with pytest.raises(ProgramError):
        engine.store.store("O1\nM30\n", replace=True)
    run_out(engine, clock)
    engine.store.delete(1)
    assert 1 not in engine.store


def test_modal_groups_as_system_variables() -> None:
    engine, clock = started("O1\nG91 G18 G1 X1. F600\nM0\nM30\n")
    clock.set(1.0)
    groups = engine.modal_groups()
    assert (groups[1], groups[2], groups[3], groups[6], groups[14]) == (1.0, 18.0, 91.0, 21.0, 54.0)
    assert groups[30] is None


def test_an_endless_macro_loop_does_not_hang_a_read() -> None:
    engine, clock = started("O1\nWHILE [1 EQ 1] DO1\n#1 = #1 + 1\nEND1\nM30\n")
    clock.advance(1.0)
    assert state_of(engine) is CycleState.START
    clock.advance(1.0)
    assert engine.interpreter.locals[1] is not None


def test_a_loop_without_motion_waits_for_no_fin() -> None:
    """The time a block-only loop is given is the engine's own, no M/S/T/B function: ODBST
    ``mstb`` stays 0 (FIN is for an M, S, T or B function alone)."""
    engine, clock = started("O1\nWHILE [1 EQ 1] DO1\n#1 = #1 + 1\nEND1\nM30\n")
    for _ in range(20):
        clock.advance(0.0005)
        assert engine.flags() == (CycleState.START, MotionKind.NONE, False)
        assert not engine.waiting
    m_code, clock = started("O1\nM8\nM30\n", m_function_time=1.0)
    clock.advance(0.5)
    assert m_code.flags() == (CycleState.START, MotionKind.NONE, True) and m_code.waiting


def test_idle_engines_are_read_without_stepping() -> None:
    clock = ManualClock()
    engines = [Engine(clock) for _ in range(1000)]
    clock.advance(10.0)
    assert all(e.state is CycleState.RESET for e in engines)
    assert all(e.interpreter.program is None for e in engines)


def test_settings_for_other_axes_and_their_checks() -> None:
    lathe = NcSettings.for_axes(("X", "Z"), stroke_limits=((-10.0, 200.0), None))
    assert lathe.rapid_rates == (24000.0, 24000.0)
    clock = ManualClock()
    engine = Engine(clock, lathe)
    engine.store.store("O1\nG18 G0 X20. Z5.\nG2 X20. Z-5. R5. F300\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    run_out(engine, clock, 0.1)
    assert engine.alarm is None
    assert engine.machine_position() == pytest.approx((20.0, -5.0))
    with pytest.raises(ValueError, match="rapid_rates has 3 entries for 2 axes"):
        NcSettings(axes=("X", "Z"))
    with pytest.raises(ValueError, match="stroke limit"):
        NcSettings(stroke_limits=((5.0, -5.0), None, None))


def test_the_real_time_clock_runs_at_its_speed() -> None:
    wall = [100.0]
    clock = RealTimeClock(speed=10.0, source=lambda: wall[0])
    wall[0] += 1.5
    assert clock.now() == pytest.approx(15.0)
    clock.set_speed(2.0)
    wall[0] += 1.0
    assert clock.speed == 2.0
    assert clock.now() == pytest.approx(17.0)
    with pytest.raises(ValueError, match="positive"):
        RealTimeClock(speed=0)


def test_the_manual_clock_never_goes_back() -> None:
    clock = ManualClock(5.0)
    assert clock.advance(1.0) == 6.0
    with pytest.raises(ValueError, match="cannot go back"):
        clock.set(1.0)
    with pytest.raises(ValueError, match="finite"):
        clock.advance(-1.0)


def test_overrides_are_checked() -> None:
    engine = Engine(ManualClock())
    with pytest.raises(ValueError, match=r"feed override is 0\.\.254 %, got 300"):
        engine.set_feed_override(300)
    with pytest.raises(ValueError, match="rapid override"):
        engine.set_rapid_override(-1)


def test_block_delete_skips_marked_blocks_only_with_the_switch() -> None:
    for switch, expected in ((False, 2.0), (True, 1.0)):
        engine = Engine(ManualClock())
        engine.store.store("O1\nG91 G1 X1. F600\n/X1.\nM30\n")
        engine.store.select(1)
        engine.set_block_delete(switch)
        engine.cycle_start()
        run_out(engine, engine.clock, 0.1)  # type: ignore[arg-type]
        assert engine.machine_position()[0] == pytest.approx(expected)


def test_m99_in_a_main_program_runs_it_again() -> None:
    engine, clock = started("O1\nG91 G1 X1. F600\nM99\n")
    clock.set(0.35)  # three passes of 0.1 s each are done
    assert engine.machine_position()[0] == pytest.approx(3.5)
    assert engine.state is CycleState.START and engine.parts_count == 0


def test_tool_length_compensation_moves_z_and_keeps_the_program_position() -> None:
    clock = ManualClock()
    engine = Engine(clock, tool_offsets={1: 100.0})
    engine.store.store("O1\nG90 G0 Z50.\nG43 H1\nM0\nG0 Z10.\nM0\nG49\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    seen = []
    for _ in range(3):
        run_out(engine, clock, 0.05)
        seen.append((engine.machine_position()[2], engine.absolute_position()[2]))
        engine.cycle_start()
    expected = [(150.0, 50.0), (110.0, 10.0), (10.0, 10.0)]
    assert seen == [pytest.approx(e) for e in expected]


def test_an_alarm_from_the_machine_stops_the_cycle() -> None:
    engine, clock = started("O1\nG1 X60. F1200\nM30\n")
    clock.set(1.0)
    alarm = NcAlarm(AlarmKind.PS, 1000, "EMERGENCY STOP")
    engine.alarm_stop(alarm)
    clock.set(2.0)
    assert engine.alarm == alarm and engine.state is CycleState.STOP
    assert engine.machine_position()[0] == pytest.approx(20.0)
    with pytest.raises(NcStateError, match="PS1000"):
        engine.cycle_start()


@settings(max_examples=40, deadline=None)
@given(
    st.sampled_from([("G17", 0, 1, "XYIJ"), ("G18", 2, 0, "ZXKI"), ("G19", 1, 2, "YZJK")]),
    st.sampled_from(["G2", "G3"]),
    st.floats(1.0, 50.0),
    st.floats(0.0, 359.0),
    st.floats(0.0, 359.0),
)
def test_random_arcs_keep_their_radius_and_reach_their_end(
    plane: tuple[str, int, int, str], code: str, radius: float, start: float, end: float
) -> None:
    name, a, b, letters = plane
    wa, wb, ca, cb = tuple(letters)
    sa, sb = radius * math.cos(math.radians(start)), radius * math.sin(math.radians(start))
    ea, eb = radius * math.cos(math.radians(end)), radius * math.sin(math.radians(end))
    text = (
        f"O1\n{name} G90 G0 {wa}{sa:.4f} {wb}{sb:.4f}\n"
        f"{code} {wa}{ea:.4f} {wb}{eb:.4f} {ca}{-sa:.4f} {cb}{-sb:.4f} F3000\nM30\n"
    )
    engine, clock = started(text)
    for _ in range(2000):
        if engine.state is not CycleState.START:
            break
        p = engine.machine_position()
        if isinstance(engine._action, ArcMove):
            assert math.hypot(p[a], p[b]) == pytest.approx(radius, abs=1e-3)
        clock.advance(0.01)
    assert engine.alarm is None
    p = engine.machine_position()
    assert (p[a], p[b]) == pytest.approx((round(ea, 4), round(eb, 4)), abs=1e-9)
