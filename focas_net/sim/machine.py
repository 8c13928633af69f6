"""The simulated CNC: state and typed operations, with no sockets and no event loop.

A :class:`Machine` holds everything a FOCAS client can see of one CNC: axes, parameters,
diagnostics, macro variables, PMC areas, the operator panel, an optional parameter password,
active alarms and the alarm history, the ``cnc_sysinfo`` identity, a VersaMax I/O station and
the motion figures (positions, feed, spindle, program numbers) a native front end reports.

Typed operations raise :class:`MachineError` carrying the FANUC ``EW_*`` code, with the checks
in the order of PROTOCOL.md sections 3-5. Every write checks everything before it changes
anything, so a failed write leaves the machine exactly as it was.

Decisions where the contract leaves the order open (also in ``docs/protocol.md``):

* A read-only machine (``read_only = True``) answers EW_PROT to every write and every control
  command right after the payload-size check and before any other check. Control commands on a
  machine with control disabled answer EW_FUNC before anything else, payload size included.
* ``raise_alarm`` checks, after the payload size: ``alm_type`` outside 0..31 -> EW_DATA, then a
  negative ``alm_no`` -> EW_DATA (-1 means "any" to ``clear_alarms``, so such an alarm could not
  be cleared on its own), then ``axis_no`` outside 0..axes -> EW_ATTRIB.
* ``cnc_rdalmmsg`` with a ``type`` that is neither -1 nor an alarm type simply matches nothing.
* ``cnc_wrunlockparam`` is connection state, not machine state: it works on a read-only machine.

The parameter password is compared in constant time and never logged or shown in ``repr``.
"""

from __future__ import annotations

import hashlib
import hmac
import logging
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from itertools import islice
from typing import Final

from focas_net.errors import EW, FocasError

from ..protocol import (
    EW_OK_BYTES,
    MAX_ALARM_MSG,
    MAX_CONFIG_CHUNK,
    MAX_HISTORY_DEPTH,
    MAX_PMC_CHUNK,
    ActiveAlarm,
    AlarmHistory,
    AlarmHistoryEntry,
    MacroValue,
    ParamValue,
    Password,
    PmcArea,
    StatusInfo,
    SysInfo,
    VersaMaxReply,
)
from ..versamax import IOModuleRecord

__all__ = [
    "AUT_MODES",
    "DEFAULT_HISTORY_CAPACITY",
    "MDI",
    "MEM",
    "POSITION_DECIMALS",
    "Clock",
    "DataItem",
    "Machine",
    "MachineError",
    "MacroRange",
    "MotionData",
    "PackedTable",
    "Panel",
    "PmcAreaSpec",
    "Session",
    "utc_now",
]

logger = logging.getLogger(__name__)

#: Command id -> handler of one request payload (built by :mod:`focas_net.sim.packed`).
PackedTable = dict[int, Callable[["Session", bytes], bytes]]
#: A source of the current time; the machine stamps alarms with it (as UTC, whole seconds).
Clock = Callable[[], datetime]

#: ``aut`` values: 0 MDI, 1 MEM, 3 EDIT, 4 HND, 5 JOG, 6 Teach-in JOG, 7 Teach-in HND, 8 INC,
#: 9 REF, 10 RMT (2 is not a mode).
AUT_MODES: Final = frozenset({0, 1, 3, 4, 5, 6, 7, 8, 9, 10})
MDI: Final = 0
MEM: Final = 1
#: Alarm history capacity of a FANUC 0i/30i (and the deepest ``cnc_rdalmhistry`` read).
DEFAULT_HISTORY_CAPACITY: Final = MAX_HISTORY_DEPTH
#: Alarm type numbers a CNC can carry (``alm_type`` is a bit number in FANUC's masks).
MAX_ALARM_TYPE: Final = 31
#: Highest rack and slot of a VersaMax station.
MAX_RACK: Final = 7
MAX_SLOT: Final = 9

