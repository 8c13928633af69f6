"""Payload codecs of every command (``docs/protocol.md`` sections 3-5), declared once each.

Every payload is a frozen, slotted dataclass with ``encode()`` and ``decode(bytes)``; the
request codec the client encodes with is the one the server decodes with, and the same holds
for responses. :data:`COMMANDS` maps each command id to its :class:`CommandSpec`.

Responses of reads and writes start with ``i16 ew``; the response codecs here decode a non-zero
``ew`` to an :class:`EwReply` carrying the code (the client turns it into :class:`CncError`).
Counted lists (alarm messages, alarm history) carry their error inside their own dataclass.
"""

from __future__ import annotations

import enum
import struct
from dataclasses import dataclass
from decimal import Decimal
from typing import Any, ClassVar, Final, Self

from .._memo import Memoized
from .._typed import PASSWORD_SIZE, password_bytes
from ..errors import PayloadError
from ._base import I16, INT_RANGES, Codec, FixedPayload, field_error
from .alarms import ActiveAlarmList, AlarmHistory
from .commands import Command
from .faults import FaultList, FaultsCleared, FaultsRequest
from .pmc import PmcData, PmcRange
from .programs import (
    CycleControl,
    DirectoryRequest,
    LoadMeters,
    Overrides,
    ProgramChunk,
    ProgramChunkRequest,
    ProgramDirectory,
    ProgramNumber,
    ProgramText,
    RunInfo,
)
from .versamax import VersaMaxReply, VersaMaxRequest

__all__ = [
    "COMMANDS",
    "EW_OK_BYTES",
    "MAX_REAL_DECIMALS",
    "PASSWORD_SIZE",
    "ActualValue",
    "AlarmHistoryRequest",
    "AlarmMsgRequest",
    "AxisPosition",
    "ClearAlarms",
    "CommandSpec",
    "DataRequest",
    "EwReply",
    "InjectFault",
    "MacroRequest",
    "MacroValue",
    "ParamAttributes",
    "ParamAttributesRequest",
    "ParamDataType",
    "ParamValue",
    "Password",
    "PathNumber",
    "PathSelection",
    "PositionData",
    "PositionKind",
    "PositionRequest",
    "ProgramNumbers",
    "RaiseAlarm",
    "SetPanel",
    "StatusInfo",
    "SysInfo",
    "VacateMacro",
    "encode_ew",
    "encode_response",
]

#: ``i16 ew = 0``, the start of every successful read or write answer.
EW_OK_BYTES: Final = b"\x00\x00"


@dataclass(frozen=True, slots=True)
class EwReply:
    """A response that carries only a non-zero EW code."""

    ew: int


def encode_ew(ew: int) -> bytes:
    """The 2-byte ``i16 ew`` payload: ValueError naming a code outside -32768..32767, which
    no ``i16`` carries, TypeError for one that is no ``int``."""
    if isinstance(ew, bool) or not isinstance(ew, int):
        raise TypeError(f"an EW code must be an integer, got {ew!r}")
    if not -0x8000 <= ew <= 0x7FFF:
        raise ValueError(f"EW code {ew} is outside -32768..32767 (an i16)")
    return I16.pack(ew)


class _Empty:
    """The empty payload (requests of status/sysinfo, data part of write answers)."""

    @staticmethod
    def encode(_value: None) -> bytes:
        return b""

    @staticmethod
    def decode(data: bytes) -> None:
        if data:
            raise PayloadError(f"expected an empty payload, got {len(data)} bytes")


EMPTY: Final[Codec[None]] = Codec("Empty", _Empty.encode, _Empty.decode)


# -- fixed-layout payloads -----------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class StatusInfo(FixedPayload):
    """ODBST (``cnc_rdcncstat`` / ``cnc_statinfo``): 9 x i16."""

    FORMAT: ClassVar[str] = "<9h"
    hdck: int
    tmmode: int
    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int


@dataclass(frozen=True, slots=True)
class DataRequest(FixedPayload):
    """Request of ``cnc_rdparam`` and ``cnc_rddiag``: ``i16 datano, i16 axis``."""

    FORMAT: ClassVar[str] = "<hh"
    datano: int
    axis: int


