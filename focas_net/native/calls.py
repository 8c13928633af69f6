"""What each FOCAS function of FANUC's library puts on the wire, per command set.

Each function here is named after the FOCAS function (``cnc_rdparam``...) and returns a
:class:`LibraryCall`: the typed requests of every data-request frame the library sends for
that call, in order (one tuple of blocks per frame). They were captured from libfwlib32 1.0.5
(``tests/fwlib_capture.py``, data in ``tests/data/fwlib_v2.json`` and ``fwlib_v3.json``).

The command set is picked by the version word of the open answer (:class:`CommandSet`): "16i
class" up to version 2, "30i class" from version 3 (see :mod:`.opening`).
"""

from __future__ import annotations

import enum
import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Final, ParamSpec, cast

from focas_net._memo import Memo

from .axes import (
    AxisCountRequest,
    AxisDisplayRequest,
    AxisNameRequest,
    AxisUnitRequest,
    NativePositionRequest,
    ServoMeterRequest,
    SpindleLoadRequest,
)
from .blocks import RequestBlock, encode_request
from .items import (
    Diagnostic3Request,
    DiagnosticRequest,
    ItemRecord,
    ParamInfo3Request,
    ParamInfoRequest,
    ParamRead3Request,
    ParamReadRequest,
    ParamWrite3Request,
    ParamWriteRequest,
    ScaledItemRecord,
)
from .macros import (
    MacroDoubleReadRequest,
    MacroDoubleWriteRequest,
    MacroReadRequest,
    MacroWriteRequest,
)
from .modal import (
    ActivePointerRequest,
    BlockCounterRequest,
    CommandRequest,
    ExecutingPathRequest,
    GCodeRequest,
    MdiPointerRequest,
    ModalAuxRequest,
    ModalGRequest,
    OperatorMessage3Request,
    OperatorMessageRequest,
)
from .pmc import NativePmcData, PmcReadRequest, PmcWriteRequest
from .programs import (
    ExecutingBlocksRequest,
    ProgramDeleteRequest,
    ProgramDirRequest,
    ProgramMemoryRequest,
    ProgramSearchRequest,
)
from .records import ScaledNumber
from .requests import (
    ActualFeedRequest,
    ActualSpindleSpeedRequest,
    AlarmMessageRequest,
    AlarmStatusRequest,
    CncIdRequest,
    ExecutingProgramRequest,
    HdckRequest,
    NativeAlarmHistoryRequest,
    NativeRequest,
    ProgramNumberRequest,
    SequenceNumberRequest,
    StatInfoRequest,
    SysInfoRequest,
    TimerRequest,
    TmModeRequest,
)
from .session import Part, encode_part

__all__ = [
    "ALARM_HISTORY_CHUNK",
    "OPTION_PARAMETER",
    "POSITION_PARAMETER",
    "CommandSet",
    "LibraryCall",
]

#: The parameter FANUC's library reads while connecting at 16i class (its FOCAS option bits).
OPTION_PARAMETER: Final = 9968
#: The parameter ``cnc_rdposition`` reads at 16i class (display bits, one slot per axis).
POSITION_PARAMETER: Final = 3115
#: Most alarm history records ``cnc_rdalmhistry`` asks per request.
ALARM_HISTORY_CHUNK: Final = 23
#: Most answers one call keeps decoded (and values made of them).
_ANSWERS_KEPT: Final = 16


class CommandSet(enum.StrEnum):
    """The command set of a handle, picked by the open answer's version word (a ``str``
    enumeration, ``"16i"`` or ``"30i"``: it hashes as its value, part of the key of the calls
    kept by their arguments)."""

    FS16I = "16i"
    FS30I = "30i"

    @classmethod
    def for_version(cls, version: int) -> CommandSet:
        """16i class up to version 2, 30i class from version 3."""
        return cls.FS16I if version <= 2 else cls.FS30I


