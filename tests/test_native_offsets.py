"""Tool offsets, work zero offsets and tool life: the machine's model, the machine file, the
codec (golden bytes as FANUC's library sent them, round trips), the native adapter and the
native client against a served machine, in both command sets."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, Served, serving

from focas_net.adapters import NativeAdapter
from focas_net.client import NativeClient, ToolGroupData
from focas_net.errors import EW, CncError
from focas_net.native import (
    CommandSet,
    LibraryCall,
    OffsetWrite,
    RequestBlock,
    ResponseBlock,
    ScaledValues,
    ToolEntry,
    ToolGroupRecord,
    ToolGroupRecords,
    ToolGroupRequest,
    ToolGroupsInUse,
    ToolGroupsInUseRequest,
    ToolLifeCounts,
    ToolLifeCountsRequest,
    ToolLifeInfoRequest,
    ToolNumberRequest,
    ToolNumbers,
    ToolOffsetInfoRequest,
    ToolOffsetMemory,
    ToolOffsetRequest,
    ToolOffsetWriteRequest,
    WorkOffsetRequest,
    WorkOffsetWriteRequest,
    decode_frame,
    decode_request,
    decode_response_body,
    encode_request_body,
    offset_type_of,
)
from focas_net.native import offsets as calls
from focas_net.sim import (
    LifeTool,
    Machine,
    MachineError,
    MachineFileError,
    PathSpec,
    ToolGroup,
    ToolsSpec,
    default_machine,
    machine_from_dict,
)
from focas_net.sim.nc import ManualClock

_16I, _30I = CommandSet.FS16I, CommandSet.FS30I


# --------------------------------------------------------------------------------------------
# Golden bytes: the request blocks FANUC's library (libfwlib32 1.0.5) sent, from its own log


def _block_hex(call: LibraryCall, frame: int = 0) -> str:
    body = call.encode()[frame][10:]  # after the 10-byte header
    return body[2:].hex()  # after the block count


GOLDEN = [
    (calls.cnc_rdtofs(_16I, 1, 0), "001c0001000100080000000100000001000003e80000000000000000"),
    (calls.cnc_rdtofs(_30I, 2, 3), "001c0001000100080000000200000002000003eb0000000000000000"),
    (calls.cnc_rdtofsr(_16I, 1, 3, 2), "001c0001000100080000000100000002000000030000000000000000"),
    (calls.cnc_rdzofs(_30I, 1, -1), "001c00010001000b0000000100000001ffffffff0000000000000000"),
    (calls.cnc_rdzofs(_16I, 0, 1), "001c00010001000b0000000000000000000000010000000000000000"),
    (calls.cnc_rdzofsr(_30I, 0, -1, 6), "001c00010001000b0000000000000006ffffffff0000000000000000"),
    (calls.cnc_rdtofsinfo(_16I), "001c00010001000a0000000000000000000000000000000000000000"),
    (calls.cnc_toolnum(_30I, 2, 3), "001c00010001004d0000000200000003000000030000000000000000"),
    (calls.cnc_rdntool(_16I, 2), "001c00010001008b0000000200000002000000000000000000000000"),
    (calls.cnc_rdlife(_30I, 1), "001c00010001008b0000000100000001000000000000000000000000"),
    (calls.cnc_rdtoolgrp(_16I, 7, 2), "001c00010001004d0000000700000001000000020000000000000000"),
    (calls.cnc_rdngrp(_30I), "001c00010001004a0000000000000000000000000000000000000000"),
    (calls.cnc_rdtlinfo(_16I), "001c00010001004a0000000000000000000000000000000000010000"),
    (calls.cnc_rdtlinfo(_30I), "001c0001000101c40000000000000000000000000000000000000000"),
    (calls.cnc_rdusegrpid(_16I), "001c0001000100480000000000000000000000000000000000000000"),
    (
        calls.cnc_wrtofs(_16I, 3, 2, -777),
        "00240001000100090000000300000003000003ea0000000000000008fffffcf70000ffff",
    ),
]


@pytest.mark.parametrize(("call", "golden"), GOLDEN, ids=[c.function for c, _ in GOLDEN])
def test_the_blocks_are_those_the_library_sent(call: LibraryCall, golden: str) -> None:
    assert _block_hex(call) == golden


def test_the_library_s_work_offset_write_sends_max_axes_records() -> None:
    call = calls.cnc_wrzofs(_16I, 1, -1, (0,) * 8)
    expected = "005c00010001000c0000000100000001ffffffff0000000000000040" + "00000000 0000ffff" * 8
    assert _block_hex(call) == expected.replace(" ", "")


def test_answers_decode_as_the_library_read_them() -> None:
    # cnc_rdtofsinfo: bytes 00 00 01 90 00 02 00 07 gave ofs_type 2, use_no 400, enable 7
    assert ToolOffsetMemory.decode(bytes.fromhex("0000019000020007")) == ToolOffsetMemory(400, 2, 7)
    # cnc_rdtoolgrp: 0x8B (7, 2, 0, 100, 0, 42) gave grp_num 7, ntool 2, life 100, count 42
    record = ToolGroupRecords.decode(
        bytes.fromhex("00000007000000020000000000000064000000000000002a")
    )
    assert record.records == (ToolGroupRecord(7, 2, 0, 100, 0, 42),)
    # cnc_toolnum: the T number sits after the 8-byte head
    numbers = ToolNumbers.decode(
        bytes.fromhex("0000000200000003" + "00000006000000060000001a00000001")
    )
    assert numbers == ToolNumbers(2, 3, (ToolEntry(6, 6, 26, 1),))
    # cnc_rdusegrpid: next, use and select after the library's 4-byte head (the group in use)
    in_use = ToolGroupsInUse(1, 2, 3)
    assert in_use.encode() == bytes.fromhex("000000010000000200000003")
    assert ToolGroupsInUse.decode(in_use.encode()) == in_use


# --------------------------------------------------------------------------------------------
# Round trips

_i32 = st.integers(-(2**31), 2**31 - 1)


@given(_i32, st.integers(-(2**15), 2**15 - 1), st.integers(-(2**15), 2**15 - 1))
def test_offset_memory_round_trips(count: int, kind: int, enable: int) -> None:
    record = ToolOffsetMemory(count, kind, enable)
    assert ToolOffsetMemory.decode(record.encode()) == record


@given(st.lists(st.tuples(*[_i32] * 6).map(lambda t: ToolGroupRecord(*t)), max_size=4))
def test_group_records_round_trip(records: list[ToolGroupRecord]) -> None:
    answer = ToolGroupRecords(tuple(records))
    assert ToolGroupRecords.decode(answer.encode()) == answer


@given(_i32, _i32, st.lists(st.tuples(*[_i32] * 4).map(lambda t: ToolEntry(*t)), max_size=5))
def test_tool_numbers_round_trip(group: int, first: int, tools: list[ToolEntry]) -> None:
    answer = ToolNumbers(group, first, tuple(tools))
    assert ToolNumbers.decode(answer.encode()) == answer


@given(st.tuples(*[_i32] * 5).map(lambda t: ToolLifeCounts(*t)))
def test_life_counts_round_trip(counts: ToolLifeCounts) -> None:
    assert ToolLifeCounts.decode(counts.encode()) == counts


@given(st.tuples(*[_i32] * 3).map(lambda t: ToolGroupsInUse(*t)))
def test_groups_in_use_round_trip(groups: ToolGroupsInUse) -> None:
    assert ToolGroupsInUse.decode(groups.encode()) == groups


@given(
    st.integers(-(2**31), 2**31 - 1),
    st.integers(-(2**31), 2**31 - 1),
    st.integers(-1, 1006),
    st.lists(_i32, min_size=1, max_size=8),
)
def test_requests_round_trip_through_their_blocks(
    first: int, last: int, kind: int, values: list[int]
) -> None:
    requests = [
        ToolOffsetRequest(first, last, kind),
        ToolOffsetWriteRequest(first, last, kind, OffsetWrite(tuple(values))),
        WorkOffsetRequest(first, last, kind),
        WorkOffsetWriteRequest(first, last, kind, OffsetWrite(tuple(values))),
        ToolGroupRequest(first, last),
        ToolNumberRequest(kind, first, last),
        ToolLifeCountsRequest(first),
        ToolOffsetInfoRequest(),
        ToolGroupsInUseRequest(),
        ToolLifeInfoRequest(),
    ]
    for request in requests:
        assert decode_request(request.to_block(2)) == request


def test_offset_types_as_sent() -> None:
    assert offset_type_of(1003) == 3  # cnc_rdtofs
    assert offset_type_of(3) == 3  # cnc_rdtofsr
    assert offset_type_of(-1) is None


# --------------------------------------------------------------------------------------------
# The machine's model


def _spec() -> ToolsSpec:
    return ToolsSpec(
        offsets=10,
        offset_values={(1, "length_geometry"): 100_000, (1, "length_wear"): -50},
        work={"G54": [1000, -2000, 3000]},
        groups=(
            ToolGroup(1, 2, "count", 0, [LifeTool(5, 5, 25), LifeTool(6, 6, 26)]),
            ToolGroup(3, 1, "time", 0, [LifeTool(7)]),
        ),
    )


def _machine(clock: ManualClock | None = None) -> Machine:
    return Machine("tools", axes=["X", "Y", "Z"], tools={1: _spec()}, sim_clock=clock)


def test_the_length_offset_is_what_g43_applies() -> None:
    clock = ManualClock()
    machine = _machine(clock)
    assert machine.path_engine().tool_offsets == {1: pytest.approx(99.95)}
    machine.store_program("O0001\nG91 G1 X0 F6000\nG43 H1 G1 X1.\nM30\n")
    machine.set_panel(1)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(30)
    # the G54 Z offset and the length H1 (99.95 mm) move the machine's Z
    assert machine.positions("machine", 3) == [("Z", 99_950)]
    machine.write_tool_offset(1, 2, 0)
    assert machine.path_engine().tool_offsets == {1: 100.0}
    machine.write_tool_offset(1, 3, 0)
    assert machine.path_engine().tool_offsets == {}


@pytest.mark.parametrize(
    ("call", "ew", "words"),
    [
        (lambda m: m.tool_offsets(0, 1, 0), EW.NUMBER, "tool offset number 0 is outside 1..10"),
        (lambda m: m.tool_offsets(1, 11, 0), EW.NUMBER, "11 is outside 1..10"),
        (lambda m: m.tool_offsets(2, 1, 0), EW.NUMBER, "1 is outside 2..10"),
        (lambda m: m.tool_offsets(1, 1, 4), EW.ATTRIB, "type 4 is outside 0..3"),
        (lambda m: m.write_tool_offset(1, 3, 1_000_000), EW.DATA, "1000000 is outside"),
        (lambda m: m.work_offsets(7, 7, None), EW.NUMBER, "work offset number 7"),
        (lambda m: m.work_offsets(0, 0, 4), EW.ATTRIB, "axis 4 is outside 1..3"),
        (lambda m: m.write_work_offset(1, None, [1, 2]), EW.LENGTH, "2 values for 3 axes"),
        (lambda m: m.write_work_offset(1, 1, [10**9]), EW.DATA, "1000000000 is outside"),
        (lambda m: m.tool_group(2), EW.NUMBER, "tool group 2"),
        (lambda m: m.tool_group(17), EW.NUMBER, "tool group 17 is outside 1..16"),
        (lambda m: m.group_tools(2, 1, 1), EW.NUMBER, "tool group 2"),
        (lambda m: m.group_tools(1, 3, 3), EW.NUMBER, "group 1's tool 3 is outside 1..2"),
        (lambda m: m.group_tools(1, 2, 1), EW.NUMBER, "group 1's last tool 1 is outside 2..2"),
        (lambda m: m.set_tool_life_count(1, 3), EW.DATA, "count 3 is outside 0..2"),
        (lambda m: m.tool_offsets(1, 1, 0, path=2), EW.PATH, "path 2"),
    ],
)
def test_the_machine_refuses(call: Any, ew: int, words: str) -> None:
    """Each refusal is the machine's, with its EW code and the value given in its words."""
    with pytest.raises(MachineError, match=words) as info:
        call(_machine())
    assert info.value.ew == ew


