"""Several paths on the native wire: the open answer of a multi-path machine (golden bytes of 2
and 4 paths in both layouts) and the adapter answering each block for the path in its path
word. FANUC's library itself drives a twin-turret machine in ``tests/test_fwlib_paths.py``;
the frames it exchanged are checked here without it (``tests/data/fwlib_paths.json``)."""

from __future__ import annotations

import json
import struct
from collections.abc import Sequence
from decimal import Decimal
from functools import cache
from pathlib import Path
from typing import Any

import pytest
from fwlib_capture_paths import PROBE_MAX_AXES, PROBE_PATHS, SIM_SETS, SIM_TIME
from hypothesis import given
from hypothesis import strategies as st
from paths_support import SHARED_MACRO, VALUES, twin_turret

from focas_net.adapters import NativeAdapter, ProgramTransfer
from focas_net.errors import EW
from focas_net.native import (
    NO_PATH,
    PATH_RECORDS,
    NativeCommand,
    OpenHeadV2,
    OpenHeadV3,
    PathDescription,
    RequestBlock,
    ResponseBlock,
    TransferError,
    TransferFrame,
    TransferStart,
    answer_refusal,
    build_open_answer,
    decode_frame,
    decode_open_answer,
    decode_request_body,
    decode_response_body,
    encode_request_body,
    open_answer_size,
)
from focas_net.sim import default_machine

TURRET = PathDescription(" T", 2, 1)
MILL = PathDescription(" M", 3, 2)
#: A path record of no path, in each layout.
ABSENT_V2 = "0000 0000 0000 0000"
ABSENT_V3 = "0000" * 16


def _hex(*parts: str) -> bytes:
    return bytes.fromhex(" ".join(parts))


# ---------------------------------------------------------------------------------------------
# The open answer of 2 and 4 paths


def test_two_paths_version_2() -> None:
    body = build_open_answer([TURRET, TURRET], 4, version=2, records=PATH_RECORDS)
    assert body == _hex(
        # kind 0, max axes 4, 10 path records, the path count cnc_getpath reports: 2
        "0000 0000 0004 0000 000a 0002 0000 0000",
        "2054 0000 0002 0001",  # " T", 2 axes, 1 spindle
        "2054 0000 0002 0001",
        *[ABSENT_V2] * 8,
    )
    assert open_answer_size(body, 2) == len(body) == 16 + 8 * 10
    answer = decode_open_answer(body, 2)
    assert isinstance(answer.head, OpenHeadV2)
    assert (answer.head.paths, answer.head.max_paths) == (10, 2)
    assert answer.present() == (TURRET, TURRET)
    assert answer.encode() == body


def test_two_paths_version_3() -> None:
    body = build_open_answer([TURRET, TURRET], 4, version=3, records=PATH_RECORDS)
    turret = "2054 0002 0000 0002 0000 0001" + " 0000" * 10  # " T", lathe, 2 axes, 1 spindle
    assert body == _hex(
        # record format 1, max axes 4, max spindles 1, 10 path records
        "0000 0000 0001 0004 0001 000a",
        "0000 0000 0000 0000",
        "0002",  # the controlled spindles of the CNC (cnc_sysinfo_ex ctrl_spdl)
        "0002",  # the path count cnc_getpath reports
        "0000 0000",
        "0001",  # option bits
        "0000 0000 0000 0000 0000",
        turret,
        turret,
        *[ABSENT_V3] * 8,
    )
    assert open_answer_size(body, 3) == len(body) == 40 + 32 * 10
    answer = decode_open_answer(body, 3)
    assert isinstance(answer.head, OpenHeadV3)
    assert (answer.head.paths, answer.head.max_paths) == (10, 2)
    assert answer.present() == (TURRET, TURRET)
    assert answer.encode() == body


