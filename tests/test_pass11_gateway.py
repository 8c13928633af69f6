"""Pass 11 of the gateway and of the labels every front end shares: the paths a machine has not
are named in the machine's words; a client never reached closes without a word; the MQTT
settings that would make a topic, a client id or a credential MQTT cannot carry, or a gateway
name that is no topic level, are refused naming the key; a peer that ends the connection
before any answer to MQTT's CONNECT is told so at once, whether it reset or closed it."""

from __future__ import annotations

import asyncio
import logging
from dataclasses import replace
from decimal import Decimal

import pytest
from gateway_support import machine_shape
from opcua_support import cnc_path, connected, machine_node, running
from poller_support import QUICK, SLOW
from support import free_port, reset_at_close, serving, wait_until

from focas_net._refusals import no_path
from focas_net.cli._format import sysinfo_rows
from focas_net.client import ClientState, FocasClient, NativeClient
from focas_net.client._failures import BEFORE_ANY_ANSWER
from focas_net.client._probes import GATEWAY, diagnosed
from focas_net.errors import FocasConnectionError
from focas_net.gateway import (
    ConfigError,
    MachineConfig,
    MqttSettings,
    WriteGates,
    parse_config,
    shard,
)
from focas_net.gateway.mqtt import MqttSink
from focas_net.gateway.reads import describe
from focas_net.gateway.writer import GatedWriter
from focas_net.protocol import SysInfo
from focas_net.sim import default_machine

MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


# -- the paths a machine has not: the machine's words -----------------------------------------
@pytest.mark.parametrize(("paths", "missing"), [((1, 3), [3]), ((2, 3), [2, 3])])
async def test_paths_the_cnc_has_not_are_told_in_the_machines_words(
    paths: tuple[int, ...], missing: list[int], caplog: pytest.LogCaptureFixture
) -> None:
    async with (
        serving(default_machine()) as served,
        FocasClient("127.0.0.1", served.port) as client,
    ):
        config = MachineConfig("m1", "127.0.0.1", port=served.port, protocol="packed", paths=paths)
        with caplog.at_level(logging.WARNING, "focas_net.gateway"):
            await describe(config, client)
    (record,) = caplog.records
    said = record.getMessage()
    assert said.startswith(f"m1: {no_path(missing, 1)} (machine.paths)"), said
    assert no_path(3, 1) == "the CNC has no path 3: it has path 1 only"  # (one path: as before)


# -- a client the gateway never reached closes without a word ----------------------------------
@pytest.mark.parametrize("kind", [FocasClient, NativeClient])
async def test_a_client_never_connected_says_nothing_when_closed(
    kind: type[FocasClient] | type[NativeClient], caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.INFO, "focas_net.client")
    client = kind("127.0.0.1", free_port(), timeout=1.0, reconnect=QUICK)
    with pytest.raises(OSError):
        await client.connect()
    await client.aclose()
    assert not [r.getMessage() for r in caplog.records if r.getMessage().endswith(" closed")]


async def test_a_client_that_was_connected_still_says_closed(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO, "focas_net.client")
    async with serving() as served, NativeClient("127.0.0.1", served.port):
        pass
    assert f"127.0.0.1:{served.port} closed" in [r.getMessage() for r in caplog.records]


# -- [mqtt]: what MQTT cannot carry, and a gateway name that is no topic level ----------------
LONG = "x" * 70_000


