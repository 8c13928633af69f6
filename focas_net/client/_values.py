"""What both clients check and convert, written once: a call's arguments, macro and parameter
values, positions.

Every public method of :class:`~focas_net.client.FocasClient` and
:class:`~focas_net.client.NativeClient` checks its arguments with these functions in the
caller's own frame, before anything is queued or sent: a value of the wrong type raises
:class:`TypeError`, a value the wire cannot carry :class:`ValueError`, each naming what was
given. The conversions are pure: a macro value to FANUC's ``(mcr_val, dec_val)`` and back, a
parameter value to what its type carries.
"""

from __future__ import annotations

import enum
import math
import sys
from dataclasses import dataclass
from decimal import Decimal
from typing import Final

from .._bits import bits_of_text
from .._typed import (
    alarm_axis_unfit,
    field_unfit,
    item_axis_unfit,
    macro_to_wire,
    nan_refused,
    param_decimals_refused,
    param_value_unfit,
    pmc_count_unfit,
    typed_number,
    whole_number,
)
from ..errors import EW, CncError
from ..protocol import (
    MAX_HISTORY_DEPTH,
    MAX_REAL_DECIMALS,
    ParamDataType,
    PmcArea,
    PositionKind,
    alarm_type_of,
)

#: The public name of this module (exported by ``focas_net.client``); the checks and the
#: conversions are the clients' own.
__all__ = ["Paths", "Positions"]

I16_MAX: Final = 0x7FFF
I32_MIN: Final = -(2**31)
I32_MAX: Final = 2**31 - 1
_U16_LIMIT: Final = 0x10000
_MAX_ALARM_TYPE: Final = 31
_MAX_HISTORY_DEPTH: Final = MAX_HISTORY_DEPTH
#: The IODBPSD width of a real parameter's REALPRM.
REAL_WIDTH: Final = 8

AreaLike = str | int | PmcArea
#: Most paths a FANUC control has: a path is 1..10.
MAX_PATHS: Final = 10


@dataclass(frozen=True, slots=True)
class Paths:
    """The answer of ``read_paths`` (FANUC's ``cnc_getpath``): ``current``, the path the
    client's calls read when given no ``path=`` (0 on a packed connection whose last
    ``cnc_setpath`` was refused), and ``count``, the number of paths of the CNC."""

    current: int
    count: int


@dataclass(frozen=True, slots=True)
class Positions:
    """The answer of ``read_positions``.

    ``values`` maps each axis name to its position (``increments / 10**decimals``, a Decimal
    with ``decimals`` places); ``increments`` holds the raw least-input-increment counts. Both
    keep the CNC's axis order.
    """

    kind: PositionKind
    decimals: int
    values: dict[str, Decimal]
    increments: dict[str, int]


# -- arguments -----------------------------------------------------------------------------------
def check_int(what: str, value: object, low: int, high: int) -> int:
    """``value`` when it is an ``int`` (not a ``bool``) within ``low..high``.

    :raises TypeError: not an integer (naming ``what`` and the value given).
    :raises ValueError: outside the range (naming ``what`` and the value given).
    """
    number = an_int(what, value)
    why = field_unfit(what, number, low, high)
    if why is not None:
        raise ValueError(why)
    return number


