"""The simulated CNC: state and typed operations, in no protocol's terms.

A :class:`Machine` holds everything a FOCAS client can see of one CNC: axes, parameters,
diagnostics, macro variables, PMC areas, the operator panel, an optional parameter password,
active alarms and the alarm history, its identity (what ``cnc_sysinfo`` reports), a VersaMax I/O
station and the motion figures (positions, feed, spindle, program numbers).

The machine is a facade over components, each of one concern, in private modules beside this
one: identity and control class (``_identity``), parameters and diagnostics (``_items``), the
parameter password and sessions (``_password``), macro variables (``_macros``), PMC areas and
the G/F signals of automatic operation (``_pmc``), active alarms and the history (``_alarms``,
read, raised and cleared by the operations of ``_alarm_ops``), the VersaMax station
(``_station``), and the path (``_path``): programs, NC engine on machine time (``_time``),
panel, status and figures, and its production on its own (``_production``), and the program
folders of a 30i-class control over the paths' programs (``_folders``).
A component keeps its own state and checks and moves the version counters
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
  any alarm stops the cycle; reset clears the alarms the program raised;
* the program folders (``_folders``): a 16i-class control has none (EW_FUNC), then EW_PATH, a
  name that is no folder or no file of the tree -> EW_DATA, deleting a program being executed
  -> EW_REJECT.

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
from collections import deque
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import astuple, replace
from decimal import Decimal

from focas_net._refusals import (
    PARAM_GATE,
    READ_ONLY_MACHINE,
    no_item,
    param_refusal,
    system_read_only,
)
from focas_net.errors import EW
from focas_net.versamax import IOModuleRecord

from ._alarm_ops import AlarmOperations
from ._alarms import (
    DEFAULT_HISTORY_CAPACITY,
    MAX_HISTORY_CAPACITY,
    Alarm,
    Alarms,
    Clock,
    HistoryEntry,
    utc_now,
)
from ._base import (
    Counters,
    MachineError,
    n_bytes,
    need_flag,
    need_int,
    need_items,
    need_mapping,
    need_one,
)
from ._folders import FolderOperations
from ._identity import (
    CONTROL_CLASSES,
    DEFAULT_CONTROL_CLASS,
    Identity,
    checked_identity,
    checked_name,
    known_class,
)
from ._information import InformationOperations
from ._items import MAX_REAL_DECIMALS as MAX_REAL_DECIMALS  # the native adapter's
from ._items import PARTS_COUNT, PARTS_TOTAL, DataItem, Items, ParamKind
from ._known_params import check_known, check_rename, with_known_ranges
from ._macros import MAX_MACRO_DECIMALS, MacroRange, Macros
from ._modal import ModalOperations
from ._password import ParamLock, Session, need_session
from ._path import ENGINE_VARIABLES, PARTS_VARIABLES, Path, Shared
from ._paths import (
    MAX_PATHS,
    PATH_PARAMS,
    SETTING_PARAMS,
    PathInfo,
    PathItems,
    Paths,
    PathSpec,
    checked_specs,
    kind_of,
    own_params,
    path_specs,
)
from ._pmc import F_SIGNALS, G_SIGNALS, PMC_AREAS, Pmc, PmcAreaSpec, need_pmc_count
from ._signals import (
    CLOCK_VARIABLES,
    SERVO_POWER_DIAG,
    TIMER_PARAMS,
    Collected,
    SignalOperations,
    clock_variable,
    collected_diags,
    collected_params,
)
from ._station import Station
from ._status import (
    AUT_MODES,
    MDI,
    MEM,
    MODE_NAMES,
    POSITION_DECIMALS,
    POSITION_KINDS,
    TIMER_KINDS,
    MotionData,
    Panel,
    Status,
    mode_name,
)
from ._tool_ops import ToolOperations, build_tools
from ._tools import ToolsSpec
from .nc import Engine, ProgramStore, RealTimeClock, SimClock, check_sim_clock
from .nc.scenario import Scenario, ScenarioEvent, checked_scenario
from .nc.waits import PathSync

__all__ = [
    "AUT_MODES",
    "CONTROL_CLASSES",
    "DEFAULT_CONTROL_CLASS",
    "DEFAULT_HISTORY_CAPACITY",
    "F_SIGNALS",
    "G_SIGNALS",
    "MAX_HISTORY_CAPACITY",
    "MAX_MACRO_DECIMALS",
    "MAX_PATHS",
    "MDI",
    "MEM",
    "MODE_NAMES",
    "PATH_PARAMS",
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
    "PathInfo",
    "PathSpec",
    "PmcAreaSpec",
    "Session",
    "Status",
    "utc_now",
]


class Machine(
    AlarmOperations,
    FolderOperations,
    SignalOperations,
    ToolOperations,
    ModalOperations,
    InformationOperations,
):
    """One simulated CNC.

    Build one with :func:`focas_net.sim.default_machine`, :func:`focas_net.sim.load_machine` or
    this constructor. Everything is synchronous; a front end calls it from one thread.

    A machine has 1..10 paths (:data:`MAX_PATHS`): ``paths`` describes each
    (:class:`PathSpec`); without it the machine has one path of ``axes``, ``programs``,
    ``main_program``, ``panel`` and ``motion``, which may not be given with ``paths``.
    """

    def __init__(
        self,
        name: str,
        *,
        axes: Iterable[str] | None = None,
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
        paths: Sequence[PathSpec] | None = None,
        tools: Mapping[int, ToolsSpec] | None = None,
    ) -> None:
        self._name = checked_name(name)
        params, diags = need_items("params", params, DataItem), need_items("diags", diags, DataItem)
        macro_ranges = need_items("macro_ranges", macro_ranges, MacroRange)
        macro_values = need_mapping("macro_values", macro_values, int, (Decimal, int, type(None)))
        pmc = need_items("pmc", pmc, PmcAreaSpec)
        station = need_mapping("station", station, tuple, IOModuleRecord)
        tools = need_mapping("tools", tools, int, ToolsSpec) if tools is not None else None
        paths = need_items("paths", paths, PathSpec) if paths is not None else None
        identity = need_one("identity", identity, Identity)
        panel, motion = need_one("panel", panel, Panel), need_one("motion", motion, MotionData)
        #: How the machine runs on its own when it is told to (:meth:`start_scenario`;
        #: ``serve`` starts it): a machine file's ``[run]``, None when it has none.
        self.scenario = checked_scenario(scenario)
        specs = path_specs(paths, axes, panel, motion, programs, main_program, identity)
        infos = checked_specs(specs)
        #: Every axis of the machine, path by path.
        self.axes: list[str] = [a for info in infos for a in info.axes]
        n = len(self.axes)
        control_class = known_class(control_class)  # "30I" as a machine file takes it
        self._identity = checked_identity(identity, control_class, n)
        #: Which class of FANUC control this machine is (one of :data:`CONTROL_CLASSES`).
        self.control_class = control_class
        #: Whether the simulator control commands of a front end are served.
        self.control_enabled = need_flag("control_enabled", control_enabled)
        self.read_only = need_flag("read_only", read_only)
        for spec in specs:
            if spec.panel is not None and spec.panel.mode not in AUT_MODES:
                raise ValueError(f"panel mode {spec.panel.mode} is not an aut value")
            if spec.motion is not None:
                Path.check_motion(spec.motion, len(spec.axes))
        self._lock = ParamLock(param_password)
        self._station = Station(station or {})
        c = self._counters = Counters()
        self._items = Items(
            collected_params(with_known_ranges(params)), collected_diags(diags), n, c
        )
        check_known(self._items, self.axes)  # the types of what the machine reads, 1020
        self._collected = Collected()
        self._macros = Macros(macro_ranges, macro_values or {}, c)
        self._pmc = Pmc(pmc, c)
        self._pmc.paths = len(specs)
        self._alarms = Alarms(name, history_capacity, clock, c)
        shared = Shared(c, self._items, self._macros, self._alarms, self._pmc)
        time = RealTimeClock() if sim_clock is None else check_sim_clock(sim_clock, "sim_clock")
        built: list[Path] = []
        offset = 0
        sync = PathSync() if len(specs) > 1 else None
        for spec, info in zip(specs, infos, strict=True):
            k = len(info.axes)
            built.append(
                Path(
                    name if len(specs) == 1 else f"{name}/{info.name}",
                    list(info.axes),
                    shared,
                    number=info.number,
                    lathe=info.kind == "T",
                    items=PathItems(self._items, offset, k, own_params(self._items, info.number)),
                    sync=sync,
                    path_count=len(specs),
                    panel=spec.panel or Panel(),
                    motion=spec.motion or MotionData([0] * k, [0] * k, [0] * k, [0] * k),
                    programs=spec.programs,
                    main_program=spec.main_program,
                    clock=time,
                )
            )
            offset += k
        for p in built:
            p.group = built
        self._paths = Paths(built, infos)
        #: Each path's tool offsets and tool life (``tools``: per path number).
        self._tools = build_tools(self._paths, tools or {})
        self._path = first = built[0]
        #: Path 1's operator panel and the run state it shows (:meth:`path_panel`).
        self.panel: Panel = first.panel
        #: Path 1's programs (the engine marks those in use; :meth:`path_programs`).
        self.programs: ProgramStore = first.programs
        #: Path 1's NC engine that runs them (:meth:`path_engine`).
        self.engine: Engine = first.engine
        #: The scenario's events as they were applied: ``(event, "begin" | "end" |
        #: "skipped")``, the newest 1000.
        self.scenario_log: deque[tuple[ScenarioEvent, str]] = first.production.log
        for number in range(1, len(built) + 1):  # the G signals of the overrides in use
            self._show_overrides(number)
        self._show_state()
        self._init_folders()

    @property
    def name(self) -> str:
        """The machine's name (the server's ready line, the logs): 1..64 printable characters
        (:data:`MAX_NAME_LENGTH`; ValueError otherwise)."""
        return self._name

    @name.setter
    def name(self, name: str) -> None:
        self._name = self._alarms.name = checked_name(name)
        for p, info in zip(self._paths, self._paths.infos, strict=True):
            p.name = name if self._paths.count == 1 else f"{name}/{info.name}"

    def __repr__(self) -> str:
        """``Machine('focas-sim-0i', axes=('X', 'Y', 'Z'))``; a machine of several paths shows
        each path's axes (``paths=[('X1', 'Z1'), ('X2', 'Z2')]``), never the names run
        together."""
        infos = self._paths.infos
        if len(infos) == 1:
            return f"Machine({self.name!r}, axes={tuple(self.axes)!r})"
        return f"Machine({self.name!r}, paths={[tuple(i.axes) for i in infos]!r})"

    # -- paths ---------------------------------------------------------------------------
    @property
    def path_count(self) -> int:
        """How many paths the machine has (1..10)."""
        return self._paths.count

    def path_info(self, path: int = 1) -> PathInfo:
        """What path ``path`` is (number, name, kind, axes, spindles): EW_PATH for a path
        the machine has not."""
        return self._paths.info(path)

    def path_panel(self, path: int = 1) -> Panel:
        """The operator panel of ``path`` (EW_PATH)."""
        return self._paths.at(path).panel

    def path_programs(self, path: int = 1) -> ProgramStore:
        """The program store of ``path`` (EW_PATH)."""
        return self._paths.at(path).programs

    def path_engine(self, path: int = 1) -> Engine:
        """The NC engine of ``path`` (EW_PATH)."""
        return self._paths.at(path).engine

    def _sync(self) -> None:
        """Bring every path to the clock's time."""
        paths = self._paths
        if paths.count == 1:
            self._path.sync()
        else:
            paths.sync()

    # -- counters (each brings the engines to the clock's time first) --------------------
    @property
    def version(self) -> int:
        """Incremented on every change of machine state."""
        if self._paths.live:  # what moves with time
            self._sync()
        return self._counters.version

    @property
    def status_version(self) -> int:
        """Incremented when the status of a path changes (panel, run state, motion, active
        alarms). While the cycle runs, time changes the status only when an action ends or a
        scenario event is due, so until then a read costs a clock call and two compares."""
        for path in self._paths.all:
            if path.live and (
                path.time.now() >= path.steady_until or path.engine.revision != path.steady_revision
            ):
                self._sync()
                break
        return self._counters.status

    @property
    def data_version(self) -> int:
        """Incremented when a parameter or diagnostic value changes (parts counts, and the
        run-time parameters as time moves)."""
        if self._paths.live:
            self._sync()
        self._tick_data()
        return self._counters.data

    @property
    def macro_version(self) -> int:
        """Incremented when a macro variable changes (while a program runs: whenever machine
        time moved, for the system variables follow the engine)."""
        if self._paths.live:
            self._sync()
        self._tick_macro()
        return self._counters.macro

    @property
    def alarm_version(self) -> int:
        """Incremented when the active alarms or the alarm history change."""
        if self._paths.live:
            self._sync()
        return self._counters.alarm

    @property
    def pmc_version(self) -> int:
        """Incremented when PMC data changes (the F signals of the state as it changes)."""
        if self._paths.live:
            self._sync()
        self._show_state()
        return self._counters.pmc

    @property
    def motion_version(self) -> int:
        """Incremented when the motion figures change: while a program runs, whenever machine
        time moved."""
        if self._paths.live:
            self._sync()
        return self._counters.motion

    def check_writable(self) -> None:
        """EW_PROT when the machine is read-only: the first check of every write."""
        if self.read_only:
            raise MachineError(EW.PROT, READ_ONLY_MACHINE)

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

    def status(self, *, path: int = 1) -> Status:
        """The status of ``path``, derived from its panel, its active alarms and (while it
        drives the figures) its engine's run state and motion (``motion`` 3 while it waits
        at a waiting M code for the other paths)."""
        p = self._paths.at(path)
        if self._paths.live:
            self._sync()
        return p.status(1 if self._alarms.on(path) else 0)

    def identity(self) -> Identity:
        """What the CNC says it is."""
        return self._identity

    def path_identity(self, path: int = 1) -> Identity:
        """What the CNC says it is on ``path`` (``cnc_sysinfo`` after ``cnc_setpath``):
        EW_PATH for a path the machine has not. The axes are the path's, and the machine
        type is the machine's code when that is of the path's kind (a lathe of two paths
        reports ``"TT"`` on each, as FANUC's T series of 2/3 paths does), else the kind's
        own (``" M"`` on the milling path of a machine whose code is ``"TT"``, ``" T"`` on a
        lathe path of a machine left at ``" M"``)."""
        info = self.path_info(path)
        i = self._identity
        mt_type = i.mt_type if kind_of(i.mt_type) == info.kind else f" {info.kind}"
        return replace(i, mt_type=mt_type, axes=f"{len(info.axes):02d}")

    # -- parameters and diagnostics ------------------------------------------------------
    def param_item(self, datano: int) -> DataItem | None:
        """The description of parameter ``datano`` (None when the machine has none)."""
        need_int("parameter number", datano)
        return self._items.params.get(datano)

    def diag_item(self, datano: int) -> DataItem | None:
        """The description of diagnostic ``datano`` (None when the machine has none)."""
        need_int("diagnostic number", datano)
        return self._items.diags.get(datano)

    def param_numbers(self) -> tuple[int, ...]:
        """The numbers of every parameter, ascending."""
        return tuple(sorted(self._items.params))

    def diag_numbers(self) -> tuple[int, ...]:
        """The numbers of every diagnostic, ascending."""
        return tuple(sorted(self._items.diags))

    def read_param(self, datano: int, axis: int, *, path: int = 1) -> int:
        """The value of parameter ``datano`` (``axis`` 0 for a non-axis item, else 1..n, the
        axes of ``path``; a path-type parameter, :data:`PATH_PARAMS`, the path's own value):
        EW_PATH, EW_NUMBER, then EW_ATTRIB. Its width is :meth:`param_item`'s."""
        p = self._paths.at(path)
        if self._paths.live:
            self._sync()
        item, i = p.items.lookup(False, datano, axis)
        if datano in TIMER_PARAMS:
            return self._timer_param(datano, item, path)
        return item.values[i]

    def read_diag(self, datano: int, axis: int, *, path: int = 1) -> int:
        """The value of diagnostic ``datano`` (axes those of ``path``; a spindle diagnostic's
        ``axis`` is the spindle, see :mod:`._signals`): EW_PATH, EW_NUMBER, then EW_ATTRIB."""
        need_int("number", datano)
        need_int("axis", axis)
        spindle = self._spindle_diag(datano, axis, path)
        if spindle is not None:
            return spindle
        item, i = self._paths.at(path).items.lookup(True, datano, axis)
        if datano == SERVO_POWER_DIAG and item.axis:
            return self._servo_power(axis, path)
        return item.values[i]

    def param_gate_open(self, session: Session, *, path: int = 1) -> bool:
        """PWE on, ``path`` in MDI mode, and (when there is a password) this session
        unlocked."""
        return self.param_gate_closed(session, path=path) is None

    def param_gate_closed(self, session: Session, *, path: int = 1) -> str | None:
        """Why a parameter write from ``session`` to ``path`` is refused (the first closed
        gate, in the order an operator opens them: PWE, MDI mode, the password), or None when
        it is open."""
        need_session(session)
        p = self._paths.at(path).panel
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
        path: int = 1,
    ) -> None:
        """Write parameter ``datano``; ``width`` is the width (1, 2, 4, 8 for a real) the value
        was given in, checked against the parameter's type when given. ``value`` is in the
        parameter's terms: 0..255 for a bit parameter, the mantissa of a real one. EW_PROT
        (read-only machine), EW_NUMBER, EW_ATTRIB, EW_LENGTH (width), EW_PASSWD (write gate),
        EW_DATA (range).

        ``decimals`` (a real parameter only) says how many decimals the mantissa ``value``
        has: it is rescaled to the parameter's own, and a value that does not have an exact
        mantissa there (``1.2345`` for a 3-decimal parameter) is EW_DATA.

        ``path`` says whose axes ``axis`` numbers, whose value of a path-type parameter is
        written, and whose mode the write gate asks (EW_PATH before everything but the
        read-only machine)."""
        self.check_writable()
        need_session(session)
        for what, given in (("width", width), ("decimals", decimals)):
            if given is not None:
                need_int(f"parameter {what}", given)
        p = self._paths.at(path)
        items = self._items
        item, i = p.items.lookup(False, datano, axis)
        if width is not None and width != item.width:
            raise MachineError(EW.LENGTH, f"parameter {datano} is {n_bytes(item.width)} wide")
        closed = self.param_gate_closed(session, path=path)
        if closed is not None:
            raise MachineError(EW.PASSWD, f"{PARAM_GATE}: {closed}")
        value = items.rescaled(item, value, decimals)
        check_rename(datano, value, self.axes[i])
        try:
            items.set(item, i, value, "parameter")
        except MachineError as exc:  # its range: in the words every front end gives
            raise MachineError(EW.DATA, self._range_refusal(item, axis, value)) from exc
        if datano in TIMER_PARAMS:
            self._write_timer_param(datano, value, path)
        if datano in (PARTS_COUNT, PARTS_TOTAL):
            p.set_parts(datano, value)
        elif datano in SETTING_PARAMS:
            for each in self._paths:  # from the next block, as a control applies them
                each.take_settings()

    @staticmethod
    def _range_refusal(item: DataItem, axis: int, value: int) -> str:
        """Why parameter ``item`` of ``axis`` does not take ``value`` (in its terms)."""
        assert item.low is not None and item.high is not None
        shown = Decimal(value).scaleb(-item.decimals) if item.kind is ParamKind.REAL else value
        span = (item.low, item.high)
        return param_refusal(EW.DATA, item.number, shown, axis=axis, span=span) or ""

    def set_diag(self, datano: int, axis: int, value: int, *, path: int = 1) -> None:
        """Change a diagnostic value (simulation code; a CNC has no diagnostic write):
        EW_PATH, EW_NUMBER, EW_ATTRIB, EW_DATA (range)."""
        item, i = self._paths.at(path).items.lookup(True, datano, axis)
        self._items.set(item, i, value, "diagnostic")

    # -- macro variables -----------------------------------------------------------------
    def macro_writable(self, number: int) -> bool | None:
        """True/False for a writable/read-only variable; None when there is no such variable."""
        need_int("macro number", number)
        if number in CLOCK_VARIABLES:
            return False
        r = self._macros.range_of(number)
        return None if r is None else r.writable

    def read_macro(self, number: int, *, path: int = 1) -> Decimal | None:
        """The value of macro variable ``number`` as ``path`` sees it (#100-#199 and the
        system variables its own, #500-#999 shared), None when vacant: EW_PATH, EW_NUMBER for
        an unknown variable."""
        need_int("macro variable number", number)
        p = self._paths.at(path)
        macros = self._macros
        if number in CLOCK_VARIABLES:
            self._follow_clock()
            return Decimal(clock_variable(number, self.now()))
        if macros.range_of(number) is None:
            raise MachineError(EW.NUMBER, no_item("macro variable", f"#{number}"))
        if self._paths.live:
            self._sync()
        if number in PARTS_VARIABLES:
            return Decimal(p.parts(PARTS_VARIABLES[number]))
        if p.driven and any(number in r for r in ENGINE_VARIABLES):
            return p.engine_variable(number)
        return p.macro_values(number).get(number)

    def write_macro(self, number: int, value: Decimal | int | None, *, path: int = 1) -> None:
        """Set macro variable ``number`` of ``path`` (see :meth:`read_macro`) to ``value``
        (None: vacant). EW_PROT (read-only machine), EW_PATH, EW_NUMBER, EW_PROT (read-only
        variable), EW_DATA (a value the variable cannot hold: see the module docstring).
        Making a vacant variable vacant changes nothing."""
        need_int("macro variable number", number)
        self.check_writable()
        p = self._paths.at(path)
        if number in CLOCK_VARIABLES:
            raise MachineError(EW.PROT, system_read_only(number) or READ_ONLY_MACHINE)
        self._macros.check_write(number)
        if number in PARTS_VARIABLES:
            p.write_parts(number, value)
        else:
            self._macros.write(number, value, p.macro_values(number))

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
        EW_LENGTH (a ``length`` below 1: a PMC range holds one byte at least, as FANUC's
        ``pmc_rdpmcrng`` from ``s`` to ``e`` does), EW_NUMBER (addresses outside the area)."""
        area = self._pmc.area(letter)
        need_int("PMC start address", start)
        need_pmc_count(need_int("PMC byte count", length))
        if area.letter == "F":
            if self._paths.live:
                self._sync()  # the F signals follow the run state
            self._show_state()
        end = start + length
        if start < 0 or end > area.size:
            raise area.beyond(start, end)
        return bytes(area.data[start:end])

    def write_pmc(self, letter: str, start: int, data: bytes, *, force: bool = False) -> None:
        """Write ``data`` into area ``letter`` from address ``start`` (``force``: the
        simulator's own write, which ignores write protection): EW_PROT (read-only machine),
        EW_NOOPT, EW_LENGTH (no bytes: a PMC range holds one at least, as :meth:`read_pmc`'s),
        EW_NUMBER (addresses outside the area), EW_PROT (write-protected area).
        A write that changes G signals of automatic operation (:data:`G_SIGNALS`) acts on
        them as the CNC does."""
        self.check_writable()
        need_flag("force", force)
        for path, asked in self._pmc.write(letter, start, data, force):
            self._paths.at(path).apply(asked)
            self._show_overrides(path)
        if letter.upper() == "G":
            self._watch_meters()

    # -- VersaMax ------------------------------------------------------------------------
    def module_record(self, rack: int, slot: int) -> IOModuleRecord | None:
        """The configuration record in ``rack``/``slot`` (None when empty)."""
        need_int("rack", rack)
        need_int("slot", slot)
        return self._station.records.get((rack, slot))

    def config_record(self, rack: int, slot: int) -> bytes:
        """The bytes of the configuration record in ``rack``/``slot``: EW_NUMBER when the slot
        is empty or out of range."""
        need_int("rack", rack)
        need_int("slot", slot)
        return self._station.config_record(rack, slot)

    def read_config(self, rack: int, slot: int, offset: int, length: int) -> bytes:
        """Up to ``length`` bytes of the configuration record in ``rack``/``slot`` from
        ``offset``: EW_NUMBER (empty slot), EW_NUMBER (offset outside the record)."""
        for what, value in (("rack", rack), ("slot", slot), ("offset", offset), ("length", length)):
            need_int(what, value)
        return self._station.read(rack, slot, offset, length)

    # -- whole-state view ----------------------------------------------------------------
    def state_digest(self) -> str:
        """A stable SHA-256 hex digest of all machine state (not of sessions or caches)."""
        h = hashlib.sha256()

        def put(*parts: object) -> None:
            h.update(repr(parts).encode())
            h.update(b"\n")

        self._show_state()  # the F signals of the state, as a read shows them
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
        for p in self._paths.all[1:]:
            put("path", p.number, *astuple(p.panel), *astuple(p.figures()))
        return h.hexdigest()
