"""Part programs over the native protocol, without FANUC's library.

The frames FANUC's library sent for the scenario of ``tests/test_fwlib_programs.py``, and the
answers it accepted, are kept in ``tests/data/fwlib_programs.json``; they are replayed here
through the adapter, byte for byte. Then the declarations (golden bytes taken from those
frames, hypothesis round trips), the adapter's refusals, and a real server for what only a
connection shows (a dropped download stores nothing).
"""

from __future__ import annotations

import asyncio
import json
import struct
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any, Final

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving, wait_until

from focas_net.adapters import NativeAdapter, ProgramTransfer
from focas_net.errors import EW
from focas_net.native import (
    PROGRAM_CHUNK,
    CommandSet,
    Device,
    ExecutingBlocks,
    ExecutingBlocksRequest,
    NativeCommand,
    NativePayloadError,
    ProgramDeleteRequest,
    ProgramDirEntries,
    ProgramDirEntry,
    ProgramDirRequest,
    ProgramMemory,
    ProgramMemoryRequest,
    ProgramSearchRequest,
    RequestBlock,
    TransferError,
    TransferFrame,
    TransferStart,
    calls,
    decode_frame,
    decode_response_body,
    encode_native_frame,
    encode_request_body,
    error_frame_type,
    parse_program_range,
)
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.sim.default import DEMO_PROGRAM
from focas_net.sim.nc import ManualClock

HERE = Path(__file__).parent
GOLDEN: Final = json.loads((HERE / "data" / "fwlib_programs.json").read_text())
MACHINE_16I: Final = HERE / "data" / "fwlib_16i_machine.toml"

#: The library's 0x06 block of ``cnc_rdprogdir2(type 2, top 0, num 10)`` (both sets) [V].
RDPROGDIR2_BLOCK: Final = bytes.fromhex(
    "001c000100010006 00000000 0000000a 00000002 00000000 00000000"
)
#: The body of the library's ``0x1501`` for ``cnc_upstart(1)``: 0, 1, ``O1-O1``, NULs [V].
UPSTART_1: Final = bytes.fromhex("000000014f312d4f31") + bytes(507)
#: The body of its ``0x1101`` for ``cnc_dwnstart`` [V].
DWNSTART: Final = bytes.fromhex("00000001") + bytes(512)

PROGRAM: Final = "O0321 (NATIVE)\nN10 G91 G1 X10. F600\nN20 M30\n"


def build_machine(set_name: str) -> Machine:
    """The machine of ``tests/test_fwlib_programs.py``'s scenario in ``set_name``."""
    if set_name == "30i":
        machine = default_machine(sim_clock=ManualClock())
    else:
        machine = load_machine(MACHINE_16I, sim_clock=ManualClock())
        machine.store_program(DEMO_PROGRAM)
    machine.set_panel(0, 1, 0)  # MDI, parameter writes enabled
    return machine


def frame(frame_type: int, body: bytes = b"") -> bytes:
    return encode_native_frame(frame_type, body)


def data_block(adapter: NativeAdapter, block: RequestBlock) -> tuple[int, bytes]:
    """The EW code and data of the one-block answer to ``block``."""
    answer = decode_frame(adapter.answer(encode_request_body([block])))
    (got,) = decode_response_body(answer.body)
    return got.ew, got.data


def refusal(frames: list[bytes] | None, request_type: int) -> int:
    """The EW code of a transfer refusal."""
    assert frames is not None and len(frames) == 1
    answer = decode_frame(frames[0])
    assert answer.type == error_frame_type(request_type)
    return TransferError.decode(answer.body).code


def download(adapter: NativeAdapter, state: ProgramTransfer, data: bytes) -> list[bytes] | None:
    started = adapter.transfer(TransferFrame.DOWNLOAD_START, DWNSTART, state)
    assert started == [encode_native_frame(0x1102, b"", adapter.version)]
    assert adapter.transfer(TransferFrame.DOWNLOAD_DATA, data, state) == []
    return adapter.transfer(TransferFrame.DOWNLOAD_END, b"", state)


# --------------------------------------------------------------------------------------------
# The library's frames, replayed


