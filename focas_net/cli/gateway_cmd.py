"""``focas-net gateway CONFIG.toml``: poll the machines of a configuration file and publish
them to the MQTT broker and the OPC UA server it names, until SIGINT or SIGTERM
(``docs/gateway.md``).

Once its outputs are up it prints, flushed, one line::

    focas-net: gateway polling 4 machines (shard 1/2); MQTT 127.0.0.1:1883; OPC UA opc.tcp://...

A bad ``--shard`` (checked before the file is read), a bad configuration, or an output whose
package is not installed, ends with one line and exit code 2, before anything connects; an
output that cannot start (a port in use) with exit code 1. SIGINT and SIGTERM end it cleanly:
the outputs stop, the clients close, exit 0. Machines that cannot be reached are not an error:
they are shown lost, and tried again.
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import sys
from contextlib import AsyncExitStack
from typing import Any
from urllib.parse import urlsplit

from focas_net._typed import os_reason, whole_number
from focas_net.gateway import (
    ConfigError,
    Gateway,
    GatewayConfig,
    Sink,
    load_config,
    outputs,
    shard,
)
from focas_net.gateway.config import shard_refusal, with_port

from ._args import (
    EXIT_CNC,
    EXIT_OK,
    EXIT_USAGE,
    FILE_NAME,
    LOG_LEVEL,
    PROG,
    argument_type,
    command_parser,
    print_error,
)
from ._run import stopping_on_signals

__all__: list[str] = []

_ERROR_PREFIX = f"{PROG} gateway: error"  # as serve and argparse word their errors
_log = logging.getLogger("focas_net.cli.gateway")


def parse_shard(text: str) -> tuple[int, int]:
    """``I/N`` as two integers, shard I of N (whether the file has a machine for it is
    checked with the file, by ``shard``)."""
    first, slash, second = text.strip().partition("/")
    try:  # (each number as every number option reads it: a sign is its range's to refuse)
        index, count = whole_number(first), whole_number(second)
    except ValueError:
        slash = ""
    if not slash:
        raise ValueError(f"give the shard as I/N (1/4: the first of four), got {text!r}")
    why = shard_refusal(index, count)
    if why is not None:
        raise ValueError(f"{why}, got {text!r}")
    return index, count


SHARD = argument_type(parse_shard, "shard")


def register(subparsers: Any) -> None:
    """Add the ``gateway`` subcommand."""
    p = command_parser(
        subparsers,
        "gateway",
        help="poll CNCs and publish them over MQTT and OPC UA",
        description="Poll the FANUC CNCs of a configuration file (TOML, docs/gateway.md) and "
        "publish their values, alarms and availability to an MQTT broker and an OPC UA server.",
    )
    p.add_argument(
        "config", type=FILE_NAME, metavar="CONFIG.toml", help="the gateway's configuration file"
    )
    p.add_argument(
        "--shard",
        type=SHARD,
        default=None,
        metavar="I/N",
        help="poll only shard I of N (machines I, I+N, I+2N, ... of the file), so that N "
        "gateway processes share a plant; shard I serves OPC UA on the endpoint's port + I-1 "
        "and connects to MQTT as CLIENT_ID-I, named GATEWAY-I in its topics",
    )
    p.add_argument(
        "--log-level",
        default="WARNING",
        type=LOG_LEVEL,
        metavar="LEVEL",
        help="logging threshold of focas-net's own messages on stderr: DEBUG, INFO, WARNING, "
        "ERROR or CRITICAL, in any case (default %(default)s; other libraries' from WARNING)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Entry point of ``focas-net gateway``; returns the exit code."""
    log_to_stderr(args.log_level)
    try:
        config = load_config(args.config)
        if args.shard is not None:
            index, count = args.shard
            config = shard(config, index, count, args.config)
    except ConfigError as exc:
        print_error(str(exc), _ERROR_PREFIX)
        return EXIT_USAGE
    return asyncio.run(_serve(config, args.shard, args.config))


