"""Machine files: a simulated CNC described in TOML (schema in ``docs/machine-file.md``).

:func:`load_machine` reads a file with the standard ``tomllib`` and builds a
:class:`~focas_net.sim.machine.Machine`. Every key is checked; anything wrong raises
:class:`MachineFileError`, whose message names the file, the key as a dotted path
(``parameters.1320.range``, ``versamax[1].references[0].type``) and what is wrong. Unknown keys
are errors too, so a misspelt key never passes silently.
"""

from __future__ import annotations

import math
import re
import tomllib
from collections.abc import Mapping
from decimal import Decimal
from os import PathLike
from pathlib import Path
from typing import Any, Final

from focas_net._bits import bits_hint, bits_of_text
from focas_net._typed import decimal_number, file_name_unfit, macro_unfit, os_words
from focas_net.versamax import BoardId, IOModuleRecord, RefType

from ._base import NUMBERS, n_values
from ._identity import CLASS_MAX_AXES, control_class_unfit, known_class, name_problem
from ._known_params import (
    AXIS_NAME_PARAM,
    KNOWN_DIAGS,
    KNOWN_PARAMS,
    axis_letter_problem,
    known_range,
    param_type_problem,
)
from ._modal import ExternalMessage, message_problem
from ._paths import kind_of
from ._pmc import pmc_letter
from ._signals import CLOCK_VARIABLES
from ._station import MAX_RACK, MAX_SLOT
from ._variables import PARTS_VARIABLES
from .default import gniu_record, mdd844_record
from .filecheck import (
    _I16,
    _I32,
    MachineFileError,
    TomlFloat,
    _ascii,
    _bool,
    _bytes,
    _Ctx,
    _int,
    _kind,
    _list,
    _number_key,
    _only,
    _str,
    _table,
    _text,
    toml_point_hint,
)
from .machine import (
    DEFAULT_CONTROL_CLASS,
    DEFAULT_HISTORY_CAPACITY,
    MAX_HISTORY_CAPACITY,
    MAX_REAL_DECIMALS,
    MODE_NAMES,
    PMC_AREAS,
    Clock,
    DataItem,
    Identity,
    Machine,
    MacroRange,
    ParamKind,
    PathSpec,
    PmcAreaSpec,
    utc_now,
)
from .nc import Scenario, SimClock
from .nc.scenario import MAX_PARTS, MAX_SEED
from .pathfile import _axes, _motion, _panel, _programs, path_specs
from .toolfile import tool_specs

__all__ = ["MODE_NAMES", "MachineFileError", "load_machine", "machine_from_dict", "state_folder"]


#: ``type`` names of a parameter or diagnostic, as every front end names the types
#: (``two-word``); those of older files still load (``2-word``, and the width names ``i16`` and
#: ``i32``, which are ``word`` and ``two-word``).
_TYPES: Final[dict[str, ParamKind]] = {
    "bit": ParamKind.BIT,
    "byte": ParamKind.BYTE,
    "word": ParamKind.WORD,
    "i16": ParamKind.WORD,
    "2-word": ParamKind.TWO_WORD,
    "two-word": ParamKind.TWO_WORD,
    "i32": ParamKind.TWO_WORD,
    "real": ParamKind.REAL,
}
_TYPE_NAMES: Final = '"bit", "byte", "word", "two-word", "real"'
_MODULES: Final = {"IC200GBI001": gniu_record, "IC200MDD844": mdd844_record}
_REF_TYPES: Final[dict[str, RefType]] = {"I": RefType.I, "Q": RefType.Q, "AI": RefType.AI}
_REF_TYPES["AQ"] = RefType.AQ


# -- sections -----------------------------------------------------------------------------------


