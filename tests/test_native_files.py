"""The program folders of a 30i-class control: the machine's tree, the codec (golden bytes of
FANUC's library, round trips), the adapter's answers and the native client's calls.

The golden request bytes are those libfwlib32 1.0.5 sent (``tests/test_fwlib_files.py``
checks the same frames against the library itself when it is present).
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving, two_path_lathe

from focas_net.adapters import NativeAdapter
from focas_net.client import NativeClient
from focas_net.errors import EW, CncError
from focas_net.native import (
    CommandSet,
    CurrentFolderRequest,
    CurrentFolderWriteRequest,
    DriveInfo,
    DriveInfoRequest,
    DriveListRequest,
    DriveName,
    DriveNames,
    FileDeleteRequest,
    FileInfo,
    FileInfoRequest,
    FolderCount,
    FolderCountRequest,
    FolderListRequest,
    FolderRecord,
    FolderRecords,
    FolderText,
    LibraryCall,
    MainFileRequest,
    MainSelectRequest,
    NativePayloadError,
    RequestBlock,
    SubfolderRecord,
    SubfolderRecords,
    SubfolderRequest,
    cnc_pdf_del,
    cnc_rdpdf_alldir,
    cnc_rdpdf_drive,
    cnc_rdpdf_inf,
    cnc_rdpdf_prginf,
    decode_frame,
    decode_response_body,
    encode_request_body,
    size_in,
)
from focas_net.sim import Machine, MachineError, default_machine, load_machine
from focas_net.sim.default import DEMO_PROGRAM
from focas_net.sim.nc import ManualClock

PATH1 = "//CNC_MEM/USER/PATH1/"
CS = CommandSet.FS30I
MACHINE_16I = "tests/data/fwlib_16i_machine.toml"


def body(call: LibraryCall) -> bytes:
    """The body of the call's one request frame (after the 10-byte head)."""
    return call.encode()[0][10:]


def data_block(adapter: NativeAdapter, block: RequestBlock) -> tuple[int, bytes]:
    """The EW code and data of the one-block answer to ``block``."""
    answer = decode_frame(adapter.answer(encode_request_body([block])))
    (got,) = decode_response_body(answer.body)
    return got.ew, got.data


# --------------------------------------------------------------------------------------------
# Golden bytes: what FANUC's library sends


def test_drive_requests_golden() -> None:
    assert body(cnc_rdpdf_drive(CS)) == bytes.fromhex(
        "0001001c0001000100ae0000000000000000000000000000000000000000"
    )
    assert body(cnc_rdpdf_inf(CS, "//CNC_MEM/", 0)) == bytes.fromhex(
        "000100280001000100af000000000000000000000000000000000000000c2f2f434e435f4d454d2f0000"
    )


def test_listing_and_file_requests_golden() -> None:
    alldir = body(cnc_rdpdf_alldir(CS, PATH1, 0, 20, 1, 1))
    assert alldir[:40] == bytes.fromhex(
        "0001011c0001000100b300000000000000140000000100000001000001002f2f434e435f4d454d2f"
    )
    assert alldir[30:] == PATH1.encode().ljust(256, b"\0")
    prginf = body(cnc_rdpdf_prginf(CS, PATH1 + "O0001", 0, 0))
    assert prginf[:30] == bytes.fromhex(
        "000101100001000102b100000000000000010000000000000000000000f4"
    )
    assert prginf[30:] == (PATH1 + "O0001").encode().ljust(244, b"\0")
    delete = body(cnc_pdf_del(CS, PATH1 + "O0321"))
    assert delete[:30] == bytes.fromhex(
        "0001011c0001000100b60000000000000000000000000000000000000100"
    )
    assert len(delete) == 30 + 256


def test_file_info_sends_brief_for_type_0() -> None:
    """The library sends 1 in the second argument for IDBPDFPRG's type 0, 0 for type 1."""
    assert cnc_rdpdf_prginf(CS, "O1", 2, 0).frames[0][0].to_block().args[:2] == (2, 1)
    assert cnc_rdpdf_prginf(CS, "O1", 2, 1).frames[0][0].to_block().args[:2] == (2, 0)
    assert FileInfoRequest("O1", 1, 1).detail == 0


