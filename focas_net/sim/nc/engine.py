"""The execution engine: a program's blocks in machine time, computed when read.

Nothing ticks. Every read (and every command) first advances the engine to its clock's time:
the current action's progress moves at the override's rate, finished actions give way to the
interpreter's next ones. A read with nothing to do costs a clock call and a comparison;
running costs one interpreter step per block, whenever the blocks are read.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from typing import Final

from .actions import BUSY, Action, Dwell, ProgramEnd, Stop, Sync, Wait
from .alarms import ALARM_MESSAGES, AlarmKind, AlarmRaised, NcAlarm, number_text
from .clock import SimClock
from .interpreter import Interpreter
from .macro import MemoryVariables, NcVariables
from .motion import Motion, RapidMove, Vector
from .program import ProgramStore
from .settings import NcSettings
from .waits import MISMATCH, PathSync, Unknown

__all__ = ["CycleState", "Engine", "EngineEvent", "MotionKind", "NcStateError"]


class CycleState(Enum):
    """Automatic operation: reset (no program under way), stopped within a program (M0/M1,
    single block, an alarm), feed hold, cycle start."""

    RESET = "reset"
    STOP = "stop"
    HOLD = "hold"
    START = "start"


class MotionKind(Enum):
    """What the axes do: nothing, move, dwell, or wait at a waiting M code for the other
    paths."""

    NONE = "none"
    MOTION = "motion"
    DWELL = "dwell"
    WAIT = "wait"


class NcStateError(ValueError):
    """A command the engine's state refuses (cycle start without a main program, with an
    alarm, ...); the message says why."""


@dataclass(frozen=True, slots=True)
class EngineEvent:
    """Something the machine may want to record, at machine time ``time``: ``kind`` is
    ``"alarm"`` (with ``alarm``), ``"part"`` (M2/M30; ``value`` the parts count),
    ``"tool"`` (M6; ``value`` the tool number) or ``"end"`` (the program's end)."""

    time: float
    kind: str
    value: int = 0
    alarm: NcAlarm | None = None


class Engine:
    """One control's automatic operation. ``clock`` gives machine time; ``store`` holds the
    programs (the engine tells it which are in use); ``variables`` serves #500-#999 and the
    system variables the engine does not own; ``work_offsets`` ([0] external, [1..6]
    G54..G59) and ``tool_offsets`` (H number -> length) may be shared with the machine."""

    def __init__(
        self,
        clock: SimClock,
        settings: NcSettings | None = None,
        *,
        store: ProgramStore | None = None,
        variables: NcVariables | None = None,
        work_offsets: Sequence[Sequence[float]] | None = None,
        tool_offsets: Mapping[int, float] | None = None,
        sync: PathSync | None = None,
    ) -> None:
        self.clock = clock
        self.settings = settings or NcSettings()
        n = len(self.settings.axes)
        self.store = store if store is not None else ProgramStore()
        offsets = [list(row) for row in work_offsets] if work_offsets else [[0.0] * n] * 7
        if len(offsets) != 7 or any(len(row) != n for row in offsets):
            raise ValueError(f"work offsets are 7 rows (external, G54..G59) of {n} axes")
        self.work_offsets = [list(row) for row in offsets]
        self.tool_offsets: dict[int, float] = dict(tool_offsets or {})
        self.interpreter = Interpreter(
            self.settings,
            self.store,
            variables if variables is not None else MemoryVariables(),
            self.work_offsets,
            self.tool_offsets,
        )
        self.store.in_use = self._in_use
        self._time = clock.now()
        self._state = CycleState.RESET
        self._queue: deque[Action] = deque()
        self._action: Action | None = None
        self._progress = 0.0
        self._limit = 0.0  #: progress at which the action ends (earlier on an overtravel)
        self._overtravel: NcAlarm | None = None
        self._position: Vector = (0.0,) * n
        self._relative_origin: list[float] = [0.0] * n
        self._zero_steps = 0
        self._single_block_pending = False
        self._alarm: NcAlarm | None = None
        self.events: list[EngineEvent] = []
        self.single_block = False
        #: Production: after M2/M30 the main program starts again at once (no reset between).
        self.repeat = False
        #: With :attr:`repeat`: how many more parts to make before production stops (the
        #: cycle then ends in reset as without ``repeat``); None: no limit.
        self.parts_to_go: int | None = None
        self._feed_override = 100.0
        self._rapid_override = 100.0
        self.spindle_override = 100.0
        #: Moves on every command that can change when the current action ends or what
        #: follows it (see :meth:`steady_until`).
        self.revision = 0
        self._parts_count = 0
        self._parts_total = 0
        self._operating_time = 0.0
        self._cutting_time = 0.0
        self._cycle_time = 0.0
        #: The waiting M codes of the control this engine is a path of (None: one path).
        self.sync = sync
        self.path_number = sync.join(self) if sync is not None else 1
        #: At a waiting M code: when the engine arrived, when the wait ends once every path
        #: of it arrived (None until then), and the PS0160 detail of a mismatch.
        self.sync_arrival = 0.0
        self.released_at: float | None = None
        self.sync_mismatch: str | None = None

    # --- commands -------------------------------------------------------------------------

    def cycle_start(self, *, since: float | None = None) -> None:
        """Start the main program from its head (reset), continue it (stop) or resume it
        (hold). Refused with an alarm active or without a main program.

        ``since`` (from reset only): the machine time the cycle started, earlier than now
        for a machine that has been at work for a while when it is first read; the next
        read runs the program from then."""
        self.advance()
        self.revision += 1
        if self._alarm is not None:
            raise NcStateError(f"cycle start refused: alarm {self._alarm.code} is active")
        if self._state is CycleState.START:
            return
        self.interpreter.message = None  # a stop's message goes with the cycle start
        if self._state is CycleState.RESET:
            main = self.store.find(self.store.main) if self.store.main is not None else None
            if main is None:
                raise NcStateError("cycle start refused: no main program is selected")
            self.interpreter.rewind(main)
            self.interpreter.position = list(self._position)
            self._cycle_time = 0.0
            if since is not None:
                if not math.isfinite(since):
                    raise ValueError(f"a cycle starts at a finite machine time, got {since!r}")
                self._time = min(self._time, since)
        self._state = CycleState.START

    def feed_hold(self) -> None:
        """Stop the axes where they are; cycle start resumes."""
        self.advance()
        self.revision += 1
        if self._state is CycleState.START:
            self._state = CycleState.HOLD

    def select_program(self, number: int) -> None:
        """A program search: ``number`` becomes the main program (``store.select``, refused
        the same way) and, as on a control, the sequence number goes back to 0 (``N00000``;
        the one shown belonged to the program run before)."""
        self.advance()
        self.store.select(number)
        if self._state is CycleState.RESET:
            self.interpreter.sequence = None
        self.revision += 1

    def apply_settings(self, settings: NcSettings) -> None:
        """Go on with ``settings`` (the same axes), as a control applies a parameter written
        while it runs: a motion under way keeps the limits it was planned with, the next
        block uses the new ones."""
        if settings.axes != self.settings.axes:
            raise ValueError(f"settings for axes {settings.axes}, not {self.settings.axes}")
        self.settings = settings
        self.interpreter.settings = settings

    def reset(self) -> None:
        """Stop, clear the alarm, rewind to the head of the main program; the spindle and
        coolant stop."""
        self.advance()
        self.revision += 1
        self._stop_motion()
        self._state = CycleState.RESET
        self._alarm = None
        self._single_block_pending = False
        it = self.interpreter
        it.rewind(None)
        it.message = None
        it.spindle = 5
        it.coolant = False
        it.position = list(self._position)

    def program_stop(self) -> None:
        """Stop the cycle where it is, as M0 would (STOP; cycle start goes on from there)."""
        self.advance()
        self.revision += 1
        if self._state in (CycleState.START, CycleState.HOLD):
            self._state = CycleState.STOP

    def alarm_stop(self, alarm: NcAlarm) -> None:
        """An alarm raised outside the program (emergency stop, a servo or PMC alarm): the
        cycle stops as for a program error, and cycle start is refused until reset."""
        self.advance()
        self.revision += 1
        self._stop_motion()
        self._alarm = alarm
        if self._state is not CycleState.RESET:
            self._state = CycleState.STOP

    def set_feed_override(self, percent: float) -> None:
        self.feed_override = percent

    def set_rapid_override(self, percent: float) -> None:
        self.rapid_override = percent

    @property
    def feed_override(self) -> float:
        """Feed override (0..254 %), which scales the cutting feeds from now on."""
        return self._feed_override

    @feed_override.setter
    def feed_override(self, percent: float) -> None:
        value = _percent(percent, 0, 254, "feed override")
        self.advance()
        self._feed_override = value
        self.revision += 1

    @property
    def rapid_override(self) -> float:
        """Rapid traverse override (0..100 %)."""
        return self._rapid_override

    @rapid_override.setter
    def rapid_override(self, percent: float) -> None:
        value = _percent(percent, 0, 100, "rapid override")
        self.advance()
        self._rapid_override = value
        self.revision += 1

    def set_spindle_override(self, percent: float) -> None:
        self.advance()
        self.spindle_override = _percent(percent, 0, 254, "spindle override")

    @property
    def spindle_override(self) -> float:
        """Percent, read by the spindle speed (and a lathe's feed per revolution)."""
        return self.interpreter.spindle_override

    @spindle_override.setter
    def spindle_override(self, percent: float) -> None:
        self.interpreter.spindle_override = percent

    def set_optional_stop(self, on: bool) -> None:
        self.advance()
        self.interpreter.optional_stop = on

    def set_block_delete(self, on: bool) -> None:
        self.advance()
        self.interpreter.block_delete = on

    def set_single_block(self, on: bool) -> None:
        self.advance()
        self.revision += 1
        self.single_block = on

    def preset_relative(self, axis: int, value: float = 0.0) -> None:
        """Set the relative position of ``axis`` (0-based) to ``value``."""
        self.advance()
        self._relative_origin[axis] = self._current()[axis] - value

    def take_events(self) -> list[EngineEvent]:
        """The events since the last call, oldest first."""
        self.advance()
        events, self.events = self.events, []
        return events

    # --- reads ----------------------------------------------------------------------------

    @property
    def alarm(self) -> NcAlarm | None:
        """The alarm that stopped the cycle (cleared by reset)."""
        self.advance()
        return self._alarm

    @property
    def parts_count(self) -> int:
        """Parts counted by M2/M30 (parameter 6711)."""
        self.advance()
        return self._parts_count

    @parts_count.setter
    def parts_count(self, value: int) -> None:
        self.advance()
        self._parts_count = value

    @property
    def parts_total(self) -> int:
        """Total parts (parameter 6712)."""
        self.advance()
        return self._parts_total

    @parts_total.setter
    def parts_total(self, value: int) -> None:
        self.advance()
        self._parts_total = value

    @property
    def operating_time(self) -> float:
        """Seconds of automatic operation (cycle start, not hold or stop)."""
        self.advance()
        return self._operating_time

    @property
    def cutting_time(self) -> float:
        """Seconds of cutting feed (G1/G2/G3 moving)."""
        self.advance()
        return self._cutting_time

    @property
    def cycle_time(self) -> float:
        """Seconds of automatic operation since the cycle start from reset."""
        self.advance()
        return self._cycle_time

    @property
    def state(self) -> CycleState:
        self.advance()
        return self._state

    @property
    def motion(self) -> MotionKind:
        return self.flags()[1]

    @property
    def sync_wait(self) -> Sync | None:
        """The waiting M code the engine stands at (None: none), as it was last brought to
        its time."""
        action = self._action
        return action if isinstance(action, Sync) else None

    @property
    def waiting(self) -> bool:
        """Whether an M, S or T function is waiting for its completion (FIN)."""
        self.advance()
        action = self._action
        return self._state is CycleState.START and isinstance(action, Wait) and action.fin

    def flags(self) -> tuple[CycleState, MotionKind, bool]:
        """:attr:`state`, :attr:`motion` and :attr:`waiting` at once, from one advance."""
        self.advance()
        state, action = self._state, self._action
        if state is not CycleState.START or action is None:
            return state, MotionKind.NONE, False
        if isinstance(action, Wait):
            return state, MotionKind.NONE, action.fin
        if isinstance(action, Sync):
            return state, MotionKind.WAIT, False
        return state, MotionKind.DWELL if isinstance(action, Dwell) else MotionKind.MOTION, False

    def steady_until(self) -> float:
        """The machine time before which time alone changes none of :meth:`flags` and
        raises no event: the end of the current action at the current overrides; infinite
        while the cycle does not run (or a zero override holds the action); until a command
        (:attr:`revision` moves). Brings the engine to the clock's time first."""
        self.advance()
        if self._state is not CycleState.START:
            return math.inf
        action = self._action
        if action is None:  # between actions: the next advance takes one
            return -math.inf
        if isinstance(action, Sync):  # until the other paths arrive (they say when)
            end = self.released_at
            return math.inf if end is None else max(end, self._time)
        rate = self._rate(action)
        if rate <= 0:
            return math.inf
        return self._time + (self._limit - self._progress) / rate

    def machine_position(self) -> Vector:
        self.advance()
        return self._current()

    def absolute_position(self) -> Vector:
        """Work coordinates: machine position less the offsets of the current block."""
        current = self.machine_position()
        it = self.interpreter
        return tuple(p - it.offset(i) for i, p in enumerate(current))

    def relative_position(self) -> Vector:
        current = self.machine_position()
        return tuple(p - o for p, o in zip(current, self._relative_origin, strict=True))

    def distance_to_go(self) -> Vector:
        current = self.machine_position()
        action = self._action
        if not isinstance(action, Motion):
            return (0.0,) * len(current)
        end = action.at(self._limit)
        return tuple(e - c for e, c in zip(end, current, strict=True))

    @property
    def actual_feed(self) -> float:
        """mm/min along the path now (0 when not moving)."""
        self.advance()
        action = self._action
        if self._state is not CycleState.START or not isinstance(action, Motion):
            return 0.0
        return action.speed(self._progress) * self._rate(action)

    @property
    def cutting(self) -> bool:
        """Whether a cutting feed (G1/G2/G3) is moving the axes now."""
        self.advance()
        action = self._action
        return (
            self._state is CycleState.START
            and isinstance(action, Motion)
            and not action.rapid
            and self._progress < self._limit
        )

    def axis_speeds(self) -> Vector:
        """mm/min of each axis now (unsigned; 0 when not moving)."""
        self.advance()
        action = self._action
        n = len(self._position)
        if self._state is not CycleState.START or not isinstance(action, Motion):
            return (0.0,) * n
        p, end = self._progress, self._limit
        if p >= end:
            return (0.0,) * n
        h = min(_SPEED_STEP, end - p)
        a, b = action.at(p), action.at(p + h)
        scale = 60.0 * self._rate(action) / h
        return tuple(abs(y - x) * scale for x, y in zip(a, b, strict=True))

    @property
    def actual_spindle_speed(self) -> float:
        self.advance()
        it = self.interpreter
        action = self._action
        if self._state is CycleState.START and isinstance(action, RapidMove):
            # G96 in a rapid block: the surface speed of the block's end point, as FANUC
            return it.spindle_speed([p - it.offset(i) for i, p in enumerate(action.end)])
        return it.spindle_speed(self.absolute_position())

    @property
    def program_number(self) -> int | None:
        """The program being executed (the main program when reset)."""
        self.advance()
        program = self.interpreter.program
        return program.number if program is not None else self.store.main

    @property
    def sequence_number(self) -> int | None:
        self.advance()
        return self.interpreter.sequence

    def modal_groups(self) -> dict[int, float | None]:
        """Groups 1..30 as #4001-#4030 read them (``None``: a group not modelled)."""
        self.advance()
        return {g: self.interpreter.read(4000 + g) for g in range(1, 31)}

    # --- the lazy advance -----------------------------------------------------------------

    def advance(self, until: float | None = None) -> None:
        """Bring the state to the clock's time (every read and command calls this), or to
        machine time ``until`` (another path at a waiting M code brings this one to its
        moment)."""
        now = self.clock.now() if until is None else until
        if now <= self._time and (self._action is not None or self._state is not CycleState.START):
            return
        budget = 1_000_000  # blocks per advance: bounds a read whatever the program
        while budget > 0 and self._state is CycleState.START:
            if self._time >= now and self._action is not None:
                break
            if self._action is None:
                budget -= 1
                if not self._next():
                    continue
                if self._action is None:
                    continue
            if isinstance(self._action, Sync):
                if self._through_wait(now):
                    continue
                break
            rate = self._rate(self._action)
            if rate <= 0:
                break
            remaining = (self._limit - self._progress) / rate
            if self._time + remaining <= now:
                self._account(remaining)
                self._time += remaining
                self._progress = self._limit
                self._finish()
            else:
                dt = now - self._time
                self._account(dt)
                self._progress += dt * rate
                self._time = now
        if self._state is not CycleState.START or self._rate_zero():
            self._time = max(self._time, now)

    def _through_wait(self, now: float) -> bool:
        """At a waiting M code: True once the engine went on past it (the wait ended by
        ``now``), else False with the engine waiting at ``now`` (operating time runs), still
        where it was (the other paths cannot tell yet: it asks again when next brought to a
        moment) or stopped by PS0160."""
        end = 0.0
        if self.sync is not None:
            found = self.sync.release(self, self.path_number, now)
            mismatch = self.sync_mismatch
            if mismatch is not None:
                self._raise(MISMATCH, mismatch, AlarmKind.PS)
                return False
            if isinstance(found, Unknown):
                return False
            if found is None or found > now:
                self._account(now - self._time)
                self._time = now
                return False
            end = found
        if end > self._time:
            self._account(end - self._time)
            self._time = end
        self._progress = self._limit = 0.0
        self._finish()
        return True

    def _rate_zero(self) -> bool:
        return self._action is not None and self._rate(self._action) <= 0

    def _rate(self, action: Action) -> float:
        if self._state is not CycleState.START:
            return 0.0
        if isinstance(action, Motion):
            return (self._rapid_override if action.rapid else self._feed_override) / 100.0
        return 1.0

    def _account(self, dt: float) -> None:
        self._operating_time += dt
        self._cycle_time += dt
        action = self._action
        if isinstance(action, Motion) and not action.rapid:
            self._cutting_time += dt

    def _current(self) -> Vector:
        action = self._action
        if isinstance(action, Motion):
            return action.at(self._progress)
        return self._position

    def _stop_motion(self) -> None:
        self._position = self._current()
        self._action = None
        self.released_at = None
        self.sync_mismatch = None
        self._queue.clear()
        self._progress = self._limit = 0.0
        self._overtravel = None

    def _raise(self, number: int, detail: str, kind: AlarmKind, axis: int | None = None) -> None:
        it = self.interpreter
        program = it.program
        message = ALARM_MESSAGES.get((kind, number), "MACRO ALARM" if kind is AlarmKind.MC else "")
        if kind is AlarmKind.MC:
            message, detail = detail or message, ""
        alarm = NcAlarm(
            kind,
            number,
            message,
            program.number if program is not None else None,
            it.sequence,
            axis,
            detail,
        )
        self._stop_motion()
        self._alarm = alarm
        self._state = CycleState.STOP
        self.events.append(EngineEvent(self._time, "alarm", number, alarm))

    def _next(self) -> bool:
        """Take the next action (stepping the interpreter when the queue is empty); False
        when the engine stopped instead."""
        if not self._queue:
            if self._single_block_pending and self.single_block:
                self._single_block_pending = False
                self._state = CycleState.STOP
                return False
            try:
                step = self.interpreter.step()
            except AlarmRaised as e:
                self._raise(e.number, e.detail, e.kind)
                return False
            except (ArithmeticError, ValueError, IndexError, KeyError) as e:  # pragma: no cover
                self._raise(114, f"{type(e).__name__}: {e}", AlarmKind.PS)
                return False
            self._single_block_pending = step.nc_block
            self._queue.extend(step.actions)
            if all(map(_instant, step.actions)):  # none, or dwells of 0 s: no time
                self._zero_steps += 1
                if self._zero_steps > self.settings.zero_time_blocks:
                    self._queue.append(Wait(self.settings.busy_block_time, BUSY))
                elif not step.actions:
                    return True
        action = self._queue.popleft()
        if isinstance(action, Stop):
            self._state = CycleState.STOP
            self._single_block_pending = False
            return False
        if isinstance(action, ProgramEnd):
            short = self._short_part(action)
            if short <= 1e-9:
                self._end(action)
                return False
            self._queue.appendleft(action)  # after the rest of the part's least time
            action = Wait(short, BUSY)
        if not (isinstance(action, Wait) and not action.fin) and not _instant(action):
            self._zero_steps = 0
        self._start(action)
        return True

    def _start(self, action: Action) -> None:
        self._action = action
        self._progress = 0.0
        duration = action.duration if isinstance(action, Motion) else 0.0
        if isinstance(action, Dwell | Wait):
            duration = action.seconds
        elif isinstance(action, Sync):
            duration = math.inf  # until the other paths arrive
            self.sync_arrival = self._time
            self.released_at = None
            self.sync_mismatch = None
        self._limit = duration
        self._overtravel = None
        if isinstance(action, Motion):
            self._check_stroke(action)
        if isinstance(action, Wait) and action.code.startswith("M6"):
            self.events.append(EngineEvent(self._time, "tool", self.interpreter.tool))

    def _finish(self) -> None:
        action = self._action
        if isinstance(action, Motion):
            self._position = action.at(self._limit)
        elif isinstance(action, Sync):
            self.released_at = None
        self._action = None
        if self._overtravel is not None:
            alarm = self._overtravel
            self._raise(alarm.number, alarm.detail, alarm.kind, alarm.axis)

    def _short_part(self, action: ProgramEnd) -> float:
        """In production (:attr:`repeat`), the seconds a part ending at ``action`` (M2/M30)
        lacks to the time of M30's FIN (``m_function_time``): a part takes at least that, so
        that a program of (almost) no machine time counts its parts as time goes rather than
        without end at one instant. 0 otherwise."""
        if not self.repeat or action.code is None:
            return 0.0
        return self.settings.m_function_time - self._cycle_time

    def _end(self, action: ProgramEnd) -> None:
        if action.code is not None:
            self._parts_count += 1
            self._parts_total += 1
            self.events.append(EngineEvent(self._time, "part", self._parts_count))
        self.events.append(EngineEvent(self._time, "end", action.code or 0))
        self._stop_motion()
        self._state = CycleState.RESET
        it = self.interpreter
        it.rewind(None)
        it.message = None
        it.spindle = 5
        it.coolant = False
        it.position = list(self._position)
        main = self.store.find(self.store.main) if self.store.main is not None else None
        if self.parts_to_go is not None and action.code is not None:
            self.parts_to_go = max(0, self.parts_to_go - 1)
        more = self.parts_to_go is None or self.parts_to_go > 0
        if self.repeat and more and action.code is not None and main is not None:
            # production: the next part starts at once, from the head of the main program
            it.rewind(main)
            it.position = list(self._position)
            self._cycle_time = 0.0
            self._state = CycleState.START

    def _check_stroke(self, motion: Motion) -> None:
        """Cut the motion short where it would leave a stroke limit: the axis stops on the
        limit and the overtravel alarm follows (OT0500 plus side, OT0501 minus side)."""
        limits = self.settings.stroke_limits
        if all(limit is None for limit in limits):
            return

        def outside(p: float) -> tuple[int, int] | None:
            for i, (value, limit) in enumerate(zip(motion.at(p), limits, strict=True)):
                if limit is None:
                    continue
                if value > limit[1] + 1e-9:
                    return i, 500
                if value < limit[0] - 1e-9:
                    return i, 501
            return None

        points = motion.critical()
        previous = 0.0
        if outside(0.0) is not None:
            points = [0.0]
        for p in points:
            hit = outside(p)
            if hit is None:
                previous = p
                continue
            lo, hi = previous, p
            if lo < hi:
                for _ in range(60):
                    mid = (lo + hi) / 2
                    if outside(mid) is None:
                        lo = mid
                    else:
                        hi = mid
            hit = outside(hi) or hit
            axis, number = hit
            name = self.settings.axes[axis]
            limit = limits[axis]
            assert limit is not None
            side = limit[1] if number == 500 else limit[0]
            self._limit = lo
            self._overtravel = NcAlarm(
                AlarmKind.OT,
                number,
                ALARM_MESSAGES[(AlarmKind.OT, number)],
                axis=axis + 1,
                detail=f"{name} would pass its stroke limit {number_text(side)}",
            )
            return

    def _in_use(self) -> frozenset[int]:
        if self._state is CycleState.RESET:
            return frozenset()
        return self.interpreter.programs_in_use()


#: Nominal seconds over which :meth:`Engine.axis_speeds` measures the axes' speed.
_SPEED_STEP: Final = 0.01


def _percent(value: float, low: float, high: float, what: str) -> float:
    if not (math.isfinite(value) and low <= value <= high):
        raise ValueError(f"{what} is {low:g}..{high:g} %, got {value!r}")
    return float(value)


def _instant(action: Action) -> bool:
    """A dwell of no time (``G4 P0``): a block of no time, as one without actions."""
    return isinstance(action, Dwell) and action.seconds <= 0
