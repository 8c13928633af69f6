"""Simulation clocks: machine time in seconds, read when state is read.

The engine never ticks: it asks its clock for the time whenever its state is read and
advances lazily to it. :class:`RealTimeClock` follows the host's monotonic clock times a speed
factor; :class:`ManualClock` moves only when a test (or a scenario) steps it.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Protocol

__all__ = ["ManualClock", "RealTimeClock", "SimClock"]


class SimClock(Protocol):
    """A source of machine time: seconds since an arbitrary origin, never decreasing."""

    def now(self) -> float: ...


class RealTimeClock:
    """Machine time from the host's monotonic clock, ``speed`` times as fast (``speed=10``:
    ten machine seconds per wall second). One clock can drive any number of engines."""

    def __init__(self, speed: float = 1.0, source: Callable[[], float] = time.monotonic):
        self._source = source
        self._origin = source()
        self._base = 0.0
        self._speed = _checked_speed(speed)

    @property
    def speed(self) -> float:
        return self._speed

    def set_speed(self, speed: float) -> None:
        """Change the speed from now on; the time goes on from where it is."""
        speed = _checked_speed(speed)
        self._base = self.now()
        self._origin = self._source()
        self._speed = speed

    def now(self) -> float:
        return self._base + (self._source() - self._origin) * self._speed


def _checked_speed(speed: float) -> float:
    if not (math.isfinite(speed) and speed > 0):
        raise ValueError(f"the clock speed must be a positive number, got {speed!r}")
    return float(speed)


class ManualClock:
    """Machine time that moves only when :meth:`advance` or :meth:`set` is called."""

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)

    def now(self) -> float:
        return self._now

    def advance(self, seconds: float) -> float:
        """Move the time forward by ``seconds`` (>= 0); returns the new time."""
        if not (math.isfinite(seconds) and seconds >= 0):
            raise ValueError(
                f"a clock advances by a finite number of seconds >= 0, got {seconds!r}"
            )
        self._now += seconds
        return self._now

    def set(self, when: float) -> None:
        """Jump to ``when``, which may not be earlier than the current time."""
        if not (math.isfinite(when) and when >= self._now):
            raise ValueError(f"the clock cannot go back from {self._now} to {when!r}")
        self._now = float(when)
