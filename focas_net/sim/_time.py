"""Machine time as a path's engine reads it: one clock object for the engine's whole life.

The engine asks its clock for the time whenever it is read. A path gives it a
:class:`MachineTime`, which reads the machine's clock (``sim_clock``) or, while the path
applies what happened at one moment (a sync, a scenario's event), stands at that moment, so the
engine advances once however many of its figures are read then. :meth:`Machine.set_clock`
changes the clock it reads, through :meth:`MachineTime.set_source`.
"""

from __future__ import annotations

from collections.abc import Callable

from .nc import SimClock

__all__ = ["MachineTime"]


class _HeldClock:
    """Machine time held at one moment."""

    __slots__ = ("at",)

    def __init__(self) -> None:
        self.at = 0.0

    def now(self) -> float:
        return self.at


class MachineTime:
    """The engine's clock for its whole life: machine time from the machine's clock (the one
    :meth:`Machine.set_clock` sets), or held at one moment while the path applies what
    happened then (a sync, a scenario's event). While nothing is held, ``now`` is the
    clock's own method: the engine reads it at the cost of the clock alone."""

    __slots__ = ("_held", "_held_now", "now", "source")
    now: Callable[[], float]

    def __init__(self, source: SimClock) -> None:
        self._held = _HeldClock()
        self._held_now = self._held.now
        self.set_source(source)

    def check(self, clock: SimClock) -> None:
        """ValueError, saying what to give, when ``clock`` is behind machine time: a machine
        goes on from where it is."""
        now = self.now()
        behind = now - clock.now()
        if behind > 0:
            raise ValueError(
                f"the clock is {behind} s behind the machine's time {now}: a machine goes on "
                f"from where it is, so give a clock at {now} or later (ManualClock({now})), "
                "or give the clock when the machine is built (sim_clock=)"
            )

    def set_source(self, source: SimClock) -> None:
        """Read machine time from ``source`` from now on (nothing held)."""
        self.source = source
        self.now = source.now

    def hold(self, at: float) -> None:
        """Machine time stands at ``at`` until :meth:`release`."""
        self._held.at = at
        self.now = self._held_now

    def release(self) -> None:
        self.now = self.source.now
