"""A lathe's own codes (FANUC's T series, G code system A): feed per minute and per
revolution (G98/G99), constant surface speed (G96/G97), the spindle speed limit and the
coordinate system setting of G50, as the machine's spindle speed, feed, positions and modal
reads give them; and the codes it still refuses (G90, G91, G94)."""

from __future__ import annotations

import pytest
from support import alarm_words, started_engine

from focas_net.sim.nc import CycleState, Engine, ManualClock, NcSettings
from focas_net.sim.nc.modal import modal_state

_LATHE = NcSettings.for_axes(("X", "Z"), lathe=True)
#: a lathe whose rapids take seconds (6 m/min)
_SLOW = NcSettings.for_axes(("X", "Z"), lathe=True, rapid_rates=(600.0, 600.0))


def _engine(text: str, settings: NcSettings = _LATHE) -> tuple[Engine, ManualClock]:
    return started_engine(text, settings)


def test_g99_feeds_f_per_revolution_of_the_spindle() -> None:
    """`G99 F0.2` at 500 min^-1 is 100 mm/min: 10 mm take 6 s."""
    engine, clock = _engine("O1\nG99 G97 S500 M3\nG1 W-10. F0.2\nM30\n")
    clock.advance(3.5)
    assert (engine.state, alarm_words(engine)) == (CycleState.START, None)
    assert engine.axis_speeds()[1] == pytest.approx(100.0)
    assert engine.modal_groups()[10] == 99
    clock.advance(3.5)
    assert (engine.state, alarm_words(engine)) == (CycleState.RESET, None)
    assert engine.absolute_position() == pytest.approx((0.0, -10.0))


def test_g99_follows_the_spindle_override() -> None:
    engine, clock = _engine("O1\nG99 S500 M3\nG1 W-10. F0.2\nM30\n")
    engine.set_spindle_override(50)
    clock.advance(1.0)
    assert engine.axis_speeds()[1] == pytest.approx(50.0)


def test_g99_with_the_spindle_stopped_raises_ps0011() -> None:
    engine, clock = _engine("O1\nG99\nG1 W-10. F0.2\nM30\n")
    clock.advance(1)
    assert (alarm_words(engine) or "").startswith("PS0011 G99 F0.2: feed per revolution")


def test_g98_after_g99_feeds_per_minute_again() -> None:
    engine, clock = _engine("O1\nG99 S500 M3\nG98 G1 W-10. F600\nM30\n")
    clock.advance(1.0)
    assert engine.axis_speeds()[1] == pytest.approx(600.0)
    assert engine.modal_groups()[10] == 98


def test_g96_turns_the_spindle_for_the_surface_speed_at_x() -> None:
    """`G96 S157` at X50. (a diameter): 1000 x 157 / (pi x 50) = 999.5 min^-1."""
    engine, clock = _engine("O1\nG0 X50. Z0\nG96 S157 M3\nG4 P10000\nM30\n")
    clock.advance(2)
    assert engine.actual_spindle_speed == pytest.approx(999.49, abs=0.01)
    assert engine.modal_groups()[13] == 96


def test_g96_follows_x_as_the_tool_moves() -> None:
    engine, clock = _engine("O1\nG0 X100. Z0\nG96 S157 M3\nG1 X50. F300\nM30\n")
    clock.advance(1)
    before = engine.actual_spindle_speed
    clock.advance(4)
    assert engine.actual_spindle_speed > before


def test_g50_s_clamps_the_spindle_speed_of_g96() -> None:
    engine, clock = _engine("O1\nG50 S800\nG0 X10. Z0\nG96 S157 M3\nG4 P10000\nM30\n")
    clock.advance(2)
    assert alarm_words(engine) is None
    assert engine.actual_spindle_speed == pytest.approx(800.0)


def test_g50_s_leaves_the_commanded_speed_and_g97_reads_s_as_rpm() -> None:
    engine, clock = _engine("O1\nG97 S500 M3\nG50 S2000\nG4 P10000\nM30\n")
    clock.advance(2)
    assert alarm_words(engine) is None
    assert engine.actual_spindle_speed == pytest.approx(500.0)
    engine, clock = _engine("O1\nG97 S500 M3\nG50 S300\nG4 P10000\nM30\n")
    clock.advance(2)
    assert engine.actual_spindle_speed == pytest.approx(300.0)


def test_g50_x_z_sets_the_coordinate_system_where_the_tool_is() -> None:
    engine, clock = _engine("O1\nG0 X20. Z10.\nG50 X100. Z50.\nG4 P10000\nM30\n")
    clock.advance(2)
    assert alarm_words(engine) is None
    assert engine.absolute_position() == pytest.approx((100.0, 50.0))
    engine, clock = _engine("O1\nG0 X20. Z10.\nG50 X100. Z50.\nG0 X80. W-5.\nM30\n")
    clock.advance(5)
    assert alarm_words(engine) is None
    assert engine.absolute_position() == pytest.approx((80.0, 45.0))


@pytest.mark.parametrize(
    ("block", "words"),
    [
        ("G90 X50. Z-20. F100", "PS0010 G90: on a lathe the outer and inner diameter cutting"),
        ("G91 G0 X1.", "PS0010 G91: no code of a lathe's G code system A"),
        ("G94 X50. Z-2. F100", "PS0010 G94: on a lathe the end face turning cycle"),
    ],
)
def test_a_lathe_still_refuses_its_cutting_cycles_and_g91(block: str, words: str) -> None:
    engine, _ = _engine(f"O1\n{block}\nM30\n")
    assert (alarm_words(engine) or "").startswith(words)


def test_a_machining_centre_refuses_g96() -> None:
    engine, _ = _engine("O1\nG96 S100\nM30\n", NcSettings())
    assert (alarm_words(engine) or "").startswith("PS0010 G96")


def test_the_modal_s_stays_the_commanded_s_after_g50_s() -> None:
    engine, clock = _engine("O1\nG97 S500 M3\nG50 S2000\nG4 P10000\nM30\n")
    clock.advance(2)
    engine.advance()
    assert modal_state(engine.interpreter).address("S").value == 500.0


def test_g96_in_a_rapid_block_turns_for_the_block_s_end_point() -> None:
    """FANUC computes the surface speed of a G0 block at its end point, not as X passes."""
    engine, clock = _engine("O1\nG50 X100. Z0\nG96 S157 M3\nG0 X50.\nM30\n", _SLOW)
    clock.advance(2.0)
    assert 50.0 < engine.absolute_position()[0] < 100.0
    assert engine.actual_spindle_speed == pytest.approx(999.49, abs=0.01)
