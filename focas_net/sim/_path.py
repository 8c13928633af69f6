"""One path of the machine: its programs, its NC engine on the machine's time, its operator
panel and status, its motion figures and its production (:mod:`._production`).

A FANUC control with several paths (a twin-turret lathe) runs one program on each, each with
its own mode, status and program alarms, while the PMC, most parameters, the macro variables
#500-#999 and the alarm history are shared: a :class:`Path` is given those (the parameters as
it sees them: :class:`~._paths.PathItems`), and owns the rest. The machine answers every read
and command of a path through the path (:mod:`._paths` holds the collection).

Nothing ticks: every read and every counter of the machine first brings the engine to the
clock's time (:meth:`Path.sync`, the engine's clock held there while the path reads it):
program alarms go into the active alarms and the history, parts into parameters 6711/6712;
while a program runs, the motion and macro counters move whenever time moved, so no front end
serves a cached answer of a moving machine. The engine keeps one clock object for life
(:class:`MachineTime`): :meth:`Machine.set_clock` changes where it reads the time from.

Which figures are shown: those of the constructor (the ``[motion]`` table) and of
``Machine.set_motion`` / ``Machine.set_run`` until the first cycle start or program selection;
from then on the engine's, until ``set_motion`` or ``set_run`` is called again.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from decimal import Decimal
from typing import Final

from focas_net._refusals import SEARCH, axis_past, mode_refusal, not_ready, parts_refusal
from focas_net._typed import override_percent, override_unfit
from focas_net.errors import EW

from ._alarms import MAX_ALARM_TEXT, NC_ALARM_TYPES, AlarmKey, Alarms, nc_alarm
from ._base import I32_MAX, I32_MIN, Counters, MachineError, logger, n_values, need_int, need_text
from ._items import PARTS_COUNT, PARTS_TOTAL, Items
from ._macros import Macros, float_macro, macro_value
from ._paths import PATH_MACROS, PathItems
from ._pmc import GRequest, Pmc
from ._production import Production
from ._status import (
    AUT_MODES,
    EDIT,
    MEM,
    MOTION_NUMBERS,
    POSITION_DECIMALS,
    POSITION_KINDS,
    TIMER_KINDS,
    MotionData,
    Panel,
    Status,
    mode_name,
    switch_unfit,
    unknown_mode,
)
from ._time import MachineTime
from ._variables import PARTS_VARIABLES, PathVariables
from .nc import (
    CycleState,
    Engine,
    EngineEvent,
    MotionKind,
    NcSettings,
    NcStateError,
    ProgramError,
    ProgramErrorReason,
    ProgramStore,
    SimClock,
)
from .nc.alarms import AlarmRaised
from .nc.waits import PathSync

__all__ = [
    "ENGINE_VARIABLES",
    "PARTS_VARIABLES",
    "Path",
    "Shared",
]

#: System variables that come from the engine while it drives the figures: modal G codes
#: #4001-#4030, the last block's codes #4102-#4130, positions #5001-#5043.
ENGINE_VARIABLES: Final = (range(4001, 4031), range(4102, 4131), range(5001, 5044))

#: The parameters of the lowest and the highest waiting M code.
WAIT_LOW: Final = 8110
WAIT_HIGH: Final = 8111
#: The run state (ODBST ``run``) and motion of each engine state.
_RUN: Final = {CycleState.RESET: 0, CycleState.STOP: 1, CycleState.HOLD: 2, CycleState.START: 3}
#: ODBST ``motion`` 3 (WAIT): the path waits at a waiting M code for the other paths.
_MOTION: Final = {
    MotionKind.NONE: 0,
    MotionKind.MOTION: 1,
    MotionKind.DWELL: 2,
    MotionKind.WAIT: 3,
}
_MM: Final = 10**POSITION_DECIMALS
#: Rapid traverse (mm/min) of an axis whose parameter 1420 gives no positive rate.
_DEFAULT_RAPID: Final = 24000.0
#: The cycle states as plain constants: an enum member read through its class is slow on the
#: read path of every status answer.
_START: Final = CycleState.START
_RESET: Final = CycleState.RESET
_MOTION_SCALARS: Final = tuple(MOTION_NUMBERS)
_SKIP: Final = "skip"
#: The distance to go, as the machine's figures name it.
_DISTANCE: Final = "distance_to_go"
#: The EW code of each refusal of the program store.
_PROGRAM_EW: Final = {
    ProgramErrorReason.FORMAT: EW.DATA,
    ProgramErrorReason.RANGE: EW.NUMBER,
    ProgramErrorReason.DUPLICATE: EW.REJECT,
    ProgramErrorReason.NOT_FOUND: EW.NUMBER,
    ProgramErrorReason.IN_USE: EW.BUSY,
    ProgramErrorReason.NO_SPACE: EW.OVRFLOW,
    ProgramErrorReason.TOO_MANY: EW.OVRFLOW,
}


def _increments(values: Iterable[float]) -> list[int]:
    """Positions in mm as i32 least input increments."""
    return [max(I32_MIN, min(I32_MAX, round(v * _MM))) for v in values]


def _figure(value: float | int | None) -> int:
    return 0 if value is None else max(0, min(I32_MAX, round(value)))


def _system_value(value: float | None, decimals: int) -> Decimal | None:
    """A system variable the engine reads as a float, as the machine shows it: positions
    with 3 decimals, codes as integers (40.1: one decimal)."""
    if value is None:
        return None
    if decimals:
        return Decimal(round(value * _MM)).scaleb(-decimals)
    if value == int(value):
        return Decimal(int(value))
    return float_macro(value)


def program_axes(axes: list[str]) -> tuple[str, ...]:
    """The addresses a path's programs move its axes by: the axis names without the subscript
    digits a multi-path control shows (X1 and Z1 of path 1 are programmed X and Z, as FANUC's
    parameter 1020 names them and 3131 subscripts them), or the names as they are when that
    would name two axes alike."""
    bare = tuple(a.rstrip("0123456789") or a for a in axes)
    return bare if len(set(bare)) == len(bare) else tuple(axes)


def _program_refusal(exc: ProgramError) -> MachineError:
    return MachineError(_PROGRAM_EW[exc.reason], str(exc))


@dataclass(frozen=True, slots=True)
class Shared:
    """What the paths of a machine share: its version counters, its parameters (as each path
    sees them: :class:`~._paths.PathItems`), its macro variables, its alarms and its PMC."""

    counters: Counters
    items: Items
    macros: Macros
    alarms: Alarms
    pmc: Pmc


class Path:
    """One path: its program store, its engine, its panel, its figures, its production
    (``panel`` and ``motion`` checked by the machine), and what it shares with the machine's
    other paths (:class:`Shared`).

    The machine's version counters read :attr:`live` first: while it is false, time alone
    changes nothing the path shows (every command that starts or changes the cycle settles
    the counters itself)."""

    __slots__ = (
        "_figures",
        "alarms",
        "axes",
        "counters",
        "driven",
        "engine",
        "engine_alarms",
        "group",
        "items",
        "key",
        "lathe",
        "listeners",
        "live",
        "local_macros",
        "macros",
        "manual",
        "mstb",
        "name",
        "number",
        "panel",
        "pmc",
        "powered_at",
        "production",
        "programs",
        "steady_revision",
        "steady_until",
        "synced_at",
        "time",
    )

    def __init__(
        self,
        name: str,
        axes: list[str],
        shared: Shared,
        *,
        number: int = 1,
        lathe: bool = False,
        items: PathItems | None = None,
        sync: PathSync | None = None,
        path_count: int = 1,
        panel: Panel,
        motion: MotionData,
        programs: Iterable[str],
        main_program: int | None,
        clock: SimClock,
    ) -> None:
        self.name = name
        self.axes = axes
        #: The path's number (1..), and whether it is a lathe's (T series).
        self.number = number
        self.lathe = lathe
        self.counters = shared.counters
        self.items = items or PathItems(shared.items, 0, len(axes), {})
        self.macros = shared.macros
        #: The values of the path's own variables #1-#33, #100-#199 (path 1: the machine's).
        self.local_macros = shared.macros.values if number == 1 else {}
        self.alarms = shared.alarms
        self.pmc = shared.pmc
        self.panel = panel
        #: The figures given to the constructor or by hand (shown until :attr:`driven`).
        self.manual = motion
        self.time = MachineTime(clock)
        self.powered_at = self.time.now()
        #: The programs in the path's memory (the engine marks those in use).
        self.programs = ProgramStore()
        first: int | None = None
        for text in programs:
            number = self.programs.store(text).number
            first = number if first is None else first
        self.engine = Engine(
            self.time,
            self._nc_settings(path_count),
            store=self.programs,
            variables=PathVariables(self, self.macros),
            sync=sync,
        )
        self.engine.parts_count = self.items.param_or(PARTS_COUNT, 0)
        self.engine.parts_total = self.items.param_or(PARTS_TOTAL, 0)
        main = need_int("main_program", main_program) if main_program is not None else first
        if main is not None:
            self.programs.select(main)
            if motion.program_running == motion.program_main == 0:
                # The figures name no program: they show the selected one, as a control does.
                self.manual = replace(motion, program_running=main, program_main=main)
        #: Whether the engine shows the run state and the figures (see ``Machine.driven``).
        self.driven = False
        #: Whether time alone may change what the path shows: the cycle runs or a scenario
        #: drives the path.
        self.live = False
        self.synced_at = math.nan
        #: Until this machine time (and while the engine's revision is this one) time alone
        #: changes nothing of the status (see ``Machine.status_version``).
        self.steady_until = -math.inf
        self.steady_revision = -1
        #: The engine's state and motion as last settled, and its FIN wait (ODBST ``mstb``).
        self.key = (_RESET, MotionKind.NONE)
        self.mstb = 0
        #: The active alarms the program raised (a reset clears them).
        self.engine_alarms: set[AlarmKey] = set()
        self._figures: tuple[int, MotionData] | None = None
        #: Every path of the machine, this one among them (the machine sets it).
        self.group: list[Path] = [self]
        self.production = Production(self)
        #: Called with every event the engine reports, after the path recorded it.
        self.listeners: list[Callable[[EngineEvent, float], None]] = []

    def macro_values(self, number: int) -> dict[int, Decimal]:
        """Where variable ``number``'s value is held: the path's own #1-#33 and #100-#199 (the
        ones its program reads and writes), else the machine's."""
        return self.local_macros if number in PATH_MACROS else self.macros.values

    @staticmethod
    def check_motion(motion: MotionData, axes: int) -> None:
        """ValueError unless each position list has one value per axis (for machine
        builders)."""
        for key in POSITION_KINDS:
            if len(getattr(motion, key)) != axes:
                raise ValueError(f"motion {key}: {n_values(len(getattr(motion, key)), axes)}")

    def take_settings(self) -> None:
        """The settings again after a write of one of them (``SETTING_PARAMS``): from the next
        block, as on a control (none of them needs the power turned off)."""
        self.engine.apply_settings(self._nc_settings(len(self.group)))

    def _nc_settings(self, path_count: int) -> NcSettings:
        """Execution settings from the parameters (again on a write: :meth:`take_settings`):
        rapid 1420 (mm/min; an axis whose rate is not above 0 traverses at 24,000), maximum
        feed 1422, stroke limit 1 1320/1321 (0.001 mm, or mm for a real parameter; no limit on
        an axis where plus is not above minus), reference position 1240; on a machine of
        several paths the waiting M codes 8110..8111 (none unless both are above 0 and the
        lowest is not above the highest)."""
        items = self.items
        axes = range(1, len(self.axes) + 1)
        rapid = tuple(
            rate if rate > 0 else _DEFAULT_RAPID
            for rate in (items.param_float(1420, _DEFAULT_RAPID, a, 1.0) for a in axes)
        )
        limits: list[tuple[float, float] | None] = []
        for a in axes:
            plus = items.param_float(1320, 0.0, a, 1 / _MM)
            minus = items.param_float(1321, 0.0, a, 1 / _MM)
            limits.append((minus, plus) if plus > minus else None)
        reference = tuple(items.param_float(1240, 0.0, a, 1 / _MM) for a in axes)
        values: dict[str, object] = {
            "lathe": self.lathe,
            "rapid_rates": rapid,
            "stroke_limits": tuple(limits),
            "reference": reference,
        }
        feed = items.param_float(1422, 0.0, 0, 1.0)  # mm/min, a real one's value as it reads
        if feed > 0:
            values["max_cutting_feed"] = feed
        low, high = items.param_or(WAIT_LOW, 0), items.param_or(WAIT_HIGH, 0)
        if path_count > 1 and 0 < low <= high:
            values["waiting_m"] = (low, high)
            values["path_number"] = self.number
            values["path_count"] = path_count
        return NcSettings.for_axes(program_axes(self.axes), **values)

    # -- time ----------------------------------------------------------------------------
    def check_clock(self, clock: SimClock) -> None:
        """ValueError when ``clock`` is behind the path's machine time."""
        self.time.check(clock)

    def set_clock(self, clock: SimClock) -> None:
        self.check_clock(clock)
        self.time.set_source(clock)

    def sync(self) -> None:
        """Bring the engine to the clock's time: apply a scenario's due events, record the
        program's alarms and parts, and move the counters of what the engine shows. Costs one
        comparison while not :attr:`live`, a clock call when the time has not moved or a
        scenario's next event is not due."""
        run = self.production.run
        if self.key[0] is not _START:
            if run is None:
                return
            now = self.time.now()
            if now < run.next_time or now == self.synced_at:
                return
        else:
            now = self.time.now()
            if now == self.synced_at:
                return
        self.synced_at = now
        e = self.engine
        self.time.hold(now)  # the engine advances once, however many figures are read
        try:
            moved = self.key[0] is _START
            if run is not None and run.next_time <= now:
                run.play(now)
                moved = True
            self.settled(moved)
            if run is not None and run.finished(e):
                self.production.run = None
                self.moving()
        finally:
            self.time.release()

    def settled(self, moved: bool, force: bool = False) -> None:
        """Take the engine's state after a command or a sync, record what it reported on the
        way (a cycle start runs the blocks that take no time at once: an error in the first
        block, an M30 alone), and move the counters of what changed: while :attr:`driven`,
        the figures and the system variables whenever time ``moved``, the status when the
        state did (``force``: all of them)."""
        e = self.engine
        state, motion, wait = e.flags()
        events = e.take_events()
        if events:
            now = self.time.now()
            for event in events:
                self.engine_event(event, now)
                for listen in self.listeners:
                    listen(event, now)
        key = (state, motion)
        changed = key != self.key
        self.key = key
        waiting = 1 if wait else 0
        if waiting != self.mstb:
            self.mstb = waiting
            changed = True
        if self.driven:  # the F signals of the run state (as :meth:`show_cycle`)
            self.pmc.show_cycle(state, self.number)
        steady = e.steady_until()
        run = self.production.run
        if run is not None and run.next_time < steady:
            steady = run.next_time
        self.steady_until = steady
        self.steady_revision = e.revision
        self.live = state is _START or run is not None  # as :meth:`moving`
        if force or (self.driven and (changed or moved)):
            c = self.counters
            c.motion += 1
            c.macro += 1
            c.version += 1
            if force or changed:
                c.status += 1

    def moving(self) -> None:
        """Set :attr:`live` from the settled state and the production."""
        self.live = self.key[0] is _START or self.production.run is not None

    def show_cycle(self) -> None:
        """The F signals of the run state, while the engine drives the path (before, F is as
        written)."""
        if self.driven:
            self.pmc.show_cycle(self.key[0], self.number)

    def engine_event(self, event: EngineEvent, now: float) -> None:
        """Record what the engine reports at machine time ``now``: a part into the parts
        parameters, an alarm into the machine's alarms (stamped when it was raised) and the
        log with the words of the block that raised it (a warning: the alarm screen, the
        history and the page show FANUC's message alone)."""
        if event.kind == "part":
            self._store_parts(PARTS_COUNT, self.engine.parts_count)
            self._store_parts(PARTS_TOTAL, self.engine.parts_total)
        elif event.kind == "alarm" and event.alarm is not None:
            alarm = event.alarm
            logger.warning("%s: %s", self.name, alarm)
            key = (alarm.axis or 0, NC_ALARM_TYPES[alarm.kind], alarm.number)
            text = alarm.message[:MAX_ALARM_TEXT].encode("latin-1", "replace").decode("latin-1")
            stamp = self.alarms.stamp(now - event.time)
            if self.alarms.add(key, text, stamp, self.number):
                self.engine_alarms.add(key)

    # -- parts ---------------------------------------------------------------------------
    def parts(self, number: int) -> int:
        return self.engine.parts_count if number == PARTS_COUNT else self.engine.parts_total

    def _store_parts(self, number: int, value: int) -> None:
        if self.items.clamp(number, value):
            self.counters.macro += 1

    def set_parts(self, number: int, value: int) -> None:
        """Set the parts count or the total parts (parameter ``number``)."""
        if number == PARTS_COUNT:
            self.engine.parts_count = value
        else:
            self.engine.parts_total = value
        self._store_parts(number, value)

    def write_parts(self, variable: int, value: Decimal | int | None) -> None:
        """Write the parts count or the total parts through its macro variable: EW_DATA for
        anything but a whole number >= 0."""
        if value is None:  # in the words the clients' sim.vacate_macro gives
            raise MachineError(EW.DATA, parts_refusal(variable, None))
        held = macro_value(value)
        if held is None or held != held.to_integral_value() or held < 0:
            raise MachineError(EW.DATA, parts_refusal(variable, value))
        self.set_parts(PARTS_VARIABLES[variable], int(held))

    # -- status and panel ----------------------------------------------------------------
    def status(self, alarm: int) -> Status:
        """The status once synced; ``alarm`` is the machine's alarm flag."""
        p = self.panel
        run, motion, mstb = p.run, p.motion, p.mstb
        if self.driven:
            run, motion = _RUN[self.key[0]], _MOTION[self.key[1]]
            mstb = self.mstb
        return Status(p.hdck, p.tmmode, p.mode, run, motion, mstb, p.emergency, alarm, p.edit)

    def set_panel(self, mode: int | None, pwe: int | None, emergency: int | None) -> None:
        """Switch the panel (None: as it is): EW_DATA for a value it has not; leaving MEM
        holds the feed, the emergency stop resets."""
        p = self.panel
        mode = p.mode if mode is None else mode
        pwe = p.pwe if pwe is None else pwe
        emergency = p.emergency if emergency is None else emergency
        if mode not in AUT_MODES:
            raise MachineError(EW.DATA, unknown_mode(mode))
        for name, value in (("pwe", pwe), ("emergency", emergency)):
            if value not in (0, 1):
                raise MachineError(EW.DATA, switch_unfit(name, value))
        self.sync()
        leaving_mem = p.mode == MEM and mode != MEM
        stop = emergency and not p.emergency
        p.mode, p.pwe, p.emergency = mode, pwe, emergency
        logger.debug("%s: panel mode %d pwe %d emergency %d", self.name, mode, pwe, emergency)
        if stop:
            self.engine.reset()  # emergency stop resets the control
        elif leaving_mem:
            self.engine.feed_hold()  # automatic operation stops outside MEM
        self.counters.status_changed()
        self.settled(bool(stop or leaving_mem))

    def set_run(self, run: int, motion: int) -> None:
        """The run state and motion the status shows by hand: EW_DATA for a value it has not."""
        if run not in range(5):
            raise MachineError(EW.DATA, f"run is 0..4, got {run}")
        if motion not in range(3):
            raise MachineError(EW.DATA, f"motion is 0..2, got {motion}")
        self.panel.run, self.panel.motion = run, motion
        self.driven = False
        self.counters.status_changed()

    # -- motion figures ------------------------------------------------------------------
    def set_motion(
        self, positions: tuple[Iterable[int] | None, ...], scalars: tuple[int | None, ...]
    ) -> None:
        """Set the figures given (positions in :data:`POSITION_KINDS` order, then the
        scalars): EW_DATA, nothing changed, when a value does not fit."""
        n = len(self.axes)
        lists: dict[str, list[int]] = {}
        for key, values in zip(POSITION_KINDS, positions, strict=True):
            if values is None:
                continue
            if isinstance(values, str | bytes) or not isinstance(values, Iterable):
                raise TypeError(f"{key} must be a list of integers, got {values!r}")
            got = [need_int(f"{key}[{i}]", v) for i, v in enumerate(values)]
            if len(got) != n or not all(I32_MIN <= v <= I32_MAX for v in got):
                raise MachineError(EW.DATA, f"{key}: {n} i32 values expected, got {got!r}")
            lists[key] = got
        numbers: dict[str, int] = {}
        for key, value in zip(_MOTION_SCALARS, scalars, strict=True):
            if value is None:
                continue
            low, high = MOTION_NUMBERS[key]
            if not low <= need_int(key, value) <= high:
                raise MachineError(EW.DATA, f"{key} = {value!r} outside {low}..{high}")
            numbers[key] = value
        m = self.manual
        self.sync()
        if self.driven:
            self.driven = False
            self.counters.status_changed()
        for key, got in lists.items():
            setattr(m, key, got)
        for key, number in numbers.items():
            setattr(m, key, number)
        self.counters.motion += 1
        self.counters.version += 1

    def figures(self) -> MotionData:
        """The motion figures: the engine's while it drives them, else the manual ones."""
        if self.live:
            self.sync()
        if not self.driven:
            return self.manual
        version = self.counters.motion
        if self._figures is not None and self._figures[0] == version:
            return self._figures[1]
        e = self.engine
        figures = MotionData(
            _increments(e.absolute_position()),
            _increments(e.machine_position()),
            _increments(e.relative_position()),
            _increments(e.distance_to_go()),
            feed=_figure(e.actual_feed),
            spindle_speed=_figure(e.actual_spindle_speed),
            program_running=_figure(e.program_number),
            program_main=_figure(self.programs.main),
            sequence=_figure(e.sequence_number),
        )
        self._figures = (version, figures)
        return figures

    def positions(self, kind: str, axis: int | None) -> list[tuple[str, int]]:
        """``(axis name, value)`` of every axis or of one: EW_ATTRIB (kind), EW_NOOPT (skip),
        EW_ATTRIB (axis). ``kind`` is read in any case, as the clients read it (ASCII only, as
        every name typed), ``distance`` (and ``-`` for ``_``) as the command line names the
        distance to go."""
        given = need_text("position kind", kind)
        if kind.isascii():
            kind = kind.strip().lower().replace("-", "_")
        kind = _DISTANCE if kind == "distance" else kind  # as the command line names it
        if kind not in POSITION_KINDS:
            if kind == _SKIP:
                raise MachineError(EW.NOOPT, "no skip function")
            raise MachineError(
                EW.ATTRIB,
                f"unknown position kind {given!r} (absolute, machine, relative, distance)",
            )
        values: list[int] = getattr(self.figures(), kind)
        if axis is not None:
            need_int("axis", axis)
        if axis is None:
            return list(zip(self.axes, values, strict=True))
        if not 1 <= axis <= len(self.axes):
            raise MachineError(EW.ATTRIB, axis_past(axis, len(self.axes)))
        return [(self.axes[axis - 1], values[axis - 1])]

    def engine_variable(self, number: int) -> Decimal | None:
        """#4001-#4030, #4102-#4130 and #5001+ (block end) as the interpreter reads them;
        #5021+ (machine) and #5041+ (work coordinates) at the axes' current position."""
        e = self.engine
        n = len(self.axes)
        value: float | None
        if 5021 <= number < 5021 + n:
            value = e.machine_position()[number - 5021]
        elif 5041 <= number < 5041 + n:
            value = e.absolute_position()[number - 5041]
        else:
            try:
                value = e.interpreter.read(number)
            except AlarmRaised:
                return self.macros.values.get(number)
        return _system_value(value, POSITION_DECIMALS if number >= 5001 else 0)

    # -- the cycle -----------------------------------------------------------------------
    def check_ready(self, refused: str) -> None:
        """What automatic operation needs: EW_ALARM (emergency stop, an active alarm),
        EW_MODE (not MEM); ``refused`` begins the message."""
        p, ew = self.panel, None
        if p.emergency or self.alarms.on(self.number):
            ew = EW.ALARM
        elif p.mode != MEM:
            ew = EW.MODE
        if ew is not None:
            why = not_ready(refused, ew, mode=mode_name(p.mode), emergency=bool(p.emergency))
            raise MachineError(ew, why or refused)

    def cycle_start(self, repeat: bool | None) -> None:
        self.sync()
        self.check_ready("cycle start refused")
        if repeat is not None:
            self.engine.repeat = repeat
        try:
            self.engine.cycle_start()
        except NcStateError as exc:
            ew = EW.ALARM if self.engine.alarm is not None else EW.DATA
            raise MachineError(ew, str(exc)) from None
        self.driven = True
        self.settled(True, force=True)

    def feed_hold(self) -> None:
        self.sync()
        self.engine.feed_hold()
        self.settled(True)

    def reset(self) -> None:
        self.sync()
        self.reset_cycle()
        self.settled(True)

    def reset_cycle(self) -> None:
        """The engine reset, the alarms the program raised cleared."""
        self.engine.reset()
        self.alarms.remove(self.engine_alarms, self.number)
        self.engine_alarms.clear()

    def alarm_stop(self, key: AlarmKey, text: str) -> None:
        """An alarm raised outside the program stops the cycle (cycle start wants a reset)."""
        if self.engine.state is not _RESET:
            self.engine.alarm_stop(nc_alarm(key, text))
            self.settled(True)

    def set_overrides(self, feed: int | None, rapid: int | str | None, spindle: int | None) -> None:
        self.sync()
        given: dict[str, int] = {}
        for what, value in (("feed", feed), ("rapid", rapid), ("spindle", spindle)):
            if value is None:
                continue
            given[what] = percent = override_percent(what, value)
            unfit = override_unfit(what, percent)
            if unfit is not None:
                raise MachineError(EW.DATA, unfit)
        e = self.engine
        if "feed" in given:
            e.set_feed_override(given["feed"])
        if "rapid" in given:
            e.set_rapid_override(given["rapid"])
        if "spindle" in given:
            e.set_spindle_override(given["spindle"])
        self.settled(True)

    def apply(self, asked: GRequest) -> None:
        """Act on what a write of G signals asks (the machine checked it may be written): the
        rising edge of ERS resets, the falling edge of *SP holds the feed, a change of the mode
        bits of G43 selects the mode, G12/G14/G30 set the overrides, the falling edge
        of ST starts the cycle (with *SP on). What the CNC refuses (cycle start with an alarm
        ...) is ignored, as a CNC ignores the signal."""
        try:
            if asked.reset:
                self.reset()
            if asked.hold:
                self.feed_hold()
            if asked.mode is not None and asked.mode != self.panel.mode:
                self.set_panel(asked.mode, None, None)
            if asked.overrides != (None, None, None):
                self.set_overrides(*asked.overrides)
            if asked.start:
                self.cycle_start(None)
        except MachineError as exc:
            logger.debug("%s: G signal ignored: %s", self.name, exc)
        self.show_cycle()

    def parts_counts(self) -> tuple[int, int]:
        self.sync()
        return self.engine.parts_count, self.engine.parts_total

    def overrides(self) -> tuple[int, int, int]:
        e = self.engine
        return round(e.feed_override), round(e.rapid_override), round(e.spindle_override)

    def timer(self, kind: int) -> float:
        if not 0 <= kind < len(TIMER_KINDS):
            raise MachineError(EW.NUMBER, f"timer {kind} outside 0..{len(TIMER_KINDS) - 1}")
        self.sync()
        e = self.engine
        if kind == 0:
            return self.time.now() - self.powered_at
        return (e.operating_time, e.cutting_time, e.cycle_time)[kind - 1]

    # -- the program store ---------------------------------------------------------------
    def program_text(self, number: int) -> str:
        try:
            return self.programs.text(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None

    def store_program(self, text: str, replace: bool) -> int:
        self.sync()
        try:
            number = self.programs.store(text, replace=replace).number
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        self._programs_changed()
        return number

    def delete_program(self, number: int) -> None:
        self.sync()
        try:
            self.programs.delete(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        # The figures shown while nothing drives the path name the deleted program no more,
        # as the engine's do (a program search or a cycle makes them name one again).
        m = self.manual
        running, main = (0 if n == number else n for n in (m.program_running, m.program_main))
        self.manual = replace(m, program_running=running, program_main=main)
        self._programs_changed()

    def select_program(self, number: int) -> None:
        self.sync()
        if self.panel.mode not in (MEM, EDIT):
            mode = mode_name(self.panel.mode)
            raise MachineError(EW.MODE, mode_refusal(SEARCH, "MEM or EDIT", mode))
        try:
            self.engine.select_program(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        self.driven = True
        self._programs_changed()
        self.settled(True, force=True)

    def _programs_changed(self) -> None:
        self._figures = None
        self.counters.motion += 1
        self.counters.version += 1