def _identity(ctx: _Ctx, value: Any, n_axes: int, control_class: str) -> Identity:
    t = _table(ctx, value)
    _only(ctx, t, ("addinfo", "max_axis", "cnc_type", "mt_type", "series", "version"))
    most = max(CLASS_MAX_AXES[control_class], n_axes)
    max_axis = _int(ctx.sub("max_axis"), t.get("max_axis", most), (n_axes, 32))
    return Identity(
        _int(ctx.sub("addinfo"), t.get("addinfo", 2), _I16),
        max_axis,
        _ascii(ctx.sub("cnc_type"), t.get("cnc_type", " 0"), 2),
        _ascii(ctx.sub("mt_type"), t.get("mt_type", " M"), 2),
        _ascii(ctx.sub("series"), t.get("series", "D4F1"), 4),
        _ascii(ctx.sub("version"), t.get("version", "32.0"), 4),
        f"{n_axes:02d}",
    )


def _items(ctx: _Ctx, value: Any, n_axes: int, *, names: list[str] | None = None) -> list[DataItem]:
    """Parameters (``names``: the machine's axes, which parameter 1020 must name) or
    diagnostics (``names`` None); the types of those the machine reads or computes are
    checked."""
    t = _table(ctx, value)
    items: list[DataItem] = []
    for key, raw in t.items():
        c = ctx.sub(key)
        number = _number_key(c, key, NUMBERS)
        if any(item.number == number for item in items):
            c.fail(f"number {number} is given twice")
        spec = _table(c, raw)
        _only(c, spec, ("type", "axis", "range", "value", "name", "decimals"))
        if "type" not in spec:
            c.sub("type").fail(f"missing (one of {_TYPE_NAMES})")
        type_name = _str(c.sub("type"), spec["type"])
        kind = _TYPES.get(type_name.strip().lower())
        if kind is None:
            c.sub("type").fail(f"unknown type {type_name!r} (expected one of {_TYPE_NAMES})")
        decimals = 0
        if kind is ParamKind.REAL:
            decimals = _int(c.sub("decimals"), spec.get("decimals", 0), (0, MAX_REAL_DECIMALS))
        elif "decimals" in spec:
            c.sub("decimals").fail('applies to type = "real" only')
        span = kind.span

        is_axis = _bool(c.sub("axis"), spec.get("axis", False))
        low, high = span if names is None else known_range(number, kind)
        if "range" in spec:
            rc = c.sub("range")
            bounds = _list(rc, spec["range"])
            if len(bounds) != 2:
                rc.fail("must be [low, high]")
            low = _item_value(rc.sub(0), bounds[0], kind, decimals, span)
            high = _item_value(rc.sub(1), bounds[1], kind, decimals, span)
            if low > high:
                rc.fail(f"low {bounds[0]} is above high {bounds[1]}")
        vc = c.sub("value")
        raw_value = spec.get("value")
        if raw_value is None and names is not None and number == AXIS_NAME_PARAM and is_axis:
            values = [ord(axis[0]) for axis in names]  # each axis's letter, as a control has it
            for v, axis in zip(values, names, strict=True):
                if not low <= v <= high:
                    c.sub("range").fail(f"{low}..{high} leaves out axis {axis}'s letter {v}")
        elif raw_value is None:  # 0, or the low end of the range (a real one's mantissa)
            values = [0 if low <= 0 <= high else low] * (n_axes if is_axis else 1)
        elif isinstance(raw_value, list):
            if not is_axis:
                vc.fail("a list of values needs axis = true")
            if len(raw_value) != n_axes:
                vc.fail(n_values(len(raw_value), n_axes))
            values = [
                _item_value(vc.sub(i), v, kind, decimals, (low, high))
                for i, v in enumerate(raw_value)
            ]
        else:
            values = [_item_value(vc, raw_value, kind, decimals, (low, high))] * (
                n_axes if is_axis else 1
            )
        known = KNOWN_DIAGS if names is None else KNOWN_PARAMS
        problem = param_type_problem(number, kind, is_axis, known)
        if problem:
            c.sub("type").fail(problem)
        if names is not None and number == AXIS_NAME_PARAM:
            for i, (v, axis) in enumerate(zip(values, names, strict=True)):
                wrong = axis_letter_problem(v, axis)
                if wrong:
                    (vc.sub(i) if isinstance(raw_value, list) else vc).fail(wrong)
        name = _str(c.sub("name"), spec.get("name", ""))
        items.append(DataItem(number, kind.width, is_axis, low, high, values, name, kind, decimals))
    return items