def test_a_groups_tools_by_index() -> None:
    machine = _machine()
    assert machine.group_tools(1, 1, 2) == machine.tool_group(1).tools
    assert machine.group_tools(1, 2, 2) == machine.tool_group(1).tools[1:]


def test_a_read_only_machine_refuses_writes() -> None:
    machine = Machine("ro", axes=["X"], read_only=True)
    writes: list[Callable[[], None]] = [
        lambda: machine.write_tool_offset(1, 0, 1),
        lambda: machine.write_work_offset(1, None, [1]),
        lambda: machine.set_tool_life_count(1, 0),
    ]
    for write in writes:
        with pytest.raises(MachineError) as info:
            write()
        assert info.value.ew == EW.PROT


def test_count_life_expires_a_tool_and_the_next_takes_over() -> None:
    clock = ManualClock()
    machine = _machine(clock)
    machine.store_program("O0001\nG91 G1 X0 F6000\nT5 M6\nG1 X1.\nT5 M6\nM30\n")
    machine.set_panel(1)
    machine.select_program(1)
    states = []
    for _ in range(5):
        machine.cycle_start()
        clock.advance(60)
        group = machine.tool_group(1)
        states.append((group.count, group.in_use, tuple(t[3] for t in group.tools)))
    assert states == [
        (1, 1, (1, 0)),  # counted once per cycle, at the first change to the group
        (2, 1, (2, 0)),  # T5's life of 2 reached: expired
        (1, 2, (2, 1)),  # the next selection takes T6
        (2, 2, (2, 2)),  # the group's last tool expired
        (2, 2, (2, 2)),  # and stays in use, at its life
    ]
    assert machine.tool_life_info().selected == 1
    machine.set_tool_life_count(1, 1)
    group = machine.tool_group(1)
    assert (group.count, group.tools[1][3]) == (1, 1)


