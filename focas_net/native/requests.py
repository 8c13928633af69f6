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

This module holds the declaration's machinery, the table of every request
(:data:`REQUEST_TYPES`, which the modules of each area join) and the requests of the CNC's
identity, status, program numbers, feed and speed, and alarms; the requests of parameters and
diagnostics, macro variables, the PMC, the axes and part programs are declared in
:mod:`.items`, :mod:`.macros`, :mod:`.pmc`, :mod:`.axes` and :mod:`.programs`.
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
    CncId,
    ExecutingProgram,
    HdckStatus,
    NativeAlarmHistory,
    NativeProgramNumbers,
    NativeSysInfo,
    NoData,
    ScaledValues,
    SequenceNumber,
    StatInfo,
    TimerValue,
    TmModeStatus,
)

__all__ = [
    "EXTRA_LENGTH",
    "REQUEST_TYPES",
    "ActualFeedRequest",
    "ActualSpindleSpeedRequest",
    "AlarmMessageRequest",
    "AlarmStatusRequest",
    "CncIdRequest",
    "ExecutingProgramRequest",
    "HdckRequest",
    "NativeAlarmHistoryRequest",
    "NativeCommand",
    "NativeRequest",
    "ProgramNumberRequest",
    "SequenceNumberRequest",
    "StatInfoRequest",
    "SysInfoRequest",
    "TimerRequest",
    "TmModeRequest",
    "decode_request",
]


