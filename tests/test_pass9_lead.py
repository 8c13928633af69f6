"""A usage error keeps what was typed as it was typed: runs of spaces inside a value stay. The
native client's parameter write does not rest on the number word of the 30i set's information
answer, whose place is not known."""

from __future__ import annotations

from typing import Any

import pytest
from cli_support import fails

from focas_net.adapters import _native_data
from focas_net.cli import EXIT_USAGE
from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError
from focas_net.native.items import ParamInfo3
from focas_net.sim import Machine, ParamKind


@pytest.mark.parametrize("typed", [" ", "  ", "   "])
async def test_a_usage_error_quotes_a_host_of_spaces_as_typed(typed: str) -> None:
    line = await fails(EXIT_USAGE, "status", "--host", typed, prefix="focas-net")
    assert f"empty host {typed!r}" in line


async def test_a_usage_error_is_still_one_line() -> None:
    line = await fails(EXIT_USAGE, "status", "--port", "x" * 200, prefix="focas-net")
    assert "x" * 200 in line


def _numberless(prev_no: int, next_no: int, number: int, *rest: Any) -> ParamInfo3:
    """A 30i information answer whose number words hold something else than numbers."""
    return ParamInfo3(-1, -1, 0x5A5A, *rest)


async def test_a_30i_write_holds_without_the_information_answers_number(
    both_clients: tuple[Machine, FocasClient, NativeClient], monkeypatch: pytest.MonkeyPatch
) -> None:
    machine, _cnc, native = both_clients
    monkeypatch.setattr(_native_data, "ParamInfo3", _numberless)
    machine.set_panel(0, 1, 0)  # MDI, parameter writes enabled
    byte = next(
        n for n in range(1, 10000) if (i := machine.param_item(n)) and i.kind is ParamKind.BYTE
    )
    await native.write_param(byte, 7)
    assert await native.read_param(byte) == 7
    for value in (1, 10**6):  # sent and refused by the CNC; refused before it is sent
        with pytest.raises(CncError) as refused:
            await native.write_param(7000, value)
        assert refused.value.ew == EW.NUMBER
    with pytest.raises(ValueError, match=f"parameter {byte} is a byte parameter: 1000000"):
        await native.write_param(byte, 10**6)
    assert machine.param_item(7000) is None
