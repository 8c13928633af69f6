"""Answers that leave only once what they acknowledge is durable (``serve --state``).

With a :class:`Keeper`, every connection's transport is a :class:`HeldTransport`: what a
connection writes during a turn of the event loop is held, and one call scheduled at the end
of the turn (``loop.call_soon`` from the first held write) makes the machines' changes durable
(one ``save``: each changed machine's state file written and flushed to the disk) and then
releases every held answer, in order. The writes of one turn, from any number of connections
and machines, cost one save; a turn with no change saves nothing (the state files compare
their machine's version counters first).

A write whose answer never left may be in the state or not: the server may have died before
the save, during it (a record cut short is ignored at the next start, a replaced file is
found old or new, whole), or after it and before the answer was sent. A write whose answer
left is in the state.

When the save fails (a full disk, a vanished directory, any error), the held answers are not
sent: their connections are aborted, as a control that cannot keep a change does not acknowledge it.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import Any

__all__ = ["HeldTransport", "Keeper"]

_log = logging.getLogger("focas_net.server")


class Keeper:
    """Holds the answers of a loop turn until ``save`` made the changes durable.

    ``save`` writes what changed (it raises OSError when it cannot). :meth:`flush` runs at
    the end of every turn in which an answer was written; call it at shutdown too."""

    __slots__ = ("_held", "_save", "_scheduled", "flushes")

    def __init__(self, save: Callable[[], object]) -> None:
        self._save = save
        self._held: list[HeldTransport] = []
        self._scheduled = False
        #: How many turns were flushed.
        self.flushes = 0

    def hold(self, transport: Any) -> HeldTransport:
        """``transport`` with its writes held until the end of the turn."""
        return HeldTransport(transport, self)

    def _enqueue(self, held: HeldTransport) -> None:
        self._held.append(held)
        if not self._scheduled:
            self._scheduled = True
            asyncio.get_running_loop().call_soon(self.flush)

    def flush(self) -> bool:
        """Save, then release every held answer (abort their connections when the save
        failed). Whether the save succeeded (a caller with an answer of its own to give, such
        as the web dashboard's, gives it only then)."""
        self._scheduled = False
        held, self._held = self._held, []
        self.flushes += 1
        try:
            self._save()
        except Exception as exc:  # not only OSError: an answer is never sent unsaved nor held
            _log.error("cannot keep the machines' state (%s): the answers are not sent", exc)
            for transport in held:
                transport.drop()
            return False
        for transport in held:
            transport.release()
        return True


class HeldTransport:
    """A transport whose writes leave at the end of the loop turn, once saved (see
    :class:`Keeper`). Everything else is the transport's own."""

    __slots__ = ("_base", "_chunks", "_close", "_keeper")

    def __init__(self, base: Any, keeper: Keeper) -> None:
        self._base = base
        self._keeper = keeper
        self._chunks: list[bytes] = []
        self._close = False

    def __getattr__(self, name: str) -> Any:
        return getattr(self._base, name)

    @property
    def holding(self) -> bool:
        """Whether answers are held (the end of the turn will send them)."""
        return bool(self._chunks)

    def write(self, data: bytes | bytearray | memoryview) -> None:
        if self._close:
            return
        if not self._chunks:
            self._keeper._enqueue(self)
        self._chunks.append(bytes(data))

    def writelines(self, lines: Any) -> None:
        for data in lines:
            self.write(data)

    def get_write_buffer_size(self) -> int:
        held = sum(len(c) for c in self._chunks)
        return int(self._base.get_write_buffer_size()) + held

    def is_closing(self) -> bool:
        return self._close or bool(self._base.is_closing())

    def close(self) -> None:
        """Close once the held answers are released."""
        if self._chunks:
            self._close = True
        else:
            self._base.close()

    def abort(self) -> None:
        self._chunks.clear()
        self._base.abort()

    def release(self) -> None:
        """Send what is held (the keeper saved)."""
        chunks, self._chunks = self._chunks, []
        base = self._base
        if not base.is_closing():
            base.write(chunks[0] if len(chunks) == 1 else b"".join(chunks))
            if self._close:
                base.close()

    def drop(self) -> None:
        """The keeper could not save: nothing held is sent, the connection is aborted."""
        self._chunks.clear()
        self._base.abort()
