"""Waiting for the answers of a batch of packed requests without a task: one done-callback per
future (see :meth:`~focas_net.client.connection.Connection.request_all`)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Sequence

__all__ = ["settled"]


async def settled(
    loop: asyncio.AbstractEventLoop,
    entries: Sequence[tuple[asyncio.Future[bytes], int, int, float]],
    stop_early: bool,
    failed: Callable[[bytes], bool] | None,
) -> None:
    """Wait until every future of ``entries`` is done or, with ``stop_early``, one fails (or
    its answer is rejected by ``failed``). No task is created: one callback per future."""
    done: asyncio.Future[None] = loop.create_future()
    left = len(entries)
    if not left:
        return

    def one_settled(future: asyncio.Future[bytes]) -> None:
        nonlocal left
        if done.done():
            return
        left -= 1
        if left == 0 or (
            stop_early
            and (
                future.cancelled()
                or future.exception() is not None
                or (failed is not None and failed(future.result()))
            )
        ):
            done.set_result(None)

    for entry in entries:
        entry[0].add_done_callback(one_settled)
    try:
        await done
    finally:
        for entry in entries:
            entry[0].remove_done_callback(one_settled)
