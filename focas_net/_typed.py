"""What a user types, read alike by every front end (it knows no protocol and no machine):
number text (the page, the command line, the clients' text values and the machine file), a
macro value as the wire carries it and the words for one that does not fit (the machine, the
clients and the page), a program number
(the command line and the page), a program's text of a character beyond ASCII (a file, the
clients' ``write_program``), an override's type and range (the machine and the
clients), an alarm's axis and an alarm message that is no line of single-byte text (the
machine and the encoded text of every front end), whether a host typed is the loopback (the
dashboard's and the gateway's guards), a parameter password (the codec, the machine and
the command line), what an unlock of a CNC without a parameter password
means (the command line and the page), and the words of the system's refusal of a file or
address the user named (every front end).

Number text is read as a CNC's MDI keys write a number: ASCII digits, a sign and, for a
decimal, a decimal point; a whole number may also be written ``0x``, ``0b`` or ``0o`` (with
``_`` between its digits), as a bit parameter is shown. An exponent (``1e3``), NaN and
infinity words, digits of other scripts (``'\u0661'``) and empty text are refused, each in
the same words wherever it was typed, naming the text.
"""

from __future__ import annotations

import asyncio
import ipaddress
import json
import math
import os
import re
import socket
import ssl
from collections.abc import Iterable, Mapping
from decimal import Decimal
from typing import Final

__all__ = [
    "CNC_YEARS",
    "MAX_ALARM_NO",
    "MAX_ALARM_TEXT",
    "MAX_ALARM_TYPE",
    "MAX_DIGITS",
    "MODE_TYPE",
    "NO_PASSWORD_NOTE",
    "OVERRIDE_RANGES",
    "PASSWORD_SIZE",
    "PMC_BYTES",
    "PROGRAM_NUMBERS",
    "RAPID_F0",
    "RAPID_STEPS",
    "WRONG_PASSWORD",
    "alarm_axis_unfit",
    "alarm_key_unfit",
    "alarm_text_unfit",
    "cnc_year_unfit",
    "decimal_number",
    "decimal_text",
    "field_unfit",
    "file_text",
    "is_loopback",
    "item_axis_unfit",
    "item_number_unfit",
    "lead_as_typed",
    "macro_number",
    "macro_to_wire",
    "macro_unfit",
    "nan_refused",
    "os_reason",
    "os_words",
    "override_percent",
    "override_unfit",
    "param_value_unfit",
    "password_bytes",
    "pmc_count_unfit",
    "program_number",
    "program_text_unfit",
    "rapid_shown",
    "rapid_step",
    "rapid_text",
    "read_otherwise",
    "switch",
    "switch_value",
    "typed_number",
    "typed_numbers",
    "typed_shown",
    "whole_number",
]

#: The percentages each override takes: feed 0..254, rapid 0..100 (in :data:`RAPID_STEPS`
#: only), spindle 0..254.
OVERRIDE_RANGES: Final[Mapping[str, tuple[int, int]]] = {
    "feed": (0, 254),
    "rapid": (0, 100),
    "spindle": (0, 254),
}

#: The rapid traverse override's steps (%), as the panel's switch and G14's ROV1 ROV2 give
#: them: F0 (a parameter's low speed, kept as 0 %), 25, 50, 100. No other value exists.
RAPID_STEPS: Final[tuple[int, ...]] = (0, 25, 50, 100)
#: The slowest rapid override step by its name: F0 is a rate of its own (a parameter's, 1421
#: on a FANUC control), no percentage, so every front end shows it as the panel names it.
RAPID_F0: Final = "F0"


def rapid_shown(percent: int) -> int | str:
    """A rapid override as shown in data (``--json``): ``"F0"`` for the slowest step (kept as
    0 %), else its percentage."""
    return RAPID_F0 if percent == 0 else percent


def rapid_text(percent: int) -> str:
    """A rapid override as shown in text: ``F0``, or ``25 %``."""
    return RAPID_F0 if percent == 0 else f"{percent} %"


#: What an unlock of a CNC without a parameter password means, as every front end says it.
NO_PASSWORD_NOTE: Final = (
    "the CNC has no parameter password: it accepts any, and a parameter write needs no unlock "
    "(it needs MDI mode and PWE on, and a machine that is not read-only)"
)

