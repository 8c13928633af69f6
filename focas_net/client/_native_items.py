"""What the native client decodes from answer blocks, and its parameter and diagnostic calls.

:class:`NativeItems` is the part of :class:`~focas_net.client.NativeClient` that reads and
writes parameters and diagnostics (``cnc_rdparam``, ``cnc_diagnoss``, ``cnc_wrparam``: the
primitives of :class:`~focas_net.client._composite.CompositeCalls` on FOCAS/2); the functions
turn an answer block into its value, an EW code into :class:`CncError`.
"""

# Every call takes a per-call ``timeout=`` by contract, so ASYNC109 does not apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import contextlib
import struct
from collections.abc import AsyncIterator, Callable
from decimal import Decimal
from typing import Any, Final, TypeVar

from focas_net.errors import EW, CncError, PayloadError, ProtocolError

from ..native import (
    CommandSet,
    DiagType,
    ItemRecord,
    ItemValues,
    LibraryCall,
    ParamInfo,
    ParamInfo3,
    ParamType,
    ResponseBlock,
    ScaledItemRecord,
    ScaledItemValues,
    ScaledNumber,
    calls,
    info,
)
from ..protocol import ParamDataType, ParamValue
from ._failures import native_call_text, undecodable_error
from ._native_link import Handle, NativeLink, check_axis_of
from ._values import (
    REAL_WIDTH,
    bits_shaped,
    byte_to_wire,
    check_item,
    int_to_wire,
    param_int,
    real_to_wire,
    width_refused,
)

__all__: list[str] = []

_T = TypeVar("_T")

_PARAM_WIDTH: Final[dict[int, int]] = {
    ParamType.BIT: 1,
    ParamType.BYTE: 1,
    ParamType.WORD: 2,
    ParamType.TWO_WORD: 4,
}
_DIAG_WIDTH: Final[dict[int, int]] = {0: 1, 1: 2, 2: 4, 3: 1, 4: 1}
#: The builder of each item read's call.
_READS: Final[dict[str, Callable[[CommandSet, int, int], LibraryCall]]] = {
    "cnc_rdparam": calls.cnc_rdparam,
    "cnc_diagnoss": calls.cnc_diagnoss,
    "cnc_rdset": info.cnc_rdset,
}
#: What :func:`made_once` finds when nothing was made for an answer yet.
_NOT_MADE: Final[Any] = object()


def only_answer(handle: Handle, call: LibraryCall, blocks: tuple[ResponseBlock, ...]) -> Any:
    """The decoded answer of ``call``, a call of one frame of one block, on ``handle``."""
    return decoded(handle, call, blocks, 0, handle.max_axes)


def made_once(
    handle: Handle,
    call: LibraryCall,
    blocks: tuple[ResponseBlock, ...],
    make: Callable[[Handle, LibraryCall, tuple[ResponseBlock, ...], int], _T],
    path: int = 1,
) -> _T:
    """``make(handle, call, blocks, path)``, the result of a call of one frame on ``path``,
    made once for the same answer on a handle of the same axes (kept in
    :attr:`LibraryCall.results`): a poll whose answer repeats decodes nothing again."""
    axes = handle.axes_on(path)
    if len(blocks) == 1:
        block = blocks[0]
        key: tuple[object, ...] = (handle.max_axes, axes, block.ew, block.data)
    else:
        key = (handle.max_axes, axes, *[(b.ew, b.data) for b in blocks])
    results = call.results
    made: _T = results.get(key, _NOT_MADE)
    if made is _NOT_MADE:
        made = make(handle, call, blocks, path)  # (what it raises is raised, nothing kept)
        results.put(key, made)
    return made


def block_data(block: ResponseBlock, function: str) -> bytes:
    """The data of ``block``; :class:`CncError` for its EW code."""
    if block.ew:
        raise CncError.from_ew(block.ew, function)
    return block.data