def _item_value(
    ctx: _Ctx, value: Any, kind: ParamKind, decimals: int, bounds: tuple[int, int]
) -> int:
    """A value of a parameter of ``kind`` as the machine holds it: a bit parameter's integer
    0..255 or its bits as text (:func:`_bits`); a real parameter's number (``12.345``,
    ``"12.345"``) as its mantissa with ``decimals`` decimals."""
    if kind is ParamKind.BIT and isinstance(value, str):
        value = _bits(ctx, value)
    if kind is ParamKind.REAL:
        if isinstance(value, bool) or not isinstance(value, str | int | float):
            ctx.fail(f"must be a number such as 12.345, got {_kind(value)}")
        if isinstance(value, float) and not math.isfinite(value):
            ctx.fail(f"must be a finite number, got {value}")
        if isinstance(value, str):
            try:  # as every front end reads number text: digits, a sign, a point
                number = decimal_number(value)
            except ValueError as exc:
                ctx.fail(f"must be a number such as 12.345: {exc}")
        else:
            number = Decimal(repr(value))
        scaled = number.scaleb(decimals)
        if scaled != scaled.to_integral_value():
            ctx.fail(f"{value} has more than {decimals} decimals (the item's decimals key)")
        mantissa = int(scaled)
        if not bounds[0] <= mantissa <= bounds[1]:
            low = Decimal(bounds[0]).scaleb(-decimals)
            high = Decimal(bounds[1]).scaleb(-decimals)
            ctx.fail(f"{value} is outside {low}..{high}")
        return mantissa
    return _int(ctx, value, bounds)


def _bits(ctx: _Ctx, text: str) -> int:
    """A bit parameter's value given as text: the eight bits #7..#0 (``"10110000"``), or a
    binary number with ``0b`` (``"0b1011"`` is 11), read as the command line and the page read
    them (:func:`focas_net._bits.bits_of_text`); ``_`` may separate digits. Other text,
    fewer than eight bits without ``0b`` (``"1011"``: #3..#0 or #7..#4?) among it, is refused
    with how to write it."""
    try:
        value = bits_of_text(text)
    except ValueError:
        value = None
    if value is None:
        ctx.fail(f"{bits_hint(text)} without quotes")
    return value


def _macro_pair(value: float) -> str:
    """How a value written as a float is written in a machine file (`` (1.5 is [15, 1])``),
    when a variable holds it; empty otherwise."""
    if not math.isfinite(value) or abs(value) >= 1e10:
        return ""
    shown = Decimal(repr(value)).normalize()
    exponent = shown.as_tuple().exponent
    assert isinstance(exponent, int)
    places = max(0, -exponent)
    mcr = int(shown.scaleb(places))
    if places > 9 or not _I32[0] <= mcr <= _I32[1]:
        return ""
    return f" ({value!r} is [{mcr}, {places}])"


#: The macro variables the machine computes, which no value of ``[macros]`` could set.
_COMPUTED: Final = {
    **{
        number: f"the {what}, parameter {PARTS_VARIABLES[number]}'s value: give it there"
        for number, what in ((3901, "parts count"), (3902, "total parts"))
    },
    **{
        number: f"the CNC's clock (the {what}): the machine keeps it, no file gives it"
        for number, what in zip(CLOCK_VARIABLES, ("date", "time"), strict=True)
    },
}