#: Why an unlock with a password that is not the CNC's is refused (EW_PASSWD), as every front
#: end says it (the machine, so the dashboard; the command line's reason of the code).
WRONG_PASSWORD: Final = "the password is not the CNC's"

#: The words for an operator panel mode of another type than text or an integer (``True``,
#: ``1.5``), alike on every front end (the machine, the clients' and the page's reading).
MODE_TYPE: Final = "mode must be an AutMode, its name or its number"

#: Bytes of a parameter password (``cnc_wrunlockparam``'s ``password[4]``).
PASSWORD_SIZE: Final = 4


def password_bytes(text: object) -> bytes:
    """A parameter password as the CNC keeps it and ``cnc_wrunlockparam`` carries it: 1..4
    ASCII characters, no NUL, padded to 4 bytes with NUL (a longer one is never cut). The one
    rule of every front end (the codec's ``Password.from_text``, the machine, the command
    line): ValueError ``parameter password 'abcde': must be 1..4 ASCII characters`` for any
    other text, TypeError for what is neither text nor bytes."""
    if not isinstance(text, str | bytes | bytearray):
        raise TypeError(f"a parameter password is text or bytes, got {text!r}")
    shown = text if isinstance(text, str) else bytes(text).decode("latin-1")
    if not (1 <= len(shown) <= PASSWORD_SIZE and shown.isascii() and "\x00" not in shown):
        raise ValueError(
            f"parameter password {shown!r}: must be 1..{PASSWORD_SIZE} ASCII characters"
        )
    return shown.encode("ascii").ljust(PASSWORD_SIZE, b"\x00")


#: Characters of an alarm's message the CNC keeps (a longer one is cut).
MAX_ALARM_TEXT: Final = 32
#: Alarm type numbers a CNC can carry (``alm_type`` is a bit number in FANUC's masks).
MAX_ALARM_TYPE: Final = 31
#: The highest alarm number the CNC holds (its ``alm_no`` is a signed 16-bit word).
MAX_ALARM_NO: Final = 0x7FFF

#: The most O-numbers a program number has (O1 .. O99999999).
_MAX_PROGRAM: int = 99_999_999
#: What a program number is, as every refusal of one says it.
PROGRAM_NUMBERS: Final = f"(O1..O{_MAX_PROGRAM}, e.g. O1000)"


def macro_unfit(value: object) -> str:
    """Why ``value`` does not fit a macro variable, and what to type instead; a Decimal in
    plain decimals as it was typed (``0.0000000001``, not ``1E-10``) unless that would take
    more than 40 places (``1E+99999``)."""
    if isinstance(value, Decimal) and value.is_finite() and abs(value.adjusted()) <= 40:
        value = decimal_text(value)
    return (
        f"{value} does not fit a macro variable: give at most 9 decimals and at most 10 digits, "
        "which without the decimal point stay within 32 bits (-2147483648..2147483647)"
    )


def nan_refused(what: str, kind: str = "a number of seconds") -> str:
    """The refusal of a NaN given as ``what`` where ``kind`` is wanted, saying what is wrong,
    in the words of every API (``timeout must be a positive number of seconds, got nan (not
    a number)``)."""
    return f"{what} must be {kind}, got nan (not a number)"


#: The 32 bits of a macro variable's ``mcr_val``.
_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
#: Decimals a macro variable holds at most (``dec_val``).
_MAX_MACRO_DECIMALS: Final = 9
#: The highest power of ten a macro value reaches (its 32 bits stop below 1e10: adjusted 9).
_MAX_MACRO_MAGNITUDE: Final = 9


