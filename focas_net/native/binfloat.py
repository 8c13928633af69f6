"""The base-2 macro record of 16i-class controls, converted exactly as FANUC's library does.

A macro variable travels as an 8-byte record ``i32 mantissa, i16 base, i16 decimals``. With
base 10 the value is ``mantissa / 10**decimals`` and FANUC's library passes the pair through
unchanged. With any other base (2 in practice) the record is a **binary number**: the value is
``mantissa / 2**decimals``, with the mantissa normalised to ``2**30 <= |mantissa| < 2**31``.

* ``cnc_wrmacro`` on a 16i-class handle (open answer version <= 2) sends the caller's
  ``(mcr_val, dec_val)`` as such a binary record: 12.345 given as (12345, 3) goes out as
  ``62C28F5C 0002 001B``. :func:`decimal_to_binary` computes it.
* ``cnc_rdmacro`` on any handle turns a received binary record into ``(mcr_val, dec_val)``
  with nine significant digits: ``62C28F5C 0002 001B`` comes back as (123450000, 7).
  :func:`binary_to_decimal` computes it.

The library does both with its own 32-bit binary floating point, whose multiply, divide and
add truncate, so the results are not the correctly rounded ones (2**-10 reads back as
976563000 with 12 decimals, not 976562500). The functions here reproduce that arithmetic step
for step, so they agree with the library bit for bit (checked against libfwlib32 1.0.5 over
the captured cases in ``tests/data/fwlib_float.json``).
"""

from __future__ import annotations

from typing import Final, NamedTuple

__all__ = ["binary_to_decimal", "decimal_to_binary"]

_TWO31: Final = 1 << 31
_TWO32: Final = 1 << 32
_TWO63: Final = 1 << 63
_TWO64: Final = 1 << 64
_POW10: Final = tuple(10**i for i in range(10))


def _i32(x: int) -> int:
    return ((x + _TWO31) % _TWO32) - _TWO31


def _i64(x: int) -> int:
    return ((x + _TWO63) % _TWO64) - _TWO63


def _halve(x: int) -> int:
    """Half of a 32-bit integer, rounded toward zero."""
    return _i32((x + 1 if x < 0 else x) >> 1)


def _div_toward_zero(a: int, b: int) -> int:
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


class _Bin(NamedTuple):
    """A binary float: value = ``m * 2**-e``, ``m`` a 32-bit integer kept with
    ``|m| >= 2**30`` (or ``-2**31``), zero as (0, 0)."""

    m: int
    e: int

    @classmethod
    def normal(cls, m: int, e: int) -> _Bin:
        m = _i32(m)
        if m == 0:
            return _ZERO
        while _i32(m + (1 << 30)) >= 0:
            m = _i32(2 * m)
            e += 1
        return cls(m, e)

    @classmethod
    def of(cls, n: int) -> _Bin:
        return cls.normal(n, 0)

    def __mul__(self, other: object) -> _Bin:
        assert isinstance(other, _Bin)
        product = self.m * other.m
        if product >> 32 == 0:
            return _ZERO
        e = self.e + other.e - 32
        while _i64(product + (1 << 62)) >= 0:
            product = _i64(2 * product)
            e += 1
        return _Bin.normal(product >> 32, e)

    def __truediv__(self, other: object) -> _Bin:
        assert isinstance(other, _Bin)
        if other.m == 0:
            return self
        e = self.e - other.e
        num = self.m << 32
        if abs(self.m) < abs(other.m):
            num >>= 1
            e += 31
        else:
            num = _div_toward_zero(num, 4)
            e += 30
        return _Bin.normal(_i32(_div_toward_zero(num, other.m)), e)

    def __add__(self, other: object) -> _Bin:
        assert isinstance(other, _Bin)
        if other.m == 0:
            return self
        if self.m == 0:
            return other
        shift = self.e - other.e
        if shift > 31:
            return other
        if shift < -31:
            return self
        a, b = self.m, other.m
        if shift >= 0:
            for _ in range(shift):
                a = _halve(a)
            e = other.e
        else:
            for _ in range(-shift):
                b = _halve(b)
            e = self.e
        total = a + b
        if not -_TWO31 <= total < _TWO31:
            total = _div_toward_zero(total, 2)
            e -= 1
        return _Bin.normal(total, e)

    def at_least(self, other: _Bin) -> bool:
        """``self >= other`` as the library compares two normal values."""
        if other.m == 0:
            return self.m >= 0
        if other.m > 0:
            if self.m <= 0:
                return False
            return other.e > self.e if self.e != other.e else self.m >= other.m
        if self.m >= 0:
            return True
        return self.e >= other.e if self.e != other.e else self.m >= other.m

    def integer(self) -> int:
        """The integer part (toward zero); saturated when far out of range."""
        m, e = self.m, self.e
        if e > 31:
            return m >> 31
        if e < -31:
            return _i32((m % _TWO32 >> 31) + _TWO31 - 1)
        if e > 0:
            for _ in range(e):
                m = _halve(m)
        else:
            for _ in range(-e):
                m = _i32(2 * m)
        return m


