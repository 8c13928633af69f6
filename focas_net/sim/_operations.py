"""The operations of one path of a machine, a part of :class:`~focas_net.sim.Machine`: its
panel and run state, its motion figures and positions, its cycle and overrides, its parts and
timers, its production and loads, its program store.

Each takes ``path`` (keyword, 1 by default) and answers for that path: a path outside
1..path_count is EW_PATH naming it (:meth:`~._paths.Paths.at`). A path's rules are those of
the machine's module docstring; each path keeps them on its own.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from contextlib import AbstractContextManager

from focas_net._typed import MODE_TYPE
from focas_net.errors import EW

from ._base import MachineError, need_flag, need_flag_or_none, need_int
from ._paths import Paths
from ._signals import METER, Collected
from ._spindles import (
    LOOP_GAIN_PARAMETER,
    STANDARD_LOOP_GAIN,
    Spindle,
    servo_motor_speeds,
    spindle_states,
)
from ._status import MotionData, panel_mode, switch_unfit
from .nc import ProgramInfo, SimClock, check_sim_clock
from .nc.scenario import DEFAULT_SCENARIO, Scenario, checked_scenario

__all__ = ["PathOperations"]


class PathOperations:
    """The per-path operations of the machine (a base of :class:`~focas_net.sim.Machine`,
    which builds :attr:`_paths`)."""

    _paths: Paths
    _collected: Collected
    #: G12/G14/G30 of a path from its overrides (:class:`~._signals.SignalOperations`).
    _show_overrides: Callable[[int], None]
    #: Seconds of a path's integrating meter (:class:`~._signals.SignalOperations`).
    _meter: Callable[[int], float]
    scenario: Scenario | None

    def check_writable(self) -> None:  # pragma: no cover - the machine's
        raise NotImplementedError

    # -- operator panel and motion figures -----------------------------------------------
    def set_panel(
        self,
        mode: int | str | None = None,
        pwe: int | None = None,
        emergency: int | None = None,
        *,
        path: int = 1,
    ) -> None:
        """Set the operator panel: ``mode`` an ``aut`` value other than 2 or its name
        (``"MDI"``), ``pwe`` and ``emergency`` 0/1, else EW_DATA; a switch given as None stays
        as it is. EW_PROT on a read-only machine. Leaving MEM holds the feed; the emergency
        stop resets. TypeError for a mode that is neither an integer nor text (``True`` is no
        mode); a switch may be a ``bool``."""
        if isinstance(mode, str):
            try:
                mode = panel_mode(mode)
            except ValueError as exc:
                raise MachineError(EW.DATA, str(exc)) from None
        elif mode is not None and (isinstance(mode, bool) or not isinstance(mode, int)):
            raise TypeError(f"{MODE_TYPE}, got {mode!r}")
        for what, value in (("pwe", pwe), ("emergency", emergency)):
            if value is not None and not isinstance(value, int):
                raise TypeError(switch_unfit(what, value))
        self.check_writable()
        self._paths.at(path).set_panel(mode, pwe, emergency)

    def set_run(self, run: int, motion: int = 0, *, path: int = 1) -> None:
        """Set the run state (0 reset, 1 STOP, 2 HOLD, 3 STRT, 4 MSTR) and motion (0, 1 MTN,
        2 DWL) shown by the status (simulation code only): EW_DATA otherwise."""
        need_int("run", run)
        need_int("motion", motion)
        self._paths.at(path).set_run(run, motion)

    def set_motion(
        self,
        *,
        path: int = 1,
        absolute: Iterable[int] | None = None,
        machine: Iterable[int] | None = None,
        relative: Iterable[int] | None = None,
        distance_to_go: Iterable[int] | None = None,
        feed: int | None = None,
        spindle_speed: int | None = None,
        program_running: int | None = None,
        program_main: int | None = None,
        sequence: int | None = None,
    ) -> None:
        """Set motion figures (simulation code only); what is not given stays.

        Positions are one i32 per axis in least input increments; feed and spindle speed are
        0..2**31-1, a program number 0..9999 and the sequence number 0..99999 (FANUC's four
        and five digits, 0 for none). EW_DATA (and nothing changes) when a value does not fit
        or a position list does not have one value per axis; TypeError naming a value of
        another type (``absolute[2] must be an integer, got 3.5``).
        """
        self._paths.at(path).set_motion(
            (absolute, machine, relative, distance_to_go),
            (feed, spindle_speed, program_running, program_main, sequence),
        )

    @property
    def motion(self) -> MotionData:
        """Path 1's motion figures (:meth:`path_motion`)."""
        return self._paths.all[0].figures()

    def path_motion(self, *, path: int = 1) -> MotionData:
        """The motion figures of ``path``: the engine's while it drives them
        (:meth:`path_driven`), else those :meth:`set_motion` set."""
        return self._paths.at(path).figures()

    def positions(
        self, kind: str, axis: int | None = None, *, path: int = 1
    ) -> list[tuple[str, int]]:
        """``(axis name, value)`` of every axis (``axis`` None) or of axis ``axis`` (1..n), in
        least input increments (:data:`POSITION_DECIMALS` decimals). ``kind`` is one of
        :data:`POSITION_KINDS`. Checks, in order: an unknown kind -> EW_ATTRIB; ``"skip"`` ->
        EW_NOOPT (the machine has no skip function); ``axis`` outside 1..n -> EW_ATTRIB."""
        return self._paths.at(path).positions(kind, axis)

    @property
    def driven(self) -> bool:
        """Whether the engine shows the run state and the motion figures: from a cycle start
        or a program selection until :meth:`set_motion` or :meth:`set_run` sets them by hand
        (before, the figures given to the constructor or by hand are shown). Path 1's:
        :meth:`path_driven` for another."""
        return self._paths.all[0].driven

    def path_driven(self, *, path: int = 1) -> bool:
        """Whether the engine of ``path`` shows its run state and figures (:attr:`driven`)."""
        return self._paths.at(path).driven

    # -- machine time and the cycle ------------------------------------------------------
    @property
    def sim_clock(self) -> SimClock:
        """The clock of machine time (seconds): ``RealTimeClock()`` unless the constructor or
        :meth:`set_clock` gave another."""
        return self._paths.all[0].time.source

    def instant(self) -> AbstractContextManager[None]:
        """Machine time stands still while the ``with`` block runs: every read inside is of one
        instant, as a CNC answers one request (a front end wraps each request frame in it).
        The clock is read once on entry; nested blocks share the outer one's instant. Time
        that passes meanwhile is caught up by the next read after the block."""
        return self._paths

    def set_clock(self, clock: SimClock) -> None:
        """Take machine time from ``clock`` from now on: the engine, the timers and a running
        scenario read it (a fleet shares one: ``serve --speed``; a test gives a
        :class:`~focas_net.sim.nc.ManualClock` and steps it). This is the one way the
        engine's clock is set after the constructor's ``sim_clock``. The machine goes on from
        where it is, so ``clock`` may not be behind the machine's time (ValueError); the time
        it is ahead passes at once, as if the machine had been left alone that long."""
        check_sim_clock(clock)
        for p in self._paths:  # every path's first, so a refusal changes nothing
            p.check_clock(clock)
        for p in self._paths:
            p.set_clock(clock)

    def cycle_start(self, *, path: int = 1, repeat: bool | None = None) -> None:
        """Cycle start: run the main program from its head (reset), go on (stop) or resume
        (feed hold). EW_PROT (read-only machine), EW_ALARM (emergency stop, an active alarm,
        or an alarm that stopped the cycle and wants a reset), EW_MODE (not MEM), EW_DATA (no
        main program). From here the engine shows the run state and the figures.

        ``repeat`` True: production, the main program starts again at once after each M2/M30
        (a part counted each time) until ``repeat`` False is given or an alarm stops it; None
        leaves the setting as it is (another value is a TypeError)."""
        self.check_writable()
        need_flag_or_none("repeat", repeat)
        self._paths.at(path).cycle_start(repeat)

    def feed_hold(self, *, path: int = 1) -> None:
        """Feed hold: the axes stop where they are (HOLD); cycle start resumes. EW_PROT on a
        read-only machine."""
        self.check_writable()
        self._paths.at(path).feed_hold()

    def reset(self, *, path: int = 1) -> None:
        """Reset: the cycle stops and rewinds, the alarms the program raised are cleared (the
        history keeps them). EW_PROT on a read-only machine."""
        self.check_writable()
        self._paths.at(path).reset()

    def set_overrides(
        self,
        feed: int | None = None,
        rapid: int | str | None = None,
        spindle: int | None = None,
        *,
        path: int = 1,
    ) -> None:
        """Feed override 0..254 %, rapid override one of FANUC's steps 0 (F0), 25, 50, 100 %,
        spindle override 0..254 % (None: unchanged): EW_PROT (read-only machine), EW_DATA (a
        value outside its range, a rapid override between the steps), TypeError (a value that
        is no whole number). The rapid override also takes the name of its slowest step as the
        command line and the page read it, ``"F0"`` (any case; ``"F25"`` is a ValueError listing
        the steps)."""
        self.check_writable()
        self._paths.at(path).set_overrides(feed, rapid, spindle)
        self._show_overrides(path)

    def parts_counts(self, *, path: int = 1) -> tuple[int, int]:
        """Parts count and total parts (M2/M30 count them; parameters 6711 and 6712)."""
        return self._paths.at(path).parts_counts()

    def overrides(self, *, path: int = 1) -> tuple[int, int, int]:
        """Feed, rapid and spindle override in percent."""
        return self._paths.at(path).overrides()

    def timer(self, kind: int, *, path: int = 1) -> float:
        """Seconds of timer ``kind`` (FANUC's ``cnc_rdtimer`` types): 0 power-on (machine
        time since the machine was built), 1 operating, 2 cutting, 3 cycle (this cycle's time
        since its start from reset), 4 the general-purpose integrating meter (while TMRON,
        G53.0, is 1); EW_NUMBER for another kind. A write of the run-time parameters
        6750-6758 sets them (:mod:`._signals`)."""
        need_int("timer kind", kind)
        if kind == METER:
            self._paths.at(path)
            return self._meter(path)
        return self._collected.shifted(path, kind, self._paths.at(path).timer(kind))

    def timer_ms(self, kind: int, *, path: int = 1) -> int:
        """Whole milliseconds of timer ``kind`` (:meth:`timer`), as a counter shows them: the
        millisecond under way is not counted yet. Both protocols answer this figure."""
        return math.floor(
            self.timer(kind, path=path) * 1000 + 1e-6
        )  # 1e-6 ms: 1.234 s * 1000 is 1233.99..

    # -- production on its own: scenarios, loads -----------------------------------------
    def start_scenario(self, scenario: Scenario | None = None) -> None:
        """Run on its own: the main program from its head, repeated for the scenario's parts
        (or forever) with its pauses, tool-change waits and alarms, from ``scenario.phase``
        seconds ago (see :mod:`focas_net.sim.nc.scenario`). ``scenario`` None: the machine's
        own (:attr:`scenario`, a machine file's ``[run]``), else the default. The cycle
        rewinds first. Refused as cycle start is: EW_ALARM (emergency stop, an active alarm),
        EW_MODE (not MEM), EW_DATA (no main program); a read-only machine runs it too (the
        machine works, clients only read it). On a machine of several paths the scenario
        drives path 1 (its events, its parts) and every other path produces alongside from
        the same moment, the waiting M codes keeping them in step. A ``scenario`` of another
        type is a TypeError naming it."""
        chosen = checked_scenario(scenario) or checked_scenario(self.scenario) or DEFAULT_SCENARIO
        self._paths.start_production(chosen)

    def stop_scenario(self) -> None:
        """Stop running on its own: the cycle goes on as it is (production without the
        scenario's events and part limit)."""
        self._paths.stop_production()

    @property
    def scenario_running(self) -> bool:
        """Whether a scenario drives the machine (until its parts are made)."""
        return self.active_scenario is not None

    @property
    def active_scenario(self) -> Scenario | None:
        """The scenario driving the machine (as started, its seed the machine's own), None
        when none does."""
        return self._paths.all[0].production.active()

    @property
    def seed(self) -> int:
        """The seed of the loads' noise (a scenario's seed once one runs)."""
        return self._paths.all[0].production.seed

    @seed.setter
    def seed(self, seed: int) -> None:
        for p in self._paths:
            p.production.seed = seed

    def spindle_loads(self, *, path: int = 1) -> tuple[int, ...]:
        """The load of each spindle (one) in percent: 0 with the spindle stopped, a few
        percent turning without cutting, rising with the feed and the spindle speed while
        the program cuts, with a small noise that depends on :attr:`seed` and the machine
        time only (0 while the figures are set by hand)."""
        return self._paths.at(path).production.spindle_loads()

    def spindles(self, *, path: int = 1) -> tuple[Spindle, ...]:
        """Every spindle of ``path`` now (:mod:`focas_net.sim._spindles`): the first turns at
        the path's spindle speed (:meth:`path_motion`) with its load (:meth:`spindle_loads`),
        the others stand."""
        p = self._paths.at(path)
        count = self._paths.info(path).spindles
        speed = p.figures().spindle_speed
        top = round(p.engine.settings.max_spindle_speed)
        load = p.production.spindle_loads()[0]
        return spindle_states(count, speed, load, top)

    def servo_speeds(self, *, path: int = 1) -> tuple[int, ...]:
        """The servo motor speed of each axis in min^-1: the axis's speed over a
        :data:`~._spindles.SCREW_LEAD` mm ball screw driven one to one (0 at rest, and while
        the figures are set by hand)."""
        p = self._paths.at(path)
        p.sync()
        if not p.driven:
            return (0,) * len(p.axes)
        return servo_motor_speeds(p.engine.axis_speeds())

    def loop_gains(self, *, path: int = 1) -> tuple[int, ...]:
        """The position loop gain of each axis in 0.01/s: its servo loop gain parameter
        (1825) when the machine has it, else FANUC's standard 3000 (30/s)."""
        p = self._paths.at(path)
        return tuple(
            p.items.param_or(LOOP_GAIN_PARAMETER, STANDARD_LOOP_GAIN, axis)
            for axis in range(1, len(p.axes) + 1)
        )

    def servo_loads(self, *, path: int = 1) -> tuple[int, ...]:
        """The servo load of each axis in percent: 0 at rest, rising with the axis's speed
        and more while it cuts, with a small noise as :meth:`spindle_loads` has."""
        return self._paths.at(path).production.servo_loads()

    # -- the program store ---------------------------------------------------------------
    def program_directory(self, *, path: int = 1) -> list[ProgramInfo]:
        """Every stored program (number, name, characters), by number."""
        return self._paths.at(path).programs.directory()

    def program_text(self, number: int, *, path: int = 1) -> str:
        """The text of program ``number`` as stored: EW_NUMBER when there is none."""
        need_int("program number", number)
        return self._paths.at(path).program_text(number)

    def store_program(self, text: str, *, path: int = 1, replace: bool = False) -> int:
        """Store one program (its O number is returned). EW_PROT (read-only machine), EW_DATA
        (not one O-number program), EW_NUMBER (number outside the store's range), EW_REJECT
        (the number is stored and ``replace`` is false), EW_BUSY (replacing a program being
        executed), EW_OVRFLOW (memory or directory full)."""
        self.check_writable()
        if not isinstance(text, str):
            raise TypeError(f"a program must be text (str), got {text!r}")
        need_flag("replace", replace)
        return self._paths.at(path).store_program(text, replace)

    def delete_program(self, number: int, *, path: int = 1) -> None:
        """Delete program ``number``: EW_PROT (read-only machine), EW_NUMBER (no such
        program), EW_BUSY (being executed). Deleting the main program unselects it."""
        self.check_writable()
        need_int("program number", number)
        self._paths.at(path).delete_program(number)

    def select_program(self, number: int, *, path: int = 1) -> None:
        """Make ``number`` the main program (a program search): EW_PROT (read-only
        machine), EW_MODE (a mode other than MEM and EDIT), EW_NUMBER (no such program),
        EW_BUSY (another program is being executed)."""
        self.check_writable()
        need_int("program number", number)
        self._paths.at(path).select_program(number)
