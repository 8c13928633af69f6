"""The floor: the least a plain-asyncio implementation of the focas_net frame can cost.

Two servers that answer every frame with a fixed 20-byte status payload (command 0x0001; any
other command gets ``EW_FUNC``), one answer write per read: a ``BufferedProtocol`` one
(:class:`FloorServer`, reading into its own buffer) and a plain ``Protocol`` one
(:class:`FloorPlainServer`, handed a fresh ``bytes`` per read). Neither wins everywhere (the
buffered one with many connections, the plain one with many frames per read), so the suite
runs both and takes the faster in each mode and repetition as the floor. The client matches
answers to callers by request id, gathers the frames written in one event-loop turn into
writes of at most 16 frames (the server starts on the first while the callers of the turn make
the rest: about 30 % more requests per second with 64 in flight than one write per turn) and
reads into its own buffer. No codecs, no machine, no checks beyond the length bounds: whatever
the real library spends above this is its own overhead.

``python -m benchmarks.floor --port 0 [--variant buffered|plain]`` serves until killed and
prints ``floor: listening on HOST:PORT`` when ready.
"""

from __future__ import annotations

import argparse
import asyncio
import struct
from typing import Final, Literal, cast

HEADER: Final = struct.Struct("<IHH")
MAX_FRAME: Final = 65_536
STATUS: Final = 0x0001
#: ``ew = 0`` then ODBST (hdck, tmmode, aut = 1 MEM, run, motion, mstb, emergency, alarm, edit).
STATUS_PAYLOAD: Final = struct.pack("<h9h", 0, 0, 0, 1, 0, 0, 0, 0, 0, 0)
_EW_FUNC: Final = struct.pack("<h", 1)
#: Most frames of one loop turn the client writes at once.
WRITE_CHUNK: Final = 16
#: The server variants: ``asyncio.BufferedProtocol`` and ``asyncio.Protocol``.
VARIANTS: Final = ("buffered", "plain")
Variant = Literal["buffered", "plain"]


def _answers(buf: bytes | bytearray, pos: int, end: int) -> tuple[bytearray | None, int]:
    """The answers to the whole frames in ``buf[pos:end]`` and where the first partial frame
    starts; None (and ``pos``) on a length outside the bounds."""
    out = bytearray()
    while end - pos >= 8:
        length, command, request_id = HEADER.unpack_from(buf, pos)
        if length < 4 or length > MAX_FRAME:
            return None, pos
        if end - pos < 4 + length:
            break
        pos += 4 + length
        payload = STATUS_PAYLOAD if command == STATUS else _EW_FUNC
        out += HEADER.pack(4 + len(payload), command, request_id)
        out += payload
    return out, pos


class FloorServer(asyncio.BufferedProtocol):
    """One connection of the floor server."""

    def __init__(self) -> None:
        self._buf = bytearray(4096)
        self._start = self._end = 0
        self._transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self._transport = cast(asyncio.Transport, transport)  # uvloop's does not subclass it

    def get_buffer(self, sizehint: int) -> memoryview:
        if len(self._buf) - self._end < 1024:  # a frame larger than the buffer: grow it
            self._buf = self._buf + bytes(len(self._buf))
        return memoryview(self._buf)[self._end :]

    def buffer_updated(self, nbytes: int) -> None:
        buf, end = self._buf, self._end + nbytes
        out, pos = _answers(buf, self._start, end)
        if out is None:
            if self._transport is not None:
                self._transport.abort()
            return
        if out and self._transport is not None:
            self._transport.write(out)
        if pos == end:
            pos = end = 0
        elif pos:  # keep the partial frame at the front
            buf[: end - pos] = buf[pos:end]
            pos, end = 0, end - pos
        self._start, self._end = pos, end

    def connection_lost(self, exc: Exception | None) -> None:
        self._transport = None


class FloorPlainServer(asyncio.Protocol):
    """One connection of the floor server's plain ``Protocol`` variant."""

    def __init__(self) -> None:
        self._held = b""  # a partial frame from the previous read
        self._transport: asyncio.Transport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self._transport = cast(asyncio.Transport, transport)  # uvloop's does not subclass it

    def data_received(self, data: bytes) -> None:
        if self._held:
            data = self._held + data
        out, pos = _answers(data, 0, len(data))
        if out is None:
            if self._transport is not None:
                self._transport.abort()
            return
        if out and self._transport is not None:
            self._transport.write(out)
        self._held = data[pos:] if pos < len(data) else b""

    def connection_lost(self, exc: Exception | None) -> None:
        self._transport = None