_WIDTH_RANGES: Final[dict[int, tuple[int, int]]] = {
    1: (-0x80, 0x7F),
    2: (-0x8000, 0x7FFF),
    4: (-0x8000_0000, 0x7FFF_FFFF),
}
#: Decimals of the least input increment of the positions (0.001 mm, IS-B).
POSITION_DECIMALS: Final = 3
#: ``cnc_rdposition`` types: 0 absolute, 1 machine, 2 relative, 3 distance to go.
_POSITION_FIELDS: Final = ("absolute", "machine", "relative", "distance_to_go")
_MOTION_SCALARS: Final = ("feed", "spindle_speed", "program_running", "program_main", "sequence")
_I32_MIN: Final = -0x8000_0000
_I32_MAX: Final = 0x7FFF_FFFF
_MACRO_LENGTH: Final = 8
_VACANT: Final = (0, -1)


def utc_now() -> datetime:
    """The default clock: now, timezone-aware UTC."""
    return datetime.now(UTC)


class MachineError(FocasError):
    """A typed operation refused: ``ew`` is the FANUC ``EW_*`` code the CNC answers."""

    def __init__(self, ew: int, detail: str = "") -> None:
        self.ew = int(ew)
        self.detail = detail
        name = EW(self.ew).name if self.ew in EW._value2member_map_ else str(self.ew)
        super().__init__(f"EW_{name}: {detail}" if detail else f"EW_{name}")


@dataclass(slots=True)
class Session:
    """Per-connection state: whether this connection unlocked the parameter password (and
    under which password: ``epoch`` counts :meth:`Machine.set_param_password` calls)."""

    unlocked: bool = False
    epoch: int = 0


@dataclass(slots=True)
class DataItem:
    """A parameter or a diagnostic: number, width (1 byte, 2 i16, 4 i32), per-axis or not,
    allowed range (inclusive) and its value(s): one value, or one per axis."""

    number: int
    width: int
    axis: bool = False
    low: int | None = None
    high: int | None = None
    values: list[int] = field(default_factory=lambda: [0])
    name: str = ""

    def check(self, axes: int) -> None:
        """Raise ValueError when the item is not consistent (for machine builders)."""
        if not -0x8000 <= self.number <= 0x7FFF:
            raise ValueError(f"number {self.number} is outside i16")
        span = _WIDTH_RANGES.get(self.width)
        if span is None:
            raise ValueError(f"width must be 1, 2 or 4, got {self.width}")
        if self.low is None:
            self.low = span[0]
        if self.high is None:
            self.high = span[1]
        if not span[0] <= self.low <= self.high <= span[1]:
            raise ValueError(
                f"range {self.low}..{self.high} is empty or outside the type ({span[0]}..{span[1]})"
            )
        want = axes if self.axis else 1
        if self.axis and len(self.values) == 1 and want > 1:
            self.values = self.values * want
        if len(self.values) != want:
            raise ValueError(f"{len(self.values)} values given, {want} expected")
        for v in self.values:
            if not self.low <= v <= self.high:
                raise ValueError(f"value {v} is outside {self.low}..{self.high}")


@dataclass(frozen=True, slots=True)
class MacroRange:
    """Macro variables ``first..last`` (inclusive), writable or read-only."""

    first: int
    last: int
    writable: bool = True


@dataclass(frozen=True, slots=True)
class PmcAreaSpec:
    """A PMC area: its letter, its size in bytes, protection against ``pmc_wrpmcrng`` and its
    initial bytes as ``{address: bytes}``."""

    letter: str
    size: int
    write_protected: bool = False
    initial: Mapping[int, bytes] = field(default_factory=dict)


@dataclass(slots=True)
class Panel:
    """The operator panel and the run state shown by ``cnc_rdcncstat``."""

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
    """Figures for a native front end: positions per axis in least input increments, actual
    feed, spindle speed, program numbers and the sequence number."""

    absolute: list[int]
    machine: list[int]
    relative: list[int]
    distance_to_go: list[int]
    feed: int = 0
    spindle_speed: int = 0
    program_running: int = 0
    program_main: int = 0
    sequence: int = 0


