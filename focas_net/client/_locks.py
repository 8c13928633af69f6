"""Locks keyed by an address, created on demand and dropped when idle."""

from __future__ import annotations

import asyncio
from collections import deque
from collections.abc import AsyncIterator, Hashable
from contextlib import asynccontextmanager
from typing import Generic, TypeVar

from focas_net.errors import FocasTimeoutError

__all__ = ["KeyedLocks"]

K = TypeVar("K", bound=Hashable)


class _Entry:
    """One key's lock: held or not, and a first-in first-out line of waiters. A release hands
    the lock straight to the first waiter (it stays held), so a caller arriving before that
    waiter has run still finds it held and waits in line, within its own deadline."""

    __slots__ = ("held", "users", "waiters")

    def __init__(self) -> None:
        self.held = False
        self.users = 0
        self.waiters: deque[asyncio.Future[None]] = deque()

    def release(self) -> None:
        waiters = self.waiters
        while waiters:
            waiter = waiters.popleft()
            if not waiter.done():
                waiter.set_result(None)  # handed over: still held
                return
        self.held = False

    def leave_line(self, waiter: asyncio.Future[None]) -> None:
        """A waiter gave up: if the lock was handed to it already, pass it on."""
        if waiter.done() and not waiter.cancelled():
            self.release()
            return
        waiter.cancel()
        try:
            self.waiters.remove(waiter)
        except ValueError:
            pass


class KeyedLocks(Generic[K]):
    """One lock per key, alive only while someone holds or waits for it.

    The table therefore holds at most as many locks as there are callers inside
    :meth:`hold`; it never grows with the number of distinct keys ever used.
    """

    __slots__ = ("_entries",)

    def __init__(self) -> None:
        self._entries: dict[K, _Entry] = {}

    def __len__(self) -> int:
        return len(self._entries)

    @asynccontextmanager
    async def hold(
        self, key: K, deadline: float | None = None, what: str | None = None
    ) -> AsyncIterator[None]:
        """Hold the lock of ``key``; waiting for it counts towards ``deadline``. ``what`` names
        the key for a user (``R100``) when the deadline passes while waiting (the key's repr
        otherwise)."""
        entries = self._entries
        entry = entries.get(key)
        if entry is None:
            entry = entries[key] = _Entry()
        entry.users += 1
        try:
            if entry.held:
                waiter: asyncio.Future[None] = asyncio.get_running_loop().create_future()
                entry.waiters.append(waiter)
                try:
                    async with asyncio.timeout_at(deadline):
                        await waiter
                except TimeoutError:
                    entry.leave_line(waiter)
                    raise FocasTimeoutError(
                        f"{what or repr(key)}: another bit write of this client held it past "
                        "the call's deadline (no request was sent)"
                    ) from None
                except BaseException:
                    entry.leave_line(waiter)
                    raise
            else:
                entry.held = True  # free: taken without suspending
            try:
                yield
            finally:
                entry.release()
        finally:
            entry.users -= 1
            if not entry.users:
                del entries[key]
