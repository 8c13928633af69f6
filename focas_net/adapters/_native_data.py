"""The native adapter's handlers of values: macro variables, parameters and diagnostics
(``docs/native-protocol.md``; what a handler is: :mod:`focas_net.adapters.native`), and how a
value travels in FANUC's library's numbering.

A block reads and writes as the path in its path word sees the values (0 is path 1): its own
macro variables #100-#199 and system variables, its axes, its value of a path-type parameter;
the machine shares the others. A path the machine has not is the machine's EW_PATH.
"""

from __future__ import annotations

import math
import struct
from bisect import bisect_left, bisect_right
from collections.abc import Callable
from decimal import MAX_EMAX, MAX_PREC, MIN_EMIN, ROUND_HALF_EVEN, Context, Decimal
from typing import Final, Protocol

from focas_net.errors import EW
from focas_net.native import (
    SCALED_SIZE,
    DiagType,
    ItemRecord,
    MacroDouble,
    MacroDoubleReadRequest,
    MacroDoubles,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    MacroWriteRequest,
    ParamInfo,
    ParamInfo3,
    ParamInfo3Request,
    ParamInfoEntry,
    ParamInfoRequest,
    ParamType,
    ParamWrite3Request,
    ParamWriteRequest,
    RequestBlock,
    ScaledItemRecord,
    ScaledNumber,
    binary_to_decimal,
)
from focas_net.sim import MAX_MACRO_DECIMALS, DataItem, Machine, MachineError, ParamKind, Session
from focas_net.sim.machine import MAX_REAL_DECIMALS

from ._common import Refused, need_room
from ._native_cnc import block_path

__all__ = ["DataHandlers", "macro_from_double", "native_diag_type", "native_param_type"]

_I32_MIN: Final = -(2**31)
_I32_MAX: Final = 2**31 - 1
_QUANTA: Final = tuple(Decimal(1).scaleb(-d) for d in range(MAX_MACRO_DECIMALS + 1))
_ITEM_HEAD_SIZE: Final = 8
#: Width in bytes of a value of each 16i/30i parameter type (BIT travels as a byte, REAL as
#: REALPRM).
_PARAM_WIDTHS: Final[dict[int, int]] = {
    ParamType.BIT: 1,
    ParamType.BYTE: 1,
    ParamType.WORD: 2,
    ParamType.TWO_WORD: 4,
    ParamType.REAL: 8,
}
#: Diagnostic type word of each kind (the library reads no bit type in a diagnostic).
_DIAG_TYPES: Final[dict[ParamKind, DiagType]] = {
    ParamKind.BIT: DiagType.BYTE,
    ParamKind.BYTE: DiagType.BYTE,
    ParamKind.WORD: DiagType.WORD,
    ParamKind.TWO_WORD: DiagType.TWO_WORD,
    ParamKind.REAL: DiagType.REAL,
}
#: A context that neither rounds nor overflows: scaling a coefficient by its exponent is exact.
_EXACT: Final = Context(prec=MAX_PREC, Emax=MAX_EMAX, Emin=MIN_EMIN)
_pack_scaled = ScaledNumber.STRUCT.pack
#: An empty value slot of the 30i set: (0, 10, 0).
_SCALED_ZERO: Final = _pack_scaled(0, 10, 0)
_ITEM_HEAD_PACK: Final = struct.Struct(">ihh").pack
_I32_PACK: Final = struct.Struct(">i").pack
_I32_ZERO: Final = bytes(4)


class _ReadItem(Protocol):
    """``Machine.read_param`` or ``Machine.read_diag``."""

    def __call__(self, datano: int, axis: int, *, path: int = 1) -> int: ...


def native_param_type(item: DataItem) -> ParamType:
    """The type word of parameter ``item`` in FANUC's library's numbering (0 bit, 1 byte,
    2 word, 3 two-word, 4 real): its :attr:`~focas_net.sim.DataItem.kind`, which FANUC numbers
    the same way."""
    assert item.kind is not None
    return ParamType(int(item.kind))


def native_diag_type(item: DataItem) -> DiagType:
    """The type word of diagnostic ``item`` in FANUC's library's numbering (0 byte, 1 word,
    2 two-word, 5 real); a bit diagnostic is a byte."""
    assert item.kind is not None
    return _DIAG_TYPES[item.kind]