def _macros(ctx: _Ctx, value: Any) -> tuple[list[MacroRange], dict[int, Decimal]]:
    t = _table(ctx, value)
    _only(ctx, t, ("ranges", "values"))
    rc = ctx.sub("ranges")
    ranges: list[MacroRange] = []
    for i, raw in enumerate(_list(rc, t.get("ranges", []))):
        c = rc.sub(i)
        spec = _table(c, raw)
        _only(c, spec, ("first", "last", "writable"))
        for key in ("first", "last"):
            if key not in spec:
                c.sub(key).fail("missing")
        first = _int(c.sub("first"), spec["first"], NUMBERS)
        last = _int(c.sub("last"), spec["last"], NUMBERS)
        if first > last:
            c.fail(f"first {first} is above last {last}")
        for j, other in enumerate(ranges):
            if first <= other.last and other.first <= last:
                c.fail(f"overlaps {rc.key}[{j}] (#{other.first}..#{other.last})")
        ranges.append(MacroRange(first, last, _bool(c.sub("writable"), spec.get("writable", True))))
    vc = ctx.sub("values")
    values: dict[int, Decimal] = {}
    for key, raw in _table(vc, t.get("values", {})).items():
        c = vc.sub(key)
        number = _number_key(c, key, NUMBERS)
        if number in values:
            c.fail(f"#{number} is given twice")
        if not any(r.first <= number <= r.last for r in ranges):
            c.fail(f"#{number} is in no macro range" + ("" if ranges else " (ranges gives none)"))
        if number in _COMPUTED:  # read from the parts count or the clock, never from here
            c.fail(f"#{number} is {_COMPUTED[number]}")
        if isinstance(raw, float):
            c.fail(f"must be an integer or [mcr_val, dec_val]{_macro_pair(raw)}, got {raw!r}")
        if isinstance(raw, str):
            try:  # a number in quotes: its pair, as for a float
                pair = _macro_pair(float(decimal_number(raw)))
            except ValueError:
                pair = ""
            c.fail(f"must be an integer or [mcr_val, dec_val]{pair}, got {_kind(raw)}")
        if isinstance(raw, list):
            if len(raw) != 2:
                c.fail("must be an integer or [mcr_val, dec_val]")
            digits = _mcr_val(c.sub(0), raw[0])
            decimals = _int(c.sub(1), raw[1], (0, 9))
            values[number] = Decimal(f"{digits}E-{decimals}")
        else:
            values[number] = Decimal(_mcr_val(c, raw))
    return ranges, values


def _mcr_val(ctx: _Ctx, value: Any) -> int:
    """A macro value's digits (``mcr_val``): a 32-bit integer, one that is not refused in the
    words the machine, the clients and the command line give (:func:`macro_unfit`)."""
    low, high = _I32
    if isinstance(value, int) and not isinstance(value, bool) and not low <= value <= high:
        ctx.fail(macro_unfit(value))
    return _int(ctx, value, _I32)


def _pmc(ctx: _Ctx, value: Any) -> list[PmcAreaSpec]:
    t = _table(ctx, value)
    areas: list[PmcAreaSpec] = []
    for key, raw in t.items():
        c = ctx.sub(key)
        try:
            letter = pmc_letter(key)  # "r" is R, as everywhere an area is named
        except ValueError:
            c.fail(f"unknown PMC area (expected one of: {', '.join(PMC_AREAS)})")
        if any(area.letter == letter for area in areas):
            c.fail(f"area {letter} is given twice")
        spec = _table(c, raw)
        _only(c, spec, ("size", "write_protected", "values"))
        if "size" not in spec:
            c.sub("size").fail("missing")
        size = _int(c.sub("size"), spec["size"], (1, 65536))
        initial: dict[int, bytes] = {}
        vc = c.sub("values")
        for key, data in _table(vc, spec.get("values", {})).items():
            ac = vc.sub(key)
            address = _number_key(ac, key, (0, size - 1))
            if address in initial:
                ac.fail(f"address {address} is given twice")
            raw_bytes = (
                _bytes(ac, data) if isinstance(data, list) else bytes([_int(ac, data, (0, 255))])
            )
            if address + len(raw_bytes) > size:
                ac.fail(f"{len(raw_bytes)} bytes at {address} run past the {size}-byte area")
            initial[address] = raw_bytes
        areas.append(
            PmcAreaSpec(
                letter,
                size,
                _bool(c.sub("write_protected"), spec.get("write_protected", False)),
                initial,
            )
        )
    return areas


