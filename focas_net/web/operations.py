"""What the dashboard's buttons do: each page action is one machine operation (pure).

Every write goes through the :class:`~focas_net.sim.Machine` operation a protocol calls, with
its checks and their order: a parameter write with PWE off is refused with ``EW_PASSWD`` here
as on the wire. A refusal raises the machine's :class:`~focas_net.sim.MachineError` (its
``ew``, named with :func:`focas_net.errors.ew_name`, is what the page shows). An argument the
page cannot send in the operation's terms (a missing field, text where a number belongs)
raises :class:`ActionError`, whose message names the field and the value given.

The page is the operator at the machine: the simulator's own controls (the cycle, the panel,
alarms, PMC X and F, fault injection) work whatever ``control_enabled`` says (that flag is
about FOCAS clients); a read-only dashboard (``read_only``) or machine refuses every write with
``EW_PROT``. PMC bits of areas other than X and F are written as ``pmc_wrpmcrng`` writes
them, so a write-protected area answers ``EW_PROT``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from decimal import Decimal
from typing import Any, Final, TypeVar

from focas_net._bits import bits_of_text
from focas_net._refusals import no_item
from focas_net._typed import (
    MAX_DIGITS,
    NO_PASSWORD_NOTE,
    PROGRAM_NUMBERS,
    decimal_number,
    field_unfit,
    item_axis_unfit,
    item_number_unfit,
    lead_as_typed,
    macro_number,
    macro_to_wire,
    param_decimals_refused,
    param_value_unfit,
    program_number,
    rapid_step,
    switch_value,
    typed_number,
    typed_numbers,
    whole_number,
)
from focas_net._typed import typed_shown as shown
from focas_net.errors import EW, ew_name
from focas_net.protocol import (
    ALARM_TYPES,
    AutMode,
    CycleAction,
    FaultKind,
    FaultScope,
    InjectFault,
    alarm_active_already,
    alarm_filter_text,
    alarm_message,
    alarm_type_of,
    cycle_action_of,
    ew_of_text,
    fault_arg_needed,
    fault_kind_of,
    nothing_cleared,
    pmc_bit_refusal,
)
from focas_net.server.faults import FaultQueue, fault_refusal, no_faults_cleared, parse_inject
from focas_net.sim import MAX_PATHS, Machine, MachineError, ParamKind, Session

from .view import JsonDict, PathTrail, macro_value, param_data

__all__ = [
    "ACTIONS",
    "ACTION_KEYS",
    "FORCED_PMC_AREAS",
    "ActionError",
    "Station",
    "action_args",
    "decimal_number",
    "no_twice",
    "path_unfit",
    "perform",
    "refusal",
    "shown",
    "whole_number",
]

#: PMC areas the page writes as the simulator (0x0E04 set_pmc), ignoring write protection.
FORCED_PMC_AREAS: Final = frozenset({"X", "F"})


class ActionError(ValueError):
    """A page action with an argument it cannot carry out (the message names it)."""


@dataclass(eq=False)
class Station:
    """One machine as the dashboard sees it: its index in the fleet, its port, its
    machine-wide fault queue, the page's own session (the parameter-write unlock) and the
    tool path seen so far."""

    index: int
    machine: Machine
    faults: FaultQueue = field(default_factory=FaultQueue)
    port: int = 0
    session: Session = field(init=False)
    trail: PathTrail = field(default_factory=PathTrail)
    _trails: dict[int, PathTrail] = field(default_factory=dict, init=False, repr=False)
    _macro_numbers: tuple[int, ...] | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        self.session = self.machine.new_session()

    def trail_of(self, path: int = 1) -> PathTrail:
        """The tool path seen of ``path`` (:attr:`trail` for path 1)."""
        if path == 1:
            return self.trail
        return self._trails.setdefault(path, PathTrail())

    def record_trails(self) -> None:
        """Add every path's current absolute position to its tool path."""
        machine = self.machine
        for path in range(1, machine.path_count + 1):
            self.trail_of(path).record(machine.path_motion(path=path).absolute)

    def macro_numbers(self) -> tuple[int, ...]:
        """Every macro variable number the machine has (found once, then kept)."""
        if self._macro_numbers is None:
            writable = self.machine.macro_writable
            self._macro_numbers = tuple(
                n for n in range(-0x8000, 0x8000) if writable(n) is not None
            )
        return self._macro_numbers

    def fault_listing(self) -> list[tuple[str, int, int]]:
        """The machine-wide armed faults as ``(kind name, answers left, arg)``."""
        return [(FaultKind(f.kind).name, f.remaining, f.arg) for f in self.faults.listing().faults]


