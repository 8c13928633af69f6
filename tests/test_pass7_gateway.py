"""The gateway's file refusals say each thing once, with what was typed as typed: a range is
not repeated inside parentheses, a deadband of ``-1`` is named ``-1``, an endpoint's port out
of range is named as such, and a poll interval below the shortest one is refused. An output
that cannot start is named in one line, without the OPC UA library's traceback."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest
from cli_support import fails, gateway_process

from focas_net.cli import EXIT_CNC, EXIT_OK
from focas_net.gateway import MIN_INTERVAL
from focas_net.gateway.config import ConfigError, parse_config

ONE = "[[machine]]\nname = 'mill-1'\nhost = '127.0.0.1'\n"


def refusal(text: str) -> str:
    with pytest.raises(ConfigError) as caught:
        parse_config(text, "plant.toml")
    return str(caught.value)


@pytest.mark.parametrize(
    ("text", "whole"),
    [
        (ONE + "port = 65536", "plant.toml: machine[1].port: got 65536; expected a port 1..65535"),
        (ONE + "port = true", "plant.toml: machine[1].port: got true; expected a port 1..65535"),
        (ONE + "port = 1.5", "plant.toml: machine[1].port: got 1.5; expected a port 1..65535"),
        (
            ONE + "paths = [11]",
            "plant.toml: machine[1].paths[1]: got 11; expected a path number 1..10",
        ),
        (
            ONE + "paths = [1.0]",
            "plant.toml: machine[1].paths[1]: got 1.0; expected a path number 1..10",
        ),
        (
            "[[fleet]]\nname_prefix='f'\nhost='h'\nfirst_port=0\ncount=1",
            "plant.toml: fleet[1].first_port: got 0; expected a port 1..65535",
        ),
        (
            ONE + "[mqtt.deadbands]\nfeed = -1",
            "plant.toml: mqtt.deadbands.feed: got -1; expected a number >= 0",
        ),
        (
            ONE + "[opcua]\nendpoint = 'opc.tcp://127.0.0.1:99999/x'",
            "plant.toml: opcua.endpoint: got 'opc.tcp://127.0.0.1:99999/x'; "
            "expected opc.tcp://HOST:PORT/PATH with a PORT of 0..65535",
        ),
    ],
)
def test_refusal_is_said_once(text: str, whole: str) -> None:
    assert refusal(text) == whole


def test_a_host_refusal_keeps_the_check_s_reason() -> None:
    """Where the check knows more than the range (a host with a port), its reason stays."""
    text = refusal(ONE.replace("'127.0.0.1'", "'127.0.0.1:8193'"))
    assert "give the host '127.0.0.1' and the port 8193 apart" in text


@pytest.mark.parametrize("key", ["fast", "slow", "alarms"])
def test_an_interval_below_the_shortest_is_refused(key: str) -> None:
    text = refusal(f"[groups]\n{key} = 0.001\n" + ONE)
    assert text == (
        f"plant.toml: groups.{key}: got 0.001; expected a number of seconds >= {MIN_INTERVAL:g}"
    )
    text = refusal(ONE + f"[machine.groups]\n{key} = 0.005")
    assert text.startswith(f"plant.toml: machine[1].groups.{key}: got 0.005;")


def test_the_shortest_interval_is_taken() -> None:
    config = parse_config(f"[groups]\nfast = {MIN_INTERVAL}\n" + ONE, "plant.toml")
    assert config.machines[0].groups.fast == MIN_INTERVAL


def test_a_deadband_typed_as_an_integer_is_kept_as_a_number_of_the_unit() -> None:
    config = parse_config(ONE + "[mqtt.deadbands]\nfeed = 2\n", "plant.toml")
    assert config.mqtt is not None
    assert config.mqtt.deadbands == {"feed": 2.0}
    assert isinstance(config.mqtt.deadbands["feed"], float)


async def test_an_opc_ua_port_in_use_is_one_line_naming_the_endpoint(tmp_path: Path) -> None:
    """The OPC UA server that cannot listen is exit 1 with one line that names it, and no
    traceback of the OPC UA library's before it."""
    taken = socket.socket()
    taken.bind(("127.0.0.1", 0))
    taken.listen()
    try:
        port = taken.getsockname()[1]
        endpoint = f"opc.tcp://127.0.0.1:{port}/plant/"
        config = tmp_path / "plant.toml"
        config.write_text(ONE + f'port = 1\n[opcua]\nendpoint = "{endpoint}"\n')
        line = await fails(EXIT_CNC, "gateway", str(config), prefix="focas-net gateway: ")
    finally:
        taken.close()
    assert line == (
        f"focas-net gateway: error: the OPC UA server on {endpoint} cannot start: "
        "address already in use"
    )


async def test_users_without_a_certificate_are_warned_in_the_gateways_words(
    tmp_path: Path,
) -> None:
    config = tmp_path / "plant.toml"
    config.write_text(
        ONE
        + "port = 1\n"
        + '[opcua]\nendpoint = "opc.tcp://127.0.0.1:0/plant/"\nanonymous = false\n'
        + '[[opcua.users]]\nname = "op"\npassword = "pw"\n'
    )
    async with gateway_process(str(config)) as gateway:
        assert gateway.ready.startswith("focas-net: gateway polling 1 machine; OPC UA ")
        assert await gateway.stop() == EXIT_OK
    warned = [line for line in gateway.err.decode().splitlines() if "WARNING" in line]
    assert any("passwords travel unencrypted" in w and "certificate" in w for w in warned)
    assert not any("asyncua" in w for w in warned), warned
