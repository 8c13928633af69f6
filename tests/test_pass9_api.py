"""The Python API as a new user meets it, a ninth pass: the packed and the native client asked
the same thing answer the same, and the public classes refuse arguments that contradict one
another, naming them."""

from __future__ import annotations

import re
import struct
from collections.abc import AsyncIterator
from decimal import Decimal
from pathlib import Path

import pytest
from fwlib_support import LIBRARY, buf, s16, served_cnc
from support import with_both_clients

from focas_net import (
    EW,
    CncError,
    FocasClient,
    FocasServer,
    NativeClient,
    default_machine,
    load_machine,
)
from focas_net.sim import LifeTool, Machine, ParamKind, ToolGroup, ToolsSpec
from focas_net.sim.nc import ManualClock

MACHINE_16I = Path(__file__).with_name("data") / "fwlib_16i_machine.toml"


@pytest.fixture(params=["30i", "16i"])
async def both_sets(
    request: pytest.FixtureRequest, both_clients: tuple[Machine, FocasClient, NativeClient]
) -> AsyncIterator[tuple[Machine, FocasClient, NativeClient]]:
    """A machine of either command set, served, with a packed and a native client on it."""
    if request.param == "30i":
        yield both_clients
        return
    machine = load_machine(MACHINE_16I, sim_clock=ManualClock())
    async with with_both_clients(machine) as both:
        yield both


# -- a parameter the CNC does not have ---------------------------------------------------------
@pytest.mark.parametrize("number", [7000, 1, 32767])
@pytest.mark.parametrize("value", [10**6, 1, -1, 300, Decimal("1.5"), "0b1", 2**31 - 1])
async def test_a_write_of_a_parameter_the_cnc_does_not_have_is_ew_number_on_both_clients(
    both_sets: tuple[Machine, FocasClient, NativeClient], number: int, value: int | Decimal | str
) -> None:
    machine, cnc, native = both_sets
    machine.set_panel(0, 1, 0)  # MDI, parameter writes enabled
    assert machine.param_item(number) is None
    with pytest.raises(CncError) as packed:
        await cnc.write_param(number, value)
    with pytest.raises(CncError) as through_native:
        await native.write_param(number, value)
    assert packed.value.ew == through_native.value.ew == EW.NUMBER
    assert str(through_native.value) == str(packed.value)
    assert machine.param_item(number) is None


async def test_a_parameter_the_cnc_has_is_still_refused_by_its_own_range(
    both_sets: tuple[Machine, FocasClient, NativeClient],
) -> None:
    machine, cnc, native = both_sets
    machine.set_panel(0, 1, 0)
    byte = next(
        n for n in range(1, 10000) if (i := machine.param_item(n)) and i.kind is ParamKind.BYTE
    )
    for client in (cnc, native):
        with pytest.raises(ValueError, match=f"parameter {byte} is a byte parameter: 1000000"):
            await client.write_param(byte, 10**6)


@pytest.mark.skipif(
    not LIBRARY, reason="set FOCAS_NET_FWLIB to the path of FANUC's libfwlib32 to run it"
)
@pytest.mark.parametrize("set_name", ["30i", "16i"])
async def test_fanucs_library_writes_a_missing_parameter_by_the_next_ones_information(
    set_name: str,
) -> None:
    """The information answer of a number the CNC lacks is the next parameter's: the library
    checks the caller's length against that one's type (EW_LENGTH, nothing sent) and otherwise
    sends the write, which the CNC refuses with EW_NUMBER; the native client answers
    EW_NUMBER whatever the value."""
    async with served_cnc(set_name) as cnc:
        machine = cnc.machine
        following = next(n for n in range(7000, 32768) if machine.param_item(n))
        item = machine.param_item(following)
        assert item is not None
        info = buf(4 + 8 * 10)
        assert await cnc.call("cnc_rdparainfo", s16(7000), s16(1), info) == 0
        assert struct.unpack_from("<h", info, 6)[0] == following  # info[0].prm_no
        fits = 4 + item.width
        for length in (5, 6, 8, 12):
            b = buf(4 + 8 * 32)
            struct.pack_into("<hhi", b, 0, 7000, 0, 1)
            rc = await cnc.call("cnc_wrparam", s16(length), b)
            assert rc == (EW.NUMBER if length == fits else EW.LENGTH), length
        async with NativeClient(cnc.served.host, cnc.served.port, timeout=5) as native:
            for value in (1, 10**6):
                with pytest.raises(CncError) as refused:
                    await native.write_param(7000, value)
                assert refused.value.ew == EW.NUMBER
        assert machine.param_item(7000) is None


# -- arguments that contradict one another -----------------------------------------------------
@pytest.mark.parametrize("client", [FocasClient])
def test_a_server_hostname_without_tls_is_refused_naming_it(client: type[FocasClient]) -> None:
    with pytest.raises(ValueError, match=r"server_hostname='cnc-7' is the name .* without ssl"):
        client("127.0.0.1", server_hostname="cnc-7")


