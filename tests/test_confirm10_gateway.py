"""A confirming pass over the gateway and the labels every front end shares: the log tells a
machine never reached as unavailable and one that was online as lost; the docs map each screen
word of ``emergency`` and ``alarm`` to the gateway's boolean; a path the CNC has not is worded
alike by the clients, the gateway's writes, the machine and the command line; a parameter
written with an axis past the path's says which to give; the page's tile reads the emergency
field by the gateway's rule; OPC UA's operation mode of no selection is BadOutOfRange; the OPC
UA endpoint's host is checked as a machine's; load_config of an empty name says so as the
command line does; a deadband of a number that names something is refused."""

from __future__ import annotations

import dataclasses
import logging
import re
from decimal import Decimal
from pathlib import Path
from typing import Literal

import pytest
from gateway_support import gated_writer
from poller_support import all_online, config, polling, until
from support import free_port

from focas_net._refusals import no_path
from focas_net.cli._args import parse_file_name
from focas_net.errors import EW, CncError
from focas_net.gateway import ConfigError, load_config, parse_config
from focas_net.gateway._opcua_model import _operation_mode
from focas_net.gateway.model import ITEMS
from focas_net.gateway.reads import _status
from focas_net.protocol import AlarmState, AutMode, EmergencyState, StatusInfo
from focas_net.protocol.values import LabelledValue
from focas_net.server import FocasServer
from focas_net.sim import MachineError, default_machine
from focas_net.sim.nc import ManualClock
from focas_net.web.view import machine_tile


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


# -- a path the CNC has not: one wording on every front end ---------------------------------
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_write_to_a_path_the_cnc_has_not_says_it_as_the_cli_and_the_page_do(
    protocol: Literal["native", "packed"],
) -> None:
    machine = default_machine()
    async with gated_writer(machine, protocol) as (writer, client):
        with pytest.raises(CncError) as refused:
            await writer.write_macro("m1", 100, Decimal("1.5"), 2)
        with pytest.raises(CncError) as read:
            await client.read_status(path=3)
    said = no_path(2, 1)
    assert said == "the CNC has no path 2: it has path 1 only"
    assert refused.value.ew == EW.PATH and str(refused.value).endswith(f"cnc_wrmacro: {said}")
    assert str(read.value).endswith(f": {no_path(3, 1)}"), read.value
    with pytest.raises(MachineError) as page:
        machine.status(path=2)
    assert str(page.value).endswith(said), page.value


# -- an axis past the path's: what to give, as the command line says it ---------------------
@pytest.mark.parametrize("protocol", ["packed", "native"])
async def test_a_parameter_written_with_an_axis_past_the_paths_says_which_to_give(
    protocol: Literal["native", "packed"],
) -> None:
    machine = default_machine()
    machine.set_panel("MDI", pwe=1)
    async with gated_writer(machine, protocol) as (writer, _):
        with pytest.raises(CncError) as refused:
            await writer.write_param("m1", 1420, 5000, 9)
    exc = refused.value
    assert exc.ew == EW.ATTRIB
    assert str(exc).endswith("; axis 9 is outside 1..3: the path has 3 axes: give Axis 1..3"), exc


# -- the emergency stop: one rule for the gateway's boolean and the page's tile ---------------
@pytest.mark.parametrize("state", list(EmergencyState))
async def test_the_tile_and_the_gateway_read_the_emergency_field_by_one_rule(
    state: EmergencyState, monkeypatch: pytest.MonkeyPatch
) -> None:
    machine = default_machine()
    real = machine.status
    monkeypatch.setattr(
        machine, "status", lambda path=1: dataclasses.replace(real(path=path), emergency=state)
    )
    fields = dict.fromkeys(("hdck", "tmmode", "aut", "run", "motion", "mstb", "alarm"), 0)
    gateway = _status(1, StatusInfo(**fields, emergency=state.value, edit=0))
    tile = machine_tile(0, machine, 8193)
    assert tile["emergency"] is gateway[(1, "emergency", "")] is (state == EmergencyState.EMG)


