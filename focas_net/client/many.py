"""Reading many machines from one task: :func:`read_status_all`, :func:`read_dynamic_all`.

A gateway polling a plant reads the status of hundreds of machines every cycle. Calling
``client.read_status()`` for each one in a task of its own (or through
:func:`asyncio.gather`, which makes those tasks) costs every poll a task step, a coroutine and,
for a task sleeping until its next poll, a timer. :func:`read_status_all` sends every request
first, each on its client's live connection and without a coroutine, then awaits the answers
in turn in the calling task: the answers that arrived together are taken in one wake-up. It
reads :class:`FocasClient` and :class:`NativeClient` alike, mixed in one list if need be;
:func:`read_dynamic_all` does the same for ``cnc_rddynamic2`` over native clients.
"""

# The per-read timeout= is the client's own contract (docs/client.md), so ASYNC109 does not
# apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Final, TypeVar, cast

from focas_net.errors import FocasError

from ..protocol import COMMANDS, StatusInfo
from ..protocol import Command as C
from .connection import NotSentError
from .native import DynamicData, NativeClient, _check_dynamic_axis
from .reconnect import _UNLOCK_AND_RETRY

if TYPE_CHECKING:
    from ..native.calls import LibraryCall
    from .client import FocasClient
    from .connection import Connection, _Pending
    from .native import _Handle, _Job

__all__ = ["read_dynamic_all", "read_status_all"]

T = TypeVar("T")

_RDCNCSTAT: Final = COMMANDS[C.RDCNCSTAT]
_EMPTY: Final = b""


async def read_status_all(
    clients: Sequence[FocasClient | NativeClient], *, timeout: float | None = None
) -> list[StatusInfo | FocasError]:
    """``cnc_rdcncstat`` (``cnc_statinfo`` on a :class:`NativeClient`) on every client at
    once: each one's :class:`StatusInfo`, or the :class:`FocasError` its read ended with, in
    the order of ``clients``.

    Every read is the one ``client.read_status(timeout=timeout)`` makes (``timeout`` None:
    each client's own default), with the same results and errors; one read failing does not
    touch the others. A client that cannot send at once (connecting, reconnecting, closed, or
    every request slot taken; a native client's call waits in its queue for the frame in
    flight instead, as its own calls do) is read by its own ``read_status`` in a task of its
    own, which waits for the reconnect as that call does; so is a packed read whose request
    never left (:class:`NotSentError`, sent again on the next connection when a reconnect
    policy is set) and one answered ``EW_PASSWD`` while a password is known (unlocked and sent
    once more). Cancelling the caller gives up every read still unanswered (packed request
    ids stay reserved until their late answers, as for a cancelled call; a native call still
    queued is dropped from its queue) and cancels those tasks. An exception that is not a
    :class:`FocasError` is raised, after the same clean-up.
    """
    loop = asyncio.get_running_loop()
    results: list[StatusInfo | FocasError | None] = [None] * len(clients)
    deadlines: list[float | None] = []
    started: list[tuple[int, Connection, _Pending]] = []
    queued: list[tuple[int, NativeClient, _Handle, _Job]] = []
    others: list[tuple[int, asyncio.Task[StatusInfo]]] = []
    finished = 0  # entries of ``started`` whose connection was told the caller is done
    try:
        for i, client in enumerate(clients):
            deadline = client._deadline(timeout)
            deadlines.append(deadline)
            if isinstance(client, NativeClient):
                begun = client._start_status(deadline)
                if begun is None:
                    others.append((i, loop.create_task(client.read_status(timeout=timeout))))
                else:
                    queued.append((i, client, begun[0], begun[1]))
                continue
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
            packed = cast("FocasClient", clients[i])
            if raw is not None:
                try:
                    value = packed._answer(_RDCNCSTAT, raw)
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
            others.append((i, loop.create_task(packed.read_status(timeout=left))))
        for i, native, handle, job in queued:
            try:
                results[i] = native._status_of(handle, await job.future)
            except FocasError as exc:
                results[i] = exc
        await _await_tasks(others, results)
    finally:
        for _, conn, entry in started[finished:]:
            conn.finish(entry)
        _give_up(queued, others)
    return cast(list[StatusInfo | FocasError], results)


async def read_dynamic_all(
    clients: Sequence[NativeClient], axis: int = -1, *, timeout: float | None = None
) -> list[DynamicData | FocasError]:
    """``cnc_rddynamic2`` on every native client at once: each one's
    :class:`~focas_net.client.DynamicData` (of every axis, or of ``axis``), or the
    :class:`FocasError` its read ended with, in the order of ``clients``.

    Every read is the one ``client.read_dynamic(axis, timeout=timeout)`` makes, with the same
    results and errors (an ``axis`` outside 1..0x7FFF and not -1 raises :class:`ValueError`
    before anything is sent); one read failing does not touch the others. A client with no
    open connection is read by its own ``read_dynamic`` in a task of its own (which waits
    for a reconnect under way, as that call does); a client with a frame in flight queues the
    read for its next frame, as its own calls do. Cancelling the caller drops the reads still
    queued, ignores the answers of those sent and cancels those tasks.
    """
    _check_dynamic_axis(axis)
    loop = asyncio.get_running_loop()
    results: list[DynamicData | FocasError | None] = [None] * len(clients)
    queued: list[tuple[int, NativeClient, _Handle, LibraryCall, _Job]] = []
    others: list[tuple[int, asyncio.Task[DynamicData]]] = []
    try:
        for i, client in enumerate(clients):
            try:
                begun = client._start_dynamic(axis, client._deadline(timeout))
            except FocasError as exc:
                results[i] = exc
                continue
            if begun is None:
                others.append((i, loop.create_task(client.read_dynamic(axis, timeout=timeout))))
            else:
                queued.append((i, client, *begun))
        for i, native, handle, call, job in queued:
            try:
                results[i] = native._dynamic_of(handle, call, axis, await job.future)
            except FocasError as exc:
                results[i] = exc
        await _await_tasks(others, results)
    finally:
        _give_up(queued, others)
    return cast(list[DynamicData | FocasError], results)


async def _await_tasks(
    others: list[tuple[int, asyncio.Task[T]]], results: list[T | FocasError | None]
) -> None:
    """Each task's result, or the :class:`FocasError` it ended with, into ``results``."""
    for i, task in others:
        try:
            results[i] = await task
        except FocasError as exc:
            results[i] = exc


def _give_up(
    queued: Sequence[tuple[Any, ...]], others: list[tuple[int, asyncio.Task[Any]]]
) -> None:
    """The caller is done: the native jobs of ``queued`` (each entry's last item) not answered
    are given up as their own caller gives them up (a queued one is dropped, a sent one's
    blocks ignored), tasks not done are cancelled, and the failures of those done retrieved
    (so that none is reported unseen)."""
    for entry in queued:
        job: _Job = entry[-1]
        if not job.future.done():
            job.future.cancel()
    for _, task in others:
        if not task.done():
            task.cancel()
        elif not task.cancelled():
            task.exception()
