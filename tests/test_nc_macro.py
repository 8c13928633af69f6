"""Custom macro B: expressions, FANUC's vacant-variable rules, functions in degrees, the
variable interface, and random programs that never raise a Python exception."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from focas_net.sim.nc import (
    CycleState,
    Engine,
    ManualClock,
    MemoryVariables,
    NcSettings,
    VariableRefused,
)
from focas_net.sim.nc.alarms import AlarmRaised, ProgramError, ProgramErrorReason
from focas_net.sim.nc.macro import Cursor, Value, evaluate, parse_expression


def value_of(text: str, variables: dict[int, float | None] | None = None) -> Value:
    values = variables or {}
    cur = Cursor(text)
    expr = parse_expression(cur)
    assert cur.done(), text
    return evaluate(expr, lambda n: values.get(n))


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1+2*3", 1 + 2 * 3),
        ("[1+2]*3", (1 + 2) * 3),
        ("10/4", 10 / 4),
        ("-2*-3", 6.0),
        ("7MOD3", 7 % 3),
        ("-7MOD3", -1.0),  # the dividend's sign, as C
        ("12AND10", 12 & 10),
        ("12OR3", 12 | 3),
        ("12XOR10", 12 ^ 10),
        ("SIN[30]", math.sin(math.radians(30))),
        ("COS[60]", math.cos(math.radians(60))),
        ("TAN[45]", math.tan(math.radians(45))),
        ("ASIN[-0.5]", 330.0),  # 270..90
        ("ACOS[0.5]", 60.0),
        ("ATAN[1]/[-1]", 135.0),
        ("ATAN[-1]/[-1]", 225.0),  # 0..360
        ("SQRT[16]", 4.0),
        ("ABS[-2.5]", 2.5),
        ("ROUND[2.5]", 3.0),
        ("ROUND[-2.5]", -3.0),
        ("FIX[-1.7]", -1.0),
        ("FUP[-1.2]", -2.0),
        ("FUP[1.2]", 2.0),
        ("FUP[2]", 2.0),
        ("LN[EXP[2]]", 2.0),
        ("2GT1", 1.0),
        ("2LE1", 0.0),
    ],
)
def test_operators_and_functions(text: str, expected: float) -> None:
    assert value_of(text) == pytest.approx(expected)


def test_vacant_rules() -> None:
    assert value_of("#1") is None  # a bare vacant variable stays vacant
    assert value_of("#0") is None
    assert value_of("#1*5") == 0.0  # an operation reads it as 0
    assert value_of("#1+#1") == 0.0
    assert value_of("#1EQ#0") == 1.0  # EQ tells vacant from 0
    assert value_of("#1EQ0") == 0.0
    assert value_of("#1NE0") == 1.0
    assert value_of("#1GE0") == 1.0  # the other comparisons do not
    assert value_of("#1LT0.1") == 1.0
    assert value_of("#[#2+1]", {2: 4.0, 5: 9.0}) == 9.0


@pytest.mark.parametrize(
    ("text", "alarm"),
    [("1/0", 112), ("1MOD0", 112), ("SQRT[-1]", 119), ("LN[0]", 119), ("ASIN[2]", 119)],
)
def test_evaluation_alarms(text: str, alarm: int) -> None:
    with pytest.raises(AlarmRaised) as info:
        value_of(text)
    assert info.value.number == alarm


def test_common_variables_go_through_the_interface() -> None:
    writes: list[tuple[int, float | None]] = []

    class Recorder(MemoryVariables):
        def write_variable(self, number: int, value: float | None) -> None:
            writes.append((number, value))
            super().write_variable(number, value)

    clock = ManualClock()
    variables = Recorder()
    engine = Engine(clock, variables=variables)
    engine.store.store("O1\n#500 = 2.5\n#501 = #500 * 2\n#502 = #0\n#100 = 1\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    assert engine.state is CycleState.RESET
    # #100 is offered to the interface too (a machine holds it); this one refuses it (PS0115)
    # and the interpreter keeps it itself
    assert writes == [(500, 2.5), (501, 5.0), (502, None), (100, 1.0)]
    with pytest.raises(VariableRefused):
        variables.read_variable(1000)


def test_a_system_variable_the_machine_refuses_is_ps0115() -> None:
    engine = Engine(ManualClock())
    engine.store.store("O1\n#1 = #1234\nM30\n")
    engine.store.select(1)
    engine.cycle_start()
    assert engine.alarm is not None and engine.alarm.code == "PS0115"


_WORDS = st.sampled_from(
    ["G0", "G1", "G2", "G3", "G4", "G17", "G18", "G19", "G20", "G21", "G28", "G43", "G49",
     "G53", "G54", "G59", "G90", "G91", "G98", "G12", "G65", "X", "Y", "Z", "I", "J", "K",
     "R", "F", "S", "T", "M3", "M5", "M6", "M8", "M98", "M99", "M0", "M1", "M30", "P", "L",
     "H", "A", "Q", "#", "[", "]", "=", "GOTO", "IF", "WHILE", "DO", "END", "THEN", "EQ",
     "/", "*", "+", "-", "SIN", "(", ")", ";", ".", "N", "$"]
)  # fmt: skip
_NUMBERS = st.one_of(
    st.integers(-100000, 100000).map(str),
    st.floats(-1000, 1000, allow_nan=False).map(lambda v: f"{v:.3f}"),
    st.just(""),
)
_BLOCKS = st.lists(
    st.lists(st.tuples(_WORDS, _NUMBERS).map("".join), min_size=0, max_size=6).map(" ".join),
    min_size=1,
    max_size=12,
)


@settings(max_examples=100, deadline=None)
@given(_BLOCKS, st.lists(st.floats(0, 3), min_size=1, max_size=8))
def test_random_programs_never_raise_a_python_exception(
    blocks: list[str], steps: list[float]
) -> None:
    clock = ManualClock()
    limits = ((-500.0, 500.0), (-500.0, 500.0), None)
    engine = Engine(clock, NcSettings(stroke_limits=limits, zero_time_blocks=50))
    engine.store.store("O2\nG91 G1 X1. F100\nM99\n")
    try:  # malformed blocks are kept; a comment not closed in its line is refused
        engine.store.store("O1\n" + "\n".join(blocks) + "\n")
    except ProgramError as exc:
        assert exc.reason is ProgramErrorReason.FORMAT and "has no ')'" in str(exc)
        engine.store.store("O1\n" + ")\n".join(blocks) + ")\n")  # each line closed
    engine.store.select(1)
    engine.cycle_start()
    for dt in steps:
        clock.advance(dt)
        engine.machine_position()
        engine.distance_to_go()
        assert engine.actual_feed >= 0
        engine.modal_groups()
        if engine.state is not CycleState.START:
            engine.reset()
            engine.cycle_start()
    assert engine.state in set(CycleState)
