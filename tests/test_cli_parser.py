"""The parser of the client commands: every subcommand and option, as recorded in
``tests/data/cli_parser.json``.

The record holds what ``argparse`` was given (flags, metavars, defaults, types, choices, help
texts, groups, descriptions) rather than the formatted ``--help`` text, so it does not depend
on the terminal width or on how a Python version lays out help. ``serve`` has its own options
(``tests/test_cli_serve.py``) and is left out. Regenerate the record with
``python tests/test_cli_parser.py > tests/data/cli_parser.json`` after a deliberate change.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from focas_net.cli import build_parser

RECORD = Path(__file__).resolve().parent / "data" / "cli_parser.json"
#: The commands that are not client commands (each has its own tests).
NOT_RECORDED = frozenset({"serve", "gateway"})


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction[Any] | None:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action
    return None


def _type_name(action: argparse.Action) -> str | None:
    if action.type is None:
        return None
    return str(getattr(action.type, "__name__", repr(action.type)))


def _action(action: argparse.Action) -> dict[str, Any]:
    return {
        "kind": type(action).__name__,
        "flags": list(action.option_strings),
        "dest": action.dest,
        "metavar": action.metavar,
        "nargs": action.nargs,
        "default": repr(action.default),
        "type": _type_name(action),
        "choices": None if action.choices is None else [str(c) for c in action.choices],
        "required": action.required,
        "help": action.help,
    }


def parser_tree(
    parser: argparse.ArgumentParser, skip: frozenset[str] = frozenset()
) -> dict[str, Any]:
    """What ``parser`` and its subparsers were built from, as JSON-ready data."""
    sub = _subparsers(parser)
    node: dict[str, Any] = {
        "description": parser.description,
        "epilog": parser.epilog,
        "groups": [[g.title, [a.dest for a in g._group_actions]] for g in parser._action_groups],
        "actions": [_action(a) for a in parser._actions if a is not sub],
        "defaults": {
            k: (v.__name__ if callable(v) else repr(v))
            for k, v in sorted(parser._defaults.items())
            if k != "func"
        },
        "has_func": "func" in parser._defaults,
    }
    if sub is not None:
        node["subcommands"] = {
            "dest": sub.dest,
            "metavar": sub.metavar,
            "required": sub.required,
            "help": {a.dest: a.help for a in sub._choices_actions},
            "order": [a.dest for a in sub._choices_actions],
            "commands": {
                name: parser_tree(p) for name, p in sub.choices.items() if name not in skip
            },
        }
    return node


def _leaves(node: dict[str, Any], path: tuple[str, ...] = ()) -> list[tuple[str, ...]]:
    sub = node.get("subcommands")
    if sub is None:
        return [path]
    return [leaf for name, n in sub["commands"].items() for leaf in _leaves(n, (*path, name))]


def test_the_parser_is_the_recorded_one() -> None:
    recorded = json.loads(RECORD.read_text())
    assert parser_tree(build_parser(), NOT_RECORDED) == recorded


def test_the_record_covers_every_client_command() -> None:
    leaves = _leaves(json.loads(RECORD.read_text()))
    assert len(leaves) == 24
    assert ("status",) in leaves and ("sim", "fault") in leaves and ("pmc", "bit") in leaves
    assert ("macro", "clear") in leaves
    assert ("sim", "cycle") in leaves and ("sim", "override") in leaves
    assert ("watch",) in leaves


if __name__ == "__main__":  # pragma: no cover
    print(json.dumps(parser_tree(build_parser(), NOT_RECORDED), indent=1))  # noqa: T201