def test_answer_records_golden() -> None:
    assert DriveName(b"CNC_MEM").encode() == b"CNC_MEM\0\0\0\0\0"
    assert DriveInfo(1, 2, 3, 4).encode() == bytes.fromhex("00000001000000020000000300000004")
    assert SubfolderRecord(1, b"USER").encode() == b"\0\0\0\1USER" + b"\0" * 32
    record = FolderRecord(1, 2026, 12, 7, 4, 5, 6, 0, 0, 223, 0, b"O0001", b"DEMO", b"")
    raw = record.encode()
    assert len(raw) == 128
    assert raw[:28] == bytes.fromhex("000107ea000c0007000400050006000000000000000000df00000000")
    assert raw[28:33] == b"O0001" and raw[64:68] == b"DEMO"
    info = FileInfo(2026, 12, 7, 4, 5, 6, 223, 0, b"DEMO", b"").encode()
    assert len(info) == 84
    assert info[:20] == bytes.fromhex("07ea000c0007000400050006000000df00000000")
    assert FolderCount(2, 1).encode() == bytes.fromhex("0000000200000001")
    assert FolderText.of(PATH1).encode() == PATH1.encode() + b"\0"


def test_names_are_checked_when_built() -> None:
    with pytest.raises(ValueError):
        cnc_pdf_del(CS, "X" * 256)
    with pytest.raises(ValueError):
        cnc_rdpdf_inf(CS, "//CNC_MEM/USER/", 0)  # 12 bytes: no room for the NUL
    with pytest.raises(ValueError):
        cnc_pdf_del(CS, "O0001\n")


def test_a_received_name_is_read_to_its_nul() -> None:
    block = RequestBlock(1, 1, 0xB6, (0, 0, 0, 0, 8), b"O0001\0\xff\xff")
    assert FileDeleteRequest.from_block(block).name == "O0001"
    with pytest.raises(NativePayloadError) as raised:
        FileDeleteRequest.from_block(RequestBlock(1, 1, 0xB6, (0, 0, 0, 0, 300), b"A" * 300))
    assert raised.value.ew == EW.LENGTH


def test_sizes_in_units() -> None:
    assert [size_in(1025, k) for k in range(4)] == [5, 1025, 2, 1]
    with pytest.raises(NativePayloadError) as raised:
        size_in(1, 4)
    assert raised.value.ew == EW.DATA


# --------------------------------------------------------------------------------------------
# Round trips

_NAMES = st.text(st.characters(min_codepoint=0x21, max_codepoint=0x7E), min_size=1, max_size=200)
_I16 = st.integers(-0x8000, 0x7FFF)
_I32 = st.integers(-0x8000_0000, 0x7FFF_FFFF)


@given(_NAMES, _I16, _I16, _I16, _I16)
def test_named_requests_round_trip(name: str, a: int, b: int, c: int, d: int) -> None:
    for request in (
        FolderListRequest(name, a, b, c, d),
        SubfolderRequest(name, a, b),
        FolderCountRequest(name),
        FileDeleteRequest(name),
        MainSelectRequest(name),
        CurrentFolderWriteRequest(name, a),
        FileInfoRequest(name, a, b),
        DriveInfoRequest(name[:11], a),
    ):
        assert type(request).from_block(request.to_block()) == request


@given(st.lists(st.tuples(st.integers(0, 1), _I16, _I32, st.binary(max_size=36)), max_size=5))
def test_listing_answers_round_trip(rows: list[tuple[int, int, int, bytes]]) -> None:
    records = tuple(
        FolderRecord(k, y, 1, 2, 3, 4, 5, 0, 0, s, 0, n.rstrip(b"\0"), b"c", b"")
        for k, y, s, n in rows
    )
    assert FolderRecords.decode(FolderRecords(records).encode()) == FolderRecords(records)
    subs = tuple(SubfolderRecord(k, n.rstrip(b"\0")) for k, _, _, n in rows)
    assert SubfolderRecords.decode(SubfolderRecords(subs).encode()) == SubfolderRecords(subs)


_TEXT = st.binary(max_size=12).map(lambda b: b.replace(b"\0", b"A"))


@given(st.tuples(*[_I16] * 6), _I32, st.integers(0, 0xFFFF_FFFF), _TEXT, _TEXT)
def test_file_info_round_trip(
    date: tuple[int, int, int, int, int, int], size: int, attr: int, comment: bytes, o_time: bytes
) -> None:
    y, mo, d, h, mi, sec = date
    info = FileInfo(y, mo, d, h, mi, sec, size, attr, comment, o_time)
    assert len(info.encode()) == 84
    assert FileInfo.decode(info.encode()) == info