def test_four_paths_version_2() -> None:
    paths = [TURRET, MILL, TURRET, MILL]
    body = build_open_answer(paths, 4, version=2, records=PATH_RECORDS)
    assert body == _hex(
        "0000 0000 0004 0000 000a 0004 0000 0000",
        "2054 0000 0002 0001",
        "204d 0000 0003 0002",  # " M", 3 axes, 2 spindles
        "2054 0000 0002 0001",
        "204d 0000 0003 0002",
        *[ABSENT_V2] * 6,
    )
    assert decode_open_answer(body, 2).present() == tuple(paths)


def test_four_paths_version_3() -> None:
    paths = [TURRET, MILL, TURRET, MILL]
    body = build_open_answer(paths, 4, version=3, records=PATH_RECORDS)
    turret = "2054 0002 0000 0002 0000 0001" + " 0000" * 10
    mill = "204d 0001 0000 0003 0000 0002" + " 0000" * 10  # " M", machining, 3 axes, 2 sp.
    assert body == _hex(
        "0000 0000 0001 0004 0002 000a",  # max spindles: the most of a path, 2
        "0000 0000 0000 0000 0006 0004 0000 0000 0001",  # 6 controlled spindles, 4 paths
        "0000 0000 0000 0000 0000",
        turret,
        mill,
        turret,
        mill,
        *[ABSENT_V3] * 6,
    )
    answer = decode_open_answer(body, 3)
    assert answer.present() == tuple(paths)
    assert [r.machine_type for r in answer.paths].count(NO_PATH) == 6


@pytest.mark.parametrize("version", [2, 3])
def test_one_record_per_path_unless_asked(version: int) -> None:
    """Without ``records`` an answer has one record per path (a single-path machine's answer is
    what it always was)."""
    body = build_open_answer([TURRET, MILL], 4, version=version)
    answer = decode_open_answer(body, version)
    assert len(answer.paths) == 2
    assert answer.head.paths == 2


@given(
    st.lists(
        st.builds(
            PathDescription, st.sampled_from([" M", " T"]), st.integers(1, 8), st.integers(0, 4)
        ),
        min_size=1,
        max_size=PATH_RECORDS,
    ),
    st.sampled_from([1, 2, 3, 4]),
    st.data(),
)
def test_open_answers_of_1_to_10_paths_round_trip(
    paths: list[PathDescription], version: int, data: st.DataObject
) -> None:
    records = data.draw(st.integers(len(paths), PATH_RECORDS))
    body = build_open_answer(paths, 8, version=version, records=records)
    assert open_answer_size(body, version) == len(body)
    answer = decode_open_answer(body, version)
    assert answer.present() == tuple(paths)
    assert (answer.head.paths, answer.head.max_paths) == (records, len(paths))
    assert answer.encode() == body


@pytest.mark.parametrize("records", [1, PATH_RECORDS + 1])
def test_records_between_the_paths_and_ten(records: int) -> None:
    with pytest.raises(ValueError, match=f"{records} path records for 2 paths"):
        build_open_answer([TURRET, TURRET], 4, records=records)


# ---------------------------------------------------------------------------------------------
# The adapter answers each block for the path in its path word

SETS = ("16i", "30i")
C = NativeCommand


def ask(adapter: NativeAdapter, blocks: Sequence[RequestBlock]) -> tuple[ResponseBlock, ...]:
    frame = decode_frame(adapter.answer(encode_request_body(list(blocks))))
    answers = decode_response_body(frame.body)
    assert [(a.device, a.path, a.command) for a in answers] == [
        (b.device, b.path, b.command) for b in blocks
    ]
    return answers


def cnc(path: int, command: int, *args: int) -> RequestBlock:
    return RequestBlock(1, path, command, (*args, *[0] * (5 - len(args))))  # type: ignore[arg-type]


def scaled(data: bytes) -> list[int]:
    """The mantissas of a run of 8-byte number records."""
    return [m for m, _, _ in struct.iter_unpack(">ihh", data)]


@pytest.mark.parametrize("set_name", SETS)
def test_the_open_answer_describes_both_turrets(set_name: str) -> None:
    adapter = NativeAdapter(twin_turret(set_name))
    assert adapter.version == (2 if set_name == "16i" else 3)
    answer = decode_open_answer(adapter.open_answer(), adapter.version)
    assert len(answer.paths) == PATH_RECORDS
    assert answer.head.max_paths == 2
    assert answer.present() == (PathDescription(" T", 2, 1), PathDescription(" T", 3, 1))
    assert answer.max_axes == 8


