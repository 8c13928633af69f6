"""The simulated CNC: state and typed operations, in no protocol's terms.

A :class:`Machine` holds everything a FOCAS client can see of one CNC: axes, parameters,
diagnostics, macro variables, PMC areas, the operator panel, an optional parameter password,
active alarms and the alarm history, its identity (what ``cnc_sysinfo`` reports), a VersaMax I/O
station and the motion figures (positions, feed, spindle, program numbers).

Arguments and results are domain values, never wire types or payload bytes: PMC areas by letter
(``"G"``, ``"D"``...) with data of any length, parameter values as ``int``, macro values as
:class:`~decimal.Decimal` (``None`` for a vacant variable), timezone-aware UTC datetimes, and
the frozen dataclasses :class:`Status`, :class:`Identity`, :class:`Alarm` and
:class:`HistoryEntry`. Front ends translate: :mod:`focas_net.adapters` holds one pure adapter
per protocol (the packed protocol of ``docs/protocol.md``, FANUC's native FOCAS/2 protocol of
``docs/native-protocol.md``). Nothing here touches a socket or an event loop.

A refusal raises :class:`MachineError` carrying the FANUC ``EW_*`` code. Every write checks
everything before it changes anything, so a failed write leaves the machine exactly as it was.

The CNC's rules and the wire's rules
------------------------------------
The machine enforces what the CNC itself refuses, each operation's checks written here once, in
the order its docstring gives:

* a read-only machine (``read_only = True``) answers EW_PROT to every write, before any other
  check of the machine (:meth:`Machine.check_writable` asks only that);
* parameters and diagnostics: each has a FANUC type (:class:`ParamKind`: bit, byte, word,
  two-word, real). Unknown number -> EW_NUMBER, axis 0 for an axis item or an axis
  for a non-axis item or an axis outside 1..n -> EW_ATTRIB, a value given in another width than
  the parameter's type -> EW_LENGTH, write gate closed (PWE off, not MDI, password not unlocked
  by this session) -> EW_PASSWD, value outside the parameter's range -> EW_DATA;
* macro variables: unknown number -> EW_NUMBER, read-only variable -> EW_PROT, a value the
  variable cannot hold -> EW_DATA. A variable holds a decimal of 0..9 decimal places (the
  ``Decimal``'s exponent within -9..0, kept as given: ``Decimal("1.50")`` reads back as
  ``1.50``) whose digits as an integer fit a signed 32-bit word; an ``int`` is a value with no
  decimals; ``None`` makes the variable vacant;
* PMC: an area this machine does not have -> EW_NOOPT (:meth:`Machine.check_pmc_area` asks only
  that), addresses outside the area -> EW_NUMBER, writing a write-protected area -> EW_PROT
  (``force``, the simulator's own write, ignores protection). Any length within the area;
* alarms: ``alm_type`` outside 0..31 -> EW_DATA, a negative ``alm_no`` -> EW_DATA (-1 means
  "any" to :meth:`Machine.clear_alarms`, so such an alarm could not be cleared on its own),
  ``axis_no`` outside 0..axes -> EW_ATTRIB; the CNC keeps 32 characters of a message. The
  history keeps ``history_capacity`` entries; active alarms and the history are read to any
  depth;
* positions: an unknown kind -> EW_ATTRIB, the skip position -> EW_NOOPT (no skip function),
  an axis outside 1..n -> EW_ATTRIB;
* the VersaMax station: an empty (or impossible) rack/slot -> EW_NUMBER, an offset outside the
  record -> EW_NUMBER; a read returns what the record has from there, up to the length asked;
* the operator panel: a mode that is not an ``aut`` value other than 2, ``pwe`` or
  ``emergency`` other than 0/1 -> EW_DATA; a switch given as None stays as it is.

What a wire cannot carry is its adapter's to refuse: payload sizes and layouts, unknown commands,
the packed protocol's ``type_a`` codes and ``type_d``, its ceiling of 32 PMC bytes, 32 alarm
messages, 250 history entries and 128 configuration bytes per call, the ``length`` word of its
ODBM, its position type numbers; the native protocol's answer size and its own numbering. Where
a wire's check sits in the middle of the order above, the adapter asks the machine for the
checks before it (:meth:`Machine.check_writable`, :meth:`Machine.check_pmc_area`,
:meth:`Machine.config_record`) and then calls the operation, which repeats them harmlessly.
Whether simulator control commands are served (``control_enabled``) is a flag the adapters read.

``unlock`` is session state, not machine state: it works on a read-only machine. The parameter
password is 1..4 ASCII characters; only an exact match unlocks (a longer password offered is
wrong, never cut to a prefix). It is compared in constant time and never logged or shown in
``repr``.

Counters (:attr:`Machine.version` and the narrower ``*_version``) move on every change they
cover, so front ends can key caches of their answers on them.

Part programs and their execution
---------------------------------
The machine owns a :class:`~focas_net.sim.nc.ProgramStore` (:attr:`Machine.programs`) and an
:class:`~focas_net.sim.nc.Engine` (:attr:`Machine.engine`) on its ``sim_clock``: machine time in
seconds, ``RealTimeClock()`` unless given (``serve --speed`` shares one ``RealTimeClock(speed)``
across a fleet; a test gives a :class:`~focas_net.sim.nc.ManualClock` and steps it). The other
clock, ``clock``, gives the datetimes of alarm stamps only: an alarm the program raises is
stamped ``clock()`` less the machine time between the alarm and the read that recorded it.

Nothing ticks: every read and every counter first brings the engine to the clock's time
(:meth:`Machine._sync`): program alarms go into the active alarms and the history, parts into
parameters 6711/6712; while a program runs, the motion and macro counters move whenever time
moved, so no front end serves a cached answer of a moving machine. ``cycle_start()``,
``feed_hold()``, ``reset()``, ``set_overrides()`` and the G signals control it.

Which figures are shown: those of the constructor (the ``[motion]`` table) and of
:meth:`Machine.set_motion` / :meth:`Machine.set_run` until the first cycle start or program
selection; from then on the engine's, until ``set_motion`` or ``set_run`` is called again. The
CNC's rules of the cycle: cycle start only in MEM, not with the emergency stop or an alarm
(EW_ALARM; an alarm that stopped the cycle wants a reset), not without a main program
(EW_DATA); leaving MEM holds the feed; the emergency stop resets; any alarm stops the cycle;
reset clears the alarms the program raised.

At work on its own
------------------
:meth:`Machine.start_scenario` runs a :class:`~focas_net.sim.nc.scenario.Scenario` (a machine
file's ``[run]``; ``serve --run`` gives the default one): the main program repeated for a
number of parts or forever, with seeded operator pauses (feed hold), tool-change waits (the
cycle stopped) and alarms (the cycle stopped until the repair time is over, then reset and a
new cycle). No timer runs: the scenario's events are machine times drawn from the seed, and a
read applies those that are due, each at its own machine time, before it reads the engine.
:meth:`Machine.spindle_loads` and :meth:`Machine.servo_loads` follow the cutting, with a noise
fixed by :attr:`Machine.seed` and the machine time.
"""

from __future__ import annotations

import hashlib
import math
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from datetime import datetime
from decimal import Decimal
from typing import Final

from focas_net.errors import EW
from focas_net.versamax import IOModuleRecord

