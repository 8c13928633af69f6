"""The page actions' arguments as the API receives them: a key an action does not take, a key
given twice, a JSON number with a point, a word where a number belongs, and the body itself
(a new user's pass over the web API, POSTing JSON of wrong types)."""

from __future__ import annotations

from decimal import Decimal
from typing import Any

import pytest
from support import serving

from focas_net.sim import default_machine
from focas_net.web import (
    ACTION_KEYS,
    ACTIONS,
    ActionError,
    Dashboard,
    Station,
    action_args,
    perform,
    stations_of,
)


def _station() -> Station:
    m = default_machine()
    m.set_panel(mode=0, pwe=1)  # MDI, PWE on: parameter writes allowed
    return Station(0, m)


def test_every_action_says_its_keys() -> None:
    assert set(ACTION_KEYS) == set(ACTIONS)
    assert all("path" in keys for keys in ACTION_KEYS.values())


def test_a_misspelt_key_is_refused_not_read_as_left_out() -> None:
    station = _station()
    m = station.machine
    m.raise_alarm(0, 3, 100, "KEPT")
    m.raise_alarm(0, 2, 5, "ALSO KEPT")
    with pytest.raises(ActionError) as refused:
        perform(station, "clear_alarms", {"type": 3})  # alm_type misspelt: clear all?
    assert str(refused.value) == ("clear_alarms takes no 'type' (it takes alm_no, alm_type, path)")
    assert len(m.active_alarms()) == 2  # nothing cleared
    with pytest.raises(ActionError, match=r"inject_fault takes no 'scope' \(it takes arg"):
        perform(station, "inject_fault", {"kind": "delay", "arg": 5, "scope": 7})
    with pytest.raises(ActionError, match="write_macro takes no 'val', 'x'"):
        perform(station, "write_macro", {"number": 500, "val": "1", "x": 2})
    assert m.read_macro(500) is None


def test_a_key_given_twice_is_refused() -> None:
    with pytest.raises(ActionError, match="the key 'number' is given twice"):
        action_args(b'{"number": 500, "number": 600, "value": "1"}')
    assert action_args(b'{"number": 500, "value": "1"}') == {"number": 500, "value": "1"}


@pytest.mark.parametrize(
    ("body", "words"),
    [
        (b"{", "the body is not JSON"),
        (b"\xff\xfe", "the body is not JSON"),
        (b'{"a": 1}{"a": 1}', "the body is not JSON"),
        (b"[]", "the body must be a JSON object"),
        (b"null", "the body must be a JSON object"),
    ],
)
def test_a_body_that_is_no_object_is_named(body: bytes, words: str) -> None:
    with pytest.raises(ActionError) as refused:
        action_args(body)
    assert str(refused.value) == words
    assert action_args(b"") == action_args(b"  ") == {}


@pytest.mark.parametrize(
    ("value", "stored"), [(1.5, Decimal("1.5")), (0.1, Decimal("0.1")), (-2.0, Decimal("-2.0"))]
)
def test_a_json_number_with_a_point_is_the_number_it_shows(value: float, stored: Decimal) -> None:
    station = _station()
    assert perform(station, "write_macro", {"number": 500, "value": value})["ok"]
    assert station.machine.read_macro(500) == stored


@pytest.mark.parametrize("value", [float("nan"), float("inf"), float("-inf")])
def test_a_json_number_that_is_not_finite_is_named(value: float) -> None:
    with pytest.raises(ActionError, match=r"value: a finite number is needed, got"):
        perform(_station(), "write_macro", {"number": 500, "value": value})


def test_a_json_number_with_a_point_for_a_whole_parameter_is_refused_as_typed() -> None:
    station = _station()
    words = r"parameter 1420 is not a real parameter: 1\.5 is no integer"
    with pytest.raises(ActionError, match=words):
        perform(station, "write_param", {"number": 1420, "value": 1.5, "axis": 1})
    perform(station, "write_param", {"number": 1420, "value": 1200.0, "axis": 1})
    assert station.machine.read_param(1420, 1) == 1200


@pytest.mark.parametrize(
    ("action", "args", "words"),
    [
        ("panel", {"pwe": "maybe"}, "pwe: expected 1, on, true, yes or set, or 0, off, false"),
        (
            "pmc_bit",
            {"area": "R", "address": "yes", "bit": 1},
            "address: not a whole number: 'yes'",
        ),
        ("write_macro", {"number": 500, "value": "seven"}, "value: not a number: 'seven'"),
        (
            "write_macro",
            {"number": 500, "value": "1e5"},
            "value: not a number: '1e5' (no exponent: write the digits)",
        ),
        (
            "pmc_bit",
            {"area": "R", "address": "1E3", "bit": 1},
            "address: not a whole number: '1E3' (no exponent: write the digits)",
        ),
    ],
)
def test_the_exponent_hint_is_given_for_an_exponent_only(
    action: str, args: dict[str, Any], words: str
) -> None:
    with pytest.raises(ActionError) as refused:
        perform(_station(), action, args)
    assert str(refused.value).startswith(words)
    if "exponent" not in words:
        assert "exponent" not in str(refused.value)


async def test_the_http_api_answers_400_naming_the_key() -> None:
    aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard tests need aiohttp")
    async with serving(default_machine()) as served:
        web = Dashboard(stations_of(served.server), port=0)
        async with web, aiohttp.ClientSession() as session:
            url = f"{web.url}api/machines/0/actions/write_macro"
            body = b'{"number": 500, "number": 501, "value": "1"}'
            headers = {"Content-Type": "application/json"}
            async with session.post(url, data=body, headers=headers) as response:
                assert response.status == 400
                assert await response.json() == {
                    "ok": False,
                    "error": "the key 'number' is given twice",
                }
            async with session.post(url, data=b"\xff\xfe", headers=headers) as response:
                assert (response.status, (await response.json())["error"]) == (
                    400,
                    "the body is not JSON",
                )
        assert served.machine.read_macro(500) is None
        assert served.machine.read_macro(501) is None


@pytest.mark.parametrize(
    ("typed", "on"), [("on", 1), (" YES ", 1), (True, 1), ("off", 0), (False, 0), ("0", 0), (1, 1)]
)
def test_a_switch_takes_the_command_lines_words_and_json_booleans(typed: object, on: int) -> None:
    """``{"pwe": "on"}`` was "not a whole number: 'on'", though ``sim panel --pwe on`` works."""
    station = _station()
    perform(station, "panel", {"pwe": 1 - on})
    perform(station, "panel", {"pwe": typed})
    assert station.machine.panel.pwe == on
    perform(station, "pmc_bit", {"area": "R", "address": 5, "bit": 2, "value": typed})
    assert station.machine.read_pmc("R", 5, 1)[0] == on << 2
