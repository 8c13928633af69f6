"""A client's address is checked where both clients and the command line pass: a host with a
port, an empty host or a name that is not one is refused at construction, naming what was
given, before any connection is tried."""

from __future__ import annotations

import re

import pytest

from focas_net.cli._args import parse_host
from focas_net.client import FocasClient, NativeClient
from focas_net.protocol import PmcArea

CLIENTS = [FocasClient, NativeClient]


@pytest.mark.parametrize("kind", CLIENTS)
@pytest.mark.parametrize(
    ("host", "words"),
    [
        ("127.0.0.1:18193", "give the host '127.0.0.1' and the port 18193 apart"),
        ("[::1]:8193", "give the host '::1' and the port 8193 apart"),
        ("cnc-01:8193", "give the host 'cnc-01' and the port 8193 apart"),
        ("", "empty host ''"),
        ("[]", "brackets are for IPv6 addresses, got host '[]'"),
        ("[cnc]", "brackets are for IPv6 addresses, got host '[cnc]'"),
        ("1::2::3", "not an IPv6 address: host '1::2::3'"),
        ("cnc 01", "not a host name: 'cnc 01'"),
        (" 127.0.0.1", "host ' 127.0.0.1' has spaces around it: give '127.0.0.1'"),
        ("a..b", "has a part of 0 characters"),
        ("256.1.1.1", "not an IPv4 address: host '256.1.1.1'"),
        ("10.0.5", "not an IPv4 address: host '10.0.5'"),
        ("x" * 64, "has a part of 64 characters"),
    ],
)
def test_a_bad_host_is_refused_at_construction(kind: type, host: str, words: str) -> None:
    with pytest.raises(ValueError) as info:
        kind(host, 8193)
    assert words in str(info.value)


@pytest.mark.parametrize("kind", CLIENTS)
def test_a_host_that_is_no_text_is_a_type_error(kind: type) -> None:
    with pytest.raises(TypeError, match=r"host must be a str, got \('127.0.0.1', 8193\)"):
        kind(("127.0.0.1", 8193), 8193)


@pytest.mark.parametrize("kind", CLIENTS)
@pytest.mark.parametrize("port", [0, -1, 65536])
def test_a_client_port_is_1_to_65535(kind: type, port: int) -> None:
    """0 means "any port" only to a server that listens: a client cannot connect to it."""
    with pytest.raises(ValueError, match=rf"port {port} is outside 1\.\.65535"):
        kind("127.0.0.1", port)
    with pytest.raises(TypeError, match=r"port must be an integer 1\.\.65535, got '8193'"):
        kind("127.0.0.1", "8193")
    assert kind("127.0.0.1", 65535).port == 65535


@pytest.mark.parametrize("area", [b"R", True, 5.0, None])
def test_a_pmc_area_of_another_type_is_a_type_error_naming_it(area: object) -> None:
    with pytest.raises(TypeError, match=rf"a PMC area is its letter .*got {re.escape(repr(area))}"):
        PmcArea.parse(area)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="unknown PMC area number 99"):
        PmcArea.parse(99)


@pytest.mark.parametrize("kind", CLIENTS)
@pytest.mark.parametrize(
    ("host", "kept"),
    [
        ("127.0.0.1", "127.0.0.1"),
        ("::1", "::1"),
        ("[::1]", "::1"),
        ("cnc-01.plant.", "cnc-01.plant."),
        ("localhost", "localhost"),
        ("drehbank-ü1", "drehbank-ü1"),
    ],
)
def test_a_good_host_is_kept(kind: type, host: str, kept: str) -> None:
    client = kind(host, 8193)
    assert client.host == kept
    assert client.address == (f"[{kept}]:8193" if ":" in kept else f"{kept}:8193")


def test_the_command_line_points_a_host_and_port_to_its_options() -> None:
    with pytest.raises(ValueError, match=r"give --host 127\.0\.0\.1 --port 18193"):
        parse_host("127.0.0.1:18193")
    with pytest.raises(ValueError, match=r"give --host ::1 --port 8193"):
        parse_host(" [::1]:8193 ")
    assert parse_host(" cnc-01 ") == "cnc-01"
    with pytest.raises(ValueError, match="empty host"):
        parse_host("  ")