def macro_to_wire(value: int | Decimal | float | str) -> tuple[int, int]:
    """``(mcr_val, dec_val)`` for ``value``; :class:`ValueError` when it cannot be carried,
    :class:`TypeError` when it is not a number.

    An ``int`` keeps ``dec_val = 0``; a ``Decimal`` or string keeps the digits it was given
    (``"1.50"`` -> ``(150, 2)``) when they fit, else the fewest that represent it exactly; a
    ``float`` uses its shortest decimal form (``0.1`` -> ``(1, 1)``). ``dec_val`` is 0..9 and
    ``mcr_val`` an i32.
    """
    if isinstance(value, bool):
        raise TypeError("a macro value must be a number, not a bool")
    if isinstance(value, int):
        if not _I32_MIN <= value <= _I32_MAX:
            raise ValueError(f"macro value {macro_unfit(value)}")
        return value, 0
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"macro value {value} is not finite")
        dec = Decimal(repr(value))
    elif isinstance(value, Decimal):
        dec = value
    elif isinstance(value, str):
        dec = Decimal(typed_number(value))  # as every front end reads number text
    else:
        raise TypeError(f"a macro value must be int, Decimal, float or str, not {value!r}")
    if not dec.is_finite():
        raise ValueError(f"macro value {value} is not finite")
    if dec and not -_MAX_MACRO_DECIMALS <= dec.adjusted() <= _MAX_MACRO_MAGNITUDE:
        # below 1e-9 or from 1e10 on no variable holds it (nor need its digits be worked out:
        # 1e99999999999 has more than any context takes)
        raise ValueError(f"macro value {macro_unfit(value)}")
    for candidate in (dec, dec.normalize()):
        exponent = candidate.as_tuple().exponent
        assert isinstance(exponent, int)
        places = max(0, -exponent)
        if places > _MAX_MACRO_DECIMALS:
            continue
        mcr = int(candidate.scaleb(places))
        if _I32_MIN <= mcr <= _I32_MAX:
            return mcr, places
    raise ValueError(f"macro value {macro_unfit(value)}")


def typed_shown(value: object) -> str:
    """A value as a refusal names what was typed or sent: text quoted (``'abc'``), anything
    else as the JSON that was sent (``true``, ``null``, ``[1]``), never as Python writes it."""
    if isinstance(value, str):
        return repr(value)
    try:
        return json.dumps(value)
    except (TypeError, ValueError):  # not from JSON: as Python shows it
        return repr(value)


def field_unfit(what: str, value: int, low: int, high: int) -> str | None:
    """Why ``value`` cannot be ``what`` (``parameter number``), a field of ``low..high``, in
    the words of every front end (``parameter number 99999 is outside 0..32767``); None when
    it can."""
    return None if low <= value <= high else f"{what} {value} is outside {low}..{high}"


#: PMC bytes a range reaches at most: its addresses are a request's ``u16`` fields (0..65535).
PMC_BYTES: Final = 0x10000


def pmc_count_unfit(count: int) -> str | None:
    """Why ``count`` PMC bytes are no range, in the words of every front end (the machine's
    EW_LENGTH, both clients' ValueError before sending): ``PMC byte count 0 is outside
    1..65536 (a PMC range holds one byte at least)``, as for a range whose end is before its
    start (FANUC's ``pmc_rdpmcrng`` and ``pmc_wrpmcrng`` take it from ``s`` to ``e``, both
    included); None for 1..65536 (whether the area has them is the CNC's to say)."""
    why = field_unfit("PMC byte count", count, 1, PMC_BYTES)
    if why is None or count > 0:
        return why
    return f"{why} (a PMC range holds one byte at least)"


#: The numbers a CNC's fields carry: a parameter's (a C ``short`` of no sign) and a macro
#: variable's (a C ``short``).
_ITEM_NUMBERS: Final[Mapping[str, tuple[int, int]]] = {
    "parameter number": (0, 0x7FFF),
    "macro variable number": (-0x8000, 0x7FFF),
}


def item_number_unfit(what: str, number: int) -> str | None:
    """Why ``number`` is no ``what`` (``parameter number``, ``macro variable number``) a CNC's
    field carries (:func:`field_unfit`); None when it is one."""
    low, high = _ITEM_NUMBERS[what]
    return field_unfit(what, number, low, high)


def item_axis_unfit(axis: int, what: str) -> str | None:
    """Why ``axis`` is no axis of a ``what`` (``parameter``, ``diagnostic``) a CNC's field
    carries, in the words of every front end (``axis -1 is outside 0..32767 (0: not an axis
    parameter)``); None when it is one (whether the item has that axis is the CNC's to say)."""
    why = field_unfit("axis", axis, 0, 0x7FFF)
    return None if why is None else f"{why} (0: not an axis {what})"