class NativeCommand(enum.IntEnum):
    """Command words of the requests this codec declares (the FOCAS functions sending them)."""

    SEARCH = 0x03  # cnc_search / cnc_searcho8 (focas_net.native.programs)
    DELETE = 0x05  # cnc_delete / cnc_deleteo8
    RDPROGDIR = 0x06  # cnc_rdprogdir / cnc_rdprogdir2 / cnc_rdprogdir3
    RDPROGINFO = 0x07  # cnc_rdproginfo
    RDTOFS = 0x08  # cnc_rdtofs / cnc_rdtofsr (focas_net.native.offsets)
    WRTOFS = 0x09  # cnc_wrtofs
    RDTOFSINFO = 0x0A  # cnc_rdtofsinfo / cnc_rdtofsinfo2
    RDZOFS = 0x0B  # cnc_rdzofs / cnc_rdzofsr
    WRZOFS = 0x0C  # cnc_wrzofs
    WRPARAM = 0x0F  # cnc_wrparam, 16i class (after 0x10)
    RDPARAM = 0x0E  # cnc_rdparam, 16i class (4-byte value slots)
    RDPARAINFO = 0x10  # cnc_rdparainfo; cnc_wrparam, 16i class
    RDPARANUM = 0x11  # cnc_rdparanum (focas_net.native.info)
    RDMACRO = 0x15  # cnc_rdmacro / cnc_rdmacror: scaled numbers
    WRMACRO = 0x16  # cnc_wrmacro: one scaled number (binary at 16i class)
    SYSINFO = 0x18  # cnc_allclibhndl3 (stored for cnc_sysinfo): ODBSYS
    STATINFO = 0x19  # cnc_statinfo: ODBST; cnc_rdposition (16i class)
    ALARM = 0x1A  # cnc_alarm / cnc_alarm2 / cnc_rddynamic2: alarm bits
    GETFIGURE = 0x1B  # cnc_getfigure (focas_net.native.info)
    RDPRGNUM = 0x1C  # cnc_rdprgnum / cnc_rdprgnumo8 / cnc_rddynamic2
    RDSEQNUM = 0x1D  # cnc_rdseqnum / cnc_rddynamic2
    RDEXECPROG = 0x20  # cnc_rdexecprog (focas_net.native.programs)
    GMODAL = 0x21  # cnc_modal: G codes (focas_net.native.modal)
    AMODAL = 0x22  # cnc_modal: other data
    RDALMMSG = 0x23  # cnc_rdalmmsg / cnc_rdalmmsg2: alarm messages
    ACTF = 0x24  # cnc_actf / cnc_rddynamic2: actual feed rate
    ACTS = 0x25  # cnc_acts / cnc_rddynamic2: actual spindle speed
    POSITION = 0x26  # cnc_absolute / machine / relative / distance / rdposition / rddynamic2
    RDSET = 0x29  # cnc_rdset, 16i set (focas_net.native.info)
    RDSETINFO = 0x2B  # cnc_rdsetinfo
    RDDIAG = 0x30  # cnc_diagnoss, 16i class (4-byte value slots)
    RDDIAGINFO = 0x31  # cnc_rddiaginfo
    RDDIAGNUM = 0x32  # cnc_rddiagnum
    RDOPMSG = 0x34  # cnc_rdopmsg / cnc_rdopmsg2; cnc_rdopmsg3, 16i class
    RDBLKCOUNT = 0x35  # cnc_rdblkcount
    RDMDIPNTR = 0x38  # cnc_rdmdipntr
    RDSPLOAD = 0x40  # cnc_rdspload / rdspmaxrpm / rdspgear / acts2 / rdspmeter (16i)
    RDSYSSOFT = 0x41  # cnc_rdsyssoft
    RDPRSTRINFO = 0x43  # cnc_rdprstrinfo (with 0x26 kinds 13 and 14)
    RDUSEGRPID = 0x48  # cnc_rdusegrpid (focas_net.native.offsets)
    RDNGRP = 0x4A  # cnc_rdngrp / cnc_rdmaxgrp / cnc_rdmaxtool; cnc_rdtlinfo, 16i class
    TOOLNUM = 0x4D  # cnc_toolnum; cnc_rdtoolgrp (after 0x8B)
    GETTIMER = 0x45  # cnc_gettimer (focas_net.native.clock)
    SETTIMER = 0x46  # cnc_settimer
    RDSVMETER = 0x56  # cnc_rdsvmeter / rdcurrent / rdloopgain / rdsrvspeed
    RDOPNLSGNL = 0x5D  # cnc_rdopnlsgnl (focas_net.native.clock)
    RDALMHISTRY = 0x6C  # cnc_rdalmhistry
    AXIS_UNIT = 0x88  # cnc_rdposition: units
    AXIS_NAME = 0x89  # cnc_rdaxisname / cnc_rdsvmeter / cnc_rdposition: axis names
    SPDLNAME = 0x8A  # cnc_rdspdlname / cnc_rdspmeter / cnc_rdspeed: spindle names
    RDTOOLGRP = 0x8B  # cnc_rdntool / cnc_rdlife / cnc_rdcount / cnc_rdtoolgrp
    RDPARAM3 = 0x8D  # cnc_rdparam, 30i class (8-byte scaled slots)
    WRPARAM3 = 0x8E  # cnc_wrparam, 30i class (after 0xA0)
    RDSET3 = 0x90  # cnc_rdset, 30i set
    RDDIAG3 = 0x93  # cnc_diagnoss, 30i class (8-byte scaled slots)
    RDGCODE = 0x96  # cnc_rdgcode
    RDCOMMAND = 0x97  # cnc_rdcommand
    STAT_TMMODE = 0x98  # cnc_statinfo: ODBST tmmode
    RDPARAINFO3 = 0xA0  # cnc_wrparam, 30i class
    AXIS_DISPLAY = 0xA3  # cnc_rdposition, 30i class: display flags
    AXIS_COUNT = 0xA4  # cnc_rdposition / cnc_rdspload / cnc_rdsvmeter, 30i class: counts
    RDMACRO_DOUBLE = 0xA7  # cnc_rdmacror2: IEEE doubles
    WRMACRO_DOUBLE = 0xA8  # cnc_wrmacror2: IEEE double
    RDPDF_DRIVE = 0xAE  # cnc_rdpdf_drive (focas_net.native.files)
    RDPDF_INF = 0xAF  # cnc_rdpdf_inf
    RDPDF_CURDIR = 0xB0  # cnc_rdpdf_curdir
    WRPDF_CURDIR = 0xB1  # cnc_wrpdf_curdir
    RDPDF_SUBDIR = 0xB2  # cnc_rdpdf_subdir
    RDPDF_ALLDIR = 0xB3  # cnc_rdpdf_alldir
    RDPDF_SUBDIRN = 0xB4  # cnc_rdpdf_subdirn
    PDF_DEL = 0xB6  # cnc_pdf_del
    PDF_RDMAIN = 0xB9  # cnc_pdf_rdmain
    PDF_SLCTMAIN = 0xBA  # cnc_pdf_slctmain
    EXEPRGNAME = 0xCF  # cnc_exeprgname
    RDOPMSG3 = 0xD0  # cnc_rdopmsg3, 30i class
    STAT_HDCK = 0xE1  # cnc_statinfo: ODBST hdck
    STATINFO2 = 0xE2  # cnc_statinfo2 (with 0xE1 and 0x98)
    RDCNCID = 0xE8  # cnc_rdcncid
    EXEPRGNAME2 = 0xFC  # cnc_exeprgname2
    RDTIMER = 0x120  # cnc_rdtimer
    RDETHERINFO = 0x159  # cnc_rdetherinfo
    RDACTPT = 0x162  # cnc_rdactpt
    RDTLINFO = 0x1C4  # cnc_rdtlinfo, 30i class
    RDPDF_PRGINF = 0x2B1  # cnc_rdpdf_prginf (focas_net.native.files)
    PMC_RDPMCRNG = 0x8001  # pmc_rdpmcrng (device PMC)
    PMC_WRPMCRNG = 0x8002  # pmc_wrpmcrng (device PMC)
    PMC_RDPMCINFO = 0x8003  # pmc_rdpmcinfo (device PMC)
    PMC_RDPMCTITLE = 0x800B  # pmc_rdpmctitle (device PMC)


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


#: Every request this codec declares, keyed by ``(device, command)``: this module's, and those
#: each area's module (:mod:`.items`, :mod:`.macros`, :mod:`.pmc`, :mod:`.axes`,
#: :mod:`.programs`) adds with :func:`_register` when it is imported (the package imports them
#: all).
REQUEST_TYPES: Final[dict[tuple[int, int], type[NativeRequest]]] = {}


def _register(*classes: type[NativeRequest]) -> None:
    """Adds the typed requests ``classes`` to :data:`REQUEST_TYPES`."""
    for cls in classes:
        REQUEST_TYPES[(cls.DEVICE, cls.COMMAND)] = cls


_register(
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
)


def decode_request(block: RequestBlock) -> NativeRequest | None:
    """The typed request of ``block``; None when the command is not declared (answer it with
    EW_FUNC); :class:`NativePayloadError` when the block does not fit its command."""
    cls = REQUEST_TYPES.get((block.device, block.command))
    if cls is None:
        return None
    return cls.from_block(block)
