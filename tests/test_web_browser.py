"""The dashboard in a real browser: headless Chromium driven by Selenium
(:mod:`browser_support` starts it and serves the machines and their dashboard).

Each test works the page as a user would and reads the result back over FOCAS (the packed
client, and for alarms the native FOCAS/2 client too). Every wait is a ``WebDriverWait`` with a
timeout. Screenshots go to the test's tmp directory, or to ``$FOCAS_NET_SCREENSHOTS`` when set
(how ``docs/web-*.png`` are made).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from decimal import Decimal
from pathlib import Path
from typing import Any

from browser_support import Page, browser, client_of, dashboard, machine_page
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.remote.webdriver import WebDriver
from selenium.webdriver.support.select import Select
from support import IO_TIMEOUT

from focas_net.client import NativeClient
from focas_net.protocol import FaultKind
from focas_net.sim import default_machine, load_machine
from focas_net.sim.machine import MDI
from focas_net.sim.nc import ManualClock

__all__ = ["browser"]  # the fixture, used by name


async def test_the_fleet_view_shows_every_machine(browser: WebDriver, tmp_path: Path) -> None:
    machines = [default_machine() for _ in range(12)]
    for i, m in enumerate(machines):
        m.name = f"lathe-{i + 1:02d}"
    async with dashboard(browser, tmp_path, machines) as (server, _, page):
        await page.open()

        def tiles(d: WebDriver) -> list[Any] | bool:
            found = d.find_elements(By.CSS_SELECTOR, "#fleet .tile")
            return found if len(found) == len(machines) else False

        await page.until(tiles, "a tile per machine")
        shown = await page.call(
            page.driver.execute_script,
            """return [...document.querySelectorAll('#fleet .tile')].map(t =>
                [t.querySelector('.name').textContent, t.querySelector('.row').textContent])""",
        )
        assert [name for name, _ in shown] == [m.name for m in machines]
        ports = [f":{listener.port}" for listener in server.listeners]
        assert [row.split("MEM")[0] for _, row in shown] == ports
        summary = await page.text_of("fleet-summary", lambda t: "12 machines" in t, "the count")
        assert "0 running" in summary
        await page.screenshot("fleet.png")


async def test_cycle_start_on_the_page_runs_the_machine(browser: WebDriver, tmp_path: Path) -> None:
    async with dashboard(browser, tmp_path) as (server, _, page):
        async with client_of(server) as cnc:
            assert (await cnc.read_status()).run == 0
            await page.open("machine/0")
            await page.text_of("run-state", lambda t: t == "****", "the reset state")
            await page.click("cycle-start")
            await page.text_of("run-state", lambda t: t == "STRT", "STRT")
            assert (await cnc.read_status()).run == 3  # STRT through the packed protocol
            await page.screenshot("machine-running.png")


async def test_an_alarm_raised_on_the_page_reaches_both_protocols(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with dashboard(browser, tmp_path) as (server, _, page):
        await page.open("machine/0")
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        await page.type("alarm-type", "2")
        await page.type("alarm-no", "1234")
        await page.type("alarm-msg", "RAISED ON THE PAGE")
        await page.click("alarm-raise")
        await page.text_of("alarms", lambda t: "RAISED ON THE PAGE" in t, "the alarm")
        async with client_of(server) as cnc:
            packed = await cnc.read_alarms()
        host, port = server.listeners[0].address
        async with NativeClient(host, port, timeout=IO_TIMEOUT) as native:
            focas2 = await native.read_alarms()
        expected = (0, 2, 1234, "RAISED ON THE PAGE")
        assert [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in packed] == [expected]
        assert [(a.axis_no, a.alm_type, a.alm_no, a.msg) for a in focas2] == [expected]


async def test_a_pmc_bit_toggled_on_the_page_is_read_back(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with dashboard(browser, tmp_path) as (server, _, page):
        async with client_of(server) as cnc:
            assert await cnc.read_pmc_bit("X", 4, 3) is False
            await page.open("machine/0")
            await page.until(lambda d: d.find_elements(By.ID, "pmc-X4-3"), "the X area")
            await page.click("pmc-X4-3")  # X is set as the simulator sets it
            await page.until(
                lambda d: "on" in str(d.find_element(By.ID, "pmc-X4-3").get_attribute("class")),
                "X4.3 on",
            )
            assert await cnc.read_pmc_bit("X", 4, 3) is True
            await page.call(
                lambda: Select(page.driver.find_element(By.ID, "pmc-area")).select_by_value("R")
            )
            await page.until(lambda d: d.find_elements(By.ID, "pmc-R0-7"), "the R area")
            await page.click("pmc-R0-7")
            await page.until(
                lambda d: "on" in str(d.find_element(By.ID, "pmc-R0-7").get_attribute("class")),
                "R0.7 on",
            )
            assert await cnc.read_pmc_bit("R", 0, 7) is True


async def test_a_refused_parameter_write_shows_its_ew_name(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with dashboard(browser, tmp_path) as (server, _, page):
        await page.open("machine/0")
        await page.until(lambda d: d.find_elements(By.ID, "param-6713-0"), "parameter 6713")
        await page.type("param-search", "6713")
        await page.until(
            lambda d: len(d.find_elements(By.CSS_SELECTOR, "#params tr")) == 2, "one parameter"
        )
        await page.type("param-6713-0", "25")
        await page.click("param-save-6713-0")
        message = await page.text_of("message", lambda t: "refused" in t, "the refusal")
        assert "EW_PASSWD" in message
        async with client_of(server) as cnc:
            assert await cnc.read_param(6713) == 0
        await page.screenshot("refused.png")


async def test_the_panel_opens_the_parameter_write(browser: WebDriver, tmp_path: Path) -> None:
    machine = default_machine()
    machine.set_panel(mode=MDI)
    async with dashboard(browser, tmp_path, [machine]) as (server, _, page):
        await page.open("machine/0")
        await page.until(lambda d: d.find_elements(By.ID, "param-6713-0"), "parameter 6713")
        await page.click("pwe")
        await page.text_of("message", lambda t: "panel: done" in t, "PWE on")
        await page.type("param-6713-0", "25")
        await page.click("param-save-6713-0")
        await page.text_of("message", lambda t: "write_param: done" in t, "the write")
        async with client_of(server) as cnc:
            assert await cnc.read_param(6713) == 25


async def test_read_only_disables_the_controls_and_refuses(
    browser: WebDriver, tmp_path: Path
) -> None:
    machine = default_machine()
    before = machine.state_digest()
    async with dashboard(browser, tmp_path, [machine], read_only=True) as (_, web, page):
        await page.open("machine/0")
        await page.text_of("run-state", lambda t: t == "****", "the machine")
        await page.until(lambda d: d.find_element(By.ID, "ro-banner").is_displayed(), "banner")
        for control in ("cycle-start", "feed-hold", "reset", "pwe", "alarm-raise"):
            enabled = await page.call(
                lambda c=control: page.driver.find_element(By.ID, c).is_enabled()
            )
            assert not enabled, control
        status = await page.call(
            page.driver.execute_async_script,
            """const done = arguments[arguments.length - 1];
            fetch('/api/machines/0/actions/cycle', {method: 'POST',
                headers: {'Content-Type': 'application/json'},
                body: JSON.stringify({action: 'start'})})
              .then(async r => done([r.status, (await r.json()).ew_name]));""",
        )
        assert status == [403, "EW_PROT"]
        assert web.read_only
    assert machine.state_digest() == before


async def test_screenshots_of_a_fleet_at_work(browser: WebDriver, tmp_path: Path) -> None:
    """Twenty machines on one hand-stepped clock, started one after another, some in alarm,
    held or in MDI: the pictures of docs/web-fleet.png and docs/web-machine.png."""
    clock = ManualClock()
    machines = [default_machine(sim_clock=clock) for _ in range(20)]
    for i, m in enumerate(machines):
        m.name = f"focas-sim-0i-{i + 1}"
        m.cycle_start(repeat=True)
        clock.advance(1.7)
    machines[2].raise_alarm(0, 2, 1001, "LUBRICANT LOW")  # some history on the machine shown
    machines[2].clear_alarms()
    machines[2].reset()
    machines[2].cycle_start(repeat=True)
    async with dashboard(browser, tmp_path, machines) as (_, web, page):
        for _ in range(200):  # about a part and a half of machine time, the path recorded
            clock.advance(0.25)
            web.broadcaster.record_paths()
        machines[6].raise_alarm(0, 2, 1001, "LUBRICANT LOW")
        machines[11].feed_hold()
        machines[15].reset()
        machines[15].set_panel(mode=MDI)
        await page.call(page.driver.set_window_size, 1500, 1000)
        await page.open()
        await page.text_of("fleet-summary", lambda t: "20 machines" in t, "the fleet")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, ".tile")) == 20, "tiles")
        summary = await page.text_of("fleet-summary", lambda t: "17 running" in t, "17 running")
        assert "1 in alarm" in summary
        fleet_png = await page.screenshot("web-fleet.png")
        await page.call(page.driver.set_window_size, 1500, 1900)
        await page.open("machine/2")
        await page.text_of("run-state", lambda t: t == "STRT", "the machine at work")
        await page.until(
            lambda d: d.execute_script(
                "return document.querySelector('#program-text .cur') !== null"
            ),
            "the running block",
        )
        machine_png = await page.screenshot("web-machine.png")
        await page.call(page.driver.set_window_size, 1500, 1000)
    assert fleet_png.stat().st_size > 10_000 and machine_png.stat().st_size > 10_000


async def test_bit_parameters_show_their_bits_and_axes_and_take_hex_and_binary(
    browser: WebDriver, tmp_path: Path
) -> None:
    machine = default_machine()
    machine.set_panel(mode=MDI, pwe=1)
    async with machine_page(browser, tmp_path, machine) as (server, page):
        await page.until(lambda d: d.find_elements(By.ID, "param-1815-1"), "the parameters")
        await page.type("param-search", "1815")
        await page.until(lambda d: value_of_now(d, "param-1815-1") == "00110000", "8 bits")
        row = await page.text_of("params", lambda t: "1815" in t and "20 " not in t, "1815")
        assert "bit" in row and "two_word" not in row
        names = await page.call(
            page.driver.execute_script,
            "return [...document.querySelectorAll('#params .axis')].map(n => n.textContent)",
        )
        assert names == ["X", "Y", "Z"]  # each value named by its axis
        await page.type("param-1815-2", "10110001" + Keys.ENTER)  # edited as its 8 bits
        await page.text_of("message", lambda t: "write_param: done" in t, "the write")
        await page.type("param-1815-3", "0xC3")
        await page.click("param-save-1815-3")
        await page.until(lambda d: value_of_now(d, "param-1815-3") == "11000011", "0xC3 written")
        await page.type("param-1815-1", "176")  # a decimal would read as bits: refused
        await page.click("param-save-1815-1")
        why = await page.text_of("param-1815-1-why", lambda t: "176" in t, "176 refused")
        assert "8 bits #7..#0" in why
        async with client_of(server) as cnc:
            assert [await cnc.read_param(1815, axis=a) for a in (1, 2, 3)] == [0x30, 0xB1, 0xC3]
        await page.type("param-search", "1826")
        await page.text_of("params", lambda t: "two-word" in t, "the type of 1826")
        assert await page.errors() == []


async def test_an_address_of_no_machine_is_said_and_breaks_nothing(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with machine_page(browser, tmp_path) as (_, page):
        await page.text_of("run-state", lambda t: t == "****", "machine 0")
        await page.call(page.driver.execute_script, "location.hash = '#/machine/999'")
        notice = await page.text_of("notice", lambda t: "999" in t, "the notice")
        assert notice.startswith("no machine '999'")
        shown = await page.call(
            lambda: [
                page.driver.find_element(By.ID, view).is_displayed()
                for view in ("machine-view", "fleet-view")
            ]
        )
        assert shown == [False, True]  # never machine 0's view under another address
        await page.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#fleet .tile"), "the fleet")
        await page.call(page.driver.execute_script, "location.hash = '#/machine/0'")
        await page.until(lambda d: not d.find_element(By.ID, "notice").is_displayed(), "no notice")
        assert await page.errors() == []


async def test_a_fault_argument_that_is_not_a_number_is_refused_on_the_page(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with machine_page(browser, tmp_path) as (server, page):
        await page.until(lambda d: d.find_elements(By.CSS_SELECTOR, "#fault-kind option"), "kinds")
        await page.call(
            lambda: Select(page.driver.find_element(By.ID, "fault-kind")).select_by_value("DELAY")
        )
        await page.type("fault-arg", "abc")
        await page.click("fault-inject")
        message = await page.text_of("message", lambda t: "refused" in t, "the refusal")
        assert message == "inject_fault refused: arg: not a whole number: 'abc'"
        assert len(server.listeners[0].faults) == 0
        await page.type("fault-arg", "250")
        await page.click("fault-inject")
        await page.text_of("faults", lambda t: "DELAY 250 ms: 1 answer left" in t, "the delay")


async def test_enter_writes_a_macro_variable(browser: WebDriver, tmp_path: Path) -> None:
    async with machine_page(browser, tmp_path) as (server, page):
        await page.type("macro-search", "500-501")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#macros tr")) == 3, "#500")
        await page.type("macro-500", "12.5" + Keys.ENTER)
        await page.text_of("message", lambda t: "write_macro: done" in t, "the write")
        assert server.machines[0].read_macro(500) == Decimal("12.5")


async def test_an_alarm_message_beyond_ascii_is_refused_on_the_page(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with machine_page(browser, tmp_path) as (server, page):
        machine = server.machines[0]
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        await page.type("alarm-msg", "TEMP 40\u00b0C")
        await page.click("alarm-raise")
        message = await page.text_of("message", lambda t: "refused" in t, "the refusal")
        assert "alarm message must be ASCII" in message
        assert machine.active_alarms() == []
        machine.raise_alarm(0, 15, 1001, "EX1001 COOLANT LEVEL LOW")
        shown = await page.text_of("alarms", lambda t: "COOLANT" in t, "the alarm")
        assert shown == "EX1001 COOLANT LEVEL LOW"  # its code, once, as the CLI writes it


async def test_a_tile_counts_one_part_and_the_alarm_by_its_code(
    browser: WebDriver, tmp_path: Path
) -> None:
    machines = [default_machine(f"m{i}") for i in range(3)]
    for count, machine in enumerate(machines):
        machine.set_panel(mode=MDI, pwe=1)
        machine.write_param(machine.new_session(), 6711, 0, count)
    machines[2].raise_alarm(0, 15, 1001, "EX1001 COOLANT LEVEL LOW")
    async with dashboard(browser, tmp_path, machines) as (_, _, page):
        await page.open()
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, ".tile")) == 3, "tiles")

        def tiles(d: WebDriver) -> list[list[str]] | bool:
            found = d.execute_script(
                """return [...document.querySelectorAll('#fleet .tile')].map(t =>
                    [t.querySelector('.parts').textContent, t.querySelector('.alm').textContent])"""
            )
            return found if found[2][1].startswith("ALM") else False

        shown = await page.until(tiles, "the tiles' parts and alarm")
        assert [parts for parts, _ in shown] == ["0 parts", "1 part", "2 parts"]
        assert shown[2][1] == "ALM EX1001 COOLANT LEVEL LOW"
        icon = await page.call(
            page.driver.execute_async_script,
            """const done = arguments[arguments.length - 1];
            fetch(document.querySelector('link[rel=icon]').href).then(r => done(r.status));""",
        )
        assert icon == 200


async def value_of(page: Page, element_id: str) -> str:
    return str(
        await page.call(lambda: page.driver.find_element(By.ID, element_id).get_property("value"))
    )


async def test_writes_from_outside_show_and_a_refused_value_stays_with_its_reason(
    browser: WebDriver, tmp_path: Path
) -> None:
    machine = default_machine()
    async with machine_page(browser, tmp_path, machine) as (server, page):
        await page.type("param-search", "6713")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#params tr")) == 2, "6713")
        await page.type("macro-search", "500-501")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#macros tr")) == 3, "#500")
        async with client_of(server) as cnc:  # a client writes: the page follows
            await cnc.sim.set_panel(mode=MDI, pwe=True)
            await cnc.write_param(6713, 40)
            await cnc.write_macro(500, Decimal("7.5"))
        await page.until(lambda d: value_of_now(d, "param-6713-0") == "40", "40 from the client")
        await page.until(lambda d: value_of_now(d, "macro-500") == "7.5", "7.5 from the client")
        machine.set_panel(pwe=0)
        await page.type("param-6713-0", "25")
        await page.click("param-save-6713-0")
        why = await page.text_of("param-6713-0-why", lambda t: "EW_PASSWD" in t, "the reason")
        assert "parameter write enable (PWE) is off" in why
        machine.write_macro(501, Decimal(3))  # the lists are read again meanwhile
        await page.until(lambda d: value_of_now(d, "macro-501") == "3", "#501 from outside")
        assert await value_of(page, "param-6713-0") == "25"  # the refused value stays
        assert machine.read_param(6713, 0) == 40
        await page.type("macro-500", "1e3" + Keys.ENTER)
        why = await page.text_of("macro-500-why", lambda t: "1e3" in t, "the macro refusal")
        assert "no exponent" in why and await value_of(page, "macro-500") == "1e3"
        assert machine.read_macro(500) == Decimal("7.5")
        assert await page.errors() == []


def holding(part: str) -> Callable[[str], bool]:
    """A check that a text holds ``part``."""
    return lambda text: part in text


def value_of_now(driver: WebDriver, element_id: str) -> str:
    found = driver.find_elements(By.ID, element_id)
    return str(found[0].get_property("value")) if found else ""


async def test_number_boxes_take_ascii_digits_only_and_say_why(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with machine_page(browser, tmp_path) as (server, page):
        machine = server.machines[0]
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        for typed in ("\u0661\u0662", "1e3"):
            await page.type("alarm-no", typed)
            await page.click("alarm-raise")
            named = f"{typed!r}"
            message = await page.text_of("message", holding(named), f"{typed} refused")
            assert message.startswith("raise_alarm refused: alm_no: ")
        assert machine.active_alarms() == []
        await page.type("alarm-msg", "M" * 40)  # the machine's rule: it keeps 32 characters
        await page.type("alarm-no", "1000")
        await page.click("alarm-raise")
        message = await page.text_of("message", lambda t: "keeps 32" in t, "what was kept")
        assert message.endswith(f"the CNC keeps 32 characters of a message: {'M' * 32!r}")
        assert [a.msg for a in machine.active_alarms()] == ["M" * 32]
        machine.clear_alarms()
        await page.call(
            lambda: Select(page.driver.find_element(By.ID, "fault-kind")).select_by_value("DELAY")
        )
        await page.type("fault-arg", "70000")
        await page.click("fault-inject")
        message = await page.text_of("message", lambda t: "70000" in t, "the delay refused")
        assert message == "inject_fault refused: EW_DATA a delay is 0..60000 ms, got 70000"
        assert len(server.listeners[0].faults) == 0
        maxlength = "return document.querySelectorAll('input[maxlength]').length"
        assert await page.call(page.driver.execute_script, maxlength) == 0


async def test_searches_say_what_is_wrong_and_forget_it_after_a_good_one(
    browser: WebDriver, tmp_path: Path
) -> None:
    async with machine_page(browser, tmp_path) as (_, page):
        await page.until(lambda d: d.find_elements(By.ID, "macro-0"), "the macros")
        await page.type("macro-search", "600-500")
        note = await page.text_of("macro-note", lambda t: "empty range" in t, "empty range")
        assert "#600 is above #500" in note
        await page.type("macro-search", "1-99999")
        await page.text_of("macro-note", lambda t: "#99999 is beyond" in t, "beyond the cap")
        await page.type("macro-search", "500-501")
        await page.until(lambda d: d.find_element(By.ID, "macro-note").text == "", "no error")
        await page.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, "#macros tr")) == 3, "#500")
        await page.type("macro-search", "0")
        await page.text_of("macro-note", lambda t: "first 200 of" in t, "what is left out")
        await page.type("pmc-start", "R100" + Keys.ENTER)
        await page.until(lambda d: d.find_elements(By.ID, "pmc-R100-0"), "R100")
        assert await value_of(page, "pmc-area") == "R"
        await page.type("pmc-start", "E5" + Keys.ENTER)
        note = await page.text_of("pmc-note", lambda t: "EW_NOOPT" in t, "no area E")
        assert "the CNC has no PMC area E" in note
        await page.type("pmc-start", "104" + Keys.ENTER)
        await page.until(lambda d: d.find_elements(By.ID, "pmc-R104-0"), "R104")
        await page.until(lambda d: "EW" not in d.find_element(By.ID, "pmc-note").text, "no error")
        assert await page.errors() == []


async def test_enter_unlocks_and_a_longer_password_is_refused_not_cut(
    browser: WebDriver, tmp_path: Path
) -> None:
    machine = default_machine(param_password="1234")
    async with machine_page(browser, tmp_path, machine) as (_, page):
        await page.until(lambda d: d.find_elements(By.ID, "param-6713-0"), "parameter 6713")
        await page.type("param-password", "12345" + Keys.ENTER)
        message = await page.text_of("message", lambda t: "unlock" in t, "the refusal")
        assert message == (
            "unlock refused: EW_PASSWD parameter password '12345': must be 1..4 ASCII characters"
        )
        await page.type("param-password", "1234" + Keys.ENTER)
        await page.text_of("message", lambda t: t == "unlock: done", "unlocked")


LATHE = Path(__file__).resolve().parent.parent / "examples" / "lathe_2path.toml"


async def test_a_machine_of_two_paths_shows_each_and_the_page_acts_on_the_one_chosen(
    browser: WebDriver, tmp_path: Path
) -> None:
    lathe = load_machine(LATHE)
    async with dashboard(browser, tmp_path, [default_machine("mill"), lathe]) as (_, _, page):
        await page.open()

        def lines(d: WebDriver) -> list[list[str]] | bool:
            found: list[list[str]] = d.execute_script(
                """return [...document.querySelectorAll('#fleet .tile')].map(t =>
                    [...t.querySelectorAll('.row.path')].map(r => r.textContent))"""
            )
            return found if len(found) == 2 and found[1] else False

        shown = await page.until(lines, "a line per path")
        assert shown[0] == []  # a single-path machine's tile is as it was
        assert [line.split()[:3] for line in shown[1]] == [
            ["TURRET1", "MEM", "****"],
            ["TURRET2", "MEM", "****"],
        ]
        await page.open("machine/1")
        await page.text_of("path-2-state", lambda t: "MEM" in t, "path 2's card")
        await page.click("path-2-start")  # the cycle of path 2 only
        await page.text_of("message", lambda t: t == "cycle: done", "the start")
        assert lathe.status(path=2).run == 3 and lathe.status(path=1).run == 0
        await page.text_of("path-2-state", lambda t: "STRT O2001" in t, "path 2 running")
        await page.click("path-2-show")  # the details of path 2
        await page.text_of("crumb", lambda t: t.endswith("TURRET2"), "path 2 chosen")
        axes = await page.text_of("pos-table", lambda t: "X2" in t, "path 2's axes")
        assert "X1" not in axes and "Z2" in axes
        await page.type("alarm-no", "1234")
        await page.click("alarm-raise")
        await page.text_of("message", lambda t: t == "raise_alarm: done", "the alarm")
        assert [a.alm_no for a in lathe.active_alarms(path=2)] == [1234]
        assert lathe.active_alarms(path=1) == []
        await page.text_of("path-2-alarm", lambda t: "1234" in t, "path 2's alarm")
        await page.text_of("path-1-alarm", lambda t: t == "no alarm", "path 1 clear")
        await page.click("path-1-show")
        await page.text_of("crumb", lambda t: t.endswith("TURRET1"), "path 1 chosen")
        await page.text_of("alarms", lambda t: "no active alarm" in t, "path 1's alarms")
        await page.screenshot("web-paths.png")
        await page.open("machine/0")
        await page.text_of("run-state", lambda t: t == "****", "the mill")
        hidden = await page.call(
            lambda: not page.driver.find_element(By.ID, "paths-box").is_displayed()
        )
        assert hidden  # one path: no path section
        assert await page.errors() == []


async def test_a_long_alarm_message_is_cut_as_the_machine_cuts_it_and_the_page_says_so(
    browser: WebDriver, tmp_path: Path
) -> None:
    typed = "SPINDLE OVERHEAT ON THE LEFT SIDE OF THE HEAD"
    async with machine_page(browser, tmp_path) as (server, page):
        await page.text_of("alarms", lambda t: "no active alarm" in t, "no alarm")
        await page.type("alarm-type", "15")
        await page.type("alarm-no", "1001")
        await page.type("alarm-msg", typed)
        await page.click("alarm-raise")
        message = await page.text_of("message", lambda t: "done" in t, "the answer")
        assert message.endswith(f"the CNC keeps 32 characters of a message: {typed[:32]!r}")
        (alarm,) = server.machines[0].active_alarms()
        assert alarm.msg == typed[:32]


# -- a seventh new user's pass: counts and their nouns, an address typed in another script,
# the servo loads by axis, the armed faults in the command line's words, Enter in the alarm and
# fault boxes, the alarm history's time as the command line writes it

#: Choose a fault kind in the page's list.
_FAULT_KIND = "document.getElementById('fault-kind').value = '{}'"


async def test_one_machine_is_counted_in_the_singular(
    browser: WebDriver,
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
    browser: WebDriver,
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
        await page.call(page.driver.execute_script, _FAULT_KIND.format("DROP"))
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
    browser: WebDriver,
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


async def test_a_machine_without_a_program_shows_none_as_the_command_line_does(
    browser: WebDriver, tmp_path: Path
) -> None:
    """No program selected is ``none`` on the tile and in the machine view, as ``program`` and
    ``watch`` write it; the page wrote ``O0000``, a number no program can have."""
    path = tmp_path / "m.toml"
    path.write_text('[machine]\nname = "bare"\naxes = ["X", "Y"]\n', encoding="utf-8")
    machine = load_machine(path)
    async with dashboard(browser, tmp_path, [machine]) as (server, _, page):
        async with client_of(server) as cnc:
            numbers = await cnc.read_program_numbers()
        assert (numbers.running, numbers.main) == (0, 0)
        await page.errors()
        await page.open()

        def tile(d: WebDriver) -> str | bool:
            text = str(d.find_element(By.CSS_SELECTOR, "#fleet a").text)
            return text if "bare" in text else False

        shown = await page.until(tile, "the tile")
        assert "none" in shown.split() and "O0000" not in shown
        await page.open("machine/0")
        program = await page.text_of("m-program", bool, "the program")
        assert program == "none"
        assert await page.errors() == []