def refusal(exc: MachineError) -> JsonDict:
    """What the page is told of a refused operation: code, EW name, detail."""
    return {"ok": False, "ew": exc.ew, "ew_name": ew_name(exc.ew), "error": exc.detail or str(exc)}


# -- arguments ------------------------------------------------------------------------------
def _int(args: Mapping[str, Any], key: str, default: int | None = None) -> int:
    """``args[key]`` as a whole number (decimal, ``0x``, ``0b`` or ``0o``, ASCII digits only:
    :func:`~focas_net._typed.whole_number`, as every front end reads it); ``default`` when it
    is not given, but a field sent empty is refused like a field that is not a number."""
    value = args.get(key)
    if value is None and default is not None:
        return default
    if value is None or (isinstance(value, str) and not value.strip()):
        raise ActionError(f"{key}: a number is needed")
    if isinstance(value, bool):
        raise ActionError(f"{key}: a number is needed, got {shown(value)}")
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        try:
            return whole_number(value)
        except ValueError as exc:
            raise ActionError(f"{key}: {exc}") from None
    raise ActionError(f"{key}: not a whole number: {shown(value)}")


def _optional_int(args: Mapping[str, Any], key: str) -> int | None:
    value = args.get(key)
    if value is None or value == "":
        return None
    return _int(args, key)


_T = TypeVar("_T")


def _read_as(
    args: Mapping[str, Any],
    key: str,
    parse: Callable[[str], int],
    fallback: Callable[[Mapping[str, Any], str], _T],
) -> int | _T:
    """``args[key]`` typed as text, read by ``parse`` as the command line reads the option
    (:func:`~focas_net._typed.rapid_step` for ``F0``, :func:`~focas_net.protocol.ew_of_text`
    for ``EW_BUSY``), its refusal naming ``key``; anything else (a JSON number, nothing, empty
    text) as ``fallback(args, key)`` reads it (:func:`_int`: needed; :func:`_optional_int`:
    None when not given)."""
    value = args.get(key)
    if isinstance(value, str) and value.strip():
        try:
            return parse(value)
        except ValueError as exc:
            raise ActionError(f"{key}: {exc}") from None
    return fallback(args, key)


def _text(args: Mapping[str, Any], key: str, default: str = "", *, needed: str = "") -> str:
    """``args[key]`` as text (``default`` when not given); with ``needed`` (what the key
    names: ``start, hold or reset``), a key not given (or ``null``) is refused saying so,
    rather than as the empty text no one typed."""
    value = args.get(key, default)
    if needed and args.get(key) is None:
        raise ActionError(f"{key}: {needed} is needed")
    if not isinstance(value, str):
        raise ActionError(f"{key}: text is needed, got {shown(value)}")
    return value


def _named(args: Mapping[str, Any], key: str, needed: str, read: Callable[[object], _T]) -> _T:
    """``args[key]`` read by ``read`` as the command line reads the word typed (a cycle's
    action, a fault's kind), which names what it refuses, a JSON value that is no text too
    (``unknown cycle action 1``); a key not given (or ``null``) is refused saying what is
    ``needed``."""
    value = args.get(key)
    if value is None:
        raise ActionError(f"{key}: {needed} is needed")
    try:
        return read(value)
    except ValueError as exc:
        raise ActionError(f"{key}: {exc}") from None


def _decimal(args: Mapping[str, Any], key: str) -> Decimal | None:
    """``args[key]`` as a number: decimal text (``12.345``) or a whole number written as the
    command line writes it (``0xB0``, ``0b10110000``), read by
    :func:`~focas_net._typed.typed_number` as every front end reads it; None when empty."""
    value = args.get(key)
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    if isinstance(value, float):  # a JSON number with a point: the digits it shows
        if not math.isfinite(value):
            raise ActionError(f"{key}: a finite number is needed, got {shown(value)}")
        return Decimal(repr(value))
    if isinstance(value, bool) or not isinstance(value, str | int):
        raise ActionError(f"{key}: a number is needed, got {shown(value)}")
    if isinstance(value, int):
        return Decimal(value)
    try:
        return Decimal(typed_number(value))
    except ValueError as exc:
        raise ActionError(f"{key}: {exc}") from None