@dataclass(frozen=True, slots=True)
class MacroRequest(FixedPayload):
    """Request of ``cnc_rdmacro``: ``i16 number``."""

    FORMAT: ClassVar[str] = "<h"
    number: int


@dataclass(frozen=True, slots=True)
class VacateMacro(FixedPayload):
    """Request of ``sim_vacate_macro`` (0x0E11): ``i16 number``, the variable made vacant."""

    FORMAT: ClassVar[str] = "<h"
    number: int


@dataclass(frozen=True, slots=True)
class MacroValue(FixedPayload):
    """ODBM: ``i16 number, i16 length (8), i32 mcr_val, i16 dec_val``.

    Value = ``mcr_val / 10**dec_val``; vacant is ``mcr_val = 0, dec_val = -1``.
    """

    FORMAT: ClassVar[str] = "<hhih"
    number: int
    length: int
    mcr_val: int
    dec_val: int

    @property
    def vacant(self) -> bool:
        return self.mcr_val == 0 and self.dec_val == -1


@dataclass(frozen=True, slots=True)
class SysInfo(FixedPayload):
    """ODBSYS (``cnc_sysinfo``): 18 bytes; the character fields are ASCII."""

    FORMAT: ClassVar[str] = "<hh2s2s4s4s2s"
    addinfo: int
    max_axis: int
    cnc_type: bytes
    mt_type: bytes
    series: bytes
    version: bytes
    axes: bytes

    @property
    def axes_count(self) -> int | None:
        """The ``axes`` field as a number ("03" -> 3), or None when not numeric."""
        text = self.axes.decode("latin-1").strip()
        return int(text) if text.isdigit() else None


@dataclass(frozen=True, slots=True)
class AlarmMsgRequest(FixedPayload):
    """Request of ``cnc_rdalmmsg``: ``i16 type`` (-1 all), ``i16 max`` (1..32)."""

    FORMAT: ClassVar[str] = "<hh"
    type: int
    max: int


@dataclass(frozen=True, slots=True)
class AlarmHistoryRequest(FixedPayload):
    """Request of ``cnc_rdalmhistry``: ``i16 depth`` (1..250)."""

    FORMAT: ClassVar[str] = "<h"
    depth: int


@dataclass(frozen=True, slots=True)
class Password(FixedPayload):
    """``cnc_wrunlockparam``: ``byte password[4]``, ASCII right-padded with NUL.

    A parameter password is 1..4 ASCII characters: :meth:`from_text` refuses anything else
    (a longer one is never cut: ``docs/protocol.md``)."""

    FORMAT: ClassVar[str] = "<4s"
    password: bytes

    @classmethod
    def from_text(cls, text: str | bytes) -> Self:
        """The payload of ``text``; ValueError, naming it, unless 1..4 ASCII characters
        (TypeError unless text or bytes): the one rule, :func:`~focas_net._typed.password_bytes`,
        which the machine and the command line apply too."""
        return cls(password_bytes(text))


@dataclass(frozen=True, slots=True)
class SetPanel(FixedPayload):
    """0x0E01: ``i16 mode`` (an ``aut`` value other than 2), ``i16 pwe``, ``i16 emergency``."""

    FORMAT: ClassVar[str] = "<hhh"
    mode: int
    pwe: int
    emergency: int


@dataclass(frozen=True, slots=True)
class ClearAlarms(FixedPayload):
    """0x0E03: ``i16 alm_type, i16 alm_no`` (-1 = any)."""

    FORMAT: ClassVar[str] = "<hh"
    alm_type: int
    alm_no: int


@dataclass(frozen=True, slots=True)
class InjectFault(FixedPayload):
    """0x0E05: ``i16 kind, i16 scope, i16 count, i32 arg``."""

    FORMAT: ClassVar[str] = "<hhhi"
    kind: int
    scope: int
    count: int
    arg: int


@dataclass(frozen=True, slots=True)
class ProgramNumbers(FixedPayload):
    """Answer of ``cnc_rdprgnum``: ``i32 running, i32 main`` (O numbers; 0 = none)."""

    FORMAT: ClassVar[str] = "<ii"
    running: int
    main: int


@dataclass(frozen=True, slots=True)
class ActualValue(FixedPayload):
    """Answer of ``cnc_actf`` (feed rate) and ``cnc_acts`` (spindle speed): ``i32 data``."""

    FORMAT: ClassVar[str] = "<i"
    data: int


