"""The Python API and the gateway as a new user meets them, a confirming pass: what the
seventh pass did not try, each refused with the right exception naming the argument and what
was given, never a Python error of the library's insides."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Literal

import pytest
from asyncua import ua
from opcua_support import LATHE, Handler, connected, machine_node, running
from poller_support import QUICK, RecordingSink, all_online, config, until

import focas_net
from focas_net import FocasServer, default_machine
from focas_net.gateway import (
    AlarmChange,
    Gateway,
    GatewayConfig,
    MachineConfig,
    MqttSettings,
    OpcUaSettings,
    check_machines,
    outputs,
)
from focas_net.gateway._opcua_types import CNC_NAMESPACE, CncId
from focas_net.gateway.mqtt import MqttSink
from focas_net.gateway.opcua import OpcUaSink
from focas_net.gateway.poller import Poller
from focas_net.sim import Machine
from focas_net.sim.nc import ManualClock

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


# -- the OPC UA server's conditions ----------------------------------------------------------
@pytest.mark.parametrize("on_machine", [False, True])
async def test_condition_refresh_sends_the_active_alarms_again(on_machine: bool) -> None:
    """docs/gateway.md: "ConditionRefresh on a subscription sends the active conditions
    again", to a subscription on the Server object as to one on the machine's object."""
    raised = AlarmChange("lathe", 2, 3, 10, 0, "IMPROPER G-CODE", True, 1_800_000_000.0)
    async with running() as sink:
        sink.described(LATHE)
        sink.alarms([raised])
        await sink.flush()
        async with connected(sink) as client:
            cnc = await client.get_namespace_index(CNC_NAMESPACE)
            alarm_type = client.get_node(ua.NodeId(CncId.ALARM_TYPE, cnc))
            handler = Handler()
            sub = await client.create_subscription(10, handler)
            source = await machine_node(client, "lathe") if on_machine else client.nodes.server
            await sub.subscribe_events(source, alarm_type)
            condition_type = client.get_node(ua.NodeId(ua.ObjectIds.ConditionType))
            await condition_type.call_method(
                ua.NodeId(ua.ObjectIds.ConditionType_ConditionRefresh),
                ua.Variant(sub.subscription_id, ua.VariantType.UInt32),
            )
            sent = await handler.event()
            assert sent.ConditionName == "PS0010"
            assert sent.Message.Text == "PS0010 IMPROPER G-CODE"
            assert getattr(sent, "ActiveState/Id") is True and sent.Retain is True
            with pytest.raises(ua.uaerrors.BadSubscriptionIdInvalid):
                await condition_type.call_method(
                    ua.NodeId(ua.ObjectIds.ConditionType_ConditionRefresh),
                    ua.Variant(sub.subscription_id + 1000, ua.VariantType.UInt32),
                )
            await sub.delete()


# -- the README ------------------------------------------------------------------------------
def test_the_readme_s_manual_clock_calls_run_as_written() -> None:
    """Each ``...(sim_clock=ManualClock())`` the README writes builds a machine as written."""
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    calls = re.findall(r"`((\w+)\(sim_clock=ManualClock\(\)\))`", readme)
    assert calls
    for call, name in calls:
        scope = {name: getattr(focas_net, name, None) or Machine, "ManualClock": ManualClock}
        assert isinstance(eval(call, scope), Machine), call


# -- the gateway's reason of a lost machine --------------------------------------------------
@pytest.mark.parametrize("protocol", ["native", "packed"])
async def test_a_machine_lost_is_told_with_why_not_with_the_client_s_state(
    protocol: Literal["native", "packed"],
) -> None:
    """docs/gateway.md: the outputs are told a machine lost "with the reason"; a connection
    the server closed is that (``closed: connection closed by HOST:PORT``), not the client's
    state (``lost: the connection is reconnecting``)."""
    clock = ManualClock(1_000.0)
    sink = RecordingSink()
    server = FocasServer(default_machine(), host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    port = server.listeners[0].address[1]
    try:
        async with Poller(
            [config("one", port, protocol)], [sink], clock=clock.now, policy=QUICK
        ) as poller:
            await until(poller, clock, all_online(poller))
            sink.clear()
            await server.aclose()
            await until(poller, clock, lambda: poller.is_online("one") is False, 1.0)
            [(_, online, reason)] = [s for s in sink.states if s[0] == "one"]
            assert online is False
            assert "is reconnecting" not in reason
            assert f"127.0.0.1:{port}" in reason, reason
    finally:
        await server.aclose()


# -- shards on one broker --------------------------------------------------------------------
def test_each_shard_is_a_gateway_of_its_own_name_on_the_broker() -> None:
    """Shards publish to one broker: each has its own ``$gateway/G/state`` topic (and will),
    so that one shard stopping cleanly does not say that the others are offline."""
    from focas_net.gateway import parse_config, shard

    text = '[[fleet]]\nname_prefix = "m"\nhost = "127.0.0.1"\nfirst_port = 9000\ncount = 4\n'
    config = parse_config(text + "[mqtt]\n")
    assert shard(config, 1, 1).mqtt == config.mqtt
    names = set()
    for i in (1, 2):
        settings = shard(config, i, 2).mqtt
        assert settings is not None and settings.gateway == f"focas-net-{i}"
        sink = MqttSink(settings)
        assert sink.publication.gateway_name == settings.gateway
        names.add(settings.gateway)
    assert len(names) == 2
    assert MqttSink(MqttSettings()).publication.gateway_name == "focas-net"
    with pytest.raises(ValueError, match=r"mqtt\.gateway: got ''; expected a non-empty string"):
        MqttSettings(gateway="").check()


# -- the packed client's max_frame -----------------------------------------------------------
async def test_an_answer_above_a_lowered_max_frame_is_named_as_the_client_s_limit() -> None:
    """A ``max_frame`` below a FOCAS answer refuses the answer: the error says so, not that
    the server does not speak FOCAS (which it does)."""
    from focas_net import FocasClient, ProtocolError

    async with FocasServer(default_machine(), host="127.0.0.1", port=0) as server:
        host, port = server.addresses[0]
        with pytest.raises(ProtocolError) as caught:
            async with FocasClient(host, port, max_frame=10, timeout=5) as cnc:
                await cnc.read_status()
    words = str(caught.value)
    assert "does not speak" not in words
    assert f"{host}:{port} sent a frame of " in words
    assert "more than this client's max_frame=10 takes" in words


# -- a gateway entered twice -----------------------------------------------------------------
async def test_a_gateway_is_entered_once_and_runs_once() -> None:
    """Entering a running gateway again would start a second poll loop on one poller, and one
    that has run has closed its clients: both are refused in words, and the running one goes
    on."""
    gateway = Gateway(GatewayConfig((MachineConfig("m", "127.0.0.1", 1),)))
    async with gateway:
        with pytest.raises(RuntimeError, match="the gateway is running already: enter it once"):
            async with gateway:
                pass
        assert gateway.running
    assert not gateway.running
    with pytest.raises(RuntimeError, match="has run and closed its clients: make a new Gateway"):
        async with gateway:
            pass
