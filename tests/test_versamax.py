"""VersaMax Read Configuration (docs/protocol.md section 5): the IC200MDD844 record, board ids."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import PayloadError
from focas_net.protocol import (
    COMMANDS,
    MAX_CONFIG_CHUNK,
    EwReply,
    VersaMaxReply,
    VersaMaxRequest,
)
from focas_net.versamax import BoardId, IOModuleRecord, ModuleType, RefDesc, RefType

# The manual's 82-byte Read Configuration Reply, copied from docs/protocol.md section 5.
REPLY_82 = bytes.fromhex(
    "00 52 00 03 00 00 80 08 80 80 44 38 34 34 32 00"
    "00 00 00 00 00 00 00 00 00 00 00 00 00 00 34 00"
    "80 08 80 80 30 00 01 00 01 00 00 00 00 00 03 00"
    "00 00 02 00 00 00 00 00 01 10 11 00 02 00 2C 00"
    "02 12 08 00 02 00 2E 00 00 00 00 00 00 00 00 00"
    "00 00"
)
RECORD_76 = REPLY_82[6:]


def mdd844() -> IOModuleRecord:
    """The IC200MDD844 as ``build`` makes it: 16 outputs (primary), 16 inputs (secondary)."""
    return IOModuleRecord.build(
        BoardId.make(ModuleType.DISCRETE_DC, outputs=16),
        BoardId.make(ModuleType.DISCRETE_DC, inputs=16),
        "D844",
        [(RefType.I, 17, 2), (RefType.Q, 8, 2)],
        setup=3,
        default_inputs=b"\x00\x00",
        default_outputs=b"\x00\x00",
        module_data=b"\x00\x00",
    )


def test_the_golden_reply_is_82_bytes_of_a_76_byte_record() -> None:
    assert len(REPLY_82) == 82
    assert len(RECORD_76) == 76


def test_build_encodes_the_manual_record_exactly() -> None:
    record = mdd844()
    assert record.encode() == RECORD_76
    assert VersaMaxReply(0, 3, 0, record.encode()).encode() == REPLY_82


def test_decoding_the_golden_reply() -> None:
    answer = COMMANDS[0x0201].response.decode(b"\x00\x00" + REPLY_82)
    assert answer == VersaMaxReply(rack=0, slot=3, offset=0, data=RECORD_76)
    record = IOModuleRecord.decode(answer.data)
    assert record.inputs == 16
    assert record.outputs == 16
    assert record.label == "D844"
    i_ref = record.reference(RefType.I)
    q_ref = record.reference(RefType.Q)
    assert i_ref is not None and q_ref is not None
    assert i_ref.offset == 17
    assert q_ref.offset == 8
    assert record.setup == 3
    assert record.setup & 1  # defaults defined
    assert record.setup & 2  # fault reporting
    assert record.reference(RefType.AI) is None
    assert record.references == (RefDesc(1, 16, 17, 2, 44), RefDesc(2, 18, 8, 2, 46))
    assert (record.input_segment_mode, record.output_segment_mode) == (0, 0)
    assert record.default_inputs == b"\x00\x00"
    assert record.default_outputs == b"\x00\x00"
    assert record.module_data == b"\x00\x00"
    assert record == mdd844()


def test_board_ids_in_the_golden_record_are_msb_first() -> None:
    assert RECORD_76[0:2] == b"\x80\x08"  # secondary
    assert RECORD_76[2:4] == b"\x80\x80"  # primary
    record = IOModuleRecord.decode(RECORD_76)
    assert record.secondary_id == BoardId(0x8008)
    assert record.primary_id == BoardId(0x8080)


@pytest.mark.parametrize(
    ("value", "valid", "module_type", "current", "diagnostics", "outputs", "inputs"),
    [
        # 100 00 0 00 0000 1000: discrete DC, 8 input pairs
        (0x8008, True, ModuleType.DISCRETE_DC, False, 0, 0, 16),
        # 100 00 0 00 1000 0000: discrete DC, 8 output pairs
        (0x8080, True, ModuleType.DISCRETE_DC, False, 0, 16, 0),
        # 100 01 0 01 0010 0011: discrete AC, diagnostics 1, 2 output pairs, 3 input pairs
        (0x8923, True, ModuleType.DISCRETE_AC, False, 1, 4, 6),
        # 100 10 1 10 0010 0100: analog, current, diagnostics 2, 2 out channels, 4 in channels
        (0x9624, True, ModuleType.ANALOG, True, 2, 2, 4),
        # 100 10 0 11 0000 1000: analog, voltage, diagnostics 3, 8 input channels
        (0x9308, True, ModuleType.ANALOG, False, 3, 0, 8),
        # bits 15-13 not 100
        (0x4008, False, ModuleType.DISCRETE_DC, False, 0, 0, 16),
    ],
)
def test_board_id_fields(
    value: int,
    valid: bool,
    module_type: ModuleType,
    current: bool,
    diagnostics: int,
    outputs: int,
    inputs: int,
) -> None:
    board = BoardId(value)
    assert board.valid is valid
    assert board.module_type is module_type
    assert board.analog_current is current
    assert board.diagnostics == diagnostics
    assert board.outputs == outputs
    assert board.inputs == inputs


def test_board_id_make_gives_the_hand_computed_values() -> None:
    assert BoardId.make(ModuleType.DISCRETE_DC, inputs=16).value == 0x8008
    assert BoardId.make(ModuleType.DISCRETE_DC, outputs=16).value == 0x8080
    assert BoardId.make(ModuleType.DISCRETE_AC, inputs=6, outputs=4, diagnostics=1).value == 0x8923
    assert (
        BoardId.make(ModuleType.ANALOG, inputs=4, outputs=2, current=True, diagnostics=2).value
        == 0x9624
    )


@pytest.mark.parametrize(
    "kwargs",
    [
        {"inputs": 3},  # discrete points come in pairs
        {"outputs": 1},
        {"inputs": 32},  # 16 pairs do not fit in 4 bits
        {"diagnostics": 4},
        {"inputs": -2},
    ],
)
def test_board_id_make_rejects_impossible_fields(kwargs: dict[str, int]) -> None:
    with pytest.raises(ValueError):
        BoardId.make(ModuleType.DISCRETE_DC, **kwargs)  # type: ignore[arg-type]


def test_analog_board_ids_count_channels_not_pairs() -> None:
    with pytest.raises(ValueError):
        BoardId.make(ModuleType.ANALOG, inputs=16)
    assert BoardId.make(ModuleType.ANALOG, inputs=15).inputs == 15


@given(
    module_type=st.sampled_from(
        [ModuleType.DISCRETE_DC, ModuleType.DISCRETE_AC, ModuleType.ANALOG]
    ),
    ins=st.integers(0, 15),
    outs=st.integers(0, 15),
    current=st.booleans(),
    diagnostics=st.integers(0, 3),
)
def test_board_id_make_and_fields_agree(
    module_type: ModuleType, ins: int, outs: int, current: bool, diagnostics: int
) -> None:
    per = 1 if module_type is ModuleType.ANALOG else 2
    board = BoardId.make(
        module_type,
        inputs=ins * per,
        outputs=outs * per,
        current=current,
        diagnostics=diagnostics,
    )
    assert board.valid
    assert 0 <= board.value <= 0xFFFF
    assert board.module_type is module_type
    assert board.analog_current is current
    assert board.diagnostics == diagnostics
    assert board.inputs == ins * per
    assert board.outputs == outs * per


def test_ref_types() -> None:
    assert (RefType.I, RefType.Q, RefType.AI, RefType.AQ) == (16, 18, 10, 12)
    assert RefType.I.is_input and RefType.AI.is_input
    assert not RefType.Q.is_input and not RefType.AQ.is_input


def test_build_without_defaults_has_no_default_offsets() -> None:
    record = IOModuleRecord.build(
        BoardId.make(ModuleType.ANALOG, inputs=4),
        BoardId.make(ModuleType.ANALOG, outputs=2),
        "ALG4",
        [(RefType.AI, 1, 8), (RefType.AQ, 1, 4)],
        setup=2,
    )
    assert [r.defaults_offset for r in record.references] == [0, 0]
    assert [r.sequence for r in record.references] == [1, 2]
    data = record.encode()
    # 26 header + 24 fixed + 2 x 8 references + 4 segment modes, no defaults, no module data
    assert len(data) == 26 + 24 + 16 + 4
    assert data[8:10] == (24 + 16 + 4).to_bytes(2, "little")
    assert data[24:26] == (52).to_bytes(2, "little")  # 44 padded to a multiple of 26
    assert IOModuleRecord.decode(data) == record
    assert record.inputs == 4 and record.outputs == 2


def test_encode_rejects_a_label_that_is_not_four_characters() -> None:
    record = mdd844()
    for label in ("D84", "D8444", ""):
        with pytest.raises(ValueError):
            IOModuleRecord(
                record.secondary_id, record.primary_id, label, record.references
            ).encode()


def test_encode_rejects_defaults_of_the_wrong_size() -> None:
    with pytest.raises(ValueError):
        IOModuleRecord.build(
            BoardId(0x8080),
            BoardId(0x8008),
            "D844",
            [(RefType.I, 17, 2), (RefType.Q, 8, 2)],
            setup=1,
            default_inputs=b"\x00",
            default_outputs=b"\x00\x00",
        ).encode()
    with pytest.raises(ValueError):  # setup bit 0 clear: no defaults may be sent
        IOModuleRecord.build(
            BoardId(0x8080), BoardId(0x8008), "D844", [(RefType.I, 17, 2)], default_inputs=b"\x00"
        ).encode()


def test_encode_rejects_a_board_id_wider_than_16_bits_with_value_error() -> None:
    record = IOModuleRecord(BoardId(0x1_8008), BoardId(0x8080), "D844")
    with pytest.raises(ValueError):
        record.encode()


def test_encode_rejects_an_unknown_reference_type() -> None:
    record = IOModuleRecord(BoardId(0x8008), BoardId(0x8080), "D844", (RefDesc(1, 5, 0, 2, 0),))
    with pytest.raises(ValueError):
        record.encode()


def test_record_decode_rejects_broken_records() -> None:
    with pytest.raises(PayloadError):
        IOModuleRecord.decode(RECORD_76[:49])  # shorter than header + fixed fields
    with pytest.raises(PayloadError):
        IOModuleRecord.decode(RECORD_76[:-1])  # additional length 50, 49 carried
    with pytest.raises(PayloadError):
        IOModuleRecord.decode(RECORD_76 + b"\x00")  # one byte too many
    # claim 3 %I references: they run past the record
    many_refs = bytearray(RECORD_76)
    many_refs[26 + 6] = 3
    many_refs[26 + 8] = 3
    with pytest.raises(PayloadError):
        IOModuleRecord.decode(bytes(many_refs))
    # module-specific data claimed longer than what is carried
    long_md = bytearray(RECORD_76)
    long_md[26 + 18] = 9
    with pytest.raises(PayloadError):
        IOModuleRecord.decode(bytes(long_md))


def test_request_and_reply_datagram_checks() -> None:
    request = COMMANDS[0x0201].request
    with pytest.raises(PayloadError):
        request.decode(bytes.fromhex("00 8000 03 00"))  # 5 bytes
    with pytest.raises(PayloadError):
        request.decode(bytes.fromhex("00 8000 03 0000 00"))  # 7 bytes
    with pytest.raises(PayloadError):
        VersaMaxReply.decode(REPLY_82[:-1])  # length field 82, 81 bytes carried
    with pytest.raises(PayloadError):
        VersaMaxReply.decode(bytes.fromhex("00 0600 03"))  # shorter than its header
    assert VersaMaxReply.decode(bytes.fromhex("01 0600 09 1000")) == VersaMaxReply(1, 9, 16, b"")
    with pytest.raises(ValueError):
        VersaMaxRequest(256, 128, 3, 0).encode()  # rack is a byte


def test_reading_a_record_by_offset_reassembles_it() -> None:
    """A record read in chunks of at most MAX_CONFIG_CHUNK bytes, by offset, reassembles."""
    record = IOModuleRecord.build(
        BoardId.make(ModuleType.ANALOG, inputs=8),
        BoardId.make(ModuleType.ANALOG, outputs=4),
        "ALG8",
        [(RefType.AI, 1, 16), (RefType.AQ, 1, 8)],
        setup=1,
        default_inputs=bytes(range(16)),
        default_outputs=bytes(range(8)),
        module_data=bytes(range(200)),
    ).encode()
    assert len(record) > MAX_CONFIG_CHUNK
    codec = COMMANDS[0x0201].response
    pieces = []
    for offset in range(0, len(record), MAX_CONFIG_CHUNK):
        chunk = record[offset : offset + MAX_CONFIG_CHUNK]
        wire = codec.encode(VersaMaxReply(0, 4, offset, chunk))
        reply = codec.decode(wire)
        assert not isinstance(reply, EwReply)
        assert reply.offset == offset
        pieces.append(reply.data)
    decoded = IOModuleRecord.decode(b"".join(pieces))
    assert decoded.module_data == bytes(range(200))
    assert decoded.default_inputs == bytes(range(16))
    assert decoded.inputs == 8 and decoded.outputs == 4