def test_the_ignore_number_names_the_group() -> None:
    import tomllib

    clock = ManualClock()
    tools = (
        "[[tools]]\nignore_number = 100\n[[tools.group]]\nnumber = 3\nlife = 9\ntools = [5, 6]\n"
    )
    machine = machine_from_dict(tomllib.loads(_FILE + tools), sim_clock=clock)
    machine.store_program("O0001\nG91 G1 X0 F6000\nT103 M6\nM30\n")
    machine.set_panel(1)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(60)
    assert machine.tool_group(3).count == 1  # T103: group 3 (ignore number 100)
    assert machine.tool_life_info().selected == 3


def test_time_life_counts_whole_minutes_of_cutting() -> None:
    clock = ManualClock()
    machine = _machine(clock)
    machine.store_program("O0001\nG91 G1 X0 F6000\nT7 M6\nG1 X100. F60\nM30\n")
    machine.set_panel(1)
    machine.select_program(1)
    machine.cycle_start()
    clock.advance(30)
    assert machine.tool_group(3).count == 0  # less than a minute of cutting
    clock.advance(300)
    group = machine.tool_group(3)
    assert (group.count, group.tools[0][3]) == (1, 2)  # 1 minute: the life, expired


def test_a_lathe_has_the_lathe_offsets() -> None:
    machine = Machine(
        "lathe",
        paths=[PathSpec(("X", "Z"), kind="T"), PathSpec(("X2", "Z2"), kind="M")],
        tools={1: ToolsSpec(offset_values={(2, "tip"): 3, (2, "x_wear"): -10})},
    )
    info = machine.tool_offset_info()
    assert (info.kind, len(info.types), info.count) == ("T", 7, 64)
    assert machine.tool_offsets(2, 2, None) == [(-10, 0, 0, 0, 0, 0, 3)]
    with pytest.raises(MachineError) as err:
        machine.write_tool_offset(2, 6, 10)  # a tip is 0..9
    assert err.value.ew == EW.DATA
    assert machine.tool_offset_info(path=2).kind == "M"
    with pytest.raises(ValueError, match="tip is a lathe's offset, not a machining centre's"):
        Machine("bad", axes=["X"], tools={1: ToolsSpec(offset_values={(1, "tip"): 1})})