def _module(ctx: _Ctx, spec: dict[str, Any]) -> IOModuleRecord:
    if "module" in spec:
        _only(ctx, spec, ("rack", "slot", "module"))
        name = _str(ctx.sub("module"), spec["module"])
        if name.strip().upper() in _MODULES:  # case does not matter, as for control_class
            return _MODULES[name.strip().upper()]()
        ctx.sub("module").fail(
            f"unknown module {name!r} (built in: {', '.join(_MODULES)}; "
            "or describe the record with label, primary_id, ...)"
        )
    keys: tuple[str, ...] = ("rack", "slot", "label", "primary_id", "secondary_id")
    keys += ("references", "setup", "default_inputs", "default_outputs", "module_data")
    keys += ("input_segment_mode", "output_segment_mode")
    _only(ctx, spec, keys)
    for key in ("label", "primary_id"):
        if key not in spec:
            ctx.sub(key).fail("missing (or give module = a built-in model)")
    ids = []
    for key in ("primary_id", "secondary_id"):
        board = BoardId(_int(ctx.sub(key), spec.get(key, 0x8000), (0, 0xFFFF)))
        if not board.valid:
            ctx.sub(key).fail(f"0x{board.value:04X} is not a board id (bits 15-13 must be 100)")
        ids.append(board)
    refs = []
    rc = ctx.sub("references")
    for i, raw in enumerate(_list(rc, spec.get("references", []))):
        c = rc.sub(i)
        ref = _table(c, raw)
        _only(c, ref, ("type", "offset", "length"))
        for key in ("type", "offset", "length"):
            if key not in ref:
                c.sub(key).fail("missing")
        kind = _str(c.sub("type"), ref["type"])
        if kind.strip().upper() in _REF_TYPES:  # in either case, as the PMC's letters
            kind = kind.strip().upper()
        else:
            c.sub("type").fail(f"unknown reference type {kind!r} (expected I, Q, AI or AQ)")
        refs.append(
            (
                _REF_TYPES[kind],
                _int(c.sub("offset"), ref["offset"], (0, 0xFFFF)),
                _int(c.sub("length"), ref["length"], (1, 0xFFFF)),
            )
        )
    setup = _int(ctx.sub("setup"), spec.get("setup", 0), (0, 0xFFFF))
    record = IOModuleRecord.build(
        ids[0],
        ids[1],
        _ascii(ctx.sub("label"), spec["label"], 4),
        refs,
        setup=setup,
        default_inputs=_bytes(ctx.sub("default_inputs"), spec.get("default_inputs", [])),
        default_outputs=_bytes(ctx.sub("default_outputs"), spec.get("default_outputs", [])),
        module_data=_bytes(ctx.sub("module_data"), spec.get("module_data", [])),
        input_segment_mode=_int(
            ctx.sub("input_segment_mode"), spec.get("input_segment_mode", 0), (0, 0xFFFF)
        ),
        output_segment_mode=_int(
            ctx.sub("output_segment_mode"), spec.get("output_segment_mode", 0), (0, 0xFFFF)
        ),
    )
    try:
        encoded = record.encode()
    except ValueError as exc:
        key = "default_inputs" if setup & 1 else "setup"
        ctx.sub(key).fail(str(exc))
    if len(encoded) > 0xFFFF:
        ctx.fail("the record is too long")
    return record


def _station(ctx: _Ctx, value: Any) -> dict[tuple[int, int], IOModuleRecord]:
    station: dict[tuple[int, int], IOModuleRecord] = {}
    for i, raw in enumerate(_list(ctx, value)):
        c = ctx.sub(i)
        spec = _table(c, raw)
        for key in ("rack", "slot"):
            if key not in spec:
                c.sub(key).fail("missing")
        rack = _int(c.sub("rack"), spec["rack"], (0, MAX_RACK))
        slot = _int(c.sub("slot"), spec["slot"], (0, MAX_SLOT))
        if (rack, slot) in station:
            c.sub("slot").fail(f"rack {rack} slot {slot} is given twice")
        station[rack, slot] = _module(c, spec)
    return station


