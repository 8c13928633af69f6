"""The dashboard's aiohttp shell against real machines: the REST actions, the WebSocket of live
frames, read-only, a clean stop; ``focas-net serve --web``."""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
import json
import logging
import os
import re
import signal
import sys
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from typing import Any

import pytest
from support import IO_TIMEOUT, killed_at_exit, wait_until

from focas_net.cli import serve
from focas_net.client import FocasClient, NativeClient
from focas_net.protocol import FaultKind
from focas_net.server import FocasServer
from focas_net.server.faults import fault_refusal
from focas_net.sim import Machine, default_machine, load_machine
from focas_net.web import Dashboard, stations_of

aiohttp = pytest.importorskip("aiohttp", reason="the web dashboard tests need aiohttp")

#: Ticks of the live updates in these tests (fast, so a frame is never far away).
INTERVAL = 0.02


@asynccontextmanager
async def dashboard(
    machines: list[Machine] | None = None, *, read_only: bool = False
) -> AsyncIterator[tuple[FocasServer, Dashboard]]:
    """Machines on 127.0.0.1 ephemeral ports and their dashboard on another."""
    fleet = machines if machines is not None else [default_machine()]
    async with FocasServer(fleet, host="127.0.0.1", port=0, grace_period=1.0) as server:
        web = Dashboard(stations_of(server), port=0, read_only=read_only, interval=INTERVAL)
        async with web:
            yield server, web


async def post(
    session: Any, web: Dashboard, action: str, args: dict[str, Any], index: int = 0
) -> tuple[int, dict[str, Any]]:
    url = f"{web.url}api/machines/{index}/actions/{action}"
    async with session.post(url, json=args) as response:
        return response.status, await response.json()


async def get(session: Any, url: str) -> tuple[int, Any]:
    async with session.get(url) as response:
        return response.status, await response.json()


async def test_the_dashboard_listens_on_loopback_and_serves_the_page() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        host, port = web.address
        assert host == "127.0.0.1" and port > 0 and web.url == f"http://127.0.0.1:{port}/"
        async with session.get(web.url) as response:
            assert response.status == 200
            page = await response.text()
        assert "/static/app.js" in page and "cycle-start" in page
        for name, kind in (("app.js", "javascript"), ("style.css", "css")):
            async with session.get(f"{web.url}static/{name}") as response:
                assert response.status == 200 and kind in response.content_type
        assert await get(session, f"{web.url}api/info") == (
            200,
            {"read_only": False, "machines": 1},
        )


async def test_the_page_has_an_icon() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        async with session.get(web.url) as response:
            page = await response.text()
        (icon,) = re.findall(r'<link rel="icon" href="([^"]+)"', page)
        for path in (icon.lstrip("/"), "favicon.ico"):
            async with session.get(f"{web.url}{path}") as response:
                assert response.status == 200, path
                assert response.content_type == "image/svg+xml"
                assert (await response.text()).startswith("<svg")


async def test_a_fault_argument_the_page_cannot_read_is_refused() -> None:
    async with dashboard() as (server, web), aiohttp.ClientSession() as session:
        status, body = await post(session, web, "inject_fault", {"kind": "DELAY", "arg": "abc"})
        assert status == 400 and body == {"ok": False, "error": "arg: not a whole number: 'abc'"}
        status, body = await post(session, web, "inject_fault", {"kind": "DELAY", "arg": ""})
        assert status == 400 and body["error"] == (
            "arg: a delay fault needs its delay in milliseconds (0..60000)"
        )
        assert len(server.listeners[0].faults) == 0  # nothing armed


