"""The machine shapes the gateway's tests describe to their sinks: one builder, so that the
MQTT, OPC UA and poller tests share one declaration of a machine (its name, ``cnc_sysinfo``'s
words and the axes and spindles of each path); and one poll of a served machine, the values
the gateway reads of it; and one gated writer over a served machine, on either transport."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Literal

from poller_support import all_online, config, polling, until
from support import serving

from focas_net.client import FocasClient, NativeClient
from focas_net.gateway import MachineConfig, WriteGates
from focas_net.gateway.model import MachineShape, PathShape, Sample
from focas_net.gateway.writer import GatedWriter
from focas_net.sim import Machine
from focas_net.sim.nc import ManualClock

__all__ = ["ALL_WRITES", "gated_writer", "machine_shape", "polled_once"]

#: Every macro variable and parameter writable through the gateway.
ALL_WRITES = WriteGates(macros=((0, 99999),), params=((0, 99999),))


@asynccontextmanager
async def gated_writer(
    machine: Machine, protocol: Literal["native", "packed"], writes: WriteGates = ALL_WRITES
) -> AsyncIterator[tuple[GatedWriter, FocasClient | NativeClient]]:
    """The gateway's writer of ``machine``, served on 127.0.0.1 as the configured machine
    ``m1`` with ``writes``, reached by the client of ``protocol``; the writer and its client."""
    async with serving(machine) as served:
        kind_of = FocasClient if protocol == "packed" else NativeClient
        async with kind_of("127.0.0.1", served.port) as client:
            config = MachineConfig("m1", "127.0.0.1", served.port, protocol, writes=writes)
            yield GatedWriter(lambda name: (config, client)), client


async def polled_once(port: int) -> dict[tuple[int, str, str], Sample]:
    """The samples of the first reads of every group of the machine served on ``port`` of
    127.0.0.1 (called ``mill``, through FOCAS/2): what the gateway gives its outputs."""
    clock = ManualClock(1_000.0)
    async with polling([config("mill", port)], clock) as (poller, sink):
        await until(poller, clock, all_online(poller))
        clock.advance(10.0)  # (each group's first reads are staggered over its interval)
        await poller.step()
        return sink.of("mill")


def machine_shape(
    name: str = "lathe",
    *axes: tuple[str, ...],
    mt_type: str = "T",
    series: str = "G421",
    host: str = "127.0.0.1",
    port: int = 8193,
) -> MachineShape:
    """A 30i-class control called ``name`` with one path per entry of ``axes`` (its axis
    names; path N has spindle ``SN``), two paths of X and Z when none is given."""
    paths = axes or (("X", "Z"), ("X", "Z"))
    return MachineShape(
        name=name,
        host=host,
        port=port,
        protocol="native",
        cnc_type="31",
        mt_type=mt_type,
        series=series,
        version="30.0",
        paths=tuple(PathShape(i, names, (f"S{i}",)) for i, names in enumerate(paths, 1)),
    )
