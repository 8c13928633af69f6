"""The seventh new user's pass over the dashboard, in the browser (headless Chromium, as
``test_web_browser`` drives it): counts and their nouns, an address typed in another script,
the servo loads by axis, the armed faults in the command line's words, Enter in the alarm and
fault boxes."""

from __future__ import annotations

import re
from pathlib import Path

from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.remote.webdriver import WebDriver
from test_web_browser import browser, dashboard, machine_page  # noqa: F401

from focas_net.protocol import FaultKind
from focas_net.sim import default_machine

#: Choose a fault kind in the page's list.
_KIND = "document.getElementById('fault-kind').value = '{}'"


async def test_one_machine_is_counted_in_the_singular(
    browser: WebDriver,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The fleet line said "1 machines"; an address of no machine "machines 0..0"."""
    async with dashboard(browser, tmp_path) as (_, _, page):
        await page.errors()
        await page.open()
        summary = await page.text_of("fleet-summary", bool, "the fleet line")
        assert summary == "1 machine, 0 running, 0 in alarm"
        await page.open("machine/%D9%A1")  # an Arabic-Indic 1, as the browser sends it
        notice = await page.text_of("notice", bool, "the notice")
        assert notice == "no machine '\u0661' (this dashboard shows machine 0)"
        await page.open("machine/")
        notice = await page.text_of("notice", lambda t: "given" in t, "the notice")
        assert notice == "no machine given (this dashboard shows machine 0)"
        assert await page.errors() == []


async def test_the_servo_loads_and_the_armed_faults_read_as_the_command_line_writes_them(
    browser: WebDriver,  # noqa: F811
    tmp_path: Path,
) -> None:
    """The loads were "servo load 0 %, 0 %, 0 %" (no axis; ``watch`` names each), an armed
    fault "DROP arg 0: 2 answer(s) left" (``sim faults``: ``drop  -``, a delay ``250 ms``)."""
    async with machine_page(browser, tmp_path, default_machine()) as (server, page):
        loads = await page.text_of("loads", bool, "the loads")
        assert loads == "spindle load 0 % | servo load X 0 %, Y 0 %, Z 0 %"
        table = await page.text_of("pos-table", bool, "the positions")
        assert table.splitlines()[0] == "absolute machine relative distance"  # as watch
        await page.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#fault-kind option"), "kinds")
        await page.call(page.driver.execute_script, _KIND.format("DROP"))
        await page.type("fault-count", "2" + Keys.ENTER)  # Enter arms it, as the button does
        await page.text_of("faults", lambda t: "DROP" in t, "the drop armed")
        await page.call(
            lambda: page.driver.execute_script(
                "document.getElementById('fault-kind').value='DELAY'"
            )
        )
        await page.type("fault-count", "1")
        await page.type("fault-arg", "250" + Keys.ENTER)
        faults = await page.text_of("faults", lambda t: "DELAY" in t, "the delay armed")
        assert faults.splitlines() == ["DROP -: 2 answers left", "DELAY 250 ms: 1 answer left"]
        listed = server.listeners[0].faults.listing().faults
        assert [(f.kind, f.remaining, f.arg) for f in listed] == [
            (FaultKind.DROP, 2, 0),
            (FaultKind.DELAY, 1, 250),
        ]
        assert await page.errors() == []


async def test_enter_in_the_alarm_boxes_raises_the_alarm(
    browser: WebDriver,  # noqa: F811
    tmp_path: Path,
) -> None:
    """Enter in the alarm's message box did nothing (the macro and parameter boxes write); the
    history's time was spelt otherwise than the command line's."""
    async with machine_page(browser, tmp_path) as (server, page):
        await page.text_of("run-state", bool, "the machine")
        await page.type("alarm-type", "15")
        await page.type("alarm-no", "1001")
        await page.type("alarm-msg", "COOLANT LEVEL LOW" + Keys.ENTER)
        await page.text_of("alarms", lambda t: "EX1001" in t, "the alarm")
        (alarm,) = server.machines[0].active_alarms()
        assert (alarm.alm_type, alarm.alm_no, alarm.msg) == (15, 1001, "COOLANT LEVEL LOW")
        # the history's time as alarms --history writes it (it was "2026-12-07 10:54:37Z")
        history = await page.text_of("history", bool, "the history")
        assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ EX1001 COOLANT LEVEL LOW", history)
        assert await page.errors() == []