class PositionKind(enum.IntEnum):
    """``type`` of ``cnc_rdposition``: which position is read."""

    ABSOLUTE = 0
    MACHINE = 1
    RELATIVE = 2
    DISTANCE = 3  # distance to go

    @classmethod
    def parse(cls, kind: str | int | PositionKind) -> PositionKind:
        """``"absolute"``, ``"machine"``, ``"relative"``, ``"distance"`` (or
        ``"distance_to_go"``), a ``PositionKind`` or 0..3; ValueError naming the kinds
        otherwise, TypeError for what is neither text nor an integer."""
        if isinstance(kind, PositionKind):
            return kind
        kinds = "absolute, machine, relative, distance or 0..3"
        if isinstance(kind, str):
            kinds = "absolute, machine, relative, distance, or 0..3 as an integer"
            key = kind.strip().upper().replace("-", "_")
            if key == "DISTANCE_TO_GO":
                key = "DISTANCE"
            try:
                return cls[key]
            except KeyError:
                raise ValueError(f"unknown position kind {kind!r} ({kinds})") from None
        if isinstance(kind, bool) or not isinstance(kind, int):
            raise TypeError(f"position kind must be a name, a PositionKind or 0..3, got {kind!r}")
        try:
            return cls(kind)
        except ValueError:
            raise ValueError(f"unknown position kind {kind!r} ({kinds})") from None


@dataclass(frozen=True, slots=True)
class PositionRequest(FixedPayload):
    """Request of ``cnc_rdposition``: ``i16 type`` (0..3), ``i16 axis`` (-1 all, 1..n)."""

    FORMAT: ClassVar[str] = "<hh"
    type: int
    axis: int


@dataclass(frozen=True, slots=True)
class PathNumber(FixedPayload):
    """Request of ``cnc_setpath`` (0x0140): ``i16 path``, the path the connection's per-path
    requests are answered for from now on (1..the machine's paths)."""

    FORMAT: ClassVar[str] = "<h"
    path: int


@dataclass(frozen=True, slots=True)
class PathSelection(FixedPayload):
    """Answer of ``cnc_getpath`` (0x0040) after ``ew``: ``i16 current`` (the connection's
    selected path; 0 after a refused ``cnc_setpath``: none), ``i16 max`` (the number of paths
    of the machine)."""

    FORMAT: ClassVar[str] = "<hh"
    current: int
    max: int


# -- variable-layout payloads --------------------------------------------------------------

_PARAM_HEAD: Final = struct.Struct("<hh")
_WIDTH_FORMATS: Final[dict[int, struct.Struct]] = {
    1: struct.Struct("<hhb"),
    2: struct.Struct("<hhh"),
    4: struct.Struct("<hhi"),
    8: struct.Struct("<hhii"),
}
_WIDTH_CODES: Final[dict[int, str]] = {1: "b", 2: "h", 4: "i", 8: "i"}
#: Most decimals of a real parameter value (REALPRM ``dec_val``).
MAX_REAL_DECIMALS: Final = 9


