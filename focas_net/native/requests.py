"""Typed requests: one frozen dataclass per command, declared once for both sides.

A request class names its ``DEVICE`` and ``COMMAND``, lays out its five arguments in ``ARGS``
(a field name, a constant, or :data:`EXTRA_LENGTH` for the length of the extra bytes), and its
answer type in ``ANSWER``. From that single declaration:

* ``to_block(path)`` builds the block a client sends, ``from_block(block)`` reads it back (a
  field given twice, as in ``(n, n)``, is read from its first place);
* ``decode_answer(data)`` reads the answer block's data (``ANSWER.decode``) and
  ``encode_answer(answer)`` writes it.

The FOCAS functions that send each request are named in its docstring, per command set:
"16i class" (open answer version <= 2) and "30i class" (version >= 3), see :mod:`.opening`.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, ClassVar, Final, Self, cast

from focas_net.errors import EW

from .._memo import Memo
from .base import NativePayloadError
from .blocks import Device, RequestBlock
from .records import (
    AlarmMessages,
    AlarmStatus,
    AxisCount,
    AxisDisplays,
    AxisNames,
    AxisUnits,
    CncId,
    ExecutingProgram,
    HdckStatus,
    ItemHead,
    ItemRecord,
    ItemValues,
    MacroDouble,
    MacroDoubles,
    NativeAlarmHistory,
    NativePmcData,
    NativeProgramNumbers,
    NativeSysInfo,
    NoData,
    ParamInfo,
    ParamInfo3,
    PositionAxisNames,
    ScaledItemRecord,
    ScaledItemValues,
    ScaledNumber,
    ScaledValues,
    SequenceNumber,
    StatInfo,
    TimerValue,
    TmModeStatus,
    _pack_double,
    _unpack_double,
)

__all__ = [
    "EXTRA_LENGTH",
    "REQUEST_TYPES",
    "ActualFeedRequest",
    "ActualSpindleSpeedRequest",
    "AlarmMessageRequest",
    "AlarmStatusRequest",
    "AxisCountRequest",
    "AxisDisplayRequest",
    "AxisNameRequest",
    "AxisUnitRequest",
    "CncIdRequest",
    "Diagnostic3Request",
    "DiagnosticRequest",
    "ExecutingProgramRequest",
    "HdckRequest",
    "MacroDoubleReadRequest",
    "MacroDoubleWriteRequest",
    "MacroReadRequest",
    "MacroWriteRequest",
    "NativeAlarmHistoryRequest",
    "NativeCommand",
    "NativePmcArea",
    "NativePositionKind",
    "NativePositionRequest",
    "NativeRequest",
    "ParamInfo3Request",
    "ParamInfoRequest",
    "ParamRead3Request",
    "ParamReadRequest",
    "ParamWrite3Request",
    "ParamWriteRequest",
    "PmcReadRequest",
    "PmcWriteRequest",
    "ProgramNumberRequest",
    "SequenceNumberRequest",
    "ServoMeterRequest",
    "SpindleLoadRequest",
    "StatInfoRequest",
    "SysInfoRequest",
    "TimerRequest",
    "TmModeRequest",
    "decode_request",
    "resolve_position_kind",
]


class NativeCommand(enum.IntEnum):
    """Command words of the requests this codec declares (the FOCAS functions sending them)."""

    SEARCH = 0x03  # cnc_search / cnc_searcho8 (focas_net.native.programs)
    DELETE = 0x05  # cnc_delete / cnc_deleteo8
    RDPROGDIR = 0x06  # cnc_rdprogdir / cnc_rdprogdir2 / cnc_rdprogdir3
    RDPROGINFO = 0x07  # cnc_rdproginfo
    WRPARAM = 0x0F  # cnc_wrparam, 16i class (after 0x10)
    RDPARAM = 0x0E  # cnc_rdparam, 16i class (4-byte value slots)
    RDPARAINFO = 0x10  # cnc_rdparainfo; cnc_wrparam, 16i class
    RDMACRO = 0x15  # cnc_rdmacro / cnc_rdmacror: scaled numbers
    WRMACRO = 0x16  # cnc_wrmacro: one scaled number (binary at 16i class)
    SYSINFO = 0x18  # cnc_allclibhndl3 (stored for cnc_sysinfo): ODBSYS
    STATINFO = 0x19  # cnc_statinfo: ODBST; cnc_rdposition (16i class)
    ALARM = 0x1A  # cnc_alarm / cnc_alarm2 / cnc_rddynamic2: alarm bits
    RDPRGNUM = 0x1C  # cnc_rdprgnum / cnc_rdprgnumo8 / cnc_rddynamic2
    RDSEQNUM = 0x1D  # cnc_rdseqnum / cnc_rddynamic2
    RDEXECPROG = 0x20  # cnc_rdexecprog (focas_net.native.programs)
    RDALMMSG = 0x23  # cnc_rdalmmsg / cnc_rdalmmsg2: alarm messages
    ACTF = 0x24  # cnc_actf / cnc_rddynamic2: actual feed rate
    ACTS = 0x25  # cnc_acts / cnc_rddynamic2: actual spindle speed
    POSITION = 0x26  # cnc_absolute / machine / relative / distance / rdposition / rddynamic2
    RDDIAG = 0x30  # cnc_diagnoss, 16i class (4-byte value slots)
    RDSPLOAD = 0x40  # cnc_rdspload
    RDSVMETER = 0x56  # cnc_rdsvmeter
    RDALMHISTRY = 0x6C  # cnc_rdalmhistry
    AXIS_UNIT = 0x88  # cnc_rdposition: units
    AXIS_NAME = 0x89  # cnc_rdaxisname / cnc_rdsvmeter / cnc_rdposition: axis names
    RDPARAM3 = 0x8D  # cnc_rdparam, 30i class (8-byte scaled slots)
    WRPARAM3 = 0x8E  # cnc_wrparam, 30i class (after 0xA0)
    RDDIAG3 = 0x93  # cnc_diagnoss, 30i class (8-byte scaled slots)
    STAT_TMMODE = 0x98  # cnc_statinfo: ODBST tmmode
    RDPARAINFO3 = 0xA0  # cnc_wrparam, 30i class
    AXIS_DISPLAY = 0xA3  # cnc_rdposition, 30i class: display flags
    AXIS_COUNT = 0xA4  # cnc_rdposition / cnc_rdspload / cnc_rdsvmeter, 30i class: counts
    RDMACRO_DOUBLE = 0xA7  # cnc_rdmacror2: IEEE doubles
    WRMACRO_DOUBLE = 0xA8  # cnc_wrmacror2: IEEE double
    EXEPRGNAME = 0xCF  # cnc_exeprgname
    STAT_HDCK = 0xE1  # cnc_statinfo: ODBST hdck
    RDCNCID = 0xE8  # cnc_rdcncid
    RDTIMER = 0x120  # cnc_rdtimer
    PMC_RDPMCRNG = 0x8001  # pmc_rdpmcrng (device PMC)
    PMC_WRPMCRNG = 0x8002  # pmc_wrpmcrng (device PMC)


class _ExtraLength:
    """Marker of the argument carrying the length of the extra bytes."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "EXTRA_LENGTH"


