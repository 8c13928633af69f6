"""The ``focas-net`` command line: ``serve`` and the client commands.

Each subcommand module exposes ``register(subparsers)``, which adds its parsers and sets
``func`` (``args -> exit code``) on each.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    from . import client_cmds, serve

    parser = argparse.ArgumentParser(
        prog="focas-net",
        description="A simulated FANUC CNC (focas-net serve) and a FOCAS client for the terminal.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    serve.register(sub)
    client_cmds.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code: int = args.func(args)
    except KeyboardInterrupt:
        return 130
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
