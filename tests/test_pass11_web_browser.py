"""An eleventh new user's pass over the dashboard, in a real browser (headless Chromium, as
tests/test_web_browser.py drives it): what the page says of an action that changed nothing,
compared with the command line's words for it."""

from __future__ import annotations

from pathlib import Path

from browser_support import browser, machine_page
from selenium.webdriver.remote.webdriver import WebDriver

__all__ = ["browser"]  # the fixture, used by name


async def test_an_action_that_changes_nothing_says_why_not_done(
    browser: WebDriver, tmp_path: Path
) -> None:
    """The "Clear all" button with no alarm active, or "Raise" of an alarm active already, said
    ``clear_alarms: done`` and ``raise_alarm: done``; the page says what ``sim clear`` and
    ``sim alarm`` say."""
    async with machine_page(browser, tmp_path) as (server, page):
        machine = server.machines[0]
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        await page.click("alarm-clear")
        said = await page.text_of("message", lambda t: "clear_alarms" in t, "the clear")
        assert said == "clear_alarms: no active alarms; nothing to clear"
        await page.type("alarm-type", "PS")
        await page.type("alarm-no", "100")
        await page.click("alarm-raise")
        await page.text_of("message", lambda t: t == "raise_alarm: done", "the alarm")
        await page.type("alarm-msg", "ANOTHER")
        await page.click("alarm-raise")
        said = await page.text_of("message", lambda t: "already" in t, "the alarm active")
        assert said.startswith("raise_alarm: PS0100 is already active (with no message)")
        assert [a.msg for a in machine.active_alarms()] == [""]
        assert await page.errors() == []