#: In ``ARGS``: this argument is the number of extra bytes (the fifth argument of writes).
EXTRA_LENGTH: Final = _ExtraLength()

_ArgSpec = str | int | _ExtraLength

#: (request type, arguments of a block of no extra bytes) -> the typed request it carries.
_READS: Final = Memo(1024)


class NativeRequest:
    """Base of the typed requests: a command with its arguments, as one frozen dataclass.

    Subclasses declare ``COMMAND`` (and ``DEVICE`` when not the CNC), ``ARGS`` and ``ANSWER``;
    a request with extra bytes overrides :meth:`extra` and :meth:`_extra_fields`.
    ``from_block`` raises :class:`NativePayloadError` (with the EW code to answer) when the
    block does not fit.
    """

    __slots__ = ()
    DEVICE: ClassVar[int] = Device.CNC
    COMMAND: ClassVar[int]
    #: The five arguments: a field name, a constant, or :data:`EXTRA_LENGTH`; missing ones are 0.
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ()
    #: The type of the answer data.
    ANSWER: ClassVar[Any] = NoData
    #: Whether the request changes the CNC.
    WRITE: ClassVar[bool] = False

    _arg_places: ClassVar[tuple[tuple[int, str], ...]] = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if len(cls.ARGS) > 5:
            raise TypeError(f"{cls.__name__}.ARGS has more than five arguments")
        places: dict[str, int] = {}
        for i, spec in enumerate(cls.ARGS):
            if isinstance(spec, str):
                places.setdefault(spec, i)
        cls._arg_places = tuple((i, name) for name, i in places.items())

    def args(self) -> tuple[int, int, int, int, int]:
        """The five arguments of the block."""
        out = [0, 0, 0, 0, 0]
        extra_length: int | None = None
        for i, spec in enumerate(self.ARGS):
            if isinstance(spec, str):
                out[i] = getattr(self, spec)
            elif isinstance(spec, _ExtraLength):
                if extra_length is None:
                    extra_length = len(self.extra())
                out[i] = extra_length
            else:
                out[i] = spec
        return (out[0], out[1], out[2], out[3], out[4])

    def extra(self) -> bytes:
        """The extra bytes of the block."""
        return b""

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        """The fields carried by the extra bytes of a received block."""
        return {}

    def to_block(self, path: int = 1) -> RequestBlock:
        """The request block of this request."""
        return RequestBlock(self.DEVICE, path, self.COMMAND, self.args(), self.extra())

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        """The typed request carried by ``block`` (a block of no extra bytes, a read, decodes
        once: the same block is answered with the same immutable request again)."""
        extra = block.extra
        args = block.args
        if not extra:
            known: Self | None = _READS.get((cls, args))
            if known is not None:
                return known
        fields = {name: args[i] for i, name in cls._arg_places}
        fields.update(cls._extra_fields(extra))
        request = cls(**fields)
        if not extra:
            _READS.put((cls, args), request)
        return request

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> Any:
        """The answer data of this request, an ``ANSWER`` (``max_axes``: the slot count of
        multi-record parameter and diagnostic answers, otherwise taken from the length)."""
        return self.ANSWER.decode(data)

    def encode_answer(self, answer: Any) -> bytes:
        """The answer data carrying ``answer`` (the inverse of :meth:`decode_answer`)."""
        data: bytes = cast(Any, answer).encode()
        return data


