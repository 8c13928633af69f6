"""Helpers of the poller's tests: a sink that records, a machine's configuration on 127.0.0.1,
a poller stepped by hand on a ManualClock until a condition holds (a bounded number of turns),
peers that never answer or answer garbage."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Callable, Sequence
from contextlib import asynccontextmanager
from typing import Literal

import pytest
from support import LoopbackPeer

from focas_net.client import ReconnectPolicy
from focas_net.gateway import AlarmChange, GroupIntervals, MachineConfig, MachineShape, Sample
from focas_net.gateway.poller import Poller
from focas_net.sim.nc import ManualClock

#: Fast reconnects in real time (the poller's own first-connection retries follow the clock).
QUICK = ReconnectPolicy(initial_delay=0.01, max_delay=0.05, jitter=0.0)
#: Bound of the turns of a wait.
TURNS = 400


class RecordingSink:
    """A sink that keeps everything it is told."""

    def __init__(self) -> None:
        self.shapes: list[MachineShape] = []
        self.states: list[tuple[str, bool, str]] = []
        self.got: list[Sample] = []
        self.changes: list[AlarmChange] = []

    def described(self, shape: MachineShape) -> None:
        self.shapes.append(shape)

    def online(self, machine: str, online: bool, reason: str, time: float) -> None:
        self.states.append((machine, online, reason))

    def samples(self, samples: Sequence[Sample]) -> None:
        self.got.extend(samples)

    def alarms(self, changes: Sequence[AlarmChange]) -> None:
        self.changes.extend(changes)

    def of(self, machine: str) -> dict[tuple[int, str, str], Sample]:
        """The last sample of each key of ``machine``."""
        return {(s.path, s.item.name, s.key): s for s in self.got if s.machine == machine}

    def clear(self) -> None:
        self.got.clear()
        self.changes.clear()
        self.states.clear()


def config(name: str, port: int, protocol: Literal["native", "packed"] = "native") -> MachineConfig:
    return MachineConfig(
        name, "127.0.0.1", port, protocol, timeout=2.0, groups=GroupIntervals(1.0, 10.0, 1.0)
    )


@asynccontextmanager
async def polling(
    machines: Sequence[MachineConfig], clock: ManualClock
) -> AsyncIterator[tuple[Poller, RecordingSink]]:
    sink = RecordingSink()
    async with Poller(machines, [sink], clock=clock.now, policy=QUICK) as poller:
        yield poller, sink


async def until(
    poller: Poller, clock: ManualClock, done: Callable[[], bool], step: float = 0.0
) -> None:
    """Turn the poller (moving the clock by ``step`` each turn) until ``done()``."""
    for _ in range(TURNS):
        await poller.step()
        if done():
            return
        clock.advance(step)
        await asyncio.sleep(0.005)
    pytest.fail(f"not done within {TURNS} turns")


def all_online(poller: Poller) -> Callable[[], bool]:
    return lambda: all(poller.is_online(m) for m in poller.machines)


class Silent(LoopbackPeer):
    """A peer that accepts TCP and never answers (a hung control); ``asked`` counts the
    connections and the requests it got."""

    def __init__(self) -> None:
        self.asked = 0

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.asked += 1
        while await reader.read(4096):  # until the client gives up
            self.asked += 1
        writer.close()


class Garbage(Silent):
    """A peer that answers every request with bytes of no protocol."""

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.asked += 1
        while await reader.read(4096):
            self.asked += 1
            writer.write(b"\xff\x00garbage\x00\x00\x00\x08" * 4)
        writer.close()


#: Attempts 5 s apart on the poller's clock.
SLOW = ReconnectPolicy(initial_delay=5.0, max_delay=5.0, jitter=0.0)
