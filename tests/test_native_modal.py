"""Modal data, operator messages and program pointers over the native protocol, without
FANUC's library: the frames the library sends (golden bytes, as its log showed them in both
command sets), the answer records it decoded, hypothesis round trips, the machine's model
(``#3006``, external operator messages), the adapter idle and running, and the native client
against a real server. ``tests/test_fwlib_modal.py`` runs the same through the library.
"""

from __future__ import annotations

import struct
from decimal import Decimal
from pathlib import Path
from typing import Any, Final

import pytest
from fwlib_support import MACHINE_16I
from hypothesis import given
from hypothesis import strategies as st
from support import IO_TIMEOUT, serving

from focas_net.adapters import NativeAdapter
from focas_net.client import (
    CommandValue,
    GCode,
    ModalGroup,
    ModalValue,
    NativeClient,
    OperatorMessageText,
)
from focas_net.errors import EW, CncError
from focas_net.native import (
    ActivePointer,
    BlockCounter,
    CommandRecord,
    CommandRecords,
    CommandRequest,
    CommandSet,
    ExecutingPath,
    GCodeRecord,
    GCodeRecords,
    GCodeRequest,
    MdiPointer,
    MdiPointerRequest,
    ModalAux,
    ModalAuxData,
    ModalAuxRequest,
    ModalGCode,
    ModalGCodes,
    ModalGRequest,
    NativePayloadError,
    NativeRequest,
    OperatorMessage3Request,
    OperatorMessageRecord,
    OperatorMessageRecords,
    OperatorMessageRequest,
    RequestBlock,
    calls,
    decode_frame,
    decode_response_body,
    encode_request_body,
    g_code_of,
)
from focas_net.sim import (
    ExternalMessage,
    Machine,
    MachineFileError,
    OperatorMessage,
    PathSpec,
    default_machine,
    load_machine,
)
from focas_net.sim.nc import ManualClock

SETS: Final = [CommandSet.FS16I, CommandSet.FS30I]

#: A program that stops with a message, then cuts with modal codes set.
MESSAGE_PROGRAM: Final = (
    "O0007 (MESSAGE)\n"
    "N10 G90 G17 G54 G00 X0 Y0 Z0\n"
    "N20 #3006 = 1 (CHECK THE PART)\n"
    "N30 G91 G01 X50. F600 S1200 M3\n"
    "N40 G04 P500\n"
    "N50 G90 G00 X0\n"
    "N60 M30\n"
)


def block(command: int, *args: int) -> bytes:
    """A CNC request block of path 1 as the library sends it."""
    full = (*args, *(0,) * (5 - len(args)))
    return struct.pack(">HHHH5i", 28, 1, 1, command, *full)


# --------------------------------------------------------------------------------------------
# What FANUC's library sends (its log, both command sets) [V]

#: (call, its arguments) -> the one request block the library sent, in both command sets.
LIBRARY_BLOCKS: Final = [
    ("cnc_modal", (1, 0), block(0x21, 1, 0)),
    ("cnc_modal", (-1, 0), block(0x21, -1, 0)),
    ("cnc_modal", (-2, 0), block(0x22, -1, 0)),
    ("cnc_modal", (-3, 0), block(0x22, -2, 0)),
    ("cnc_modal", (-4, 0), block(0x21, -2, 0)),
    ("cnc_modal", (-5, 0), block(0x21, -3, 0)),
    ("cnc_modal", (100, 0), block(0x22, 1, 0)),
    ("cnc_modal", (101, 1), block(0x22, 3, 1)),
    ("cnc_modal", (107, 0), block(0x22, 21, 0)),
    ("cnc_modal", (108, 2), block(0x22, 22, 2)),
    ("cnc_modal", (126, 0), block(0x22, 13, 0)),
    ("cnc_modal", (200, 0), block(0x22, 100, 0)),
    ("cnc_modal", (231, 0), block(0x22, 131, 0)),
    ("cnc_modal", (300, 0), block(0x21, 100, 0)),
    ("cnc_rdgcode", (-1, 0), block(0x96, -1, 0)),
    ("cnc_rdcommand", (-1, 0), block(0x97, -1, 0)),
    ("cnc_rdopmsg", (), block(0x34, 0)),
    ("cnc_exeprgname2", (), block(0xFC)),
    ("cnc_rdactpt", (), block(0x162)),
    ("cnc_rdblkcount", (), block(0x35)),
    ("cnc_rdmdipntr", (), block(0x38)),
]


