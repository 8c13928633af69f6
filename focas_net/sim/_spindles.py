"""The spindles of a path as a control reports them: name, speed, load, top speed and gear.

A path has 1..8 spindles (:class:`~._paths.PathSpec`). The first is the path's main spindle:
it turns as the path's program commands it (the S word, M3/M4/M5 and the spindle override,
the engine's ``actual_spindle_speed``; or the speed :meth:`~focas_net.sim.Machine.set_motion`
set by hand) and carries the path's spindle load
(:meth:`~focas_net.sim.Machine.spindle_loads`). The others are sub spindles no program of this
simulator turns: they stand, with no load. Every spindle is named ``S`` followed by its number
(``S1``, ``S2``...), as a control with one spindle name ``S`` per path shows them; every
spindle runs in its first gear (the simulated spindles have no gear change) and its top speed
is the path's largest spindle speed (the engine's ``max_spindle_speed``, in min^-1).

The servo figures of the axes are here too: the motor speed of an axis is its speed over a
ball screw of :data:`SCREW_LEAD` mm driven one to one; its position loop gain is the servo
loop gain parameter (:data:`LOOP_GAIN_PARAMETER`, 0.01/s) of the machine, FANUC's standard
:data:`STANDARD_LOOP_GAIN` (30/s) when the machine has none.

No protocol here: the front ends read :class:`Spindle` records and encode them themselves.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final

__all__ = [
    "LOOP_GAIN_PARAMETER",
    "SCREW_LEAD",
    "SPINDLE_NAME",
    "STANDARD_LOOP_GAIN",
    "Spindle",
    "servo_motor_speeds",
    "spindle_states",
]

#: Lead of the ball screw of every simulated axis, mm per motor revolution.
SCREW_LEAD: Final = 10.0
#: The servo loop gain parameter (per axis, 0.01/s).
LOOP_GAIN_PARAMETER: Final = 1825
#: FANUC's standard position loop gain, 0.01/s.
STANDARD_LOOP_GAIN: Final = 3000

#: The name letter of every spindle (each followed by its number as suffix).
SPINDLE_NAME: Final = "S"
#: The gear every simulated spindle runs in.
_GEAR: Final = 1


@dataclass(frozen=True, slots=True)
class Spindle:
    """One spindle of a path now.

    ``number`` 1..n on its path; ``name`` the name letter and ``suffix`` its number as text
    (``"S"``, ``"1"``); ``speed`` the actual speed in min^-1 (the motor speed of a spindle
    driven one to one); ``load`` the load meter in percent; ``max_speed`` the top speed in
    min^-1; ``gear`` the gear it runs in (1..4).
    """

    number: int
    name: str
    suffix: str
    speed: int
    load: int
    max_speed: int
    gear: int


def spindle_states(count: int, speed: int, load: int, max_speed: int) -> tuple[Spindle, ...]:
    """The ``count`` spindles of a path whose main spindle turns at ``speed`` with ``load``
    percent, each with top speed ``max_speed`` (the module docstring's rules)."""
    return tuple(
        Spindle(
            number,
            SPINDLE_NAME,
            str(number),
            speed if number == 1 else 0,
            load if number == 1 else 0,
            max_speed,
            _GEAR,
        )
        for number in range(1, count + 1)
    )


def servo_motor_speeds(axis_speeds: Iterable[float]) -> tuple[int, ...]:
    """The motor speed in min^-1 of axes moving at ``axis_speeds`` mm/min."""
    return tuple(round(v / SCREW_LEAD) for v in axis_speeds)
