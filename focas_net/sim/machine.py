"""The simulated CNC: state and typed operations, in no protocol's terms.

A :class:`Machine` holds everything a FOCAS client can see of one CNC: axes, parameters,
diagnostics, macro variables, PMC areas, the operator panel, an optional parameter password,
active alarms and the alarm history, its identity (what ``cnc_sysinfo`` reports), a VersaMax I/O
station and the motion figures (positions, feed, spindle, program numbers).

The machine is a facade over components, each of one concern, in private modules beside this
one: identity and control class (``_identity``), parameters and diagnostics (``_items``), the
parameter password and sessions (``_password``), macro variables (``_macros``), PMC areas and
the G/F signals of automatic operation (``_pmc``), active alarms and the history
(``_alarms``), the VersaMax station (``_station``), and the path (``_path``): programs, NC
engine on machine time (``_time``), panel, status and figures, and its production on its own
(``_production``). A component keeps its own state and checks and moves the version counters
it shares with the others (``_base``); the machine builds them, asks for the checks in each
operation's order and answers its reads through them. A control with several paths would hold
one path each, sharing the rest.

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
The machine enforces what the CNC itself refuses, each check written once (here or in the
component whose state it guards) and asked in the order the operation's docstring gives:

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
* alarms: ``alm_type`` outside 0..31 -> EW_DATA, ``alm_no`` outside 0..32767 (what the CNC
  holds; -1 means "any" to :meth:`Machine.clear_alarms`) -> EW_DATA, ``axis_no`` outside
  0..axes -> EW_ATTRIB; the CNC keeps 32 characters of a message. The history keeps
  ``history_capacity`` entries; both are read to any depth;
* positions: an unknown kind -> EW_ATTRIB, the skip position -> EW_NOOPT (no skip function),
  an axis outside 1..n -> EW_ATTRIB;
* the VersaMax station: an empty (or impossible) rack/slot -> EW_NUMBER, an offset outside the
  record -> EW_NUMBER; a read returns what the record has from there, up to the length asked;
* the operator panel: a mode that is not an ``aut`` value other than 2, ``pwe`` or
  ``emergency`` other than 0/1 -> EW_DATA; a switch given as None stays as it is;
* the cycle: cycle start only in MEM, not with the emergency stop or an alarm (EW_ALARM; an
  alarm that stopped the cycle wants a reset), not without a main program (EW_DATA); program
  search only in MEM or EDIT (EW_MODE); leaving MEM holds the feed; the emergency stop resets;
  any alarm stops the cycle; reset clears the alarms the program raised.

What a wire cannot carry is its adapter's to refuse: payload sizes and layouts, unknown commands,
the packed protocol's ``type_a`` codes and ``type_d``, its ceiling of 32 PMC bytes, 32 alarm
messages, 250 history entries and 128 configuration bytes per call, the ``length`` word of its
ODBM, its position type numbers; the native protocol's answer size and its own numbering. Where
a wire's check sits in the middle of the order above, the adapter asks the machine for the
checks before it (:meth:`Machine.check_writable`, :meth:`Machine.check_pmc_area`,
:meth:`Machine.config_record`) and then calls the operation, which repeats them harmlessly.
Whether simulator control commands are served (``control_enabled``) is a flag the adapters read.

``unlock`` is session state, not machine state: it works on a read-only machine (the password's
rules: :mod:`focas_net.sim._password`).

Counters (:attr:`Machine.version` and the narrower ``*_version``) move on every change they
cover, so front ends can key caches of their answers on them.

Machine time
------------
The path's :class:`~focas_net.sim.nc.Engine` (:attr:`Machine.engine`) runs the programs of
:attr:`Machine.programs` on ``sim_clock``, machine time in seconds (``RealTimeClock()`` unless
given; :meth:`Machine.set_clock` changes it). Nothing ticks: every read and every counter
first brings the engine to the clock's time (:mod:`focas_net.sim._path`), a scenario's events
included (:mod:`focas_net.sim._production`). The other clock, ``clock``, stamps the alarms: one
the program raises is stamped ``clock()`` less the machine time since it was raised.
"""

from __future__ import annotations

import hashlib
import math
from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import astuple
from datetime import datetime
from decimal import Decimal

from focas_net.errors import EW
from focas_net.versamax import IOModuleRecord