class FloorClient(asyncio.BufferedProtocol):
    """The floor client: one connection, many requests in flight, matched by request id; the
    frames written in one event-loop turn leave in writes of at most :data:`WRITE_CHUNK`
    frames; answers are read into its own buffer (``recv_into``, no allocation per read)."""

    def __init__(self) -> None:
        self._buf = bytearray(4096)
        self._end = 0
        self._pending: dict[int, asyncio.Future[bytes]] = {}
        self._next_id = 0
        self._transport: asyncio.Transport | None = None
        self._out = bytearray()
        self._queued = 0  # frames in _out
        self._loop = asyncio.get_running_loop()

    @classmethod
    async def connect(cls, host: str, port: int) -> FloorClient:
        loop = asyncio.get_running_loop()
        _, protocol = await loop.create_connection(cls, host, port)
        return protocol

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self._transport = cast(asyncio.Transport, transport)  # uvloop's does not subclass it

    def get_buffer(self, sizehint: int) -> memoryview:
        if len(self._buf) - self._end < 1024:  # an answer larger than the buffer: grow it
            self._buf = self._buf + bytes(len(self._buf))
        return memoryview(self._buf)[self._end :]

    def buffer_updated(self, nbytes: int) -> None:
        buf, size = self._buf, self._end + nbytes
        pending = self._pending
        pos = 0
        while size - pos >= 8:
            length, _command, request_id = HEADER.unpack_from(buf, pos)
            if size - pos < 4 + length:
                break
            future = pending.pop(request_id, None)
            if future is not None and not future.done():
                future.set_result(bytes(buf[pos + 8 : pos + 4 + length]))
            pos += 4 + length
        if pos == size:
            self._end = 0
        else:  # keep the partial answer at the front
            buf[: size - pos] = buf[pos:size]
            self._end = size - pos

    def _flush(self) -> None:
        out, self._out = self._out, bytearray()
        self._queued = 0
        if out and self._transport is not None:
            self._transport.write(out)

    def connection_lost(self, exc: Exception | None) -> None:
        self._transport = None
        for future in self._pending.values():
            if not future.done():
                future.set_exception(ConnectionError("floor connection lost"))
        self._pending.clear()

    def send(self, command: int, payload: bytes = b"") -> asyncio.Future[bytes]:
        """Send one request (with the others of this loop turn) and return its answer's future."""
        if self._transport is None:
            raise ConnectionError("floor connection closed")
        request_id = self._next_id
        while request_id in self._pending:
            request_id = (request_id + 1) & 0xFFFF
        self._next_id = (request_id + 1) & 0xFFFF
        future: asyncio.Future[bytes] = self._loop.create_future()
        self._pending[request_id] = future
        if not self._out:
            self._loop.call_soon(self._flush)
        self._out += HEADER.pack(4 + len(payload), command, request_id)
        self._out += payload
        self._queued += 1
        if self._queued >= WRITE_CHUNK:
            self._flush()
        return future

    async def request(self, command: int, payload: bytes = b"") -> bytes:
        return await self.send(command, payload)

    async def read_status(self) -> bytes:
        return await self.request(STATUS)

    async def close(self) -> None:
        if self._transport is not None:
            self._transport.close()
            self._transport = None


async def serve(host: str, port: int, variant: Variant = "buffered") -> asyncio.Server:
    """Start the floor server of ``variant``; the caller owns the returned server."""
    factory: type[asyncio.BaseProtocol] = FloorServer if variant == "buffered" else FloorPlainServer
    return await asyncio.get_running_loop().create_server(factory, host, port, backlog=1024)


async def _main(host: str, port: int, variant: Variant) -> None:
    server = await serve(host, port, variant)
    bound = server.sockets[0].getsockname()
    print(f"floor: listening on {bound[0]}:{bound[1]}", flush=True)
    async with server:
        await server.serve_forever()


if __name__ == "__main__":
    from benchmarks._loop import run_forever

    parser = argparse.ArgumentParser(description="Run the floor server.")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--uvloop", action="store_true")
    parser.add_argument("--variant", choices=VARIANTS, default="buffered")
    args = parser.parse_args()
    run_forever(_main(args.host, args.port, args.variant), use_uvloop=args.uvloop)