def test_a_single_path_machine_answers_one_record() -> None:
    answer = decode_open_answer(NativeAdapter(default_machine()).open_answer(), 3)
    assert len(answer.paths) == 1
    assert answer.head.max_paths == 1


@pytest.mark.parametrize("set_name", SETS)
def test_each_path_reads_its_own_values(set_name: str) -> None:
    adapter = NativeAdapter(twin_turret(set_name))
    for path, v in ((0, VALUES[0]), (1, VALUES[0]), (2, VALUES[1])):
        status, numbers, seq, feed, speed, absolute, machine, name = ask(
            adapter,
            [
                cnc(path, C.STATINFO),
                cnc(path, C.RDPRGNUM),
                cnc(path, C.RDSEQNUM),
                cnc(path, C.ACTF),
                cnc(path, C.ACTS),
                cnc(path, C.POSITION, 4, -1),
                cnc(path, C.POSITION, 1, 2),
                cnc(path, C.EXEPRGNAME),
            ],
        )
        assert struct.unpack(">7h", status.data)[0] == v.mode
        assert struct.unpack(">2i", numbers.data) == (v.running, v.main)
        assert struct.unpack(">i", seq.data) == (v.sequence,)
        assert scaled(feed.data) == [v.feed] and scaled(speed.data) == [v.speed]
        assert scaled(absolute.data) == [*v.absolute] + [0] * (8 - len(v.axes))  # max axes
        assert scaled(machine.data) == [v.machine[1]]
        o_number, text = struct.unpack(">i36s", name.data)
        assert (o_number, text.rstrip(b"\0")) == (v.running, f"O{v.running}".encode())


@pytest.mark.parametrize("set_name", SETS)
def test_each_path_has_its_axes_spindles_and_identity(set_name: str) -> None:
    adapter = NativeAdapter(twin_turret(set_name))
    for path, v in ((1, VALUES[0]), (2, VALUES[1])):
        sysinfo, names, axes, spindles = ask(
            adapter,
            [
                cnc(path, C.SYSINFO),
                cnc(path, C.AXIS_NAME, 0),
                cnc(path, C.AXIS_COUNT, 0),
                cnc(path, C.AXIS_COUNT, 1),
            ],
        )
        assert sysinfo.data[6:8] == b"TT"  # mt_type: a T series of 2 paths
        assert sysinfo.data[-2:] == f"{len(v.axes):02d}".encode()  # axes
        assert [names.data[i : i + 2] for i in range(0, len(names.data), 4)] == [
            a.encode() for a in v.axes
        ]
        assert struct.unpack(">H", axes.data) == (len(v.axes),)
        assert struct.unpack(">H", spindles.data) == (1,)


@pytest.mark.parametrize("set_name", SETS)
def test_macros_parameters_and_alarms_per_path(set_name: str) -> None:
    adapter = NativeAdapter(twin_turret(set_name))
    read_param = C.RDPARAM if set_name == "16i" else C.RDPARAM3
    shared_number, shared_value = SHARED_MACRO
    for path, v in ((1, VALUES[0]), (2, VALUES[1])):
        own, shared, parts, bits, messages = ask(
            adapter,
            [
                cnc(path, C.RDMACRO, 100, 100),
                cnc(path, C.RDMACRO, shared_number, shared_number),
                cnc(path, read_param, 6711, 6711, 0),
                cnc(path, C.ALARM),
                cnc(path, C.RDALMMSG, -1, 10, 2, 32),
            ],
        )
        mantissa, _, decimals = struct.unpack(">ihh", own.data)
        assert Decimal(mantissa).scaleb(-decimals) == v.macro
        mantissa, _, decimals = struct.unpack(">ihh", shared.data)
        assert Decimal(mantissa).scaleb(-decimals) == shared_value
        assert struct.unpack_from(">i", parts.data, 8) == (v.parts,)
        axis, alm_type, number, _ = v.alarm
        assert struct.unpack(">i", bits.data) == (1 << alm_type,)
        assert struct.unpack_from(">4i", messages.data) == (number, alm_type, axis, 15)
        assert len(messages.data) == 16 + 32  # that path's one alarm