class _Area:
    __slots__ = ("code", "data", "letter", "size", "write_protected")

    def __init__(self, spec: PmcAreaSpec) -> None:
        self.letter = spec.letter.upper()
        self.code = int(PmcArea[self.letter])
        self.size = spec.size
        self.write_protected = spec.write_protected
        self.data = bytearray(spec.size)
        for address, raw in spec.initial.items():
            if address < 0 or address + len(raw) > spec.size:
                raise ValueError(f"initial bytes at {address} run past the {spec.size}-byte area")
            self.data[address : address + len(raw)] = raw


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
        sysinfo: SysInfo | None = None,
        params: Iterable[DataItem] = (),
        diags: Iterable[DataItem] = (),
        macro_ranges: Iterable[MacroRange] = (),
        macro_values: Mapping[int, tuple[int, int]] | None = None,
        pmc: Iterable[PmcAreaSpec] = (),
        panel: Panel | None = None,
        param_password: str | bytes | None = None,
        station: Mapping[tuple[int, int], IOModuleRecord] | None = None,
        motion: MotionData | None = None,
        history_capacity: int = DEFAULT_HISTORY_CAPACITY,
        clock: Clock = utc_now,
        control_enabled: bool = True,
        read_only: bool = False,
    ) -> None:
        self.name = name
        self.axes: list[str] = list(axes)
        n = len(self.axes)
        if not 1 <= n <= 32:
            raise ValueError(f"a machine has 1..32 axes, got {n}")
        self.control_enabled = control_enabled
        self.read_only = read_only
        self.clock = clock
        self._sysinfo = sysinfo or SysInfo(
            2, max(n, 8), b" 0", b" M", b"D4F1", b"32.0", b"%02d" % n
        )
        self._params = self._items(params, "parameter")
        self._diags = self._items(diags, "diagnostic")
        self._macro_ranges = tuple(sorted(macro_ranges, key=lambda r: r.first))
        for r in self._macro_ranges:
            if not -0x8000 <= r.first <= r.last <= 0x7FFF:
                raise ValueError(f"macro range {r.first}..{r.last} is empty or outside i16")
        for a, b in zip(self._macro_ranges, self._macro_ranges[1:], strict=False):
            if b.first <= a.last:
                raise ValueError(f"macro ranges {a.first}..{a.last} and {b.first}.. overlap")
        self._macros: dict[int, tuple[int, int]] = {}
        for number, (mcr_val, dec_val) in (macro_values or {}).items():
            if self._macro_range(number) is None:
                raise ValueError(f"macro #{number} is not in any macro range")
            if (mcr_val, dec_val) != _VACANT:
                if not -0x8000_0000 <= mcr_val <= 0x7FFF_FFFF or not 0 <= dec_val <= 9:
                    raise ValueError(f"macro #{number}: value ({mcr_val}, {dec_val}) invalid")
                self._macros[number] = (mcr_val, dec_val)
        self._areas: dict[int, _Area] = {}
        for spec in pmc:
            area = _Area(spec)
            if area.code in self._areas:
                raise ValueError(f"PMC area {area.letter} given twice")
            self._areas[area.code] = area
        self.panel = panel or Panel()
        if self.panel.mode not in AUT_MODES:
            raise ValueError(f"panel mode {self.panel.mode} is not an aut value")
        self._password: bytes | None = (
            None if param_password is None else Password.from_text(param_password).password
        )
        self._password_epoch = 0
        self._station: dict[tuple[int, int], bytes] = {}
        self._records: dict[tuple[int, int], IOModuleRecord] = {}
        for (rack, slot), record in (station or {}).items():
            if not (0 <= rack <= MAX_RACK and 0 <= slot <= MAX_SLOT):
                raise ValueError(f"VersaMax rack {rack} slot {slot} is out of range")
            self._records[rack, slot] = record
            self._station[rack, slot] = record.encode()
        self.motion = motion or MotionData([0] * n, [0] * n, [0] * n, [0] * n)
        for key in _POSITION_FIELDS:
            if len(getattr(self.motion, key)) != n:
                raise ValueError(
                    f"motion {key}: {len(getattr(self.motion, key))} values for {n} axes"
                )
        if history_capacity < 1:
            raise ValueError("alarm history capacity must be at least 1")
        self._active: dict[tuple[int, int, int], ActiveAlarm] = {}
        self._history: deque[AlarmHistoryEntry] = deque(maxlen=history_capacity)
        self._status_bytes: bytes | None = None
        self._history_cache: dict[int, tuple[AlarmHistoryEntry, ...]] = {}
        self._history_bytes: dict[int, bytes] = {}
        #: Incremented on every change of machine state (front ends may key caches on it).
        self.version = 0
        #: Incremented when a parameter or diagnostic value changes.
        self.data_version = 0
        #: Incremented when a macro variable changes.
        self.macro_version = 0
        #: Incremented when the set of active alarms changes.
        self.alarm_version = 0
        #: Filled in by :mod:`focas_net.sim.packed` (its dispatch table for this machine).
        self.packed_table: PackedTable | None = None

    def _items(self, items: Iterable[DataItem], what: str) -> dict[int, DataItem]:
        table: dict[int, DataItem] = {}
        for item in items:
            try:
                item.check(len(self.axes))
            except ValueError as exc:
                raise ValueError(f"{what} {item.number}: {exc}") from None
            if item.number in table:
                raise ValueError(f"{what} {item.number} given twice")
            table[item.number] = item
        return table

    def __repr__(self) -> str:
        return f"Machine({self.name!r}, axes={''.join(self.axes)!r})"

    # -- sessions, status, identity ------------------------------------------------------
    def new_session(self) -> Session:
        """Per-connection state for a new connection (locked)."""
        return Session(False, self._password_epoch)

    def set_param_password(self, password: str | bytes | None) -> None:
        """Set (None: remove) the parameter password, cut at 4 bytes. Connections unlocked
        under the previous password are locked again."""
        self._password = None if password is None else Password.from_text(password).password
        self._password_epoch += 1
        self.version += 1

    @property
    def has_password(self) -> bool:
        """True when parameter writes need a per-connection unlock."""
        return self._password is not None

    def status(self) -> StatusInfo:
        """ODBST derived from the panel and the active alarms."""
        p = self.panel
        return StatusInfo(
            p.hdck,
            p.tmmode,
            p.mode,
            p.run,
            p.motion,
            p.mstb,
            p.emergency,
            1 if self._active else 0,
            p.edit,
        )

    def status_payload(self) -> bytes:
        """The whole ``cnc_rdcncstat`` answer payload (``ew`` then ODBST), cached until the
        panel or the alarms change. Front ends may call this on their hot path."""
        cached = self._status_bytes
        if cached is None:
            cached = self._status_bytes = EW_OK_BYTES + self.status().encode()
        return cached

    def _status_changed(self) -> None:
        self._status_bytes = None
        self.version += 1

    def sysinfo(self) -> SysInfo:
        """The ``cnc_sysinfo`` identity."""
        return self._sysinfo

    def sysinfo_payload(self) -> bytes:
        """The whole ``cnc_sysinfo`` answer payload."""
        return EW_OK_BYTES + self._sysinfo.encode()

    # -- parameters and diagnostics ------------------------------------------------------
    def _lookup(self, table: dict[int, DataItem], datano: int, axis: int) -> tuple[DataItem, int]:
        item = table.get(datano)
        if item is None:
            raise MachineError(EW.NUMBER, f"no item {datano}")
        if item.axis:
            if not 1 <= axis <= len(self.axes):
                raise MachineError(EW.ATTRIB, f"item {datano} needs an axis 1..{len(self.axes)}")
            return item, axis - 1
        if axis != 0:
            raise MachineError(EW.ATTRIB, f"item {datano} is not an axis item")
        return item, 0

    def param_item(self, datano: int) -> DataItem | None:
        """The description of parameter ``datano`` (None when the machine has none)."""
        return self._params.get(datano)

    def diag_item(self, datano: int) -> DataItem | None:
        """The description of diagnostic ``datano`` (None when the machine has none)."""
        return self._diags.get(datano)

    def param_numbers(self) -> tuple[int, ...]:
        """The numbers of every parameter, ascending."""
        return tuple(sorted(self._params))

    def diag_numbers(self) -> tuple[int, ...]:
        """The numbers of every diagnostic, ascending."""
        return tuple(sorted(self._diags))

    def read_param(self, datano: int, axis: int) -> ParamValue:
        """``cnc_rdparam``: EW_NUMBER, then EW_ATTRIB."""
        item, i = self._lookup(self._params, datano, axis)
        return ParamValue(datano, axis, item.values[i], item.width)

    def read_diag(self, datano: int, axis: int) -> ParamValue:
        """``cnc_rddiag``: EW_NUMBER, then EW_ATTRIB."""
        item, i = self._lookup(self._diags, datano, axis)
        return ParamValue(datano, axis, item.values[i], item.width)

    def param_gate_open(self, session: Session) -> bool:
        """PWE on, MDI mode, and (when there is a password) this connection unlocked."""
        p = self.panel
        if p.pwe != 1 or p.mode != MDI:
            return False
        return self._password is None or (
            session.unlocked and session.epoch == self._password_epoch
        )

    def write_param(self, session: Session, datano: int, axis: int, value: int, width: int) -> None:
        """``cnc_wrparam``: EW_PROT (read-only machine), EW_NUMBER, EW_ATTRIB, EW_LENGTH (width),
        EW_PASSWD (write gate), EW_DATA (range)."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        item, i = self._lookup(self._params, datano, axis)
        if width != item.width:
            raise MachineError(EW.LENGTH, f"parameter {datano} is {item.width} bytes wide")
        if not self.param_gate_open(session):
            raise MachineError(EW.PASSWD, "parameter write not enabled")
        low, high = item.low, item.high
        assert low is not None and high is not None
        if not low <= value <= high:
            raise MachineError(EW.DATA, f"parameter {datano}: {value} outside {low}..{high}")
        item.values[i] = value
        self.data_version += 1
        self.version += 1

    def set_diag(self, datano: int, axis: int, value: int) -> None:
        """Change a diagnostic value (for simulation code; not reachable over the wire)."""
        item, i = self._lookup(self._diags, datano, axis)
        low, high = item.low, item.high
        assert low is not None and high is not None
        if not low <= value <= high:
            raise MachineError(EW.DATA, f"diagnostic {datano}: {value} outside {low}..{high}")
        item.values[i] = value
        self.data_version += 1
        self.version += 1

    # -- macro variables -----------------------------------------------------------------
    def _macro_range(self, number: int) -> MacroRange | None:
        for r in self._macro_ranges:
            if number < r.first:
                return None
            if number <= r.last:
                return r
        return None

    def macro_writable(self, number: int) -> bool | None:
        """True/False for a writable/read-only variable; None when there is no such variable."""
        r = self._macro_range(number)
        return None if r is None else r.writable

    def read_macro(self, number: int) -> MacroValue:
        """``cnc_rdmacro``: EW_NUMBER for an unknown variable; vacant is (0, -1)."""
        if self._macro_range(number) is None:
            raise MachineError(EW.NUMBER, f"no macro variable #{number}")
        mcr_val, dec_val = self._macros.get(number, _VACANT)
        return MacroValue(number, _MACRO_LENGTH, mcr_val, dec_val)

    def write_macro(self, number: int, mcr_val: int, dec_val: int) -> None:
        """``cnc_wrmacro``: EW_PROT (read-only machine), EW_NUMBER, EW_PROT (read-only
        variable), EW_DATA (``dec_val`` outside 0..9)."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        r = self._macro_range(number)
        if r is None:
            raise MachineError(EW.NUMBER, f"no macro variable #{number}")
        if not r.writable:
            raise MachineError(EW.PROT, f"macro variable #{number} is read-only")
        if not 0 <= dec_val <= 9:
            raise MachineError(EW.DATA, f"dec_val {dec_val} outside 0..9")
        self._macros[number] = (mcr_val, dec_val)
        self.macro_version += 1
        self.version += 1

    def clear_macro(self, number: int) -> None:
        """Make macro ``number`` vacant (what a native ``cnc_wrmacro`` of a null value does):
        EW_PROT (read-only machine), EW_NUMBER, EW_PROT (read-only variable)."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        r = self._macro_range(number)
        if r is None:
            raise MachineError(EW.NUMBER, f"no macro variable #{number}")
        if not r.writable:
            raise MachineError(EW.PROT, f"macro variable #{number} is read-only")
        if self._macros.pop(number, None) is not None:
            self.macro_version += 1
            self.version += 1

    # -- PMC -------------------------------------------------------------------------------
    def pmc_area(self, letter: str) -> tuple[int, bool] | None:
        """``(size, write_protected)`` of area ``letter``, or None when the machine has none
        (ValueError for a letter that is no PMC area at all)."""
        area = self._areas.get(int(PmcArea.parse(letter)))
        return None if area is None else (area.size, area.write_protected)

    def _pmc_check(self, type_a: int, type_d: int, start: int, end: int) -> _Area:
        area = self._areas.get(type_a)
        if area is None:
            if type_a not in PmcArea._value2member_map_:
                raise MachineError(EW.ATTRIB, f"unknown PMC area code {type_a}")
            raise MachineError(EW.NOOPT, f"no PMC area {PmcArea(type_a).name}")
        if type_d != 0:
            raise MachineError(EW.ATTRIB, f"type_d {type_d}: only bytes (0)")
        count = end - start + 1
        if not 1 <= count <= MAX_PMC_CHUNK:
            raise MachineError(EW.LENGTH, f"{count} bytes: one call carries 1..{MAX_PMC_CHUNK}")
        return area

    def read_pmc(self, type_a: int, type_d: int, start: int, end: int) -> bytes:
        """``pmc_rdpmcrng``: EW_ATTRIB, EW_NOOPT, EW_ATTRIB, EW_LENGTH, EW_NUMBER."""
        area = self._pmc_check(type_a, type_d, start, end)
        if end >= area.size or start < 0:
            raise MachineError(EW.NUMBER, f"{area.letter}{start}..{end} beyond {area.size} bytes")
        return bytes(area.data[start : end + 1])

    def write_pmc(
        self, type_a: int, type_d: int, start: int, end: int, data: bytes, *, force: bool = False
    ) -> None:
        """``pmc_wrpmcrng`` (``force`` = the control command set_pmc, which ignores write
        protection): EW_PROT (read-only machine), EW_ATTRIB, EW_NOOPT, EW_ATTRIB, EW_LENGTH,
        EW_LENGTH (data), EW_NUMBER, EW_PROT (area)."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        area = self._pmc_check(type_a, type_d, start, end)
        if len(data) != end - start + 1:
            raise MachineError(EW.LENGTH, f"{len(data)} data bytes for {end - start + 1}")
        if end >= area.size or start < 0:
            raise MachineError(EW.NUMBER, f"{area.letter}{start}..{end} beyond {area.size} bytes")
        if area.write_protected and not force:
            raise MachineError(EW.PROT, f"PMC area {area.letter} is write-protected")
        area.data[start : end + 1] = data
        self.version += 1

    # -- password ------------------------------------------------------------------------
    def unlock(self, session: Session, password: bytes) -> None:
        """``cnc_wrunlockparam``: unlock parameter writes for ``session``; a mismatch answers
        EW_PASSWD and locks the session again."""
        expected = self._password
        session.epoch = self._password_epoch
        if expected is None:
            session.unlocked = True
            return
        given = bytes(password[:4]).ljust(4, b"\x00")
        if hmac.compare_digest(given, expected):
            session.unlocked = True
            return
        session.unlocked = False
        raise MachineError(EW.PASSWD, "parameter password mismatch")

    # -- alarms --------------------------------------------------------------------------
    def active_alarms(self, alm_type: int = -1, max: int = 32) -> list[ActiveAlarm]:
        """``cnc_rdalmmsg``: at most ``max`` (1..32, else EW_LENGTH) active alarms of
        ``alm_type`` (-1 all), oldest raised first."""
        if not 1 <= max <= 32:
            raise MachineError(EW.LENGTH, f"max {max} outside 1..32")
        alarms = self._active.values()
        if alm_type == -1:
            return list(islice(alarms, max))
        return list(islice((a for a in alarms if a.alm_type == alm_type), max))

    def alarm_history(self, depth: int) -> tuple[AlarmHistoryEntry, ...]:
        """``cnc_rdalmhistry``: the ``depth`` (1..250, else EW_LENGTH) newest entries, newest
        first."""
        if not 1 <= depth <= MAX_HISTORY_DEPTH:
            raise MachineError(EW.LENGTH, f"depth {depth} outside 1..{MAX_HISTORY_DEPTH}")
        cached = self._history_cache.get(depth)
        if cached is None:
            cached = self._history_cache[depth] = tuple(islice(self._history, depth))
        return cached

    def alarm_history_payload(self, depth: int) -> bytes:
        """The whole ``cnc_rdalmhistry`` answer payload for ``depth``, cached until the next
        alarm is raised (EW_LENGTH as :meth:`alarm_history`)."""
        cached = self._history_bytes.get(depth)
        if cached is None:
            cached = AlarmHistory(self.alarm_history(depth)).encode()
            self._history_bytes[depth] = cached
        return cached

    @property
    def history_capacity(self) -> int:
        cap = self._history.maxlen
        assert cap is not None
        return cap

    def now(self) -> datetime:
        """The clock, as aware UTC cut to whole seconds."""
        t = self.clock()
        t = t.replace(tzinfo=UTC) if t.tzinfo is None else t.astimezone(UTC)
        return t.replace(microsecond=0)

    def raise_alarm(self, axis_no: int, alm_type: int, alm_no: int, msg: bytes) -> None:
        """Make an alarm active and record it in the history (UTC, whole seconds). An alarm
        already active (same axis_no, alm_type, alm_no) changes nothing. ``msg`` is cut at 32
        bytes. EW_PROT (read-only machine), EW_DATA (alm_type, alm_no), EW_ATTRIB (axis_no)."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        if not 0 <= alm_type <= MAX_ALARM_TYPE:
            raise MachineError(EW.DATA, f"alm_type {alm_type} outside 0..{MAX_ALARM_TYPE}")
        if alm_no < 0:
            raise MachineError(EW.DATA, f"alm_no {alm_no} is negative")
        if not 0 <= axis_no <= len(self.axes):
            raise MachineError(EW.ATTRIB, f"axis_no {axis_no} outside 0..{len(self.axes)}")
        key = (axis_no, alm_type, alm_no)
        if key in self._active:
            return
        text = bytes(msg[:MAX_ALARM_MSG]).decode("latin-1")
        logger.debug(
            "%s: alarm raised: axis %d type %d no %d", self.name, axis_no, alm_type, alm_no
        )
        self._active[key] = ActiveAlarm(axis_no, alm_type, alm_no, text)
        self._history.appendleft(AlarmHistoryEntry(self.now(), axis_no, alm_type, alm_no, text))
        self._history_cache.clear()
        self._history_bytes.clear()
        self.alarm_version += 1
        self._status_changed()

    def clear_alarms(self, alm_type: int = -1, alm_no: int = -1) -> int:
        """Remove the active alarms matching ``alm_type`` and ``alm_no`` (-1 = any); the
        history is kept. Returns how many were removed. EW_PROT on a read-only machine."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        gone = [
            k
            for k in self._active
            if (alm_type == -1 or k[1] == alm_type) and (alm_no == -1 or k[2] == alm_no)
        ]
        for k in gone:
            del self._active[k]
        if gone:
            logger.debug("%s: %d alarm(s) cleared", self.name, len(gone))
            self.alarm_version += 1
            self._status_changed()
        return len(gone)

    # -- operator panel ------------------------------------------------------------------
    def set_panel(self, mode: int, pwe: int, emergency: int) -> None:
        """The control command set_panel: ``mode`` an ``aut`` value other than 2, ``pwe`` and
        ``emergency`` 0/1, else EW_DATA. EW_PROT on a read-only machine."""
        if self.read_only:
            raise MachineError(EW.PROT, "read-only machine")
        if mode not in AUT_MODES or pwe not in (0, 1) or emergency not in (0, 1):
            raise MachineError(EW.DATA, f"panel mode={mode} pwe={pwe} emergency={emergency}")
        p = self.panel
        p.mode, p.pwe, p.emergency = mode, pwe, emergency
        logger.debug("%s: panel mode %d pwe %d emergency %d", self.name, mode, pwe, emergency)
        self._status_changed()

    def set_run(self, run: int, motion: int = 0) -> None:
        """Set the run state (0 reset, 1 STOP, 2 HOLD, 3 STRT, 4 MSTR) and motion (0, 1 MTN,
        2 DWL) shown by ``cnc_rdcncstat`` (simulation code only)."""
        if run not in range(5) or motion not in range(3):
            raise MachineError(EW.DATA, f"run={run} motion={motion}")
        self.panel.run, self.panel.motion = run, motion
        self._status_changed()

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
            _POSITION_FIELDS, (absolute, machine, relative, distance_to_go), strict=True
        ):
            if values is None:
                continue
            got = list(values)
            if len(got) != n or not all(type(v) is int and _I32_MIN <= v <= _I32_MAX for v in got):
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
            if type(value) is not int or not 0 <= value <= _I32_MAX:
                raise MachineError(EW.DATA, f"{key} = {value!r} outside 0..{_I32_MAX}")
            scalars[key] = value
        m = self.motion
        for key, got in lists.items():
            setattr(m, key, got)
        for key, value in scalars.items():
            setattr(m, key, value)
        self.version += 1

    def positions(self, kind: int, axis: int) -> list[tuple[str, int]]:
        """``cnc_rdposition``: ``(axis name, value)`` of every axis (``axis = -1``) or of axis
        ``axis`` (1..n), in least input increments (:data:`POSITION_DECIMALS` decimals).
        ``kind`` 0 absolute, 1 machine, 2 relative, 3 distance to go. Checks, in order:
        ``kind`` outside 0..3 -> EW_ATTRIB; ``axis`` 0, below -1 or above the axes ->
        EW_ATTRIB."""
        if not 0 <= kind < len(_POSITION_FIELDS):
            raise MachineError(EW.ATTRIB, f"position type {kind} outside 0..3")
        values: list[int] = getattr(self.motion, _POSITION_FIELDS[kind])
        if axis == -1:
            return list(zip(self.axes, values, strict=True))
        if not 1 <= axis <= len(self.axes):
            raise MachineError(EW.ATTRIB, f"axis {axis} outside -1, 1..{len(self.axes)}")
        return [(self.axes[axis - 1], values[axis - 1])]

    # -- VersaMax ------------------------------------------------------------------------
    def module_record(self, rack: int, slot: int) -> IOModuleRecord | None:
        """The configuration record in ``rack``/``slot`` (None when empty)."""
        return self._records.get((rack, slot))

    def versamax_read(self, rack: int, length: int, slot: int, offset: int) -> VersaMaxReply:
        """Read Configuration: EW_NUMBER (empty or out-of-range rack/slot), EW_LENGTH (length
        outside 1..128), EW_NUMBER (offset at or past the end of the record)."""
        record = self._station.get((rack, slot))
        if record is None:
            raise MachineError(EW.NUMBER, f"rack {rack} slot {slot} is empty")
        if not 1 <= length <= MAX_CONFIG_CHUNK:
            raise MachineError(EW.LENGTH, f"length {length} outside 1..{MAX_CONFIG_CHUNK}")
        if not 0 <= offset < len(record):
            raise MachineError(EW.NUMBER, f"offset {offset} past the {len(record)}-byte record")
        return VersaMaxReply(rack, slot, offset, record[offset : offset + length])

    # -- whole-state view ----------------------------------------------------------------
    def state_digest(self) -> str:
        """A stable SHA-256 hex digest of all machine state (not of sessions or caches)."""
        h = hashlib.sha256()

        def put(*parts: object) -> None:
            h.update(repr(parts).encode())
            h.update(b"\n")

        put("axes", self.axes, self.read_only, self.control_enabled)
        for t, table in (("param", self._params), ("diag", self._diags)):
            for n in sorted(table):
                it = table[n]
                put(t, n, it.width, it.axis, it.low, it.high, it.values)
        put("macro-ranges", [(r.first, r.last, r.writable) for r in self._macro_ranges])
        put("macros", sorted(self._macros.items()))
        for code in sorted(self._areas):
            a = self._areas[code]
            put("pmc", a.letter, a.size, a.write_protected)
            h.update(a.data)
        p = self.panel
        put("panel", p.mode, p.pwe, p.emergency, p.run, p.motion, p.mstb, p.edit, p.hdck, p.tmmode)
        put("password", hashlib.sha256(self._password or b"").hexdigest())
        put("active", list(self._active.values()))
        put("history", self.history_capacity, list(self._history))
        put("sysinfo", self._sysinfo)
        put("station", sorted(self._station.items()))
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
