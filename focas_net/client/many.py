"""Reading many machines from one task: :func:`read_status_all`,
:func:`read_status_paths_all`, :func:`read_dynamic_all`.

A gateway polling a plant reads the status of hundreds of machines every cycle. Calling
``client.read_status()`` for each one in a task of its own (or through
:func:`asyncio.gather`, which makes those tasks) costs every poll a task step, a coroutine and,
for a task sleeping until its next poll, a timer. These functions start every read first
(``start_read_status``: each client sends its request at once when it can) and then await the
answers in turn in the calling task, so the answers that arrived together are taken in one
wake-up. They read :class:`FocasClient` and :class:`NativeClient` alike, mixed in one list if
need be; :func:`read_dynamic_all` reads ``cnc_rddynamic2`` of native clients.
"""

# The per-read timeout= is the client's own contract (docs/client.md), so ASYNC109 does not
# apply here.
# ruff: noqa: ASYNC109

from __future__ import annotations

import asyncio
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import TypeVar

from focas_net.errors import CncError, FocasError

from ..protocol import StatusInfo
from ._started import StartedCall
from ._values import check_timeout
from .client import FocasClient
from .native import DynamicData, NativeClient

__all__ = ["read_dynamic_all", "read_status_all", "read_status_paths_all"]

T = TypeVar("T")
C = TypeVar("C")


async def _all(clients: Sequence[C], start: Callable[[C], StartedCall[T]]) -> list[T | FocasError]:
    """``start(client)`` for every client, then each one's result (or the :class:`FocasError`
    it ended with), in order. Whatever ends this early (a cancellation, an exception that is
    not a :class:`FocasError`) gives up every read still unanswered."""
    started: list[StartedCall[T]] = []
    results: list[T | FocasError] = []
    try:
        for client in clients:
            started.append(start(client))
        for call in started:
            try:
                results.append(await call.result())
            except FocasError as exc:
                results.append(exc)
    finally:
        for call in started:
            call.cancel()
    return results


async def read_status_all(
    clients: Sequence[FocasClient | NativeClient], *, timeout: float | None = None
) -> list[StatusInfo | FocasError]:
    """``cnc_rdcncstat`` (``cnc_statinfo`` on a :class:`NativeClient`) on every client at
    once: each one's :class:`StatusInfo`, or the :class:`FocasError` its read ended with, in
    the order of ``clients``.

    Every read is the one ``client.read_status(timeout=timeout)`` makes (``timeout`` None:
    each client's own default), with the same results and errors; one read failing does not
    touch the others. A client that cannot send at once (connecting, reconnecting, closed, or
    every request slot taken) is read by its own ``read_status`` in a task of its own; a
    native client's read waits in its queue for the frame in flight, as its own calls do.
    Cancelling the caller gives up every read still unanswered (a packed request id stays
    reserved until its late answer; a native call still queued is dropped from its queue).
    An exception that is not a :class:`FocasError` is raised, after the same clean-up.
    """
    _check_clients(clients, "start_read_status", "a FocasClient or a NativeClient", timeout)
    return await _all(clients, lambda client: client.start_read_status(timeout=timeout))


def _check_clients(clients: object, method: str, kinds: str, timeout: object) -> None:
    """``clients`` is a sequence of clients that have ``method``, and ``timeout`` a call's
    timeout: TypeError or ValueError naming what was given otherwise, before any read."""
    check_timeout(timeout)
    if isinstance(clients, str | bytes) or not isinstance(clients, Sequence):
        words = "clients must be a list of clients, got"
        if isinstance(clients, Mapping):
            raise TypeError(f"{words} a {type(clients).__name__}")
        if isinstance(clients, Iterable) and not isinstance(clients, str | bytes):
            # a generator's or a set's repr tells nothing ("<generator object ... at 0x...>")
            kind = type(clients).__name__
            article = "an" if kind[:1].lower() in "aeiou" else "a"
            raise TypeError(f"{words} {article} {kind} (make it a list: list(...))")
        raise TypeError(f"{words} {clients!r}")
    for i, client in enumerate(clients):
        if not callable(getattr(client, method, None)):
            raise TypeError(f"clients[{i}] must be {kinds}, got {client!r}")


async def read_dynamic_all(
    clients: Sequence[NativeClient], axis: int = -1, *, timeout: float | None = None
) -> list[DynamicData | FocasError]:
    """``cnc_rddynamic2`` on every native client at once: each one's
    :class:`~focas_net.client.DynamicData` (of every axis, or of ``axis``), or the
    :class:`FocasError` its read ended with, in the order of ``clients``.

    Every read is the one ``client.read_dynamic(axis, timeout=timeout)`` makes, with the same
    results and errors (an ``axis`` outside 1..0x7FFF and not -1 raises :class:`ValueError`
    before anything is sent); one read failing does not touch the others. Cancelling the
    caller drops the reads still queued and ignores the answers of those sent.
    """
    _check_clients(clients, "start_read_dynamic", "a NativeClient", timeout)
    return await _all(clients, lambda client: client.start_read_dynamic(axis, timeout=timeout))


async def _path_count(client: FocasClient | NativeClient, timeout: float | None) -> int:
    """The number of paths of ``client``'s CNC: known (the native open answer, the packed
    client's last ``read_paths``), else read once with ``read_paths``; 1 for a CNC that
    cannot tell (it answers ``cnc_getpath`` with an EW code)."""
    count = client.path_count
    if count is None:
        try:
            count = (await client.read_paths(timeout=timeout)).count
        except CncError:
            count = 1
    return max(count, 1)


async def read_status_paths_all(
    clients: Sequence[FocasClient | NativeClient], *, timeout: float | None = None
) -> list[tuple[StatusInfo, ...] | FocasError]:
    """The status of every path of every client at once: for each client the
    :class:`StatusInfo` of its paths 1..n in order, or the :class:`FocasError` a read ended
    with, in the order of ``clients``.

    Every path's read is the one ``client.read_status(path=p, timeout=timeout)`` makes. The
    number of paths is the client's :attr:`path_count`; a packed client that does not know it
    yet reads it first (``read_paths``, once). Then every read of a client is started before
    any answer is awaited, so the reads of one machine leave together: one write of
    ``cnc_rdcncstat`` requests with the ``cnc_setpath`` between paths on a packed connection,
    one frame of blocks with each path's path word on a native one (within ``max_blocks``).
    Cancelling the caller gives up every read still unanswered, as :func:`read_status_all`.
    """
    _check_clients(clients, "start_read_status", "a FocasClient or a NativeClient", timeout)
    counts = await asyncio.gather(
        *(_path_count(client, timeout) for client in clients), return_exceptions=True
    )
    started: list[list[StartedCall[StatusInfo]] | FocasError] = []
    results: list[tuple[StatusInfo, ...] | FocasError] = []
    try:
        for client, count in zip(clients, counts, strict=True):
            if isinstance(count, FocasError):
                started.append(count)
            elif isinstance(count, BaseException):
                raise count
            else:
                started.append(
                    [
                        client.start_read_status(path=path, timeout=timeout)
                        for path in range(1, count + 1)
                    ]
                )
        for calls in started:
            if isinstance(calls, FocasError):
                results.append(calls)
                continue
            try:
                results.append(tuple([await call.result() for call in calls]))
            except FocasError as exc:
                results.append(exc)
    finally:
        for calls in started:
            if not isinstance(calls, FocasError):
                for call in calls:
                    call.cancel()
    return results