# --------------------------------------------------------------------------------------------
# The machine file


_FILE = """
[machine]
name = "m"
axes = ["X", "Y", "Z"]
"""


def _file(tools: str) -> Machine:
    import tomllib

    return machine_from_dict(tomllib.loads(_FILE + tools))


def test_the_machine_file_declares_tools() -> None:
    machine = _file(
        """
[[tools]]
offsets = 20
work = { G55 = [1, 2.5, -3.125] }
max_groups = 8
[[tools.offset]]
number = 4
radius_geometry = 4.5
[[tools.group]]
number = 8
life = 10
count = 3
type = "time"
tools = [11, { t = 12, h = 2, d = 22 }]
"""
    )

    assert machine.tool_offset_info().count == 20
    assert machine.tool_offsets(4, 4, 1) == [(4500,)]
    assert machine.work_offsets(2, 2, None) == [(1000, 2500, -3125)]
    group = machine.tool_group(8)
    assert (group.life_type, group.life, group.count) == ("time", 10, 3)
    assert group.tools == ((11, 0, 0, 0), (12, 2, 22, 0))
    assert machine.tool_life_info().max_groups == 8


@pytest.mark.parametrize(
    ("tools", "where"),
    [
        ("[[tools]]\nbogus = 1\n", r"tools\[0\]\.bogus"),
        ("[[tools]]\n[[tools]]\n", r"tools\[1\]\.path"),
        ("[[tools]]\n[[tools.offset]]\nnumber = 1\nradius_wear = 0.0001\n", "radius_wear"),
        ("[[tools]]\n[[tools.offset]]\nradius_wear = 1\n", "number"),
        ("[[tools]]\n[[tools.offset]]\nnumber = 1\ntip = 10\n", "tip"),
        ("[[tools]]\nwork = { G60 = [0, 0, 0] }\n", "work"),
        ("[[tools]]\nwork = { G54 = [0, 0] }\n", "G54"),
        ("[[tools]]\nwork = { G54 = [1e9, 0, 0] }\n", r"G54: 1000000000\.000 mm is beyond"),
        ("[[tools]]\n[[tools.group]]\nnumber = 1\nlife = 5\ntype = 'x'\ntools = [1]\n", "type"),
        ("[[tools]]\n[[tools.group]]\nnumber = 1\nlife = 5\ncount = 6\ntools = [1]\n", "count"),
        (
            "[[tools]]\nmax_tools = 1\n[[tools.group]]\nnumber = 1\nlife = 5\ntools = [1, 2]\n",
            "tools",
        ),
        ("[[tools]]\npath = 2\n", "path 2"),
    ],
)
def test_the_machine_file_names_what_is_wrong(tools: str, where: str) -> None:
    with pytest.raises(MachineFileError, match=where):
        _file(tools)