def test_a_port_beside_ports_is_refused_naming_both() -> None:
    machines = [default_machine(), default_machine()]
    with pytest.raises(ValueError, match=r"port=5000 and ports=\[6000, 6001\] both given"):
        FocasServer(machines, port=5000, ports=[6000, 6001])


@pytest.mark.parametrize(
    ("group", "refused"),
    [
        (
            ToolGroup(1, life=5, tools=[LifeTool(1)], current=3),
            r"tool group 1: the tool in use, current=3, is outside 0..0 \(the index among "
            r"its 1 tools\)",
        ),
        (
            ToolGroup(1, life=5, tools=[LifeTool(1)], current=-1),
            r"tool group 1: the tool in use, current=-1, is outside 0..0",
        ),
        (ToolGroup(1, life=5, count=9, tools=[LifeTool(1)]), r"count 9 is outside 0..5"),
        (ToolGroup(1, life=5, count=-1, tools=[LifeTool(1)]), r"count -1 is outside 0..5"),
        (ToolGroup(1, life=5), r"tool group 1 has 0 tools: 1..4 are allowed"),
    ],
)
def test_a_tool_group_at_odds_with_itself_is_refused_naming_the_values(
    group: ToolGroup, refused: str
) -> None:
    with pytest.raises(ValueError, match=refused):
        Machine("x", tools={1: ToolsSpec(groups=[group])})


# -- a width that is not the parameter's -------------------------------------------------------
@pytest.mark.parametrize("width", [1, 2, 8])
@pytest.mark.parametrize("value", [5, 24000])
async def test_a_width_the_parameter_does_not_have_is_ew_length_in_the_same_words(
    both_sets: tuple[Machine, FocasClient, NativeClient], width: int, value: int
) -> None:
    machine, cnc, native = both_sets
    machine.set_panel(0, 1, 0)
    number = next(
        n
        for n in range(1, 10000)
        if (i := machine.param_item(n)) and i.kind is ParamKind.TWO_WORD and not i.axis
    )
    before = machine.param_item(number)
    assert before is not None
    kept = list(before.values)
    refusals = []
    for client in (cnc, native):
        with pytest.raises(CncError) as refused:
            await client.write_param(number, value, width=width)
        refusals.append(str(refused.value))
        assert refused.value.ew == EW.LENGTH
    assert refusals[0] == refusals[1]
    assert f"cnc_wrparam: parameter {number} is 4 bytes wide, not {width}" in refusals[0]
    assert machine.param_item(number).values == kept  # type: ignore[union-attr]


# -- an alarm type typed as its number ---------------------------------------------------------
@pytest.mark.parametrize(("typed", "number"), [("1", 1), (" 31 ", 31), ("0", 0), ("+3", 3)])
async def test_an_alarm_type_given_as_digits_is_its_number_as_the_page_takes_it(
    both_clients: tuple[Machine, FocasClient, NativeClient], typed: str, number: int
) -> None:
    """``read_alarms(alm_type="1")`` was refused with ``(one of SW PW ..., or 0..31)``, though
    the hint names numbers and the page takes ``"31"``."""
    machine, cnc, native = both_clients
    machine.raise_alarm(0, number, 100, "TYPED")
    for client in (cnc, native):
        found = await client.read_alarms(alm_type=typed)
        assert [(a.alm_type, a.alm_no) for a in found] == [(number, 100)]
    await cnc.sim.clear_alarms(alm_type=typed)
    assert machine.active_alarms() == []


@pytest.mark.parametrize(
    ("typed", "refused"),
    [
        ("32", "alarm type 32 is outside -1..31"),
        ("1.5", "not a whole number: '1.5'"),
        ("P S", "unknown alarm type 'P S'"),
    ],
)
async def test_alarm_type_text_that_is_none_is_refused_naming_it(
    both_clients: tuple[Machine, FocasClient, NativeClient], typed: str, refused: str
) -> None:
    _, cnc, native = both_clients
    for client in (cnc, native):
        with pytest.raises(ValueError, match=re.escape(refused)):
            await client.read_alarms(alm_type=typed)


def test_the_calls_the_native_guide_says_it_lacks_are_lacking_and_the_stand_ins_exist() -> None:
    text = (Path(__file__).resolve().parent.parent / "docs" / "native-client.md").read_text()
    start = text.index("Not methods of the native client at all")
    paragraph = text[start : text.index("\n\n", start)]
    lacking, stand_ins = paragraph.split("Over\nFOCAS/2")
    named = [n for n in re.findall(r"`(\w+)`", lacking) if n != "AttributeError"]
    assert named and all(not hasattr(NativeClient, n) for n in named), named
    assert all(hasattr(FocasClient, n) for n in named), named
    offered = [n for n in re.findall(r"`(\w+)`", stand_ins) if n not in named]
    assert offered and all(hasattr(NativeClient, n) for n in offered), offered
