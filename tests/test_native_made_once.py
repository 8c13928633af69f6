"""What the native client makes once: a library call for equal arguments (its frames encoded
once), and a call's result for an answer that repeats; what changes is made again."""

from __future__ import annotations

from decimal import Decimal

import pytest
from support import IO_TIMEOUT, serving

from focas_net.client.native import NativeClient
from focas_net.native import calls
from focas_net.native.calls import CommandSet, LibraryCall
from focas_net.native.macros import MacroReadRequest
from focas_net.native.pmc import NativePmcData, PmcWriteRequest


@pytest.mark.parametrize("cs", list(CommandSet))
def test_equal_arguments_give_one_call_encoded_as_a_fresh_one(cs: CommandSet) -> None:
    call = calls.cnc_rdmacro(cs, 100)
    assert calls.cnc_rdmacro(cs, 100) is call
    assert calls.cnc_rdmacro(cs, 101) is not call
    fresh = LibraryCall("cnc_rdmacro", ((MacroReadRequest(100, 100),),))
    assert call.parts == fresh.parts and call.encode() == fresh.encode()


def test_pmc_values_given_as_a_list_or_a_tuple_give_one_call() -> None:
    cs = CommandSet.FS30I
    call = calls.pmc_wrpmcrng(cs, 9, 0, 20, 23, [1, 2, 3, 4])
    assert calls.pmc_wrpmcrng(cs, 9, 0, 20, 23, (1, 2, 3, 4)) is call
    assert calls.pmc_wrpmcrng(cs, 9, 0, 20, 23, [1, 2, 3, 5]) is not call
    data = NativePmcData.from_values(0, [1, 2, 3, 4])
    fresh = LibraryCall("pmc_wrpmcrng", ((PmcWriteRequest(20, 23, 9, 0, data),),))
    assert call.encode() == fresh.encode()


async def test_a_repeated_answer_gives_the_result_made_before_and_a_new_one_a_new_result() -> None:
    async with (
        serving() as served,
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as cnc,
    ):
        served.machine.write_macro(100, Decimal("12.5"))
        first = await cnc.read_macro(100)
        status = await cnc.read_status()
        assert first == Decimal("12.5")
        assert await cnc.read_macro(100) is first
        assert await cnc.read_status() is status
        served.machine.write_macro(100, Decimal("-3.25"))
        assert await cnc.read_macro(100) == Decimal("-3.25")
        served.machine.write_macro(100, None)
        assert await cnc.read_macro(100) is None  # vacant: a result of None is kept too
        assert await cnc.read_macro(100) is None
        served.machine.write_macro(100, Decimal("12.5"))
        assert await cnc.read_macro(100) == first
