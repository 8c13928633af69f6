"""Custom macro B expressions: their syntax tree, the parser over a block's text and the
evaluation with FANUC's rules for vacant variables.

Values are ``float``; ``None`` is the vacant value (``#0``, or a variable never set). A bare
variable keeps its vacancy (``#2 = #1`` copies it); any operation reads a vacant operand as 0;
``EQ`` and ``NE`` tell vacant from 0, the other comparisons do not. Trigonometric functions
work in degrees; ``ASIN`` answers 270..90 and two-argument ``ATAN`` (``ATAN[a]/[b]``, or the
30i's ``ATAN[a,b]``) 0..360, as with FANUC's parameter 6004#0 NAT = 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final, Protocol

from .alarms import AlarmRaised, number_text

__all__ = [
    "MACRO_FUNCTIONS",
    "MemoryVariables",
    "NcVariables",
    "VariableRefused",
]

Value = float | None

#: The functions an expression may call.
MACRO_FUNCTIONS: Final = (
    "ASIN",
    "ACOS",
    "ATAN",
    "SIN",
    "COS",
    "TAN",
    "SQRT",
    "ABS",
    "ROUND",
    "BIN",
    "BCD",
    "FIX",
    "FUP",
    "LN",
    "EXP",
)
_COMPARISONS: Final = ("EQ", "NE", "GT", "GE", "LT", "LE")
#: Deepest bracket nesting a CNC accepts (PS0118 beyond).
MAX_BRACKETS: Final = 5
#: Largest magnitude a macro value may reach (PS0111 beyond).
MAX_VALUE: Final = 1e47


class VariableRefused(Exception):
    """Raised by an :class:`NcVariables` implementation: ``alarm`` is 115 (no such variable)
    or 116 (the variable may not be written)."""

    def __init__(self, alarm: int, detail: str = "") -> None:
        super().__init__(detail)
        self.alarm = alarm


class NcVariables(Protocol):
    """The variables the interpreter does not own (common #500-#999, system variables): the
    machine implements these two calls; either may raise :class:`VariableRefused`."""

    def read_variable(self, number: int) -> float | None: ...

    def write_variable(self, number: int, value: float | None) -> None: ...


class MemoryVariables:
    """A stand-alone :class:`NcVariables`: #500-#999 kept in memory, any other number
    refused with PS0115."""

    def __init__(self) -> None:
        self.values: dict[int, float | None] = {}

    def read_variable(self, number: int) -> float | None:
        if 500 <= number <= 999:
            return self.values.get(number)
        raise VariableRefused(115, f"#{number}")

    def write_variable(self, number: int, value: float | None) -> None:
        if 500 <= number <= 999:
            self.values[number] = value
            return
        raise VariableRefused(115, f"#{number}")


# --- syntax tree -------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Num:
    value: float


@dataclass(frozen=True, slots=True)
class Var:
    index: Expr


@dataclass(frozen=True, slots=True)
class Neg:
    operand: Expr


@dataclass(frozen=True, slots=True)
class BinOp:
    op: str
    left: Expr
    right: Expr


@dataclass(frozen=True, slots=True)
class Call:
    name: str
    args: tuple[Expr, ...]


Expr = Num | Var | Neg | BinOp | Call


# --- parser ------------------------------------------------------------------------------


class Cursor:
    """A position in a block's text (spaces and comments already removed, upper case)."""

    __slots__ = ("depth", "pos", "text")

    def __init__(self, text: str, pos: int = 0) -> None:
        self.text = text
        self.pos = pos
        self.depth = 0

    def peek(self) -> str:
        return self.text[self.pos] if self.pos < len(self.text) else ""

    def at(self, word: str) -> bool:
        return self.text.startswith(word, self.pos)

    def take(self, word: str) -> bool:
        if self.text.startswith(word, self.pos):
            self.pos += len(word)
            return True
        return False

    def expect(self, word: str) -> None:
        if not self.take(word):
            rest = self.text[self.pos :] or "the end of the block"
            raise AlarmRaised(114, f"expected {word!r} at {rest!r}")

    def done(self) -> bool:
        return self.pos >= len(self.text)


def parse_number(cur: Cursor) -> tuple[float, bool, int]:
    """An unsigned literal: (value, whether it had a decimal point, digits)."""
    start = cur.pos
    digits = 0
    point = False
    while not cur.done():
        c = cur.peek()
        if c.isdigit():
            digits += 1
        elif c == "." and not point:
            point = True
        else:
            break
        cur.pos += 1
    text = cur.text[start : cur.pos]
    if digits == 0:
        raise AlarmRaised(5, f"no digits in {text or cur.text[start:]!r}")
    if digits > 9:
        raise AlarmRaised(3, text)
    return float(text), point, digits


def parse_expression(cur: Cursor) -> Expr:
    """A full expression, comparisons included (lowest precedence)."""
    left = _additive(cur)
    for op in _COMPARISONS:
        if cur.take(op):
            return BinOp(op, left, _additive(cur))
    return left


def _additive(cur: Cursor) -> Expr:
    left = _multiplicative(cur)
    while True:
        for op in ("+", "-", "OR", "XOR"):
            if cur.take(op):
                left = BinOp(op, left, _multiplicative(cur))
                break
        else:
            return left


def _multiplicative(cur: Cursor) -> Expr:
    left = _unary(cur)
    while True:
        for op in ("*", "/", "AND", "MOD"):
            if cur.take(op):
                left = BinOp(op, left, _unary(cur))
                break
        else:
            return left


def _unary(cur: Cursor) -> Expr:
    if cur.take("-"):
        return Neg(_unary(cur))
    if cur.take("+"):
        return _unary(cur)
    return _primary(cur)


def bracketed(cur: Cursor) -> Expr:
    """``[ expression ]``."""
    return _arguments(cur, pair=False)[0]


def _arguments(cur: Cursor, *, pair: bool) -> tuple[Expr, Expr | None]:
    """``[a]``, or with ``pair`` also ``[a,b]`` (the 30i's ``ATAN[a,b]``)."""
    cur.expect("[")
    cur.depth += 1
    if cur.depth > MAX_BRACKETS:
        raise AlarmRaised(118, f"more than {MAX_BRACKETS} nested brackets")
    first = parse_expression(cur)
    second = parse_expression(cur) if pair and cur.take(",") else None
    cur.expect("]")
    cur.depth -= 1
    return first, second


def variable(cur: Cursor) -> Var:
    """``#n``, ``#[expr]`` or ``##n`` (the ``#`` already seen is not consumed yet)."""
    cur.expect("#")
    c = cur.peek()
    if c == "[":
        return Var(bracketed(cur))
    if c == "#":
        return Var(variable(cur))
    if c.isdigit():
        value, point, _ = parse_number(cur)
        if point:
            raise AlarmRaised(115, f"#{value} has a decimal point")
        return Var(Num(value))
    raise AlarmRaised(114, f"'#' without a number at {cur.text[cur.pos :]!r}")


def _primary(cur: Cursor) -> Expr:
    c = cur.peek()
    if c == "[":
        return bracketed(cur)
    if c == "#":
        return variable(cur)
    if c.isdigit() or c == ".":
        return Num(parse_number(cur)[0])
    for name in MACRO_FUNCTIONS:
        if cur.take(name):  # ATAN[a]/[b] or ATAN[a,b]: the angle of the point (b, a)
            first, second = _arguments(cur, pair=name == "ATAN")
            if second is None and name == "ATAN" and cur.at("/["):
                cur.pos += 1
                second = bracketed(cur)
            return Call(name, (first,) if second is None else (first, second))
    rest = cur.text[cur.pos :] or "the end of the block"
    raise AlarmRaised(114, f"expected a value at {rest!r}")


# --- evaluation --------------------------------------------------------------------------


Reader = Callable[[int], Value]


def variable_number(value: Value) -> int:
    """The variable a ``#[...]`` names: rounded to an integer, vacant is #0."""
    if value is None:
        return 0
    number = round_fanuc(value)
    if number < 0:
        raise AlarmRaised(115, f"#{number}")
    return number


def round_fanuc(value: float) -> int:
    """Round half away from zero (FANUC's ROUND)."""
    return math.floor(abs(value) + 0.5) * (1 if value >= 0 else -1)


def _z(value: Value) -> float:
    return 0.0 if value is None else value


def evaluate(expr: Expr, read: Reader) -> Value:
    """Evaluate ``expr``; ``read`` answers a variable number. Raises :class:`AlarmRaised`."""
    if isinstance(expr, Num):
        return expr.value
    if isinstance(expr, Var):
        return read(variable_number(evaluate(expr.index, read)))
    if isinstance(expr, Neg):
        return _checked(-_z(evaluate(expr.operand, read)))
    if isinstance(expr, Call):
        args = [_z(evaluate(a, read)) for a in expr.args]
        return _checked(_call(expr.name, args))
    left = evaluate(expr.left, read)
    right = evaluate(expr.right, read)
    op = expr.op
    if op in ("EQ", "NE"):
        same = (left is None and right is None) or (
            left is not None and right is not None and left == right
        )
        return 1.0 if same == (op == "EQ") else 0.0
    a, b = _z(left), _z(right)
    if op in ("GT", "GE", "LT", "LE"):
        result = {"GT": a > b, "GE": a >= b, "LT": a < b, "LE": a <= b}[op]
        return 1.0 if result else 0.0
    if op == "+":
        return _checked(a + b)
    if op == "-":
        return _checked(a - b)
    if op == "*":
        return _checked(a * b)
    if op == "/":
        if b == 0:
            raise AlarmRaised(112, "division by zero")
        return _checked(a / b)
    ia, ib = round_fanuc(a), round_fanuc(b)
    if op == "MOD":
        if ib == 0:
            raise AlarmRaised(112, "MOD by zero")
        return float(int(math.fmod(ia, ib)))
    if op == "AND":
        return float(ia & ib)
    if op == "OR":
        return float(ia | ib)
    return float(ia ^ ib)


def _checked(value: float) -> float:
    if not math.isfinite(value) or abs(value) > MAX_VALUE:
        raise AlarmRaised(111, number_text(value))
    return value


#: The largest value BCD gives (8 decimal digits in 32 bits), and BIN takes.
_BCD_MAX: Final = 99_999_999
_BCD_BITS_MAX: Final = 0x9999_9999


def _bin_bcd(name: str, x: float) -> int:
    """BIN[x]: the BCD value ``x`` (each 4 bits a decimal digit) as a number; BCD[x]: the
    whole number ``x`` as BCD. PS0119 for what they cannot convert."""
    if name == "BCD":
        if x != math.floor(x) or not 0 <= x <= _BCD_MAX:
            raise AlarmRaised(119, f"BCD[{number_text(x)}]: 0..{_BCD_MAX}")
        return int(f"{int(x)}", 16)
    if x != math.floor(x) or not 0 <= x <= _BCD_BITS_MAX:
        raise AlarmRaised(119, f"BIN[{number_text(x)}]: 0..{_BCD_BITS_MAX} (BCD 0..{_BCD_MAX})")
    digits = f"{int(x):x}"
    if not digits.isdigit():
        raise AlarmRaised(
            119, f"BIN[{number_text(x)}]: {int(x)} (0x{digits.upper()}) is no BCD value"
        )
    return int(digits)


def _call(name: str, args: list[float]) -> float:
    x = args[0]
    if name == "SIN":
        return math.sin(math.radians(x))
    if name == "COS":
        return math.cos(math.radians(x))
    if name == "TAN":
        if math.isclose(math.fmod(abs(x), 180.0), 90.0):
            raise AlarmRaised(119, f"TAN[{number_text(x)}]")
        return math.tan(math.radians(x))
    if name in ("ASIN", "ACOS"):
        if not -1.0 <= x <= 1.0:
            raise AlarmRaised(119, f"{name}[{number_text(x)}]")
        if name == "ACOS":
            return math.degrees(math.acos(x))
        angle = math.degrees(math.asin(x))
        return angle + 360.0 if angle < 0 else angle
    if name == "ATAN":
        if len(args) == 2:
            angle = math.degrees(math.atan2(x, args[1]))
        else:
            angle = math.degrees(math.atan(x))
        return angle + 360.0 if angle < 0 else angle
    if name == "SQRT":
        if x < 0:
            raise AlarmRaised(119, f"SQRT[{number_text(x)}]")
        return math.sqrt(x)
    if name == "ABS":
        return abs(x)
    if name == "ROUND":
        return float(round_fanuc(x))
    if name in ("BIN", "BCD"):
        return float(_bin_bcd(name, x))
    if name == "FIX":
        return float(math.trunc(x))
    if name == "FUP":
        return float(math.trunc(x) if x == math.trunc(x) else math.trunc(x) + math.copysign(1, x))
    if name == "LN":
        if x <= 0:
            raise AlarmRaised(119, f"LN[{number_text(x)}]")
        return math.log(x)
    if x > 109:  # EXP beyond ~1e47 overflows the macro range
        raise AlarmRaised(111, f"EXP[{number_text(x)}]")
    return math.exp(x)