@pytest.mark.parametrize("cs", SETS)
@pytest.mark.parametrize(("function", "args", "sent"), LIBRARY_BLOCKS)
def test_the_calls_send_what_the_library_sent(
    cs: CommandSet, function: str, args: tuple[int, ...], sent: bytes
) -> None:
    call = getattr(calls, function)(cs, *args)
    (requests,) = call.frames
    assert encode_request_body([r.to_block() for r in requests]) == b"\x00\x01" + sent


def test_opmsg3_sends_0x34_in_the_16i_set_and_0xd0_in_the_30i_set() -> None:
    (sixteen,) = calls.cnc_rdopmsg3(CommandSet.FS16I, -1, 5).frames
    (thirty,) = calls.cnc_rdopmsg3(CommandSet.FS30I, -1, 5).frames
    assert encode_request_body([r.to_block() for r in sixteen])[2:] == block(0x34, -1)
    assert encode_request_body([r.to_block() for r in thirty])[2:] == block(0xD0, 0, -1, 5)


@pytest.mark.parametrize("kind", [127, 199, -6, -100])
def test_cnc_modal_refuses_the_types_the_library_refuses(kind: int) -> None:
    with pytest.raises(ValueError, match="refused by the library"):
        calls.cnc_modal(CommandSet.FS30I, kind, 0)


# --------------------------------------------------------------------------------------------
# The answer records (golden bytes the library decoded) [V]


def test_modal_g_golden() -> None:
    # the library keeps the first byte of each pair: 0x81 is G01 commanded in group 01
    codes = ModalGCodes((ModalGCode(0x81), ModalGCode(0x00)))
    assert codes.encode() == bytes.fromhex("81000000")
    assert ModalGCodes.decode(bytes.fromhex("81000000")) == codes
    assert codes.records[0].index == 1 and codes.records[0].commanded
    assert g_code_of(0, 0x81) == 10 and g_code_of(13, 5) == 590 and g_code_of(19, 0) is None


def test_modal_aux_golden() -> None:
    # M6 commanded: (6, 0x81, 0) came out of ODBMDL's aux as (6, 129, 0)
    assert ModalAux.of(6, True).encode() == bytes.fromhex("00000006 0081 0000")
    assert ModalAux.of(1, False).encode() == bytes.fromhex("00000001 0001 0000")
    f = ModalAux.of(12.5, True)
    assert f == ModalAux(125, 0x80 | 0x40 | 3, 1) and f.value == 12.5
    assert ModalAux.of(-3.25, False).value == -3.25
    assert ModalAux.of(None, False) == ModalAux(0, 0, 0)
    assert ModalAuxData.decode(f.encode() * 2).records == (f, f)


def test_g_code_record_golden() -> None:
    record = GCodeRecord(22, 0, 501, 1)
    assert record.encode() == bytes.fromhex("0016 0000 000001f5 00000001")
    assert record.code == "G50.1"  # the library wrote b"G50.1"
    assert GCodeRecord(1, 1, 0, 0).code == "G00"
    assert GCodeRecords.decode(record.encode()).records == (record,)


def test_command_record_golden() -> None:
    record = CommandRecord("M", 0, 1, 6, 0)
    assert record.encode() == bytes.fromhex("4d00 0001 00000006 00000000")
    assert CommandRecords.decode(record.encode()).records == (record,)


def test_operator_message_record_golden() -> None:
    record = OperatorMessageRecord(2000, 0, 4, b"MSG0")
    raw = record.encode()
    assert raw[:16] == bytes.fromhex("000007d0 00000000 00000004") + b"MSG0"
    assert len(raw) == 268 == OperatorMessageRecord.SIZE
    assert OperatorMessageRecords.decode(raw).records[0].message == b"MSG0"