@pytest.mark.parametrize("recorded", GOLDEN["sets"], ids=lambda s: s["command_set"])
def test_the_librarys_frames_get_the_recorded_answers(recorded: dict[str, Any]) -> None:
    machine = build_machine(recorded["command_set"])
    machine.store_program("O0123 (SECOND ONE)\nG0 X1.\nM30\n")  # the scenario's first step
    adapter = NativeAdapter(machine)
    state = ProgramTransfer()
    assert recorded["exchanges"], "no exchange recorded"
    for exchange in recorded["exchanges"]:
        if machine.panel.mode != exchange["mode"]:
            machine.set_panel(exchange["mode"])
        body = bytes.fromhex(exchange["request"])
        got: list[str] | None
        if exchange["type"] == 0x2101:
            got = [adapter.answer(body).hex()]
        else:
            out = adapter.transfer(exchange["type"], body, state)
            got = None if out is None else [f.hex() for f in out]
        assert got == exchange["answers"], f"frame 0x{exchange['type']:04X} {body[:40].hex()}"


def test_the_recorded_calls_all_did_what_the_tests_expect() -> None:
    for recorded in GOLDEN["sets"]:
        returns = [(c["function"], c["return"]) for c in recorded["calls"]]
        assert ("cnc_upstart", EW.NUMBER) in returns
        assert ("cnc_dwnstart3/cnc_download3/cnc_dwnend3", EW.REJECT) in returns
        i = returns.index(("cnc_delete", 0))
        assert returns[i + 1] == ("cnc_delete", EW.NUMBER)
        assert ("cnc_dwnstart4/cnc_download4/cnc_dwnend4", 0) in returns


def test_the_call_table_sends_what_the_library_sent() -> None:
    for recorded in GOLDEN["sets"]:
        cs = CommandSet(recorded["command_set"])
        sent = [bytes.fromhex(e["request"]) for e in recorded["exchanges"] if e["type"] == 0x2101]
        expected = [
            *(calls.cnc_rdprogdir2(cs, kind, 0, 10) for kind in (0, 1, 2)),
            calls.cnc_rdprogdir3(cs, 2, 0, 10),
            calls.cnc_rdprogdir(cs, 1, 0),
            calls.cnc_rdprogdir(cs, 1, 124),  # the next page, from the last number + 1
            calls.cnc_rdproginfo(cs),
            calls.cnc_search(cs, 321),
            calls.cnc_search(cs, 321),
            calls.cnc_delete(cs, 321),
            calls.cnc_delete(cs, 321),
            calls.cnc_rdexecprog(cs, 256),
        ]
        frames = [f for call in expected for f in call.encode()]
        assert [decode_frame(f).body for f in frames] == sent


# --------------------------------------------------------------------------------------------
# Declarations: golden bytes


def test_directory_request_golden() -> None:
    request = ProgramDirRequest(0, 10, 2)
    assert encode_request_body([request.to_block()]) == b"\x00\x01" + RDPROGDIR2_BLOCK
    assert request.args() == (0, 10, 2, 0, 0)
    assert ProgramDirRequest.from_block(request.to_block()) == request


def test_directory_entry_golden() -> None:
    entry = ProgramDirEntry(1, 223, b"(DEMO CONTOUR)")
    raw = entry.encode()
    assert raw == bytes.fromhex("00000001000000df") + b"(DEMO CONTOUR)" + bytes(50)
    assert ProgramDirEntry.SIZE == 72
    assert ProgramDirEntries.decode(raw * 2).records == (entry, entry)


def test_program_memory_golden() -> None:
    raw = ProgramMemory(2, 398, 253, 511747).encode()
    assert raw == bytes.fromhex("00000002 0000018e 000000fd 0007cf03")
    assert ProgramMemory.decode(raw) == ProgramMemory(2, 398, 253, 511747)


def test_transfer_start_golden() -> None:
    start = TransferStart.decode(UPSTART_1)
    assert start == TransferStart(0, 1, b"O1-O1")
    assert start.encode() == UPSTART_1
    assert parse_program_range(start.name) == (1, 1)
    assert TransferStart.decode(DWNSTART) == TransferStart(0, 1, b"")


def test_transfer_error_golden() -> None:
    assert TransferError(0, 13, 0, 0).encode() == bytes.fromhex("0000000d00000000")
    assert error_frame_type(TransferFrame.UPLOAD_START) == 0x1503
    assert error_frame_type(TransferFrame.DOWNLOAD_END) == 0x1303


