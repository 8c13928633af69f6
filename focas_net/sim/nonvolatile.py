"""What a machine keeps across power-off, as plain data (protocol-free, no I/O).

A FANUC control keeps some of its memory when it is switched off (battery-backed SRAM and
FROM) and loses the rest. :func:`capture` takes what a machine keeps, :func:`restore` puts it
back into a machine just built from the same machine file (the power-on), and :func:`shape`
describes what the kept data must fit (axes, paths, the ranges of the tables), so that a state
written for another machine is refused naming the difference instead of half applied.

Kept (the nonvolatile memory):

* every parameter value (path-type parameters per path), the parts counts (parameters
  6711/6712 and the engine's counters) and the run-time timers (power-on, operating, cutting:
  parameters 6750-6754, and the general-purpose integrating meter 6755/6756), in whole
  seconds;
* the common variables #500-#999;
* each path's part programs and its main (selected) program;
* the alarm history, and how far the CNC's clock was set (``cnc_settimer``);
* the PMC's keep relays K, data table D, counters C and timers T;
* each path's tool offsets, work offsets and tool life groups (counts, tool states).

Reset as a power cycle resets it (by not being kept):

* the local variables #1-#33 and the common variables #100-#199 are vacant. FANUC's
  parameter 6001 bit 6 (CCV) decides whether a *reset* clears #100-#199; a power-off clears
  them whatever it says, so no parameter keeps them here either;
* the PMC's R, G, F, X, Y (and E, A) areas are zero (the F signals are shown again from the
  state);
* the programs are rewound: no cycle runs, the main program is at its head;
* every active alarm is cleared (a simulated alarm has no cause that would raise it again at
  power-on); the history keeps its entries;
* the operator panel, the overrides, the modal state and the cycle time are those of the
  machine file.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from datetime import datetime, timedelta
from decimal import Decimal, InvalidOperation
from typing import TYPE_CHECKING, Any, Final

from ._alarms import HistoryEntry
from ._base import MachineError
from ._items import PARTS_COUNT, PARTS_TOTAL
from ._macros import macro_value
from ._signals import METER
from ._tools import LifeTool, ToolGroup

if TYPE_CHECKING:
    from .machine import Machine

__all__ = [
    "KEPT_MACROS",
    "KEPT_PMC_AREAS",
    "KEPT_TIMERS",
    "StateMismatch",
    "capture",
    "restore",
    "shape",
    "shape_differences",
]

#: The macro variables a power cycle keeps: the common variables #500-#999.
KEPT_MACROS: Final = range(500, 1000)
#: The PMC areas a power cycle keeps: keep relays, data table, counters, timers.
KEPT_PMC_AREAS: Final = ("K", "D", "C", "T")
#: The timers (``cnc_rdtimer`` types) a power cycle keeps: power-on, operating, cutting.
KEPT_TIMERS: Final = (0, 1, 2)

JSON = dict[str, Any]


class StateMismatch(ValueError):
    """Kept data that does not fit the machine (another machine file, or a malformed state);
    the message names what differs."""


def shape(m: Machine) -> JSON:
    """What the kept data must fit: the control class, each path's kind and axes, each
    parameter's type, axis flag and range, the macro ranges, the PMC areas, the history
    capacity and each path's tool tables."""
    items = m._items
    return {
        "control_class": m.control_class,
        "paths": [[info.kind, "".join(info.axes)] for info in m._paths.infos],
        "params": {
            str(n): [int(it.kind or 0), bool(it.axis), it.low, it.high, it.decimals]
            for n, it in sorted(items.params.items())
        },
        "macro_ranges": [[r.first, r.last, r.writable] for r in m._macros.ranges],
        "pmc": {letter: a.size for letter, a in sorted(m._pmc.areas.items())},
        "history_capacity": m.history_capacity,
        "tools": [
            [t.offsets.kind, t.offsets.count, t.life.max_groups, t.life.max_tools]
            for _, t in sorted(m._tools.items())
        ],
    }


_SHAPE_NAMES: Final = {
    "control_class": "the control class",
    "paths": "the paths (kind, axes)",
    "params": "parameter",
    "macro_ranges": "the macro variable ranges",
    "pmc": "PMC area",
    "history_capacity": "the alarm history capacity",
    "tools": "the tool tables (kind, offsets, groups, tools per group)",
}