# --------------------------------------------------------------------------------------------
# The adapter


def _blocks(adapter: NativeAdapter, *blocks: RequestBlock) -> list[ResponseBlock]:
    frame = decode_frame(adapter.answer(encode_request_body(list(blocks))))
    return list(decode_response_body(frame.body))


def test_the_adapter_pads_every_axis_to_the_max_axes() -> None:
    machine = _machine()
    adapter = NativeAdapter(machine)
    (block,) = _blocks(adapter, WorkOffsetRequest(1, 2, -1).to_block())
    values = ScaledValues.decode(block.data).values
    assert len(values) == 2 * adapter.max_axis
    assert [v.mantissa for v in values[:3]] == [1000, -2000, 3000]
    assert all(v.mantissa == 0 for v in values[3 : adapter.max_axis])


def test_the_adapter_refuses_what_the_wire_cannot_carry() -> None:
    lathe = Machine("lathe", paths=[PathSpec(("X", "Z"), kind="T")])
    (block,) = _blocks(NativeAdapter(lathe), ToolOffsetRequest(1, 2, -1).to_block())
    assert (block.ew, len(ScaledValues.decode(block.data).values)) == (0, 14)  # 7 types each
    adapter = NativeAdapter(_machine())
    write = ToolOffsetWriteRequest(1, 2, 1003, OffsetWrite((5,)))
    (block,) = _blocks(adapter, write.to_block())
    assert block.ew == EW.LENGTH  # two numbers, one value
    zofs = WorkOffsetWriteRequest(1, 1, -1, OffsetWrite((1, 2)))
    (block,) = _blocks(adapter, zofs.to_block())
    assert block.ew == EW.LENGTH  # fewer than the max axes
    (block,) = _blocks(adapter, ToolNumberRequest(1, 1, 3).to_block())
    assert block.ew == EW.NUMBER  # group 1 has two tools
    (block,) = _blocks(adapter, ToolOffsetRequest(1, 1, 0).to_block(path=2))
    assert block.ew == EW.PATH


def test_a_refused_write_of_several_numbers_changes_nothing() -> None:
    machine = _machine()
    adapter = NativeAdapter(machine)
    before = machine.tool_offsets(1, 2, None)
    write = ToolOffsetWriteRequest(1, 2, 1003, OffsetWrite((7, 1_000_000)))
    (block,) = _blocks(adapter, write.to_block())
    assert block.ew == EW.DATA  # the second value is past 999.999 mm
    assert machine.tool_offsets(1, 2, None) == before
    g54 = machine.work_offsets(1, 2, None)
    zofs = WorkOffsetWriteRequest(1, 2, 1, OffsetWrite((5, 10**9)))
    (block,) = _blocks(adapter, zofs.to_block())
    assert block.ew == EW.DATA
    assert machine.work_offsets(1, 2, None) == g54
    (block,) = _blocks(adapter, WorkOffsetWriteRequest(1, 2, 1, OffsetWrite((5, 6))).to_block())
    assert block.ew == 0
    assert [row[0] for row in machine.work_offsets(1, 2, None)] == [5, 6]


