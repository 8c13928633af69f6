"""The MQTT output hooks into aiomqtt's client where aiomqtt has no public way: a connection
attempt ended before the broker's answer fails at once, and a late answer after a given-up
attempt is disconnected. These are the attributes it uses, on the aiomqtt installed (the
project bounds aiomqtt below 3): should a release keep them otherwise, this test says so,
and the output falls back to aiomqtt's own timeout.
"""

from __future__ import annotations

import asyncio

import pytest

aiomqtt = pytest.importorskip("aiomqtt")


async def test_the_client_has_the_attributes_the_output_hooks_into() -> None:
    client = aiomqtt.Client("127.0.0.1", 1883)
    assert isinstance(client._connected, asyncio.Future)
    assert isinstance(client._disconnected, asyncio.Future)
    paho = client._client
    assert hasattr(paho, "on_disconnect")
    assert callable(paho.disconnect)