from ._alarms import (
    DEFAULT_HISTORY_CAPACITY,
    MAX_ALARM_TEXT,
    Alarm,
    Alarms,
    Clock,
    HistoryEntry,
    utc_now,
)
from ._base import I32_MAX, I32_MIN, Counters, MachineError, logger
from ._items import MAX_REAL_DECIMALS as MAX_REAL_DECIMALS  # the native adapter's
from ._items import (
    PARTS_COUNT,
    PARTS_REQUIRED,
    PARTS_TOTAL,
    DataItem,
    Items,
    ParamKind,
)
from ._macros import MAX_MACRO_DECIMALS, MacroRange, Macros, float_macro, macro_value
from ._password import ParamLock, Session
from ._pmc import F_SIGNALS, G_SIGNALS, PMC_AREAS, GRequest, Pmc, PmcAreaSpec
from ._station import Station
from .nc import (
    AlarmKind,
    CycleState,
    Engine,
    EngineEvent,
    MotionKind,
    NcAlarm,
    NcSettings,
    NcStateError,
    ProgramError,
    ProgramErrorReason,
    ProgramInfo,
    ProgramStore,
    RealTimeClock,
    SimClock,
    VariableRefused,
)
from .nc.alarms import AlarmRaised
from .nc.scenario import (
    DEFAULT_SCENARIO,
    SCENARIO_ALARMS,
    Scenario,
    ScenarioEvent,
    Schedule,
    noise,
    servo_load,
    spindle_load,
)

__all__ = [
    "AUT_MODES",
    "CONTROL_CLASSES",
    "DEFAULT_CONTROL_CLASS",
    "DEFAULT_HISTORY_CAPACITY",
    "F_SIGNALS",
    "G_SIGNALS",
    "MAX_MACRO_DECIMALS",
    "MDI",
    "MEM",
    "PMC_AREAS",
    "POSITION_DECIMALS",
    "POSITION_KINDS",
    "TIMER_KINDS",
    "Alarm",
    "Clock",
    "DataItem",
    "HistoryEntry",
    "Identity",
    "Machine",
    "MachineError",
    "MacroRange",
    "MotionData",
    "Panel",
    "ParamKind",
    "PmcAreaSpec",
    "Session",
    "Status",
    "utc_now",
]


#: ``aut`` values: 0 MDI, 1 MEM, 3 EDIT, 4 HND, 5 JOG, 6 Teach-in JOG, 7 Teach-in HND, 8 INC,
#: 9 REF, 10 RMT (2 is not a mode).
AUT_MODES: Final = frozenset({0, 1, 3, 4, 5, 6, 7, 8, 9, 10})
MDI: Final = 0
MEM: Final = 1
EDIT: Final = 3
#: Decimals of the least input increment of the positions (0.001 mm, IS-B).
POSITION_DECIMALS: Final = 3
#: The position kinds :meth:`Machine.positions` serves (``"skip"`` answers EW_NOOPT).
POSITION_KINDS: Final = ("absolute", "machine", "relative", "distance_to_go")
#: The control classes a machine can be, as FANUC names its series; a front end speaks as that
#: class of control does (FANUC's native protocol: the 16i command set for 16i, 18i, 21i and
#: 0i-C, the 30i set for 0i-D, 0i-F, 30i, 31i and 32i).
CONTROL_CLASSES: Final = ("16i", "18i", "21i", "0i-C", "0i-D", "0i-F", "30i", "31i", "32i")
#: The control class of a machine that does not say (the built-in machine is a 0i-F).
DEFAULT_CONTROL_CLASS: Final = "0i-F"

#: The timers :meth:`Machine.timer` reads, by FANUC's ``cnc_rdtimer`` type number.
TIMER_KINDS: Final = ("power_on", "operating", "cutting", "cycle")
#: Alarm type numbers of the alarms the program raises (FANUC 0i-D/F, 30i numbering).
_NC_ALARM_TYPES: Final = {AlarmKind.PS: 3, AlarmKind.OT: 4, AlarmKind.MC: 8}
_ALARM_KINDS: Final = {3: AlarmKind.PS, 4: AlarmKind.OT, 8: AlarmKind.MC}
#: The run state (ODBST ``run``) and motion of each engine state.
_RUN: Final = {CycleState.RESET: 0, CycleState.STOP: 1, CycleState.HOLD: 2, CycleState.START: 3}
_MOTION: Final = {MotionKind.NONE: 0, MotionKind.MOTION: 1, MotionKind.DWELL: 2}
#: The macro variables of the parts count and the total parts.
_PARTS_VARIABLES: Final = {3901: PARTS_COUNT, 3902: PARTS_TOTAL}
#: System variables that come from the engine while it drives the figures: modal G codes
#: #4001-#4030, the last block's codes #4102-#4130, positions #5001-#5043.
_ENGINE_VARIABLES: Final = (range(4001, 4031), range(4102, 4131), range(5001, 5044))
_MM: Final = 10**POSITION_DECIMALS
#: Rapid traverse (mm/min) of an axis whose parameter 1420 gives no positive rate.
_DEFAULT_RAPID: Final = 24000.0
#: The cycle states as plain constants: an enum member read through its class is slow on the
#: read path of every status answer.
_START: Final = CycleState.START
_RESET: Final = CycleState.RESET
_HOLD: Final = CycleState.HOLD
_STOP: Final = CycleState.STOP

_MOTION_SCALARS: Final = ("feed", "spindle_speed", "program_running", "program_main", "sequence")
_SKIP: Final = "skip"
#: Identity texts and their widths (ODBSYS).
_IDENTITY_TEXTS: Final = (("cnc_type", 2), ("mt_type", 2), ("series", 4), ("version", 4))


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


class _Variables:
    """The machine's variables as the interpreter reads and writes them: #3901/#3902 (parts),
    the machine's macro ranges (#500-#999 and whatever else it has); 115 for a number the
    machine lacks, 116 for a read-only one, 111 for a value a variable cannot hold."""

    __slots__ = ("_machine",)

    def __init__(self, machine: Machine) -> None:
        self._machine = machine

    def read_variable(self, number: int) -> float | None:
        m = self._machine
        if number in _PARTS_VARIABLES:
            return float(m._parts(_PARTS_VARIABLES[number]))
        if m._macros.range_of(number) is None:
            raise VariableRefused(115, f"#{number}")
        value = m._macros.values.get(number)
        return None if value is None else float(value)

    def write_variable(self, number: int, value: float | None) -> None:
        m = self._machine
        if number in _PARTS_VARIABLES:
            m._set_parts(_PARTS_VARIABLES[number], 0 if value is None else round(value))
            return
        macros = m._macros
        r = macros.range_of(number)
        if r is None:
            raise VariableRefused(115, f"#{number}")
        if not r.writable:
            raise VariableRefused(116, f"#{number}")
        if value is None:
            macros.values.pop(number, None)
        else:
            held = float_macro(value)
            if held is None:
                raise VariableRefused(111, f"#{number} = {value!r}")
            macros.values[number] = held
        macros.changed()


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


def _program_refusal(exc: ProgramError) -> MachineError:
    return MachineError(_PROGRAM_EW[exc.reason], str(exc))


class _HeldClock:
    """Machine time held at one moment."""

    __slots__ = ("at",)

    def __init__(self) -> None:
        self.at = 0.0

    def now(self) -> float:
        return self.at


class _MachineTime:
    """The engine's clock for its whole life: machine time from the machine's clock (the one
    :meth:`Machine.set_clock` sets), or held at one moment while the machine applies what
    happened then (a sync, a scenario's event). While nothing is held, ``now`` is the
    clock's own method: the engine reads it at the cost of the clock alone."""

    __slots__ = ("_held", "_held_now", "now", "source")
    now: Callable[[], float]

    def __init__(self, source: SimClock) -> None:
        self._held = _HeldClock()
        self._held_now = self._held.now
        self.set_source(source)

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