@given(_I16)
def test_unnamed_requests_read_back(kind: int) -> None:
    for request in (CurrentFolderRequest(kind), DriveListRequest(), MainFileRequest()):
        assert type(request).from_block(request.to_block()) == request


@given(_I32, _I32, _I32, _I32)
def test_fixed_answers_round_trip(a: int, b: int, c: int, d: int) -> None:
    assert DriveInfo.decode(DriveInfo(a, b, c, d).encode()) == DriveInfo(a, b, c, d)
    assert FolderCount.decode(FolderCount(a, b).encode()) == FolderCount(a, b)


@given(st.binary(max_size=300))
def test_text_answers_decode_any_bytes(raw: bytes) -> None:
    answer = FolderText.decode(raw)
    assert answer.encode() == raw
    assert FolderText.decode(FolderText.of(answer.text).encode()).text == answer.text


# --------------------------------------------------------------------------------------------
# The machine and the adapter


def build(clock: ManualClock | None = None) -> Machine:
    machine = default_machine(sim_clock=clock or ManualClock())
    machine.clock = lambda: datetime(2026, 3, 4, 5, 6, 7, tzinfo=UTC)
    return machine


def listing(
    adapter: NativeAdapter, folder: str, first: int = 0, count: int = 20, **kw: int
) -> tuple[int, tuple[FolderRecord, ...]]:
    request = FolderListRequest(folder, first, count, kw.get("detail", 1), kw.get("size_kind", 1))
    ew, data = data_block(adapter, request.to_block())
    return ew, FolderRecords.decode(data).records


def test_a_stored_program_is_a_file_with_its_date() -> None:
    adapter = NativeAdapter(build())
    adapter.machine.store_program("O0042 (FORTY TWO)\nG0 X1.\nM30\n")
    ew, records = listing(adapter, PATH1)
    assert ew == 0
    assert [(r.name, r.data_kind, r.comment) for r in records] == [
        (b"O0001", 1, b"DEMO CONTOUR"),
        (b"O0042", 1, b"FORTY TWO"),
    ]
    sizes = {e.number: e.size for e in adapter.machine.program_directory()}
    assert [r.size for r in records] == [sizes[1], sizes[42]]
    assert (records[1].year, records[1].month, records[1].day, records[1].second) == (
        2026,
        3,
        4,
        7,
    )
    ew, data = data_block(adapter, FileInfoRequest(PATH1 + "O0042", 2, 0).to_block())
    info = FileInfo.decode(data)
    assert (ew, info.size, info.comment, info.year) == (0, 1, b"FORTY TWO", 2026)


def test_listing_windows_and_refusals() -> None:
    adapter = NativeAdapter(build())
    for n in range(2, 40):
        adapter.machine.store_program(f"O{n} (P{n})\nM30\n")
    ew, records = listing(adapter, PATH1, count=20)
    assert ew == 0 and len(records) == 20
    ew, records = listing(adapter, PATH1, first=30, count=20)
    assert [r.name for r in records] == [f"O{n:04d}".encode() for n in range(31, 40)]
    assert listing(adapter, PATH1, first=39)[0] == EW.NUMBER
    assert listing(adapter, PATH1, count=0)[0] == EW.LENGTH
    assert listing(adapter, PATH1, detail=2)[0] == EW.DATA
    assert listing(adapter, PATH1, size_kind=4)[0] == EW.DATA
    assert listing(adapter, "//CNC_MEM/USER/PATH9/")[0] == EW.DATA
    assert listing(adapter, "//CNC_MEM/SYSTEM/")[0] == EW.NUMBER  # empty
    # at version 2 (1450 bytes) fewer fit one answer than asked
    small = NativeAdapter(adapter.machine, version=2)
    assert len(listing(small, PATH1, count=20)[1]) == (small.limit - 2 - 16) // 128


