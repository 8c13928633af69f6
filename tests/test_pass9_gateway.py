"""Pass 9 of the gateway and of the labels every front end shares: an alarm carries the same
keys on MQTT as on the command line and the web page, the password rule is one rule in one
wording, and a status field is named alike by the command line, the web page and the
gateway."""

from __future__ import annotations

import json
import logging
from typing import Any

import pytest
from cli_support import Cli, run_focas_net
from gateway_support import polled_once
from support import serving

from focas_net.client import FocasClient
from focas_net.gateway import AlarmChange, ConfigError, MachineConfig, MqttSettings, parse_config
from focas_net.gateway._mqtt_messages import ActiveAlarms, AlarmEvent, Publication
from focas_net.gateway.reads import describe
from focas_net.protocol import ActiveAlarm, Password
from focas_net.sim import MachineError, default_machine
from focas_net.web.view import machine_view, status_fields

# -- one alarm, one set of keys ---------------------------------------------------------------
ALARM = (2, 6, 411, "EXCESS ERROR IN MOVE")  # axis_no, alm_type, alm_no, msg


def _core(d: dict[str, Any]) -> dict[str, Any]:
    return {k: d[k] for k in ("code", "axis_no", "alm_type", "alm_no", "msg")}


async def test_an_alarm_has_the_same_keys_on_mqtt_as_on_the_cli_and_the_web_page(
    capsys: pytest.CaptureFixture[str],
) -> None:
    axis_no, alm_type, alm_no, msg = ALARM
    machine = default_machine()
    machine.raise_alarm(*ALARM)
    async with serving(machine) as served:
        cli = Cli(served, capsys)
        (listed,) = (await cli.json("alarms"))["active"]
    (shown,) = machine_view(0, machine, 8193)["alarms"]
    change = AlarmChange("m1", 1, alm_type, alm_no, axis_no, msg, True, 0.0)
    event, active = Publication("focas", "gw", {}).alarms([change])
    sent = json.loads(event.payload)
    assert set(listed) == {"code", "axis_no", "alm_type", "alm_no", "msg"}
    assert set(sent) == set(listed) | {"active", "time"}
    assert _core(sent) == _core(shown) == listed
    assert json.loads(active.payload)["alarms"] == [sent]
    decoded = AlarmEvent.decode(event.payload)
    assert (decoded.axis_no, decoded.alm_type, decoded.alm_no, decoded.msg) == ALARM
    kept = ActiveAlarms.decode(active.payload).alarms
    assert kept is not None and [a.key for a in kept] == [ActiveAlarm(*ALARM).key]
    assert (change.axis_no, change.msg) == (axis_no, msg)  # the change's names are the same


# -- one password rule, one wording -----------------------------------------------------------
@pytest.mark.parametrize("typed", ["abcde", "a\u00e9", "", "\uff11"])
async def test_a_password_is_refused_in_one_wording_by_the_codec_the_machine_and_the_cli(
    typed: str,
) -> None:
    reason = f"parameter password {typed!r}: must be 1..4 ASCII characters"
    with pytest.raises(ValueError) as codec:
        Password.from_text(typed)
    assert str(codec.value) == reason
    machine = default_machine()
    with pytest.raises(ValueError) as kept:
        machine.set_param_password(typed)
    assert str(kept.value) == reason
    with pytest.raises(MachineError) as offered:
        machine.unlock(machine.new_session(), typed)
    assert reason in str(offered.value)
    code, out, err = await run_focas_net("unlock", typed, "--port", "1")
    assert (code, out) == (2, "")
    assert err.strip() == (
        f"focas-net unlock: error: argument PASSWORD: {reason}; see focas-net unlock --help"
    )


# -- one status field, one label ----------------------------------------------------------------
async def test_the_gateway_names_mode_run_and_motion_as_the_cli_and_the_web_page_do(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A reset path in MEM: ``run`` ``****``, ``motion`` ``***`` on the CNC screen, in
    ``status``, on the web page, and on MQTT and OPC UA (the one table's label)."""
    machine = default_machine()
    async with serving(machine) as served:
        shown = await Cli(served, capsys).json("status")
        got = await polled_once(served.port)
    web = {f["field"]: f["name"] for f in status_fields(machine)}
    for item, field in (("mode", "mode"), ("run", "run"), ("motion", "motion")):
        assert got[(1, item, "")].value == shown[field]["name"] == web[field], item
    assert (shown["run"]["name"], shown["motion"]["name"]) == ("****", "***")


# -- the gateway's file: new cases --------------------------------------------------------------
MACHINE = '[[machine]]\nname = "m1"\nhost = "127.0.0.1"\n'


@pytest.mark.parametrize("secret", ['password = "p"', 'password_env = "P9_SECRET"'])
def test_an_mqtt_password_without_a_username_is_refused_not_dropped(
    secret: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """MQTT carries a password only beside a user name: the client would connect without
    it, anonymously, as if the key were not there."""
    monkeypatch.setenv("P9_SECRET", "s3cret")
    with pytest.raises(ConfigError) as refused:
        parse_config(MACHINE + f"[mqtt]\n{secret}\n", "plant.toml")
    assert str(refused.value) == (
        "plant.toml: mqtt.username: missing (MQTT sends a password only with a user name: "
        "give username too)"
    )
    with pytest.raises(ConfigError, match=r"^mqtt.username: missing \(MQTT sends"):
        MqttSettings(password="p").check()
    taken = parse_config(MACHINE + f'[mqtt]\nusername = "u"\n{secret}\n', "plant.toml").mqtt
    assert taken is not None and (taken.username, taken.password) == ("u", taken.password)


@pytest.mark.parametrize(("paths", "said"), [((1, 3), "path 3"), ((2, 3), "paths 2, 3")])
async def test_paths_the_cnc_has_not_are_named_in_words_and_none_left_is_said(
    paths: tuple[int, ...], said: str, caplog: pytest.LogCaptureFixture
) -> None:
    async with (
        serving(default_machine()) as served,
        FocasClient("127.0.0.1", served.port) as client,
    ):
        config = MachineConfig("m1", "127.0.0.1", port=served.port, protocol="packed", paths=paths)
        with caplog.at_level(logging.WARNING, "focas_net.gateway"):
            reader = await describe(config, client)
    (record,) = caplog.records
    left = "" if 1 in paths else "; nothing of it is read"
    assert record.getMessage() == (
        f"m1: the CNC has no {said}: it has path 1 only (machine.paths){left}"
    )
    assert [p.number for p in reader.shape.paths] == [p for p in paths if p == 1]