class _ScenarioRun:
    """A scenario under way: its schedule, the event in progress (until its end)."""

    __slots__ = ("current", "ends_at", "free_at", "scenario", "schedule")

    def __init__(self, scenario: Scenario, schedule: Schedule) -> None:
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


@dataclass(frozen=True, slots=True)
class Status:
    """The status of the CNC (FANUC's ODBST fields), derived from the panel and the alarms."""

    hdck: int
    tmmode: int
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int


@dataclass(frozen=True, slots=True)
class Identity:
    """What the CNC says it is (FANUC's ODBSYS): ``cnc_type`` and ``mt_type`` 2 characters,
    ``series`` and ``version`` 4, ``axes`` 2 (the number of axes, ``"03"``)."""

    addinfo: int
    max_axis: int
    cnc_type: str
    mt_type: str
    series: str
    version: str
    axes: str


@dataclass(slots=True)
class Panel:
    """The operator panel and the run state shown by the status."""

    mode: int = MEM
    pwe: int = 0
    emergency: int = 0
    run: int = 0
    motion: int = 0
    mstb: int = 0
    edit: int = 0
    hdck: int = 0
    tmmode: int = 0


@dataclass(slots=True)
class MotionData:
    """Motion figures: positions per axis in least input increments (:data:`POSITION_DECIMALS`
    decimals), actual feed, spindle speed, program numbers and the sequence number."""

    absolute: list[int]
    machine: list[int]
    relative: list[int]
    distance_to_go: list[int]
    feed: int = 0
    spindle_speed: int = 0
    program_running: int = 0
    program_main: int = 0
    sequence: int = 0


