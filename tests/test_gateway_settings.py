"""The outputs' settings built in Python are refused as the file's are, with the same words
naming the key: one check per output (``OpcUaSettings.check``, ``MqttSettings.check``) that the
file's reader and the sinks both call, and one loopback test."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pytest

from focas_net.gateway import config, opcua
from focas_net.gateway.config import (
    ConfigError,
    MqttSettings,
    OpcUaSettings,
    OpcUaUser,
    parse_config,
)
from focas_net.gateway.mqtt import MqttSink
from focas_net.gateway.opcua import OpcUaSink

ONE = "[[machine]]\nname = 'm'\nhost = '127.0.0.1'\n"
USERS = (OpcUaUser("operator", "s3cret"),)
LOCAL = OpcUaSettings(endpoint="opc.tcp://127.0.0.1:0/focas_net/")


def test_one_loopback_test() -> None:
    assert opcua.is_loopback is config.is_loopback
    assert all(config.is_loopback(h) for h in ("127.0.0.1", "::1", "[::1]", "LOCALHOST"))
    assert not any(config.is_loopback(h) for h in ("0.0.0.0", "plant.example", None))


def refused_by_file(text: str, tmp_path: Path) -> str:
    with pytest.raises(ConfigError) as refused:
        parse_config(ONE + text, "plant.toml", folder=tmp_path)
    message = str(refused.value)
    assert message.startswith("plant.toml: ")
    return message.removeprefix("plant.toml: ")


@pytest.mark.parametrize(
    ("settings", "text"),
    [
        (
            replace(LOCAL, endpoint="opc.tcp://10.0.0.1:4840/", anonymous=True, users=USERS),
            "[opcua]\nendpoint = 'opc.tcp://10.0.0.1:4840/'\nanonymous = true",
        ),
        (replace(LOCAL, writes=True, anonymous=True), "[opcua]\nwrites = true\nanonymous = true"),
        (replace(LOCAL, writes=True), "[opcua]\nwrites = true"),
        (
            replace(LOCAL, endpoint="opc.tcp://10.0.0.1:4840/"),
            "[opcua]\nendpoint = 'opc.tcp://10.0.0.1:4840/'",
        ),
        (
            replace(LOCAL, endpoint="opc.tcp://10.0.0.1:4840/", anonymous=False, users=USERS),
            "[opcua]\nendpoint = 'opc.tcp://10.0.0.1:4840/'\nanonymous = false\n"
            "[[opcua.users]]\nname = 'operator'\npassword = 's3cret'",
        ),
        (replace(LOCAL, certificate=Path("c.pem")), "[opcua]\ncertificate = 'c.pem'"),
        (replace(LOCAL, endpoint="http://127.0.0.1/"), "[opcua]\nendpoint = 'http://127.0.0.1/'"),
    ],
)
def test_opcua_settings_are_refused_as_the_files_are(
    settings: OpcUaSettings, text: str, tmp_path: Path
) -> None:
    said = refused_by_file(text, tmp_path)
    assert said.startswith("opcua")
    with pytest.raises(ConfigError) as refused:
        OpcUaSink(settings)
    assert str(refused.value) == said


@pytest.mark.parametrize(
    ("settings", "text"),
    [
        (MqttSettings(prefix="a/"), "[mqtt]\nprefix = 'a/'"),
        (MqttSettings(prefix="/a"), "[mqtt]\nprefix = '/a'"),
        (MqttSettings(prefix="$SYS"), "[mqtt]\nprefix = '$SYS'"),
        (MqttSettings(prefix="a/+/b"), "[mqtt]\nprefix = 'a/+/b'"),
        (MqttSettings(prefix=""), "[mqtt]\nprefix = ''"),
        (MqttSettings(qos=3), "[mqtt]\nqos = 3"),
        (MqttSettings(port=0), "[mqtt]\nport = 0"),
        (MqttSettings(port=70000), "[mqtt]\nport = 70000"),
        (MqttSettings(host=""), "[mqtt]\nhost = ''"),
        (MqttSettings(host="127.0.0.1:80"), "[mqtt]\nhost = '127.0.0.1:80'"),
        (MqttSettings(buffer=0), "[mqtt]\nbuffer = 0"),
        (MqttSettings(keepalive=0), "[mqtt]\nkeepalive = 0"),
        (MqttSettings(deadbands={"mode": 1.0}), "[mqtt.deadbands]\nmode = 1.0"),
        (MqttSettings(deadbands={"feed": -1.0}), "[mqtt.deadbands]\nfeed = -1.0"),
        (MqttSettings(deadbands={"feed": math.inf}), "[mqtt.deadbands]\nfeed = inf"),
    ],
)
def test_mqtt_settings_are_refused_as_the_files_are(
    settings: MqttSettings, text: str, tmp_path: Path
) -> None:
    said = refused_by_file(text, tmp_path)
    assert said.startswith("mqtt.")
    with pytest.raises(ConfigError) as refused:
        MqttSink(settings)
    assert str(refused.value) == said


def test_settings_the_outputs_can_use_pass() -> None:
    LOCAL.check()
    assert LOCAL.anonymous_sessions and not replace(LOCAL, writes=True).anonymous_sessions
    MqttSettings(prefix="plant/a", deadbands={"feed": 5, "absolute": 0.01}).check()
    MqttSink(MqttSettings(prefix="plant/a"))
