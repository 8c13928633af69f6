"""``focas-net serve``: run simulated CNCs until SIGINT or SIGTERM.

Each machine's port answers both the packed protocol (``docs/protocol.md``) and FANUC's native
FOCAS/2 Ethernet protocol (``docs/native-protocol.md``), as a real CNC's port 8193 does. When
every listener is bound it prints, flushed, one line per machine::

    focas-net: <machine name> listening on HOST:PORT

(``<machine name> (TLS, read-only) listening on`` when those apply; then, with
``--native-port``, one ``focas-net: <machine name> (native FOCAS/2) listening on HOST:PORT``
line per machine for the ports serving the native protocol only) so scripts and tests can wait
for it; the address is always the line's last word. A bad machine file, TLS file or option
ends with a one-line error and exit code 2 (options are all checked before anything is
allocated); a port that cannot be bound with exit code 1. SIGINT and SIGTERM shut down
gracefully (stop accepting, answer what is in flight, close) and exit 0.

With ``--web`` one more line follows the machines', ``focas-net: web dashboard on
http://HOST:PORT/`` (``docs/web.md``).
"""

from __future__ import annotations

import argparse
import gc
import importlib.util
import logging
import ssl
import sys
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import anyio

from focas_net._typed import os_reason, typed_number
from focas_net.server import (
    DEFAULT_GRACE_PERIOD,
    DEFAULT_HOST,
    DEFAULT_IDLE_TIMEOUT,
    DEFAULT_MAX_CONNECTIONS,
    DEFAULT_PORT,
    NATIVE_MAGIC_LENGTH,
    FocasServer,
    ListenError,
)

from ._args import (
    EXIT_CNC,
    EXIT_USAGE,
    FILE_NAME,
    LISTEN_HOST,
    LISTEN_PORT,
    LOG_LEVEL,
    NON_NEGATIVE,
    PASSWORD,
    POSITIVE,
    PROG,
    argument_type,
    command_parser,
    parse_at_least,
    parse_bounded,
    pem_holds,
    print_error,
    print_usage_error,
    ssl_error_text,
    typed_lead,
)
from ._fleet import (
    ConfigError,
    OptionRefused,
    build_machines,
    fleet_indices,
    machines_per_process,
)
from ._format import address_text
from ._run import stopping_on_signals
from ._state import Kept, keep_running, saver
from ._workers import MAX_WORKERS, run_workers

if TYPE_CHECKING:
    from focas_net.web import Dashboard

__all__ = ["DEFAULT_SEED", "MAX_FLEET", "check_options", "register", "run"]

_log = logging.getLogger("focas_net.cli.serve")

_SERVE: Final = f"{PROG} serve"
_ERROR_PREFIX = f"{_SERVE}: error"  # as argparse words its usage errors


#: Fastest ``serve --speed``.
MAX_SPEED: Final = 10_000.0
#: Most machines one ``serve --fleet`` runs.
MAX_FLEET: Final = 10_000
#: Largest ``serve --downtime`` factor.
MAX_DOWNTIME: Final = 100.0
#: The fleet seed of ``serve --run`` when ``--seed`` is not given (and the machine file's
#: ``[run]`` gives none): the same fleet on every run.
DEFAULT_SEED: Final = 0
#: Files a server keeps for itself besides its listening sockets (standard streams, the event
#: loop, a few connections).
_RESERVED_FILES: Final = 32


def _typed(text: str) -> float:
    """A number as every front end reads number text (no exponent, no NaN or infinity; a
    whole number in ``0x``/``0b``/``0o`` too: :func:`focas_net._typed.typed_number`), its
    refusal argparse's one line."""
    try:
        value = float(typed_number(text))
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if value in (float("inf"), float("-inf")):
        raise argparse.ArgumentTypeError(f"must be finite, got {text.strip()}")
    return value


def _seconds(text: str) -> float:
    value = _typed(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"must be a number >= 0, got {text}")
    return value


def _speed(text: str) -> float:
    value = _typed(text)
    if not 0 < value <= MAX_SPEED:
        raise argparse.ArgumentTypeError(f"must be above 0 and at most {MAX_SPEED:g}, got {text}")
    return value


def _downtime(text: str) -> float:
    value = _typed(text)
    if not 0 <= value <= MAX_DOWNTIME:
        raise argparse.ArgumentTypeError(f"must be 0..{MAX_DOWNTIME:g}, got {text}")
    return value


