"""Pure formatting and parsing for the client commands of ``focas-net``.

Nothing here does I/O: the ODBST fields (labels and meanings from the one table of
:mod:`focas_net.protocol`, which the dashboard uses too), alarm codes (``PS0100``, the
protocol's ``alarm_code``), the ODBSYS identity, VersaMax records,
PMC hex dumps, column tables, and the parsers of the command-line forms (``1815.0``,
``100.3``, ``PS0100``, PMC data). Each function returns plain text or JSON-ready values so that
it can be tested on its own.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from datetime import datetime
from decimal import Decimal
from typing import Any, Final

from focas_net._typed import alarm_key_unfit, decimal_text, switch, typed_number, whole_number
from focas_net.errors import ChunkedWriteError, CncError, ew_info, ew_label
from focas_net.protocol import (
    STATUS_FIELDS,
    ActiveAlarm,
    AlarmHistoryEntry,
    AutMode,
    LabelledValue,
    ParamDataType,
    ParamValue,
    ProgramNumbers,
    StatusInfo,
    SysInfo,
    alarm_code,
    alarm_fields,
    alarm_text,
    alarm_time_text,
    alarm_type_of,
    cnc_type_label,
    ew_of_text,
    mt_type_label,
    status_labels,
)
from focas_net.protocol import field_label as field_name
from focas_net.versamax import BoardId, IOModuleRecord, RefType

__all__ = [
    "STATUS_FIELDS",
    "FieldValues",
    "address_text",
    "alarm_code",
    "alarm_dict",
    "bytes_summary",
    "decimal_text",
    "error_line",
    "ew_text",
    "field_name",
    "format_active_alarm",
    "format_history_entry",
    "hexdump",
    "history_dict",
    "macro_text",
    "module_dict",
    "module_lines",
    "mt_type_text",
    "one_line",
    "parse_alarm",
    "parse_alarm_filter",
    "parse_aut",
    "parse_bool",
    "parse_byte_list",
    "parse_ew",
    "parse_hex",
    "parse_int",
    "parse_number_bit",
    "positions_dict",
    "positions_rows",
    "program_dict",
    "program_rows",
    "render_table",
    "status_dict",
    "status_rows",
    "status_summary",
    "sysinfo_dict",
    "sysinfo_json",
    "sysinfo_rows",
    "utc_text",
]


#: An ODBST enumeration (``AutMode``, ...): its members carry a ``label`` and a ``meaning``.
FieldValues = type[LabelledValue]
_SUMMARY_FIELDS: Final = ("mode", "run", "motion", "mstb", "emergency", "alarm", "edit")


def status_summary(status: StatusInfo) -> str:
    """One line: ``mode=MEM run=STRT motion=MTN mstb=*** emergency=**** alarm=ALM edit=****``
    (the keys of :data:`STATUS_FIELDS`)."""
    labels = {f: label for f, _, label, _ in status_labels(status)}
    return " ".join(f"{f}={labels[f]}" for f in _SUMMARY_FIELDS)


def status_rows(status: StatusInfo, mt_type: str | None) -> list[tuple[str, str, str, str]]:
    """``(field, value, name, meaning)`` for every ODBST field; ``tmmode`` named by the
    machine's ``mt_type`` (ODBSYS; None when not known), as every front end names it."""
    return [(f, str(v), name, meaning) for f, v, name, meaning in status_labels(status, mt_type)]


def status_dict(status: StatusInfo, mt_type: str | None) -> dict[str, dict[str, Any]]:
    """``{field: {"value": n, "name": ..., "meaning": ...}}`` for every ODBST field (``mt_type``
    as for :func:`status_rows`)."""
    return {
        f: {"value": v, "name": name, "meaning": meaning}
        for f, v, name, meaning in status_labels(status, mt_type)
    }


# -- ODBSYS --------------------------------------------------------------------------------


def _ascii(raw: bytes) -> str:
    return raw.decode("latin-1").strip(" \x00")


def mt_type_text(info: SysInfo) -> str:
    """ODBSYS ``mt_type`` as text (``"M"``): what names a status's ``tmmode``."""
    return _ascii(info.mt_type)