async def test_a_refused_fault_argument_says_why_in_the_servers_words() -> None:
    async with dashboard() as (server, web), aiohttp.ClientSession() as session:
        for kind, count, arg in (("DELAY", "1", "70000"), ("ERROR", "1", "0"), ("DROP", "0", "")):
            args = {"kind": kind, "count": count, "arg": arg}
            status, body = await post(session, web, "inject_fault", args)
            number = int(FaultKind[kind])
            reason = fault_refusal(number, 1, int(count), int(arg or 0))
            assert reason is not None
            assert (status, body["ew_name"], body["error"]) == (409, "EW_DATA", reason)
        status, body = await post(session, web, "inject_fault", {"kind": "DELAY", "arg": "1e3"})
        assert status == 400 and "'1e3'" in body["error"] and "exponent" in body["error"]
        assert len(server.listeners[0].faults) == 0  # nothing armed


async def test_numbers_are_ascii_digits_and_nothing_is_cut() -> None:
    async with dashboard() as (server, web), aiohttp.ClientSession() as session:
        machine = server.machines[0]
        for typed in ("\u0661\u0662", "1e3", "1_000", "12.0", " "):
            args = {"alm_type": "3", "alm_no": typed, "msg": ""}
            status, body = await post(session, web, "raise_alarm", args)
            assert status == 400 and body["error"].startswith("alm_no: "), typed
        assert machine.active_alarms() == []
        status, body = await post(session, web, "write_param", {"number": 6713, "value": "1e3"})
        assert status == 400 and "'1e3'" in body["error"]
        status, body = await post(session, web, "write_param", {"number": 6713, "value": "25"})
        assert (status, body["ew_name"]) == (409, "EW_PASSWD") and "(PWE) is off" in body["error"]


async def test_searches_and_pmc_windows_say_what_is_wrong() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        base = f"{web.url}api/machines/0"
        status, body = await get(session, f"{base}/macros?q=600-500")
        assert status == 400 and "an empty range (#600 is above #500)" in body["error"]
        status, body = await get(session, f"{base}/macros?q=1-99999")
        assert status == 400 and "#99999 is beyond the variable numbers" in body["error"]
        status, body = await get(session, f"{base}/macros?q=2000-2100")
        assert status == 400 and "no variable in #2000..#2100 (the machine has #" in body["error"]
        status, body = await get(session, f"{base}/macros?q=500-501")
        assert status == 200 and len(body["macros"]) == 2 and body["note"] == ""
        status, body = await get(session, f"{base}/macros?q=")
        assert body["note"].startswith("the first 200 of ")
        status, body = await get(session, f"{base}/pmc?area=X&start=R100")
        assert (status, body["area"], body["start"]) == (200, "R", 100)
        status, body = await get(session, f"{base}/pmc?area=E&start=0")
        assert (status, body["ew_name"]) == (409, "EW_NOOPT")
        assert body["error"].startswith("the CNC has no PMC area E (it has X, Y, F")
        for start in ("R100.3", "\u0661", "Q5"):
            status, body = await get(session, f"{base}/pmc?area=X&start={start}")
            assert status == 400 and repr(start) in body["error"], start
        status, body = await get(session, f"{base}/pmc?area=X&start=-1")  # as `pmc read X -1`
        assert (status, body["error"]) == (400, "PMC start address -1 is outside 0..65535")


async def test_cycle_start_from_the_page_is_read_through_the_packed_client() -> None:
    async with dashboard() as (server, web), aiohttp.ClientSession() as session:
        host, port = server.listeners[0].address
        async with FocasClient(host, port, timeout=IO_TIMEOUT) as cnc:
            assert (await cnc.read_status()).run == 0
            assert await post(session, web, "cycle", {"action": "start"}) == (200, {"ok": True})
            assert (await cnc.read_status()).run == 3  # STRT
            assert await post(session, web, "cycle", {"action": "hold"}) == (200, {"ok": True})
            assert (await cnc.read_status()).run == 2  # HOLD


async def test_a_refused_parameter_write_answers_its_ew_name() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        status, body = await post(session, web, "write_param", {"number": 6713, "value": "5"})
        assert status == 409
        assert (body["ok"], body["ew_name"]) == (False, "EW_PASSWD")
        status, body = await post(session, web, "write_param", {"number": 6713, "value": "x"})
        assert status == 400 and "'x'" in body["error"]


