"""A fleet of 200 machines at work on their own, polled through the packed client for 10 s of
machine time (a hand-stepped clock: the wall time the test takes does not matter)."""

from __future__ import annotations

import asyncio
import math
from contextlib import AsyncExitStack
from dataclasses import dataclass, field, replace

from support import IO_TIMEOUT, serving

from focas_net import FocasClient, LoadMeters, StatusInfo
from focas_net.client.native import NativeClient
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine
from focas_net.sim.nc import DEFAULT_SCENARIO, ManualClock, fleet_seed

FLEET = 200
#: Machine seconds between two polls, and polls (10 s of machine time in all).
STEP = 2.0
POLLS = 5
#: The demo contour's envelope in machine coordinates (mm): X 0..80, Y 0..60, Z -2..50.
ENVELOPE = ((0.0, 80.0), (0.0, 60.0), (-2.0, 50.0))
#: The run states a running machine shows: STOP, HOLD, STRT (reset only once its parts are
#: made, and these run forever).
RUNNING_STATES = {1, 2, 3}


@dataclass
class Seen:
    """What one poll read of one machine."""

    status: StatusInfo
    machine: tuple[int, ...]
    feed: int
    spindle: int
    parts: int
    power_on_ms: int
    loads: LoadMeters


@dataclass
class History:
    polls: list[Seen] = field(default_factory=list)


def fleet(clock: ManualClock) -> list[Machine]:
    """Machines of the default scenario with more interruptions than a plant has, so that
    10 s show some of each, every machine with its own seed and phase."""
    scenario = replace(
        DEFAULT_SCENARIO, phase_span=30.0, pause_rate=30.0, tool_rate=10.0, alarm_rate=6.0
    )
    machines = []
    for i in range(FLEET):
        machine = default_machine(sim_clock=clock)
        machine.name = f"cell-{i + 1}"
        machine.start_scenario(replace(scenario, seed=fleet_seed(13, i)))
        machines.append(machine)
    return machines


async def poll(client: FocasClient) -> Seen:
    status, positions, feed, spindle, info, loads = await asyncio.gather(
        client.read_status(),
        client.read_positions("machine"),
        client.read_feed(),
        client.read_spindle_speed(),
        client.read_run_info(),
        client.read_loads(),
    )
    return Seen(
        status,
        tuple(positions.increments.values()),
        feed,
        spindle,
        info.parts_count,
        info.power_on_ms,
        loads,
    )


async def test_a_fleet_of_200_running_machines_gives_plausible_changing_values() -> None:
    clock = ManualClock()
    machines = fleet(clock)
    histories = [History() for _ in machines]
    async with FocasServer(machines, host="127.0.0.1", port=0, grace_period=1.0) as server:
        async with AsyncExitStack() as stack:
            clients = []
            for listener in server.listeners:
                host, port = listener.address
                clients.append(
                    await stack.enter_async_context(FocasClient(host, port, timeout=IO_TIMEOUT))
                )
            for _ in range(POLLS + 1):
                seen = await asyncio.gather(*(poll(c) for c in clients))
                for history, one in zip(histories, seen, strict=True):
                    history.polls.append(one)
                clock.advance(STEP)

    rapid = 24000 * math.sqrt(3)  # the demo machine's rapid rate on three axes at once
    states: set[int] = set()
    alarms = 0
    for history in histories:
        polls = history.polls
        for one in polls:
            assert one.status.run in RUNNING_STATES
            assert one.status.aut == 1  # MEM
            for value, (low, high) in zip(one.machine, ENVELOPE, strict=True):
                assert low * 1000 - 1 <= value <= high * 1000 + 1
            assert 0 <= one.feed <= rapid
            assert one.spindle in (0, 3000)  # S3000, or stopped
            assert len(one.loads.spindle) == 1 and len(one.loads.servo) == 3
            assert all(0 <= v <= 200 for v in (*one.loads.spindle, *one.loads.servo))
            if one.status.run != 3:
                assert one.feed == 0 and sum(one.loads.servo) == 0
            states.add(one.status.run)
            alarms += one.status.alarm
        parts = [one.parts for one in polls]
        assert parts == sorted(parts)  # never decreasing
        timers = [one.power_on_ms for one in polls]
        assert timers == [timers[0] + round(i * STEP * 1000) for i in range(POLLS + 1)]
        moved = len({one.machine for one in polls}) > 1
        stood = any(one.status.run != 3 for one in polls)
        assert moved or stood  # a machine that did not move was held, stopped or in alarm
    moving = sum(1 for h in histories if len({one.machine for one in h.polls}) > 1)
    assert moving >= 0.75 * FLEET
    assert states == RUNNING_STATES  # mostly STRT, some HOLD and STOP
    assert alarms > 0
    assert sum(histories[i].polls[-1].parts > histories[i].polls[0].parts for i in range(FLEET)) > 0
    # the machines are not in step: each that moved went its own way
    paths = [tuple(one.machine for one in h.polls) for h in histories]
    travelled = [p for p in paths if len(set(p)) > 1]
    assert len(set(travelled)) > 0.95 * len(travelled)


async def test_both_protocols_read_the_loads_of_the_cut() -> None:
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    async with serving(machine) as served:
        async with (
            FocasClient(served.host, served.port, timeout=IO_TIMEOUT) as packed,
            NativeClient(served.host, served.port, timeout=IO_TIMEOUT) as native,
        ):
            idle = await packed.read_loads()
            assert idle == LoadMeters((0,), (0, 0, 0))
            assert await native.read_spindle_loads() == (0,)
            machine.cycle_start()
            for _ in range(50):  # bounded: the demo contour cuts within 25 s
                clock.advance(0.5)
                if machine.engine.cutting:
                    break
            assert machine.engine.cutting
            loads = await packed.read_loads()
            assert loads.spindle[0] > 10
            assert max(loads.servo) > 0
            assert await native.read_spindle_loads() == loads.spindle
            assert await native.read_spindle_loads(1) == loads.spindle
            meters = await native.read_servo_meters()
            assert [m.name for m in meters] == ["X", "Y", "Z"]
            assert tuple(int(m.load) for m in meters) == loads.servo
