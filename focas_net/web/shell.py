"""The dashboard's thin aiohttp shell: routes, the WebSocket, start and stop.

aiohttp is imported when the dashboard starts (``pip install 'focas-net[web]'``), so the rest
of focas_net needs only anyio. It runs in the caller's event loop, beside the
:class:`~focas_net.server.FocasServer` whose machines it shows.

Routes::

    GET  /                                   the page (static/index.html)
    GET  /static/<file>                      its script, style sheet and icon
    GET  /favicon.ico                        the icon (static/favicon.svg)
    GET  /api/info                           {"read_only", "machines"}
    GET  /api/fleet                          the fleet view
    GET  /api/machines/<i>?path=P            machine i's view of path P (1 when not given)
    GET  /api/machines/<i>/params?q=TEXT&path=P  parameters (number prefix or name)
    GET  /api/machines/<i>/macros?q=N[-M]&path=P macro variables and a note of any left out
    GET  /api/machines/<i>/pmc?area=X&start=0  16 bytes of a PMC area (start 100 or R100)
    POST /api/machines/<i>/actions/<action>  a page action (JSON object of arguments)
    GET  /ws                                 live frames; send {"subscribe": "fleet"} or
                                             {"subscribe": "machine", "index": i,
                                              "pmc_area": "X", "pmc_start": 0, "path": 1}

An action takes ``"path"`` (1 when not given) for what a path has: the cycle, the panel,
overrides, alarms, parameters and macro variables of a path, program selection.

A read takes the query keys shown, each once (another, or one twice, is 400); an action
takes none (its arguments are its body's keys: a query key is 400).
An action answers 200 ``{"ok": true, ...}``; a refusal 409 (403 on a read-only dashboard)
``{"ok": false, "ew": 5, "ew_name": "EW_PASSWD", "error": ...}``; a bad argument 400
``{"ok": false, "error": ...}``; an unknown machine 404. A URL under ``/api/`` the dashboard
has not is 404, a method the URL does not take 405, both in JSON too.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

from focas_net.errors import EW
from focas_net.sim import MachineError

from .address import DEFAULT_WEB_HOST
from .broadcast import DEFAULT_INTERVAL, FLEET, Broadcaster, Topic, machine_topic
from .operations import (
    ActionError,
    Station,
    action_args,
    json_int,
    no_twice,
    path_unfit,
    perform,
    refusal,
    shown,
    whole_number,
)
from .view import (
    JsonDict,
    fleet_view,
    machine_view,
    macro_note,
    macro_rows,
    no_machine,
    param_rows,
    pmc_address,
    pmc_window,
)

if TYPE_CHECKING:
    from aiohttp import web

    from focas_net.server import FocasServer

__all__ = ["STATIC_DIR", "Dashboard", "WebUnavailableError", "stations_of"]

_log = logging.getLogger(__name__)

#: The page's files, shipped in the package.
STATIC_DIR: Final = Path(__file__).resolve().parent / "static"
#: The most bytes of an action's body read (more is answered 413, in JSON like any refusal).
_MAX_BODY: Final = 1024 * 1024
#: The keys of a subscription of each kind.
_SUBSCRIPTION_KEYS: Final[dict[str, frozenset[str]]] = {
    "fleet": frozenset({"subscribe"}),
    "machine": frozenset({"subscribe", "index", "path", "pmc_area", "pmc_start"}),
}
#: How long the stop waits for requests in flight.
_SHUTDOWN_TIMEOUT: Final = 2.0


class WebUnavailableError(ImportError):
    """aiohttp is not installed: the dashboard needs ``pip install 'focas-net[web]'``."""


def _aiohttp() -> Any:
    try:
        from aiohttp import web
    except ImportError:
        raise WebUnavailableError(
            "the web dashboard needs aiohttp: pip install 'focas-net[web]'"
        ) from None
    return web


def stations_of(server: FocasServer) -> list[Station]:
    """A station per machine of ``server`` (its port once bound, its machine-wide faults)."""
    return [
        Station(i, listener.machine, listener.faults, listener.port)
        for i, listener in enumerate(server.listeners)
    ]


def _whole(value: object) -> bool:
    """Whether ``value`` (from JSON) is a whole number (``true`` is not)."""
    return isinstance(value, int) and not isinstance(value, bool)


async def _api_errors(request: web.Request, handler: Any) -> web.StreamResponse:
    """The dashboard's middleware: a request of ``/api/`` for a URL it has not (404) or a
    method the URL does not take (405) is answered in JSON as its other refusals are,
    ``{"ok": false, "error": "GET /api/machines/0/actions/cycle: this URL takes POST"}``,
    not in aiohttp's plain text."""
    aw = _aiohttp()
    try:
        response: web.StreamResponse = await handler(request)
    except aw.HTTPException as exc:
        if not request.path.startswith("/api/") or exc.content_type == "application/json":
            raise
        if isinstance(exc, aw.HTTPMethodNotAllowed):
            takes = ", ".join(sorted(m for m in exc.allowed_methods if m != "HEAD"))
            why = f"{request.method} {request.path}: this URL takes {takes}"
        elif isinstance(exc, aw.HTTPNotFound):
            why = f"{request.path}: the dashboard has no such URL"
        else:
            raise
        answer: web.Response = aw.json_response({"ok": False, "error": why}, status=exc.status)
        if "Allow" in exc.headers:
            answer.headers["Allow"] = exc.headers["Allow"]
        return answer
    return response