def test_program_requests_take_their_number() -> None:
    assert ProgramDeleteRequest(321).to_block().args == (321, 0, 0, 0, 0)
    assert ProgramDeleteRequest(321).to_block().command == NativeCommand.DELETE
    assert int(NativeCommand.DELETE) == 0x05
    assert (ProgramSearchRequest(9).to_block().command, int(NativeCommand.SEARCH)) == (3, 3)
    assert (ProgramMemoryRequest().to_block().command, int(NativeCommand.RDPROGINFO)) == (7, 7)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (b"O1-O1", (1, 1)),
        (b"O12", (12, 12)),
        (b"O0100-O0200", (100, 200)),
        (b"N:O0001", (1, 1)),  # cnc_upstart4
        (b"N://CNC_MEM/USER/PATH1/O0123", (123, 123)),
    ],
)
def test_program_ranges(text: bytes, expected: tuple[int, int]) -> None:
    assert parse_program_range(text) == expected


@pytest.mark.parametrize("text", [b"", b"1-2", b"O5-O2", b"OX", b"O1-", b"N:", b"N://X/"])
def test_a_bad_range_names_what_was_sent(text: bytes) -> None:
    with pytest.raises(NativePayloadError) as info:
        parse_program_range(text)
    assert info.value.ew == EW.DATA
    assert repr(text.decode())[1:-1] in str(info.value)


# --------------------------------------------------------------------------------------------
# Declarations: round trips

i32 = st.integers(-(2**31), 2**31 - 1)
comment = st.binary(max_size=64).map(lambda b: b.rstrip(b"\x00"))


@given(i32, i32, comment)
def test_directory_entry_round_trip(number: int, length: int, text: bytes) -> None:
    entry = ProgramDirEntry(number, length, text)
    assert ProgramDirEntry.decode(entry.encode()) == entry


@given(i32, i32, i32, i32)
def test_program_memory_round_trip(a: int, b: int, c: int, d: int) -> None:
    memory = ProgramMemory(a, b, c, d)
    assert ProgramMemory.decode(memory.encode()) == memory


@given(st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), st.binary(max_size=512))
def test_transfer_start_round_trip(data_type: int, unit: int, name: bytes) -> None:
    start = TransferStart(data_type, unit, name.rstrip(b"\x00"))
    assert TransferStart.decode(start.encode()) == start


@given(st.tuples(*[st.integers(-0x8000, 0x7FFF)] * 4))
def test_transfer_error_round_trip(words: tuple[int, int, int, int]) -> None:
    error = TransferError(*words)
    assert TransferError.decode(error.encode()) == error


@given(i32, i32, i32)
def test_directory_request_round_trip(top: int, count: int, kind: int) -> None:
    request = ProgramDirRequest(top, count, kind)
    assert ProgramDirRequest.from_block(request.to_block()) == request


@given(st.binary(max_size=600))
def test_transfer_start_decodes_any_bytes_or_refuses(raw: bytes) -> None:
    try:
        start = TransferStart.decode(raw)
    except NativePayloadError as exc:
        assert len(raw) != TransferStart.SIZE
        assert exc.ew == EW.LENGTH
    else:
        assert len(raw) == TransferStart.SIZE and start.encode().rstrip(b"\0") == raw.rstrip(b"\0")


# --------------------------------------------------------------------------------------------
# The adapter


@pytest.fixture
def adapter() -> NativeAdapter:
    return NativeAdapter(build_machine("30i"))


def test_the_directory_answers_what_fits(adapter: NativeAdapter) -> None:
    machine = adapter.machine
    for n in range(2, 60):
        machine.store_program(f"O{n} (P{n})\nM30\n")
    ew, data = data_block(adapter, ProgramDirRequest(0, 100, 2).to_block())
    entries = ProgramDirEntries.decode(data).records
    assert ew == 0 and len(entries) == (adapter.limit - 2 - 16) // ProgramDirEntry.SIZE
    assert [e.number for e in entries] == [e.number for e in machine.program_directory()][
        : len(entries)
    ]
    ew, data = data_block(adapter, ProgramDirRequest(59, 100, 2).to_block())
    assert [e.number for e in ProgramDirEntries.decode(data).records] == [59]
    assert data_block(adapter, ProgramDirRequest(60, 10, 2).to_block()) == (0, b"")
    assert data_block(adapter, ProgramDirRequest(0, 0, 2).to_block()) == (EW.LENGTH, b"")


def test_the_directory_comment_is_in_parentheses(adapter: NativeAdapter) -> None:
    adapter.machine.store_program("O0005\nM30\n")
    adapter.machine.store_program("O0006 (" + "X" * 80 + ")\nM30\n")
    _, data = data_block(adapter, ProgramDirRequest(5, 2, 2).to_block())
    unnamed, long = ProgramDirEntries.decode(data).records
    assert unnamed.comment == b""
    assert long.comment == b"(" + b"X" * 61 + b")"  # 63 bytes: a NUL always ends it


