"""Pass 10 of the gateway and of the labels every front end shares: a write the CNC refuses
is logged with its reason, in the command line's words; a shard with no machine names the
file; a machine's availability tells its current loss, not its first."""

from __future__ import annotations

from argparse import Namespace
from decimal import Decimal
from pathlib import Path
from typing import Literal

import pytest
from cli_support import fails
from gateway_support import gated_writer
from poller_support import SLOW, Garbage, RecordingSink, all_online, config, polling, until

from focas_net.cli import EXIT_USAGE
from focas_net.cli._reasons import reason
from focas_net.cli.gateway_cmd import parse_shard
from focas_net.cli.read_cmds import axis_hint
from focas_net.errors import EW, CncError
from focas_net.gateway import (
    ConfigError,
    MachineConfig,
    WriteGates,
    load_config,
    parse_config,
    shard,
)
from focas_net.gateway._opcua_methods import refusal
from focas_net.gateway.poller import Poller
from focas_net.protocol import PmcArea
from focas_net.server import FocasServer
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock


# -- a refused write says why, in the command line's words ------------------------------------
@pytest.mark.parametrize(
    ("write", "why"),
    [
        (("param", 6711, 1_000_000_000, 0), "the CNC refused 1000000000 for parameter 6711: "
         "outside its range"),
        (("param", 9999, 1, 0), "the CNC has no parameter 9999"),
        (("param", 1020, 90, 1), "the CNC refused 90 for parameter 1020 axis 1: outside its "
         "range, or a letter other than the axis's own"),
        (("macro", 5001, 1, 1), "macro variable #5001 is read-only (FANUC's #5001..#5120"),
        (("macro", 20000, 1, 1), "the CNC has no macro variable #20000"),
    ],
)  # fmt: skip
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_write_the_cnc_refuses_is_logged_with_the_reason_the_cli_gives(
    write: tuple[str, int, int, int],
    why: str,
    protocol: Literal["native", "packed"],
) -> None:
    kind, number, value, where = write
    machine = default_machine()
    machine.set_panel("MDI", pwe=1)
    async with gated_writer(machine, protocol) as (writer, _):
        with pytest.raises(Exception) as refused:
            if kind == "param":
                await writer.write_param("m1", number, value, where)
            else:
                await writer.write_macro("m1", number, Decimal(value), where)
    exc = refused.value
    assert isinstance(exc, CncError) and why in str(exc), exc
    assert refusal(exc).is_bad()
    command, args = (
        ("param set", Namespace(number=str(number), value=str(value), axis=where))
        if kind == "param"
        else ("macro set", Namespace(number=number, value=str(value), path=where))
    )
    assert why in (reason(command, args, CncError(exc.ew)) or "")


@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_parameter_write_outside_mdi_names_the_gate_and_the_missing_password(
    protocol: Literal["native", "packed"],
) -> None:
    async with gated_writer(default_machine(), protocol) as (writer, _):
        with pytest.raises(CncError) as refused:
            await writer.write_param("m1", 6711, 5, 0)
    assert str(refused.value) == (
        "EW_PASSWD (17): protection / password error: cnc_wrparam; parameter writes need MDI "
        "mode and PWE on at the CNC; the gateway sends no parameter password (a CNC that has "
        "one takes no parameter write from it)"
    )


# -- a shard with no machine names the file -----------------------------------------------------
MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


async def test_a_shard_with_no_machine_names_the_file(tmp_path: Path) -> None:
    plant = tmp_path / "plant.toml"
    plant.write_text(MACHINE)
    line = await fails(
        EXIT_USAGE, "gateway", str(plant), "--shard", "2/2", prefix="focas-net gateway: error: "
    )
    words = "--shard 2/2: no machine (the file has 1 machine)"
    assert line == f"focas-net gateway: error: {plant}: {words}"
    with pytest.raises(ConfigError) as refused:
        shard(parse_config(MACHINE), 2, 2, "plant.toml")
    assert str(refused.value) == f"plant.toml: {words}"
    two = MACHINE + MACHINE.replace("m1", "m2")
    top = two + "[opcua]\nendpoint = 'opc.tcp://127.0.0.1:65535/'\n"
    with pytest.raises(ConfigError) as refused:
        shard(parse_config(top), 2, 2, "plant.toml")
    assert str(refused.value).startswith("plant.toml: --shard 2/2: the OPC UA port of this shard")


# -- availability tells the current loss ----------------------------------------------------------
async def test_availability_tells_the_current_loss_not_the_first() -> None:
    """A machine lost to a peer that breaks the protocol, then refused when the peer is gone:
    the outputs are told the second reason too, not left with the first."""
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    async with Garbage() as peer:
        machines = [MachineConfig("bad", "127.0.0.1", peer.port, "native", timeout=0.5)]
        async with Poller(machines, [sink], clock=clock.now, policy=SLOW) as poller:
            await until(poller, clock, lambda: poller.is_online("bad") is False)
            await peer.stop()
            clock.advance(5.0)
            await until(poller, clock, lambda: len(sink.states) == 2)
            await poller.step()
    (_, up1, first), (_, up2, second) = sink.states
    assert (up1, up2) == (False, False)
    assert first.startswith("protocol: ") and second.startswith("refused: "), sink.states
    assert poller.is_online("bad") is False