def param_value_unfit(number: int, value: int, width: int, *, bit: bool = False) -> str | None:
    """Why ``value`` cannot travel as the value of integer parameter ``number``, ``width``
    bytes wide (1, 2 or 4; ``bit``: a bit parameter, 0..255), in the words of every front end
    (both clients refuse it before anything is sent, the dashboard before the write gates);
    None when the wire carries it. A value the wire carries but the parameter does not is the
    CNC's to refuse (EW_DATA), after its write gates. The range named is the type's, the one
    every front end knows: FOCAS/2's ``cnc_rdparainfo`` tells no parameter's own range."""
    if bit:
        if 0 <= value <= 0xFF:
            return None
        return f"bit parameter {number} holds 0..255 (0b00000000..0b11111111), got {value}"
    high = (1 << (8 * width - 1)) - 1
    if -high - 1 <= value <= high:
        return None
    label = {1: "byte", 2: "word", 4: "two-word"}.get(width, f"{width}-byte")
    return f"parameter {number} is a {label} parameter: {value} is outside {-high - 1}..{high}"


#: Years the CNC's clock can be set to (FANUC's calendar): ``cnc_settimer`` refuses another
#: with EW_DATA.
CNC_YEARS: Final = (1987, 2037)


def cnc_year_unfit(year: int) -> str | None:
    """Why the CNC's clock cannot be set to a date of ``year``, in the words of the machine
    and of the client it refuses (``year 1900 is outside 1987..2037``); None when it can."""
    return field_unfit("year", year, *CNC_YEARS)


def override_unfit(what: str, value: int) -> str | None:
    """Why the ``what`` override (feed, rapid, spindle) cannot be ``value`` percent, in the
    machine's words; None when it can."""
    if what == "rapid":
        if value in RAPID_STEPS:
            return None
        return f"rapid override {value} is not a step of FANUC's: 0 (F0), 25, 50 or 100 %"
    low, high = OVERRIDE_RANGES[what]
    if low <= value <= high:
        return None
    return f"{what} override {value} outside {low}..{high} %"


def override_percent(what: str, value: object) -> int:
    """The ``what`` override (feed, rapid, spindle) given from Python, as a whole number of
    percent: an ``int``, or for the rapid override also the name of its slowest step as every
    front end reads it, ``"F0"`` (any case; ``"F25"`` is :func:`rapid_step`'s ValueError
    listing the steps); TypeError naming the override and the value for another type (a
    ``bool``, a float, digits as text). Its range is :func:`override_unfit`'s."""
    if what == "rapid" and isinstance(value, str) and value.strip().upper().startswith("F"):
        return rapid_step(value)
    if isinstance(value, bool) or not isinstance(value, int):
        also = " or the text F0" if what == "rapid" else ""
        raise TypeError(f"{what} override must be a whole number{also}, got {value!r}")
    return value


def alarm_key_unfit(alm_type: int, alm_no: int, *, every: bool = False) -> str | None:
    """Why no alarm is of type ``alm_type`` and number ``alm_no``, in the words of every front
    end (``alarm number 99999 is outside 0..32767``, as the command line and the client say
    it); with ``every`` (a clear's filter), -1 is any type or any number, and the range named
    is the one the argument takes (``alarm type -2 is outside -1..31``). None when one is."""
    low = -1 if every else 0
    for what, value, high in (
        ("alarm type", alm_type, MAX_ALARM_TYPE),
        ("alarm number", alm_no, MAX_ALARM_NO),
    ):
        why = field_unfit(what, value, low, high)
        if why is not None:
            return why
    return None


def alarm_axis_unfit(axis_no: int, axes: int | None = None) -> str | None:
    """Why an alarm cannot be of axis ``axis_no`` (0: an alarm of no axis), in the words of
    every front end: one the field does not carry (``axis -1 is outside 0..32767 (0: an alarm
    of no axis)``, what the command line's parser, the clients and the page say alike), then,
    given the path's ``axes``, one past them, naming the count (``axis 5 is outside 0..3: the
    path has 3 axes``); None when it can be."""
    why = field_unfit("axis", axis_no, 0, 0x7FFF)
    if why is not None:
        return f"{why} (0: an alarm of no axis)"
    if axes is None or axis_no <= axes:
        return None
    counted = f"{axes} axis" if axes == 1 else f"{axes} axes"
    return f"axis {axis_no} is outside 0..{axes}: the path has {counted}"


