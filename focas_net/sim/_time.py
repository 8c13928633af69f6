"""Machine time as a path's engine reads it: one clock object for the engine's whole life.

The engine asks its clock for the time whenever it is read. A path gives it a
:class:`MachineTime`, which reads the machine's clock (``sim_clock``) or, while the path
applies what happened at one moment (a sync, a scenario's event), stands at that moment, so the
engine advances once however many of its figures are read then. :meth:`Machine.set_clock`
changes the clock it reads, through :meth:`MachineTime.set_source`.

A CNC answers one request at one instant: while a front end answers one request frame (every
block of a FOCAS/2 data request, every figure of one packed answer), the machine's
:meth:`~focas_net.sim.Machine.instant` stops the clock of every path at one reading of it
(:meth:`MachineTime.stop`), so the figures of one answer agree (an axis's absolute and relative
positions are of the same moment) however long the answer takes to build.
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

    __slots__ = ("_base_now", "_held", "_held_now", "_stopped", "_stopped_now", "now", "source")
    now: Callable[[], float]

    def __init__(self, source: SimClock) -> None:
        self._held = _HeldClock()
        self._held_now = self._held.now
        self._stopped = _HeldClock()
        self._stopped_now = self._stopped.now
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
        """Read machine time from ``source`` from now on (nothing held or stopped)."""
        self.source = source
        self._base_now = self.now = source.now

    def stop(self, at: float) -> None:
        """The clock stands at ``at`` (a reading of :attr:`source`) until :meth:`go`: the
        instant of one answer. A :meth:`hold` meanwhile returns to ``at`` on release."""
        self._stopped.at = at
        self._base_now = self.now = self._stopped_now

    def go(self) -> None:
        """The clock reads :attr:`source` again."""
        self._base_now = self.now = self.source.now

    def hold(self, at: float) -> None:
        """Machine time stands at ``at`` until :meth:`release`."""
        self._held.at = at
        self.now = self._held_now

    def release(self) -> None:
        self.now = self._base_now
