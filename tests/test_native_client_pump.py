"""The native client between frames: what an idle connection costs and what it notices.

B's bytes are parsed as they arrive, so a CNC that closes B, or sends what nobody asked for
while no frame is in flight, ends the connection at once rather than at the next call; a call
costs no task of its own.
"""

from __future__ import annotations

import asyncio
from collections.abc import Coroutine, Generator
from typing import Any

from support import IO_TIMEOUT, LoopbackPeer, serving, wait_until

from focas_net.client import ClientState, NativeClient
from focas_net.native import (
    FrameType,
    NativeFrameDecoder,
    PathDescription,
    ResponseBlock,
    ScaledNumber,
    ScaledValues,
    build_open_answer,
    decode_request_body,
    encode_close_response,
    encode_native_response,
    encode_open_response,
)
from focas_net.native.requests import NativeCommand


class _TrailingPeer(LoopbackPeer):
    """A FOCAS/2 peer (30i class) answering macro reads with the variable's number; with
    ``trailing`` set, it sends those bytes right after the next macro answer."""

    def __init__(self) -> None:
        self.trailing = b""
        #: With ``split`` set, macro answers go out in pieces of this many bytes.
        self.split = 0
        self.macro_frames = 0

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        decoder = NativeFrameDecoder()
        try:
            while data := await reader.read(65536):
                for frame in decoder.feed(data):
                    if frame.type == FrameType.OPEN_REQUEST:
                        body = build_open_answer([PathDescription()], 8, version=3)
                        writer.write(encode_open_response(body, 3))
                    elif frame.type == FrameType.CLOSE_REQUEST:
                        writer.write(encode_close_response(3))
                    else:
                        blocks = decode_request_body(frame.body)
                        answers: list[ResponseBlock] = []
                        for b in blocks:
                            if b.command == NativeCommand.RDMACRO:
                                value = ScaledValues((ScaledNumber(b.args[0], 0),))
                                answers.append(b.reply(value.encode()))
                            elif b.command == NativeCommand.SYSINFO:
                                answers.append(b.reply(bytes(4) + b" 0 MD4F132.003"))
                            else:
                                answers.append(b.reply(ew=1))
                        answer = encode_native_response(answers, 3)
                        macro = any(b.command == NativeCommand.RDMACRO for b in blocks)
                        if macro and self.split:
                            for i in range(0, len(answer), self.split):
                                writer.write(answer[i : i + self.split])
                                await writer.drain()
                                await asyncio.sleep(0.001)
                        else:
                            writer.write(answer)
                        if macro:
                            self.macro_frames += 1
                            writer.write(self.trailing)
                            self.trailing = b""
        except ConnectionError:
            pass
        finally:
            writer.close()


async def test_sequential_calls_start_no_task() -> None:
    created = 0

    def factory(
        loop: asyncio.AbstractEventLoop,
        coro: Generator[Any, None, Any] | Coroutine[Any, Any, Any],
        **kwargs: Any,
    ) -> asyncio.Task[Any]:
        nonlocal created
        created += 1
        return asyncio.Task(coro, loop=loop, **kwargs)

    loop = asyncio.get_running_loop()
    async with serving() as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
            served.machine.write_macro(100, 7)
            await native.read_macro(100)
            loop.set_task_factory(factory)
            try:
                values = [await native.read_macro(100) for _ in range(50)]
            finally:
                loop.set_task_factory(None)
    assert values == [7] * 50
    assert created == 0


async def test_a_server_that_goes_away_is_noticed_without_a_call() -> None:
    async with serving() as served:
        native = NativeClient("127.0.0.1", served.port, timeout=IO_TIMEOUT)
        await native.connect()
        assert await native.read_macro(100) is None
    try:
        await wait_until(lambda: native.state is ClientState.DISCONNECTED)
    finally:
        await native.aclose()


async def test_unsolicited_bytes_on_b_end_the_connection_without_a_call() -> None:
    async with _TrailingPeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            assert await native.read_macro(5) == 5
            peer.trailing = b"\xa0"
            assert await native.read_macro(6) == 6
            await wait_until(lambda: native.state is ClientState.DISCONNECTED)
            assert peer.macro_frames == 2


async def test_an_answer_in_pieces_reaches_its_call() -> None:
    async with _TrailingPeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            assert await native.read_macro(5) == 5
            for split in (1, 3, 11):
                peer.split = split
                assert await native.read_macro(split) == split
            peer.split = 0
            assert await native.read_macro(6) == 6
            assert native.state is ClientState.CONNECTED


async def test_an_answer_seen_before_reaches_its_call_whole_in_pieces_and_followed() -> None:
    # The same answer bytes, for the same call, arrive whole (known by then), in pieces
    # (no piece is a whole answer), then followed by a byte nobody asked for.
    async with _TrailingPeer() as peer:
        async with NativeClient("127.0.0.1", peer.port, timeout=IO_TIMEOUT) as native:
            assert [await native.read_macro(5) for _ in range(3)] == [5, 5, 5]
            peer.split = 3
            assert await native.read_macro(5) == 5
            peer.split = 0
            assert await native.read_macro(5) == 5
            state_then: ClientState = native.state
            assert state_then is ClientState.CONNECTED
            peer.trailing = b"\xa0"
            assert await native.read_macro(5) == 5
            await wait_until(lambda: native.state is ClientState.DISCONNECTED)
            assert peer.macro_frames == 6
