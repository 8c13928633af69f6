"""A call started now and finished later: :class:`StartedCall`.

A poller reading many machines from one task starts every read first (each client sends its
request at once when it can) and then awaits the answers in turn
(:func:`~focas_net.client.read_status_all`). Both clients give their reads in this form
(``start_read_status``, and ``start_read_dynamic`` on the native client); a read that cannot be
sent at once (connecting, reconnecting, no request slot free) runs as the client's own call in
a task of its own. :meth:`StartedCall.on_done` tells when the answer is there, so that a poller
can take the answers in the order they come rather than the order it started them.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any, Generic, TypeVar

__all__ = ["StartedCall"]

T = TypeVar("T")


def _nothing() -> None:
    pass


class StartedCall(Generic[T]):
    """A read already sent (or running); :meth:`result` awaits its value.

    Await :meth:`result` once, or call :meth:`cancel` to give the call up (its request's
    answer is then dropped when it comes, as for a cancelled call); ``cancel`` after the
    result is harmless, so a ``finally`` may call it on every started call.
    """

    __slots__ = ("_done", "_ended", "_finish", "_give_up")

    def __init__(
        self,
        finish: Callable[[], Awaitable[T]],
        give_up: Callable[[], None],
        done: asyncio.Future[Any] | None = None,
    ) -> None:
        self._finish = finish
        self._give_up = give_up
        self._done = done
        self._ended = False

    def __repr__(self) -> str:
        """``<StartedCall waiting>``, ``answered`` (its result there to take), ``failed``
        (before anything was sent) or ``ended`` (its result taken, or given up)."""
        done = self._done
        state = (
            "ended"
            if self._ended
            else "failed"
            if done is None
            else "answered"
            if done.done()
            else "waiting"
        )
        return f"<StartedCall {state}>"

    def on_done(self, callback: Callable[[], None]) -> None:
        """Call ``callback()`` (from the event loop, once) when the answer (or the failure)
        is there: :meth:`result` then returns without waiting on the wire (a packed read
        answered EW_PASSWD, or never sent, is made again after it, within its deadline).
        A call started without its answer's future (a failure found at once) calls it
        soon. TypeError, naming it, for a ``callback`` that is not callable."""
        if not callable(callback):
            raise TypeError(f"on_done takes a callable with no arguments, got {callback!r}")
        done = self._done
        if done is None:
            asyncio.get_running_loop().call_soon(callback)
        else:
            done.add_done_callback(lambda _: callback())

    @classmethod
    def running(cls, call: Coroutine[Any, Any, T]) -> StartedCall[T]:
        """``call`` run in a task of its own from now."""
        task = asyncio.get_running_loop().create_task(call)

        def give_up() -> None:
            if not task.done():
                task.cancel()
            elif not task.cancelled():
                task.exception()  # retrieved, so that none is reported unseen

        async def finish() -> T:
            return await task

        return cls(finish, give_up, task)

    @classmethod
    def failed(cls, error: BaseException) -> StartedCall[T]:
        """A call that failed before anything was sent: :meth:`result` raises ``error``."""

        async def finish() -> T:
            raise error

        return cls(finish, _nothing)

    async def result(self) -> T:
        """The call's result, or the exception it ended with."""
        try:
            return await self._finish()
        finally:
            self._ended = True
            self._give_up()

    def cancel(self) -> None:
        """Give the call up, unless it ended."""
        if not self._ended:
            self._ended = True
            self._give_up()