def test_drives_folders_and_counts() -> None:
    adapter = NativeAdapter(build())
    ew, data = data_block(adapter, DriveListRequest().to_block())
    assert (ew, DriveNames.decode(data).records) == (0, (DriveName(b"CNC_MEM"),))
    ew, data = data_block(adapter, SubfolderRequest("//CNC_MEM/USER/", 0, 5).to_block())
    assert [(r.name, r.has_folders) for r in SubfolderRecords.decode(data).records] == [
        (b"PATH1", 0),
        (b"LIBRARY", 0),
    ]
    ew, data = data_block(adapter, FolderCountRequest(PATH1).to_block())
    assert FolderCount.decode(data) == FolderCount(0, 1)
    ew, data = data_block(adapter, DriveInfoRequest("//CNC_MEM/", 0).to_block())
    assert ew == 0 and DriveInfo.decode(data).used_entries == 7


def test_current_folder_and_relative_names() -> None:
    adapter = NativeAdapter(build())
    read = CurrentFolderRequest(1).to_block()
    assert data_block(adapter, read) == (0, PATH1.encode() + b"\0")
    block = CurrentFolderWriteRequest("//cnc_mem/user", 1).to_block()
    assert data_block(adapter, block) == (0, b"")
    assert data_block(adapter, read) == (0, b"//CNC_MEM/USER/\0")
    assert data_block(adapter, CurrentFolderRequest(2).to_block())[1] == PATH1.encode() + b"\0"
    ew, data = data_block(adapter, FolderCountRequest("PATH1").to_block())
    assert (ew, FolderCount.decode(data)) == (0, FolderCount(0, 1))
    assert data_block(adapter, CurrentFolderRequest(0).to_block())[0] == EW.DATA
    assert data_block(adapter, CurrentFolderWriteRequest("//X/", 1).to_block())[0] == EW.DATA


def test_delete_and_main_through_files() -> None:
    clock = ManualClock()
    adapter = NativeAdapter(build(clock))
    machine = adapter.machine
    machine.store_program("O0321 (NEW)\nG91 G1 X10. F600\nM30\n")
    assert data_block(adapter, MainFileRequest().to_block()) == (0, (PATH1 + "O0001\0").encode())
    select = MainSelectRequest(PATH1 + "O0321").to_block()
    machine.set_panel(0)
    assert data_block(adapter, select)[0] == EW.MODE  # MDI: no program search
    machine.set_panel(1)
    assert data_block(adapter, select) == (0, b"")
    assert machine.motion.program_main == 321
    machine.cycle_start()
    clock.advance(0.2)
    delete = FileDeleteRequest(PATH1 + "O0321").to_block()
    assert data_block(adapter, delete)[0] == EW.REJECT
    machine.reset()
    assert data_block(adapter, delete) == (0, b"")
    assert [e.number for e in machine.program_directory()] == [1]
    assert data_block(adapter, delete)[0] == EW.DATA
    assert data_block(adapter, FileDeleteRequest("//CNC_MEM/USER/").to_block())[0] == EW.DATA
    assert data_block(adapter, MainFileRequest().to_block()) == (0, b"\0")


def test_a_read_only_machine_keeps_its_files() -> None:
    adapter = NativeAdapter(default_machine(read_only=True))
    assert data_block(adapter, FileDeleteRequest(PATH1 + "O0001").to_block())[0] == EW.PROT
    assert [e.number for e in adapter.machine.program_directory()] == [1]


def test_each_path_has_its_folder() -> None:
    machine = two_path_lathe()
    machine.store_program("O0007 (TWO)\nM30\n", path=2)
    adapter = NativeAdapter(machine)
    ew, data = data_block(adapter, SubfolderRequest("//CNC_MEM/USER/", 0, 5).to_block())
    assert ew == 0
    assert [r.name for r in SubfolderRecords.decode(data).records] == [
        b"PATH1",
        b"PATH2",
        b"LIBRARY",
    ]
    assert listing(adapter, "//CNC_MEM/USER/PATH2/")[1][0].name == b"O0007"
    on_path2 = RequestBlock(1, 2, 0xB0, (1, 0, 0, 0, 0))
    assert data_block(adapter, on_path2)[1] == b"//CNC_MEM/USER/PATH2/\0"
    on_path3 = RequestBlock(1, 3, 0xB0, (1, 0, 0, 0, 0))
    assert data_block(adapter, on_path3)[0] == EW.PATH
    # a program of path 2 is not path 1's main program
    machine.set_panel(1, path=1)
    block = MainSelectRequest("//CNC_MEM/USER/PATH2/O0007").to_block()
    assert data_block(adapter, block)[0] == EW.DATA


