"""How the native client packs concurrent calls into request frames, against the real server.

Calls issued together are queued in call order and sent greedily: each frame takes the calls
at the queue's head while its block count stays within ``max_blocks`` and its answer and
request bodies within the size the open answer allows; a frame takes at least one call.
Hypothesis draws mixes of calls of different block counts and answer sizes (runs of one call
and changes of call), and the frames written on B are checked against that rule, the results
against each call made alone.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import serving

from focas_net.client import native as native_module
from focas_net.client._channel import Channel
from focas_net.client.native import NativeClient
from focas_net.native.frame import NATIVE_HEADER_SIZE

#: The calls drawn from, each one request frame: a block or several, small and large answers.
_Call = Callable[[NativeClient], Awaitable[Any]]
_MENU: dict[str, _Call] = {
    "macro100": lambda c: c.read_macro(100),
    "macro101": lambda c: c.read_macro(101),
    "status": lambda c: c.read_status(),
    "dynamic": lambda c: c.read_dynamic(),
    "pmc_r_small": lambda c: c.read_pmc("R", 0, 4),
    "pmc_d_big": lambda c: c.read_pmc("D", 0, 600),
    "feed": lambda c: c.read_feed(),
}


class _FrameSpy:
    """Stands in for B's channel: keeps each request frame's block count."""

    def __init__(self, transport: Channel) -> None:
        self.transport = transport
        self.counts: list[int] = []
        self.frames: list[bytes] = []

    def write(self, data: bytes) -> None:
        self.counts.append(int.from_bytes(data[NATIVE_HEADER_SIZE : NATIVE_HEADER_SIZE + 2]))
        self.frames.append(data)
        self.transport.write(data)


def _greedy(parts: list[tuple[int, int, int]], max_blocks: int, limit: int) -> list[int]:
    """The block counts of the frames that carry jobs of ``parts`` (blocks, answer bytes,
    request bytes each) in order: each frame as many from the head as fit, at least one."""
    frames: list[int] = []
    i = 0
    while i < len(parts):
        blocks, answer, sent = parts[i]
        i += 1
        answer += 2
        sent += 2
        while i < len(parts):
            b, a, s = parts[i]
            if blocks + b > max_blocks or answer + a > limit or sent + s > limit:
                break
            blocks, answer, sent = blocks + b, answer + a, sent + s
            i += 1
        frames.append(blocks)
    return frames


async def _check(names: list[str], max_blocks: int) -> None:
    parts: dict[str, native_module._Part] = {}

    async with serving() as served:
        served.machine.write_macro(100, 7)
        served.machine.write_macro(101, -3)
        async with NativeClient(served.host, served.port, max_blocks=max_blocks) as native:
            handle = native._handle
            assert handle is not None
            spy = _FrameSpy(handle.b)
            handle.b = spy  # type: ignore[assignment]
            try:
                alone = {}
                for name in set(names):
                    spy.counts.clear()
                    spy.frames.clear()
                    alone[name] = await _MENU[name](native)
                    assert len(spy.counts) == 1, "each drawn call is one frame"
                    # its part: the one whose frame alone is the frame written
                    (parts[name],) = {
                        part
                        for _, part in native_module._PARTS.values()
                        if part[4] == spy.frames[0]
                    }
                spy.counts.clear()
                got = await asyncio.gather(*(_MENU[name](native) for name in names))
                sent = list(spy.counts)
            finally:
                handle.b = spy.transport
            assert got == [alone[name] for name in names]
            expected = _greedy(
                [(parts[n][3], parts[n][1], parts[n][2]) for n in names], max_blocks, handle.limit
            )
            assert sent == expected


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    names=st.lists(st.sampled_from(sorted(_MENU)), min_size=1, max_size=40),
    max_blocks=st.integers(1, 24),
)
def test_concurrent_calls_are_packed_greedily_in_call_order(
    names: list[str], max_blocks: int
) -> None:
    asyncio.run(_check(names, max_blocks))


@pytest.mark.parametrize("call", ["read_macro", "read_feed"])
async def test_a_call_queued_behind_a_frame_in_flight_has_its_whole_job(call: str) -> None:
    """read_macro builds such a job itself, the other calls through ``_send``."""
    async with serving() as served:
        served.machine.write_macro(100, 7)
        async with NativeClient(served.host, served.port, timeout=5.0) as native:
            handle = native._handle
            assert handle is not None
            make = (lambda: native.read_macro(100)) if call == "read_macro" else native.read_feed
            alone = await make()
            first = asyncio.ensure_future(make())
            for _ in range(10):  # the first call's frame leaves at the end of a loop turn
                if handle.inflight is not None:
                    break
                await asyncio.sleep(0)
            assert handle.inflight is not None
            later = [asyncio.ensure_future(make()) for _ in range(3)]
            await asyncio.sleep(0)  # the three calls are made, behind the frame in flight
            queued = list(native._queue)
            assert len(queued) == 3
            for job in queued:
                made = {name: getattr(job, name) for name in native_module._Job.__slots__}
                assert made["task"] is None and made["unarmed"] is False
                assert made["part"] is native_module._NO_PART and not job.sent
                assert made["command_set"] is handle.command_set
                assert isinstance(made["deadline"], float) and not made["future"].done()
                assert made["requests"] == handle.inflight[0].requests
            assert await asyncio.gather(first, *later) == [alone] * 4
            if call == "read_macro":
                assert alone == 7
