"""What data collectors read of a machine besides its status: the run-time parameters, the
CNC's clock, the servo power diagnostic, the operator panel's signals and the F signals of the
mode and of readiness, each following the machine (a part of :class:`~focas_net.sim.Machine`).

* **Run-time parameters** (FANUC's numbering, path-type: each path its own): 6750 power-on
  time (minutes), 6751/6752 operating time (ms, minutes), 6753/6754 cutting time (ms,
  minutes), 6757/6758 cycle time, the run time of the cycle under way (ms, minutes). They read
  the timers ``cnc_rdtimer`` reads (:meth:`Machine.timer_ms`): minutes are whole minutes, the
  ms parameter the milliseconds past them. A write of one sets the timer from then on, as on
  a CNC (a cycle time written holds for the cycle under way). 6755/6756 are the
  general-purpose integrating meter (``cnc_rdtimer`` type 4): it counts while the path's
  TMRON signal (G53.0) is 1. A machine that does not give them has them (two-word, not per
  axis).
* **The CNC's clock**: the machine's wall clock (``clock``, UTC) moved by what was set
  (``cnc_settimer``: :meth:`SignalOperations.set_cnc_date`, ``set_cnc_time``); the alarms are
  stamped by it. ``#3011`` reads its date as YYYYMMDD and ``#3012`` its time as HHMMSS
  (read-only, EW_PROT to a write; 116 to a program).
* **Diagnostic 4901**, the servo motor's power consumption in watts per axis: the axis's
  servo load (:meth:`Machine.servo_loads`) times :data:`SERVO_WATTS_PER_PERCENT` (while the
  machine drives its figures, as 410 and 4902 below). A machine that does not give it has it.
* **Spindle diagnostics** (:data:`SPINDLE_DIAGS`, FANUC's numbers of the serial spindle's
  data: 400 link, 403 motor temperature, 408 communication, 410 load, 411 speed, 417/418
  position coder and loop deviation, 425 sync error, 445 position, 710/712 error and warning,
  1520/1521 revolutions, 4902 power): as on a CNC, the axis argument of a read names the
  spindle (1..the path's spindles; 0 the first). 410 is the spindle's load in percent
  (:meth:`Machine.spindle_loads`), 4902 its power in watts (the load times
  :data:`SPINDLE_WATTS_PER_PERCENT`), while the machine drives its figures (a program was
  started or searched; before, what is set by hand, as with the loads); the others read the
  value the machine holds. A machine
  that does not give 4902 has it.
* **F signals of the state** (per path, at the path's offset of 1000 bytes): F0.6 SA (servo
  ready: no emergency stop), F1.7 MA (CNC ready), F1.0 AL (an alarm on the path), the mode
  F3.0 MINC, F3.1 MH, F3.2 MJ, F3.3 MMDI, F3.4 MRMT, F3.5 MMEM, F3.6 MEDT, F3.7 MTCHIN and
  F4.5 MREF. They follow the status whenever it changed (what is written into F stays until
  then); F0.7 OP, F0.5 STL, F0.4 SPL and F1.1 RST follow the cycle (:mod:`._pmc`).
* **The operator panel's signals** (``cnc_rdopnlsgnl``): :class:`OperatorSignals`.
"""

from __future__ import annotations

import calendar
import math
from collections.abc import Iterable
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import TYPE_CHECKING, Final

from focas_net._refusals import SPINDLE_DIAGS
from focas_net._typed import cnc_year_unfit, field_unfit
from focas_net.errors import EW

from ._base import MachineError, need_int
from ._items import DataItem, ParamKind
from ._pmc import PATH_SIGNALS_STRIDE

if TYPE_CHECKING:
    from ._alarms import Alarms
    from ._base import Counters
    from ._paths import Paths
    from ._pmc import Pmc
    from ._status import Status

__all__ = [
    "CLOCK_VARIABLES",
    "METER",
    "SERVO_POWER_DIAG",
    "SERVO_WATTS_PER_PERCENT",
    "SPINDLE_DIAGS",
    "SPINDLE_WATTS_PER_PERCENT",
    "TIMER_PARAMS",
    "Collected",
    "OperatorSignals",
    "SignalOperations",
    "clock_variable",
    "collected_diags",
    "collected_params",
]