def test_pointer_records_golden() -> None:
    assert ActivePointer(1, 3).encode() == bytes.fromhex("00000001 00000003")
    assert BlockCounter(14).encode() == bytes.fromhex("0000000e")
    assert MdiPointer(1, 71, 1, 81).encode() == bytes.fromhex("00000001 00000047 00000001 00000051")
    path = ExecutingPath(b"//CNC_MEM/USER/PATH1/O0001")
    raw = path.encode()
    assert len(raw) == 256 and raw.startswith(b"//CNC_MEM/USER/PATH1/O0001\x00")
    assert ExecutingPath.decode(raw) == path
    for size in (0, 255, 257):
        with pytest.raises(NativePayloadError):
            ExecutingPath.decode(bytes(size))
    with pytest.raises(ValueError):
        ExecutingPath(bytes(257)).encode()


@given(st.integers(-(10**6), 10**6), st.integers(0, 3), st.booleans())
def test_modal_aux_round_trip(mantissa: int, decimals: int, commanded: bool) -> None:
    value = mantissa / 10**decimals
    entry = ModalAux.of(value, commanded)
    assert ModalAux.decode(entry.encode()) == entry
    assert entry.value == pytest.approx(value)
    assert entry.commanded is commanded


@given(st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), st.integers(0, 9999), st.integers(0, 3))
def test_g_code_record_round_trip(group: int, flag: int, number: int, decimals: int) -> None:
    record = GCodeRecord(group, flag, number, decimals)
    assert GCodeRecord.decode(record.encode()) == record


@given(st.integers(-(2**31), 2**31 - 1), st.integers(-1, 4), st.binary(max_size=256))
def test_operator_message_round_trip(number: int, kind: int, text: bytes) -> None:
    text = text.rstrip(b"\x00")
    record = OperatorMessageRecord(number, kind, len(text), text)
    assert OperatorMessageRecord.decode(record.encode()) == record


_I32 = st.integers(-(2**31), 2**31 - 1)
_I16 = st.integers(-(2**15), 2**15 - 1)


@given(st.lists(st.integers(0, 255), max_size=22))
def test_modal_g_round_trip(g_data: list[int]) -> None:
    codes = ModalGCodes(tuple(ModalGCode(g) for g in g_data))
    assert ModalGCodes.decode(codes.encode()) == codes


@given(st.characters(min_codepoint=0x41, max_codepoint=0x5A), st.integers(0, 255), _I16, _I32, _I32)
def test_command_record_round_trip(
    address: str, number: int, flag: int, value: int, decimals: int
) -> None:
    record = CommandRecord(address, number, flag, value, decimals)
    assert CommandRecords.decode(record.encode()).records == (record,)


@given(_I32, _I32, _I32, _I32)
def test_pointer_records_round_trip(a: int, b: int, c: int, d: int) -> None:
    assert ActivePointer.decode(ActivePointer(a, b).encode()) == ActivePointer(a, b)
    assert BlockCounter.decode(BlockCounter(c).encode()) == BlockCounter(c)
    assert MdiPointer.decode(MdiPointer(a, b, c, d).encode()) == MdiPointer(a, b, c, d)


@given(st.binary(max_size=256).map(lambda b: b.rstrip(b"\x00")))
def test_executing_path_round_trip(path: bytes) -> None:
    raw = ExecutingPath(path).encode()
    assert len(raw) == 256 and ExecutingPath.decode(raw) == ExecutingPath(path)


@given(
    st.sampled_from(
        [ModalGRequest, ModalAuxRequest, GCodeRequest, CommandRequest, OperatorMessageRequest]
    ),
    _I32,
    st.integers(0, 2),
)
def test_modal_requests_round_trip(kind: type[NativeRequest], first: int, block: int) -> None:
    make: Any = kind
    request = make(first) if kind is OperatorMessageRequest else make(first, block)
    assert type(request).from_block(request.to_block()) == request


@given(st.integers(-1, 4), st.integers(0, 10))
def test_opmsg3_request_round_trip(kind: int, count: int) -> None:
    request = OperatorMessage3Request(0, kind, count)
    assert OperatorMessage3Request.from_block(request.to_block()) == request
    assert MdiPointerRequest.from_block(MdiPointerRequest().to_block()) == MdiPointerRequest()


# --------------------------------------------------------------------------------------------
# The machine's model