@dataclass(frozen=True, slots=True)
class LibraryCall:
    """One call of a FOCAS function: its name, the requests of each frame it sends and, for a
    client, those frames' blocks encoded (one :class:`~focas_net.native.session.Part` per
    frame, path 1).

    :raises ValueError: a request whose fields do not fit its block (made with arguments the
        wire cannot carry).
    """

    function: str
    frames: tuple[tuple[NativeRequest, ...], ...]
    parts: tuple[Part, ...] = field(init=False, repr=False, compare=False)
    #: Answers decoded, by (frame, request, max axes, the answer bytes): see :meth:`answer`.
    _answers: dict[tuple[int, int, int, bytes], Any] = field(
        init=False, repr=False, compare=False, default_factory=dict
    )
    #: What a client made of whole answers of this call alone, by the answers' bytes and
    #: whatever else the value depends on, a few per call (the values are immutable): a poll
    #: whose answer repeats makes its value once (the native client's ``made_once``).
    results: Memo = field(
        init=False, repr=False, compare=False, default_factory=lambda: Memo(_ANSWERS_KEPT)
    )
    #: The parts of the frames on paths after the first, by (frame, path): see :meth:`part`.
    _path_parts: dict[tuple[int, int], Part] = field(
        init=False, repr=False, compare=False, default_factory=dict
    )

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "parts", tuple(encode_part(frame, 1, self.function) for frame in self.frames)
        )

    def answer(self, frame: int, index: int, data: bytes, max_axes: int) -> Any:
        """The answer ``data`` of request ``index`` of frame ``frame``, decoded
        (``max_axes``: the slot count of multi-record answers). Kept by its bytes, a few per
        call: a poll whose answer repeats decodes it once; the values are immutable.

        :raises NativePayloadError: data that does not decode (nothing kept).
        """
        key = (frame, index, max_axes, data)
        answers = self._answers
        value = answers.get(key)
        if value is None:
            value = self.frames[frame][index].decode_answer(data, max_axes)
            if len(answers) >= _ANSWERS_KEPT:
                answers.clear()
            answers[key] = value
        return value

    def part(self, frame: int, path: int) -> Part:
        """Frame ``frame``'s :class:`~focas_net.native.session.Part` with ``path`` in every
        block's path word (:attr:`parts` for path 1; the others encoded once, then kept)."""
        if path == 1:
            return self.parts[frame]
        key = (frame, path)
        part = self._path_parts.get(key)
        if part is None:
            part = self._path_parts[key] = encode_part(self.frames[frame], path, self.function)
        return part

    def blocks(self, path: int = 1) -> tuple[tuple[RequestBlock, ...], ...]:
        """The request blocks of each frame."""
        return tuple(tuple(r.to_block(path) for r in frame) for frame in self.frames)

    def encode(self, path: int = 1) -> tuple[bytes, ...]:
        """The whole data-request frames, as the library sends them (version 1)."""
        return tuple(encode_request(blocks) for blocks in self.blocks(path))


def _one(function: str, *requests: NativeRequest) -> LibraryCall:
    return LibraryCall(function, (tuple(requests),))


_P = ParamSpec("_P")
#: Most calls each function keeps built.
_MEMO_SIZE: Final = 1024


def _memoized(build: Callable[_P, LibraryCall]) -> Callable[_P, LibraryCall]:
    """``build``, each call made once for equal arguments (kept by their values in a bounded
    :func:`functools.lru_cache`, whose look-up runs no Python code): a poll that repeats a
    call encodes its frames once. The arguments are hashable (PMC values a tuple)."""
    return cast(Callable[_P, LibraryCall], functools.lru_cache(maxsize=_MEMO_SIZE)(build))


_16I: Final = CommandSet.FS16I


# -- connection ---------------------------------------------------------------------------------


@_memoized
def cnc_allclibhndl3(cs: CommandSet, paths: int = 1) -> LibraryCall:
    """The data requests of the connect: one 0x18 block per path present (path i + 1), then at
    16i class parameter 9968 (option bits; not with open-answer kind 2 or 3) [V]."""
    frames: list[tuple[NativeRequest, ...]] = [tuple(SysInfoRequest() for _ in range(paths))]
    if cs is _16I:
        frames.append((ParamReadRequest(OPTION_PARAMETER, OPTION_PARAMETER, 0),))
    return LibraryCall("cnc_allclibhndl3", tuple(frames))


# -- status, programs, alarms ------------------------------------------------------------------


@_memoized
def cnc_statinfo(cs: CommandSet) -> LibraryCall:
    """0x19, 0xE1, 0x98 in one frame [V]."""
    return _one("cnc_statinfo", StatInfoRequest(), HdckRequest(), TmModeRequest())


@_memoized
def cnc_alarm(cs: CommandSet) -> LibraryCall:
    """0x1A [V]."""
    return _one("cnc_alarm", AlarmStatusRequest())