def alarm_text_unfit(text: str) -> str | None:
    """Why ``text`` cannot be an alarm's message, in the machine's words (a character beyond
    U+00FF, or a control character: a tab, a line break, NUL...); None when it can. The
    machine and the clients (before sending) say the same."""
    wide = next((c for c in text if ord(c) > 0xFF), None)
    if wide is not None:
        return f"alarm message {text!r} is not single-byte text"
    control = next((c for c in text if c < " " or "\x7f" <= c < "\xa0"), None)
    if control is not None:
        return (
            f"alarm message {text!r} holds the control character {control!r} "
            f"(U+{ord(control):04X}): a message is one line of text"
        )
    return None


#: The words of a switch turned on, and off (the command line's and the page's).
_ON: Final = frozenset({"1", "on", "true", "yes", "set"})
_OFF: Final = frozenset({"0", "off", "false", "no", "clear"})
#: What a switch takes, as its refusal says it.
_SWITCH_WORDS: Final = "expected 1, on, true, yes or set, or 0, off, false, no or clear"


def switch(typed: str) -> bool:
    """A switch as typed: ``1/on/true/yes/set`` or ``0/off/false/no/clear`` (any case,
    spaces around); ValueError naming what was typed and the words."""
    word = typed.strip().lower()
    if word in _ON:
        return True
    if word in _OFF:
        return False
    raise ValueError(f"{_SWITCH_WORDS}, got {typed!r}")


def switch_value(value: object) -> bool:
    """A switch given as text (:func:`switch`) or as the number the wire carries, 0 or 1 (a
    JSON ``true``/``false`` too); ValueError in :func:`switch`'s words naming what was given
    (``got 2``) for any other."""
    if isinstance(value, str):
        return switch(value)
    if isinstance(value, int) and value in (0, 1):
        return bool(value)
    raise ValueError(f"{_SWITCH_WORDS}, got {typed_shown(value)}")


def rapid_step(text: str) -> int:
    """A rapid override as typed on every front end: ``F0`` (any case: 0 %, as the panel's
    switch names it) or a whole number (:func:`whole_number`), which the machine checks
    against :data:`RAPID_STEPS`."""
    word = text.strip().upper()
    if word == RAPID_F0:
        return 0
    if word.startswith("F"):  # F25 ...: only F0 is a name; the other steps are percentages
        steps = ", ".join(str(s) for s in RAPID_STEPS[1:])
        raise ValueError(f"{text!r} is no rapid override: F0, or a step of {steps} (%)")
    return whole_number(text)


def program_number(typed: object) -> int:
    """The O-number typed as the command line and the page take it: ``O1000``, ``o1000`` or
    ``1000`` (ASCII digits, 1..99999999), or a whole number; ValueError naming what was
    typed."""
    if isinstance(typed, int) and not isinstance(typed, bool) and 1 <= typed <= _MAX_PROGRAM:
        return typed
    text = typed.strip().upper().removeprefix("O") if isinstance(typed, str) else ""
    # the digits counted before they become a number (Python refuses to read 4,301 and more)
    digits = text.lstrip("0")
    fits = len(digits) <= len(str(_MAX_PROGRAM))
    if not (text.isascii() and text.isdigit() and fits and 1 <= int(digits or 0) <= _MAX_PROGRAM):
        raise ValueError(f"{typed!r} is not a program number {PROGRAM_NUMBERS}")
    return int(digits)


# -- number text -----------------------------------------------------------------------------
#: A whole number: ASCII digits with a sign, or ``0x``, ``0b``, ``0o`` digits (``_`` between).
_WHOLE: Final = re.compile(r"[+-]?(?:[0-9]+|0x[0-9a-f_]+|0b[01_]+|0o[0-7_]+)", re.ASCII)
#: A decimal: ASCII digits with a sign and a decimal point.
_DECIMAL: Final = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)", re.ASCII)
#: A number written with an exponent (``1e3``, ``-2.5E-4``): a CNC's keys have none.
_EXPONENT: Final = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)e[+-]?[0-9]+", re.ASCII)
#: Words Python reads as numbers that are none (NaN, infinity), signs left out.
_NOT_FINITE: Final = frozenset({"nan", "snan", "inf", "infinity"})
#: The prefixes of a whole number written in another base.
_PREFIXES: Final = ("0x", "0b", "0o")


