"""The alarms of a machine's paths as its operations read, raise and clear them, and the wall
clock that stamps them: a base class of :class:`~focas_net.sim.Machine` (no protocol).

The alarms themselves, their checks and the history are :mod:`focas_net.sim._alarms`'s; these
operations add what the machine asks first: a read-only machine refuses every change
(EW_PROT), then a path the machine has not (EW_PATH); reads bring the engines to the clock's
time first, so an alarm a program raised is there; an alarm raised stops its path's cycle.
"""

from __future__ import annotations

from datetime import datetime

from ._alarms import Alarm, Alarms, Clock, HistoryEntry
from ._paths import Paths

__all__ = ["AlarmOperations"]


class AlarmOperations:
    """Active alarms, the history and the alarm clock (a base of
    :class:`~focas_net.sim.Machine`, which builds :attr:`_alarms` and :attr:`_paths`)."""

    _alarms: Alarms
    _paths: Paths

    def _sync(self) -> None:  # pragma: no cover
        raise NotImplementedError

    def check_writable(self) -> None:  # pragma: no cover
        raise NotImplementedError

    def active_alarms(
        self, alm_type: int = -1, limit: int | None = None, *, path: int = 1
    ) -> list[Alarm]:
        """The active alarms of ``path`` of ``alm_type`` (-1: every type; a type no alarm has
        matches nothing), oldest raised first, at most ``limit`` of them (None: all): EW_PATH
        for a path the machine has not."""
        self._paths.at(path)
        self._sync()
        return self._alarms.read(alm_type, limit, path)

    def alarm_history(self, depth: int | None = None) -> tuple[HistoryEntry, ...]:
        """The ``depth`` newest entries of the history (None: all), newest first (the paths
        share one history)."""
        self._sync()
        return self._alarms.read_history(depth)

    @property
    def history_capacity(self) -> int:
        """How many entries the alarm history keeps."""
        return self._alarms.capacity

    @property
    def clock(self) -> Clock:
        """The wall clock the machine stamps alarms with (:meth:`now`)."""
        return self._alarms.clock

    @clock.setter
    def clock(self, clock: Clock) -> None:
        self._alarms.clock = clock

    def now(self) -> datetime:
        """The clock, as aware UTC cut to whole seconds."""
        return self._alarms.now()

    def raise_alarm(
        self, axis_no: int, alm_type: int, alm_no: int, msg: str = "", *, path: int = 1
    ) -> bool:
        """Make an alarm active and record it in the history (UTC, whole seconds); True when it
        was raised.

        A CNC shows one entry per alarm: an alarm already active (same axis_no, alm_type,
        alm_no) changes nothing, whatever ``msg`` says: it keeps the message it was raised
        with, the history gets no second entry, and the answer is False. Clear it first to raise
        it with another message. The CNC keeps 32 characters of ``msg``, single-byte (Latin-1)
        text. EW_PROT (read-only machine), EW_DATA (alm_type outside 0..31, alm_no outside
        0..32767), EW_ATTRIB (axis_no), EW_DATA (a character beyond U+00FF). Any alarm stops
        the cycle of its path.

        The alarm is ``path``'s (EW_PATH for a path the machine has not, after EW_PROT);
        ``axis_no`` numbers that path's axes. The order is the wire's (axis first), unlike
        a client's ``sim.raise_alarm``; named, the same arguments serve both."""
        self.check_writable()
        p = self._paths.at(path)
        text = self._alarms.checked(axis_no, alm_type, alm_no, msg, len(p.axes))
        self._sync()
        key = (axis_no, alm_type, alm_no)
        if not self._alarms.add(key, text, self.now(), path):
            return False
        p.alarm_stop(key, text)
        return True

    def clear_alarms(self, alm_type: int = -1, alm_no: int = -1, *, path: int = 1) -> int:
        """Remove the active alarms of ``path`` matching ``alm_type`` and ``alm_no`` (-1 =
        any); the history is kept. Returns how many were removed. EW_PROT on a read-only
        machine, then EW_PATH, then EW_DATA (alm_type outside -1..31, alm_no outside
        -1..32767)."""
        self.check_writable()
        self._paths.at(path)
        return self._alarms.clear(alm_type, alm_no, path)
