"""Parameters have their FANUC type: bit parameters are eight bits, written and shown as such;
real parameters a mantissa with decimals (REALPRM on the wire)."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path

import pytest
from cli_support import Cli
from support import REAL_FILE, serving

from focas_net.cli import EXIT_CNC, EXIT_USAGE
from focas_net.client import FocasClient
from focas_net.errors import EW, CncError
from focas_net.protocol import (
    Command,
    DataRequest,
    ParamAttributes,
    ParamAttributesRequest,
    ParamDataType,
    ParamValue,
)
from focas_net.sim import (
    DataItem,
    Machine,
    MachineError,
    ParamKind,
    default_machine,
    load_machine,
)
from focas_net.web import ActionError, Station, perform


def test_param_kind_numbers_and_widths() -> None:
    assert [(k.name, int(k), k.width) for k in ParamKind] == [
        ("BIT", 0, 1), ("BYTE", 1, 1), ("WORD", 2, 2), ("TWO_WORD", 3, 4), ("REAL", 4, 8)
    ]  # fmt: skip
    assert [int(t) for t in ParamDataType] == [int(k) for k in ParamKind]


def test_default_machine_bit_parameters_are_bit() -> None:
    m = default_machine()
    for number in (1001, 1005, 1006, 1815, 3401):
        item = m.param_item(number)
        assert item is not None and item.kind is ParamKind.BIT, number
        assert (item.low, item.high, item.width) == (0, 255, 1)
    for number, kind in ((20, ParamKind.BYTE), (3216, ParamKind.WORD), (1320, ParamKind.TWO_WORD)):
        item = m.param_item(number)
        assert item is not None and item.kind is kind


def test_data_item_width_follows_kind() -> None:
    item = DataItem(1, kind=ParamKind.WORD)
    item.check(3)
    assert item.width == 2 and (item.low, item.high) == (-32768, 32767)
    with pytest.raises(ValueError, match="bit item is 1 byte wide"):
        DataItem(1, 2, kind=ParamKind.BIT).check(3)
    with pytest.raises(ValueError, match="decimals"):
        DataItem(1, kind=ParamKind.WORD, decimals=2).check(3)


def test_machine_bit_parameter_holds_0_to_255() -> None:
    m = default_machine()
    s = m.new_session()
    m.set_panel(0, 1, 0)
    m.write_param(s, 1815, 1, 0b1011_0000, width=1)
    assert m.read_param(1815, 1) == 176
    with pytest.raises(MachineError, match=r"outside its range 0\.\.255"):
        m.write_param(s, 1815, 1, 256, width=1)


def test_machine_file_types_bits_and_reals(tmp_path: Path) -> None:
    path = tmp_path / "m.toml"
    path.write_text(REAL_FILE, encoding="utf-8")
    m = load_machine(path)
    real = m.param_item(1420)
    assert real is not None and real.kind is ParamKind.REAL and real.decimals == 3
    assert (real.low, real.high) == (0, 99_999_999)
    assert [m.read_param(1420, a) for a in (1, 2)] == [12345, 7500]
    assert [m.read_param(1815, a) for a in (1, 2)] == [176, 1]
    assert m.param_item(3216).kind is ParamKind.WORD  # type: ignore[union-attr]
    assert m.param_item(6711).kind is ParamKind.TWO_WORD  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("spec", "problem"),
    [
        ('type = "bit"\nvalue = 256', "256 is outside 0..255"),
        ('type = "bit"\nvalue = "1012"', "is not 8 bits"),
        ('type = "bit"\nvalue = "1011"', 'write the eight bits #7..#0 ("00001011"), a binary'),
        ('type = "bit"\nvalue = "176"', "or an integer 0..255 without quotes"),
        ('type = "bit"\nvalue = "0b101100001"', "has 9 bits"),
        ('type = "bit"\nrange = [0, "11"]', "is not 8 bits"),
        ('type = "real"\ndecimals = 2\nvalue = 1.234', "has more than 2 decimals"),
        ('type = "real"\ndecimals = 10', "outside 0..9"),
        ('type = "word"\ndecimals = 1', 'applies to type = "real" only'),
        ('type = "float"', "unknown type 'float'"),
    ],
)
def test_machine_file_type_errors(tmp_path: Path, spec: str, problem: str) -> None:
    path = tmp_path / "m.toml"
    path.write_text(f'[machine]\nname = "m"\naxes = ["X"]\n[parameters.9]\n{spec}\n')
    with pytest.raises(ValueError, match=r"parameters\.9") as exc:
        load_machine(path)
    assert problem in str(exc.value)


@pytest.mark.parametrize(
    ("text", "value"),
    [("00001011", 11), ("1011_0000", 176), ("0b1011", 11), ("0B10110000", 176), (" 0b0 ", 0)],
)
def test_a_bit_value_given_as_text_is_read_as_bits(tmp_path: Path, text: str, value: int) -> None:
    path = tmp_path / "m.toml"
    path.write_text(f'[machine]\nname = "m"\naxes = ["X"]\n[parameters.9]\ntype = "bit"\n'
                    f'value = "{text}"\n')  # fmt: skip
    assert load_machine(path).read_param(9, 0) == value


async def test_wire_bit_parameter_is_the_signed_byte_of_its_bits() -> None:
    m = default_machine()
    async with serving(m) as served:
        async with await served.connect() as w:
            m.set_panel(0, 1, 0)
            assert await w.ew(Command.WRPARAM, ParamValue(1815, 1, -80, 1).encode()) == 0
            assert m.read_param(1815, 1) == 176
            answer = await w.request(Command.RDPARAM, DataRequest(1815, 1))
            assert answer == ParamValue(1815, 1, -80, 1)
            assert answer.bits == 176
            info = await w.request(Command.RDPARAINFO, ParamAttributesRequest(1815))
            assert info == ParamAttributes(1815, ParamDataType.BIT, 1, 0, 0, 255)
            assert await w.ew(Command.RDPARAINFO, ParamAttributesRequest(9).encode()) == EW.NUMBER


@pytest.fixture
async def real_machine(tmp_path: Path) -> Machine:
    path = tmp_path / "m.toml"
    path.write_text(REAL_FILE, encoding="utf-8")
    return load_machine(path)


async def test_wire_and_client_real_parameter(real_machine: Machine) -> None:
    m = real_machine
    async with serving(m) as served:
        async with await served.connect() as w:
            answer = await w.request(Command.RDPARAM, DataRequest(1420, 1))
            assert answer == ParamValue(1420, 1, 12345, 8, 3)
        async with FocasClient(served.host, served.port) as cnc:
            assert await cnc.read_param_real(1420, axis=1) == Decimal("12.345")
            with pytest.raises(ValueError, match="real parameter"):
                await cnc.read_param(1420, axis=1)
            assert await cnc.read_param_real(3216) == Decimal(10)
            await cnc.sim.set_panel("MDI", pwe=True)
            await cnc.write_param(1420, Decimal("1.5"), axis=2)
            assert m.read_param(1420, 2) == 1500
            await cnc.write_param(1420, "99999.999", axis=2)
            assert await cnc.read_param_real(1420, axis=2) == Decimal("99999.999")
            with pytest.raises(CncError) as exc:
                await cnc.write_param(1420, "1.2345", axis=2)  # 4 decimals: no exact mantissa
            assert exc.value.ew == EW.DATA
            with pytest.raises(ValueError, match="real parameter: it has no bits"):
                await cnc.write_param_bit(1420, 0, True, axis=1)
            attrs = await cnc.read_param_attributes(1420)
            assert attrs.type is ParamDataType.REAL and attrs.decimals == 3


async def test_client_bit_parameter_reads_and_writes_0_to_255() -> None:
    async with serving(default_machine()) as served:
        async with FocasClient(served.host, served.port) as cnc:
            await cnc.sim.set_panel("MDI", pwe=True)
            await cnc.write_param(1815, 0xB0, axis=1)
            assert await cnc.read_param(1815, axis=1) == 176
            await cnc.write_param(1815, "0b00000011", axis=2)
            assert served.machine.read_param(1815, 2) == 3
            with pytest.raises(ValueError, match=r"bit parameter 1815 holds 0\.\.255"):
                await cnc.write_param(1815, 256, axis=1)
            with pytest.raises(ValueError, match="parameter 20 is a byte parameter: 176"):
                await cnc.write_param(20, 176)
            assert served.machine.read_param(20, 0) == 4


async def test_parameter_attributes_print_their_type() -> None:
    async with serving(default_machine()) as served:
        async with FocasClient(served.host, served.port) as cnc:
            attrs = await cnc.read_param_attributes(1815)
    assert attrs.type is ParamDataType.BIT
    assert repr(attrs) == (
        "ParamAttributes(datano=1815, type=ParamDataType.BIT, axis=1, decimals=0, low=0, high=255)"
    )
    assert repr(ParamAttributes(5, 9, 0, 0, 0, 1)).startswith("ParamAttributes(datano=5, kind=9,")


@pytest.fixture
async def cli(capsys: pytest.CaptureFixture[str]) -> AsyncIterator[Cli]:
    async with serving(default_machine()) as served:
        yield Cli(served, capsys)


async def test_cli_bit_parameter_written_and_shown_as_bits(cli: Cli) -> None:
    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    out = await cli.ok("param", "set", "1815", "0xb0", "--axis", "1", "--password", "1234")
    assert out.strip() == "1815 axis 1 = 176 (10110000), bit parameter (written)"
    out = await cli.ok("param", "get", "1815", "--axis", "1")
    assert out.strip() == "1815 axis 1 = 176 (10110000), bit parameter"
    await cli.ok("param", "set", "1815", "0b00000111", "--axis", "2")
    assert cli.served.machine.read_param(1815, 2) == 7
    data = await cli.json("param", "get", "1815", "--axis", "1")
    assert data == {
        "number": 1815, "axis": 1, "value": 176, "width": 1, "type": "bit", "bits": "10110000"
    }  # fmt: skip
    out = await cli.ok("param", "get", "1815.7", "--axis", "1")
    assert out.strip() == "1815.7 axis 1 = 1"
    err = await cli.fails(EXIT_USAGE, "param", "set", "1815", "256", "--axis", "1")
    assert "bit parameter 1815 holds 0..255" in err
    # a byte parameter is still signed
    out = await cli.ok("param", "get", "20")
    assert out.strip() == "20 = 4 (0x04, 0b00000100), byte parameter"
    await cli.fails(EXIT_CNC, "param", "set", "20", "99")


async def test_cli_real_parameter(
    real_machine: Machine, capsys: pytest.CaptureFixture[str]
) -> None:
    async with serving(real_machine) as served:
        cli = Cli(served, capsys)
        out = await cli.ok("param", "get", "1420", "--axis", "1")
        assert out.strip() == "1420 axis 1 = 12.345 (real, 3 decimals)"
        await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
        out = await cli.ok("param", "set", "1420", "2.25", "--axis", "1")
        assert out.strip() == "1420 axis 1 = 2.250 (real, 3 decimals) (written)"
        err = await cli.fails(EXIT_USAGE, "param", "get", "1420.1", "--axis", "1")
        assert "real parameter: it has no bits" in err
        data = await cli.json("param", "get", "1420", "--axis", "1")
        assert data["value"] == "2.250" and data["type"] == "real" and data["decimals"] == 3


def test_machine_file_doc_parameter_examples_load(tmp_path: Path) -> None:
    doc = (Path(__file__).resolve().parent.parent / "docs" / "machine-file.md").read_text()
    blocks = [b for b in re.findall(r"```toml\n(.*?)```", doc, re.S) if "[parameters." in b]
    assert len(blocks) == 2
    path = tmp_path / "doc.toml"
    head = '[machine]\nname = "doc"\naxes = ["X", "Y", "Z"]\n'
    path.write_text(head + "\n".join(blocks), encoding="utf-8")
    m = load_machine(path)
    assert [m.read_param(1815, a) for a in (1, 2, 3)] == [48, 48, 49]
    assert m.read_param(1430, 0) == 2_500_500
    assert m.param_item(1420).kind is ParamKind.TWO_WORD  # type: ignore[union-attr]


@pytest.mark.parametrize(
    ("text", "value"), [("00000011", 3), ("00000101", 5), ("00010000", 16), ("10110000", 176)]
)
async def test_eight_bits_typed_are_the_bits_on_every_front_end(
    cli: Cli, text: str, value: int
) -> None:
    """The command line shows a bit parameter as its eight bits: typed back (CLI, both
    clients, the page) they are those bits, as the machine file reads them, not a decimal."""
    m = cli.served.machine
    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    out = await cli.ok("param", "set", "1001", text)
    assert out.strip() == f"1001 = {value} ({value:08b}), bit parameter (written)"
    await cli.ok("param", "set", "1815", text, "--axis", "1", "--protocol", "native")
    assert m.read_param(1815, 1) == value
    async with FocasClient(cli.served.host, cli.served.port) as cnc:
        await cnc.write_param(1815, text, axis=2)
    assert m.read_param(1815, 2) == value
    station = Station(0, m)
    perform(station, "write_param", {"number": 1815, "axis": 3, "value": text})
    assert m.read_param(1815, 3) == value


async def test_zero_led_digits_that_are_not_eight_bits_are_refused(cli: Cli) -> None:
    await cli.ok("sim", "panel", "--mode", "MDI", "--pwe", "on")
    err = await cli.fails(EXIT_USAGE, "param", "set", "1001", "0101")
    assert "'0101' is not 8 bits" in err and '"00000101"' in err
    with pytest.raises(ActionError, match="'0101' is not 8 bits"):
        perform(Station(0, cli.served.machine), "write_param", {"number": 1001, "value": "0101"})
    out = await cli.ok("param", "set", "6713", "0042")  # not a bit parameter: a decimal
    assert cli.served.machine.read_param(6713, 0) == 42 and "(written)" in out