@pytest.mark.parametrize("set_name", SETS)
def test_a_path_past_the_last_is_ew_path_and_shared_reads_ignore_it(set_name: str) -> None:
    adapter = NativeAdapter(twin_turret(set_name))
    per_path = [
        cnc(3, C.SYSINFO),
        cnc(3, C.STATINFO),
        cnc(3, C.RDPRGNUM),
        cnc(3, C.POSITION, 4, -1),
        cnc(3, C.RDMACRO, 100, 100),
        cnc(3, C.ALARM),
        cnc(3, C.AXIS_COUNT, 0),
        cnc(3, C.RDPROGDIR, 0, 10),
        cnc(3, C.RDMACRO, 5, 1),  # the path is checked before the arguments (EW_LENGTH)
    ]
    shared = [cnc(3, C.RDCNCID), cnc(3, C.RDALMHISTRY, 1, 1, 1)]
    answers = ask(adapter, per_path + shared)
    assert [a.ew for a in answers[: len(per_path)]] == [EW.PATH] * len(per_path)
    assert [a.ew for a in answers[len(per_path) :]] == [0, 0]
    assert answers[-2].data == ask(adapter, [cnc(1, C.RDCNCID)])[0].data
    # the PMC is the machine's: its refusal of an area it has not, not EW_PATH
    (pmc,) = ask(adapter, [RequestBlock(2, 3, C.PMC_RDPMCRNG, (0, 3, 5, 0, 0))])
    assert pmc.ew == ask(adapter, [RequestBlock(2, 1, C.PMC_RDPMCRNG, (0, 3, 5, 0, 0))])[0].ew
    assert pmc.ew != EW.PATH


@pytest.mark.parametrize("set_name", SETS)
def test_a_write_goes_to_the_blocks_path(set_name: str) -> None:
    machine = twin_turret(set_name)
    adapter = NativeAdapter(machine)
    record = struct.pack(">ihh", 75, 10, 1)  # 7.5
    (answer,) = ask(adapter, [RequestBlock(1, 2, C.WRMACRO, (101, 101, 0, 0, 8), record)])
    assert answer.ew == 0
    assert machine.read_macro(101, path=2) == Decimal("7.5")
    assert machine.read_macro(101, path=1) is None


def test_uploads_and_downloads_are_of_the_start_frames_path() -> None:
    machine = twin_turret()
    machine.store_program("O2001 (TURRET 2)\nN10 M30\n", path=2)
    adapter = NativeAdapter(machine)

    def upload(path: int, name: bytes) -> list[bytes]:
        frames = adapter.transfer(
            TransferFrame.UPLOAD_START, TransferStart(0, path, name).encode(), ProgramTransfer()
        )
        assert frames is not None
        return [decode_frame(f).body for f in frames]

    assert b"O2001 (TURRET 2)" in b"".join(upload(2, b"O2001-O2001"))
    for path, ew in ((1, EW.NUMBER), (0, EW.NUMBER), (3, EW.PATH)):
        (refusal,) = upload(path, b"O2001-O2001")
        assert TransferError.decode(refusal).code == ew
    (refusal,) = upload(3, b"NOT A RANGE")  # the path first
    assert TransferError.decode(refusal).code == EW.PATH
    state = ProgramTransfer()
    for frame_type, body in (
        (TransferFrame.DOWNLOAD_START, TransferStart(0, 2, b"").encode()),
        (TransferFrame.DOWNLOAD_DATA, b"\nO2002\nN10 M30\n%"),
        (TransferFrame.DOWNLOAD_END, b""),
    ):
        adapter.transfer(frame_type, body, state)
    assert [e.number for e in machine.program_directory(path=2)] == [2001, 2002]
    assert machine.program_directory(path=1) == []
    start = TransferStart(0, 3, b"").encode()
    (refusal,) = adapter.transfer(TransferFrame.DOWNLOAD_START, start, ProgramTransfer()) or []
    assert TransferError.decode(decode_frame(refusal).body).code == EW.PATH


