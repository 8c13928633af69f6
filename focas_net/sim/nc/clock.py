"""Simulation clocks: machine time in seconds, read when state is read.

The engine never ticks: it asks its clock for the time whenever its state is read and
advances lazily to it. :class:`RealTimeClock` follows the host's monotonic clock times a speed
factor; :class:`ManualClock` moves only when a test (or a scenario) steps it.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from typing import Protocol

__all__ = ["ManualClock", "RealTimeClock", "SimClock", "check_sim_clock"]


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


def _finite(value: float) -> bool:
    """Whether ``value`` is a finite number a float holds (``10**400`` is not one)."""
    return abs(value) <= sys.float_info.max if isinstance(value, int) else math.isfinite(value)


def _checked_speed(speed: float) -> float:
    if not (_finite(speed) and speed > 0):
        raise ValueError(f"the clock speed must be a positive number, got {speed!r}")
    return float(speed)


def _seconds(what: str, value: object) -> float:
    """``value`` as a finite number of seconds: TypeError for what is no number (a ``bool``,
    text), ValueError for NaN and the infinities, each naming ``what`` and the value."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"{what} must be a number of seconds, got {value!r}")
    if not _finite(value):
        raise ValueError(f"{what} must be a finite number of seconds, got {value!r}")
    return float(value)


def check_sim_clock(clock: object, what: str = "clock") -> SimClock:
    """``clock`` when it is a clock object with ``now()`` (a :class:`ManualClock`, a
    :class:`RealTimeClock`...); TypeError naming ``what`` and what was given otherwise (a
    class rather than its instance, a number, text)."""
    if isinstance(clock, type) or not callable(getattr(clock, "now", None)):
        raise TypeError(
            f"{what} must be a clock with now() (ManualClock(), RealTimeClock()), got {clock!r}"
        )
    return clock  # type: ignore[return-value]


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


class ManualClock:
    """Machine time that moves only when :meth:`advance` or :meth:`set` is called."""

    def __init__(self, start: float = 0.0) -> None:
        self._now = _seconds("start", start)

    def __repr__(self) -> str:
        """``ManualClock(12.5)``: the clock as built to stand where it stands."""
        return f"ManualClock({self._now!r})"

    def now(self) -> float:
        return self._now

    def advance(self, seconds: float) -> float:
        """Move the time forward by ``seconds`` (>= 0); returns the new time."""
        if not _is_number(seconds):
            _seconds("seconds", seconds)  # TypeError
        if not (_finite(seconds) and seconds >= 0):
            raise ValueError(
                f"a clock advances by a finite number of seconds >= 0, got {seconds!r}"
            )
        self._now += seconds
        return self._now

    def set(self, when: float) -> None:
        """Jump to ``when``, which may not be earlier than the current time."""
        if not _is_number(when):
            _seconds("when", when)  # TypeError
        if not _finite(when):
            raise ValueError(f"a clock is set to a finite time, got {when!r}")
        if not when >= self._now:
            raise ValueError(f"the clock cannot go back from {self._now} to {when!r}")
        self._now = float(when)
