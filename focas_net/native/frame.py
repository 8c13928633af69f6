"""Frames of FANUC's FOCAS/2 Ethernet protocol, and the open and close exchanges.

A frame is ``A0 A0 A0 A0``, ``u16 version``, ``u16 type``, ``u16 length`` (body bytes that
follow), then the body; every integer is big-endian. FANUC's library builds the type word as
two bytes, a *kind* (``0x01`` open, ``0x02`` close, ``0x21`` data) and a *direction* (``0x01``
request, ``0x02`` answer, ``0x03`` error answer), and only checks that an answer's kind matches
its request's.

The errors are in :mod:`.base` (:class:`NativeFrameError` for a framing violation).
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar, Final, NamedTuple

from focas_net.errors import ProtocolError

from .base import NativeFrameError, NativeRecord

__all__ = [
    "CLIENT_VERSION",
    "DEFAULT_MAX_BODY",
    "DEFAULT_SERVER_VERSION",
    "LIBRARY_MAX_REQUEST_BODY",
    "MAGIC",
    "MAGIC_WORD",
    "NATIVE_HEADER",
    "NATIVE_HEADER_SIZE",
    "FrameType",
    "NativeFrame",
    "NativeFrameDecoder",
    "OpenRequest",
    "check_server_max_body",
    "decode_frame",
    "encode_close_request",
    "encode_close_response",
    "encode_native_frame",
    "encode_open_request",
    "encode_open_response",
    "max_response_body",
]


# --------------------------------------------------------------------------------------------
# Frame


#: The four sync bytes that open every frame.
MAGIC: Final = b"\xa0\xa0\xa0\xa0"
#: :data:`MAGIC` as the ``u32`` that opens :data:`NATIVE_HEADER`.
MAGIC_WORD: Final = 0xA0A0A0A0
#: ``magic, u16 version, u16 type, u16 length``.
NATIVE_HEADER: Final = struct.Struct(">IHHH")
NATIVE_HEADER_SIZE: Final = NATIVE_HEADER.size
#: Version word clients send (pyfocas, pyfanuc and FANUC's library all send 1).
CLIENT_VERSION: Final = 1
#: Version word this codec puts on responses unless told otherwise (16i-series controls send 2,
#: 0i-D 3, 30i 4); it keeps every response within 1450 body bytes, see :func:`max_response_body`.
DEFAULT_SERVER_VERSION: Final = 2
#: Default ceiling of an incoming frame's body (the decoder refuses more before buffering).
DEFAULT_MAX_BODY: Final = 4096
#: The longest request body FANUC's library sends: it cuts a PMC write into requests of at
#: most 1450 body bytes, whatever the answer version; a download's data frames carry 1280
#: and a transfer start 516 [V, libfwlib32 1.0.5]. A server's body limit is at least this.
LIBRARY_MAX_REQUEST_BODY: Final = 1450
_U16_MAX: Final = 0xFFFF


def check_server_max_body(value: int, name: str) -> int:
    """``value`` as a server's limit on an incoming frame's body, the argument called ``name``:
    :class:`ValueError` below :data:`LIBRARY_MAX_REQUEST_BODY` (with less, FANUC's library's
    requests would close the connection before any answer) or above 65535."""
    if not LIBRARY_MAX_REQUEST_BODY <= value <= _U16_MAX:
        raise ValueError(
            f"{name} must be within {LIBRARY_MAX_REQUEST_BODY}..{_U16_MAX}, got {value}: "
            f"FANUC's library sends request bodies of up to {LIBRARY_MAX_REQUEST_BODY} bytes "
            "(a PMC write is cut into requests of that size)"
        )
    return value


class FrameType(enum.IntEnum):
    """The ``type`` word of a frame: kind byte (0x01 open, 0x02 close, 0x21 data), then the
    direction byte (0x01 request, 0x02 answer, 0x03 error answer)."""

    OPEN_REQUEST = 0x0101
    OPEN_RESPONSE = 0x0102
    CLOSE_REQUEST = 0x0201
    CLOSE_RESPONSE = 0x0202
    DATA_REQUEST = 0x2101
    DATA_RESPONSE = 0x2102
    #: An error answer to a data request; FANUC's library reads its body as four i16 words
    #: ``loc, code, detail1, detail2`` and returns ``code``. Never needed: put the code in the
    #: answer block instead.
    DATA_ERROR = 0x2103


class NativeFrame(NamedTuple):
    """One decoded frame: its version word, its type word and its body."""

    version: int
    type: int
    body: bytes


def max_response_body(version: int) -> int:
    """Largest answer body FANUC's library accepts in an answer carrying ``version``.

    1450 bytes up to version 2, 2910 for 3, 3470 for 4 and 4950 above (the library refuses one
    byte more with EW_PROTOCOL and drops the connection; verified with libfwlib32 1.0.5 at
    1450/1451 and 2910/2911, and from its code for 3470 and 4950).
    """
    if version <= 2:
        return 1450
    if version == 3:
        return 2910
    if version == 4:
        return 3470
    return 4950


_pack_header = NATIVE_HEADER.pack
_unpack_header_from = NATIVE_HEADER.unpack_from


def encode_native_frame(frame_type: int, body: bytes = b"", version: int = CLIENT_VERSION) -> bytes:
    """The bytes of one frame."""
    if len(body) > _U16_MAX:
        raise ValueError(f"frame body of {len(body)} bytes exceeds {_U16_MAX}")
    try:
        return _pack_header(MAGIC_WORD, version, frame_type, len(body)) + body
    except struct.error as exc:
        raise ValueError(f"frame header: {exc}") from None


def decode_frame(data: bytes, max_body: int = _U16_MAX) -> NativeFrame:
    """Decode exactly one whole frame (no trailing bytes); raises :class:`NativeFrameError`."""
    if len(data) < NATIVE_HEADER_SIZE:
        raise NativeFrameError(f"frame of {len(data)} bytes is shorter than its header")
    magic, version, frame_type, length = _unpack_header_from(data)
    if magic != MAGIC_WORD:
        raise NativeFrameError("frame does not start with A0 A0 A0 A0")
    if length > max_body:
        raise NativeFrameError(f"frame body length {length} exceeds {max_body}")
    if len(data) != NATIVE_HEADER_SIZE + length:
        raise NativeFrameError(
            f"frame announces {length} body bytes but carries {len(data) - NATIVE_HEADER_SIZE}"
        )
    return NativeFrame(version, frame_type, bytes(data[NATIVE_HEADER_SIZE:]))


class NativeFrameDecoder:
    """Incremental frame decoder.

    ``feed(chunk)`` returns every frame completed by ``chunk`` (possibly none) and keeps the
    trailing partial frame. The magic is checked byte by byte as it arrives, and the length word
    against ``max_body`` as soon as the 10-byte header is in, before any of the body is
    buffered. A violation raises :class:`NativeFrameError`, whose ``frames`` are the frames the
    same ``feed`` completed before it (to be answered before closing, as the packed decoder
    does); the decoder is then poisoned and every further ``feed`` raises the same error (the
    connection must be closed).
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

    def _fail(self, message: str, frames: list[NativeFrame] | None = None) -> NativeFrameError:
        """Poison the decoder; the error raised carries the ``frames`` this ``feed`` completed
        before the violation (a later ``feed`` raises the error alone)."""
        self._buf.clear()
        self._error = NativeFrameError(message)
        return NativeFrameError(message, frames)

    def feed(self, data: bytes | bytearray | memoryview) -> list[NativeFrame]:
        """Add ``data`` and return every frame now complete, in order."""
        if self._error is not None:
            raise self._error
        buf = self._buf
        if buf:
            held = len(buf)
            if held < NATIVE_HEADER_SIZE:
                # Complete and check the pending header before taking in any body bytes.
                need = NATIVE_HEADER_SIZE - held
                buf += data[:need]
                data = data[need:]
                if len(buf) < NATIVE_HEADER_SIZE:
                    if not MAGIC.startswith(bytes(buf[:4])):
                        raise self._fail("frame does not start with A0 A0 A0 A0")
                    return []
                magic, _, _, length = _unpack_header_from(buf)
                if magic != MAGIC_WORD:
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
            if avail < NATIVE_HEADER_SIZE:
                head = bytes(view[pos : pos + min(avail, 4)])
                if not MAGIC.startswith(head):
                    raise self._fail("frame does not start with A0 A0 A0 A0", frames)
                break
            magic, version, frame_type, length = _unpack_header_from(view, pos)
            if magic != MAGIC_WORD:
                raise self._fail("frame does not start with A0 A0 A0 A0", frames)
            if length > max_body:
                raise self._fail(f"frame body length {length} exceeds {max_body}", frames)
            end = pos + NATIVE_HEADER_SIZE + length
            if end > size:
                break
            frames.append(
                NativeFrame(version, frame_type, bytes(view[pos + NATIVE_HEADER_SIZE : end]))
            )
            pos = end
        if view is buf:
            if pos:
                del buf[:pos]
        elif pos < size:
            buf += view[pos:]
        return frames


