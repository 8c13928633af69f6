"""The frame of ``docs/protocol.md`` section 1 and its incremental decoder.

``u32 length`` (bytes after the field = 4 + payload), ``u16 command``, ``u16 request_id``,
then the payload; all little-endian. The decoder is fed byte chunks of any size and returns
whole frames; it checks each length prefix against ``max_frame`` as soon as the 4-byte field is
in, before it buffers anything of the body.
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


_new_frame = tuple.__new__


class FrameDecoder:
    """Incremental frame decoder.

    ``feed(chunk)`` returns the frames completed by ``chunk`` (possibly none) and keeps any
    trailing partial frame. A length prefix below 4 or above ``max_frame`` raises
    :class:`FrameError` the moment the 4-byte field is complete (its ``frames`` are the whole
    frames this call decoded before the bad one); after that the decoder is poisoned and every
    further ``feed`` raises again, with no frames (the connection must be closed).
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
        self._error = FrameError(message)
        return FrameError(message, frames)

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
        if not buf:
            if type(data) is bytes:
                size = len(data)
                if size >= 8:
                    # The commonest case, one whole frame and nothing else, without the loop.
                    length, command, request_id = _unpack_header_from(data)
                    if size == 4 + length and _MIN_LENGTH <= length <= self.max_frame:
                        return [(command, request_id, data[8:])]
                # The usual case: whole frames in a fresh chunk; a slice of bytes is the one
                # copy of each payload.
                frames, pos, bad = self._frames(data, None)
                if bad >= 0:
                    raise self._violation(bad, frames)
                if pos < len(data):
                    buf += data[pos:]
                return frames
            buf += data
        else:
            buf += data
        # Bytes held from before: payloads are copied once, out of a view of the buffer (the
        # view is released before the buffer is trimmed).
        with memoryview(buf) as view:
            frames, pos, bad = self._frames(buf, view)
        if bad >= 0:
            raise self._violation(bad, frames)
        if pos:
            del buf[:pos]
        return frames

    def _frames(
        self, data: bytes | bytearray, view: memoryview | None
    ) -> tuple[list[RawFrame], int, int]:
        """The whole frames at the start of ``data``, where they end, and the length prefix
        that violates the bounds (-1: none). Payloads are slices of ``data`` when it is
        ``bytes`` (``view`` None), else copies out of ``view``, a view of it."""
        frames: list[RawFrame] = []
        append = frames.append
        size = len(data)
        pos = 0
        max_frame = self.max_frame
        while size - pos >= 8:
            length, command, request_id = _unpack_header_from(data, pos)
            if length < _MIN_LENGTH or length > max_frame:
                return frames, pos, length
            end = pos + 4 + length
            if end > size:
                return frames, pos, -1
            if view is None:
                append((command, request_id, data[pos + 8 : end]))  # type: ignore[arg-type]
            else:
                append((command, request_id, bytes(view[pos + 8 : end])))
            pos = end
        if size - pos >= 4:  # a length prefix alone is checked as soon as it is complete
            (length,) = _unpack_length_from(data, pos)
            if length < _MIN_LENGTH or length > max_frame:
                return frames, pos, length
        return frames, pos, -1
