"""The shared receive side: one buffer per thread, each read handed on as bytes of its size,
and every protocol class of the package read through it (``recv_into``, not ``recv``). (The
native client reads its own sockets: ``tests/test_native_channel.py``.)"""

from __future__ import annotations

import asyncio
import threading

import pytest
from support import IO_TIMEOUT, serving

from focas_net._receive import SIZE, Received, receive_buffer
from focas_net.client import FocasClient
from focas_net.client.connection import Connection
from focas_net.server._base import BaseConnection
from focas_net.sim import default_machine


class Recorder(Received, asyncio.Protocol):
    def __init__(self) -> None:
        self.chunks: list[bytes] = []

    def data_received(self, data: bytes) -> None:
        self.chunks.append(data)


def test_each_read_is_handed_on_as_bytes_of_its_own_size() -> None:
    r = Recorder()
    view = r.get_buffer(-1)
    assert len(view) == SIZE
    view[:5] = b"hello"
    r.buffer_updated(5)
    view = r.get_buffer(-1)
    view[:3] = b"abc"  # the next read reuses the buffer: the first chunk is a copy
    r.buffer_updated(3)
    assert r.chunks == [b"hello", b"abc"]
    assert all(type(c) is bytes for c in r.chunks)


def test_the_buffer_is_the_threads_own() -> None:
    mine = receive_buffer()
    assert receive_buffer() is mine
    theirs: list[memoryview] = []
    t = threading.Thread(target=lambda: theirs.append(receive_buffer()))
    t.start()
    t.join(IO_TIMEOUT)
    assert theirs and theirs[0] is not mine
    assert theirs[0].obj is not mine.obj


@pytest.mark.parametrize("cls", [Connection, BaseConnection])
def test_every_connection_class_is_a_buffered_protocol(cls: type) -> None:
    # asyncio's transports read a BufferedProtocol with recv_into, never recv(256 KiB)
    assert issubclass(cls, asyncio.BufferedProtocol)
    assert issubclass(cls, Received)


async def test_a_large_answer_arrives_whole_through_the_shared_buffer() -> None:
    machine = default_machine()
    machine.write_pmc("D", 0, bytes(i * 7 % 251 for i in range(4096)))
    async with serving(machine) as served:
        async with (
            FocasClient(served.host, served.port) as a,
            FocasClient(served.host, served.port) as b,
        ):
            # two connections of one loop share the buffer; answers of both stay whole
            bigs, statuses = await asyncio.wait_for(
                asyncio.gather(
                    asyncio.gather(a.read_pmc("D", 0, 4096), b.read_pmc("D", 0, 4096)),
                    asyncio.gather(*(c.read_status() for c in (a, b) for _ in range(50))),
                ),
                IO_TIMEOUT,
            )
            expected = bytes(machine.read_pmc("D", 0, 4096))
            assert [bytes(big) for big in bigs] == [expected, expected]
            assert len(statuses) == 100