def shape_differences(kept: JSON, now: JSON, limit: int = 5) -> list[str]:
    """What differs between the shape a state was written for and the machine's now, in
    words (at most ``limit`` entries, and a count of the rest)."""
    found: list[str] = []
    for key, name in _SHAPE_NAMES.items():
        was, is_ = kept.get(key), now.get(key)
        if was == is_:
            continue
        if isinstance(was, dict) and isinstance(is_, dict):
            for sub in sorted(set(was) | set(is_), key=_number_first):
                if sub not in is_:
                    found.append(f"{name} {sub}: in the state, not in the machine")
                elif sub not in was:
                    found.append(f"{name} {sub}: in the machine, not in the state")
                elif was[sub] != is_[sub]:
                    found.append(
                        f"{name} {sub}: {_brief(was[sub])} in the state, {_brief(is_[sub])} now"
                    )
        elif was is None or is_ is None:
            found.append(f"{name}: {'not in the state' if was is None else 'not in the machine'}")
        else:
            found.append(f"{name}: {_brief(was)} in the state, {_brief(is_)} now")
    if len(found) > limit:
        found = [*found[:limit], f"and {len(found) - limit} more"]
    return found


def _brief(value: object, room: int = 80) -> str:
    """``value`` as text, cut to ``room`` characters (an error stays one readable line)."""
    text = str(value)
    return text if len(text) <= room else text[: room - 3] + "..."


def _number_first(text: str) -> tuple[int, str]:
    return (int(text), "") if text.isdigit() else (1 << 30, text)


