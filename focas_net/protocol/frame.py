"""The frame of ``docs/protocol.md`` section 1 and its incremental decoder.

``u32 length`` (bytes after the field = 4 + payload), ``u16 command``, ``u16 request_id``,
then the payload; all little-endian. The decoder is fed byte chunks of any size and returns
whole frames; it checks each length prefix against ``max_frame`` as soon as the 4-byte field is
in, before it buffers anything of the body.

:func:`scan_frames` is the decoder's own scan, pure and stateless: the whole frames at the start
of a buffer, where they end and the first length prefix out of bounds. A receiver with a read
buffer of its own can take whole frames straight out of it, by the decoder's rules.
"""

from __future__ import annotations

import struct
from typing import Final, NamedTuple

from ..errors import FrameError

__all__ = [
    "DEFAULT_MAX_FRAME",
    "HEADER",
    "HEADER_SIZE",
    "Frame",
    "FrameDecoder",
    "RawFrame",
    "encode_frame",
    "foreign_client",
    "is_tls_record",
    "scan_frames",
]

#: Default ceiling of ``length`` (both sides; configurable).
DEFAULT_MAX_FRAME: Final = 65_536
#: ``u32 length, u16 command, u16 request_id``.
HEADER: Final = struct.Struct("<IHH")
HEADER_SIZE: Final = HEADER.size
_MIN_LENGTH: Final = 4
_pack_header = HEADER.pack
_unpack_header_from = HEADER.unpack_from
_unpack_length_from = struct.Struct("<I").unpack_from


class Frame(NamedTuple):
    """One decoded frame."""

    command: int
    request_id: int
    payload: bytes


#: A decoded frame as a plain tuple ``(command, request_id, payload)``: what
#: :meth:`FrameDecoder.feed_raw` returns. The same fields as :class:`Frame`, which costs a
#: NamedTuple construction per frame; the server's and the client's data paths use this.
RawFrame = tuple[int, int, bytes]


def encode_frame(command: int, request_id: int, payload: bytes = b"") -> bytes:
    """The bytes of one frame."""
    return _pack_header(len(payload) + 4, command, request_id) + payload


def scan_frames(
    data: bytes | memoryview, max_frame: int, size: int | None = None
) -> tuple[list[RawFrame], int, int]:
    """The whole frames at the start of ``data[:size]`` (all of ``data`` when ``size`` is
    None): ``(frames, end, bad)``.

    ``frames`` are the frames that stand whole there, back to back from the first byte, in
    order; ``end`` is where the last of them ends (where the first frame not whole, or not
    valid, starts); ``bad`` is the length prefix found at ``end`` when it is below 4 or above
    ``max_frame`` (a violation: the connection must be closed), else -1. A length prefix is
    checked as soon as its four bytes are in, before the rest of its header. Each payload is
    copied once (a slice of ``bytes``, or copied out of a view): nothing returned refers to a
    buffer behind ``data``."""
    if size is None:
        size = len(data)
    frames: list[RawFrame] = []
    pos = 0
    while size - pos >= 8:
        length, command, request_id = _unpack_header_from(data, pos)
        if length < _MIN_LENGTH or length > max_frame:
            return frames, pos, length
        end = pos + 4 + length
        if end > size:
            return frames, pos, -1
        payload = data[pos + 8 : end] if length > _MIN_LENGTH else b""
        frames.append(
            (command, request_id, payload.tobytes() if type(payload) is memoryview else payload)
        )
        pos = end
    if size - pos >= 4:  # a length prefix alone is checked as soon as it is complete
        (length,) = _unpack_length_from(data, pos)
        if length < _MIN_LENGTH or length > max_frame:
            return frames, pos, length
    return frames, pos, -1


_new_frame = tuple.__new__