def an_int(what: str, value: object) -> int:
    """``value`` when it is an ``int`` (not a ``bool``); TypeError naming ``what`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{what} must be an integer, got {value!r}")
    return value


def check_path(path: object) -> int:
    """A client's or a call's ``path``: an ``int`` within 1..10 (a path the CNC does not have
    is the CNC's to refuse, with EW_PATH).

    :raises TypeError: not an integer; :raises ValueError: outside 1..10 (naming it)."""
    return check_int("path", path, 1, MAX_PATHS)


def check_timeout(timeout: object) -> float | None:
    """A call's or a client's ``timeout``: None (no deadline) or a positive number of seconds
    (``inf`` is no deadline either, and so is a whole number too large for a float)."""
    if timeout is None:
        return None
    if isinstance(timeout, bool) or not isinstance(timeout, int | float):
        raise TypeError(f"timeout must be a number of seconds or None, got {timeout!r}")
    if timeout != timeout:
        raise ValueError(nan_refused("timeout", "a positive number of seconds"))
    if not timeout > 0:
        raise ValueError(f"timeout must be positive, got {timeout}")
    if timeout > sys.float_info.max:  # 10**400: no float holds it, no deadline ends it
        return None
    return None if math.isinf(timeout) else float(timeout)


def check_macro(number: object) -> int:
    """A macro variable number (``cnc_rdmacro`` takes a C ``short``)."""
    return check_int("macro variable number", number, -I16_MAX - 1, I16_MAX)


def check_item(number: object, axis: object, what: str) -> None:
    """A parameter's or a diagnostic's number and axis (0: not an axis item)."""
    check_int(f"{what} number", number, 0, I16_MAX)
    if isinstance(axis, bool) or not isinstance(axis, int):
        raise TypeError(f"axis must be an integer (0: not an axis {what}), got {axis!r}")
    why = item_axis_unfit(axis, what)
    if why is not None:
        raise ValueError(why)


def check_alarm_axis(axis_no: object) -> int:
    """An alarm's axis (0: an alarm of no axis), refused in the words of every front end
    (:func:`~focas_net._typed.alarm_axis_unfit`); whether the path has it is the CNC's."""
    if isinstance(axis_no, bool) or not isinstance(axis_no, int):
        raise TypeError(f"axis must be an integer (0: an alarm of no axis), got {axis_no!r}")
    why = alarm_axis_unfit(axis_no)
    if why is not None:
        raise ValueError(why)
    return axis_no


def check_axis(axis: object, what: str = "axis", *, every: int | None = None) -> int | None:
    """One axis (or spindle) 1..n, or ``every`` (None, or -1) for all of them (returned as
    None)."""
    if axis is every or (every is not None and axis == every and not isinstance(axis, bool)):
        return None
    if isinstance(axis, bool) or not isinstance(axis, int):
        raise TypeError(f"{what} must be an integer, got {axis!r}")
    if not 1 <= axis <= I16_MAX:
        every_one = f" ({every}: every {what})" if every is not None else ""
        raise ValueError(f"{what} {axis} is outside 1..{I16_MAX}{every_one}")
    return axis


def check_bit(bit: object, width: int | None = 1, what: str = "") -> int:
    """A bit number of a value ``width`` bytes wide (``what``, when given, names the value
    in the error: ``parameter 20 is 1 byte wide``); ``width`` None checks the type only, for
    a value whose width is learnt later (a parameter's, once read), to name its real range."""
    if width is None:
        return an_int("bit", bit)
    if what and isinstance(bit, int) and not isinstance(bit, bool):
        if not 0 <= bit < 8 * width:
            unit = "byte" if width == 1 else "bytes"
            raise ValueError(
                f"bit {bit} is outside 0..{8 * width - 1}: {what} is {width} {unit} wide"
            )
    return check_int("bit", bit, 0, 8 * width - 1)


def check_bit_value(value: object) -> bool:
    """The value of one bit: ``True``/``False`` or ``1``/``0``; anything else (``2``,
    ``"0"``, ``None``) raises rather than counting as set because it is truthy."""
    if isinstance(value, bool):
        return value
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    raise TypeError(f"a bit's value is True, False, 1 or 0, got {value!r}")


def check_pmc_range(start: object, count: object) -> tuple[int, int]:
    """``count`` (at least 1) PMC bytes from ``start``, ending by 65535."""
    first = check_int("PMC start address", start, 0, _U16_LIMIT - 1)
    size = an_int("PMC byte count", count)
    why = pmc_count_unfit(size)
    if why is not None:
        raise ValueError(why)
    if first + size > _U16_LIMIT:
        raise ValueError(
            f"{size} PMC bytes from {first} run to {first + size - 1}, "
            f"past {_U16_LIMIT - 1} (the last PMC address)"
        )
    return first, size


def history_depth(depth: object) -> int:
    """The alarm history entries to read: ``depth`` from 1, more than 250 read as 250 (the
    history holds no more); below 1 is a ValueError naming it, as the command line says."""
    given = an_int("history depth", depth)
    if given < 1:
        raise ValueError(
            f"history depth {given} is below 1 (the latest entries to read; more than "
            f"{_MAX_HISTORY_DEPTH} reads the {_MAX_HISTORY_DEPTH} the history holds)"
        )
    return min(given, _MAX_HISTORY_DEPTH)


def number_of_name(names: type[enum.IntEnum], given: str, what: str, numbers: str) -> int:
    """The number of member ``given`` of ``names`` by its name, in either case: ValueError
    naming ``what`` was given, the names and ``numbers`` (what else may be given)."""
    try:
        return int(names[given.strip().upper()])
    except KeyError:
        known = " ".join(m.name for m in names)
        raise ValueError(f"unknown {what} {given!r} (one of {known}, or {numbers})") from None


def alarm_type_number(alm_type: object, *, every: bool = False) -> int:
    """An alarm type number from its name (``"PS"``), an :class:`AlarmType` or 0..31 (and -1,
    every type, with ``every``), the number also as text (``"3"``), as the page takes it."""
    if isinstance(alm_type, str):
        if not alm_type.strip().lstrip("+-")[:1].isdigit():
            return alarm_type_of(alm_type)
        alm_type = whole_number(alm_type)
    return check_int("alarm type", alm_type, -1 if every else 0, _MAX_ALARM_TYPE)


def pmc_data(start: object, data: object) -> bytes:
    """PMC bytes to write from ``start``: bytes-like, at least one, ending by 65535."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise TypeError(f"PMC data must be bytes, got {data!r}")
    raw = bytes(data)
    check_pmc_range(start, len(raw))
    return raw


# -- macro values ----------------------------------------------------------------------------
def macro_write(number: int, value: int | Decimal | float | str) -> tuple[int, int]:
    """``(mcr_val, dec_val)`` of a write of ``value`` to ``#number``, checked as both clients
    check it: the number (:func:`check_macro`), then the value (:func:`macro_to_wire`), whose
    refusal names the variable (``#100: not a number: 'abc'``)."""
    check_macro(number)
    try:
        return macro_to_wire(value)
    except ValueError as exc:
        raise ValueError(f"#{number}: {exc}") from None
    except TypeError as exc:
        raise TypeError(f"#{number}: {exc}") from None


def macro_from_wire(mcr_val: int, dec_val: int) -> Decimal | None:
    """The value of an ODBM: ``mcr_val / 10**dec_val``, or None when vacant."""
    if mcr_val == 0 and dec_val == -1:
        return None
    return Decimal(mcr_val).scaleb(-dec_val)


# -- parameter values --------------------------------------------------------------------------
def not_finite(number: int, value: Decimal) -> str:
    """The refusal of a Decimal NaN or infinity as a parameter's value, in the words a front
    end gives the same text."""
    return f"parameter {number}: not a number: {value} (no NaN or infinity)"


def bits_shaped(text: str) -> bool:
    """Whether ``text`` is written as a bit parameter's bits (``"1011_0000"``, ``"1011"``),
    which :func:`~focas_net._bits.bits_of_text` reads, or refuses in its words, once the
    parameter is known to be one."""
    try:
        return bits_of_text(text) is not None
    except ValueError:
        return True


def param_int(number: int, value: object, kind: ParamDataType | None = None) -> int:
    """An integer parameter value from ``value`` (text: decimal, leading zeros allowed, ``0x``,
    ``0b`` or ``0o``, decimals of none but zeros, read by :func:`focas_net._typed.typed_number`,
    refused with decimals in the words of a ``Decimal``); for a bit parameter
    (``kind``) eight 0/1 digits of text are its bits #7..#0, as the machine file and the page
    read them (:func:`focas_net._bits.bits_of_text`)."""
    if isinstance(value, str):
        if kind is ParamDataType.BIT:
            bits = bits_of_text(value)
            if bits is not None:
                return bits
        try:  # as every front end reads a number (0042, 0xB0, 1.0; no exponent)
            value = typed_number(value)
        except ValueError as exc:
            raise ValueError(f"parameter {number}: {exc}") from None
    if isinstance(value, bool) or not isinstance(value, int | Decimal):
        raise TypeError(f"parameter {number}: a value is an integer, got {value!r}")
    if isinstance(value, Decimal):
        if not value.is_finite():
            raise ValueError(not_finite(number, value))
        if value != value.to_integral_value():  # text "1.5" as Decimal("1.5"), in one wording
            raise ValueError(param_decimals_refused(number, value))
        return int(value)
    return value


def byte_to_wire(number: int, value: int, kind: ParamDataType | None) -> int:
    """The signed byte of a 1-byte parameter's ``value``: a bit parameter's 0..255 as the byte
    of the same eight bits, a byte parameter's -128..127 as it is (refused in the words of
    :func:`~focas_net._typed.param_value_unfit`)."""
    bit = kind is ParamDataType.BIT
    why = param_value_unfit(number, value, 1, bit=bit)
    if why is not None:
        raise ValueError(why)
    return value - 0x100 if bit and value > 0x7F else value


def width_refused(number: int, size: int, width: int, why: str = "") -> CncError:
    """EW_LENGTH of ``cnc_wrparam`` given ``width`` for parameter ``number``, ``size`` bytes
    wide (as FANUC's library answers a length that is not the type's), in the same words on
    both clients."""
    wide = "1 byte" if size == 1 else f"{size} bytes"
    return CncError.from_ew(
        EW.LENGTH, f"cnc_wrparam: parameter {number} is {wide} wide, not {width}{why}"
    )


def int_to_wire(number: int, value: int, width: int, kind: ParamDataType | None) -> int:
    """The signed value of an integer parameter ``width`` bytes wide (1, 2 or 4; ``kind``
    tells a bit parameter's byte from a byte parameter's): ValueError naming the parameter,
    its kind and its range when ``value`` does not fit, in the words of every front end
    (:func:`~focas_net._typed.param_value_unfit`)."""
    if width == 1:
        return byte_to_wire(number, value, kind)
    why = param_value_unfit(number, value, width)
    if why is not None:
        raise ValueError(why)
    return value


def real_to_wire(number: int, value: object) -> tuple[int, int]:
    """``(prm_val, dec_val)`` of a real parameter's value."""
    if isinstance(value, bool) or not isinstance(value, int | Decimal | str):
        raise TypeError(f"parameter {number}: a real value is a number, got {value!r}")
    if isinstance(value, str):
        try:  # text no number at all is named as every front end names it
            typed_number(value)
        except ValueError as exc:
            raise ValueError(f"real parameter {number}: {exc}") from None
    try:
        return macro_to_wire(value)
    except ValueError:
        raise ValueError(
            f"real parameter {number}: {value!r} cannot be carried as an i32 mantissa with "
            f"0..{MAX_REAL_DECIMALS} decimals"
        ) from None
