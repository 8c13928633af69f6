"""Event-loop selection for the benchmark processes: asyncio's own, or uvloop when asked."""

from __future__ import annotations

import asyncio
import importlib.util
from collections.abc import Callable, Coroutine
from typing import Any, TypeVar

T = TypeVar("T")


def uvloop_available() -> bool:
    """True when uvloop can be imported (it is optional, never required)."""
    return importlib.util.find_spec("uvloop") is not None


def loop_factory(use_uvloop: bool) -> Callable[[], asyncio.AbstractEventLoop] | None:
    """The loop factory for :class:`asyncio.Runner`: uvloop's when asked and installed."""
    if use_uvloop and uvloop_available():
        import uvloop

        return uvloop.new_event_loop
    return None


def make_runner(use_uvloop: bool) -> asyncio.Runner:
    """A runner whose loop lives until it is closed (connections survive between runs)."""
    return asyncio.Runner(loop_factory=loop_factory(use_uvloop))


def run_forever(coro: Coroutine[Any, Any, T], *, use_uvloop: bool) -> T | None:
    """Run ``coro`` to completion; Ctrl-C ends it quietly."""
    with make_runner(use_uvloop) as runner:
        try:
            return runner.run(coro)
        except KeyboardInterrupt:
            return None