@_memoized
def cnc_alarm2(cs: CommandSet) -> LibraryCall:
    """0x1A [V]."""
    return _one("cnc_alarm2", AlarmStatusRequest())


@_memoized
def cnc_rdalmmsg(cs: CommandSet, alarm_type: int, count: int) -> LibraryCall:
    """0x23 ``(type, count, 2, 32)`` [V]."""
    return _one("cnc_rdalmmsg", AlarmMessageRequest(alarm_type, count, 2, 32))


@_memoized
def cnc_rdalmmsg2(cs: CommandSet, alarm_type: int, count: int) -> LibraryCall:
    """0x23 ``(type, count, 2, 64)`` [V]."""
    return _one("cnc_rdalmmsg2", AlarmMessageRequest(alarm_type, count, 2, 64))


@_memoized
def cnc_rdalmhistry(cs: CommandSet, first: int, last: int) -> LibraryCall:
    """0x6C ``(s, s + k - 1, 1)``, one frame per chunk of at most 23 records, up to ``last``
    [V]. The library stops early, quietly, when a chunk after the first answers EW_NUMBER."""
    frames: list[tuple[NativeRequest, ...]] = []
    for start in range(first, last + 1, ALARM_HISTORY_CHUNK):
        stop = min(start + ALARM_HISTORY_CHUNK - 1, last)
        frames.append((NativeAlarmHistoryRequest(start, stop, 1),))
    return LibraryCall("cnc_rdalmhistry", tuple(frames))


@_memoized
def cnc_rdprgnum(cs: CommandSet) -> LibraryCall:
    """0x1C [V]."""
    return _one("cnc_rdprgnum", ProgramNumberRequest())


@_memoized
def cnc_rdprgnumo8(cs: CommandSet) -> LibraryCall:
    """0x1C [V]."""
    return _one("cnc_rdprgnumo8", ProgramNumberRequest())


@_memoized
def cnc_exeprgname(cs: CommandSet) -> LibraryCall:
    """0xCF [V]."""
    return _one("cnc_exeprgname", ExecutingProgramRequest())


@_memoized
def cnc_rdseqnum(cs: CommandSet) -> LibraryCall:
    """0x1D [V]."""
    return _one("cnc_rdseqnum", SequenceNumberRequest())


@_memoized
def cnc_rdcncid(cs: CommandSet) -> LibraryCall:
    """0xE8 [V]."""
    return _one("cnc_rdcncid", CncIdRequest())


@_memoized
def cnc_rdtimer(cs: CommandSet, timer_type: int) -> LibraryCall:
    """0x120 ``(type)`` [V]."""
    return _one("cnc_rdtimer", TimerRequest(timer_type))


# -- part programs -----------------------------------------------------------------------------
# The same frames in both command sets; uploads and downloads use frames of their own on the
# first connection (focas_net.native.programs), not data requests.


@_memoized
def cnc_rdprogdir2(cs: CommandSet, kind: int, top: int, count: int) -> LibraryCall:
    """0x06 ``(top, count, type)`` [V: types 0, 1, 2]."""
    return _one("cnc_rdprogdir2", ProgramDirRequest(top, count, kind))


@_memoized
def cnc_rdprogdir3(cs: CommandSet, kind: int, top: int, count: int) -> LibraryCall:
    """0x06 ``(top, count, type)``, type 2 (with the dates) sent as 3 [V: types 1, 2]."""
    return _one("cnc_rdprogdir3", ProgramDirRequest(top, count, 3 if kind == 2 else kind))


@_memoized
def cnc_rdprogdir(cs: CommandSet, kind: int, start: int) -> LibraryCall:
    """0x06 ``(start, 19, type)``, one page: the library asks 19 entries a frame and sends
    the next page from the last number + 1 until a page has no entry [V]."""
    return _one("cnc_rdprogdir", ProgramDirRequest(start, 19, kind))


@_memoized
def cnc_rdproginfo(cs: CommandSet) -> LibraryCall:
    """0x07, no arguments, for either type [V]."""
    return _one("cnc_rdproginfo", ProgramMemoryRequest())


@_memoized
def cnc_delete(cs: CommandSet, number: int) -> LibraryCall:
    """0x05 ``(number)`` [V]."""
    return _one("cnc_delete", ProgramDeleteRequest(number))


