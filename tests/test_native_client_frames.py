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

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import serving

from focas_net.client import NativeClient
from focas_net.native import calls
from focas_net.native.calls import CommandSet, LibraryCall
from focas_net.native.frame import max_response_body

#: The calls drawn from, each one request frame: a block or several, small and large answers;
#: and the library call each sends (to reckon its blocks and sizes).
_Call = Callable[[NativeClient], Awaitable[Any]]
_MENU: dict[str, tuple[_Call, Callable[[CommandSet], LibraryCall]]] = {
    "macro100": (lambda c: c.read_macro(100), lambda cs: calls.cnc_rdmacro(cs, 100)),
    "macro101": (lambda c: c.read_macro(101), lambda cs: calls.cnc_rdmacro(cs, 101)),
    "status": (lambda c: c.read_status(), calls.cnc_statinfo),
    "dynamic": (lambda c: c.read_dynamic(), lambda cs: calls.cnc_rddynamic2(cs, -1)),
    "pmc_r_small": (lambda c: c.read_pmc("R", 0, 4), lambda cs: calls.pmc_rdpmcrng(cs, 5, 0, 0, 3)),
    "pmc_d_big": (
        lambda c: c.read_pmc("D", 0, 600),
        lambda cs: calls.pmc_rdpmcrng(cs, 9, 0, 0, 599),
    ),
    "feed": (lambda c: c.read_feed(), calls.cnc_actf),
}


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
    async with serving() as served:
        served.machine.write_macro(100, 7)
        served.machine.write_macro(101, -3)
        async with NativeClient(served.host, served.port, max_blocks=max_blocks) as native:
            assert native.command_set is not None and native.version is not None
            max_axes = native.max_axes or 0
            alone = {}
            for name in set(names):
                frames = native.frames_sent
                alone[name] = await _MENU[name][0](native)
                assert native.frames_sent - frames == 1, "each drawn call is one frame"
            frames, blocks = native.frames_sent, native.blocks_sent
            got = await asyncio.gather(*(_MENU[name][0](native) for name in names))
            assert got == [alone[name] for name in names]
            parts = [_MENU[name][1](native.command_set).parts[0] for name in names]
            expected = _greedy(
                [
                    (p.count, p.answer_fixed + p.answer_axes * 16 * max_axes, len(p.blocks))
                    for p in parts
                ],
                max_blocks,
                max_response_body(native.version),
            )
            assert native.frames_sent - frames == len(expected)
            assert native.blocks_sent - blocks == sum(expected)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    names=st.lists(st.sampled_from(sorted(_MENU)), min_size=1, max_size=40),
    max_blocks=st.integers(1, 24),
)
def test_concurrent_calls_are_packed_greedily_in_call_order(
    names: list[str], max_blocks: int
) -> None:
    asyncio.run(_check(names, max_blocks))
