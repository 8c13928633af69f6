"""What the gateway says when the MQTT broker cannot be reached: the operating system's words
(never ``[Errno 104] ...``), the broker's refusal with its reason code, and a hint where the
settings may be the cause (TLS to a plain port, plain MQTT to port 8883, a peer that never
answers MQTT's CONNECT)."""

from __future__ import annotations

import aiomqtt
import pytest
from aiomqtt.exceptions import MqttConnectError
from paho.mqtt.packettypes import PacketTypes
from paho.mqtt.reasoncodes import ReasonCode

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
            "connection reset by peer (tls = true: is that the broker's TLS port?)",
        ),
        (
            "[SSL: WRONG_VERSION_NUMBER] wrong version number (_ssl.c:1000)",
            TLS,
            "[SSL: WRONG_VERSION_NUMBER] wrong version number (_ssl.c:1000) "
            "(tls = true: is that the broker's TLS port?)",
        ),
        (
            "[Errno 104] Connection reset by peer",
            MqttSettings(host="127.0.0.1", port=8883),
            "connection reset by peer (port 8883 is MQTT over TLS by convention: tls = true?)",
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
