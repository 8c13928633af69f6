"""What the gateway says when the MQTT broker cannot be reached: the operating system's words
(never ``[Errno 104] ...``), the broker's refusal with its reason code, and a hint where the
settings may be the cause (TLS to a plain port, plain MQTT to port 8883, a peer that never
answers MQTT's CONNECT). Topics of what a machine no longer has are deleted."""

from __future__ import annotations

from dataclasses import replace

import aiomqtt
import pytest
from aiomqtt.exceptions import MqttConnectError
from gateway_support import machine_shape
from paho.mqtt.packettypes import PacketTypes
from paho.mqtt.reasoncodes import ReasonCode

from focas_net.errors import OPCUA_GOOD
from focas_net.gateway import AlarmChange, PathShape, Sample, Value, item
from focas_net.gateway._mqtt_messages import Publication
from focas_net.gateway.config import MqttSettings
from focas_net.gateway.mqtt import broker_reason

PLAIN = MqttSettings(host="127.0.0.1", port=1883)
TLS = MqttSettings(host="127.0.0.1", port=1883, tls=True)


@pytest.mark.parametrize(
    ("text", "settings", "said"),
    [
        ("[Errno 111] Connection refused", PLAIN, "connection refused"),
        (
            "[Errno 104] Connection reset by peer",
            TLS,
            "connection reset by peer during the TLS handshake "
            "(tls = true: is that the broker's TLS port?)",
        ),
        (
            "[SSL: WRONG_VERSION_NUMBER] wrong version number (_ssl.c:1000)",
            TLS,
            "TLS handshake failed (wrong version number) "
            "(tls = true: is that the broker's TLS port?)",
        ),
        (
            "TLS/SSL connection has been closed (EOF) (_ssl.c:2426)",
            TLS,
            "TLS handshake failed (TLS/SSL connection has been closed (EOF)) "
            "(tls = true: is that the broker's TLS port?)",
        ),
        (
            "[Errno 104] Connection reset by peer",
            MqttSettings(host="127.0.0.1", port=8883),
            "connection reset by peer before any answer to MQTT's CONNECT "
            "(port 8883 is MQTT over TLS by convention: tls = true?)",
        ),
        (
            "Operation timed out",
            MqttSettings(host="plc.local", port=8193),
            "no answer to MQTT's CONNECT in time (is that a broker's port?)",
        ),
        ("[Errno -2] Name or service not known", PLAIN, "name or service not known"),
    ],
)
def test_a_socket_error_is_words_with_a_hint(text: str, settings: MqttSettings, said: str) -> None:
    assert broker_reason(aiomqtt.MqttError(text), settings) == said


def test_a_refusal_of_the_broker_names_its_reason_code() -> None:
    refused = MqttConnectError(ReasonCode(PacketTypes.CONNACK, identifier=135))
    assert broker_reason(refused, PLAIN) == (
        "the broker refused: not authorized (MQTT reason code 135)"
    )


SHAPE = machine_shape("lathe", ("X1", "Z1"), ("X2", "Z2"))


def good(name: str, value: Value, path: int, key: str = "") -> Sample:
    return Sample("lathe", path, item(name), key, value, OPCUA_GOOD, 0.0)


def test_topics_of_what_a_machine_no_longer_has_are_deleted_once() -> None:
    """A machine described again without its second path and without Z1 gets an empty
    retained message (the broker's retained one deleted) on each value topic of the axes,
    spindle and path it lost and on the lost path's alarm list, once; what it still has
    stays, and the retained state published again after a reconnection leaves them out."""
    p = Publication("f", "gw")
    p.described(SHAPE)
    p.samples(
        [
            good("absolute", 1.0, 1, "X1"),
            good("absolute", 2.0, 1, "Z1"),
            good("spindle_load", 3.0, 1, "S1"),
            good("feed", 4.0, 1),
            good("absolute", 5.0, 2, "X2"),
            good("feed", 6.0, 2),
        ]
    )
    p.alarms([AlarmChange("lathe", 2, 4, 100, 0, "PARAMETER ENABLE", True, 0.0)])
    smaller = replace(SHAPE, paths=(PathShape(1, ("X1",), ("S1",)),))
    messages = p.described(smaller)
    deleted = sorted(m.topic for m in messages if m.payload == b"")
    assert deleted == [
        "f/lathe/path1/absolute/Z1",
        "f/lathe/path2/absolute/X2",
        "f/lathe/path2/alarms/active",
        "f/lathe/path2/feed",
    ]
    assert all(m.retain for m in messages)
    assert [m.topic for m in messages if m.payload != b""] == ["f/lathe/$model"]
    kept = {m.topic for m in p.retained()}
    assert {"f/lathe/path1/absolute/X1", "f/lathe/path1/feed"} <= kept
    assert not kept & set(deleted)
    assert [m for m in p.described(smaller) if m.payload == b""] == []  # once
    # a machine lost afterwards marks only what it has Bad
    lost = p.online("lathe", False, "refused", 1.0)
    assert not {m.topic for m in lost} & set(deleted)