def test_a_16i_has_no_folders() -> None:
    machine = load_machine(MACHINE_16I)
    machine.store_program(DEMO_PROGRAM)
    adapter = NativeAdapter(machine)
    for request in (
        DriveListRequest(),
        DriveInfoRequest("//CNC_MEM/"),
        CurrentFolderRequest(1),
        FolderListRequest(PATH1),
        FileDeleteRequest(PATH1 + "O0001"),
        MainFileRequest(),
    ):
        assert data_block(adapter, request.to_block())[0] == EW.FUNC
    assert [e.number for e in machine.program_directory()] == [1]
    with pytest.raises(MachineError):
        machine.folder_entries(PATH1)


# --------------------------------------------------------------------------------------------
# The native client


async def test_the_client_reads_and_changes_the_folders() -> None:
    machine = build()
    machine.store_program("O0042 (FORTY TWO)\nM30\n")
    async with serving(machine) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as client:
            assert await client.read_drives() == ("CNC_MEM",)
            usage = await client.read_drive_usage()
            assert usage.used_entries == 8 and usage.pages == 2000
            assert await client.read_current_folder() == PATH1
            assert await client.read_subfolders("//CNC_MEM/") == [
                ("SYSTEM", False),
                ("MTB1", False),
                ("MTB2", False),
                ("USER", True),
            ]
            entries = await client.read_folder(PATH1)
            stamp = datetime(2026, 3, 4, 5, 6, 7)
            assert [(e.name, e.is_folder, e.comment) for e in entries] == [
                ("O0001", False, "DEMO CONTOUR"),
                ("O0042", False, "FORTY TWO"),
            ]
            assert entries[1].modified == stamp
            assert [e.size for e in entries] == [e.size for e in machine.program_directory()]
            assert (await client.read_folder("//CNC_MEM/"))[3].modified is None
            assert await client.read_folder("//CNC_MEM/MTB1/") == []
            counts = await client.read_folder_counts("//CNC_MEM/USER/")
            assert (counts.folders, counts.files) == (2, 0)
            info = await client.read_file_info("O0042", size_kind=0)
            assert (info.size, info.comment, info.modified) == (1, "FORTY TWO", stamp)
            assert await client.read_main_file() == PATH1 + "O0001"
            await client.write_current_folder("//CNC_MEM/USER/")
            assert await client.read_current_folder() == "//CNC_MEM/USER/"
            await client.delete_file("PATH1/O0042")
            assert [e.number for e in machine.program_directory()] == [1]
            with pytest.raises(CncError) as raised:
                await client.delete_file("PATH1/O0042")
            assert raised.value.ew == EW.DATA
            machine.set_panel(0)
            with pytest.raises(CncError) as raised:
                await client.select_main_file(PATH1 + "O0001")
            assert raised.value.ew == EW.MODE
            machine.set_panel(1)
            await client.select_main_file(PATH1 + "O0001")


async def test_the_client_checks_before_sending() -> None:
    async with serving(build()) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as client:
            with pytest.raises(ValueError):
                await client.delete_file("O" * 300)
            with pytest.raises(ValueError):
                await client.read_current_folder(3)
            with pytest.raises(ValueError):
                await client.read_folder(PATH1, size_kind=7)
            with pytest.raises(TypeError):
                await client.read_file_info(PATH1 + "O0001", size_kind=True)
            with pytest.raises(TypeError, match="name must be text, got 5"):
                await client.read_folder(5)  # type: ignore[arg-type]
            assert [e.number for e in served.machine.program_directory()] == [1]


async def test_the_client_on_a_16i() -> None:
    async with serving(load_machine(MACHINE_16I)) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as client:
            with pytest.raises(CncError) as raised:
                await client.read_drives()
            assert raised.value.ew == EW.FUNC


# --------------------------------------------------------------------------------------------
# The machine's folders


def test_a_files_date_is_when_it_was_last_stored() -> None:
    times = iter(datetime(2026, 5, d, tzinfo=UTC) for d in range(1, 10))
    machine = default_machine(sim_clock=ManualClock())
    built = machine.file_entry(PATH1 + "O0001").stamped
    machine.clock = lambda: next(times)
    machine.store_program("O0042\nM30\n")
    assert machine.file_entry(PATH1 + "O0042").stamped == datetime(2026, 5, 1, tzinfo=UTC)
    machine.store_program("O0042\nG0 X1.\nM30\n", replace=True)
    entry = machine.file_entry(PATH1 + "O0042")
    assert entry.stamped == datetime(2026, 5, 2, tzinfo=UTC) and entry.size == len(
        "O0042\nG0 X1.\nM30\n"
    )
    assert machine.file_entry(PATH1 + "O0001").stamped == built
    machine.delete_program(42)
    machine.store_program("O0042\nM30\n")
    assert machine.file_entry(PATH1 + "O0042").stamped == datetime(2026, 5, 3, tzinfo=UTC)


