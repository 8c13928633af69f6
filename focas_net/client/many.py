"""Reading many machines from one task: :func:`read_status_all`.

A gateway polling a plant reads the status of hundreds of machines every cycle. Calling
``client.read_status()`` for each one in a task of its own (or through
:func:`asyncio.gather`, which makes those tasks) costs every poll a task step, a coroutine and,
for a task sleeping until its next poll, a timer. :func:`read_status_all` sends every request
first, each on its client's live connection and without a coroutine, then awaits the answers
in turn in the calling task: the answers that arrived together are taken in one wake-up.
"""

# The per-read timeout= is the client's own contract (docs/client.md), so ASYNC109 does not
# apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from typing import TYPE_CHECKING, Final, cast

from focas_net.errors import FocasError

from ..protocol import COMMANDS, StatusInfo
from ..protocol import Command as C
from .connection import NotSentError
from .reconnect import _UNLOCK_AND_RETRY

if TYPE_CHECKING:
    from .client import FocasClient
    from .connection import Connection, _Pending

__all__ = ["read_status_all"]

_RDCNCSTAT: Final = COMMANDS[C.RDCNCSTAT]
_EMPTY: Final = b""


async def read_status_all(
    clients: Sequence[FocasClient], *, timeout: float | None = None
) -> list[StatusInfo | FocasError]:
    """``cnc_rdcncstat`` on every client at once: each one's :class:`StatusInfo`, or the
    :class:`FocasError` its read ended with, in the order of ``clients``.

    Every read is the one ``client.read_status(timeout=timeout)`` makes (``timeout`` None:
    each client's own default), with the same results and errors; one read failing does not
    touch the others. A client that cannot send at once (connecting, reconnecting, closed, or
    every request slot taken) is read by its own ``read_status`` in a task of its own, which
    waits for the reconnect as that call does; so is a read whose request never left
    (:class:`NotSentError`, sent again on the next connection when a reconnect policy is
    set) and one answered ``EW_PASSWD`` while a password is known (unlocked and sent once
    more). Cancelling the caller gives up every read still unanswered (their request ids
    stay reserved until their late answers, as for a cancelled call) and cancels those tasks.
    An exception that is not a :class:`FocasError` is raised, after the same clean-up.
    """
    loop = asyncio.get_running_loop()
    results: list[StatusInfo | FocasError | None] = [None] * len(clients)
    deadlines: list[float | None] = []
    started: list[tuple[int, Connection, _Pending]] = []
    others: list[tuple[int, asyncio.Task[StatusInfo]]] = []
    finished = 0  # entries of ``started`` whose connection was told the caller is done
    try:
        for i, client in enumerate(clients):
            deadline = client._deadline(timeout)
            deadlines.append(deadline)
            sent = client._start(_RDCNCSTAT, _EMPTY, deadline)
            if sent is None:
                others.append((i, loop.create_task(client.read_status(timeout=timeout))))
            else:
                started.append((i, sent[0], sent[1]))
        for i, conn, entry in started:
            try:
                raw = await entry[0]
            except NotSentError:
                raw = None
            except FocasError as exc:
                results[i] = exc
                continue
            finally:
                finished += 1
                conn.finish(entry)
            client = clients[i]
            if raw is not None:
                try:
                    value = client._answer(_RDCNCSTAT, raw)
                except FocasError as exc:
                    results[i] = exc
                    continue
                if value is not _UNLOCK_AND_RETRY:
                    results[i] = value
                    continue
            # Never sent, or to be unlocked and sent again: the call made the usual way, within
            # what is left of this read's deadline.
            deadline = deadlines[i]
            left = timeout if deadline is None else max(0.0, deadline - loop.time())
            others.append((i, loop.create_task(client.read_status(timeout=left))))
        for i, task in others:
            try:
                results[i] = await task
            except FocasError as exc:
                results[i] = exc
    finally:
        for _, conn, entry in started[finished:]:
            conn.finish(entry)
        for _, task in others:
            if not task.done():
                task.cancel()
            elif not task.cancelled():
                task.exception()  # retrieved: a failure left behind is not reported unseen
    return cast(list[StatusInfo | FocasError], results)