_MESSAGE_ADDRESS: Final = re.compile(r"A(\d{1,5})\.([0-7])", re.ASCII)


def _operator_messages(ctx: _Ctx, value: Any) -> list[ExternalMessage]:
    """``[[operator_messages]]``: ``address`` (``"A0.1"``), ``number`` (2000..2999) and
    ``text`` of each external operator message (the machine checks the rest)."""
    out = []
    for i, raw in enumerate(_list(ctx, value)):
        c = ctx.sub(i)
        spec = _table(c, raw)
        _only(c, spec, ("address", "number", "text"))
        for key in ("address", "number", "text"):
            if key not in spec:
                c.sub(key).fail("missing")
        address = _str(c.sub("address"), spec["address"]).strip().upper()
        match = _MESSAGE_ADDRESS.fullmatch(address)
        if match is None:
            c.sub("address").fail(f'{address!r} is not an A-area bit such as "A0.1"')
        number = _int(c.sub("number"), spec["number"], (2000, 2999))
        text = _str(c.sub("text"), spec["text"])
        problem = message_problem(text)
        if problem is not None:
            c.sub("text").fail(problem)
        out.append(ExternalMessage(int(match.group(1)), int(match.group(2)), number, text))
    return out


#: Largest number a ``[run]`` rate or time may be (events per hour, seconds: a year).
_MAX_RUN_NUMBER: Final = 31_536_000.0
#: The keys of ``[run]`` that are numbers of seconds or events per hour (>= 0).
_RUN_NUMBERS: Final = (
    "phase",
    "pause_rate",
    "pause_time",
    "tool_rate",
    "tool_time",
    "alarm_rate",
    "alarm_time",
)


def _run(ctx: _Ctx, value: Any) -> Scenario:
    """The ``[run]`` table: how the machine runs on its own when served."""
    t = _table(ctx, value)
    _only(ctx, t, ("parts", "seed", *_RUN_NUMBERS))
    given: dict[str, Any] = {}
    if "parts" in t:
        c = ctx.sub("parts")
        raw = t["parts"]
        if isinstance(raw, str):
            if raw.strip().lower() != "required":
                c.fail(f'must be a count >= 0 or "required", got {raw!r}')
            given["parts"] = "required"
        else:
            given["parts"] = _int(c, raw, (0, MAX_PARTS))
    if "seed" in t:
        given["seed"] = _int(ctx.sub("seed"), t["seed"], (0, MAX_SEED))
    for key in _RUN_NUMBERS:
        if key not in t:
            continue
        c = ctx.sub(key)
        raw = t[key]
        if isinstance(raw, bool) or not isinstance(raw, int | float):
            c.fail(f"must be a number, got {_kind(raw)}")
        if not math.isfinite(raw):
            c.fail(f"must be a finite number, got {raw}")
        if raw < 0 or raw > _MAX_RUN_NUMBER:
            c.fail(f"{raw} is outside 0..{_MAX_RUN_NUMBER:.0f}")
        given[key] = float(raw)
    return Scenario(**given)


_MACHINE_KEYS: Final = ("name", "axes", "param_password", "control", "read_only",
                        "history_capacity", "control_class", "state")  # fmt: skip
_TOP: Final = (
    "machine",
    "sysinfo",
    "panel",
    "parameters",
    "diagnostics",
    "macros",
    "pmc",
    "versamax",
    "motion",
    "program",
    "run",
    "path",
    "operator_messages",
    "tools",
)