#: Run-time parameter -> (``cnc_rdtimer`` type, whether it holds minutes, not milliseconds).
TIMER_PARAMS: Final[dict[int, tuple[int, bool]]] = {
    6750: (0, True),
    6751: (1, False),
    6752: (1, True),
    6753: (2, False),
    6754: (2, True),
    6755: (4, False),
    6756: (4, True),
    6757: (3, False),
    6758: (3, True),
}
_CYCLE: Final = 3
#: ``cnc_rdtimer`` type of the general-purpose integrating meter, and its TMRON signal G53.0.
METER: Final = 4
_TMRON: Final = (53, 0)
_NAMES: Final = {
    6750: "power-on time (min)",
    6751: "operating time (ms)",
    6752: "operating time (min)",
    6753: "cutting time (ms)",
    6754: "cutting time (min)",
    6755: "integrating meter (ms)",
    6756: "integrating meter (min)",
    6757: "cycle time (ms)",
    6758: "cycle time (min)",
}
_MAX_MINUTES: Final = 999_999_999
_MS_PER_MINUTE: Final = 60_000
#: #3011 (date, YYYYMMDD) and #3012 (time, HHMMSS).
CLOCK_VARIABLES: Final = (3011, 3012)
#: Servo motor power consumption, watts per axis (a two-word axis diagnostic).
SERVO_POWER_DIAG: Final = 4901
#: Watts of diagnostic 4901 per percent of servo load (a 1.5 kW motor at 100 %).
SERVO_WATTS_PER_PERCENT: Final = 15
#: Spindle load (percent) and spindle motor power consumption (W): diagnostics that follow the
#: spindle's load.
SPINDLE_LOAD_DIAG: Final = 410
SPINDLE_POWER_DIAG: Final = 4902
#: Watts of diagnostic 4902 per percent of spindle load (a 7.5 kW motor at 100 %).
SPINDLE_WATTS_PER_PERCENT: Final = 75

#: The F signals of the state: bit of F0 (SA), F1 (AL, MA) and F4 (MREF).
_SA: Final = 6
_AL: Final = 0
_MA: Final = 7
_MREF: Final = 5
#: The panel mode (an ``aut`` value) -> the mode bits of F3 (MINC #0 MH #1 MJ #2 MMDI #3 MRMT
#: #4 MMEM #5 MEDT #6 MTCHIN #7) and of F4 (MREF #5).
_F3_OF_MODE: Final = {
    0: 0x08,
    1: 0x20,
    3: 0x40,
    4: 0x02,
    5: 0x04,
    6: 0x84,
    7: 0x82,
    8: 0x01,
    10: 0x10,
}
_F4_OF_MODE: Final = {9: 1 << _MREF}


def collected_params(params: Iterable[DataItem]) -> list[DataItem]:
    """``params`` and the run-time parameters 6750-6758 the machine lacks (two-word, not per
    axis, 0 to start)."""
    items = list(params)
    given = {item.number for item in items}
    for number in range(6750, 6759):
        if number not in given:
            ms = number in (6751, 6753, 6755, 6757)
            high = _MS_PER_MINUTE - 1 if ms else _MAX_MINUTES
            items.append(DataItem(number, 4, False, 0, high, [0], _NAMES[number]))
    return items


def collected_diags(diags: Iterable[DataItem]) -> list[DataItem]:
    """``diags`` and diagnostics 4901 (servo power, W, per axis) and 4902 (spindle power, W)
    when the machine lacks them."""
    items = list(diags)
    given = {item.number for item in items}
    if SERVO_POWER_DIAG not in given:
        items.append(
            DataItem(SERVO_POWER_DIAG, kind=ParamKind.TWO_WORD, axis=True, name="servo power")
        )
    if SPINDLE_POWER_DIAG not in given:
        items.append(DataItem(SPINDLE_POWER_DIAG, kind=ParamKind.TWO_WORD, name="spindle power"))
    return items


def clock_variable(number: int, when: datetime) -> int:
    """#3011 (``when``'s date as YYYYMMDD) or #3012 (its time as HHMMSS)."""
    if number == CLOCK_VARIABLES[0]:
        return when.year * 10_000 + when.month * 100 + when.day
    return when.hour * 10_000 + when.minute * 100 + when.second


@dataclass(frozen=True, slots=True)
class OperatorSignals:
    """The operator panel's signals as ``cnc_rdopnlsgnl`` reads them (IODBSGNL): ``mode`` the
    panel's mode (an ``aut`` value), ``rapid`` the rapid override step (0 100 %, 1 50 %, 2
    25 %, 3 F0: G14's ROV2 ROV1), ``feed`` the feed override in 10 % steps (0..25),
    ``single_block``, ``block_delete``, ``machine_lock``, ``dry_run`` (G46.1, G44.0, G44.1,
    G46.7 of the path), ``feed_hold`` (1 while the cycle is held); the manual handle, jog
    override, spindle override (not used outside FS15) and memory protection are 0."""

    mode: int = 0
    handle_axis: int = 0
    handle_move: int = 0
    rapid: int = 0
    jog: int = 0
    feed: int = 0
    spindle: int = 0
    block_delete: int = 0
    single_block: int = 0
    machine_lock: int = 0
    dry_run: int = 0
    memory_protect: int = 0
    feed_hold: int = 0


