"""The dashboard's view model: machines as JSON-able dicts (pure functions, no I/O).

Each function reads a :class:`~focas_net.sim.Machine` through its public methods, exactly as
the protocol adapters do, and answers plain ``dict``/``list``/``str``/``int``/``float``/``bool``
values the shell sends as JSON. Positions are in millimetres (the machine's least input
increments over ``10**POSITION_DECIMALS``), times in seconds. Status fields carry their FOCAS
(ODBST) names and the labels a FANUC screen shows.
"""

from __future__ import annotations

import contextlib
import re
from collections import deque
from collections.abc import Iterable, Sequence
from decimal import Decimal
from typing import Any, Final

from focas_net._typed import (
    decimal_text,
    lead_as_typed,
    read_otherwise,
    typed_numbers,
    whole_number,
)
from focas_net.errors import EW, ew_name
from focas_net.protocol import (
    AutMode,
    EmergencyState,
    FaultKind,
    ParamDataType,
    RunState,
    alarm_fields,
    alarm_text,
    alarm_time_text,
    pmc_address_unfit,
    status_labels,
)
from focas_net.server.faults import fault_arg_text
from focas_net.sim import (
    AUT_MODES,
    PMC_AREAS,
    POSITION_DECIMALS,
    POSITION_KINDS,
    TIMER_KINDS,
    DataItem,
    Machine,
    MachineError,
    ParamKind,
    pmc_letter,
)

__all__ = [
    "HISTORY_SHOWN",
    "MACRO_SEARCH_CAP",
    "PATH_POINTS",
    "PMC_ROW_BYTES",
    "JsonDict",
    "PathTrail",
    "fleet_view",
    "machine_tile",
    "machine_view",
    "macro_note",
    "macro_range",
    "macro_rows",
    "no_machine",
    "param_data",
    "param_rows",
    "param_text",
    "pmc_address",
    "pmc_window",
    "status_fields",
]

JsonDict = dict[str, Any]


def no_machine(named: str, count: int) -> str:
    """The refusal of machine ``named`` (as typed, or a JSON number) by a dashboard of
    ``count`` machines, as the page says it over its fleet view."""
    shows = "machine 0" if count == 1 else f"machines 0..{count - 1}"
    return f"no machine {named} (this dashboard shows {shows})"


#: Points of the tool path a :class:`PathTrail` keeps.
PATH_POINTS: Final = 1500
#: Alarm history entries the machine view shows (newest first).
HISTORY_SHOWN: Final = 50
#: Bytes of a PMC area the viewer shows at a time.
PMC_ROW_BYTES: Final = 16
#: Most lines of a program the machine view carries.
PROGRAM_LINES: Final = 2000

_MM: Final = 10**POSITION_DECIMALS

_MODE_LABELS: Final = {m.value: m.label for m in AutMode}
_RUN_LABELS: Final = {m.value: m.label for m in RunState}
_RUN_NAMES: Final = {m.value: m.name for m in RunState}


def status_fields(machine: Machine, path: int = 1) -> list[JsonDict]:
    """The ODBST fields of ``path``: ``{"field": "run", "value": 3, "name": "STRT",
    "meaning": ...}``, named by the table the command line uses (``tmmode`` by the machine's
    series), with the keys of ``status --json`` (``name``: the label a FANUC screen shows)."""
    rows = status_labels(machine.status(path=path), machine.path_identity(path).mt_type)
    return [{"field": f, "value": v, "name": label, "meaning": m} for f, v, label, m in rows]


def _alarm(axis_no: int, alm_type: int, alm_no: int, msg: str) -> JsonDict:
    """An alarm's numbers, message, code and the text every front end shows."""
    return {
        **alarm_fields(axis_no, alm_type, alm_no, msg),
        "text": alarm_text(alm_type, alm_no, msg, axis_no),
    }


#: A position kind as every front end names it (``position --kind``, ``watch``): the
#: distance to go is ``distance``.
_POSITION_NAMES: Final = {"distance_to_go": "distance"}


def _mm(value: int) -> float:
    return value / _MM