def machine_from_dict(
    data: Mapping[str, Any],
    *,
    path: str = "<machine file>",
    clock: Clock = utc_now,
    param_password: str | None = None,
    control_enabled: bool | None = None,
    sim_clock: SimClock | None = None,
    base: Path | None = None,
) -> Machine:
    """Build a machine from the parsed TOML ``data``; ``path`` names it in error messages.

    ``param_password`` and ``control_enabled``, when given, override the file. ``sim_clock``
    drives its programs; ``base`` is the folder a program's ``file`` is relative to (None:
    the current folder)."""
    if not isinstance(data, Mapping):
        raise TypeError(f"a machine file's data must be a mapping (parsed TOML), got {data!r}")
    root = _Ctx(path, "")
    top = _table(root, dict(data))
    _only(root, top, _TOP)
    mc = root.sub("machine")
    if "machine" not in top:
        mc.fail("missing (the [machine] table with at least name and axes)")
    head = _table(mc, top["machine"])
    _only(mc, head, _MACHINE_KEYS)
    if "name" not in head:
        mc.sub("name").fail("missing")
    name = _str(mc.sub("name"), head["name"]).strip()
    if not name:
        mc.sub("name").fail("must not be empty")
    if "state" in head:
        folder = _str(mc.sub("state"), head["state"])
        if not folder.strip():
            mc.sub("state").fail("must not be empty (the folder of the machine's state file)")
        if "\x00" in folder:  # no file system takes it
            mc.sub("state").fail(f"{folder!r}: a folder name has no NUL character")
    problem = name_problem(name)  # the machine's own rule
    if problem is not None:
        mc.sub("name").fail(problem)
    paths = path_specs(root, top, base)
    if paths is None and "axes" not in head:
        mc.sub("axes").fail("missing (or give each path's in [[path]] tables)")
    axes = (
        _axes(mc.sub("axes"), head["axes"])
        if paths is None
        else [a for spec in paths for a in spec.axes]
    )
    password: str | None = None
    if "param_password" in head:
        password = _ascii(mc.sub("param_password"), head["param_password"])
        if not 1 <= len(password) <= 4:
            mc.sub("param_password").fail("must be 1..4 ASCII characters")
    if param_password is not None:
        password = param_password
    control = _bool(mc.sub("control"), head.get("control", True))
    if control_enabled is not None:
        control = control_enabled
    capacity = _int(
        mc.sub("history_capacity"),
        head.get("history_capacity", DEFAULT_HISTORY_CAPACITY),
        (1, MAX_HISTORY_CAPACITY),
    )
    ranges, values = _macros(root.sub("macros"), top.get("macros", {}))
    messages = _operator_messages(root.sub("operator_messages"), top.get("operator_messages", []))
    try:
        programs = _programs(root.sub("program"), top.get("program", []), base)
        machine = _build(
            root,
            top,
            name,
            axes,
            password,
            control,
            capacity,
            ranges,
            values,
            clock,
            programs=programs,
            sim_clock=sim_clock,
            paths=paths,
        )
    except MachineFileError:
        raise
    except ValueError as exc:  # a check of the machine itself that the file checks missed
        root.fail(str(exc))
    for i in range(len(messages)):  # the first entry the machine refuses, named by its index
        try:
            machine.set_external_messages(messages[: i + 1])
        except ValueError as exc:  # the machine's checks: the A area, a number or bit twice
            root.sub("operator_messages").sub(i).fail(str(exc))
    return machine