async def test_bad_requests_are_answered_not_crashed() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        status, body = await get(session, f"{web.url}api/machines/5")
        assert status == 404 and "'5'" in body["error"]
        url = f"{web.url}api/machines/0/actions/cycle"
        async with session.post(url, data=b"{not json") as response:
            assert response.status == 400
            assert "JSON" in (await response.json())["error"]
        async with session.post(url, json=[1, 2]) as response:
            assert response.status == 400
        status, body = await get(session, f"{web.url}api/machines/0/pmc?area=E")
        assert status == 409 and body["ew_name"] == "EW_NOOPT"
        status, body = await get(session, f"{web.url}api/machines/0/macros?q=zz")
        assert status == 400 and "'zz'" in body["error"]


@pytest.mark.parametrize(
    ("action", "args", "status", "ew_name"),
    [
        ("raise_alarm", {"alm_type": 15, "alm_no": 40000, "msg": "BIG"}, 409, "EW_DATA"),
        ("raise_alarm", {"alm_type": 15, "alm_no": 99999999999}, 409, "EW_DATA"),
        ("write_macro", {"number": 100, "value": "1" * 5000}, 400, None),  # > 100 digits
        ("write_param", {"number": 1420, "axis": 1, "value": "1E+999999"}, 400, None),
        ("write_param", {"number": 1420, "axis": 1, "value": "1" * 5000}, 400, None),
    ],
)
async def test_what_a_machine_cannot_hold_is_refused_and_every_protocol_reads_on(
    caplog: pytest.LogCaptureFixture,
    action: str,
    args: dict[str, Any],
    status: int,
    ew_name: str | None,
) -> None:
    caplog.set_level(logging.WARNING)
    machine = default_machine()
    machine.set_panel(0, 1)  # MDI, PWE on: a parameter write gets as far as its value
    before = machine.state_digest()
    async with dashboard([machine]) as (server, web), aiohttp.ClientSession() as session:
        answered, body = await post(session, web, action, args)
        assert (answered, body.get("ew_name")) == (status, ew_name), body
        assert machine.state_digest() == before
        host, port = server.listeners[0].address
        async with (
            FocasClient(host, port, timeout=IO_TIMEOUT) as packed,
            NativeClient(host, port, timeout=IO_TIMEOUT) as native,
        ):
            for cnc in (packed, native):
                assert await cnc.read_alarms() == ()
                assert (await cnc.read_alarm_history()).entries == ()
    assert [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING] == []


async def test_the_rest_reads() -> None:
    machine = default_machine()
    machine.write_macro(100, 7)
    async with dashboard([machine]) as (_, web), aiohttp.ClientSession() as session:
        status, body = await get(session, f"{web.url}api/machines/0/params?q=6711")
        assert status == 200 and [p["number"] for p in body["params"]] == [6711]
        status, body = await get(session, f"{web.url}api/machines/0/macros?q=100-101")
        assert [m["value"] for m in body["macros"]] == [
            "7",
            None,
        ]  # vacant: null, as macro get --json
        status, body = await get(session, f"{web.url}api/machines/0/pmc?area=G&start=8")
        assert (body["area"], body["start"], len(body["bytes"])) == ("G", 8, 16)
        status, body = await get(session, f"{web.url}api/fleet")
        assert [t["name"] for t in body["machines"]] == [machine.name]
        status, body = await get(session, f"{web.url}api/machines/0")
        assert body["name"] == machine.name and len(body["positions"]) == 3