def _path_tile(machine: Machine, path: int, trail: PathTrail | None = None) -> JsonDict:
    """What a tile shows of one path: mode, run state, program, sequence, parts, alarm. The
    machine is read once per figure (a read of a running machine moves its engine)."""
    status = machine.status(path=path)
    motion = machine.path_motion(path=path)
    if trail is not None:
        trail.record(motion.absolute)
    count, total = machine.parts_counts(path=path)
    alarms = machine.active_alarms(path=path)
    first = alarms[0] if alarms else None
    return {
        "path_no": path,
        "path_name": machine.path_info(path).name,
        "mode": _MODE_LABELS.get(status.aut, str(status.aut)),
        "run": _RUN_LABELS.get(status.run, str(status.run)),
        "run_state": _RUN_NAMES.get(status.run, str(status.run)),
        "emergency": status.emergency == EmergencyState.EMG,  # (the gateway's rule: not RESET)
        "program": motion.program_running,
        "sequence": motion.sequence,
        "parts": count,
        "parts_total": total,
        "alarm": None
        if first is None
        else alarm_text(first.alm_type, first.alm_no, first.msg, first.axis_no),
        "alarms": len(alarms),
    }


def machine_tile(
    index: int, machine: Machine, port: int, trail: PathTrail | None = None
) -> JsonDict:
    """One tile of the fleet view: name, port, and path 1's mode, run state, program, parts
    and alarm; ``paths`` holds the same of every path (one for a single-path machine). The
    tile is running when a path runs and in alarm when a path is; the absolute position of
    path 1 read goes into ``trail`` when given."""
    paths = [
        _path_tile(machine, p, trail if p == 1 else None) for p in range(1, machine.path_count + 1)
    ]
    first = paths[0]
    alarmed = next((t for t in paths if t["alarms"]), first)
    running = next((t for t in paths if t["run"] == "STRT"), first)
    return {
        "index": index,
        "name": machine.name,
        "port": port,
        **{k: v for k, v in first.items() if k not in ("path_no", "path_name")},
        "run_state": running["run_state"],
        "alarm": alarmed["alarm"],
        "alarms": max(t["alarms"] for t in paths),
        "running": running["run"] == "STRT",
        "paths": paths,
    }


def fleet_view(
    entries: Iterable[tuple[int, Machine, int]], trails: Sequence[PathTrail] | None = None
) -> JsonDict:
    """The fleet view: a tile per ``(index, machine, port)`` and the counts of each run state;
    ``trails[index]``, when given, records each machine's tool path on the way."""
    tiles = [
        machine_tile(i, m, port, None if trails is None else trails[i]) for i, m, port in entries
    ]
    running = sum(1 for t in tiles if t["running"])
    alarmed = sum(1 for t in tiles if t["alarms"])
    return {"machines": tiles, "count": len(tiles), "running": running, "alarmed": alarmed}


class PathTrail:
    """The tool path: the newest :data:`PATH_POINTS` absolute positions seen, in millimetres.

    The shell records the positions a few times per second; a position equal to the last one
    is not recorded twice, so a machine at rest keeps its path."""

    __slots__ = ("points",)

    def __init__(self, size: int = PATH_POINTS) -> None:
        self.points: deque[tuple[float, ...]] = deque(maxlen=size)

    def record(self, absolute: Sequence[int]) -> None:
        point = tuple(_mm(v) for v in absolute)
        if not self.points or self.points[-1] != point:
            self.points.append(point)

    def clear(self) -> None:
        self.points.clear()


def _program(machine: Machine, path: int) -> JsonDict | None:
    """The running (else the main) program of ``path``: its lines and the line of the block
    executing."""
    engine = machine.path_engine(path)
    interpreter = engine.interpreter
    program = interpreter.program
    line: int | None = None
    if program is not None and interpreter.block is not None:
        if 0 <= interpreter.block < len(program.blocks):
            line = program.blocks[interpreter.block].line
    number = program.number if program is not None else machine.path_programs(path).main
    if number is None:
        return None
    try:
        text = machine.program_text(number, path=path)
    except MachineError:
        return None
    return {"number": number, "lines": text.splitlines()[:PROGRAM_LINES], "line": line}