def message_machine(clock: ManualClock) -> Machine:
    machine = default_machine(sim_clock=clock, programs=[MESSAGE_PROGRAM])
    machine.set_panel(1)
    return machine


def test_3006_stops_with_its_message_until_cycle_start() -> None:
    clock = ManualClock()
    machine = message_machine(clock)
    assert machine.operator_messages() == ()
    machine.cycle_start()
    clock.advance(1.0)
    assert machine.operator_messages() == (OperatorMessage(1, "CHECK THE PART", False),)
    assert machine.status().run == 1  # STOP
    pointer = machine.program_pointer()
    assert (pointer.program, pointer.block) == (7, 2)
    machine.cycle_start()
    assert machine.operator_messages() == ()


def test_the_modal_state_follows_the_program() -> None:
    clock = ManualClock()
    machine = message_machine(clock)
    idle = machine.modal_state()
    assert idle.group(1) is not None and idle.group(1).text == "G00"  # type: ignore[union-attr]
    assert idle.address("F").value is None
    machine.cycle_start()
    clock.advance(1.0)
    machine.cycle_start()  # past the message
    clock.advance(1.0)  # in N30's cut
    state = machine.modal_state()
    g1 = state.group(1)
    assert g1 is not None and (g1.text, g1.commanded) == ("G01", True)
    assert state.group(3) is not None and state.group(3).text == "G91"  # type: ignore[union-attr]
    assert state.address("F").value == 600 and state.address("F").commanded
    assert state.address("S").value == 1200
    assert state.address("X").value == 50 and state.address("X").commanded
    assert machine.program_pointer().blocks_run == 3
    # the system variables name FANUC's groups too: G40.1 in 18, G50.1 in 22
    assert machine.read_macro(4018) == Decimal("40.1")
    assert machine.read_macro(4022) == Decimal("50.1")
    assert state.group(18) is not None and state.group(22) is not None


def test_external_messages_follow_their_a_bits() -> None:
    machine = default_machine()
    machine.set_external_messages(
        [ExternalMessage(0, 1, 2001, "DOOR OPEN"), ExternalMessage(2, 7, 2100, "OIL LOW")]
    )
    assert machine.operator_messages() == ()
    machine.write_pmc("A", 0, b"\x02")
    machine.write_pmc("A", 2, b"\x80")
    assert machine.operator_messages() == (
        OperatorMessage(2001, "DOOR OPEN", True),
        OperatorMessage(2100, "OIL LOW", True),
    )
    assert machine.operator_messages(path=1) == machine.operator_messages()


@pytest.mark.parametrize(
    ("message", "reason"),
    [
        (ExternalMessage(0, 8, 2000, "X"), "outside the A area"),
        (ExternalMessage(10**6, 0, 2000, "X"), "outside the A area"),
        (ExternalMessage(0, 0, 1000, "X"), "external alarm messages"),
        (ExternalMessage(0, 0, 3000, "X"), "2000..2999"),
        (ExternalMessage(0, 0, 2000, ""), "1..255"),
        (ExternalMessage(0, 0, 2000, "\u00e9"), "printable ASCII, got '\u00e9'"),
        (ExternalMessage("0", 0, 2000, "X"), "byte is not an integer"),  # type: ignore[arg-type]
        (ExternalMessage(0, True, 2000, "X"), "bit is not an integer"),
        (ExternalMessage(0, 0, 2000.0, "X"), "number is not an integer"),  # type: ignore[arg-type]
        (ExternalMessage(0, 0, 2000, 5), "a message is text, got 5"),  # type: ignore[arg-type]
    ],
)
def test_external_messages_are_checked(message: ExternalMessage, reason: str) -> None:
    machine = default_machine()
    with pytest.raises(ValueError, match=reason):
        machine.set_external_messages([message])
    assert machine.external_messages == ()


def test_an_external_message_number_is_given_once() -> None:
    machine = default_machine()
    with pytest.raises(ValueError, match="twice"):
        machine.set_external_messages(
            [ExternalMessage(0, 0, 2000, "A"), ExternalMessage(0, 1, 2000, "B")]
        )


# --------------------------------------------------------------------------------------------
# The adapter


def ask(adapter: NativeAdapter, request: bytes) -> tuple[int, bytes]:
    answer = decode_frame(adapter.answer(b"\x00\x01" + request))
    (got,) = decode_response_body(answer.body)
    return got.ew, got.data


