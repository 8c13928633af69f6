"""The machine shapes the gateway's tests describe to their sinks: one builder, so that the
MQTT, OPC UA and poller tests share one declaration of a machine (its name, ``cnc_sysinfo``'s
words and the axes and spindles of each path); and one poll of a served machine, the values
the gateway reads of it."""

from __future__ import annotations

from poller_support import all_online, config, polling, until

from focas_net.gateway.model import MachineShape, PathShape, Sample
from focas_net.sim.nc import ManualClock

__all__ = ["machine_shape", "polled_once"]


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
