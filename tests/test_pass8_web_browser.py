"""The eighth pass's dashboard cases in a real browser (:mod:`browser_support`): what the
fault form's arg box takes for each kind, and a drop armed from the page; the timers as
``focas-net watch`` writes them."""

from __future__ import annotations

import json
from pathlib import Path

from browser_support import browser, machine_page
from cli_support import at, ok
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.remote.webdriver import WebDriver
from selenium.webdriver.support.select import Select

from focas_net.cli.watch_cmds import duration_text
from focas_net.protocol import FaultKind
from focas_net.sim import default_machine
from focas_net.sim.nc import ManualClock

__all__ = ["browser"]  # the fixture, used by name


async def test_the_fault_form_says_a_drop_takes_no_arg_and_shuts_the_box(
    browser: WebDriver, tmp_path: Path
) -> None:
    """A DROP armed with 500 in the arg box was armed, the 500 unread, and only the box's
    tooltip said so: the box is shut for a drop and the page says why beside it."""
    async with machine_page(browser, tmp_path) as (server, page):
        await page.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#fault-kind option"), "kinds")

        def choose(kind: str) -> None:
            Select(page.driver.find_element(By.ID, "fault-kind")).select_by_value(kind)

        def arg_box() -> tuple[bool, str]:
            box = page.driver.find_element(By.ID, "fault-arg")
            return bool(box.is_enabled()), str(
                page.driver.find_element(By.ID, "fault-arg-note").text
            )

        assert await page.call(arg_box) == (True, "milliseconds")  # DELAY, the first kind
        for kind, shown in (
            ("DROP", (False, "DROP takes no arg")),
            ("SPLIT", (False, "SPLIT takes no arg")),
            ("ERROR", (True, "EW code, by number or name")),
            ("DROP", (False, "DROP takes no arg")),
        ):
            await page.call(choose, kind)
            assert await page.call(arg_box) == shown
        await page.type("fault-count", "2" + Keys.ENTER)  # the 500 in the shut box is not sent
        await page.text_of("faults", lambda t: "DROP -: 2 answers left" in t, "the drop armed")
        listed = server.listeners[0].faults.listing().faults
        assert [(f.kind, f.remaining, f.arg) for f in listed] == [(FaultKind.DROP, 2, 0)]
        assert await page.errors() == []


async def test_the_timers_read_as_watch_writes_them(browser: WebDriver, tmp_path: Path) -> None:
    """The page cut the timers to whole seconds (``1:02:03``) where ``watch`` writes tenths
    (``1:02:03.4``); on a hand-stepped clock both show the same now."""
    clock = ManualClock()
    machine = default_machine(sim_clock=clock)
    clock.advance(3723.45)
    async with machine_page(browser, tmp_path, machine) as (server, page):
        frame = json.loads(await ok("watch", *at(server.listeners[0]), "--count", "1", "--json"))
        times = frame["state"]["times_ms"]
        table = await page.text_of("timer-table", lambda t: "power on" in t, "the timers")
        shown = dict(line.rsplit(" ", 1) for line in table.splitlines()[:4])
        assert shown == {
            "power on": duration_text(times["power_on"]),
            "operating": duration_text(times["operating"]),
            "cutting": duration_text(times["cutting"]),
            "cycle": duration_text(times["cycle"]),
        }
        assert shown["power on"] == "1:02:03.4"
        assert await page.errors() == []


async def test_a_variable_made_vacant_on_the_page_shows_an_empty_box(
    browser: WebDriver, tmp_path: Path
) -> None:
    """A vacant variable is ``null`` in the page's answers (as ``macro get --json``); its box
    shows nothing, with its placeholder, never the word null."""
    machine = default_machine()
    machine.write_macro(500, 7)
    async with machine_page(browser, tmp_path, machine) as (_, page):
        await page.type("macro-search", "500-501")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#macros tr")) == 3, "#500")
        await page.type("macro-500", Keys.ENTER)  # the box emptied: vacant
        await page.text_of("message", lambda t: "write_macro: done" in t, "the write")
        assert machine.read_macro(500) is None

        def boxes() -> list[tuple[str, str]]:
            found = page.driver.find_elements(By.CSS_SELECTOR, "#macro-500, #macro-501")
            return [
                (str(b.get_attribute("value")), str(b.get_attribute("placeholder"))) for b in found
            ]

        assert await page.call(boxes) == [("", "vacant"), ("", "vacant")]
        assert await page.errors() == []