@_memoized
def cnc_search(cs: CommandSet, number: int) -> LibraryCall:
    """0x03 ``(number)`` [V]."""
    return _one("cnc_search", ProgramSearchRequest(number))


@_memoized
def cnc_rdexecprog(cs: CommandSet, length: int) -> LibraryCall:
    """0x20 ``(length)`` [V]."""
    return _one("cnc_rdexecprog", ExecutingBlocksRequest(length))


# -- macro variables ---------------------------------------------------------------------------


@_memoized
def cnc_rdmacro(cs: CommandSet, number: int) -> LibraryCall:
    """0x15 ``(n, n)`` [V]."""
    return _one("cnc_rdmacro", MacroReadRequest(number, number))


@_memoized
def cnc_wrmacro(cs: CommandSet, number: int, mcr_val: int, dec_val: int) -> LibraryCall:
    """0x16 ``(n, n, 0, 0, 8)`` + a binary record at 16i class, a base-10 one at 30i [V]."""
    value = ScaledNumber.from_macro(mcr_val, dec_val, binary=cs is _16I)
    return _one("cnc_wrmacro", MacroWriteRequest(number, value))


@_memoized
def cnc_rdmacror2(cs: CommandSet, first: int, count: int) -> LibraryCall:
    """0xA7 ``(first, count)`` [V]."""
    return _one("cnc_rdmacror2", MacroDoubleReadRequest(first, count))


@_memoized
def cnc_wrmacror2(cs: CommandSet, number: int, value: float) -> LibraryCall:
    """0xA8 ``(n, 0, 0, 0, 8)`` + the double [V]."""
    return _one("cnc_wrmacror2", MacroDoubleWriteRequest(number, value))


# -- parameters and diagnostics ----------------------------------------------------------------


@_memoized
def cnc_rdparam(cs: CommandSet, number: int, axis: int) -> LibraryCall:
    """0x0E (16i) or 0x8D (30i) ``(n, n, axis)`` [V]."""
    if cs is _16I:
        return _one("cnc_rdparam", ParamReadRequest(number, number, axis))
    return _one("cnc_rdparam", ParamRead3Request(number, number, axis))


@_memoized
def cnc_wrparam(cs: CommandSet, record: ItemRecord | ScaledItemRecord) -> LibraryCall:
    """Two frames: 0x10 ``(n, 1)`` then 0x0F + ``record`` (16i), or 0xA0 ``(n, 1)`` then
    0x8E + ``record`` (30i); ``record`` holds max-axes slots [V]."""
    info = wrparam_info(cs, record.number).frames[0]
    if isinstance(record, ItemRecord):
        return LibraryCall("cnc_wrparam", (info, (ParamWriteRequest(record),)))
    return LibraryCall("cnc_wrparam", (info, (ParamWrite3Request(record),)))


@_memoized
def wrparam_info(cs: CommandSet, number: int) -> LibraryCall:
    """The first frame of ``cnc_wrparam`` alone: the parameter's information, 0x10 ``(n, 1)``
    at 16i class or 0xA0 ``(n, 1)`` at 30i, which the library reads before it builds the
    write [V]."""
    if cs is _16I:
        return _one("cnc_wrparam", ParamInfoRequest(number, 1))
    return _one("cnc_wrparam", ParamInfo3Request(number, 1))


@_memoized
def cnc_rdparainfo(cs: CommandSet, first: int, count: int) -> LibraryCall:
    """0x10 ``(s, n)`` in both command sets [V]."""
    return _one("cnc_rdparainfo", ParamInfoRequest(first, count))


@_memoized
def cnc_diagnoss(cs: CommandSet, number: int, axis: int) -> LibraryCall:
    """0x30 (16i) or 0x93 (30i) ``(n, n, axis)`` [V]."""
    if cs is _16I:
        return _one("cnc_diagnoss", DiagnosticRequest(number, number, axis))
    return _one("cnc_diagnoss", Diagnostic3Request(number, number, axis))


# -- PMC ---------------------------------------------------------------------------------------


@_memoized
def pmc_rdpmcrng(cs: CommandSet, area: int, data_type: int, first: int, last: int) -> LibraryCall:
    """Device PMC, 0x8001 ``(s, e, area, type)`` [V]."""
    return _one("pmc_rdpmcrng", PmcReadRequest(first, last, area, data_type))