class Machine:
    """One simulated CNC.

    Build one with :func:`focas_net.sim.default_machine`, :func:`focas_net.sim.load_machine` or
    this constructor. Everything is synchronous; a front end calls it from one thread.
    """

    def __init__(
        self,
        name: str,
        *,
        axes: Iterable[str] = ("X", "Y", "Z"),
        identity: Identity | None = None,
        params: Iterable[DataItem] = (),
        diags: Iterable[DataItem] = (),
        macro_ranges: Iterable[MacroRange] = (),
        macro_values: Mapping[int, Decimal | int | None] | None = None,
        pmc: Iterable[PmcAreaSpec] = (),
        panel: Panel | None = None,
        param_password: str | bytes | None = None,
        station: Mapping[tuple[int, int], IOModuleRecord] | None = None,
        motion: MotionData | None = None,
        history_capacity: int = DEFAULT_HISTORY_CAPACITY,
        clock: Clock = utc_now,
        control_enabled: bool = True,
        read_only: bool = False,
        control_class: str = DEFAULT_CONTROL_CLASS,
        programs: Iterable[str] = (),
        main_program: int | None = None,
        sim_clock: SimClock | None = None,
        scenario: Scenario | None = None,
    ) -> None:
        self._name = name
        #: How the machine runs on its own when it is told to (:meth:`start_scenario`;
        #: ``serve`` starts it): a machine file's ``[run]``, None when it has none.
        self.scenario = scenario
        if control_class not in CONTROL_CLASSES:
            raise ValueError(
                f"unknown control class {control_class!r} (one of {', '.join(CONTROL_CLASSES)})"
            )
        #: Which class of FANUC control this machine is (one of :data:`CONTROL_CLASSES`).
        self.control_class = control_class
        self.axes: list[str] = list(axes)
        n = len(self.axes)
        if not 1 <= n <= 32:
            raise ValueError(f"a machine has 1..32 axes, got {n}")
        #: Whether the simulator control commands of a front end are served.
        self.control_enabled = control_enabled
        self.read_only = read_only
        self._identity = identity or Identity(2, max(n, 8), " 0", " M", "D4F1", "32.0", f"{n:02d}")
        self._check_identity(self._identity)
        self.panel = panel or Panel()
        if self.panel.mode not in AUT_MODES:
            raise ValueError(f"panel mode {self.panel.mode} is not an aut value")
        self._lock = ParamLock(param_password)
        self._station = Station(station or {})
        self._motion = motion or MotionData([0] * n, [0] * n, [0] * n, [0] * n)
        for key in POSITION_KINDS:
            if len(getattr(self._motion, key)) != n:
                raise ValueError(
                    f"motion {key}: {len(getattr(self._motion, key))} values for {n} axes"
                )
        self._counters = Counters()
        self._items = Items(params, diags, n, self._counters)
        self._macros = Macros(macro_ranges, macro_values or {}, self._counters)
        self._pmc = Pmc(pmc, self._counters)
        self._alarms = Alarms(name, history_capacity, clock, self._counters)
        self._build_engine(programs, main_program, sim_clock)

    @staticmethod
    def _check_identity(identity: Identity) -> None:
        texts = (*_IDENTITY_TEXTS, ("axes", 2))
        for key, size in texts:
            text = getattr(identity, key)
            if not isinstance(text, str) or len(text) != size or not text.isascii():
                raise ValueError(f"identity {key} must be {size} ASCII characters, got {text!r}")

    @property
    def name(self) -> str:
        """The machine's name (the server's ready line, the logs)."""
        return self._name

    @name.setter
    def name(self, name: str) -> None:
        self._name = self._alarms.name = name

    def __repr__(self) -> str:
        return f"Machine({self.name!r}, axes={''.join(self.axes)!r})"

    # -- counters (each brings the engine to the clock's time first) ---------------------
    @property
    def version(self) -> int:
        """Incremented on every change of machine state."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.version

    @property
    def status_version(self) -> int:
        """Incremented when the status changes (panel, run state, motion, active alarms).
        While the cycle runs, time changes the status only when an action ends or a scenario
        event is due, so until then a read costs a clock call and two compares."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            if (
                self._time.now() >= self._steady_until
                or self.engine.revision != self._steady_revision
            ):
                self._sync()
        return self._counters.status

    @property
    def data_version(self) -> int:
        """Incremented when a parameter or diagnostic value changes (parts counts too)."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.data

    @property
    def macro_version(self) -> int:
        """Incremented when a macro variable changes (while a program runs: whenever machine
        time moved, for the system variables follow the engine)."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.macro

    @property
    def alarm_version(self) -> int:
        """Incremented when the active alarms or the alarm history change."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.alarm

    @property
    def pmc_version(self) -> int:
        """Incremented when PMC data changes."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.pmc

    @property
    def motion_version(self) -> int:
        """Incremented when the motion figures change: while a program runs, whenever machine
        time moved."""
        if self._engine_key[0] is _START or self._run is not None:  # what moves with time
            self._sync()
        return self._counters.motion

    def check_writable(self) -> None:
        """EW_PROT when the machine is read-only: the first check of every write."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")

    # -- sessions, status, identity ------------------------------------------------------
    def new_session(self) -> Session:
        """Per-connection state for a new connection (locked)."""
        return Session(False, self._lock.epoch)

    def set_param_password(self, password: str | bytes | None) -> None:
        """Set (None: remove) the parameter password, 1..4 ASCII characters (ValueError
        otherwise). Connections unlocked under the previous password are locked again."""
        self._lock.set(password)
        self._counters.version += 1

    @property
    def has_password(self) -> bool:
        """True when parameter writes need a per-session unlock."""
        return self._lock.is_set

    def status(self) -> Status:
        """The status, derived from the panel, the active alarms and (while it drives the
        figures) the engine's run state and motion."""
        self._sync()
        p = self.panel
        run, motion, mstb = p.run, p.motion, p.mstb
        if self._driven:
            run, motion = _RUN[self._engine_key[0]], _MOTION[self._engine_key[1]]
            mstb = self._mstb
        return Status(
            p.hdck,
            p.tmmode,
            p.mode,
            run,
            motion,
            mstb,
            p.emergency,
            1 if self._alarms.active else 0,
            p.edit,
        )

    def identity(self) -> Identity:
        """What the CNC says it is."""
        return self._identity

    # -- parameters and diagnostics ------------------------------------------------------
    def param_item(self, datano: int) -> DataItem | None:
        """The description of parameter ``datano`` (None when the machine has none)."""
        return self._items.params.get(datano)

    def diag_item(self, datano: int) -> DataItem | None:
        """The description of diagnostic ``datano`` (None when the machine has none)."""
        return self._items.diags.get(datano)

    def param_numbers(self) -> tuple[int, ...]:
        """The numbers of every parameter, ascending."""
        return tuple(sorted(self._items.params))

    def diag_numbers(self) -> tuple[int, ...]:
        """The numbers of every diagnostic, ascending."""
        return tuple(sorted(self._items.diags))

    def read_param(self, datano: int, axis: int) -> int:
        """The value of parameter ``datano`` (``axis`` 0 for a non-axis item, else 1..n):
        EW_NUMBER, then EW_ATTRIB. Its width is :meth:`param_item`'s."""
        self._sync()
        items = self._items
        item, i = items.lookup(items.params, datano, axis)
        return item.values[i]

    def read_diag(self, datano: int, axis: int) -> int:
        """The value of diagnostic ``datano``: EW_NUMBER, then EW_ATTRIB."""
        items = self._items
        item, i = items.lookup(items.diags, datano, axis)
        return item.values[i]

    def param_gate_open(self, session: Session) -> bool:
        """PWE on, MDI mode, and (when there is a password) this session unlocked."""
        p = self.panel
        if p.pwe != 1 or p.mode != MDI:
            return False
        return self._lock.admits(session)

    def write_param(
        self,
        session: Session,
        datano: int,
        axis: int,
        value: int,
        *,
        width: int | None = None,
        decimals: int | None = None,
    ) -> None:
        """Write parameter ``datano``; ``width`` is the width (1, 2, 4, 8 for a real) the value
        was given in, checked against the parameter's type when given. ``value`` is in the
        parameter's terms: 0..255 for a bit parameter, the mantissa of a real one. EW_PROT
        (read-only machine), EW_NUMBER, EW_ATTRIB, EW_LENGTH (width), EW_PASSWD (write gate),
        EW_DATA (range).

        ``decimals`` (a real parameter only) says how many decimals the mantissa ``value``
        has: it is rescaled to the parameter's own, and a value that does not have an exact
        mantissa there (``1.2345`` for a 3-decimal parameter) is EW_DATA."""
        self.check_writable()
        items = self._items
        item, i = items.lookup(items.params, datano, axis)
        if width is not None and width != item.width:
            raise MachineError(EW.LENGTH, f"parameter {datano} is {item.width} bytes wide")
        if not self.param_gate_open(session):
            raise MachineError(EW.PASSWD, "parameter write not enabled")
        value = items.rescaled(item, value, decimals)
        items.set(item, i, value, "parameter")
        if datano in (PARTS_COUNT, PARTS_TOTAL):
            self._set_parts(datano, value)

    def set_diag(self, datano: int, axis: int, value: int) -> None:
        """Change a diagnostic value (simulation code; a CNC has no diagnostic write):
        EW_NUMBER, EW_ATTRIB, EW_DATA (range)."""
        items = self._items
        item, i = items.lookup(items.diags, datano, axis)
        items.set(item, i, value, "diagnostic")

    # -- macro variables -----------------------------------------------------------------
    def macro_writable(self, number: int) -> bool | None:
        """True/False for a writable/read-only variable; None when there is no such variable."""
        r = self._macros.range_of(number)
        return None if r is None else r.writable

    def read_macro(self, number: int) -> Decimal | None:
        """The value of macro variable ``number``, None when vacant: EW_NUMBER for an unknown
        variable."""
        macros = self._macros
        if macros.range_of(number) is None:
            raise MachineError(EW.NUMBER, f"no macro variable #{number}")
        self._sync()
        if number in _PARTS_VARIABLES:
            return Decimal(self._parts(_PARTS_VARIABLES[number]))
        if self._driven and any(number in r for r in _ENGINE_VARIABLES):
            return self._engine_variable(number)
        return macros.values.get(number)

    def write_macro(self, number: int, value: Decimal | int | None) -> None:
        """Set macro variable ``number`` to ``value`` (None: vacant). EW_PROT (read-only
        machine), EW_NUMBER, EW_PROT (read-only variable), EW_DATA (a value the variable cannot
        hold: see the module docstring). Making a vacant variable vacant changes nothing."""
        self.check_writable()
        self._macros.check_write(number)
        if number in _PARTS_VARIABLES:
            held_parts = None if value is None else macro_value(value)
            if held_parts is None or held_parts != held_parts.to_integral_value() or held_parts < 0:
                raise MachineError(EW.DATA, f"#{number} = {value}: a count of parts")
            self._set_parts(_PARTS_VARIABLES[number], int(held_parts))
            return
        self._macros.write(number, value)

    # -- PMC -------------------------------------------------------------------------------
    def pmc_area(self, letter: str) -> tuple[int, bool] | None:
        """``(size, write_protected)`` of area ``letter``, or None when the machine has none
        (ValueError for a letter that is no PMC area at all)."""
        return self._pmc.info(letter)

    def check_pmc_area(self, letter: str) -> None:
        """EW_NOOPT when the machine has no PMC area ``letter`` (whatever the letter)."""
        self._pmc.area(letter)

    def read_pmc(self, letter: str, start: int, length: int) -> bytes:
        """``length`` bytes of area ``letter`` from address ``start``: EW_NOOPT (no such area),
        EW_NUMBER (addresses outside the area)."""
        area = self._pmc.area(letter)
        if length < 0:
            raise ValueError(f"a PMC read of {length} bytes")
        if area.letter == "F":
            self._sync()  # the F signals follow the run state
        end = start + length
        if start < 0 or end > area.size:
            raise area.beyond(start, end)
        return bytes(area.data[start:end])

    def write_pmc(self, letter: str, start: int, data: bytes, *, force: bool = False) -> None:
        """Write ``data`` into area ``letter`` from address ``start`` (``force``: the
        simulator's own write, which ignores write protection): EW_PROT (read-only machine),
        EW_NOOPT, EW_NUMBER (addresses outside the area), EW_PROT (write-protected area)."""
        self.check_writable()
        asked = self._pmc.write(letter, start, data, force)
        if asked is not None:
            self._g_signals(asked)

    # -- password ------------------------------------------------------------------------
    def unlock(self, session: Session, password: str | bytes) -> None:
        """Unlock parameter writes for ``session``. ``password`` matches only when it is the
        machine's exactly (as 4 bytes padded with NUL: ``b"12\\0\\0"`` is ``"12"``); a longer
        one never matches, not even when it starts with the machine's. A mismatch answers
        EW_PASSWD and locks the session again. A machine without a password unlocks any."""
        self._lock.unlock(session, password)

    # -- alarms --------------------------------------------------------------------------
    def active_alarms(self, alm_type: int = -1, limit: int | None = None) -> list[Alarm]:
        """The active alarms of ``alm_type`` (-1: every type; a type no alarm has matches
        nothing), oldest raised first, at most ``limit`` of them (None: all)."""
        self._sync()
        return self._alarms.read(alm_type, limit)

    def alarm_history(self, depth: int | None = None) -> tuple[HistoryEntry, ...]:
        """The ``depth`` newest entries of the history (None: all), newest first."""
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

    def raise_alarm(self, axis_no: int, alm_type: int, alm_no: int, msg: str = "") -> bool:
        """Make an alarm active and record it in the history (UTC, whole seconds); True when it
        was raised.

        A CNC shows one entry per alarm: an alarm already active (same axis_no, alm_type,
        alm_no) changes nothing, whatever ``msg`` says: it keeps the message it was raised
        with, the history gets no second entry, and the answer is False. Clear it first to raise
        it with another message. The CNC keeps 32 characters of ``msg``, single-byte (Latin-1)
        text. EW_PROT (read-only machine), EW_DATA (alm_type, alm_no), EW_ATTRIB (axis_no),
        EW_DATA (a character beyond U+00FF)."""
        self.check_writable()
        text = self._alarms.checked(axis_no, alm_type, alm_no, msg, len(self.axes))
        self._sync()
        key = (axis_no, alm_type, alm_no)
        if not self._alarms.add(key, text, self.now()):
            return False
        if self.engine.state is not _RESET:
            # any alarm stops the cycle; cycle start wants a reset after it
            kind = _ALARM_KINDS.get(alm_type, AlarmKind.PS)
            self.engine.alarm_stop(NcAlarm(kind, alm_no, text, axis=axis_no or None))
            self._settled(True)
        return True

    def clear_alarms(self, alm_type: int = -1, alm_no: int = -1) -> int:
        """Remove the active alarms matching ``alm_type`` and ``alm_no`` (-1 = any); the
        history is kept. Returns how many were removed. EW_PROT on a read-only machine."""
        self.check_writable()
        return self._alarms.clear(alm_type, alm_no)

    # -- operator panel ------------------------------------------------------------------
    def set_panel(
        self, mode: int | None = None, pwe: int | None = None, emergency: int | None = None
    ) -> None:
        """Set the operator panel: ``mode`` an ``aut`` value other than 2, ``pwe`` and
        ``emergency`` 0/1, else EW_DATA; a switch given as None stays as it is. EW_PROT on a
        read-only machine."""
        self.check_writable()
        p = self.panel
        mode = p.mode if mode is None else mode
        pwe = p.pwe if pwe is None else pwe
        emergency = p.emergency if emergency is None else emergency
        if mode not in AUT_MODES or pwe not in (0, 1) or emergency not in (0, 1):
            raise MachineError(EW.DATA, f"panel mode={mode} pwe={pwe} emergency={emergency}")
        self._sync()
        leaving_mem = p.mode == MEM and mode != MEM
        stop = emergency and not p.emergency
        p.mode, p.pwe, p.emergency = mode, pwe, emergency
        logger.debug("%s: panel mode %d pwe %d emergency %d", self.name, mode, pwe, emergency)
        if stop:
            self.engine.reset()  # emergency stop resets the control
        elif leaving_mem:
            self.engine.feed_hold()  # automatic operation stops outside MEM
        self._counters.status_changed()
        self._settled(stop or leaving_mem)

    def set_run(self, run: int, motion: int = 0) -> None:
        """Set the run state (0 reset, 1 STOP, 2 HOLD, 3 STRT, 4 MSTR) and motion (0, 1 MTN,
        2 DWL) shown by the status (simulation code only): EW_DATA otherwise."""
        if run not in range(5) or motion not in range(3):
            raise MachineError(EW.DATA, f"run={run} motion={motion}")
        self.panel.run, self.panel.motion = run, motion
        self._driven = False
        self._counters.status_changed()

    # -- motion figures ------------------------------------------------------------------
    def set_motion(
        self,
        *,
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

        Positions are one i32 per axis in least input increments; the other figures are
        0..2**31-1. EW_DATA (and nothing changes) when a value does not fit or a position list
        does not have one value per axis.
        """
        n = len(self.axes)
        lists: dict[str, list[int]] = {}
        for key, values in zip(
            POSITION_KINDS, (absolute, machine, relative, distance_to_go), strict=True
        ):
            if values is None:
                continue
            got = list(values)
            if len(got) != n or not all(type(v) is int and I32_MIN <= v <= I32_MAX for v in got):
                raise MachineError(EW.DATA, f"{key}: {n} i32 values expected, got {got!r}")
            lists[key] = got
        scalars: dict[str, int] = {}
        for key, value in zip(
            _MOTION_SCALARS,
            (feed, spindle_speed, program_running, program_main, sequence),
            strict=True,
        ):
            if value is None:
                continue
            if type(value) is not int or not 0 <= value <= I32_MAX:
                raise MachineError(EW.DATA, f"{key} = {value!r} outside 0..{I32_MAX}")
            scalars[key] = value
        m = self._motion
        self._sync()
        if self._driven:
            self._driven = False
            self._counters.status_changed()
        for key, got in lists.items():
            setattr(m, key, got)
        for key, value in scalars.items():
            setattr(m, key, value)
        self._counters.motion += 1
        self._counters.version += 1

    def positions(self, kind: str, axis: int | None = None) -> list[tuple[str, int]]:
        """``(axis name, value)`` of every axis (``axis`` None) or of axis ``axis`` (1..n), in
        least input increments (:data:`POSITION_DECIMALS` decimals). ``kind`` is one of
        :data:`POSITION_KINDS`. Checks, in order: an unknown kind -> EW_ATTRIB; ``"skip"`` ->
        EW_NOOPT (the machine has no skip function); ``axis`` outside 1..n -> EW_ATTRIB."""
        if kind not in POSITION_KINDS:
            if kind == _SKIP:
                raise MachineError(EW.NOOPT, "no skip function")
            raise MachineError(EW.ATTRIB, f"position kind {kind!r}")
        values: list[int] = getattr(self.motion, kind)
        if axis is None:
            return list(zip(self.axes, values, strict=True))
        if not 1 <= axis <= len(self.axes):
            raise MachineError(EW.ATTRIB, f"axis {axis} outside 1..{len(self.axes)}")
        return [(self.axes[axis - 1], values[axis - 1])]

    # -- part programs and their execution ---------------------------------------------
    @property
    def sim_clock(self) -> SimClock:
        """The clock of machine time (seconds): ``RealTimeClock()`` unless the constructor or
        :meth:`set_clock` gave another."""
        return self._time.source

    def set_clock(self, clock: SimClock) -> None:
        """Take machine time from ``clock`` from now on: the engine, the timers and a running
        scenario read it (a fleet shares one: ``serve --speed``; a test gives a
        :class:`~focas_net.sim.nc.ManualClock` and steps it). This is the one way the
        engine's clock is set after the constructor's ``sim_clock``. The machine goes on from
        where it is, so ``clock`` may not be behind the machine's time (ValueError); the time
        it is ahead passes at once, as if the machine had been left alone that long."""
        behind = self._time.now() - clock.now()
        if behind > 0:
            raise ValueError(f"the clock is {behind} s behind the machine's time")
        self._time.set_source(clock)

    def _build_engine(
        self, programs: Iterable[str], main_program: int | None, sim_clock: SimClock | None
    ) -> None:
        self._time = _MachineTime(sim_clock if sim_clock is not None else RealTimeClock())
        self._powered_at = self._time.now()
        #: The programs in the machine's memory (the engine marks those in use).
        self.programs = ProgramStore()
        first: int | None = None
        for text in programs:
            number = self.programs.store(text).number
            first = number if first is None else first
        self.engine = Engine(
            self._time, self._nc_settings(), store=self.programs, variables=_Variables(self)
        )
        self.engine.parts_count = self._items.param_or(PARTS_COUNT, 0)
        self.engine.parts_total = self._items.param_or(PARTS_TOTAL, 0)
        main = main_program if main_program is not None else first
        if main is not None:
            self.programs.select(main)
        self._driven = False
        self._synced_at = math.nan
        #: Until this machine time (and while the engine's revision is this one) time alone
        #: changes nothing of the status (see :attr:`status_version`).
        self._steady_until = -math.inf
        self._steady_revision = -1
        self._engine_key = (_RESET, MotionKind.NONE)
        self._engine_alarms: set[tuple[int, int, int]] = set()
        self._figures: tuple[int, MotionData] | None = None
        self._mstb = 0
        self._run: _ScenarioRun | None = None
        #: The seed of the loads' noise (a scenario's seed once one runs).
        self.seed = 0
        self._hardness = 1.0
        #: The scenario's events as they were applied: ``(event, "begin" | "end" |
        #: "skipped")``, the newest 1000.
        self.scenario_log: deque[tuple[ScenarioEvent, str]] = deque(maxlen=1000)

    def _nc_settings(self) -> NcSettings:
        """Execution settings from the parameters, read when the machine is built: rapid
        traverse 1420 (mm/min; an axis whose rate is not above 0 traverses at 24,000), maximum
        cutting feed 1422, stroke limit 1 1320/1321 (0.001 mm, or mm for a real parameter; no
        limit on an axis where plus is not above minus), reference position 1240."""
        n = len(self.axes)
        axes = range(1, n + 1)
        rapid = tuple(
            rate if rate > 0 else _DEFAULT_RAPID
            for rate in (self._items.param_float(1420, _DEFAULT_RAPID, a, 1.0) for a in axes)
        )
        limits: list[tuple[float, float] | None] = []
        for a in axes:
            plus = self._items.param_float(1320, 0.0, a, 1 / _MM)
            minus = self._items.param_float(1321, 0.0, a, 1 / _MM)
            limits.append((minus, plus) if plus > minus else None)
        reference = tuple(self._items.param_float(1240, 0.0, a, 1 / _MM) for a in axes)
        values: dict[str, object] = {
            "rapid_rates": rapid,
            "stroke_limits": tuple(limits),
            "reference": reference,
        }
        feed = self._items.param_or(1422, 0)
        if feed > 0:
            values["max_cutting_feed"] = float(feed)
        return NcSettings.for_axes(self.axes, **values)

    @property
    def driven(self) -> bool:
        """Whether the engine shows the run state and the motion figures: from a cycle start
        or a program selection until :meth:`set_motion` or :meth:`set_run` sets them by hand
        (before, the figures given to the constructor or by hand are shown)."""
        return self._driven

    def _sync(self) -> None:
        """Bring the engine to the clock's time: record its alarms and parts, and move the
        counters of what it shows. Costs one comparison while the cycle is not running and no
        scenario drives the machine (time then changes nothing the engine shows: every command
        that starts or changes the cycle settles the counters itself), a clock call when the
        time has not moved or a scenario's next event is not due."""
        run = self._run
        if self._engine_key[0] is not _START:
            if run is None:
                return
            now = self._time.now()
            if now < run.next_time or now == self._synced_at:
                return
        else:
            now = self._time.now()
            if now == self._synced_at:
                return
        self._synced_at = now
        e = self.engine
        self._time.hold(now)  # the engine advances once, however many figures are read
        try:
            moved = self._engine_key[0] is _START
            if run is not None and run.next_time <= now:
                self._play(run, now)
                moved = True
            for event in e.take_events():
                self._engine_event(event, now)
            self._settled(moved)
            if run is not None and run.finished(e):
                self._run = None
        finally:
            self._time.release()

    def _settled(self, moved: bool, force: bool = False) -> None:
        state, motion, wait = self.engine.flags()
        key = (state, motion)
        changed = key != self._engine_key
        self._engine_key = key
        waiting = 1 if wait else 0
        if waiting != self._mstb:
            self._mstb = waiting
            changed = True
        self._f_signals()
        e = self.engine
        steady = e.steady_until()
        run = self._run
        if run is not None and run.next_time < steady:
            steady = run.next_time
        self._steady_until = steady
        self._steady_revision = e.revision
        if force or (self._driven and (changed or moved)):
            self._counters.motion += 1
            self._counters.macro += 1
            self._counters.version += 1
            if force or changed:
                self._counters.status += 1

    def _g_signals(self, asked: GRequest) -> None:
        """Act on the G signals a write changed (see :data:`G_SIGNALS`): the rising edge of
        ERS resets, the falling edge of *SP holds the feed, a change of the mode bits of G43
        selects the mode, a change of G12 sets the feed override, the falling edge of ST
        starts the cycle (with *SP on). What the CNC refuses (cycle start with an alarm ...)
        is ignored, as a CNC ignores the signal."""
        try:
            if asked.reset:
                self.reset()
            if asked.hold:
                self.feed_hold()
            if asked.mode is not None and asked.mode != self.panel.mode:
                self.set_panel(mode=asked.mode)
            if asked.feed_override is not None:
                self.set_overrides(feed=asked.feed_override)
            if asked.start:
                self.cycle_start()
        except MachineError as exc:
            logger.debug("%s: G signal ignored: %s", self.name, exc)
        self._f_signals()

    def _f_signals(self) -> None:
        """Set the F signals a ladder reads from the run state (see :data:`F_SIGNALS`) while
        the engine drives the machine (:attr:`driven`); before, F is as written."""
        if self._driven:
            self._pmc.show_cycle(self._engine_key[0])

    def _engine_event(self, event: EngineEvent, now: float) -> None:
        if event.kind == "part":
            self._store_parts(PARTS_COUNT, self.engine.parts_count)
            self._store_parts(PARTS_TOTAL, self.engine.parts_total)
        elif event.kind == "alarm" and event.alarm is not None:
            alarm = event.alarm
            key = (alarm.axis or 0, _NC_ALARM_TYPES[alarm.kind], alarm.number)
            text = alarm.message[:MAX_ALARM_TEXT].encode("latin-1", "replace").decode("latin-1")
            if self._alarms.add(key, text, self._alarms.stamp(now - event.time)):
                self._engine_alarms.add(key)

    def _parts(self, number: int) -> int:
        return self.engine.parts_count if number == PARTS_COUNT else self.engine.parts_total

    def _store_parts(self, number: int, value: int) -> None:
        if self._items.clamp(number, value):
            self._counters.macro += 1

    def _set_parts(self, number: int, value: int) -> None:
        if number == PARTS_COUNT:
            self.engine.parts_count = value
        else:
            self.engine.parts_total = value
        self._store_parts(number, value)

    def cycle_start(self, *, repeat: bool | None = None) -> None:
        """Cycle start: run the main program from its head (reset), go on (stop) or resume
        (feed hold). EW_PROT (read-only machine), EW_ALARM (emergency stop, an active alarm,
        or an alarm that stopped the cycle and wants a reset), EW_MODE (not MEM), EW_DATA (no
        main program). From here the engine shows the run state and the figures.

        ``repeat`` True: production, the main program starts again at once after each M2/M30
        (a part counted each time) until ``repeat`` False is given or an alarm stops it; None
        leaves the setting as it is."""
        self.check_writable()
        self._sync()
        if self.panel.emergency:
            raise MachineError(EW.ALARM, "cycle start refused: emergency stop")
        if self._alarms.active:
            raise MachineError(EW.ALARM, "cycle start refused: an alarm is active")
        if self.panel.mode != MEM:
            raise MachineError(EW.MODE, f"cycle start refused: mode {self.panel.mode} is not MEM")
        if repeat is not None:
            self.engine.repeat = repeat
        try:
            self.engine.cycle_start()
        except NcStateError as exc:
            ew = EW.ALARM if self.engine.alarm is not None else EW.DATA
            raise MachineError(ew, str(exc)) from None
        self._driven = True
        self._settled(True, force=True)

    def feed_hold(self) -> None:
        """Feed hold: the axes stop where they are (HOLD); cycle start resumes. EW_PROT on a
        read-only machine."""
        self.check_writable()
        self._sync()
        self.engine.feed_hold()
        self._settled(True)

    def reset(self) -> None:
        """Reset: the cycle stops and rewinds, the alarms the program raised are cleared (the
        history keeps them). EW_PROT on a read-only machine."""
        self.check_writable()
        self._sync()
        self._reset_cycle()
        self._settled(True)

    def _reset_cycle(self) -> None:
        self.engine.reset()
        self._alarms.remove(self._engine_alarms)
        self._engine_alarms.clear()

    def set_overrides(
        self, feed: int | None = None, rapid: int | None = None, spindle: int | None = None
    ) -> None:
        """Feed override 0..254 %, rapid override 0..100 %, spindle override 0..254 % (None:
        unchanged): EW_PROT (read-only machine), EW_DATA (a value outside its range)."""
        self.check_writable()
        self._sync()
        for value, low, high, what in (
            (feed, 0, 254, "feed"),
            (rapid, 0, 100, "rapid"),
            (spindle, 0, 254, "spindle"),
        ):
            if value is not None and not low <= value <= high:
                raise MachineError(EW.DATA, f"{what} override {value} outside {low}..{high} %")
        e = self.engine
        if feed is not None:
            e.set_feed_override(feed)
        if rapid is not None:
            e.set_rapid_override(rapid)
        if spindle is not None:
            e.set_spindle_override(spindle)
        self._settled(True)

    def parts_counts(self) -> tuple[int, int]:
        """Parts count and total parts (M2/M30 count them; parameters 6711 and 6712)."""
        self._sync()
        return self.engine.parts_count, self.engine.parts_total

    def overrides(self) -> tuple[int, int, int]:
        """Feed, rapid and spindle override in percent."""
        e = self.engine
        return round(e.feed_override), round(e.rapid_override), round(e.spindle_override)

    def timer(self, kind: int) -> float:
        """Seconds of timer ``kind`` (FANUC's ``cnc_rdtimer`` types): 0 power-on (machine
        time since the machine was built), 1 operating, 2 cutting, 3 cycle (this cycle's time
        since its start from reset); EW_NUMBER for another kind."""
        if not 0 <= kind < len(TIMER_KINDS):
            raise MachineError(EW.NUMBER, f"timer {kind} outside 0..{len(TIMER_KINDS) - 1}")
        self._sync()
        e = self.engine
        if kind == 0:
            return self._time.now() - self._powered_at
        return (e.operating_time, e.cutting_time, e.cycle_time)[kind - 1]

    def timer_ms(self, kind: int) -> int:
        """Whole milliseconds of timer ``kind`` (:meth:`timer`), as a counter shows them: the
        millisecond under way is not counted yet. Both protocols answer this figure."""
        return math.floor(self.timer(kind) * 1000 + 1e-6)  # 1e-6 ms: 1.234 s * 1000 is 1233.99..

    # -- production on its own: scenarios, loads -----------------------------------------
    def start_scenario(self, scenario: Scenario | None = None) -> None:
        """Run on its own: the main program from its head, repeated for the scenario's parts
        (or forever) with its pauses, tool-change waits and alarms, from ``scenario.phase``
        seconds ago (see :mod:`focas_net.sim.nc.scenario`). ``scenario`` None: the machine's
        own (:attr:`scenario`, a machine file's ``[run]``), else the default. The cycle
        rewinds first. Refused as cycle start is: EW_ALARM (emergency stop, an active alarm),
        EW_MODE (not MEM), EW_DATA (no main program); a read-only machine runs it too (the
        machine works, clients only read it)."""
        chosen = scenario or self.scenario or DEFAULT_SCENARIO
        self._sync()
        if self.panel.emergency:
            raise MachineError(EW.ALARM, "a scenario cannot start: emergency stop")
        if self._alarms.active:
            raise MachineError(EW.ALARM, "a scenario cannot start: an alarm is active")
        if self.panel.mode != MEM:
            mode = self.panel.mode
            raise MachineError(EW.MODE, f"a scenario cannot start: mode {mode} is not MEM")
        if self.programs.main is None:
            raise MachineError(EW.DATA, "a scenario cannot start: no main program is selected")
        e = self.engine
        e.reset()
        now = self._time.now()
        origin = now - chosen.start_phase()
        e.repeat = True
        if chosen.parts == "required":
            required = self._items.param_or(PARTS_REQUIRED, 0)
            e.parts_to_go = max(0, required - e.parts_count) if required > 0 else None
        else:
            e.parts_to_go = chosen.parts or None
        self.seed = chosen.seed
        self._hardness = 0.85 + 0.15 * (noise(chosen.seed, 0.0, -1) + 1.0)
        self._powered_at = min(self._powered_at, origin)
        run = _ScenarioRun(chosen, Schedule(chosen, origin, len(self.axes)))
        self._run = run
        self._time.hold(origin)
        try:  # the cycle starts at the origin; the events since then follow in their order
            e.cycle_start(since=origin)
            self._driven = True
            self._synced_at = math.nan
            self._settled(True, force=True)
        except NcStateError as exc:  # pragma: no cover - the checks above cover it
            self._run = None
            raise MachineError(EW.DATA, str(exc)) from None
        finally:
            self._time.release()
        self._sync()

    def stop_scenario(self) -> None:
        """Stop running on its own: the cycle goes on as it is (production without the
        scenario's events and part limit)."""
        self._sync()
        run = self._run
        if run is None:
            return
        self._run = None
        self.engine.parts_to_go = None

    @property
    def scenario_running(self) -> bool:
        """Whether a scenario drives the machine (until its parts are made)."""
        return self.active_scenario is not None

    @property
    def active_scenario(self) -> Scenario | None:
        """The scenario driving the machine (as started, its seed the machine's own), None
        when none does."""
        self._sync()
        return None if self._run is None else self._run.scenario

    def _play(self, run: _ScenarioRun, now: float) -> None:
        """Apply the scenario's events and ends due by ``now``, each at its own machine time
        (the engine's clock held there meanwhile, then at ``now`` again: this runs within
        :meth:`_sync`). An event due while another is under way begins when that one ends."""
        e = self.engine
        time = self._time
        try:
            while run.next_time <= now:
                when = run.next_time
                time.hold(when)
                for happened in e.take_events():
                    self._engine_event(happened, now)
                current = run.current
                if current is not None:
                    run.current = None
                    run.free_at = when
                    self._scenario_end(current, now)
                    continue
                event = run.schedule.pop()
                if e.state is not _START or run.finished(e):
                    self.scenario_log.append((event, "skipped"))
                    continue
                self._scenario_begin(event, when, now)
                run.current = event
                run.ends_at = when + event.duration
        finally:
            time.hold(now)

    def _scenario_begin(self, event: ScenarioEvent, when: float, now: float) -> None:
        e = self.engine
        self.scenario_log.append((event, "begin"))
        if event.kind == "pause":
            e.feed_hold()
        elif event.kind == "tool":
            e.program_stop()
        else:
            spec = SCENARIO_ALARMS[event.alarm]
            key = (event.axis, spec.alm_type, spec.alm_no)
            text = spec.message[:MAX_ALARM_TEXT]
            self._alarms.add(key, text, self._alarms.stamp(now - when))
            kind = _ALARM_KINDS.get(spec.alm_type, AlarmKind.PS)
            e.alarm_stop(NcAlarm(kind, spec.alm_no, text, axis=event.axis or None))
        self._settled(True, force=True)

    def _scenario_end(self, event: ScenarioEvent, now: float) -> None:
        e = self.engine
        self.scenario_log.append((event, "end"))
        if event.kind == "alarm":
            spec = SCENARIO_ALARMS[event.alarm]
            key = (event.axis, spec.alm_type, spec.alm_no)
            if not self._alarms.remove((key,)):
                return  # cleared by hand: the operator takes it from here
            self._reset_cycle()
        elif (event.kind == "pause" and e.state is not _HOLD) or (
            event.kind == "tool" and e.state is not _STOP
        ):
            return  # someone else changed the cycle meanwhile
        if not self._alarms.active and not self.panel.emergency and self.panel.mode == MEM:
            try:
                e.cycle_start()
            except NcStateError:
                pass
        self._settled(True, force=True)

    def spindle_loads(self) -> tuple[int, ...]:
        """The load of each spindle (one) in percent: 0 with the spindle stopped, a few
        percent turning without cutting, rising with the feed and the spindle speed while
        the program cuts, with a small noise that depends on :attr:`seed` and the machine
        time only (0 while the figures are set by hand)."""
        self._sync()
        if not self._driven:
            return (0,)
        e = self.engine
        wiggle = noise(self.seed, self._time.now(), 0)
        speed = e.actual_spindle_speed
        top = e.settings.max_spindle_speed
        return (spindle_load(e.cutting, e.actual_feed, speed, top, wiggle, self._hardness),)

    def servo_loads(self) -> tuple[int, ...]:
        """The servo load of each axis in percent: 0 at rest, rising with the axis's speed
        and more while it cuts, with a small noise as :meth:`spindle_loads` has."""
        self._sync()
        n = len(self.axes)
        if not self._driven:
            return (0,) * n
        e = self.engine
        when = self._time.now()
        cutting, feed = e.cutting, e.actual_feed
        rapid = e.settings.rapid_rates
        return tuple(
            servo_load(v, rapid[i], cutting, feed, noise(self.seed, when, i + 1))
            for i, v in enumerate(e.axis_speeds())
        )

    @property
    def motion(self) -> MotionData:
        """The motion figures: the engine's while it drives them (:attr:`driven`), else those
        :meth:`set_motion` set."""
        self._sync()
        if not self._driven:
            return self._motion
        version = self._counters.motion
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

    def _engine_variable(self, number: int) -> Decimal | None:
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
                return self._macros.values.get(number)
        return _system_value(value, POSITION_DECIMALS if number >= 5001 else 0)

    # -- the program store ---------------------------------------------------------------
    def program_directory(self) -> list[ProgramInfo]:
        """Every stored program (number, name, characters), by number."""
        return self.programs.directory()

    def program_text(self, number: int) -> str:
        """The text of program ``number`` as stored: EW_NUMBER when there is none."""
        try:
            return self.programs.text(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None

    def store_program(self, text: str, *, replace: bool = False) -> int:
        """Store one program (its O number is returned). EW_PROT (read-only machine), EW_DATA
        (not one O-number program), EW_NUMBER (number outside the store's range), EW_REJECT
        (the number is stored and ``replace`` is false), EW_BUSY (replacing a program being
        executed), EW_OVRFLOW (memory or directory full)."""
        self.check_writable()
        self._sync()
        try:
            number = self.programs.store(text, replace=replace).number
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        self._programs_changed()
        return number

    def delete_program(self, number: int) -> None:
        """Delete program ``number``: EW_PROT (read-only machine), EW_NUMBER (no such
        program), EW_BUSY (being executed). Deleting the main program unselects it."""
        self.check_writable()
        self._sync()
        try:
            self.programs.delete(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        self._programs_changed()

    def select_program(self, number: int) -> None:
        """Make ``number`` the main program (a program search): EW_PROT (read-only
        machine), EW_MODE (a mode other than MEM and EDIT), EW_NUMBER (no such program),
        EW_BUSY (another program is being executed)."""
        self.check_writable()
        self._sync()
        if self.panel.mode not in (MEM, EDIT):
            raise MachineError(EW.MODE, f"program search in mode {self.panel.mode}: MEM or EDIT")
        try:
            self.programs.select(number)
        except ProgramError as exc:
            raise _program_refusal(exc) from None
        self._driven = True
        self._programs_changed()
        self._settled(True, force=True)

    def _programs_changed(self) -> None:
        self._figures = None
        self._counters.motion += 1
        self._counters.version += 1

    # -- VersaMax ------------------------------------------------------------------------
    def module_record(self, rack: int, slot: int) -> IOModuleRecord | None:
        """The configuration record in ``rack``/``slot`` (None when empty)."""
        return self._station.records.get((rack, slot))

    def config_record(self, rack: int, slot: int) -> bytes:
        """The bytes of the configuration record in ``rack``/``slot``: EW_NUMBER when the slot
        is empty or out of range."""
        return self._station.config_record(rack, slot)

    def read_config(self, rack: int, slot: int, offset: int, length: int) -> bytes:
        """Up to ``length`` bytes of the configuration record in ``rack``/``slot`` from
        ``offset``: EW_NUMBER (empty slot), EW_NUMBER (offset outside the record)."""
        return self._station.read(rack, slot, offset, length)

    # -- whole-state view ----------------------------------------------------------------
    def state_digest(self) -> str:
        """A stable SHA-256 hex digest of all machine state (not of sessions or caches)."""
        h = hashlib.sha256()

        def put(*parts: object) -> None:
            h.update(repr(parts).encode())
            h.update(b"\n")

        put("axes", self.axes, self.read_only, self.control_enabled)
        for t, table in (("param", self._items.params), ("diag", self._items.diags)):
            for n in sorted(table):
                it = table[n]
                put(t, n, it.width, it.kind, it.decimals, it.axis, it.low, it.high, it.values)
        put("macro-ranges", [(r.first, r.last, r.writable) for r in self._macros.ranges])
        put("macros", sorted(self._macros.values.items()))
        for letter in sorted(self._pmc.areas):
            a = self._pmc.areas[letter]
            put("pmc", a.letter, a.size, a.write_protected)
            h.update(a.data)
        p = self.panel
        put("panel", p.mode, p.pwe, p.emergency, p.run, p.motion, p.mstb, p.edit, p.hdck, p.tmmode)
        put("password", self._lock.digest())
        put("active", list(self._alarms.active.values()))
        put("history", self.history_capacity, list(self._alarms.history))
        put("identity", self._identity)
        put("station", sorted(self._station.encoded.items()))
        m = self.motion
        put(
            "motion",
            m.absolute,
            m.machine,
            m.relative,
            m.distance_to_go,
            m.feed,
            m.spindle_speed,
            m.program_running,
            m.program_main,
            m.sequence,
        )
        return h.hexdigest()