def test_search_and_delete_are_the_machines(adapter: NativeAdapter) -> None:
    assert data_block(adapter, ProgramSearchRequest(1).to_block()) == (EW.MODE, b"")
    adapter.machine.set_panel(1)
    assert data_block(adapter, ProgramSearchRequest(1).to_block()) == (0, b"")
    assert adapter.machine.motion.program_main == 1
    assert data_block(adapter, ProgramDeleteRequest(1).to_block()) == (0, b"")
    assert adapter.machine.program_directory() == []
    assert data_block(adapter, ProgramDeleteRequest(1).to_block()) == (EW.NUMBER, b"")


def test_a_read_only_machine_refuses_every_change() -> None:
    machine = default_machine(read_only=True)
    adapter = NativeAdapter(machine)
    state = ProgramTransfer()
    before = machine.program_directory()
    assert data_block(adapter, ProgramDeleteRequest(1).to_block())[0] == EW.PROT
    assert data_block(adapter, ProgramSearchRequest(1).to_block())[0] == EW.PROT
    out = adapter.transfer(TransferFrame.DOWNLOAD_START, DWNSTART, state)
    assert refusal(out, TransferFrame.DOWNLOAD_START) == EW.PROT
    assert not state.downloading
    assert machine.program_directory() == before
    # an upload reads only
    out = adapter.transfer(TransferFrame.UPLOAD_START, UPSTART_1, state)
    assert out is not None and decode_frame(out[0]).type == TransferFrame.UPLOAD_START_ANSWER


def test_an_upload_is_the_text_in_chunks(adapter: NativeAdapter) -> None:
    long = "O0400\n" + "".join(f"N{n} G0 X{n}.\n" for n in range(10, 2000, 10)) + "M30\n"
    adapter.machine.store_program(long)
    body = TransferStart(0, 1, b"O400-O400").encode()
    out = adapter.transfer(TransferFrame.UPLOAD_START, body, ProgramTransfer())
    assert out is not None
    frames = [decode_frame(f) for f in out]
    assert frames[0].type == TransferFrame.UPLOAD_START_ANSWER
    assert frames[-1].type == TransferFrame.UPLOAD_END
    data = [f for f in frames[1:-1]]
    assert all(f.type == TransferFrame.UPLOAD_DATA for f in data)
    assert all(len(f.body) <= PROGRAM_CHUNK for f in data) and len(data) > 1
    text = b"".join(f.body for f in data).decode()
    assert text == "%\n" + adapter.machine.program_text(400) + "%"


def test_an_upload_of_a_range(adapter: NativeAdapter) -> None:
    adapter.machine.store_program(PROGRAM)
    body = TransferStart(0, 1, b"O1-O500").encode()
    out = adapter.transfer(TransferFrame.UPLOAD_START, body, ProgramTransfer())
    assert out is not None
    text = b"".join(decode_frame(f).body for f in out[1:-1]).decode()
    m = adapter.machine
    assert text == "%\n" + m.program_text(1) + m.program_text(321) + "%"
    none = TransferStart(0, 1, b"O2-O300").encode()
    out = adapter.transfer(TransferFrame.UPLOAD_START, none, ProgramTransfer())
    assert refusal(out, TransferFrame.UPLOAD_START) == EW.NUMBER
    bad = TransferStart(0, 1, b"PROGRAM").encode()
    out = adapter.transfer(TransferFrame.UPLOAD_START, bad, ProgramTransfer())
    assert refusal(out, TransferFrame.UPLOAD_START) == EW.DATA


def test_a_download_is_stored_at_its_end(adapter: NativeAdapter) -> None:
    state = ProgramTransfer()
    assert adapter.transfer(TransferFrame.DOWNLOAD_START, DWNSTART, state) is not None
    for piece in (b"\n%\nO0321 (NATIVE)\nN10 G91 G1 X10. ", b"F600\nN20 M30\n%\n"):
        assert adapter.transfer(TransferFrame.DOWNLOAD_DATA, piece, state) == []
        assert 321 not in [e.number for e in adapter.machine.program_directory()]
    out = adapter.transfer(TransferFrame.DOWNLOAD_END, b"", state)
    assert out == [encode_native_frame(0x1302, b"", adapter.version)]
    assert adapter.machine.program_text(321) == PROGRAM
    assert not state.downloading and not state.received