def ok(adapter: NativeAdapter, request: bytes) -> bytes:
    """The data of an answer without an EW code."""
    ew, data = ask(adapter, request)
    assert ew == 0
    return data


@pytest.mark.parametrize("version", [2, 3])
def test_the_adapter_answers_idle_and_running(version: int) -> None:
    clock = ManualClock()
    machine = message_machine(clock)
    adapter = NativeAdapter(machine, version=version)
    data = ok(adapter, block(0x21, -1, 0))
    assert len(data) == 44 and data[0] == 0  # G00, not commanded
    data = ok(adapter, block(0x35))
    assert BlockCounter.decode(data).count == 0
    data = ok(adapter, block(0x34, 0))
    assert OperatorMessageRecords.decode(data).records[0].number == -1  # no message
    machine.cycle_start()
    clock.advance(1.0)
    data = ok(adapter, block(0x34, 0))
    (record,) = OperatorMessageRecords.decode(data).records
    assert (record.number, record.message) == (1, b"CHECK THE PART")
    data = ok(adapter, block(0x162))
    assert ActivePointer.decode(data) == ActivePointer(7, 2)
    machine.cycle_start()
    clock.advance(1.0)
    data = ok(adapter, block(0x21, 0, 0))
    assert ModalGCodes.decode(data).records == (ModalGCode(0x81),)  # G01 commanded
    data = ok(adapter, block(0x22, 5, 0))  # F
    assert ModalAuxData.decode(data).records == (ModalAux.of(600, True),)
    data = ok(adapter, block(0x22, -2, 0))  # the axes
    assert [r.value for r in ModalAuxData.decode(data).records] == [50, 0, 0]
    data = ok(adapter, block(0x96, -1, 0))
    codes = {r.group: r.code for r in GCodeRecords.decode(data).records}
    assert (codes[1], codes[3], codes[14]) == ("G01", "G91", "G54")
    data = ok(adapter, block(0x97, -1, 0))
    values = {r.address: r.value for r in CommandRecords.decode(data).records}
    assert (values["F"], values["S"], values["M"], values["N"]) == (600, 1200, 3, 30)
    data = ok(adapter, block(0xFC))
    assert ExecutingPath.decode(data).text == b"//CNC_MEM/USER/PATH1/O0007"
    data = ok(adapter, block(0x38))
    pointer = MdiPointer.decode(data)
    assert pointer.mdiprog == 7 and MESSAGE_PROGRAM[pointer.mdipntr :].startswith("N30")


@pytest.mark.parametrize(
    "request_block",
    [
        block(0x21, 0, 3),  # no block 3
        block(0x21, 22, 0),  # no such group
        block(0x21, -2, 0),  # one-shot codes
        block(0x22, 14, 0),  # a slot of no address
        block(0x22, 103, 0),  # an axis the path has not
        block(0x96, 30, 0),
        block(0x97, 29, 0),
        block(0x34, 5),
        block(0xD0, 0, 7, 5),
    ],
)
def test_the_adapter_refuses_what_the_control_has_not(request_block: bytes) -> None:
    ew, data = ask(NativeAdapter(default_machine()), request_block)
    assert (ew, data) == (EW.NUMBER, b"")


def test_the_messages_of_every_type_and_a_count() -> None:
    machine = default_machine()
    machine.set_external_messages(
        [ExternalMessage(0, b, 2000 + b, f"MESSAGE {b}") for b in range(3)]
    )
    machine.write_pmc("A", 0, b"\x07")
    adapter = NativeAdapter(machine, version=3)
    data = ok(adapter, block(0xD0, 0, -1, 2))
    assert [r.number for r in OperatorMessageRecords.decode(data).records] == [2000, 2001]
    data = ok(adapter, block(0x34, -1))
    assert len(OperatorMessageRecords.decode(data).records) == 3
    data = ok(adapter, block(0x34, 1))  # type 1 holds none
    assert OperatorMessageRecords.decode(data).records[0].number == -1


# --------------------------------------------------------------------------------------------
# The native client against a real server


