"""Codec of FANUC's own FOCAS/2 Ethernet protocol (the one real controls speak on TCP 8193).

Pure and synchronous: bytes in, objects out. Everything is big-endian. Layout, as documented in
``docs/native-protocol.md``:

* **frame**: ``A0 A0 A0 A0``, ``u16 version``, ``u16 type``, ``u16 length`` (bytes of body that
  follow), then the body. Types: 0x0101/0x0102 open request/response, 0x0201/0x0202 close
  request/response, 0x2101/0x2102 data request/response.
* **data request body**: ``u16 count``, then ``count`` request blocks, each ``u16 length``
  (including itself), ``u16 device`` (1 CNC, 2 PMC), ``u16 path``, ``u16 command``,
  ``5 x i32`` arguments, then ``length - 28`` extra bytes (data of a write).
* **data response body**: ``u16 count``, then one response block per request block, in order:
  ``u16 length`` (16 + data), ``u16 device``, ``u16 path``, ``u16 command`` (all echoed),
  ``i16 ew``, ``i16 detail1``, ``i16 detail2``, ``u16 data length``, then the data.

On top of the blocks sit the typed requests (one frozen dataclass per command, with
``to_block``/``from_block``) and the typed reply data (one frozen dataclass per shape, with
``encode``/``decode``), each declared once and used by both sides.

Exceptions (all derive from :class:`NativeProtocolError`, itself a
:class:`focas_net.errors.ProtocolError`)::

    NativeProtocolError          anything this codec refuses to decode
     +-- NativeFrameError        bad magic, length above the maximum, broken block structure:
     |                           the connection cannot be resynchronised and must be closed
     |                           (also a focas_net FrameError)
     +-- NativePayloadError      one block whose arguments or data do not fit its command
                                 (a request on the server, reply data on the client);
                                 ``ew`` is the code to answer a request block with (also a
                                 focas_net PayloadError)

Decoding arbitrary bytes raises nothing else. Encoding a value that cannot be put on the wire
raises :class:`ValueError` (a programming error, not a peer error).
"""

from __future__ import annotations

import enum
import math
import struct
from dataclasses import dataclass
from typing import ClassVar, Final, NamedTuple, Self

from focas_net.errors import EW, FrameError, PayloadError, ProtocolError

__all__ = [
    "CLIENT_VERSION",
    "DEFAULT_MAX_BODY",
    "DEFAULT_SERVER_VERSION",
    "HEADER",
    "HEADER_SIZE",
    "MAGIC",
    "REQUEST_BLOCK_SIZE",
    "REQUEST_TYPES",
    "RESPONSE_BLOCK_SIZE",
    "SCALED_SIZE",
    "VACANT",
    "ActualFeedRequest",
    "ActualSpindleSpeedRequest",
    "AlarmMessage",
    "AlarmMessageRequest",
    "AlarmMessages",
    "Device",
    "DiagnosticRequest",
    "FrameType",
    "ItemRecord",
    "ItemValues",
    "MacroDoubleReadRequest",
    "MacroDoubleWriteRequest",
    "MacroDoubles",
    "MacroReadRequest",
    "NativeCommand",
    "NativeFrame",
    "NativeFrameDecoder",
    "NativeFrameError",
    "NativePayloadError",
    "NativeProtocolError",
    "NativeRequest",
    "OpenRequest",
    "ParamRead3Request",
    "ParamReadRequest",
    "PmcArea",
    "PmcData",
    "PmcDataType",
    "PmcReadRequest",
    "PositionKind",
    "PositionRequest",
    "ProgramNumberRequest",
    "ProgramNumbers",
    "RequestBlock",
    "ResponseBlock",
    "ScaledItemRecord",
    "ScaledItemValues",
    "ScaledNumber",
    "ScaledValues",
    "StatInfo",
    "StatInfoRequest",
    "SysInfo",
    "SysInfoRequest",
    "decode_frame",
    "decode_request",
    "decode_request_body",
    "decode_response_body",
    "encode_close_request",
    "encode_close_response",
    "encode_frame",
    "encode_open_request",
    "encode_open_response",
    "encode_request",
    "encode_request_body",
    "encode_response",
    "encode_response_body",
    "max_response_body",
    "resolve_position_kind",
]


# --------------------------------------------------------------------------------------------
# Exceptions


class NativeProtocolError(ProtocolError):
    """The peer sent bytes the native FOCAS/2 Ethernet protocol does not allow."""


class NativeFrameError(NativeProtocolError, FrameError):
    """Framing violation (bad magic, oversize length, broken block list): close the connection."""


class NativePayloadError(NativeProtocolError, PayloadError):
    """A block's arguments or data do not fit its command.

    On the server the block is answered with :attr:`ew` (the connection stays up).
    """

    def __init__(self, message: str, ew: int = EW.LENGTH) -> None:
        super().__init__(message)
        self.ew: int = ew


# --------------------------------------------------------------------------------------------
# Frame


#: The four sync bytes that open every frame.
MAGIC: Final = b"\xa0\xa0\xa0\xa0"
_MAGIC_U32: Final = 0xA0A0A0A0
#: ``magic, u16 version, u16 type, u16 length``.
HEADER: Final = struct.Struct(">IHHH")
HEADER_SIZE: Final = HEADER.size
#: Version word clients send (pyfocas, pyfanuc and FANUC's library all send 1).
CLIENT_VERSION: Final = 1
#: Version word this codec puts on responses unless told otherwise (16i-series controls send 2,
#: 0i-D 3, 30i 4); it keeps every response within 1450 body bytes, see :func:`max_response_body`.
DEFAULT_SERVER_VERSION: Final = 2
#: Default ceiling of an incoming frame's body (the decoder refuses more before buffering).
DEFAULT_MAX_BODY: Final = 4096
_U16_MAX: Final = 0xFFFF