async def test_a_read_only_dashboard_refuses_and_changes_nothing() -> None:
    machine = default_machine()
    before = machine.state_digest()
    async with dashboard([machine], read_only=True) as (_, web):
        async with aiohttp.ClientSession() as session:
            assert (await get(session, f"{web.url}api/info"))[1]["read_only"] is True
            for action, args in (
                ("cycle", {"action": "start"}),
                ("raise_alarm", {"alm_type": 2, "alm_no": 1}),
                ("pmc_bit", {"area": "X", "address": 0, "bit": 0}),
                ("panel", {"pwe": 1}),
            ):
                status, body = await post(session, web, action, args)
                assert (status, body["ew_name"]) == (403, "EW_PROT"), action
    assert machine.state_digest() == before


async def receive(ws: Any, kind: str) -> dict[str, Any]:
    """The next frame of type ``kind`` (a bounded number of frames, each within the timeout)."""
    for _ in range(50):
        msg = await ws.receive(timeout=IO_TIMEOUT)
        assert msg.type == aiohttp.WSMsgType.TEXT, msg
        frame: dict[str, Any] = json.loads(msg.data)
        if frame["type"] == kind:
            return frame
    pytest.fail(f"no {kind} frame in 50")


LATHE = os.path.join(os.path.dirname(__file__), "..", "examples", "lathe_2path.toml")


async def test_each_path_is_read_and_worked_and_a_path_past_the_last_is_refused() -> None:
    lathe = load_machine(LATHE)
    async with dashboard([lathe]) as (_, web), aiohttp.ClientSession() as session:
        base = f"{web.url}api/machines/0"
        status, view = await get(session, f"{base}?path=2")
        assert (status, view["path_name"], view["axes"]) == (200, "TURRET2", ["X2", "Z2"])
        status, body = await get(session, f"{base}?path=3")
        assert (status, body["ew_name"]) == (409, "EW_PATH") and "path 3" in body["error"]
        status, body = await get(session, f"{base}/params?q=6711&path=x")
        assert status == 400 and body["error"].startswith("path: ")
        status, body = await post(session, web, "cycle", {"action": "start", "path": 2})
        assert status == 200 and lathe.status(path=2).run == 3 and lathe.status(path=1).run == 0
        status, body = await post(session, web, "cycle", {"action": "start", "path": 3})
        assert (status, body["ew_name"]) == (409, "EW_PATH")
        async with session.ws_connect(f"{web.url}ws") as ws:
            await ws.send_json({"subscribe": "machine", "index": 0, "path": 2})
            frame = await receive(ws, "machine")
            assert frame["data"]["path_no"] == 2 and frame["data"]["run"] == "STRT"
            await ws.send_json({"subscribe": "machine", "index": 0, "path": 5})
            error = await receive(ws, "error")
            assert error["error"] == "the CNC has no path 5: it has paths 1..2 (machine 0)"
        await wait_until(lambda: not web.broadcaster.subscriptions)


async def test_the_websocket_pushes_the_fleet_and_a_machine() -> None:
    machines = [default_machine() for _ in range(3)]
    for i, m in enumerate(machines):
        m.name = f"cell-{i}"
    async with dashboard(machines) as (server, web), aiohttp.ClientSession() as session:
        async with session.ws_connect(f"{web.url}ws") as ws:
            await ws.send_json({"subscribe": "fleet"})
            fleet = await receive(ws, "fleet")
            assert [t["name"] for t in fleet["data"]["machines"]] == ["cell-0", "cell-1", "cell-2"]
            ports = [listener.port for listener in server.listeners]
            assert [t["port"] for t in fleet["data"]["machines"]] == ports
            await ws.send_json({"subscribe": "machine", "index": 2, "pmc_area": "R"})
            frame = await receive(ws, "machine")
            assert frame["data"]["name"] == "cell-2" and frame["pmc"]["area"] == "R"
            machines[2].raise_alarm(0, 2, 500, "PUSHED")
            for _ in range(50):  # later ticks carry the change
                frame = await receive(ws, "machine")
                if frame["data"]["alarms"]:
                    break
            assert frame["data"]["alarms"][0]["msg"] == "PUSHED"
            await ws.send_str("nonsense")
            assert (await receive(ws, "error"))["error"] == "bad subscription: not JSON: 'nonsense'"
        await wait_until(lambda: not web.broadcaster.subscriptions)


