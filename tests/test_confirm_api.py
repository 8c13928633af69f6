"""The Python API and the gateway as a new user meets them, a confirming pass: what the
seventh pass did not try, each refused with the right exception naming the argument and what
was given, never a Python error of the library's insides."""

from __future__ import annotations

from typing import Any

import pytest

from focas_net.gateway import (
    Gateway,
    GatewayConfig,
    MachineConfig,
    MqttSettings,
    OpcUaSettings,
    check_machines,
    outputs,
)

_MACHINE = MachineConfig("m", "127.0.0.1")


@pytest.mark.parametrize("config", ["plant.toml", None, {"machines": [_MACHINE]}])
def test_outputs_names_a_config_that_is_no_gateway_config(config: Any) -> None:
    writer = Gateway(GatewayConfig((_MACHINE,))).writer
    with pytest.raises(TypeError, match=r"config must be a GatewayConfig \(load_config"):
        outputs(config, writer)


@pytest.mark.parametrize(
    ("section", "value", "words"),
    [
        ("mqtt", "127.0.0.1", r"config\.mqtt must be an MqttSettings or None, got '127\.0\.0\.1'"),
        ("mqtt", {"host": "h"}, r"config\.mqtt must be an MqttSettings or None, got \{'host'"),
        ("mqtt", OpcUaSettings(), r"config\.mqtt must be an MqttSettings or None, got OpcUa"),
        ("opcua", "opc.tcp://h:1/", r"config\.opcua must be an OpcUaSettings or None, got 'opc"),
        ("opcua", MqttSettings(), r"config\.opcua must be an OpcUaSettings or None, got Mqtt"),
    ],
)
def test_an_output_of_another_type_is_named_by_gateway_and_outputs(
    section: str, value: Any, words: str
) -> None:
    config = GatewayConfig((_MACHINE,), **{section: value})
    with pytest.raises(TypeError, match=words):
        Gateway(config)
    writer = Gateway(GatewayConfig((_MACHINE,))).writer
    with pytest.raises(TypeError, match=words):
        outputs(config, writer)


def test_the_sinks_name_settings_of_another_type() -> None:
    from focas_net.gateway.mqtt import MqttSink
    from focas_net.gateway.opcua import OpcUaSink

    with pytest.raises(TypeError, match=r"settings must be an MqttSettings, got None"):
        MqttSink(None)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"settings must be an OpcUaSettings, got \{'endpoint'"):
        OpcUaSink({"endpoint": "opc.tcp://127.0.0.1:0/"})  # type: ignore[arg-type]


@pytest.mark.parametrize("machines", [iter([_MACHINE]), (m for m in [_MACHINE]), {_MACHINE}])
def test_machines_that_are_no_sequence_are_named(machines: Any) -> None:
    with pytest.raises(TypeError, match=r"machines must be a tuple of MachineConfig, got"):
        check_machines(machines)
    with pytest.raises(TypeError, match=r"config\.machines must be a tuple of MachineConfig"):
        Gateway(GatewayConfig(machines))