class Dashboard:
    """The web dashboard of ``stations`` (see :func:`stations_of`) on ``host:port``.

    ``async with Dashboard(...) as d:`` starts it (:attr:`url` is then its address) and
    stops it: the broadcaster ends, open WebSockets are closed, the port is released.
    ``read_only`` disables the page's controls and refuses every action with ``EW_PROT``.
    ``keep`` (``serve --state``: the server's keeper's ``flush``) makes an action's change
    durable before its answer; when it returns False the action answers 503.
    Raises :class:`WebUnavailableError` on start when aiohttp is missing, OSError when the
    port cannot be bound."""

    def __init__(
        self,
        stations: Sequence[Station],
        *,
        host: str = DEFAULT_WEB_HOST,
        port: int = 0,
        read_only: bool = False,
        interval: float = DEFAULT_INTERVAL,
        keep: Callable[[], bool] | None = None,
    ) -> None:
        self.stations = list(stations)
        self.keep = keep
        self.host = host
        self.port = port
        self.read_only = read_only
        self.broadcaster = Broadcaster(self.stations, interval=interval)
        self.address: tuple[str, int] = (host, port)
        self._runner: web.AppRunner | None = None
        self._task: asyncio.Task[None] | None = None
        self._sockets: set[web.WebSocketResponse] = set()

    def __repr__(self) -> str:
        """``<Dashboard http://127.0.0.1:8080/ 20 machines>`` (port 0 until it listens on
        the port it picked)."""
        count = len(self.stations)
        return f"<Dashboard {self.url} {count} machine{'' if count == 1 else 's'}>"

    @property
    def url(self) -> str:
        host, port = self.address
        shown = f"[{host}]" if ":" in host else host
        return f"http://{shown}:{port}/"

    async def __aenter__(self) -> Dashboard:
        await self.start()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.stop()

    # -- lifecycle ------------------------------------------------------------------------
    async def start(self) -> None:
        aw = _aiohttp()
        app = aw.Application(client_max_size=_MAX_BODY, middlewares=[aw.middleware(_api_errors)])
        app.router.add_get("/", self._index)
        app.router.add_static("/static/", STATIC_DIR, show_index=False)
        app.router.add_get("/favicon.ico", self._icon)
        app.router.add_get("/api/info", self._info)
        app.router.add_get("/api/fleet", self._fleet)
        app.router.add_get("/api/machines/{index}", self._machine)
        app.router.add_get("/api/machines/{index}/params", self._params)
        app.router.add_get("/api/machines/{index}/macros", self._macros)
        app.router.add_get("/api/machines/{index}/pmc", self._pmc)
        app.router.add_post("/api/machines/{index}/actions/{action}", self._action)
        app.router.add_get("/ws", self._ws)
        app.on_shutdown.append(self._close_sockets)
        runner = aw.AppRunner(app, shutdown_timeout=_SHUTDOWN_TIMEOUT, access_log=None)
        await runner.setup()
        try:
            site = aw.TCPSite(runner, self.host, self.port)
            await site.start()
        except BaseException:
            await runner.cleanup()
            raise
        self._runner = runner
        addresses = runner.addresses  # the port actually bound (port 0: an ephemeral one)
        if addresses:
            self.address = (str(addresses[0][0]), int(addresses[0][1]))
        self._task = asyncio.get_running_loop().create_task(self.broadcaster.run())

    async def stop(self) -> None:
        """Stop the live updates, close the pages' sockets and the listener (idempotent)."""
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
        self.broadcaster.close()
        runner, self._runner = self._runner, None
        if runner is not None:
            await runner.cleanup()

    async def _close_sockets(self, _app: Any) -> None:
        from aiohttp import WSCloseCode

        for ws in list(self._sockets):
            await ws.close(code=WSCloseCode.GOING_AWAY, message=b"server shutdown")

    # -- helpers --------------------------------------------------------------------------
    @staticmethod
    def _json(data: JsonDict, status: int = 200) -> web.Response:
        aw = _aiohttp()
        response: web.Response = aw.json_response(data, status=status)
        return response

    def _station(self, request: web.Request) -> Station:
        text = request.match_info["index"]
        if not (text.isascii() and text.isdigit()) or not int(text) < len(self.stations):
            aw = _aiohttp()
            raise aw.HTTPNotFound(
                text=json.dumps({"ok": False, "error": no_machine(repr(text), len(self.stations))}),
                content_type="application/json",
            )
        return self.stations[int(text)]

    # -- handlers -------------------------------------------------------------------------
    @staticmethod
    def _file(name: str) -> web.StreamResponse:
        aw = _aiohttp()
        response: web.FileResponse = aw.FileResponse(STATIC_DIR / name)
        return response

    async def _index(self, _request: web.Request) -> web.StreamResponse:
        return self._file("index.html")

    async def _icon(self, _request: web.Request) -> web.StreamResponse:
        return self._file("favicon.svg")

    def _query(self, request: web.Request, *keys: str) -> web.Response | None:
        """The 400 answer to a query holding a key the endpoint does not take or a key given
        twice (as an action's body is refused: ``?pth=2`` would show path 1), else None."""
        given = list(request.query.keys())
        unknown = sorted({k for k in given if k not in keys})
        if unknown:
            takes = ", ".join(keys) if keys else "none"
            named = ", ".join(map(repr, unknown))
            why = f"{request.path} takes no query key {named} (it takes {takes})"
            return self._json({"ok": False, "error": why}, 400)
        twice = next((k for k in keys if len(request.query.getall(k, ())) > 1), None)
        if twice is not None:
            return self._json(
                {"ok": False, "error": f"the query key {twice!r} is given twice"}, 400
            )
        return None

    async def _info(self, request: web.Request) -> web.Response:
        refused = self._query(request)
        if refused is not None:
            return refused
        return self._json({"read_only": self.read_only, "machines": len(self.stations)})

    async def _fleet(self, request: web.Request) -> web.Response:
        refused = self._query(request)
        if refused is not None:
            return refused
        entries = ((s.index, s.machine, s.port) for s in self.stations)
        return self._json(fleet_view(entries))

    def _path(self, request: web.Request, s: Station, *also: str) -> int | web.Response:
        """``?path=N`` (1 when not given), or the answer refusing it: 400 for text that is no
        number or a query key the endpoint does not take (``also``: the others it takes), 409
        EW_PATH for a path the machine has not."""
        refused = self._query(request, "path", *also)
        if refused is not None:
            return refused
        try:
            path = whole_number(request.query.get("path", "1"))
            why = path_unfit(path)
            if why is not None:
                raise ValueError(why)
            s.machine.path_info(path)
        except ValueError as exc:
            return self._json({"ok": False, "error": f"path: {exc}"}, 400)
        except MachineError as exc:
            return self._json(refusal(exc), 409)
        return path

    async def _machine(self, request: web.Request) -> web.Response:
        s = self._station(request)
        path = self._path(request, s)
        if not isinstance(path, int):
            return path
        trail = s.trail_of(path)
        view = machine_view(
            s.index, s.machine, s.port, trail=trail, faults=s.fault_listing(), path=path
        )
        return self._json(view)

    async def _params(self, request: web.Request) -> web.Response:
        s = self._station(request)
        path = self._path(request, s, "q")
        if not isinstance(path, int):
            return path
        try:
            rows = param_rows(s.machine, request.query.get("q", ""), path=path)
        except ValueError as exc:
            return self._json({"ok": False, "error": str(exc)}, 400)
        return self._json({"params": rows})

    async def _macros(self, request: web.Request) -> web.Response:
        s = self._station(request)
        path = self._path(request, s, "q")
        if not isinstance(path, int):
            return path
        query = request.query.get("q", "")
        try:
            rows = macro_rows(s.machine, s.macro_numbers(), query, path=path)
        except ValueError as exc:
            return self._json({"ok": False, "error": str(exc)}, 400)
        return self._json({"macros": rows, "note": macro_note(s.macro_numbers(), query, len(rows))})

    async def _pmc(self, request: web.Request) -> web.Response:
        s = self._station(request)
        refused = self._query(request, "area", "start")
        if refused is not None:
            return refused
        area = request.query.get("area", "X")
        try:
            letter, start = pmc_address(request.query.get("start", "0"), area)
        except ValueError as exc:
            return self._json({"ok": False, "error": str(exc)}, 400)
        try:
            return self._json(pmc_window(s.machine, letter, start))
        except MachineError as exc:
            return self._json(refusal(exc), 409)

    async def _action(self, request: web.Request) -> web.Response:
        s = self._station(request)
        action = request.match_info["action"]
        if request.query:  # never read: a query's alm_type would leave every alarm cleared
            named = ", ".join(map(repr, sorted(set(request.query.keys()))))
            why = (
                f"{request.path} takes no query key {named} "
                "(an action's arguments are the keys of its JSON body)"
            )
            return self._json({"ok": False, "error": why}, 400)
        try:
            body = await request.read() if request.can_read_body else b""
        except _aiohttp().HTTPRequestEntityTooLarge:
            why = f"the body is more than {_MAX_BODY} bytes: an action takes a small JSON object"
            return self._json({"ok": False, "error": why}, 413)
        try:
            args = action_args(body)
            result = perform(s, action, args, read_only=self.read_only)
        except ActionError as exc:
            return self._json({"ok": False, "error": str(exc)}, 400)
        except MachineError as exc:
            status = 403 if exc.ew == EW.PROT and (self.read_only or s.machine.read_only) else 409
            return self._json(refusal(exc), status)
        _log.info("%s: page action %s %s", s.machine.name, action, args)
        if self.keep is not None and not self.keep():
            return self._json({"ok": False, "error": "the change could not be kept"}, 503)
        return self._json(result)

    def _topic(self, message: str) -> Topic | str:
        """The topic a page's ``message`` subscribes to, or why it names none: each field of
        a machine's topic checked (its number, path, PMC window) and named when wrong."""
        try:
            wanted = json.loads(message, object_pairs_hook=no_twice, parse_int=json_int)
        except ActionError as exc:
            return f"bad subscription: {exc}"
        except (ValueError, RecursionError):
            return f"bad subscription: not JSON: {message[:40]!r}"
        if not isinstance(wanted, dict):
            return f"bad subscription: a JSON object is expected, got {message[:40]}"
        kind = wanted.get("subscribe")
        if not isinstance(kind, str) or kind not in _SUBSCRIPTION_KEYS:
            return f'bad subscription: "subscribe" is "fleet" or "machine", got {shown(kind)}'
        unknown = sorted(set(wanted) - _SUBSCRIPTION_KEYS[kind])
        if unknown:  # a misspelt "pmc_strat" would show X0 unsaid
            takes = ", ".join(sorted(_SUBSCRIPTION_KEYS[kind]))
            named = ", ".join(map(repr, unknown))
            return f"bad subscription: a {kind} subscription takes no {named} (it takes {takes})"
        if kind == "fleet":
            return FLEET
        index, area = wanted.get("index"), wanted.get("pmc_area")
        start, path = wanted.get("pmc_start", 0), wanted.get("path", 1)
        if "index" not in wanted:
            return 'bad subscription: "index" is missing (a machine\'s number)'
        if not _whole(index):
            return f'bad subscription: "index" is a machine\'s number, got {shown(index)}'
        for key, value in (("path", path), ("pmc_start", start)):
            if not _whole(value):
                return f'bad subscription: "{key}" is a whole number, got {shown(value)}'
        if area is not None and not isinstance(area, str):
            return f'bad subscription: "pmc_area" is a PMC area\'s letter, got {shown(area)}'
        assert isinstance(index, int) and isinstance(start, int) and isinstance(path, int)
        # no area named: the machine's first (a machine with none shows that in its frames)
        letter = self.broadcaster.first_pmc_area(index) if area is None else area
        topic = machine_topic(index, letter, start, path)
        window = "pmc_area" in wanted or "pmc_start" in wanted
        refused = self.broadcaster.refusal(topic, window=window)
        return topic if refused is None else refused

    async def _ws(self, request: web.Request) -> web.StreamResponse:
        aw = _aiohttp()
        from aiohttp import WSMsgType

        ws: web.WebSocketResponse = aw.WebSocketResponse(heartbeat=30.0)
        await ws.prepare(request)
        self._sockets.add(ws)
        sub = self.broadcaster.subscribe(FLEET)
        sender = asyncio.get_running_loop().create_task(self._send(ws, sub))
        try:
            async for msg in ws:
                if msg.type == WSMsgType.BINARY:  # said, not left unanswered
                    topic: Topic | str = (
                        "bad subscription: a text frame of JSON is expected, got a binary frame"
                    )
                elif msg.type != WSMsgType.TEXT:
                    continue
                else:
                    topic = self._topic(msg.data)
                if isinstance(topic, str):  # refused: the page keeps what it had
                    await ws.send_str(json.dumps({"type": "error", "error": topic}))
                    continue
                sub.topic = topic
                sub.offer(self.broadcaster.frame(topic))  # at once, not at the next tick
        finally:
            self.broadcaster.unsubscribe(sub)
            self._sockets.discard(ws)
            sender.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await sender
        return ws

    @staticmethod
    async def _send(ws: web.WebSocketResponse, sub: Any) -> None:
        with contextlib.suppress(ConnectionError):
            while (frame := await sub.next()) is not None:
                if ws.closed:
                    return
                await ws.send_str(frame)
