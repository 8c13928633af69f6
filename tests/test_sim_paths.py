"""Machines of several paths: each path its own axes, programs, engine, status, parts and
alarms; waiting M codes keep the paths' programs in step as FANUC's do (the longer segment
between two waits governs); a path outside the machine is EW_PATH naming it."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from decimal import Decimal

import pytest

from focas_net.errors import EW
from focas_net.sim import (
    MAX_PATHS,
    DataItem,
    Machine,
    MachineError,
    MacroRange,
    PathInfo,
    PathSpec,
    Session,
    default_machine,
)
from focas_net.sim.nc import ManualClock

#: ODBST ``motion`` of a path waiting at a waiting M code, and of a moving one.
WAIT, MTN = 3, 1
#: ODBST ``run``: reset and cycle start.
RESET, STRT = 0, 3


def waiting_params(low: int = 100, high: int = 199) -> list[DataItem]:
    return [
        DataItem(8110, width=4, values=[low]),
        DataItem(8111, width=4, values=[high]),
        DataItem(6711, width=4),
        DataItem(6712, width=4),
    ]


def lathe(programs: list[str], clock: ManualClock, **kwargs: object) -> Machine:
    """A machine of one path per program, path n with axes Xn and Zn."""
    specs = [
        PathSpec((f"X{n}", f"Z{n}"), kind="T", programs=(text,))
        for n, text in enumerate(programs, 1)
    ]
    params = kwargs.pop("params", waiting_params())
    assert isinstance(params, list)
    return Machine("lathe", paths=specs, sim_clock=clock, params=params)


def seconds(distance_mm: float, feed_mm_min: float) -> float:
    """The time a straight cut of ``distance_mm`` at ``feed_mm_min`` takes."""
    return distance_mm / feed_mm_min * 60.0


def program(number: int, segments: Sequence[tuple[float, float]], waits: list[str]) -> str:
    """A program moving X to each ``(position, feed)`` of ``segments`` in turn, with the
    block ``waits[i]`` after segment i."""
    blocks = [f"O{number}"]
    for (x, feed), wait in zip(segments, waits, strict=True):
        blocks.append(f"G1 X{x:g}. F{feed:g}")
        blocks.append(wait)
    blocks += ["M30", "%"]
    return "\n".join(blocks)


# The two programs: path 1's and path 2's segments (X end in mm, feed in mm/min) between the
# waiting M codes M100, M101 and M102.
PATH1 = [(10, 600), (40, 600), (0, 1200)]
PATH2 = [(30, 600), (35, 600), (0, 700)]


def segment_times(segments: Sequence[tuple[float, float]]) -> list[float]:
    times, x = [], 0.0
    for end, feed in segments:
        times.append(seconds(abs(end - x), feed))
        x = end
    return times


def test_each_path_waits_for_the_other_and_the_longer_segment_governs() -> None:
    clock = ManualClock()
    waits = ["M100", "M101", "M102"]
    m = lathe([program(1, PATH1, waits), program(2, PATH2, waits)], clock)
    one, two = segment_times(PATH1), segment_times(PATH2)
    # FANUC's waiting rule: each segment between two waits lasts as long as the longer path's
    meets = []
    t = 0.0
    for a, b in zip(one, two, strict=True):
        t += max(a, b)
        meets.append(t)
    cycle = meets[-1]
    assert one != two  # each path is the longer one somewhere
    assert any(a > b for a, b in zip(one, two, strict=True))
    assert any(b > a for a, b in zip(one, two, strict=True))

    m.cycle_start(path=1)
    m.cycle_start(path=2)
    start = 0.0
    for end, a, b in zip(meets, one, two, strict=True):
        shorter, longer = (1, 2) if a < b else (2, 1)
        clock.set(start + min(a, b) / 2)  # both move
        assert (m.status(path=1).motion, m.status(path=2).motion) == (MTN, MTN)
        clock.set(start + (min(a, b) + max(a, b)) / 2)  # the shorter one waits
        assert m.status(path=shorter).motion == WAIT
        assert m.status(path=shorter).run == STRT  # waiting is automatic operation
        assert m.status(path=longer).motion == MTN
        waiting_at = PATH1 if shorter == 1 else PATH2
        index = meets.index(end)
        x_mm = waiting_at[index][0]
        assert m.positions("absolute", 1, path=shorter) == [(f"X{shorter}", x_mm * 1000)]
        start = end
    clock.set(cycle)
    for path in (1, 2):
        assert m.status(path=path).run == RESET
        assert m.parts_counts(path=path) == (1, 1)
        assert m.timer(3, path=path) == pytest.approx(cycle)  # the cycle time of each path
        assert m.timer(1, path=path) == pytest.approx(cycle)  # waiting is operating time


def test_a_path_held_at_a_wait_goes_on_only_once_resumed() -> None:
    clock = ManualClock()
    m = lathe([program(1, [(10, 600)], ["M100"]), program(2, [(30, 600)], ["M100"])], clock)
    first, second = seconds(10, 600), seconds(30, 600)
    m.cycle_start(path=1)
    m.cycle_start(path=2)
    clock.set(first + (second - first) / 2)
    m.feed_hold(path=1)  # held while it waits
    clock.set(second + 1.0)
    assert m.status(path=2).run == RESET  # path 2 went on when it arrived
    assert m.status(path=1).run == 2  # HOLD
    m.cycle_start(path=1)
    clock.advance(0.001)
    assert m.status(path=1).run == RESET
    assert [m.parts_counts(path=p)[0] for p in (1, 2)] == [1, 1]


def test_with_p_only_the_paths_named_wait() -> None:
    clock = ManualClock()
    texts = [
        program(1, [(10, 600)], ["M100 P12"]),
        program(2, [(30, 600)], ["M100 P12"]),
        program(3, [(20, 600)], ["M5"]),  # no wait: path 3 runs alone
    ]
    m = lathe(texts, clock)
    for path in (1, 2, 3):
        m.cycle_start(path=path)
    path3 = seconds(20, 600) + 0.5  # M5, an ordinary M code, takes the M function time
    clock.set(path3 + 0.01)
    assert m.status(path=3).run == RESET
    assert m.status(path=1).motion == WAIT
    clock.set(seconds(30, 600))
    assert [m.status(path=p).run for p in (1, 2, 3)] == [RESET] * 3
    assert m.timer(3, path=1) == pytest.approx(seconds(30, 600))


def test_paths_that_wait_with_other_codes_stop_with_ps0160() -> None:
    clock = ManualClock()
    m = lathe([program(1, [(10, 600)], ["M100"]), program(2, [(30, 600)], ["M101"])], clock)
    m.cycle_start(path=1)
    m.cycle_start(path=2)
    clock.set(seconds(30, 600) + 1.0)
    for path in (1, 2):
        (alarm,) = m.active_alarms(path=path)
        assert (alarm.alm_type, alarm.alm_no) == (3, 160)  # PS0160
        assert alarm.msg == "MISMATCH WAITING M-CODE"
        assert m.status(path=path).alarm == 1
    m.reset(path=1)
    assert m.active_alarms(path=1) == []  # a reset clears the path's program alarm
    assert len(m.active_alarms(path=2)) == 1


def test_paths_that_wait_for_each_other_with_another_p_stop_with_ps0160() -> None:
    clock = ManualClock()
    texts = [
        program(1, [(10, 600)], ["M100 P12"]),
        program(2, [(30, 600)], ["M100 P123"]),
        program(3, [(5, 600)], ["M5"]),
    ]
    m = lathe(texts, clock)
    for path in (1, 2, 3):
        m.cycle_start(path=path)
    clock.set(seconds(30, 600) + 1.0)
    assert [a.alm_no for a in m.active_alarms(path=1)] == [160]
    assert [a.alm_no for a in m.active_alarms(path=2)] == [160]
    assert m.active_alarms(path=3) == []


@pytest.mark.parametrize(
    ("path", "block"),
    [
        (1, "M100 P13"),  # path 3 on a 2-path machine
        (1, "M100 P1"),  # the path alone
        (1, "M100 P11"),  # a path twice
        (2, "M100 P10"),  # path 10 (digit 0) and path 1: not path 2
        (1, "M100 P2"),  # not the path itself
    ],
)
def test_a_p_naming_no_valid_paths_is_ps0161(path: int, block: str) -> None:
    clock = ManualClock()
    texts = [program(1, [(10, 600)], ["M5"]), program(2, [(10, 600)], ["M5"])]
    texts[path - 1] = program(path, [(10, 600)], [block])
    m = lathe(texts, clock)
    m.cycle_start(path=path)
    clock.set(seconds(10, 600) + 0.1)
    (alarm,) = m.active_alarms(path=path)
    assert (alarm.alm_type, alarm.alm_no, alarm.msg) == (3, 161, "ILLEGAL P OF WAITING M-CODE")


def test_an_m_code_outside_the_waiting_range_is_an_ordinary_m_code() -> None:
    clock = ManualClock()
    m = lathe(
        [program(1, [(10, 600)], ["M99"]), program(2, [(30, 600)], ["M200"])],
        clock,
        params=waiting_params(100, 199),
    )
    m.cycle_start(path=2)  # path 1 never starts: path 2 does not wait for it
    clock.set(seconds(30, 600) + 0.5)  # the M function time of M200
    assert m.status(path=2).run == RESET
    assert m.parts_counts(path=2) == (1, 1)


def test_without_8110_8111_no_m_code_waits() -> None:
    clock = ManualClock()
    m = lathe(
        [program(1, [(10, 600)], ["M100"]), program(2, [(30, 600)], ["M100"])],
        clock,
        params=[DataItem(6711, width=4)],
    )
    m.cycle_start(path=1)
    clock.set(seconds(10, 600) + 0.5)
    assert m.status(path=1).run == RESET


def test_a_single_path_machine_has_no_waiting_m_codes() -> None:
    clock = ManualClock()
    m = Machine(
        "one",
        axes=("X", "Z"),
        programs=(program(1, [(10, 600)], ["M100"]),),
        params=waiting_params(),
        sim_clock=clock,
    )
    m.cycle_start()
    clock.set(seconds(10, 600) + 0.5)
    assert m.status().run == RESET


# -- the model ----------------------------------------------------------------------------


def two_paths(clock: ManualClock | None = None) -> Machine:
    return Machine(
        "twin",
        paths=[
            PathSpec(("X1", "Z1"), name="HEAD1", kind="T", programs=("O10\nG1 X5. F600\nM30\n%",)),
            PathSpec(("X2", "Y2", "Z2"), kind="M", spindles=2, programs=("O20\nM30\n%",)),
        ],
        params=[
            DataItem(6711, width=4),
            DataItem(1420, width=4, axis=True, values=[1000, 2000, 3000, 4000, 5000]),
        ],
        macro_ranges=[MacroRange(100, 199), MacroRange(500, 999)],
        sim_clock=clock or ManualClock(),
    )


def test_path_info_and_count() -> None:
    m = two_paths()
    assert m.path_count == 2
    assert m.path_info(1) == PathInfo(1, "HEAD1", "T", ("X1", "Z1"), 1)
    assert m.path_info(2) == PathInfo(2, "PATH2", "M", ("X2", "Y2", "Z2"), 2)
    assert m.axes == ["X1", "Z1", "X2", "Y2", "Z2"]


@pytest.mark.parametrize("path", [0, 3, 11, -1])
def test_a_path_the_machine_has_not_is_ew_path_naming_it(path: int) -> None:
    m = two_paths()
    calls: list[Callable[[], object]] = [
        lambda: m.status(path=path),
        lambda: m.positions("absolute", path=path),
        lambda: m.path_info(path),
        lambda: m.parts_counts(path=path),
        lambda: m.active_alarms(path=path),
        lambda: m.program_directory(path=path),
        lambda: m.read_param(6711, 0, path=path),
        lambda: m.read_macro(500, path=path),
        lambda: m.cycle_start(path=path),
        lambda: m.timer(0, path=path),
    ]
    for call in calls:
        with pytest.raises(MachineError) as info:
            call()
        assert info.value.ew == EW.PATH
        assert info.value.detail == f"the CNC has no path {path}: it has paths 1..2"


def test_the_default_machine_has_one_path_and_path_2_is_ew_path() -> None:
    m = default_machine()
    assert m.path_count == 1
    assert m.path_info().axes == tuple(m.axes)
    assert m.status(path=1) == m.status()
    with pytest.raises(MachineError) as info:
        m.status(path=2)
    assert (info.value.ew, info.value.detail) == (
        EW.PATH,
        "the CNC has no path 2: it has path 1 only",
    )


def test_each_path_has_its_own_programs_engine_and_parts() -> None:
    clock = ManualClock()
    m = two_paths(clock)
    assert [p.number for p in m.program_directory(path=1)] == [10]
    assert [p.number for p in m.program_directory(path=2)] == [20]
    m.cycle_start(path=1)
    clock.set(seconds(5, 600) / 2)
    assert m.status(path=1).run == STRT
    assert m.status(path=2).run == RESET
    assert m.positions("absolute", path=1) == [("X1", 2500), ("Z1", 0)]
    assert m.positions("absolute", path=2) == [("X2", 0), ("Y2", 0), ("Z2", 0)]
    clock.set(seconds(5, 600))
    assert m.parts_counts(path=1) == (1, 1)
    assert m.parts_counts(path=2) == (0, 0)
    assert m.read_param(6711, 0, path=1) == 1  # a path-type parameter: one value per path
    assert m.read_param(6711, 0, path=2) == 0
    assert m.path_motion(path=1).program_main == 10
    assert m.motion == m.path_motion(path=1)


def test_axis_parameters_are_numbered_by_the_path_s_own_axes() -> None:
    m = two_paths()
    assert [m.read_param(1420, a, path=1) for a in (1, 2)] == [1000, 2000]
    assert [m.read_param(1420, a, path=2) for a in (1, 2, 3)] == [3000, 4000, 5000]
    with pytest.raises(MachineError) as info:
        m.read_param(1420, 3, path=1)
    assert info.value.ew == EW.ATTRIB


def test_a_path_type_parameter_is_written_for_the_path_given() -> None:
    m = two_paths()
    session = Session(True, 0)
    m.set_panel(0, 1, path=2)  # MDI and PWE on path 2 only
    m.write_param(session, 6711, 0, 7, path=2)
    assert (m.read_param(6711, 0, path=1), m.read_param(6711, 0, path=2)) == (0, 7)
    assert m.parts_counts(path=2) == (7, 0)
    with pytest.raises(MachineError) as info:  # path 1 is in MEM: its gate is closed
        m.write_param(session, 6711, 0, 7, path=1)
    assert info.value.ew == EW.PASSWD


def test_common_variables_100_199_are_each_path_s_and_500_999_shared() -> None:
    m = two_paths()
    m.write_macro(100, 1, path=1)
    m.write_macro(100, 2, path=2)
    m.write_macro(500, 5, path=2)
    assert (m.read_macro(100, path=1), m.read_macro(100, path=2)) == (Decimal(1), Decimal(2))
    assert m.read_macro(500, path=1) == Decimal(5)


def test_alarms_are_each_path_s() -> None:
    m = two_paths()
    version = m.alarm_version
    assert m.raise_alarm(0, 2, 1001, "PATH TWO", path=2)
    assert m.alarm_version > version
    assert m.active_alarms(path=1) == []
    assert [a.alm_no for a in m.active_alarms(path=2)] == [1001]
    assert (m.status(path=1).alarm, m.status(path=2).alarm) == (0, 1)
    assert m.raise_alarm(0, 2, 1001, "PATH ONE", path=1)  # the same alarm on another path
    assert [e.msg for e in m.alarm_history()] == ["PATH ONE", "PATH TWO"]  # one history
    with pytest.raises(MachineError) as info:  # an alarm stops cycle start of its path only
        m.cycle_start(path=2)
    assert info.value.ew == EW.ALARM
    assert m.clear_alarms(path=2) == 1
    assert [a.msg for a in m.active_alarms(path=1)] == ["PATH ONE"]
    with pytest.raises(MachineError) as info:  # axis_no numbers the path's own axes
        m.raise_alarm(3, 2, 1002, path=1)
    assert info.value.ew == EW.ATTRIB
    assert m.raise_alarm(3, 2, 1002, path=2)


def test_the_counters_move_when_any_path_changes() -> None:
    clock = ManualClock()
    m = two_paths(clock)
    status, motion = m.status_version, m.motion_version
    m.cycle_start(path=1)
    assert m.status_version > status
    moved = m.motion_version
    assert moved > motion
    clock.advance(0.1)
    assert m.motion_version > moved


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"paths": []}, "1..10 paths, got 0"),
        ({"paths": [PathSpec(("X",))] * (MAX_PATHS + 1)}, "1..10 paths, got 11"),
        ({"paths": [PathSpec(("X1",)), PathSpec(())]}, "path 2: a path has 1..20 axes, got 0"),
        ({"paths": [PathSpec(("X",)), PathSpec(("X",))]}, "path 2: axis 'X' is named also on"),
        ({"paths": [PathSpec(("X",), kind="L")]}, "path 1: kind 'L'"),
        ({"paths": [PathSpec(("X",), spindles=0)]}, "path 1: 1..8 spindles"),
        ({"paths": [PathSpec(("X",), name="A"), PathSpec(("Y",), name="A")]}, "path 2: name"),
        ({"paths": [PathSpec(("X",))], "axes": ("X",)}, "axes given with paths"),
        ({"paths": [PathSpec(("X",))], "programs": ("O1\nM30\n%",)}, "programs given"),
    ],
)
def test_the_constructor_refuses_bad_paths(kwargs: dict[str, object], words: str) -> None:
    with pytest.raises(ValueError, match=words):
        Machine("bad", **kwargs)  # type: ignore[arg-type]


def test_ten_paths_each_answer_for_themselves() -> None:
    clock = ManualClock()
    specs = [
        PathSpec((f"X{n}",), programs=(f"O{n}\nG1 X{n}. F600\nM30\n%",))
        for n in range(1, MAX_PATHS + 1)
    ]
    m = Machine("ten", paths=specs, params=waiting_params(), sim_clock=clock)
    for n in range(1, MAX_PATHS + 1):
        m.cycle_start(path=n)
    clock.set(seconds(MAX_PATHS, 600))
    assert [m.positions("absolute", path=n)[0][1] for n in range(1, 11)] == [
        n * 1000 for n in range(1, 11)
    ]
    assert [m.parts_counts(path=n)[0] for n in range(1, 11)] == [1] * 10