def test_each_path_answers_its_own_tools() -> None:
    machine = Machine(
        "two",
        paths=[PathSpec(("X", "Z"), kind="T"), PathSpec(("X2", "Y2", "Z2"), kind="M")],
        tools={2: _spec()},
    )
    adapter = NativeAdapter(machine)
    one, two = _blocks(
        adapter,
        ToolOffsetRequest(1, 1, 1003).to_block(path=1),
        ToolOffsetRequest(1, 1, 1003).to_block(path=2),
    )
    assert ScaledValues.decode(one.data).values[0].mantissa == 0  # path 1: Z wear geometry
    assert ScaledValues.decode(two.data).values[0].mantissa == 100_000
    (block,) = _blocks(adapter, ToolGroupRequest(1, 1).to_block(path=2))
    assert ToolGroupRecords.decode(block.data).records == (ToolGroupRecord(1, 2, 0, 2, 0, 0),)


# --------------------------------------------------------------------------------------------
# The native client, both command sets


def _served_machine(set_name: str) -> Machine:
    """The built-in 0i-F (30i set), or a 16i of the same tools (16i set)."""
    if set_name == "30i":
        machine = default_machine()
    else:
        group = ToolGroup(1, 500, "count", 0, [LifeTool(1, 1, 1), LifeTool(11, 11, 11)])
        tools = ToolsSpec(offset_values={(1, "length_geometry"): 125_000}, groups=(group,))
        machine = Machine("fs16i", axes=["X", "Y", "Z"], control_class="16i", tools={1: tools})
    machine.set_panel(0, 1, 0)
    return machine


@pytest.fixture(params=["30i", "16i"])
async def served(request: pytest.FixtureRequest) -> AsyncIterator[Served]:
    async with serving(_served_machine(request.param)) as s:
        yield s


async def test_client_reads_and_writes_tool_offsets(served: Served) -> None:
    machine = served.machine
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        assert await native.read_tool_offset(1, 3) == 125_000
        rows = await native.read_tool_offsets(1, 2)
        assert rows == tuple(machine.tool_offsets(1, 2, None))
        assert await native.read_tool_offsets(1, 3, 3) == tuple(machine.tool_offsets(1, 3, 3))
        await native.write_tool_offset(3, 0, -42)
        assert machine.tool_offsets(3, 3, 0) == [(-42,)]
        memory = await native.read_tool_offset_memory()
        assert (memory.type, memory.count) == (2, 64)
        with pytest.raises(CncError) as info:
            await native.read_tool_offset(65, 0)
        assert info.value.ew == EW.NUMBER
        with pytest.raises(ValueError, match="offset type"):
            await native.read_tool_offset(1, 100)


async def test_client_reads_and_writes_work_offsets(served: Served) -> None:
    machine = served.machine
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        await native.write_work_offset(1, [1000, -2000, 3000])
        assert machine.work_offsets(1, 1, None) == [(1000, -2000, 3000)]
        assert await native.read_work_offset(1) == (1000, -2000, 3000)
        await native.write_work_offset(1, [7], axis=2)
        assert await native.read_work_offset(1, 2) == (7,)
        assert await native.read_work_offsets(0, 2) == ((0, 0, 0), (1000, 7, 3000), (0, 0, 0))
        assert await native.read_work_offsets(1, 3, axis=3) == ((3000,), (0,), (0,))
        with pytest.raises(ValueError, match="3 axes"):
            await native.write_work_offset(1, [1, 2])


async def test_client_reads_tool_life(served: Served) -> None:
    machine = served.machine
    async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
        info = await native.read_tool_life_info()
        expected = machine.tool_life_info()
        assert (info.max_groups, info.max_tools, info.max_minutes, info.max_cycles) == (
            expected.max_groups,
            expected.max_tools,
            4300,
            9999,
        )
        assert await native.read_tool_group_in_use() == 0
        with pytest.raises(CncError) as refused:
            await native.read_tool_group(2 if info.groups == 1 else 3)
        assert refused.value.ew == EW.NUMBER
        group = await native.read_tool_group(1)
        assert group == ToolGroupData(1, 500, 0, (ToolEntry(1, 1, 1, 0), ToolEntry(11, 11, 11, 0)))
        assert await native.read_tool_number(1, 2) == 11