class FrameType(enum.IntEnum):
    """The ``type`` word of a frame."""

    OPEN_REQUEST = 0x0101
    OPEN_RESPONSE = 0x0102
    CLOSE_REQUEST = 0x0201
    CLOSE_RESPONSE = 0x0202
    DATA_REQUEST = 0x2101
    DATA_RESPONSE = 0x2102


class NativeFrame(NamedTuple):
    """One decoded frame: its version word, its type word and its body."""

    version: int
    type: int
    body: bytes


def max_response_body(version: int) -> int:
    """Largest response body a FANUC library accepts for a response carrying ``version``.

    Reported from FANUC's own library: 1450 bytes for version 1 or 2, 2910 for 3, 3470 above.
    """
    if version <= 2:
        return 1450
    if version == 3:
        return 2910
    return 3470


_pack_header = HEADER.pack
_unpack_header_from = HEADER.unpack_from


def encode_frame(frame_type: int, body: bytes = b"", version: int = CLIENT_VERSION) -> bytes:
    """The bytes of one frame."""
    if len(body) > _U16_MAX:
        raise ValueError(f"frame body of {len(body)} bytes exceeds {_U16_MAX}")
    try:
        return _pack_header(_MAGIC_U32, version, frame_type, len(body)) + body
    except struct.error as exc:
        raise ValueError(f"frame header: {exc}") from None


def decode_frame(data: bytes, max_body: int = _U16_MAX) -> NativeFrame:
    """Decode exactly one whole frame (no trailing bytes); raises :class:`NativeFrameError`."""
    if len(data) < HEADER_SIZE:
        raise NativeFrameError(f"frame of {len(data)} bytes is shorter than its header")
    magic, version, frame_type, length = _unpack_header_from(data)
    if magic != _MAGIC_U32:
        raise NativeFrameError("frame does not start with A0 A0 A0 A0")
    if length > max_body:
        raise NativeFrameError(f"frame body length {length} exceeds {max_body}")
    if len(data) != HEADER_SIZE + length:
        raise NativeFrameError(
            f"frame announces {length} body bytes but carries {len(data) - HEADER_SIZE}"
        )
    return NativeFrame(version, frame_type, bytes(data[HEADER_SIZE:]))


class NativeFrameDecoder:
    """Incremental frame decoder.

    ``feed(chunk)`` returns every frame completed by ``chunk`` (possibly none) and keeps the
    trailing partial frame. The magic is checked byte by byte as it arrives, and the length word
    against ``max_body`` as soon as the 10-byte header is in, before any of the body is
    buffered. A violation raises :class:`NativeFrameError`; the decoder is then poisoned and
    every further ``feed`` raises the same error (the connection must be closed).
    """

    __slots__ = ("_buf", "_error", "max_body")

    def __init__(self, max_body: int = DEFAULT_MAX_BODY) -> None:
        if not 0 <= max_body <= _U16_MAX:
            raise ValueError(f"max_body must be within 0..{_U16_MAX}, got {max_body}")
        self.max_body = max_body
        self._buf = bytearray()
        self._error: NativeFrameError | None = None

    @property
    def buffered(self) -> int:
        """Bytes held for a frame not yet complete."""
        return len(self._buf)

    def _fail(self, message: str) -> NativeFrameError:
        self._buf.clear()
        self._error = NativeFrameError(message)
        return self._error

    def feed(self, data: bytes | bytearray | memoryview) -> list[NativeFrame]:
        """Add ``data`` and return every frame now complete, in order."""
        if self._error is not None:
            raise self._error
        buf = self._buf
        if buf:
            held = len(buf)
            if held < HEADER_SIZE:
                # Complete and check the pending header before taking in any body bytes.
                need = HEADER_SIZE - held
                buf += data[:need]
                data = data[need:]
                if len(buf) < HEADER_SIZE:
                    if not MAGIC.startswith(bytes(buf[:4])):
                        raise self._fail("frame does not start with A0 A0 A0 A0")
                    return []
                magic, _, _, length = _unpack_header_from(buf)
                if magic != _MAGIC_U32:
                    raise self._fail("frame does not start with A0 A0 A0 A0")
                if length > self.max_body:
                    raise self._fail(f"frame body length {length} exceeds {self.max_body}")
            buf += data
            view: bytes | bytearray | memoryview = buf
        else:
            view = data
        frames: list[NativeFrame] = []
        size = len(view)
        pos = 0
        max_body = self.max_body
        while pos < size:
            avail = size - pos
            if avail < HEADER_SIZE:
                head = bytes(view[pos : pos + min(avail, 4)])
                if not MAGIC.startswith(head):
                    raise self._fail("frame does not start with A0 A0 A0 A0")
                break
            magic, version, frame_type, length = _unpack_header_from(view, pos)
            if magic != _MAGIC_U32:
                raise self._fail("frame does not start with A0 A0 A0 A0")
            if length > max_body:
                raise self._fail(f"frame body length {length} exceeds {max_body}")
            end = pos + HEADER_SIZE + length
            if end > size:
                break
            frames.append(NativeFrame(version, frame_type, bytes(view[pos + HEADER_SIZE : end])))
            pos = end
        if view is buf:
            if pos:
                del buf[:pos]
        elif pos < size:
            buf += view[pos:]
        return frames


# Open / close handshake

_U16: Final = struct.Struct(">H")
#: Open-response body sent by default: 16 zero bytes (a header announcing no records).
_OPEN_RESPONSE_BODY: Final = bytes(16)


