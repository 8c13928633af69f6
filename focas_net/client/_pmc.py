"""The packed client's PMC primitives: ranges over 32-byte calls.

A ``pmc_rdpmcrng`` or ``pmc_wrpmcrng`` call carries at most 32 data bytes
(``docs/protocol.md``). A longer range is split into consecutive 32-byte chunks sent as one
batch in one write on the live connection, with no task per chunk:

* a read raises the first chunk's failure at once (the other chunks are given up) and falls
  back to one :meth:`Link._request` per chunk when the batch cannot complete on this
  connection (not sent and a reconnect is due, or ``EW_PASSWD`` with a password known):
  reads are safe to repeat;
* a write waits for every chunk and gives each one's outcome (written, or its error and
  whether it was sent); :mod:`._composite` makes of them the call's
  :class:`~focas_net.errors.ChunkedWriteError`.

Chunks follow the rules of the single request path: never sent -> sent again on the next
connection with a reconnect policy; ``EW_PASSWD`` with a password -> one unlock, one retry.
"""

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from functools import partial
from typing import Any, Final

from focas_net.errors import (
    CncError,
    FocasConnectionError,
    FocasTimeoutError,
    PayloadError,
)

from ..protocol import COMMANDS, MAX_PMC_CHUNK, CommandSpec, EwReply, PmcArea, PmcData, PmcRange
from ..protocol import Command as C
from ._composite import ChunkOutcome, write_chunked
from ._link import Link
from .connection import Connection, NotSentError

__all__ = ["read_pmc_range", "write_pmc_chunks", "write_pmc_range"]

_RDPMCRNG: Final = COMMANDS[C.RDPMCRNG]
_U16_LIMIT: Final = 0x10000


def _chunks(start: int, count: int) -> list[tuple[int, int]]:
    """``(first, count)`` of consecutive chunks of at most 32 bytes."""
    return [(a, min(MAX_PMC_CHUNK, start + count - a)) for a in range(start, start + count, 32)]


def _checked(value: PmcData, start: int, count: int) -> bytes:
    """The data of a read answer, which must be ``count`` bytes from ``start``."""
    if len(value.data) != count or value.datano_s != start:
        raise PayloadError(
            f"pmc_rdpmcrng answer: {len(value.data)} bytes from {value.datano_s}, "
            f"asked {count} from {start}"
        )
    return value.data


# -- reads ---------------------------------------------------------------------------------------
async def _read_pmc_chunk(
    link: Link, area: PmcArea, start: int, count: int, deadline: float | None
) -> bytes:
    """One ``pmc_rdpmcrng`` call (``count`` at most 32)."""
    payload = _RDPMCRNG.request.encode(PmcRange(area, 0, start, start + count - 1))
    value: PmcData = await link._request_at(_RDPMCRNG, payload, deadline)
    return _checked(value, start, count)


async def read_pmc_range(
    link: Link, area: PmcArea, start: int, count: int, deadline: float | None
) -> bytes:
    """``count`` bytes of ``area`` from ``start`` (a checked range): one call up to 32 bytes,
    else one batch of 32-byte chunks (or one call per chunk, see the module)."""
    if count <= MAX_PMC_CHUNK:
        return await _read_pmc_chunk(link, area, start, count, deadline)
    conn = link._conn
    if conn is not None and not conn.closed:
        data = await _read_batch(link, conn, area, start, count, deadline)
        if data is not None:
            return data
    parts = await _all_or_first_error(
        [_read_pmc_chunk(link, area, s, n, deadline) for s, n in _chunks(start, count)]
    )
    return b"".join(parts)


async def _read_batch(
    link: Link, conn: Connection, area: PmcArea, start: int, count: int, deadline: float | None
) -> bytes | None:
    """Every chunk of a chunked read in one batch on ``conn``; None when the read must go
    through the per-chunk path instead (the batch was not sent and a reconnect is due, or a
    chunk answered ``EW_PASSWD`` and a password is known): reads are safe to repeat."""
    chunks = _chunks(start, count)
    encode = _RDPMCRNG.request.encode
    payloads = [encode(PmcRange(area, 0, s, s + n - 1)) for s, n in chunks]
    try:
        answers = await conn.request_all(_RDPMCRNG.command, payloads, deadline, _ew_not_ok)
    except NotSentError:
        if link._policy is None:
            raise
        return None
    decode = partial(link._decoded, _RDPMCRNG)
    parts: list[bytes] = []
    for (first, n), raw in zip(chunks, answers, strict=True):
        if raw is None:
            continue  # given up after another chunk failed; that one is raised below
        value = decode(raw)
        if type(value) is EwReply:
            if link._retries_after_unlock(_RDPMCRNG, value.ew):
                return None
            raise CncError.from_ew(value.ew, _RDPMCRNG.function)
        parts.append(_checked(value, first, n))
    if len(parts) != len(chunks):  # not reached: a chunk given up implies one raised
        raise PayloadError("pmc_rdpmcrng: a chunked read ended with chunks missing")
    return b"".join(parts)