@pytest.mark.parametrize(
    ("line", "said"),
    [
        (f'gateway = "{LONG}"', "mqtt.gateway: got 'xxxx"),
        (f'client_id = "{LONG}"', "mqtt.client_id: got 'xxxx"),
        (f'prefix = "{LONG}"', "mqtt.prefix: got 'xxxx"),
        (f'username = "{LONG}"\npassword = "p"', "mqtt.username: got 'xxxx"),
        (f'username = "u"\npassword = "{"é" * 40_000}"', "mqtt.password: got 'éééé"),
        ('gateway = "+"', "mqtt.gateway: got '+'; expected one level of a topic"),
        ('gateway = "#"', "mqtt.gateway: got '#'; expected one level of a topic"),
        ('gateway = "cell/7"', "mqtt.gateway: got 'cell/7'; expected one level of a topic"),
        ('gateway = "/"', "mqtt.gateway: got '/'; expected one level of a topic"),
        ('gateway = ""', "mqtt.gateway: got ''; expected a non-empty string"),
        ('client_id = "plant/1"', "mqtt.client_id: got 'plant/1'; expected one level of a"),
        # (a broker closes a CONNECT whose will topic or user name holds a control character)
        ('prefix = "a\\nb"', "mqtt.prefix: got 'a\\nb'; expected a topic prefix of at most"),
        ('username = "u\\tx"\npassword = "p"', "mqtt.username: got 'u\\tx'; expected a"),
    ],
)
def test_mqtt_text_that_makes_no_topic_or_no_mqtt_string_is_refused_naming_the_key(
    line: str, said: str
) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_config(f"{MACHINE}[mqtt]\n{line}\n", "plant.toml")
    assert str(caught.value).startswith(f"plant.toml: {said}"), str(caught.value)
    assert len(str(caught.value)) < 400  # (a long value is cut, never printed whole)


def test_a_client_id_with_a_slash_is_taken_beside_a_gateway_name() -> None:
    taken = parse_config(f'{MACHINE}[mqtt]\nclient_id = "plant/1"\ngateway = "plant-1"\n').mqtt
    assert taken is not None and taken.gateway_name == "plant-1"


def test_the_sinks_gateway_name_is_checked_as_the_files() -> None:
    with pytest.raises(ConfigError, match=r"^mqtt.gateway: got '\+'; expected one level"):
        MqttSink(MqttSettings(), gateway_name="+")


# -- a peer that ends the connection before any answer to MQTT's CONNECT -----------------------
async def _warned_of(peer: str, caplog: pytest.LogCaptureFixture) -> str:
    """The first warning of a sink whose broker's port is served by a peer that resets
    (``reset``) or closes (``close``, once it read the CONNECT) each connection."""

    async def serve(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        if peer == "reset":
            reset_at_close(writer.get_extra_info("socket"))
            writer.transport.abort()
        else:
            await reader.read(4096)
            writer.close()

    caplog.set_level(logging.WARNING, "focas_net.gateway")
    server = await asyncio.start_server(serve, "127.0.0.1", 0)
    async with server:
        port = server.sockets[0].getsockname()[1]
        # (a timeout no test waits out: the end is told as it comes)
        async with MqttSink(MqttSettings(port=port), reconnect=(60.0, 60.0), timeout=60.0):
            for _ in range(400):
                if caplog.records:
                    break
                await asyncio.sleep(0.025)
    return caplog.records[0].getMessage().partition(f"127.0.0.1:{port}: ")[2]


@pytest.mark.parametrize(
    ("peer", "said"),
    [("reset", "connection reset by peer"), ("close", "connection closed by peer")],
)
async def test_a_connection_ended_before_connack_is_told_so_at_once(
    peer: str, said: str, caplog: pytest.LogCaptureFixture
) -> None:
    assert await _warned_of(peer, caplog) == (
        f"{said} before any answer to MQTT's CONNECT (is that a broker's port?)"
    )


# -- the control's type: one name on the command line and in OPC UA --------------------------
@pytest.mark.parametrize(
    ("cnc_type", "mt_type", "label", "name"),
    [
        ("0", "M", "Series 0i", "Series 0i-M"),
        ("31", "T", "Series 31i", "Series 31i-T"),
        ("16", "M", "Series 16/16i", "Series 16/16i-M"),
        ("PD", "M", "Power Mate i-D", "Power Mate i-D"),
        ("ZZ", "M", "", "ZZ-M"),
    ],
)
async def test_opc_uas_cnc_type_name_is_the_command_lines_label(
    cnc_type: str, mt_type: str, label: str, name: str
) -> None:
    info = SysInfo(
        0, 4, cnc_type.rjust(2).encode(), mt_type.rjust(2).encode(), b"D4F1", b"32.0", b"03"
    )
    assert {r[0]: r[2] for r in sysinfo_rows(info)}["cnc_type"] == label
    shape = replace(machine_shape("m1", ("X",)), cnc_type=cnc_type, mt_type=mt_type)
    async with running() as sink:
        sink.described(shape)
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "m1")
            assert await (await cnc_path(client, root, "CncTypeName")).read_value() == name