@dataclass(frozen=True, slots=True)
class OpenRequest:
    """Body of an open request: one ``u16``.

    pyfocas and pyfanuc send 2; FANUC's library sends 1 on its first (control) connection and
    2 on its second (data) connection.
    """

    channel: int = 2

    def encode(self) -> bytes:
        try:
            return _U16.pack(self.channel)
        except struct.error as exc:
            raise ValueError(f"OpenRequest: {exc}") from None

    @classmethod
    def decode(cls, body: bytes) -> Self:
        if len(body) != 2:
            raise NativeFrameError(f"open request body of {len(body)} bytes, expected 2")
        return cls(_U16.unpack(body)[0])


def encode_open_request(channel: int = 2, version: int = CLIENT_VERSION) -> bytes:
    """A whole open-request frame (pyfocas sends ``A0A0A0A0 0001 0101 0002 0002``)."""
    return encode_frame(FrameType.OPEN_REQUEST, OpenRequest(channel).encode(), version)


def encode_open_response(
    body: bytes = _OPEN_RESPONSE_BODY, version: int = DEFAULT_SERVER_VERSION
) -> bytes:
    """A whole open-response frame (its body is not interpreted by pyfocas or pyfanuc)."""
    return encode_frame(FrameType.OPEN_RESPONSE, body, version)


def encode_close_request(version: int = CLIENT_VERSION) -> bytes:
    """A whole close-request frame: ``A0A0A0A0 0001 0201 0000``."""
    return encode_frame(FrameType.CLOSE_REQUEST, b"", version)


def encode_close_response(version: int = DEFAULT_SERVER_VERSION) -> bytes:
    """A whole close-response frame, empty body."""
    return encode_frame(FrameType.CLOSE_RESPONSE, b"", version)


# --------------------------------------------------------------------------------------------
# Blocks


class Device(enum.IntEnum):
    """The ``device`` (class) word of a block."""

    CNC = 1
    PMC = 2


#: ``u16 length, u16 device, u16 path, u16 command, 5 x i32``.
_REQUEST_BLOCK: Final = struct.Struct(">HHHHiiiii")
REQUEST_BLOCK_SIZE: Final = _REQUEST_BLOCK.size
#: ``u16 length, u16 device, u16 path, u16 command, i16 ew, i16 detail1, i16 detail2, u16 len``.
_RESPONSE_BLOCK: Final = struct.Struct(">HHHHhhhH")
RESPONSE_BLOCK_SIZE: Final = _RESPONSE_BLOCK.size
_ZERO_ARGS: Final = (0, 0, 0, 0, 0)


@dataclass(frozen=True, slots=True)
class RequestBlock:
    """One request block: a command, its five arguments and any extra bytes."""

    device: int
    path: int
    command: int
    args: tuple[int, int, int, int, int] = _ZERO_ARGS
    extra: bytes = b""

    def encode(self) -> bytes:
        """The bytes of this block, length word included."""
        try:
            return (
                _REQUEST_BLOCK.pack(
                    REQUEST_BLOCK_SIZE + len(self.extra),
                    self.device,
                    self.path,
                    self.command,
                    *self.args,
                )
                + self.extra
            )
        except (struct.error, TypeError) as exc:
            raise ValueError(f"RequestBlock: {exc}") from None

    def reply(self, data: bytes = b"", ew: int = 0) -> ResponseBlock:
        """The response block answering this one (device, path and command echoed)."""
        return ResponseBlock(self.device, self.path, self.command, ew, data)


@dataclass(frozen=True, slots=True)
class ResponseBlock:
    """One response block: the echoed command, the EW code and the data."""

    device: int
    path: int
    command: int
    ew: int = 0
    data: bytes = b""
    detail1: int = 0
    detail2: int = 0

    def encode(self) -> bytes:
        """The bytes of this block, length word included."""
        size = RESPONSE_BLOCK_SIZE + len(self.data)
        if size > _U16_MAX:
            raise ValueError(f"response block data of {len(self.data)} bytes is too long")
        try:
            return (
                _RESPONSE_BLOCK.pack(
                    size,
                    self.device,
                    self.path,
                    self.command,
                    self.ew,
                    self.detail1,
                    self.detail2,
                    len(self.data),
                )
                + self.data
            )
        except struct.error as exc:
            raise ValueError(f"ResponseBlock: {exc}") from None


def encode_request_body(blocks: tuple[RequestBlock, ...] | list[RequestBlock]) -> bytes:
    """``u16 count`` followed by the blocks."""
    if len(blocks) > _U16_MAX:
        raise ValueError(f"{len(blocks)} blocks exceed {_U16_MAX}")
    return _U16.pack(len(blocks)) + b"".join(block.encode() for block in blocks)


def encode_request(
    blocks: tuple[RequestBlock, ...] | list[RequestBlock], version: int = CLIENT_VERSION
) -> bytes:
    """A whole data-request frame carrying ``blocks``."""
    return encode_frame(FrameType.DATA_REQUEST, encode_request_body(blocks), version)


def decode_request_body(body: bytes) -> tuple[RequestBlock, ...]:
    """The blocks of a data-request body.

    An empty body (FANUC's library sends one during its handshake) decodes to no blocks.
    Anything that does not walk to exactly the end of the body raises
    :class:`NativeFrameError`.
    """
    size = len(body)
    if size == 0:
        return ()
    if size < 2:
        raise NativeFrameError("data request body shorter than its block count")
    (count,) = _U16.unpack_from(body, 0)
    pos = 2
    blocks: list[RequestBlock] = []
    unpack_block = _REQUEST_BLOCK.unpack_from
    for index in range(count):
        if size - pos < REQUEST_BLOCK_SIZE:
            raise NativeFrameError(f"request block {index} of {count} is truncated")
        length, device, path, command, a1, a2, a3, a4, a5 = unpack_block(body, pos)
        if length < REQUEST_BLOCK_SIZE or pos + length > size:
            raise NativeFrameError(f"request block {index} has a bad length {length}")
        extra = bytes(body[pos + REQUEST_BLOCK_SIZE : pos + length])
        blocks.append(RequestBlock(device, path, command, (a1, a2, a3, a4, a5), extra))
        pos += length
    if pos != size:
        raise NativeFrameError(f"{size - pos} bytes follow the last request block")
    return tuple(blocks)