# ---------------------------------------------------------------------------------------------
# What FANUC's library did with several paths (tests/data/fwlib_paths.json)


@cache
def paths_capture() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(
        (Path(__file__).with_name("data") / "fwlib_paths.json").read_text()
    )
    return data


@pytest.mark.parametrize("version", [2, 3])
def test_the_library_refuses_a_path_past_the_last_itself(version: int) -> None:
    (probe,) = [p for p in paths_capture()["probes"] if p["version"] == version]
    body = build_open_answer(PROBE_PATHS, PROBE_MAX_AXES, version=version, records=PATH_RECORDS)
    assert probe["open_answer"] == body.hex()
    assert probe["connect"]["return"] == 0
    # while connecting: one 0x18 block per present path, the path word its record's index + 1
    sysinfo = bytes.fromhex(probe["connect"]["requests"][2]["request"])
    blocks = decode_request_body(sysinfo[10:])
    assert [(b.command, b.path) for b in blocks] == [(C.SYSINFO, 1), (C.SYSINFO, 2)]
    assert probe["getpath"] == [0, 1, 2]
    for selection in probe["setpath"]:  # each made from path 2
        p = selection["path"]
        if p <= 0:  # path 1
            assert (selection["return"], selection["getpath"]) == (0, [0, 1, 2])
        elif p <= 2:
            assert (selection["return"], selection["getpath"]) == (0, [0, p, 2])
        else:  # refused, path 2 kept
            assert (selection["return"], selection["getpath"]) == (EW.PATH, [0, 2, 2])
    assert probe["setpath_frames"] == 0  # cnc_getpath and cnc_setpath send nothing
    # after cnc_setpath(2), every block carries path 2
    (request,) = probe["statinfo_on_path_2"]["requests"]
    blocks = decode_request_body(bytes.fromhex(request)[10:])
    assert {b.path for b in blocks} == {2}
    # the axis count of the selected path's record (3 axes, then 2): at version 2 the library
    # refuses axis 3 of path 2 unsent; at version 3 it checks against the max axes
    checks = {c["path"]: (c["return"], c["frames"]) for c in probe["cnc_absolute_axis_3"]}
    assert checks == {1: (0, 1), 2: (EW.ATTRIB, 0) if version == 2 else (0, 1)}


@pytest.mark.parametrize("set_name", SIM_SETS)
def test_the_twin_turret_answers_as_the_library_took_it(set_name: str) -> None:
    (data,) = [s for s in paths_capture()["sets"] if s["command_set"] == set_name]
    assert paths_capture()["time"] == SIM_TIME.isoformat()
    machine = twin_turret(set_name, clock=lambda: SIM_TIME)
    machine.set_panel(0, 1, 0)
    adapter = NativeAdapter(machine)
    assert adapter.open_response().hex() == data["open_response"]
    seen_paths = set()
    for call in data["calls"]:
        if call["function"] == "cnc_setpath":
            assert call["exchanges"] == []  # sent nothing
            want = EW.PATH if call["arguments"]["path"] == 3 else 0
            assert call["return"] == want
            continue
        assert call["return"] == 0, (call["function"], call["path"])
        for ex in call["exchanges"]:
            body = bytes.fromhex(ex["request"])
            answer = adapter.answer(body)
            assert answer.hex() == ex["answer"], (call["function"], call["path"])
            blocks = decode_request_body(body)
            seen_paths |= {b.path for b in blocks}
            frame = decode_frame(answer)
            assert answer_refusal(frame.body, len(blocks), frame.version) is None
    assert seen_paths == {1, 2}
    (getpath,) = [c for c in data["calls"] if c["function"] == "cnc_getpath"]
    assert getpath["arguments"] == {"path": 1, "max": 2}
