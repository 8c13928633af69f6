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
from focas_net.gateway import (
    MIN_INTERVAL,
    Gateway,
    GatewayConfig,
    GroupIntervals,
    MachineConfig,
    WriteGates,
)
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
            "plant.toml: mqtt.deadbands.feed: got -1; expected a finite number >= 0",
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
        f"plant.toml: groups.{key}: got 0.001; expected a finite number of seconds "
        f">= {MIN_INTERVAL:g}"
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
    # named with the port the server took, as the ready line names it
    endpoint = gateway.ready.rstrip("\n").rpartition("; OPC UA ")[2]
    assert any(f"OPC UA {endpoint}: users' passwords" in w for w in warned), (endpoint, warned)
    assert not any("asyncua" in w for w in warned), warned


def machine_refusal(*machines: MachineConfig) -> str:
    with pytest.raises(ConfigError) as caught:
        Gateway(GatewayConfig(machines))
    return str(caught.value)


@pytest.mark.parametrize(
    ("machine", "whole"),
    [
        (
            MachineConfig("mill 1", "127.0.0.1"),
            "machine[1].name: got 'mill 1'; expected a name of 1..64 letters, digits, '-', '_' "
            "or '.'",
        ),
        (
            MachineConfig("m", "127.0.0.1:8193"),
            "machine[1].host: got '127.0.0.1:8193'; expected a host name or address (host "
            "'127.0.0.1:8193' is a host and a port: give the host '127.0.0.1' and the port "
            "8193 apart)",
        ),
        (MachineConfig("m", "h", 0), "machine[1].port: got 0; expected a port 1..65535"),
        (
            MachineConfig("m", "h", protocol=5),  # type: ignore[arg-type]
            "machine[1].protocol: got 5; expected 'native' or 'packed'",
        ),
        (
            MachineConfig("m", "h", paths=(1, 11)),
            "machine[1].paths[2]: got 11; expected a path number 1..10",
        ),
        (MachineConfig("m", "h", paths=()), "machine[1].paths: got 0 entries; expected 1..10"),
        (
            MachineConfig("m", "h", timeout=-1),
            "machine[1].timeout: got -1; expected a finite number of seconds > 0",
        ),
        (
            MachineConfig("m", "h", groups=GroupIntervals(fast=0.001)),
            "machine[1].groups.fast: got 0.001; expected a finite number of seconds >= 0.01",
        ),
        (
            MachineConfig("m", "h", writes=WriteGates(macros=((600, 500),))),
            "machine[1].writes.macros[1][2]: got 500; expected an integer 600..32767",
        ),
        (
            MachineConfig("m", "h", writes=WriteGates(pmc=(("Q", 0, 9),))),
            "machine[1].writes.pmc[1]: got ('Q', 0, 9); expected (area, first, last): "
            "('R', 0, 99), the area one of XYFGRTCDKAE",
        ),
    ],
)
def test_a_machine_built_in_python_is_refused_as_the_files_is(
    machine: MachineConfig, whole: str
) -> None:
    assert machine_refusal(machine) == whole


def test_a_machine_name_given_twice_in_python_names_the_first() -> None:
    one = MachineConfig("m", "127.0.0.1")
    assert machine_refusal(one, MachineConfig("n", "h"), one) == (
        "machine[3].name: machine name 'm' is used twice (first by machine[1])"
    )


def test_good_machines_built_in_python_are_taken() -> None:
    gates = WriteGates(macros=((500, 599),), params=((6711, 6713),), pmc=(("R", 100, 199),))
    gateway = Gateway(GatewayConfig((MachineConfig("m", "::1", paths=(1, 2), writes=gates),)))
    assert gateway.config.machines[0].writes == gates


def test_a_gateway_file_and_a_machine_file_are_read_alike(tmp_path: Path) -> None:
    """A byte-order mark (Windows Notepad) is read past, a byte that is no UTF-8 is named as
    the machine file names it, and text that is no TOML is "not valid TOML" in both."""
    from focas_net.gateway.config import load_config
    from focas_net.sim import MachineFileError, load_machine

    marked = tmp_path / "marked.toml"
    marked.write_bytes(b"\xef\xbb\xbf" + ONE.encode())
    assert load_config(marked).machines[0].name == "mill-1"
    latin = tmp_path / "latin.toml"
    latin.write_bytes(b"# caf\xe9\n" + ONE.encode())
    with pytest.raises(ConfigError) as gateway:
        load_config(latin)
    with pytest.raises(MachineFileError) as machine:
        load_machine(latin)
    said = "not UTF-8 text: byte 0xE9 at byte 5 (save the file as UTF-8)"
    assert str(gateway.value) == f"{latin}: {said}"
    assert str(machine.value).endswith(said)
    assert refusal("[[machine]\n").startswith("plant.toml: not valid TOML: ")
