"""A path at work on its own: a scenario's production, and the loads of its cutting.

:meth:`Production.start` runs a :class:`~focas_net.sim.nc.scenario.Scenario` on the path: the
main program repeated for a number of parts or forever, with seeded operator pauses (feed
hold), tool-change waits (the cycle stopped) and alarms (the cycle stopped until the repair
time is over, then reset and a new cycle). No timer runs: the scenario's events are machine
times drawn from the seed, and the path's sync applies those that are due, each at its own
machine time (:meth:`ScenarioRun.play`), before it reads the engine.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING, Final

from focas_net._refusals import not_ready
from focas_net.errors import EW

from ._alarms import MAX_ALARM_TEXT, nc_alarm
from ._base import MachineError
from ._items import PARTS_REQUIRED
from .nc import CycleState, Engine, NcStateError
from .nc.scenario import (
    SCENARIO_ALARMS,
    Scenario,
    ScenarioEvent,
    Schedule,
    noise,
    servo_load,
    spindle_load,
)

if TYPE_CHECKING:
    from ._path import Path

__all__ = ["Production", "ScenarioRun"]

_START: Final = CycleState.START
_RESET: Final = CycleState.RESET
_HOLD: Final = CycleState.HOLD
_STOP: Final = CycleState.STOP
#: How many applied events :attr:`Production.log` keeps.
_LOG_SIZE: Final = 1000


class ScenarioRun:
    """A scenario under way on a path: its schedule, the event in progress (until its end)."""

    __slots__ = ("current", "ends_at", "free_at", "production", "scenario", "schedule")

    def __init__(self, production: Production, scenario: Scenario, schedule: Schedule) -> None:
        self.production = production
        self.scenario = scenario
        self.schedule = schedule
        self.current: ScenarioEvent | None = None
        self.ends_at = math.inf  #: when the current event ends
        self.free_at = -math.inf  #: when the last event ended

    @property
    def next_time(self) -> float:
        """Machine time of the next begin or end."""
        if self.current is not None:
            return self.ends_at
        return max(self.schedule.next_time, self.free_at)

    def finished(self, engine: Engine) -> bool:
        """The parts are made (the cycle ended in reset with none to go)."""
        return engine.parts_to_go == 0 and engine.state is _RESET

    def play(self, now: float) -> None:
        """Apply the events and ends due by ``now``, each at its own machine time (the
        engine's clock held there meanwhile, then at ``now`` again: this runs within the
        path's sync). An event due while another is under way begins when that one ends."""
        path = self.production.path
        e = path.engine
        time = path.time
        log = self.production.log
        try:
            while self.next_time <= now:
                when = self.next_time
                time.hold(when)
                for happened in e.take_events():
                    path.engine_event(happened, now)
                current = self.current
                if current is not None:
                    self.current = None
                    self.free_at = when
                    self._end(current)
                    continue
                event = self.schedule.pop()
                if e.state is not _START or self.finished(e):
                    log.append((event, "skipped"))
                    continue
                self._begin(event, when, now)
                self.current = event
                self.ends_at = when + event.duration
        finally:
            time.hold(now)

    def _begin(self, event: ScenarioEvent, when: float, now: float) -> None:
        path = self.production.path
        e = path.engine
        self.production.log.append((event, "begin"))
        if event.kind == "pause":
            e.feed_hold()
        elif event.kind == "tool":
            e.program_stop()
        else:
            spec = SCENARIO_ALARMS[event.alarm]
            key = (event.axis, spec.alm_type, spec.alm_no)
            text = spec.message[:MAX_ALARM_TEXT]
            path.alarms.add(key, text, path.alarms.stamp(now - when), path.number)
            e.alarm_stop(nc_alarm(key, text))
        path.settled(True, force=True)

    def _restart_others(self) -> None:
        """After an alarm's repair, the machine's other paths start their programs anew with
        the path the scenario drives (they would otherwise meet it at another waiting M
        code): each is reset and, when ready, started at the same moment."""
        path = self.production.path
        when = path.time.now()
        for other in path.group:
            if other is path:
                continue
            other.time.hold(when)
            try:
                other.reset_cycle()
                try:
                    other.check_ready("the scenario's cycle cannot go on")
                    other.engine.cycle_start()
                except (MachineError, NcStateError):
                    pass
                other.settled(True, force=True)
            finally:
                other.time.release()

    def _end(self, event: ScenarioEvent) -> None:
        path = self.production.path
        e = path.engine
        self.production.log.append((event, "end"))
        if event.kind == "alarm":
            spec = SCENARIO_ALARMS[event.alarm]
            key = (event.axis, spec.alm_type, spec.alm_no)
            if not path.alarms.remove((key,), path.number):
                return  # cleared by hand: the operator takes it from here
            path.reset_cycle()
            self._restart_others()
        elif (event.kind == "pause" and e.state is not _HOLD) or (
            event.kind == "tool" and e.state is not _STOP
        ):
            return  # someone else changed the cycle meanwhile
        try:
            path.check_ready("the scenario's cycle cannot go on")
            e.cycle_start()
        except (MachineError, NcStateError):
            pass
        path.settled(True, force=True)


class Production:
    """What a path makes on its own: the scenario under way (None: none), the seed of the
    loads' noise and the log of the events applied."""

    __slots__ = ("_hardness", "log", "path", "run", "seed")

    def __init__(self, path: Path) -> None:
        self.path = path
        self.run: ScenarioRun | None = None
        #: The seed of the loads' noise (a scenario's seed once one runs).
        self.seed = 0
        self._hardness = 1.0
        #: The scenario's events as they were applied: ``(event, "begin" | "end" |
        #: "skipped")``, the newest 1000.
        self.log: deque[tuple[ScenarioEvent, str]] = deque(maxlen=_LOG_SIZE)

    def check_start(self) -> None:
        """What production needs: EW_ALARM, EW_MODE (as cycle start), EW_DATA (no main
        program)."""
        path = self.path
        path.sync()
        refused = "a scenario cannot start"
        if len(path.group) > 1:  # which path of several lacks what
            refused += f" on path {path.number}"
        path.check_ready(refused)
        if path.programs.main is None:
            raise MachineError(EW.DATA, not_ready(refused, EW.DATA) or refused)

    def start(self, scenario: Scenario, *, settle: bool = True) -> float:
        """Run ``scenario`` from its phase ago, the cycle rewound first: EW_ALARM, EW_MODE (as
        cycle start), EW_DATA (no main program). Returns the machine time it started at;
        ``settle`` False leaves the path there (the machine brings its paths to the clock's
        time together)."""
        path = self.path
        self.check_start()
        e = path.engine
        e.reset()
        now = path.time.now()
        origin = now - scenario.start_phase()
        e.repeat = True
        if scenario.parts == "required":
            required = path.items.param_or(PARTS_REQUIRED, 0)
            e.parts_to_go = max(0, required - e.parts_count) if required > 0 else None
        else:
            e.parts_to_go = scenario.parts or None
        self.seed = scenario.seed
        self._hardness = 0.85 + 0.15 * (noise(scenario.seed, 0.0, -1) + 1.0)
        path.powered_at = min(path.powered_at, origin)
        self.run = ScenarioRun(self, scenario, Schedule(scenario, origin, len(path.axes)))
        path.time.hold(origin)
        try:  # the cycle starts at the origin; the events since then follow in their order
            e.cycle_start(since=origin)
            path.driven = True
            path.synced_at = math.nan
            path.settled(True, force=True)
        except NcStateError as exc:  # pragma: no cover - the checks above cover it
            self.run = None
            path.moving()
            raise MachineError(EW.DATA, str(exc)) from None
        finally:
            path.time.release()
        if settle:
            path.sync()
        return origin

    def follow(self, origin: float, parts: int | None) -> None:
        """Produce from machine time ``origin`` alongside the path a scenario drives: the main
        program repeated, ``parts`` more of them (None: no limit), no events of its own."""
        path = self.path
        e = path.engine
        e.reset()
        e.repeat = True
        e.parts_to_go = parts
        path.powered_at = min(path.powered_at, origin)
        path.time.hold(origin)
        try:
            e.cycle_start(since=origin)
            path.driven = True
            path.synced_at = math.nan
            path.settled(True, force=True)
        except NcStateError as exc:  # pragma: no cover - check_start covers it
            raise MachineError(EW.DATA, str(exc)) from None
        finally:
            path.time.release()

    def stop(self) -> None:
        """The cycle goes on as it is, without the scenario's events and part limit."""
        self.path.sync()
        if self.run is None:
            return
        self.run = None
        self.path.moving()
        self.path.engine.parts_to_go = None

    def active(self) -> Scenario | None:
        self.path.sync()
        return None if self.run is None else self.run.scenario

    def spindle_loads(self) -> tuple[int, ...]:
        path = self.path
        path.sync()
        if not path.driven:
            return (0,)
        e = path.engine
        wiggle = noise(self.seed, path.time.now(), 0)
        speed = e.actual_spindle_speed
        top = e.settings.max_spindle_speed
        return (spindle_load(e.cutting, e.actual_feed, speed, top, wiggle, self._hardness),)

    def servo_loads(self) -> tuple[int, ...]:
        path = self.path
        path.sync()
        if not path.driven:
            return (0,) * len(path.axes)
        e = path.engine
        when = path.time.now()
        cutting, feed = e.cutting, e.actual_feed
        rapid = e.settings.rapid_rates
        return tuple(
            servo_load(v, rapid[i], cutting, feed, noise(self.seed, when, i + 1))
            for i, v in enumerate(e.axis_speeds())
        )
