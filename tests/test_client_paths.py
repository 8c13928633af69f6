"""Path selection through the clients (issue 43): a 2-path machine served on 127.0.0.1, read
through the packed client (cnc_setpath/cnc_getpath, ``docs/protocol.md`` section 8, "Paths")
and through the native client (the path word of every block)."""

from __future__ import annotations

import asyncio
import struct
from collections.abc import AsyncIterator

import pytest
from support import IO_TIMEOUT, Served, serving, two_path_lathe

from focas_net.client import FocasClient, NativeClient, Paths
from focas_net.errors import EW, CncError
from focas_net.protocol import (
    COMMANDS,
    Command,
    InjectFault,
    PathNumber,
    PathSelection,
    StatusInfo,
)


@pytest.fixture
async def lathe() -> AsyncIterator[Served]:
    async with serving(two_path_lathe()) as served:
        yield served


def _getpath(answer: bytes) -> PathSelection:
    value = COMMANDS[Command.GETPATH].response.decode(answer)
    assert isinstance(value, PathSelection)
    return value


def _ew(answer: bytes) -> int:
    value: int = struct.unpack_from("<h", answer)[0]
    return value


# -- the server: a connection's selection -----------------------------------------------------
async def test_a_connection_starts_on_path_1_and_setpath_selects(lathe: Served) -> None:
    wire = await lathe.connect()
    async with wire:
        assert _getpath(await wire.call(Command.GETPATH)) == PathSelection(1, 2)
        one = await wire.call(Command.RDPRGNUM)
        assert await wire.call(Command.SETPATH, PathNumber(2).encode()) == b"\x00\x00"
        assert _getpath(await wire.call(Command.GETPATH)) == PathSelection(2, 2)
        two = await wire.call(Command.RDPRGNUM)
        assert (one, two) == (
            bytes.fromhex("0000 01000000 01000000"),
            bytes.fromhex("0000 02000000 02000000"),
        )
        # path-independent commands ignore the selection
        assert _ew(await wire.call(Command.SYSINFO)) == 0


async def test_a_refused_setpath_leaves_no_path_selected(lathe: Served) -> None:
    wire = await lathe.connect()
    async with wire:
        await wire.call(Command.SETPATH, PathNumber(2).encode())
        # pipelined: a refused selection, then reads; none reads path 2 (or 1)
        wire.send(Command.SETPATH, PathNumber(3).encode())
        wire.send(Command.RDPRGNUM)
        wire.send(Command.RDALMMSG, bytes.fromhex("ffff 2000"))
        wire.send(Command.SYSINFO)
        wire.send(Command.GETPATH)
        setpath, prgnum, alarms, sysinfo, getpath = await wire.recv_many(5)
        assert setpath.payload == bytes.fromhex("0b00")  # EW_PATH
        assert prgnum.payload == bytes.fromhex("0b00")
        assert alarms.payload == bytes.fromhex("ffff 0b00")  # a counted list's error
        assert _ew(sysinfo.payload) == 0
        assert _getpath(getpath.payload) == PathSelection(0, 2)
        # a malformed setpath leaves none selected either
        await wire.call(Command.SETPATH, PathNumber(1).encode())
        assert _ew(await wire.call(Command.SETPATH, b"\x01")) == EW.LENGTH
        assert _ew(await wire.call(Command.RDCNCSTAT)) == EW.PATH
        await wire.call(Command.SETPATH, PathNumber(1).encode())
        assert _ew(await wire.call(Command.RDCNCSTAT)) == 0


async def test_path_commands_are_never_faulted(lathe: Served) -> None:
    wire = await lathe.connect()
    async with wire:
        inject = COMMANDS[Command.SIM_INJECT_FAULT].request
        await wire.call(Command.SIM_INJECT_FAULT, inject.encode(InjectFault(2, 0, 1, -1)))
        assert await wire.call(Command.SETPATH, PathNumber(2).encode()) == b"\x00\x00"
        assert _getpath(await wire.call(Command.GETPATH)) == PathSelection(2, 2)
        assert _ew(await wire.call(Command.RDCNCSTAT)) == -1  # the fault took this answer


# -- the packed client ---------------------------------------------------------------------------
async def test_packed_client_reads_each_path(lathe: Served) -> None:
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as cnc:
        assert await cnc.read_paths() == Paths(1, 2)
        assert (await cnc.read_program_numbers()).running == 1
        assert (await cnc.read_program_numbers(path=2)).running == 2
        assert await cnc.read_paths() == Paths(2, 2)  # the last call selected path 2
        pos = await cnc.read_positions(path=2)
        assert pos.increments == {"X2": 5000, "Z2": 5001, "C2": 5002}
        assert (await cnc.read_positions()).increments == {"X1": 1000, "Z1": 1001}
        assert await cnc.read_feed(path=2) == 700
        assert await cnc.read_feed() == 1500


async def test_packed_client_default_path(lathe: Served) -> None:
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT, path=2) as cnc:
        assert cnc.path == 2
        assert await cnc.read_feed() == 700
        assert await cnc.read_feed(path=1) == 1500
        cnc.path = 1
        assert await cnc.read_feed() == 1500


async def test_packed_pipelined_mixed_paths_each_read_their_own(lathe: Served) -> None:
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as cnc:
        paths = [1, 2, 2, 1, 2, 1, 1, 2] * 8
        results = await asyncio.gather(*(cnc.read_feed(path=p) for p in paths))
        assert results == [1500 if p == 1 else 700 for p in paths]
        conn = cnc.connection
        assert conn is not None and conn.in_flight == 0 and conn.slots_taken == 0