# -- the actions ----------------------------------------------------------------------------
_Action = Callable[[Station, Mapping[str, Any]], JsonDict]


def path_unfit(path: int) -> str | None:
    """Why ``path`` is no path a CNC has (outside 1..10), in the words the command line's
    ``--path`` and the clients give (``path 0 is outside 1..10``); None when it may be one
    (whether the machine has it is the machine's to say, with EW_PATH)."""
    return field_unfit("path", path, 1, MAX_PATHS)


def _path(args: Mapping[str, Any]) -> int:
    """The path an action is for: ``path`` (1 when not given), refused as :func:`path_unfit`
    words it; the machine refuses one it has not (EW_PATH, naming it)."""
    path = _int(args, "path", 1)
    why = path_unfit(path)
    if why is not None:
        raise ActionError(f"path: {why}")
    return path


def _cycle(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    # as `sim cycle ACTION` reads it: Start, " reset "
    what = _named(args, "action", "start, hold or reset", cycle_action_of)
    path = _path(args)
    if what is CycleAction.START:
        m.cycle_start(path=path)
    elif what is CycleAction.HOLD:
        m.feed_hold(path=path)
    else:
        m.reset(path=path)
    return {}


def _mode(args: Mapping[str, Any]) -> int | None:
    """``mode`` as the command line takes it: text (a name, ``MDI``, ``mdi``, ``EDIT``, or an
    ``aut`` number, ``1``) read by :meth:`AutMode.parse_panel` as ``--mode`` reads it, or a
    JSON number, the ``aut`` value as the wire carries it (the machine refuses one that is
    not a mode, with EW_DATA); None (the mode left as it is) when not given or ``null``."""
    value = args.get("mode")
    if not isinstance(value, str):
        return _optional_int(args, "mode")
    try:  # text of no mode (spaces, nothing) is refused, as `--mode ''` is: no panel has it
        return int(AutMode.parse_panel(value))
    except ValueError as exc:
        raise ActionError(f"mode: {exc}") from None


def _switch(args: Mapping[str, Any], key: str) -> int | None:
    """A switch (PWE, the emergency stop, a PMC bit) as the command line takes it: text read
    by :func:`~focas_net._typed.switch` as ``--pwe`` reads it (``1``/``0``, ``on``/``off`` and
    its other words), a JSON ``true``/``false``, or a JSON number 0 or 1, the value as the
    wire carries it; another (``2``, ``"+1"``, text of only spaces) is refused in the words of
    ``--pwe 2``. None when not given or ``null``."""
    value = args.get(key)
    if value is None:
        return None
    try:
        return int(switch_value(value))
    except ValueError as exc:
        raise ActionError(f"{key}: {exc}") from None


def _panel(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.set_panel(
        _mode(args),
        _switch(args, "pwe"),
        _switch(args, "emergency"),
        path=_path(args),
    )
    return {}


def _overrides(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.set_overrides(
        _optional_int(args, "feed"),
        _read_as(args, "rapid", rapid_step, _optional_int),
        _optional_int(args, "spindle"),
        path=_path(args),
    )
    return {}


def _alarm_type(args: Mapping[str, Any], default: int | None = None) -> int:
    """``alm_type`` by its number or its name (``PS``), as the command line and the client
    take it (:func:`~focas_net.protocol.alarm_type_of`); one left out (without a
    ``default``) or empty is asked for by its names and numbers."""
    value = args.get("alm_type")
    if (value is None and default is None) or (isinstance(value, str) and not value.strip()):
        raise ActionError(f"alm_type: an alarm type is needed ({ALARM_TYPES})")
    return _read_as(args, "alm_type", _alarm_type_text, lambda a, k: _int(a, k, default))


def _alarm_type_text(text: str) -> int:
    """An alarm type typed as text: a number (``3``) or, any other text, a name (``PS``),
    refused naming what was typed and the names (``P S`` or ``T31`` is no number either)."""
    word = text.strip().lstrip("+-")
    return whole_number(text) if word[:1].isdigit() else alarm_type_of(text)


def _raise_alarm(station: Station, args: Mapping[str, Any]) -> JsonDict:
    msg = _text(args, "msg")
    try:
        alarm_message(msg)  # text, as the client and the command line take it
    except ValueError as exc:
        raise ActionError(f"msg: {exc}") from None
    m, path = station.machine, _path(args)
    key = (_int(args, "axis_no", 0), _alarm_type(args), _int(args, "alm_no"))
    raised = m.raise_alarm(*key, msg, path=path)
    # the machine's rule, as for every front end: it keeps the first 32 characters (and takes
    # its alarm table's text for none); the answer says what it kept (an alarm active before
    # keeps its message), and that it cut one given
    kept = next(a.msg for a in m.active_alarms(path=path) if a.key == key)
    result: JsonDict = {"raised": raised, "msg": kept}
    if not raised:  # in the words of sim alarm: nothing changed
        result["note"] = alarm_active_already(key[1], key[2], kept, key[0], on=_on(m, path))
    elif msg and kept != msg:
        result["note"] = f"the CNC keeps {len(kept)} characters of a message: {kept!r}"
    return result


def _on(machine: Machine, path: int) -> str:
    """`` on path 2`` on a machine of several paths, as the command line names the path."""
    return f" on path {path}" if machine.path_count > 1 else ""


def _clear_alarms(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Clear the matching alarms: ``alm_type`` and ``alm_no`` left out (or ``-1``) match any;
    ``alm_type`` ``"all"`` is every type, as ``sim clear all`` takes it."""
    typed = args.get("alm_type")
    every = isinstance(typed, str) and typed.strip().lower() == "all"
    alm_type = -1 if every else _alarm_type(args, -1)
    alm_no, path = _int(args, "alm_no", -1), _path(args)
    cleared = station.machine.clear_alarms(alm_type, alm_no, path=path)
    if cleared:
        return {"cleared": cleared}
    # as sim clear says it, naming the alarms asked for as the CNC names them
    given = alarm_filter_text(alm_type, alm_no)
    m = station.machine
    elsewhere = [
        (other, n)
        for other in range(1, m.path_count + 1)
        if other != path
        and (n := sum(1 for a in m.active_alarms(path=other) if _matches(a, alm_type, alm_no)))
    ]
    note = nothing_cleared(given, on=_on(m, path), elsewhere=elsewhere)
    return {"cleared": 0, "note": note}


def _matches(alarm: Any, alm_type: int, alm_no: int) -> bool:
    """Whether ``alarm`` is one a clear of ``alm_type`` and ``alm_no`` (-1: any) takes."""
    return alm_type in (-1, alarm.alm_type) and alm_no in (-1, alarm.alm_no)


def _pmc_bit(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Toggle (or, with ``value`` 0/1, set) one PMC bit."""
    m = station.machine
    typed = _text(args, "area", needed="a PMC area's letter (X, R, ...)")
    try:
        m.pmc_area(typed)  # the machine's words for a letter that is no PMC area
    except ValueError as exc:
        raise ActionError(str(exc)) from None
    m.check_pmc_area(typed)  # and for an area this machine has not (EW_NOOPT)
    area = typed.strip().upper()
    address, bit = _int(args, "address"), _int(args, "bit")
    why = pmc_bit_refusal(area, address, bit)  # as `pmc bit R 1.8` is refused
    if why is not None:
        raise ActionError(why)
    m.check_writable()
    (byte,) = m.read_pmc(area, address, 1)
    value = _switch(args, "value")
    if value is None:
        byte ^= 1 << bit
    else:
        byte = byte | 1 << bit if value else byte & ~(1 << bit)
    m.write_pmc(area, address, bytes([byte]), force=area in FORCED_PMC_AREAS)
    # the bit as `focas-net pmc bit --json` names it (its "byte" is the address: the byte's
    # value is not answered under that name)
    return {"area": area, "address": address, "bit": bit, "value": byte >> bit & 1}


#: Digits of a parameter value the page passes on (a parameter holds 10 at most): beyond, the
#: number is refused before it becomes an int, which would take minutes for 1E+999999.
_PARAM_DIGITS: Final = 20


def _param_value(m: Machine, number: int, text: Decimal) -> tuple[int, int | None]:
    """A parameter value as the page typed it -> (value in the parameter's terms, decimals)."""
    digits = len(text.as_tuple().digits)
    if digits > _PARAM_DIGITS or (not text.is_zero() and text.adjusted() >= _PARAM_DIGITS):
        shown = f"{text:.3E}" if digits > _PARAM_DIGITS else str(text)
        raise ActionError(f"value: {shown} is no parameter value (more than 20 digits)")
    item = m.param_item(number)
    if item is not None and item.kind is ParamKind.REAL:
        exponent = text.as_tuple().exponent
        assert isinstance(exponent, int)
        decimals = max(0, -exponent)
        return int(text.scaleb(decimals)), decimals
    if text != text.to_integral_value():
        raise ActionError(f"value: {param_decimals_refused(number, text)}")
    return int(text), None


#: The other way the page takes a bit parameter's value, for the words of a refused one.
_HEX_BYTE: Final = 'a hexadecimal number with 0x ("0xB0")'


def _bits(number: int, value: object) -> int | None:
    """The value of bit parameter ``number`` as the page shows it: its eight bits #7..#0
    (``10110000``), or ``0xB0`` / ``0b10110000`` as the command line takes them (a JSON
    number is the byte); None when nothing is given. A decimal is refused: eight digits of 0
    and 1 would read as bits, so the page takes none."""
    if value is None or (isinstance(value, int) and not isinstance(value, bool)):
        return value
    if not isinstance(value, str) or not value.strip():
        return None
    text = value.strip()
    try:
        bits = bits_of_text(text, _HEX_BYTE)  # the machine file's and the command line's

    except ValueError as exc:
        raise ActionError(f"value: {exc}") from None
    if bits is not None:
        return bits
    if text.lower().lstrip("+-").startswith(("0x", "0b")):
        return _int({"value": text}, "value")
    raise ActionError(
        f"value: parameter {number} is a bit parameter: write its 8 bits #7..#0 (10110000), "
        f"0x.. or 0b.., got {shown(value)}"
    )


def _item_number(args: Mapping[str, Any], what: str) -> int:
    """``number`` of a parameter or a macro variable (``#100`` too, as FANUC writes one:
    :func:`~focas_net._typed.macro_number`), refused as every front end refuses a number the
    CNC's field does not carry (``parameter number 99999 is outside 0..32767``)."""
    typed = args.get("number")
    if what == "macro variable number" and isinstance(typed, str) and typed.strip():
        try:
            number = macro_number(typed)
        except ValueError as exc:
            raise ActionError(f"number: {exc}") from None
    else:
        number = _int(args, "number")
    why = item_number_unfit(what, number)
    if why is not None:
        raise ActionError(f"number: {why}")
    return number


def _write_param(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    number, axis = _item_number(args, "parameter number"), _int(args, "axis", 0)
    why = item_axis_unfit(axis, "parameter")  # an axis no field carries, as the clients say
    if why is not None:
        raise ActionError(f"axis: {why}")
    item = m.param_item(number)
    bits = _bits(number, args.get("value")) if item and item.kind is ParamKind.BIT else None
    given = _decimal(args, "value") if bits is None else Decimal(bits)
    if given is None:
        raise ActionError("value: a number is needed")
    if item is not None:  # a value no wire carries is refused before the write gates, as
        value, decimals = _param_value(m, number, given)  # every client refuses to send it
        kind = item.kind
        why = (
            None
            if kind is ParamKind.REAL
            else param_value_unfit(number, value, item.width, bit=kind is ParamKind.BIT)
        )
        if why is not None:
            raise ActionError(f"value: {why}")
    m.check_writable()  # the machine's order: read-only first, then the number
    if item is None:
        raise MachineError(EW.NUMBER, no_item("parameter", number))
    path = _path(args)
    m.write_param(station.session, number, axis, value, decimals=decimals, path=path)
    # the value as `param get --json` gives it (a real one's as its decimal text, not the
    # number of its least units), and the text the page shows
    return param_data(item, axis, m.read_param(number, axis, path=path))


def _unlock(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Unlock the page's session; on a machine without a password, say what that means in
    the command line's words (``focas-net unlock``)."""
    m = station.machine
    password = _text(args, "password", needed="a parameter password (1..4 ASCII characters)")
    m.unlock(station.session, password)
    if not m.has_password:
        return {"password_set": False, "note": NO_PASSWORD_NOTE}
    return {"password_set": True}


def _write_macro(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    number, path = _item_number(args, "macro variable number"), _path(args)
    if "value" not in args:  # a variable is made vacant when told, never for a key left out
        raise ActionError('value: a number is needed (null or "" makes the variable vacant)')
    value, typed = _decimal(args, "value"), args.get("value")
    if value is not None:  # a value no wire carries, refused as the clients refuse to send it
        try:  # (naming the text typed, as the command line's macro set does)
            mcr_val, dec_val = macro_to_wire(typed if isinstance(typed, str) else value)
        except ValueError as exc:
            raise ActionError(f"#{number}: {exc}") from None
        value = Decimal(mcr_val).scaleb(-dec_val)  # the digits the clients send
    m.write_macro(number, value, path=path)
    return {"number": number, "value": macro_value(m.read_macro(number, path=path))}


def _select_program(station: Station, args: Mapping[str, Any]) -> JsonDict:
    path, typed = _path(args), args.get("number")
    if typed is None or (isinstance(typed, str) and not typed.strip()):
        raise ActionError("number: a program number is needed (e.g. O1000)")
    if not isinstance(typed, str | int) or isinstance(typed, bool):
        raise ActionError(f"number: {shown(typed)} is not a program number {PROGRAM_NUMBERS}")
    try:  # O1000 or 1000, as the command line reads it
        number = program_number(typed)
    except ValueError as exc:
        raise ActionError(f"number: {exc}") from None
    station.machine.select_program(number, path=path)
    station.trail_of(path).clear()
    return {}


def _inject_fault(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Arm a machine-wide fault with the checks of 0x0E05 inject_fault: a refused argument is
    ``EW_DATA`` with the reason :func:`~focas_net.server.faults.fault_refusal` gives every
    front end."""
    kinds = ", ".join(sorted(k.name.lower() for k in FaultKind))
    # by its name, as `sim fault KIND` takes it (a number is none: "1" was a delay)
    kind = _named(args, "kind", f"one of {kinds}", fault_kind_of)
    count = _int(args, "count", 1)
    # a delay or an error needs its argument; a drop or a split takes none
    needed, given = fault_arg_needed(int(kind)), args.get("arg")
    if needed is not None and (given is None or (isinstance(given, str) and not given.strip())):
        raise ActionError(f"arg: {needed}")  # as `sim fault delay` without --arg is refused
    if kind is FaultKind.ERROR:
        arg = _read_as(args, "arg", ew_of_text, _int)
    elif kind is FaultKind.DELAY:
        arg = _int(args, "arg")
    elif args.get("arg") not in (None, ""):  # as `sim fault drop --arg 5` is refused
        raise ActionError(f"arg does not apply to a {kind.name.lower()} fault")
    else:
        arg = 0
    station.machine.check_writable()  # the order of every control command: read-only first
    reason = fault_refusal(int(kind), int(FaultScope.MACHINE), count, arg)
    if reason is not None:
        raise MachineError(EW.DATA, reason)
    payload = InjectFault(int(kind), int(FaultScope.MACHINE), count, arg).encode()
    parsed = parse_inject(payload, read_only=station.machine.read_only)
    assert not isinstance(parsed, int), parsed  # the checks above are parse_inject's
    _, fault = parsed
    armed = station.faults.arm(fault)
    if armed:
        raise MachineError(armed, "the fault queue is full")
    return {"armed": len(station.faults)}


def _clear_faults(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.check_writable()
    cleared = station.faults.clear()
    return {"cleared": cleared} if cleared else {"cleared": 0, "note": no_faults_cleared(_OURS)}


#: The faults the page arms and clears, as the command line names them (``--scope machine``).
_OURS: Final = "of this machine"


def _clear_path(station: Station, args: Mapping[str, Any]) -> JsonDict:
    path = _path(args)
    station.machine.path_info(path)  # EW_PATH for a path the machine has not
    station.trail_of(path).clear()
    return {}


#: The page actions by name.
ACTIONS: Final[Mapping[str, _Action]] = {
    "cycle": _cycle,
    "panel": _panel,
    "overrides": _overrides,
    "raise_alarm": _raise_alarm,
    "clear_alarms": _clear_alarms,
    "pmc_bit": _pmc_bit,
    "write_param": _write_param,
    "unlock": _unlock,
    "write_macro": _write_macro,
    "select_program": _select_program,
    "inject_fault": _inject_fault,
    "clear_faults": _clear_faults,
    "clear_path": _clear_path,
}

#: The keys each action's arguments take (every one takes ``path``): another is refused,
#: naming these, rather than left unread (a ``clear_alarms`` whose ``alm_type`` is misspelt
#: would clear every alarm).
ACTION_KEYS: Final[Mapping[str, frozenset[str]]] = {
    action: frozenset({"path", *keys})
    for action, keys in {
        "cycle": ("action",),
        "panel": ("mode", "pwe", "emergency"),
        "overrides": ("feed", "rapid", "spindle"),
        "raise_alarm": ("axis_no", "alm_type", "alm_no", "msg"),
        "clear_alarms": ("alm_type", "alm_no"),
        "pmc_bit": ("area", "address", "bit", "value"),
        "write_param": ("number", "axis", "value"),
        "unlock": ("password",),
        "write_macro": ("number", "value"),
        "select_program": ("number",),
        "inject_fault": ("kind", "count", "arg"),
        "clear_faults": (),
        "clear_path": (),
    }.items()
}


def no_twice(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's members, refused when a key is given twice (which one counts is no
    rule JSON makes)."""
    args: dict[str, Any] = {}
    for key, value in pairs:
        if key in args:
            raise ActionError(f"the key {key!r} is given twice")
        args[key] = value
    return args


def json_int(text: str) -> int:
    """A JSON number without a point (``-12``): one of more than
    :data:`~focas_net._typed.MAX_DIGITS` digits is refused saying so, as typed text of as many
    is (Python refuses to read 4,301 and more in words of its own, and the body would read as
    no JSON)."""
    count = len(text.lstrip("-"))
    if count > MAX_DIGITS:
        raise ActionError(
            f"a JSON number of {count} digits ({text[:12]}...): no value holds more than "
            f"{MAX_DIGITS}"
        )
    return int(text)


def action_args(body: bytes) -> dict[str, Any]:
    """The arguments of an action from its request body (empty: none): a JSON object, each
    key once; :class:`ActionError` saying what the body is instead."""
    if not body.strip():
        return {}
    try:
        args = json.loads(body, object_pairs_hook=no_twice, parse_int=json_int)
    except RecursionError:
        raise ActionError("the body nests too deep to be an action's arguments") from None
    except ValueError as exc:
        if isinstance(exc, ActionError):
            raise
        raise ActionError("the body is not JSON") from None
    if not isinstance(args, dict):
        raise ActionError("the body must be a JSON object")
    return args


#: Actions that change nothing in the machine (allowed on a read-only dashboard).
_VIEW_ONLY: Final = frozenset({"clear_path"})


def perform(
    station: Station, action: str, args: Mapping[str, Any], *, read_only: bool = False
) -> JsonDict:
    """Carry out page action ``action`` with ``args`` on ``station``; ``{"ok": True, ...}``.

    Raises :class:`ActionError` for an unknown action or a bad argument and
    :class:`~focas_net.sim.MachineError` for a refusal (``EW_PROT`` on a ``read_only``
    dashboard, before anything else)."""
    operation = ACTIONS.get(action)
    if operation is None:
        raise ActionError(f"unknown action {action!r} (one of {', '.join(ACTIONS)})")
    unknown = sorted(set(args) - ACTION_KEYS[action], key=str)
    if unknown:
        takes = ", ".join(sorted(ACTION_KEYS[action]))
        raise ActionError(f"{action} takes no {', '.join(map(repr, unknown))} (it takes {takes})")
    if read_only and action not in _VIEW_ONLY:
        raise MachineError(EW.PROT, "the dashboard is read-only")
    try:
        # every action names a path the machine has, the machine-wide ones (PMC, the
        # password, faults) too: a page of a path the machine has not is refused, not served
        # path 1
        station.machine.path_info(_path(args))
        return {"ok": True, **operation(station, args)}
    except ActionError as exc:
        raise ActionError(_as_typed(str(exc), args)) from None
    except MachineError as exc:
        led = _as_typed(exc.detail, args)
        if led == exc.detail:
            raise
        raise MachineError(exc.ew, led) from None


def _as_typed(why: str, args: Mapping[str, Any]) -> str:
    """A refusal, ``why``, led by the numbers of ``args`` it names as they were typed where
    they read otherwise (``0x10000 reads as 65536: ...``), as the command line leads its
    refusals (:func:`~focas_net._typed.lead_as_typed`); after the key a refusal of one
    argument names first (``number: 0x10000 reads as 65536: parameter number 65536 ...``)."""
    key, sep, rest = why.partition(": ")
    if sep and key in args:
        return f"{key}: {lead_as_typed(rest, typed_numbers([args[key]]))}"
    return lead_as_typed(why, typed_numbers(args.values()))
