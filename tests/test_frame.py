"""The frame of docs/protocol.md section 1 and its incremental decoder."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given
from hypothesis import strategies as st

from focas_net.errors import FrameError, ProtocolError
from focas_net.protocol import (
    DEFAULT_MAX_FRAME,
    HEADER_SIZE,
    Frame,
    FrameDecoder,
    encode_frame,
    scan_frames,
)

# Hand-written frames: u32 length (4 + payload), u16 command, u16 request_id, payload.
STATUS_REQUEST = bytes.fromhex("04000000 0100 0100")
PARAM_REQUEST = bytes.fromhex("08000000 0200 0200 2805 0100")
MACRO_ANSWER = bytes.fromhex("10000000 0300 0300 0000 6400 0800 39300000 0300")
THREE = STATUS_REQUEST + PARAM_REQUEST + MACRO_ANSWER
THREE_FRAMES = [
    Frame(0x0001, 1, b""),
    Frame(0x0002, 2, bytes.fromhex("2805 0100")),
    Frame(0x0003, 3, bytes.fromhex("0000 6400 0800 39300000 0300")),
]


def test_defaults() -> None:
    assert DEFAULT_MAX_FRAME == 65_536
    assert HEADER_SIZE == 8
    assert FrameDecoder().max_frame == DEFAULT_MAX_FRAME


def test_encode_frame_matches_hand_written_bytes() -> None:
    assert encode_frame(0x0001, 1) == STATUS_REQUEST
    assert encode_frame(0x0002, 2, bytes.fromhex("2805 0100")) == PARAM_REQUEST
    assert encode_frame(0xFFFF, 0xFFFF, b"\xab") == bytes.fromhex("05000000 ffff ffff ab")


def test_all_at_once() -> None:
    decoder = FrameDecoder()
    assert decoder.feed(THREE) == THREE_FRAMES
    assert decoder.buffered == 0


def test_one_byte_at_a_time() -> None:
    decoder = FrameDecoder()
    got: list[Frame] = []
    for i in range(len(THREE)):
        got += decoder.feed(THREE[i : i + 1])
        # a frame comes out exactly when its last byte is in
        if i + 1 == len(STATUS_REQUEST):
            assert got == THREE_FRAMES[:1]
    assert got == THREE_FRAMES
    assert decoder.buffered == 0


def test_empty_chunks_are_harmless() -> None:
    decoder = FrameDecoder()
    assert decoder.feed(b"") == []
    assert decoder.feed(THREE[:3]) == []
    assert decoder.feed(b"") == []
    assert decoder.feed(THREE[3:]) == THREE_FRAMES


def test_several_frames_in_one_chunk_with_a_partial_tail() -> None:
    decoder = FrameDecoder()
    chunk = STATUS_REQUEST + PARAM_REQUEST + MACRO_ANSWER[:5]
    assert decoder.feed(chunk) == THREE_FRAMES[:2]
    assert decoder.buffered == 5
    assert decoder.held == MACRO_ANSWER[:5]  # the same bytes, read without a call
    assert decoder.feed(MACRO_ANSWER[5:]) == THREE_FRAMES[2:]
    assert decoder.buffered == 0
    assert not decoder.held


@pytest.mark.parametrize("cut", [1, 2, 3, 4, 5, 6, 7])
def test_chunk_ending_mid_header(cut: int) -> None:
    decoder = FrameDecoder()
    assert decoder.feed(PARAM_REQUEST[:cut]) == []
    assert decoder.buffered == len(decoder.held) == cut
    assert decoder.feed(PARAM_REQUEST[cut:]) == [THREE_FRAMES[1]]
    assert decoder.buffered == len(decoder.held) == 0


@pytest.mark.parametrize("cut", [8, 9, 12, 19])
def test_chunk_ending_mid_body(cut: int) -> None:
    decoder = FrameDecoder()
    assert decoder.feed(STATUS_REQUEST + MACRO_ANSWER[:cut]) == [THREE_FRAMES[0]]
    assert decoder.buffered == cut
    assert decoder.feed(MACRO_ANSWER[cut:] + PARAM_REQUEST) == [THREE_FRAMES[2], THREE_FRAMES[1]]


def test_accepts_bytearray_and_memoryview() -> None:
    decoder = FrameDecoder()
    assert decoder.feed(bytearray(THREE[:10])) == [THREE_FRAMES[0]]
    assert decoder.feed(memoryview(THREE)[10:]) == THREE_FRAMES[1:]
    fresh = FrameDecoder()
    assert fresh.feed(memoryview(THREE)) == THREE_FRAMES
    assert all(type(f.payload) is bytes for f in THREE_FRAMES)


def test_frames_do_not_share_the_callers_buffer() -> None:
    decoder = FrameDecoder()
    chunk = bytearray(PARAM_REQUEST)
    [frame] = decoder.feed(chunk)
    chunk[8:] = b"\xff" * 4
    assert frame.payload == bytes.fromhex("2805 0100")


@pytest.mark.parametrize("max_frame", [4, 16, DEFAULT_MAX_FRAME])
def test_exactly_max_frame_is_accepted(max_frame: int) -> None:
    payload = bytes(range(256)) * ((max_frame - 4) // 256) + bytes((max_frame - 4) % 256)
    frame = encode_frame(0x0010, 9, payload)
    assert int.from_bytes(frame[:4], "little") == max_frame
    decoder = FrameDecoder(max_frame)
    assert decoder.feed(frame) == [Frame(0x0010, 9, payload)]
    # and byte by byte at a small ceiling too
    if max_frame <= 16:
        slow = FrameDecoder(max_frame)
        got: list[Frame] = []
        for i in range(len(frame)):
            got += slow.feed(frame[i : i + 1])
        assert got == [Frame(0x0010, 9, payload)]


@pytest.mark.parametrize("max_frame", [16, DEFAULT_MAX_FRAME])
def test_one_over_max_frame_is_rejected_at_the_length_field(max_frame: int) -> None:
    decoder = FrameDecoder(max_frame)
    with pytest.raises(FrameError):
        decoder.feed((max_frame + 1).to_bytes(4, "little"))
    assert decoder.buffered == 0


def test_oversize_length_rejected_before_any_body_is_fed() -> None:
    decoder = FrameDecoder()
    huge = bytes.fromhex("ffffffff")  # 4 GiB claimed
    assert decoder.feed(huge[:3]) == []
    assert decoder.buffered == 3
    with pytest.raises(FrameError):
        decoder.feed(huge[3:])  # the fourth length byte: no header rest, no body fed
    assert decoder.buffered == 0  # nothing buffered, nothing allocated for the claimed body


def test_oversize_length_after_valid_frames_in_one_chunk() -> None:
    decoder = FrameDecoder()
    with pytest.raises(FrameError):
        decoder.feed(STATUS_REQUEST + (DEFAULT_MAX_FRAME + 1).to_bytes(4, "little"))
    assert decoder.buffered == 0


@pytest.mark.parametrize("length", [0, 1, 2, 3])
def test_length_below_four_is_rejected(length: int) -> None:
    decoder = FrameDecoder()
    with pytest.raises(FrameError):
        decoder.feed(length.to_bytes(4, "little"))
    assert decoder.buffered == 0


def test_length_four_is_an_empty_payload() -> None:
    assert FrameDecoder().feed(bytes.fromhex("04000000 0500 0700")) == [Frame(5, 7, b"")]


def test_poisoned_after_a_violation() -> None:
    decoder = FrameDecoder()
    with pytest.raises(FrameError) as first:
        decoder.feed(bytes.fromhex("02000000"))
    for _ in range(3):
        with pytest.raises(FrameError) as again:
            decoder.feed(STATUS_REQUEST)  # a valid frame is refused too
        assert str(again.value) == str(first.value) and again.value.frames == []
    with pytest.raises(FrameError):
        decoder.feed(b"")
    assert decoder.buffered == 0


def test_frame_error_is_a_protocol_error() -> None:
    assert issubclass(FrameError, ProtocolError)


def test_max_frame_below_four_is_refused() -> None:
    with pytest.raises(ValueError):
        FrameDecoder(3)


# -- hypothesis -----------------------------------------------------------------------------

frames_st = st.lists(
    st.builds(
        Frame,
        st.integers(0, 0xFFFF),
        st.integers(0, 0xFFFF),
        st.binary(max_size=300),
    ),
    max_size=12,
)


@given(frames=frames_st, data=st.data())
def test_random_splits_decode_to_the_same_frames(frames: list[Frame], data: st.DataObject) -> None:
    stream = b"".join(encode_frame(*f) for f in frames)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(stream)), max_size=40), label="cuts"))
    bounds = [0, *cuts, len(stream)]
    decoder = FrameDecoder()
    got: list[Frame] = []
    for a, b in itertools.pairwise(bounds):
        got += decoder.feed(stream[a:b])
    assert got == frames
    assert decoder.buffered == 0


@given(
    frames=st.lists(
        st.builds(Frame, st.integers(0, 0xFFFF), st.integers(0, 0xFFFF), st.binary(max_size=40)),
        min_size=1,
        max_size=6,
    ),
    extra=st.integers(1, 1000),
    split=st.integers(0, 3),
)
def test_oversize_frame_anywhere_in_the_stream_is_rejected(
    frames: list[Frame], extra: int, split: int
) -> None:
    max_frame = 44
    stream = b"".join(encode_frame(*f) for f in frames)
    bad = (max_frame + extra).to_bytes(4, "little")
    decoder = FrameDecoder(max_frame)
    got = decoder.feed(stream + bad[:split])
    assert got == frames
    with pytest.raises(FrameError):
        decoder.feed(bad[split:])
    assert decoder.buffered == 0


@given(st.binary(max_size=200), st.integers(4, 64))
def test_arbitrary_bytes_give_frames_or_frame_error(blob: bytes, max_frame: int) -> None:
    decoder = FrameDecoder(max_frame)
    try:
        frames = decoder.feed(blob)
    except FrameError:
        assert decoder.buffered == 0
        return
    assert sum(HEADER_SIZE + len(f.payload) for f in frames) + decoder.buffered == len(blob)


def test_violation_carries_the_frames_decoded_before_it() -> None:
    decoder = FrameDecoder(max_frame=64)
    good = bytes.fromhex("0400000001000700") + bytes.fromhex("06000000030008000500")
    bad = bytes.fromhex("ffff0000")
    with pytest.raises(FrameError) as info:
        decoder.feed(good + bad)
    assert info.value.frames == [Frame(1, 7, b""), Frame(3, 8, b"\x05\x00")]
    with pytest.raises(FrameError) as again:
        decoder.feed(bytes.fromhex("0400000001000900"))
    assert again.value.frames == []  # poisoned: nothing more is decoded, nothing repeated


# -- scan_frames: the decoder's own scan, pure --------------------------------------------


def _encoded(frames: list[Frame]) -> bytes:
    return b"".join(encode_frame(*f) for f in frames)


@given(frames=frames_st, tail=st.data())
def test_scan_finds_the_whole_frames_and_where_they_end(
    frames: list[Frame], tail: st.DataObject
) -> None:
    stream = _encoded(frames)
    partial = tail.draw(st.builds(encode_frame, st.just(1), st.just(2), st.binary(max_size=20)))
    cut = partial[: tail.draw(st.integers(0, len(partial) - 1), label="cut")]
    found, end, bad = scan_frames(stream + cut, DEFAULT_MAX_FRAME)
    assert [Frame(*f) for f in found] == frames
    assert (end, bad) == (len(stream), -1)


@given(frames=frames_st, garbage=st.binary(max_size=30))
def test_scan_reads_a_view_up_to_size_and_copies_every_payload(
    frames: list[Frame], garbage: bytes
) -> None:
    stream = _encoded(frames)
    buffer = bytearray(stream + garbage)
    found, end, bad = scan_frames(memoryview(buffer), DEFAULT_MAX_FRAME, len(stream))
    buffer[:] = bytes(len(buffer))  # the buffer is reused: what was found must not change
    assert [Frame(*f) for f in found] == frames
    assert all(type(payload) is bytes for _, _, payload in found)
    assert (end, bad) == (len(stream), -1)


@given(
    frames=frames_st,
    length=st.one_of(st.integers(0, 3), st.integers(45, 0xFFFFFFFF)),
    rest=st.binary(max_size=12),
)
def test_scan_reports_a_length_out_of_bounds_as_soon_as_it_is_in(
    frames: list[Frame], length: int, rest: bytes
) -> None:
    stream = _encoded([f for f in frames if len(f.payload) <= 40])
    found, end, bad = scan_frames(stream + length.to_bytes(4, "little") + rest, 44)
    assert _encoded([Frame(*f) for f in found]) == stream
    assert (end, bad) == (len(stream), length)


@given(st.binary(max_size=200), st.integers(4, 64))
def test_the_decoder_rejects_exactly_what_the_scan_rejects(blob: bytes, max_frame: int) -> None:
    found, end, bad = scan_frames(blob, max_frame)
    decoder = FrameDecoder(max_frame)
    try:
        decoded = decoder.feed_raw(blob)
    except FrameError as exc:
        assert bad >= 0 and exc.frames == found
        return
    assert bad == -1 and decoded == found
    assert decoder.buffered == len(blob) - end
