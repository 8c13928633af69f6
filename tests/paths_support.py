"""A twin-turret lathe (two paths) with different values on each path, for the tests of the
native wire's paths (with and without FANUC's library) and their capture: turret 1 has the
axes X1 and Z1, turret 2 the axes X2, Z2 and B2 (a tailstock), so that what the library takes
from each path's record (its axis count) differs too."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from focas_net.sim import (
    Clock,
    DataItem,
    Identity,
    Machine,
    MacroRange,
    Panel,
    PathSpec,
    utc_now,
)
from focas_net.sim.nc import ManualClock

#: The control classes of the two command sets: a 16i answers version 2, a 0i-F version 3.
CLASSES = {"16i": "16i", "30i": "0i-F"}
_STROKE = 999_999_999


@dataclass(frozen=True)
class PathValues:
    """What one path of :func:`twin_turret` shows."""

    axes: tuple[str, ...]
    absolute: tuple[int, ...]
    machine: tuple[int, ...]
    relative: tuple[int, ...]
    distance: tuple[int, ...]
    feed: int
    speed: int
    running: int
    main: int
    sequence: int
    parts: int
    macro: Decimal
    alarm: tuple[int, int, int, str]  # axis, type, number, message
    mode: int  # the panel's mode: path 1 MDI (0), path 2 MEM (1)


#: Path 1 (turret 1) and path 2 (turret 2): no figure the same.
VALUES = (
    PathValues(
        ("X1", "Z1"), (1000, -2000), (11000, -12000), (100, 200), (10, -20), 150, 1200,
        1111, 1110, 15, 3, Decimal("1.5"), (1, 4, 500, "OVER TRAVEL +X1"), 0,
    ),
    PathValues(
        ("X2", "Z2", "B2"), (3000, -4000, 500), (33000, -44000, 5500), (300, 400, 50),
        (30, -40, 5), 250, 2200,
        2222, 2220, 27, 8, Decimal("-2.25"), (2, 4, 511, "OVER TRAVEL -Z2"), 1,
    ),
)  # fmt: skip
#: A macro variable the paths share (#500-#999), and its value.
SHARED_MACRO = (500, Decimal("42.125"))


def twin_turret(
    set_name: str = "30i",
    *,
    clock: Clock = utc_now,
    sim_clock: ManualClock | None = None,
) -> Machine:
    """A twin-turret lathe of the control class of ``set_name`` ("16i" or "30i"): paths X1/Z1
    and X2/Z2/B2, one spindle each, every figure of :data:`VALUES` set on its path (parts count
    in parameter 6711, a path-type parameter), :data:`SHARED_MACRO` set, an alarm on each
    path. ``clock`` is the machine's wall clock (alarm stamps)."""
    machine = Machine(
        "twin-turret",
        paths=[
            PathSpec(v.axes, kind="T", spindles=1, panel=Panel(mode=v.mode, pwe=1, emergency=0))
            for v in VALUES
        ],
        identity=Identity(2, 8, " 0", "TT", "D6F1", "32.0", "05"),
        params=[
            DataItem(1320, 4, True, -_STROKE, _STROKE, [_STROKE], "stroke limit +"),
            DataItem(6711, 4, False, 0, _STROKE, [0], "parts count"),
            DataItem(6712, 4, False, 0, _STROKE, [0], "total parts"),
        ],
        macro_ranges=[MacroRange(100, 199), MacroRange(500, 999), MacroRange(3901, 3902)],
        control_class=CLASSES[set_name],
        clock=clock,
        sim_clock=sim_clock if sim_clock is not None else ManualClock(),
    )
    for path, v in enumerate(VALUES, 1):
        machine.set_motion(
            path=path,
            absolute=v.absolute,
            machine=v.machine,
            relative=v.relative,
            distance_to_go=v.distance,
            feed=v.feed,
            spindle_speed=v.speed,
            program_running=v.running,
            program_main=v.main,
            sequence=v.sequence,
        )
        machine.write_macro(3901, v.parts, path=path)
        machine.write_macro(100, v.macro, path=path)
        machine.raise_alarm(*v.alarm, path=path)
    machine.write_macro(*SHARED_MACRO)
    return machine
