"""Request and answer blocks: the bodies of data frames (``0x2101`` / ``0x2102``).

* **data request body**: ``u16 count``, then ``count`` request blocks, each
  :class:`RequestBlockHead` (``u16 length`` = 28 + extra, ``u16 device`` (class: 1 CNC,
  2 PMC), ``u16 path``, ``u16 command``, ``5 x i32`` arguments), then ``length - 28`` extra
  bytes (the data of a write).
* **data answer body**: ``u16 count``, then one answer block per request block, in order, each
  :class:`ResponseBlockHead` (``u16 length`` = 16 + data, ``u16 device``, ``u16 path``,
  ``u16 command`` (echoed), ``i16 ew``, ``i16 detail1``, ``i16 detail2``, ``u16 data length``),
  then the data.

FANUC's library refuses an answer body whose block count is 0, differs from the number of
request blocks, or whose block lengths do not add up to exactly the body
(:func:`answer_refusal` says which); it does not check the echoed device, path and command, nor
the data-length word (but counts records from it, so it must be right).
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar, Final

from .base import NativeFrameError, NativeRecord
from .frame import (
    CLIENT_VERSION,
    DEFAULT_SERVER_VERSION,
    FrameType,
    encode_native_frame,
    max_response_body,
)

__all__ = [
    "REQUEST_BLOCK_SIZE",
    "RESPONSE_BLOCK_SIZE",
    "BlockCount",
    "Device",
    "RequestBlock",
    "RequestBlockHead",
    "ResponseBlock",
    "ResponseBlockHead",
    "answer_refusal",
    "decode_request_body",
    "decode_response_body",
    "encode_native_response",
    "encode_request",
    "encode_request_body",
    "encode_response_body",
]

_U16_MAX: Final = 0xFFFF


class Device(enum.IntEnum):
    """The ``device`` (class) word of a block."""

    CNC = 1
    PMC = 2


@dataclass(frozen=True, slots=True)
class BlockCount(NativeRecord):
    """The ``u16`` block count that opens every data body."""

    FORMAT: ClassVar[str] = ">H"
    count: int


@dataclass(frozen=True, slots=True)
class RequestBlockHead(NativeRecord):
    """The 28-byte head of a request block: length (28 + extra), device, path, command and the
    five i32 arguments."""

    FORMAT: ClassVar[str] = ">HHHHiiiii"
    length: int
    device: int
    path: int
    command: int
    arg1: int
    arg2: int
    arg3: int
    arg4: int
    arg5: int


@dataclass(frozen=True, slots=True)
class ResponseBlockHead(NativeRecord):
    """The 16-byte head of an answer block: length (16 + data), device, path, command, EW code,
    two detail words (``cnc_getdtailerr`` for EW_NUMBER) and the data length."""

    FORMAT: ClassVar[str] = ">HHHHhhhH"
    length: int
    device: int
    path: int
    command: int
    ew: int
    detail1: int
    detail2: int
    data_length: int


_REQUEST_BLOCK: Final = RequestBlockHead.STRUCT
REQUEST_BLOCK_SIZE: Final = RequestBlockHead.SIZE
_RESPONSE_BLOCK: Final = ResponseBlockHead.STRUCT
RESPONSE_BLOCK_SIZE: Final = ResponseBlockHead.SIZE
_U16: Final = BlockCount.STRUCT
_ZERO_ARGS: Final = (0, 0, 0, 0, 0)


@dataclass(frozen=True, slots=True)
class RequestBlock:
    """One request block: a command, its five arguments and any extra bytes."""

    device: int
    path: int
    command: int
    args: tuple[int, int, int, int, int] = _ZERO_ARGS
    extra: bytes = b""

    @property
    def head(self) -> RequestBlockHead:
        """The block's 28-byte head."""
        return RequestBlockHead(
            REQUEST_BLOCK_SIZE + len(self.extra), self.device, self.path, self.command, *self.args
        )

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
        """The answer block to this one (device, path and command echoed)."""
        return ResponseBlock(self.device, self.path, self.command, ew, data)