def macro_from_double(value: float) -> tuple[int, int] | None:
    """``(digits, decimals)`` of the decimal a double written with 0xA8 stands for (the value
    is ``digits / 10**decimals``); None when there is none a macro variable can hold
    (infinite, NaN, or too large for a 32-bit mantissa even with no decimals).

    Rule: take the shortest decimal that reads back as the same double (Python's ``repr``),
    round it half-even to at most 9 decimals, drop decimals (rounding again) until the mantissa
    fits a signed 32-bit integer, then drop trailing zeros. So 100.0 -> (100, 0), 1.5 -> (15, 1),
    0.1 -> (1, 1), 1/3 -> (333333333, 9), 12345.678901234 -> (123456789, 4).
    """
    if not math.isfinite(value) or abs(value) > -_I32_MIN:
        return None
    exact = Decimal(repr(value))
    exponent = exact.as_tuple().exponent
    assert isinstance(exponent, int)
    decimals = min(max(-exponent, 0), MAX_MACRO_DECIMALS)
    while True:
        rounded = exact.quantize(_QUANTA[decimals], rounding=ROUND_HALF_EVEN)
        mantissa = int(rounded.scaleb(decimals))
        if _I32_MIN <= mantissa <= _I32_MAX:
            break
        if decimals == 0:
            return None
        decimals -= 1
    return _trimmed(mantissa, decimals)


def _trimmed(mantissa: int, decimals: int) -> tuple[int, int]:
    while decimals > 0 and mantissa % 10 == 0:
        mantissa //= 10
        decimals -= 1
    return mantissa, decimals


def _acceptable(item: DataItem, value: int, decimals: list[int] | None, i: int) -> bool:
    """Whether the machine takes ``value`` for ``item`` (a real one's mantissa with
    ``decimals[i]`` decimals, rescaled to the item's own exactly), as to its range."""
    if decimals is not None and item.kind is ParamKind.REAL:
        if not 0 <= decimals[i] <= MAX_REAL_DECIMALS:
            return False
        shift = item.decimals - decimals[i]
        if shift >= 0:
            value *= 10**shift
        elif value % 10**-shift:
            return False
        else:
            value //= 10**-shift
    assert item.low is not None and item.high is not None
    return item.low <= value <= item.high


def _macro_parts(value: Decimal | None) -> tuple[int, int]:
    """``(mantissa, decimals)`` of a macro value (a machine's value has 0..9 decimals); vacant
    is ``(0, -1)``."""
    if value is None:
        return 0, -1
    exponent = value.as_tuple()[2]
    assert isinstance(exponent, int)
    return int(value.scaleb(-exponent, _EXACT)), -exponent


def _macro_of_double(value: float) -> Decimal:
    """The value :func:`macro_from_double` makes of ``value``, or ``value`` itself as a decimal
    when there is none (for the machine to refuse with EW_DATA after its other checks)."""
    stored = macro_from_double(value)
    if stored is None:
        return Decimal(repr(value))
    mantissa, decimals = stored
    return Decimal(f"{mantissa}E-{decimals}")


def info_window(
    numbers: tuple[int, ...], first: int, count: int
) -> tuple[int, int, tuple[int, ...]]:
    """The window of a 0x10-layout answer over the ascending ``numbers``: the number before
    ``first`` and the one after the window (0: none), and up to ``count`` numbers from
    ``first`` on; EW_LENGTH for a count below 1, EW_NUMBER with none from ``first`` on."""
    if count < 1:
        raise Refused(EW.LENGTH)
    lo = bisect_left(numbers, first)
    chosen = numbers[lo : lo + count]
    if not chosen:
        raise Refused(EW.NUMBER)
    end = lo + len(chosen)
    return numbers[lo - 1] if lo else 0, numbers[end] if end < len(numbers) else 0, chosen


