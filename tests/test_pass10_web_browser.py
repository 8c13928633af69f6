"""A tenth new user's pass over the dashboard, in a real browser (headless Chromium, as
tests/test_web_browser.py drives it): what the page's forms send, compared with the command
line's options for the same input."""

from __future__ import annotations

from pathlib import Path

from browser_support import browser, client_of, machine_page
from selenium.webdriver.remote.webdriver import WebDriver

__all__ = ["browser"]  # the fixture, used by name


# -- the page in a browser --------------------------------------------------------------------
async def test_the_pages_alarm_form_raises_an_alarm_of_an_axis(
    browser: WebDriver, tmp_path: Path
) -> None:
    """``sim alarm SV0411 --axis 2`` had no counterpart on the page, whose form raised alarms of
    no axis only; its axis box is checked by the same rule, its refusal shown in its words."""
    async with machine_page(browser, tmp_path) as (server, page):
        machine = server.machines[0]
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        await page.type("alarm-type", "SV")
        await page.type("alarm-no", "411")
        await page.type("alarm-axis", "5")
        await page.click("alarm-raise")
        message = await page.text_of("message", lambda t: "refused" in t, "the refusal")
        assert "axis 5 is outside 0..3: the path has 3 axes" in message
        assert machine.active_alarms() == []
        await page.type("alarm-axis", "2")
        await page.click("alarm-raise")
        shown = await page.text_of("alarms", lambda t: "SV0411" in t, "the alarm")
        assert "(axis 2)" in shown
        async with client_of(server) as cnc:
            assert [(a.axis_no, a.alm_type, a.alm_no) for a in await cnc.read_alarms()] == [
                (2, 6, 411)
            ]


async def test_the_spindle_override_is_on_the_page(browser: WebDriver, tmp_path: Path) -> None:
    """``sim override --spindle`` had no control on the page, which showed the feed and the
    rapid overrides only: its dial sets it, and its text shows the machine's value."""
    async with machine_page(browser, tmp_path) as (server, page):
        machine = server.machines[0]
        await page.text_of("spindle-ov-text", lambda t: t == "100 %", "the spindle override")
        await page.call(
            lambda: page.driver.execute_script(
                "const d = document.getElementById('spindle-ov'); d.value = 80;"
                "d.dispatchEvent(new Event('change'));"
            )
        )
        await page.text_of("spindle-ov-text", lambda t: t == "80 %", "80 %")
        assert machine.overrides() == (100, 100, 80)
        machine.set_overrides(spindle=0)
        await page.text_of("spindle-ov-text", lambda t: t == "0 %", "the machine's 0 %")
