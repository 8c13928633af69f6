"""Locks keyed by an address, created on demand and dropped when idle."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Hashable
from contextlib import asynccontextmanager
from typing import Generic, TypeVar

from ..protocol import FocasTimeoutError

__all__ = ["KeyedLocks"]

K = TypeVar("K", bound=Hashable)


class _Entry:
    __slots__ = ("lock", "users")

    def __init__(self) -> None:
        self.lock = asyncio.Lock()
        self.users = 0


class KeyedLocks(Generic[K]):
    """One :class:`asyncio.Lock` per key, alive only while someone holds or waits for it.

    The table therefore holds at most as many locks as there are callers inside
    :meth:`hold`; it never grows with the number of distinct keys ever used.
    """

    __slots__ = ("_entries",)

    def __init__(self) -> None:
        self._entries: dict[K, _Entry] = {}

    def __len__(self) -> int:
        return len(self._entries)

    @asynccontextmanager
    async def hold(self, key: K, deadline: float | None = None) -> AsyncIterator[None]:
        """Hold the lock of ``key``; waiting for it counts towards ``deadline``."""
        entries = self._entries
        entry = entries.get(key)
        if entry is None:
            entry = entries[key] = _Entry()
        entry.users += 1
        try:
            lock = entry.lock
            if lock.locked():
                try:
                    async with asyncio.timeout_at(deadline):
                        await lock.acquire()
                except TimeoutError:
                    raise FocasTimeoutError(f"lock of {key!r} not free in time") from None
            else:
                await lock.acquire()  # free: returns without suspending
            try:
                yield
            finally:
                lock.release()
        finally:
            entry.users -= 1
            if not entry.users:
                del entries[key]