def _beyond_ascii(text: str) -> str | None:
    """What is wrong with number text holding a character beyond ASCII, else None."""
    odd = next((c for c in text if not c.isascii()), None)
    if odd is None:
        return None
    what = "a digit" if odd.isdigit() else "a character"
    return f"{text!r} holds {what} beyond ASCII ({odd!r}, U+{ord(odd):04X}): write 0-9"


#: The most digits a number may have: no value of a CNC comes near, and Python refuses to
#: read a whole number of more than 4300 digits in words of its own.
MAX_DIGITS: Final = 100


def _too_long(what: str, typed: str, digits: str) -> ValueError | None:
    """The refusal of ``typed`` when its ``digits`` (a sign and a prefix left out) are more
    than :data:`MAX_DIGITS`; None otherwise."""
    count = sum(c.isalnum() for c in digits)
    if count <= MAX_DIGITS:
        return None
    return ValueError(f"{what}: {typed!r} ({count} digits: no value holds more than {MAX_DIGITS})")


def _refused(what: str, typed: str) -> ValueError:
    """The refusal of ``typed`` as ``what``, with a hint for an exponent, a NaN or infinity
    word and empty text."""
    low = typed.strip().lower()
    hint = ""
    if _EXPONENT.fullmatch(low):
        hint = " (no exponent: write the digits)"
    elif low.lstrip("+-") in _NOT_FINITE:
        hint = " (no NaN or infinity: write the digits)"
    elif not low:
        hint = " (nothing typed)"
    return ValueError(f"{what}: {typed!r}{hint}")


def whole_number(text: str) -> int:
    """A whole number as a person types it on every front end: ASCII digits with a sign
    (``-0``, ``+12``, ``0042``), or ``0x``, ``0b``, ``0o`` (``_`` between digits allowed
    there), spaces around. ValueError naming the text for anything else: digits of other
    scripts (``'\u0661\u0662'``), an exponent (``1e3``), a decimal point, ``_`` between
    decimal digits, empty text."""
    stripped = text.strip()
    odd = _beyond_ascii(stripped)
    if odd is not None:
        raise ValueError(odd)
    low = stripped.lower()
    digits = low.lstrip("+-")
    if _WHOLE.fullmatch(low) is None or low.endswith("_") or digits[2:3] == "_":
        raise _refused("not a whole number", text)
    base_digits = digits[2:] if digits.startswith(_PREFIXES) else digits
    too_long = _too_long("not a whole number", text, base_digits)
    if too_long is not None:
        raise too_long
    if digits.startswith(_PREFIXES):
        return int(stripped.replace("_", ""), 0)
    return int(stripped, 10)


def read_otherwise(text: str) -> bool:
    """Whether a whole number typed as ``text`` reads as a value written otherwise: one typed
    in another base than ten (``0x10``, ``-0b1``), which a refusal naming the value read
    (``16``) would not name as typed (a sign or a leading zero does not count)."""
    return text.strip().lower().lstrip("+-").startswith(_PREFIXES)


def typed_numbers(given: Iterable[object]) -> dict[int, str]:
    """The whole numbers among ``given`` (all a front end was given at once: text, numbers)
    typed otherwise than they read (:func:`read_otherwise`), by the value read: ``{65536:
    "0x10000"}``, for :func:`lead_as_typed`. A value also given as it reads (``1`` beside
    ``0x1``) is left out: a refusal naming it would not say which was meant."""
    typed: dict[int, str] = {}
    plain: set[object] = set()
    for text in given:
        if not isinstance(text, str):
            if isinstance(text, int | float | Decimal):  # (a JSON list is no number)
                plain.add(text)
            continue
        try:
            value = typed_number(text)
        except ValueError:  # no number: its own refusal names the text
            continue
        if isinstance(value, int) and read_otherwise(text):
            typed[value] = text.strip()
        else:
            plain.add(value)
    return {value: text for value, text in typed.items() if value not in plain}


