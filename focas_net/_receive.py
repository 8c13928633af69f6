"""The receive side every connection of the package shares: reads into one buffer per thread.

asyncio's selector transports read a plain :class:`asyncio.Protocol`'s data with
``recv(256 KiB)``: every read allocates a 256 KiB ``bytes`` object and shrinks it to what
arrived. glibc serves an allocation that large with ``mmap`` and the shrink with ``mremap``
(and the free with ``munmap``) until its dynamic threshold has been raised by some earlier
large free, so in a process that has not done one, each read of a small answer costs system
calls and page faults of its own (about 15 us of system time per read on the benchmark
machine, more than the rest of a poll). A :class:`asyncio.BufferedProtocol` is read with
``recv_into`` instead.

:class:`Received` makes a protocol a buffered one that still sees its input as
``data_received(bytes)``: the transport reads into a buffer of :data:`SIZE` bytes owned by the
thread (an event loop runs in one thread and calls ``get_buffer``, reads and calls
``buffer_updated`` in one go, so the connections of a loop can share it), and the bytes read
are copied out once, at their own size, before anything else runs. Every transport asyncio and
uvloop give a buffered protocol (TCP, TLS) drives it this way.
"""

from __future__ import annotations

import asyncio
import threading
from typing import TYPE_CHECKING, Final

#: Bytes one read may bring (asyncio's own read size for a plain protocol).
SIZE: Final = 256 * 1024

_local = threading.local()


def receive_buffer() -> memoryview:
    """The calling thread's receive buffer (made on first use)."""
    try:
        view: memoryview = _local.view
    except AttributeError:
        view = _local.view = memoryview(bytearray(SIZE))
    return view


class Received(asyncio.BufferedProtocol):
    """A buffered protocol that hands what each read brought to ``data_received`` as bytes
    (mixed in before :class:`asyncio.Protocol` or a protocol deriving from it)."""

    __slots__ = ()

    def get_buffer(self, sizehint: int) -> memoryview:
        try:
            view: memoryview = _local.view  # receive_buffer() without its call
        except AttributeError:
            view = receive_buffer()
        return view

    def buffer_updated(self, nbytes: int) -> None:
        self.data_received(bytes(_local.view[:nbytes]))

    if TYPE_CHECKING:  # given by the protocol it is mixed into (none here: see the MRO)

        def data_received(self, data: bytes) -> None: ...
