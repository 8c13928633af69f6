"""A confirming pass over the gateway and the labels every front end shares: the log tells a
machine never reached as unavailable and one that was online as lost."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
from poller_support import all_online, config, polling, until
from support import free_port

from focas_net.gateway.model import ITEMS
from focas_net.gateway.reads import _status
from focas_net.protocol import AlarmState, EmergencyState, StatusInfo
from focas_net.protocol.values import LabelledValue
from focas_net.server import FocasServer
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock


# -- a machine never reached is unavailable, one that was online is lost ----------------------
async def test_a_machine_never_reached_is_unavailable_in_the_log(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO, "focas_net.gateway.poller")
    clock = ManualClock(1_000.0)
    async with polling([config("mill", free_port())], clock) as (poller, sink):
        await until(poller, clock, lambda: poller.is_online("mill") is False)
    ((_, up, reason),) = sink.states
    assert not up and reason.startswith("refused: ")
    told = [m for m in caplog.messages if m.startswith("mill: ")]
    assert told == [f"mill: {reason}", f"mill: unavailable ({reason})"], told


async def test_a_machine_that_was_online_is_lost_in_the_log(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO, "focas_net.gateway.poller")
    clock = ManualClock(1_000.0)
    server = FocasServer(default_machine(), host="127.0.0.1", port=0, grace_period=0.5)
    await server.start()
    try:
        port = server.listeners[0].address[1]
        async with polling([config("mill", port)], clock) as (poller, sink):
            await until(poller, clock, all_online(poller))
            await server.aclose()
            await until(poller, clock, lambda: poller.is_online("mill") is False, 1.0)
    finally:
        await server.aclose()
    ups = [(up, reason) for _, up, reason in sink.states]
    assert ups[0] == (True, "") and not ups[1][0]
    lost = [m for m in caplog.messages if m.startswith("mill: lost (")]
    assert lost and lost[0] == f"mill: lost ({ups[1][1]})", caplog.messages
    assert not [m for m in caplog.messages if "unavailable" in m], caplog.messages


# -- the booleans of the status fields, as the docs map them ----------------------------------
def _either(labels: list[str]) -> str:
    words = [f"`{w}`" for w in labels]
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} or {words[-1]}"


@pytest.mark.parametrize(("name", "states"), [("emergency", EmergencyState), ("alarm", AlarmState)])
def test_the_docs_map_each_screen_word_of_emergency_and_alarm_to_the_gateways_boolean(
    name: str, states: type[LabelledValue]
) -> None:
    text = " ".join((Path(__file__).parents[1] / "docs" / "gateway.md").read_text().split())
    fields = dict.fromkeys(("hdck", "tmmode", "aut", "run", "motion", "mstb", "edit"), 0)
    shown = {}
    for state in states:
        status = StatusInfo(**fields, **{"emergency": 0, "alarm": 0, name: state.value})
        shown[state.label] = _status(1, status)[(1, name, "")]
    true = [label for label, on in shown.items() if on is True]
    false = [label for label, on in shown.items() if on is False]
    assert len(true) + len(false) == len(shown) and true
    assert f"`{name}` is true when the field reads {_either(true)}" in text
    assert f"false when it reads {_either(false)}" in text
    assert ITEMS[name].kind is bool