# -- [opcua] endpoint: only what the server serves as typed ------------------------------------
@pytest.mark.parametrize(
    "endpoint",
    [
        "opc.tcp://op@127.0.0.1:4840/x",  # (it advertised opc.tcp://127.0.0.1:4840/x)
        "opc.tcp://127.0.0.1:4840/x?y=1",
        "opc.tcp://127.0.0.1:4840/x#f",
        "opc.tcp://127.0.0.1:4840/focas_net/ ",
    ],
)
def test_an_endpoint_with_a_user_a_query_or_a_space_is_refused_naming_the_key(
    endpoint: str,
) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_config(f'{MACHINE}[opcua]\nendpoint = "{endpoint}"\n', "plant.toml")
    assert str(caught.value) == (
        f"plant.toml: opcua.endpoint: got {endpoint!r}; expected opc.tcp://HOST:PORT/PATH "
        "without a user (users: [[opcua.users]]), a '?' query, a '#' fragment or a space"
    )


# -- a write to a machine being reconnected ----------------------------------------------------
@pytest.mark.parametrize("write", ["macro", "param", "pmc"])
async def test_a_write_to_a_machine_being_reconnected_is_refused_at_once_with_why(
    write: str,
) -> None:
    """It waited out the call's timeout for a reconnect (holding the OPC UA session's other
    requests with it) and said ``still reconnecting ... when the call timed out``."""
    async with serving() as served:
        client = NativeClient("127.0.0.1", served.port, timeout=30.0, reconnect=SLOW)
        await client.connect()
    await wait_until(lambda: client.state is ClientState.RECONNECTING)
    gates = WriteGates(macros=((500, 500),), params=((6711, 6711),), pmc=(("R", 0, 0),))
    config = MachineConfig("m1", "127.0.0.1", served.port, writes=gates)
    writer = GatedWriter(lambda name: (config, client))
    calls = {
        "macro": lambda: writer.write_macro("m1", 500, Decimal(1), 1),
        "param": lambda: writer.write_param("m1", 6711, 1, 0),
        "pmc": lambda: writer.write_pmc("m1", "R", 0, 1),
    }
    try:
        with pytest.raises(FocasConnectionError) as caught:
            async with asyncio.timeout(10.0):  # (a bound: the write is refused at once)
                await calls[write]()
    finally:
        await client.aclose()
    assert str(caught.value).startswith(f"m1: not connected to 127.0.0.1:{served.port} (")
    assert str(caught.value).endswith("): nothing was written")


# -- the probes of a port that said nothing stay out of the log ---------------------------------
async def test_the_probes_of_a_port_that_closed_say_nothing_in_the_log(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """At a port that closes every connection (an MQTT broker's, for one) each attempt's
    probe logged `connection to HOST:PORT lost: ...` at WARNING, and `connected`, `closed` at
    INFO, for a machine the gateway never reached: only the poller's words are told."""

    async def closing(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await reader.read(4096)
        writer.close()

    server = await asyncio.start_server(closing, "127.0.0.1", 0)
    async with server:
        port = server.sockets[0].getsockname()[1]
        exc = FocasConnectionError(f"connection closed by 127.0.0.1:{port} {BEFORE_ANY_ANSWER}")
        caplog.set_level(logging.INFO, "focas_net")
        await diagnosed(exc, "127.0.0.1", port, "native", False, 2.0, wording=GATEWAY)
    assert [r.getMessage() for r in caplog.records if r.name.startswith("focas_net.client")] == []


def test_a_name_the_shards_suffix_makes_too_long_is_told_with_the_shard() -> None:
    """A client id of 1000 characters (the most) with ``--shard 2/2`` was refused as ``got
    'cccc...' (1002 characters)``, a value nobody wrote."""
    machines = f'{MACHINE}[[machine]]\nname = "m2"\nhost = "127.0.0.1"\n'
    config = parse_config(f'{machines}[mqtt]\nclient_id = "{"c" * 1000}"\n', "plant.toml")
    with pytest.raises(ConfigError) as caught:
        shard(config, 2, 2, "plant.toml")
    assert str(caught.value) == (
        "plant.toml: --shard 2/2: mqtt.client_id with this shard's '-2' has 1002 characters, "
        "more than 1000: give a shorter one"
    )