@pytest.mark.parametrize(
    ("data", "ew"),
    [
        (b"\nO0001 (AGAIN)\nM30\n%", EW.REJECT),  # the number is stored
        (b"\nG0 X1.\nM30\n%", EW.DATA),  # no O number
        (b"\nO0321 (\xe9)\nM30\n%", EW.DATA),  # not ASCII
        (b"%\n%", EW.DATA),  # nothing
        (b"\nO99999 (BIG)\nM30\n%", EW.NUMBER),  # outside O1..O9999
        (b"\nO0321 (\x07)\nM30\n%", EW.DATA),  # a control character
        (b"\nO0321\nM30\nO0322\nM30\n%", EW.DATA),  # two programs
        (b"%\nO0321\nM30\n%\nO0322\nM30\n%", EW.DATA),  # a program after the closing %
    ],
)
def test_download_refusals(adapter: NativeAdapter, data: bytes, ew: int) -> None:
    before = adapter.machine.program_directory()
    out = download(adapter, ProgramTransfer(), data)
    assert refusal(out, TransferFrame.DOWNLOAD_END) == ew
    assert adapter.machine.program_directory() == before


def test_a_download_keeps_a_percent_sign_inside_a_block(adapter: NativeAdapter) -> None:
    """Only a line that starts with ``%`` is a tape mark; the NUL a C string ends with is no
    part of the text."""
    out = download(adapter, ProgramTransfer(), b"\nO0321 (50% FEED)\nM30\n%\x00")
    assert out == [encode_native_frame(0x1302, b"", adapter.version)]
    assert adapter.machine.program_text(321) == "O0321 (50% FEED)\nM30\n"


def test_a_download_end_without_a_start_is_ew_func(adapter: NativeAdapter) -> None:
    state = ProgramTransfer()
    assert adapter.transfer(TransferFrame.DOWNLOAD_DATA, PROGRAM.encode(), state) == []
    out = adapter.transfer(TransferFrame.DOWNLOAD_END, b"", state)
    assert refusal(out, TransferFrame.DOWNLOAD_END) == EW.FUNC
    assert 321 not in [e.number for e in adapter.machine.program_directory()]


