"""The native side's memos of pure results. The front end: a request body seen before gives
its blocks again, a block of a read gives its typed request again; whatever they hold, the
answers are those computed from nothing, a body is looked up by its bytes whatever holds them,
and what cannot be decoded is refused every time."""

from __future__ import annotations

from dataclasses import replace
from decimal import Decimal

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import focas_net.native.requests as requests_module
from focas_net.adapters import NativeAdapter
from focas_net.native import (
    MacroReadRequest,
    MacroWriteRequest,
    NativeFrameError,
    NativePayloadError,
    RequestBlock,
    ScaledNumber,
    ScaledValues,
    decode_frame,
    decode_response_body,
    encode_request_body,
)
from focas_net.sim import default_machine

#: Variables of the built-in machine's common range, read and written below.
NUMBERS = st.integers(100, 110)
VALUES = st.one_of(
    st.none(), st.decimals(min_value=-9999, max_value=9999, places=3, allow_nan=False)
)
#: (read, first, last) or (write, number, value) steps, read bodies repeating.
STEPS = st.lists(
    st.one_of(
        st.tuples(st.just("read"), NUMBERS, st.integers(0, 3)),
        st.tuples(st.just("write"), NUMBERS, VALUES),
    ),
    min_size=1,
    max_size=20,
)


def _forget() -> None:
    requests_module._READS.clear()


def _read_body(first: int, extra: int) -> bytes:
    # two blocks, so that one body holds equal blocks that are distinct objects
    block = MacroReadRequest(first, first + extra).to_block(1)
    return encode_request_body([block, block])


@settings(max_examples=60, deadline=None)
@given(STEPS)
def test_memos_answer_what_is_computed_from_nothing(
    steps: list[tuple[str, int, int | Decimal | None]],
) -> None:
    machine = default_machine()
    adapter = NativeAdapter(machine)
    for action, number, arg in steps:
        if action == "write":
            assert not isinstance(arg, int)
            machine.write_macro(number, arg)
            continue
        assert isinstance(arg, int)
        body = _read_body(number, arg)
        remembered = adapter.answer(body)
        _forget()
        assert remembered == NativeAdapter(machine).answer(body)  # its own memo empty too
        assert adapter.answer(body) == remembered  # the memos filled again, the same answer


@pytest.mark.parametrize("wrap", [bytes, bytearray, memoryview])
def test_a_body_is_looked_up_by_its_bytes(wrap: type[bytes | bytearray | memoryview]) -> None:
    adapter = NativeAdapter(default_machine())
    body = _read_body(100, 0)
    first = adapter.answer(body)
    # an equal body in another object, mutable or a view, is the body seen before
    assert adapter.answer(wrap(bytearray(body))) is first


def test_a_broken_body_is_refused_every_time() -> None:
    adapter = NativeAdapter(default_machine())
    broken = _read_body(100, 0)[:-3]
    for _ in range(2):
        with pytest.raises(NativeFrameError, match=r"bad length|truncated|follow"):
            adapter.answer(broken)


def test_a_read_block_decodes_once_and_a_write_block_every_time() -> None:
    read = MacroReadRequest(120, 121).to_block(1)
    same = RequestBlock(read.device, read.path, read.command, read.args)  # equal, not the same
    first = MacroReadRequest.from_block(read)
    assert first == MacroReadRequest(120, 121)
    assert MacroReadRequest.from_block(same) is first
    block = WRITE.to_block(1)
    write = MacroWriteRequest.from_block(block)
    assert write == WRITE
    assert MacroWriteRequest.from_block(block) is not write  # extra bytes: not kept


#: #120 = 12.5, base 10.
WRITE = MacroWriteRequest(120, ScaledNumber(mantissa=125, base=10, decimals=1))


def test_a_block_missing_its_extra_bytes_is_refused_every_time() -> None:
    bare = replace(WRITE.to_block(1), extra=b"")
    for _ in range(2):
        with pytest.raises(NativePayloadError):
            MacroWriteRequest.from_block(bare)


@given(st.integers(-(2**31), 2**31 - 1), st.integers(0, 9))
def test_a_macro_reads_as_its_coefficient_and_decimals(coefficient: int, decimals: int) -> None:
    """A value the machine holds travels as its digits and its decimals as they are (1.50 is
    (150, 2)); a vacant one as (0, -1)."""
    machine = default_machine()
    adapter = NativeAdapter(machine)
    body = encode_request_body([MacroReadRequest(100, 101).to_block(1)])
    machine.write_macro(100, Decimal(coefficient).scaleb(-decimals))
    machine.write_macro(101, None)
    data = decode_response_body(decode_frame(adapter.answer(body))[2])[0].data
    assert ScaledValues.decode(data).values == (
        ScaledNumber(coefficient, decimals),
        ScaledNumber(0, -1),
    )