def _build(
    root: _Ctx,
    top: dict[str, Any],
    name: str,
    axes: list[str],
    password: str | None,
    control: bool,
    capacity: int,
    ranges: list[MacroRange],
    values: dict[int, Decimal],
    clock: Clock,
    *,
    programs: tuple[list[str], int | None] = ([], None),
    sim_clock: SimClock | None = None,
    paths: list[PathSpec] | None = None,
) -> Machine:
    n = len(axes)
    mc = root.sub("machine")
    head = top["machine"]
    alone = paths is None  # one path: its axes, panel, motion and programs are the machine's
    control_class = _control_class(mc.sub("control_class"), head)
    identity = _identity(root.sub("sysinfo"), top.get("sysinfo", {}), n, control_class)
    shapes = (
        [(kind_of(identity.mt_type), n)]
        if paths is None
        else [(spec.kind, len(spec.axes)) for spec in paths]
    )
    return Machine(
        name,
        axes=axes if alone else None,
        paths=paths,
        identity=identity,
        params=_items(root.sub("parameters"), top.get("parameters", {}), n, names=axes),
        diags=_items(root.sub("diagnostics"), top.get("diagnostics", {}), n),
        macro_ranges=ranges,
        macro_values=values,
        pmc=_pmc(root.sub("pmc"), top.get("pmc", {})),
        panel=_panel(root.sub("panel"), top.get("panel", {})) if alone else None,
        param_password=password,
        station=_station(root.sub("versamax"), top.get("versamax", [])),
        motion=_motion(root.sub("motion"), top.get("motion", {}), n) if alone else None,
        history_capacity=capacity,
        clock=clock,
        control_enabled=control,
        read_only=_bool(mc.sub("read_only"), head.get("read_only", False)),
        control_class=control_class,
        programs=programs[0],
        main_program=programs[1],
        sim_clock=sim_clock,
        scenario=_run(root.sub("run"), top["run"]) if "run" in top else None,
        tools=tool_specs(root.sub("tools"), top["tools"], shapes) if "tools" in top else None,
    )


def _control_class(ctx: _Ctx, head: dict[str, Any]) -> str:
    if "control_class" not in head:
        return DEFAULT_CONTROL_CLASS
    text = _str(ctx, head["control_class"])
    why = control_class_unfit(text)
    if why is not None:
        ctx.fail(why)
    return known_class(text)


def load_machine(
    path: str | PathLike[str],
    *,
    clock: Clock = utc_now,
    param_password: str | None = None,
    control_enabled: bool | None = None,
    sim_clock: SimClock | None = None,
) -> Machine:
    """Read the machine file at ``path`` (TOML). Raises :class:`MachineFileError`. A
    program's ``file`` is relative to the machine file's folder, an empty name or one with a
    NUL is refused as the command line refuses it; TypeError naming a ``path`` that is no
    ``str`` or path object."""
    if not isinstance(path, str | PathLike):
        raise TypeError(f"a machine file's path must be a str or a Path, got {path!r}")
    p = Path(path)
    name = str(path)
    why = file_name_unfit(name)
    if why is not None:
        raise MachineFileError("", "", why)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise MachineFileError(name, "", f"cannot read: {os_words(exc)}") from None
    return machine_from_dict(
        _toml(name, raw),
        path=name,
        clock=clock,
        param_password=param_password,
        control_enabled=control_enabled,
        sim_clock=sim_clock,
        base=p.parent,
    )


def _toml(name: str, raw: bytes) -> dict[str, Any]:
    """The machine file ``name`` of bytes ``raw`` as TOML, each float reading as typed; a
    MachineFileError for what is no UTF-8 or no TOML (with TOML's rule of a number's point
    where a part program's habit broke it)."""
    text = _text(name, raw)
    try:
        return tomllib.loads(text, parse_float=TomlFloat)
    except tomllib.TOMLDecodeError as exc:
        hint = toml_point_hint(text, str(exc))
        raise MachineFileError(name, "", f"not valid TOML: {exc}{hint}") from None


def state_folder(path: str | PathLike[str]) -> Path | None:
    """The folder ``[machine] state`` of the machine file at ``path`` names (relative to the
    machine file's folder), where ``serve`` keeps the machine's nonvolatile memory; None when
    it names none. MachineFileError as :func:`load_machine`."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise MachineFileError(str(path), "", f"cannot read: {os_words(exc)}") from None
    head = _toml(str(path), raw).get("machine")
    folder = head.get("state") if isinstance(head, dict) else None
    if not isinstance(folder, str) or not folder.strip():
        return None
    return p.parent / folder.strip()