def sysinfo_dict(info: SysInfo) -> dict[str, Any]:
    """The ODBSYS fields as text and numbers."""
    return {
        "addinfo": info.addinfo,
        "max_axis": info.max_axis,
        "cnc_type": _ascii(info.cnc_type),
        "mt_type": mt_type_text(info),
        "series": _ascii(info.series),
        "version": _ascii(info.version),
        "axes": _ascii(info.axes),
        "axes_count": info.axes_count,
    }


def sysinfo_json(info: SysInfo) -> dict[str, Any]:
    """``sysinfo --json``: the ODBSYS fields as text and numbers; the two coded fields,
    ``cnc_type`` and ``mt_type``, as ``{"value": ..., "meaning": ...}`` like the ODBST fields
    of ``status --json``."""
    data = sysinfo_dict(info)
    data["cnc_type"] = {"value": data["cnc_type"], "meaning": cnc_type_label(data["cnc_type"])}
    data["mt_type"] = {"value": data["mt_type"], "meaning": mt_type_label(data["mt_type"])}
    return data


def sysinfo_rows(info: SysInfo) -> list[tuple[str, str, str]]:
    """``(field, value, meaning)`` rows of ODBSYS."""
    d = sysinfo_dict(info)
    axes = d["axes_count"]
    return [
        ("cnc_type", d["cnc_type"], cnc_type_label(d["cnc_type"])),
        ("mt_type", d["mt_type"], mt_type_label(d["mt_type"])),
        ("series", d["series"], "software series"),
        ("version", d["version"], "software version"),
        ("axes", d["axes"], f"{axes} controlled axes" if axes is not None else ""),
        ("max_axis", str(d["max_axis"]), "maximum controlled axes"),
        ("addinfo", str(d["addinfo"]), "additional information bits"),
    ]


# -- program numbers, feed, spindle, positions -------------------------------------------------


def _o_number(number: int) -> str:
    return f"O{number:04d}" if number else "none"


def program_dict(numbers: ProgramNumbers, feed: int, spindle_speed: int) -> dict[str, Any]:
    """Program numbers, actual feed and spindle speed as JSON-ready values."""
    return {
        "program_running": numbers.running,
        "program_main": numbers.main,
        "feed": feed,
        "spindle_speed": spindle_speed,
    }