@dataclass(frozen=True, slots=True)
class ParamValue:
    """IODBPSD: ``i16 datano, i16 axis``, then the value as signed byte, i16 or i32, or for a
    real parameter FANUC's REALPRM: ``i32 prm_val, i32 dec_val`` (``docs/protocol.md`` section
    8), value ``prm_val / 10**dec_val``.

    The width (1, 2, 4 or 8) is implied by the payload length; ``decimals`` is the REALPRM's
    ``dec_val`` (0 for the other widths). Used by the answer of ``cnc_rdparam``/``cnc_rddiag``
    and by the request of ``cnc_wrparam``. A bit parameter travels as the signed byte holding
    its eight bits (``0b10110000`` is -80 here; see :attr:`bits`).
    """

    datano: int
    axis: int
    value: int
    width: int
    decimals: int = 0

    @property
    def bits(self) -> int:
        """The value as unsigned bits (a 1-byte value -80 is 176, ``0b10110000``)."""
        return self.value & ((1 << 8 * min(self.width, 4)) - 1)

    @property
    def real(self) -> Decimal:
        """The value as a decimal number: ``value / 10**decimals``."""
        return Decimal(self.value).scaleb(-self.decimals)

    def encode(self) -> bytes:
        st = _WIDTH_FORMATS.get(self.width)
        if st is None:
            raise ValueError(f"parameter width must be 1, 2, 4 or 8, got {self.width}")
        lo, hi = INT_RANGES[_WIDTH_CODES[self.width]]
        if not (isinstance(self.value, int) and lo <= self.value <= hi):
            kind = (
                "real parameter's mantissa" if self.width == 8 else f"{self.width}-byte parameter"
            )
            raise ValueError(f"value {self.value!r} does not fit a {kind} ({lo}..{hi})")
        for what, field in (("parameter number", self.datano), ("axis", self.axis)):
            if not (isinstance(field, int) and -0x8000 <= field <= 0x7FFF):
                raise ValueError(f"{what} {field!r} is outside -32768..32767")
        if self.width == 8:
            if not 0 <= self.decimals <= MAX_REAL_DECIMALS:
                raise ValueError(f"decimals {self.decimals} outside 0..{MAX_REAL_DECIMALS}")
            return st.pack(self.datano, self.axis, self.value, self.decimals)
        return st.pack(self.datano, self.axis, self.value)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        width = len(data) - 4
        st = _WIDTH_FORMATS.get(width)
        if st is None:
            raise PayloadError(f"IODBPSD of {len(data)} bytes (expected 5, 6, 8 or 12)")
        if width == 8:
            datano, axis, value, decimals = st.unpack(data)
            return cls(datano, axis, value, width, decimals)
        datano, axis, value = st.unpack(data)
        return cls(datano, axis, value, width)


class ParamDataType(enum.IntEnum):
    """``kind`` of ``cnc_rdparainfo``: a parameter's data type, FANUC's numbering."""

    BIT = 0
    BYTE = 1
    WORD = 2
    TWO_WORD = 3
    REAL = 4

    @property
    def label(self) -> str:
        """The type as every front end names it: ``bit``, ``byte``, ``word``, ``two-word``,
        ``real``."""
        return self.name.lower().replace("_", "-")


@dataclass(frozen=True, slots=True)
class ParamAttributesRequest(FixedPayload):
    """Request of ``cnc_rdparainfo``: ``i16 datano``."""

    FORMAT: ClassVar[str] = "<h"
    datano: int


@dataclass(frozen=True, slots=True)
class ParamAttributes(FixedPayload):
    """Answer of ``cnc_rdparainfo`` (one parameter): ``i16 datano, i16 kind`` (a
    :class:`ParamDataType`), ``i16 axis`` (1: an axis parameter, 0: not), ``i16 decimals`` (of a
    real parameter, else 0), ``i32 low, i32 high``: the range it accepts (a real parameter's
    in mantissas, a bit parameter's 0..255)."""

    FORMAT: ClassVar[str] = "<hhhhii"
    datano: int
    kind: int
    axis: int
    decimals: int
    low: int
    high: int

    @property
    def type(self) -> ParamDataType | None:
        """:attr:`kind` as a :class:`ParamDataType` (None for a number it does not have)."""
        return ParamDataType(self.kind) if self.kind in ParamDataType._value2member_map_ else None

    def __repr__(self) -> str:
        """Shown by its :attr:`type`, as the docs name it (a number with no type: its kind)."""
        kind = self.type
        shown = f"type=ParamDataType.{kind.name}" if kind is not None else f"kind={self.kind}"
        return (
            f"ParamAttributes(datano={self.datano}, {shown}, axis={self.axis}, "
            f"decimals={self.decimals}, low={self.low}, high={self.high})"
        )


_RAISE_HEAD: Final = struct.Struct("<hhhh")