async def test_packed_pipelined_with_slots_full(lathe: Served) -> None:
    """More calls than request slots: those waiting for a slot still read their own path."""
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT, max_in_flight=2) as cnc:
        paths = [1, 2, 1, 1, 2, 2, 1, 2] * 4
        results = await asyncio.gather(*(cnc.read_feed(path=p) for p in paths))
        assert results == [1500 if p == 1 else 700 for p in paths]


async def test_packed_path_past_the_last_answers_ew_path(lathe: Served) -> None:
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as cnc:
        results = await asyncio.gather(
            cnc.read_feed(path=2),
            cnc.read_feed(path=3),
            cnc.read_status(path=3),
            cnc.read_sysinfo(),
            cnc.read_feed(path=1),
            return_exceptions=True,
        )
        assert results[0] == 700
        for refused in results[1:3]:
            assert isinstance(refused, CncError) and refused.ew == EW.PATH
        assert not isinstance(results[3], BaseException)
        assert results[4] == 1500


async def test_path_arguments_are_checked_before_sending(lathe: Served) -> None:
    async with FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as cnc:
        with pytest.raises(ValueError, match=r"path 11 is outside 1\.\.10"):
            await cnc.read_status(path=11)
        with pytest.raises(TypeError, match="path must be an integer, got '2'"):
            await cnc.read_feed(path="2")  # type: ignore[arg-type]
        with pytest.raises(ValueError, match=r"path 0 is outside 1\.\.10"):
            cnc.path = 0
        assert cnc.connection is not None and cnc.connection.path == 1
    with pytest.raises(ValueError, match="path 0 is outside"):
        FocasClient("127.0.0.1", 1, path=0)
    with pytest.raises(TypeError, match="path must be an integer"):
        NativeClient("127.0.0.1", 1, path=True)


async def test_packed_reconnect_restores_the_selection(lathe: Served) -> None:
    async with FocasClient(
        lathe.host, lathe.port, timeout=IO_TIMEOUT, reconnect=True, path=2
    ) as cnc:
        assert await cnc.read_feed() == 700
        first = cnc.connection
        assert first is not None
        first.abort()
        await asyncio.wait_for(first.wait_closed(), IO_TIMEOUT)
        assert await cnc.read_feed(timeout=IO_TIMEOUT) == 700
        assert cnc.connection is not first


def _needs_native_paths(paths: Paths) -> None:
    """Skip unless the FOCAS/2 server's open answer announces both paths (its path records
    and per-block path dispatch are the native server's, built apart)."""
    if paths.count != 2:
        pytest.skip(f"the FOCAS/2 server announces {paths.count} path(s) of 2: no path records")


# -- both protocols read the same per-path values ---------------------------------------------
async def test_both_protocols_read_the_same_per_path_values(lathe: Served) -> None:
    async with (
        FocasClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as packed,
        NativeClient(lathe.host, lathe.port, timeout=IO_TIMEOUT) as native,
    ):
        _needs_native_paths(await native.read_paths())
        for path in (1, 2):
            p_status: StatusInfo = await packed.read_status(path=path)
            n_status = await native.read_status(path=path)
            assert p_status.run == n_status.run and p_status.aut == n_status.aut
            assert await packed.read_program_numbers(path=path) == (
                await native.read_program_numbers(path=path)
            )
            assert await packed.read_feed(path=path) == await native.read_feed(path=path)
            p_pos = await packed.read_positions("machine", path=path)
            n_pos = await native.read_positions("machine", path=path)
            # the same values under the same names (FOCAS/2's name and suffix, "X" and "1",
            # read as the screen shows them: "X1")
            assert p_pos.increments == n_pos.increments
            assert list(p_pos.increments)[:2] == [f"X{path}", f"Z{path}"]
        with pytest.raises(CncError) as info:
            await native.read_feed(path=3)
        assert info.value.ew == EW.PATH


async def test_native_read_paths_sends_nothing(lathe: Served) -> None:
    async with NativeClient(lathe.host, lathe.port, timeout=IO_TIMEOUT, path=2) as native:
        paths = await native.read_paths()
        _needs_native_paths(paths)
        assert paths == Paths(2, 2)


async def test_the_selection_answers_read_only_and_without_control() -> None:
    """0x0040 and 0x0140 are connection-level: a read-only server without control answers
    them, and a per-path control command with none selected answers EW_FUNC first."""
    machine = two_path_lathe()
    machine.read_only = True
    machine.control_enabled = False
    async with serving(machine) as served:
        wire = await served.connect()
        async with wire:
            assert await wire.call(Command.SETPATH, PathNumber(2).encode()) == b"\x00\x00"
            assert _getpath(await wire.call(Command.GETPATH)) == PathSelection(2, 2)
            assert _ew(await wire.call(Command.GETPATH, b"\x00")) == EW.LENGTH
            assert _ew(await wire.call(Command.SETPATH, PathNumber(0).encode())) == EW.PATH
            assert _ew(await wire.call(Command.SIM_CYCLE, b"\x00\x00")) == EW.FUNC
            assert _ew(await wire.call(Command.RDPRGNUM)) == EW.PATH
            assert _ew(await wire.call(Command.SYSINFO)) == 0  # path-independent