def test_a_download_too_large_is_ew_ovrflow(adapter: NativeAdapter) -> None:
    state = ProgramTransfer()
    adapter.transfer(TransferFrame.DOWNLOAD_START, DWNSTART, state)
    piece = b"N10 G0 X1.\n" * 100
    for _ in range((1 << 20) // len(piece) + 2):
        adapter.transfer(TransferFrame.DOWNLOAD_DATA, piece, state)
    assert state.overflow and len(state.received) < 1 << 20
    out = adapter.transfer(TransferFrame.DOWNLOAD_END, b"", state)
    assert refusal(out, TransferFrame.DOWNLOAD_END) == EW.OVRFLOW


def test_answer_types_and_others_are_not_transfers(adapter: NativeAdapter) -> None:
    state = ProgramTransfer()
    for frame_type in (0x1502, 0x1102, 0x1302, 0x1604, 0x1701, 0x1901, 0x2401):
        assert adapter.transfer(frame_type, b"", state) is None
    # the library's own end and abort of an upload answer nothing
    assert adapter.transfer(TransferFrame.UPLOAD_END_ANSWER, b"", state) == []
    assert adapter.transfer(TransferFrame.UPLOAD_ABORT, bytes(8), state) == []
    bad = adapter.transfer(TransferFrame.DOWNLOAD_START, b"\x00\x01", state)
    assert refusal(bad, TransferFrame.DOWNLOAD_START) == EW.LENGTH


def test_memory_follows_the_store(adapter: NativeAdapter) -> None:
    machine = adapter.machine
    before = ProgramMemory.decode(data_block(adapter, ProgramMemoryRequest().to_block())[1])
    machine.store_program(PROGRAM)
    after = ProgramMemory.decode(data_block(adapter, ProgramMemoryRequest().to_block())[1])
    size = machine.program_directory()[-1].size
    assert after.registered == before.registered + 1
    assert after.unregistered == before.unregistered - 1
    assert (after.used, after.unused) == (before.used + size, before.unused - size)
    assert after.used + after.unused == machine.programs.capacity


# --------------------------------------------------------------------------------------------
# A real server: per-connection state


@pytest.fixture
async def served_machine() -> AsyncIterator[Any]:
    async with serving(build_machine("30i")) as served:
        yield served


async def _open_native(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    async with asyncio.timeout(IO_TIMEOUT):
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(frame(0x0101, b"\x00\x01"))
        head = await reader.readexactly(10)
        await reader.readexactly(struct.unpack(">H", head[8:10])[0])
    return reader, writer


async def _read_frame(reader: asyncio.StreamReader) -> tuple[int, bytes]:
    async with asyncio.timeout(IO_TIMEOUT):
        head = await reader.readexactly(10)
        body = await reader.readexactly(struct.unpack(">H", head[8:10])[0])
    return struct.unpack(">H", head[6:8])[0], body


async def test_a_dropped_download_stores_nothing(served_machine: Any) -> None:
    machine = served_machine.machine
    before = machine.program_directory()
    reader, writer = await _open_native(served_machine.port)
    writer.write(frame(TransferFrame.DOWNLOAD_START, DWNSTART))
    assert (await _read_frame(reader))[0] == TransferFrame.DOWNLOAD_START_ANSWER
    writer.write(frame(TransferFrame.DOWNLOAD_DATA, b"\n" + PROGRAM.encode() + b"%"))
    await writer.drain()
    writer.close()
    await writer.wait_closed()
    listener = served_machine.server.listeners[0]
    await wait_until(lambda: not listener.native_connections)
    assert machine.program_directory() == before
    # another connection has no download under way
    reader, writer = await _open_native(served_machine.port)
    writer.write(frame(TransferFrame.DOWNLOAD_END))
    kind, body = await _read_frame(reader)
    assert kind == 0x1303 and TransferError.decode(body).code == EW.FUNC
    writer.close()
    await writer.wait_closed()
    assert machine.program_directory() == before


async def test_an_upload_over_a_connection(served_machine: Any) -> None:
    reader, writer = await _open_native(served_machine.port)
    writer.write(frame(TransferFrame.UPLOAD_START, UPSTART_1))
    kinds, text = [], b""
    for _ in range(20):
        kind, body = await _read_frame(reader)
        kinds.append(kind)
        if kind == TransferFrame.UPLOAD_DATA:
            text += body
        if kind == TransferFrame.UPLOAD_END:
            break
    writer.write(frame(TransferFrame.UPLOAD_END_ANSWER))
    writer.write(frame(0x2101, encode_request_body([RequestBlock(Device.CNC, 1, 0x19)])))
    kind, _ = await _read_frame(reader)  # the connection still answers data requests
    assert kind == 0x2102
    writer.close()
    await writer.wait_closed()
    assert kinds[0] == TransferFrame.UPLOAD_START_ANSWER
    assert text.decode() == "%\n" + served_machine.machine.program_text(1) + "%"


def test_the_blocks_being_executed_follow_the_sequence_number() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    adapter = NativeAdapter(machine)
    text = machine.program_text(1)
    request = ExecutingBlocksRequest(4096).to_block()
    ew, data = data_block(adapter, request)
    shown = ExecutingBlocks.decode(data)
    body = text.split("\n", 1)[1]  # the blocks after the O line
    assert ew == 0 and shown == ExecutingBlocks(body.count("\n"), body.encode())
    machine.set_panel(1)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(2.0)
    sequence = machine.motion.sequence
    assert sequence > 0
    _, data = data_block(adapter, ExecutingBlocksRequest(30).to_block())
    shown = ExecutingBlocks.decode(data)
    rest = text[text.index(f"\nN{sequence} ") + 1 :]
    assert rest.startswith(shown.text.decode()) and shown.text.startswith(f"N{sequence} ".encode())
    assert len(shown.text) <= 30 and shown.blocks == shown.text.count(b"\n")
    assert data_block(adapter, ExecutingBlocksRequest(0).to_block()) == (EW.LENGTH, b"")


def test_executing_blocks_golden_and_round_trip() -> None:
    raw = ExecutingBlocks(2, b"N30 T1 M6\nN40 S3000 M3\n").encode()
    assert raw == bytes.fromhex("00000002") + b"N30 T1 M6\nN40 S3000 M3\n"
    assert ExecutingBlocks.decode(raw) == ExecutingBlocks(2, b"N30 T1 M6\nN40 S3000 M3\n")
    with pytest.raises(NativePayloadError):
        ExecutingBlocks.decode(b"\x00\x01")


@given(i32, st.binary(max_size=300))
def test_executing_blocks_round_trip(blocks: int, text: bytes) -> None:
    value = ExecutingBlocks(blocks, text)
    assert ExecutingBlocks.decode(value.encode()) == value