class Collected:
    """The machine's state of what collectors read: the shifts the run-time parameters'
    writes set, and what the counters last saw of time (see :meth:`tick`)."""

    __slots__ = (
        "clock_followed",
        "data_followed",
        "data_seen",
        "macro_seen",
        "meters",
        "shifts",
        "status_seen",
    )

    def __init__(self) -> None:
        #: (path, timer type) -> (seconds added to the machine's timer, its value then).
        self.shifts: dict[tuple[int, int], tuple[float, float]] = {}
        #: path -> (seconds the integrating meter counted, machine time TMRON rose or None).
        self.meters: dict[int, tuple[float, float | None]] = {}
        self.data_seen: tuple[int, tuple[float, int] | None, int] | None = None
        self.macro_seen: tuple[int, ...] | None = None
        #: Whether a figure that follows time (a run-time parameter, 410, 4901, 4902) was read
        #: since the data counter last moved (``data_seen`` is what it depended on then):
        #: until one is, time cannot make a kept answer stale, and nothing is checked.
        self.data_followed = False
        #: The same for the clock's variables (#3011, #3012) and the macro counter.
        self.clock_followed = False
        self.status_seen = -1

    def shifted(self, path: int, kind: int, base: float) -> float:
        """Timer ``kind`` of ``path`` as written: ``base``, the machine's seconds, and the
        shift a write set (the cycle time's until a new cycle starts)."""
        entry = self.shifts.get((path, kind))
        if entry is None:
            return base
        shift, at = entry
        if kind == _CYCLE and base < at:
            del self.shifts[(path, kind)]
            return base
        return base + shift