#: The 16i-class machine file with an A area and an external operator message.
MESSAGES_TOML: Final = """
[[operator_messages]]
address = "A0.0"
number = 2005
text = "COOLANT"

[pmc.A]
size = 16
"""


def machine_of(control: str, clock: ManualClock, tmp_path: Path) -> Machine:
    """The program of :data:`MESSAGE_PROGRAM` selected on a 16i-class machine file (with
    :data:`MESSAGES_TOML`) or the built-in 0i-F, and the message of A0.0 on both."""
    if control == "0i-F":
        machine = message_machine(clock)
        machine.set_external_messages([ExternalMessage(0, 0, 2005, "COOLANT")])
        return machine
    text = MACHINE_16I.read_text().replace("[pmc.R]", MESSAGES_TOML + "[pmc.R]", 1)
    file = tmp_path / "messages.toml"
    file.write_text(text)
    machine = load_machine(file, sim_clock=clock)
    machine.store_program(MESSAGE_PROGRAM)
    machine.set_panel(1)
    machine.select_program(7)
    return machine


@pytest.mark.parametrize("control", ["16i", "0i-F"])
async def test_the_client_reads_what_the_machine_holds(control: str, tmp_path: Path) -> None:
    clock = ManualClock()
    machine = machine_of(control, clock, tmp_path)
    assert machine.external_messages == (ExternalMessage(0, 0, 2005, "COOLANT"),)
    async with serving(machine) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
            groups = await native.read_modal_groups()
            assert groups[0] == ModalGroup(1, "G00", 0, False) and len(groups) == 22
            assert await native.read_operator_message() == OperatorMessageText(-1, 0, "")
            machine.write_pmc("A", 0, b"\x01")
            machine.cycle_start()
            clock.advance(1.0)
            assert await native.read_operator_messages() == (
                OperatorMessageText(2005, 0, "COOLANT"),
                OperatorMessageText(1, 0, "CHECK THE PART"),
            )
            assert await native.read_operator_message() == OperatorMessageText(2005, 0, "COOLANT")
            machine.cycle_start()
            clock.advance(1.0)
            assert (await native.read_modal_groups(1))[0] == ModalGroup(1, "G01", 1, True)
            values = {v.address: v for v in await native.read_modal_values()}
            assert values["F"] == ModalValue("F", 600.0, True)
            assert (await native.read_modal_values("S"))[0].value == 1200
            codes = await native.read_g_codes()
            assert GCode(1, "G01", True) in codes and GCode(14, "G54", False) in codes
            commands = await native.read_commands()
            assert CommandValue("F", Decimal(600), True) in commands
            assert await native.read_program_path() == "//CNC_MEM/USER/PATH1/O0007"
            assert await native.read_active_pointer() == ActivePointer(7, 3)
            assert await native.read_block_count() == 3
            pointer = await native.read_mdi_pointer()
            assert pointer.mdiprog == pointer.crntprog == 7
            # the machine reads no block ahead: the next blocks start from this state
            assert await native.read_modal_groups(1, block=1) == (ModalGroup(1, "G01", 1, True),)
            assert await native.read_modal_values("F", block=2) == (values["F"],)


async def test_the_client_checks_its_arguments_first() -> None:
    native = NativeClient("127.0.0.1", 1, timeout=IO_TIMEOUT)
    with pytest.raises(ValueError, match="group"):
        await native.read_modal_groups(23)
    with pytest.raises(ValueError, match="block"):
        await native.read_modal_groups(1, block=3)
    for address in ("G", "", "BD"):
        with pytest.raises(ValueError, match=f"address {address!r} is not one of B, D"):
            await native.read_modal_values(address)
    with pytest.raises(TypeError, match=r"address must be a letter .*got 5"):
        await native.read_modal_values(5)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="count"):
        await native.read_operator_messages(count=0)


async def test_the_controls_refusal_names_what_was_asked() -> None:
    async with serving(default_machine()) as served:
        async with NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native:
            # group type 19 (FANUC's group 20) and slot 14 (no address) the control has not
            for read, detail in (
                (native.read_g_codes(19), "cnc_rdgcode: type 19, block 0"),
                (native.read_commands(14, block=1), "cnc_rdcommand: type 14, block 1"),
            ):
                with pytest.raises(CncError, match=detail) as refused:
                    await read
                assert refused.value.ew == EW.NUMBER