from ._alarms import DEFAULT_HISTORY_CAPACITY, Alarm, Alarms, Clock, HistoryEntry, utc_now
from ._base import Counters, MachineError
from ._identity import (
    CONTROL_CLASSES,
    DEFAULT_CONTROL_CLASS,
    Identity,
    axes_problem,
    checked_identity,
    checked_name,
)
from ._items import MAX_REAL_DECIMALS as MAX_REAL_DECIMALS  # the native adapter's
from ._items import PARTS_COUNT, PARTS_TOTAL, DataItem, Items, ParamKind
from ._macros import MAX_MACRO_DECIMALS, MacroRange, Macros
from ._password import ParamLock, Session
from ._path import (
    AUT_MODES,
    ENGINE_VARIABLES,
    MDI,
    MEM,
    MODE_NAMES,
    PARTS_VARIABLES,
    POSITION_DECIMALS,
    POSITION_KINDS,
    TIMER_KINDS,
    MotionData,
    Panel,
    Path,
    Shared,
    Status,
    mode_name,
)
from ._pmc import F_SIGNALS, G_SIGNALS, PMC_AREAS, Pmc, PmcAreaSpec
from ._station import Station
from .nc import Engine, ProgramInfo, ProgramStore, RealTimeClock, SimClock
from .nc.scenario import DEFAULT_SCENARIO, Scenario, ScenarioEvent

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
    "MODE_NAMES",
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
        self._name = checked_name(name)
        #: How the machine runs on its own when it is told to (:meth:`start_scenario`;
        #: ``serve`` starts it): a machine file's ``[run]``, None when it has none.
        self.scenario = scenario
        self.axes: list[str] = list(axes)
        problem = axes_problem(self.axes)
        if problem is not None:
            raise ValueError(problem)
        n = len(self.axes)
        self._identity = checked_identity(identity, control_class, n)
        #: Which class of FANUC control this machine is (one of :data:`CONTROL_CLASSES`).
        self.control_class = control_class
        #: Whether the simulator control commands of a front end are served.
        self.control_enabled = control_enabled
        self.read_only = read_only
        panel = panel or Panel()
        if panel.mode not in AUT_MODES:
            raise ValueError(f"panel mode {panel.mode} is not an aut value")
        self._lock = ParamLock(param_password)
        self._station = Station(station or {})
        motion = motion or MotionData([0] * n, [0] * n, [0] * n, [0] * n)
        Path.check_motion(motion, n)
        c = self._counters = Counters()
        self._items = Items(params, diags, n, c)
        self._macros = Macros(macro_ranges, macro_values or {}, c)
        self._pmc = Pmc(pmc, c)
        self._alarms = Alarms(name, history_capacity, clock, c)
        self._path = Path(
            name,
            self.axes,
            Shared(c, self._items, self._macros, self._alarms, self._pmc),
            panel=panel,
            motion=motion,
            programs=programs,
            main_program=main_program,
            clock=sim_clock if sim_clock is not None else RealTimeClock(),
        )
        #: The operator panel and the run state it shows (the path's).
        self.panel: Panel = self._path.panel
        #: The programs in the machine's memory (the engine marks those in use).
        self.programs: ProgramStore = self._path.programs
        #: The NC engine that runs them.
        self.engine: Engine = self._path.engine
        #: The scenario's events as they were applied: ``(event, "begin" | "end" |
        #: "skipped")``, the newest 1000.
        self.scenario_log: deque[tuple[ScenarioEvent, str]] = self._path.production.log

    @property
    def name(self) -> str:
        """The machine's name (the server's ready line, the logs): 1..64 printable characters
        (:data:`MAX_NAME_LENGTH`; ValueError otherwise)."""
        return self._name

    @name.setter
    def name(self, name: str) -> None:
        self._name = self._alarms.name = self._path.name = checked_name(name)

    def __repr__(self) -> str:
        return f"Machine({self.name!r}, axes={''.join(self.axes)!r})"

    # -- counters (each brings the engine to the clock's time first) ---------------------
    @property
    def version(self) -> int:
        """Incremented on every change of machine state."""
        path = self._path
        if path.live:  # what moves with time
            path.sync()
        return self._counters.version

    @property
    def status_version(self) -> int:
        """Incremented when the status changes (panel, run state, motion, active alarms).
        While the cycle runs, time changes the status only when an action ends or a scenario
        event is due, so until then a read costs a clock call and two compares."""
        path = self._path
        if path.live and (
            path.time.now() >= path.steady_until or path.engine.revision != path.steady_revision
        ):
            path.sync()
        return self._counters.status

    @property
    def data_version(self) -> int:
        """Incremented when a parameter or diagnostic value changes (parts counts too)."""
        path = self._path
        if path.live:
            path.sync()
        return self._counters.data

    @property
    def macro_version(self) -> int:
        """Incremented when a macro variable changes (while a program runs: whenever machine
        time moved, for the system variables follow the engine)."""
        path = self._path
        if path.live:
            path.sync()
        return self._counters.macro

    @property
    def alarm_version(self) -> int:
        """Incremented when the active alarms or the alarm history change."""
        path = self._path
        if path.live:
            path.sync()
        return self._counters.alarm

    @property
    def pmc_version(self) -> int:
        """Incremented when PMC data changes."""
        path = self._path
        if path.live:
            path.sync()
        return self._counters.pmc

    @property
    def motion_version(self) -> int:
        """Incremented when the motion figures change: while a program runs, whenever machine
        time moved."""
        path = self._path
        if path.live:
            path.sync()
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

    def unlock(self, session: Session, password: str | bytes) -> None:
        """Unlock parameter writes for ``session``. ``password`` matches only when it is the
        machine's exactly (as 4 bytes padded with NUL: ``b"12\\0\\0"`` is ``"12"``); a longer
        one never matches, not even when it starts with the machine's. A mismatch answers
        EW_PASSWD and locks the session again. A machine without a password unlocks any."""
        self._lock.unlock(session, password)

    def status(self) -> Status:
        """The status, derived from the panel, the active alarms and (while it drives the
        figures) the engine's run state and motion."""
        path = self._path
        if path.live:
            path.sync()
        return path.status(1 if self._alarms.active else 0)

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
        if self._path.live:
            self._path.sync()
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
        return self.param_gate_closed(session) is None

    def param_gate_closed(self, session: Session) -> str | None:
        """Why a parameter write from ``session`` is refused (the first closed gate, in the
        order an operator opens them: PWE, MDI mode, the password), or None when it is open."""
        p = self.panel
        if p.pwe != 1:
            return "parameter write enable (PWE) is off"
        if p.mode != MDI:
            return f"the mode is {mode_name(p.mode)}, not MDI"
        if not self._lock.admits(session):
            return "the parameter password is not unlocked on this connection"
        return None

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
        closed = self.param_gate_closed(session)
        if closed is not None:
            raise MachineError(EW.PASSWD, f"parameter write not enabled: {closed}")
        value = items.rescaled(item, value, decimals)
        items.set(item, i, value, "parameter")
        if datano in (PARTS_COUNT, PARTS_TOTAL):
            self._path.set_parts(datano, value)

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
        path = self._path
        if path.live:
            path.sync()
        if number in PARTS_VARIABLES:
            return Decimal(path.parts(PARTS_VARIABLES[number]))
        if path.driven and any(number in r for r in ENGINE_VARIABLES):
            return path.engine_variable(number)
        return macros.values.get(number)

    def write_macro(self, number: int, value: Decimal | int | None) -> None:
        """Set macro variable ``number`` to ``value`` (None: vacant). EW_PROT (read-only
        machine), EW_NUMBER, EW_PROT (read-only variable), EW_DATA (a value the variable cannot
        hold: see the module docstring). Making a vacant variable vacant changes nothing."""
        self.check_writable()
        self._macros.check_write(number)
        if number in PARTS_VARIABLES:
            self._path.write_parts(number, value)
        else:
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
        if area.letter == "F" and self._path.live:
            self._path.sync()  # the F signals follow the run state
        end = start + length
        if start < 0 or end > area.size:
            raise area.beyond(start, end)
        return bytes(area.data[start:end])

    def write_pmc(self, letter: str, start: int, data: bytes, *, force: bool = False) -> None:
        """Write ``data`` into area ``letter`` from address ``start`` (``force``: the
        simulator's own write, which ignores write protection): EW_PROT (read-only machine),
        EW_NOOPT, EW_NUMBER (addresses outside the area), EW_PROT (write-protected area).
        A write that changes G signals of automatic operation (:data:`G_SIGNALS`) acts on
        them as the CNC does."""
        self.check_writable()
        asked = self._pmc.write(letter, start, data, force)
        if asked is not None:
            self._path.apply(asked)

    # -- alarms --------------------------------------------------------------------------
    def active_alarms(self, alm_type: int = -1, limit: int | None = None) -> list[Alarm]:
        """The active alarms of ``alm_type`` (-1: every type; a type no alarm has matches
        nothing), oldest raised first, at most ``limit`` of them (None: all)."""
        self._path.sync()
        return self._alarms.read(alm_type, limit)

    def alarm_history(self, depth: int | None = None) -> tuple[HistoryEntry, ...]:
        """The ``depth`` newest entries of the history (None: all), newest first."""
        self._path.sync()
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
        text. EW_PROT (read-only machine), EW_DATA (alm_type outside 0..31, alm_no outside
        0..32767), EW_ATTRIB (axis_no), EW_DATA (a character beyond U+00FF). Any alarm stops
        the cycle."""
        self.check_writable()
        text = self._alarms.checked(axis_no, alm_type, alm_no, msg, len(self.axes))
        self._path.sync()
        key = (axis_no, alm_type, alm_no)
        if not self._alarms.add(key, text, self.now()):
            return False
        self._path.alarm_stop(key, text)
        return True

    def clear_alarms(self, alm_type: int = -1, alm_no: int = -1) -> int:
        """Remove the active alarms matching ``alm_type`` and ``alm_no`` (-1 = any); the
        history is kept. Returns how many were removed. EW_PROT on a read-only machine."""
        self.check_writable()
        return self._alarms.clear(alm_type, alm_no)

    # -- operator panel and motion figures -----------------------------------------------
    def set_panel(
        self, mode: int | None = None, pwe: int | None = None, emergency: int | None = None
    ) -> None:
        """Set the operator panel: ``mode`` an ``aut`` value other than 2, ``pwe`` and
        ``emergency`` 0/1, else EW_DATA; a switch given as None stays as it is. EW_PROT on a
        read-only machine. Leaving MEM holds the feed; the emergency stop resets."""
        self.check_writable()
        self._path.set_panel(mode, pwe, emergency)

    def set_run(self, run: int, motion: int = 0) -> None:
        """Set the run state (0 reset, 1 STOP, 2 HOLD, 3 STRT, 4 MSTR) and motion (0, 1 MTN,
        2 DWL) shown by the status (simulation code only): EW_DATA otherwise."""
        self._path.set_run(run, motion)

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
        self._path.set_motion(
            (absolute, machine, relative, distance_to_go),
            (feed, spindle_speed, program_running, program_main, sequence),
        )

    @property
    def motion(self) -> MotionData:
        """The motion figures: the engine's while it drives them (:attr:`driven`), else those
        :meth:`set_motion` set."""
        return self._path.figures()

    def positions(self, kind: str, axis: int | None = None) -> list[tuple[str, int]]:
        """``(axis name, value)`` of every axis (``axis`` None) or of axis ``axis`` (1..n), in
        least input increments (:data:`POSITION_DECIMALS` decimals). ``kind`` is one of
        :data:`POSITION_KINDS`. Checks, in order: an unknown kind -> EW_ATTRIB; ``"skip"`` ->
        EW_NOOPT (the machine has no skip function); ``axis`` outside 1..n -> EW_ATTRIB."""
        return self._path.positions(kind, axis)

    @property
    def driven(self) -> bool:
        """Whether the engine shows the run state and the motion figures: from a cycle start
        or a program selection until :meth:`set_motion` or :meth:`set_run` sets them by hand
        (before, the figures given to the constructor or by hand are shown)."""
        return self._path.driven

    # -- machine time and the cycle ------------------------------------------------------
    @property
    def sim_clock(self) -> SimClock:
        """The clock of machine time (seconds): ``RealTimeClock()`` unless the constructor or
        :meth:`set_clock` gave another."""
        return self._path.time.source

    def set_clock(self, clock: SimClock) -> None:
        """Take machine time from ``clock`` from now on: the engine, the timers and a running
        scenario read it (a fleet shares one: ``serve --speed``; a test gives a
        :class:`~focas_net.sim.nc.ManualClock` and steps it). This is the one way the
        engine's clock is set after the constructor's ``sim_clock``. The machine goes on from
        where it is, so ``clock`` may not be behind the machine's time (ValueError); the time
        it is ahead passes at once, as if the machine had been left alone that long."""
        self._path.set_clock(clock)

    def cycle_start(self, *, repeat: bool | None = None) -> None:
        """Cycle start: run the main program from its head (reset), go on (stop) or resume
        (feed hold). EW_PROT (read-only machine), EW_ALARM (emergency stop, an active alarm,
        or an alarm that stopped the cycle and wants a reset), EW_MODE (not MEM), EW_DATA (no
        main program). From here the engine shows the run state and the figures.

        ``repeat`` True: production, the main program starts again at once after each M2/M30
        (a part counted each time) until ``repeat`` False is given or an alarm stops it; None
        leaves the setting as it is."""
        self.check_writable()
        self._path.cycle_start(repeat)

    def feed_hold(self) -> None:
        """Feed hold: the axes stop where they are (HOLD); cycle start resumes. EW_PROT on a
        read-only machine."""
        self.check_writable()
        self._path.feed_hold()

    def reset(self) -> None:
        """Reset: the cycle stops and rewinds, the alarms the program raised are cleared (the
        history keeps them). EW_PROT on a read-only machine."""
        self.check_writable()
        self._path.reset()

    def set_overrides(
        self, feed: int | None = None, rapid: int | None = None, spindle: int | None = None
    ) -> None:
        """Feed override 0..254 %, rapid override 0..100 %, spindle override 0..254 % (None:
        unchanged): EW_PROT (read-only machine), EW_DATA (a value outside its range)."""
        self.check_writable()
        self._path.set_overrides(feed, rapid, spindle)

    def parts_counts(self) -> tuple[int, int]:
        """Parts count and total parts (M2/M30 count them; parameters 6711 and 6712)."""
        return self._path.parts_counts()

    def overrides(self) -> tuple[int, int, int]:
        """Feed, rapid and spindle override in percent."""
        return self._path.overrides()

    def timer(self, kind: int) -> float:
        """Seconds of timer ``kind`` (FANUC's ``cnc_rdtimer`` types): 0 power-on (machine
        time since the machine was built), 1 operating, 2 cutting, 3 cycle (this cycle's time
        since its start from reset); EW_NUMBER for another kind."""
        return self._path.timer(kind)

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
        self._path.production.start(scenario or self.scenario or DEFAULT_SCENARIO)

    def stop_scenario(self) -> None:
        """Stop running on its own: the cycle goes on as it is (production without the
        scenario's events and part limit)."""
        self._path.production.stop()

    @property
    def scenario_running(self) -> bool:
        """Whether a scenario drives the machine (until its parts are made)."""
        return self.active_scenario is not None

    @property
    def active_scenario(self) -> Scenario | None:
        """The scenario driving the machine (as started, its seed the machine's own), None
        when none does."""
        return self._path.production.active()

    @property
    def seed(self) -> int:
        """The seed of the loads' noise (a scenario's seed once one runs)."""
        return self._path.production.seed

    @seed.setter
    def seed(self, seed: int) -> None:
        self._path.production.seed = seed

    def spindle_loads(self) -> tuple[int, ...]:
        """The load of each spindle (one) in percent: 0 with the spindle stopped, a few
        percent turning without cutting, rising with the feed and the spindle speed while
        the program cuts, with a small noise that depends on :attr:`seed` and the machine
        time only (0 while the figures are set by hand)."""
        return self._path.production.spindle_loads()

    def servo_loads(self) -> tuple[int, ...]:
        """The servo load of each axis in percent: 0 at rest, rising with the axis's speed
        and more while it cuts, with a small noise as :meth:`spindle_loads` has."""
        return self._path.production.servo_loads()

    # -- the program store ---------------------------------------------------------------
    def program_directory(self) -> list[ProgramInfo]:
        """Every stored program (number, name, characters), by number."""
        return self.programs.directory()

    def program_text(self, number: int) -> str:
        """The text of program ``number`` as stored: EW_NUMBER when there is none."""
        return self._path.program_text(number)

    def store_program(self, text: str, *, replace: bool = False) -> int:
        """Store one program (its O number is returned). EW_PROT (read-only machine), EW_DATA
        (not one O-number program), EW_NUMBER (number outside the store's range), EW_REJECT
        (the number is stored and ``replace`` is false), EW_BUSY (replacing a program being
        executed), EW_OVRFLOW (memory or directory full)."""
        self.check_writable()
        return self._path.store_program(text, replace)

    def delete_program(self, number: int) -> None:
        """Delete program ``number``: EW_PROT (read-only machine), EW_NUMBER (no such
        program), EW_BUSY (being executed). Deleting the main program unselects it."""
        self.check_writable()
        self._path.delete_program(number)

    def select_program(self, number: int) -> None:
        """Make ``number`` the main program (a program search): EW_PROT (read-only
        machine), EW_MODE (a mode other than MEM and EDIT), EW_NUMBER (no such program),
        EW_BUSY (another program is being executed)."""
        self.check_writable()
        self._path.select_program(number)

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
        put("panel", *astuple(self.panel))
        put("password", self._lock.digest())
        put("active", list(self._alarms.active.values()))
        put("history", self.history_capacity, list(self._alarms.history))
        put("identity", self._identity)
        put("station", sorted(self._station.encoded.items()))
        put("motion", *astuple(self.motion))
        return h.hexdigest()