def encode_response_body(blocks: tuple[ResponseBlock, ...] | list[ResponseBlock]) -> bytes:
    """``u16 count`` followed by the blocks."""
    if len(blocks) > _U16_MAX:
        raise ValueError(f"{len(blocks)} blocks exceed {_U16_MAX}")
    return _U16.pack(len(blocks)) + b"".join(block.encode() for block in blocks)


def encode_response(
    blocks: tuple[ResponseBlock, ...] | list[ResponseBlock],
    version: int = DEFAULT_SERVER_VERSION,
) -> bytes:
    """A whole data-response frame; :class:`ValueError` if its body exceeds what ``version``
    allows (:func:`max_response_body`)."""
    body = encode_response_body(blocks)
    limit = max_response_body(version)
    if len(body) > limit:
        raise ValueError(f"response body of {len(body)} bytes exceeds {limit} (version {version})")
    return encode_frame(FrameType.DATA_RESPONSE, body, version)


def decode_response_body(body: bytes) -> tuple[ResponseBlock, ...]:
    """The blocks of a data-response body (the client side); raises :class:`NativeFrameError`."""
    size = len(body)
    if size < 2:
        raise NativeFrameError("data response body shorter than its block count")
    (count,) = _U16.unpack_from(body, 0)
    pos = 2
    blocks: list[ResponseBlock] = []
    unpack_block = _RESPONSE_BLOCK.unpack_from
    for index in range(count):
        if size - pos < RESPONSE_BLOCK_SIZE:
            raise NativeFrameError(f"response block {index} of {count} is truncated")
        length, device, path, command, ew, detail1, detail2, data_len = unpack_block(body, pos)
        if length != RESPONSE_BLOCK_SIZE + data_len or pos + length > size:
            raise NativeFrameError(f"response block {index} has a bad length {length}")
        data = bytes(body[pos + RESPONSE_BLOCK_SIZE : pos + length])
        blocks.append(ResponseBlock(device, path, command, ew, data, detail1, detail2))
        pos += length
    if pos != size:
        raise NativeFrameError(f"{size - pos} bytes follow the last response block")
    return tuple(blocks)


# --------------------------------------------------------------------------------------------
# Commands and typed requests


class NativeCommand(enum.IntEnum):
    """Command words of the supported requests (FOCAS function each one serves)."""

    RDPARAM = 0x0E  # cnc_rdparam (16i style: 4-byte value slots)
    RDMACRO = 0x15  # cnc_rdmacro / cnc_rdmacror: scaled numbers
    SYSINFO = 0x18  # cnc_sysinfo: ODBSYS
    STATINFO = 0x19  # cnc_statinfo: ODBST
    RDPRGNUM = 0x1C  # cnc_rdprgnum: running and main program numbers
    RDALMMSG = 0x23  # cnc_rdalmmsg / cnc_rdalmmsg2: alarm messages
    ACTF = 0x24  # cnc_actf: actual feed rate
    ACTS = 0x25  # cnc_acts: actual spindle speed
    POSITION = 0x26  # cnc_absolute / cnc_machine / cnc_relative / cnc_distance / cnc_skip
    RDDIAG = 0x30  # cnc_diagnoss (16i style: 4-byte value slots)
    RDPARAM3 = 0x8D  # cnc_rdparam on 30i-style controls (8-byte scaled slots)
    RDMACRO_DOUBLE = 0xA7  # cnc_rdmacror2: IEEE doubles
    WRMACRO_DOUBLE = 0xA8  # cnc_wrmacror2: IEEE double
    PMC_RDPMCRNG = 0x8001  # pmc_rdpmcrng (device PMC)


class NativeRequest:
    """Base of the typed requests: a command with its arguments, as one frozen dataclass.

    ``to_block(path)`` builds the block a client sends; ``from_block(block)`` reads it back on
    the server and raises :class:`NativePayloadError` (with the EW code to answer) when the
    block does not fit.
    """

    __slots__ = ()
    DEVICE: ClassVar[int] = Device.CNC
    COMMAND: ClassVar[int]

    def args(self) -> tuple[int, int, int, int, int]:
        """The five arguments of the block."""
        return _ZERO_ARGS

    def extra(self) -> bytes:
        """The extra bytes of the block."""
        return b""

    def to_block(self, path: int = 1) -> RequestBlock:
        """The request block of this request."""
        return RequestBlock(self.DEVICE, path, self.COMMAND, self.args(), self.extra())

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        """The typed request carried by ``block``."""
        return cls()


@dataclass(frozen=True, slots=True)
class SysInfoRequest(NativeRequest):
    """cnc_sysinfo (0x18): no arguments; answered with :class:`SysInfo`."""

    COMMAND: ClassVar[int] = NativeCommand.SYSINFO


@dataclass(frozen=True, slots=True)
class StatInfoRequest(NativeRequest):
    """cnc_statinfo (0x19): no arguments; answered with :class:`StatInfo`."""

    COMMAND: ClassVar[int] = NativeCommand.STATINFO


