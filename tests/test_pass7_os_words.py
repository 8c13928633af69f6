"""The system's refusal of a file or address a user named reads alike on every front end: its
words with a lower-case first letter (``no such file or directory``), never ``[Errno 2] ...``
nor the capitalised ``No such file or directory`` some front ends printed."""

from __future__ import annotations

import errno
import socket
from pathlib import Path

import pytest
from cli_support import fails

from focas_net._typed import os_reason, os_words
from focas_net.cli import EXIT_USAGE
from focas_net.gateway.config import ConfigError, load_config
from focas_net.sim import MachineFileError, load_machine


def test_os_words() -> None:
    assert os_words(FileNotFoundError(errno.ENOENT, "No such file or directory", "x")) == (
        "no such file or directory"
    )
    assert os_words(OSError("Something odd")) == "something odd"
    assert os_words(OSError()) == "OSError"
    assert os_reason(ConnectionRefusedError(errno.ECONNREFUSED, "x")) == "connection refused"
    assert os_reason(socket.gaierror(-2, "Name or service not known")) == (
        "name or service not known"
    )


def test_the_machine_file_and_the_gateway_file_say_it_alike(tmp_path: Path) -> None:
    missing = tmp_path / "none.toml"
    with pytest.raises(MachineFileError) as machine:
        load_machine(missing)
    with pytest.raises(ConfigError) as gateway:
        load_config(missing)
    assert str(machine.value).endswith("no such file or directory")
    assert str(gateway.value).endswith("no such file or directory")


@pytest.mark.parametrize(
    "argv",
    [
        ("program", "load", "/nonexistent/o1000.nc", "--port", "1"),
        ("status", "--tls", "--tls-ca", "/nonexistent/ca.pem", "--port", "1"),
    ],
)
async def test_the_command_line_says_it_in_lower_case(argv: tuple[str, ...]) -> None:
    line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
    # (the parser's form: the argument, the reason, then where the help is)
    assert f"no such file or directory; see focas-net {argv[0]} --help" in line, line


async def test_serve_says_it_in_lower_case() -> None:
    for argv in (
        ("serve", "--port", "0", "--machine", "/nonexistent/m.toml"),
        ("serve", "--port", "0", "--tls-cert", "/nonexistent/c.pem", "--tls-key", "/n/k.pem"),
    ):
        line = await fails(EXIT_USAGE, *argv, prefix="focas-net")
        assert line.endswith("no such file or directory"), line