def log_to_stderr(level: str) -> None:
    """Log records of ``level`` and above of focas_net's loggers on standard error; other
    libraries' (asyncua's, aiomqtt's) from WARNING, so that INFO tells the machines and the
    outputs, not every node the OPC UA server adds."""
    threshold = getattr(logging, level)
    logging.basicConfig(
        level=max(threshold, logging.WARNING),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
        stream=sys.stderr,
    )
    logging.getLogger("focas_net").setLevel(threshold)


def _ready_line(config: GatewayConfig, part: tuple[int, int] | None, sinks: list[Sink]) -> str:
    count = len(config.machines)
    words = [f"gateway polling {count} machine{'s' if count != 1 else ''}"]
    if part is not None:
        words[0] += f" (shard {part[0]}/{part[1]})"
    if config.mqtt is not None:
        words.append(f"MQTT {config.mqtt.host}:{config.mqtt.port}")
    if config.opcua is not None:
        words.append(f"OPC UA {_listening(config.opcua.endpoint, sinks)}")
    if config.mqtt is None and config.opcua is None:
        words.append("no output ([mqtt] or [opcua])")
    return f"{PROG}: {'; '.join(words)}\n"


def _output_name(config: GatewayConfig, output: object) -> str:
    """The output ``output`` is, as its error names it: ``the OPC UA server on opc.tcp://...``
    or ``the MQTT publisher to HOST:PORT``."""
    if config.opcua is not None:
        from focas_net.gateway.opcua import OpcUaSink  # (imported already: the output is made)

        if isinstance(output, OpcUaSink):
            return f"the OPC UA server on {config.opcua.endpoint}"
    if config.mqtt is not None:
        return f"the MQTT publisher to {config.mqtt.host}:{config.mqtt.port}"
    return "an output"


def _listening(endpoint: str, sinks: list[Sink]) -> str:
    """``endpoint`` with the port its OPC UA server listens on (port 0 asks for any free
    one, which the ready line must name)."""
    if urlsplit(endpoint).port != 0:
        return endpoint
    from focas_net.gateway.opcua import OpcUaSink  # (imported already: the output runs)

    for sink in sinks:
        if isinstance(sink, OpcUaSink):
            return with_port(endpoint, sink.port)
    return endpoint


async def _serve(config: GatewayConfig, part: tuple[int, int] | None, source: str) -> int:
    stop = asyncio.Event()
    gateway = Gateway(config)
    with stopping_on_signals(stop.set):
        async with AsyncExitStack() as stack:
            what = "an output"
            try:
                for output in outputs(config, gateway.writer):
                    what = _output_name(config, output)
                    gateway.add_sink(await stack.enter_async_context(output))
            except ValueError as exc:  # (a missing extra; ConfigError: a file it names)
                text = " ".join(str(exc).split())
                print_error(
                    f"{source}: {text}" if isinstance(exc, ConfigError) else text, _ERROR_PREFIX
                )
                await gateway.poller.aclose()
                return EXIT_USAGE
            except OSError as exc:
                print_error(f"{what} cannot start: {os_reason(exc)}", _ERROR_PREFIX)
                await gateway.poller.aclose()
                return EXIT_CNC
            except Exception as exc:  # an output's own failure to start, as one line
                _log.debug("an output failed to start", exc_info=True)
                text = " ".join(str(exc).split()) or type(exc).__name__
                print_error(f"{what} cannot start: {text}", _ERROR_PREFIX)
                await gateway.poller.aclose()
                return EXIT_CNC
            async with gateway:
                sys.stdout.write(_ready_line(config, part, gateway.poller.sinks))
                sys.stdout.flush()
                waiting = asyncio.ensure_future(stop.wait())
                failed = asyncio.ensure_future(gateway.wait())
                done, _ = await asyncio.wait({waiting, failed}, return_when="FIRST_COMPLETED")
                for task in (waiting, failed):
                    task.cancel()
                await asyncio.gather(waiting, failed, return_exceptions=True)
                if failed in done and not failed.cancelled() and failed.exception() is not None:
                    _log.error("the poller failed", exc_info=failed.exception())
                    return EXIT_CNC
    _log.info("stopped")
    return EXIT_OK