class DataHandlers:
    """The handlers of the values of one machine (see the module docstring)."""

    __slots__ = ("_diag_numbers", "_param_numbers", "machine", "max_axis")

    def __init__(self, machine: Machine, max_axis: int) -> None:
        self.machine = machine
        #: Value slots per parameter and diagnostic record: the open answer's max axes.
        self.max_axis = max_axis
        self._param_numbers = machine.param_numbers()
        self._diag_numbers = machine.diag_numbers()

    def read_macros(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = MacroReadRequest.from_block(block)
        count = req.last - req.first + 1
        if count < 1:
            raise Refused(EW.LENGTH)
        need_room(SCALED_SIZE * count, room)
        read = self.machine.read_macro
        path = block_path(block)
        parts = []
        for number in range(req.first, req.last + 1):
            mantissa, decimals = _macro_parts(read(number, path=path))
            parts.append(_pack_scaled(mantissa, 10, decimals))  # vacant: (0, -1)
        return b"".join(parts)

    def write_macro(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x16: a base-10 record as it is (decimals -1: vacant); a binary one (the 16i set)
        as the decimal ``cnc_rdmacro`` shows of it, trailing zeros dropped (12.345 sent as
        ``62C28F5C 0002 001B`` is written 12.345)."""
        req = MacroWriteRequest.from_block(block)
        v = req.value
        value: Decimal | None
        if v.vacant:
            value = None
        elif v.binary:
            mantissa, decimals = _trimmed(*binary_to_decimal(v.mantissa, v.decimals))
            value = Decimal(mantissa).scaleb(-decimals)
        else:
            value = Decimal(v.mantissa).scaleb(-v.decimals)
        self.machine.write_macro(req.number, value, path=block_path(block))
        return b""

    def read_macro_doubles(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = MacroDoubleReadRequest.from_block(block)
        if req.count < 1:
            raise Refused(EW.LENGTH)
        need_room(MacroDouble.SIZE * req.count, room)
        read = self.machine.read_macro
        path = block_path(block)
        values: list[float | None] = []
        for number in range(req.first, req.first + req.count):
            value = read(number, path=path)
            if value is None:
                values.append(None)  # a quiet NaN
            else:
                mantissa, decimals = _macro_parts(value)
                values.append(mantissa / 10**decimals)
        return MacroDoubles(tuple(values)).encode()

    def write_macro_double(self, block: RequestBlock, room: int, session: Session) -> bytes:
        req = MacroDoubleWriteRequest.from_block(block)
        value = None if req.value is None else _macro_of_double(req.value)
        self.machine.write_macro(req.number, value, path=block_path(block))
        return b""

    def _items(
        self,
        block: RequestBlock,
        room: int,
        numbers: tuple[int, ...],
        read: _ReadItem,
        item_of: Callable[[int], DataItem | None],
        type_of: Callable[[DataItem], int],
        scaled: bool,
    ) -> bytes:
        """Records of the items ``first..last`` (``axis`` 0, k or -1): 4-byte slots (16i set)
        or 8-byte slots (30i set), ``max_axis`` of them; a real value is ``(mantissa, 10,
        decimals)``, two 4-byte slots or one 8-byte slot."""
        args = block.args
        first, last, axis = args[0], args[1], args[2]
        if last < first:
            raise Refused(EW.LENGTH)
        lo = bisect_left(numbers, first)
        hi = bisect_right(numbers, last)
        if lo == hi:
            raise Refused(EW.NUMBER)
        max_axis = self.max_axis
        slot = SCALED_SIZE if scaled else 4
        path = block_path(block)
        n_axes = len(self.machine.path_info(path).axes)
        # a real record of the 16i set takes two slots per value
        need_room((hi - lo) * (_ITEM_HEAD_SIZE + slot * max(max_axis, 2 * n_axes)), room)
        slots_size = slot * max_axis
        parts: list[bytes] = []
        for number in numbers[lo:hi]:
            if axis == -1:
                try:
                    first_value = read(number, 0, path=path)
                except MachineError as exc:
                    if exc.ew != EW.ATTRIB:
                        raise
                    values = [read(number, a, path=path) for a in range(1, n_axes + 1)]
                    record_axis = -1
                else:
                    values = [first_value]
                    record_axis = 0
            else:
                values = [read(number, axis, path=path)]
                record_axis = axis
            item = item_of(number)
            assert item is not None
            parts.append(_ITEM_HEAD_PACK(number, record_axis, type_of(item)))
            if item.kind is ParamKind.REAL:
                decimals = item.decimals
                data = b"".join(_pack_scaled(v, 10, decimals) for v in values)
            elif scaled:
                data = b"".join(_pack_scaled(v, 10, 0) for v in values)
            else:
                data = b"".join(map(_I32_PACK, values))
            parts.append(data)
            if len(data) < slots_size:  # empty slots: (0, 10, 0) or a zero i32
                empty = _SCALED_ZERO if scaled else _I32_ZERO
                parts.append(empty * ((slots_size - len(data)) // len(empty)))
        return b"".join(parts)

    def read_params(self, block: RequestBlock, room: int, session: Session) -> bytes:
        m = self.machine
        numbers = self._param_numbers
        return self._items(
            block, room, numbers, m.read_param, m.param_item, native_param_type, False
        )

    def read_params_30i(self, block: RequestBlock, room: int, session: Session) -> bytes:
        m = self.machine
        numbers = self._param_numbers
        return self._items(
            block, room, numbers, m.read_param, m.param_item, native_param_type, True
        )

    def read_diags(self, block: RequestBlock, room: int, session: Session) -> bytes:
        m = self.machine
        numbers = self._diag_numbers
        return self._items(block, room, numbers, m.read_diag, m.diag_item, native_diag_type, False)

    def read_diags_30i(self, block: RequestBlock, room: int, session: Session) -> bytes:
        m = self.machine
        numbers = self._diag_numbers
        return self._items(block, room, numbers, m.read_diag, m.diag_item, native_diag_type, True)

    def _info_items(self, first: int, count: int) -> tuple[int, int, list[DataItem]]:
        """``prev, next`` and the parameters from ``first`` on, ``count`` of them."""
        prev_no, next_no, chosen = info_window(self._param_numbers, first, count)
        items = [self.machine.param_item(n) for n in chosen]
        return prev_no, next_no, [i for i in items if i is not None]

    def read_param_info(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x10: ``prev, next``, then per parameter from ``first`` on its number and attribute
        (type in bits 0-1; bit 8, the axis bit, is left 0 as ``cnc_wrparam`` needs)."""
        req = ParamInfoRequest.from_block(block)
        prev_no, next_no, items = self._info_items(req.first, req.count)
        need_room(8 + ParamInfoEntry.SIZE * len(items), room)
        entries = tuple(ParamInfoEntry(i.number, native_param_type(i) & 3) for i in items)
        return ParamInfo(prev_no, next_no, entries).encode()

    def read_param_info_30i(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0xA0: 28 bytes of the parameter ``first``: its type (0..4) and 2 for an axis
        parameter."""
        req = ParamInfo3Request.from_block(block)
        prev_no, next_no, items = self._info_items(req.first, 1)
        item = items[0]
        axis_kind = 2 if item.axis else 0
        return ParamInfo3(
            prev_no, next_no, item.number, native_param_type(item), axis_kind
        ).encode()

    def _write_items(
        self,
        session: Session,
        path: int,
        number: int,
        axis: int,
        ptype: int,
        values: list[int],
        decimals: list[int] | None = None,
    ) -> None:
        """Write parameter ``number`` of ``path`` (``axis`` 0, k or -1 for every axis of the
        path, ``values`` one per slot) given as type ``ptype`` (a real one's mantissas, each
        with its ``decimals``)."""
        m = self.machine
        m.check_writable()
        width = _PARAM_WIDTHS.get(ptype)
        if width is None:
            raise Refused(EW.ATTRIB)
        item = m.param_item(number)
        if item is not None and item.kind is ParamKind.BIT and width == 1:
            values = [v & 0xFF for v in values]  # the byte carries the eight bits #7..#0

        def write(a: int, i: int) -> None:
            d = None if decimals is None else decimals[i]
            m.write_param(session, number, a, values[i], width=width, decimals=d, path=path)

        if axis == -1:
            n = len(m.path_info(path).axes)
            if len(values) < n:
                raise Refused(EW.LENGTH)
            if item is not None and not item.axis:
                write(0, 0)
                return
            # the machine writes one axis at a time: an axis whose value it would refuse is
            # written first, so that a refused write changes no axis
            order = list(range(1, n + 1))
            if item is not None:
                order.sort(key=lambda a: _acceptable(item, values[a - 1], decimals, a - 1))
            for a in order:
                write(a, a - 1)
            return
        if not values:
            raise Refused(EW.LENGTH)
        write(axis, 0)

    def write_param(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x0F: one record with 4-byte slots (16i set). A real value cannot be given in it:
        a REAL record answers EW_LENGTH (as a 1-byte value of a real parameter does)."""
        rec: ItemRecord = ParamWriteRequest.from_block(block).record
        if rec.type == ParamType.REAL:
            self.machine.check_writable()
            raise Refused(EW.LENGTH)
        width = _PARAM_WIDTHS.get(rec.type, 4)
        bits = 8 * width
        values = [((v + (1 << (bits - 1))) % (1 << bits)) - (1 << (bits - 1)) for v in rec.values]
        self._write_items(session, block_path(block), rec.number, rec.axis, rec.type, values)
        return b""

    def write_param_30i(self, block: RequestBlock, room: int, session: Session) -> bytes:
        """0x8E: one record with 8-byte slots (30i set); the mantissa of each slot, and of a
        REAL record the decimals of each slot."""
        rec: ScaledItemRecord = ParamWrite3Request.from_block(block).record
        decimals = None
        if rec.type == ParamType.REAL:
            decimals = [v.decimals for v in rec.values]
        values = [v.mantissa for v in rec.values]
        path = block_path(block)
        self._write_items(session, path, rec.number, rec.axis, rec.type, values, decimals)
        return b""