@dataclass(frozen=True, slots=True)
class RaiseAlarm:
    """0x0E02: ``i16 axis_no, i16 alm_type, i16 alm_no, i16 msg_len, msg`` (ASCII)."""

    axis_no: int
    alm_type: int
    alm_no: int
    msg: bytes

    def encode(self) -> bytes:
        try:
            head = _RAISE_HEAD.pack(self.axis_no, self.alm_type, self.alm_no, len(self.msg))
        except struct.error as exc:
            fields: tuple[tuple[str, object, str], ...] = (
                ("axis", self.axis_no, "h"),
                ("alarm type", self.alm_type, "h"),
                ("alarm number", self.alm_no, "h"),
                ("message length", len(self.msg), "h"),
            )
            raise ValueError(field_error(fields, exc)) from None
        return head + self.msg

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 8:
            raise PayloadError(f"raise_alarm of {len(data)} bytes is shorter than its header")
        axis_no, alm_type, alm_no, msg_len = _RAISE_HEAD.unpack_from(data, 0)
        if msg_len != len(data) - 8:
            raise PayloadError(f"raise_alarm msg_len {msg_len}, {len(data) - 8} bytes sent")
        return cls(axis_no, alm_type, alm_no, data[8:])


_POS_HEAD: Final = struct.Struct("<hh")  # dec, count
_POS_ENTRY: Final = struct.Struct("<i4s")  # value, name
_POS_ENTRY_SIZE: Final = _POS_ENTRY.size


@dataclass(frozen=True, slots=True)
class AxisPosition:
    """One entry of a ``cnc_rdposition`` answer: the axis name (1..4 ASCII characters on a
    simulated machine; NUL-padded to 4 on the wire) and the value in least input increments."""

    name: str
    value: int


@dataclass(frozen=True, slots=True)
class PositionData:
    """Answer of ``cnc_rdposition`` after ``ew``: ``i16 dec, i16 count``, then ``count``
    entries of ``i32 value, char name[4]``. Value = ``value / 10**dec``."""

    dec: int
    axes: tuple[AxisPosition, ...]

    def encode(self) -> bytes:
        try:
            parts = [_POS_HEAD.pack(self.dec, len(self.axes))]
            for a in self.axes:
                raw = a.name.encode("latin-1")
                if len(raw) > 4 or b"\x00" in raw:
                    raise ValueError(f"axis name {a.name!r}: 0..4 characters, no NUL")
                parts.append(_POS_ENTRY.pack(a.value, raw))
        except (struct.error, UnicodeEncodeError) as exc:
            raise ValueError(f"position answer: {exc}") from None
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) < 4:
            raise PayloadError(f"position answer of {len(data)} bytes has no dec and count")
        dec, count = _POS_HEAD.unpack_from(data, 0)
        if count < 0 or len(data) != 4 + count * _POS_ENTRY_SIZE:
            raise PayloadError(f"position answer of {len(data)} bytes for count {count}")
        axes = tuple(
            AxisPosition(name.rstrip(b"\x00").decode("latin-1"), value)
            for value, name in _POS_ENTRY.iter_unpack(data[4:])
        )
        return cls(dec, axes)


# -- response wrapping -----------------------------------------------------------------------


def _ew_response(inner: Codec[Any], memo: int = 0) -> Codec[Any]:
    """An answer that starts with ``i16 ew``: 0 then ``inner``, else only the code.

    With ``memo`` > 0 the inner values are immutable (frozen dataclasses of ints and bytes) and
    ``decode`` keeps the values it decoded from ``bytes`` payloads in a dict keyed by the
    payload, emptied whenever it reaches ``memo`` entries: a poller reading the same status
    again and again gets the value it decoded before (equal, and as immutable) without
    building a new one. Its ``decode_bytes`` is that dict's own look-up (a payload not seen
    yet is decoded and kept by the dict's ``__missing__``).
    """
    inner_encode, inner_decode = inner.encode, inner.decode

    def encode(value: Any) -> bytes:
        if isinstance(value, EwReply):
            if value.ew == 0:
                raise ValueError("EwReply carries a non-zero code")
            return encode_ew(value.ew)
        return EW_OK_BYTES + inner_encode(value)

    def decode(data: bytes) -> Any:
        if len(data) < 2:
            raise PayloadError(f"answer of {len(data)} bytes has no EW code")
        if data[0] or data[1]:
            return EwReply(I16.unpack_from(data, 0)[0])
        return inner_decode(data[2:])

    if memo <= 0:
        return Codec(f"EW+{inner.name}", encode, decode)
    values = Memoized(memo, decode)
    decoded = values.__getitem__

    def memo_decode(data: bytes) -> Any:
        if type(data) is not bytes:  # bytearray, memoryview: not hashable (or not stable)
            return decode(data)
        return decoded(data)

    return Codec(f"EW+{inner.name}", encode, memo_decode, decoded)