@pytest.mark.parametrize(
    ("area", "address", "why"),
    [
        ("R", 65535, "R65535 goes past the end of PMC area R"),
        ("X", 0, "PMC area X is write-protected (the machine drives it), or the machine is "
         "read-only"),
        ("E", 0, "the CNC has no PMC area E"),
    ],
)  # fmt: skip
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_pmc_write_the_cnc_refuses_says_why_as_the_cli_does(
    area: str, address: int, why: str, protocol: Literal["native", "packed"]
) -> None:
    gates = WriteGates(pmc=((area, 0, 65535),))
    async with gated_writer(default_machine(), protocol, gates) as (writer, _):
        with pytest.raises(CncError) as refused:
            await writer.write_pmc("m1", area, address, 1)
    assert str(refused.value).endswith(f"pmc_wrpmcrng: {why}")
    args = Namespace(area=PmcArea.parse(area), start=address, values=["1"], hex=None)
    assert why in (reason("pmc write", args, CncError(refused.value.ew)) or "")


@pytest.mark.parametrize(
    ("number", "axis", "why", "cli"),
    [
        (1420, 0, "parameter 1420 is an axis parameter: give Axis 1..3", "give --axis 1..3"),
        (6711, 1, "parameter 6711 is not an axis parameter: give Axis 0", "leave out --axis"),
    ],
)
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_parameter_written_with_the_wrong_axis_says_which_axis_to_give(
    number: int, axis: int, why: str, cli: str, protocol: Literal["native", "packed"]
) -> None:
    """EW_ATTRIB: an axis parameter written without its axis, or one of no axis with one;
    the command line says the same of ``--axis``."""
    machine = default_machine()
    machine.set_panel("MDI", pwe=1)
    async with gated_writer(machine, protocol) as (writer, client):
        with pytest.raises(CncError) as refused:
            await writer.write_param("m1", number, 1000, axis)
        hinted = await axis_hint(client, CncError(EW.ATTRIB), "parameter", number, axis)
    assert str(refused.value).endswith(f"cnc_wrparam; {why}")
    assert str(hinted).endswith(why.replace(why.rpartition(": ")[2], cli))


@pytest.mark.parametrize(
    ("typed", "why"),
    [
        ("1/-1", "the number of shards must be 1 or more"),
        ("-1/2", "the shard must be within 1..2"),
        ("+1/2", None),
    ],
)
def test_a_signed_shard_is_told_by_its_range_not_as_no_shard(typed: str, why: str | None) -> None:
    if why is None:
        assert parse_shard(typed) == (1, 2)
        return
    with pytest.raises(ValueError) as refused:
        parse_shard(typed)
    assert str(refused.value) == f"{why}, got {typed!r}"


@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_availability_follows_the_client_s_own_reconnect_attempts(
    protocol: Literal["native", "packed"],
) -> None:
    """A machine lost while it was online (its server closed) whose client's own reconnect
    attempts are then refused: the outputs are told the refusal, the current reason."""
    clock = ManualClock(1_000.0)
    server = FocasServer(default_machine(), host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    port = server.listeners[0].address[1]
    refused = f"refused: cannot connect to 127.0.0.1:{port}: connection refused"

    def lost(sink: RecordingSink) -> list[str]:
        return [reason for _, up, reason in sink.states if not up]

    try:
        async with polling([config("one", port, protocol)], clock) as (poller, sink):
            await until(poller, clock, all_online(poller))
            await server.aclose()
            await until(poller, clock, lambda: lost(sink)[-1:] == [refused], 1.0)
    finally:
        await server.aclose()
    assert len(lost(sink)) >= 2 and lost(sink)[0] != refused
    assert poller.is_online("one") is False


@pytest.mark.parametrize(("index", "count", "said"), [
    ("1", 2, "index must be an int, got '1'"),
    (1.0, 2, "index must be an int, got 1.0"),
    (1, "2", "count must be an int, got '2'"),
    (True, 2, "index must be an int, got True"),
])  # fmt: skip
def test_a_shard_of_another_type_is_a_type_error_not_out_of_range(
    index: object, count: object, said: str
) -> None:
    """``shard(config, "1", 2)`` said ``the shard must be within 1..2``, of a shard that is."""
    config = parse_config(MACHINE)
    with pytest.raises(TypeError) as refused:
        shard(config, index, count)  # type: ignore[arg-type]
    assert str(refused.value) == f"shard(): {said}"


def test_the_machines_are_in_the_file_s_order_whichever_block_comes_first() -> None:
    """examples/gateway.toml lists a [[fleet]] of two, then machines 3 and 4: ``--shard 1/2``
    is the first and the third of the file, as its comment and the option's help say."""
    config = load_config(Path(__file__).parent.parent / "examples" / "gateway.toml")
    names = [m.name for m in config.machines]
    assert names == ["lathe-0001", "lathe-0002", "lathe-packed-3", "lathe-packed-4"]
    assert [m.name for m in shard(config, 1, 2).machines] == ["lathe-0001", "lathe-packed-3"]


@pytest.mark.parametrize(("data", "got"), [(b"[[machine]]\n", "bytes"), (None, "None"), (5, "int")])
def test_parse_config_of_neither_text_nor_a_table_is_a_type_error(data: object, got: str) -> None:
    """It said ``<config>: got b"[[machine]]\\n"; expected a table``: a Python repr, and a
    value error for a wrong type."""
    with pytest.raises(TypeError) as refused:
        parse_config(data)  # type: ignore[arg-type]
    assert str(refused.value) == (
        "parse_config(): data must be TOML text (a str; load_config reads a file) or the "
        f"table it reads as, got {got}"
    )