@pytest.mark.parametrize(
    "name",
    ["", "O0001", "//DATA_SV/O0001", "//CNC_MEM/USER/PATH1/X1", "//CNC_MEM/" + "A" * 300, "é"],
)
def test_names_that_are_no_file(name: str) -> None:
    machine = default_machine(sim_clock=ManualClock())
    machine.set_current_folder("//CNC_MEM/")
    with pytest.raises(MachineError) as raised:
        machine.file_entry(name)
    assert raised.value.ew == EW.DATA


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda m: m.folder_entries(5), r"folder or file name must be text \(str\), got 5"),
        (lambda m: m.drive_usage(3), r"drive must be text \(str\), got 3"),
        (lambda m: m.transfer_path(b"//CNC_MEM/"), r"must be text \(str\), got b'//CNC_MEM/'"),
        (lambda m: m.current_folder("1"), "current folder kind must be an integer, got '1'"),
    ],
)
def test_the_machine_refuses_a_value_of_another_type_as_every_call(call: Any, words: str) -> None:
    """A name that is no text, or a kind that is no integer, is a TypeError naming it, as
    every call of the machine says it (it was EW_DATA, the answer to a wire's value)."""
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(TypeError, match=words):
        call(machine)


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda m: m.file_entry("//CNC_MEM/USER/PATHX/O0001"), "PATHX/O0001"),
        (lambda m: m.file_entry("//CNC_MEM/USER/PATH/O0001"), "PATH/O0001"),
        (lambda m: m.file_entry("//CNC_MEM/USER/PATH01/O0001"), "PATH01/O0001"),
        (lambda m: m.delete_file("//CNC_MEM/USER/PATH2/O0001"), "PATH2/O0001"),
        (lambda m: m.folder_entries("//CNC_MEM/" + "A" * 300), "1..255 printable ASCII"),
        (lambda m: m.set_current_folder("//CNC_MEM/ÜSER/"), "ÜSER.*printable ASCII"),
    ],
)
def test_the_machine_names_what_it_refuses(call: Any, words: str) -> None:
    """A name that is no path's folder (``PATH01`` is not ``PATH1``), too long, not ASCII
    or no text at all is EW_DATA naming what was given, never a Python error."""
    machine = default_machine(sim_clock=ManualClock())
    with pytest.raises(MachineError, match=words) as raised:
        call(machine)
    assert raised.value.ew == EW.DATA
    assert [e.number for e in machine.program_directory()] == [1]


def test_a_name_that_is_no_text_is_refused_when_built() -> None:
    with pytest.raises(TypeError, match="name must be text, got 5"):
        cnc_pdf_del(CS, 5)  # type: ignore[arg-type]


def test_the_folders_while_a_program_runs() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    machine.set_panel(1)
    machine.cycle_start()
    clock.advance(1.0)
    assert machine.path_motion().program_running == 1
    assert machine.main_file() == PATH1 + "O0001"
    assert [e.name for e in machine.folder_entries(PATH1)] == ["O0001"]
    with pytest.raises(MachineError) as raised:
        machine.delete_file(PATH1 + "O0001")
    assert raised.value.ew == EW.REJECT


def test_a_transfer_by_folder_is_of_that_folders_path() -> None:
    machine = two_path_lathe()
    assert machine.transfer_path("//CNC_MEM/USER/PATH2/") == 2
    assert machine.transfer_path("//CNC_MEM/USER/PATH2/O0007", path=1) == 2
    assert machine.transfer_path("O0007", path=2) == 2
    assert machine.transfer_path("") == 1
    for name in ("//CNC_MEM/USER/LIBRARY/", "//CNC_MEM/USER/PATH3/", "//CNC_MEM/"):
        with pytest.raises(MachineError) as raised:
            machine.transfer_path(name)
        assert raised.value.ew == EW.DATA
    # a control without folders keeps the handle's path
    assert load_machine(MACHINE_16I).transfer_path("//CNC_MEM/USER/PATH2/") == 1