def machine_view(
    index: int,
    machine: Machine,
    port: int,
    *,
    trail: PathTrail | None = None,
    faults: Iterable[tuple[str, int, int]] = (),
    path: int = 1,
) -> JsonDict:
    """Everything the machine view shows of ``path``, at one moment, and ``paths``, what a
    tile shows of every path. ``faults`` are the machine-wide armed faults as ``(kind name,
    answers left, arg)``; the absolute position read goes into ``trail`` (the tool path
    shown) when given. EW_PATH (MachineError) for a path the machine has not."""
    info = machine.path_info(path)
    status = machine.status(path=path)
    motion = machine.path_motion(path=path)
    if trail is not None:
        trail.record(motion.absolute)
    count, total = machine.parts_counts(path=path)
    feed_ov, rapid_ov, spindle_ov = machine.overrides(path=path)
    panel = machine.path_panel(path)
    positions = []
    for axis_index, axis in enumerate(info.axes):
        row: JsonDict = {"axis": axis}
        for kind in POSITION_KINDS:  # named as the command line names them (distance)
            row[_POSITION_NAMES.get(kind, kind)] = _mm(getattr(motion, kind)[axis_index])
        positions.append(row)
    try:
        required = machine.read_param(6713, 0, path=path)
    except MachineError:
        required = None
    main = machine.path_programs(path).main
    running = motion.program_running
    return {
        "index": index,
        "name": machine.name,
        "port": port,
        "control_class": machine.control_class,
        "read_only": machine.read_only,
        "path_no": path,
        "path_name": info.name,
        "path_count": machine.path_count,
        "paths": [_path_tile(machine, p) for p in range(1, machine.path_count + 1)],
        "axes": list(info.axes),
        "status": status_fields(machine, path),
        "mode": _MODE_LABELS.get(status.aut, str(status.aut)),
        "run": _RUN_LABELS.get(status.run, str(status.run)),
        "positions": positions,
        "path": [list(p) for p in trail.points] if trail is not None else [],
        "feed": motion.feed,
        "spindle_speed": motion.spindle_speed,
        "sequence": motion.sequence,
        "program_running": running,
        "program_main": motion.program_main,
        "overrides": {"feed": feed_ov, "rapid": rapid_ov, "spindle": spindle_ov},
        "loads": {
            "spindle": list(machine.spindle_loads(path=path)),
            "servo": list(machine.servo_loads(path=path)),
        },
        "timers": {kind: machine.timer(k, path=path) for k, kind in enumerate(TIMER_KINDS)},
        "parts": {"count": count, "total": total, "required": required},
        "panel": {"mode": panel.mode, "pwe": panel.pwe, "emergency": panel.emergency},
        "modes": [[m, _MODE_LABELS[m]] for m in sorted(AUT_MODES)],
        "alarms": [
            _alarm(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in machine.active_alarms(path=path)
        ],
        "history": [
            {
                "occurred_at": alarm_time_text(h.occurred_at),
                **_alarm(h.axis_no, h.alm_type, h.alm_no, h.msg),
            }
            for h in machine.alarm_history(HISTORY_SHOWN)
        ],
        "programs": [
            {
                "number": p.number,
                "name": p.name,
                "size": p.size,
                "main": p.number == main,
                "running": p.number == running and status.run != 0,
            }
            for p in machine.program_directory(path=path)
        ],
        "program": _program(machine, path),
        "pmc_areas": _pmc_areas(machine),
        "faults": [
            {"kind": k, "remaining": n, "arg": arg, "arg_text": fault_arg_text(FaultKind[k], arg)}
            for k, n, arg in faults
        ],
        "fault_kinds": [k.name for k in FaultKind],
        "versions": {"data": machine.data_version, "macro": machine.macro_version},
    }


def _pmc_areas(machine: Machine) -> list[JsonDict]:
    areas = []
    for letter in PMC_AREAS:
        info = machine.pmc_area(letter)
        if info is not None:
            size, protected = info
            areas.append({"area": letter, "size": size, "write_protected": protected})
    return areas


_PMC_ADDRESS: Final = re.compile(r"([A-Za-z]?)\s*([0-9]+)", re.ASCII)


def pmc_address(text: str, area: str) -> tuple[str, int]:
    """``(area, address)`` of a PMC address as the command line writes one: ``100`` (in
    ``area``) or ``R100`` (the letter names the area, in either case). ValueError naming
    ``text`` for anything else (a letter that is no PMC area, a bit ``R100.3``, a sign)."""
    found = _PMC_ADDRESS.fullmatch(text.strip())
    if found is None:
        try:  # a whole number as the command line reads pmc read's START (0x10, +16)
            number = whole_number(text)
        except ValueError:
            raise ValueError(f"PMC address {text!r}: write a byte address, 100 or R100") from None
        beyond = pmc_address_unfit(number)  # -1 as `pmc read R -1` is refused
        if beyond is not None:  # (named as typed: 0x10000 reads as 65536)
            raise ValueError(lead_as_typed(beyond, typed_numbers([text])))
        found = _PMC_ADDRESS.fullmatch(str(number))
        assert found is not None
    try:
        letter = pmc_letter(found[1] or area)  # the machine's words for no PMC area
    except ValueError as exc:
        raise ValueError(f"PMC address {text!r}: {exc}" if found[1] else str(exc)) from None
    digits = found[2]
    if len(digits) > 6:
        raise ValueError(f"PMC address {text!r}: beyond every PMC area")
    beyond = pmc_address_unfit(int(digits))  # as `pmc read R 70000` is refused
    if beyond is not None:
        raise ValueError(beyond)
    return letter, int(digits)


def pmc_window(machine: Machine, area: str, start: int, length: int = PMC_ROW_BYTES) -> JsonDict:
    """``length`` bytes of PMC area ``area`` from ``start`` (cut to the area's end), with the
    area's size. MachineError (EW_NOOPT, EW_NUMBER) for an area or address it does not have."""
    try:
        letter = pmc_letter(area)
    except ValueError as exc:  # the machine's words for a letter that is no PMC area
        raise MachineError(EW.NUMBER, str(exc)) from None
    info = machine.pmc_area(letter)
    if info is None:
        machine.check_pmc_area(letter)  # EW_NOOPT in the machine's words
    assert info is not None
    size, protected = info
    # (an address outside the area: one byte asked, for the machine's words of its refusal)
    data = machine.read_pmc(letter, start, min(length, size - start) if 0 <= start < size else 1)
    return {
        "area": letter,
        "start": start,
        "size": size,
        "write_protected": protected,
        "bytes": list(data),
    }


def param_text(item: DataItem, value: int) -> str:
    """A parameter value as the page shows it: a bit parameter's eight bits #7..#0
    (``10110000``), a real one with its decimals, the others in decimal."""
    if item.kind is ParamKind.BIT:
        return f"{value & 0xFF:08b}"
    if item.kind is ParamKind.REAL and item.decimals:
        return decimal_text(Decimal(value).scaleb(-item.decimals))  # 0.0000001, not 1E-7
    return str(value)


def param_data(item: DataItem, axis: int, value: int) -> JsonDict:
    """A parameter's value as ``focas-net param get --json`` gives it (``number``, ``axis``,
    ``value``, ``width``, ``type``; a real one's ``value`` as decimal text with its
    ``decimals``, a bit one's ``bits``), and ``text`` as the page shows it
    (:func:`param_text`)."""
    data: JsonDict = {"number": item.number, "axis": axis, "value": value, "width": item.width}
    if item.kind is not None:
        data["type"] = ParamDataType(item.kind).label
    if item.kind is ParamKind.REAL:
        data["value"] = decimal_text(Decimal(value).scaleb(-item.decimals))
        data["decimals"] = item.decimals
    elif item.kind is ParamKind.BIT:
        data["value"] = value & 0xFF
        data["bits"] = f"{value & 0xFF:08b}"
    return {**data, "text": param_text(item, value)}


#: A parameter's bit as the command line names it (``1815.1``): the page finds the parameter.
_NUMBER_BIT: Final = re.compile(r"([0-9]+)\.[0-7]")


def param_rows(
    machine: Machine, query: str = "", limit: int = 200, *, path: int = 1
) -> list[JsonDict]:
    """The parameters whose number starts with ``query`` or whose name contains it (case
    insensitive), at most ``limit`` of them, by number. ``type`` is the type as every front
    end names it (``two-word``); an axis parameter has a value per axis, named in ``axes``;
    a bit parameter's values are its eight bits #7..#0 (``10110000``), as the page edits
    them, and ``bits`` too; ``1815.1``, a bit as ``param get`` names it, finds parameter 1815.
    ValueError for a number typed in digits of another script (``'\u0661\u0663'``), which
    would find nothing and not say why."""
    q = query.strip().lower()
    one_bit = _NUMBER_BIT.fullmatch(q)
    exact = one_bit is not None  # the one parameter of that number
    if one_bit is not None:
        q = one_bit[1]
    elif read_otherwise(q):  # 0x717, as param get 0x717 names parameter 1815
        with contextlib.suppress(ValueError):
            q, exact = str(whole_number(q)), True
    if any(c.isdigit() and not c.isascii() for c in q):
        try:
            whole_number(q)  # the words every front end refuses such digits with
        except ValueError as exc:
            raise ValueError(f"parameter search: {exc}") from None
    path_axes = list(machine.path_info(path).axes)
    rows: list[JsonDict] = []
    for number in machine.param_numbers():
        item = machine.param_item(number)
        assert item is not None
        found = number == int(q) if exact else (str(number).startswith(q) or q in item.name.lower())
        if q and not found:
            continue
        axes = path_axes if item.axis else []
        raw = [
            machine.read_param(number, axis, path=path) for axis in range(1, len(axes) + 1) or (0,)
        ]
        rows.append(
            {
                "number": number,
                "name": item.name,
                "type": "" if item.kind is None else ParamDataType(item.kind).label,
                "axis": item.axis,
                "axes": axes,
                "low": item.low,
                "high": item.high,
                "decimals": item.decimals,
                "values": [param_text(item, value) for value in raw],
                "bits": [f"{v & 0xFF:08b}" for v in raw] if item.kind is ParamKind.BIT else None,
            }
        )
        if len(rows) >= limit:
            break
    return rows


def macro_value(value: Decimal | None) -> str | None:
    """A macro value as the page is given it: text as the command line writes it
    (``-0.000000001``, never ``-1E-9``, which its box would refuse), None (JSON ``null``) when
    vacant, as ``focas-net macro get --json`` gives it."""
    return None if value is None else decimal_text(value)


#: The macro variable numbers a search may name (FOCAS carries a variable number as a short).
MACRO_SEARCH_CAP: Final = 0x7FFF


_MACRO_QUERY: Final = re.compile(r"#?(-?[0-9]+)(?:\s*-\s*#?(-?[0-9]+))?", re.ASCII)


def _runs(numbers: Sequence[int]) -> str:
    """``#1..#33, #100..#199``: ascending ``numbers`` as runs."""
    runs: list[list[int]] = []
    for n in numbers:
        if runs and runs[-1][1] == n - 1:
            runs[-1][1] = n
        else:
            runs.append([n, n])
    return ", ".join(f"#{a}" if a == b else f"#{a}..#{b}" for a, b in runs) or "none"


def macro_range(query: str) -> tuple[int, int]:
    """The numbers ``low..high`` a macro search names: ``"N"`` from N on, ``"N-M"`` (a ``#``
    before either allowed), ``""`` all. ValueError, naming ``query``, for other text, an empty
    range (N above M) and a number beyond ``-32768..32767``."""
    q = query.strip()
    if not q:
        return -0x8000, MACRO_SEARCH_CAP
    found = _MACRO_QUERY.fullmatch(q)
    if found is None:
        raise ValueError(f"macro search {query!r}: write N or N-M (variable numbers, 0-9)")
    for text in (t for t in found.groups() if t is not None):
        if len(text.lstrip("-")) > 5 or not -0x8000 <= int(text) <= MACRO_SEARCH_CAP:
            raise ValueError(
                f"macro search {query!r}: #{text} is beyond the variable numbers "
                f"(-32768..{MACRO_SEARCH_CAP})"
            )
    low = int(found[1])
    high = int(found[2]) if found[2] is not None else MACRO_SEARCH_CAP
    if low > high:
        raise ValueError(f"macro search {query!r}: an empty range (#{low} is above #{high})")
    return low, high


def macro_rows(
    machine: Machine,
    numbers: Sequence[int],
    query: str = "",
    limit: int = 200,
    *,
    path: int = 1,
) -> list[JsonDict]:
    """Macro variables among ``numbers`` (the machine's, ascending) in the range
    :func:`macro_range` reads from ``query``, at most ``limit``. ValueError, naming
    ``query``, for a query that names no range, or a range holding none of ``numbers`` (the
    message lists the machine's)."""
    low, high = macro_range(query)
    rows: list[JsonDict] = []
    for number in numbers:
        if not low <= number <= high:
            continue
        if len(rows) >= limit:
            break
        try:
            value = machine.read_macro(number, path=path)
        except MachineError as exc:
            rows.append({"number": number, "value": "", "error": ew_name(exc.ew)})
            continue
        rows.append(
            {
                "number": number,
                "value": macro_value(value),
                "writable": bool(machine.macro_writable(number)),
            }
        )
    if not rows:
        shown = f"#{low}" if high == MACRO_SEARCH_CAP else f"#{low}..#{high}"
        raise ValueError(
            f"macro search {query!r}: no variable in {shown} (the machine has {_runs(numbers)})"
        )
    return rows


def macro_note(numbers: Sequence[int], query: str, shown: int) -> str:
    """What a macro search's answer says of what it left out (empty when nothing)."""
    low, high = macro_range(query)
    found = sum(1 for n in numbers if low <= n <= high)
    if found <= shown:
        return ""
    return f"the first {shown} of {found} variables: narrow the range (N-M) to see the others"