def encode_response(command: int, value: Any) -> bytes:
    """Encode a response payload with the codec of ``command``."""
    return COMMANDS[command].response.encode(value)


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One row of the command table: ``focas_name`` is the call's name in this protocol
    (with the command id, what a wire's words name), :attr:`function` FANUC's library's."""

    command: Command
    focas_name: str
    request: Codec[Any]
    response: Codec[Any]
    counted: bool = False

    @property
    def function(self) -> str:
        """The function of FANUC's library a refusal of this call names (``cnc_diagnoss``
        where this protocol says ``cnc_rddiag``): a user reads one name on both transports."""
        return _LIBRARY_NAMES.get(self.focas_name, self.focas_name)

    def error_payload(self, ew: int) -> bytes:
        """The answer carrying only ``ew`` (``count = -1, ew`` for counted lists)."""
        return struct.pack("<hh", -1, ew) if self.counted else encode_ew(ew)


#: The calls this protocol names otherwise than FANUC's library (its table's names in brackets).
_LIBRARY_NAMES: Final = {"cnc_rdcncstat": "cnc_statinfo", "cnc_rddiag": "cnc_diagnoss"}


def _counted(cls: type[ActiveAlarmList] | type[AlarmHistory]) -> Codec[Any]:
    return Codec(cls.__name__, cls.encode, cls.decode)


def _spec(
    command: Command, name: str, request: Codec[Any], response: Codec[Any], counted: bool = False
) -> CommandSpec:
    return CommandSpec(command, name, request, response, counted)


_STATUS: Final = StatusInfo.codec()
_PARAM: Final = Codec("ParamValue", ParamValue.encode, ParamValue.decode)
_PMC_DATA: Final = Codec("PmcData", PmcData.encode, PmcData.decode)
_OK_ONLY: Final = _ew_response(EMPTY)
_ACTUAL: Final = ActualValue.codec()
#: Entries of the decoded-answer memo of each read command (see :func:`_ew_response`).
_MEMO: Final = 256

#: Part programs and the cycle (``protocol/programs.py``).
_PROGRAM_SPECS: Final = (
    _spec(
        Command.RDPROGDIR,
        "cnc_rdprogdir",
        DirectoryRequest.codec(),
        _ew_response(Codec("ProgramDirectory", ProgramDirectory.encode, ProgramDirectory.decode)),
    ),
    _spec(
        Command.RDPROGRAM,
        "cnc_upload",
        ProgramChunkRequest.codec(),
        _ew_response(Codec("ProgramChunk", ProgramChunk.encode, ProgramChunk.decode)),
    ),
    _spec(Command.RDRUNINFO, "cnc_rdtimer", EMPTY, _ew_response(RunInfo.codec())),
    _spec(
        Command.RDLOADS,
        "cnc_rdspload",
        EMPTY,
        _ew_response(Codec("LoadMeters", LoadMeters.encode, LoadMeters.decode), _MEMO),
    ),
    _spec(
        Command.WRPROGRAM,
        "cnc_download",
        Codec("ProgramText", ProgramText.encode, ProgramText.decode),
        _ew_response(ProgramNumber.codec()),
    ),
    _spec(Command.DELPROGRAM, "cnc_delete", ProgramNumber.codec(), _OK_ONLY),
    _spec(Command.SELPROGRAM, "cnc_search", ProgramNumber.codec(), _OK_ONLY),
    _spec(Command.SIM_CYCLE, "sim_cycle", CycleControl.codec(), _OK_ONLY),
    _spec(Command.SIM_SET_OVERRIDES, "sim_set_overrides", Overrides.codec(), _OK_ONLY),
)

#: command id -> request and response codecs.
COMMANDS: Final[dict[int, CommandSpec]] = {
    s.command.value: s
    for s in (
        _spec(Command.RDCNCSTAT, "cnc_rdcncstat", EMPTY, _ew_response(_STATUS, _MEMO)),
        _spec(Command.RDPARAM, "cnc_rdparam", DataRequest.codec(), _ew_response(_PARAM, _MEMO)),
        _spec(
            Command.RDMACRO,
            "cnc_rdmacro",
            MacroRequest.codec(),
            _ew_response(MacroValue.codec(), _MEMO),
        ),
        _spec(Command.RDDIAG, "cnc_rddiag", DataRequest.codec(), _ew_response(_PARAM, _MEMO)),
        _spec(Command.SYSINFO, "cnc_sysinfo", EMPTY, _ew_response(SysInfo.codec(), _MEMO)),
        _spec(
            Command.RDALMMSG,
            "cnc_rdalmmsg",
            AlarmMsgRequest.codec(),
            _counted(ActiveAlarmList),
            counted=True,
        ),
        _spec(Command.RDPRGNUM, "cnc_rdprgnum", EMPTY, _ew_response(ProgramNumbers.codec(), _MEMO)),
        _spec(Command.ACTF, "cnc_actf", EMPTY, _ew_response(_ACTUAL, _MEMO)),
        _spec(Command.ACTS, "cnc_acts", EMPTY, _ew_response(_ACTUAL, _MEMO)),
        _spec(
            Command.RDPOSITION,
            "cnc_rdposition",
            PositionRequest.codec(),
            _ew_response(Codec("PositionData", PositionData.encode, PositionData.decode), _MEMO),
        ),
        _spec(Command.RDPMCRNG, "pmc_rdpmcrng", PmcRange.codec(), _ew_response(_PMC_DATA, _MEMO)),
        _spec(Command.WRPARAM, "cnc_wrparam", _PARAM, _OK_ONLY),
        _spec(Command.WRMACRO, "cnc_wrmacro", MacroValue.codec(), _OK_ONLY),
        _spec(Command.WRPMCRNG, "pmc_wrpmcrng", _PMC_DATA, _OK_ONLY),
        _spec(Command.WRUNLOCKPARAM, "cnc_wrunlockparam", Password.codec(), _OK_ONLY),
        _spec(Command.GETPATH, "cnc_getpath", EMPTY, _ew_response(PathSelection.codec())),
        _spec(Command.SETPATH, "cnc_setpath", PathNumber.codec(), _OK_ONLY),
        _spec(
            Command.VERSAMAX_RDCONFIG,
            "versamax_rdconfig",
            Codec("VersaMaxRequest", VersaMaxRequest.encode, VersaMaxRequest.decode),
            _ew_response(Codec("VersaMaxReply", VersaMaxReply.encode, VersaMaxReply.decode)),
        ),
        _spec(Command.SIM_SET_PANEL, "sim_set_panel", SetPanel.codec(), _OK_ONLY),
        _spec(
            Command.SIM_READ_PANEL,
            "sim_read_panel",
            EMPTY,
            _ew_response(SetPanel.codec()),
        ),
        _spec(Command.SIM_VACATE_MACRO, "sim_vacate_macro", VacateMacro.codec(), _OK_ONLY),
        _spec(
            Command.RDPARAINFO,
            "cnc_rdparainfo",
            ParamAttributesRequest.codec(),
            _ew_response(ParamAttributes.codec(), _MEMO),
        ),
        _spec(
            Command.SIM_RAISE_ALARM,
            "sim_raise_alarm",
            Codec("RaiseAlarm", RaiseAlarm.encode, RaiseAlarm.decode),
            _OK_ONLY,
        ),
        _spec(Command.SIM_CLEAR_ALARMS, "sim_clear_alarms", ClearAlarms.codec(), _OK_ONLY),
        _spec(Command.SIM_SET_PMC, "sim_set_pmc", _PMC_DATA, _OK_ONLY),
        _spec(Command.SIM_INJECT_FAULT, "sim_inject_fault", InjectFault.codec(), _OK_ONLY),
        _spec(
            Command.SIM_LIST_FAULTS,
            "sim_list_faults",
            FaultsRequest.codec(),
            _ew_response(Codec("FaultList", FaultList.encode, FaultList.decode)),
        ),
        _spec(
            Command.SIM_CLEAR_FAULTS,
            "sim_clear_faults",
            FaultsRequest.codec(),
            _ew_response(FaultsCleared.codec()),
        ),
        _spec(
            Command.RDALMHISTRY,
            "cnc_rdalmhistry",
            AlarmHistoryRequest.codec(),
            _counted(AlarmHistory),
            counted=True,
        ),
        *_PROGRAM_SPECS,
    )
}
