"""The native client on parameters of every FANUC type: bit parameters as 0..255 and real
parameters through ``read_param_real``, as the packed client gives them, in both command sets
(the machine files of the live tests with FANUC's library, ``tests/data/fwlib_*_machine.toml``).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path

import pytest
from support import IO_TIMEOUT, Served, serving

from focas_net.client import FocasClient, NativeClient
from focas_net.errors import EW, CncError
from focas_net.native import CommandSet
from focas_net.sim import load_machine

DATA = Path(__file__).with_name("data")
FILES = {"16i": DATA / "fwlib_16i_machine.toml", "30i": DATA / "fwlib_30i_machine.toml"}


@pytest.fixture(params=sorted(FILES))
async def served(request: pytest.FixtureRequest) -> AsyncIterator[Served]:
    async with serving(load_machine(FILES[request.param])) as s:
        yield s


@pytest.fixture
async def both(served: Served) -> AsyncIterator[tuple[NativeClient, FocasClient]]:
    async with (
        NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
        FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
    ):
        yield native, packed


async def test_every_parameter_reads_as_the_packed_client_reads_it(
    served: Served, both: tuple[NativeClient, FocasClient]
) -> None:
    native, packed = both
    for number in served.machine.param_numbers():
        item = served.machine.param_item(number)
        assert item is not None
        for axis in (1, 2, 3) if item.axis else (0,):
            want = await packed.read_param_real(number, axis=axis)
            assert await native.read_param_real(number, axis=axis) == want, number
            assert await native.read_param_value(number, axis=axis) == (
                await packed.read_param_value(number, axis=axis)
            ), number
            if item.width != 8:
                assert await native.read_param(number, axis=axis) == (
                    await packed.read_param(number, axis=axis)
                )
    # a bit parameter as its eight bits, a real one with its decimals
    assert [await native.read_param(1815, axis=a) for a in (1, 2, 3)] == [0xB0, 0x01, 0xFF]
    assert await native.read_param_real(1451) == Decimal("12.345")
    assert await native.read_param_real(1420, axis=3) == Decimal("3.1")
    with pytest.raises(ValueError, match="read_param_real"):
        await native.read_param(1451)


async def test_bit_parameters_are_written_as_0_to_255(
    both: tuple[NativeClient, FocasClient],
) -> None:
    native, packed = both
    await packed.sim.set_panel("MDI", pwe=True)
    await native.write_param(1815, 0xC3, axis=2)
    assert await packed.read_param(1815, axis=2) == 0xC3
    await native.write_param(3401, "0b10000001")
    assert await packed.read_param(3401) == 0x81
    await native.write_param_bit(3401, 6, True)
    assert await packed.read_param(3401) == 0xC1
    await native.write_param_bit(3401, 7, False)
    assert await native.read_param(3401) == 0x41
    with pytest.raises(ValueError, match=r"0\.\.255"):
        await native.write_param(3401, 256)
    with pytest.raises(ValueError, match=r"0\.\.255"):
        await native.write_param(3401, -1)


async def test_real_parameters_are_written_in_the_30i_set_only(
    both: tuple[NativeClient, FocasClient],
) -> None:
    native, packed = both
    await packed.sim.set_panel("MDI", pwe=True)
    # a value with decimals to a parameter its information does not give as real (or bit,
    # in the 16i set): refused in the packed client's words, nothing written
    parts = await packed.read_param(6711)
    with pytest.raises(ValueError, match=r"parameter 6711 is not a real parameter: 1\.5 is no"):
        await native.write_param(6711, Decimal("1.5"))
    assert await packed.read_param(6711) == parts
    # a value that does not fit a parameter: the same words from both
    cases: tuple[tuple[int, int | Decimal | str], ...] = (
        (6711, Decimal("1.5")), (6711, "1.5"), (6711, 2**31), (3216, 99999), (3216, -40000),
    )  # fmt: skip
    for number, value in cases:
        said = set()
        for client in (native, packed):
            with pytest.raises(ValueError) as unfit:
                await client.write_param(number, value)
            said.add(str(unfit.value))
        assert len(said) == 1, said
    if native.command_set is CommandSet.FS16I:
        # the 16i set has no way to write a real parameter: EW_LENGTH, as FANUC's library,
        # whether the value has decimals or not
        for real in (5, Decimal("12.5"), "12.5"):
            with pytest.raises(CncError) as refused:
                await native.write_param(1451, real)
            assert refused.value.ew == EW.LENGTH
        assert await packed.read_param_real(1451) == Decimal("12.345")
        return
    await native.write_param(1451, Decimal("-1.5"))
    assert await packed.read_param_real(1451) == Decimal("-1.500")
    await native.write_param(1420, "2.5", axis=2, width=8)
    assert await packed.read_param_real(1420, axis=2) == Decimal("2.5")
    with pytest.raises(CncError) as inexact:
        await native.write_param(1451, Decimal("1.2345"))
    assert inexact.value.ew == EW.DATA
    with pytest.raises(ValueError, match="parameter 1451: not a number: 'many'"):  # as packed
        await native.write_param(1451, "many")
    with pytest.raises(ValueError, match="no bits"):
        await native.write_param_bit(1451, 0, True)
