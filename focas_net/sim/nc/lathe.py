"""A lathe's own spindle and feed codes (FANUC's T series, G code system A).

G96 holds the surface speed S (m/min) constant: the spindle turns at 1000 S / (pi |X|)
min^-1, X the diameter where the tool is in the work coordinate system; G97 reads S as
min^-1. ``G50 S`` limits either to its value. In G99 F is mm per revolution: the feed is F
times the spindle speed; in G98 it is mm/min. The interpreter keeps the state (its ``modal``
groups 10 and 13, ``spindle_command``, ``spindle_limit``), this module computes from it.
"""

from __future__ import annotations

import math
from typing import Final, Protocol

__all__ = ["CSS", "FEED_PER_REVOLUTION", "SpindleState", "spindle_speed"]

#: G96 (group 13) and G99 (group 10), x10.
CSS: Final = 960
FEED_PER_REVOLUTION: Final = 990


class SpindleState(Protocol):
    """What the interpreter holds of the spindle."""

    spindle: int
    spindle_command: float
    spindle_limit: float | None
    spindle_override: float
    modal: dict[int, int]


def spindle_speed(state: SpindleState, x: float | None, maximum: float) -> float:
    """The spindle's min^-1 with the tool at diameter ``x`` (work coordinate; None: the path
    has no X): 0 unless M3/M4, the override applied, then limited by ``G50 S`` and by
    ``maximum`` (parameter 3772)."""
    if state.spindle not in (3, 4):
        return 0.0
    speed = state.spindle_command
    if state.modal.get(13) == CSS and x is not None:
        speed = math.inf if x == 0 else 1000.0 * speed / (math.pi * abs(x))
    speed *= state.spindle_override / 100.0
    if state.spindle_limit is not None:
        maximum = min(maximum, state.spindle_limit)
    return min(speed, maximum)
