"""The request slots of a packed connection: at most ``max_in_flight`` calls wait for answers
at once (a counter, and a first-in first-out line of waiters when every slot is taken; the wait
for a slot counts towards the call's deadline). A slot is freed once, when its request leaves
the table of requests in flight, and goes straight to the first in line. A batch is admitted
like one call and then takes one slot per request (see
:meth:`~focas_net.client.connection.Connection.request_all`).

:class:`RequestSlots` is mixed into :class:`~focas_net.client.connection.Connection`, whose
hot path reads the counter and the line directly (one attribute each, no call).
"""

from __future__ import annotations

import asyncio
from collections import deque

from focas_net.errors import FocasTimeoutError

from ._failures import command_text

__all__ = ["RequestSlots"]


class RequestSlots:
    """The slots of a connection's requests in flight, and the line of callers waiting."""

    _loop: asyncio.AbstractEventLoop
    _max_in_flight: int
    #: Slots in use: calls in flight and callers handed a slot not yet sent.
    _slots_taken: int
    #: Callers waiting for a slot, first in first out (only while every slot is taken).
    _slot_waiters: deque[asyncio.Future[None]]

    def _init_slots(self, max_in_flight: int) -> None:
        self._max_in_flight = max_in_flight
        self._slots_taken = 0
        self._slot_waiters = deque()

    @property
    def slots_taken(self) -> int:
        """Request slots in use: calls in flight and callers handed a slot not yet sent."""
        return self._slots_taken

    @property
    def waiting_for_slot(self) -> int:
        """Callers waiting in line for a request slot (every slot is taken)."""
        return len(self._slot_waiters)

    async def _admit(self, command: int, count: int, deadline: float | None) -> None:
        """Take ``count`` slots for a batch: at once when one is free and nobody waits, else
        after waiting in line for one (the batch then goes over the bound)."""
        if self._slots_taken < self._max_in_flight and not self._slot_waiters:
            self._slots_taken += count
        else:
            await self._wait_for_slot(command, deadline)
            self._slots_taken += count - 1

    async def _wait_for_slot(self, command: int, deadline: float | None) -> None:
        """Wait in line for a slot; the slot is handed over by :meth:`_release_slot`."""
        waiter: asyncio.Future[None] = self._loop.create_future()
        self._slot_waiters.append(waiter)
        try:
            if deadline is None:
                await waiter
            else:
                async with asyncio.timeout_at(deadline):
                    await waiter
        except TimeoutError:
            self._leave_line(waiter)
            raise FocasTimeoutError(
                f"no free request slot for {command_text(command)} in time"
            ) from None
        except BaseException:
            self._leave_line(waiter)
            raise

    def _leave_line(self, waiter: asyncio.Future[None]) -> None:
        """A waiter gave up: if a slot was handed to it already, pass the slot on."""
        if waiter.done() and not waiter.cancelled():
            self._release_slot()
            return
        waiter.cancel()
        try:
            self._slot_waiters.remove(waiter)
        except ValueError:
            pass

    def _release_slots(self, count: int) -> None:
        if not self._slot_waiters:  # nobody to hand a slot to: what _release_slot does
            self._slots_taken -= count
            return
        for _ in range(count):
            self._release_slot()

    def _release_slot(self) -> None:
        waiters = self._slot_waiters
        if self._slots_taken > self._max_in_flight:  # over the bound (a batch): no hand-over
            self._slots_taken -= 1
            return
        while waiters:
            waiter = waiters.popleft()
            if not waiter.done():
                waiter.set_result(None)  # the slot goes straight to the first in line
                return
        self._slots_taken -= 1
