"""The ``focas-net`` command line: ``serve``, ``gateway`` and the client commands.

``focas-net serve`` runs simulated CNCs (:mod:`.serve`); ``focas-net gateway CONFIG.toml``
polls CNCs for MQTT and OPC UA (:mod:`.gateway_cmd`, ``docs/gateway.md``). The client commands
read and write a CNC from the terminal: ``status``, ``sysinfo``, ``program``, ``position``,
``param get|set``, ``macro get|set``, ``diag``, ``pmc read|write|bit``, ``alarms``, ``unlock``,
``versamax`` and ``sim panel|alarm|clear|fault|faults``. They are one table (:mod:`._table`) of
handlers from :mod:`.read_cmds`, :mod:`.write_cmds` and :mod:`.sim_cmds`, run by :mod:`._run`;
what all commands share (exit codes, argument types, the one-line error) is in :mod:`._args`.

Every client command takes ``--host`` (default 127.0.0.1), ``--port`` (8193), ``--timeout``
(seconds, 3), ``--json`` and the TLS options ``--tls``, ``--tls-ca FILE``, ``--tls-insecure``;
the commands that write also take ``--password`` (sent with ``cnc_wrunlockparam`` right after
connecting).

Output is a readable table by default (FOCAS names and their meanings); ``--json`` prints one
JSON document instead (``alarms --follow --json`` prints one JSON object per line). A failure
prints one line on stderr, ``focas-net: EW_PASSWD (17): protection / password error
(cnc_wrparam); parameter writes need ...`` (a usage error: ``focas-net CMD: error: ...; see
focas-net CMD --help``), and exits with:

====  ==========================================================================
0     success
1     the CNC answered an EW code (or a chunked PMC write failed part way)
2     usage error (bad arguments, or a value the protocol cannot carry)
3     connection refused or lost, or no answer within ``--timeout``
4     the peer broke the wire protocol
====  ==========================================================================

``alarms --follow`` polls until interrupted (Ctrl-C or SIGTERM end it cleanly with exit 0), or
until ``--count`` events were printed; it reconnects when the connection is lost, and gives up
with one line when it cannot make progress (a peer that is not a FOCAS server, 10 failed
reconnect attempts after one loss, or 20 failed polls in a row). ``docs/cli.md`` has the
details and every ``--json`` shape.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ._args import (
    EXIT_CNC,
    EXIT_CONNECTION,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_PROTOCOL,
    EXIT_USAGE,
    PROG,
)

__all__ = [
    "EXIT_CNC",
    "EXIT_CONNECTION",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_PROTOCOL",
    "EXIT_USAGE",
    "build_parser",
    "main",
]


def build_parser() -> argparse.ArgumentParser:
    """The ``focas-net`` parser: ``serve``, ``gateway``, then the client commands of the
    table."""
    from focas_net import __version__

    from . import _table, gateway_cmd, serve
    from ._args import Parser

    parser = Parser(
        prog=PROG,
        description="A simulated FANUC CNC (focas-net serve) and a FOCAS client for the terminal.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    serve.register(sub)
    gateway_cmd.register(sub)
    _table.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    try:
        args = build_parser().parse_args(argv)
        code: int = args.func(args)
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