@dataclass(frozen=True, slots=True)
class ProgramNumberRequest(NativeRequest):
    """cnc_rdprgnum (0x1C): no arguments; answered with :class:`ProgramNumbers`."""

    COMMAND: ClassVar[int] = NativeCommand.RDPRGNUM


@dataclass(frozen=True, slots=True)
class ActualFeedRequest(NativeRequest):
    """cnc_actf (0x24): no arguments; answered with one :class:`ScaledNumber`."""

    COMMAND: ClassVar[int] = NativeCommand.ACTF


@dataclass(frozen=True, slots=True)
class ActualSpindleSpeedRequest(NativeRequest):
    """cnc_acts (0x25): no arguments; answered with one :class:`ScaledNumber`."""

    COMMAND: ClassVar[int] = NativeCommand.ACTS


@dataclass(frozen=True, slots=True)
class MacroReadRequest(NativeRequest):
    """Macro read as scaled numbers (0x15): args ``first, last`` (inclusive numbers).

    Answered with :class:`ScaledValues`, one 8-byte record per variable.
    """

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO
    first: int
    last: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.last, 0, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1])


@dataclass(frozen=True, slots=True)
class MacroDoubleReadRequest(NativeRequest):
    """Macro read as doubles (0xA7): args ``first, count`` (a count, not a last number).

    Answered with :class:`MacroDoubles`.
    """

    COMMAND: ClassVar[int] = NativeCommand.RDMACRO_DOUBLE
    first: int
    count: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.count, 0, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1])


_DOUBLE: Final = struct.Struct(">d")
_NAN_BITS: Final = b"\x7f\xf8\x00\x00\x00\x00\x00\x00"


def _pack_double(value: float | None) -> bytes:
    if value is None:
        return _NAN_BITS
    if math.isnan(value):
        raise ValueError("NaN is reserved for a vacant variable; pass None")
    return _DOUBLE.pack(value)


def _unpack_double(data: bytes | memoryview, offset: int) -> float | None:
    (value,) = _DOUBLE.unpack_from(data, offset)
    return None if math.isnan(value) else float(value)


@dataclass(frozen=True, slots=True)
class MacroDoubleWriteRequest(NativeRequest):
    """Macro write as a double (0xA8): args ``number, 0, 0, 0, 8`` then 8 bytes of IEEE double.

    ``value`` None writes a vacant variable (sent as a quiet NaN, this project's choice).
    Answered with no data.
    """

    COMMAND: ClassVar[int] = NativeCommand.WRMACRO_DOUBLE
    number: int
    value: float | None

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.number, 0, 0, 0, _DOUBLE.size)

    def extra(self) -> bytes:
        return _pack_double(self.value)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        if len(block.extra) != _DOUBLE.size:
            raise NativePayloadError(
                f"macro double write carries {len(block.extra)} data bytes, expected 8", EW.LENGTH
            )
        return cls(block.args[0], _unpack_double(block.extra, 0))


@dataclass(frozen=True, slots=True)
class ParamReadRequest(NativeRequest):
    """Parameter read, 16i style (0x0E): args ``first, last, axis``.

    ``axis`` 0 for a non-axis item, n for axis n, -1 for all axes. Answered with
    :class:`ItemValues` (4-byte value slots).
    """

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM
    first: int
    last: int
    axis: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.last, self.axis, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1], block.args[2])


@dataclass(frozen=True, slots=True)
class ParamRead3Request(NativeRequest):
    """Parameter read, 30i style (0x8D): args ``first, last, axis``.

    Answered with :class:`ScaledItemValues` (8-byte scaled value slots).
    """

    COMMAND: ClassVar[int] = NativeCommand.RDPARAM3
    first: int
    last: int
    axis: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.last, self.axis, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1], block.args[2])


@dataclass(frozen=True, slots=True)
class DiagnosticRequest(NativeRequest):
    """Diagnostic read (0x30): args ``first, last, axis``; answered with :class:`ItemValues`."""

    COMMAND: ClassVar[int] = NativeCommand.RDDIAG
    first: int
    last: int
    axis: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.last, self.axis, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1], block.args[2])


class PmcArea(enum.IntEnum):
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


class PmcDataType(enum.IntEnum):
    """PMC data types and their width in bytes (``1 << value``)."""

    BYTE = 0
    WORD = 1
    LONG = 2

    @property
    def width(self) -> int:
        return 1 << self.value


@dataclass(frozen=True, slots=True)
class PmcReadRequest(NativeRequest):
    """pmc_rdpmcrng (device PMC, 0x8001): args ``first, last, area, data_type``.

    ``first`` and ``last`` are inclusive byte addresses (``last = first + width * count - 1``).
    Answered with :class:`PmcData`.
    """

    DEVICE: ClassVar[int] = Device.PMC
    COMMAND: ClassVar[int] = NativeCommand.PMC_RDPMCRNG
    first: int
    last: int
    area: int
    data_type: int

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.first, self.last, self.area, self.data_type, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1], block.args[2], block.args[3])


@dataclass(frozen=True, slots=True)
class AlarmMessageRequest(NativeRequest):
    """Alarm messages (0x23): args ``alarm_type, count, text_mode, text_length``.

    ``alarm_type`` -1 for every type; ``count`` the most entries wanted; the text is filled only
    when ``text_mode`` is non-zero (FANUC's library sends 2); every entry carries a text field of
    ``text_length`` bytes (FANUC's library asks 64). Answered with :class:`AlarmMessages`.
    """

    COMMAND: ClassVar[int] = NativeCommand.RDALMMSG
    alarm_type: int = -1
    count: int = 10
    text_mode: int = 2
    text_length: int = 64

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.alarm_type, self.count, self.text_mode, self.text_length, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        a = block.args
        return cls(a[0], a[1], a[2], a[3])