def _names(message: str, word: str) -> bool:
    """Whether ``message`` names ``word`` (a number, or text as typed) as a word of its own."""
    return re.search(rf"(?<![\w.-]){re.escape(word)}(?![\w.])", message) is not None


def lead_as_typed(message: str, typed: Mapping[int, str]) -> str:
    """``message`` (a refusal whose words name the values checked, as the machine's and the
    clients' range words do) led by the numbers it names as they were typed, where they read
    otherwise (``typed``: :func:`typed_numbers`): ``0x10000 reads as 65536: PMC start address
    65536 is outside 0..65535``; the words of every front end (the command line, the page).
    A message that names the text typed already has no lead."""
    named = [
        (value, text)
        for value, text in typed.items()
        if _names(message, str(value)) and not _names(message, text)
    ]
    if not named:
        return message
    (value, text), *more = named
    lead = f"{text} reads as {value}" + "".join(f", {t} as {v}" for v, t in more)
    return f"{lead}: {message}"


def macro_number(text: str) -> int:
    """A macro variable's number as a person types it on every front end: a whole number
    (:func:`whole_number`), or as FANUC writes it, ``#100`` (spaces around); ValueError
    naming the text as typed otherwise."""
    rest = text.strip()
    if not rest.startswith("#"):
        return whole_number(text)
    digits = rest[1:]
    if not digits.strip() or digits != digits.lstrip():  # '#', '# 100': no number after it
        raise ValueError(f"not a whole number: {text!r}")
    try:
        return whole_number(digits)
    except ValueError as exc:
        raise ValueError(str(exc).replace(repr(digits), repr(text), 1)) from None


def decimal_number(text: str) -> Decimal:
    """A number as a person types it on every front end: ASCII digits with a sign and a
    decimal point (``-12.5``, ``.5``, ``3.``), spaces around; the digits as typed
    (``"1.50"`` keeps two decimals). ValueError naming the text otherwise: an exponent
    (``1e3``), NaN or infinity, digits of other scripts, empty text."""
    stripped = text.strip()
    odd = _beyond_ascii(stripped)
    if odd is not None:
        raise ValueError(odd)
    if _DECIMAL.fullmatch(stripped) is None:
        pointed = stripped.replace(",", ".")
        if stripped.count(",") == 1 and _DECIMAL.fullmatch(pointed):  # 1,5: a decimal comma
            raise ValueError(f"not a number: {text!r} (the decimal point is '.': {pointed})")
        raise _refused("not a number", text)
    too_long = _too_long("not a number", text, stripped.lstrip("+-"))
    if too_long is not None:
        raise too_long
    return Decimal(stripped)


def decimal_text(value: Decimal) -> str:
    """A number written as every front end writes it, in plain decimals as the CNC screen
    shows it (``-0.000000001``, never ``-1E-9``, nor ``1E+3``): text that
    :func:`decimal_number` reads back."""
    return format(value, "f")


def param_decimals_refused(number: int, value: Decimal) -> str:
    """The refusal of a value with decimals for parameter ``number``, one of no decimals, in
    the words of every front end (clients, command line, page), whether typed or a Decimal."""
    return f"parameter {number} is not a real parameter: {decimal_text(value)} is no integer"


def typed_number(text: str) -> int | Decimal:
    """A number typed where a whole number or a decimal may stand (a parameter's or a macro
    variable's value): ``0x``, ``0b`` or ``0o`` text as :func:`whole_number` (an ``int``),
    anything else as :func:`decimal_number` (a ``Decimal``)."""
    if text.strip().lower().lstrip("+-").startswith(_PREFIXES):
        return whole_number(text)
    return decimal_number(text)


#: Names of the loopback as hosts files give them.
_LOOPBACK_NAMES: Final = frozenset(
    {"localhost", "localhost.", "localhost.localdomain", "ip6-localhost"}
)