# --------------------------------------------------------------------------------------------
# Identity, status, programs


@dataclass(frozen=True, slots=True)
class SysInfoRequest(NativeRequest):
    """0x18, no arguments: :class:`NativeSysInfo`. FANUC's library sends one per path while
    connecting (``cnc_allclibhndl3``) and answers ``cnc_sysinfo`` from it [V]."""

    COMMAND: ClassVar[int] = NativeCommand.SYSINFO
    ANSWER: ClassVar[Any] = NativeSysInfo


@dataclass(frozen=True, slots=True)
class StatInfoRequest(NativeRequest):
    """0x19, no arguments: :class:`StatInfo`. ``cnc_statinfo`` sends it with 0xE1 and 0x98;
    ``cnc_rdposition`` (16i class) sends it first and last [V]."""

    COMMAND: ClassVar[int] = NativeCommand.STATINFO
    ANSWER: ClassVar[Any] = StatInfo


@dataclass(frozen=True, slots=True)
class HdckRequest(NativeRequest):
    """0xE1, no arguments: :class:`HdckStatus` (``cnc_statinfo``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.STAT_HDCK
    ANSWER: ClassVar[Any] = HdckStatus


@dataclass(frozen=True, slots=True)
class TmModeRequest(NativeRequest):
    """0x98, no arguments: :class:`TmModeStatus` (``cnc_statinfo``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.STAT_TMMODE
    ANSWER: ClassVar[Any] = TmModeStatus


@dataclass(frozen=True, slots=True)
class CncIdRequest(NativeRequest):
    """0xE8, no arguments: :class:`CncId` (``cnc_rdcncid``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDCNCID
    ANSWER: ClassVar[Any] = CncId


@dataclass(frozen=True, slots=True)
class TimerRequest(NativeRequest):
    """0x120, args ``type``: :class:`TimerValue` (``cnc_rdtimer``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDTIMER
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("type",)
    ANSWER: ClassVar[Any] = TimerValue
    type: int = 0


@dataclass(frozen=True, slots=True)
class ProgramNumberRequest(NativeRequest):
    """0x1C, no arguments: :class:`NativeProgramNumbers` (``cnc_rdprgnum``, ``cnc_rdprgnumo8``,
    ``cnc_rddynamic2``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDPRGNUM
    ANSWER: ClassVar[Any] = NativeProgramNumbers


@dataclass(frozen=True, slots=True)
class SequenceNumberRequest(NativeRequest):
    """0x1D, no arguments: :class:`SequenceNumber` (``cnc_rdseqnum``, ``cnc_rddynamic2``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.RDSEQNUM
    ANSWER: ClassVar[Any] = SequenceNumber


@dataclass(frozen=True, slots=True)
class ExecutingProgramRequest(NativeRequest):
    """0xCF, no arguments: :class:`ExecutingProgram` (``cnc_exeprgname``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.EXEPRGNAME
    ANSWER: ClassVar[Any] = ExecutingProgram


@dataclass(frozen=True, slots=True)
class ActualFeedRequest(NativeRequest):
    """0x24, no arguments: one :class:`ScaledNumber` (``cnc_actf``, ``cnc_rddynamic2``; the
    library takes the mantissa) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.ACTF
    ANSWER: ClassVar[Any] = ScaledValues


@dataclass(frozen=True, slots=True)
class ActualSpindleSpeedRequest(NativeRequest):
    """0x25, no arguments: one :class:`ScaledNumber` (``cnc_acts``, ``cnc_rddynamic2``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.ACTS
    ANSWER: ClassVar[Any] = ScaledValues


# --------------------------------------------------------------------------------------------
# Alarms


@dataclass(frozen=True, slots=True)
class AlarmStatusRequest(NativeRequest):
    """0x1A, no arguments: :class:`AlarmStatus` (``cnc_alarm``, ``cnc_alarm2``,
    ``cnc_rddynamic2``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.ALARM
    ANSWER: ClassVar[Any] = AlarmStatus


@dataclass(frozen=True, slots=True)
class AlarmMessageRequest(NativeRequest):
    """0x23, args ``alarm_type, count, text_mode, text_length`` (``cnc_rdalmmsg`` sends
    ``(type, count, 2, 32)``, ``cnc_rdalmmsg2`` ``(type, count, 2, 64)``) [V].

    ``alarm_type`` -1 for every type; ``count`` the most entries wanted; the text is filled only
    when ``text_mode`` is non-zero; every entry carries a text field of ``text_length`` bytes.
    Answered with :class:`AlarmMessages`.
    """

    COMMAND: ClassVar[int] = NativeCommand.RDALMMSG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("alarm_type", "count", "text_mode", "text_length")
    ANSWER: ClassVar[Any] = AlarmMessages
    alarm_type: int = -1
    count: int = 10
    text_mode: int = 2
    text_length: int = 64

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> AlarmMessages:
        if self.text_length < 0:
            raise NativePayloadError(f"text length {self.text_length} is negative", EW.LENGTH)
        return AlarmMessages.decode(data, self.text_length)

    def encode_answer(self, answer: AlarmMessages) -> bytes:
        return answer.encode(self.text_length)


@dataclass(frozen=True, slots=True)
class NativeAlarmHistoryRequest(NativeRequest):
    """0x6C, args ``first, last, mode`` (``cnc_rdalmhistry(s, e)`` sends ``(s, s + k - 1, 1)``
    with k <= 23 records per request, looping to ``e``) [V]: :class:`NativeAlarmHistory`."""

    COMMAND: ClassVar[int] = NativeCommand.RDALMHISTRY
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "mode")
    ANSWER: ClassVar[Any] = NativeAlarmHistory
    first: int
    last: int
    mode: int = 1


# --------------------------------------------------------------------------------------------
# Macro variables


@dataclass(frozen=True, slots=True)
class MacroReadRequest(NativeRequest):
    """0x15, args ``first, last`` (inclusive; ``cnc_rdmacro(n)`` sends ``(n, n)``) [V]:
    :class:`ScaledValues`, one record per variable."""

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last")
    ANSWER: ClassVar[Any] = ScaledValues
    first: int
    last: int


@dataclass(frozen=True, slots=True)
class MacroWriteRequest(NativeRequest):
    """0x16, args ``(number, number, 0, 0, 8)``, extra: one :class:`ScaledNumber`
    (``cnc_wrmacro``) [V]: base 2 at 16i class, base 10 at 30i class, see
    :meth:`ScaledNumber.from_macro`. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRMACRO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("number", "number", 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    number: int
    value: ScaledNumber

    def extra(self) -> bytes:
        return self.value.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) != ScaledNumber.SIZE:
            raise NativePayloadError(
                f"macro write carries {len(extra)} data bytes, expected 8", EW.LENGTH
            )
        return {"value": ScaledNumber.decode(extra)}


@dataclass(frozen=True, slots=True)
class MacroDoubleReadRequest(NativeRequest):
    """0xA7, args ``first, count`` (a count, not a last number; ``cnc_rdmacror2``) [V]:
    :class:`MacroDoubles`."""

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO_DOUBLE
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = MacroDoubles
    first: int
    count: int


@dataclass(frozen=True, slots=True)
class MacroDoubleWriteRequest(NativeRequest):
    """0xA8, args ``(number, 0, 0, 0, 8)``, extra: the IEEE double (``cnc_wrmacror2``) [V].

    ``value`` None writes a vacant variable (sent as a quiet NaN, this project's choice).
    No answer data.
    """

    COMMAND: ClassVar[int] = NativeCommand.WRMACRO_DOUBLE
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("number", 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    number: int
    value: float | None

    def extra(self) -> bytes:
        return _pack_double(self.value)

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        if len(extra) != MacroDouble.SIZE:
            raise NativePayloadError(
                f"macro double write carries {len(extra)} data bytes, expected 8", EW.LENGTH
            )
        return {"value": _unpack_double(extra, 0)}


# --------------------------------------------------------------------------------------------
# Parameters and diagnostics


def _item_slots(data: bytes, slot: int, max_axes: int | None, single: bool) -> int:
    """Slots per record: ``max_axes`` when given, else (one record) from the data length."""
    if max_axes is not None:
        return max_axes
    if single and len(data) >= ItemHead.SIZE + slot:
        return (len(data) - ItemHead.SIZE) // slot
    raise ValueError("max_axes is needed to decode several records")


@dataclass(frozen=True, slots=True)
class ParamReadRequest(NativeRequest):
    """0x0E, args ``first, last, axis`` (``cnc_rdparam(n, axis)``, 16i class, sends
    ``(n, n, axis)``, axis 0, k or -1) [V]: :class:`ItemValues` (4-byte slots, type numbering
    :class:`ParamType`). FANUC's library also reads parameter 9968 with it while connecting
    (its "FOCAS option bits", low byte of slot 0) and 3115 in ``cnc_rdposition``."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ItemValues:
        slots = _item_slots(data, 4, max_axes, self.first == self.last)
        return ItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class ParamInfoRequest(NativeRequest):
    """0x10, args ``first, count`` (``cnc_wrparam`` at 16i class sends ``(n, 1)`` first;
    ``cnc_rdparainfo(s, n)`` sends ``(s, n)`` in both classes) [V]: :class:`ParamInfo`."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAINFO
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = ParamInfo
    first: int
    count: int = 1


@dataclass(frozen=True, slots=True)
class ParamWriteRequest(NativeRequest):
    """0x0F, args ``(0, 0, 0, 0, 8 + 4 * max_axes)``, extra: one :class:`ItemRecord` with
    ``max_axes`` slots (``cnc_wrparam``, 16i class, after 0x10) [V]. The value sits
    sign-extended in slot 0 (one axis) or slots 0..axes-1; unused slots hold whatever the
    library's buffer held. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRPARAM
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    record: ItemRecord

    def extra(self) -> bytes:
        return self.record.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"record": ItemRecord.decode(extra)}


@dataclass(frozen=True, slots=True)
class ParamRead3Request(NativeRequest):
    """0x8D, args ``first, last, axis`` (``cnc_rdparam``, 30i class) [V]:
    :class:`ScaledItemValues` (8-byte slots)."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ScaledItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ScaledItemValues:
        slots = _item_slots(data, 8, max_axes, self.first == self.last)
        return ScaledItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class ParamInfo3Request(NativeRequest):
    """0xA0, args ``first, count`` (``cnc_wrparam``, 30i class, sends ``(n, 1)`` first) [V]:
    :class:`ParamInfo3` (28 bytes)."""

    COMMAND: ClassVar[int] = NativeCommand.RDPARAINFO3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "count")
    ANSWER: ClassVar[Any] = ParamInfo3
    first: int
    count: int = 1


@dataclass(frozen=True, slots=True)
class ParamWrite3Request(NativeRequest):
    """0x8E, args ``(0, 0, 0, 0, 8 + 8 * max_axes)``, extra: one :class:`ScaledItemRecord`
    with ``max_axes`` slots (``cnc_wrparam``, 30i class, after 0xA0) [V]. No answer data."""

    COMMAND: ClassVar[int] = NativeCommand.WRPARAM3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = (0, 0, 0, 0, EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    record: ScaledItemRecord

    def extra(self) -> bytes:
        return self.record.encode()

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"record": ScaledItemRecord.decode(extra)}


@dataclass(frozen=True, slots=True)
class DiagnosticRequest(NativeRequest):
    """0x30, args ``first, last, axis`` (``cnc_diagnoss``, 16i class) [V]: :class:`ItemValues`
    with the :class:`DiagType` numbering."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ItemValues:
        slots = _item_slots(data, 4, max_axes, self.first == self.last)
        return ItemValues.decode(data, max(slots, 1))


@dataclass(frozen=True, slots=True)
class Diagnostic3Request(NativeRequest):
    """0x93, args ``first, last, axis`` (``cnc_diagnoss``, 30i class) [V]:
    :class:`ScaledItemValues` with the :class:`DiagType` numbering."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAG3
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "axis")
    ANSWER: ClassVar[Any] = ScaledItemValues
    first: int
    last: int
    axis: int

    def decode_answer(self, data: bytes, max_axes: int | None = None) -> ScaledItemValues:
        slots = _item_slots(data, 8, max_axes, self.first == self.last)
        return ScaledItemValues.decode(data, max(slots, 1))


# --------------------------------------------------------------------------------------------
# PMC


class NativePmcArea(enum.IntEnum):
    """PMC address letters and their FOCAS ``adr_type`` numbers."""

    G = 0
    F = 1
    Y = 2
    X = 3
    A = 4
    R = 5
    T = 6
    K = 7
    C = 8
    D = 9
    M = 10
    N = 11
    E = 12
    Z = 13


@dataclass(frozen=True, slots=True)
class PmcReadRequest(NativeRequest):
    """Device PMC, 0x8001, args ``first, last, area, data_type`` (``pmc_rdpmcrng(a, t, s, e)``
    sends ``(s, e, a, t)``) [V].

    ``first`` and ``last`` are inclusive byte addresses (``last = first + width * count - 1``);
    ``data_type`` 0 byte, 1 word, 2 long (:class:`PmcDataType`). Answered with
    :class:`NativePmcData`.
    """

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_RDPMCRNG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "area", "data_type")
    ANSWER: ClassVar[Any] = NativePmcData
    first: int
    last: int
    area: int
    data_type: int


@dataclass(frozen=True, slots=True)
class PmcWriteRequest(NativeRequest):
    """Device PMC, 0x8002, args ``first, last, area, data_type, nbytes``, extra: the data,
    words and longs big-endian (``pmc_wrpmcrng``) [V]. No answer data."""

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_WRPMCRNG
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("first", "last", "area", "data_type", EXTRA_LENGTH)
    WRITE: ClassVar[bool] = True
    first: int
    last: int
    area: int
    data_type: int
    data: NativePmcData

    def extra(self) -> bytes:
        return self.data.raw

    @classmethod
    def _extra_fields(cls, extra: bytes) -> dict[str, Any]:
        return {"data": NativePmcData(bytes(extra))}

    def values(self) -> tuple[int, ...]:
        """The unsigned values written."""
        return self.data.values(self.data_type)


# --------------------------------------------------------------------------------------------
# Positions, axes, spindles


class NativePositionKind(enum.Enum):
    """What a position read (0x26) asks for."""

    ABSOLUTE = "absolute"
    MACHINE = "machine"
    RELATIVE = "relative"
    DISTANCE = "distance"
    SKIP = "skip"


#: Both numberings FANUC's library sends [V]: 4/1/6/7 (``cnc_absolute``, ``cnc_machine``,
#: ``cnc_relative``, ``cnc_distance``, ``cnc_rddynamic2``; 8 skip from public captures) and
#: 0..3 (``cnc_rdposition``); 1 means the machine position in both.
_POSITION_KINDS: Final[dict[int, NativePositionKind]] = {
    0: NativePositionKind.ABSOLUTE,
    1: NativePositionKind.MACHINE,
    2: NativePositionKind.RELATIVE,
    3: NativePositionKind.DISTANCE,
    4: NativePositionKind.ABSOLUTE,
    6: NativePositionKind.RELATIVE,
    7: NativePositionKind.DISTANCE,
    8: NativePositionKind.SKIP,
}


def resolve_position_kind(code: int) -> NativePositionKind | None:
    """The position a 0x26 kind code asks for, or None for a code this codec does not know."""
    return _POSITION_KINDS.get(code)


@dataclass(frozen=True, slots=True)
class NativePositionRequest(NativeRequest):
    """0x26, args ``kind, axis`` (axis -1 = all axes, n = axis n) [V]: :class:`ScaledValues`,
    one record per axis (for -1 send max-axes records: ``cnc_rddynamic2`` packs its four
    arrays with a stride of the number received)."""

    COMMAND: ClassVar[int] = NativeCommand.POSITION
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "axis")
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int
    axis: int = -1

    @property
    def position_kind(self) -> NativePositionKind | None:
        return resolve_position_kind(self.kind)


@dataclass(frozen=True, slots=True)
class AxisNameRequest(NativeRequest):
    """0x89, args ``kind``: 0 -> :class:`AxisNames` (4 bytes per axis; ``cnc_rdaxisname``,
    ``cnc_rdsvmeter``), -1 -> :class:`PositionAxisNames` (16 bytes per axis;
    ``cnc_rdposition``) [V]."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_NAME
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisNames
    kind: int = 0

    def decode_answer(
        self, data: bytes, max_axes: int | None = None
    ) -> AxisNames | PositionAxisNames:
        if self.kind == -1:
            return PositionAxisNames.decode(data)
        return AxisNames.decode(data)


@dataclass(frozen=True, slots=True)
class AxisUnitRequest(NativeRequest):
    """0x88, args ``kind`` (``cnc_rdposition``: 2 at 16i class, 1 then 2 at 30i class) [V]:
    :class:`AxisUnits`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_UNIT
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisUnits
    kind: int = 2


@dataclass(frozen=True, slots=True)
class AxisCountRequest(NativeRequest):
    """0xA4, args ``kind``: 0 axes (``cnc_rdposition``), 1 spindles (``cnc_rdspload``), 2 servo
    axes (``cnc_rdsvmeter``), 30i class; sent before and after the read [V]:
    :class:`AxisCount`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_COUNT
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = AxisCount
    kind: int = 0


@dataclass(frozen=True, slots=True)
class AxisDisplayRequest(NativeRequest):
    """0xA3, args ``(0, -1)`` (``cnc_rdposition``, 30i class) [V]: :class:`AxisDisplays`."""

    COMMAND: ClassVar[int] = NativeCommand.AXIS_DISPLAY
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "axis")
    ANSWER: ClassVar[Any] = AxisDisplays
    kind: int = 0
    axis: int = -1


@dataclass(frozen=True, slots=True)
class SpindleLoadRequest(NativeRequest):
    """0x40, args ``(0, spindle)`` (``cnc_rdspload(sp)``, -1 all) [V]: :class:`ScaledValues`,
    one per spindle (the library keeps the low 16 bits of each mantissa)."""

    COMMAND: ClassVar[int] = NativeCommand.RDSPLOAD
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind", "spindle")
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int = 0
    spindle: int = -1


@dataclass(frozen=True, slots=True)
class ServoMeterRequest(NativeRequest):
    """0x56, args ``(1)`` (``cnc_rdsvmeter``) [V]: :class:`ScaledValues`, one per axis (the
    library takes |mantissa| and the decimals; it does not check the length)."""

    COMMAND: ClassVar[int] = NativeCommand.RDSVMETER
    ARGS: ClassVar[tuple[_ArgSpec, ...]] = ("kind",)
    ANSWER: ClassVar[Any] = ScaledValues
    kind: int = 1


#: Every request this codec declares, keyed by ``(device, command)``.
REQUEST_TYPES: Final[dict[tuple[int, int], type[NativeRequest]]] = {
    (cls.DEVICE, cls.COMMAND): cls
    for cls in (
        SysInfoRequest,
        StatInfoRequest,
        HdckRequest,
        TmModeRequest,
        CncIdRequest,
        TimerRequest,
        ProgramNumberRequest,
        SequenceNumberRequest,
        ExecutingProgramRequest,
        ActualFeedRequest,
        ActualSpindleSpeedRequest,
        AlarmStatusRequest,
        AlarmMessageRequest,
        NativeAlarmHistoryRequest,
        MacroReadRequest,
        MacroWriteRequest,
        MacroDoubleReadRequest,
        MacroDoubleWriteRequest,
        ParamReadRequest,
        ParamInfoRequest,
        ParamWriteRequest,
        ParamRead3Request,
        ParamInfo3Request,
        ParamWrite3Request,
        DiagnosticRequest,
        Diagnostic3Request,
        PmcReadRequest,
        PmcWriteRequest,
        NativePositionRequest,
        AxisNameRequest,
        AxisUnitRequest,
        AxisCountRequest,
        AxisDisplayRequest,
        SpindleLoadRequest,
        ServoMeterRequest,
    )
}


def decode_request(block: RequestBlock) -> NativeRequest | None:
    """The typed request of ``block``; None when the command is not declared (answer it with
    EW_FUNC); :class:`NativePayloadError` when the block does not fit its command."""
    cls = REQUEST_TYPES.get((block.device, block.command))
    if cls is None:
        return None
    return cls.from_block(block)