class PositionKind(enum.Enum):
    """What a position read (0x26) asks for."""

    ABSOLUTE = "absolute"
    MACHINE = "machine"
    RELATIVE = "relative"
    DISTANCE = "distance"
    SKIP = "skip"


#: Both numberings seen in public captures: 4/1/6/7/8 (cnc_absolute family, pyfanuc, FANUC's
#: library) and 0..3 (cnc_rdposition style); 1 means the machine position in both.
_POSITION_KINDS: Final[dict[int, PositionKind]] = {
    0: PositionKind.ABSOLUTE,
    1: PositionKind.MACHINE,
    2: PositionKind.RELATIVE,
    3: PositionKind.DISTANCE,
    4: PositionKind.ABSOLUTE,
    6: PositionKind.RELATIVE,
    7: PositionKind.DISTANCE,
    8: PositionKind.SKIP,
}


def resolve_position_kind(code: int) -> PositionKind | None:
    """The position a 0x26 kind code asks for, or None for a code this codec does not know."""
    return _POSITION_KINDS.get(code)


@dataclass(frozen=True, slots=True)
class PositionRequest(NativeRequest):
    """Positions (0x26): args ``kind, axis`` (axis -1 = all axes, n = axis n).

    Answered with :class:`ScaledValues`, one record per axis.
    """

    COMMAND: ClassVar[int] = NativeCommand.POSITION
    kind: int
    axis: int = -1

    @property
    def position_kind(self) -> PositionKind | None:
        return resolve_position_kind(self.kind)

    def args(self) -> tuple[int, int, int, int, int]:
        return (self.kind, self.axis, 0, 0, 0)

    @classmethod
    def from_block(cls, block: RequestBlock) -> Self:
        return cls(block.args[0], block.args[1])


#: The one table of supported requests, keyed by ``(device, command)``.
REQUEST_TYPES: Final[dict[tuple[int, int], type[NativeRequest]]] = {
    (cls.DEVICE, cls.COMMAND): cls
    for cls in (
        SysInfoRequest,
        StatInfoRequest,
        ProgramNumberRequest,
        ActualFeedRequest,
        ActualSpindleSpeedRequest,
        MacroReadRequest,
        MacroDoubleReadRequest,
        MacroDoubleWriteRequest,
        ParamReadRequest,
        ParamRead3Request,
        DiagnosticRequest,
        PmcReadRequest,
        AlarmMessageRequest,
        PositionRequest,
    )
}


def decode_request(block: RequestBlock) -> NativeRequest | None:
    """The typed request of ``block``; None when the command is not supported (answer it with
    EW_FUNC); :class:`NativePayloadError` when the block does not fit its command."""
    cls = REQUEST_TYPES.get((block.device, block.command))
    if cls is None:
        return None
    return cls.from_block(block)


# --------------------------------------------------------------------------------------------
# Reply data


def _need(data: bytes, size: int, what: str) -> None:
    if len(data) != size:
        raise NativePayloadError(f"{what}: {len(data)} bytes, expected {size}", EW.LENGTH)


def _fixed_text(value: str, size: int, what: str) -> bytes:
    try:
        raw = value.encode("latin-1")
    except UnicodeEncodeError:
        raw = b""
    if len(raw) != size:
        raise ValueError(f"{what} must be exactly {size} single-byte characters, got {value!r}")
    return raw


_SYSINFO: Final = struct.Struct(">hh2s2s4s4s2s")