class SignalOperations:
    """The operations of :mod:`focas_net.sim._signals`, a base of
    :class:`~focas_net.sim.Machine` (which builds the attributes named here)."""

    _paths: Paths
    _alarms: Alarms
    _pmc: Pmc
    _counters: Counters
    _collected: Collected

    def check_writable(self) -> None:  # pragma: no cover - the machine's
        raise NotImplementedError

    def timer(self, kind: int, *, path: int = 1) -> float:  # pragma: no cover
        raise NotImplementedError

    def status(self, *, path: int = 1) -> Status:  # pragma: no cover - the machine's
        raise NotImplementedError

    # -- the CNC's clock -----------------------------------------------------------------
    def set_cnc_date(self, year: int, month: int, day: int) -> None:
        """Set the date of the CNC's clock (its time of day runs on): EW_PROT (read-only
        machine), EW_DATA (no such date, or a year outside 1987..2037)."""
        self.check_writable()
        for what, value in (("year", year), ("month", month), ("day", day)):
            need_int(what, value)
        now = self._alarms.now()
        why = cnc_year_unfit(year) or field_unfit("month", month, 1, 12)
        if why is None:
            days = calendar.monthrange(year, month)[1]
            why = field_unfit("day", day, 1, days)
            why = None if why is None else f"{why} ({year:04d}-{month:02d})"
        if why is not None:
            raise MachineError(EW.DATA, why)
        self._set_clock(now.replace(year=year, month=month, day=day) - now)

    def set_cnc_time(self, hour: int, minute: int, second: int) -> None:
        """Set the time of day of the CNC's clock (its date stays): EW_PROT (read-only
        machine), EW_DATA (outside 00:00:00..23:59:59)."""
        self.check_writable()
        for what, value in (("hour", hour), ("minute", minute), ("second", second)):
            need_int(what, value)
        now = self._alarms.now()
        for what, value, high in (
            ("hour", hour, 23),
            ("minute", minute, 59),
            ("second", second, 59),
        ):
            why = field_unfit(what, value, 0, high)
            if why is not None:
                raise MachineError(EW.DATA, why)
        self._set_clock(now.replace(hour=hour, minute=minute, second=second) - now)

    def _set_clock(self, by: timedelta) -> None:
        if by:
            self._alarms.shift += by
            c = self._counters
            c.macro += 1
            c.version += 1

    # -- run-time parameters, diagnostic 4901 ---------------------------------------------
    def _timer_param(self, datano: int, item: DataItem, path: int) -> int:
        """The value of run-time parameter ``datano`` of ``path`` (held in ``item``'s range)."""
        kind, minutes = TIMER_PARAMS[datano]
        self._follow_data()
        ms = math.floor(self.timer(kind, path=path) * 1000 + 1e-6)
        value = ms // _MS_PER_MINUTE if minutes else ms % _MS_PER_MINUTE
        assert item.low is not None and item.high is not None
        return max(item.low, min(item.high, value))

    def _write_timer_param(self, datano: int, value: int, path: int) -> None:
        """Set the timer of run-time parameter ``datano`` of ``path`` so that it reads
        ``value`` (the other unit's part stays)."""
        kind, minutes = TIMER_PARAMS[datano]
        base = 0.0 if kind == METER else self._paths.at(path).timer(kind)
        ms = math.floor(self.timer(kind, path=path) * 1000 + 1e-6)
        whole, part = divmod(ms, _MS_PER_MINUTE)
        wanted = (value * _MS_PER_MINUTE + part) if minutes else whole * _MS_PER_MINUTE + value
        if kind == METER:
            since = self._collected.meters.get(path, (0.0, None))[1]
            now = self._paths.at(path).time.now()
            self._collected.meters[path] = (wanted / 1000, None if since is None else now)
        else:
            self._collected.shifts[(path, kind)] = (wanted / 1000 - base, base)

    def _meter(self, path: int) -> float:
        """Seconds of ``path``'s general-purpose integrating meter."""
        counted, since = self._collected.meters.get(path, (0.0, None))
        if since is None:
            return counted
        return counted + self._paths.at(path).time.now() - since

    def _watch_meters(self) -> None:
        """Start or stop each path's integrating meter as its TMRON (G53.0) now reads."""
        area = self._pmc.areas.get("G")
        if area is None:
            return
        meters = self._collected.meters
        for number in range(1, self._paths.count + 1):
            at = PATH_SIGNALS_STRIDE * (number - 1) + _TMRON[0]
            if at >= area.size:
                break
            on = bool(area.data[at] >> _TMRON[1] & 1)
            counted, since = meters.get(number, (0.0, None))
            now = self._paths.at(number).time.now()
            if on and since is None:
                meters[number] = (counted, now)
            elif not on and since is not None:
                meters[number] = (counted + now - since, None)

    def _servo_power(self, axis: int, path: int) -> int:
        """Diagnostic 4901 of ``axis`` (1..) of ``path``: watts from the servo load (the
        value held while the figures are set by hand)."""
        p = self._paths.at(path)
        self._follow_data()
        if not p.driven:
            item, i = p.items.lookup(True, SERVO_POWER_DIAG, axis)
            return item.values[i]
        item, _ = p.items.lookup(True, SERVO_POWER_DIAG, axis)
        loads = p.production.servo_loads()
        value = loads[axis - 1] * SERVO_WATTS_PER_PERCENT if axis <= len(loads) else 0
        assert item.low is not None and item.high is not None
        return max(item.low, min(item.high, value))  # within the range the machine gives it

    def _spindle_diag(self, datano: int, axis: int, path: int) -> int | None:
        """A spindle diagnostic of spindle ``axis`` (0: the first) of ``path``, None when
        ``datano`` is no spindle diagnostic the machine has as such (an item per axis, or none):
        EW_PATH, EW_ATTRIB (a spindle the path has not)."""
        p = self._paths.at(path)
        item = p.items.items.diags.get(datano)
        if datano not in SPINDLE_DIAGS or item is None or item.axis:
            return None
        spindles = self._paths.info(path).spindles
        if not 0 <= axis <= spindles:
            raise MachineError(EW.ATTRIB, f"diagnostic {datano}: spindle {axis} of {spindles}")
        self._follow_data()
        if datano not in (SPINDLE_LOAD_DIAG, SPINDLE_POWER_DIAG) or not p.driven:
            return item.values[0]
        loads = p.production.spindle_loads()
        load = loads[max(axis, 1) - 1] if max(axis, 1) <= len(loads) else 0
        value = load * (SPINDLE_WATTS_PER_PERCENT if datano == SPINDLE_POWER_DIAG else 1)
        assert item.low is not None and item.high is not None
        return max(item.low, min(item.high, value))

    def _data_stamp(self) -> tuple[int, tuple[float, int] | None, int]:
        """What the figures that follow time depend on now: the power-on minute; machine time
        while a path runs, a meter counts or a path's figures (the loads of 410, 4901, 4902)
        are driven; which paths are driven."""
        paths = self._paths
        every = paths.all
        first = every[0]
        now = first.time.now()
        driven = 0  # a bit per driven path
        for i, p in enumerate(every):
            if p.driven:
                driven |= 1 << i
        c = self._collected
        moving = bool(driven) or paths.live
        if not moving and c.meters:
            moving = any(since is not None for _, since in c.meters.values())  # a meter counts
        minute = math.floor((now - first.powered_at) / 60)
        # the loads change with the figures as well as with time (a feed hold, a new mode)
        return (minute, (now, self._counters.motion) if moving else None, driven)

    def _follow_data(self) -> None:
        """A figure that follows time is being read: from now on the data counter follows
        what it depends on (:meth:`_tick_data`)."""
        c = self._collected
        if not c.data_followed:
            c.data_seen = self._data_stamp()
            c.data_followed = True

    def _tick_data(self) -> None:
        """Move the data counter when what follows time may read otherwise than when it was
        last read (:meth:`_data_stamp`). Only once such a figure was read since the counter
        last moved (a kept answer can hold it): otherwise time changes nothing read, and
        nothing is checked."""
        c = self._collected
        if c.data_followed and self._data_stamp() != c.data_seen:
            c.data_followed = False
            self._counters.data += 1

    def _clock_second(self) -> tuple[int, ...]:
        """The CNC clock's second, as #3011/#3012 read it."""
        t = self._alarms.clock()
        return (t.second, t.minute, t.hour, t.day, t.month, t.year)

    def _follow_clock(self) -> None:
        """#3011 or #3012 is being read: from now on the macro counter follows the clock's
        second (:meth:`_tick_macro`)."""
        c = self._collected
        if not c.clock_followed:
            c.macro_seen = self._clock_second()
            c.clock_followed = True

    def _tick_macro(self) -> None:
        """Move the macro counter when the clock's second changed since #3011/#3012 were read
        (a setting of the clock moves it itself); nothing is checked until one is read."""
        c = self._collected
        if c.clock_followed and self._clock_second() != c.macro_seen:
            c.clock_followed = False
            self._counters.macro += 1

    # -- signals ---------------------------------------------------------------------------
    def _show_overrides(self, path: int) -> None:
        """G12/G14/G30 of ``path`` from the overrides it uses."""
        e = self._paths.at(path).engine
        feed, rapid, spindle = (
            round(e.feed_override),
            round(e.rapid_override),
            round(e.spindle_override),
        )
        self._pmc.show_overrides(path, feed, rapid, spindle)

    def _show_state(self) -> None:
        """The F signals of the state of every path (SA, MA, AL, the mode), when the status
        changed since they were last set."""
        c = self._counters
        if c.status == self._collected.status_seen:
            return
        self._collected.status_seen = c.status
        area = self._pmc.areas.get("F")
        if area is None:
            return
        f = area.data
        changed = False
        for number in range(1, self._paths.count + 1):
            base = PATH_SIGNALS_STRIDE * (number - 1)
            if base + 4 >= area.size:
                break
            s = self.status(path=number)
            ready = 0 if s.emergency else 1
            wanted = (
                f[base] & ~(1 << _SA) | ready << _SA,
                f[base + 1] & ~(1 << _MA | 1 << _AL) | ready << _MA | (1 if s.alarm else 0),
                _F3_OF_MODE.get(s.aut, 0),
                f[base + 4] & ~(1 << _MREF) | _F4_OF_MODE.get(s.aut, 0),
            )
            for i, value in zip((0, 1, 3, 4), wanted, strict=True):
                if f[base + i] != value:
                    f[base + i] = value
                    changed = True
        if changed:
            c.pmc += 1
            c.version += 1

    def panel_signals(self, *, path: int = 1) -> OperatorSignals:
        """The operator panel's signals of ``path`` (:class:`OperatorSignals`): EW_PATH."""
        p = self._paths.at(path)
        s = self.status(path=path)
        e = p.engine
        rapid = next(i for i, step in enumerate((100, 50, 25, 0)) if e.rapid_override >= step)
        g = self._pmc.areas.get("G")
        base = PATH_SIGNALS_STRIDE * (path - 1)

        def bit(address: int, n: int) -> int:
            if g is None or base + address >= g.size:
                return 0
            return g.data[base + address] >> n & 1

        return OperatorSignals(
            mode=s.aut,
            rapid=rapid,
            feed=min(25, math.floor(e.feed_override / 10 + 1e-9)),
            block_delete=bit(44, 0),
            single_block=bit(46, 1),
            machine_lock=bit(44, 1),
            dry_run=bit(46, 7),
            feed_hold=1 if s.run == 2 else 0,
        )