def program_rows(data: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """``(item, value, meaning)`` rows of :func:`program_dict`."""
    return [
        ("running", _o_number(data["program_running"]), "program being executed (cnc_rdprgnum)"),
        ("main", _o_number(data["program_main"]), "main program (cnc_rdprgnum)"),
        ("feed", str(data["feed"]), "actual feed rate (cnc_actf)"),
        ("spindle", str(data["spindle_speed"]), "actual spindle speed, min^-1 (cnc_acts)"),
    ]


def positions_dict(
    kind: str, decimals: int, values: Mapping[str, Decimal], increments: Mapping[str, int]
) -> dict[str, Any]:
    """A position read as JSON-ready values (positions as decimal strings)."""
    return {
        "kind": kind,
        "decimals": decimals,
        "axes": [
            {"name": name, "position": str(value), "increments": increments[name]}
            for name, value in values.items()
        ],
    }


def positions_rows(data: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """``(axis, position, increments)`` rows of :func:`positions_dict`."""
    return [(a["name"], a["position"], str(a["increments"])) for a in data["axes"]]


# -- alarms --------------------------------------------------------------------------------


def utc_text(when: datetime) -> str:
    """``2024-05-01T12:00:00Z``, as every front end writes an alarm's time."""
    return alarm_time_text(when)


def format_active_alarm(alarm: ActiveAlarm) -> str:
    """``PS0100 PARAMETER WRITE ENABLE`` (with `` (axis n)`` for an axis alarm)."""
    return alarm_text(alarm.alm_type, alarm.alm_no, alarm.msg, alarm.axis_no)


def format_history_entry(entry: AlarmHistoryEntry) -> str:
    """``2024-05-01T12:00:00Z PS0100 PARAMETER WRITE ENABLE``."""
    text = alarm_text(entry.alm_type, entry.alm_no, entry.msg, entry.axis_no)
    return f"{utc_text(entry.occurred_at)} {text}"


def alarm_dict(alarm: ActiveAlarm) -> dict[str, Any]:
    return alarm_fields(alarm.axis_no, alarm.alm_type, alarm.alm_no, alarm.msg)


def history_dict(entry: AlarmHistoryEntry) -> dict[str, Any]:
    fields = alarm_fields(entry.axis_no, entry.alm_type, entry.alm_no, entry.msg)
    return {"occurred_at": utc_text(entry.occurred_at), **fields}


#: ``PS0100``: ASCII letters and digits only, as every number is typed (a digit of another
#: script is refused); the number's range is the codec's to say (``0..32767``).
_ALARM_RE: Final = re.compile(r"^([A-Za-z]{2})([0-9]+)$", re.ASCII)
#: ``3:100``, or ``T31:0005`` as a type with no name is printed (``alarm_code``).
_ALARM_NUMERIC_RE: Final = re.compile(r"^[Tt]?([0-9]{1,2}):([0-9]+)$", re.ASCII)


def _alarm_type(prefix: str) -> int:
    return alarm_type_of(prefix)  # the words of every front end


def parse_alarm(text: str) -> tuple[int, int]:
    """``"PS0100"`` -> ``(3, 100)``; ``"3:100"`` (type number, alarm number) also works, and
    ``"T31:0005"``, the code of a type with no name as it is printed."""
    s = text.strip()
    m = _ALARM_RE.match(s) or _ALARM_NUMERIC_RE.match(s)
    if m is None:
        raise ValueError(f"not an alarm code: {text!r} (expected e.g. PS0100, 3:100 or T31:0005)")
    # a code names an alarm: its type and number are one an alarm has (0..31, 0..32767; -1,
    # any, is a filter argument's alone), in the words of every front end
    key = (_alarm_type(m[1]) if m[1].isalpha() else int(m[1]), whole_number(m[2]))
    why = alarm_key_unfit(*key)
    if why is not None:
        raise ValueError(why)
    return key


def parse_alarm_filter(text: str | None) -> tuple[int, int]:
    """Filter of ``sim clear``: None -> every alarm ``(-1, -1)``; ``"PS"`` -> every PS alarm
    ``(3, -1)``, as its number ``"3"`` (the refusal of a type names 0..31) and a type of no
    name as it is printed, ``"T31"``; ``"PS0100"`` -> ``(3, 100)``."""
    if text is None:
        return (-1, -1)
    s = text.strip()
    if s.isalpha() and len(s) == 2:
        return (_alarm_type(s), -1)
    number = _TYPE_NUMBER_RE.match(s)
    if number is not None:
        alm_type = whole_number(number[1])
        why = alarm_key_unfit(alm_type, 0)
        if why is not None:
            raise ValueError(why)
        return (alm_type, -1)
    return parse_alarm(text)  # (its refusal shows the text as typed, spaces too)


#: A whole alarm type by its number, ``3``, or as a type of no name is printed, ``T31``.
_TYPE_NUMBER_RE: Final = re.compile(r"^[Tt]?([0-9]+)$", re.ASCII)


# -- VersaMax ------------------------------------------------------------------------------

_REF_NAMES: Final[dict[int, str]] = {
    RefType.I: "%I",
    RefType.Q: "%Q",
    RefType.AI: "%AI",
    RefType.AQ: "%AQ",
}


def _board_dict(board: BoardId) -> dict[str, Any]:
    return {
        "id": f"0x{board.value:04X}",
        "valid": board.valid,
        "module_type": board.module_type.name,
        "inputs": board.inputs,
        "outputs": board.outputs,
    }


def module_dict(rack: int, slot: int, record: IOModuleRecord) -> dict[str, Any]:
    """A VersaMax module record as JSON-ready values."""
    return {
        "rack": rack,
        "slot": slot,
        "label": record.label,
        "primary_id": _board_dict(record.primary_id),
        "secondary_id": _board_dict(record.secondary_id),
        "inputs": record.inputs,
        "outputs": record.outputs,
        "setup": record.setup,
        "defaults_defined": bool(record.setup & 1),
        "fault_reporting": bool(record.setup & 2),
        "references": [
            {
                "sequence": r.sequence,
                "type": _REF_NAMES.get(r.ref_type, str(r.ref_type)),
                "offset": r.offset,
                "bytes": r.byte_length,
                "defaults_offset": r.defaults_offset,
            }
            for r in record.references
        ],
        "input_segment_mode": record.input_segment_mode,
        "output_segment_mode": record.output_segment_mode,
        "default_inputs": record.default_inputs.hex(),
        "default_outputs": record.default_outputs.hex(),
        "module_data": record.module_data.hex(),
    }


def _board_text(board: BoardId) -> str:
    kind = board.module_type.name.lower().replace("_", " ")
    return f"0x{board.value:04X} ({kind}, {board.inputs} in, {board.outputs} out)"


def module_lines(rack: int, slot: int, record: IOModuleRecord) -> list[str]:
    """Readable lines describing a VersaMax module record."""
    flags = [
        "defaults defined" if record.setup & 1 else "no defaults",
        "fault reporting on" if record.setup & 2 else "fault reporting off",
    ]
    lines = [
        f"rack {rack} slot {slot}: {record.label}, {record.inputs} inputs, "
        f"{record.outputs} outputs",
        render_table(
            ("field", "value"),
            [
                ("primary board", _board_text(record.primary_id)),
                ("secondary board", _board_text(record.secondary_id)),
                ("setup", f"0x{record.setup:04X} ({', '.join(flags)})"),
                (
                    "segment modes",
                    f"in {record.input_segment_mode}, out {record.output_segment_mode}",
                ),
                ("default inputs", record.default_inputs.hex(" ") or "-"),
                ("default outputs", record.default_outputs.hex(" ") or "-"),
                ("module data", record.module_data.hex(" ") or "-"),
            ],
        ),
    ]
    if record.references:
        lines.append(
            render_table(
                ("seq", "ref", "offset", "bytes", "defaults at"),
                [
                    (
                        str(r.sequence),
                        _REF_NAMES.get(r.ref_type, str(r.ref_type)),
                        str(r.offset),
                        str(r.byte_length),
                        str(r.defaults_offset),
                    )
                    for r in record.references
                ],
            )
        )
    return lines


# -- tables and dumps ----------------------------------------------------------------------


def render_table(headers: Sequence[str] | None, rows: Iterable[Sequence[str]]) -> str:
    """Left-aligned columns separated by two spaces; no trailing blanks."""
    body = [list(map(str, r)) for r in rows]
    all_rows = ([list(headers)] if headers else []) + body
    if not all_rows:
        return ""
    ncols = max(len(r) for r in all_rows)
    widths = [max((len(r[i]) for r in all_rows if i < len(r)), default=0) for i in range(ncols)]
    lines = []
    for r in all_rows:
        cells = [c.ljust(widths[i]) for i, c in enumerate(r)]
        lines.append("  ".join(cells).rstrip())
    return "\n".join(lines)


#: Most bytes a one-line summary shows (``pmc write``).
SUMMARY_BYTES: Final = 16


def bytes_summary(data: bytes, limit: int = SUMMARY_BYTES) -> str:
    """``01 02 03`` for a few bytes; the first ``limit`` then ``... (8000 bytes)`` for more."""
    if len(data) <= limit:
        return data.hex(" ")
    return f"{data[:limit].hex(' ')} ... ({len(data)} bytes)"


def hexdump(area: str, start: int, data: bytes, per_line: int = 16) -> str:
    """``R0100  01 02 03 ...`` lines, ``per_line`` bytes each, addressed by their first byte."""
    width = max(4, len(str(start + max(len(data) - 1, 0))))
    lines = []
    for off in range(0, len(data), per_line):
        chunk = data[off : off + per_line]
        lines.append(f"{area}{start + off:0{width}d}  {chunk.hex(' ')}")
    return "\n".join(lines)


# -- parameters ----------------------------------------------------------------------------

#: The IODBPSD width of a real parameter (REALPRM).
REAL_WIDTH: Final = 8


#: A parameter's type told by its value's width alone (a 1-byte value is a bit or a byte one).
_TYPE_OF_WIDTH: Final = {
    2: ParamDataType.WORD,
    4: ParamDataType.TWO_WORD,
    REAL_WIDTH: ParamDataType.REAL,
}


def param_type(pv: ParamValue, kind: ParamDataType | None = None) -> ParamDataType | None:
    """The type of ``pv``: ``kind`` as the CNC told it, else what its width tells (None for a
    1-byte value of a CNC that did not tell)."""
    return kind if kind is not None else _TYPE_OF_WIDTH.get(pv.width)


def param_text(pv: ParamValue, kind: ParamDataType | None = None) -> str:
    """A parameter value as the CNC screen would show it, named by its type as every front end
    names it (:attr:`ParamDataType.label`): a bit parameter as unsigned and as its bits #7..#0
    (``176 (10110000), bit parameter``), a real parameter with its decimals (``12.345 (real, 3
    decimals)``), the others signed with their hex (and a byte's bits): ``24000 (0x00005DC0),
    two-word parameter``."""
    if pv.width == REAL_WIDTH:
        return f"{decimal_text(pv.real)} (real, {pv.decimals} decimal{'s' * (pv.decimals != 1)})"
    kind = param_type(pv, kind)
    if kind is ParamDataType.BIT and pv.width == 1:
        return f"{pv.bits} ({pv.bits:08b}), bit parameter"
    width = pv.width
    text = f"{pv.value} (0x{pv.bits:0{2 * width}X}"
    if width == 1:
        text += f", 0b{pv.bits:08b}"
    return f"{text}), " + ("1 byte" if kind is None else f"{kind.label} parameter")


def param_dict(
    number: int, axis: int, pv: ParamValue, kind: ParamDataType | None = None
) -> dict[str, Any]:
    """The JSON data of a parameter value: ``value`` unsigned for a bit parameter (with its
    ``bits``), a decimal string for a real one (with its ``decimals``); ``type`` when known
    (:func:`param_type`)."""
    data: dict[str, Any] = {"number": number, "axis": axis, "value": pv.value, "width": pv.width}
    kind = param_type(pv, kind)
    if kind is not None:
        data["type"] = kind.label
    if pv.width == REAL_WIDTH:
        data["value"] = decimal_text(pv.real)
        data["decimals"] = pv.decimals
    elif kind is ParamDataType.BIT:
        data["value"] = pv.bits
        data["bits"] = f"{pv.bits:08b}"
    return data


# -- parsers -------------------------------------------------------------------------------


def parse_param_value(text: str) -> int | Decimal | str:
    """A parameter value typed on the command line: an integer (decimal, ``0x`` hex, ``0b``
    bits #7 first, ``0o`` octal) or, for a real parameter, a decimal number (``12.345``), read
    as every front end reads number text (:func:`focas_net._typed.typed_number`: no exponent).
    Plain digits stay text: the client reads them by the parameter's type (on a bit parameter
    ``00000011`` is its eight bits, ``0000_0011`` too)."""
    stripped = text.strip()
    if stripped.replace("_", "").isdecimal() and stripped.isascii():
        return stripped
    return typed_number(text)


def parse_int(text: str) -> int:
    """A decimal, ``0x`` hex, ``0b`` binary or ``0o`` octal integer, in ASCII digits, as every
    front end reads a whole number (:func:`focas_net._typed.whole_number`: no exponent, no
    digits of other scripts)."""
    return whole_number(text)


def parse_number_bit(
    text: str, expected: str = "NUMBER or NUMBER.BIT (e.g. 1815 or 1815.0)"
) -> tuple[int, int | None]:
    """``"1815"`` -> ``(1815, None)``; ``"1815.0"`` -> ``(1815, 0)``; ``expected`` names the
    argument as its command's help does. The number is read as every whole number is
    (:func:`parse_int`: ``0x717`` too, as ``diag 0x12c`` and ``pmc read R 0x10`` read theirs;
    a negative one is the client's range check to refuse, in its words)."""
    s = text.strip()
    number, dot, bit = s.partition(".")
    try:
        value = parse_int(number)
    except ValueError as exc:
        # the rule's own reason where it has one (nothing typed, too many digits, a digit
        # beyond ASCII), after the form the argument takes
        why = str(exc)
        rest = why.removeprefix(f"not a whole number: {number!r}")
        detail = f" ({why})" if rest == why else rest
        if dot and not number.strip():  # ``.4``: something was typed, only the number not
            detail = " (no number before the dot)"
        raise ValueError(f"expected {expected}, got {text!r}{detail}") from None
    # a sign is part of a number (``1.-1`` is bit -1, refused by the range every front end
    # words: ``R1.-1: bit -1 is outside 0..7``); anything else is no bit number
    digits = bit.removeprefix("-").removeprefix("+") if bit[:1] in "+-" else bit
    if dot and not (digits.isascii() and digits.isdigit()):
        raise ValueError(
            f"{text!r}: the bit after the dot must be a bit number (0..7 of a byte), got {bit!r}"
        )
    return value, (int(bit) if dot else None)


def parse_bool(text: str) -> bool:
    """``1/on/true/yes/set`` or ``0/off/false/no/clear`` (:func:`focas_net._typed.switch`,
    which the page reads too)."""
    return switch(text)


def parse_hex(text: str) -> bytes:
    """``"01ff"``, ``"01 ff"``, ``"0x01ff"`` or ``"01:ff"`` -> bytes."""
    s = text.strip()
    if s[:2].lower() == "0x":
        s = s[2:]
    # a separator parts whole bytes: "0 1" is no byte 01, nor "1:2" a byte 12
    groups = [g for g in re.split(r"[\s:_-]", s) if g]
    if len(groups) > 1 and any(len(g) % 2 for g in groups):
        raise ValueError(
            f"not hex bytes: {text!r} (write each byte as two digits between separators, "
            "e.g. 00 01)"
        )
    try:
        data = bytes.fromhex("".join(groups))
    except ValueError:
        raise ValueError(f"not hex bytes: {text!r}") from None
    if not data:
        raise ValueError("no data bytes given")
    return data


def parse_byte_list(items: Iterable[str]) -> bytes:
    """Byte values given as numbers (``1 2 0xff``, also comma separated) -> bytes; an empty
    item of a comma list (``1,,2``, ``1,``) is refused, naming it."""
    values: list[int] = []
    for item in items:
        pieces = item.split(",")
        if len(pieces) > 1:
            for i, piece in enumerate(pieces, 1):
                if not piece.strip():
                    raise ValueError(
                        f"empty item {i} in the byte list {item!r}: give a byte value "
                        "between each two commas"
                    )
        for part in item.replace(",", " ").split():
            v = parse_int(part)
            if not 0 <= v <= 255:
                raise ValueError(f"byte value {part!r} outside 0..255")
            values.append(v)
    if not values:
        raise ValueError("no data bytes given")
    return bytes(values)


def parse_aut(text: str) -> AutMode:
    """A mode by FOCAS name (``MDI``, ``mdi``, ``MEM``, ``EDIT``, ...) or ``aut`` number, as
    every front end reads it (:meth:`AutMode.parse_panel`); 2 (``****``, no selection) is not
    a mode."""
    return AutMode.parse_panel(text)


def parse_ew(text: str) -> int:
    """An EW code by number or name (``17``, ``EW_PASSWD``, ``passwd``, ``-1``), as every
    front end reads one."""
    return ew_of_text(text)


# -- errors --------------------------------------------------------------------------------


def ew_text(ew: int) -> str:
    """``EW_BUSY (-1)``: an EW code's name and number (``EW_UNKNOWN(12345)``: the number
    once)."""
    return ew_label(ew)


def address_text(host: str, port: int) -> str:
    """``HOST:PORT``; an IPv6 address in brackets, ``[::1]:8193``."""
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def error_line(exc: BaseException) -> str:
    """The one-line text of a failure (without the ``focas-net:`` prefix).

    A CNC error reads ``EW_PASSWD (17): protection / password error (cnc_wrparam)``.
    """
    if isinstance(exc, CncError):
        info = ew_info(exc.ew)
        text = f"{ew_label(exc.ew)}: {info.meaning}"
        if exc.detail:
            text += f" ({exc.detail})"
    elif isinstance(exc, ChunkedWriteError):
        text = str(exc)
    else:
        text = str(exc) or type(exc).__name__
    return one_line(text)


#: A line break with the spaces around it.
_LINE_BREAK: Final = re.compile(r"[ \t]*[\r\n]\s*")


def one_line(text: str) -> str:
    """``text`` on one line: each line break, with the spaces around it, one space; spaces
    within a line (a value's own, as typed) kept."""
    return _LINE_BREAK.sub(" ", text.strip())


def macro_text(value: Decimal | None) -> str:
    """A macro value as the CNC shows it (:func:`decimal_text`); a vacant variable is
    ``<vacant>``."""
    return "<vacant>" if value is None else decimal_text(value)