async def test_pages_share_one_broadcaster_and_the_stop_closes_them() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        sockets = [await session.ws_connect(f"{web.url}ws") for _ in range(3)]
        for ws in sockets:
            await ws.send_json({"subscribe": "fleet"})
        for ws in sockets:
            await receive(ws, "fleet")
        assert len(web.broadcaster.subscriptions) == 3
        ticks = web.broadcaster.ticks
        await wait_until(lambda: web.broadcaster.ticks >= ticks + 3)
        # one fleet view per tick, whatever the number of pages (plus one per subscription)
        assert web.broadcaster.views_computed <= web.broadcaster.ticks + 3
        await web.stop()
        for ws in sockets:
            msg = await ws.receive(timeout=IO_TIMEOUT)
            while msg.type == aiohttp.WSMsgType.TEXT:
                msg = await ws.receive(timeout=IO_TIMEOUT)
            assert msg.type in (aiohttp.WSMsgType.CLOSE, aiohttp.WSMsgType.CLOSED)
            await ws.close()
        assert web.broadcaster.subscriptions == set()
        with pytest.raises(aiohttp.ClientConnectionError):
            await session.get(web.url)


async def test_a_page_that_never_reads_holds_up_no_other() -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        slow = await session.ws_connect(f"{web.url}ws")
        await slow.send_json({"subscribe": "machine", "index": 0})
        async with session.ws_connect(f"{web.url}ws") as fast:
            await fast.send_json({"subscribe": "machine", "index": 0})
            ticks = web.broadcaster.ticks
            for _ in range(20):  # twenty frames while the other page reads none
                await receive(fast, "machine")
            assert web.broadcaster.ticks >= ticks + 19
        subs = web.broadcaster.subscriptions
        assert subs and all(len(sub) <= sub.depth for sub in subs)  # what waits is bounded
        await slow.close()