def decoded(
    handle: Handle,
    call: LibraryCall,
    blocks: tuple[ResponseBlock, ...],
    index: int,
    max_axes: int,
    frame: int = 0,
) -> Any:
    """The answer in ``blocks[index]`` to request ``index`` of frame ``frame`` of ``call``
    on ``handle`` (decoded once for the same bytes, :meth:`LibraryCall.answer`);
    :class:`CncError` for its EW code, :class:`PayloadError` naming the peer and the call
    for data that does not decode."""
    data = block_data(blocks[index], call.function)
    try:
        return call.answer(frame, index, data, max_axes)
    except (ProtocolError, ValueError, struct.error) as exc:
        command = call.frames[frame][index].COMMAND
        raise undecodable_error(
            handle.peer, native_call_text(call.function, command), exc
        ) from None


def text(raw: bytes | str) -> str:
    if isinstance(raw, str):
        return raw.rstrip("\x00")
    return raw.split(b"\x00", 1)[0].decode("latin-1")


def axis_name(entry: bytes) -> str:
    """The axis name of a 4-byte name entry as the control's screen shows it: the name
    character and its suffix (parameter 3131's subscript: ``X`` and ``1`` give ``X1``, the
    name the packed protocol gives), a NUL or a space in either left out."""
    return entry[:2].replace(b"\x00", b"").decode("latin-1").replace(" ", "")


def signed(raw: int, width: int) -> int:
    """The signed integer of the ``8 * width`` bits of ``raw``."""
    bits = 8 * width
    raw &= (1 << bits) - 1
    return raw - (1 << bits) if raw >= 1 << (bits - 1) else raw


