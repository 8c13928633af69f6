"""The OPC UA sink's queue while its task is held back: each variable keeps its newest sample
(older ones coalesced), so no change is lost however far the task falls behind, and memory is
bounded by the number of variables; a machine's loss queued after its samples still wins."""

from __future__ import annotations

import asyncio
from collections.abc import Sequence

from opcua_support import MILL, cnc_path, connected, machine_node, running, sample

from focas_net.gateway.model import Sample
from focas_net.gateway.opcua import OpcUaSink

T0 = 1_800_000_000.0


def hold(sink: OpcUaSink) -> asyncio.Event:
    """Hold the sink's task at its next batch of samples until the event returned is set."""
    gate = asyncio.Event()
    apply = sink.apply_samples

    async def held(samples: Sequence[Sample]) -> None:
        await gate.wait()
        await apply(samples)

    sink.apply_samples = held  # type: ignore[method-assign]
    return gate


async def test_a_held_back_sink_keeps_every_variables_newest_sample() -> None:
    async with running() as sink:
        sink.described(MILL)
        await sink.flush()
        gate = hold(sink)
        sink.samples([sample("mill", 1, "feed", 1.0, time=T0)])  # the task holds on this one
        await asyncio.sleep(0)
        sink.samples([sample("mill", 1, "feed", 100.0, time=T0 + 1)])  # then never changes
        for i in range(2000):  # a busy variable, far more samples than it has variables
            sink.samples([sample("mill", 1, "parts", i, time=T0 + 2 + i)])
        assert sink.pending == 2  # feed and parts: one each
        assert sink.coalesced == 1999
        gate.set()
        await sink.flush()
        assert sink.pending == 0
        async with connected(sink) as client:
            root = await machine_node(client, "mill")
            feed = await cnc_path(client, root, "CncChannelList", "Channel_1", "ActFeedrate")
            dv = await feed.read_data_value()
            assert dv.StatusCode is not None and dv.StatusCode.is_good()
            assert dv.Value is not None and dv.Value.Value == 100.0
            ns = await client.get_namespace_index("urn:focas-net:gateway")
            parts = await root.get_child([f"{ns}:Focas", f"{ns}:Path_1", f"{ns}:parts"])
            assert await parts.read_value() == 1999


async def test_a_loss_queued_after_samples_leaves_them_bad() -> None:
    async with running() as sink:
        sink.described(MILL)
        await sink.flush()
        gate = hold(sink)
        sink.samples([sample("mill", 1, "feed", 1.0, time=T0)])
        await asyncio.sleep(0)
        sink.samples([sample("mill", 1, "feed", 2.0, time=T0 + 1)])
        sink.online("mill", False, "connection lost", T0 + 2)
        gate.set()
        await sink.flush()
        async with connected(sink) as client:
            root = await machine_node(client, "mill")
            feed = await cnc_path(client, root, "CncChannelList", "Channel_1", "ActFeedrate")
            dv = await feed.read_data_value(raise_on_bad_status=False)
            assert dv.StatusCode is not None and not dv.StatusCode.is_good()