# -- focas-net serve --web ----------------------------------------------------------------
def _parse(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    serve.register(parser.add_subparsers())
    return parser.parse_args(["serve", *argv])


def test_the_web_option() -> None:
    assert _parse().web is None
    assert _parse("--web", "8080").web == ("127.0.0.1", 8080)
    assert _parse("--web", "0.0.0.0:80").web == ("0.0.0.0", 80)


@pytest.mark.parametrize("value", ["http", "70000", "host:", "::1:80"])
def test_a_bad_web_value_is_named(value: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exc:
        _parse("--web", value)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--web" in err and repr(value) in err


def test_a_missing_aiohttp_is_named(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    real = importlib.util.find_spec

    def find_spec(name: str, *args: Any) -> Any:
        return None if name == "aiohttp" else real(name, *args)

    monkeypatch.setattr(importlib.util, "find_spec", find_spec)
    with pytest.raises(SystemExit):
        _parse("--web", "8080")
    assert "pip install 'focas-net[web]'" in capsys.readouterr().err


READY_WEB = re.compile(r"^focas-net: web dashboard(?P<modes> \([^)]*\))? on (?P<url>http://\S+)$")


@asynccontextmanager
async def serving_web(*args: str) -> AsyncIterator[tuple[asyncio.subprocess.Process, str]]:
    """``focas-net serve --port 0 ARGS --web 0`` until the dashboard's ready line."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", *args, "--web", "0",
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE, env={**os.environ},
    )  # fmt: skip
    assert proc.stdout is not None
    async with killed_at_exit(proc), asyncio.timeout(30.0):
        for _ in range(100):
            line = (await proc.stdout.readline()).decode().rstrip("\n")
            assert line, "serve ended before the dashboard's ready line"
            match = READY_WEB.match(line)
            if match:
                yield proc, match["url"]
                break


async def test_serve_web_prints_the_url_and_stops_on_sigterm() -> None:
    async with serving_web("--fleet", "2", "--run", "--read-only") as (proc, url):
        assert url.startswith("http://127.0.0.1:")
        async with aiohttp.ClientSession() as session:
            status, fleet = await get(session, f"{url}api/fleet")
            assert status == 200 and fleet["count"] == 2 and fleet["running"] == 2
            assert (await get(session, f"{url}api/info"))[1]["read_only"] is True
            status, body = await post_url(session, f"{url}api/machines/0/actions/cycle")
            assert (status, body["ew_name"]) == (403, "EW_PROT")
        proc.send_signal(signal.SIGTERM)
        async with asyncio.timeout(30.0):
            assert await proc.wait() == 0


async def post_url(session: Any, url: str) -> tuple[int, dict[str, Any]]:
    async with session.post(url, json={"action": "reset"}) as response:
        return response.status, await response.json()


async def test_serve_web_beyond_loopback_that_cannot_listen_is_one_line() -> None:
    """192.0.2.1 (TEST-NET-1) is no address of this host: the error alone, no warning of a
    dashboard that does not listen."""
    proc = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "focas_net", "serve", "--port", "0", "--web", "192.0.2.1:0",
        stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    async with killed_at_exit(proc), asyncio.timeout(30.0):
        out, err = await proc.communicate()
    assert proc.returncode == 1 and out == b""
    (error,) = err.decode().splitlines()
    assert error.startswith("focas-net serve: error: --web 192.0.2.1:0: cannot listen")


async def test_a_dashboard_beyond_loopback_warns_once_it_listens(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The warning comes once the dashboard listens (here on 127.0.0.1, taken for a host
    beyond the loopback, as nothing in a test may listen beyond it)."""
    import focas_net.web
    from focas_net.cli.serve import _dashboard

    monkeypatch.setattr(focas_net.web, "is_loopback", lambda host: False)
    async with FocasServer(default_machine(), host="127.0.0.1", port=0) as server:
        async with _dashboard(server, ("127.0.0.1", 0), read_only=False) as dashboard:
            assert dashboard is not None
            warned = capsys.readouterr().err
    assert warned == (
        "focas-net serve: warning: the web dashboard listens on 127.0.0.1, beyond loopback, "
        "with no authentication\n"
    )


@pytest.mark.parametrize(
    ("area", "status"), [("E", 409), ("e", 409), (" E", 409), ("Q", 400), ("", 400), ("EE", 400)]
)
async def test_a_pmc_area_is_refused_alike_by_a_read_and_a_write(area: str, status: int) -> None:
    """The machine's words and one status for both: EW_NOOPT (409) for an area this machine
    has not, 400 for a letter that is no PMC area."""
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        base = f"{web.url}api/machines/0"
        async with session.get(f"{base}/pmc", params={"area": area}) as response:
            read = response.status, await response.json()
        write = await post(session, web, "pmc_bit", {"area": area, "address": 0, "bit": 1})
    assert read[0] == write[0] == status, (read, write)
    assert read[1] == write[1], (read, write)
    if status == 409:
        assert read[1]["ew_name"] == "EW_NOOPT"
        has = "X, Y, F, G, R, T, C, D, K, A"
        assert read[1]["error"] == f"the CNC has no PMC area E (it has {has})"
    else:
        assert read[1]["error"] == (
            f"unknown PMC area {area!r} (one of X, Y, F, G, R, T, C, D, K, A, E)"
        )


@pytest.mark.parametrize(
    ("message", "reason"),
    [
        ("nonsense", "bad subscription: not JSON: 'nonsense'"),
        ("[1]", "bad subscription: a JSON object is expected, got [1]"),
        (
            '{"subscribe": "tiles"}',
            'bad subscription: "subscribe" is "fleet" or "machine", got \'tiles\'',
        ),
        ('{"subscribe": "machine"}', 'bad subscription: "index" is missing (a machine\'s number)'),
        (
            '{"subscribe": "machine", "index": "0"}',
            "bad subscription: \"index\" is a machine's number, got '0'",
        ),
        ('{"subscribe": "machine", "index": 9}', "no machine 9 (this dashboard shows machine 0)"),
        (
            '{"subscribe": "machine", "index": 0, "path": true}',
            'bad subscription: "path" is a whole number, got true',
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_area": 5}',
            'bad subscription: "pmc_area" is a PMC area\'s letter, got 5',
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_start": 1.5}',
            'bad subscription: "pmc_start" is a whole number, got 1.5',
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_area": "Q"}',
            "PMC window: unknown PMC area 'Q' (one of X, Y, F, G, R, T, C, D, K, A, E)",
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_area": "E"}',
            "PMC window: the CNC has no PMC area E (it has X, Y, F, G, R, T, C, D, K, A)",
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_start": -1}',
            "PMC window: PMC start address -1 is outside 0..65535",
        ),
        (
            '{"subscribe": "machine", "index": 0, "pmc_start": 128}',
            "PMC window: X128 goes past the end of PMC area X (X0..X127)",
        ),
    ],
)
async def test_a_refused_subscription_says_why_and_keeps_the_one_before(
    message: str, reason: str
) -> None:
    async with dashboard() as (_, web), aiohttp.ClientSession() as session:
        async with session.ws_connect(f"{web.url}ws") as ws:
            await ws.send_json({"subscribe": "machine", "index": 0, "pmc_area": "R"})
            assert (await receive(ws, "machine"))["pmc"]["area"] == "R"
            await ws.send_str(message)
            assert (await receive(ws, "error"))["error"] == reason
            frame = await receive(ws, "machine")  # the page's view goes on
            assert frame["pmc"]["area"] == "R" and "error" not in frame["pmc"]
        await wait_until(lambda: not web.broadcaster.subscriptions)


async def test_a_long_alarm_message_is_kept_as_the_machine_keeps_it() -> None:
    """One rule, the machine's (and the CLI's, the clients'): a CNC keeps 32 characters of a
    message; the answer says what it kept."""
    typed = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789XYZ"
    async with dashboard() as (server, web), aiohttp.ClientSession() as session:
        args = {"alm_type": 15, "alm_no": 1001, "msg": typed}
        status, body = await post(session, web, "raise_alarm", args)
        assert status == 200 and body["raised"] is True, body
        (alarm,) = server.machines[0].active_alarms()
        assert alarm.msg == typed[:32] == body["msg"]
        assert body["note"] == f"the CNC keeps 32 characters of a message: {typed[:32]!r}"
        status, body = await post(
            session, web, "raise_alarm", {**args, "alm_no": 1002, "msg": "OK"}
        )
        assert status == 200 and body["msg"] == "OK" and "note" not in body


async def test_an_action_answers_once_its_change_is_kept(tmp_path: Any) -> None:
    """``serve --state``: a page's write is in the state file before its answer; 503 when it
    cannot be kept."""
    from focas_net.sim.statefile import StateFile, decode_state, save_all

    state = StateFile(tmp_path / "m.state")
    m = state.load(default_machine)

    def keep() -> bool:
        try:
            save_all([(state, m)])
        except OSError:
            return False
        return True

    async with FocasServer(m, host="127.0.0.1", port=0) as server:
        async with Dashboard(stations_of(server), port=0, keep=keep) as web:
            async with aiohttp.ClientSession() as session:
                status, _ = await post(session, web, "write_macro", {"number": 520, "value": "7"})
                kept = decode_state(state.path.read_bytes())["kept"]["macros"]
                assert (status, kept.get("520")) == (200, "7")
                web.keep = lambda: False
                status, body = await post(
                    session, web, "write_macro", {"number": 521, "value": "1"}
                )
                assert (status, body["ok"]) == (503, False)
