"""A collector reading every path of every machine (issue 43): :func:`read_status_paths_all`
sends the reads of one machine together, one write per packed connection and one frame per
native client, whatever the number of paths."""

from __future__ import annotations

from collections.abc import AsyncIterator, Iterable
from contextlib import AsyncExitStack, asynccontextmanager

import pytest
from support import IO_TIMEOUT, Served, serving, two_path_lathe

from focas_net import FocasClient, NativeClient, read_status_paths_all
from focas_net.client.connection import Connection
from focas_net.errors import EW, CncError
from focas_net.protocol import Command, FrameDecoder, StatusInfo

MDI, MEM = 0, 1


@asynccontextmanager
async def plant(two_path: int) -> AsyncIterator[list[Served]]:
    """``two_path`` lathes of two paths, then one default machine of one path."""
    async with AsyncExitStack() as stack:
        served = [
            await stack.enter_async_context(serving(two_path_lathe())) for _ in range(two_path)
        ]
        served.append(await stack.enter_async_context(serving()))
        yield served


class Writes:
    """The commands a packed connection writes, and how many of its requests were waiting for
    an answer at its last write: all of them when every request left before the first
    answer came (one round trip)."""

    def __init__(self, conn: Connection) -> None:
        transport = conn._transport
        assert transport is not None
        self.commands: list[int] = []
        self.waiting_at_last_write = 0
        plain = transport.write

        def seen(data: bytes) -> None:
            self.commands += [f.command for f in FrameDecoder().feed(data)]
            self.waiting_at_last_write = conn.in_flight

        def write(data: bytes | bytearray | memoryview) -> None:
            seen(bytes(data))
            plain(data)

        def writelines(list_of_data: Iterable[bytes | bytearray | memoryview]) -> None:
            data = b"".join(bytes(piece) for piece in list_of_data)
            seen(data)  # one write of several buffers (Python 3.12 and later send it so)
            plain(data)

        transport.write = write  # type: ignore[method-assign]
        transport.writelines = writelines  # type: ignore[method-assign]


async def test_every_path_of_every_packed_machine_in_one_write_each() -> None:
    async with plant(3) as served, AsyncExitStack() as stack:
        clients = [
            await stack.enter_async_context(FocasClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        await clients[1].sim.set_panel(MDI, path=2)  # one path told apart by its mode
        first = await read_status_paths_all(clients)  # learns the path counts: read_paths
        assert [c.path_count for c in clients] == [2, 2, 2, 1]
        writes = []
        for client in clients:
            assert client.connection is not None
            writes.append(Writes(client.connection))
        again = await read_status_paths_all(clients)
    assert again == first
    for result, paths in zip(again, (2, 2, 2, 1), strict=True):
        assert isinstance(result, tuple) and len(result) == paths
        assert all(isinstance(s, StatusInfo) for s in result)
    second_lathe = again[1]
    assert isinstance(second_lathe, tuple)
    assert [s.aut for s in second_lathe] == [MEM, MDI]
    status, setpath = int(Command.RDCNCSTAT), int(Command.SETPATH)
    for w in writes[:3]:  # the last poll left path 2 selected: 1, then 2 again
        assert w.commands == [setpath, status, setpath, status]
        assert w.waiting_at_last_write == 4  # every frame out before the first answer
    assert writes[3].commands == [status]  # one path: no selection
    assert writes[3].waiting_at_last_write == 1


async def test_a_machine_of_fewer_paths_fails_alone() -> None:
    async with plant(1) as served, AsyncExitStack() as stack:
        clients = [
            await stack.enter_async_context(FocasClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        results = await read_status_paths_all(clients)
        assert [len(r) for r in results if isinstance(r, tuple)] == [2, 1]
        # a client whose default path the machine lacks still reads paths 1..n
        lone = FocasClient(served[1].host, served[1].port, timeout=IO_TIMEOUT, path=2)
        async with lone:
            with pytest.raises(CncError) as info:
                await lone.read_status()
            assert info.value.ew == EW.PATH
            (result,) = await read_status_paths_all([lone])
            assert isinstance(result, tuple) and len(result) == 1


async def test_every_path_of_a_native_machine_in_one_frame() -> None:
    async with plant(2) as served, AsyncExitStack() as stack:
        clients = [
            await stack.enter_async_context(NativeClient(s.host, s.port, timeout=IO_TIMEOUT))
            for s in served
        ]
        if clients[0].path_count != 2:
            pytest.skip("the FOCAS/2 server announces one path: no path records")
        await read_status_paths_all(clients)
        frames = [c.frames_sent for c in clients]
        results = await read_status_paths_all(clients)
        assert [c.frames_sent - n for c, n in zip(clients, frames, strict=True)] == [1, 1, 1]
        assert [len(r) for r in results if isinstance(r, tuple)] == [2, 2, 1]