# Open / close handshake

_U16: Final = struct.Struct(">H")
#: Open-response body sent when none is given: 16 zero bytes (a version 2 header announcing no
#: path). It passes the size check of FANUC's library but leads to its refusal one step later;
#: build a real one with :func:`focas_net.native.build_open_answer`.
_OPEN_RESPONSE_BODY: Final = bytes(16)


@dataclass(frozen=True, slots=True)
class OpenRequest(NativeRecord):
    """Body of an open request: one ``u16``.

    pyfocas and pyfanuc send 2; FANUC's library sends 1 on its first connection (A, which
    carries nothing after the open but its close) and 2 on its second (B, every data request).
    A body of another size is a framing violation (:class:`NativeFrameError`).
    """

    FORMAT: ClassVar[str] = ">H"
    ERROR: ClassVar[Callable[[str], ProtocolError]] = NativeFrameError
    WHAT: ClassVar[str] = "open request body"
    channel: int = 2


def encode_open_request(channel: int = 2, version: int = CLIENT_VERSION) -> bytes:
    """A whole open-request frame (pyfocas sends ``A0A0A0A0 0001 0101 0002 0002``)."""
    return encode_native_frame(FrameType.OPEN_REQUEST, OpenRequest(channel).encode(), version)


def encode_open_response(
    body: bytes = _OPEN_RESPONSE_BODY, version: int = DEFAULT_SERVER_VERSION
) -> bytes:
    """A whole open-response frame (pyfocas and pyfanuc ignore its body; FANUC's library needs
    the one :func:`focas_net.native.build_open_answer` makes)."""
    return encode_native_frame(FrameType.OPEN_RESPONSE, body, version)


def encode_close_request(version: int = CLIENT_VERSION) -> bytes:
    """A whole close-request frame: ``A0A0A0A0 0001 0201 0000``."""
    return encode_native_frame(FrameType.CLOSE_REQUEST, b"", version)


def encode_close_response(version: int = DEFAULT_SERVER_VERSION) -> bytes:
    """A whole close-response frame, empty body."""
    return encode_native_frame(FrameType.CLOSE_RESPONSE, b"", version)