#: ``--fleet N``: 1..:data:`MAX_FLEET` machines, both ends refused by the parser alike.
_FLEET: Final = argument_type(partial(parse_bounded, low=1, high=MAX_FLEET), "count")
#: ``--workers N``: 1..:data:`MAX_WORKERS` processes, both ends refused by the parser alike
#: (no more than the machines of ``--fleet``: :func:`check_options`).
_WORKERS: Final = argument_type(partial(parse_bounded, low=1, high=MAX_WORKERS), "count")


#: ``--max-frame`` at its shortest, 4 bytes: a frame's length field alone.
_FRAME_BYTES: Final = argument_type(partial(parse_at_least, low=4), "count")


def _max_frame(text: str) -> int:
    value = _FRAME_BYTES(text)
    if value >= NATIVE_MAGIC_LENGTH:
        # A native FOCAS/2 frame opens with A0 A0 A0 A0: as a packed length that is 0xA0A0A0A0,
        # which must stay a violation for both protocols to share a port.
        raise argparse.ArgumentTypeError(
            f"must be below 0xA0A0A0A0 ({NATIVE_MAGIC_LENGTH}, how the first four bytes of a "
            f"native FOCAS/2 frame read as a length), got {text}"
        )
    return value


def _web_address(text: str) -> tuple[str, int]:
    """``--web [HOST:]PORT``: checked here, aiohttp's presence too."""
    from focas_net.web import parse_web_address

    try:
        address = parse_web_address(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if importlib.util.find_spec("aiohttp") is None:
        raise argparse.ArgumentTypeError(
            f"{text}: the web dashboard needs aiohttp: pip install 'focas-net[web]'"
        )
    return address


def register(subparsers: Any) -> None:
    """Add the ``serve`` subcommand."""
    p = command_parser(
        subparsers,
        "serve",
        help="run a simulated CNC (or a fleet of them)",
        description="Run simulated FANUC CNCs speaking the focas_net packed protocol and "
        "FANUC's native FOCAS/2 Ethernet protocol, both on each machine's port.",
    )
    p.add_argument(
        "--host",
        type=LISTEN_HOST,
        default=DEFAULT_HOST,
        help="address to bind (default %(default)s)",
    )
    p.add_argument(
        "--port",
        type=LISTEN_PORT,
        default=DEFAULT_PORT,
        help="port of the first machine; 0 = ephemeral ports (default %(default)s)",
    )
    p.add_argument(
        "--machine",
        type=FILE_NAME,
        metavar="FILE",
        help="machine file (TOML, see docs/machine-file.md); default: the built-in machine",
    )
    p.add_argument(
        "--fleet",
        type=_FLEET,
        default=1,
        metavar="N",
        help=f"serve N independent machines (1..{MAX_FLEET}) on ports PORT..PORT+N-1 (or N "
        "ephemeral ports)",
    )
    p.add_argument(
        "--workers",
        type=_WORKERS,
        default=1,
        metavar="N",
        help=f"serve the fleet from N processes (1..{MAX_WORKERS}), each the machines of a "
        "contiguous slice of its ports (default %(default)s: this process)",
    )
    p.add_argument(
        "--param-password",
        type=PASSWORD,
        metavar="TEXT",
        help="parameter-write password (cnc_wrunlockparam), 1..4 ASCII characters",
    )
    p.add_argument(
        "--no-control",
        action="store_true",
        help="answer the simulator control commands (sim_set_panel ... sim_set_overrides, "
        "0x0E01..0x0E21) with EW_FUNC, like a real CNC",
    )
    p.add_argument(
        "--read-only",
        action="store_true",
        help="answer every write (parameter, macro, PMC, control) with EW_PROT",
    )
    p.add_argument(
        "--state",
        type=FILE_NAME,
        metavar="DIR",
        help="keep each machine's nonvolatile memory (parameters, offsets, #500-#999, "
        "programs, alarm history, parts and timers, PMC K/D/C/T) in DIR across restarts (the "
        "machine file's [machine] state names one too); an "
        "answer leaves once its write is on the disk (docs/machine-file.md, State files)",
    )
    p.add_argument(
        "--max-connections",
        type=POSITIVE,
        default=DEFAULT_MAX_CONNECTIONS,
        metavar="N",
        help="connections per machine; extra ones are closed at once (default %(default)s)",
    )
    p.add_argument(
        "--idle-timeout",
        type=_seconds,
        default=DEFAULT_IDLE_TIMEOUT,
        metavar="SECONDS",
        help="close a connection without a request for this long; 0 = never (default %(default)s)",
    )
    p.add_argument(
        "--max-frame",
        type=_max_frame,
        default=65_536,
        metavar="BYTES",
        help="largest packed frame length accepted, below 0xA0A0A0A0; a longer one closes the "
        "connection (default %(default)s)",
    )
    p.add_argument(
        "--grace-period",
        type=_seconds,
        default=DEFAULT_GRACE_PERIOD,
        metavar="SECONDS",
        help="how long shutdown waits for answers in flight (default %(default)s)",
    )
    p.add_argument(
        "--native-port",
        type=LISTEN_PORT,
        default=None,
        metavar="PORT",
        help="also serve FANUC's native FOCAS/2 Ethernet protocol alone on PORT (PORT+i for "
        "machine i of a fleet; 0 = ephemeral); off by default (the main port speaks it too, "
        "unless --tls-cert makes it TLS, which FOCAS/2 clients do not speak)",
    )
    p.add_argument(
        "--uvloop",
        action="store_true",
        help="run on uvloop (pip install 'focas-net[uvloop]')",
    )
    p.add_argument(
        "--tls-cert",
        type=FILE_NAME,
        metavar="FILE",
        help="serve TLS with this certificate (PEM)",
    )
    p.add_argument(
        "--tls-key", type=FILE_NAME, metavar="FILE", help="private key of --tls-cert (PEM)"
    )
    p.add_argument(
        "--speed",
        type=_speed,
        default=1.0,
        metavar="FACTOR",
        help="machine time runs FACTOR times as fast as the wall clock (default %(default)s)",
    )
    p.add_argument(
        "--run",
        action="store_true",
        help="every machine starts its main program at once and repeats it forever, a part "
        "counted each time, with the seeded operator pauses, tool-change waits and alarms of "
        "its machine file's [run] section or of the default scenario (production; a machine "
        "file with [run] runs without --run too)",
    )
    p.add_argument(
        "--seed",
        type=NON_NEGATIVE,
        default=None,
        metavar="N",
        help="fleet seed of the running machines' events and loads; machine i gets a seed of "
        f"its own derived from N and i (default: the [run] seed, else {DEFAULT_SEED})",
    )
    p.add_argument(
        "--run-parts",
        type=NON_NEGATIVE,
        default=None,
        metavar="N",
        help="each running machine makes N parts, then stops in reset; 0 = forever (default: "
        "the [run] parts, else forever)",
    )
    p.add_argument(
        "--downtime",
        type=_downtime,
        default=1.0,
        metavar="FACTOR",
        help="multiply the rates of pauses, tool-change waits and alarms of the running "
        "machines by FACTOR (0..100); 0 = production without interruptions (default "
        "%(default)s)",
    )
    p.add_argument(
        "--web",
        type=_web_address,
        metavar="[HOST:]PORT",
        help="also serve the web dashboard on HOST:PORT (HOST 127.0.0.1 unless given; 0 = "
        "ephemeral port; pip install 'focas-net[web]'); --read-only makes it read-only",
    )
    p.add_argument(
        "--log-level",
        default="WARNING",
        type=LOG_LEVEL,
        metavar="LEVEL",
        help="logging threshold on stderr: DEBUG, INFO, WARNING, ERROR or CRITICAL, in any case "
        "(default %(default)s)",
    )
    p.set_defaults(func=run)


def check_options(args: argparse.Namespace) -> None:
    """Check the options that bound what ``serve`` allocates, before it allocates anything:
    the fleet's size and port ranges, the files a fleet needs, ``--uvloop``. Raises
    :class:`ConfigError`."""
    fleet = args.fleet  # (1..MAX_FLEET: its parser's check)
    workers = getattr(args, "workers", 1)
    if fleet == 1 and 1 < workers <= MAX_WORKERS:
        raise OptionRefused(
            "--workers",
            f"{workers} workers spread a fleet over processes, and the fleet is 1 machine "
            f"(without --fleet): give --fleet N (at least {workers} machines)",
        )
    if workers > fleet:  # (1..MAX_WORKERS: its parser's check)
        raise OptionRefused(
            "--workers",
            f"at most {MAX_WORKERS}, and no more than the {fleet} "
            f"machine{'s' if fleet > 1 else ''} of --fleet, got {workers}",
        )
    if workers > 1 and getattr(args, "web", None) is not None:
        raise OptionRefused(
            "--web",
            f"the dashboard shows the machines of one process, not of --workers {workers}: "
            "serve it from a fleet without --workers",
        )
    ranges = [("--port", args.port)]
    if args.native_port is not None:
        ranges.append(("--native-port", args.native_port))
    served = len(fleet_indices(args))  # a worker checks the ports of its own slice
    for option, first in ranges:
        if first and first + served - 1 > 65_535:
            raise OptionRefused(
                "--fleet",
                f"{fleet} machine{'s' if fleet > 1 else ''} from {option} {first} run past "
                f"65535 (the last machine would get port {first + served - 1})",
            )
    if args.native_port is not None and getattr(args, "max_connections", 2) < 2:
        raise OptionRefused(
            "--max-connections",
            f"{args.max_connections} leaves --native-port unusable: it speaks FOCAS/2 alone, "
            "whose open takes two connections (give 2 or more)",
        )
    if args.port and args.native_port == args.port and fleet == 1:
        raise OptionRefused(
            "--native-port",
            f"{args.native_port} is the port of --port {args.port}, which speaks FOCAS/2 too: "
            "leave --native-port out, or give it another port",
        )
    if args.port and args.native_port and abs(args.port - args.native_port) < fleet:
        raise OptionRefused(
            "--native-port",
            f"{args.native_port} overlaps the ports {args.port}..{args.port + fleet - 1} of "
            f"--fleet {fleet}",
        )
    sockets = machines_per_process(args) * (2 if args.native_port is not None else 1)
    limit = _open_files_limit()
    if limit is not None and sockets + _RESERVED_FILES > limit:
        raise ConfigError(
            f"--fleet {fleet} needs {sockets} listening sockets, but this process may open "
            f"{limit} files (ulimit -n)"
        )
    if args.uvloop and importlib.util.find_spec("uvloop") is None:
        raise ConfigError("--uvloop: uvloop is not installed")


def _open_files_limit() -> int | None:
    try:
        import resource
    except ImportError:  # pragma: no cover - not on POSIX
        return None
    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    return None if soft == resource.RLIM_INFINITY else int(soft)


def _ssl_context(args: argparse.Namespace) -> ssl.SSLContext | None:
    if args.tls_cert is None and args.tls_key is None:
        return None
    if args.tls_cert is None:
        raise OptionRefused("--tls-key", "needs --tls-cert")
    ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    try:
        # (asked only for a key under a pass phrase, which OpenSSL would ask on the terminal)
        ctx.load_cert_chain(args.tls_cert, args.tls_key, password=_no_pass_phrase)
    except _PassPhrase:
        flag, path = (
            ("--tls-cert", args.tls_cert) if args.tls_key is None else ("--tls-key", args.tls_key)
        )
        raise ConfigError(
            f"{flag} {path}: its private key is encrypted (under a pass phrase), which serve "
            f"cannot ask for: give it unencrypted (openssl pkey -in {path} -out KEY.pem)"
        ) from None
    except (OSError, ssl.SSLError) as exc:
        raise ConfigError(_tls_files_error(args.tls_cert, args.tls_key, exc)) from None
    return ctx


class _PassPhrase(Exception):
    """The private key of ``--tls-key`` (or ``--tls-cert``) is encrypted."""


def _no_pass_phrase() -> bytes:
    raise _PassPhrase


def _tls_files_error(cert: str, key: str | None, exc: OSError) -> str:
    """Why ``--tls-cert cert`` (with ``--tls-key key``) cannot serve TLS, naming the file."""
    for flag, path in (("--tls-cert", cert), ("--tls-key", key)):
        try:
            if path is not None:
                Path(path).read_bytes()
        except OSError as unreadable:
            return f"{flag} {path}: {os_reason(unreadable)}"
    if not pem_holds(cert, "CERTIFICATE"):
        return f"--tls-cert {cert}: no PEM certificate in it"
    if key is None and not pem_holds(cert, "PRIVATE KEY"):
        return f"--tls-cert {cert} holds no private key: give --tls-key FILE"
    if key is not None and not pem_holds(key, "PRIVATE KEY"):
        return f"--tls-key {key}: no PEM private key in it"
    reason = getattr(exc, "reason", None)
    if reason == "KEY_VALUES_MISMATCH":
        return f"--tls-key {key or cert}: the private key does not belong to the certificate"
    files = cert if key is None else f"{cert}, {key}"
    return f"TLS certificate/key ({files}): {ssl_error_text(exc)}"


def run(args: argparse.Namespace) -> int:
    """Entry point of ``focas-net serve``; returns the exit code."""
    logging.basicConfig(
        level=getattr(logging, args.log_level),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )
    try:
        check_options(args)  # every option, before anything is allocated
        ssl_context = _ssl_context(args)
        if getattr(args, "workers", 1) > 1:
            return run_workers(args, run)
        states: list[Kept] = []
        machines = build_machines(args, states)
    except OptionRefused as exc:  # in the parser's words (a number named as typed: 0x3)
        print_usage_error(f"argument {exc.option}: {typed_lead(exc.why, args)}", _SERVE)
        return EXIT_USAGE
    except ConfigError as exc:  # (a number of an option named as typed: --fleet 0x3)
        print_error(typed_lead(str(exc), args), _ERROR_PREFIX)
        return EXIT_USAGE
    server = FocasServer(
        machines,
        host=args.host,
        port=args.port,
        ssl=ssl_context,
        max_frame=args.max_frame,
        max_connections=args.max_connections,
        idle_timeout=args.idle_timeout,
        grace_period=args.grace_period,
        native_port=args.native_port,
        durable=saver(states) if states and not args.read_only else None,
    )
    try:
        return anyio.run(
            _serve,
            server,
            ssl_context is not None,
            bool(args.read_only),
            getattr(args, "web", None),
            states,
            backend="asyncio",
            backend_options={"use_uvloop": args.uvloop},
        )
    except ListenError as exc:
        option = " (--native-port)" if exc.native_only else ""
        print_error(f"cannot listen on {exc.where}{option}: {os_reason(exc)}", _ERROR_PREFIX)
        return EXIT_CNC
    except OSError as exc:
        print_error(
            f"cannot listen on {address_text(args.host, args.port)}: {os_reason(exc)}",
            _ERROR_PREFIX,
        )
        return EXIT_CNC


def _modes(tls: bool, read_only: bool, *first: str) -> str:
    """`` (TLS, read-only)``: what the ready line says about a listener, or nothing."""
    modes = [*first, *(["TLS"] if tls else []), *(["read-only"] if read_only else [])]
    return f" ({', '.join(modes)})" if modes else ""


def _freeze_what_was_built() -> None:
    """Move what the process holds once it serves (the machines, their programs and tables,
    the listeners) out of the garbage collector's reach: it lives as long as the process, and
    a full collection would otherwise walk all of it while every request in flight waits
    (about 70 ms with 1,000 machines). Garbage made afterwards is collected as before."""
    gc.collect()
    gc.freeze()


async def _serve(
    server: FocasServer,
    tls: bool,
    read_only: bool,
    web: tuple[str, int] | None = None,
    states: list[Kept] | None = None,
) -> int:
    told = anyio.Event()
    with stopping_on_signals(told.set):
        async with (
            server,
            _dashboard(server, web, read_only) as dashboard,
            keep_running(server, states or [], read_only),
        ):
            if dashboard is None and web is not None:
                return EXIT_CNC
            _freeze_what_was_built()
            out = sys.stdout
            for listener in server.listeners:
                out.write(
                    f"focas-net: {listener.label}{_modes(tls, read_only)} listening on "
                    f"{listener.address_text}\n"
                )
            for listener in server.listeners:
                if listener.native is not None:
                    native_modes = _modes(False, read_only, "native FOCAS/2")
                    out.write(
                        f"focas-net: {listener.label}{native_modes} listening on "
                        f"{listener.native.address_text}\n"
                    )
            if dashboard is not None:
                out.write(
                    f"focas-net: web dashboard{_modes(False, read_only)} on {dashboard.url}\n"
                )
            out.flush()
            await told.wait()
            _log.info("told to stop (SIGINT or SIGTERM): shutting down")
    return 0


@asynccontextmanager
async def _dashboard(
    server: FocasServer, web: tuple[str, int] | None, read_only: bool
) -> AsyncIterator[Dashboard | None]:
    """The web dashboard of ``--web`` while the machines are served (None without it, or
    when it cannot listen: that is reported here)."""
    if web is None:
        yield None
        return
    from focas_net.web import Dashboard, is_loopback, stations_of

    host, port = web
    keep = None if server.keeper is None or read_only else server.keeper.flush
    dashboard = Dashboard(stations_of(server), host=host, port=port, read_only=read_only, keep=keep)
    try:
        await dashboard.start()
    except OSError as exc:
        where = address_text(host, port)
        try:
            taken = server.listener_for(port) if port else None
        except KeyError:
            taken = None
        hint = (
            f" (a CNC of this command listens on port {port}: give --web another)" if taken else ""
        )
        print_error(f"--web {where}: cannot listen: {os_reason(exc)}{hint}", _ERROR_PREFIX)
        yield None
        return
    if not is_loopback(host):  # (once it listens: a bind that failed warns of nothing)
        sys.stderr.write(
            f"{PROG} serve: warning: the web dashboard listens on {host}, beyond loopback, "
            "with no authentication\n"
        )
    try:
        yield dashboard
    finally:
        await dashboard.stop()
