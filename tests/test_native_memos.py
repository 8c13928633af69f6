"""The native side's memos of pure results. The front end: a request body seen before gives
its blocks again, a block of a read gives its typed request again; whatever they hold, the
answers are those computed from nothing, and what cannot be decoded is refused every time."""

from __future__ import annotations

from dataclasses import replace
from decimal import Decimal

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import focas_net.adapters.native as adapter_module
import focas_net.native.requests as requests_module
from focas_net.adapters import NativeAdapter
from focas_net.adapters.native import _macro_parts
from focas_net.native import (
    MacroReadRequest,
    MacroWriteRequest,
    NativeFrameError,
    NativePayloadError,
    RequestBlock,
    ScaledNumber,
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
    adapter_module._REQUEST_BODIES.clear()
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


def test_a_body_seen_before_is_not_decoded_again() -> None:
    adapter = NativeAdapter(default_machine())
    body = _read_body(100, 0)
    adapter.answer(body)
    blocks = adapter_module._REQUEST_BODIES[body]
    assert adapter._blocks(bytes(bytearray(body))) is blocks  # an equal body: the same blocks
    assert adapter._blocks(bytearray(body)) is blocks  # a mutable one is looked up as bytes


def test_a_broken_body_is_refused_every_time() -> None:
    adapter = NativeAdapter(default_machine())
    broken = _read_body(100, 0)[:-3]
    for _ in range(2):
        with pytest.raises(NativeFrameError, match=r"bad length|truncated|follow"):
            adapter.answer(broken)
    assert broken not in adapter_module._REQUEST_BODIES


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


@given(st.decimals(allow_nan=False, allow_infinity=False, min_value=-(10**30), max_value=10**30))
def test_macro_parts_are_the_coefficient_and_its_decimals(value: Decimal) -> None:
    sign, digits, exponent = value.as_tuple()
    assert isinstance(exponent, int)
    coefficient = int("".join(map(str, digits)))
    assert _macro_parts(value) == ((-coefficient if sign else coefficient), -exponent)
    assert _macro_parts(None) == (0, -1)
