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

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from typing import Any, Final

from focas_net._bits import bits_of_text
from focas_net.errors import EW, ew_name
from focas_net.protocol import FaultKind, FaultScope, InjectFault, alarm_message
from focas_net.server.faults import FaultQueue, parse_inject
from focas_net.sim import Machine, MachineError, ParamKind, Session

from .view import JsonDict, PathTrail

__all__ = [
    "ACTIONS",
    "FORCED_PMC_AREAS",
    "ActionError",
    "Station",
    "perform",
    "refusal",
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
    _macro_numbers: tuple[int, ...] | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        self.session = self.machine.new_session()

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
    """``args[key]`` as a whole number (decimal, ``0x`` or ``0b``); ``default`` when it is not
    given, but a field sent empty is refused like a field that is not a number."""
    value = args.get(key)
    if value is None and default is not None:
        return default
    if value is None or (isinstance(value, str) and not value.strip()):
        raise ActionError(f"{key}: a number is needed")
    if isinstance(value, bool):
        raise ActionError(f"{key}: a number is needed, got {value!r}")
    if isinstance(value, int):
        return value
    if isinstance(value, str):
        number = _prefixed(value)
        if number is not None:
            return number
        try:
            return int(value.strip())
        except ValueError:
            pass
    raise ActionError(f"{key}: not a whole number: {value!r}")


_PREFIXES: Final = ("0x", "0b", "0o")


def _prefixed(text: str) -> int | None:
    """``0xB0``, ``0b1011_0000`` or ``0o260`` (a sign allowed) as the number it writes, as
    the command line reads them; None for text without such a prefix or not a number."""
    body = text.strip().lower().lstrip("+-")
    if not body.startswith(_PREFIXES):
        return None
    try:
        return int(text.strip().replace("_", ""), 0)
    except ValueError:
        return None


def _optional_int(args: Mapping[str, Any], key: str) -> int | None:
    value = args.get(key)
    if value is None or value == "":
        return None
    return _int(args, key)


def _text(args: Mapping[str, Any], key: str, default: str = "") -> str:
    value = args.get(key, default)
    if not isinstance(value, str):
        raise ActionError(f"{key}: text is needed, got {value!r}")
    return value


def _decimal(args: Mapping[str, Any], key: str) -> Decimal | None:
    """``args[key]`` as a number: decimal text (``12.345``) or a whole number written as the
    command line writes it (``0xB0``, ``0b10110000``); None when empty."""
    value = args.get(key)
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    if isinstance(value, bool) or not isinstance(value, str | int):
        raise ActionError(f"{key}: a number is needed, got {value!r}")
    whole = _prefixed(value) if isinstance(value, str) else None
    if whole is not None:
        return Decimal(whole)
    try:
        number = Decimal(str(value).strip())
    except InvalidOperation:
        raise ActionError(f"{key}: not a number: {value!r}") from None
    if not number.is_finite():
        raise ActionError(f"{key}: not a finite number: {value!r}")
    return number


# -- the actions ----------------------------------------------------------------------------
_Action = Callable[[Station, Mapping[str, Any]], JsonDict]


def _cycle(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    what = _text(args, "action")
    if what == "start":
        m.cycle_start()
    elif what == "hold":
        m.feed_hold()
    elif what == "reset":
        m.reset()
    else:
        raise ActionError(f"action: one of start, hold, reset, got {what!r}")
    return {}


def _panel(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.set_panel(
        _optional_int(args, "mode"), _optional_int(args, "pwe"), _optional_int(args, "emergency")
    )
    return {}


def _overrides(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.set_overrides(
        _optional_int(args, "feed"), _optional_int(args, "rapid"), _optional_int(args, "spindle")
    )
    return {}


def _raise_alarm(station: Station, args: Mapping[str, Any]) -> JsonDict:
    msg = _text(args, "msg")
    try:
        alarm_message(msg)  # text, as the client and the command line take it
    except ValueError as exc:
        raise ActionError(f"msg: {exc}") from None
    raised = station.machine.raise_alarm(
        _int(args, "axis_no", 0), _int(args, "alm_type"), _int(args, "alm_no"), msg
    )
    return {"raised": raised}


def _clear_alarms(station: Station, args: Mapping[str, Any]) -> JsonDict:
    cleared = station.machine.clear_alarms(_int(args, "alm_type", -1), _int(args, "alm_no", -1))
    return {"cleared": cleared}


def _pmc_bit(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Toggle (or, with ``value`` 0/1, set) one PMC bit."""
    m = station.machine
    area = _text(args, "area").strip().upper()
    address, bit = _int(args, "address"), _int(args, "bit")
    if not 0 <= bit <= 7:
        raise ActionError(f"bit: 0..7, got {bit}")
    try:
        if m.pmc_area(area) is None:
            raise MachineError(EW.NOOPT, f"no PMC area {area}")
    except ValueError:
        raise ActionError(f"area: not a PMC area: {area!r}") from None
    m.check_writable()
    (byte,) = m.read_pmc(area, address, 1)
    value = _optional_int(args, "value")
    if value is None:
        byte ^= 1 << bit
    elif value in (0, 1):
        byte = byte | 1 << bit if value else byte & ~(1 << bit)
    else:
        raise ActionError(f"value: 0 or 1, got {value}")
    m.write_pmc(area, address, bytes([byte]), force=area in FORCED_PMC_AREAS)
    return {"area": area, "address": address, "byte": byte}


#: Digits of a parameter value the page passes on (a parameter holds 10 at most): beyond, the
#: number is refused before it becomes an int, which would take minutes for 1E+999999.
_PARAM_DIGITS: Final = 20


def _param_value(
    m: Machine, number: int, text: Decimal, typed: object = None
) -> tuple[int, int | None]:
    """A parameter value as the page typed it -> (value in the parameter's terms, decimals);
    on a bit parameter eight 0/1 digits ``typed`` are its bits, as the command line reads them."""
    item = m.param_item(number)
    if item is not None and item.kind is ParamKind.BIT and isinstance(typed, str):
        try:
            bits = bits_of_text(typed)
        except ValueError as exc:
            raise ActionError(f"value: {exc}") from None
        if bits is not None:
            return bits, None
    digits = len(text.as_tuple().digits)
    if digits > _PARAM_DIGITS or (not text.is_zero() and text.adjusted() >= _PARAM_DIGITS):
        shown = f"{text:.3E}" if digits > _PARAM_DIGITS else str(text)
        raise ActionError(f"value: {shown} is no parameter value (more than 20 digits)")
    if item is not None and item.kind is ParamKind.REAL:
        exponent = text.as_tuple().exponent
        assert isinstance(exponent, int)
        decimals = max(0, -exponent)
        return int(text.scaleb(decimals)), decimals
    if text != text.to_integral_value():
        raise ActionError(f"value: parameter {number} takes a whole number, got {text}")
    return int(text), None


def _write_param(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    number, axis = _int(args, "number"), _int(args, "axis", 0)
    given = _decimal(args, "value")
    if given is None:
        raise ActionError("value: a number is needed")
    m.check_writable()  # the machine's order: read-only first, then the number
    if m.param_item(number) is None:
        raise MachineError(EW.NUMBER, f"no parameter {number}")
    value, decimals = _param_value(m, number, given, args["value"])
    m.write_param(station.session, number, axis, value, decimals=decimals)
    return {"number": number, "value": m.read_param(number, axis)}


def _unlock(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.unlock(station.session, _text(args, "password"))
    return {}


def _write_macro(station: Station, args: Mapping[str, Any]) -> JsonDict:
    m = station.machine
    number = _int(args, "number")
    m.write_macro(number, _decimal(args, "value"))
    value = m.read_macro(number)
    return {"number": number, "value": "" if value is None else str(value)}


def _select_program(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.select_program(_int(args, "number"))
    station.trail.clear()
    return {}


_I16: Final = range(-0x8000, 0x8000)
_I32: Final = range(-0x8000_0000, 0x8000_0000)


def _inject_fault(station: Station, args: Mapping[str, Any]) -> JsonDict:
    """Arm a machine-wide fault with the checks of 0x0E05 inject_fault."""
    kind_text = _text(args, "kind").strip().upper()
    try:
        kind = FaultKind[kind_text] if not kind_text.isdigit() else FaultKind(int(kind_text))
    except (KeyError, ValueError):
        names = ", ".join(k.name for k in FaultKind)
        raise ActionError(f"kind: one of {names}, got {kind_text!r}") from None
    # a delay or an error needs its argument; a drop or a split ignores one it is given
    needs_arg = kind in (FaultKind.DELAY, FaultKind.ERROR)
    count, arg = _int(args, "count", 1), _int(args, "arg", None if needs_arg else 0)
    if count not in _I16:
        raise ActionError(f"count: 1..10000, got {count}")
    if arg not in _I32:
        raise ActionError(f"arg: outside 32 bits: {arg}")
    payload = InjectFault(int(kind), int(FaultScope.MACHINE), count, arg).encode()
    parsed = parse_inject(payload, read_only=station.machine.read_only)
    if isinstance(parsed, int):
        raise MachineError(parsed, f"fault kind {kind.name} count {count} arg {arg}")
    _, fault = parsed
    armed = station.faults.arm(fault)
    if armed:
        raise MachineError(armed, "the fault queue is full")
    return {"armed": len(station.faults)}


def _clear_faults(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.machine.check_writable()
    return {"cleared": station.faults.clear()}


def _clear_path(station: Station, args: Mapping[str, Any]) -> JsonDict:
    station.trail.clear()
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
    if read_only and action not in _VIEW_ONLY:
        raise MachineError(EW.PROT, "the dashboard is read-only")
    return {"ok": True, **operation(station, args)}