def is_loopback(host: str | None) -> bool:
    """Whether ``host`` is a loopback address (``127.x.y.z``, ``::1``, also ``[::1]`` as a URL
    writes it) or a name of the loopback (``localhost``); None, as a URL without a host gives
    it, is not."""
    if host is None:
        return False
    if host.lower() in _LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def os_words(exc: OSError) -> str:
    """What the operating system's refusal ``exc`` says, as every front end writes it: its
    number's words with the first letter in lower case (``no such file or directory``,
    ``connection refused``), never ``[Errno 2] ...``; its own text when it has no number."""
    text = os.strerror(exc.errno) if exc.errno is not None and exc.errno > 0 else ""
    text = text or exc.strerror or str(exc)
    return text[:1].lower() + text[1:] if text else type(exc).__name__


def file_name_unfit(name: str) -> str | None:
    """Why ``name``, typed as the name of a file or a folder, names none: empty (it would read
    as the current folder, which no one means) or holding a NUL (which no system takes in a
    name), in the words of the command line and the Python API; None when it may."""
    if not name.strip():
        return f"an empty name is no file or folder, got {name!r}"
    if "\0" in name:
        return f"a file name holds no NUL character, got {name!r}"
    return None


#: The byte-order mark an editor (Windows Notepad) may write before UTF-8 text.
_BOM: Final = b"\xef\xbb\xbf"


def file_text(raw: bytes) -> str:
    """The text of a file a user wrote (a machine file, a gateway's configuration): UTF-8,
    with or without a byte-order mark; ValueError naming the first byte that is not
    (``not UTF-8 text: byte 0xFF at byte 12 (save the file as UTF-8)``)."""
    skip = len(_BOM) if raw.startswith(_BOM) else 0
    try:
        return raw[skip:].decode("utf-8")
    except UnicodeDecodeError as exc:
        where = skip + exc.start
        bad = raw[where : where + 1].hex().upper()
        raise ValueError(
            f"not UTF-8 text: byte 0x{bad} at byte {where} (save the file as UTF-8)"
        ) from None


def program_file_text(raw: bytes) -> str:
    """The text of a part program's file (``program load``, a machine file's
    ``[[program]] file``): ASCII, after a UTF-8 byte-order mark if any; ValueError naming the
    line of the first character that is not, in the program store's words
    (:func:`program_text_unfit`), or its byte when it starts no UTF-8 character."""
    text = raw.removeprefix(_BOM).decode("utf-8", "surrogateescape")
    why = program_text_unfit(text)
    if why is not None:
        raise ValueError(why)
    return text


def program_text_unfit(text: str) -> str | None:
    """Why ``text`` is no program text, in the program store's words, naming the line of its
    first character beyond ASCII (``line 2: character 'É' (U+00C9) in '(CAFÉ)': a program is
    printable ASCII text``; a byte a file's UTF-8 does not decode, kept as
    ``surrogateescape`` does, as the byte); None when it is ASCII. The words of a file's
    text, of the clients' ``write_program`` and of the machine alike."""
    at = next((i for i, c in enumerate(text) if not c.isascii()), None)
    if at is None:
        return None
    start = text.rfind("\n", 0, at) + 1
    end = text.find("\n", at)
    line = text[start : len(text) if end < 0 else end]
    shown = line.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    shown = shown.strip()[:40]
    where = f"line {text.count(chr(10), 0, at) + 1}"
    char = text[at]
    if "\udc80" <= char <= "\udcff":  # a byte that starts no UTF-8 character
        what = f"byte 0x{ord(char) - 0xDC00:02X} in '{shown}' is not text"
    else:
        what = f"character {char!r} (U+{ord(char):04X}) in {shown!r}"
    return f"{where}: {what}: a program is printable ASCII text"


def os_reason(exc: BaseException) -> str:
    """What an operating system error says, as text: ``connection reset by peer``,
    ``connection refused``, ``name or service not known`` (never ``[Errno 104] ...`` or the
    address tuple asyncio adds); an end of stream is ``the peer closed the connection``."""
    if isinstance(exc, asyncio.IncompleteReadError):
        return "the peer closed the connection"
    text = str(exc)
    if isinstance(exc, OSError) and not isinstance(exc, ssl.SSLError):
        if not (isinstance(exc, socket.gaierror) and exc.strerror):
            return os_words(exc)
        text = exc.strerror
    if not text:
        return type(exc).__name__
    return text[:1].lower() + text[1:]