def _ew_not_ok(raw: bytes) -> bool:
    """True for an answer that is not a success (an EW code, or too short for one)."""
    return len(raw) < 2 or raw[0] != 0 or raw[1] != 0


async def _all_or_first_error(coros: Sequence[Any]) -> list[Any]:
    """Run ``coros`` concurrently; on the first failure cancel the rest and raise it."""
    loop = asyncio.get_running_loop()
    tasks = [loop.create_task(c) for c in coros]
    try:
        await asyncio.wait(tasks, return_when=asyncio.FIRST_EXCEPTION)
    finally:
        unfinished = [t for t in tasks if not t.done()]
        for t in unfinished:
            t.cancel()
        if unfinished:
            await asyncio.wait(unfinished)
        # Retrieve every failure (also when this call is being cancelled), so that none is
        # reported as never retrieved; the first, in order, is raised.
        failures = [t.exception() for t in tasks if not t.cancelled()]
    first = next((e for e in failures if e is not None), None)
    if first is not None:
        raise first
    return [t.result() for t in tasks]


# -- writes --------------------------------------------------------------------------------------
async def write_pmc_range(
    link: Link, spec: CommandSpec, area: PmcArea, start: int, data: bytes, deadline: float | None
) -> None:
    """Write ``data`` (a checked range) to ``area`` from ``start`` with ``spec``
    (``pmc_wrpmcrng`` or the simulator's ``set_pmc``) in 32-byte chunks."""

    async def write(chunks: Sequence[tuple[int, bytes]]) -> list[ChunkOutcome]:
        return await write_pmc_chunks(link, spec, area, chunks, deadline)

    await write_chunked(area, start, data, MAX_PMC_CHUNK, write)


async def write_pmc_chunks(
    link: Link,
    spec: CommandSpec,
    area: PmcArea,
    chunks: Sequence[tuple[int, bytes]],
    deadline: float | None,
) -> list[ChunkOutcome]:
    """Write each ``(first, data)`` chunk (32 bytes at most) with ``spec``: one request alone,
    several as batches; the outcome of each chunk."""
    encode = spec.request.encode
    payloads = [encode(PmcData(area, 0, first, first + len(d) - 1, d)) for first, d in chunks]
    errors, unanswered = await _write_chunks(link, spec, payloads, deadline)
    return [None if e is None else (e, u) for e, u in zip(errors, unanswered, strict=True)]


async def _write_chunks(
    link: Link, spec: CommandSpec, payloads: list[bytes], deadline: float | None
) -> tuple[list[Exception | None], list[bool]]:
    """Send the chunks of a chunked write as batches and wait for every chunk.

    Returns, per chunk, the exception it ended with (None: confirmed written) and whether
    it was sent and left unanswered (a timeout, or the connection lost after it left).
    Chunks never sent go out again on the next connection when a reconnect policy is set;
    chunks answered ``EW_PASSWD`` are sent once more after one unlock when a password is
    known (on the next connection, with a reconnect policy, if this one is lost around the
    unlock); every other chunk's outcome is final after one batch.
    """
    count = len(payloads)
    errors: list[Exception | None] = [None] * count
    unanswered = [False] * count
    retried = [False] * count  # sent again after an unlock already
    decode = partial(link._decoded, spec)
    todo = list(range(count))
    while todo:
        try:
            conn = await link._connection(deadline)
            results = await conn.request_each(spec.command, [payloads[i] for i in todo], deadline)
        except NotSentError as exc:
            if link._policy is not None:
                continue  # nothing left: every chunk goes out on the next connection
            for i in todo:
                errors[i] = exc
            break
        except (FocasConnectionError, FocasTimeoutError) as exc:
            # Nothing of this batch was sent: not connected (or still reconnecting when
            # the deadline passed), or no request slot free in time.
            for i in todo:
                errors[i] = exc
            break
        again: list[int] = []
        locked: list[int] = []
        for i, result in zip(todo, results, strict=True):
            if isinstance(result, bytes):
                try:
                    value = decode(result)
                except Exception as exc:  # an answer that does not decode
                    errors[i] = exc
                    continue
                if type(value) is EwReply:
                    if not retried[i] and link._retries_after_unlock(spec, value.ew):
                        locked.append(i)
                    else:
                        errors[i] = CncError.from_ew(value.ew, spec.function)
            elif not isinstance(result, Exception):
                raise result
            elif isinstance(result, NotSentError):
                if link._policy is not None:
                    again.append(i)  # never reached the peer: sent on the next connection
                else:
                    errors[i] = result
            else:
                errors[i] = result
                unanswered[i] = isinstance(result, (FocasTimeoutError, FocasConnectionError))
        if locked:
            try:
                # One unlock for the batch. Lost around it with a reconnect policy, this
                # returns: the chunks go out once more on the next connection, which the
                # reconnect unlocks, like chunks never sent.
                await link._unlock_for_retry(conn, deadline)
            except Exception as exc:
                # The unlock failed: each of these chunks was refused, so not written.
                for i in locked:
                    errors[i] = exc
                locked = []
            for i in locked:
                retried[i] = True
            again.extend(locked)
            again.sort()
        todo = again
    return errors, unanswered