def capture(m: Machine) -> JSON:
    """What ``m`` keeps across power-off, as JSON-ready data (see the module docstring)."""
    m._sync()
    paths = m._paths
    per_path: list[JSON] = []
    for p in paths.all:
        store = p.programs
        tools = m._tools[p.number]
        life = tools.life
        per_path.append(
            {
                "own_params": {str(n): list(it.values) for n, it in sorted(p.items.own.items())},
                "programs": [store.text(info.number) for info in store.directory()],
                "main": store.main,
                "parts": [p.engine.parts_count, p.engine.parts_total],
                "timers": [m.timer_ms(kind, path=p.number) // 1000 * 1000 for kind in KEPT_TIMERS],
                "meter": m.timer_ms(METER, path=p.number) // 1000 * 1000,
                "tool_offsets": sorted([n, t, v] for (n, t), v in tools.offsets._values.items()),
                "work_offsets": [list(row) for row in p.engine.work_offsets],
                "tool_groups": [
                    [
                        g.number,
                        g.life_type,
                        g.life,
                        g.count,
                        g.current,
                        [[t.number, t.h, t.d, t.state] for t in g.tools],
                    ]
                    for _, g in sorted(life.groups.items())
                ],
            }
        )
    return {
        "params": {str(n): list(it.values) for n, it in sorted(m._items.params.items())},
        "macros": {str(n): str(v) for n, v in sorted(m._macros.values.items()) if n in KEPT_MACROS},
        "pmc": {
            letter: m._pmc.areas[letter].data.hex()
            for letter in KEPT_PMC_AREAS
            if letter in m._pmc.areas
        },
        "history": [
            [e.occurred_at.isoformat(), e.axis_no, e.alm_type, e.alm_no, e.msg]
            for e in m._alarms.history
        ],
        "clock_shift": m._alarms.shift.total_seconds(),
        "paths": per_path,
    }


def restore(m: Machine, kept: Mapping[str, Any]) -> None:
    """Put ``kept`` (from :func:`capture`, of a machine of the same :func:`shape`) into
    ``m``, a machine just built: the power-on. StateMismatch for data that does not fit;
    ``m`` is then half restored and must be dropped (the loader builds a new one)."""
    try:
        _restore(m, kept)
    except StateMismatch:
        raise
    except (MachineError, KeyError, IndexError, TypeError, ValueError, AttributeError) as exc:
        raise StateMismatch(f"malformed state: {type(exc).__name__}: {exc}") from None


def _ints(values: Any, what: str) -> list[int]:
    if not isinstance(values, list) or not all(
        isinstance(v, int) and not isinstance(v, bool) for v in values
    ):
        raise StateMismatch(f"{what}: a list of integers expected, got {values!r}")
    return values


def _restore_params(table: Mapping[int, Any], kept: Mapping[str, Any], m: Machine) -> None:
    for key, values in kept.items():
        item = table.get(int(key))
        if item is None:
            raise StateMismatch(f"parameter {key}: not in the machine")
        values = _ints(values, f"parameter {key}")
        if len(values) != len(item.values):
            raise StateMismatch(
                f"parameter {key}: {len(values)} values in the state, {len(item.values)} now"
            )
        for i, value in enumerate(values):
            m._items.set(item, i, value, "parameter")


def _restore(m: Machine, kept: Mapping[str, Any]) -> None:
    _restore_params(m._items.params, kept["params"], m)
    macros = m._macros
    for number in [n for n in macros.values if n in KEPT_MACROS]:
        macros.write(number, None)  # a variable vacated since: vacant, whatever the file gives
    for key, text in kept["macros"].items():
        number = int(key)
        if number not in KEPT_MACROS or macros.range_of(number) is None:
            raise StateMismatch(f"macro variable #{number}: not kept by this machine")
        try:
            value = macro_value(Decimal(text))
        except InvalidOperation:
            value = None
        if value is None:
            raise StateMismatch(f"macro variable #{number}: {text!r} is no value it can hold")
        macros.write(number, value)
    for letter, data in kept["pmc"].items():
        area = m._pmc.areas.get(letter)
        if letter not in KEPT_PMC_AREAS or area is None:
            raise StateMismatch(f"PMC area {letter}: not kept by this machine")
        raw = bytes.fromhex(data)
        if len(raw) != area.size:
            raise StateMismatch(f"PMC area {letter}: {len(raw)} bytes in the state, {area.size}")
        area.data[:] = raw
    alarms = m._alarms
    history = [
        HistoryEntry(datetime.fromisoformat(when), int(axis), int(kind), int(no), str(msg))
        for when, axis, kind, no, msg in kept["history"]
    ]
    if len(history) > alarms.capacity or any(e.occurred_at.tzinfo is None for e in history):
        raise StateMismatch("the alarm history does not fit the machine")
    alarms.history.clear()
    alarms.history.extend(history)
    alarms.active.clear()
    shift = float(kept["clock_shift"])
    if not math.isfinite(shift):
        raise StateMismatch(f"clock shift {shift}")
    alarms.shift = timedelta(seconds=shift)
    paths = kept["paths"]
    if len(paths) != m.path_count:
        raise StateMismatch(f"{len(paths)} paths in the state, {m.path_count} now")
    for p, data in zip(m._paths.all, paths, strict=True):
        _restore_path(m, p.number, data)
    counters = m._counters
    counters.alarm += 1
    counters.pmc += 1
    counters.status_changed()


def _restore_path(m: Machine, number: int, data: Mapping[str, Any]) -> None:
    p = m._paths.at(number)
    _restore_params(p.items.own, data["own_params"], m)
    store = p.programs
    for info in list(store.directory()):
        store.delete(info.number)
    for text in data["programs"]:
        if not isinstance(text, str):
            raise StateMismatch(f"path {number}: a program is no text")
        p.store_program(text, False)
    main = data["main"]
    if main is not None:
        store.select(int(main))
        p.manual = replace(p.manual, program_running=int(main), program_main=int(main))
    count, total = _ints(data["parts"], f"path {number} parts")
    p.set_parts(PARTS_COUNT, count)
    p.set_parts(PARTS_TOTAL, total)
    for kind, ms in zip(KEPT_TIMERS, _ints(data["timers"], f"path {number} timers"), strict=True):
        base = p.timer(kind)
        m._collected.shifts[(number, kind)] = (ms / 1000 - base, base)
    (meter,) = _ints([data.get("meter", 0)], f"path {number} meter")  # none before the meter
    if meter < 0:
        raise StateMismatch(f"path {number}: meter {meter}")
    m._collected.meters[number] = (meter / 1000, None)  # TMRON (G53.0) is 0 at power-on
    tools = m._tools[number]
    offsets = tools.offsets
    for n, t in list(offsets._values):
        offsets.write(n, t, 0)
    for n, t, v in data["tool_offsets"]:
        offsets.write(int(n), int(t), int(v))
    rows = data["work_offsets"]
    engine_rows = p.engine.work_offsets
    if len(rows) != len(engine_rows) or any(
        len(row) != len(mine) for row, mine in zip(rows, engine_rows, strict=True)
    ):
        raise StateMismatch(f"path {number}: the work offsets do not fit its axes")
    for row, mine in zip(rows, engine_rows, strict=True):
        mine[:] = [float(v) for v in row]
    life = tools.life
    life.groups.clear()
    for g_number, life_type, life_value, count, current, tools_ in data["tool_groups"]:
        group = ToolGroup(
            int(g_number),
            int(life_value),
            str(life_type),
            int(count),
            [LifeTool(int(t), int(h), int(d), int(s)) for t, h, d, s in tools_],
            int(current),
        )
        if not 0 <= group.current < len(group.tools):
            raise StateMismatch(f"path {number}: tool group {g_number}'s tool in use")
        life.add(group)