def pmc_wrpmcrng(
    cs: CommandSet, area: int, data_type: int, first: int, last: int, values: Sequence[int]
) -> LibraryCall:
    """Device PMC, 0x8002 ``(s, e, area, type, nbytes)`` + the values, big-endian [V]."""
    return _pmc_wrpmcrng(cs, area, data_type, first, last, tuple(values))


@_memoized
def _pmc_wrpmcrng(
    cs: CommandSet, area: int, data_type: int, first: int, last: int, values: tuple[int, ...]
) -> LibraryCall:
    data = NativePmcData.from_values(data_type, values)
    return _one("pmc_wrpmcrng", PmcWriteRequest(first, last, area, data_type, data))


# -- positions, axes, spindles, feed -------------------------------------------------------------


@_memoized
def cnc_actf(cs: CommandSet) -> LibraryCall:
    """0x24 [V]."""
    return _one("cnc_actf", ActualFeedRequest())


@_memoized
def cnc_acts(cs: CommandSet) -> LibraryCall:
    """0x25 [V]."""
    return _one("cnc_acts", ActualSpindleSpeedRequest())


@_memoized
def cnc_absolute(cs: CommandSet, axis: int) -> LibraryCall:
    """0x26 ``(4, axis)`` [V]."""
    return _one("cnc_absolute", NativePositionRequest(4, axis))


@_memoized
def cnc_machine(cs: CommandSet, axis: int) -> LibraryCall:
    """0x26 ``(1, axis)`` [V]."""
    return _one("cnc_machine", NativePositionRequest(1, axis))


@_memoized
def cnc_relative(cs: CommandSet, axis: int) -> LibraryCall:
    """0x26 ``(6, axis)`` [V]."""
    return _one("cnc_relative", NativePositionRequest(6, axis))


@_memoized
def cnc_distance(cs: CommandSet, axis: int) -> LibraryCall:
    """0x26 ``(7, axis)`` [V]."""
    return _one("cnc_distance", NativePositionRequest(7, axis))


@_memoized
def cnc_rdposition(cs: CommandSet) -> LibraryCall:
    """One frame: at 16i class 0x19, 0x26 (0..3, -1), 0x89(-1), 0x0E 3115 (-1), 0x88(2),
    0x19 (9 blocks); at 30i class 0xA4(0), 0x89(-1), 0x88(1), 0x88(2), 0xA3(0, -1), 0x26
    (0..3, -1), 0xA4(0) (10 blocks) [V]."""
    positions = tuple(NativePositionRequest(kind, -1) for kind in range(4))
    if cs is _16I:
        return _one(
            "cnc_rdposition",
            StatInfoRequest(),
            *positions,
            AxisNameRequest(-1),
            ParamReadRequest(POSITION_PARAMETER, POSITION_PARAMETER, -1),
            AxisUnitRequest(2),
            StatInfoRequest(),
        )
    return _one(
        "cnc_rdposition",
        AxisCountRequest(0),
        AxisNameRequest(-1),
        AxisUnitRequest(1),
        AxisUnitRequest(2),
        AxisDisplayRequest(0, -1),
        *positions,
        AxisCountRequest(0),
    )


@_memoized
def cnc_rddynamic2(cs: CommandSet, axis: int) -> LibraryCall:
    """One frame of 9 blocks: 0x1A, 0x1C, 0x1D, 0x24, 0x25, 0x26 (4, 1, 6, 7; axis) [V]."""
    return _one(
        "cnc_rddynamic2",
        AlarmStatusRequest(),
        ProgramNumberRequest(),
        SequenceNumberRequest(),
        ActualFeedRequest(),
        ActualSpindleSpeedRequest(),
        *(NativePositionRequest(kind, axis) for kind in (4, 1, 6, 7)),
    )


@_memoized
def cnc_rdaxisname(cs: CommandSet) -> LibraryCall:
    """0x89 ``(0)`` [V]."""
    return _one("cnc_rdaxisname", AxisNameRequest(0))


@_memoized
def cnc_rdspload(cs: CommandSet, spindle: int) -> LibraryCall:
    """0x40 ``(0, sp)``; at 30i class between two 0xA4(1) [V]."""
    if cs is _16I:
        return _one("cnc_rdspload", SpindleLoadRequest(0, spindle))
    return _one(
        "cnc_rdspload", AxisCountRequest(1), SpindleLoadRequest(0, spindle), AxisCountRequest(1)
    )


