"""What a new user runs into, fifth pass: the command line as a child process against a real
server (127.0.0.1, ephemeral port), its exit codes and its one-line messages.

Each test names what a user typed and what the command must say.
"""

from __future__ import annotations

import pytest
from cli_support import run_focas_net
from support import Served

from focas_net.cli import EXIT_OK, EXIT_USAGE


def at(served: Served) -> list[str]:
    return ["--host", "127.0.0.1", "--port", str(served.port)]


def one_line(err: str) -> str:
    """The one ``focas-net:`` line of a failure."""
    assert err.startswith("focas-net") and err.count("\n") == 1, err
    return err.strip()


async def fails(code: int, *argv: str) -> str:
    got, out, err = await run_focas_net(*argv)
    assert got == code, (argv, got, err)
    assert out == ""
    return one_line(err)


async def ok(*argv: str) -> str:
    got, out, err = await run_focas_net(*argv)
    assert got == EXIT_OK, (argv, got, err)
    assert err == ""
    return out


# -- a poll interval: 0.05 s .. one hour, and each refusal with its own reason -------------------


@pytest.mark.parametrize("command", [["watch", "--count", "1"], ["alarms", "--follow"]])
@pytest.mark.parametrize(
    ("value", "reason"),
    [
        ("inf", "must be finite, got inf"),
        ("1e9", "must be 0.05..3600 seconds, got 1e9"),
        ("3600.5", "must be 0.05..3600 seconds, got 3600.5"),
        ("0.01", "must be 0.05..3600 seconds, got 0.01"),
        ("-1", "must be 0.05..3600 seconds, got -1"),
        ("nan", "not a number: 'nan'"),
    ],
)
async def test_a_poll_interval_out_of_range_says_why(
    server: Served, command: list[str], value: str, reason: str
) -> None:
    line = await fails(EXIT_USAGE, *command, "--interval", value, *at(server))
    assert f"argument --interval: {reason};" in line, line


@pytest.mark.parametrize(
    ("value", "reason"), [("inf", "must be finite, got inf"), ("0", "must be positive, got 0")]
)
async def test_a_timeout_out_of_range_says_why(server: Served, value: str, reason: str) -> None:
    line = await fails(EXIT_USAGE, "status", "--timeout", value, *at(server))
    assert f"argument --timeout: {reason};" in line, line


async def test_an_hour_is_the_longest_poll_interval(server: Served) -> None:
    assert "frame 1" in await ok("watch", "--count", "1", "--interval", "3600", *at(server))