# -- OPC UA's operation mode: a mode it has no value for is BadOutOfRange, as the docs say -----
@pytest.mark.parametrize("mode", list(AutMode))
def test_each_mode_is_the_docs_operation_mode_and_no_selection_none(mode: AutMode) -> None:
    text = " ".join((Path(__file__).parents[1] / "docs" / "gateway.md").read_text().split())
    row = text.split("| `mode` |")[1].split("| `run` |")[0]
    got = _operation_mode(mode.label)
    if mode is AutMode.NOSEL:
        assert got is None  # (the variable BadOutOfRange: no mode of OPC 40502's)
        assert "`****` (no selection) → BadOutOfRange" in row
    else:
        assert isinstance(got, int) and got in (0, 1, 2)
        name = ("Manual", "MDA", "Automatic")[got]
        assert re.search(rf"\b{re.escape(mode.label)}\b[^;|]*→ {name} \({got}\)", row), mode
    assert _operation_mode("11") is None  # a number with no name


# -- the OPC UA endpoint's host: the host rule of every front end -----------------------------
@pytest.mark.parametrize(
    ("host", "why"),
    [
        ("256.0.0.1", "not an IPv4 address: host '256.0.0.1'"),
        ("plant..local", "host name 'plant..local' has a part of 0 characters"),
    ],
)
def test_an_endpoint_host_no_server_can_listen_on_is_named_as_a_machine_host_is(
    host: str, why: str
) -> None:
    text = (
        '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n[opcua]\n'
        f'endpoint = "opc.tcp://{host}:4840/"\n[[opcua.users]]\nname = "op"\npassword = "pw"\n'
    )
    with pytest.raises(ConfigError) as refused:
        parse_config(text, source="plant.toml")
    said = str(refused.value)
    assert said.startswith(
        f"plant.toml: opcua.endpoint: got 'opc.tcp://{host}:4840/'; expected opc.tcp://HOST:PORT"
    ), said
    assert why in said and "no way in" not in said and "certificate" not in said


# -- load_config of a name that names no file ---------------------------------------------
@pytest.mark.parametrize(
    ("name", "words"),
    [
        ("", "an empty name is no file or folder, got ''"),
        ("  ", "an empty name is no file or folder, got '  '"),
        ("plant\0.toml", "a file name holds no NUL character, got 'plant\\x00.toml'"),
    ],
)
def test_load_config_of_an_empty_name_says_so_as_the_command_line_does(
    name: str, words: str
) -> None:
    with pytest.raises(ConfigError) as refused:
        load_config(name)
    assert str(refused.value) == words
    assert parse_file_name_words(name) == words


def parse_file_name_words(name: str) -> str:
    with pytest.raises(ValueError) as refused:
        parse_file_name(name)
    return str(refused.value)


@pytest.mark.parametrize("path", [None, 5, b"plant.toml"])
def test_load_config_of_no_file_name_is_a_type_error_naming_it(path: object) -> None:
    with pytest.raises(TypeError) as refused:
        load_config(path)  # type: ignore[arg-type]
    assert str(refused.value) == (
        f"load_config(): path must be a file name (a str or a Path), got {path!r}"
    )


# -- a deadband on a number that names something ---------------------------------------------
@pytest.mark.parametrize("item", ["program", "main_program", "sequence", "tool"])
def test_a_deadband_of_a_number_that_names_something_is_refused(item: str) -> None:
    text = f'[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n[mqtt]\ndeadbands = {{ {item} = 1 }}\n'
    with pytest.raises(ConfigError) as refused:
        parse_config(text, source="plant.toml")
    said = str(refused.value)
    assert said.startswith(
        f"plant.toml: mqtt.deadbands.{item}: {item} is a number that names a program, a block or "
        "a tool, not a quantity: a deadband would hide a change of it (the items a deadband is "
        "for: absolute, cutting_time, "
    ), said
    listed = said.rpartition("for: ")[2]
    assert not {"program", "main_program", "sequence", "tool"} & set(listed[:-1].split(", "))
    assert "parts" in listed and "feed" in listed