@_memoized
def cnc_rdsvmeter(cs: CommandSet) -> LibraryCall:
    """0x56(1), 0x89(0) at 16i class; 0xA4(2), 0x89(0), 0x56(1), 0xA4(2) at 30i [V]."""
    if cs is _16I:
        return _one("cnc_rdsvmeter", ServoMeterRequest(1), AxisNameRequest(0))
    return _one(
        "cnc_rdsvmeter",
        AxisCountRequest(2),
        AxisNameRequest(0),
        ServoMeterRequest(1),
        AxisCountRequest(2),
    )


# -- modal data, operator messages, program pointers (focas_net.native.modal) -------------------


def _modal_request(kind: int, block: int) -> ModalGRequest | ModalAuxRequest | None:
    """The request ``cnc_modal(type, block)`` sends (see :mod:`.modal`) [V]; None for a type
    the library refuses with EW_NUMBER without sending (127..199, -6 and less)."""
    if 0 <= kind <= 99 or kind == -1:
        return ModalGRequest(kind, block)
    if kind in (-4, -5):
        return ModalGRequest(kind + 2, block)
    if kind >= 300:
        return ModalGRequest(kind - 200, block)
    if 100 <= kind <= 126:
        return ModalAuxRequest(_MODAL_SLOTS[kind - 100], block)
    if kind in (-2, -3):
        return ModalAuxRequest(kind + 1, block)
    if kind >= 200:
        return ModalAuxRequest(kind - 100, block)
    return None


#: The slot ``cnc_modal`` sends for types 100..126 (B D E F H L M S T R P Q A C I J K N O U V W
#: X Y Z, the second and third M codes) [V].
_MODAL_SLOTS: Final = (1, 3, 4, 5, 6, 10, 11, 21, 22, 20, 18, 19, 0, 2, 7, 8, 9, 16, 17, 23,
                       24, 25, 26, 27, 28, 12, 13)  # fmt: skip


@_memoized
def cnc_modal(cs: CommandSet, kind: int, block: int) -> LibraryCall:
    """0x21 or 0x22 ``(kind, block)`` [V] (:func:`_modal_request`; ValueError for a type the
    library refuses)."""
    request = _modal_request(kind, block)
    if request is None:
        raise ValueError(f"cnc_modal type {kind} is refused by the library")
    return _one("cnc_modal", request)


@_memoized
def cnc_rdgcode(cs: CommandSet, kind: int, block: int) -> LibraryCall:
    """0x96 ``(type, block)`` [V]."""
    return _one("cnc_rdgcode", GCodeRequest(kind, block))


@_memoized
def cnc_rdcommand(cs: CommandSet, kind: int, block: int) -> LibraryCall:
    """0x97 ``(type, block)`` [V]."""
    return _one("cnc_rdcommand", CommandRequest(kind, block))


@_memoized
def cnc_rdopmsg(cs: CommandSet) -> LibraryCall:
    """0x34 ``(0)`` (``cnc_rdopmsg`` and ``cnc_rdopmsg2``, type 0) [V]."""
    return _one("cnc_rdopmsg", OperatorMessageRequest(0))


@_memoized
def cnc_rdopmsg3(cs: CommandSet, kind: int, count: int) -> LibraryCall:
    """0x34 ``(type)`` at 16i class; 0xD0 ``(0, type, num)`` at 30i [V]."""
    if cs is _16I:
        return _one("cnc_rdopmsg3", OperatorMessageRequest(kind))
    return _one("cnc_rdopmsg3", OperatorMessage3Request(0, kind, count))


@_memoized
def cnc_exeprgname2(cs: CommandSet) -> LibraryCall:
    """0xFC [V]."""
    return _one("cnc_exeprgname2", ExecutingPathRequest())


@_memoized
def cnc_rdactpt(cs: CommandSet) -> LibraryCall:
    """0x162 [V]."""
    return _one("cnc_rdactpt", ActivePointerRequest())


@_memoized
def cnc_rdblkcount(cs: CommandSet) -> LibraryCall:
    """0x35 [V]."""
    return _one("cnc_rdblkcount", BlockCounterRequest())


@_memoized
def cnc_rdmdipntr(cs: CommandSet) -> LibraryCall:
    """0x38 (``cnc_rdmdipntr``, ``cnc_rdmdipntro8``) [V]."""
    return _one("cnc_rdmdipntr", MdiPointerRequest())