_ZERO: Final = _Bin(0, 0)
_BILLION: Final = _Bin.of(10**9)  # (0x77359400, 1)
_BILLIONTH: Final = _Bin(0x44B82FA0, 60)  # 10**-9, truncated
_HALF: Final = _Bin(0x40000000, 31)


def decimal_to_binary(mcr_val: int, dec_val: int) -> tuple[int, int]:
    """The binary record ``(mantissa, exponent)`` FANUC's library sends for the macro value
    ``mcr_val / 10**dec_val`` on a 16i-class handle (the record's base word is 2).

    12.345 = (12345, 3) -> (0x62C28F5C, 27); -2.5 = (-25, 1) -> (-0x50000000, 29);
    100 = (100, 0) -> (0x64000000, 24). Zero keeps its decimals: (0, 3) -> (0, 3).
    """
    value = _Bin.of(mcr_val)
    if value.m == 0:
        return (0, dec_val)
    if dec_val == 0:
        return (value.m, value.e)
    if 0 < dec_val <= 9:
        value = value / _Bin.of(_POW10[dec_val])
        return (value.m, value.e)
    if dec_val < -9:
        while True:
            dec_val += 9
            value = value * _BILLION
            if dec_val >= -9:
                break
    elif dec_val > 9:
        while True:
            value = value * _BILLIONTH
            dec_val -= 9
            if dec_val < 0:
                break
    value = value * _Bin.of(_POW10[-dec_val])
    return (value.m, value.e)


def binary_to_decimal(mantissa: int, exponent: int) -> tuple[int, int]:
    """The ``(mcr_val, dec_val)`` FANUC's library reports for a received binary record
    ``mantissa / 2**exponent`` (any base word other than 10): nine significant digits.

    (0x62C28F5C, 27) -> (123450000, 7); (0x40000000, 30) = 1.0 -> (100000000, 8);
    (0x40000000, 0) -> (107374182, -1). A zero mantissa keeps its exponent as decimals.
    """
    mantissa = _i32(mantissa)
    if mantissa == 0:
        return (0, exponent)
    x = _Bin.normal(mantissa, exponent)
    negative = x.m < 0
    if negative:
        x = _Bin(0x40000000, x.e - 1) if x.m == -_TWO31 else _Bin(-x.m, x.e)
    below_one = x.e > 30
    decimals = 0
    scaled_up = 0
    while x.e > 30:
        x = x * _BILLION
        decimals += 9
        scaled_up += 1
    while x.at_least(_BILLION):
        x = x * _BILLIONTH
        decimals -= 9
    whole = x.integer()
    digits = 1
    while digits < 9 and whole >= _POW10[digits]:
        digits += 1
    if below_one:
        for _ in range(scaled_up):
            x = x + _HALF
        x = _Bin.of(x.integer())
    shift = 9 - digits
    decimals += shift
    x = x * _Bin.of(_POW10[shift])
    if not below_one:
        x = x + _HALF
    result = x.integer()
    if result == 10**9:
        result = 10**8
        decimals -= 1
    return (-result if negative else result, decimals)
