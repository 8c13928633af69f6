"""``focas-net gateway CONFIG.toml`` with an ``[mqtt]`` table, as a user runs it: a simulated
2-path lathe served on 127.0.0.1, mosquitto, and a subscriber that sees the gateway's birth,
the lathe's ``$model`` and values of both paths, and ``offline`` once the gateway stops."""

from __future__ import annotations

import json
from pathlib import Path

from cli_support import gateway_process
from mosquitto_support import Broker, broker, subscriber
from support import serving

from focas_net.cli import EXIT_OK
from focas_net.gateway._mqtt_messages import ValuePayload
from focas_net.sim import load_machine
from focas_net.sim.nc import ManualClock

__all__ = ["broker"]  # the fixture, used by name

LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


async def test_the_gateway_publishes_a_2_path_lathe_to_the_broker(
    tmp_path: Path, broker: Broker
) -> None:
    async with serving(load_machine(LATHE, sim_clock=ManualClock())) as lathe:
        config = tmp_path / "plant.toml"
        config.write_text(
            f'[[machine]]\nname = "lathe"\nhost = "127.0.0.1"\nport = {lathe.port}\n'
            f'[mqtt]\nport = {broker.port}\nprefix = "plant/focas"\n'
            "[mqtt.deadbands]\nabsolute = 0.001\n"
        )
        state = "plant/focas/$gateway/focas-net/state"
        async with subscriber(broker, "plant/#") as seen:
            async with gateway_process(str(config)) as gateway:
                assert gateway.ready == (
                    f"focas-net: gateway polling 1 machine; MQTT 127.0.0.1:{broker.port}\n"
                )
                await seen.until(lambda s: s.latest(state) == b"online")
                model_topic = "plant/focas/lathe/$model"
                await seen.until(lambda s: s.latest(model_topic) is not None)
                model = json.loads(seen.latest(model_topic) or b"")
                assert [p["number"] for p in model["paths"]] == [1, 2]
                assert model["items"]["absolute"]["deadband"] == 0.001
                topics = [
                    f"{p['topic']}/absolute/{axis}" for p in model["paths"] for axis in p["axes"]
                ] + [f"{p['topic']}/mode" for p in model["paths"]]
                await seen.until(lambda s: all(s.latest(t) is not None for t in topics))
                assert {ValuePayload.decode(seen.latest(t) or b"").status for t in topics} == {
                    "Good"
                }
                code = await gateway.stop()
                await seen.until(lambda s: s.latest(state) == b"offline")
    assert code == EXIT_OK, gateway.err
    assert b"Traceback" not in gateway.err