@dataclass(frozen=True, slots=True)
class SysInfo:
    """Reply data of 0x18: ODBSYS, 18 bytes; the texts are fixed-width ASCII (space padded)."""

    addinfo: int
    max_axis: int
    cnc_type: str
    mt_type: str
    series: str
    version: str
    axes: str

    def encode(self) -> bytes:
        try:
            return _SYSINFO.pack(
                self.addinfo,
                self.max_axis,
                _fixed_text(self.cnc_type, 2, "cnc_type"),
                _fixed_text(self.mt_type, 2, "mt_type"),
                _fixed_text(self.series, 4, "series"),
                _fixed_text(self.version, 4, "version"),
                _fixed_text(self.axes, 2, "axes"),
            )
        except struct.error as exc:
            raise ValueError(f"SysInfo: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        _need(data, _SYSINFO.size, "SysInfo")
        addinfo, max_axis, cnc, mt, series, version, axes = _SYSINFO.unpack(data)
        return cls(
            addinfo,
            max_axis,
            cnc.decode("latin-1"),
            mt.decode("latin-1"),
            series.decode("latin-1"),
            version.decode("latin-1"),
            axes.decode("latin-1"),
        )


_STATINFO: Final = struct.Struct(">7h")


@dataclass(frozen=True, slots=True)
class StatInfo:
    """Reply data of 0x19: 7 x i16 ``aut, run, motion, mstb, emergency, alarm, edit``."""

    aut: int
    run: int
    motion: int
    mstb: int
    emergency: int
    alarm: int
    edit: int

    def encode(self) -> bytes:
        try:
            return _STATINFO.pack(
                self.aut, self.run, self.motion, self.mstb, self.emergency, self.alarm, self.edit
            )
        except struct.error as exc:
            raise ValueError(f"StatInfo: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        _need(data, _STATINFO.size, "StatInfo")
        return cls(*_STATINFO.unpack(data))


_PROGRAM_NUMBERS: Final = struct.Struct(">ii")


@dataclass(frozen=True, slots=True)
class ProgramNumbers:
    """Reply data of 0x1C: ``i32 running, i32 main``."""

    running: int
    main: int

    def encode(self) -> bytes:
        try:
            return _PROGRAM_NUMBERS.pack(self.running, self.main)
        except struct.error as exc:
            raise ValueError(f"ProgramNumbers: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        _need(data, _PROGRAM_NUMBERS.size, "ProgramNumbers")
        return cls(*_PROGRAM_NUMBERS.unpack(data))


_SCALED: Final = struct.Struct(">ihh")
SCALED_SIZE: Final = _SCALED.size


@dataclass(frozen=True, slots=True)
class ScaledNumber:
    """The 8-byte number record: ``i32 mantissa, i16 base, i16 decimals``.

    Value = mantissa / base ** decimals; base is 10 (some clients also accept 2). A vacant
    variable is ``decimals = -1`` (bytes 6..7 = FF FF) with mantissa 0.
    """

    mantissa: int
    decimals: int
    base: int = 10

    @property
    def vacant(self) -> bool:
        return self.decimals == -1

    def to_float(self) -> float | None:
        """The value, or None when vacant."""
        if self.vacant:
            return None
        if self.base == 0:
            return float(self.mantissa)
        return float(self.mantissa / self.base**self.decimals)

    @classmethod
    def from_float(cls, value: float, decimals: int) -> Self:
        """``value`` rounded to ``decimals`` places (0..9); ValueError if it does not fit."""
        if not 0 <= decimals <= 9:
            raise ValueError(f"decimals must be 0..9, got {decimals}")
        if not math.isfinite(value):
            raise ValueError(f"{value} cannot be sent as a scaled number")
        mantissa = round(value * 10**decimals)
        if not -(2**31) <= mantissa < 2**31:
            raise ValueError(f"{value} with {decimals} decimals does not fit 32 bits")
        return cls(mantissa, decimals)

    def encode(self) -> bytes:
        try:
            return _SCALED.pack(self.mantissa, self.base, self.decimals)
        except struct.error as exc:
            raise ValueError(f"ScaledNumber: {exc}") from None

    @classmethod
    def decode(cls, data: bytes) -> Self:
        _need(data, SCALED_SIZE, "ScaledNumber")
        mantissa, base, decimals = _SCALED.unpack(data)
        return cls(mantissa, decimals, base)


#: The record of a vacant variable.
VACANT: Final = ScaledNumber(0, -1)


def _scaled_tuple(data: bytes | memoryview, start: int, count: int) -> tuple[ScaledNumber, ...]:
    unpack = _SCALED.unpack_from
    out: list[ScaledNumber] = []
    for i in range(count):
        mantissa, base, decimals = unpack(data, start + i * SCALED_SIZE)
        out.append(ScaledNumber(mantissa, decimals, base))
    return tuple(out)


def _encode_scaled(values: tuple[ScaledNumber, ...]) -> bytes:
    return b"".join(v.encode() for v in values)


@dataclass(frozen=True, slots=True)
class ScaledValues:
    """Reply data of 0x15 (macros), 0x24 (feed), 0x25 (spindle) and 0x26 (positions):
    consecutive 8-byte :class:`ScaledNumber` records."""

    values: tuple[ScaledNumber, ...]

    def encode(self) -> bytes:
        return _encode_scaled(self.values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) % SCALED_SIZE:
            raise NativePayloadError(
                f"ScaledValues: {len(data)} bytes is not a multiple of 8", EW.LENGTH
            )
        return cls(_scaled_tuple(data, 0, len(data) // SCALED_SIZE))


@dataclass(frozen=True, slots=True)
class MacroDoubles:
    """Reply data of 0xA7: one 8-byte IEEE double per variable; None = vacant (sent as NaN)."""

    values: tuple[float | None, ...]

    def encode(self) -> bytes:
        return b"".join(_pack_double(v) for v in self.values)

    @classmethod
    def decode(cls, data: bytes) -> Self:
        if len(data) % _DOUBLE.size:
            raise NativePayloadError(
                f"MacroDoubles: {len(data)} bytes is not a multiple of 8", EW.LENGTH
            )
        return cls(tuple(_unpack_double(data, i) for i in range(0, len(data), _DOUBLE.size)))


_ITEM_HEAD: Final = struct.Struct(">ihh")
_I32: Final = struct.Struct(">i")


@dataclass(frozen=True, slots=True)
class ItemRecord:
    """One parameter/diagnostic record with 4-byte slots (0x0E, 0x30).

    ``i32 number, i16 axis (0 non-axis, n, -1 all), i16 type``, then ``max_axis`` slots of
    ``i32`` (a byte or word value sign-extended). A non-axis or single-axis item uses the first
    slot; the others are zero.
    """

    number: int
    axis: int
    type: int
    values: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class ItemValues:
    """Reply data of 0x0E and 0x30: ``records``, each ``8 + 4 * max_axis`` bytes."""

    records: tuple[ItemRecord, ...]

    def encode(self, max_axis: int) -> bytes:
        parts: list[bytes] = []
        try:
            for r in self.records:
                if len(r.values) != max_axis:
                    raise ValueError(f"record {r.number} has {len(r.values)} slots, not {max_axis}")
                parts.append(_ITEM_HEAD.pack(r.number, r.axis, r.type))
                parts.append(struct.pack(f">{max_axis}i", *r.values))
        except struct.error as exc:
            raise ValueError(f"ItemValues: {exc}") from None
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, max_axis: int) -> Self:
        if max_axis < 1:
            raise ValueError(f"max_axis must be positive, got {max_axis}")
        size = _ITEM_HEAD.size + 4 * max_axis
        if len(data) % size:
            raise NativePayloadError(
                f"ItemValues: {len(data)} bytes is not a multiple of {size}", EW.LENGTH
            )
        slots = struct.Struct(f">{max_axis}i")
        records = []
        for pos in range(0, len(data), size):
            number, axis, kind = _ITEM_HEAD.unpack_from(data, pos)
            values = slots.unpack_from(data, pos + _ITEM_HEAD.size)
            records.append(ItemRecord(number, axis, kind, values))
        return cls(tuple(records))


@dataclass(frozen=True, slots=True)
class ScaledItemRecord:
    """One parameter record with 8-byte scaled slots (0x8D): the same 8-byte head as
    :class:`ItemRecord`, then ``max_axis`` :class:`ScaledNumber` slots."""

    number: int
    axis: int
    type: int
    values: tuple[ScaledNumber, ...]


@dataclass(frozen=True, slots=True)
class ScaledItemValues:
    """Reply data of 0x8D: ``records``, each ``8 + 8 * max_axis`` bytes."""

    records: tuple[ScaledItemRecord, ...]

    def encode(self, max_axis: int) -> bytes:
        parts: list[bytes] = []
        try:
            for r in self.records:
                if len(r.values) != max_axis:
                    raise ValueError(f"record {r.number} has {len(r.values)} slots, not {max_axis}")
                parts.append(_ITEM_HEAD.pack(r.number, r.axis, r.type))
                parts.append(_encode_scaled(r.values))
        except struct.error as exc:
            raise ValueError(f"ScaledItemValues: {exc}") from None
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, max_axis: int) -> Self:
        if max_axis < 1:
            raise ValueError(f"max_axis must be positive, got {max_axis}")
        size = _ITEM_HEAD.size + SCALED_SIZE * max_axis
        if len(data) % size:
            raise NativePayloadError(
                f"ScaledItemValues: {len(data)} bytes is not a multiple of {size}", EW.LENGTH
            )
        records = []
        for pos in range(0, len(data), size):
            number, axis, kind = _ITEM_HEAD.unpack_from(data, pos)
            values = _scaled_tuple(data, pos + _ITEM_HEAD.size, max_axis)
            records.append(ScaledItemRecord(number, axis, kind, values))
        return cls(tuple(records))


@dataclass(frozen=True, slots=True)
class PmcData:
    """Reply data of 0x8001: the bytes of the range; words and longs are big-endian."""

    raw: bytes

    def encode(self) -> bytes:
        return self.raw

    @classmethod
    def decode(cls, data: bytes) -> Self:
        return cls(bytes(data))

    def values(self, data_type: int) -> tuple[int, ...]:
        """The unsigned values of ``data_type`` (0 byte, 1 word, 2 long)."""
        kind = _pmc_type(data_type)
        if len(self.raw) % kind.width:
            raise NativePayloadError(
                f"PmcData: {len(self.raw)} bytes is not a multiple of {kind.width}", EW.LENGTH
            )
        fmt = {1: "B", 2: "H", 4: "I"}[kind.width]
        return struct.unpack(f">{len(self.raw) // kind.width}{fmt}", self.raw)

    @classmethod
    def from_values(cls, data_type: int, values: tuple[int, ...] | list[int]) -> Self:
        """The reply carrying unsigned ``values`` of ``data_type``."""
        kind = _pmc_type(data_type)
        fmt = {1: "B", 2: "H", 4: "I"}[kind.width]
        try:
            return cls(struct.pack(f">{len(values)}{fmt}", *values))
        except struct.error as exc:
            raise ValueError(f"PmcData: {exc}") from None


def _pmc_type(data_type: int) -> PmcDataType:
    try:
        return PmcDataType(data_type)
    except ValueError:
        raise NativePayloadError(f"PMC data type {data_type} unknown", EW.ATTRIB) from None


_ALARM_HEAD: Final = struct.Struct(">iiii")


@dataclass(frozen=True, slots=True)
class AlarmMessage:
    """One alarm entry of 0x23: number, type, axis and the message bytes (ASCII on this side)."""

    number: int
    alarm_type: int
    axis: int
    message: bytes


@dataclass(frozen=True, slots=True)
class AlarmMessages:
    """Reply data of 0x23: per entry ``i32 number, i32 type, i32 axis, i32 msg_len``, then a
    text field of exactly ``text_length`` bytes (the request's 4th argument), the message then
    zero padding. No active alarm is zero bytes."""

    alarms: tuple[AlarmMessage, ...]

    def encode(self, text_length: int) -> bytes:
        if text_length < 0:
            raise ValueError(f"text_length must not be negative, got {text_length}")
        parts: list[bytes] = []
        try:
            for a in self.alarms:
                if len(a.message) > text_length:
                    raise ValueError(f"message of {len(a.message)} bytes exceeds {text_length}")
                parts.append(_ALARM_HEAD.pack(a.number, a.alarm_type, a.axis, len(a.message)))
                parts.append(a.message.ljust(text_length, b"\x00"))
        except struct.error as exc:
            raise ValueError(f"AlarmMessages: {exc}") from None
        return b"".join(parts)

    @classmethod
    def decode(cls, data: bytes, text_length: int) -> Self:
        if text_length < 0:
            raise ValueError(f"text_length must not be negative, got {text_length}")
        size = _ALARM_HEAD.size + text_length
        if len(data) % size:
            raise NativePayloadError(
                f"AlarmMessages: {len(data)} bytes is not a multiple of {size}", EW.LENGTH
            )
        alarms = []
        for pos in range(0, len(data), size):
            number, kind, axis, msg_len = _ALARM_HEAD.unpack_from(data, pos)
            if not 0 <= msg_len <= text_length:
                raise NativePayloadError(
                    f"AlarmMessages: message length {msg_len} outside 0..{text_length}", EW.LENGTH
                )
            start = pos + _ALARM_HEAD.size
            alarms.append(AlarmMessage(number, kind, axis, bytes(data[start : start + msg_len])))
        return cls(tuple(alarms))
