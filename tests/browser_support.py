"""The dashboard in a real browser, for the browser tests: headless Chromium driven by Selenium.

Each test serves its own machines and dashboard on 127.0.0.1 ephemeral ports, works the page
as a user would, and reads the result back over FOCAS (the packed client, and for alarms the
native FOCAS/2 client too). Every wait is a ``WebDriverWait`` with a timeout. Screenshots go to
the test's tmp directory, or to ``$FOCAS_NET_SCREENSHOTS`` when set (how ``docs/web-*.png``
are made).

Needs Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them) and the
``selenium`` and ``aiohttp`` packages; the tests skip, saying which is missing, without them.
"""

from __future__ import annotations

import asyncio
import os
import shutil
from collections.abc import AsyncIterator, Callable, Iterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

import pytest
from support import IO_TIMEOUT

from focas_net.client import FocasClient
from focas_net.server import FocasServer
from focas_net.sim import Machine, default_machine
from focas_net.web import Dashboard, stations_of

pytest.importorskip("aiohttp", reason="the web dashboard needs aiohttp (pip install '.[web]')")
selenium = pytest.importorskip("selenium", reason="the browser tests need selenium")

from selenium import webdriver  # noqa: E402
from selenium.common.exceptions import (  # noqa: E402
    StaleElementReferenceException,
    WebDriverException,
)
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.remote.webdriver import WebDriver  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
#: Longest wait for the page to show something.
WAIT = 15.0
#: Ticks of the live updates (fast: the page never waits long for a frame).
INTERVAL = 0.05

if not (os.access(CHROMIUM, os.X_OK) and os.access(CHROMEDRIVER, os.X_OK)):
    pytest.skip(
        f"the browser tests need Chromium ({CHROMIUM}) and chromedriver ({CHROMEDRIVER}): "
        "apt-get install chromium chromium-driver",
        allow_module_level=True,
    )


@pytest.fixture(scope="module")
def browser() -> Iterator[WebDriver]:
    """One headless Chromium for the module (each test opens its own dashboard in it)."""
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})  # the console, read back
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1500,1000",
        "--hide-scrollbars",
    ):
        options.add_argument(arg)
    try:
        driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    except WebDriverException as exc:
        pytest.skip(f"Chromium does not start here: {exc.msg}")
    driver.set_page_load_timeout(WAIT)
    driver.set_script_timeout(WAIT)
    try:
        yield driver
    finally:
        driver.quit()


class Page:
    """The browser, driven from the event loop: each call runs in a thread, so the machines
    and the dashboard keep being served meanwhile."""

    def __init__(self, driver: WebDriver, base: str, shots: Path) -> None:
        self.driver = driver
        self.base = base
        self.shots = shots

    async def call(self, fn: Callable[..., Any], *args: Any) -> Any:
        return await asyncio.to_thread(fn, *args)

    async def open(self, fragment: str = "") -> None:
        await self.call(self.driver.get, f"{self.base}#/{fragment}")

    async def until(self, condition: Callable[[WebDriver], Any], what: str) -> Any:
        wait = WebDriverWait(
            self.driver,
            WAIT,
            poll_frequency=0.05,
            ignored_exceptions=(StaleElementReferenceException,),
        )
        return await self.call(wait.until, condition, f"page never showed {what}")

    async def text_of(self, element_id: str, wanted: Callable[[str], bool], what: str) -> str:
        def check(d: WebDriver) -> str | bool:
            text = str(d.find_element(By.ID, element_id).text)
            return text if wanted(text) else False

        result: str = await self.until(check, what)
        return result

    async def click(self, element_id: str) -> None:
        """Click the element; the live updates may redraw it meanwhile, then click the new
        one (a bounded number of tries)."""

        def do() -> None:
            for _ in range(20):
                try:
                    self.driver.find_element(By.ID, element_id).click()
                    return
                except StaleElementReferenceException:
                    continue
            pytest.fail(f"{element_id} kept being redrawn")

        await self.call(do)

    async def type(self, element_id: str, text: str) -> None:
        def do() -> None:
            field = self.driver.find_element(By.ID, element_id)
            field.clear()
            field.send_keys(text)

        await self.call(do)

    async def errors(self) -> list[str]:
        """The errors the page's console logged since the last call (an exception the page
        did not catch is one; the browser's note of an answer with status 4xx, which the page
        shows as a refusal, is none)."""
        chrome: Any = self.driver  # Chrome's driver reads the console (get_log)
        entries = await self.call(chrome.get_log, "browser")
        # a refusal's answer (400, 409) is read by the page, not an error of it
        answered = "Failed to load resource: the server responded with a status of 4"
        return [
            str(e["message"])
            for e in entries
            if e["level"] == "SEVERE" and answered not in str(e["message"])
        ]

    async def screenshot(self, name: str) -> Path:
        path = self.shots / name
        ok = await self.call(self.driver.save_screenshot, str(path))
        assert ok and path.stat().st_size > 0
        return path


@asynccontextmanager
async def dashboard(
    browser: WebDriver,
    tmp_path: Path,
    machines: list[Machine] | None = None,
    *,
    read_only: bool = False,
) -> AsyncIterator[tuple[FocasServer, Dashboard, Page]]:
    """Machines and their dashboard on 127.0.0.1 ephemeral ports, and the browser on it."""
    fleet = machines if machines is not None else [default_machine()]
    shots = Path(os.environ.get("FOCAS_NET_SCREENSHOTS") or tmp_path)
    async with FocasServer(fleet, host="127.0.0.1", port=0, grace_period=1.0) as server:
        async with Dashboard(
            stations_of(server), port=0, read_only=read_only, interval=INTERVAL
        ) as web:
            page = Page(browser, web.url, shots)
            try:
                yield server, web, page
            finally:
                await page.call(browser.get, "about:blank")  # the page lets go of the socket


@asynccontextmanager
async def machine_page(
    browser: WebDriver, tmp_path: Path, machine: Machine | None = None
) -> AsyncIterator[tuple[FocasServer, Page]]:
    """The dashboard of one machine (a default one unless given), its view open in the
    browser, the console's earlier messages (of other tests' pages) read."""
    async with dashboard(browser, tmp_path, [machine or default_machine()]) as (server, _, page):
        await page.errors()
        await page.open("machine/0")
        yield server, page


def client_of(server: FocasServer, index: int = 0) -> FocasClient:
    host, port = server.listeners[index].address
    return FocasClient(host, port, timeout=IO_TIMEOUT)