class FrameDecoder:
    """Incremental frame decoder.

    ``feed(chunk)`` returns the frames completed by ``chunk`` (possibly none) and keeps any
    trailing partial frame. A length prefix below 4 or above ``max_frame`` raises
    :class:`FrameError` the moment the 4-byte field is complete (its ``frames`` are the whole
    frames this call decoded before the bad one); after that the decoder is poisoned and every
    further ``feed`` raises again, with no frames (the connection must be closed). Frames are
    found by :func:`scan_frames`.
    """

    __slots__ = ("_buf", "_error", "held", "max_frame")

    def __init__(self, max_frame: int = DEFAULT_MAX_FRAME) -> None:
        if max_frame < _MIN_LENGTH:
            raise ValueError(f"max_frame must be at least {_MIN_LENGTH}, got {max_frame}")
        self.max_frame = max_frame
        self._buf = bytearray()
        #: The bytes held for a frame not yet complete (empty, so false, when none): the
        #: decoder's own buffer, to be read, never changed. A test of it is an attribute
        #: read, where :attr:`buffered` is a call.
        self.held = self._buf
        self._error: FrameError | None = None

    @property
    def buffered(self) -> int:
        """Bytes held for a frame not yet complete."""
        return len(self._buf)

    def _violation(self, length: int, frames: list[RawFrame]) -> FrameError:
        self._buf.clear()
        message = f"frame length {length} outside 4..{self.max_frame}; closing the connection"
        self._error = FrameError(message, length=length)
        return FrameError(message, frames, length)

    def feed(self, data: bytes | bytearray | memoryview) -> list[Frame]:
        """Add ``data`` and return every frame now complete, in order (see :meth:`feed_raw`;
        the frames of a :class:`FrameError` are :class:`Frame` too)."""
        try:
            raw = self.feed_raw(data)
        except FrameError as exc:
            exc.frames = [_new_frame(Frame, f) for f in exc.frames]
            raise
        return [_new_frame(Frame, f) for f in raw]

    def feed_raw(self, data: bytes | bytearray | memoryview) -> list[RawFrame]:
        """Add ``data`` and return every frame now complete, in order, as plain tuples."""
        if self._error is not None:
            raise FrameError(str(self._error))
        buf = self._buf
        if not buf and type(data) is bytes:
            # The usual case: whole frames in a fresh chunk; a slice of bytes is the one copy
            # of each payload.
            frames, end, bad = scan_frames(data, self.max_frame)
            if bad >= 0:
                raise self._violation(bad, frames)
            if end < len(data):
                buf += data[end:]
            return frames
        buf += data
        # Bytes held from before: payloads are copied once, out of a view of the buffer (the
        # view is released before the buffer is trimmed).
        with memoryview(buf) as view:
            frames, end, bad = scan_frames(view, self.max_frame)
        if bad >= 0:
            raise self._violation(bad, frames)
        if end:
            del buf[:end]
        return frames


#: The first byte of a TLS record (change_cipher_spec, alert, handshake, application_data),
#: which a TLS peer sends where a frame's length should be; its second byte is 3 (TLS 1.x).
_TLS_RECORD_TYPES: Final = frozenset({0x14, 0x15, 0x16, 0x17})
#: The methods an HTTP request starts with (``PRI``: HTTP/2's connection preface).
_HTTP_METHODS: Final = frozenset(
    {"GET", "HEAD", "POST", "PUT", "DELETE", "CONNECT", "OPTIONS", "TRACE", "PATCH", "PRI"}
)


def is_tls_record(head: bytes | memoryview) -> bool:
    """Whether ``head``, the first bytes a peer sent, start a TLS record."""
    return len(head) >= 2 and head[0] in _TLS_RECORD_TYPES and head[1] == 3


def foreign_client(head: bytes | memoryview) -> str | None:
    """What a client of another protocol whose first bytes are ``head`` is, in words (a TLS
    client, an HTTP one naming its method), or None: the hint of a server's log. No other
    byte is shown (a chunk could hold part of an unlock request's password)."""
    if is_tls_record(head):
        return "it sent a TLS record: a TLS client, on a port that does not serve TLS"
    method, space, _ = bytes(head[:8]).partition(b" ")
    name = method.decode("ascii", "replace")
    if space and name in _HTTP_METHODS:
        return f"it sent an HTTP request ({name}): an HTTP client, on a port that serves FOCAS"
    return None