class NativeItems(NativeLink):
    """Parameters and diagnostics over FOCAS/2 (see the module docstring)."""

    _transport = "native"

    def _init_items(self) -> None:
        #: The type word (0 bit .. 4 real) of each parameter read or written.
        self._param_types: dict[int, int] = {}

    # -- parameters and diagnostics ------------------------------------------------------
    async def _read_item(
        self,
        number: int,
        axis: int,
        deadline: float | None,
        path: int,
        *,
        diagnostic: bool,
        setting: bool = False,
    ) -> ParamValue:
        """``cnc_rdparam``, ``cnc_diagnoss`` or (``setting``) ``cnc_rdset`` of a checked number
        and axis as a :class:`ParamValue` (setting data are read as parameters)."""
        function = "cnc_diagnoss" if diagnostic else "cnc_rdset" if setting else "cnc_rdparam"
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis, function, path)
        build = _READS[function]
        call = build(handle.command_set, number, axis)
        (block,) = await self._exchange(handle, call, deadline, 0, path)
        items: ItemValues | ScaledItemValues = decoded(handle, call, (block,), 0, handle.max_axes)
        if not items.records:
            raise PayloadError(f"{function}: answer for {number} carries no record")
        record = items.records[0]
        if not diagnostic and not setting:
            self._param_types[number] = record.type
        if record.type == (DiagType.REAL if diagnostic else ParamType.REAL):
            # REALPRM: (mantissa, 10, decimals)
            if isinstance(record, ItemRecord):
                reals = record.reals()
                if not reals:
                    raise PayloadError(f"{function}: real record of {number} has one slot")
                value = reals[0]
            else:
                value = record.values[0]
            return ParamValue(number, axis, value.mantissa, REAL_WIDTH, value.decimals)
        width = (_DIAG_WIDTH if diagnostic else _PARAM_WIDTH).get(record.type)
        if width is None:
            raise PayloadError(f"{function}: {number} has type {record.type}, which has no value")
        first = record.values[0]
        raw = first.mantissa if isinstance(first, ScaledNumber) else first
        return ParamValue(number, axis, signed(raw, width), width)

    async def _read_param_value(
        self, number: int, axis: int, deadline: float | None, path: int
    ) -> ParamValue:
        value = await self._read_item(number, axis, deadline, path, diagnostic=False)
        self._param_widths[number] = value.width
        return value

    async def _is_bit(self, number: int, value: ParamValue, deadline: float | None) -> bool:
        return self._param_types.get(number) == ParamType.BIT

    async def read_param_type(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> ParamDataType | None:
        """The data type of parameter ``number`` (bit, byte, word, two-word, real) from the
        type word of its ``cnc_rdparam`` record, None for a word FANUC does not number (an
        axis parameter needs its ``axis``).

        This stands in for the packed client's ``read_param_attributes``: FOCAS/2's
        ``cnc_rdparainfo`` answer has the type in two bits (no real type), and no decimals or
        range, while the record of ``cnc_rdparam`` names all five types."""
        check_item(number, axis, "parameter")
        p = self._path_of(path)
        await self._read_param_value(number, axis, self._deadline(timeout), p)
        ptype = self._param_types[number]
        return ParamDataType(ptype) if ptype in ParamDataType._value2member_map_ else None

    async def read_diag(
        self,
        number: int,
        *,
        axis: int = 0,
        path: int | None = None,
        timeout: float | None = None,
    ) -> int:
        """``cnc_diagnoss``: the value of diagnostic ``number``."""
        check_item(number, axis, "diagnostic")
        p = self._path_of(path)
        deadline = self._deadline(timeout)
        value = await self._read_item(number, axis, deadline, p, diagnostic=True)
        return value.value

    async def _param_info(
        self, handle: Handle, number: int, deadline: float | None, path: int
    ) -> tuple[int, int]:
        """The first frame of ``cnc_wrparam``: the type word and the width of the first
        parameter from ``number`` on, as the library reads them (the next one's when the CNC
        lacks ``number``; the answer's number word is not relied on: in the 30i set its place
        is not known)."""
        call = calls.wrparam_info(handle.command_set, number)
        (block,) = await self._exchange(handle, call, deadline, 0, path)
        info = decoded(handle, call, (block,), 0, handle.max_axes)
        if isinstance(info, ParamInfo3):
            ptype = info.type
        else:
            assert isinstance(info, ParamInfo)
            ptype = info.entries[0].attribute & 3 if info.entries else 0
        size = REAL_WIDTH if ptype == ParamType.REAL else _PARAM_WIDTH.get(ptype)
        if size is None:
            raise PayloadError(f"cnc_wrparam: {number} has type {ptype}, which has no value")
        return ptype, size

    async def _lacks(self, number: int, axis: int, deadline: float | None, path: int) -> bool:
        """Whether the CNC has no parameter ``number``: its read answers EW_NUMBER."""
        try:
            await self._read_item(number, axis, deadline, path, diagnostic=False)
        except CncError as exc:
            return exc.ew == EW.NUMBER
        return False

    @contextlib.asynccontextmanager
    async def _absent_first(
        self, number: int, axis: int, deadline: float | None, path: int
    ) -> AsyncIterator[None]:
        """A write's refusal by the information's type or width (raised in the block) is
        EW_NUMBER when the CNC has no parameter ``number``, whose information is then the next
        parameter's: the refusal is the CNC's answer to the write (EW_NUMBER), never a value
        judged by another parameter's type."""
        try:
            yield
        except (ValueError, CncError):
            if await self._lacks(number, axis, deadline, path):
                raise CncError.from_ew(EW.NUMBER, "cnc_wrparam") from None
            raise

    async def _write_param(
        self,
        number: int,
        value: int | Decimal | str,
        axis: int,
        width: int | None,
        deadline: float | None,
        path: int,
    ) -> None:
        # both readings of the value, before anything is sent: one is refused only if the
        # parameter's type turns out to be the one it does not fit (a value neither reading
        # takes too, in the words of that type, as the packed client refuses it)
        as_int: int | ValueError
        as_real: tuple[int, int] | ValueError
        try:
            as_int = param_int(number, value)
        except ValueError as exc:
            as_int = exc
        try:
            as_real = real_to_wire(number, value)
        except ValueError as exc:
            as_real = exc
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis, "cnc_wrparam", path)
        ptype, size = await self._param_info(handle, number, deadline, path)
        async with self._absent_first(number, axis, deadline, path):
            self._check_width(number, size, width)
            record = self._value_record(handle, number, axis, ptype, size, value, as_int, as_real)
        await self._write_record(handle, record, deadline, path)
        self._param_types[number] = ptype

    def _check_width(self, number: int, size: int, width: int | None) -> None:
        """EW_LENGTH (nothing written) when the caller's ``width`` is not the type's, as the
        library answers; the width learnt is forgotten."""
        if width is not None and width != size:
            self._param_widths.pop(number, None)
            raise width_refused(number, size, width)

    def _value_record(
        self,
        handle: Handle,
        number: int,
        axis: int,
        ptype: int,
        size: int,
        value: int | Decimal | str,
        as_int: int | ValueError,
        as_real: tuple[int, int] | ValueError,
    ) -> ItemRecord | ScaledItemRecord:
        """The write record of ``value`` for a parameter of type word ``ptype``: the reading
        of the value that fits the type, or its refusal."""
        if ptype == ParamType.REAL:
            if isinstance(as_real, ValueError):
                raise as_real
            return self._param_record(handle, number, axis, ptype, *as_real)
        kind = ParamDataType.BIT if ptype == ParamType.BIT else None
        if kind is not None and isinstance(value, str) and bits_shaped(value):
            as_int = param_int(number, value, kind)  # "1011_0000": the bits, or their words
        if isinstance(as_int, ValueError):
            if not isinstance(as_real, ValueError) and (
                handle.command_set is CommandSet.FS16I and ptype == ParamType.BIT
            ):
                # a value with decimals travels as a REALPRM, 8 bytes: the information of the
                # 16i set gives a real parameter as a bit one, and the library answers
                # EW_LENGTH, nothing written (the set cannot write a real one)
                raise width_refused(number, size, REAL_WIDTH, " (a value with decimals)")
            # a parameter the information names: refused as the packed client does
            raise as_int
        if kind is not None:
            as_int = param_int(number, value, kind)  # "00000011": the bits
        raw = signed(int_to_wire(number, as_int, size, kind), size)
        return self._param_record(handle, number, axis, ptype, raw)

    async def _write_param_bits(
        self, number: int, axis: int, bits: int, width: int, deadline: float | None, path: int
    ) -> None:
        handle = self._handle_now() or await self._handle_for(deadline)
        check_axis_of(handle, axis, "cnc_wrparam", path)
        ptype, size = await self._param_info(handle, number, deadline, path)
        async with self._absent_first(number, axis, deadline, path):
            self._check_width(number, size, width)
        raw = byte_to_wire(number, bits, ParamDataType.BIT) if ptype == ParamType.BIT else bits
        record = self._param_record(handle, number, axis, ptype, signed(raw, width))
        await self._write_record(handle, record, deadline, path)
        self._param_types[number] = ptype

    async def _write_record(
        self,
        handle: Handle,
        record: ItemRecord | ScaledItemRecord,
        deadline: float | None,
        path: int,
    ) -> None:
        """The second frame of ``cnc_wrparam``: the write of ``record``."""
        call = calls.cnc_wrparam(handle.command_set, record)
        (done,) = await self._exchange(handle, call, deadline, 1, path)
        block_data(done, "cnc_wrparam")

    @staticmethod
    def _param_record(
        handle: Handle, number: int, axis: int, ptype: int, value: int, decimals: int | None = None
    ) -> ItemRecord | ScaledItemRecord:
        """The write record, slot 0 holding ``value`` (a real one's mantissa with
        ``decimals``) and the other slots what the previous write left there (the library's
        buffer)."""
        if handle.command_set is CommandSet.FS16I:
            slots = handle.param_slots
            slots[0] = value
            return ItemRecord(number, axis, ptype, tuple(slots))
        scaled = handle.param3_slots
        scaled[0] = (
            ScaledNumber(value, -1, 0) if decimals is None else ScaledNumber(value, decimals, 10)
        )
        return ScaledItemRecord(number, axis, ptype, tuple(scaled))