@dataclass(frozen=True, slots=True)
class ResponseBlock:
    """One answer block: the echoed command, the EW code and the data."""

    device: int
    path: int
    command: int
    ew: int = 0
    data: bytes = b""
    detail1: int = 0
    detail2: int = 0

    @property
    def head(self) -> ResponseBlockHead:
        """The block's 16-byte head."""
        size = len(self.data)
        return ResponseBlockHead(
            RESPONSE_BLOCK_SIZE + size,
            self.device,
            self.path,
            self.command,
            self.ew,
            self.detail1,
            self.detail2,
            size,
        )

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


def encode_request_body(blocks: Sequence[RequestBlock]) -> bytes:
    """``u16 count`` followed by the blocks."""
    if len(blocks) > _U16_MAX:
        raise ValueError(f"{len(blocks)} blocks exceed {_U16_MAX}")
    return _U16.pack(len(blocks)) + b"".join(block.encode() for block in blocks)


def encode_request(blocks: Sequence[RequestBlock], version: int = CLIENT_VERSION) -> bytes:
    """A whole data-request frame carrying ``blocks``."""
    return encode_native_frame(FrameType.DATA_REQUEST, encode_request_body(blocks), version)


def decode_request_body(body: bytes) -> tuple[RequestBlock, ...]:
    """The blocks of a data-request body.

    An empty body decodes to no blocks (FANUC's library sends ``00 00``, zero blocks, only when
    the open answer announced no path). Anything that does not walk to exactly the end of the
    body raises :class:`NativeFrameError`.
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


def encode_response_body(blocks: Sequence[ResponseBlock]) -> bytes:
    """``u16 count`` followed by the blocks."""
    if len(blocks) > _U16_MAX:
        raise ValueError(f"{len(blocks)} blocks exceed {_U16_MAX}")
    return _U16.pack(len(blocks)) + b"".join(block.encode() for block in blocks)


def encode_native_response(
    blocks: Sequence[ResponseBlock], version: int = DEFAULT_SERVER_VERSION
) -> bytes:
    """A whole data-response frame; :class:`ValueError` if its body exceeds what ``version``
    allows (:func:`max_response_body`)."""
    body = encode_response_body(blocks)
    limit = max_response_body(version)
    if len(body) > limit:
        raise ValueError(f"response body of {len(body)} bytes exceeds {limit} (version {version})")
    return encode_native_frame(FrameType.DATA_RESPONSE, body, version)


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


def answer_refusal(body: bytes, request_blocks: int, version: int) -> str | None:
    """Why FANUC's library would refuse the data-answer ``body`` to a request of
    ``request_blocks`` blocks, answered with ``version``; None when it would take it.

    The library's checks (it returns EW_PROTOCOL, -17, on each): the body fits
    :func:`max_response_body`, it holds a block count, the count is neither 0 nor different
    from the request's, and the block lengths add up to exactly the body.
    """
    limit = max_response_body(version)
    if len(body) > limit:
        return f"PDU data size({len(body)}) is larger than MTU({limit})"
    if len(body) < 2:
        return "body shorter than its block count"
    (count,) = _U16.unpack_from(body, 0)
    if count == 0:
        return "RB count(0) incorrect"
    if count != request_blocks:
        return f"RB count({count}) differs from the {request_blocks} request blocks"
    pos = 2
    for index in range(count):
        if len(body) - pos < 2:
            return f"sum of RB size is larger than total (block {index})"
        (length,) = _U16.unpack_from(body, pos)
        if length < 2:
            return f"RB size({length}) of block {index} incorrect"
        pos += length
    if pos > len(body):
        return "sum of RB size is larger than total"
    if pos < len(body):
        return "sum of RB size is smaller than total"
    return None