def test_a_request_block_decodes_to_its_request() -> None:
    (request,) = calls.cnc_modal(CommandSet.FS30I, 101, 1).frames[0]
    again = type(request).from_block(RequestBlock(1, 1, 0x22, (3, 1, 0, 0, 0)))
    assert again == request


@pytest.mark.parametrize(
    ("entry", "problem"),
    [
        ('address = "B0.0"\nnumber = 2000\ntext = "X"', "not an A-area bit"),
        ('address = "A0.0"\nnumber = 1000\ntext = "X"', "2000..2999"),
        ('address = "A99.0"\nnumber = 2000\ntext = "X"', "outside the A area"),
        ('address = "A0.0"\nnumber = 2000', "text: missing"),
        ('address = "A0.0"\nnumber = 2000\ntext = "caf\u00e9"', "printable ASCII, got 'caf\u00e9'"),
        ('address = "A0.0"\nnumber = 2000\ntext = ""', "1..255 characters, got 0"),
        ('address = "A0.0"\nnumber = 2000\ntext = "X"\ncolor = 1', "color"),
    ],
)
def test_the_machine_file_checks_each_message(entry: str, problem: str, tmp_path: Path) -> None:
    text = MACHINE_16I.read_text().replace(
        "[pmc.R]", f"[[operator_messages]]\n{entry}\n\n[pmc.A]\nsize = 16\n[pmc.R]", 1
    )
    file = tmp_path / "bad.toml"
    file.write_text(text)
    with pytest.raises(MachineFileError, match=problem) as refused:
        load_machine(file)
    assert "operator_messages" in str(refused.value)


# --------------------------------------------------------------------------------------------
# Several paths


def test_each_path_answers_its_own_modal_state_and_pointer() -> None:
    """Path 2 runs a program of its own; path 1 stays at rest: the blocks of path word 2 carry
    path 2's codes, values and pointer, those of path 1 path 1's; path 3 is EW_PATH."""
    clock = ManualClock()
    machine = Machine(
        "twin",
        paths=[
            PathSpec(("X", "Z")),
            PathSpec(("U", "W"), programs=("O0020\nN5 G91 G01 U10. F300\nN6 M30\n",)),
        ],
        sim_clock=clock,
    )
    machine.cycle_start(path=2)
    clock.advance(0.5)
    adapter = NativeAdapter(machine, version=3)

    def on(path: int, command: int, *args: int) -> tuple[int, bytes]:
        raw = bytearray(block(command, *args))
        raw[4:6] = path.to_bytes(2, "big")
        return ask(adapter, bytes(raw))

    assert ModalGCodes.decode(on(2, 0x21, 0, 0)[1]).records == (ModalGCode(0x81),)
    assert ModalGCodes.decode(on(1, 0x21, 0, 0)[1]).records == (ModalGCode(0x00),)
    assert ModalAuxData.decode(on(2, 0x22, -2, 0)[1]).records[0] == ModalAux.of(10, True)
    assert ActivePointer.decode(on(2, 0x162)[1]) == ActivePointer(20, 1)
    assert ActivePointer.decode(on(1, 0x162)[1]) == ActivePointer(0, 0)
    assert on(3, 0x162) == (EW.PATH, b"")
    assert machine.modal_state(path=2).address("F").value == 300
    assert machine.program_pointer(path=1).blocks_run == 0


def test_a_kept_answer_follows_the_next_block() -> None:
    """The adapter answers a repeated modal request from what it kept while no block ran, and
    anew once one did."""
    clock = ManualClock()
    machine = message_machine(clock)
    adapter = NativeAdapter(machine, version=2)
    request = block(0x96, 0, 0)  # group 01
    first = ok(adapter, request)
    assert ok(adapter, request) == first
    assert GCodeRecords.decode(first).records[0].code == "G00"
    machine.cycle_start()
    clock.advance(1.0)
    machine.cycle_start()
    clock.advance(1.0)  # N30: G01
    assert GCodeRecords.decode(ok(adapter, request)).records[0].code == "G01"
    machine.reset()
    assert machine.modal_state() is machine.modal_state()  # made once while nothing runs
