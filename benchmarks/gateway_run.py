"""focas_net's gateway as ``benchmarks.gateway`` measures it, in a process of its own:
``python -m benchmarks.gateway_run --targets FILE --mqtt-port P --opcua-port Q``.

It runs :class:`~focas_net.gateway.run.Gateway` over the machines of ``FILE`` (native
FOCAS/2, one path each, the fast group every ``--fast`` seconds, the alarm list as often, the
slow group every ``--slow``), with the outputs :func:`~focas_net.gateway.run.outputs` makes of
an MQTT section (the broker on 127.0.0.1:P) and an OPC UA section (a server on
127.0.0.1:Q), each when its module is there (``--sinks`` chooses among them), plus a sink of
its own that counts what the poller tells: the machines online, the samples, the samples
whose status is not Good.

Like ``benchmarks.gateway_poll``, it prints ``{"event": "ready", ...}`` once every machine is
online, then its cumulative counts once a second until stdin ends. A poll is a group of one
machine started by the poller (it starts a group again only once its last reads are all
answered, so a cycle that overruns shows as polls missing from those due); a failed read
shows as samples that are not Good, a lost machine as ``offline``.
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
import json
import sys
import time
from collections.abc import Callable, Sequence
from contextlib import AsyncExitStack
from functools import partial
from typing import Any, Final

from benchmarks.gateway_poll import emit, raise_nofile, report
from focas_net.errors import OPCUA_GOOD
from focas_net.gateway.config import (
    GatewayConfig,
    GroupIntervals,
    MachineConfig,
    MqttSettings,
    OpcUaSettings,
)
from focas_net.gateway.model import AlarmChange, MachineShape, Sample

SINKS: Final = ("mqtt", "opcua")
#: Seconds the outputs are given to take in what every machine's coming online told them,
#: once every machine is online; past it the gateway is measured with the outputs behind.
CATCH_UP: Final = 60.0
#: Statuses that are no failed read: an item the transport has not, no tool in use.
_NOT_ERRORS: Final = ("BadNotSupported", "BadNoDataAvailable")


class CountingSink:
    """A sink that counts what it is told (called in the poller's task only)."""

    def __init__(self) -> None:
        self.up: set[str] = set()
        self.lost = 0
        self.told = 0
        self.bad = 0
        self.alarm_changes = 0
        self.first_bad = ""

    def described(self, shape: MachineShape) -> None:
        pass

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        if online:
            self.up.add(machine)
            return
        self.up.discard(machine)
        self.lost += 1
        if not self.first_bad:
            self.first_bad = f"{machine} lost: {reason}"

    def samples(self, samples: Sequence[Sample]) -> None:
        self.told += len(samples)
        for sample in samples:
            if sample.status != OPCUA_GOOD and sample.status.name not in _NOT_ERRORS:
                self.bad += 1
                if not self.first_bad:
                    self.first_bad = f"{sample.machine} {sample.item.name}: {sample.status.name}"

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        self.alarm_changes += len(changes)


class GroupCounts:
    """The polls the poller started, by group (its ``_start(station, group)``, counted), and
    its turns (``_turn()``: one pass over every machine)."""

    def __init__(self) -> None:
        self.started: dict[str, int] = {}
        self.turns = 0

    def wrap_turn(self, turn: Callable[[], float]) -> Callable[[], float]:
        def counted() -> float:
            self.turns += 1
            return turn()

        return counted

    def wrap(self, start: Callable[[Any, str], None]) -> Callable[[Any, str], None]:
        started = self.started

        def counted(station: Any, group: str) -> None:
            started[group] = started.get(group, 0) + 1
            start(station, group)

        return counted


def config_of(
    targets: Sequence[tuple[str, int]],
    sinks: Sequence[str],
    *,
    fast: float,
    slow: float,
    timeout: float,
    mqtt_port: int,
    opcua_port: int,
) -> GatewayConfig:
    """The gateway's configuration: the machines ``m0000``.. of ``targets`` and the outputs
    ``sinks`` names."""
    groups = GroupIntervals(fast=fast, slow=slow, alarms=fast)
    machines = tuple(
        MachineConfig(f"m{i:04d}", host, port, timeout=timeout, groups=groups)
        for i, (host, port) in enumerate(targets)
    )
    return GatewayConfig(
        machines,
        opcua=(
            OpcUaSettings(endpoint=f"opc.tcp://127.0.0.1:{opcua_port}/focas_net/")
            if "opcua" in sinks
            else None
        ),
        mqtt=MqttSettings(port=mqtt_port, client_id="focas-net-bench") if "mqtt" in sinks else None,
    )


def available(sinks: Sequence[str]) -> list[str]:
    """The outputs of ``sinks`` whose module is there."""
    return [s for s in sinks if importlib.util.find_spec(f"focas_net.gateway.{s}") is not None]


def _drained(sink: object) -> bool:
    """Whether ``sink`` holds at most a hundred messages unsent (an MQTT sink's ``pending``)."""
    pending: int = getattr(sink, "pending", 0)
    return pending <= 100


async def _until(condition: Callable[[], bool]) -> None:
    """Until ``condition()`` holds, asked ten times a second (an output's buffer level has no
    event to wait on)."""
    while True:
        if condition():
            return
        await asyncio.sleep(0.1)


async def run(config: GatewayConfig, sinks: Sequence[str], ready_timeout: float) -> None:
    """The gateway with its outputs and the counting sink, until stdin ends."""
    from focas_net.gateway.run import Gateway, outputs

    gateway = Gateway(config)
    counting = CountingSink()
    groups = GroupCounts()
    poller: Any = gateway.poller
    poller._start = groups.wrap(poller._start)
    poller._turn = groups.wrap_turn(poller._turn)
    n = len(config.machines)
    entered: list[Any] = []
    async with AsyncExitStack() as stack:
        for output in outputs(config, gateway.writer):
            entered.append(await stack.enter_async_context(output))
            gateway.add_sink(entered[-1])
        gateway.add_sink(counting)
        started = time.monotonic()

        def progress() -> str:
            state = [f"{len(counting.up)}/{n} online", f"{counting.lost} lost"]
            for sink in entered:
                for name in ("applied", "published", "pending", "dropped"):
                    if hasattr(sink, name):
                        state.append(f"{type(sink).__name__}.{name} {getattr(sink, name)}")
            return f"{time.monotonic() - started:.0f} s: " + ", ".join(state)

        async def log_progress() -> None:
            while True:
                await asyncio.sleep(5)
                print(progress(), file=sys.stderr, flush=True)

        async with gateway:
            logging_task = asyncio.create_task(log_progress())
            while len(counting.up) < n:
                if time.monotonic() - started > ready_timeout:
                    raise RuntimeError(f"not every machine online: {progress()}")
                if not gateway.running:
                    await gateway.wait()
                await asyncio.sleep(0.1)
            # every machine online; then until the outputs have taken in what that told them
            # (the OPC UA server builds each machine's nodes as it is described)
            left = max(1.0, ready_timeout - (time.monotonic() - started))
            behind = ""
            try:
                async with asyncio.timeout(min(left, CATCH_UP)):
                    for sink in entered:
                        if hasattr(sink, "flush"):
                            await sink.flush()
                        await _until(partial(_drained, sink))
            except TimeoutError:
                # measured anyway: what they drop in the window is reported against them
                behind = progress()
            logging_task.cancel()
            emit(
                {
                    "event": "ready",
                    "machines": n,
                    "sinks": ",".join(sinks) or "none",
                    "behind": behind,
                }
            )

            def line() -> dict[str, Any]:
                return {
                    "event": "count",
                    "t": time.monotonic(),
                    "fast": groups.started.get("fast", 0),
                    "fast_errors": counting.bad,
                    "slow": groups.started.get("slow", 0),
                    "slow_errors": counting.lost,
                    "skipped": 0,
                    "x_samples": counting.told,
                    "x_alarm_polls": groups.started.get("alarms", 0),
                    "x_turns": groups.turns,
                    **{
                        f"x_{name}": sum(int(getattr(sink, name, 0)) for sink in entered)
                        for name in ("published", "dropped", "applied")
                    },
                    "error": counting.first_bad,
                }

            await asyncio.to_thread(report, line, config.machines[0].groups.fast)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.gateway_run")
    parser.add_argument("--targets", required=True, help="JSON file: [[host, port], ...]")
    parser.add_argument("--mqtt-port", type=int, default=1883)
    parser.add_argument("--opcua-port", type=int, default=4840)
    parser.add_argument("--sinks", default=",".join(SINKS), help="mqtt,opcua or none")
    parser.add_argument("--fast", type=float, default=1.0)
    parser.add_argument("--slow", type=float, default=10.0)
    parser.add_argument("--timeout", type=float, default=3.0)
    parser.add_argument("--ready-timeout", type=float, default=240.0)
    args = parser.parse_args(argv)
    raise_nofile()
    with open(args.targets, encoding="utf-8") as f:
        targets = [(str(host), int(port)) for host, port in json.load(f)]
    sinks = available([s for s in args.sinks.split(",") if s in SINKS])
    config = config_of(
        targets,
        sinks,
        fast=args.fast,
        slow=args.slow,
        timeout=args.timeout,
        mqtt_port=args.mqtt_port,
        opcua_port=args.opcua_port,
    )
    try:
        asyncio.run(run(config, sinks, args.ready_timeout))
    except RuntimeError as exc:
        emit({"event": "failed", "error": str(exc)})
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
